"""Numerical stability stress test (issue 22): extreme but valid scenes, each must either finish with
finite, bounded, physical results or stop early with a diagnostic that names the body, the
contact, the time and the likely cause. None may hang or write NaN.

    nice -n 5 .venv/bin/python benchmarks/stress_test.py [--only NAME,...] [--group G] [--cheap]
                                                          [--out benchmarks/results/stress_test]
    make stress

Every case is the paper bearing (rigid cage unless it says flexible) for a few ms, sampled every
20 us, recording the ball loads and approaches, the cage orbit and guide forces and the power
balance. Each runs in its own process with a hang limit (HANG_S); inside, the run's wall-time
guard (flexbearing.simulation.wall_budget, max_wall_time = CASE_WALL_S) stops a run whose step rate predicts
more. Outcomes:

    finished   the run completed; the checks of flexbearing.simulation.run_checks (finite, energy balance,
               approach against its Hertz energy bound, cage in its clearance) are reported
    stopped    the library stopped it with a diagnostic: refused at setup (InputError: a load
               beyond the contacts), SimulationUnstable (ball/cage, contact, time, likely cause),
               or the wall-time guard (estimated time)
    crashed    any other exception (a defect: a traceback a user would see)
    hung       killed after HANG_S without an answer (a defect)

Results: benchmarks/results/stress_test.{md,json}. The cheap cases (CHEAP) also run in
`make test` (tests/test_stress.py), the rest there as slow tests.
"""
from __future__ import annotations

import argparse
import copy
import json
import multiprocessing as mp
import os
import platform
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

HANG_S = 600.0          # a case without an answer after this is "hung"
CASE_WALL_S = 240.0     # the wall-time guard of each run (predicted total above this: stopped)
RECORD = ["ball_loads", "contact_stress", "pocket_force", "guiding_force", "cage_speed", "cage_orbit",
          "power_loss"]
SAMPLE = 2e-5           # s


def scene_data(name, duration=2e-3, rpm=10000.0, speed=None, load=None, impacts=(), bearing=None,
               cage=None, oil=None, model=None, tol=1e-6, max_step=None, sample=SAMPLE):
    """A scene dict (flexbearing.simulation.scene format): the paper bearing at `rpm` (or the `speed` table of
    [t, rpm] points), Fa 55 kN and Fr 4 kN unless `load` says otherwise."""
    d = {"name": name, "cage": {"model": "rigid", **(cage or {})},
         "operation": {"duration": duration,
                       "speed": ({"table_rpm": [list(p) for p in speed]} if speed is not None else
                                 {"phases": [{"kind": "uniform", "duration": duration, "rpm": rpm}]}),
                       "load": dict(load if load is not None else {"axial_load": 55e3, "radial_load": 4e3})},
         "integrator": {"tolerance": tol},
         "output": {"sample_interval": sample, "record": list(RECORD), "checkpoint_every": 1000}}
    if impacts:
        d["operation"]["load"]["impacts"] = [dict(i) for i in impacts]
    if max_step:
        d["integrator"]["max_step"] = max_step
    for key, value in (("bearing", bearing), ("oil", oil), ("model", model)):
        if value:
            d[key] = dict(value)
    return d


def _impact(mag, dur, t0=2e-4, direction=None):
    d = {"t_start": t0, "duration": dur, "magnitude": mag, "shape": "half-sine"}
    if direction:
        d["direction"] = direction
    return d


