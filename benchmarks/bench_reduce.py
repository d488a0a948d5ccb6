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

The design loop (issue 32 item 4): a new geometry to a reduced cage, without the verification
checks — the paper cage at the default mesh, meshed into an empty cache (gmsh is paid) and
reduced, in a fresh process per repetition: wall time of each phase, CPU time (user + sys),
peak RSS of the process, the file's size per dataset and the time to read it back.
--code DIR runs the same in another checkout (e.g. a worktree of the code before), interleaved
with this one, repetition by repetition (the machine is shared: compare minima). --compare BEFORE
AFTER checks two reduced cage files of the same cage for equal results: frequencies, and the max
von Mises of the full basis' static answer to the stress-convergence study's load cases
(flexbearing.verification.stress_study: spin, a pocket force circumferential / axial / radial on
pocket 5, a land force) — basis-invariant numbers, so modes that rotate inside a double root
do not count as a difference. Writes benchmarks/results/reduce_design_loop.json.

--openblas DIR adds this checkout with an unpacked OpenBLAS (nothing installed) first on
LD_LIBRARY_PATH, 1 and 2 threads. --compare also gives the bound on the change of each case's max
von Mises by the 16-bit storage of AFTER (schema 6). --search-setup FILE times the run's
stress-search setup from a reduced cage file (first run: build and write; later runs: from the
search file) and gives the search file's size.

    nice .venv/bin/python benchmarks/bench_reduce.py --design-loop [--repeat 3] [--code DIR]
        [--openblas DIR]
    .venv/bin/python benchmarks/bench_reduce.py --compare BEFORE.h5 AFTER.h5
    .venv/bin/python benchmarks/bench_reduce.py --search-setup FILE.h5
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results" / "reduce_paper.json"
LOOP_RESULTS = Path(__file__).parent / "results" / "reduce_design_loop.json"

# one repetition of the design loop, run as `python -c` in a fresh process (its own peak RSS and
# CPU time) with FLEXBEARING_CACHE an empty folder; prints one JSON line
_LOOP_CHILD = r"""
import json, os, resource, sys, time
t0 = time.perf_counter()
from flexbearing.mesh.cage_geometry import PAPER_CAGE
import flexbearing.mesh.cage_mesh as cm
from flexbearing.fem_cage.reduction import build
from flexbearing.fem_cage import reduced_cage as rcf
t_import = time.perf_counter() - t0
t = time.perf_counter()
cm.cached_cage_mesh(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE)
t_mesh = time.perf_counter() - t
t = time.perf_counter()
path, red, summary = build(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER,
                           cm.DEFAULT_POCKET_SIZE, "rbe3", 30, quiet=True, checks=False,
                           degree=cm.DEFAULT_DEGREE)
t_build = time.perf_counter() - t
ru = resource.getrusage(resource.RUSAGE_SELF)
import h5py
sizes = {}
with h5py.File(path) as f:
    f.visititems(lambda n, o: sizes.__setitem__(n, int(o.id.get_storage_size()))
                 if isinstance(o, h5py.Dataset) else None)
t = time.perf_counter()
rcf.read(path)
t_read = time.perf_counter() - t
# the BLAS that ran (the code before has no flexbearing.common.blas: read the map here)
blas = sorted({l.split()[-1] for l in open("/proc/self/maps")
               if "libblas" in l.split()[-1] or "openblas" in l.split()[-1]})
print(json.dumps({"blas": blas, "import_s": t_import, "mesh_s": t_mesh, "build_s": t_build,
                  "new_geometry_s": t_mesh + t_build, "timings": red["timings"],
                  "cpu_user_s": ru.ru_utime, "cpu_sys_s": ru.ru_stime,
                  "peak_rss_MB": ru.ru_maxrss / 1024, "file_MB": os.path.getsize(path) / 1e6,
                  "dataset_MB": {k: v / 1e6 for k, v in sizes.items()}, "read_s": t_read,
                  "solver": red["info"], "schema_version": rcf.SCHEMA_VERSION}))
"""


def design_loop_once(code: Path | None, extra_env: dict | None = None) -> dict:
    """One repetition of the design loop in a fresh process and an empty cache (the module
    docstring); code: another checkout to run instead of this one; extra_env: variables set for
    the child (e.g. LD_LIBRARY_PATH to an unpacked OpenBLAS)."""
    import os
    import subprocess
    import sys
    import tempfile
    env = dict(os.environ, **(extra_env or {}))
    with tempfile.TemporaryDirectory(prefix="fb-loop-") as cache:
        env["FLEXBEARING_CACHE"] = cache
        if code is not None:
            env["PYTHONPATH"] = str(code)
        out = subprocess.run([sys.executable, "-c", _LOOP_CHILD], env=env, check=True,
                             capture_output=True, text=True, cwd=str(code or Path.cwd()))
    return json.loads(out.stdout.strip().splitlines()[-1])


