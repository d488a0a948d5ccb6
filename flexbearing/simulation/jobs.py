"""Independent jobs on dask.distributed: the one way the project runs jobs at once (the runs of a
study, flexbearing.studies.study; the cases of the slip-rate validation, flexbearing.studies.validation.slip_rate; the samples of
the validation under uncertainty).

    failures = run_jobs(func, jobs, on_result, workers=None, scheduler=None, names=None,
                        description="jobs")

func(*job) runs on a Dask worker for every job; on_result(k, result) is called in this process
as job k finishes (any order). Where the jobs run:

- scheduler None, workers 1 (or a single job): in this process, one after the other in job
  order (no cluster; tests and small runs);
- scheduler None, workers N > 1: a `distributed.LocalCluster` of min(N, jobs) worker processes
  (one thread each: a job is a compiled integration that holds the GIL), started for the call and
  closed after it; workers=None means os.cpu_count();
- scheduler "tcp://host:port": the workers of an existing cluster (`dask scheduler` and
  `dask worker tcp://host:port` on the machines; the CLI's --scheduler). The jobs' files (results,
  the reduced cage) are read and written by the workers at the paths given, so every worker must
  see the same folders (a shared file system) and run the same flexbearing.

A job that raises (or whose worker dies) is reported as a JobFailure(index, name, message) and
returned; it does not stop the others. A Ctrl-C cancels the futures, closes the client (and the
LocalCluster) and is re-raised. A tqdm bar counts finished jobs.

LocalCluster's workers are new processes (multiprocessing "spawn", Dask's default), not forks:
the parent may hold threads or an initialised MPI, and a user's script that calls run_jobs with
workers > 1 needs the usual `if __name__ == "__main__":` guard.
"""
from __future__ import annotations

import atexit
import contextlib
import json
import logging
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import uuid
from pathlib import Path
from dataclasses import dataclass

from tqdm import tqdm

from flexbearing.common.validation import InputError
from flexbearing.common.interrupt import sigint_noted

CONNECT_TIMEOUT = "20s"      # to reach the scheduler given by --scheduler

@dataclass(frozen=True)
class JobFailure:
    """A job that did not finish: its index in `jobs`, its name and what went wrong."""
    index: int
    name: str
    message: str

    def __str__(self) -> str:
        return f"{self.name}: {self.message}"


def require_workers(workers) -> int:
    """workers must be an integer >= 1 (the number of jobs run at once)."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"workers = {workers!r} is not allowed; allowed: an integer >= 1")
    return workers


def require_scheduler(scheduler) -> str | None:
    """scheduler: None or a Dask scheduler address "tcp://HOST:PORT", checked at once (a wrong one
    otherwise gives a traceback after the connection timeout). Only tcp:// is accepted: inproc://
    is a scheduler inside this very process (no cluster to use), tls:// and ws(s):// need security
    or web-socket settings this command does not take, and http:// is the dashboard's address,
    not the scheduler's."""
    if scheduler is None:
        return None
    text = scheduler if isinstance(scheduler, str) else repr(scheduler)
    proto, _, rest = text.partition("://")
    host, _, port = rest.rpartition(":")
    if proto != "tcp" or not host or not port.isdigit() or not 1 <= int(port) <= 65535:
        why = (f"protocol {proto}:// is not supported (only tcp://)" if rest and proto != "tcp"
               else "it is not an address of the form tcp://HOST:PORT")
        raise InputError(f"--scheduler = {text!r}: {why}; give the address `dask scheduler` prints, "
                         f"e.g. tcp://10.0.0.5:8786 (PORT 1-65535)")
    return scheduler


def _message(exc: BaseException) -> str:
    text = str(exc).strip()
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _bar(total: int, description: str, progress: bool):
    return tqdm(total=total, desc=description, unit="job", disable=not progress, dynamic_ncols=True)


