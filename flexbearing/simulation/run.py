"""Run a scene: scene → model → initial state → advance loop → sampled outputs → HDF5 → summary.json.

    t_k = k·dt (k = 0..N, the scene's sample interval; computed from k, never accumulated)
    the integrator is stopped at every kink or jump of the spectra (speed-table knots, load-table
    knots, impact start and end) so that no step straddles a discontinuity, and at every
    SAMPLES_PER_CALL-th sample and checkpoint; the samples between are the states its continuous
    extension gives at t_k inside a step (flexbearing.multibody.integrator, "Samples"); outputs are evaluated
    at t_k only, and only those the scene records.

The physics comes from a *backend*, a namespace with
    build_model(bearing, oil, options) -> model
    initial_state(model, speed_rad_s, Fa, Fr) -> y0
    advance(model, y, t, t_next, speed_table, load_table, impacts, tol, h) -> (y, t, h, n_steps, n_rejected)
    advance_sampled (optional)(model, y, t, t_next, sample_times, speed_table, load_table, impacts, tol, h)
              -> (y, t, h, n_steps, n_rejected, states at sample_times, snapshots at them)
    evaluate_outputs(model, t, y, ...) -> dict[str, array]      (keyword arguments it declares among
                                         outputs, speed_table, load_table, impacts, film (True when
                                         film_thickness is recorded), energy (True when power_loss
                                         is recorded) are passed)
    OUTPUT_UNITS (optional dict name -> unit; default: flexbearing.multibody.output_registry)
`default_backend(scene)` assembles it from multibody.{model, initial, integrator, outputs} (rigid
cage) or from flexbearing.coupling.flexible_cage (flexible cage); tests pass a small fake backend so that
streaming, checkpoints and resume are proven independently of the physics. Nothing here imports
the FE stack.

What each scene output records: flexbearing.multibody.output_registry (a backend whose evaluate_outputs takes
`outputs=` selects its keys itself; a key the registry does not know is recorded when it starts
with a requested output's name). The inner-ring speed and the external load (the spectra at t_k)
are always recorded. Vectors of mixed units are split into SI datasets (the registry's `source`).
"""
from __future__ import annotations

import inspect
import json
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from flexbearing.simulation.progress import RunProgress
from flexbearing.simulation.results import DiskFull, OutputTooLarge, ResultsWriter, write_summary
from flexbearing.simulation.wall_budget import WallBudget
from flexbearing.common.file_lock import exclusive_file
from flexbearing.common.validation import InputError
from flexbearing.multibody import output_registry as R
from flexbearing.multibody.profiles import load_at, speed_at


GIL_SWITCH_INTERVAL = 1e-4     # s, during a run's loop (_run_claimed: why; measured in issue 21)
SAMPLES_PER_CALL = 25          # samples per compiled call at most (progress and Ctrl-C respond
                               # after each; ~0.05 s of wall time on the paper's scenes)