def cases() -> list[dict]:
    """The case table: name, group, scene dict."""
    c = []

    def add(group, name, **kw):
        c.append({"name": name, "group": group, "scene": scene_data(name, **kw)})

    # speeds 0 ... 60,000 rpm (the scene's range); the slow end at 1 ms (its step rate, issue 21)
    for rpm in (0, 1, 100):
        add("speed", f"speed_{rpm}rpm", rpm=rpm, duration=1e-3)
    for rpm in (1000, 5000, 10000, 20000, 30000, 40000, 50000, 60000):
        add("speed", f"speed_{rpm}rpm", rpm=rpm)
    # fast accelerations, decelerations and reversals of the acceleration (speed >= 0 in a scene)
    add("speed_change", "stop_60000_to_0_in_1ms", speed=[(0, 60000), (1e-3, 0)])
    add("speed_change", "start_0_to_60000_in_1ms", speed=[(0, 0), (1e-3, 60000)], duration=2e-3)
    add("speed_change", "dip_20000_0_20000_in_0.5ms", speed=[(0, 20000), (2.5e-4, 0), (5e-4, 20000)])
    add("speed_change", "sawtooth_0_30000_every_0.25ms",
        speed=[(k * 2.5e-4, 30000 if k % 2 else 0) for k in range(9)])
    add("speed_change", "step_10000_to_40000_in_10us", speed=[(0, 10000), (5e-4, 10000), (5.1e-4, 40000)])
    add("speed_change", "step_40000_to_0_in_10us", speed=[(0, 40000), (5e-4, 40000), (5.1e-4, 0)])
    # axial load from none to beyond the contacts
    for fa, fr in ((0, 0), (0, 4e3), (1, 0), (10, 0), (100, 0), (1e3, 0), (100, 4e3)):
        add("axial_load", f"Fa_{fa:g}N_Fr_{fr:g}N", load={"axial_load": fa, "radial_load": fr})
    for fa in (5e5, 1e6, 2e6, 2.2e6, 3e6, 1e7):
        add("axial_load", f"Fa_{fa:g}N", load={"axial_load": fa, "radial_load": 4e3})
    # radial loads
    for fr in (5e4, 2e5):
        add("radial_load", f"Fr_{fr:g}N", load={"axial_load": 55e3, "radial_load": fr})
    add("radial_load", "Fr_2e4N_without_axial", load={"axial_load": 0, "radial_load": 2e4})
    # impacts 150-500 kN, 0.1-2 ms (radial, on the paper's loads), and an axial one
    for mag in (150e3, 300e3, 500e3):
        for dur in (1e-4, 5e-4, 2e-3):
            add("impact", f"impact_{mag / 1e3:g}kN_{dur * 1e3:g}ms", impacts=[_impact(mag, dur)],
                duration=max(2e-3, 2e-4 + dur + 3e-4))
    add("impact", "impact_200kN_1ms", impacts=[_impact(200e3, 1e-3)])
    add("impact", "impact_axial_300kN_0.5ms", impacts=[_impact(300e3, 5e-4, direction=[1.0, 0.0, 0.0])])
    add("impact", "impact_500kN_0.1ms_at_40000rpm", rpm=40000, impacts=[_impact(500e3, 1e-4)])
    add("impact", "impacts_3x_250kN_0.2ms", impacts=[_impact(250e3, 2e-4, t0=t) for t in (2e-4, 8e-4, 1.4e-3)])
    # clearances: bearing radial clearance, pocket and guide clearances from zero to large
    add("clearance", "radial_clearance_0", bearing={"radial_clearance": 0.0})
    add("clearance", "radial_clearance_200um", bearing={"radial_clearance": 200e-6})
    add("clearance", "radial_clearance_200um_no_axial", bearing={"radial_clearance": 200e-6},
        load={"axial_load": 0, "radial_load": 4e3})
    add("clearance", "pocket_clearance_5um", cage={"pocket_diameter": 22.01e-3})
    add("clearance", "pocket_clearance_1mm", cage={"pocket_diameter": 24e-3})
    add("clearance", "guide_clearance_10um", bearing={"guide_land_diameter": 178.82e-3})
    add("clearance", "guide_clearance_1mm", bearing={"guide_land_diameter": 181e-3})
    # skidding balls: high speed at light load, sudden acceleration, thin oil
    add("skid", "skid_40000rpm_Fa_200N", rpm=40000, load={"axial_load": 200, "radial_load": 0})
    add("skid", "skid_accelerate_0_to_30000_light", speed=[(0, 0), (5e-4, 30000)],
        load={"axial_load": 500, "radial_load": 0})
    add("skid", "skid_engine_oil_150C_30000rpm", rpm=30000, oil={"preset": "engine", "temperature_c": 150.0},
        load={"axial_load": 1e3, "radial_load": 0})
    add("skid", "skid_ehl_law_20000rpm_light", rpm=20000, model={"traction_law": "ehl"},
        load={"axial_load": 500, "radial_load": 200})
    # integrator tolerances 1e-3 ... 1e-9 on the paper's 14,000 rpm case with an impact, and the
    # ends of the scene's range (0.1 and flexbearing.simulation.scene.MIN_TOLERANCE)
    for tol in (1e-1, 1e-3, 1e-4, 1e-5, 1e-7, 1e-8, 1e-9, 1e-12):
        add("tolerance", f"tol_{tol:g}", rpm=14000, tol=tol, duration=1e-3,
            impacts=[_impact(50e3, 2e-4)])
    # the flexible cage at high spin (the paper's 26-mode reduced cage, from the cache)
    for rpm in (30000, 45000, 60000):
        add("flexible", f"flexible_{rpm}rpm", rpm=rpm, duration=1e-3, cage={"model": "flexible"})
    add("flexible", "flexible_impact_300kN_0.2ms_20000rpm", rpm=20000, duration=1e-3,
        cage={"model": "flexible"}, impacts=[_impact(300e3, 2e-4)])
    # the wall-time guard: 0 rpm for 50 ms (~5 M steps) must be stopped with its estimate
    add("guard", "guard_0rpm_50ms", rpm=0, duration=50e-3, sample=1e-4)
    return c


