"""The run orchestrator (flexbearing.simulation.run) with a small fake physics backend whose answers are known.

Fake model (same signatures as multibody.{model, initial, integrator, dynamics}):
    phi' = omega(t)                      inner-ring angle: phi(t) = integral of the speed spectrum
    J'   = Fz(t)                         impulse of the vertical load (table + impacts)
    x'' + 2·zeta·w0·x' + w0²·x = Fx(t)/m a damped oscillator driven by the axial load
integrated by an adaptive step-doubling RK4 (deterministic). The run loop stops the integrator at
the spectra's kinks, so on piecewise-linear spectra the RK4 (Simpson) quadrature of phi and J is
exact to rounding: the recorded series are checked against the closed forms.
"""
import json
import math
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from tolerances import U, assert_within, sum_roundoff
from scipy.integrate import trapezoid

from flexbearing.multibody.run_backend import RunBackend
from flexbearing.simulation.results import output_items, read_outputs, summary_path
from flexbearing.simulation.run import RunInterrupted, run_scene
from flexbearing.simulation.scene import RPM, loads_scene
from flexbearing.common.validation import InputError
from flexbearing.multibody.profiles import load_at, speed_angle_at, speed_at

W0, ZETA, MASS = 2 * math.pi * 200.0, 0.05, 10.0


def _rhs(t, y, speed_table, load_table, impacts, f3):
    load_at(t, load_table, impacts, f3)
    return np.array([speed_at(t, speed_table), f3[2], y[3],
                     f3[0] / MASS - 2 * ZETA * W0 * y[3] - W0 * W0 * y[2]])


def _rk4(t, y, h, args):
    k1 = _rhs(t, y, *args)
    k2 = _rhs(t + h / 2, y + h / 2 * k1, *args)
    k3 = _rhs(t + h / 2, y + h / 2 * k2, *args)
    k4 = _rhs(t + h, y + h * k3, *args)
    return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


_SCALE = np.array([1.0, 1.0, 1e-6, 1e-3])


def _doubled_step(t, y, step, args, tol):
    """One RK4 step against two half steps: (Richardson-extrapolated state, error / tol)."""
    y1 = _rk4(t, y, step, args)
    y2 = _rk4(t + step / 2, _rk4(t, y, step / 2, args), step / 2, args)
    return y2 + (y2 - y1) / 15.0, float(np.max(np.abs(y2 - y1) / (_SCALE + np.abs(y2)))) / 15.0 / tol


def fake_advance(model, y, t, t_next, speed_table, load_table, impacts, tol, h, ws=None):
    args = (speed_table, load_table, impacts, np.zeros(3))
    y = np.array(y, dtype=np.float64)
    n = nr = 0
    while t < t_next:
        last = t_next - t <= h
        step = t_next - t if last else h
        y_new, err = _doubled_step(t, y, step, args, tol)
        if err <= 1.0:
            y = y_new
            t = t_next if last else t + step
            n += 1
            if not last:
                h = step * min(2.0, 0.9 * max(err, 1e-10) ** -0.2)
        else:
            nr += 1
            h = step * max(0.2, 0.9 * err ** -0.2)
    return y, t, h, n, nr


def fake_advance_sampled(model, y, t, t_next, sample_times, speed_table, load_table, impacts, tol, h, ws=None):
    """fake_advance that does not stop at sample_times (flexbearing.simulation.run's `advance_sampled`): the
    state at a sample inside a step is the cubic Hermite interpolant of the step's ends and
    derivatives (as flexbearing.multibody.integrator does for BS32)."""
    args = (speed_table, load_table, impacts, np.zeros(3))
    y = np.array(y, dtype=np.float64)
    n = nr = i = 0
    states = np.zeros((len(sample_times), y.size))
    while t < t_next:
        last = t_next - t <= h
        step = t_next - t if last else h
        y_new, err = _doubled_step(t, y, step, args, tol)
        if err <= 1.0:
            t_new = t_next if last else t + step
            f0, f1 = _rhs(t, y, *args), _rhs(t_new, y_new, *args)
            while i < len(sample_times) and sample_times[i] <= t_new:
                th = (sample_times[i] - t) / step
                d = y_new - y
                states[i] = y + th * d + th * (th - 1) * ((1 - 2 * th) * d + (th - 1) * step * f0 + th * step * f1)
                i += 1
            y, t = y_new, t_new
            n += 1
            if not last:
                h = step * min(2.0, 0.9 * max(err, 1e-10) ** -0.2)
        else:
            nr += 1
            h = step * max(0.2, 0.9 * err ** -0.2)
    return y, t, h, n, nr, states, [None] * len(sample_times)


