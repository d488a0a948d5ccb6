"""Slip-rate validation data and definitions (paper §3.2, Tables 4/5) and, marked slow, the runs.

The fast tests check the transcription of Table 5 against the paper's own error column and the
slip definition; the slow ones run the dynamic model on the cases (flexbearing.studies.validation.slip_rate).
"""
import math

import numpy as np
import pytest

from flexbearing.studies.validation import slip_rate as V
from flexbearing.multibody.geometry import nominal_cage_speed

# Table 5, last column: the paper's "slip rate error" (%) = |sim − test|/test
PAPER_ERROR_COLUMN = [6.79, 6.70, 7.45, 4.38, 5.35, 12.28, 5.37, 11.91, 7.75, 7.95, 5.04, 3.18, 4.77, 4.82, 11.46]


def test_table5_transcription_reproduces_the_paper_error_column():
    """Our copy of (test, simulated) slips gives the paper's error column to its rounding
    (0.02 % points: two-decimal inputs)."""
    cases = V.slip_rate_cases()
    assert [c["case"] for c in cases] == list(range(1, 16))
    for c, e in zip(cases, PAPER_ERROR_COLUMN):
        err = 100 * abs(c["paper_slip_pct"] - c["test_slip_pct"]) / c["test_slip_pct"]
        assert err == pytest.approx(e, abs=0.02)
    # Table 4 loads: groups 1–3
    assert {(c["group"], c["axial_load"], c["radial_load"]) for c in cases} == {
        (1, 1100.0, 200.0), (2, 1500.0, 500.0), (3, 2000.0, 1000.0)}
    # the paper's own mean error over the 15 cases (the goal to beat): 7.0 %
    assert np.mean(PAPER_ERROR_COLUMN) == pytest.approx(7.0, abs=0.05)


def test_nominal_cage_speed_formula():
    """nm = 0.5·ni·(1 − Dw·cos(alpha)/dm) (paper §3.2): 10,000 rpm, alpha 30°."""
    wi = 10000 * math.pi / 30
    nm = nominal_cage_speed(wi, 0.022, 0.167, math.radians(30.0))
    assert nm == pytest.approx(0.5 * wi * (1 - 0.022 * math.cos(math.radians(30)) / 0.167), rel=1e-15)
    assert nm / wi == pytest.approx(0.44296, abs=1e-5)


def test_summary_statistics():
    rows = [dict(c, slip_pct=c["test_slip_pct"] * 1.1, error_vs_test_pct=10.0,
                 paper_error_vs_test_pct=100 * abs(c["paper_slip_pct"] - c["test_slip_pct"]) / c["test_slip_pct"])
            for c in V.slip_rate_cases()]
    s = V.summarise(rows)
    assert s["all"]["n"] == 15 and s["calibration_1_8"]["n"] == 8 and s["check_9_15"]["n"] == 7
    assert s["all"]["mean_error_pct"] == pytest.approx(10.0)
    assert s["all"]["paper_mean_error_pct"] == pytest.approx(np.mean(PAPER_ERROR_COLUMN), abs=0.01)


def test_validation_bearing_runs_in_two_point_contact_at_the_shim_angle():
    """The validation's clearance is the design value Pd = 2(fe − 0.5)·Dw·(1 − cos alphaD): hand
    value for fe 0.515, Dw 22 mm, alphaD 30°: 2·0.015·22e-3·(1 − cos 30°) = 88.42 um; with it the
    two-point free contact angle equals the shim angle (Bearing.free_contact_angle, exact algebra:
    1e-12 relative)."""
    pd = V.design_clearance()
    assert pd == pytest.approx(2 * 0.015 * 22e-3 * (1 - math.cos(math.radians(30))), rel=1e-12)
    assert pd == pytest.approx(88.42e-6, abs=0.01e-6)
    assert V.VALIDATION_BEARING.radial_clearance == pd
    assert V.VALIDATION_BEARING.free_contact_angle == pytest.approx(V.VALIDATION_BEARING.shim_angle, rel=1e-12)


