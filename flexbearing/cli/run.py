"""`flexbearing run` and `flexbearing validate`.

    flexbearing run SCENE.toml [-o RUN.h5] [--resume] [--force] [--max-wall-time S] [--quiet]
    flexbearing validate slip-rate [--json FILE] [--cases 1-8] [--workers N] [--scheduler ADDRESS]
                                   [--ball-attitude A]
                                   [--transverse-traction on|off] [--shim-angle DEG]
                                   [--radial-clearance M] [--t-min S] [--oil-temperature C]
                                   [--oil-air-fraction X] [--oil-air-scaling S] [--traction-law L]
                                   [--traction-scale K] [--gravity G] [--attitude-ring-reaction on|off]
                                   [--out-dir DIR] [--quiet]
    flexbearing validate series [--samples N] [--series ID]   (flexbearing.cli.validate_series)

`run` validates the scene before anything else, streams the results to RUN.h5 (default
out/<scene name>.h5) and writes RUN.summary.json beside it. Ctrl-C keeps what was computed and a
checkpoint; `--resume` continues from it. `validate slip-rate` runs the steady test cases of the
paper's Tables 4/5 (flexbearing.studies.validation.slip_rate) and prints our slip rate beside the test's and the paper's.
"""
from __future__ import annotations

import io
import json
import os
import sys
from pathlib import Path

from flexbearing.common.validation import InputError
from flexbearing.common.safe_files import OutputPlan, write_text_atomic
from flexbearing.cli import validate_series as cli_validate_series
from flexbearing.simulation.results import summary_path

# printed tables only: SI -> engineer's units (the files stay SI)
_PRINT_UNITS = {"Pa": (1e-6, "MPa"), "m": (1e6, "um"), "rad/s": (60.0 / (2 * 3.141592653589793), "rpm"),
                "1": (100.0, "%")}


def _positive(text: str, what: str) -> float:
    """argparse type: a finite number > 0 (nan, inf, 0 and negative numbers refused in one line)."""
    import argparse
    import math
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number ({what})") from None
    if not (math.isfinite(v) and v > 0.0):
        raise argparse.ArgumentTypeError(f"{text} is outside the allowed range: a finite number > 0 ({what})")
    return v


def positive_seconds(text: str) -> float:
    return _positive(text, "seconds of wall time")


def positive_bytes(text: str) -> float:
    return _positive(text, "bytes")


def run_output(args, scene_name: str | None) -> Path:
    """The results file of `run`: -o, else out/<scene name>.h5."""
    return Path(args.output) if args.output else Path("out") / f"{scene_name}.h5"


def planned_outputs(args, scene_name: str | None = None) -> OutputPlan:
    """Every file `flexbearing run` writes: the results file (streamed, resumable; a results file
    there is continued or, with --force, replaced) and its summary (summary_path)."""
    out = run_output(args, scene_name)
    plan = OutputPlan("flexbearing run", inputs=[args.scene])
    plan.file(out, "-o", h5_kind="results file of a run")
    plan.file(summary_path(out), "-o")
    return plan


