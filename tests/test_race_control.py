"""Race-control brackets of the cage speed and the published validation series (issue 35;
flexbearing.studies.validation: kinematics, series_file, brackets).

Plain numpy; the only project imports are the modules under test."""
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from flexbearing.common.validation import InputError
from flexbearing.studies.validation import brackets as bk, kinematics as rc, series_file as sf

ROOT = Path(__file__).resolve().parents[1]
SERIES_DIR = ROOT / "scenes" / "validation"
SERIES_FILES = sorted(SERIES_DIR.glob("*.toml"))


# --- an independent solution: rolling and no-spin conditions written as vectors ------------------

def vector_solution(speed_rpm, D, dm, ai_deg, ao_deg, control):
    """Cage speed from the contact conditions in the cage frame, solved as a 3x3 linear system.

    Ball centre at (dm/2, 0, 0); ball angular velocity W = (Wx, 0, Wz) relative to the cage;
    contact normals n_o = (cos ao, 0, sin ao) (outer), n_i = -(cos ai, 0, sin ai) (inner); in the
    cage frame the outer ring turns at -w_c, the inner ring at w_i - w_c about z. Rolling: the
    tangential (y) velocity of the ball surface equals the ring's at each contact centre. No spin
    at the controlling contact: (W - w_ring e_z) . n = 0."""
    ai, ao = math.radians(ai_deg), math.radians(ao_deg)
    rm, h, wi = dm / 2, D / 2, speed_rpm
    A = [[-h * math.sin(ao), h * math.cos(ao), rm + h * math.cos(ao)],
         [h * math.sin(ai), -h * math.cos(ai), rm - h * math.cos(ai)]]
    b = [0.0, wi * (rm - h * math.cos(ai))]
    if control == "outer":
        A.append([math.cos(ao), math.sin(ao), math.sin(ao)])
        b.append(0.0)
    else:
        A.append([-math.cos(ai), -math.sin(ai), -math.sin(ai)])
        b.append(-wi * math.sin(ai))
    wx, wz, wc = np.linalg.solve(np.array(A), np.array(b))
    return wc, wx, wz


# --- kinematics -----------------------------------------------------------------------------

@pytest.mark.parametrize("alpha", [0.0, 10.0, 15.0, 24.0, 30.0, 40.0, 60.0])
@pytest.mark.parametrize("beta_deg", [-30.0, 0.0, 12.0, 26.6, 45.0, 70.0])
def test_equal_angles_reduce_to_epicyclic_for_any_pitch_angle(alpha, beta_deg):
    """Analytically: with alpha_i = alpha_o = alpha, cos(alpha_i - beta) = cos(alpha_o - beta), so
    n_c/n_i = 1/(1 + (1 + g c)/(1 - g c)) = (1 - g c)/2 whatever beta: the epicyclic speed."""
    gamma = 22.0 / 167.0
    a = math.radians(alpha)
    try:
        ratio, _ = rc.cage_speed_ratio(gamma, a, a, math.radians(beta_deg))
    except InputError:  # beta leaves no rolling at a contact (|alpha - beta| >= 90 deg)
        assert abs(alpha - beta_deg) >= 90.0
        return
    assert ratio == pytest.approx(0.5 * (1 - gamma * math.cos(a)), rel=1e-14)


@pytest.mark.parametrize("D, dm, alpha, n", [(0.022, 0.167, 30.0, 12000.0), (0.0206, 0.150, 20.0, 25000.0),
                                              (0.0079, 0.0525, 24.0, 72000.0), (0.01, 0.2, 0.0, 1.0)])
def test_both_brackets_equal_the_epicyclic_speed_at_equal_angles(D, dm, alpha, n):
    br = rc.brackets(n, D, dm, alpha, alpha)
    nm = n / 2 * (1 - D * math.cos(math.radians(alpha)) / dm)
    assert br.epicyclic_rpm == pytest.approx(nm, rel=1e-15)
    assert br.inner.cage_speed_rpm == pytest.approx(nm, rel=1e-13)
    assert br.outer.cage_speed_rpm == pytest.approx(nm, rel=1e-13)
    assert br.inner_slip_percent == pytest.approx(0.0, abs=1e-11)
    assert br.outer_slip_percent == pytest.approx(0.0, abs=1e-11)