@pytest.mark.slow
def test_slip_rate_case_1_runs_and_settles():
    """Case 1 (4000 rpm, 1100/200 N) at the validation oil state settles within 2.5 s of
    simulated time (Aitken criterion of flexbearing.studies.validation.slip_rate; measured 1.65 s since the pressure
    rolling force's sign was corrected in session 8, 1.0 s before) and the cage runs below the
    inner-ring speed's epicyclic bound (0 < nc < ni/2)."""
    rows = V.run_slip_rate_validation(cases=[1], quiet=True, t_max=2.5)
    r = rows[0]
    assert r["settled"]
    wi = r["speed_rpm"] * math.pi / 30
    assert 0.0 < r["cage_speed"] < 0.5 * wi


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="issue 4 goal not met: benchmarks/results/slip_rate.md (mean error 135.9 % settled, session 10; "
                   "free-ball kinematics and the 4106 fit's light-load traction, diagnosis in flexbearing.studies.validation.slip_rate)")
def test_slip_rate_case_1_within_goal():
    """Goal (c): no case above 12 % relative error to the test. Case 1 as the representative."""
    r = V.run_slip_rate_validation(cases=[1], quiet=True, t_max=1.5)[0]
    assert r["error_vs_test_pct"] < 12.0


def test_steady_start_of_the_light_load_high_speed_cases():
    """start="steady" (flexbearing.multibody.steady): case 6 (12,000 rpm, 1100/200 N) starts from the fixed point of
    the thrust-only dynamics, so its first 50 ms already turn at that cage speed; the radial load
    and the weight then act (within 1 %, their effect on the cage speed here). With the paper's fit,
    case 1 (4000 rpm) has no such fixed point (the fit's dead zone) and falls back to the
    quasi-static start, saying so; the EHL law (the default, no dead zone) has one."""
    import math
    from flexbearing.common.validation import InputError
    from flexbearing.multibody.model import P_GRAV
    from flexbearing.multibody.steady import steady_thrust_state
    case6 = [c for c in V.slip_rate_cases() if c["case"] == 6][0]
    oil = V.validation_oil(None, V.case_oil_air_fraction(V.VALIDATION_OIL_AIR_FRACTION, 12000, V.VALIDATION_OIL_AIR_SCALING))
    row = V.run_slip_case(case6, V.VALIDATION_BEARING, oil, t_min=0.05, t_max=0.05, start="steady")
    assert row["start"] == "steady"
    model = V.build_validation_model(V.VALIDATION_BEARING, oil)
    p0 = model.p.copy()
    p0[P_GRAV] = 0.0
    _, info = steady_thrust_state(model._replace(p=p0), 12000 * math.pi / 30, case6["axial_load"])
    assert abs(row["window_means"][0] / info["cage_speed"] - 1.0) < 1e-2
    case1 = [c for c in V.slip_rate_cases() if c["case"] == 1][0]
    row1 = V.run_slip_case(case1, V.VALIDATION_BEARING, V.validation_oil(), t_min=0.05, t_max=0.05, start="steady",
                           traction_law="fit")
    assert row1["start"] == "quasi_static (no steady thrust state)"
    row1 = V.run_slip_case(case1, V.VALIDATION_BEARING, V.validation_oil(), t_min=0.05, t_max=0.05, start="steady")
    assert row1["start"] == "steady"
    with pytest.raises(InputError, match="start"):
        V.run_slip_case(case1, V.VALIDATION_BEARING, V.validation_oil(), t_max=0.05, start="rest")


PARALLEL_KW = dict(cases=[7, 1], quiet=True, t_max=0.1, t_min=0.05)


@pytest.fixture(scope="module")
def serial_rows():
    """0.1 s of cases 7 and 1, one after the other in this process."""
    return V.run_slip_rate_validation(**PARALLEL_KW)