def static_coordinates(path) -> dict:
    """{case: full modal vector q} of the full basis' quasi-static answer to each load case of the
    stress-convergence study (static_max_von_mises)."""
    import numpy as np
    from flexbearing.fem_cage import reduced_cage as rcf
    from flexbearing.verification import stress_study as ss
    rc = rcf.read(path)
    Z = rc.interface_modes.shape[0]
    theta = 2 * np.pi * ss.POCKET / Z
    cases = {"spin": (None, rcf.centrifugal_modal_load(rc.invariants, ss.SPIN_RAD_S)),
             "land": (None, rc.guide_modal_loads @ np.array([0.0, ss.LAND_FORCE_N, 0.0]))}
    for kind in ("circ", "axial", "radial"):
        F = np.zeros((Z, 6))
        F[ss.POCKET, :3] = ss.POCKET_FORCE_N * ss.pocket_direction(theta, kind)
        cases[f"pocket_{kind}"] = (F, None)
    out = {}
    for name, (F, g) in cases.items():
        q = np.zeros(rc.n_modes)
        q[6:] = rcf.static_correction(rc.interface_modes, rc.omega,
                                      np.zeros((Z, 6)) if F is None else F, 6, g)
        out[name] = q
    return out


def quantisation_bounds(path) -> dict:
    """{case: bound (Pa) on the change of the max von Mises by the 16-bit storage}
    (flexbearing.fem_cage.reduced_cage.quantisation_bound) for the static_coordinates cases of a
    schema-6 file; {} for older files."""
    import h5py
    from flexbearing.fem_cage import reduced_cage as rcf
    with h5py.File(path) as f:
        name = "stress/modes" + rcf.SCALE_SUFFIX
        if name not in f:
            return {}
        scale = f[name][()]
    return {k: rcf.quantisation_bound(scale, q) for k, q in static_coordinates(path).items()}


def search_setup(path, n_keep: int = 26) -> dict:
    """The run's stress-search setup from a reduced cage file: read the file, build the search
    and write its cache file (first run of a geometry), then set it up again from that file
    (every later run); seconds, and the search file's size."""
    import os
    import tempfile
    from flexbearing.coupling.flexible_cage import StressRecovery
    from flexbearing.fem_cage import reduced_cage as rcf
    t = time.perf_counter()
    rc = rcf.read(path)
    t_read = time.perf_counter() - t
    StressRecovery(rc, n_keep, None)                   # compiles and warms what both paths share
    with tempfile.TemporaryDirectory(prefix="fb-search-") as d:
        cache = Path(d) / "search.npz"
        t = time.perf_counter()
        StressRecovery(rc, n_keep, cache)
        t_first = time.perf_counter() - t
        t = time.perf_counter()
        StressRecovery(rc, n_keep, cache)
        t_again = time.perf_counter() - t
        size = os.path.getsize(cache)
    return {"read_reduced_cage_s": t_read, "first_run_build_and_write_s": t_first,
            "later_run_from_file_s": t_again, "search_file_MB": size / 1e6,
            "reduced_cage_file_MB": os.path.getsize(path) / 1e6}


def static_max_von_mises(path) -> dict:
    """Max nodal von Mises (Pa) of the full basis' quasi-static answer to each load case of the
    stress-convergence study (flexbearing.verification.stress_study: constants and directions),
    from the reduced cage file alone: q_k = (Phi_b,k^T F + g_k) / omega_k^2 for every elastic mode
    (flexbearing.fem_cage.reduced_cage.static_correction), sigma = S q."""
    import numpy as np
    from flexbearing.fem_cage import reduced_cage as rcf
    from flexbearing.fem_cage.stress_modes import von_mises
    rc = rcf.read(path)
    return {name: float(von_mises(np.einsum("nsm,m->ns", rc.stress_modes, q)).max())
            for name, q in static_coordinates(path).items()}


