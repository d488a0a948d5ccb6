"""Cost per call of the exact max-von-Mises evaluator (fem_cage.von_mises) on the paper cage.

Loads the paper cage's reduced file from the cache (builds it with `flexbearing reduce` defaults
if missing), then for n_keep = 26 (the paper's count, rigid included) and for the full basis:
1000 random modal vectors — equal modal energy q_k ~ N(0, 1/omega_k^2) (what a dynamic
response looks like) and unit N(0, 1) (worst case for the bounds) — checks the result against
brute force (must be identical) and times both (best of 5 loops, per call, one core).
Both exact kernels: MaxVonMises (two-level leaf bound, the default) and MaxVonMisesSorted
(sorted global bound + block bound). Timer: CPU time of this process (the machine is shared).
Writes benchmarks/results/reduce_von_mises.json.

    .venv/bin/python benchmarks/bench_von_mises.py [--quiet]
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results" / "reduce_von_mises.json"


def paper_file():
    from mesh.cage_geometry import PAPER_CAGE
    import mesh.cage_mesh as cm
    from fem_cage import reduced_cage as rcf
    key = rcf.cache_key(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                        rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, cm.DEFAULT_DEGREE)
    path = rcf.find_cached(key)
    if path is None:
        from fem_cage.reduction import build
        path, _, _ = build(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                           rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, quiet=False, checks=False,
                           degree=cm.DEFAULT_DEGREE)
    return path


def per_call(f, Q, repeats=5):
    f(Q[0])
    best = np.inf
    for _ in range(repeats):
        t = time.process_time()
        for q in Q:
            f(q)
        best = min(best, time.process_time() - t)
    return best / len(Q)


def main(quiet=False):
    from fem_cage import reduced_cage as rcf
    from fem_cage.von_mises import MaxVonMises, MaxVonMisesSorted
    rc = rcf.read(paper_file())
    rng = np.random.default_rng(0)
    rows = []
    for n_keep in (26, rc.n_modes):
        t = rc.truncate(n_keep)
        w = np.where(t.omega > 0, 1 / np.maximum(t.omega, 1e-300), 0.0)
        for name, make in (("leaves", lambda: MaxVonMises(t.stress_modes, mode_scale=np.where(w > 0, w, 1.0))),
                           ("sorted", lambda: MaxVonMisesSorted(t.stress_modes))):
            t0 = time.perf_counter()
            ev = make()
            setup = time.perf_counter() - t0
            for kind, scale in (("energy", w), ("unit", (t.omega > 0).astype(float)), ("static", w ** 2)):
                Q = rng.standard_normal((1000, n_keep)) * scale
                mism = sum(ev(q)[0] != ev.brute_force(q)[0] for q in Q)
                vis = np.array([ev.visits(q) for q in Q])
                row = {"n_keep": n_keep, "evaluator": name, "q": kind, "setup_s": setup,
                       "n_vertices": int(t.stress_modes.shape[0]), "mismatches_vs_brute": int(mism),
                       "fast_us": 1e6 * per_call(ev, Q), "brute_us": 1e6 * per_call(ev.brute_force, Q[:200], 3),
                       "mean_exact_node_evaluations": float(vis[:, 1].mean()),
                       "mean_bound_evaluations": float(vis[:, 0].mean())}
                rows.append(row)
                if not quiet:
                    print(row)
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps({"file": str(rcf.read(paper_file()).attrs.get("content_hash")),
                                   "rows": rows}, indent=1))
    return rows


if __name__ == "__main__":
    main("--quiet" in sys.argv)
