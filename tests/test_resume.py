"""Kill a run halfway and resume it: the final results equal an uninterrupted run's, bit for bit.

The fake backend of tests/test_run.py (deterministic adaptive RK4) stands in for the physics, so
what is tested here is the streaming, the checkpoints, the truncation and the restart logic.
"""
import os
import signal
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from flexbearing.simulation.results import output_items, read_checkpoint, read_outputs
from flexbearing.simulation.run import RunInterrupted, run_scene
from flexbearing.common.validation import InputError
from test_run import SCENE, fake_advance, fake_advance_sampled, fake_backend, fake_scene

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "ref.h5"
    summary = run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    return out, summary


def assert_same_results(a, b):
    ra, rb = read_outputs(a), read_outputs(b)
    assert sorted(ra) == sorted(rb)
    for k in ra:
        assert ra[k].dtype == rb[k].dtype and ra[k].shape == rb[k].shape, k
        assert ra[k].tobytes() == rb[k].tobytes(), f"{k} differs"   # bitwise
    with h5py.File(a) as fa, h5py.File(b) as fb:
        ca, cb = read_checkpoint(fa), read_checkpoint(fb)
        assert ca["y"].tobytes() == cb["y"].tobytes()
        assert (ca["t"], ca["h"], ca["n_samples"], ca["n_steps"], ca["n_rejected"]) == \
               (cb["t"], cb["h"], cb["n_samples"], cb["n_steps"], cb["n_rejected"])
        assert fb.attrs["status"] == "complete"


def stopping_after(n_calls, exc, inner=fake_advance):
    calls = {"n": 0}

    def advance(*a, **k):
        calls["n"] += 1
        if calls["n"] == n_calls:
            raise exc
        return inner(*a, **k)
    return advance


@pytest.mark.parametrize("n_calls", [3, 25, 41, 63])     # before the first checkpoint, and later
def test_ctrl_c_then_resume_equals_uninterrupted(tmp_path, reference, n_calls):
    ref, ref_summary = reference
    out = tmp_path / "run.h5"
    with pytest.raises(RunInterrupted) as exc:
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance=stopping_after(n_calls, KeyboardInterrupt())))
    assert isinstance(exc.value.cause, KeyboardInterrupt)
    with h5py.File(out, "r") as f:                       # a valid, readable file
        assert f.attrs["status"] == "interrupted"
        n = f["outputs/time"].shape[0]
        assert all(ds.shape[0] == n for _, ds in output_items(f["outputs"]))
        assert read_checkpoint(f)["n_samples"] == n      # Ctrl-C checkpoints the last sample
    summary = run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert_same_results(ref, out)
    assert summary["n_steps"] == ref_summary["n_steps"] and summary["n_resumes"] == 1
    for name, st in ref_summary["outputs"].items():
        assert summary["outputs"][name] == st


def test_crash_with_samples_after_the_checkpoint_is_truncated(tmp_path, reference):
    """A hard crash can leave rows written after the last checkpoint (or a half block): resume
    drops them and recomputes from the checkpoint."""
    ref, _ = reference
    out = tmp_path / "run.h5"
    with pytest.raises(RunInterrupted):
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance=stopping_after(50, RuntimeError("boom"))))
    with h5py.File(out, "r+") as f:
        assert f.attrs["status"].startswith("failed: RuntimeError: boom")
        n = f["outputs/time"].shape[0]
        for _, ds in output_items(f["outputs"]):        # simulate rows beyond the checkpoint
            ds.resize(n + 5, axis=0)
            ds[n:] = 1e300
        slot = f["checkpoint/slot0"] if f["checkpoint/slot0"].attrs["seq"] < f["checkpoint/slot1"].attrs["seq"] \
            else f["checkpoint/slot1"]
        slot.attrs["seq"] = -1                           # the newest slot was being rewritten
    run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert_same_results(ref, out)