def runs_in_this_process(workers: int | None, scheduler: str | None, n_jobs: int) -> bool:
    """Whether run_jobs runs n_jobs jobs here, one after the other (no cluster): no scheduler and
    a single worker or a single job (callers keep a run's own progress output then)."""
    return scheduler is None and ((workers if workers is not None else os.cpu_count() or 1) == 1
                                  or n_jobs == 1)


def run_jobs(func, jobs: list[tuple], on_result, *, workers: int | None = None,
             scheduler: str | None = None, names: list[str] | None = None,
             description: str = "jobs", progress: bool = True) -> list[JobFailure]:
    """Run func(*job) for every job (module docstring: where); on_result(k, result) in this
    process as job k finishes. Returns the failed jobs (index order); [] when all finished.

    names: one per job, for the failure reports and the bar (default "<description> k").
    progress: False hides the bar (the jobs still run)."""
    jobs = [tuple(j) for j in jobs]
    if names is None:
        names = [f"{description} {k}" for k in range(len(jobs))]
    names = [str(n) for n in names]
    if len(names) != len(jobs):
        raise InputError(f"names has {len(names)} entries; allowed: one per job ({len(jobs)})")
    if workers is None:
        workers = os.cpu_count() or 1
    require_workers(workers)
    require_scheduler(scheduler)
    if not jobs:
        return []
    if runs_in_this_process(workers, scheduler, len(jobs)):
        return _run_here(func, jobs, on_result, names, description, progress)
    return _run_on_dask(func, jobs, on_result, names, description, progress,
                        min(workers, len(jobs)), scheduler)


def _run_here(func, jobs, on_result, names, description, progress) -> list[JobFailure]:
    """In this process, in job order."""
    failures = []
    bar = _bar(len(jobs), description, progress)
    try:
        for k, job in enumerate(jobs):
            try:
                result = func(*job)
            except Exception as exc:           # reported; the next job goes on (Ctrl-C does not)
                if isinstance(exc.__cause__, KeyboardInterrupt):
                    raise                      # a Ctrl-C the job turned into its own error
                failures.append(JobFailure(k, names[k], _message(exc)))
                bar.set_postfix_str(f"{len(failures)} failed")
            else:
                on_result(k, result)
            bar.update(1)
    finally:
        bar.close()
    return failures


def _local_cluster(n_workers: int):
    """A LocalCluster of n worker processes, one thread each, quiet, no dashboard, no memory
    limit (a worker paused or killed for memory would stall or lose a run; the OS decides)."""
    import dask
    from distributed import LocalCluster
    with dask.config.set({"distributed.worker.daemon": False}):
        # no dashboard; the scheduler's small HTTP server (health, metrics) on a free port, not on
        # 8787, which another cluster on the machine may hold
        return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                            dashboard_address=None, scheduler_kwargs={"dashboard_address": ":0"},
                            memory_limit=0, silence_logs=logging.ERROR)


_PYTHON_IGNORING_SIGINT: str | None = None


def _python_ignoring_sigint() -> str | None:
    """An executable that starts this Python with SIGINT ignored (a two-line shell script: trap
    '' INT, exec), made once per process in a private temporary folder and tried once; None where
    it cannot run (a file system mounted noexec). A Python started with SIGINT ignored keeps it
    ignored: no KeyboardInterrupt, no traceback, when a terminal's Ctrl-C reaches it."""
    global _PYTHON_IGNORING_SIGINT
    if _PYTHON_IGNORING_SIGINT is None:
        folder = tempfile.mkdtemp(prefix="flexbearing-python-")
        atexit.register(shutil.rmtree, folder, True)
        path = os.path.join(folder, "python")
        with open(path, "w") as fh:
            fh.write(f"#!/bin/sh\ntrap '' INT\nexec {shlex.quote(sys.executable)} \"$@\"\n")
        os.chmod(path, 0o700)
        probe = "import signal, sys; sys.exit(signal.getsignal(signal.SIGINT) is not signal.SIG_IGN)"
        try:
            ok = subprocess.run([path, "-c", probe], timeout=60).returncode == 0
        except (OSError, subprocess.SubprocessError):
            ok = False
        _PYTHON_IGNORING_SIGINT = path if ok else ""
    return _PYTHON_IGNORING_SIGINT or None


