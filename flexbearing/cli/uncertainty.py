"""`flexbearing uncertainty`: Table 4's 15 slip-rate cases over the test bearing's unknown inputs.

    flexbearing uncertainty [UNKNOWNS.toml] [-o DIR] [--cases 1,2] [--workers N] [--scheduler ADDRESS]
                            [--report-dir DIR] [--report-only] [--quiet]

The work: flexbearing.studies.uncertainty (its docstring describes the sample, the fast steady model, the
bands and the sensitivity indices). Finished (point, case) rows are kept in DIR/<name>/rows.jsonl;
the same command continues an interrupted study and rewrites the report.
"""
from __future__ import annotations

import sys
from pathlib import Path
from flexbearing.common.safe_files import OutputPlan
from flexbearing.common.validation import InputError


def register(subparsers) -> None:
    p = subparsers.add_parser("uncertainty", help="slip-rate validation over the test bearing's unknowns (bands, "
                                                  "Sobol' indices)", description=__doc__.split("\n\n")[0])
    p.add_argument("unknowns", nargs="?", default="scenes/slip_rate_unknowns.toml",
                   help="unknowns file (TOML; default scenes/slip_rate_unknowns.toml)")
    p.add_argument("-o", "--output", default="out/uncertainty", help="output folder (default out/uncertainty)")
    p.add_argument("--cases", default=None, help="comma-separated case numbers (default: all 15)")
    p.add_argument("--workers", type=int, default=None, help="local Dask workers (default: the number of CPUs)")
    p.add_argument("--scheduler", default=None, help="address tcp://HOST:PORT of an existing Dask scheduler")
    p.add_argument("--report-dir", default=None,
                   help="also write slip_rate_uncertainty.md/.json/.png there (e.g. benchmarks/results)")
    p.add_argument("--report-only", action="store_true",
                   help="no runs: analyse the rows finished so far (a study still running or stopped)")
    p.add_argument("--quiet", action="store_true", help="print only the summary")
    p.set_defaults(func=cmd_uncertainty)


def planned_outputs(args, name: str) -> OutputPlan:
    """Every file `flexbearing uncertainty` writes: OUT/<name>/ points.json and rows.jsonl
    (flexbearing.studies.uncertainty; appended, resumable) and in --report-dir the report
    (flexbearing.studies.uncertainty_report: REPORT_STEM .md, .json, .png, _check.json); checked
    before any work (written in place, not staged)."""
    from flexbearing.studies.uncertainty_report import REPORT_STEM
    plan = OutputPlan("flexbearing uncertainty", inputs=[args.unknowns])
    plan.folder(args.output, "-o")
    plan.folder(Path(args.output) / name, "-o", names=("points.json", "rows.jsonl"))
    if args.report_dir:
        plan.folder(args.report_dir, "--report-dir", names=tuple(
            f"{REPORT_STEM}{ext}" for ext in (".md", ".json", ".png", "_check.json")))
    return plan


def cmd_uncertainty(args) -> int:
    from flexbearing.studies import uncertainty as U, uncertainty_report as UR
    study = U.load_unknowns(args.unknowns)
    cases = None
    if args.cases:
        try:
            cases = [int(c) for c in args.cases.split(",")]
        except ValueError:
            raise InputError(f"--cases = {args.cases!r}; allowed: comma-separated case numbers 1-15") from None
    out = Path(args.output)
    planned_outputs(args, study.name).check()          # before any run
    if not args.quiet:
        print(f"== uncertainty {study.name}: {study.points} points x "
              f"{len(cases) if cases else 15} cases -> {out / study.name}", flush=True)
    if args.report_only:
        points = U.study_points(study, [dict(study.nominal(), point="nominal")])
        rows = U.read_rows(out / study.name / "rows.jsonl")
        points += [dict(c) for c in U.candidate_points(U.analyse(study, rows, points))
                   if any(r["point"] == c["point"] for r in rows)]
        analysis = U.analyse(study, rows, points)
        print(UR.summary_text(analysis))
        if args.report_dir:
            paths = UR.write_report(analysis, args.report_dir, command=_command(args))
            print("report: " + ", ".join(str(p) for p in paths))
        return 0
    try:
        res = U.run_study(study, out, cases=cases, workers=args.workers, scheduler=args.scheduler,
                          extra_points=[dict(study.nominal(), point="nominal")], progress=not args.quiet)
    except U.UncertaintyInterrupted as exc:
        print(f"flexbearing uncertainty: {exc}", file=sys.stderr)
        return 130
    analysis = U.analyse(study, U.read_rows(res["rows_file"]), res["points"])
    candidates = U.candidate_points(analysis)
    if candidates:                       # the surrogate's best points, re-run with the model
        more = U.run_study(study, out, cases=cases, workers=args.workers, scheduler=args.scheduler,
                           extra_points=[dict(study.nominal(), point="nominal"), *candidates],
                           progress=not args.quiet)
        res["failures"] += more["failures"]
        analysis = U.analyse(study, U.read_rows(more["rows_file"]), more["points"])
    print(UR.summary_text(analysis))
    if args.report_dir:
        paths = UR.write_report(analysis, args.report_dir, command=_command(args))
        print("report: " + ", ".join(str(p) for p in paths))
    for f in res["failures"]:
        print(f"flexbearing uncertainty: {f.name} failed: {f.message} (run the same command again to retry it)",
              file=sys.stderr)
    return 1 if res["failures"] else 0


def _command(args) -> str:
    """The command line that reproduces the report (as docs/commands.md documents it)."""
    parts = ["flexbearing uncertainty", args.unknowns]
    if args.output != "out/uncertainty":
        parts += ["-o", args.output]
    if args.cases:
        parts += ["--cases", args.cases]
    parts += ["--report-dir", args.report_dir]
    return " ".join(parts)
