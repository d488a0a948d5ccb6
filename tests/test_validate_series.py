"""`flexbearing validate series` (flexbearing.studies.validation.series): the series' bearings, one steady
point against the recorded dynamics, resumable rows, the checks' verdicts and the page."""
import math
from dataclasses import replace

import pytest

from flexbearing.common.validation import InputError
from flexbearing.multibody.bearing import PAPER_BEARING
from flexbearing.studies.validation import kinematics as K, series as VS, series_file as SF

YANG = SF.VALIDATION_DIR / "yang2025_table5.toml"


def test_the_paper_series_is_the_paper_preset():
    # Table 1 = Table 3: the series file's bearing at its nominal unknowns is the one bearing definition
    vs = SF.load_series(YANG)
    b = VS.series_bearing(vs, VS.nominal_values(vs))
    for name in ("pitch_diameter", "ball_diameter", "n_balls", "fe", "fi", "inner_ring",
                 "bore_diameter", "outside_diameter", "width", "ball_material", "ball_thermal"):
        assert getattr(b, name) == getattr(PAPER_BEARING, name), name
    # derived through the closed forms from the 30° free angle (round-off of acos/cos: a few ulp)
    for name in ("radial_clearance", "guide_land_diameter", "shim_angle"):
        assert getattr(b, name) == pytest.approx(getattr(PAPER_BEARING, name), rel=1e-12), name
    assert b.cage.pocket_diameter == pytest.approx(PAPER_BEARING.cage.pocket_diameter, rel=1e-12)
    assert replace(b.cage, pocket_diameter=PAPER_BEARING.cage.pocket_diameter) == PAPER_BEARING.cage


def test_unknowns_that_no_bearing_has_are_infeasible_with_one_line():
    # a 15° free angle with 200 um clearance needs a shim angle whose cosine exceeds 1 (split ring)
    vs = SF.load_series(YANG)
    v = dict(VS.nominal_values(vs), free_contact_angle_deg=15.0, diametral_clearance=2e-4)
    with pytest.raises(InputError) as e:
        VS.series_bearing(vs, v)
    assert "bearing.shim_angle" in str(e.value) and "\n" not in str(e.value)
    # and a feasible sample: its free contact angle is the sampled one (clearance module closed forms)
    v = dict(VS.nominal_values(vs), free_contact_angle_deg=27.0, diametral_clearance=1e-4)
    b = VS.series_bearing(vs, v)
    assert math.degrees(b.free_contact_angle) == pytest.approx(27.0, rel=1e-10) and b.radial_clearance == 1e-4


def test_unknown_bearings_are_bearings_of_their_class():
    for vs in SF.load_all():
        b = VS.series_bearing(vs, VS.nominal_values(vs))
        assert b.bore_diameter < b.pitch_diameter < b.outside_diameter
        if vs.series.id == "nasa_tp1732":
            assert b.bore_diameter == 0.035 and math.degrees(b.free_contact_angle) == pytest.approx(24.0)
            assert b.inner_ring == "one_piece"


def test_steady_point_agrees_with_the_recorded_dynamics():
    # Table 5 case 1 at the preset: the steady fixed point against the dynamics' settled slip as recorded
    # (benchmarks/results/slip_rate_session14_ehl.json, -10.23 %); the uncertainty study measured this fast
    # path against the dynamics at rms 0.41 slip points over 20 pairs: 1 point is 2.5 times that
    vs = SF.load_series(YANG)
    job = VS.point_jobs(vs, 0)[0]
    assert (job.point_id, job.speed_rpm, job.axial_load, job.radial_load) == ("1", 4000.0, 1100.0, 200.0)
    row = VS.solve_point(job)
    assert row["converged"]
    assert row["slip_pct"] == pytest.approx(VS._dynamics_slips()["1"], abs=1.0)
    # the brackets are evaluated at the row's own operating angles, with the split of a running bearing
    br = K.brackets(4000.0, 0.022, 0.167, row["inner_contact_angle_deg"], row["outer_contact_angle_deg"])
    assert row["inner_control_slip_pct"] == br.inner_slip_percent > 0 > row["outer_control_slip_pct"]
    assert row["inner_contact_angle_deg"] > row["outer_contact_angle_deg"]


