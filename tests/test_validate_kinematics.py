"""flexbearing.studies.validation: the pure-rolling cage speed of the slip diagnosis (kinematics), the traction-law
plumbing and the settling test of the slip-rate validation (slip_rate).

* `pure_rolling_cage_speed_ratio` is checked against an independent vector computation: with the
  returned omega_c, the ball (spin axis at pitch angle beta, spin omega_R from the outer contact) has
  zero rolling-direction slip at BOTH contact points (race velocity − ball velocity computed from
  omega × r in the cage frame), to 1e-12 relative; and for equal contact angles it is nm/ni
  (paper §3.2) for every beta (algebraic identity, 1e-15).
* `traction_table_for`: "fit" is the paper's table; a scale k multiplies mu(s) by k exactly (A, B, D
  linear factors; 1e-12); an unknown law is an InputError naming the field.
* `cage_speed_settled` / `settled_cage_speed`: Aitken's delta-squared extrapolation of window means
  that approach their limit geometrically, m_k = L + c·q^k, returns L (to rounding: 1e-12 relative).
"""
import math

import numpy as np
import pytest

from flexbearing.studies.validation import kinematics as K, slip_rate as V
from flexbearing.common.validation import InputError
from flexbearing.multibody import traction as T

DW, DM = 0.022, 0.167


def _rolling_slips(alpha_o, alpha_i, beta, ratio, omega_i=1000.0):
    """Rolling-direction slip (race − ball surface speed along e_t) at the outer and inner contact
    points in the frame rotating with the cage, from the vectors themselves."""
    r = 0.5 * DW
    wc = ratio * omega_i
    # cage frame: x axial, y radial (ball centre at y = dm/2), t tangential; rotation about x
    centre = np.array([0.0, 0.5 * DM, 0.0])
    n_o = np.array([math.sin(alpha_o), math.cos(alpha_o), 0.0])     # towards the outer contact
    n_i = np.array([-math.sin(alpha_i), -math.cos(alpha_i), 0.0])   # towards the inner contact
    # beta > 0 turns the spin axis towards the normal of the contact line (perpendicular to n_o
    # for beta = alpha_o, to n_i for beta = alpha_i)
    axis = np.array([math.cos(beta), -math.sin(beta), 0.0])
    p_o, p_i = centre + r * n_o, centre + r * n_i
    # outer race (fixed) seen from the cage: omega = −wc about x
    v_race_o = np.cross([-wc, 0.0, 0.0], p_o)
    # choose omega_R so that the outer contact rolls: ball surface velocity = omega_R·axis × (r n_o)
    unit = np.cross(axis, r * n_o)
    omega_r = v_race_o[2] / unit[2]
    v_race_i = np.cross([omega_i - wc, 0.0, 0.0], p_i)
    v_ball_i = np.cross(omega_r * axis, r * n_i)
    return v_race_o[2] - omega_r * unit[2], (v_race_i[2] - v_ball_i[2]) / abs(v_race_i[2])


@pytest.mark.parametrize("ao,ai,beta", [(15.7, 38.0, 0.0), (15.7, 38.0, 38.0), (2.7, 41.5, 10.0), (30.0, 30.0, 5.0)])
def test_pure_rolling_ratio_has_no_slip_at_either_contact(ao, ai, beta):
    ao, ai, beta = (math.radians(v) for v in (ao, ai, beta))
    ratio = K.pure_rolling_cage_speed_ratio(ao, ai, beta, DW, DM)
    s_o, s_i = _rolling_slips(ao, ai, beta, ratio)
    assert abs(s_o) < 1e-9
    assert abs(s_i) < 1e-12


def test_pure_rolling_ratio_is_nominal_for_equal_angles():
    for alpha in (0.0, 0.3, 0.7):
        nm = 0.5 * (1.0 - DW * math.cos(alpha) / DM)
        for beta in (0.0, 0.2, alpha):
            assert K.pure_rolling_cage_speed_ratio(alpha, alpha, beta, DW, DM) == pytest.approx(nm, rel=1e-15)


def test_free_ball_with_unequal_angles_runs_above_nominal():
    """Test case 1 angles (outer 15.7°, inner 38.0°, quasi-static): a free ball (beta = 0) puts the
    cage 11.7 % above nm at the mean angle (benchmarks/results/slip_rate.md, kinematics table)."""
    ao, ai = math.radians(15.7), math.radians(38.0)
    nm = 0.5 * (1.0 - DW * math.cos(0.5 * (ao + ai)) / DM)
    slip = (nm - K.pure_rolling_cage_speed_ratio(ao, ai, 0.0, DW, DM)) / nm
    assert slip == pytest.approx(-0.1167, abs=5e-4)


def test_traction_tables():
    assert np.array_equal(V.traction_table_for("fit"), T.TRACTION_FIT_4106)
    assert V.traction_table_for("bounded").shape == (6, 4)
    k = 3.5
    tab1, tabk = V.traction_table_for("fit"), V.traction_table_for("fit", k)
    args = (150.0, 20.0, 0.0099, 2.308e11, 0.055, 393.15, 0.0965788)
    c1 = T.traction_coefficients_table(*args, tab1)
    ck = T.traction_coefficients_table(*args, tabk)
    for s in (0.001, 0.01, 0.1, 0.5):
        assert T.traction_coefficient(s, *ck) == pytest.approx(k * T.traction_coefficient(s, *c1), rel=1e-12)
    with pytest.raises(InputError, match="traction law"):
        V.traction_table_for("dry")


