"""`flexbearing report`: time-history plots, per-phase tables and the cage's von Mises field of a run.

    flexbearing report RUN.h5 [--compare OTHER.h5] [-o DIR] [--frames auto|t1,t2,...]
                              [--series T0:T1[:N]] [--displacement-scale S] [--fatigue ...] [--quiet]

The work: flexbearing.analysis.report (write_report); the statistics are defined in flexbearing.analysis.windows.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path
from flexbearing.analysis.report import _fmt, _stat_rows, write_report
from flexbearing.analysis.windows import QUANTITIES, window_title
from flexbearing.common.validation import InputError


def print_table(rows: list[dict], file=None) -> None:
    # imported here: every command builds this module's parser, only `report` prints tables
    # (flexbearing.analysis.report loads the plots and windows modules)
    file = sys.stdout if file is None else file    # the stream at call time, not at import
    keys = [q.key for q in QUANTITIES if rows and f"{q.key}_mean" in rows[0]]
    w = max(len(lab) for lab, _, _ in _stat_rows(keys)) if keys else 10
    for r in rows:
        st = r.get("settling")
        verdict = "" if not st else f"; {st['verdict']}" + (f": {st['reason']}" if st["settled"] is False else "")
        print(f"{window_title(r)}  ({r['n_samples']} samples{verdict})", file=file)
        for lab, field, qd in _stat_rows(keys):
            mark = " †" if st and st["settled"] is False and not field.endswith(f"_{qd.extreme_stat}") else ""
            print(f"  {lab:<{w}}  {_fmt(r.get(field), qd.scale):>10}{mark}", file=file)


def register(subparsers) -> None:
    p = subparsers.add_parser("report", help="plots, per-phase tables and the cage's von Mises field of a run",
                              description="Report of a run: one PNG per quantity and an overview, "
                                          "report.md/report.json with peak, p99 and mean per phase of the "
                                          "speed profile and per impact, and (flexible cage) a picture of the "
                                          "cage's von Mises field at the run's maximum and ParaView XDMF "
                                          "files of it (10-node tetrahedra, every node drawn): the peaks "
                                          "(--frames) and a time series with the balls (--series). "
                                          "Headless check and screenshot: xvfb-run -a pvpython "
                                          "docs/paraview_open.py DIR (docs/paraview.md).")
    p.add_argument("run", help="results file of `flexbearing run` (.h5)")
    p.add_argument("--compare", metavar="OTHER.h5", help="overlay and tabulate another run beside it "
                                                         "(e.g. the steady scene)")
    p.add_argument("-o", "--output", metavar="DIR", help="output folder (default: <run>_report beside the run)")
    p.add_argument("--frames", default="auto", help="von Mises frames: auto (max in each phase and each "
                                                   "impact) or times in s, e.g. 0.1,0.3")
    p.add_argument("--series", metavar="T0:T1[:N]",
                   help="ParaView time series of the window T0..T1 s at every N-th sample (default every "
                        "one): the cage placed and deformed, coloured by von Mises (series_cage.xdmf), "
                        "the balls and the cage centre (series_points.xdmf), the rings (series_rings.xdmf) "
                        "and, with ParaView's pvpython installed, the scene bearing.pvsm (File > Load State); "
                        "needs a flexible-cage run for the cage and the scene output \"kinematics\" for the "
                        "balls and the inner ring's position")
    p.add_argument("--movie", action="store_true",
                   help="with --series: also a movie of the window, bearing.avi (needs pvpython)")
    p.add_argument("--pdf", action="store_true",
                   help="also report.pdf, the page printed by headless Chromium (needs chromium)")
    p.add_argument("--displacement-scale", type=float, metavar="S",
                   help="magnification of the series' displacement_scaled field (Warp By Vector at scale "
                        "1 then draws the cage S times deformed; default: the largest displacement drawn "
                        "as about 1%% of the cage's outside diameter)")
    p.add_argument("--settle", type=float, default=None, metavar="S",
                   help="leave samples before t = S seconds (start-up transient) out of the tables and the "
                        "fatigue duty cycle (default: tables from t = 0, marked where a phase has not "
                        "settled; fatigue from the end of the start-up transient the report finds)")
    p.add_argument("--reduced-cage", metavar="FILE", help="reduced cage file (default: the one the run names)")
    p.add_argument("--fatigue", action="store_true",
                   help="add the cage's fatigue (flexible cage): damage, life and safety factor per node from "
                        "the run's stress history (rainflow, mean-stress correction, S-N curve, Miner), the "
                        "worst nodes, a picture of the damage field and fatigue.xdmf for ParaView")
    p.add_argument("--fatigue-correction", metavar="NAME",
                   help="mean-stress correction: goodman (default), gerber, swt or none")
    p.add_argument("--fatigue-material", metavar="NAME", help="S-N curve preset (default 40CrNiMoA)")
    p.add_argument("--fatigue-blocks-per-hour", type=float, metavar="N",
                   help="times the run's block is applied per hour (default: the run repeated back to back)")
    p.add_argument("--fatigue-design-life-h", type=float, metavar="H",
                   help="design life of the safety factor, hours (default 10000, assumed)")
    p.add_argument("--fatigue-nodes", default="", metavar="N1,N2,...",
                   help="extra candidate nodes (rows of the reduced cage's /mesh/vertices)")
    p.add_argument("--quiet", action="store_true", help="print only the written paths, not the table")
    p.set_defaults(func=cmd_report)


def _fatigue_settings(args):
    """FatigueSettings of the --fatigue options (None without --fatigue)."""
    if not args.fatigue:
        return None
    from flexbearing.analysis.cage_fatigue import HOUR, FatigueSettings
    try:
        nodes = tuple(int(n) for n in args.fatigue_nodes.split(",") if n.strip())
    except ValueError:
        raise InputError(f"--fatigue-nodes = {args.fatigue_nodes!r} must be node numbers separated by commas, "
                         f"e.g. 13598,12597") from None
    given = {"material": args.fatigue_material, "correction": args.fatigue_correction,
             "design_life": None if args.fatigue_design_life_h is None else args.fatigue_design_life_h * HOUR}
    return FatigueSettings(blocks_per_hour=args.fatigue_blocks_per_hour, nodes=nodes, settle=args.settle,   # None: auto
                           **{k: v for k, v in given.items() if v is not None}).validate()


def _check_reduced_cage(path) -> None:
    """InputError unless --reduced-cage names a readable reduced cage file (not, e.g., a run's
    results file)."""
    from flexbearing.common.safe_files import h5_file_kind
    p = Path(path)
    if not p.is_file():
        raise InputError(f"--reduced-cage {path}: no such file (give a reduced cage file of `flexbearing reduce`)")
    kind = h5_file_kind(p)
    if kind != "reduced cage file":
        what = f" (it is a {kind})" if kind else ""
        raise InputError(f"--reduced-cage {path}: not a reduced cage file{what}; give the reduced cage the run "
                         f"used (`flexbearing reduce` writes them; default: the one the run names)")


def cmd_report(args) -> int:
    if args.reduced_cage:
        _check_reduced_cage(args.reduced_cage)
    run = Path(args.run)
    out_dir = Path(args.output) if args.output else run.with_name(run.stem + "_report")
    if args.reduced_cage:        # only the reduced cage the run used (its key and content digest)
        from flexbearing.analysis.field_export import check_given_reduced_cage
        check_given_reduced_cage(run, args.reduced_cage)
    res = write_report(run, out_dir, compare=args.compare, frames=args.frames,
                       reduced_cage=args.reduced_cage, quiet=args.quiet,
                       settle=args.settle if args.settle is not None else 0.0,
                       series=args.series, displacement_scale=args.displacement_scale, movie=args.movie,
                       pdf=args.pdf, fatigue=_fatigue_settings(args))
    if not args.quiet:
        print_table(json.loads(res["json"].read_text())["phases"])
    print(f"report: {res['report']} (and {res['html'].name}, plots embedded)")
    print(f"plots:  {len(res['plots'])} PNG in {out_dir}")
    if res["stress_picture"]:
        print(f"stress: {res['stress_picture']}")
    if res["xdmf"]:
        print(f"xdmf:   {res['xdmf']}")
    if res["fatigue"]:
        print(f"fatigue: {res['fatigue']['xdmf']} and {res['fatigue']['picture'].name}")
    if res["series"]:
        for key in ("cage", "points", "rings"):
            if res["series"].get(key):
                print(f"series: {res['series'][key]} ({res['series']['n_frames']} frames)")
        for note in res["series"]["notes"]:
            print(f"series: {note}")
    if res.get("paraview"):
        for key in ("state", "movie"):
            if res["paraview"].get(key):
                print(f"paraview: {res['paraview'][key]}")
        if res["paraview"].get("note"):
            print(f"paraview: {res['paraview']['note']}")
    if res.get("pdf"):
        print(f"pdf:    {res['pdf']}")
    return 0
