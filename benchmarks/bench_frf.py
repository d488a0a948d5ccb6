"""Frequency response of the paper cage to a harmonic pocket force: full FE vs the reduced cage.

Builds (and caches) the reduced cage of flexbearing.mesh.cage_geometry.PAPER_CAGE at the default mesh
(P3, 5 mm, RBE3, 30 fixed-interface modes, centrifugal vector: schema v3), then compares the
elastic (mean-axis) displacement of the loaded pocket's interface node under unit
circumferential, radial and axial pocket forces (flexbearing.verification.frequency_response.compare):
full FE direct solve (K - w^2 M) u = C_l^T F per frequency (undamped, beta = 0: real LU; the
grid keeps +-2 % away from every natural frequency of both models) vs the reduced cage with
(a) 26 modes, (b) 26 modes + residual static correction of the others, (c) all modes dynamic.
Grid: 0 ... the 10th elastic natural frequency, n equally spaced points minus the exclusions;
w = 0 is the free–free inertia-relief static response.
Writes benchmarks/results/frf_paper.json.

    nice .venv/bin/python benchmarks/bench_frf.py [--n-freq 40] [--quiet]
    # with the runtime's damping, resonance peaks included:
    nice .venv/bin/python benchmarks/bench_frf.py --beta 1e-5 --exclude 0 --at-resonances \
        --output benchmarks/results/frf_paper_damped.json
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP

RESULTS = Path(__file__).parent / "results" / "frf_paper.json"


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--n-freq", type=int, default=40)
    ap.add_argument("--exclude", type=float, default=0.02)
    ap.add_argument("--load-node", type=int, default=1)
    ap.add_argument("--n-fixed", type=int, default=30, help="fixed-interface modes of the CB basis")
    ap.add_argument("--n-keep", type=int, default=DEFAULT_N_KEEP, help="modes kept dynamic (rigid included)")
    ap.add_argument("--beta", type=float, default=0.0,
                    help="stiffness-proportional damping D = beta K (s); the runtime's default is 1e-5")
    ap.add_argument("--at-resonances", action="store_true",
                    help="add the full model's natural frequencies to the grid (use with --beta > 0 --exclude 0)")
    ap.add_argument("--output", type=Path, default=RESULTS)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    from tqdm import tqdm
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    import flexbearing.mesh.cage_mesh as cm
    from flexbearing.fem_cage.reduction import build
    from flexbearing.verification.frequency_response import compare, frequency_grid
    t0 = time.perf_counter()
    path, red, _ = build(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                         "rbe3", args.n_fixed, quiet=args.quiet, checks=False, degree=cm.DEFAULT_DEGREE)
    t_build = time.perf_counter() - t0
    from flexbearing.fem_cage.modes import free_free_modes
    from flexbearing.fem_cage.craig_bampton import scipy_to_petsc
    t0 = time.perf_counter()
    f_all, _ = free_free_modes(scipy_to_petsc(red["K"]), scipy_to_petsc(red["M"]), 6 + 12)
    t_modes = time.perf_counter() - t0
    n_grid = len(frequency_grid(f_all[6 + 9], list(f_all[6:]) + list(red["frequency_hz"][6:18]),
                                args.n_freq, args.exclude)) + (10 if args.at_resonances else 0)
    bar = tqdm(total=n_grid, desc="full FE frequency response", disable=args.quiet)
    t0 = time.perf_counter()
    r = compare(red, args.load_node, args.n_keep, 10, args.n_freq, args.exclude, args.beta,
                full_hz=f_all[6:], progress=bar, at_resonances=args.at_resonances)
    bar.close()
    r["timings_s"] = {"build": t_build, "full_modes": t_modes,
                      "frf_total": time.perf_counter() - t0}
    r["file"] = str(path)
    r["n_dofs"] = int(red["n_dofs"])
    r["mesh"] = {"size_m": cm.DEFAULT_MESH_SIZE, "pocket_size_m": cm.DEFAULT_POCKET_SIZE,
                 "order": cm.DEFAULT_ORDER, "degree": cm.DEFAULT_DEGREE}
    r["n_fixed"], r["n_keep"] = args.n_fixed, args.n_keep
    args.output.parent.mkdir(exist_ok=True)
    args.output.write_text(json.dumps(r, indent=1, default=float))
    if not args.quiet:
        for k in ("a_truncated", "b_truncated_residual", "c_full_basis"):
            print(k, "max rel error", r[f"max_rel_error_{k}"], r[f"worst_{k}"],
                  "| static floor:", r.get(f"max_rel_error_static_floor_{k}"))
        print("total response (b):", r["max_rel_error_b_total_response"])


if __name__ == "__main__":
    main()