def register(subparsers) -> None:
    p = subparsers.add_parser("run", help="run a scene (TOML) and stream the results to HDF5",
                              description="Run a scene: results streamed to an HDF5 file, "
                                          "summary in <file>.summary.json beside it.")
    p.add_argument("scene", help="scene file (TOML), e.g. scenes/paper_steady_rigid.toml")
    p.add_argument("-o", "--output", help="results file (.h5); default out/<scene name>.h5")
    p.add_argument("--resume", action="store_true",
                   help="continue the run in the results file from its last checkpoint")
    p.add_argument("--force", action="store_true", help="overwrite an existing results file")
    p.add_argument("--max-wall-time", type=positive_seconds, default=None, metavar="S",
                   help="stop (at a checkpoint, resumable) a run whose step rate predicts more than S "
                        "seconds of wall time; without it such a run only warns when it predicts more "
                        "than an hour")
    p.add_argument("--max-output-size", type=positive_bytes, default=None, metavar="BYTES",
                   help="largest results file the run may write, estimated from its first block before "
                        "anything is written (default 50e9 = 50 GB; the free space is checked as well)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_run)

    v = subparsers.add_parser("validate", help="verification against the paper's test data",
                              description="Verification runs against published data.")
    vs = v.add_subparsers(dest="what", metavar="WHAT")
    s = vs.add_parser("slip-rate", help="cage slip rate vs the paper's Table 5 (15 steady test cases)")
    s.add_argument("--json", metavar="FILE", help="also write the table as JSON")
    s.add_argument("--cases", default="1-15", help="case numbers, e.g. 1-8 or 1,4,12 (default 1-15)")
    s.add_argument("--case-set", default=None, metavar="TOML",
                   help="run the cases of this case set as scenes (e.g. scenes/slip_rate_table4.toml), "
                        "one results file per case in --out; default: flexbearing.studies.validation.slip_rate's procedure "
                        "(each case until the cage speed settles)")
    s.add_argument("--out", default="out/validate/slip_rate", help="with --case-set: folder of the per-case results")
    s.add_argument("--resume", action="store_true", help="with --case-set: continue existing per-case results")
    s.add_argument("--t-max", type=float, default=None,
                   help="longest simulated time per case, s (default: flexbearing.studies.validation.slip_rate's, 15 s: the "
                        "light-load high-speed cases need 4-15 s to settle)")
    s.add_argument("--start", default=None, choices=("quasi_static", "steady"),
                   help="initial state of each case: pure rolling at the quasi-static equilibrium (default) or the "
                        "steady thrust state (flexbearing.multibody.steady), which spares the light-load high-speed cases "
                        "their seconds of settling")
    s.add_argument("--workers", type=int, default=None,
                   help="cases run at once on a local Dask cluster (default: the number of CPUs; 1 = one "
                        "after the other in this process)")
    s.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run the cases on the existing Dask cluster whose scheduler is at ADDRESS, e.g. "
                        "tcp://10.0.0.5:8786")
    # flexbearing.multibody.model.BALL_ATTITUDES, written out so that the CLI starts without importing numba
    # (tests/test_slip_rate.py checks that it takes every one of them)
    s.add_argument("--ball-attitude", default=None, choices=("free", "outer", "inner", "jones", "no_pivot"),
                   help="model option ball_attitude (default: free balls, flexbearing.studies.validation.slip_rate's "
                        "VALIDATION_BALL_ATTITUDE); no_pivot is the paper's hypothesis, with --transverse-traction "
                        "off as there; constrained attitudes run without the gyroscopic pair's ring reaction, "
                        "as in flexbearing.studies.validation.slip_rate (it destabilises them at the test's light loads)")
    s.add_argument("--transverse-traction", default="on", choices=("on", "off"),
                   help="model option transverse_traction (off = the paper's T_eta = 0)")
    s.add_argument("--shim-angle", type=float, default=None, metavar="DEG",
                   help="shim angle of the test bearing's split inner ring, degrees (default 30, assumed), "
                        "with the design clearance of that angle unless --radial-clearance is given")
    s.add_argument("--radial-clearance", type=float, default=None, metavar="M",
                   help="diametral clearance Pd of the test bearing, m (default: the design clearance)")
    # the procedure's own settings (flexbearing.studies.validation.slip_rate; defaults: its VALIDATION_*)
    s.add_argument("--t-min", type=float, default=None, metavar="S",
                   help="no settling test before this time, s (default 1.0: the cage speed can pause on its way)")
    s.add_argument("--oil-temperature", type=float, default=None, metavar="C",
                   help="oil temperature, °C (default: the calibrated VALIDATION_OIL_TEMPERATURE_C, 150)")
    s.add_argument("--oil-air-fraction", type=float, default=None, metavar="X",
                   help="cavity oil volume fraction at 4000 rpm (default: the calibrated VALIDATION_OIL_AIR_FRACTION, 0.002)")
    s.add_argument("--oil-air-scaling", default=None, choices=("constant", "inverse_speed"),
                   help="cavity oil fraction vs speed: constant, or X·4000/n (default inverse_speed)")
    s.add_argument("--traction-law", default=None, choices=("ehl", "fit", "bounded", "origin"),
                   help="traction coefficient law (default ehl, the EHL film-shear law)")
    s.add_argument("--traction-scale", type=float, default=None,
                   help="ehl: film-strength scale (0.5-2); fit laws: diagnostic multiplier of the curve (default 1)")
    s.add_argument("--gravity", type=float, default=None, metavar="M_S2",
                   help="gravity along -z, m/s^2 (default 9.81: the rig's spindle is horizontal; 0 = off)")
    s.add_argument("--attitude-ring-reaction", default="off", choices=("on", "off"),
                   help="constrained ball attitudes: the gyroscopic pair's reaction on the inner ring (default off: "
                        "it destabilises race control at the test's light loads)")
    s.add_argument("--out-dir", default=None, metavar="DIR",
                   help="also write DIR/slip_rate.md (table and summary) and DIR/slip_rate.json (every row's numbers)")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_validate_slip_rate)
    cli_validate_series.register(vs)
    v.set_defaults(func=lambda args: (v.print_help(), 2)[1])