def compare_files(before, after) -> dict:
    """Frequencies and static max von Mises (static_max_von_mises) of two files of the same cage."""
    import numpy as np
    from flexbearing.fem_cage import reduced_cage as rcf
    a, b = rcf.read(before), rcf.read(after)
    fa, fb = a.frequency_hz[6:], b.frequency_hz[6:]
    va, vb = static_max_von_mises(before), static_max_von_mises(after)
    return {"frequency_max_rel_diff": float(np.max(np.abs(fb - fa) / fa)),
            "frequency_hz_first_elastic": [float(fa[0]), float(fb[0])],
            "von_mises_Pa": {k: [va[k], vb[k]] for k in va},
            "von_mises_max_rel_diff": max(abs(vb[k] - va[k]) / va[k] for k in va),
            # bound on the change by the 16-bit storage of AFTER, relative (schema 6 files)
            "quantisation_bound_rel": {k: v / vb[k] for k, v in quantisation_bounds(after).items()},
            "rigid_mass_rel_diff": abs(b.invariants["mass"] - a.invariants["mass"]) / a.invariants["mass"]}


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--coupling", nargs="+", default=["rbe3"])
    ap.add_argument("--n-fixed", nargs="+", type=int, default=[30])
    ap.add_argument("--no-augmentation", dest="augment", action="store_false",
                    help="no land-load and no inertia-relief vectors in the basis")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--design-loop", action="store_true",
                    help="time a new geometry to a reduced cage, no checks (module docstring)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--code", type=Path, default=None,
                    help="with --design-loop: also time this checkout, interleaved")
    ap.add_argument("--openblas", type=Path, default=None, metavar="DIR",
                    help="with --design-loop: also time this checkout with DIR (an unpacked "
                         "libopenblas0-pthread's openblas-pthread folder) first on LD_LIBRARY_PATH, "
                         "1 and 2 threads, interleaved")
    ap.add_argument("--reference-blas", action="store_true",
                    help="with --design-loop: also time both checkouts on Debian's reference "
                         "(netlib) BLAS and LAPACK, put first on LD_LIBRARY_PATH, interleaved")
    ap.add_argument("--key", default="design_loop",
                    help="the key of reduce_design_loop.json to write (default: design_loop for "
                         "--design-loop, compare for --compare)")
    ap.add_argument("--compare", nargs=2, type=Path, metavar=("BEFORE", "AFTER"))
    ap.add_argument("--search-setup", type=Path, metavar="REDUCED_CAGE_H5",
                    help="time the run's stress-search setup from this file (search_setup)")
    args = ap.parse_args(argv)
    if args.search_setup:
        out = json.loads(LOOP_RESULTS.read_text()) if LOOP_RESULTS.exists() else {}
        r = search_setup(args.search_setup)
        print(json.dumps(r, indent=1))
        out.setdefault("search_setup", {})[str(args.search_setup)] = r
        LOOP_RESULTS.write_text(json.dumps(out, indent=1, default=float))
        return
    if args.compare or args.design_loop:
        out = json.loads(LOOP_RESULTS.read_text()) if LOOP_RESULTS.exists() else {}
        if args.compare:
            key = "compare" if args.key == "design_loop" else args.key
            out[key] = compare_files(*args.compare)
            out[key]["files"] = [str(p) for p in args.compare]
            print(json.dumps(out[key], indent=1))
        if args.design_loop:
            # one BLAS thread for every child: the code before did not set it (flexbearing/__init__.py)
            one = {"OPENBLAS_NUM_THREADS": "1"}
            configs = [("other", args.code, one), ("this", None, one)]
            if args.reference_blas:
                from flexbearing.common.blas import DEBIAN_REFERENCE_BLAS_DIRS
                ref = {"LD_LIBRARY_PATH": ":".join(DEBIAN_REFERENCE_BLAS_DIRS)}
                configs += [("other_refblas", args.code, ref), ("this_refblas", None, ref)]
            if args.openblas:
                configs += [(f"this_openblas{n}", None, {"LD_LIBRARY_PATH": str(args.openblas),
                                                        "OPENBLAS_NUM_THREADS": str(n)})
                            for n in (1, 2)]
            runs = {which: [] for which, _, _ in configs}
            for _ in range(args.repeat):
                for which, code, extra in configs:
                    if which.startswith("other") and code is None:
                        continue
                    r = design_loop_once(code, extra)
                    r["load_average"] = __import__("os").getloadavg()
                    runs[which].append(r)
                    print(which, f"new geometry {r['new_geometry_s']:.1f} s (mesh {r['mesh_s']:.1f}, "
                          f"reduce {r['timings']['reduce_total_s']:.1f}), cpu "
                          f"{r['cpu_user_s'] + r['cpu_sys_s']:.1f} s, peak {r['peak_rss_MB']:.0f} MB, "
                          f"file {r['file_MB']:.1f} MB", flush=True)
            out[args.key] = dict(runs, other_code=None if args.code is None else str(args.code),
                                      openblas=None if args.openblas is None else str(args.openblas))
        LOOP_RESULTS.parent.mkdir(exist_ok=True)
        LOOP_RESULTS.write_text(json.dumps(out, indent=1, default=float))
        return
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
