"""Independent jobs on dask.distributed: the one way the project runs jobs at once (the runs of a
study, flexbearing.studies.study; the cases of the slip-rate validation, flexbearing.studies.validate; the samples of
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

import logging
import os
import uuid
from dataclasses import dataclass

from tqdm import tqdm

from flexbearing.common.validation import InputError

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
    """scheduler: None or a Dask scheduler address "tcp://host:port" (also tls://, inproc://)."""
    if scheduler is None:
        return None
    if not isinstance(scheduler, str) or "://" not in scheduler or not scheduler.split("://", 1)[1]:
        raise InputError(f"--scheduler = {scheduler!r} is not a scheduler address; allowed: "
                         f"PROTOCOL://HOST:PORT as printed by `dask scheduler`, e.g. tcp://10.0.0.5:8786")
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


def _run_on_dask(func, jobs, on_result, names, description, progress, n_workers,
                 scheduler) -> list[JobFailure]:
    from distributed import Client, as_completed

    cluster = None
    client = None
    futures = []
    failures = []
    bar = _bar(len(jobs), description, progress)
    try:
        if scheduler is None:
            cluster = _local_cluster(n_workers)
            client = Client(cluster, set_as_default=False)
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
    return sorted(failures, key=lambda f: f.index)