def _format_value(value, unit: str) -> tuple[str, str]:
    if value is None:
        return "-", unit
    f, u = _PRINT_UNITS.get(unit, (1.0, unit))
    return f"{value * f:.6g}", u


def print_summary(summary: dict, file=None) -> None:
    file = sys.stdout if file is None else file    # the stream at call time, not at import
    print(f"scene {summary['scene']} ({summary['cage_model']} cage): {summary['n_samples']} samples, "
          f"status {summary['status']}", file=file)
    sps = summary.get("steps_per_s")
    rate = f", {sps:,.0f} steps/s" if sps else ""
    print(f"wall time {summary['wall_time_s']:.3f} s (+ setup {summary['setup_time_s']:.3f} s), "
          f"{summary['n_steps']} steps ({summary['n_rejected']} rejected){rate}", file=file)
    rows = []
    for name, st in summary["outputs"].items():
        for label, s in [(name, st)] + [(f"{name}[{c}]", cs) for c, cs in st.get("columns", {}).items()]:
            mx, u = _format_value(s["max"], st["unit"])
            me, _ = _format_value(s["mean"], st["unit"])
            mn, _ = _format_value(s["min"], st["unit"])
            rows.append((label, u, mx, me, mn))
    if rows:
        w = max(len(r[0]) for r in rows)
        print(f"{'output':<{w}}  {'unit':>6}  {'max':>12}  {'mean':>12}  {'min':>12}", file=file)
        for r in rows:
            print(f"{r[0]:<{w}}  {r[1]:>6}  {r[2]:>12}  {r[3]:>12}  {r[4]:>12}", file=file)


def cmd_run(args) -> int:
    from flexbearing.simulation.run import RunInterrupted, run_scene
    from flexbearing.simulation.scene import load_scene

    if args.output:
        planned_outputs(args).check()                   # before the scene is read
    scene = load_scene(args.scene)                      # refuses bad scenes before any work
    planned_outputs(args, scene.name).check()
    out = run_output(args, scene.name)
    from flexbearing.simulation.derived import run_start_lines
    for line in run_start_lines(scene):                 # what the scene did not give, and how it was found
        if line.startswith("warning:"):
            print(line, file=sys.stderr)
        elif not args.quiet:
            print(line)
    try:
        summary = run_scene(scene, out, resume=args.resume, force=args.force, quiet=args.quiet,
                            max_wall_time=args.max_wall_time, max_output_bytes=args.max_output_size)
    except RunInterrupted as exc:
        print(f"flexbearing run: {exc}", file=sys.stderr)
        if exc.resumable:
            print(f"  resume: flexbearing run {args.scene} -o {out} --resume", file=sys.stderr)
        return 130 if isinstance(exc.cause, KeyboardInterrupt) else 1
    print_summary(summary)
    print(f"results: {out}\nsummary: {summary_path(out)}")
    return 0


def parse_cases(text: str, n_max: int = 15) -> list[int]:
    """'1-8' -> [1..8]; '1,4,12' -> [1, 4, 12]; each in [1, n_max]."""
    cases: list[int] = []
    for part in str(text).split(","):
        part = part.strip()
        try:
            if "-" in part:
                a, b = (int(x) for x in part.split("-", 1))
                if b < a:
                    raise ValueError
                cases.extend(range(a, b + 1))
            else:
                cases.append(int(part))
        except ValueError:
            raise InputError(f"--cases = {text!r}: use case numbers like 1-8 or 1,4,12") from None
    for c in cases:
        if not 1 <= c <= n_max:
            raise InputError(f"--cases: case {c} is outside the allowed range [1, {n_max}]")
    return sorted(set(cases))