def test_outer_control_hand_computed_from_textbook_formulas():
    """Seed bearing geometry (D = 22 mm, d_m = 167 mm), alpha_i = 35 deg, alpha_o = 25 deg,
    n_i = 10,000 rpm; Harris & Kotzalas (5th ed., Vol. 2), outer-raceway control, long-hand:
        gamma = 22/167 = 0.1317365
        tan beta = sin 25 / (cos 25 + gamma) = 0.4226183 / 1.0380443 = 0.4071293 -> beta = 22.1527 deg
        cos(alpha_i - beta) = cos 12.8473 = 0.9749660,  cos(alpha_o - beta) = cos 2.8473 = 0.9987655
        (1 + gamma cos 25) = 1.1193938,  (1 - gamma cos 35) = 0.8920878
        n_c/n_i = 1/(1 + 1.1193938*0.9749660 / (0.8920878*0.9987655)) = 1/(1 + 1.2249019) = 0.4494580
    -> n_c = 4494.58 rpm (epicyclic at 30 deg: 4429.56 rpm; outer control runs 1.47 % fast)."""
    k = rc.race_control_kinematics(10000.0, 0.022, 0.167, 35.0, 25.0, "outer")
    assert k.pitch_angle_deg == pytest.approx(22.1527, abs=1e-4)
    assert k.cage_speed_rpm == pytest.approx(4494.580, abs=2e-3)
    assert k.cage_speed_rpm == pytest.approx(4494.5801591650525, rel=1e-12)  # vector solution below


def test_inner_control_hand_computed_from_textbook_formulas():
    """Same bearing and angles, inner-raceway control:
        tan beta = sin 35 / (cos 35 - gamma) = 0.5735764 / 0.6874155 = 0.8343955 -> beta = 39.8415 deg
        cos(alpha_i - beta) = cos(-4.8415) = 0.9964320,  cos(alpha_o - beta) = cos(-14.8415) = 0.9666382
        n_c/n_i = 1/(1 + 1.1193938*0.9964320 / (0.8920878*0.9666382)) = 1/(1 + 1.2934780) = 0.4360190
    -> n_c = 4360.19 rpm (1.57 % slower than the epicyclic 4429.56 rpm at 30 deg)."""
    k = rc.race_control_kinematics(10000.0, 0.022, 0.167, 35.0, 25.0, "inner")
    assert k.pitch_angle_deg == pytest.approx(39.8415, abs=1e-4)
    assert k.cage_speed_rpm == pytest.approx(4360.190, abs=2e-3)
    assert k.cage_speed_rpm == pytest.approx(4360.1901065249626, rel=1e-12)


@pytest.mark.parametrize("control", rc.CONTROLS)
def test_closed_form_matches_the_vector_contact_conditions(control):
    rng = np.random.default_rng(35)
    for _ in range(200):
        dm = rng.uniform(0.03, 0.3)
        D = rng.uniform(0.05, 0.25) * dm
        ai, ao = rng.uniform(5.0, 45.0, size=2)
        n = rng.uniform(100.0, 80000.0)
        k = rc.race_control_kinematics(n, D, dm, ai, ao, control)
        wc, wx, wz = vector_solution(n, D, dm, ai, ao, control)
        assert k.cage_speed_rpm == pytest.approx(wc, rel=1e-11)
        # same spin axis: W = |W| (sin beta, 0, -cos beta), beta measured from the -z direction
        assert math.degrees(math.atan2(wx, -wz)) == pytest.approx(k.pitch_angle_deg, abs=1e-8)
        assert k.ball_spin_ratio == pytest.approx(math.hypot(wx, wz) / n, rel=1e-10)


