"""Independent FE check of the paper cage: the project's P2 FE against CalculiX C3D10 on the same
meshes (issue 24, item 3; flexbearing.verification.calculix_check has the method).

For each element size (pocket size = global size, curved quadratic gmsh mesh built by
flexbearing.mesh.cage_mesh.build_cage_mesh with the sizes passed explicitly): the spinning cage (645 rad/s
about x), a 1 kN ball force on pocket 1 (pocket 0 reacting, as `flexbearing reduce --check`) in
the circumferential, axial and radial directions, and the first 20 free–free elastic
frequencies. Reports the max von Mises of each code, its node and position, the difference,
the same with CalculiX's stress recovery applied to the project's solution (what is left is the
solutions' difference), displacements, reactions of the 3-2-1 support, frequencies (the project
at its default quadrature and at ccx's 4-point rule), mesh size, dofs, run times. ccx runs on
one thread (OMP_NUM_THREADS=1), the project serial: like-for-like wall times.

Writes benchmarks/results/calculix_check.{json,md}.

    nice -n 5 .venv/bin/python benchmarks/calculix_check.py [--sizes 4 3 2.5] [--quiet]
"""
from __future__ import annotations

import argparse
import json
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
ACCEPT_VM, ACCEPT_HZ = 0.02, 0.005          # issue 24: max von Mises and location 2 %, frequencies 0.5 %


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[4.0, 3.0, 2.5],
                    help="element sizes, mm (pocket size the same)")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--markdown-only", action="store_true",
                    help="re-render calculix_check.md from the existing calculix_check.json")
    args = ap.parse_args(argv)
    if args.markdown_only:
        out = json.loads((RESULTS / "calculix_check.json").read_text())
        (RESULTS / "calculix_check.md").write_text(markdown(out))
        return 0
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    from flexbearing.verification.calculix_check import check_mesh
    import subprocess
    runs = []
    with tempfile.TemporaryDirectory(prefix="calculix-check-") as tmp:
        for h_mm in args.sizes:
            h = h_mm * 1e-3
            t0 = time.perf_counter()
            msh = build_cage_mesh(PAPER_CAGE, h, 2, Path(tmp) / f"cage_{h_mm:g}mm.msh", h)
            t_mesh = time.perf_counter() - t0
            r = check_mesh(msh, PAPER_CAGE)
            r["mesh"].update({"size_m": h, "pocket_size_m": h, "order": 2, "mesh_s": t_mesh})
            r["mesh"]["file"] = f"build_cage_mesh(PAPER_CAGE, {h:g}, 2, path, {h:g})"
            runs.append(r)
            if not args.quiet:
                print(summary_line(r), flush=True)
    ccx_version = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "calculix-ccx"],
                                 capture_output=True, text=True).stdout.strip()
    out = {"description": "project P2 (dolfinx) vs CalculiX C3D10 on the same paper-cage meshes",
           "command": "nice -n 5 .venv/bin/python benchmarks/calculix_check.py --sizes "
                      + " ".join(f"{s:g}" for s in args.sizes),
           "calculix_ccx_version": ccx_version, "machine": platform.node(),
           "date": time.strftime("%Y-%m-%d"), "acceptance": {"vm_max_rel": ACCEPT_VM, "frequency_rel": ACCEPT_HZ},
           "runs": runs}
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "calculix_check.json").write_text(json.dumps(out, indent=1, default=_jsonable))
    (RESULTS / "calculix_check.md").write_text(markdown(out))
    if not args.quiet:
        print(f"wrote {RESULTS / 'calculix_check.md'}")
    return 0


def _jsonable(x):
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(type(x))


def summary_line(r) -> str:
    parts = [f"h = {r['mesh']['size_m'] * 1e3:g} mm, {r['mesh']['dofs']} dofs"]
    for k, c in r["cases"].items():
        parts.append(f"{k} {c['vm_max_project_Pa'] / 1e6:.2f}/{c['vm_max_calculix_Pa'] / 1e6:.2f} MPa "
                     f"({100 * c['vm_max_rel_diff']:+.2f} %)")
    if "frequencies" in r:
        parts.append(f"frequencies {100 * r['frequencies']['max_abs_rel_diff']:.3f} %")
    return "; ".join(parts)


def _where(p) -> str:
    """x, r, azimuth of a point: mm, mm, degrees (from +y towards +z)."""
    x, y, z = p
    return f"x {1e3 * x:.2f}, r {1e3 * np.hypot(y, z):.2f} mm, {np.degrees(np.arctan2(z, y)):.1f}°"