def test_cases_in_parallel_give_the_same_rows_in_case_order(serial_rows):
    """workers=2 runs the cases on a Dask LocalCluster of two processes: each row is one
    deterministic integration, so the rows must equal the serial ones bit for bit, and come back
    in case order (they are started highest speed first). 0.1 s of cases 7 and 1; a bad worker
    count is refused with its name."""
    from flexbearing.common.validation import InputError
    kw = PARALLEL_KW
    serial = serial_rows
    parallel = V.run_slip_rate_validation(workers=2, **kw)
    assert [r["case"] for r in parallel] == [1, 7]
    for a, b in zip(serial, parallel):
        assert a["slip_pct"] == b["slip_pct"] and a["steps"] == b["steps"] and a["window_means"] == b["window_means"]
    with pytest.raises(InputError, match="workers"):
        V.run_slip_rate_validation(workers=0, **kw)


def test_cases_on_a_cluster_of_separate_processes(serial_rows, dask_cluster):
    """The same two cases on a scheduler and two worker processes (`--scheduler`): the serial rows."""
    rows = V.run_slip_rate_validation(scheduler=dask_cluster.address, **PARALLEL_KW)
    assert [r["case"] for r in rows] == [1, 7]
    for a, b in zip(serial_rows, rows):
        assert a["slip_pct"] == b["slip_pct"] and a["steps"] == b["steps"] and a["window_means"] == b["window_means"]


