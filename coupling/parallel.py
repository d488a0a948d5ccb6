"""Independent jobs run N at once in forked processes: the slip-rate validation's cases
(coupling.validate) and a study's runs (coupling.study).

fork (Linux): the workers inherit the compiled kernels, and a user's script needs no
`if __name__ == "__main__"` guard as it would with spawn; callers must not hold threads or an
initialised MPI when they call this (the FE stack is only ever imported in a child,
coupling.study._prepare_reduced_cages).
"""
from __future__ import annotations

from common.validation import InputError


def require_workers(workers) -> int:
    """workers must be an integer >= 1 (the number of jobs run at once)."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"workers = {workers!r} is not allowed; allowed: an integer >= 1")
    return workers


def run_in_processes(func, jobs: list[tuple], workers: int, on_result) -> None:
    """func(*job) for every job, `workers` at once; on_result(k, result) in this process as job k
    finishes (in job order when they run one after the other: workers == 1 or a single job, in
    this process). Jobs are submitted in the order given. An error in a job or a Ctrl-C cancels
    the jobs not started and propagates."""
    require_workers(workers)
    if workers == 1 or len(jobs) < 2:
        for k, job in enumerate(jobs):
            on_result(k, func(*job))
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    with ProcessPoolExecutor(max_workers=min(workers, len(jobs)),
                             mp_context=multiprocessing.get_context("fork")) as pool:
        futures = {pool.submit(func, *job): k for k, job in enumerate(jobs)}
        try:
            for f in as_completed(futures):
                on_result(futures[f], f.result())
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise
