"""Max von Mises of the cage: every integrator step (the run's monitor) vs sampling instants.

The paper's unsteady scene (scenes/paper_unsteady.toml, flexible cage, 26 modes) from 0 to
T_END = 0.12 s (through the first 50 kN impact at 0.1 s), driven interval by interval at
DT = 1e-5 s. After each interval the backend reports the maximum over every accepted integrator
step of the interval (flexbearing.multibody.stress_peak) and, evaluated again at the same state, the value at
the sampling instant. From these:

  * reference peak = max over all steps (exact over the mesh nodes at every step);
  * sampled peak at interval dt in {1e-5, 1e-4, 1e-3} s = max over the instants k·dt;
  * error of a sampled peak = 1 − sampled / reference, over the impact window [0.09, 0.11] s and
    over the steady stretch [0.02, 0.08] s.

Cost: wall time of the integration with the monitor vs without it (the same steps: the monitor
does not change the integration), per accepted step.
Writes benchmarks/results/stress_peak.json and .md.

    nice .venv/bin/python benchmarks/bench_stress_peak.py
"""
from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).parent / "results"
T_END = 0.12
DT = 1e-5


def main():
    from flexbearing.coupling.flexible_cage import backend as flexible_backend
    from flexbearing.simulation.scene import load_scene
    from flexbearing.multibody import integrator
    from flexbearing.multibody.run_backend import OutputRequest
    root = Path(__file__).resolve().parents[1]
    scene = load_scene(str(root / "scenes" / "paper_unsteady.toml"))
    be = flexible_backend(scene)
    model = be.build_model(scene.bearing, scene.oil, dict(scene.model_options))
    Fa, Fr = scene.initial_loads()
    y0 = np.array(be.initial_state(model, 10000 * np.pi / 30, Fa, Fr), dtype=float)
    request = OutputRequest(tuple(scene.outputs), scene.speed_table, scene.load_table, scene.impacts,
                            film=False, energy=False)
    tabs = (scene.speed_table, scene.load_table, scene.impacts)
    n = int(round(T_END / DT))

    def integrate(with_monitor: bool):
        y, t, h = y0.copy(), 0.0, scene.initial_step
        be.evaluate_outputs(model, 0.0, y, request)             # resets the monitor
        peaks, inst, times, steps = [], [], [], 0
        wall = 0.0
        for k in range(1, n + 1):
            t1 = k * DT
            ws = be.new_workspace(model)
            w0 = time.perf_counter()
            if with_monitor:
                y, _, h, ns, _ = be.advance(model, y, t, t1, *tabs, scene.tolerance, h, ws=ws)
            else:
                y, _, h, ns, _ = integrator.advance(model, y, t, t1, *tabs, scene.tolerance, h, ws=ws)
            wall += time.perf_counter() - w0
            steps += ns
            if with_monitor:
                p = be.evaluate_outputs(model, t1, y, request)
                d = be.evaluate_outputs(model, t1, y, request)   # monitor reset: the instant itself
                peaks.append(p["von_mises_max"])
                inst.append(d["von_mises_max"])
                times.append(p["von_mises_max_time"])
            t = t1
        return wall, steps, np.array(peaks), np.array(inst), np.array(times), y

    integrate(True)                                         # compile
    wall_on, steps_on, peaks, inst, tpk, y_on = integrate(True)
    wall_off, steps_off, _, _, _, y_off = integrate(False)
    assert steps_on == steps_off and np.array_equal(y_on, y_off), "the monitor changed the integration"
    t_inst = DT * np.arange(1, n + 1)
    rows = []
    for label, (a, b) in {"impact 50 kN (0.09-0.11 s)": (0.09, 0.11),
                          "steady stretch (0.02-0.08 s)": (0.02, 0.08)}.items():
        win = (t_inst > a) & (t_inst <= b)
        ref = float(peaks[win].max())
        row = {"window": label, "per_step_peak_Pa": ref,
               "t_peak_s": float(tpk[win][np.argmax(peaks[win])])}
        for dt in (1e-5, 1e-4, 1e-3):
            stride = int(round(dt / DT))
            sel = win & (np.arange(1, n + 1) % stride == 0)
            s = float(inst[sel].max())
            row[f"sampled_peak_dt_{dt:g}_Pa"] = s
            row[f"sampled_error_dt_{dt:g}"] = 1.0 - s / ref
        rows.append(row)
    res = {"scene": "paper_unsteady", "t_end_s": T_END, "interval_s": DT, "accepted_steps": steps_on,
           "wall_with_monitor_s": wall_on, "wall_without_monitor_s": wall_off,
           "monitor_cost_us_per_step": (wall_on - wall_off) / steps_on * 1e6,
           "rhs_cost_us_per_step_without": wall_off / steps_on * 1e6,
           "load_average": os.getloadavg()[0], "windows": rows}
    OUT.mkdir(exist_ok=True)
    (OUT / "stress_peak.json").write_text(json.dumps(res, indent=1))
    lines = ["# Max von Mises: every integrator step vs sampling instants",
             "", f"paper unsteady scene, 0–{T_END} s, {steps_on} accepted steps; "
             f"`nice .venv/bin/python benchmarks/bench_stress_peak.py`", "",
             "| window | per-step peak (MPa) | at | sampled 1e-5 s | 1e-4 s | 1e-3 s |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['window']} | {r['per_step_peak_Pa'] / 1e6:.1f} | {r['t_peak_s']:.6f} s | "
                     + " | ".join(f"{r[f'sampled_peak_dt_{dt:g}_Pa'] / 1e6:.1f} ({-100 * r[f'sampled_error_dt_{dt:g}']:+.1f} %)"
                                  for dt in (1e-5, 1e-4, 1e-3)) + " |")
    lines += ["", f"Cost: {res['monitor_cost_us_per_step']:.1f} µs per accepted step for the monitor vs "
              f"{res['rhs_cost_us_per_step_without']:.1f} µs per step for the integration itself "
              f"(wall {wall_on:.1f} s with, {wall_off:.1f} s without; load average {res['load_average']:.2f})."]
    (OUT / "stress_peak.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
