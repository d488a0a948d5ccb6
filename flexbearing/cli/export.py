"""`flexbearing export`: a run's results for other tools (flexbearing.analysis.export).

    flexbearing export RUN.h5 [--netcdf FILE.nc] [--csv DIR]

--netcdf: one netCDF-4 file (named dimensions, time coordinate, CF units); --csv: one CSV per
output in DIR for spreadsheets. The results file itself opens in xarray as it is:
xarray.open_dataset(RUN.h5, group="outputs").
"""
from __future__ import annotations

from flexbearing.common.validation import InputError
from flexbearing.common.safe_files import OutputPlan
from flexbearing.analysis.export import write_csv, write_netcdf


def register(subparsers) -> None:
    p = subparsers.add_parser("export", help="a run's results as netCDF or CSV (for xarray, spreadsheets, other tools)",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="results file (.h5) written by `flexbearing run`")
    p.add_argument("--netcdf", metavar="FILE", help="write one netCDF-4 file (.nc)")
    p.add_argument("--csv", metavar="DIR", help="write one CSV per output into DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_export)


def planned_outputs(args) -> OutputPlan:
    """Every file `flexbearing export` writes: --netcdf FILE, --csv DIR/<output>.csv (one per
    output of the run: flexbearing.analysis.export.write_csv). Each is written by a temporary
    beside it, renamed (flexbearing.common.safe_files.atomic_output)."""
    plan = OutputPlan("flexbearing export", inputs=[args.run])
    if args.netcdf:
        plan.file(args.netcdf, "--netcdf")
    if args.csv:
        plan.folder(args.csv, "--csv", patterns=("*.csv",))
    return plan


def cmd_export(args) -> int:
    if not args.netcdf and not args.csv:
        raise InputError("give --netcdf FILE and/or --csv DIR (what to write)")
    planned_outputs(args).check()                   # both outputs, before either is written
    if args.netcdf:
        print(f"netCDF: {write_netcdf(args.run, args.netcdf, quiet=args.quiet)}")
    if args.csv:
        files = write_csv(args.run, args.csv, quiet=args.quiet)
        print(f"CSV: {len(files)} files in {args.csv}")
    return 0
