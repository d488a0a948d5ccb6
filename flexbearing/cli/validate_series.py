"""`flexbearing validate series`: every published test series of scenes/validation/ against the model,
and the page docs/validation.md it writes (flexbearing.studies.validation.series).

    flexbearing validate series [--samples 16] [--series ID ...] [--out out/validate/series]
                                [--page docs/validation.md] [--workers N] [--scheduler ADDRESS]

The steady states are rows of OUT/rows.jsonl, appended as each finishes: a second call computes only
what is missing (a killed run continues), `--samples 0` gives the nominal states alone.
"""
from __future__ import annotations

import os
import shlex
import sys
from flexbearing.common.safe_files import OutputPlan
from flexbearing.studies.validation import series as VS, series_file as SF


def register(validate_subparsers) -> None:
    """Add `series` to the subcommands of `flexbearing validate` (flexbearing.cli.run)."""
    s = validate_subparsers.add_parser(
        "series", help="every published test series of scenes/validation/ against the model; writes docs/validation.md")
    s.add_argument("--samples", type=int, default=16,
                   help="Sobol' samples of each series' declared unknowns for the band (default 16; 0: nominal only)")
    s.add_argument("--series", action="append", default=None, metavar="ID",
                   help="only this series (file stem in scenes/validation/; repeatable; default: all)")
    s.add_argument("--directory", default=None, metavar="DIR", help="series folder (default scenes/validation)")
    s.add_argument("--out", default="out/validate/series", help="folder of the rows file (resumable)")
    s.add_argument("--page", default="docs/validation.md", help="the page to write (default docs/validation.md)")
    s.add_argument("--workers", type=int, default=None,
                   help="steady states computed at once on a local Dask cluster (default: the number of CPUs)")
    s.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on the Dask cluster whose scheduler is at ADDRESS (tcp://HOST:PORT)")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_validate_series)


def planned_outputs(args) -> OutputPlan:
    """Every file `flexbearing validate series` writes: OUT/rows.jsonl (appended, resumable) and
    the page (--page, written whole and renamed); checked before any work."""
    plan = OutputPlan("flexbearing validate series")
    plan.folder(args.out, "--out", names=("rows.jsonl",))
    plan.file(args.page, "--page")
    return plan


def cmd_validate_series(args) -> int:
    planned_outputs(args).check()
    directory = args.directory or SF.VALIDATION_DIR
    res = VS.run_series(args.out, directory, args.samples, args.series, args.workers or os.cpu_count() or 1,
                        args.scheduler, progress=not args.quiet)
    analysis = VS.analyse(res["series"], res["rows"])
    command = "flexbearing validate series " + " ".join(shlex.quote(a) for a in sys.argv[3:]) \
        if sys.argv[1:3] == ["validate", "series"] else f"flexbearing validate series --samples {args.samples}"
    page = VS.write_page(analysis, args.page, command.strip(), args.samples)
    for a in analysis:
        errs = [e["slip_error_pct"] for e in a["points"] if "slip_error_pct" in e]
        chk = [c for c in a["checks"] if c["verdict"] != "not computed"]
        print(f"{a['series'].series.id}: " + (f"slip error mean {sum(errs) / len(errs):.1f} %, max {max(errs):.1f} %; "
                                               if errs else "")
              + f"checks passed {sum(c['verdict'] == 'pass' for c in chk)}/{len(chk)}")
    print(f"rows: {res['rows_file']}; page: {page}")
    if res["failures"]:
        print("failed jobs: " + "; ".join(map(str, res["failures"])), file=sys.stderr)
        return 1
    return 0