def _next_multiple(k: int, m: int) -> int:
    """The smallest multiple of m that is greater than k."""
    return (k // m + 1) * m


def recorded_keys(requested, returned) -> list[str]:
    """The keys of `returned` (an evaluation's keys) to record for the requested scene outputs: those
    flexbearing.multibody.output_registry lists under them (and the ALWAYS ones); a key the registry does not
    know (another backend's) is recorded when it starts with a requested output's name."""
    want = R.evaluated_names(requested)
    return [k for k in returned
            if k in want or (k not in R.EVALUATED and any(k.startswith(r) for r in requested))]


class RunInterrupted(Exception):
    """The run stopped early (Ctrl-C or an error); the results file holds a checkpoint to resume."""

    def __init__(self, message: str, t: float, path: str, cause: BaseException | None = None,
                 resumable: bool = True):
        super().__init__(message)
        self.t = t
        self.path = path
        self.cause = cause
        self.resumable = resumable          # False: --resume would stop the same way


def default_backend(scene) -> SimpleNamespace:
    """The physics for this scene's cage model (imports only what that model needs: the flexible
    cage's backend loads the reduced cage file, and builds it with the FE stack only when it is not
    cached)."""
    if scene.cage_model == "flexible":
        from flexbearing.coupling.flexible_cage import backend
        return backend(scene)
    from flexbearing.multibody import initial, integrator, model, outputs
    return SimpleNamespace(build_model=model.build_model, initial_state=initial.initial_state,
                           advance=integrator.advance, advance_sampled=integrator.advance_sampled,
                           evaluate_outputs=outputs.evaluate_outputs,
                           new_workspace=integrator.Workspace)


def _accepted_kwargs(func, available: dict) -> dict:
    try:
        params = inspect.signature(func).parameters
    except (TypeError, ValueError):
        return {}
    if any(p.kind == p.VAR_KEYWORD for p in params.values()):
        return dict(available)
    return {k: v for k, v in available.items() if k in params}


def _prepare_output(out_path: Path, resume: bool, force: bool) -> str:
    """'new' or 'resume'; refuse to overwrite an existing file unless forced. Touches no file
    (the folder is created if missing)."""
    if resume and force:
        raise InputError("--resume and --force exclude each other: --resume continues the run in the "
                         "file, --force starts it again from t = 0 (overwriting it); give one")
    if out_path.suffix not in (".h5", ".hdf5"):
        raise InputError(f"-o {out_path}: the results file must end in .h5 or .hdf5")
    if out_path.is_dir():
        raise InputError(f"-o {out_path} is a directory: give a results file name (e.g. {out_path / 'run.h5'})")
    if resume and out_path.exists():
        return "resume"
    if out_path.exists() and not force:
        raise InputError(f"{out_path} exists: pass --resume to continue that run or --force to overwrite it")
    try:
        out_path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        blocker = next((q for q in (out_path.parent, *out_path.parent.parents) if q.exists()), None)
        why = f"{blocker} is a file, not a folder" if blocker and not blocker.is_dir() else exc.strerror
        raise InputError(f"-o {out_path}: its folder {out_path.parent} cannot be created ({why}); "
                         f"choose a file in a writable folder") from None
    return "new"


def run_scene(scene, out_path, resume: bool = False, force: bool = False, quiet: bool = False,
              backend=None, max_wall_time: float | None = None, max_output_bytes: float | None = None) -> dict:
    """Run `scene` (a validated flexbearing.simulation.scene.Scene), stream results to `out_path`, return the summary.

    resume: continue the run in `out_path` from its last checkpoint (start afresh if the file does
    not exist). On Ctrl-C or an error the file keeps every sample computed so far and a checkpoint
    at the last one, and RunInterrupted is raised. A run predicted to need more than an hour warns
    (flexbearing.simulation.wall_budget.SlowRunWarning); with `max_wall_time` [s] one predicted to need more stops
    (RunInterrupted, resumable). The file is claimed (flexbearing.common.file_lock) before it
    is touched: a file another process is writing is refused (InputError) and left as it is.
    Before the first block is written, the file's size is estimated from it (n_samples × its
    bytes per sample) and checked against the free space and `max_output_bytes`
    (flexbearing.simulation.results.DEFAULT_MAX_OUTPUT_BYTES when None): OutputTooLarge.
    """
    from flexbearing.common.validation import require_range
    if max_output_bytes is not None:
        require_range("--max-output-size", max_output_bytes, 1.0, 1e15, unit="bytes")
    from flexbearing.common.safe_files import refuse_overwriting_inputs
    out_path = Path(out_path)
    refuse_overwriting_inputs(out_path, [scene.path or None])      # a link, or the scene itself
    mode = _prepare_output(out_path, resume, force)
    with exclusive_file(out_path):
        try:
            return _run_claimed(scene, out_path, mode, quiet, backend, max_wall_time, max_output_bytes)
        except KeyboardInterrupt as exc:       # Ctrl-C during the setup, before the first step
            raise RunInterrupted("run interrupted during setup, before t = 0: nothing was computed, "
                                 "nothing to resume (run it again)", 0.0, str(out_path), exc,
                                 resumable=False) from exc


def finished_run(scene, out_path) -> dict | None:
    """The summary of a finished run of `scene` in `out_path`, read without claiming or writing the
    file; None when it holds no finished run (no file, not HDF5, interrupted, being written). A
    file written by a different scene is refused (InputError), as `run_scene(..., resume=True)`
    refuses it. Lets a study or a job list skip its finished runs before sending any job out."""
    import h5py
    from flexbearing.simulation.results import FORMAT, different_scene
    out_path = Path(out_path)
    if not out_path.is_file() or not h5py.is_hdf5(out_path):
        return None
    try:
        with h5py.File(out_path, "r") as f:
            if f.attrs.get("format") != FORMAT:
                return None
            if f.attrs.get("scene_hash") != scene.content_hash():
                raise different_scene(out_path, f.attrs.get("scene_hash"), scene)
            if str(f.attrs.get("status", "")) != "complete" or "summary" not in f.attrs:
                return None
            return json.loads(f.attrs["summary"])
    except OSError:                    # locked or damaged: the run itself will say what is wrong
        return None


def _run_claimed(scene, out_path: Path, mode: str, quiet: bool, backend, max_wall_time,
                 max_output_bytes=None) -> dict:
    """run_scene once the output file is claimed."""
    wall_start = time.perf_counter()
    if backend is None:
        backend = default_backend(scene)
    units = {**R.units(), **(getattr(backend, "OUTPUT_UNITS", {}) or {})}
    model = backend.build_model(scene.bearing, scene.oil, dict(scene.model_options))

    speed_table, load_table, impacts = scene.speed_table, scene.load_table, scene.impacts
    eval_kwargs = _accepted_kwargs(backend.evaluate_outputs, {
        "outputs": tuple(scene.outputs), "speed_table": speed_table, "load_table": load_table,
        "impacts": impacts, "film": "film_thickness" in scene.outputs, "energy": "power_loss" in scene.outputs})
    selects_itself = "outputs" in eval_kwargs
    adv_kwargs = _accepted_kwargs(backend.advance, {"max_step": scene.max_step}) if scene.max_step else {}
    # The integrator's workspace carries its FSAL derivative (f at the end of the last step) from one
    # sample interval to the next; each checkpoint stores it beside the state, so that a resumed
    # run's first step uses the same derivative as the uninterrupted run's (bit-identical files).
    ws = None
    if getattr(backend, "new_workspace", None) is not None and _accepted_kwargs(backend.advance, {"ws": 0}):
        # the workspace carries the method's tableau (flexbearing.multibody.integrator.Workspace)
        ws = backend.new_workspace(model, scene.method)
        adv_kwargs["ws"] = ws
    elif scene.method != "dopri5":
        raise InputError(f"integrator.method = {scene.method!r}: this backend integrates with its own "
                         f"method only (allowed: 'dopri5')")
    load3 = np.zeros(3)
    keys = None

    # What a backend must take at the sample itself, before the integration goes on (the flexible
    # cage's stress peak-hold since the previous sample); the rest of a sample is a function of
    # (t, y) and is evaluated later, in batches (below).
    take_snapshot = getattr(backend, "sample_snapshot", None)
    if take_snapshot is not None and not _accepted_kwargs(backend.evaluate_outputs, {"snapshot": 0}):
        take_snapshot = None

    def sample(t, y, snapshot, on_model) -> dict:
        nonlocal keys
        kw = {"snapshot": snapshot} if take_snapshot is not None else {}
        values = dict(backend.evaluate_outputs(on_model, t, y, **eval_kwargs, **kw))
        if keys is None:
            keys = list(values) if selects_itself else recorded_keys(scene.outputs, values)
        values = R.split_mixed_units({k: values[k] for k in keys})
        if "inner_ring_speed" not in values:
            values["inner_ring_speed"] = speed_at(t, speed_table)
        if "external_load" not in values:
            load_at(t, load_table, impacts, load3)
            values["external_load"] = load3.copy()
        return values

    cp = None
    if mode == "resume" and out_path.stat().st_size == 0:
        # an empty file under our claim: a run killed (SIGKILL, power loss) after claiming the file
        # and before HDF5 wrote its first byte; nothing was computed, so it starts over
        mode = "new"
    if mode == "resume":
        writer, cp = ResultsWriter.open_for_resume(out_path, scene, units)
        if cp is None:               # killed before its first checkpoint: start over in a new file
            writer.close()
            mode = "new"
        elif writer.previous_status == "complete" or cp["n_samples"] >= scene.n_samples:
            writer.set_status("complete")
            writer.close()
            return _finish(scene, out_path, cp["n_steps"], cp["n_rejected"], cp["wall_time"],
                           time.perf_counter() - wall_start)
    if mode == "new":
        writer = ResultsWriter.create(out_path, scene, units)
    writer.n_samples_expected = scene.n_samples
    if max_output_bytes is not None:
        writer.max_output_bytes = float(max_output_bytes)
    # what the backend wants the file to carry (e.g. the reduced cage file and its hash)
    for key, value in (getattr(backend, "FILE_ATTRS", None) or {}).items():
        writer.f.attrs[key] = value

    try:
        if cp is None:
            Fa, Fr = scene.initial_loads()
            f0 = np.zeros(3)
            load_at(0.0, load_table, impacts, f0)      # the full load vector when the backend takes it
            y = np.array(backend.initial_state(model, speed_at(0.0, speed_table), Fa, Fr,
                                               **_accepted_kwargs(backend.initial_state, {"load": f0})),
                         dtype=np.float64)
            t, h, n_steps, n_rejected, wall_before, k = 0.0, scene.initial_step, 0, 0, 0.0, 0
        else:
            y, t, h = cp["y"], cp["t"], cp["h"]
            if ws is not None and cp.get("dydt") is not None and cp["dydt"].shape == ws.K[0].shape:
                ws.K[0][:] = cp["dydt"]
                ws.fsal_t, ws.fsal_y = t, y.copy()
            n_steps, n_rejected, wall_before, k = cp["n_steps"], cp["n_rejected"], cp["wall_time"], cp["n_samples"]
    except BaseException:
        writer.close()
        if cp is None:                     # nothing computed yet: leave no file that blocks a rerun
            out_path.unlink(missing_ok=True)
        raise
    setup_time = time.perf_counter() - wall_start

    bps = scene.breakpoints()
    n_total = scene.n_samples
    every = scene.checkpoint_every
    # A backend with `advance_sampled` integrates a call's samples without stopping at them
    # (flexbearing.multibody.integrator, "Samples"); one call ends at the next multiple of SAMPLES_PER_CALL or
    # of the checkpoint interval (fixed sample indices: a resume stops where the uninterrupted run
    # stopped, so the files agree bit for bit), and at the breakpoints of the spectra.
    sampled = getattr(backend, "advance_sampled", None)
    per_call = SAMPLES_PER_CALL if sampled is not None else 1
    def fsal(t):
        """The derivative the integrator continues with at (t, y), if it holds one (a copy)."""
        return ws.K[0].copy() if ws is not None and ws.fsal_t == t else None

    # A sample's outputs are a function of its (t, y) (and of the backend's snapshot taken at the
    # sample), so the run only records the raw sample while it integrates,
    #     (t, y, h, n_steps, n_rejected, dydt, snapshot),
    # and the writer thread evaluates a checkpoint interval of them, then writes the block and the
    # checkpoint (flexbearing.simulation.results), while the compiled loop (nogil) goes on. The evaluation uses
    # its own model (its own scratch arrays; the integration's are in use). Evaluating after
    # every interval in the integrating thread made the loop's steps ~30 % dearer (caches) and
    # cost 0.5 ms a sample (measured on the paper's scenes, issue 21).
    # `written`: the last sample in the file, what an interruption's checkpoint records.
    eval_model = backend.build_model(scene.bearing, scene.oil, dict(scene.model_options))
    written = (y.copy(), t, h, n_steps, n_rejected, fsal(t) if cp is not None else None)
    failed_tail: list[tuple] = []  # samples a failed integrator call passed (no state to go on from)
    pending: list[tuple] = []      # integrated, not handed over
    inflight: list[tuple] = []     # handed to the writer thread, not known written

    # A record: (t, y, h, n_steps, n_rejected, dydt, snapshot); h is None for a sample the integrator
    # passed inside a step (not a state it can go on from, so no checkpoint is written there).
    def stopped_at(t) -> tuple:
        """The record of the state the integrator stopped at (a state to go on from)."""
        return (t, np.array(y, dtype=np.float64), h, n_steps, n_rejected, fsal(t),
                take_snapshot(model) if take_snapshot is not None else None)

    def passed(t, y_s, snapshot) -> tuple:
        """The record of a sample the integrator passed inside a step."""
        return (t, y_s, None, None, None, None, snapshot)

    def values_of(r) -> dict:
        return sample(r[0], r[1], r[6], eval_model)

    def evaluate(batch) -> list[tuple]:
        return [(r[0], values_of(r)) for r in batch]

    def state_of(r) -> tuple:
        return (r[1], r[0], r[2], r[3], r[4], r[5])

    def settle() -> None:
        """Wait for the interval in the writer thread: written, or (it failed: re-raised) back in
        front of `pending`, for the interrupted run to write itself."""
        nonlocal written, inflight, pending
        try:
            writer.wait()
        except BaseException:
            pending, inflight = inflight + pending, []
            raise
        if inflight:
            written = state_of(inflight[-1])
        inflight = []

    def hand_over(wall_time) -> None:
        nonlocal inflight, pending
        settle()
        inflight, pending = pending, []
        y_s, t_s, h_s, ns_s, nr_s, dydt_s = state_of(inflight[-1])
        writer.checkpoint_in_background(y_s, t_s, h_s, ns_s, nr_s, wall_time=wall_time, dydt=dydt_s,
                                        samples=lambda b=inflight: evaluate(b))

    progress = RunProgress(scene.duration, t0=t, quiet=quiet, desc=scene.name, n_steps0=n_steps)
    budget = WallBudget(scene.duration, t0=t, n_steps0=n_steps, name=scene.name, max_wall_time=max_wall_time)
    loop_start = time.perf_counter()
    # The integrating thread takes the GIL back after every compiled call (up to SAMPLES_PER_CALL
    # samples, ~30 ms; one sample without advance_sampled); with Python's default switch interval it
    # waits up to 5 ms whenever the writer thread holds it.
    switch_interval = sys.getswitchinterval()
    sys.setswitchinterval(GIL_SWITCH_INTERVAL)
    try:
        while k < n_total:
            # the call's last sample: the next multiple of per_call or of every (counted in samples), or the end
            k_end = min(n_total - 1, _next_multiple(k, per_call) - 1, _next_multiple(k, every) - 1)
            t_target = scene.sample_time(k_end)
            if k == 0:                                 # the initial state (t = 0)
                pending.append(stopped_at(t))
                k = 1
            while t < t_target:
                i = int(np.searchsorted(bps, t, side="right"))
                t_stop = bps[i] if i < len(bps) and bps[i] < t_target else t_target
                k_in = k
                while k_in < k_end and scene.sample_time(k_in) < t_stop:
                    k_in += 1
                if sampled is not None:
                    times = np.array([scene.sample_time(j) for j in range(k, k_in)])
                    try:
                        y, _t, h, ns, nr, states, snaps = sampled(model, y, t, t_stop, times, speed_table,
                                                                   load_table, impacts, scene.tolerance, h,
                                                                   **adv_kwargs)
                    except Exception as exc:
                        # an integration that fails (flexbearing.multibody.integrator.SimulationUnstable) hands over
                        # the samples it passed before: kept after the checkpoint (below)
                        part = getattr(exc, "samples", None)
                        if part is not None:
                            failed_tail = [passed(*r) for r in zip(*part)]
                        raise
                    for j in range(k, k_in):
                        pending.append(passed(times[j - k], states[j - k].copy(), snaps[j - k]))
                    k = k_in
                else:
                    y, _t, h, ns, nr = backend.advance(model, y, t, t_stop, speed_table, load_table, impacts,
                                                       scene.tolerance, h, **adv_kwargs)
                t = t_stop          # the integrator lands on t_next; keep the exact stop time
                n_steps += int(ns)
                n_rejected += int(nr)
                if k < n_total and scene.sample_time(k) == t:   # a sample at a breakpoint, or the call's last
                    pending.append(stopped_at(t))
                    k += 1
            if k % every == 0 or k == n_total:
                hand_over(wall_before + time.perf_counter() - loop_start)
            progress.update(t, n_steps)
            budget.update(t, n_steps)
        settle()
    except BaseException as exc:
        progress.close()
        if isinstance(exc, OutputTooLarge):
            writer.close()          # nothing was written: leave no file that needs --force
            out_path.unlink(missing_ok=True)
            raise exc
        if isinstance(exc, DiskFull):
            # nothing more is written (it would not fit): the file holds its last checkpoint
            writer.close()
            raise RunInterrupted(f"run stopped at t = {written[1]:.6g} s: {out_path}: {exc.strerror}",
                                 written[1], str(out_path), exc) from exc
        status = "interrupted" if isinstance(exc, KeyboardInterrupt) else f"failed: {type(exc).__name__}: {exc}"
        try:
            # keep what was integrated: the interval in the writer thread, then the rest, evaluated
            # here; an evaluation that fails stops it at the sample before
            try:
                settle()
            except Exception:
                pass
            t_last = written[1]
            done = []
            for r in pending:
                try:
                    done.append((r, values_of(r)))
                except Exception:
                    break
            after = []                                 # evaluated, after the last state to go on from
            while done and done[-1][0][2] is None:     # up to a state the integrator can go on from
                after.insert(0, done.pop())
            for r, values in done:
                writer.add_sample(r[0], values)
            if done:
                written = state_of(done[-1][0])
                t_last = written[1]
            y_w, t_w, h_w, ns_w, nr_w, dydt_w = written
            writer.checkpoint(y_w, t_w, h_w, ns_w, nr_w, wall_time=wall_before + time.perf_counter() - loop_start,
                              dydt=dydt_w)
            # what a failed call integrated up to the failure goes after the checkpoint (a resume
            # truncates it and integrates it again), with every sample since it
            if failed_tail and len(done) + len(after) == len(pending):
                for r, values in after:
                    writer.add_sample(r[0], values)
                    t_last = r[0]
                for r in failed_tail:
                    try:
                        writer.add_sample(r[0], values_of(r))
                    except Exception:
                        break
                    t_last = r[0]
                writer.write_block()
            writer.set_status(status)
        finally:
            writer.close()
        what = "interrupted" if isinstance(exc, KeyboardInterrupt) else f"stopped by {type(exc).__name__}: {exc}"
        # a failure of the physics (flexbearing.multibody.integrator.SimulationUnstable) comes back from the same
        # checkpoint the same way: the integrator is deterministic
        resumable = not getattr(exc, "repeats_on_resume", False)
        then = ("continue with --resume" if resumable else
                "resuming would repeat it from the same state: change the scene and start a new run")
        at = f"t = {t_last:.6g} s" + (f" (checkpoint at {written[1]:.6g} s)" if t_last != written[1] else "")
        raise RunInterrupted(f"run {what} at {at}; {out_path} holds {writer.n_written} "
                             f"samples and a checkpoint ({then})", t_last, str(out_path),
                             exc, resumable) from exc
    finally:
        sys.setswitchinterval(switch_interval)
    progress.close()
    wall = wall_before + time.perf_counter() - loop_start
    writer.set_status("complete")
    writer.close()
    return _finish(scene, out_path, n_steps, n_rejected, wall, setup_time)


def _finish(scene, out_path, n_steps, n_rejected, wall, setup_time) -> dict:
    import h5py
    with h5py.File(out_path, "r") as f:
        n_resumes = int(f.attrs.get("n_resumes", 0))
    extra = {"scene": scene.name, "scene_file": scene.path, "scene_hash": scene.content_hash(),
             "cage_model": scene.cage_model, "duration_s": scene.duration,
             "sample_interval_s": scene.sample_interval, "tolerance": scene.tolerance,
             "integrator_method": scene.method,
             "outputs_requested": list(scene.outputs),
             "wall_time_s": wall, "setup_time_s": setup_time, "n_steps": n_steps,
             "n_rejected": n_rejected, "steps_per_s": n_steps / wall if wall > 0 else None,
             "n_resumes": n_resumes}
    return write_summary(out_path, extra)


# ---------------------------------------------------------------- case sets (validate slip-rate)

def slip_rate_from_results(path, average_from: float) -> dict:
    """Cage slip rate of a steady run (paper §3.2): S = (nm − nc)/nm = 1 − <nc>/<nm>, with the cage
    speed nc and the nominal cage speed nm = 0.5·ni·(1 − Dw·cos(alpha)/dm) averaged over
    t >= average_from (the test measures a time-averaged cage speed). Falls back to the mean of the
    recorded slip_rate if the speeds were not recorded.

    Returns {"slip": S, "drift": S(second half of the window) − S(first half)}: a drift that is
    not small against S means the cage speed had not settled (run longer)."""
    import h5py
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


class CasesIncomplete(RuntimeError):
    """Some cases of a case set failed (flexbearing.simulation.jobs.JobFailure each, in `failures`); `rows` holds
    the finished ones (case order). Their results files stay: --resume reads them back."""

    def __init__(self, message: str, rows: list[dict], failures: list):
        super().__init__(message)
        self.rows, self.failures = rows, failures


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
    from flexbearing.simulation.jobs import require_scheduler, require_workers, run_jobs, runs_in_this_process
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