def test_the_two_forms_of_the_rolling_conditions_agree():
    """cage_speed_ratio (gamma form) and pure_rolling_cage_speed_ratio (contact radii form) are the
    same relation, n_c/n_i = q/(1 + q), q = (1 − g cos a_i) cos(a_o − b)/((1 + g cos a_o) cos(a_i − b)),
    rearranged: they agree to rounding (a few ulp of a ratio near 0.5: 1e-14) for any pitch angle;
    the radian race-control form is the degree one (1e-12: degrees <-> radians round trip)."""
    rng = np.random.default_rng(45)
    for _ in range(200):
        dm = rng.uniform(0.03, 0.3)
        D = rng.uniform(0.05, 0.25) * dm
        ai, ao = np.radians(rng.uniform(5.0, 45.0, size=2))
        beta = math.radians(rng.uniform(-10.0, 50.0))
        assert rc.cage_speed_ratio(D / dm, ai, ao, beta)[0] == pytest.approx(
            rc.pure_rolling_cage_speed_ratio(ao, ai, beta, D, dm), rel=1e-14)
        for control in rc.CONTROLS:
            ratio, b = rc.race_control_cage_speed_ratio(ao, ai, control, D, dm)
            k = rc.race_control_kinematics(1.0, D, dm, math.degrees(ai), math.degrees(ao), control)
            assert ratio == pytest.approx(k.cage_speed_rpm, rel=1e-12)
            assert math.degrees(b) == pytest.approx(k.pitch_angle_deg, abs=1e-10)


def test_no_spin_at_the_controlling_contact():
    n, D, dm, ai, ao = 10000.0, 0.022, 0.167, 33.0, 21.0
    for control in rc.CONTROLS:
        k = rc.race_control_kinematics(n, D, dm, ai, ao, control)
        b = math.radians(k.pitch_angle_deg)
        W = k.ball_spin_ratio * n * np.array([math.sin(b), 0.0, -math.cos(b)])  # relative to the cage
        a_i, a_o = math.radians(ai), math.radians(ao)
        n_o, n_i = np.array([math.cos(a_o), 0, math.sin(a_o)]), -np.array([math.cos(a_i), 0, math.sin(a_i)])
        spin_o = (W - np.array([0, 0, -k.cage_speed_rpm])) @ n_o
        spin_i = (W - np.array([0, 0, n - k.cage_speed_rpm])) @ n_i
        if control == "outer":
            assert spin_o == pytest.approx(0.0, abs=1e-9 * n)
            assert abs(spin_i) > 1e-3 * n
        else:
            assert spin_i == pytest.approx(0.0, abs=1e-9 * n)
            assert abs(spin_o) > 1e-3 * n


def test_bracket_signs_with_the_centrifugal_split():
    """alpha_i > alpha_o (centrifugal split): inner control lags the epicyclic speed at the mean
    angle (positive slip, the test's sign), outer control leads it (negative slip)."""
    br = rc.brackets(12000.0, 0.022, 0.167, 35.0, 25.0, reference_angle_deg=30.0)
    assert br.inner_slip_percent > 0 > br.outer_slip_percent
    assert br.inner.cage_speed_rpm < br.epicyclic_rpm < br.outer.cage_speed_rpm


def test_split_for_slip_round_trip():
    d = rc.split_for_slip(8000.0, 0.022, 0.167, 25.0, 3.0, "inner")
    br = rc.brackets(8000.0, 0.022, 0.167, 25.0 + d, 25.0 - d, reference_angle_deg=25.0)
    assert br.inner_slip_percent == pytest.approx(3.0, abs=1e-9)
    assert rc.split_for_slip(8000.0, 0.022, 0.167, 25.0, 3.0, "outer") is None


@pytest.mark.parametrize("kwargs, fragment", [
    (dict(ball_diameter=0.2, pitch_diameter=0.1), "need 0 < ball_diameter < pitch_diameter"),
    (dict(inner_contact_angle_deg=95.0), "inner_contact_angle_deg = 95.0: allowed range [0, 90) deg"),
])
def test_kinematics_rejects_bad_input(kwargs, fragment):
    args = dict(speed_rpm=1000.0, ball_diameter=0.02, pitch_diameter=0.15, inner_contact_angle_deg=20.0,
                outer_contact_angle_deg=20.0, control="inner")
    args.update(kwargs)
    with pytest.raises(InputError, match=None) as exc:
        rc.race_control_kinematics(**args)
    assert fragment in str(exc.value) and "\n" not in str(exc.value)