def cmd_validate_slip_rate(args) -> int:
    """Default: flexbearing.studies.validation.slip_rate.run_slip_rate_validation (the dynamics' own procedure: each case
    runs until the cage speed settles, oil temperature VALIDATION_OIL_TEMPERATURE_C). With
    --case-set FILE: every case of FILE is run as a scene through flexbearing.simulation.run (one resumable
    results file per case in --out, fixed duration, slip averaged from average_from)."""
    from flexbearing.simulation.run import RunInterrupted
    from flexbearing.simulation.scene import load_case_set
    from flexbearing.studies.case_sets import CasesIncomplete, run_case_set_slip_rate

    plan = OutputPlan("flexbearing validate slip-rate", inputs=[args.case_set])
    if args.json:
        plan.file(args.json, "--json")
    if getattr(args, "out_dir", None):
        plan.folder(args.out_dir, "--out-dir", names=("slip_rate.md", "slip_rate.json"))
    plan.check()                                        # before any case runs
    if args.case_set is None:
        return _validate_procedure(args)
    # these shape flexbearing.studies.validation.slip_rate's procedure; a case set's scenes carry their own [bearing],
    # [model] and durations, so they would be ignored without a word
    given = [flag for flag, value, default in (
        ("--t-max", args.t_max, None), ("--start", args.start, None),
        ("--ball-attitude", args.ball_attitude, None), ("--transverse-traction", args.transverse_traction, "on"),
        ("--shim-angle", args.shim_angle, None), ("--radial-clearance", args.radial_clearance, None),
        *((flag, getattr(args, name, None), None) for flag, name in _PROCEDURE_SETTINGS),
        ("--attitude-ring-reaction", getattr(args, "attitude_ring_reaction", "off"), "off"))
        if value != default]
    if given:
        raise InputError(f"{', '.join(given)} cannot be used with --case-set (they set flexbearing.studies.validation.slip_rate's "
                         f"procedure; a case set's scenes carry their own bearing, model and durations)")
    case_set = load_case_set(args.case_set)
    cases = parse_cases(args.cases, max(c["id"] for c in case_set.cases))
    workers = (os.cpu_count() or 1) if args.workers is None else args.workers
    try:
        rows = run_case_set_slip_rate(case_set, cases, args.out, resume=args.resume, quiet=args.quiet,
                                      workers=workers, scheduler=args.scheduler)
    except CasesIncomplete as exc:
        print_slip_rate_table(exc.rows)
        print(f"flexbearing validate: {exc}\n  the failed cases again, the finished ones read back: "
              f"flexbearing validate slip-rate --case-set {args.case_set} --cases {args.cases} --resume",
              file=sys.stderr)
        return 1
    except RunInterrupted as exc:
        print(f"flexbearing validate: {exc}" + (f"\n  continue with: flexbearing validate slip-rate "
              f"--case-set {args.case_set} --cases {args.cases} --resume" if exc.resumable else ""), file=sys.stderr)
        return 130 if isinstance(exc.cause, KeyboardInterrupt) else 1
    return _write_json(print_slip_rate_table(rows), args.json)


# flags of the procedure's own settings and the keyword of run_slip_rate_validation each sets
_PROCEDURE_SETTINGS = (("--t-min", "t_min"), ("--oil-temperature", "oil_temperature"),
                       ("--oil-air-fraction", "oil_air_fraction"), ("--oil-air-scaling", "oil_air_scaling"),
                       ("--traction-law", "traction_law"), ("--traction-scale", "traction_scale"),
                       ("--gravity", "gravity"), ("--out-dir", "out_dir"))


