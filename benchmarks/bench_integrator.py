"""Work–precision of the time integrators on the paper's steady case (why DOPRI5 is the default).

For each method (DOPRI5 5(4), Bogacki–Shampine 3(2)) and tolerance, integrate `--duration` s of
the paper's steady scene (14,000 rpm, Fa 55 kN, Fr 4 kN, full model) from the quasi-static start
and compare the final state with a DOPRI5 reference at tol 1e-10:
  * state error in the integrator's weighted RMS norm (model._error_scales),
  * relative error of the ball–race loads (max over balls and contacts, relative to the mean
    outer load), the quantity the user records,
against wall time, steps and rejected steps. Writes benchmarks/results/integrator_work_precision.md
and .json.

    .venv/bin/python benchmarks/bench_integrator.py [--duration 0.005]
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
sys.path.insert(0, str(ROOT))

from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL  # noqa: E402
from flexbearing.multibody.model import build_model  # noqa: E402
from flexbearing.multibody.initial import initial_state  # noqa: E402
from flexbearing.multibody import outputs as O  # noqa: E402
from flexbearing.multibody import integrator as I  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=0.005)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    a = ap.parse_args(argv)
    m = build_model(PAPER_BEARING, PAPER_OIL)
    w = 14000 * math.pi / 30
    sp = np.array([[0.0, w]])
    ld = np.array([[0.0, 55e3, 0.0, -4e3]])
    imp = np.zeros((0, 6))
    y0 = initial_state(m, w, 55e3, 4e3)
    # compile both methods
    for meth in I.METHODS:
        I.advance(m, y0.copy(), 0.0, 1e-5, sp, ld, imp, 1e-6, 1e-7, method=meth)
    t0 = time.perf_counter()
    ref, _, _, n_ref, _ = I.advance(m, y0.copy(), 0.0, a.duration, sp, ld, imp, 1e-10, 1e-8)
    t_ref = time.perf_counter() - t0
    q_ref = O.evaluate_outputs(m, a.duration, ref, sp, ld, imp)["contact_load"]
    rows = []
    for meth in ("dopri5", "bs32"):
        for tol in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8):
            if meth == "bs32" and tol < 1e-7:
                continue  # thousands of tiny steps: not competitive, skip to keep the benchmark short
            t0 = time.perf_counter()
            y, t, h, n, nr = I.advance(m, y0.copy(), 0.0, a.duration, sp, ld, imp, tol, 1e-7, method=meth)
            wall = time.perf_counter() - t0
            wgt = m.scale + m.relmask * np.abs(ref)
            err = float(np.sqrt(np.mean(((y - ref) / wgt) ** 2)))
            q = O.evaluate_outputs(m, a.duration, y, sp, ld, imp)["contact_load"]
            qerr = float(np.max(np.abs(q - q_ref)) / np.mean(q_ref[:, 0]))
            rows.append(dict(method=meth, tol=tol, wall_s=wall, steps=n, rejected=nr,
                             state_error=err, load_error=qerr, sim_s_per_wall_s=a.duration / wall))
            print(f"{meth:7s} tol {tol:.0e}: {wall:7.2f} s, {n:6d} steps ({nr} rej), state err {err:.2e}, "
                  f"load err {qerr:.2e}", flush=True)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "integrator_work_precision.json").write_text(json.dumps(
        dict(duration_s=a.duration, reference=dict(tol=1e-10, steps=n_ref, wall_s=t_ref), rows=rows,
             load=os.getloadavg()[0], date=time.strftime("%Y-%m-%d %H:%M:%S")), indent=2) + "\n")
    lines = [f"# Integrator work–precision ({a.duration} s of the paper steady case, full model)",
             f"Reference: DOPRI5 tol 1e-10, {n_ref} steps, {t_ref:.1f} s. Machine load {os.getloadavg()[0]:.1f} (2 cores).",
             "", "| method | tol | wall s | steps | rejected | state error (weighted RMS) | load error (max/mean Q_o) |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['method']} | {r['tol']:.0e} | {r['wall_s']:.2f} | {r['steps']} | {r['rejected']} | "
                     f"{r['state_error']:.2e} | {r['load_error']:.2e} |")
    (out / "integrator_work_precision.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