def fake_outputs(model, t, y, outputs=(), speed_table=None):
    """cage speed = 0.4 × the mean inner-ring speed since t = 0; nominal cage speed with alpha = 0:
    nm = 0.5·omega·(1 − Dw/dm), Dw = 22 mm, dm = 167 mm (paper bearing)."""
    out = {}
    if "cage_speed" in outputs:
        out["cage_speed"] = np.float64(0.4 * y[0] / t) if t > 0 else np.float64(0.0)
        out["nominal_cage_speed"] = np.float64(0.5 * speed_at(t, speed_table) * (1 - 22.0 / 167.0))
    if "kinematics" in outputs:
        out["ring_angle"] = np.float64(y[0])
        out["impulse_z"] = np.float64(y[1])
        out["oscillator_displacement"] = np.array([y[2], y[3]])
    return out


def fake_backend(**overrides):
    """The fake physics as a RunBackend (flexbearing.multibody.run_backend); `evaluate_outputs` may be
    given in fake_outputs' form (model, t, y, outputs, speed_table)."""
    parts = dict(
        build_model=lambda bearing, oil, options: {"n_balls": bearing.n_balls},
        initial_state=lambda model, speed, Fa, Fr, load: np.array([0.0, 0.0, Fa / (MASS * W0 * W0), 0.0]),
        advance=fake_advance, evaluate_outputs=fake_outputs,
        output_units={"ring_angle": "rad", "impulse_z": "N·s", "oscillator_displacement": "m",
                      "cage_speed": "rad/s"})
    parts.update(overrides)
    evaluate = parts["evaluate_outputs"]
    parts["evaluate_outputs"] = lambda model, t, y, request, snapshot: evaluate(
        model, t, y, request.outputs, request.speed_table)
    return RunBackend(**parts)


SCENE = """
name = "fake"
[operation]
duration = 0.06
[operation.speed]
phases = [{kind = "ramp", duration = 0.02, start_rpm = 1000, end_rpm = 4000},
          {kind = "uniform", duration = 0.02, rpm = 4000},
          {kind = "ramp", duration = 0.02, start_rpm = 4000, end_rpm = 2000}]
[operation.load]
points = [{t = 0.0, axial_load = 100.0, radial_load = 50.0}, {t = 0.013, axial_load = 300.0, radial_load = 80.0}]
[[operation.load.impacts]]
t_center = 0.03
duration = 0.004
magnitude = 1000.0
shape = "half-sine"
[[operation.load.impacts]]
t_start = 0.0453
duration = 0.002
magnitude = 500.0
shape = "rectangular"
[integrator]
tolerance = 1e-9
initial_step = 1e-5
[output]
sample_interval = 1e-3
record = ["cage_speed", "kinematics"]
checkpoint_every = 7
"""


def fake_scene(text=SCENE):
    return loads_scene(text, "fake.toml")


def impulse_z_exact(t, scene):
    """J(t) = integral of Fz: trapezoids of the piecewise-linear table + 2FT/pi per whole half-sine
    (the part of a half-sine up to t: F·T/pi·(1 − cos(pi·(t − t0)/T))) + F·(overlap) for rectangles."""
    tab = scene.load_table
    grid = np.union1d(tab[:, 0][tab[:, 0] < t], [0.0, t])
    fz = np.array([np.interp(g, tab[:, 0], tab[:, 3]) for g in grid])
    j = float(trapezoid(fz, grid))          # scipy's: numpy 2 has no np.trapz, numpy 1.24 no np.trapezoid
    for t0, T, _, _, fz_amp, shape in scene.impacts:
        s = min(max(t - t0, 0.0), T)
        j += fz_amp * (T / math.pi * (1 - math.cos(math.pi * s / T)) if shape == 0 else s)
    return j