def test_interrupted_twice(tmp_path, reference):
    ref, _ = reference
    out = tmp_path / "run.h5"
    for n in (30, 20):
        with pytest.raises(RunInterrupted):
            run_scene(fake_scene(), out, resume=True, quiet=True,
                      backend=fake_backend(advance=stopping_after(n, KeyboardInterrupt())))
    s = run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert s["n_resumes"] == 2
    assert_same_results(ref, out)
    # resuming a complete run recomputes nothing
    s2 = run_scene(fake_scene(), out, resume=True, quiet=True,
                   backend=fake_backend(advance=stopping_after(1, AssertionError("must not integrate"))))
    assert s2["n_steps"] == s["n_steps"]
    assert_same_results(ref, out)


def test_resume_refuses_another_scene(tmp_path):
    out = tmp_path / "run.h5"
    with pytest.raises(RunInterrupted):
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance=stopping_after(30, KeyboardInterrupt())))
    other = fake_scene(SCENE.replace("magnitude = 1000.0", "magnitude = 1200.0"))
    with pytest.raises(InputError, match="written by a different scene"):
        run_scene(other, out, resume=True, quiet=True, backend=fake_backend())


def test_sigkill_then_resume_equals_uninterrupted(tmp_path, reference):
    """A real kill -9 of a running process (no cleanup at all), then resume."""
    ref, _ = reference
    out = tmp_path / "run.h5"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE), str(HERE.parent)]))
    proc = subprocess.Popen([sys.executable, str(HERE / "test_run.py"), str(out)], stdout=subprocess.PIPE,
                            text=True, env=env)
    try:
        for line in proc.stdout:                         # wait for the third checkpoint
            if line.startswith("CHECKPOINT") and int(line.split()[1]) >= 21:
                break
        else:
            pytest.fail(f"the subprocess ended early (rc {proc.wait()})")
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "running"            # killed: nobody wrote a final status
        assert read_checkpoint(f)["n_samples"] >= 21
    run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert_same_results(ref, out)


@pytest.mark.slow
def test_real_model_interrupt_and_resume_bitwise(tmp_path):
    """The same with the real rigid-cage dynamics (multibody): paper steady loads, 2 ms."""
    from flexbearing.simulation.run import default_backend
    from flexbearing.simulation.scene import loads_scene
    text = """
name = "short_steady_rigid"
[operation]
duration = 0.002
[operation.speed]
phases = [{ kind = "uniform", duration = 0.002, rpm = 14000 }]
[operation.load]
axial_load = 55e3
radial_load = 4e3
[[operation.load.impacts]]
t_center = 0.001
duration = 0.0004
magnitude = 20e3
[output]
sample_interval = 1e-4
record = ["contact_stress", "ball_loads", "pocket_force", "guiding_force", "cage_speed", "slip",
          "film_thickness", "cage_orbit", "kinematics"]
checkpoint_every = 5
"""
    scene = loads_scene(text, "short.toml")
    run_scene(scene, tmp_path / "a.h5", quiet=True)
    backend = default_backend(scene)
    # the run calls advance_sampled once per 5 samples (checkpoints) and at the impact's ends
    backend.advance_sampled = stopping_after(4, KeyboardInterrupt(), inner=backend.advance_sampled)
    with pytest.raises(RunInterrupted):
        run_scene(scene, tmp_path / "b.h5", quiet=True, backend=backend)
    run_scene(scene, tmp_path / "b.h5", quiet=True, resume=True)
    assert_same_results(tmp_path / "a.h5", tmp_path / "b.h5")


def test_a_resumed_file_keeps_its_dimension_scales_and_compression(tmp_path, reference):
    """Resume truncates and extends compressed, dimension-scaled datasets (flexbearing.simulation.results format
    2): the resumed file still opens in xarray with its named dimensions, and holds the
    uninterrupted run's numbers."""
    xr = pytest.importorskip("xarray")
    ref, _ = reference
    out = tmp_path / "run.h5"
    with pytest.raises(RunInterrupted):
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance=stopping_after(41, KeyboardInterrupt())))
    run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert_same_results(ref, out)
    with h5py.File(out, "r") as f:
        load = f["outputs/external_load"]
        assert load.compression == "gzip" and load.dims[1][0].name == "/outputs/axis"
        n = f["outputs/time"].shape[0]
    with xr.open_dataset(out, group="outputs") as ds:
        assert ds["external_load"].dims == ("time", "axis") and ds.sizes["time"] == n
        assert list(ds["axis"].values) == ["x", "y", "z"]
        assert np.array_equal(ds["external_load"].values, read_outputs(ref)["external_load"])


