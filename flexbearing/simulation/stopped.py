"""Work that ended before it was done: one exception family for the job loops.

A run (flexbearing.simulation.run), a study's runs, a case set's cases and the slip-rate validation
(flexbearing.studies) all end early in one of two ways, and keep what they finished:

    WorkStopped                      the family: `rows` holds what finished (a study's or a case
    │                                set's rows; empty for a single run), `cause` the Ctrl-C or
    │                                the error (None when jobs failed one by one)
    ├── Interrupted                  the loop itself stopped (Ctrl-C, an error, the wall budget);
    │   │                            `resumable`: False when resuming would stop the same way
    │   ├── RunInterrupted           one run: its results file holds a checkpoint at `t`
    │   │                            (flexbearing.simulation.run)
    │   ├── ValidationInterrupted    the slip-rate validation: `missing` the cases not finished
    │   │                            (flexbearing.studies.validation.slip_rate)
    │   └── UncertaintyInterrupted   the uncertainty study: its rows file holds every finished job
    │                                (flexbearing.studies.uncertainty)
    └── Incomplete                   the loop ran to its end but some jobs failed
        │                            (flexbearing.simulation.jobs.JobFailure each, in `failures`)
        ├── CasesIncomplete          a slip-rate case set (flexbearing.studies.case_sets)
        └── StudyIncomplete          a parameter study (flexbearing.studies.study)

This module holds the family; each member is defined beside the loop that raises it (the module
named with it), so that a loop and its way of stopping are read together and no lower layer
names a study. A command catches WorkStopped (or the member it handles), prints its message and
exits non-zero; the finished work is on disk (or in `rows`) and running again with resume
continues it.
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