def test_rows_are_resumable_and_the_page_is_written(tmp_path):
    first = VS.run_series(tmp_path / "o", n_samples=0, series=["jlt1979_separator_forces"], workers=1,
                          progress=False)
    assert first["new_rows"] == 1 and len(first["rows"]) == 1 and not first["failures"]
    again = VS.run_series(tmp_path / "o", n_samples=0, series=["jlt1979_separator_forces"], workers=1,
                          progress=False)
    assert again["new_rows"] == 0 and len(again["rows"]) == 1
    a = VS.analyse(again["series"], again["rows"])
    page = VS.write_page(a, tmp_path / "validation.md", "flexbearing validate series --samples 0", 0)
    text = page.read_text()
    assert "`jlt1979_separator_forces`" in text and "cage_forces_tens_of_newtons" in text
    with pytest.raises(InputError) as e:
        VS.run_series(tmp_path / "o", n_samples=0, series=["no_such_series"], workers=1, progress=False)
    assert "no_such_series" in str(e.value) and "\n" not in str(e.value)
    with pytest.raises(InputError):
        VS.run_series(tmp_path / "o", n_samples=-1, workers=1, progress=False)


def _row(point, slip, fa, speed, purpose="point", **kw):
    return dict(series="yang2025_table5", point=str(point), sample=-1, purpose=purpose, speed_rpm=speed,
                axial_load=fa, radial_load=0.0, converged=True, slip_pct=slip, **kw)


def test_check_verdicts_follow_the_computed_values():
    vs = SF.load_series(YANG)
    # invented slips: positive, growing with speed, falling with load -> both Table 5 checks pass
    good = [_row(p.id, 1.0 + p.conditions["speed_rpm"].value / 1000.0 - p.conditions["axial_load"].value / 1000.0,
                 p.conditions["axial_load"].value, p.conditions["speed_rpm"].value) for p in vs.points]
    a = VS.analyse([vs], good)[0]
    assert [c["verdict"] for c in a["checks"]] == ["pass", "pass"]
    bad = [dict(r, slip_pct=-r["slip_pct"]) for r in good]
    a = VS.analyse([vs], bad)[0]
    assert [c["verdict"] for c in a["checks"]] == ["fail", "fail"]
    e = a["points"][0]
    m = vs.points[0].measured["measured_cage_slip_percent"].value
    assert e["slip_error_pct"] == pytest.approx(100 * abs(bad[0]["slip_pct"] - m) / m)


def test_a_hostile_series_file_stops_the_command_in_one_line(tmp_path, capsys):
    """`flexbearing validate series --directory D`: a series file with a value out of range, a wrong
    type or a missing field stops the command before any work, with one line naming the file, the
    field and the value, and exit code 2 (flexbearing.cli.main's InputError)."""
    from flexbearing.cli import main as cli
    good = SF.VALIDATION_DIR / "jlt1979_separator_forces.toml"
    text = good.read_text()
    cases = [("full_text_read = ", "full_text_read = 3 #", "series.full_text_read = 3: required: true or false"),
             ('id = "jlt1979_separator_forces"', 'id = "jlt1979"', "series.id = 'jlt1979': must equal the file name stem"),
             ("low = ", "low = -1e9 #", "low = -1e+09 is outside the allowed range")]
    for old, new, fragment in cases:
        assert old in text, old
        d = tmp_path / f"series_{len(list(tmp_path.iterdir()))}"
        d.mkdir()
        (d / good.name).write_text(text.replace(old, new, 1))
        code = cli.main(["validate", "series", "--directory", str(d), "--samples", "0", "--workers", "1", "--quiet",
                         "--out", str(d / "out"), "--page", str(d / "page.md")])
        err = capsys.readouterr().err
        lines = [ln for ln in err.strip().splitlines() if ln.strip()]
        assert code == 2 and len(lines) == 1 and "Traceback" not in err, err
        assert lines[0].startswith("flexbearing validate: invalid input: jlt1979_separator_forces.toml: ")
        assert fragment in lines[0], lines[0]
        assert not (d / "out" / "rows.jsonl").exists() and not (d / "page.md").exists()
