"""Slip-rate case sets: the cases of a published test table run as scenes, and the cage slip rate
read from each run (`flexbearing run --case-set`).

A case set (flexbearing.simulation.scene.load_case_set; scenes/slip_rate_table4.toml) is a base scene
and a table of operating points with the test's and the paper's slip rates; every selected case is a
run of its own results file, caseNN.h5, and its row compares the slip rate of the run,

    S = (nm − nc)/nm = 1 − <nc>/<nm>,   nm = 0.5·ni·(1 − Dw·cos(alpha)/dm)

(cage speed nc, nominal cage speed nm, both averaged over the steady window; Yang, Liu & Deng,
Lubricants 2025, 13, 249, §3.2), with the test and the paper.
"""
from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.simulation.jobs import require_scheduler, require_workers, run_jobs, runs_in_this_process
from flexbearing.simulation.run import finished_run, run_scene
from flexbearing.simulation.stopped import Incomplete


class CasesIncomplete(Incomplete):
    """Some cases of a slip-rate case set failed (`run_case_set_slip_rate`); their results files stay,
    --resume reads the finished ones back (the family: flexbearing.simulation.stopped)."""


def slip_rate_from_results(path, average_from: float) -> dict:
    """Cage slip rate of a steady run (paper §3.2): S = (nm − nc)/nm = 1 − <nc>/<nm>, with the cage
    speed nc and the nominal cage speed nm = 0.5·ni·(1 − Dw·cos(alpha)/dm) averaged over
    t >= average_from (the test measures a time-averaged cage speed). Falls back to the mean of the
    recorded slip_rate if the speeds were not recorded.

    Returns {"slip": S, "drift": S(second half of the window) − S(first half)}: a drift that is
    not small against S means the cage speed had not settled (run longer)."""
    with h5py.File(path, "r") as f:
        out = f["outputs"]
        t = out["time"][...]
        win = t >= average_from - 1e-12
        if not win.any():
            raise InputError(f"average_from = {average_from:g} s is after the last sample ({t[-1]:g} s)")
        if "cage_speed" in out and "nominal_cage_speed" in out:
            nc, nm = out["cage_speed"][...], out["nominal_cage_speed"][...]
            slip = lambda w: float(1.0 - np.mean(nc[w]) / np.mean(nm[w]))  # noqa: E731
        elif "slip_rate" in out:
            sr = out["slip_rate"][...]
            slip = lambda w: float(np.mean(sr[w]))  # noqa: E731
        else:
            raise InputError(f"{path} has neither cage_speed and nominal_cage_speed nor slip_rate: "
                             f"record 'cage_speed' and 'slip' in the case set's [base.output]")
        idx = np.flatnonzero(win)
        half = len(idx) // 2
        drift = slip(idx[half:]) - slip(idx[:half]) if half > 0 else 0.0
        return {"slip": slip(win), "drift": drift}


def _slip_and_drift(d: dict) -> dict:
    return {"slip_ours": d["slip"], "slip_drift": d["drift"]}


def _run_case(scene, path: str, resume: bool, quiet: bool, backend=None) -> dict:
    """One case of a case set (a job of flexbearing.simulation.jobs.run_jobs, on a Dask worker; a tests'
    stand-in backend only in this process)."""
    return run_scene(scene, path, resume=resume, force=not resume, quiet=quiet, backend=backend)


def run_case_set_slip_rate(case_set, case_ids, out_dir, resume: bool = False, quiet: bool = False,
                           backend=None, workers: int = 1, scheduler: str | None = None) -> list[dict]:
    """Run the selected cases of a slip-rate case set (one results file per case in out_dir,
    caseNN.h5) and return rows: case, group, axial_load, radial_load, speed_rpm, slip_ours,
    slip_test, slip_paper (slip rates as fractions), slip_drift (see slip_rate_from_results),
    wall_time_s, n_steps.

    The cases are jobs of flexbearing.simulation.jobs.run_jobs: `workers` at once on a Dask LocalCluster (1: one
    after the other in this process) or on the cluster at `scheduler`. With resume, a finished
    case (finished_run) is read back without sending it out. A case that fails does not stop the
    others: CasesIncomplete then carries the finished rows. `backend` (tests' stand-in physics)
    runs in this process only, workers = 1."""
    require_workers(workers)
    require_scheduler(scheduler)
    if backend is not None and (workers != 1 or scheduler is not None):
        raise InputError("a backend object runs in this process only: workers = 1 and no scheduler")
    by_id = {c["id"]: c for c in case_set.cases}
    unknown = [i for i in case_ids if i not in by_id]
    if unknown:
        raise InputError(f"--cases: case {unknown[0]} is not in {case_set.path} "
                         f"(allowed: {', '.join(str(i) for i in sorted(by_id))})")
    out_dir = Path(out_dir)
    summaries, todo = {}, []
    for cid in case_ids:
        path = out_dir / f"case{cid:02d}.h5"
        summary = finished_run(case_set.scenes[cid], path) if resume else None
        if summary is None:
            todo.append(cid)
        else:
            summaries[cid] = summary
    here = runs_in_this_process(workers, scheduler, len(todo))
    if not quiet:
        for cid in case_ids:
            c = by_id[cid]
            done = "finished, read back" if cid in summaries else "to run"
            print(f"case {cid}: Fa {c['axial_load']:g} N, Fr {c['radial_load']:g} N, "
                  f"{c['speed_rpm']:g} rpm -> {out_dir / f'case{cid:02d}.h5'} ({done})", flush=True)
    jobs = [(case_set.scenes[cid], str(out_dir / f"case{cid:02d}.h5"), resume, quiet or not here, backend)
            for cid in todo]
    failures = run_jobs(_run_case, jobs, lambda k, summary: summaries.__setitem__(todo[k], summary),
                        workers=workers, scheduler=scheduler, names=[f"case {cid}" for cid in todo],
                        description="slip-rate cases", progress=not (quiet or here))
    rows = []
    for cid in case_ids:
        if cid not in summaries:
            continue
        c, summary, path = by_id[cid], summaries[cid], out_dir / f"case{cid:02d}.h5"
        rows.append({"case": cid, "group": c["group"], "axial_load": c["axial_load"],
                     "radial_load": c["radial_load"], "speed_rpm": c["speed_rpm"],
                     **_slip_and_drift(slip_rate_from_results(path, case_set.average_from)),
                     "slip_test": c["test_slip_percent"] / 100.0,
                     "slip_paper": c["paper_slip_percent"] / 100.0,
                     "wall_time_s": summary["wall_time_s"], "n_steps": summary["n_steps"]})
    if failures:
        raise CasesIncomplete(f"{len(failures)} of {len(case_ids)} cases failed ({'; '.join(map(str, failures))}); "
                              f"the others are in {out_dir}", rows, failures)
    return rows