def generated_cases(n: int, seed: int) -> list[dict]:
    """n scenes drawn at random (issue 36: not only the listed cases), each within the scene's
    ranges but combining their extremes: speed 0-60,000 rpm (uniform or a step), axial load
    0-1e7 N, radial load 0-1e5 N along a direction whose components span 1e-300 ... 1e300,
    impacts of 1 N-500 kN lasting 10 us-1 ms in random directions, tolerances 1e-10 ... 1e-2.
    Each must finish with bounded results or stop with a diagnostic, like the listed cases."""
    import numpy as np
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        scale = 10.0 ** rng.uniform(-300, 300)
        direction = [0.0, float(rng.uniform(-1, 1) * scale), float(rng.uniform(-1, 1) * scale)]
        rpm = float(rng.choice([0.0, 60000.0, rng.uniform(0, 60000)]))
        speed = ([(0, rpm), (5e-4, rpm), (5e-4 + 10 ** rng.uniform(-5, -3), float(rng.uniform(0, 60000)))]
                 if rng.random() < 0.3 else None)
        load = {"axial_load": float(10 ** rng.uniform(0, 7)) if rng.random() < 0.9 else 0.0,
                "radial_load": float(10 ** rng.uniform(0, 5)), "radial_direction": direction}
        impacts = [_impact(float(10 ** rng.uniform(0, 5.7)), float(10 ** rng.uniform(-5, -3)),
                           t0=float(rng.uniform(0, 1e-3)),
                           direction=[0.0, float(rng.normal()), float(rng.normal())])
                   for _ in range(int(rng.integers(0, 3)))]
        name = f"generated_{seed}_{i}"
        out.append({"name": name, "group": "generated",
                    "scene": scene_data(name, duration=2e-3, rpm=rpm, speed=speed, load=load, impacts=impacts,
                                        tol=float(10 ** rng.uniform(-10, -2)))})
    return out


# cases cheap enough for `make test` (< ~5 s each on the 2-core machine, measured by this script)
CHEAP = ("speed_10000rpm", "speed_60000rpm", "Fa_1e+07N", "Fa_3e+06N", "impact_500kN_0.1ms",
         "radial_clearance_200um", "tol_0.001", "stop_60000_to_0_in_1ms")


