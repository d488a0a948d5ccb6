"""Run a scene: scene → model → initial state → advance loop → sampled outputs → HDF5 → summary.json.

    t_k = k·dt (k = 0..N, the scene's sample interval; computed from k, never accumulated)
    the integrator is stopped at every kink or jump of the spectra (speed-table knots, load-table
    knots, impact start and end) so that no step straddles a discontinuity, and at every
    SAMPLES_PER_CALL-th sample and checkpoint; the samples between are the states its continuous
    extension gives at t_k inside a step (flexbearing.multibody.integrator, "Samples"); outputs are evaluated
    at t_k only, and only those the scene records.

The physics comes from a backend, a flexbearing.multibody.run_backend.RunBackend (its explicit
interface: build the model, the initial state, advance, evaluate the outputs, optionally advance
across samples, take a sample's snapshot, a workspace): `default_backend(scene)` is the rigid cage's
(flexbearing.multibody.run_backend.rigid_backend) or the flexible cage's
(flexbearing.coupling.flexible_cage.backend); tests pass a small stand-in physics, so that
streaming, checkpoints and resume are proven independently of the physics. Nothing here imports
the FE stack.

What each scene output records: flexbearing.multibody.output_registry (the backend selects the
evaluated keys). The inner-ring speed and the external load (the spectra at t_k) are always
recorded. Vectors of mixed units are split into SI datasets (the registry's `source`).
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import NamedTuple

import h5py
import numpy as np

from flexbearing.common.file_lock import exclusive_file
from flexbearing.common.validation import InputError
from flexbearing.multibody import output_registry as R
from flexbearing.multibody.profiles import load_at, speed_at
from flexbearing.multibody.run_backend import OutputRequest, RunBackend, rigid_backend
from flexbearing.simulation.progress import RunProgress
from flexbearing.simulation.results import FORMAT, DiskFull, OutputTooLarge, ResultsWriter, different_scene, write_summary
from flexbearing.simulation.stopped import Interrupted
from flexbearing.simulation.wall_budget import WallBudget
from flexbearing.common.safe_files import refuse_overwriting_inputs
from flexbearing.common.validation import require_range

GIL_SWITCH_INTERVAL = 1e-4     # s, during a run's loop (RunLoop._integrate says why)
SAMPLES_PER_CALL = 25          # samples per compiled call at most (progress and Ctrl-C respond
                               # after each; ~0.05 s of wall time on the paper's scenes)


class RunInterrupted(Interrupted):
    """A run stopped early (Ctrl-C, an error, the wall budget, a full disk); the results file `path`
    holds a checkpoint at `t` to resume from (the family: flexbearing.simulation.stopped)."""

    def __init__(self, message: str, t: float, path: str, cause: BaseException | None = None,
                 resumable: bool = True):
        super().__init__(message, cause=cause, resumable=resumable)
        self.t = t
        self.path = path


def _next_multiple(k: int, m: int) -> int:
    """The smallest multiple of m that is greater than k."""
    return (k // m + 1) * m


def default_backend(scene) -> RunBackend:
    """The physics for this scene's cage model: the flexible cage's backend loads the reduced cage
    file (and builds it with the FE stack only when it is not cached)."""
    if scene.cage_model == "flexible":
        from flexbearing.coupling.flexible_cage import backend     # the flexible cage only: its file
        return backend(scene)
    return rigid_backend()


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
    if max_output_bytes is not None:
        require_range("--max-output-size", max_output_bytes, 1.0, 1e15, unit="bytes")
    if max_wall_time is not None:              # nan or <= 0 would be ignored without a word
        require_range("--max-wall-time", max_wall_time, 0.0, None, lo_open=True, unit="s")
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




class Sample(NamedTuple):
    """A sample as the loop records it while it integrates; its outputs, a function of (t, y) and
    the snapshot, are evaluated later (RunLoop.outputs_at)."""
    t: float
    y: np.ndarray
    h: float | None            # the step to go on with; None: a sample the integrator passed inside
    n_steps: int | None        # a step (not a state it can go on from: no checkpoint is written there)
    n_rejected: int | None
    dydt: np.ndarray | None    # the integrator's FSAL derivative at (t, y), if it holds one
    snapshot: object           # what the backend took at the sample (RunBackend.sample_snapshot)


def _passed(t, y, snapshot) -> Sample:
    """A sample the integrator passed inside a step."""
    return Sample(t, y, None, None, None, None, snapshot)


def _run_claimed(scene, out_path: Path, mode: str, quiet: bool, backend, max_wall_time,
                 max_output_bytes=None) -> dict:
    """run_scene once the output file is claimed."""
    wall_start = time.perf_counter()
    loop = RunLoop(scene, out_path, backend if backend is not None else default_backend(scene),
                   quiet, max_wall_time, wall_start)
    loop.max_output_bytes = max_output_bytes
    return loop.run(mode)


class RunLoop:
    """One run of a scene into its claimed results file.

    The loop integrates with the backend and records each sample raw (`Sample`). The writer thread
    evaluates a checkpoint interval of them, then writes the block and the checkpoint
    (flexbearing.simulation.results), while the compiled integration (nogil) goes on. The evaluation
    uses its own model (its own scratch arrays; the integration's are in use). Evaluating after
    every interval in the integrating thread made the loop's steps ~30 % dearer (caches) and cost
    0.5 ms a sample (measured on the paper's scenes, benchmarks/results/speed.md).

    Records move pending (integrated, not handed over) → inflight (in the writer thread, not known
    written) → written (the last sample in the file: what an interruption's checkpoint records).
    The integrator's workspace carries its FSAL derivative from one call to the next; each
    checkpoint stores it beside the state, so that a resumed run's first step uses the same
    derivative as the uninterrupted run's (bit-identical files).
    """

    max_output_bytes = None          # the file-size limit run_scene was given (None: the default)

    def __init__(self, scene, out_path: Path, backend: RunBackend, quiet: bool, max_wall_time,
                 wall_start: float):
        self.scene, self.out_path, self.backend = scene, out_path, backend
        self.quiet, self.max_wall_time, self.wall_start = quiet, max_wall_time, wall_start
        self.units = {**R.units(), **backend.output_units}
        self.model = backend.build_model(scene.bearing, scene.oil, dict(scene.model_options))
        self.request = OutputRequest(tuple(scene.outputs), scene.speed_table, scene.load_table,
                                     scene.impacts, "film_thickness" in scene.outputs,
                                     "power_loss" in scene.outputs)
        if backend.new_workspace is not None:
            # the workspace carries the method's tableau (flexbearing.multibody.integrator.Workspace)
            self.ws = backend.new_workspace(self.model, scene.method)
        elif scene.method != "dopri5":
            raise InputError(f"integrator.method = {scene.method!r}: this backend integrates with its own "
                             f"method only (allowed: 'dopri5')")
        else:
            self.ws = None
        self.breakpoints = scene.breakpoints()   # the kinks and jumps of the spectra
        # integrator.max_step reaches the integrator only when the scene sets it (a backend without
        # the keyword keeps working on every other scene)
        self.step_limit = {"max_step": scene.max_step} if scene.max_step else {}
        self.keys = None                      # the evaluated keys, in the first sample's order
        self.load3 = np.zeros(3)
        self.pending: list[Sample] = []
        self.inflight: list[Sample] = []
        self.failed_tail: list[Sample] = []   # samples a failed integrator call passed

    # ---------------------------------------------------------------- samples
    def outputs_at(self, s: Sample) -> dict:
        """The recorded values of a sample (on the evaluation's own model)."""
        values = dict(self.backend.evaluate_outputs(self.eval_model, s.t, s.y, self.request, s.snapshot))
        if self.keys is None:
            self.keys = list(values)
        values = R.split_mixed_units({k: values[k] for k in self.keys})
        if "inner_ring_speed" not in values:
            values["inner_ring_speed"] = speed_at(s.t, self.scene.speed_table)
        if "external_load" not in values:
            load_at(s.t, self.scene.load_table, self.scene.impacts, self.load3)
            values["external_load"] = self.load3.copy()
        return values

    def _fsal(self, t):
        """The derivative the integrator continues with at (t, y), if it holds one (a copy)."""
        return self.ws.K[0].copy() if self.ws is not None and self.ws.fsal_t == t else None

    def _stopped_at(self) -> Sample:
        """The state the integrator stopped at (a state to go on from)."""
        snap = self.backend.sample_snapshot
        return Sample(self.t, np.array(self.y, dtype=np.float64), self.h, self.n_steps, self.n_rejected,
                      self._fsal(self.t), snap(self.model) if snap is not None else None)

    # ---------------------------------------------------------------- the writer thread
    def _settle(self) -> None:
        """Wait for the interval in the writer thread: written, or (it failed: re-raised) back in
        front of `pending`, for the interrupted run to write itself."""
        try:
            self.writer.wait()
        except BaseException:
            self.pending, self.inflight = self.inflight + self.pending, []
            raise
        if self.inflight:
            self.written = self.inflight[-1]
        self.inflight = []

    def _hand_over(self, wall_time: float) -> None:
        self._settle()
        self.inflight, self.pending = self.pending, []
        w = self.inflight[-1]
        self.writer.checkpoint_in_background(
            w.y, w.t, w.h, w.n_steps, w.n_rejected, wall_time=wall_time, dydt=w.dydt,
            samples=lambda b=self.inflight: [(r.t, self.outputs_at(r)) for r in b])

    # ---------------------------------------------------------------- the run
    def run(self, mode: str) -> dict:
        scene, backend = self.scene, self.backend
        cp = None
        if mode == "resume" and self.out_path.stat().st_size == 0:
            # an empty file under our claim: a run killed (SIGKILL, power loss) after claiming the
            # file and before HDF5 wrote its first byte; nothing was computed, so it starts over
            mode = "new"
        if mode == "resume":
            writer, cp = ResultsWriter.open_for_resume(self.out_path, scene, self.units)
            if cp is None:               # killed before its first checkpoint: start over in a new file
                writer.close()
                mode = "new"
            elif writer.previous_status == "complete" or cp["n_samples"] >= scene.n_samples:
                writer.set_status("complete")
                writer.close()
                return _finish(scene, self.out_path, cp["n_steps"], cp["n_rejected"], cp["wall_time"],
                               time.perf_counter() - self.wall_start)
        if mode == "new":
            writer = ResultsWriter.create(self.out_path, scene, self.units)
        writer.n_samples_expected = scene.n_samples
        if self.max_output_bytes is not None:
            writer.max_output_bytes = float(self.max_output_bytes)
        self.writer = writer
        for key, value in backend.file_attrs.items():   # e.g. the reduced cage file and its hash
            writer.f.attrs[key] = value
        try:
            self._start(cp)
        except BaseException:
            writer.close()
            if cp is None:                     # nothing computed yet: leave no file that blocks a rerun
                self.out_path.unlink(missing_ok=True)
            raise
        setup_time = time.perf_counter() - self.wall_start
        self.eval_model = backend.build_model(scene.bearing, scene.oil, dict(scene.model_options))
        self.written = Sample(self.t, self.y.copy(), self.h, self.n_steps, self.n_rejected,
                              self._fsal(self.t) if cp is not None else None, None)
        wall = self._integrate()
        writer.set_status("complete")
        writer.close()
        return _finish(scene, self.out_path, self.n_steps, self.n_rejected, wall, setup_time)

    def _start(self, cp) -> None:
        """The state to start from: the backend's initial state, or the checkpoint `cp`."""
        scene = self.scene
        if cp is None:
            Fa, Fr = scene.initial_loads()
            f0 = np.zeros(3)
            load_at(0.0, scene.load_table, scene.impacts, f0)      # the full load vector
            self.y = np.array(self.backend.initial_state(self.model, speed_at(0.0, scene.speed_table),
                                                         Fa, Fr, f0), dtype=np.float64)
            if scene.start == "steady":
                self._steady_start(f0)
            self.t, self.h, self.n_steps, self.n_rejected, self.wall_before, self.k = (
                0.0, scene.initial_step, 0, 0, 0.0, 0)
            return
        self.y, self.t, self.h = cp["y"], cp["t"], cp["h"]
        ws = self.ws
        if ws is not None and cp.get("dydt") is not None and cp["dydt"].shape == ws.K[0].shape:
            ws.K[0][:] = cp["dydt"]
            ws.fsal_t, ws.fsal_y = self.t, self.y.copy()
        self.n_steps, self.n_rejected = cp["n_steps"], cp["n_rejected"]
        self.wall_before, self.k = cp["wall_time"], cp["n_samples"]

    def _steady_start(self, load0) -> None:
        """[integrator] start = "steady": the steady running state at the speed and load of t = 0
        replaces the quasi-static start, solved on the rigid cage of the same bearing; where it is
        not found, the quasi-static start stays and the run says why
        (flexbearing.multibody.steady_start.steady_start). The choice is printed and kept in the
        results file (attribute initial_state)."""
        from flexbearing.multibody.steady_start import start_line, steady_start
        scene = self.scene
        rigid = rigid_backend().build_model(scene.bearing, scene.oil, dict(scene.model_options))
        self.y, info = steady_start(rigid, speed_at(0.0, scene.speed_table), load0, self.y)
        line = start_line(info)
        print(line, file=sys.stderr)           # the fallback is said even with --quiet
        self.writer.f.attrs["initial_state"] = line[len("start: "):]

    def _integrate(self) -> float:
        """The loop from the start state to the end; returns the run's wall time. A call ends at the
        next multiple of SAMPLES_PER_CALL or of the checkpoint interval (fixed sample indices: a
        resume stops where the uninterrupted run stopped, so the files agree bit for bit), and at
        the breakpoints of the spectra."""
        scene = self.scene
        n_total, every = scene.n_samples, scene.checkpoint_every
        per_call = SAMPLES_PER_CALL if self.backend.advance_sampled is not None else 1
        progress = RunProgress(scene.duration, t0=self.t, quiet=self.quiet, desc=scene.name,
                               n_steps0=self.n_steps)
        budget = WallBudget(scene.duration, t0=self.t, n_steps0=self.n_steps, name=scene.name,
                            max_wall_time=self.max_wall_time)
        loop_start = time.perf_counter()
        # The integrating thread takes the GIL back after every compiled call (up to SAMPLES_PER_CALL
        # samples, ~30 ms; one sample without advance_sampled); with Python's default switch interval it
        # waits up to 5 ms whenever the writer thread holds it.
        switch_interval = sys.getswitchinterval()
        sys.setswitchinterval(GIL_SWITCH_INTERVAL)
        try:
            while self.k < n_total:
                # the call's last sample: the next multiple of per_call or of every (in samples), or the end
                k_end = min(n_total - 1, _next_multiple(self.k, per_call) - 1, _next_multiple(self.k, every) - 1)
                t_target = scene.sample_time(k_end)
                if self.k == 0:                                 # the initial state (t = 0)
                    self.pending.append(self._stopped_at())
                    self.k = 1
                while self.t < t_target:
                    self._advance(t_target, k_end)
                if self.k % every == 0 or self.k == n_total:
                    self._hand_over(self.wall_before + time.perf_counter() - loop_start)
                progress.update(self.t, self.n_steps)
                budget.update(self.t, self.n_steps)
            self._settle()
        except BaseException as exc:
            progress.close()
            if isinstance(exc, OutputTooLarge):
                self.writer.close()      # nothing was written: leave no file that needs --force
                self.out_path.unlink(missing_ok=True)
                raise exc
            if isinstance(exc, DiskFull):
                # nothing more is written (it would not fit): the file holds its last checkpoint
                self.writer.close()
                raise RunInterrupted(f"run stopped at t = {self.written.t:.6g} s: {self.out_path}: {exc.strerror}",
                                     self.written.t, str(self.out_path), exc) from exc
            self._stop(exc, loop_start)
        finally:
            sys.setswitchinterval(switch_interval)
        progress.close()
        return self.wall_before + time.perf_counter() - loop_start

    def _advance(self, t_target: float, k_end: int) -> None:
        """One integrator call: to the next breakpoint of the spectra or to t_target, recording the
        samples it passes (advance_sampled) and the one it stops at."""
        scene, backend = self.scene, self.backend
        bps = self.breakpoints
        i = int(np.searchsorted(bps, self.t, side="right"))
        t_stop = bps[i] if i < len(bps) and bps[i] < t_target else t_target
        tables = (scene.speed_table, scene.load_table, scene.impacts)
        if backend.advance_sampled is not None:
            k_in = self.k
            while k_in < k_end and scene.sample_time(k_in) < t_stop:
                k_in += 1
            times = np.array([scene.sample_time(j) for j in range(self.k, k_in)])
            try:
                y, _t, h, ns, nr, states, snaps = backend.advance_sampled(
                    self.model, self.y, self.t, t_stop, times, *tables, scene.tolerance, self.h, self.ws,
                    **self.step_limit)
            except Exception as exc:
                # an integration that fails (flexbearing.multibody.integrator.SimulationUnstable) hands
                # over the samples it passed before: kept after the checkpoint (_stop)
                part = getattr(exc, "samples", None)
                if part is not None:
                    self.failed_tail = [_passed(*r) for r in zip(*part)]
                raise
            for j in range(self.k, k_in):
                self.pending.append(_passed(times[j - self.k], states[j - self.k].copy(), snaps[j - self.k]))
            self.k = k_in
        else:
            y, _t, h, ns, nr = backend.advance(self.model, self.y, self.t, t_stop, *tables,
                                               scene.tolerance, self.h, self.ws, **self.step_limit)
        self.y, self.h = y, h
        self.t = t_stop          # the integrator lands on t_next; keep the exact stop time
        self.n_steps += int(ns)
        self.n_rejected += int(nr)
        if self.k < scene.n_samples and scene.sample_time(self.k) == self.t:   # at a breakpoint, or the call's last
            self.pending.append(self._stopped_at())
            self.k += 1

    def _stop(self, exc: BaseException, loop_start: float) -> None:
        """Keep what was integrated, then raise RunInterrupted: the interval in the writer thread,
        then the rest, evaluated here (an evaluation that fails stops it at the sample before), a
        checkpoint at the last state to go on from, and what a failed call passed after it."""
        writer = self.writer
        status = "interrupted" if isinstance(exc, KeyboardInterrupt) else f"failed: {type(exc).__name__}: {exc}"
        try:
            try:
                self._settle()
            except Exception:
                pass
            t_last = self.written.t
            done = []
            for r in self.pending:
                try:
                    done.append((r, self.outputs_at(r)))
                except Exception:
                    break
            after = []                                 # evaluated, after the last state to go on from
            while done and done[-1][0].h is None:      # up to a state the integrator can go on from
                after.insert(0, done.pop())
            for r, values in done:
                writer.add_sample(r.t, values)
            if done:
                self.written = done[-1][0]
                t_last = self.written.t
            w = self.written
            writer.checkpoint(w.y, w.t, w.h, w.n_steps, w.n_rejected,
                              wall_time=self.wall_before + time.perf_counter() - loop_start, dydt=w.dydt)
            # what a failed call integrated up to the failure goes after the checkpoint (a resume
            # truncates it and integrates it again), with every sample since it
            if self.failed_tail and len(done) + len(after) == len(self.pending):
                for r, values in after:
                    writer.add_sample(r.t, values)
                    t_last = r.t
                for r in self.failed_tail:
                    try:
                        writer.add_sample(r.t, self.outputs_at(r))
                    except Exception:
                        break
                    t_last = r.t
                writer.write_block()
            writer.set_status(status)
        finally:
            writer.close()
        what = "interrupted" if isinstance(exc, KeyboardInterrupt) else f"stopped by {type(exc).__name__}: {exc}"
        # a failure of the physics (flexbearing.multibody.integrator.SimulationUnstable) comes back
        # from the same checkpoint the same way: the integrator is deterministic
        resumable = not getattr(exc, "repeats_on_resume", False)
        then = ("continue with --resume" if resumable else
                "resuming would repeat it from the same state: change the scene and start a new run")
        at = f"t = {t_last:.6g} s" + (f" (checkpoint at {self.written.t:.6g} s)" if t_last != self.written.t else "")
        raise RunInterrupted(f"run {what} at {at}; {self.out_path} holds {writer.n_written} "
                             f"samples and a checkpoint ({then})", t_last, str(self.out_path),
                             exc, resumable) from exc


def _finish(scene, out_path, n_steps, n_rejected, wall, setup_time) -> dict:
    """The run summary (flexbearing.simulation.results.write_summary) of a finished run."""
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


