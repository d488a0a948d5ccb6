"""Model updating: fit the cage geometry the paper does not give to its Table 8.

Unknowns (SI, with the bounds we consider plausible for this cage and its 22 mm balls):
  pocket_diameter  22.1–23.0 mm   pocket clearance Cp = (Dp - Dw)/2 = 0.05–0.5 mm
  chamfer          0–2.0 mm       45° edge break; must stay inside the 2.5–2.9 mm side rails
  land_width       2.5–14.15 mm   each outer guide land (14.15 mm = whole width: no relief)
  relief_depth     0–3.0 mm       radial depth of the central outside relief (wall is 8.65 mm)
Objective (issue 2): least squares on the relative errors of modes 7–27,
    r_i(p) = (f_i(p) - f_i^Table8) / f_i^Table8,  i = 7..27,  min_p sum r_i^2,
frequencies sorted ascending on both sides (as Table 8 lists them). Solver: scipy
least_squares (trust-region reflective, box bounds) in normalised coordinates
z = (p - lo)/(hi - lo), with a forward-difference Jacobian of fixed step dz (remeshing noise
makes tiny steps meaningless). Each evaluation meshes the cage and solves 27 modes; every
evaluation is logged, so the fit can be audited and resumed.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from mesh.cage_geometry import NOMINAL_CAGE

BOUNDS = {
    "pocket_diameter": (22.1e-3, 23.0e-3),
    "chamfer": (0.0, 2.0e-3),
    "land_width": (2.5e-3, 14.15e-3),
    "relief_depth": (0.0, 3.0e-3),
}
DEFAULT_PARAMS = ("pocket_diameter", "chamfer", "land_width", "relief_depth")
CALIBRATION_MESH = (8e-3, 8e-3, 2, 3)   # size, pocket size, order, degree: curved P3, ~0.5 % above
# the converged value (mesh study); the result is verified at the default mesh.


def table8_vector() -> np.ndarray:
    from .modes import PAPER_TABLE8_HZ
    return np.array([PAPER_TABLE8_HZ[m] for m in range(7, 28)])


def residuals(freqs_hz) -> np.ndarray:
    """Relative errors of modes 7..27 (sorted)."""
    f = np.sort(np.asarray(freqs_hz))[6:27]
    t = np.sort(table8_vector())     # 6692.1, 6692.0 is a pair listed out of order
    return (f - t) / t


class Evaluator:
    """Geometry -> 27 frequencies on a fixed mesh recipe; memoised and logged."""

    def __init__(self, names, base=NOMINAL_CAGE, mesh=CALIBRATION_MESH, log_path=None, quiet=False):
        self.names, self.base, self.mesh = list(names), base, mesh
        self.lo = np.array([BOUNDS[n][0] for n in self.names])
        self.hi = np.array([BOUNDS[n][1] for n in self.names])
        self.log_path = Path(log_path) if log_path else None
        self.memo: dict[tuple, list] = {}
        self.history: list[dict] = []
        self.quiet = quiet
        if self.log_path and self.log_path.exists():
            for line in self.log_path.read_text().splitlines():
                rec = json.loads(line)
                key = tuple(round(rec["params"][n], 9) for n in self.names) if all(n in rec["params"] for n in self.names) else None
                if key and rec.get("mesh") == list(self.mesh):
                    self.memo[key] = rec["frequencies_hz"]

    def geometry(self, p):
        return self.base.with_(**{n: float(v) for n, v in zip(self.names, p)}).validate()

    def to_p(self, z):
        return self.lo + np.clip(z, 0, 1) * (self.hi - self.lo)

    def to_z(self, p):
        return (np.asarray(p) - self.lo) / (self.hi - self.lo)

    def frequencies(self, p):
        key = tuple(round(float(v), 9) for v in p)
        if key in self.memo:
            return np.array(self.memo[key])
        from mpi4py import MPI
        from mesh.cage_mesh import cached_cage_mesh
        from .cli import run_modes
        g = self.geometry(p)
        size, ps, order, degree = self.mesh
        t0 = time.perf_counter()
        path = cached_cage_mesh(g, size, order, ps)
        res, V, vecs = run_modes(g, path, degree, 27, classify=False)
        for v in vecs:
            v.destroy()
        del V, vecs
        import gc
        gc.collect()
        f = res["frequencies_hz"]
        self.memo[key] = f
        r = residuals(f)
        rec = {"params": {n: float(v) for n, v in zip(self.names, p)}, "mesh": list(self.mesh),
               "frequencies_hz": f, "rms": float(np.sqrt(np.mean(r ** 2))),
               "max": float(np.max(np.abs(r))), "wall_s": time.perf_counter() - t0}
        self.history.append(rec)
        if self.log_path and MPI.COMM_WORLD.rank == 0:
            with open(self.log_path, "a") as fh:
                fh.write(json.dumps(rec) + "\n")
        if not self.quiet and MPI.COMM_WORLD.rank == 0:
            ps_txt = ", ".join(f"{n}={1e3 * v:.3f} mm" for n, v in zip(self.names, p))
            print(f"  [{len(self.history):3d}] {ps_txt}: RMS {100 * rec['rms']:.2f} %, "
                  f"max {100 * rec['max']:.2f} % ({rec['wall_s']:.0f} s)", flush=True)
        return np.array(f)

    def r_of_z(self, z):
        return residuals(self.frequencies(self.to_p(z)))

    def jac_of_z(self, z, dz=0.06):
        r0 = self.r_of_z(z)
        J = np.zeros((len(r0), len(z)))
        for j in range(len(z)):
            step = dz if z[j] + dz <= 1.0 else -dz
            zz = np.array(z, dtype=float)
            zz[j] += step
            J[:, j] = (self.r_of_z(zz) - r0) / step
        return J


START = {"pocket_diameter": 22.6e-3, "chamfer": 1.2e-3, "land_width": 5.0e-3, "relief_depth": 1.0e-3}


def fit(names=DEFAULT_PARAMS, start=None, mesh=CALIBRATION_MESH, log_path=None, max_evals=40,
        quiet=False):
    """Least-squares fit; returns (best params dict, evaluator)."""
    from scipy.optimize import least_squares
    ev = Evaluator(names, mesh=mesh, log_path=log_path, quiet=quiet)
    if start is None:
        start = [START.get(n, getattr(NOMINAL_CAGE, n)) for n in names]
    z0 = np.clip(ev.to_z(start), 0.0, 1.0)
    n_jac = len(names)
    sol = least_squares(ev.r_of_z, z0, jac=ev.jac_of_z, bounds=(0.0, 1.0), method="trf",
                        x_scale=1.0, max_nfev=max(1, max_evals // (n_jac + 1)), xtol=1e-3,
                        ftol=1e-4, verbose=0)
    # best evaluation seen (the optimiser's last point is not always the best one)
    best = min(ev.memo.items(), key=lambda kv: float(np.sum(residuals(kv[1]) ** 2)))
    return dict(zip(names, best[0])), ev, sol


def run_calibration(outdir: Path, size=None, pocket_size=None, order=2, degree=3, params=None,
                    quiet=False, max_evals=40):
    """CLI driver: fit, then verify at the default mesh with mode classification; write
    calibration.json / calibration.md in outdir."""
    from mpi4py import MPI
    from mesh.cage_mesh import (cached_cage_mesh, DEFAULT_MESH_SIZE, DEFAULT_POCKET_SIZE, DEFAULT_ORDER,
                                DEFAULT_DEGREE)
    from .cli import run_modes
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    names = list(params or DEFAULT_PARAMS)
    for n in names:
        if n not in BOUNDS:
            from mesh.validation import InputError
            raise InputError(f"calibrate-cage.params: {n!r} is not one of {sorted(BOUNDS)}")
    mesh = (size or CALIBRATION_MESH[0], pocket_size or CALIBRATION_MESH[1], order, degree)
    best, ev, sol = fit(names, mesh=mesh, log_path=outdir / "evaluations.jsonl", max_evals=max_evals,
                        quiet=quiet)
    g = NOMINAL_CAGE.with_(**best).validate()
    report = {"params": best, "bounds": {n: BOUNDS[n] for n in names}, "calibration_mesh": list(mesh),
              "evaluations": len(ev.memo), "optimizer": {"status": int(sol.status), "message": sol.message}}
    # verification at the default mesh, both nominal and calibrated, with classification
    for label, geo in (("nominal", NOMINAL_CAGE), ("calibrated", g)):
        path = cached_cage_mesh(geo, DEFAULT_MESH_SIZE, DEFAULT_ORDER, DEFAULT_POCKET_SIZE)
        res, _, _ = run_modes(geo, path, DEFAULT_DEGREE, 27, classify=True)
        r = residuals(res["frequencies_hz"])
        report[label] = {"frequencies_hz": res["frequencies_hz"], "rms": float(np.sqrt(np.mean(r ** 2))),
                         "max": float(np.max(np.abs(r))), "modes": res["modes"], "ndofs": res["ndofs"]}
    if MPI.COMM_WORLD.rank == 0:
        (outdir / "calibration.json").write_text(json.dumps(report, indent=1, default=float))
        md = calibration_markdown(report)
        (outdir / "calibration.md").write_text(md)
        if not quiet:
            print(md)
    return report


def calibration_markdown(report) -> str:
    from .cli import format_table
    lines = ["# Cage calibration against Table 8", "",
             "Fitted parameters (bounds):", ""]
    for n, v in report["params"].items():
        lo, hi = report["bounds"][n]
        lines.append(f"- {n} = {1e3 * v:.3f} mm  (bounds {1e3 * lo:g}–{1e3 * hi:g} mm)")
    lines += ["", f"Calibration mesh {report['calibration_mesh']}, {report['evaluations']} evaluations; "
              f"optimizer: {report['optimizer']['message']}", ""]
    for label in ("nominal", "calibrated"):
        rep = report[label]
        lines += [f"## {label} geometry at the default mesh ({rep['ndofs']} dofs)", "", "```",
                  format_table(rep["frequencies_hz"], [m["label"] for m in rep["modes"]]), "```", ""]
        lines += family_summary(rep)
    lines += ["The paper (§4.1, Fig. 16) calls modes 7, 11, 15, 17 in-plane bending, 14 and 20 "
              "bending–torsion coupling, 24–25 end-face tilting / out-of-plane torsion, 26 irregular "
              "(pocket-driven). Families above are assigned automatically (fem_cage.classify: "
              "cross-section rigid-motion fit per azimuthal sector + Fourier order n).", ""]
    return "\n".join(lines)


def family_summary(rep) -> list[str]:
    """Relative error vs Table 8 grouped by our mode family (modes 7..27, sorted matching)."""
    r = residuals(rep["frequencies_hz"])
    fam: dict[str, list[tuple[int, float]]] = {}
    for i, m in enumerate(rep["modes"][6:27]):
        fam.setdefault(m["family"], []).append((m["mode"], r[i]))
    out = ["| family | modes | mean error | max abs error |", "|---|---|---|---|"]
    for name, items in sorted(fam.items()):
        e = np.array([x for _, x in items])
        out.append(f"| {name} | {', '.join(str(k) for k, _ in items)} | {100 * e.mean():+.2f} % | "
                   f"{100 * np.max(np.abs(e)):.2f} % |")
    return out + [""]