def _validate_procedure(args) -> int:
    """`validate slip-rate` without --case-set: flexbearing.studies.validation.slip_rate's own procedure (module docstring
    of cmd_validate_slip_rate)."""
    import flexbearing.studies.validation.slip_rate as val
    cases = parse_cases(args.cases, len(val.slip_rate_cases()))
    kw = {} if getattr(args, "t_max", None) is None else {"t_max": args.t_max}
    if getattr(args, "start", None) is not None:
        kw["start"] = args.start
    workers = getattr(args, "workers", None)
    kw["workers"] = (os.cpu_count() or 1) if workers is None else workers
    kw["scheduler"] = getattr(args, "scheduler", None)
    kw["bearing"] = val.validation_bearing(getattr(args, "shim_angle", None),
                                           getattr(args, "radial_clearance", None))
    kw["options"] = val.validation_model_options(getattr(args, "ball_attitude", None),
                                                 getattr(args, "transverse_traction", "on"),
                                                 getattr(args, "gravity", None),
                                                 getattr(args, "attitude_ring_reaction", "off"))
    for flag, key in (("t_min", "t_min"), ("oil_temperature", "oil_temperature_c"),
                      ("oil_air_fraction", "oil_air_fraction"), ("oil_air_scaling", "oil_air_scaling"),
                      ("traction_law", "traction_law"), ("traction_scale", "traction_scale")):
        if getattr(args, flag, None) is not None:
            kw[key] = getattr(args, flag)

    def table_of(raw, file):
        rows = [{"case": r["case"], "group": r.get("group"), "axial_load": r["axial_load"],
                 "radial_load": r["radial_load"], "speed_rpm": r["speed_rpm"],
                 "slip_ours": r["slip_pct"] / 100.0, "slip_test": r["test_slip_pct"] / 100.0,
                 "slip_paper": r["paper_slip_pct"] / 100.0, "settled": r.get("settled"),
                 "t_end_s": r.get("t_end"), "wall_time_s": r.get("wall_s"), "n_steps": r.get("steps"),
                 "oil_temperature_c": r.get("oil_temperature_c")} for r in raw]
        table = print_slip_rate_table(rows, file=file)
        table["summary_by_group"] = val.summarise(raw)
        return table

    def stream(raw):                   # every finished case is on disk at once
        if args.json:
            _write_json({**table_of(raw, io.StringIO()), "complete": False}, args.json, quiet=True)

    try:
        raw = val.run_slip_rate_validation(cases=cases, quiet=args.quiet, on_row=stream, **kw)
    except val.ValidationInterrupted as exc:
        table_of(exc.rows, sys.stdout)
        print(f"flexbearing validate: {exc}" + (f"; the finished cases are in {args.json}" if args.json else ""),
              file=sys.stderr)
        return 130 if isinstance(exc.cause, KeyboardInterrupt) else 1
    if getattr(args, "out_dir", None):
        val.write_report(raw, args.out_dir)
    return _write_json({**table_of(raw, sys.stdout), "complete": True}, args.json)


def _write_json(table: dict, path, quiet: bool = False) -> int:
    if path:
        write_text_atomic(path, json.dumps(table, indent=2, default=float) + "\n")   # never half a file
        if not quiet:
            print(f"written: {path}")
    return 0


def print_slip_rate_table(rows, file=None) -> dict:
    """rows: dicts with case, axial_load, radial_load, speed_rpm, slip_ours, slip_test, slip_paper
    (slip rates as fractions). Prints the table in % with the relative errors
    |ours − test|/test and |paper − test|/test, and their mean and max; returns it as a dict."""
    file = sys.stdout if file is None else file    # the stream at call time, not at import
    out = []
    print(f"{'case':>4} {'Fa/N':>6} {'Fr/N':>6} {'n/rpm':>7} {'test/%':>7} {'paper/%':>8} {'ours/%':>7} "
          f"{'err ours/%':>10} {'err paper/%':>11}", file=file)
    for r in rows:
        e_ours = abs(r["slip_ours"] - r["slip_test"]) / r["slip_test"]
        e_paper = abs(r["slip_paper"] - r["slip_test"]) / r["slip_test"]
        out.append({**r, "error_ours": e_ours, "error_paper": e_paper})
        note = "  (not settled)" if r.get("settled") is False else ""
        print(f"{r['case']:>4} {r['axial_load']:>6.0f} {r['radial_load']:>6.0f} {r['speed_rpm']:>7.0f} "
              f"{100 * r['slip_test']:>7.2f} {100 * r['slip_paper']:>8.2f} {100 * r['slip_ours']:>7.2f} "
              f"{100 * e_ours:>10.2f} {100 * e_paper:>11.2f}{note}", file=file)
    result = {"cases": out}
    if out:
        for who in ("ours", "paper"):
            errs = [r[f"error_{who}"] for r in out]
            result[f"mean_error_{who}"] = sum(errs) / len(errs)
            result[f"max_error_{who}"] = max(errs)
        unsettled = [r["case"] for r in out if "slip_drift" in r
                     and abs(r["slip_drift"]) > 0.02 * max(abs(r["slip_ours"]), 1e-3)]
        result["unsettled_cases"] = unsettled
        if unsettled:
            print(f"warning: cases {', '.join(map(str, unsettled))}: the slip rate still drifts by more "
                  f"than 2 % across the averaging window (cage speed not settled: run longer)", file=file)
        print(f"relative error vs test: ours mean {100 * result['mean_error_ours']:.2f} %, "
              f"max {100 * result['max_error_ours']:.2f} %; paper mean "
              f"{100 * result['mean_error_paper']:.2f} %, max {100 * result['max_error_paper']:.2f} %",
              file=file)
    return result