def test_an_output_evaluation_that_fails_in_the_writer_thread_keeps_the_samples_before(tmp_path, reference):
    """The writer thread evaluates a checkpoint interval's outputs (flexbearing.simulation.run): if evaluating
    sample 17 raises, the file holds samples 0-16 and a checkpoint at sample 16, the error reaches
    the caller, and resuming (with a working backend) gives the uninterrupted run bit for bit."""
    from test_run import fake_outputs
    ref, _ = reference
    out = tmp_path / "run.h5"
    t17 = fake_scene().sample_time(17)

    def failing(model, t, y, outputs=(), speed_table=None):
        if t >= t17:                          # every time it is tried (the run retries it once)
            raise RuntimeError("output evaluation failed")
        return fake_outputs(model, t, y, outputs, speed_table)
    with pytest.raises(RunInterrupted) as exc:
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(evaluate_outputs=failing))
    assert isinstance(exc.value.cause, RuntimeError)
    with h5py.File(out, "r") as f:
        assert f.attrs["status"].startswith("failed: RuntimeError")
        n = f["outputs/time"].shape[0]
        assert n == 17
        assert all(ds.shape[0] == n for _, ds in output_items(f["outputs"]))
        cp = read_checkpoint(f)
        assert cp["n_samples"] == n and cp["t"] == f["outputs/time"][-1]
    run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert_same_results(ref, out)


def test_a_block_the_writer_thread_fails_to_write_is_written_once_after(tmp_path, reference):
    """A write of the writer thread fails once (a full disk that frees up): the interrupted run
    writes that interval's samples itself, once — the file's times strictly increase, its
    checkpoint is its last sample — and resuming gives the uninterrupted run bit for bit."""
    from flexbearing.simulation import results as RS
    ref, _ = reference
    out = tmp_path / "run.h5"
    real = RS.ResultsWriter.write_block
    calls = {"n": 0}

    def flaky(self, buffer=None):
        calls["n"] += 1
        if calls["n"] == 3:                   # the third block, in the writer thread
            raise OSError("No space left on device")
        return real(self, buffer)
    RS.ResultsWriter.write_block = flaky
    try:
        with pytest.raises(RunInterrupted) as exc:
            run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    finally:
        RS.ResultsWriter.write_block = real
    assert isinstance(exc.value.cause, OSError)
    with h5py.File(out, "r") as f:
        t = f["outputs/time"][...]
        assert np.all(np.diff(t) > 0)
        assert all(ds.shape[0] == t.size for _, ds in output_items(f["outputs"]))
        cp = read_checkpoint(f)
        assert cp["n_samples"] == t.size and cp["t"] == t[-1]
    run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend())
    assert_same_results(ref, out)


# ---- the same with a backend that integrates across samples (flexbearing.simulation.run's advance_sampled):
# a call ends at every SAMPLES_PER_CALL-th sample, checkpoint and breakpoint; samples inside it are
# not states the integrator can go on from, so no checkpoint may be written there

@pytest.fixture(scope="module")
def reference_sampled(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref_sampled") / "ref.h5"
    summary = run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance_sampled=fake_advance_sampled))
    return out, summary


def test_sampled_backend_takes_fewer_steps_for_the_same_series(reference, reference_sampled):
    """Not stopping at the 601 samples saves steps; the interpolated series agree with the
    stopping run's to the tolerance (the fake backend's scene: tol 1e-6 on states of scale 1 and
    1e-6 m, 1e-3 m/s): ring angle and impulse within 1e-6 relative, the oscillator within 1e-9 m."""
    (a, sa), (b, sb) = reference, reference_sampled
    assert sb["n_steps"] < sa["n_steps"]
    ra, rb = read_outputs(a), read_outputs(b)
    assert ra["time"].tobytes() == rb["time"].tobytes()
    for k in ("ring_angle", "impulse_z"):
        assert np.allclose(rb[k], ra[k], rtol=1e-6, atol=1e-9), k
    assert np.max(np.abs(rb["oscillator_displacement"][:, 0] - ra["oscillator_displacement"][:, 0])) < 1e-9


