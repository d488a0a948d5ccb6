"""Mesh convergence of the cage's free–free frequencies: frequency vs dofs and run time.

Levels are (size_mm, pocket_size_mm, mesh order, Lagrange degree). For the finest three
levels of one (order, degree) family the limit is estimated by Richardson extrapolation with
the mesh parameter h = ndofs^(-1/3) (uniform refinement in 3-D):
    f(h) = f_inf + C h^p,
    (f1 - f2)/(f2 - f3) = (h1^p - h2^p)/(h2^p - h3^p)  -> observed order p (bisection),
    f_inf = f3 - (f2 - f3) h3^p / (h2^p - h3^p).
When the three values are not monotone or p falls outside [1, 8], p = 2 is used (the
asymptotic order of P_k eigenvalues would be 2k in h, Strang & Fix, "An Analysis of the FEM",
§6.3, but this cage's measured sequences are pre-asymptotic at about p = 2). Reference: Roache, "Verification and Validation in Computational Science
and Engineering" (1998), ch. 5.
"""
from __future__ import annotations

import csv
import json
import time
from pathlib import Path

import numpy as np
from flexbearing.mesh.cage_mesh import cached_cage_mesh, cache_path, DEFAULT_DEGREE
from .modes import run_modes
from tqdm import tqdm

# (size mm, pocket size mm, order, degree): the curved-P3 family (the default) refined, the
# curved-P2 family for comparison, one linear-tet and one straight-sided-P2 level.
DEFAULT_STUDY = [(8, 8, 2, 3), (6, 6, 2, 3), (5, 5, 2, 3), (4, 4, 2, 3),
                 (6, 3, 2, 2), (4, 2, 2, 2), (3, 1.5, 2, 2),
                 (3, 1.5, 1, 1), (4, 2, 1, 2)]


def observed_order(f1, f2, f3, h1, h2, h3, lo=0.3, hi=12.0):
    """p solving (f1-f2)/(f2-f3) = (h1^p-h2^p)/(h2^p-h3^p); None if not monotone."""
    d12, d23 = f1 - f2, f2 - f3
    if d12 * d23 <= 0 or d23 == 0:
        return None
    target = d12 / d23
    g = lambda p: (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p) - target
    a, b = lo, hi
    if g(a) * g(b) > 0:
        return None
    for _ in range(100):
        m = 0.5 * (a + b)
        if g(a) * g(m) <= 0:
            b = m
        else:
            a = m
    return 0.5 * (a + b)


def richardson(f1, f2, f3, h1, h2, h3, p_default=2.0):
    """(f_inf, p) from three levels (coarse to fine), see module docstring.

    An observed order outside [1, 8] (or none) is not trusted; p_default = 2 is then used,
    the order measured on this cage for the curved P2/P3 sequences (pre-asymptotic), which
    also gives the larger, i.e. conservative, correction."""
    p = observed_order(f1, f2, f3, h1, h2, h3)
    p_use = p if (p is not None and 1.0 <= p <= 8.0) else p_default
    finf = f3 - (f2 - f3) * h3 ** p_use / (h2 ** p_use - h3 ** p_use)
    return finf, p


def run_level(g, level, n_modes=27):
    from mpi4py import MPI
    size, ps, order, degree = level
    t0 = time.perf_counter()
    if MPI.COMM_WORLD.rank == 0:
        cached_cage_mesh(g, size * 1e-3, int(order), ps * 1e-3)
    MPI.COMM_WORLD.barrier()
    path = cache_path(g, size * 1e-3, int(order), ps * 1e-3)
    t_mesh = time.perf_counter() - t0
    res, _, _ = run_modes(g, path, int(degree), n_modes, classify=False)
    res["timing_s"]["mesh"] = t_mesh
    res["solve_s"] = res["timing_s"]["assemble"] + res["timing_s"]["eigensolve"] + res["timing_s"]["read_mesh"]
    return res