def test_fake_run_records_exact_spectra(tmp_path):
    scene = fake_scene()
    out = tmp_path / "run.h5"
    summary = run_scene(scene, out, quiet=True, backend=fake_backend())
    res = read_outputs(out)
    n = scene.n_samples
    assert n == 61
    # sample times are k·dt exactly (computed from k, not accumulated)
    np.testing.assert_array_equal(res["time"], [min(k * 1e-3, 0.06) for k in range(n)])
    # phi(t) = integral of the speed spectrum: piecewise quadratic, exact under RK4 with the kinks
    # honoured -> rounding only (1e-12 relative)
    phi = np.array([speed_angle_at(t, scene.speed_table) for t in res["time"]])
    np.testing.assert_allclose(res["ring_angle"], phi, rtol=1e-12, atol=1e-15)
    # impulse of Fz including a half-sine (not polynomial: integration error, tol 1e-9) and a
    # rectangular impact (jumps at 0.0453 and 0.0473 are breakpoints -> exact)
    jz = np.array([impulse_z_exact(t, scene) for t in res["time"]])
    np.testing.assert_allclose(res["impulse_z"], jz, rtol=1e-7, atol=1e-9)
    # the applied load and speed are recorded as the spectra say
    f = np.zeros(3)
    for k in (0, 13, 29, 30, 46, 60):
        load_at(res["time"][k], scene.load_table, scene.impacts, f)
        np.testing.assert_array_equal(res["external_load"][k], f)
        assert res["inner_ring_speed"][k] == speed_at(res["time"][k], scene.speed_table)
    assert res["inner_ring_speed"][20] == pytest.approx(4000 * RPM, rel=1e-14)
    # summary: statistics equal numpy's over the file, counters consistent
    s = json.loads(summary_path(out).read_text())
    assert s == json.loads(json.dumps(summary))
    assert s["status"] == "complete" and s["n_samples"] == n and s["scene"] == "fake"
    for name in ("ring_angle", "impulse_z", "oscillator_displacement", "external_load", "cage_speed"):
        a = res[name]
        assert s["outputs"][name]["max"] == pytest.approx(a.max(), rel=1e-15)
        assert s["outputs"][name]["min"] == pytest.approx(a.min(), rel=1e-15)
        # the same n-term sum in another order (and one division each): sum_roundoff / n
        assert_within(abs(s["outputs"][name]["mean"] - a.mean()),
                      sum_roundoff(a.ravel()) / a.size + 2 * U * abs(a.mean()), f"mean of {name}",
                      effect=np.abs(a).max())
    assert s["outputs"]["impulse_z"]["unit"] == "N·s"
    assert s["outputs"]["oscillator_displacement"]["shape"] == [2]
    assert s["n_steps"] > 0 and s["steps_per_s"] == pytest.approx(s["n_steps"] / s["wall_time_s"])
    with h5py.File(out) as h:
        assert h.attrs["status"] == "complete"
        assert h["outputs/time"].attrs["unit"] == "s"
        assert h["outputs/external_load"].attrs["unit"] == "N"
        assert h["scene"][()].decode() == scene.text
        assert h["outputs/external_load"].chunks is not None and h["outputs/external_load"].maxshape[0] is None


def test_only_requested_outputs_are_evaluated(tmp_path):
    seen = []

    def evaluate(model, t, y, outputs=(), speed_table=None):
        seen.append(tuple(outputs))
        return fake_outputs(model, t, y, outputs, speed_table)
    scene = fake_scene(SCENE.replace('record = ["cage_speed", "kinematics"]', 'record = ["cage_speed"]'))
    run_scene(scene, tmp_path / "r.h5", quiet=True, backend=fake_backend(evaluate_outputs=evaluate))
    assert set(seen) == {("cage_speed",)} and len(seen) == scene.n_samples
    assert set(read_outputs(tmp_path / "r.h5")) == {"time", "cage_speed", "nominal_cage_speed",
                                                         "inner_ring_speed", "external_load"}