def test_an_interrupted_validation_keeps_the_finished_cases(tmp_path, monkeypatch, capsys):
    """Ctrl-C during case 7 (after case 1 finished): `flexbearing validate slip-rate --json F` has already
    written case 1 to F (complete: false), prints it, and exits with 130; the Python API raises
    ValidationInterrupted carrying the same row and the missing case."""
    import json
    from flexbearing.cli.main import main
    real = V.run_slip_case

    def ctrl_c_on_case_7(case, *a, **k):
        if case["case"] == 7:
            raise KeyboardInterrupt
        return real(case, *a, **k)

    monkeypatch.setattr(V, "run_slip_case", ctrl_c_on_case_7)
    out = tmp_path / "slip.json"
    assert main(["validate", "slip-rate", "--cases", "1,7", "--t-max", "0.1", "--workers", "1", "--quiet",
                 "--json", str(out)]) == 130
    d = json.loads(out.read_text())
    assert d["complete"] is False and [c["case"] for c in d["cases"]] == [1]
    assert "cases not finished: [7]" in capsys.readouterr().err
    with pytest.raises(V.ValidationInterrupted) as info:
        V.run_slip_rate_validation(cases=[1, 7], quiet=True, t_max=0.1)
    assert [r["case"] for r in info.value.rows] == [1] and info.value.missing == [7]
    assert isinstance(info.value.cause, KeyboardInterrupt)
    monkeypatch.setattr(V, "run_slip_case", real)
    assert main(["validate", "slip-rate", "--cases", "1,7", "--t-max", "0.1", "--quiet", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["complete"] is True and [c["case"] for c in d["cases"]] == [1, 7]


def test_validate_cli_passes_the_ball_model_options(monkeypatch):
    """`flexbearing validate slip-rate --ball-attitude no_pivot --transverse-traction off` runs the
    cases with those model options, the gyroscopic pair's ring reaction off (one function,
    slip_rate.validation_model_options, builds them from the flags)."""
    from flexbearing.cli.main import main
    seen = {}

    def record(cases=None, quiet=False, on_row=None, options=None, bearing=None, **kw):
        seen.update(options=options, bearing=bearing)
        return []

    monkeypatch.setattr(V, "run_slip_rate_validation", record)
    main(["validate", "slip-rate", "--cases", "1", "--quiet", "--ball-attitude", "no_pivot",
          "--transverse-traction", "off"])
    assert seen["options"] == {"ball_attitude": "no_pivot", "transverse_traction": False,
                               "attitude_ring_reaction": False}
    assert seen["options"] == V.validation_model_options("no_pivot", "off")
    assert seen["bearing"] == V.VALIDATION_BEARING
    # the CLI's written-out choices take every attitude the model has
    from flexbearing.multibody.model import BALL_ATTITUDES
    for attitude in BALL_ATTITUDES:
        assert main(["validate", "slip-rate", "--cases", "1", "--quiet", "--ball-attitude", attitude]) == 0
        assert seen["options"]["ball_attitude"] == attitude


def test_the_test_bearings_unknowns_can_be_set(monkeypatch, capsys):
    """--shim-angle sets alphaD and, unless --radial-clearance is given, the design clearance of
    that angle, Pd = 2·(fe − 0.5)·Dw·(1 − cos alphaD) = 2·0.015·22 mm·(1 − cos 15°) = 22.5 um
    (written out below from the formula, not taken from the code); a shim angle outside [0, 45)°
    is refused naming the field and the range."""
    import math
    from flexbearing.cli.main import main
    seen = {}
    monkeypatch.setattr(V, "run_slip_rate_validation", lambda **kw: seen.update(kw) or [])
    main(["validate", "slip-rate", "--cases", "1", "--quiet", "--shim-angle", "15"])
    b = seen["bearing"]
    assert b.shim_angle == pytest.approx(math.radians(15.0))
    assert b.radial_clearance == pytest.approx(2 * 0.015 * 22e-3 * (1 - math.cos(math.radians(15.0))), rel=1e-12)
    main(["validate", "slip-rate", "--cases", "1", "--quiet", "--shim-angle", "15", "--radial-clearance", "5e-5"])
    assert seen["bearing"].radial_clearance == 5e-5
    assert main(["validate", "slip-rate", "--cases", "1", "--quiet", "--shim-angle", "50"]) != 0
    assert "shim angle (--shim-angle) = 50" in capsys.readouterr().err


def test_procedure_flags_are_refused_with_a_case_set(capsys):
    """--case-set runs scenes, which carry their own bearing, model and durations: the flags of
    flexbearing.studies.validation.slip_rate's procedure would be ignored, so they are refused, naming them."""
    from flexbearing.cli.main import main
    assert main(["validate", "slip-rate", "--case-set", "scenes/slip_rate_table4.toml", "--cases", "1",
                 "--shim-angle", "15", "--ball-attitude", "no_pivot"]) != 0
    err = capsys.readouterr().err
    assert "--ball-attitude, --shim-angle cannot be used with --case-set" in err


def test_the_procedure_settings_reach_the_validation(monkeypatch, tmp_path):
    """The settings the validation module's own command line had (issue 45: it has none now) are
    flags of `flexbearing validate slip-rate`: each reaches run_slip_rate_validation under its
    keyword, gravity and the ring reaction as model options; --out-dir writes the report; with
    --case-set they are refused like the other procedure flags."""
    from flexbearing.cli.main import main
    seen = {}
    monkeypatch.setattr(V, "run_slip_rate_validation", lambda **kw: seen.update(kw) or [])
    written = {}
    monkeypatch.setattr(V, "write_report", lambda rows, d: written.update(rows=rows, d=d))
    assert main(["validate", "slip-rate", "--cases", "1", "--quiet", "--t-min", "0.3", "--oil-temperature", "120",
                 "--oil-air-fraction", "0.005", "--oil-air-scaling", "constant", "--traction-law", "fit",
                 "--traction-scale", "2", "--gravity", "0", "--attitude-ring-reaction", "on",
                 "--out-dir", str(tmp_path / "r")]) == 0
    assert {k: seen[k] for k in ("t_min", "oil_temperature_c", "oil_air_fraction", "oil_air_scaling",
                                 "traction_law", "traction_scale")} == dict(
        t_min=0.3, oil_temperature_c=120.0, oil_air_fraction=0.005, oil_air_scaling="constant",
        traction_law="fit", traction_scale=2.0)
    assert seen["options"] == V.validation_model_options(None, "on", 0.0, "on")
    assert written == dict(rows=[], d=str(tmp_path / "r"))
    # without them the procedure's own defaults apply (the keywords are not passed at all)
    seen.clear()
    main(["validate", "slip-rate", "--cases", "1", "--quiet"])
    assert not {"t_min", "oil_temperature_c", "traction_law", "traction_scale"} & set(seen)


def test_procedure_settings_are_refused_with_a_case_set(capsys):
    from flexbearing.cli.main import main
    assert main(["validate", "slip-rate", "--case-set", "scenes/slip_rate_table4.toml", "--cases", "1",
                 "--oil-temperature", "120", "--gravity", "0"]) != 0
    assert "--oil-temperature, --gravity cannot be used with --case-set" in capsys.readouterr().err
