"""The slip-rate uncertainty study (flexbearing.studies.uncertainty, issue 23 item 2): the Sobol' estimators
against the Ishigami function's analytic indices, the sampling and scaling against hand values,
the unknowns file's validation, the surrogate, and one job of the fast path against the dynamic run."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from flexbearing.common.validation import InputError
from flexbearing.studies import uncertainty as U
from flexbearing.studies import sensitivity as SA, uncertainty_report as UR

ROOT = Path(__file__).resolve().parents[1]
UNKNOWNS = ROOT / "scenes" / "slip_rate_unknowns.toml"


# ------------------------------------------------------------------ Sobol' estimators: Ishigami
def _ishigami(u, a=7.0, b=0.1):
    x = -math.pi + 2.0 * math.pi * u
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def _ishigami_exact(a=7.0, b=0.1):
    """Analytic indices (Ishigami & Homma 1990; Sobol' & Levitan 1999): V = a²/8 + b·pi⁴/5 +
    b²·pi⁸/18 + 1/2, V1 = (1 + b·pi⁴/5)²/2, V2 = a²/8, V3 = 0, V13 = 8·b²·pi⁸/225."""
    pi = math.pi
    v = a * a / 8 + b * pi ** 4 / 5 + b * b * pi ** 8 / 18 + 0.5
    v1, v2, v13 = 0.5 * (1 + b * pi ** 4 / 5) ** 2, a * a / 8, 8 * b * b * pi ** 8 / 225
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v


def test_ishigami_values_are_the_published_ones():
    s, st = _ishigami_exact()
    # the values tabulated for a = 7, b = 0.1 (e.g. Saltelli et al., Global Sensitivity Analysis: The Primer, 2008)
    assert np.allclose(s, [0.3139, 0.4424, 0.0], atol=1e-4)
    assert np.allclose(st, [0.5576, 0.4424, 0.2437], atol=1e-4)


@pytest.mark.parametrize("seed", [0, 1])
def test_sobol_estimators_on_ishigami(seed):
    """Saltelli first order and Jansen total on n = 4096 (4096·5 evaluations). Tolerance 0.02:
    the bootstrap 95 % half-widths at this n are 0.013–0.043 (plain Monte-Carlo level, the
    bootstrap breaks the Sobol' structure and so over-states the error); the scrambled design's
    actual errors measured over 3 seeds were <= 0.0021. The exact values must also lie inside the
    reported intervals."""
    s_ex, st_ex = _ishigami_exact()
    r = SA.sobol_indices(_ishigami, 3, n=4096, seed=seed, n_boot=100)
    assert np.max(np.abs(r["S"] - s_ex)) < 0.02
    assert np.max(np.abs(r["ST"] - st_ex)) < 0.02
    assert np.all(r["S_ci"][0] <= s_ex) and np.all(s_ex <= r["S_ci"][1])
    assert np.all(r["ST_ci"][0] <= st_ex) and np.all(st_ex <= r["ST_ci"][1])


def test_sobol_of_additive_linear_function():
    """f = u0 + 2·u1 (u uniform): V_i = c_i²/12, so S = ST = (0.2, 0.8, 0); exact for the
    estimators' means, checked at 1e-2 (n = 2048)."""
    r = SA.sobol_indices(lambda u: u[:, 0] + 2.0 * u[:, 1], 3, n=2048, n_boot=10)
    assert np.allclose(r["S"], [0.2, 0.8, 0.0], atol=1e-2)
    assert np.allclose(r["ST"], [0.2, 0.8, 0.0], atol=1e-2)


# ------------------------------------------------------------------ sampling and scaling
def test_unit_to_value_scaling_by_hand():
    uni = U.Unknown("shim_angle", "uniform", 15.0, 35.0, nominal=30.0, unit="deg", reason="r")
    log = U.Unknown("oil_air_fraction", "log_uniform", 0.0005, 0.03, nominal=0.002, reason="r")
    ch = U.Unknown("ball_material", "choice", values=("steel", "silicon_nitride"), nominal="steel", reason="r")
    assert uni.from_unit(0.25) == pytest.approx(20.0)                       # 15 + 0.25·20
    assert log.from_unit(0.5) == pytest.approx(math.sqrt(0.0005 * 0.03))    # geometric middle 3.873e-3
    assert log.from_unit(0.0) == pytest.approx(0.0005) and log.from_unit(1.0) == pytest.approx(0.03)
    assert ch.from_unit(0.49) == "steel" and ch.from_unit(0.5) == "silicon_nitride" and ch.from_unit(0.999) == "silicon_nitride"
    for k, x in ((uni, 27.3), (log, 0.01)):
        assert k.from_unit(k.to_unit(x)) == pytest.approx(x)
    assert ch.from_unit(ch.to_unit("silicon_nitride")) == "silicon_nitride"


def test_sample_is_space_filling_and_reproducible():
    """64 scrambled Sobol' points: every coordinate has exactly one point in each of the 64 cells
    [k/64, (k+1)/64) (a (t, m, s)-net's one-dimensional projections stay stratified under Owen
    scrambling); the same seed gives the same points."""
    study = U.load_unknowns(UNKNOWNS)
    u = SA.unit_sample(64, 6, study.seed)
    for j in range(6):
        assert sorted(np.floor(u[:, j] * 64).astype(int)) == list(range(64))
    p1, p2 = U.sample_points(study), U.sample_points(study)
    assert p1 == p2 and len(p1) == study.points
    for p in p1:
        assert 15.0 <= p["shim_angle"] <= 35.0 and 0.5 <= p["traction_scale"] <= 2.0
        assert p["ball_material"] in ("steel", "silicon_nitride")
    assert 20 <= sum(p["ball_material"] == "silicon_nitride" for p in p1) <= 44


def test_point_bearing_and_oil_by_hand():
    """Pd = 2·(fe − 0.5)·Dw·(1 − cos 30°) + excess = 88.42 + 10 um; ball mass 3200·pi·Dw³/6 = 17.84 g
    for Si3N4; oil fraction X_ref·4000/n; traction scale passed through."""
    point = dict(shim_angle=30.0, clearance_excess=10e-6, oil_temperature=100.0, traction_scale=1.5,
                 oil_air_fraction=0.004, ball_material="silicon_nitride")
    b, oil, scale = U.point_bearing_oil(point, 8000)
    assert b.radial_clearance == pytest.approx(2 * 0.015 * 0.022 * (1 - math.cos(math.radians(30))) + 10e-6, rel=1e-12)
    assert b.radial_clearance == pytest.approx(98.42e-6, abs=0.01e-6)
    assert b.ball_mass == pytest.approx(3200 * math.pi * 0.022 ** 3 / 6) and b.ball_mass == pytest.approx(0.01784, abs=1e-5)
    assert b.shim_angle == pytest.approx(math.radians(30.0))
    assert oil.oil_air_fraction == pytest.approx(0.002) and oil.temperature_c == 100.0 and scale == 1.5


# ------------------------------------------------------------------ the unknowns file
def test_shipped_unknowns_file_loads():
    study = U.load_unknowns(UNKNOWNS)
    assert study.names == ["shim_angle", "clearance_excess", "oil_temperature", "traction_scale",
                           "oil_air_fraction", "ball_material"]
    assert study.points >= 64
    assert all(len(u.reason) > 80 for u in study.unknowns)
    assert study.nominal()["shim_angle"] == 30.0 and study.nominal()["ball_material"] == "steel"


def _edit(tmp_path, old, new):
    text = UNKNOWNS.read_text()
    assert old in text
    p = tmp_path / "u.toml"
    p.write_text(text.replace(old, new, 1))
    return p


@pytest.mark.parametrize("old, new, message", [
    ("points = 64", "points = 32", "study.points = 32"),
    ("lo = 15.0", "lo = 50.0", "unknowns.shim_angle.lo = 50"),
    ("hi = 35.0", "hi = 10.0", "unknowns.shim_angle.hi = 10"),
    ('kind = "log_uniform"\nlo = 0.5', 'kind = "log_uniform"\nlo = 0.1', "unknowns.traction_scale.lo = 0.1"),
    ('values = ["steel", "silicon_nitride"]', 'values = ["steel", "glass"]', "unknowns.ball_material.values"),
    ('kind = "uniform"\nlo = 15.0', 'kind = "normal"\nlo = 15.0', "unknowns.shim_angle.kind = 'normal'"),
    ("[unknowns.shim_angle]", "[unknowns.shim_angel]", "'shim_angel' is not an unknown"),
    ("nominal = 150.0", "nominal = 200.0", "unknowns.oil_temperature.nominal = 200"),
    ('unit = "°C"', 'unit = "K"', "unknowns.oil_temperature.unit = 'K'"),
    ("seed = 20261126", "seed = -1", "study.seed = -1"),
    ("[unknowns.shim_angle]\n", "[unknowns.shim_angle]\ncolour = 1\n", "unknowns.shim_angle: unknown key 'colour'"),
])
def test_unknowns_file_errors_name_field_and_range(tmp_path, old, new, message):
    with pytest.raises(InputError) as e:
        U.load_unknowns(_edit(tmp_path, old, new))
    assert message in str(e.value)


def test_missing_reason_and_missing_unknown(tmp_path):
    text = UNKNOWNS.read_text()
    start = text.index("[unknowns.ball_material]")
    p = tmp_path / "u.toml"
    p.write_text(text[:start])
    with pytest.raises(InputError, match="ball_material are missing"):
        U.load_unknowns(p)
    i = text.index('reason = """Contact angle')
    j = text.index('"""', i + 12) + 3
    p.write_text(text[:i] + 'reason = ""' + text[j:])
    with pytest.raises(InputError, match="unknowns.shim_angle.reason is missing"):
        U.load_unknowns(p)


# ------------------------------------------------------------------ surrogate and analysis
def test_quadratic_surrogate_recovers_a_quadratic_exactly():
    study = U.load_unknowns(UNKNOWNS)
    u = SA.unit_sample(64, 6, 3)
    mat = (u[:, 5] >= 0.5).astype(float)
    y = 1.0 + 2.0 * u[:, 0] + 3.0 * u[:, 1] ** 2 - u[:, 0] * u[:, 2] + 4.0 * mat + 0.5 * mat * u[:, 3]
    sur = SA.QuadraticSurrogate(study.unknowns).fit(u, y)
    assert sur.features(u).shape[1] == 27          # 1 + 6 + 15 cross + 5 squares (not the indicator's)
    assert np.max(np.abs(sur.loo_residuals(u, y))) < 1e-9
    v = SA.unit_sample(128, 6, 4)
    mv = (v[:, 5] >= 0.5).astype(float)
    assert np.allclose(sur(v), 1.0 + 2.0 * v[:, 0] + 3.0 * v[:, 1] ** 2 - v[:, 0] * v[:, 2] + 4.0 * mv
                       + 0.5 * mv * v[:, 3])


def _synthetic_rows(study, points, slip_of):
    from flexbearing.studies.validation.slip_rate import slip_rate_cases
    rows = []
    for p in points:
        for c in slip_rate_cases():
            rows.append(dict(point=p["point"], case=c["case"], slip_pct=slip_of(p, c), converged=True))
    return rows


def test_analyse_on_a_known_response(tmp_path):
    """Slip = test slip + 4·(traction_scale − 1.25)/0.75 (a linear function of one unknown on a
    log-uniform axis: the surrogate's quadratic fits it closely): the band contains every test point,
    all of the mean error's variance is the traction scale's, the best point is the one nearest
    scale 1.25, and the report files are written."""
    study = U.load_unknowns(UNKNOWNS)
    points = [dict(p, point=k) for k, p in enumerate(U.sample_points(study))]
    rows = _synthetic_rows(study, points, lambda p, c: c["test_slip_pct"] + 4.0 * (p["traction_scale"] - 1.25) / 0.75)
    a = U.analyse(study, rows, points, n_design=1024, n_boot=20, n_search=1024)
    assert a["n_complete"] == 64 and a["test_inside"] == 15
    me = a["sensitivity"]["mean error"]
    assert me["traction_scale"]["ST"] > 0.9
    assert all(v["ST"] < 0.05 for n, v in me.items() if n != "traction_scale")
    nearest = min(points, key=lambda p: abs(p["traction_scale"] - 1.25))
    assert a["best_sample_point"]["point"] == nearest["point"]
    paths = UR.write_report(a, tmp_path, command="flexbearing uncertainty")
    assert all(p.exists() for p in paths)
    back = json.loads(paths[1].read_text())
    assert back["test_inside"] == 15
    assert "traction_scale" in paths[0].read_text()


# ------------------------------------------------------------------ the fast path's one job
def test_steady_job_against_the_dynamic_validation_case_12():
    """Case 12 at the nominal point: the steady fixed point with weight against the dynamic
    validation run of session 14 (slip_rate_session14_ehl.json, same inputs: −7.80 %). Tolerance
    0.5 points: the frozen-azimuth approximation (flexbearing.multibody.steady) differs from the dynamics by
    0.05–0.65 points over the 15 nominal cases (benchmarks/results/slip_rate_uncertainty.md)."""
    from flexbearing.studies.validation.slip_rate import slip_rate_cases
    study = U.load_unknowns(UNKNOWNS)
    dyn = {r["case"]: r["slip_pct"] for r in json.loads(
        (ROOT / "benchmarks/results/slip_rate_session14_ehl.json").read_text())["rows"]}
    row = U.steady_case_slip(study.nominal(), slip_rate_cases()[11])
    assert row["converged"]
    assert row["slip_pct"] == pytest.approx(dyn[12], abs=0.5)


# ------------------------------------------------------------------ the command
def test_cli_continues_from_finished_rows_and_writes_the_report(tmp_path, capsys):
    """`flexbearing uncertainty --cases 12` with every (point, case) already in rows.jsonl (as after
    an interrupted study): nothing is recomputed, the band of case 12 is printed (synthetic slips
    test − 0.5 .. test + 0.5 points, so the test is inside: 1 of 15), the surrogate's best points are
    run with the model, the report is written."""
    from flexbearing.cli.main import main
    from flexbearing.studies.validation.slip_rate import slip_rate_cases
    study = U.load_unknowns(UNKNOWNS)
    d = tmp_path / "out" / study.name
    d.mkdir(parents=True)
    c12 = slip_rate_cases()[11]
    points = [dict(p, point=k) for k, p in enumerate(U.sample_points(study))] + [dict(study.nominal(), point="nominal")]
    with open(d / "rows.jsonl", "w") as f:
        for k, p in enumerate(points):
            f.write(json.dumps(dict(point=p["point"], case=12, slip_pct=c12["test_slip_pct"] - 0.5 + (k % 64) / 63.0,
                                    converged=True, cpu_s=0.0)) + "\n")
    rc = main(["uncertainty", str(UNKNOWNS), "-o", str(tmp_path / "out"), "--cases", "12", "--workers", "1",
               "--report-dir", str(tmp_path / "rep"), "--quiet"])
    out = capsys.readouterr().out
    assert rc == 0
    assert "case 12: band" in out and "test slips inside their 5-95 % band: 1/15" in out
    assert (tmp_path / "rep" / "slip_rate_uncertainty.md").exists()
    rows = U.read_rows(d / "rows.jsonl")
    # nothing recomputed; the surrogate's best point per ball material re-run with the model (2 rows)
    assert len(rows) == 67
    assert sorted(r["point"].split("_", 1)[1].rsplit("_", 1)[0] for r in rows[65:]) == ["silicon_nitride", "steel"]
    assert all(r["converged"] and abs(r["slip_pct"]) < 20 for r in rows[65:]), [
        {k: r.get(k) for k in ("point", "converged", "slip_pct", "residual", "reason")} for r in rows[65:]]
    # --report-only: the same analysis from the rows, no runs
    (tmp_path / "rep" / "slip_rate_uncertainty.md").unlink()
    assert main(["uncertainty", str(UNKNOWNS), "-o", str(tmp_path / "out"), "--cases", "12", "--report-only",
                 "--report-dir", str(tmp_path / "rep"), "--quiet"]) == 0
    assert len(U.read_rows(d / "rows.jsonl")) == 67
    assert "case 12" in (tmp_path / "rep" / "slip_rate_uncertainty.md").read_text()


def test_cli_bad_input_exit_2(tmp_path, capsys):
    from flexbearing.cli.main import main
    p = tmp_path / "u.toml"
    p.write_text(UNKNOWNS.read_text().replace("points = 64", "points = 8"))
    assert main(["uncertainty", str(p), "-o", str(tmp_path)]) == 2
    assert "study.points = 8" in capsys.readouterr().err
    assert main(["uncertainty", str(UNKNOWNS), "-o", str(tmp_path), "--cases", "x"]) == 2


def test_a_ctrl_c_of_the_study_is_one_of_the_job_loops_stops(tmp_path, monkeypatch):
    """A Ctrl-C while the jobs run comes back as UncertaintyInterrupted, of the one family every job
    loop stops with (flexbearing.simulation.stopped), naming the rows file that keeps the finished
    jobs; nothing is lost (the rows are appended as they finish)."""
    from flexbearing.simulation.stopped import Interrupted, WorkStopped
    from flexbearing.studies.uncertainty import UncertaintyInterrupted

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(U, "run_jobs", interrupted)
    study = U.load_unknowns(UNKNOWNS)
    with pytest.raises(UncertaintyInterrupted) as info:
        U.run_study(study, tmp_path, cases=[1], workers=1, progress=False)
    assert isinstance(info.value, Interrupted) and isinstance(info.value, WorkStopped)
    assert isinstance(info.value.cause, KeyboardInterrupt)
    assert info.value.rows_file == str(tmp_path / study.name / "rows.jsonl")
    assert "run the same command again" in str(info.value)