@contextlib.contextmanager
def _children_ignore_sigint():
    """Processes that multiprocessing spawns in the body (the LocalCluster's workers, and those
    its nannies restart) start with SIGINT ignored (_python_ignoring_sigint); this process keeps
    its own handler."""
    import multiprocessing.spawn as spawn
    exe = _python_ignoring_sigint()
    old = spawn.get_executable()
    if exe:
        spawn.set_executable(exe)
    try:
        yield
    finally:
        spawn.set_executable(old)


def _run_on_dask(func, jobs, on_result, names, description, progress, n_workers,
                 scheduler) -> list[JobFailure]:
    from distributed import Client, as_completed

    cluster = None
    client = None
    futures = []
    failures = []
    bar = _bar(len(jobs), description, progress)
    stack = contextlib.ExitStack()
    try:
        if scheduler is None:
            # The cluster's worker processes start with SIGINT ignored: a Ctrl-C at the terminal,
            # sent to the whole process group, reaches this process alone, which cancels the jobs
            # and closes the cluster (no traceback of every worker, no half-started cluster)
            # and a Ctrl-C while it starts is held until it has (then raised, with the cluster
            # and the client assigned for the `finally` below to close)
            stack.enter_context(_children_ignore_sigint())
            with sigint_noted() as pressed:
                cluster = _local_cluster(n_workers)
                client = Client(cluster, set_as_default=False)
            if pressed:
                raise KeyboardInterrupt
        else:
            try:
                client = Client(scheduler, set_as_default=False, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError) as exc:
                raise InputError(f"--scheduler = {scheduler!r}: no Dask scheduler answers there "
                                 f"({_message(exc)}); start one with `dask scheduler` and workers with "
                                 f"`dask worker {scheduler}`") from None
            try:
                client.wait_for_workers(1, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError):
                raise InputError(f"--scheduler = {scheduler!r}: the scheduler has no worker; start them with "
                                 f"`dask worker {scheduler}`") from None
        tag = uuid.uuid4().hex[:8]
        index = {}
        for k, job in enumerate(jobs):
            fut = client.submit(func, *job, key=f"{description}-{k}-{tag}", pure=False, retries=0)
            index[fut.key] = k
            futures.append(fut)
        for fut in as_completed(futures, loop=client.loop):
            k = index[fut.key]
            if fut.status == "finished":
                result = fut.result()
                fut.release()
                on_result(k, result)
            else:                               # "error" (raised) or "cancelled" (worker lost)
                try:
                    exc = fut.exception()
                except BaseException as e:       # a cancelled future raises CancelledError here
                    exc = e
                failures.append(JobFailure(k, names[k], _message(exc)))
                bar.set_postfix_str(f"{len(failures)} failed")
            bar.update(1)
    except BaseException:
        # Ctrl-C or an error of on_result: stop the jobs still queued or running, then re-raise
        if client is not None and futures:
            try:
                client.cancel(futures, force=True)
            except Exception:
                pass
        raise
    finally:
        bar.close()
        if client is not None:
            try:
                client.close(timeout=10)
            except Exception:
                pass
        if cluster is not None:
            try:
                cluster.close(timeout=10)
            except Exception:
                pass
        stack.close()
    return sorted(failures, key=lambda f: f.index)


def read_rows(path) -> list[dict]:
    """The rows of a JSON-lines results file, as the studies append them one finished job at a time
    (a torn last line, from a kill mid-write, is skipped; a missing file has no rows)."""
    path = Path(path)
    rows = []
    if path.exists():
        for line in path.read_text().splitlines():
            try:
                rows.append(json.loads(line))
            except json.JSONDecodeError:
                continue
    return rows