# --- the series files -------------------------------------------------------------------------

def test_there_are_series_files():
    ids = {p.stem for p in SERIES_FILES}
    assert {"yang2025_table5", "nasa_tnd7870", "nasa_tp1732"} <= ids


@pytest.mark.parametrize("path", SERIES_FILES, ids=lambda p: p.stem)
def test_every_series_loads_and_every_number_has_a_source(path):
    vs = sf.load_series(path)
    assert vs.series.id == path.stem
    assert vs.points
    n = 0
    for where, key, q in vs.all_quantities():
        n += 1
        assert isinstance(q, sf.Quantity)
        assert len(q.source.strip()) >= 8, (where, key)
        if q.digitised:
            assert q.uncertainty is not None, (where, key)
        lo, hi = q.span()
        assert lo <= hi
    assert n > 0
    for p in vs.points:
        for key, q in p.measured.items():
            assert q.source.strip(), (p.id, key)
        if p.status == "measured":
            assert p.measured
    for u in vs.unknowns:
        assert u.low < u.high and len(u.reason) >= 20
    for c in vs.checks:
        assert c.source.strip() and c.statement.strip()


@pytest.mark.parametrize("path", SERIES_FILES, ids=lambda p: p.stem)
def test_every_point_with_a_fixed_speed_gets_both_brackets(path):
    vs = sf.load_series(path)
    for p in vs.points:
        br = bk.point_brackets(vs, p)
        lo, hi = p.conditions["speed_rpm"].span()
        if lo != hi:
            assert br is None
            continue
        # at the free contact angle both brackets are the epicyclic speed
        assert br.inner_rpm == pytest.approx(br.epicyclic_rpm, rel=1e-12)
        assert br.outer_rpm == pytest.approx(br.epicyclic_rpm, rel=1e-12)
    assert "| point |" in bk.bracket_table(vs)


def test_yang_table5_matches_the_existing_case_file():
    """The transcription of Table 5 agrees with scenes/slip_rate_table4.toml (same paper)."""
    case_file = ROOT / "scenes" / "slip_rate_table4.toml"
    if not case_file.exists():
        pytest.skip("case file moved")
    cases = {str(c["id"]): c for c in tomllib.loads(case_file.read_text())["cases"]}
    vs = sf.load_series(SERIES_DIR / "yang2025_table5.toml")
    assert len(vs.points) == 15 == len(cases)
    for p in vs.points:
        c = cases[p.id]
        assert p.conditions["speed_rpm"].value == c["speed_rpm"]
        assert p.conditions["axial_load"].value == c["axial_load"]
        assert p.conditions["radial_load"].value == c["radial_load"]
        assert p.measured["measured_cage_slip_percent"].value == c["test_slip_percent"]
        assert p.reported_model["reported_model_cage_slip_percent"].value == c["paper_slip_percent"]


# --- validation errors: one line naming the field, the value and the allowed range ---------------

GOOD = """
[series]
id = "{stem}"
title = "t"
source = "A source, Table 1"
full_text_read = true
what_was_measured = "cage speed"
slip_definition = "S = (n_m - n_c)/n_m with n_m at the free angle"

[bearing]
bore = {{ value = 0.03, source = "A source, Table 1" }}
pitch_diameter = {{ value = 0.05, source = "A source, Table 1" }}
ball_diameter = {{ value = 0.008, source = "A source, Table 1" }}
free_contact_angle_deg = {{ value = 15.0, source = "A source, Table 1" }}

[[points]]
id = 1
speed_rpm = {{ value = 10000, source = "A source, Table 2" }}
measured_cage_slip_percent = {{ value = 2.0, source = "A source, Fig. 3", digitised = true, uncertainty = 0.2 }}
"""


def _write(tmp_path, text, stem="s"):
    p = tmp_path / f"{stem}.toml"
    p.write_text(text)
    return p