def run_case(case: dict, out_dir: Path, max_wall_time: float = CASE_WALL_S) -> dict:
    """Run one case in this process; the row of the table (module docstring)."""
    import warnings

    from flexbearing.common.validation import InputError
    from flexbearing.simulation.run import RunInterrupted, run_scene, default_backend
    from flexbearing.simulation.run_checks import check_run
    from flexbearing.simulation.scene import parse_scene
    from flexbearing.simulation.wall_budget import SlowRunWarning

    row = {"case": case["name"], "group": case["group"]}
    out = Path(out_dir) / f"{case['name']}.h5"
    t0 = time.perf_counter()
    try:
        scene = parse_scene(copy.deepcopy(case["scene"]), path=f"stress:{case['name']}")
        backend = default_backend(scene)
        with warnings.catch_warnings(record=True) as warned:
            warnings.simplefilter("always", SlowRunWarning)
            summary = run_scene(scene, out, force=True, quiet=True, backend=backend,
                                max_wall_time=max_wall_time)
        row.update(outcome="finished", steps=summary["n_steps"], rejected=summary["n_rejected"],
                   warnings=[str(w.message) for w in warned])
        model = backend.build_model(scene.bearing, scene.oil, dict(scene.model_options))
        row["checks"] = check_run(out, scene, model)
        row["checks_ok"] = all(c["ok"] for c in row["checks"].values())
    except InputError as exc:
        row.update(outcome="stopped", stage="setup", diagnostic=str(exc))
    except RunInterrupted as exc:
        cause = exc.cause
        row.update(outcome="stopped", stage="run", stopped_at=exc.t, diagnostic=str(cause),
                   cause=type(cause).__name__, resumable=exc.resumable)
        for attr in ("ball", "contact"):
            if getattr(cause, attr, None) is not None:
                row[attr] = getattr(cause, attr)
        try:
            from flexbearing.simulation.results import read_outputs
            import numpy as np
            o = read_outputs(out)
            row["nan_in_file"] = int(sum(np.size(v) - np.isfinite(v).sum() for v in o.values()))
        except Exception as e:  # noqa: BLE001 - reported, not hidden
            row["file_error"] = repr(e)
    except Exception as exc:  # noqa: BLE001 - a crash is an outcome of the table
        row.update(outcome="crashed", diagnostic=f"{type(exc).__name__}: {exc}",
                   traceback=traceback.format_exc(limit=6))
    row["wall_s"] = time.perf_counter() - t0
    if out.exists():
        out.unlink()
        out.with_name(out.stem + ".summary.json").unlink(missing_ok=True)
    return row


def _child(case, out_dir, queue):
    queue.put(run_case(case, out_dir))


def run_isolated(case: dict, out_dir: Path, hang_s: float = HANG_S) -> dict:
    """run_case in a fresh process, killed after hang_s (outcome "hung")."""
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    p = ctx.Process(target=_child, args=(case, str(out_dir), q))
    t0 = time.perf_counter()
    p.start()
    try:
        row = q.get(timeout=hang_s)
    except Exception:  # noqa: BLE001 - queue.Empty: no answer in time
        row = {"case": case["name"], "group": case["group"], "outcome": "hung",
               "wall_s": time.perf_counter() - t0, "diagnostic": f"no answer after {hang_s:g} s"}
    p.join(timeout=10)
    if p.is_alive():
        p.kill()
        p.join()
    if row.get("outcome") != "hung" and p.exitcode not in (0, None):
        row["exit_code"] = p.exitcode
    return row


def _fmt_check(c: dict) -> str:
    v, b = c["value"], c["bound"]
    return f"{'ok' if c['ok'] else 'FAIL'} {v:.3g}/{b:.3g}"


