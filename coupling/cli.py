"""`flexbearing` command line: one dispatcher, each command defined in the module that owns it.

A command module exposes `register(subparsers)`, which adds its parser(s) and sets
`func=callable(args) -> int`. Command modules import the heavy stacks (gmsh, dolfinx, numba)
inside their functions, so `flexbearing --help` and runs with a cached reduced cage stay light.
"""
from __future__ import annotations

import argparse
import importlib
import importlib.util
import sys

from common.validation import InputError

# Order = order in --help. A module that does not exist yet is skipped.
COMMAND_MODULES = (
    "mesh.cli",            # mesh
    "fem_cage.cli",        # modes, mesh-study, calibrate-cage
    "fem_cage.reduce_cli",  # reduce
    "coupling.run_cli",    # run, validate
    "multibody.cli",       # quasi-static
    "coupling.report",     # report
    "coupling.study",      # study
    "coupling.demo",       # demo
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="flexbearing",
        description="Flexible multibody simulation of three-point-contact ball bearings with a flexible cage.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        if importlib.util.find_spec(name) is None:
            continue
        importlib.import_module(name).register(sub)
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


if __name__ == "__main__":
    sys.exit(main())