def test_recorded_keys_follow_the_scene_outputs():
    from flexbearing.multibody.output_registry import recorded_keys
    returned = ["contact_load", "contact_angle", "contact_stress", "approach", "pocket_force",
                "cage_land_force_magnitude", "cage_speed", "nominal_cage_speed", "slip_rate",
                "cage_centre", "inner_ring_speed", "external_load", "von_mises_max",
                "film_thickness_min", "ball_position"]
    assert recorded_keys(["contact_stress"], returned) == ["contact_stress", "inner_ring_speed",
                                                           "external_load"]
    assert set(recorded_keys(["cage_speed", "slip", "cage_orbit"], returned)) == {
        "cage_speed", "nominal_cage_speed", "slip_rate", "cage_centre", "inner_ring_speed", "external_load"}
    assert "film_thickness_min" in recorded_keys(["film_thickness"], returned)
    assert "film_thickness_min" not in recorded_keys(["ball_loads"], returned)
    assert set(recorded_keys(["ball_loads"], returned)) == {"contact_load", "approach", "inner_ring_speed",
                                                           "external_load"}


def test_case_set_and_slip_rate_validation(tmp_path, capsys):
    from pathlib import Path

    from flexbearing.studies.case_sets import run_case_set_slip_rate
    from flexbearing.cli.run import parse_cases, print_slip_rate_table
    from flexbearing.simulation.scene import load_case_set
    path = Path(__file__).resolve().parents[1] / "scenes" / "slip_rate_table4.toml"
    full = load_case_set(path)
    assert [c["id"] for c in full.cases] == list(range(1, 16))
    assert full.scenes[7].load_table.tolist() == [[0.0, 1500.0, 0.0, -500.0]]
    assert full.scenes[15].speed_table[0, 1] == pytest.approx(8000 * RPM, rel=1e-15)
    # Table 5's "slip rate error" column is |paper - test| / test: recomputing it from the test and
    # simulated slip rates stored in the case set reproduces the published column (to its 0.01 %)
    table5_error_percent = [6.79, 6.70, 7.45, 4.38, 5.35, 12.28, 5.37, 11.91, 7.75, 7.95, 5.04, 3.18,
                            4.77, 4.82, 11.46]
    rows = [{"case": c["id"], "axial_load": c["axial_load"], "radial_load": c["radial_load"],
             "speed_rpm": c["speed_rpm"], "slip_ours": c["paper_slip_percent"] / 100,
             "slip_test": c["test_slip_percent"] / 100, "slip_paper": c["paper_slip_percent"] / 100}
            for c in full.cases]
    table = print_slip_rate_table(rows)
    np.testing.assert_allclose([100 * r["error_paper"] for r in table["cases"]], table5_error_percent,
                               atol=0.006)
    assert 100 * table["max_error_paper"] == pytest.approx(12.28, abs=0.006)
    assert parse_cases("1-3,12") == [1, 2, 3, 12]
    with pytest.raises(InputError, match=r"case 16 is outside the allowed range \[1, 15\]"):
        parse_cases("14-16")

    # the runner, with the fake physics on a shortened copy of the case set: the fake cage turns
    # at 0.4 omega and nm = 0.5 omega (1 - Dw/dm), so S = 1 - 0.8·167/145 for every case
    short = tmp_path / "cases.toml"
    short.write_text(path.read_text().replace("duration = 1.0 ", "duration = 0.004 ")
                     .replace("average_from = 0.8 ", "average_from = 0.002 "))
    cs = load_case_set(short)
    rows = run_case_set_slip_rate(cs, [2, 13], tmp_path / "out", quiet=True, backend=fake_backend())
    assert [r["case"] for r in rows] == [2, 13]
    for r in rows:
        assert r["slip_ours"] == pytest.approx(1 - 0.8 * 167 / 145, rel=1e-12)
        assert abs(r["slip_drift"]) < 1e-12            # the fake cage speed is steady
    assert rows[1]["slip_test"] == 0.0545 and rows[1]["slip_paper"] == 0.0519
    assert (tmp_path / "out" / "case13.h5").exists()


def test_existing_file_is_not_overwritten(tmp_path):
    out = tmp_path / "r.h5"
    out.write_bytes(b"precious")
    with pytest.raises(InputError, match="exists: pass --resume"):
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    assert out.read_bytes() == b"precious"
    run_scene(fake_scene(), out, quiet=True, force=True, backend=fake_backend())
    assert h5py.is_hdf5(out)