@pytest.mark.parametrize("n_calls", [2, 5, 9, 17])
def test_sampled_ctrl_c_then_resume_equals_uninterrupted(tmp_path, reference_sampled, n_calls):
    ref, ref_summary = reference_sampled
    out = tmp_path / "run.h5"
    stop = stopping_after(n_calls, KeyboardInterrupt(), inner=fake_advance_sampled)
    with pytest.raises(RunInterrupted):
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance_sampled=stop))
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "interrupted"
        n = f["outputs/time"].shape[0]
        cp = read_checkpoint(f)
        assert cp["n_samples"] == n and (n == 0 or cp["t"] == f["outputs/time"][-1])
    summary = run_scene(fake_scene(), out, resume=True, quiet=True,
                        backend=fake_backend(advance_sampled=fake_advance_sampled))
    assert_same_results(ref, out)
    assert summary["n_steps"] == ref_summary["n_steps"]


def test_sampled_evaluation_failure_keeps_samples_up_to_a_state_to_go_on_from(tmp_path, reference_sampled):
    """Evaluating sample 17 fails (in the writer thread, then again in the interrupted run): samples
    14-16 lie inside a call (the fake scene checkpoints every 7 samples: calls end at samples 6, 13,
    20), so the file ends at sample 13, the last state the integrator stopped at, with its
    checkpoint there, and resuming gives the uninterrupted run bit for bit."""
    from test_run import fake_outputs
    ref, _ = reference_sampled
    out = tmp_path / "run.h5"
    scene = fake_scene()
    t17 = scene.sample_time(17)

    def failing(model, t, y, outputs=(), speed_table=None):
        if t >= t17:
            raise RuntimeError("output evaluation failed")
        return fake_outputs(model, t, y, outputs, speed_table)
    with pytest.raises(RunInterrupted):
        run_scene(scene, out, quiet=True, backend=fake_backend(advance_sampled=fake_advance_sampled,
                                                               evaluate_outputs=failing))
    with h5py.File(out, "r") as f:
        n = f["outputs/time"].shape[0]
        cp = read_checkpoint(f)
        assert n == 14 and cp["n_samples"] == n and cp["t"] == f["outputs/time"][-1]
    run_scene(scene, out, resume=True, quiet=True, backend=fake_backend(advance_sampled=fake_advance_sampled))
    assert_same_results(ref, out)


def test_sampled_failure_keeps_the_samples_up_to_it_after_the_checkpoint(tmp_path, reference_sampled):
    """An integrator call that fails (as flexbearing.multibody.integrator.SimulationUnstable does) hands over the
    samples it passed before the failure (`exc.samples`): the failed run's file holds them after its
    checkpoint (the last state the integrator stopped at), RunInterrupted.t is the last sample's time,
    and a resume truncates them and gives the uninterrupted run bit for bit."""
    ref, _ = reference_sampled
    out = tmp_path / "run.h5"
    calls = {"n": 0}

    class Unstable(RuntimeError):
        repeats_on_resume = True

    def failing(model, y, t, t_next, sample_times, *a, **k):
        calls["n"] += 1
        res = fake_advance_sampled(model, y, t, t_next, sample_times, *a, **k)
        if calls["n"] == 4 and len(sample_times) > 3:      # fails after its third sample
            exc = Unstable("unstable")
            exc.samples = (sample_times[:3], res[5][:3], [None] * 3)
            raise exc
        return res
    with pytest.raises(RunInterrupted) as exc:
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance_sampled=failing))
    assert not exc.value.resumable
    ra = read_outputs(ref)
    with h5py.File(out, "r") as f:
        t = f["outputs/time"][...]
        cp = read_checkpoint(f)
        assert cp["n_samples"] == t.size - 3 and cp["t"] == t[-4]
        assert exc.value.t == t[-1]
        n = t.size
        for name, ds in output_items(f["outputs"]):
            assert ds[...].tobytes() == ra[name][:n].tobytes(), name     # the kept samples are the run's
    run_scene(fake_scene(), out, resume=True, quiet=True, backend=fake_backend(advance_sampled=fake_advance_sampled))
    assert_same_results(ref, out)
