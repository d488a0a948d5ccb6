"""Reduction of the paper cage: wall time of each stage and the verification numbers.

For each (coupling, n_fixed) asked (default: rbe3 with 30 fixed-interface modes, the
`flexbearing reduce` default), builds the reduced cage of flexbearing.mesh.cage_geometry.PAPER_CAGE at the
default mesh and runs every check of flexbearing.fem_cage.reduction_check.run_checks: static exactness (full basis
and 26-mode truncation), stress recovery, first 10 elastic free–free frequencies vs the full
model, mass properties vs direct integration, max-von-Mises evaluator vs brute force and its cost,
the free–free static centrifugal and land (guide-surface) load responses vs the full FE.
--no-augmentation builds the schema-3-like basis (centrifugal vector only, no land-load and no
inertia-relief vectors) to show what the augmentation buys (key suffix "_noaug").
Work–precision: time of the reduction vs frequency error, as n_fixed grows.
Writes benchmarks/results/reduce_paper.json (one entry per configuration).

    nice .venv/bin/python benchmarks/bench_reduce.py [--coupling rbe3 rbe2] [--n-fixed 30 60]
        [--no-augmentation] [--quiet]
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results" / "reduce_paper.json"


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--coupling", nargs="+", default=["rbe3"])
    ap.add_argument("--n-fixed", nargs="+", type=int, default=[30])
    ap.add_argument("--no-augmentation", dest="augment", action="store_false",
                    help="no land-load and no inertia-relief vectors in the basis")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    import flexbearing.mesh.cage_mesh as cm
    from flexbearing.fem_cage.reduction import build
    old = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    for coupling in args.coupling:
        for n_fixed in args.n_fixed:
            t = time.perf_counter()
            path, red, summary = build(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER,
                                       cm.DEFAULT_POCKET_SIZE, coupling, n_fixed,
                                       quiet=args.quiet, checks=True, degree=cm.DEFAULT_DEGREE,
                                       guide_loads=args.augment, inertia_relief=args.augment)
            summary["wall_time_total_s"] = time.perf_counter() - t
            summary["mesh"] = {"size_m": cm.DEFAULT_MESH_SIZE, "pocket_size_m": cm.DEFAULT_POCKET_SIZE,
                               "order": cm.DEFAULT_ORDER, "degree": cm.DEFAULT_DEGREE}
            summary["file"] = str(path)
            old[f"{coupling}_nfixed{n_fixed}" + ("" if args.augment else "_noaug")] = summary
            RESULTS.parent.mkdir(exist_ok=True)
            RESULTS.write_text(json.dumps(old, indent=1, default=float))
            if not args.quiet:
                s = summary
                print(coupling, n_fixed, "static full/26:", s["static"]["max_rel_error_full"],
                      s["static"]["max_rel_error_truncated"], "| freq err:",
                      s["frequencies"]["max_rel_error_vs_full"], "| stress:",
                      s["stress"]["rel_error_full"], "| vm us:",
                      s["von_mises_evaluator"]["energy"]["cost_per_call_us"], "| land load "
                      "disp/vm full:", s["guide"]["displacement_rel_error_full"],
                      s["guide"]["vm_max_rel_error_full"])


if __name__ == "__main__":
    main()