def test_minimal_file_loads(tmp_path):
    vs = sf.load_series(_write(tmp_path, GOOD.format(stem="s")))
    br = bk.point_brackets(vs, vs.points[0])
    assert br.geometry_known
    assert vs.points[0].measured["measured_cage_slip_percent"].digitised


@pytest.mark.parametrize("old, new, fragments", [
    ('ball_diameter = { value = 0.008', 'ball_diameter = { value = 5.0',
     ["bearing.ball_diameter.value = 5 is outside the allowed range [0.0001, 0.2]"]),
    ('bore = { value = 0.03, source = "A source, Table 1" }', 'bore = { value = 0.03 }',
     ["bearing.bore.source = None", "required"]),
    ('digitised = true, uncertainty = 0.2', 'digitised = true',
     ["measured_cage_slip_percent.uncertainty = None", "required when digitised"]),
    ('speed_rpm = { value = 10000', 'speed_rpm = { value = -5',
     ["points[1].speed_rpm.value = -5 is outside the allowed range [0, 300000]"]),
    ('free_contact_angle_deg = { value = 15.0, source = "A source, Table 1" }', '',
     ["bearing.free_contact_angle_deg = None", "[[unknowns]]"]),
    ('measured_cage_slip_percent', 'measured_cage_slipp',
     ["points[1]: unknown key 'measured_cage_slipp' (allowed: id, status, note, speed_rpm"]),
    ('slip_definition = "S = (n_m - n_c)/n_m with n_m at the free angle"', '',
     ["series.slip_definition", "required when a point gives measured_cage_slip_percent"]),
])
def test_bad_input_gives_one_clear_line(tmp_path, old, new, fragments):
    text = GOOD.format(stem="s")
    assert old in text
    path = _write(tmp_path, text.replace(old, new))
    with pytest.raises(InputError) as exc:
        sf.load_series(path)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("s.toml: ")
    for f in fragments:
        assert f in msg, msg


def test_unknown_range_and_id_checks(tmp_path):
    text = GOOD.format(stem="s").replace(
        'free_contact_angle_deg = { value = 15.0, source = "A source, Table 1" }', "")
    text += '\n[[unknowns]]\nname = "free_contact_angle_deg"\nlow = 30.0\nhigh = 20.0\nreason = "not given by the source, typical range"\n'
    with pytest.raises(InputError, match=r"unknowns\[0\]\.low = 30\.0: must be below high = 20\.0"):
        sf.load_series(_write(tmp_path, text))
    with pytest.raises(InputError, match=r"series\.id = 's': must equal the file name stem 'other'"):
        sf.load_series(_write(tmp_path, GOOD.format(stem="s"), stem="other"))