def test_failure_keeps_a_valid_file(tmp_path):
    calls = {"n": 0}

    def unstable(*a, **k):
        calls["n"] += 1
        if calls["n"] == 40:
            raise FloatingPointError("ball 3 inner contact blew up")
        return fake_advance(*a, **k)
    out = tmp_path / "r.h5"
    with pytest.raises(RunInterrupted, match="FloatingPointError") as exc:
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(advance=unstable))
    assert 0 < exc.value.t < 0.06
    with h5py.File(out, "r") as h:
        assert h.attrs["status"].startswith("failed: FloatingPointError")
        n = h["outputs/time"].shape[0]
        assert n > 0 and all(ds.shape[0] == n for _, ds in output_items(h["outputs"]))
        assert h["outputs/time"][-1] == pytest.approx(exc.value.t)


def test_cli_run_refuses_bad_scene_before_computing(tmp_path, capsys):
    from flexbearing.cli.main import main
    bad = tmp_path / "bad.toml"
    bad.write_text(SCENE.replace("axial_load = 100.0", "axial_load = -100.0"))
    assert main(["run", str(bad), "-o", str(tmp_path / "x.h5"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "operation.load.points[0].axial_load = -100 N is outside the allowed range [0, 1e+07] N" in err
    assert not (tmp_path / "x.h5").exists()


def test_rigid_scene_does_not_import_the_fe_stack():
    """DESIGN: the FE stack is never imported by a run whose cage is rigid. The integrator links
    the compiled von Mises kernel of the per-step stress monitor (flexbearing.fem_cage.von_mises: numpy +
    numba only, no FE), nothing else of fem_cage."""
    import subprocess
    code = ("import sys; from flexbearing.simulation.scene import load_scene; from flexbearing.simulation.run import default_backend; "
            "s = load_scene('scenes/paper_steady_rigid.toml'); default_backend(s); "
            "print(sorted(m for m in sys.modules if (m.split('.')[0] in ('dolfinx', 'gmsh', 'petsc4py', "
            "'slepc4py', 'ufl', 'ffcx') or m.startswith('flexbearing.fem_cage.')) "
            "and m != 'flexbearing.fem_cage.von_mises'))")
    from pathlib import Path
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=Path(__file__).resolve().parents[1])
    if out.returncode != 0 and "dynamics is not available" in out.stderr:
        pytest.skip("multibody dynamics not available")
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


def _short_case_set(tmp_path):
    from flexbearing.simulation.scene import load_case_set
    path = Path(__file__).resolve().parents[1] / "scenes" / "slip_rate_table4.toml"
    short = tmp_path / "cases.toml"
    short.write_text(path.read_text().replace("duration = 1.0 ", "duration = 0.004 ")
                     .replace("average_from = 0.8 ", "average_from = 0.002 "))
    return load_case_set(short)


def test_case_set_on_two_workers_equals_serial_and_resume_reads_back(tmp_path):
    """The real rigid dynamics, 4 ms of cases 2 and 13: on a Dask LocalCluster of two workers the
    rows equal the serial ones bit for bit; with --resume the finished cases are read back, their
    files untouched."""
    from flexbearing.studies.case_sets import run_case_set_slip_rate
    cs = _short_case_set(tmp_path)
    serial = run_case_set_slip_rate(cs, [2, 13], tmp_path / "a", quiet=True)
    parallel = run_case_set_slip_rate(cs, [2, 13], tmp_path / "b", quiet=True, workers=2)
    assert [r["case"] for r in parallel] == [2, 13]
    for a, b in zip(serial, parallel):
        assert a["slip_ours"] == b["slip_ours"] and a["n_steps"] == b["n_steps"]
    stamps = [p.stat().st_mtime_ns for p in sorted((tmp_path / "b").glob("case*.h5"))]
    again = run_case_set_slip_rate(cs, [2, 13], tmp_path / "b", quiet=True, workers=2, resume=True)
    assert [p.stat().st_mtime_ns for p in sorted((tmp_path / "b").glob("case*.h5"))] == stamps
    assert [r["slip_ours"] for r in again] == [r["slip_ours"] for r in parallel]


def test_a_failed_case_does_not_stop_the_others(tmp_path):
    """Case 2 (5,000 rpm) fails in its physics; case 1 (4,000 rpm) still runs, and CasesIncomplete
    carries its row and names case 2."""
    from flexbearing.studies.case_sets import CasesIncomplete
    from flexbearing.studies.case_sets import run_case_set_slip_rate
    cs = _short_case_set(tmp_path)

    def advance(model, y, t, t_next, speed_table, *a, **k):
        if speed_table[0, 1] == pytest.approx(5000 * RPM):
            raise FloatingPointError("case 2 blew up (simulated)")
        return fake_advance(model, y, t, t_next, speed_table, *a, **k)

    with pytest.raises(CasesIncomplete, match=r"1 of 2 cases failed \(case 2: RunInterrupted: .*blew up") as exc:
        run_case_set_slip_rate(cs, [1, 2], tmp_path / "out", quiet=True, backend=fake_backend(advance=advance))
    assert [r["case"] for r in exc.value.rows] == [1]


def test_the_scenes_max_step_reaches_the_integrator(tmp_path):
    """[integrator] max_step is handed to every integrator call (keyword max_step), and the fake
    integrator honouring it takes at least duration / max_step steps; without it the keyword is not
    passed at all (a backend without it keeps working)."""
    seen = []

    def advance(*a, max_step=None, **k):
        seen.append(max_step)
        if max_step is None:
            return fake_advance(*a, **k)
        model, y, t, t_next, sp, ld, imp, tol, h, ws = a
        return fake_advance(model, y, t, t_next, sp, ld, imp, tol, min(h, max_step), ws)

    scene = fake_scene(SCENE.replace("initial_step = 1e-5", "initial_step = 1e-5\nmax_step = 1e-4"))
    run_scene(scene, tmp_path / "capped.h5", quiet=True, backend=fake_backend(advance=advance))
    assert seen and set(seen) == {1e-4}
    seen.clear()
    run_scene(fake_scene(), tmp_path / "free.h5", quiet=True, backend=fake_backend(advance=advance))
    assert seen and set(seen) == {None}


if __name__ == "__main__":      # used by tests/test_resume.py to run a fake scene in a subprocess
    out = sys.argv[1]
    # optional: at the first checkpoint of at least this many samples, wait for a line on stdin (a
    # test that must act while this run is still writing holds it there, whatever the machine's load)
    hold_at = int(sys.argv[2]) if len(sys.argv) > 2 else None
    from flexbearing.simulation import results

    # every checkpoint, the run loop's (written by the writer thread) and the last one, goes through it
    real = results.ResultsWriter._write_checkpoint

    def announcing(self, *a, **k):
        global hold_at
        real(self, *a, **k)
        print("CHECKPOINT", self.n_written, flush=True)
        if hold_at is not None and self.n_written >= hold_at:
            hold_at = None
            sys.stdin.readline()
    results.ResultsWriter._write_checkpoint = announcing
    slow = fake_backend(advance=lambda *a, **k: (__import__("time").sleep(0.01), fake_advance(*a, **k))[1])
    run_scene(fake_scene(), out, quiet=True, backend=slow)


def test_the_job_loops_stop_with_one_exception_family():
    """A run, a case set, a study and the validation end early with members of one family
    (flexbearing.simulation.stopped; each member is defined beside the loop that raises it), so a
    caller catches WorkStopped once; Interrupted carries whether resuming helps, Incomplete the
    failed jobs beside the finished rows."""
    from flexbearing.simulation import stopped as S
    from flexbearing.simulation.jobs import JobFailure
    from flexbearing.simulation.run import RunInterrupted
    from flexbearing.studies.case_sets import CasesIncomplete
    from flexbearing.studies.study import StudyIncomplete
    from flexbearing.studies.uncertainty import UncertaintyInterrupted
    from flexbearing.studies.validation.slip_rate import ValidationInterrupted
    run = RunInterrupted("run interrupted", 0.01, "r.h5", KeyboardInterrupt(), resumable=False)
    assert isinstance(run, S.Interrupted) and isinstance(run, S.WorkStopped)
    assert (run.t, run.path, run.resumable, run.rows) == (0.01, "r.h5", False, [])
    cases = CasesIncomplete("1 of 2 cases failed", [{"case": 1}], [JobFailure(1, "case 2", "boom")])
    assert isinstance(cases, S.Incomplete) and isinstance(cases, S.WorkStopped)
    assert cases.rows == [{"case": 1}] and [f.name for f in cases.failures] == ["case 2"]
    assert issubclass(StudyIncomplete, S.Incomplete) and issubclass(ValidationInterrupted, S.Interrupted)
    assert issubclass(UncertaintyInterrupted, S.Interrupted)