def write_results(rows: list[dict], out: Path, wall: float) -> None:
    n = len(rows)
    count = lambda o: sum(r["outcome"] == o for r in rows)  # noqa: E731
    nan = sum(r.get("nan_in_file", 0) for r in rows) + sum(
        r.get("checks", {}).get("finite", {}).get("value", 0) for r in rows)
    failed_checks = [r["case"] for r in rows if r["outcome"] == "finished" and not r.get("checks_ok", True)]
    summary = {"cases": n, "finished": count("finished"), "stopped_with_diagnostic": count("stopped"),
               "crashed": count("crashed"), "hung": count("hung"), "non_finite_values_written": nan,
               "finished_failing_a_check": failed_checks, "wall_time_s": wall}
    meta = {"command": "nice -n 5 .venv/bin/python benchmarks/stress_test.py", "machine": platform.node(),
            "cpus": os.cpu_count(), "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "case_wall_limit_s": CASE_WALL_S, "hang_limit_s": HANG_S}
    out.with_suffix(".json").write_text(json.dumps({"summary": summary, "meta": meta, "rows": rows},
                                                   indent=1, default=float) + "\n")
    md = ["# Numerical stability stress test", "",
          f"`{meta['command']}` ({meta['date']}, {meta['cpus']} cores shared with other jobs; "
          f"{wall / 60:.1f} min in all). Scenes, checks and outcomes: the docstring of "
          "`benchmarks/stress_test.py` and `flexbearing/simulation/run_checks.py`.", "",
          f"**{n} cases: {summary['finished']} finished, {summary['stopped_with_diagnostic']} stopped with a "
          f"diagnostic, {summary['crashed']} crashed, {summary['hung']} hung; non-finite values written: {nan}; "
          f"finished runs failing a check: {len(failed_checks)}"
          + (f" ({', '.join(failed_checks)})" if failed_checks else "") + ".**", "",
          "checks: value/bound — energy: |ΔE − ∫P dt| / scale; approach: deepest race approach [m] / "
          "Hertz energy bound; cage: max eccentricity ratio / 1 + rim penetration.", "",
          "| case | group | outcome | wall s | steps | energy | approach | cage | diagnostic |",
          "|---|---|---|---:|---:|---|---|---|---|"]
    for r in rows:
        ch = r.get("checks", {})
        cells = [_fmt_check(ch[k]) if k in ch else "–" for k in ("energy", "approach", "cage_clearance")]
        diag = r.get("diagnostic", "")
        if r.get("warnings"):
            diag = "warning: " + r["warnings"][0]
        diag = diag.replace("|", "/").replace("\n", " ")
        if len(diag) > 420:
            diag = diag[:417] + "..."
        md.append(f"| {r['case']} | {r['group']} | {r['outcome']} | {r['wall_s']:.1f} | "
                  f"{r.get('steps', '–')} | {' | '.join(cells)} | {diag} |")
    out.with_suffix(".md").write_text("\n".join(md) + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", help="comma-separated case names")
    ap.add_argument("--group", help="only the cases of this group")
    ap.add_argument("--cheap", action="store_true", help="only the cheap cases (those of make test)")
    ap.add_argument("--generated", type=int, default=0, metavar="N",
                    help="add N scenes drawn at random (generated_cases; group 'generated')")
    ap.add_argument("--seed", type=int, default=36, help="seed of the generated scenes")
    ap.add_argument("--out", default=str(ROOT / "benchmarks/results/stress_test"),
                    help="results stem (.md and .json written)")
    args = ap.parse_args(argv)
    table = cases() + generated_cases(args.generated, args.seed)
    if args.only:
        names = set(args.only.split(","))
        table = [c for c in table if c["name"] in names]
    if args.group:
        table = [c for c in table if c["group"] == args.group]
    if args.cheap:
        table = [c for c in table if c["name"] in CHEAP]
    work = Path(os.environ.get("TMPDIR", "/tmp")) / f"stress_test_{os.getpid()}"
    work.mkdir(parents=True, exist_ok=True)
    rows, t0 = [], time.perf_counter()
    for i, case in enumerate(table):
        row = run_isolated(case, work)
        rows.append(row)
        ch = row.get("checks", {})
        print(f"[{i + 1}/{len(table)}] {row['case']}: {row['outcome']} in {row['wall_s']:.1f} s"
              + (f", {row['steps']} steps" if "steps" in row else "")
              + (f", checks {'ok' if row.get('checks_ok') else 'FAIL ' + str({k: v['value'] for k, v in ch.items() if not v['ok']})}"
                 if ch else "")
              + (f" — {row.get('diagnostic', '')[:160]}" if row["outcome"] != "finished" else ""), flush=True)
    write_results(rows, Path(args.out), time.perf_counter() - t0)
    print(f"written {args.out}.md and .json")
    return 0 if all(r["outcome"] in ("finished", "stopped") for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
