"""Integrator steps of 5 ms at constant low speeds against the 14,000 rpm run (issue 21, item 3).

The paper bearing and loads (Fa 55 kN, Fr 4 kN, rigid cage, oil and model defaults, tolerance
1e-6), started from flexbearing.multibody.initial at each constant inner-ring speed and integrated for
`--duration` (5 ms) with the run's integrator (flexbearing.multibody.integrator.advance, sample by sample at
1e-4 s). Reported per speed: accepted and rejected steps, CPU time of the integration
(time.process_time), mean step, and the ratio of steps to the 14,000 rpm run. The issue's target:
0–500 rpm within 10x the steps of 14,000 rpm. The code under test is the one on PYTHONPATH, so the
same script measures a checkout of an earlier commit.

    .venv/bin/python benchmarks/bench_low_speed.py [--rpm 0,1,100,500,1000,14000] [--json OUT]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, os.environ.get("PYTHONPATH", "").split(os.pathsep)[0] or str(ROOT))

from flexbearing.multibody import integrator as I  # noqa: E402
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL  # noqa: E402
from flexbearing.multibody.initial import initial_state  # noqa: E402
from flexbearing.multibody.model import build_model  # noqa: E402

FA, FR = 55e3, 4e3


def steps_at(model, rpm: float, duration: float, tol: float = 1e-6, dt: float = 1e-4) -> dict:
    w = rpm * math.pi / 30.0
    sp = np.array([[0.0, w]])
    ld = np.array([[0.0, FA, 0.0, -FR]])
    imp = np.zeros((0, 6))
    y = initial_state(model, w, FA, FR, load=(FA, 0.0, -FR))
    ws = I.Workspace(model)
    t, h, steps, rej = 0.0, 1e-7, 0, 0
    c0 = time.process_time()
    for k in range(1, int(round(duration / dt)) + 1):
        y, t, h, a, r = I.advance(model, y, t, k * dt, sp, ld, imp, tol, h, ws)
        steps += a
        rej += r
    cpu = time.process_time() - c0
    return {"rpm": rpm, "steps": steps, "rejected": rej, "cpu_s": round(cpu, 2), "mean_step_s": duration / steps}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rpm", default="0,1,100,500,1000,14000")
    ap.add_argument("--duration", type=float, default=5e-3)
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    model = build_model(PAPER_BEARING, PAPER_OIL, {})
    steps_at(model, 14000.0, 2e-4)                      # compile / load the numba cache
    rows = []
    for rpm in [float(x) for x in a.rpm.split(",")]:
        rows.append(steps_at(model, rpm, a.duration))
        print(json.dumps(rows[-1]), flush=True)
    ref = next((r["steps"] for r in rows if r["rpm"] == 14000.0), None)
    for r in rows:
        r["steps_vs_14000rpm"] = round(r["steps"] / ref, 2) if ref else None
    res = {"duration_s": a.duration, "load_N": [FA, FR], "tol": 1e-6, "rows": rows,
           "load_avg": round(os.getloadavg()[0], 1), "date": time.strftime("%Y-%m-%d %H:%M:%S")}
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=2) + "\n")
    return res


if __name__ == "__main__":
    main()