def run_mesh_study(g, levels, outdir: Path, n_modes=27, quiet=False):
    from mpi4py import MPI
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows = []
    for lev in tqdm(levels, desc="mesh study", disable=quiet or MPI.COMM_WORLD.rank != 0):
        r = run_level(g, lev, n_modes)
        rows.append({"size_mm": lev[0], "pocket_size_mm": lev[1], "order": int(lev[2]),
                     "degree": int(lev[3]), "ndofs": r["ndofs"], "mesh_s": r["timing_s"]["mesh"],
                     "solve_s": r["solve_s"], "f": r["frequencies_hz"]})
    if MPI.COMM_WORLD.rank != 0:
        return rows, None
    # CSV: one row per level
    with open(outdir / "mesh_study.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["size_mm", "pocket_size_mm", "order", "degree", "ndofs", "mesh_s", "solve_s"]
                   + [f"f{m}_hz" for m in range(1, n_modes + 1)])
        for r in rows:
            w.writerow([r["size_mm"], r["pocket_size_mm"], r["order"], r["degree"], r["ndofs"],
                        f"{r['mesh_s']:.2f}", f"{r['solve_s']:.2f}"] + [f"{x:.4f}" for x in r["f"]])
    # Richardson on the finest three levels of each family with >= 3 levels; the summary
    # numbers refer to the default family (curved mesh, DEFAULT_DEGREE).
    summary = {"levels": [{k: v for k, v in r.items() if k != "f"} for r in rows], "families": {}}
    for key in sorted({(r["order"], r["degree"]) for r in rows}):
        fam = sorted([r for r in rows if (r["order"], r["degree"]) == key], key=lambda r: r["ndofs"])
        if len(fam) < 3:
            continue
        a, b, c = fam[-3:]
        h = [r["ndofs"] ** (-1.0 / 3.0) for r in (a, b, c)]
        ext, orders = [], []
        for m in range(n_modes):
            finf, p = richardson(a["f"][m], b["f"][m], c["f"][m], *h)
            ext.append(finf)
            orders.append(p)
        el = slice(6, 16)   # first 10 elastic modes
        fb, fc = np.array(b["f"][el]), np.array(c["f"][el])
        summary["families"][f"order{key[0]}_P{key[1]}"] = {
            "richardson_hz": ext, "observed_order_in_h": orders,
            "finest_two": [(r["size_mm"], r["pocket_size_mm"]) for r in (b, c)],
            "finest_two_change_first10": float(np.max(np.abs(fc - fb) / fc))}
    fam_key = f"order2_P{DEFAULT_DEGREE}"
    if fam_key in summary["families"]:
        F = summary["families"][fam_key]
        ext = np.array(F["richardson_hz"])
        summary["richardson_hz"] = F["richardson_hz"]
        summary["finest_two_change_first10"] = F["finest_two_change_first10"]
        summary["per_level_error_vs_richardson_first10"] = [
            float(np.max(np.abs(np.array(r["f"][6:16]) - ext[6:16]) / ext[6:16])) for r in rows]
    (outdir / "mesh_study.json").write_text(json.dumps(summary, indent=1, default=float))
    _plot(rows, summary, outdir / "mesh_study.png")
    if not quiet:
        print(format_summary(rows, summary))
    return rows, summary


def format_summary(rows, summary) -> str:
    lines = [f"{'size':>5} {'pocket':>6} {'ord':>3} {'deg':>3} {'ndofs':>8} {'mesh s':>7} {'solve s':>8} "
             f"{'f7':>8} {'f9':>8} {'f11':>8} {'f16':>8}  max err 1st10 vs Richardson"]
    errs = summary.get("per_level_error_vs_richardson_first10", [None] * len(rows))
    for r, e in zip(rows, errs):
        f = r["f"]
        lines.append(f"{r['size_mm']:>5g} {r['pocket_size_mm']:>6g} {r['order']:>3} {r['degree']:>3} "
                     f"{r['ndofs']:>8} {r['mesh_s']:>7.1f} {r['solve_s']:>8.1f} {f[6]:>8.2f} {f[8]:>8.2f} "
                     f"{f[10]:>8.2f} {f[15]:>8.2f}  {'' if e is None else f'{100 * e:.2f} %'}")
    if "richardson_hz" in summary:
        ext = summary["richardson_hz"]
        lines.append("Richardson  " + " ".join(f"{x:.1f}" for x in ext[6:]))
        lines.append(f"finest two default-family levels: max change over the first 10 elastic modes "
                     f"{100 * summary['finest_two_change_first10']:.3f} %")
    return "\n".join(lines)


def _plot(rows, summary, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    ext = summary.get("richardson_hz")
    markers = {(2, 3): "o-", (2, 2): "d-", (1, 1): "s", (1, 2): "^"}
    names = {(2, 3): "curved P3", (2, 2): "curved P2", (1, 1): "linear P1", (1, 2): "straight P2"}
    for key in markers:
        fam = sorted([r for r in rows if (r["order"], r["degree"]) == key], key=lambda r: r["ndofs"])
        if not fam or ext is None:
            continue
        nd = [r["ndofs"] for r in fam]
        err = [100 * np.max(np.abs(np.array(r["f"][6:16]) - np.array(ext[6:16])) / np.array(ext[6:16]))
               for r in fam]
        ax[0].loglog(nd, err, markers[key], label=names[key])
        ax[1].loglog(nd, [r["solve_s"] for r in fam], markers[key], label=names[key])
    ax[0].axhline(0.5, color="grey", ls=":", lw=1)
    ax[0].set_xlabel("dofs")
    ax[0].set_ylabel("max error, modes 7-16 vs Richardson of curved P3 (%)")
    ax[1].set_xlabel("dofs")
    ax[1].set_ylabel("read + assemble + eigensolve (s)")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    fig.suptitle("Cage free-free modes: mesh convergence")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
