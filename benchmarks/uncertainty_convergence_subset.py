"""Convergence of the uncertainty study's steady solver on a random subset of its (point, case) runs.

The full study (scenes/slip_rate_unknowns.toml: 64 points x 15 cases = 960 steady solves,
flexbearing.studies.uncertainty.steady_case_slip) takes tens of minutes on 2 workers; this draws N of
its runs at random (numpy default_rng(seed)) and solves them one after the other, printing the
converged count, the reasons of the others and the CPU time. Usage:

    python benchmarks/uncertainty_convergence_subset.py [N] [seed] [out.jsonl]
"""
import json
import sys
import time

import numpy as np

import flexbearing  # noqa: F401
from flexbearing.studies.uncertainty import load_unknowns, sample_points, steady_case_slip
from flexbearing.studies.validation.slip_rate import slip_rate_cases


def main(n=64, seed=42, out=None):
    study = load_unknowns("scenes/slip_rate_unknowns.toml")
    points = sample_points(study)
    cases = slip_rate_cases()
    pairs = [(p, c) for p in range(len(points)) for c in range(len(cases))]
    pick = np.random.default_rng(seed).choice(len(pairs), size=min(n, len(pairs)), replace=False)
    rows, t0 = [], time.time()
    for k in sorted(pick):
        p, c = pairs[k]
        row = steady_case_slip(points[p], cases[c])
        row["point"] = p
        rows.append(row)
        print(f"point {p:2d} case {row['case']:2d}: converged={row['converged']} cpu {row['cpu_s']:.1f} s "
              f"{row['reason'][:140]}", flush=True)
        if out:
            with open(out, "a") as f:
                f.write(json.dumps(row) + "\n")
    conv = sum(r["converged"] for r in rows)
    print(f"converged {conv}/{len(rows)}; cpu {sum(r['cpu_s'] for r in rows):.0f} s; wall {time.time() - t0:.0f} s")


if __name__ == "__main__":
    a = sys.argv[1:]
    main(int(a[0]) if a else 64, int(a[1]) if len(a) > 1 else 42, a[2] if len(a) > 2 else None)