# hostile files (issue 45): a missing field, a wrong type, a value out of range, an unknown key;
# each refused in one InputError line that names the file and the field (and the value and the
# allowed range or values where there is one)
@pytest.mark.parametrize("old, new, fragments", [
    # missing fields
    ('title = "t"\n', '', ["s.toml: series.title = None: required"]),
    ('[series]\n', '[seriesx]\n', ["s.toml: top level: unknown key 'seriesx' (allowed: series, bearing"]),
    ('source = "A source, Table 1"\nfull', 'full', ["s.toml: series.source = None: required"]),
    ('speed_rpm = { value = 10000, source = "A source, Table 2" }\n', '',
     ["s.toml: points[1].speed_rpm = None: required"]),
    # wrong types
    ('full_text_read = true', 'full_text_read = "yes"', ["s.toml: series.full_text_read = 'yes': required: true or false"]),
    ('ball_diameter = { value = 0.008', 'ball_diameter = { value = "0.008"',
     ["s.toml: bearing.ball_diameter.value = '0.008': must be a number in [0.0001, 0.2]"]),
    ('ball_diameter = { value = 0.008', 'ball_diameter = { value = true',
     ["s.toml: bearing.ball_diameter.value = True: must be a number"]),
    ('bore = { value = 0.03, source = "A source, Table 1" }', 'bore = 0.03',
     ["s.toml: bearing.bore = 0.03: must be an inline table { value = ..."]),
    ('title = "t"', 'title = "t"\nnotes = 5', ["s.toml: series.notes = 5: must be a string"]),
    ('id = 1\n', 'id = 1.5\n', ["s.toml: points[0].id = 1.5: required: a string or an integer"]),
    ('digitised = true, uncertainty = 0.2', 'digitised = "yes", uncertainty = 0.2',
     ["measured_cage_slip_percent.digitised = 'yes': must be true or false"]),
    # out of range, not a finite number
    ('free_contact_angle_deg = { value = 15.0', 'free_contact_angle_deg = { value = 75.0',
     ["s.toml: bearing.free_contact_angle_deg.value = 75 is outside the allowed range [0, 60]"]),
    ('free_contact_angle_deg = { value = 15.0', 'free_contact_angle_deg = { value = nan',
     ["s.toml: bearing.free_contact_angle_deg.value = nan must be finite"]),
    ('speed_rpm = { value = 10000', 'speed_rpm = { value = inf', ["s.toml: points[1].speed_rpm.value = inf must be finite"]),
    ('ball_diameter = { value = 0.008', 'ball_diameter = { value = 0.06',
     ["s.toml: bearing.ball_diameter.value = 0.06: must be below pitch_diameter = 0.05"]),
    # unknown keys and values
    ('title = "t"', 'title = "t"\ntitel = "t"', ["s.toml: series: unknown key 'titel' (allowed: id, title"]),
    ('bore = { value = 0.03, source', 'bore = { value = 0.03, sourse = "x", source',
     ["s.toml: bearing.bore: unknown key 'sourse' (allowed: value, low, high, source"]),
    ('[bearing]\n', '[bearing]\ninner_ring = "three_piece"\ninner_ring_source = "A source, p. 2"\n',
     ["s.toml: bearing.inner_ring = 'three_piece': allowed values ('split', 'one_piece')"]),
])
def test_hostile_series_files_are_refused_naming_the_field(tmp_path, old, new, fragments):
    text = GOOD.format(stem="s")
    assert old in text, old
    path = _write(tmp_path, text.replace(old, new, 1))
    with pytest.raises(InputError) as exc:
        sf.load_series(path)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("s.toml: "), msg
    for f in fragments:
        assert f in msg, msg


def test_hostile_arrays_and_unreadable_files(tmp_path):
    """[[points]] / [[unknowns]] / [[checks]] that are not arrays of tables, a file that is not TOML,
    a folder that does not exist: one line each."""
    text = GOOD.format(stem="s")
    bad = 'points = 5\n' + text.split("[[points]]")[0]
    with pytest.raises(InputError, match=r"^s\.toml: points = 5: must be an array of tables \[\[points\]\]$"):
        sf.load_series(_write(tmp_path, bad))
    bad = text + '\n[[checks]]\nkind = "vibes"\nstatement = "x"\nsource = "A source, p. 3"\n'
    with pytest.raises(InputError, match=r"^s\.toml: checks\[0\]\.kind = 'vibes': allowed values \('sign'"):
        sf.load_series(_write(tmp_path, bad))
    bad = text + '\n[[unknowns]]\nname = "width"\nhigh = 0.02\nreason = "not given by the source, typical range"\n'
    with pytest.raises(InputError, match=r"^s\.toml: unknowns\[0\]\.low = None: must be a number in \[0\.001, 0\.5\]$"):
        sf.load_series(_write(tmp_path, bad))
    bad = 'bearing = 5\n' + text.split("[bearing]")[0] + "[[points]]" + text.split("[[points]]")[1]
    with pytest.raises(InputError, match=r"^s\.toml: bearing = 5 must be a table with keys bore, "):
        sf.load_series(_write(tmp_path, bad))
    with pytest.raises(InputError, match=r"^s\.toml: not valid TOML"):
        sf.load_series(_write(tmp_path, text + "\n[series\n"))
    with pytest.raises(InputError, match="series directory = .*: not a folder"):
        sf.load_all(tmp_path / "nowhere")
