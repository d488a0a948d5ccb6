"""Ctrl-C held across a stretch of work that cannot be left half-done.

`sigint_noted()` replaces Python's SIGINT handler (KeyboardInterrupt) by one that only notes the
signal in the list it yields; the caller looks at the list where stopping is safe (between two
operator applications of an eigen solve, flexbearing.fem_cage.modes; after a Dask cluster has
started, flexbearing.simulation.jobs) and raises KeyboardInterrupt itself. Python lets only the
main thread set a signal handler (signal.signal): elsewhere the list stays empty and nothing changes.
"""
from __future__ import annotations

import contextlib
import signal
import threading


@contextlib.contextmanager
def sigint_noted():
    """In the body a Ctrl-C (SIGINT) is appended to the list yielded instead of raised; the previous
    handler is put back on leaving. Main thread only (elsewhere the list stays empty)."""
    pressed: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield pressed
        return
    old = signal.signal(signal.SIGINT, lambda signum, frame: pressed.append(signum))
    try:
        yield pressed
    finally:
        signal.signal(signal.SIGINT, old)
