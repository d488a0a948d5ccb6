"""Which program wrote a file: the installed version and, from a git checkout, the commit.

Written into every results file (flexbearing.simulation.results) and printed in the report's
summary, so that a result handed on names the code that made it. The version is pyproject.toml's
[project] version, the one place it is written, as the installed distribution reports it.
"""
from __future__ import annotations

import subprocess
from functools import lru_cache
from pathlib import Path
from importlib.metadata import PackageNotFoundError, version

UNKNOWN = "unknown"


def program_version() -> str:
    """The installed flexbearing's version, or "unknown" when it runs from a source tree that was
    not installed (importlib.metadata scans the installed distributions: ask only when needed)."""
    try:
        return version("flexbearing")
    except PackageNotFoundError:
        return UNKNOWN


@lru_cache(maxsize=1)
def git_commit() -> str:
    """The commit of the source tree the package runs from (`git describe --always --dirty
    --abbrev=12`: "-dirty" when it has uncommitted changes), or "unknown" for an installed copy
    outside a git checkout or without git."""
    here = Path(__file__).resolve().parent
    try:
        out = subprocess.run(["git", "-C", str(here), "describe", "--always", "--dirty", "--abbrev=12"],
                             capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return UNKNOWN
    if out.returncode != 0:
        return UNKNOWN
    # an installed copy inside some other repository would report that repository's commit
    top = subprocess.run(["git", "-C", str(here), "rev-parse", "--show-toplevel"], capture_output=True,
                         text=True, timeout=10).stdout.strip()
    if not top or not (Path(top) / "flexbearing" / "common" / "provenance.py").is_file():
        return UNKNOWN
    return out.stdout.strip()