def test_cavity_oil_fraction_scaling():
    """X = X_ref·(4000/n) for "inverse_speed" (Parker's 1/n at constant oil supply; exact), X_ref for
    "constant"; an unknown scaling is an InputError naming the field."""
    assert V.case_oil_air_fraction(0.003, 4000, "inverse_speed") == pytest.approx(0.003, rel=1e-15)
    assert V.case_oil_air_fraction(0.003, 12000, "inverse_speed") == pytest.approx(0.001, rel=1e-15)
    assert V.case_oil_air_fraction(0.003, 12000, "constant") == 0.003
    with pytest.raises(InputError, match="oil_air_scaling"):
        V.case_oil_air_fraction(0.003, 4000, "parker2")


@pytest.mark.parametrize("race", ["outer", "inner"])
@pytest.mark.parametrize("ao,ai", [(15.7, 38.0), (30.0, 30.0), (4.9, 40.8), (21.5, 36.2)])
def test_race_control_kinematics_matches_jones_and_harris(race, ao, ai):
    """Jones's race control, in the closed forms of Harris & Kotzalas (Rolling Bearing Analysis,
    ball-spin/race-control section): tan beta = sin a_o/(cos a_o + D/dm) for outer-race control,
    tan beta = sin a_i/(cos a_i − D/dm) for inner-race control, whatever the other angle (1e-12).
    The cage speed is the pure-rolling one at that beta (1e-12), and the vector check of
    `_rolling_slips` finds no rolling slip at either contact (1e-9)."""
    ao, ai = math.radians(ao), math.radians(ai)
    ratio, beta = K.race_control_cage_speed_ratio(ao, ai, race, DW, DM)
    g = DW / DM
    expected = (math.atan(math.sin(ao) / (math.cos(ao) + g)) if race == "outer"
                else math.atan(math.sin(ai) / (math.cos(ai) - g)))
    assert beta == pytest.approx(expected, abs=1e-12)
    assert ratio == pytest.approx(K.pure_rolling_cage_speed_ratio(ao, ai, beta, DW, DM), rel=1e-12)
    s_o, s_i = _rolling_slips(ao, ai, beta, ratio)
    assert abs(s_o) < 1e-9 and abs(s_i) < 1e-9


def test_race_control_unknown_race_is_refused():
    with pytest.raises(InputError, match="control = 'cage': allowed values"):
        K.race_control_cage_speed_ratio(0.3, 0.5, "cage", DW, DM)


def test_slip_speed_decomposition_recovers_offset_and_skid():
    """benchmarks.slip_speed_decomposition: for slips built as S0 + k·(n/4000)^p at the test's speeds,
    the least-squares split returns S0 and k exactly (1e-10; the fit is linear in S0 and k) with a
    zero residual; with one slip raised by 0.1 the residual is nonzero and below 0.1."""
    from benchmarks.slip_speed_decomposition import split_offset_and_skid
    n = np.array([4000.0, 5000.0, 6000.0, 8000.0, 10000.0, 12000.0])
    for p in (1.0, 2.0, 2.6):
        s = 4.3 + 0.9 * (n / 4000.0) ** p
        s0, k, rms = split_offset_and_skid(n, s, p)
        assert abs(s0 - 4.3) < 1e-10 and abs(k - 0.9) < 1e-10 and rms < 1e-10
        s[2] += 0.1
        assert 0.0 < split_offset_and_skid(n, s, p)[2] < 0.1


@pytest.mark.parametrize("limit, c, q", [(1000.0, -50.0, 0.5), (420.0, 3.0, 0.8), (-300.0, 10.0, 0.1), (250.0, 4.0, 0.3)])
def test_settled_cage_speed_is_the_limit_of_geometric_window_means(limit, c, q):
    """Window means m_k = L + c·q^k (an exponential approach sampled once per window): Aitken's
    extrapolation m_n + d1·q/(1 − q) is L exactly in exact arithmetic; in floating point the
    cancellation in d1 = m_n − m_(n−1) costs ~|m|/|d1| ulps, far below 1e-12 relative here."""
    means = [limit + c * q ** k for k in range(6)]
    assert V.settled_cage_speed(means) == pytest.approx(limit, rel=1e-12)
    # the change still to come after the last mean m_5 is L − m_5 = −c·q^5: settled when it is below
    # settle_rel·|m_5|, not when it is above (for q <= 0.5 the last two differences, c·q^4(1 − q) and
    # c·q^3(1 − q), exceed it, so the differences test alone cannot decide it)
    rest = abs(c * q ** 5) / abs(means[-1])
    assert V.cage_speed_settled(means, 2.0 * rest)
    if q <= 0.5:
        assert not V.cage_speed_settled(means, 0.5 * rest)


def test_settling_needs_three_windows_and_refuses_oscillation():
    assert not V.cage_speed_settled([100.0, 100.0], 1e-3)
    assert V.cage_speed_settled([100.0, 100.0, 100.0], 1e-3)          # flat: both differences zero
    assert not V.cage_speed_settled([100.0, 101.0, 100.0], 1e-3)      # q = −1: not a geometric approach
    assert V.settled_cage_speed([100.0, 101.0, 100.0]) == 100.0       # no extrapolation then
