"""Work that ended before it was done: one exception family for the job loops.

A run (flexbearing.simulation.run), a study's runs, a case set's cases and the slip-rate validation
(flexbearing.studies) all end early in one of two ways, and keep what they finished:

    WorkStopped                      the family: `rows` holds what finished (a study's or a case
    │                                set's rows; empty for a single run), `cause` the Ctrl-C or
    │                                the error (None when jobs failed one by one)
    ├── Interrupted                  the loop itself stopped (Ctrl-C, an error, the wall budget);
    │   │                            `resumable`: False when resuming would stop the same way
    │   ├── RunInterrupted           one run: its results file holds a checkpoint at `t`
    │   ├── ValidationInterrupted    the slip-rate validation: `missing` the cases not finished
    │   └── UncertaintyInterrupted   the uncertainty study: its rows file holds every finished job
    └── Incomplete                   the loop ran to its end but some jobs failed
        │                            (flexbearing.simulation.jobs.JobFailure each, in `failures`)
        ├── CasesIncomplete          a slip-rate case set
        └── StudyIncomplete          a parameter study

A command catches WorkStopped, prints its message and exits non-zero; the finished work is on
disk (or in `rows`) and running again with resume continues it.
"""
from __future__ import annotations


class WorkStopped(Exception):
    """A job loop ended before all of its work was done (module docstring)."""

    def __init__(self, message: str, rows: list | None = None, cause: BaseException | None = None):
        super().__init__(message)
        self.rows = list(rows or [])
        self.cause = cause


class Interrupted(WorkStopped):
    """The loop stopped as a whole (Ctrl-C or an error)."""

    def __init__(self, message: str, rows: list | None = None, cause: BaseException | None = None,
                 resumable: bool = True):
        super().__init__(message, rows, cause)
        self.resumable = resumable          # False: resuming would stop the same way


class Incomplete(WorkStopped):
    """The loop finished, but some of its jobs failed (`failures`); `rows` holds the finished ones."""

    def __init__(self, message: str, rows: list | None = None, failures: list | None = None):
        super().__init__(message, rows)
        self.failures = list(failures or [])


class RunInterrupted(Interrupted):
    """A run stopped early (Ctrl-C or an error); the results file `path` holds a checkpoint at `t`
    to resume from."""

    def __init__(self, message: str, t: float, path: str, cause: BaseException | None = None,
                 resumable: bool = True):
        super().__init__(message, cause=cause, resumable=resumable)
        self.t = t
        self.path = path


class ValidationInterrupted(Interrupted):
    """The slip-rate validation stopped early: `rows` the finished cases (case order), `missing` the
    case numbers that did not finish, `cause` the Ctrl-C or the error."""

    def __init__(self, message: str, rows: list, missing: list[int], cause: BaseException):
        super().__init__(message, rows, cause)
        self.missing = missing


class UncertaintyInterrupted(Interrupted):
    """The uncertainty study stopped early; every finished (point, case) is in its rows file
    (`rows_file`), and running it again runs only the others."""

    def __init__(self, message: str, rows_file: str, cause: BaseException):
        super().__init__(message, cause=cause)
        self.rows_file = rows_file


class CasesIncomplete(Incomplete):
    """Some cases of a slip-rate case set failed; their results files stay, --resume reads the
    finished ones back."""


class StudyIncomplete(Incomplete):
    """Some runs of a study failed; the others are finished and on disk, and running the study
    again reuses them."""
