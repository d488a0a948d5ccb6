"""Curved-element quality of every cage preset at every mesh size the project uses, before and
after the repair (flexbearing.mesh.quality, flexbearing.mesh.cage_mesh._validate_and_repair), and what gmsh's own
high-order optimisers do with the paper cage's default-size mesh.

Sizes: the mesh study's levels (flexbearing.fem_cage.mesh_study.DEFAULT_STUDY), the calibration mesh
(flexbearing.fem_cage.calibrate.CALIBRATION_MESH), the default, and the former 5 mm default. For each: cells,
inverted cells (det J <= 0 at a node, lattice or quadrature point), cells below the Jacobian-ratio
bound, the worst ratio and scaled Jacobian, as gmsh curves them and after the repair, the cells
the repair flattened and how far it moved nodes off the surface.

    .venv/bin/python benchmarks/bench_mesh_quality.py [--quick]

Writes benchmarks/results/mesh_quality.{md,json}. Several minutes (the finest levels dominate).
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

RESULTS = Path(__file__).parent / "results"


def levels(quick: bool):
    from flexbearing.fem_cage.calibrate import CALIBRATION_MESH
    from flexbearing.fem_cage.mesh_study import DEFAULT_STUDY
    from flexbearing.mesh.cage_mesh import DEFAULT_MESH_SIZE, DEFAULT_POCKET_SIZE, DEFAULT_ORDER
    lv = {(s * 1e-3, p * 1e-3, o) for s, p, o, _ in DEFAULT_STUDY}
    lv |= {tuple(CALIBRATION_MESH[:3]), (DEFAULT_MESH_SIZE, DEFAULT_POCKET_SIZE, DEFAULT_ORDER),
           (5e-3, 5e-3, 2)}
    lv = sorted(lv, reverse=True)
    return [l for l in lv if l[1] >= 4e-3] if quick else lv


def gmsh_optimisers(work: Path) -> list[dict]:
    """The paper cage at 5 mm as gmsh curves it, then each of gmsh's high-order optimisers, run in
    the meshing session (with the CAD model, as gmsh needs to move nodes along the surfaces)."""
    import gmsh
    from flexbearing.mesh import quality as Q
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh.cage_mesh import _build_model
    rows = []
    for method in ("HighOrder", "HighOrderElastic", "HighOrderFastCurving"):
        gmsh.initialize()
        note = "ran"
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add("cage")
            _build_model(PAPER_CAGE, 5e-3, 2, 5e-3)
            try:
                gmsh.model.mesh.optimize(method)
            except Exception as exc:             # gmsh reports a failed optimisation this way
                note = f"failed: {exc}"
            out = work / f"paper5_{method}.msh"
            gmsh.write(str(out))
        finally:
            gmsh.finalize()
        s = Q.mesh_file_quality(out).summary()
        rows.append({"method": method, "note": note, "n_inverted": s["n_inverted"],
                     "min_jacobian_ratio": s["min_jacobian_ratio"], "n_below_bound": s["n_below_bound"]})
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="coarse levels only")
    ap.add_argument("--optimisers-only", action="store_true",
                    help="only redo gmsh's optimisers, keep the levels of the last full run")
    args = ap.parse_args(argv)
    from flexbearing.mesh.cage_geometry import PAPER_CAGE, CALIBRATED_CAGE, TABLE8_EQUIVALENT_CAGE
    from flexbearing.mesh.cage_mesh import build_cage_mesh, mesh_quality_of
    from flexbearing.mesh import quality as Q
    presets = {"paper": PAPER_CAGE, "calibrated": CALIBRATED_CAGE, "table8": TABLE8_EQUIVALENT_CAGE}
    rows = []
    t0 = time.perf_counter()
    suffix = "_quick" if args.quick else ""
    if args.optimisers_only:
        rows = json.loads((RESULTS / f"mesh_quality{suffix}.json").read_text())["levels"]
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name, g in ({} if args.optimisers_only else presets).items():
            for size, pocket, order in levels(args.quick):
                t = time.perf_counter()
                path = build_cage_mesh(g, size, order, work / f"{name}.msh", pocket)
                rep = mesh_quality_of(path)
                after = Q.mesh_file_quality(path).summary()       # read back from the file
                before = rep["repair"]["quality_before"]
                rows.append({"preset": name, "size_m": size, "pocket_size_m": pocket, "order": order,
                             "n_cells": after["n_cells"], "before": before, "after": after,
                             "n_cells_flattened": rep["repair"]["n_cells_flattened"],
                             "max_node_shift_m": rep["repair"]["max_node_shift_m"],
                             "mesh_s": time.perf_counter() - t})
                print(f"{name:10s} {size * 1e3:4g}/{pocket * 1e3:4g} mm order {order}: inverted "
                      f"{before['n_inverted']} -> {after['n_inverted']}, min ratio "
                      f"{before['min_jacobian_ratio']:+.3f} -> {after['min_jacobian_ratio']:+.3f}", flush=True)
        opt = gmsh_optimisers(work)
    L = ["# Curved-element quality of the cage meshes, before and after the repair", "",
         "`.venv/bin/python benchmarks/bench_mesh_quality.py` (flexbearing.mesh.quality; the repair in "
         "flexbearing.mesh.cage_mesh._validate_and_repair). Inverted: det J <= 0 somewhere (nodes, cubic lattice, "
         "P3 quadrature points; the Bernstein lower bound agrees). Ratio: min det J / |det J(centroid)|, "
         f"bound {Q.MIN_JACOBIAN_RATIO:g} (measured in cage_stress_convergence.md). Scaled Jacobian: of the "
         "straight corner tetrahedron (shape; the repair does not change it). 'After' is read back from "
         "the written file.", "",
         "| preset | size / pocket size (mm) | order | cells | inverted before → after | below bound before → after "
         "| min ratio before → after | min scaled Jacobian | cells flattened | max node shift (µm) |",
         "|---|---|---:|---:|---|---|---|---:|---:|---:|"]
    for r in rows:
        b, a = r["before"], r["after"]
        L.append(f"| {r['preset']} | {r['size_m'] * 1e3:g} / {r['pocket_size_m'] * 1e3:g} | {r['order']} | "
                 f"{r['n_cells']:,} | {b['n_inverted']} → {a['n_inverted']} | {b['n_below_bound']} → "
                 f"{a['n_below_bound']} | {b['min_jacobian_ratio']:+.3f} → {a['min_jacobian_ratio']:+.3f} | "
                 f"{a['min_scaled_jacobian']:.3f} | {r['n_cells_flattened']} | {r['max_node_shift_m'] * 1e6:.0f} |")
    L += ["", "gmsh 4.8's own high-order optimisers on the paper cage at 5 mm (2 inverted cells as curved):", "",
          "| gmsh.model.mesh.optimize | result | inverted | below bound | min ratio |", "|---|---|---:|---:|---:|"]
    for o in opt:
        L.append(f"| {o['method']} | {o['note']} | {o['n_inverted']} | {o['n_below_bound']} | "
                 f"{o['min_jacobian_ratio']:+.3f} |")
    L.append("")
    md = "\n".join(L)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"mesh_quality{suffix}.md").write_text(md)
    (RESULTS / f"mesh_quality{suffix}.json").write_text(json.dumps(
        {"levels": rows, "gmsh_optimisers": opt, "wall_time_s": time.perf_counter() - t0}, indent=1))
    print(md)


if __name__ == "__main__":
    main()
