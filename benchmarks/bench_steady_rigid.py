"""Wall time of the paper's steady scene with a rigid cage (issue 4, requirement (d)).

Scene scenes/paper_steady_rigid.toml (SPEC §6): 14,000 rpm, Fa = 55 kN, Fr = 4 kN, 0.6 s,
rigid cage, tolerance and sample interval from the scene (1e-6, 1e-4 s). The loop is the one of a
run: the integrator advances sample by sample (flexbearing.multibody.integrator.advance), the outputs the
scene records are evaluated at every sample (flexbearing.multibody.outputs.evaluate_outputs) and kept in
memory (no HDF5: that is the results engineer's part and measured by its own benchmark).

Reported: wall time (compilation excluded: a warm-up of 1 ms runs first), steps, rejected steps,
steps/s, RHS evaluations/s, and the final cage speed and slip as a sanity check. Results are
appended to benchmarks/results/steady_rigid.md and written to benchmarks/results/steady_rigid.json.

    .venv/bin/python benchmarks/bench_steady_rigid.py [--duration 0.6] [--tol 1e-6] [--quiet]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from flexbearing.multibody.model import build_model  # noqa: E402
from flexbearing.multibody.initial import initial_state  # noqa: E402
from flexbearing.multibody import outputs as O  # noqa: E402
from flexbearing.multibody import integrator as I  # noqa: E402


def load_paper_steady():
    """(bearing, oil, options, speed_table, load_table, impacts, duration, tol, dt, film)."""
    try:
        from flexbearing.simulation.scene import load_scene
        sc = load_scene(ROOT / "scenes" / "paper_steady_rigid.toml")
        return (sc.bearing, sc.oil, dict(sc.model_options), sc.speed_table, sc.load_table, sc.impacts,
                sc.duration, sc.tolerance, sc.sample_interval, "film_thickness" in sc.outputs, sc.initial_step)
    except Exception as exc:  # scene module missing: the same numbers by hand
        print(f"(scene loader unavailable: {exc!r}; using the SPEC §6 numbers)")
        from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
        w = 14000 * math.pi / 30
        return (PAPER_BEARING, PAPER_OIL, {}, np.array([[0.0, w]]), np.array([[0.0, 55e3, 0.0, -4e3]]),
                np.zeros((0, 6)), 0.6, 1e-6, 1e-4, True, 1e-7)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=None, help="simulated time, s (scene: 0.6)")
    ap.add_argument("--tol", type=float, default=None, help="integrator tolerance (scene: 1e-6)")
    ap.add_argument("--method", default="dopri5", choices=sorted(I.METHODS))
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    a = ap.parse_args(argv)
    bearing, oil, options, sp, ld, imp, duration, tol, dt, film, h0 = load_paper_steady()
    duration = a.duration or duration
    tol = a.tol or tol
    model = build_model(bearing, oil, options)
    omega = sp[0, 1]
    y0 = initial_state(model, omega, ld[0, 1], math.hypot(ld[0, 2], ld[0, 3]), load=tuple(ld[0, 1:4]))
    # warm-up: compile everything (cached on disk after the first run)
    tw = time.perf_counter()
    I.advance(model, y0.copy(), 0.0, 1e-3, sp, ld, imp, tol, h0)
    O.evaluate_outputs(model, 0.0, y0, sp, ld, imp, film=film)
    t_compile = time.perf_counter() - tw

    n = int(round(duration / dt))
    y, t, h = y0.copy(), 0.0, h0
    ws = I.Workspace(model, a.method)
    steps = rej = 0
    cage = np.zeros(n)
    slip = np.zeros(n)
    bar = None
    if not a.quiet:
        from tqdm import tqdm
        bar = tqdm(total=duration, unit="s sim", bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}] {postfix}")
    t0 = time.perf_counter()
    for k in range(1, n + 1):
        tn = min(k * dt, duration)
        y, t, h, a_, r_ = I.advance(model, y, t, tn, sp, ld, imp, tol, h, ws, method=a.method)
        steps += a_
        rej += r_
        out = O.evaluate_outputs(model, t, y, sp, ld, imp, film=film)
        cage[k - 1] = out["cage_speed"]
        slip[k - 1] = out["slip_rate"]
        if bar is not None and k % 50 == 0:
            el = time.perf_counter() - t0
            bar.update(tn - bar.n)
            bar.set_postfix_str(f"{steps / el:,.0f} steps/s, h={h:.1e}")
    wall = time.perf_counter() - t0
    if bar is not None:
        bar.close()
    n_rhs = 6 * (steps + rej) + n  # DOPRI5: 6 new stages per attempt (FSAL) + one per output restart
    res = {
        "scene": "paper_steady_rigid (14,000 rpm, Fa 55 kN, Fr 4 kN, rigid cage)",
        "duration_s": duration, "tol": tol, "method": a.method, "sample_interval_s": dt,
        "wall_s": round(wall, 2), "compile_and_warmup_s": round(t_compile, 2),
        "steps": int(steps), "rejected": int(rej), "steps_per_s": round(steps / wall),
        "rhs_per_s_approx": round(n_rhs / wall), "mean_step_s": duration / max(steps, 1),
        "cage_speed_last_0.1s_rad_s": float(np.mean(cage[-max(1, n // 6):])),
        "slip_last_0.1s": float(np.mean(slip[-max(1, n // 6):])),
        "machine": f"{platform.node()} {platform.machine()} {os.cpu_count()} cpu, load {os.getloadavg()[0]:.1f}",
        "date": time.strftime("%Y-%m-%d %H:%M:%S"),
    }
    out_dir = Path(a.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "steady_rigid.json").write_text(json.dumps(res, indent=2) + "\n")
    with open(out_dir / "steady_rigid.md", "a") as f:
        f.write(f"- {res['date']}: {duration} s simulated in {res['wall_s']} s wall "
                f"({res['steps']} steps, {res['rejected']} rejected, {res['steps_per_s']} steps/s, "
                f"tol {tol:g}, {a.method}); cage {res['cage_speed_last_0.1s_rad_s']:.2f} rad/s, "
                f"slip {100 * res['slip_last_0.1s']:.2f} %; {res['machine']}\n")
    print(json.dumps(res, indent=2))
    return res


if __name__ == "__main__":
    main()
