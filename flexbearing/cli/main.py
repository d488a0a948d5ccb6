"""`flexbearing` command line: one dispatcher over the command modules `flexbearing/cli/*.py`.

A command module only parses arguments, calls library functions and prints (docs/architecture.md).
It exposes `register(subparsers)`, which adds its parser(s) and sets `func=callable(args) -> int`,
and imports the heavy stacks (gmsh, dolfinx, numba) inside its functions, so `flexbearing --help`
and runs with a cached reduced cage stay light. A new command: a new `flexbearing/cli/<name>.py`,
listed below.
"""
from __future__ import annotations

import argparse
import sys

from flexbearing.common.validation import InputError
from flexbearing.cli import demo as cli_demo
from flexbearing.cli import export as cli_export
from flexbearing.cli import mesh as cli_mesh
from flexbearing.cli import modes as cli_modes
from flexbearing.cli import quasi_static as cli_quasi_static
from flexbearing.cli import reduce as cli_reduce
from flexbearing.cli import report as cli_report
from flexbearing.cli import run as cli_run
from flexbearing.cli import study as cli_study
from flexbearing.cli import uncertainty as cli_uncertainty
from flexbearing.common.provenance import program_version

# Order = order in --help.
COMMAND_MODULES = (
    cli_mesh,            # mesh
    cli_modes,           # modes, mesh-study, calibrate-cage
    cli_reduce,          # reduce
    cli_run,             # run, validate
    cli_quasi_static,    # quasi-static
    cli_report,          # report
    cli_study,           # study
    cli_export,          # export
    cli_uncertainty,     # uncertainty
    cli_demo,            # demo
)


def version() -> str:
    """The installed package's version (pyproject.toml's [project] version, the one place it is
    written), or "unknown" when flexbearing runs from a source tree that was not installed."""
    return program_version()


class _VersionAction(argparse.Action):
    """--version, the installed version looked up only when asked (importlib.metadata scans the
    installed distributions: ~15 ms at the start of every command otherwise)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0,
                         help=help or "show program's version number and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"flexbearing {version()}")      # stdout, as argparse's own version action
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="flexbearing",
        description="Flexible multibody simulation of three-point-contact ball bearings with a flexible cage.")
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in COMMAND_MODULES:
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except InputError as exc:
        print(f"flexbearing {args.command}: invalid input: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:          # Ctrl-C outside a run's own handling (imports, setup, reports)
        print(f"flexbearing {args.command}: interrupted (Ctrl-C)", file=sys.stderr)
        return 130
    except OSError as exc:             # a file the command could not read or write: one line, no traceback
        print(f"flexbearing {args.command}: {os_error_line(exc)}", file=sys.stderr)
        return 1


def os_error_line(exc: OSError) -> str:
    """One line for an OSError: the file and the system's reason. HDF5's own errors (h5py) come
    as a paragraph of flags with the file in "name = '...'" and the cause in "errno = N": the
    file and the reason are taken from it; a full disk says so."""
    import errno
    import re
    text = str(exc)
    name = exc.filename or (m.group(1) if (m := re.search(r"name = '([^']*)'", text)) else None)
    code = exc.errno or (int(m.group(1)) if (m := re.search(r"errno = (\d+)", text)) else None)
    if code in (errno.ENOSPC, errno.EDQUOT):
        reason = exc.strerror or "disk full (no space left on the device): free space and run again"
    elif exc.strerror:
        reason = exc.strerror
    else:
        reason = (m.group(1) if (m := re.search(r"error message = '([^']*)'", text)) else
                  text.splitlines()[0] if text else type(exc).__name__)
    return f"{name}: {reason}" if name else reason


if __name__ == "__main__":
    sys.exit(main())