def markdown(out) -> str:
    runs = out["runs"]
    L = ["# Independent FE check: project P2 (dolfinx) vs CalculiX C3D10, paper cage",
         "", f"`{out['command']}` — calculix-ccx {out['calculix_ccx_version']}, {out['date']}. "
         "Method and what is independent: `flexbearing/verification/calculix_check.py` docstring.", "",
         "Same mesh (gmsh curved quadratic tetrahedra, `build_cage_mesh(PAPER_CAGE, h, 2, path, h)`), "
         "same material (E 209 GPa, nu 0.295, rho 7870 kg/m³), same loads and 3-2-1 support. "
         "Spin: 645 rad/s about x (CalculiX computes its own CENTRIF body load). Pocket: 1 kN on "
         "pocket 1, pocket 0 reacting (the `reduce --check` case; CalculiX spreads the ball force "
         "and the reaction with its own *DISTRIBUTING couplings). Stresses: nodal von Mises over "
         "all mesh nodes (vertices and mid-edge nodes), each code's own recovery.", "",
         "## Acceptance (issue 24: max von Mises and its location within 2 %, frequencies within 0.5 %)",
         "", "| h (mm) | max von Mises: largest difference (case) | location: smallest 'other code at "
         "this code's peak' | frequencies: largest difference | met |", "|---|---|---|---|---|"]
    for r in runs:
        cs = r["cases"]
        worst = max(cs, key=lambda k: abs(cs[k]["vm_max_rel_diff"]))
        loc = min(min(c["calculix_at_project_peak_rel"], c["project_at_calculix_peak_rel"]) for c in cs.values())
        fr = r.get("frequencies", {}).get("max_abs_rel_diff", float("nan"))
        ok = (abs(cs[worst]["vm_max_rel_diff"]) <= ACCEPT_VM and loc >= 1 - ACCEPT_VM
              and (fr <= ACCEPT_HZ or np.isnan(fr)))
        L.append(f"| {r['mesh']['size_m'] * 1e3:g} | {100 * cs[worst]['vm_max_rel_diff']:+.2f} % ({worst}) | "
                 f"{100 * loc:.1f} % | {100 * fr:.3f} % | {'yes' if ok else 'no'} |")
    same = max(abs(c["same_recovery"]["vm_max_rel_diff"]) for r in runs for c in r["cases"].values())
    L += ["", "Where a row is not met, the difference is the two codes' nodal stress recovery in curved "
          "elements, not their solutions: with CalculiX's recovery applied to the project's displacement "
          f"the maxima agree within {100 * same:.2f} % on every mesh, at the same node (the quadrature "
          "difference; last column of the next table), and the recovery difference shrinks with "
          "refinement (tables below). The peak sits on the pocket's edge with the bore or the "
          "outside (x = ±11.25 mm, the pocket's axial extreme), where neighbouring nodes carry "
          "nearly the same stress: two nodes of one hot spot can swap ranks between the codes.",
          "", "## Meshes", "", "| h (mm) | nodes | C3D10 elements | dofs | project assembly (s) | whole check (s) |",
         "|---|---|---|---|---|---|"]
    for r in runs:
        m = r["mesh"]
        L.append(f"| {m['size_m'] * 1e3:g} | {m['nodes']:,} | {m['elements']:,} | {m['dofs']:,} | "
                 f"{r['project_assembly_s']:.1f} | {r['total_s']:.0f} |")
    L += ["", "## Max von Mises: each code with its own stress recovery", "",
          "| case | h (mm) | project (MPa) | CalculiX (MPa) | difference | peak node project / CalculiX "
          "| project's peak at | CalculiX's peak at | distance (mm), modulo symmetry | CalculiX at "
          "project's peak / project at CalculiX's peak | same recovery: difference |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    cases = list(runs[0]["cases"])
    L += _case_rows(runs, cases, lambda c: (
        f"{c['vm_max_project_Pa'] / 1e6:.2f} | {c['vm_max_calculix_Pa'] / 1e6:.2f} | "
        f"{100 * c['vm_max_rel_diff']:+.2f} % | {c['node_project']} / {c['node_calculix']} | "
        f"{_where(c['position_project_m'])} | {_where(c['position_calculix_m'])} | "
        f"{1e3 * c['peak_distance_symmetric_m']:.2f} | {100 * c['calculix_at_project_peak_rel']:.1f} / "
        f"{100 * c['project_at_calculix_peak_rel']:.1f} % | "
        f"{100 * c['same_recovery']['vm_max_rel_diff']:+.3f} %"))
    L += ["", "'same recovery': CalculiX's nodal stress recovery (Gauss-point stresses extrapolated "
          "to the corners, mid-edge nodes the mean of their corners, averaged over the cells) applied "
          "to the project's displacement (`flexbearing.verification.calculix_check.extrapolated_nodal_stress`), "
          "against CalculiX: the difference of the two solutions alone. Distance modulo symmetry: "
          "the spin's peaks compared after the cage's 20-fold rotation and x-mirror. 'CalculiX at "
          "project's peak': CalculiX's von Mises at the project's peak node over its own maximum "
          "(100 % = the same hot spot; > 98 % = each peak inside the other's 2 % hot spot).", "",
          "## Fields", "", "| case | h (mm) | top-20 nodes: max vM difference | top-20: max tensor "
          "difference | whole field: stress (Frobenius) | largest vM difference / max vM | same recovery: "
          "top-20 vM | displacement (L2) | max u (µm) | reactions project / CalculiX (N, max) |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    L += _case_rows(runs, cases, lambda c: (
        f"{100 * c['top_vm_rel_diff_max']:.2f} % | {100 * c['top_tensor_rel_diff_max']:.2f} % | "
        f"{100 * c['stress_rel_diff_fro']:.2f} % | {100 * c['vm_abs_diff_max_rel']:.2f} % | "
        f"{100 * c['same_recovery']['top_vm_rel_diff_max']:.3f} % | {c['u_rel_diff_l2']:.1e} | "
        f"{1e6 * c['u_max_project_m']:.2f} | {np.abs(c['reactions_project_N']).max():.1e} / "
        f"{np.abs(c['reactions_calculix_N']).max():.1e}"))
    extra = [(r["mesh"]["size_m"], c) for r in runs for k, c in r["cases"].items() if k == "spin"]
    L += ["", "Spin: the project's inertia-relief solution (K u = f − M R a, R^T M u = 0) against its "
          "3-2-1 solution, stress difference (Frobenius): "
          + ", ".join(f"{c['inertia_relief_stress_rel_diff']:.1e} ({h * 1e3:g} mm)" for h, c in extra)
          + f"; centrifugal load Σ|f| = {extra[0][1]['load_abs_sum_N']:.0f} N. Pocket: the project's "
          "held-RBE3 solution (pocket 0 held, as `reduce --check`) against its equilibrated 3-2-1 "
          "form: " + ", ".join(f"{r['cases'][k]['held_vs_equilibrated_stress_rel_diff']:.0e}"
                               for r in runs for k in cases if k.startswith("pocket")) + "."]
    if len(runs) > 1:
        h = np.array([r["mesh"]["size_m"] for r in runs])
        L += ["", "How the difference shrinks: whole-field nodal stress difference (Frobenius, own "
              "recoveries) per mesh and its observed order p (difference ~ h^p, coarsest to finest "
              "mesh); the same-recovery difference is the quadrature's; the displacement's order:", "",
              "| case | " + " | ".join(f"{x * 1e3:g} mm" for x in h) + " | p stress | "
              + " | ".join(f"same recovery {x * 1e3:g} mm" for x in h) + " | p displacement |",
              "|---|" + "---|" * (2 * len(h) + 2)]
        for k in cases:
            d = np.array([r["cases"][k]["stress_rel_diff_fro"] for r in runs])
            q = np.array([r["cases"][k]["same_recovery"]["stress_rel_diff_fro"] for r in runs])
            du = np.array([r["cases"][k]["u_rel_diff_l2"] for r in runs])
            order = (lambda v: np.log(v[0] / v[-1]) / np.log(h[0] / h[-1]))
            L.append(f"| {k} | " + " | ".join(f"{100 * x:.2f} %" for x in d) + f" | {order(d):.1f} | "
                     + " | ".join(f"{100 * x:.3f} %" for x in q) + f" | {order(du):.1f} |")
    L += ["", "## Free–free frequencies", "", "| h (mm) | max difference, project default quadrature "
          "| max difference, project with ccx's 4-point rule | project solve (s) | CalculiX (s) |",
          "|---|---|---|---|---|"]
    for r in runs:
        f = r.get("frequencies")
        if f:
            L.append(f"| {r['mesh']['size_m'] * 1e3:g} | {100 * f['max_abs_rel_diff']:.3f} % | "
                     f"{100 * f['max_abs_rel_diff_quadrature2']:.5f} % | {f['project_solve_s']:.1f} | "
                     f"{f['calculix_wall_s']:.1f} |")
    for r in runs[:1] + runs[-1:] if len(runs) > 1 else runs:
        f = r.get("frequencies")
        if not f:
            continue
        L += ["", f"h = {r['mesh']['size_m'] * 1e3:g} mm:", "",
              "| mode | project (Hz) | CalculiX (Hz) | difference | project, 4-point rule (Hz) |",
              "|---|---|---|---|---|"]
        for i, (a, b, q) in enumerate(zip(f["project_hz"], f["calculix_hz"], f["project_quadrature2_hz"])):
            L.append(f"| {i + 7} | {a:.2f} | {b:.2f} | {100 * (b / a - 1):+.3f} % | {q:.2f} |")
    L += ["", "## Run times (s, one core each)", "", "| case | h (mm) | project solve | CalculiX (deck read, "
          "solve, output) |", "|---|---|---|---|"]
    L += _case_rows(runs, cases, lambda c: f"{c['project_solve_s']:.1f} | {c['calculix_wall_s']:.1f}")
    return "\n".join(L) + "\n"


def _case_rows(runs, cases, cells) -> list[str]:
    """One table row per load case and mesh: '| case | h (mm) | cells(case result) |'."""
    return [f"| {k} | {r['mesh']['size_m'] * 1e3:g} | {cells(r['cases'][k])} |" for k in cases for r in runs]


if __name__ == "__main__":
    raise SystemExit(main())
