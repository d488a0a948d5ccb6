"""Split-inner-ring contact geometry and contact kinematics (flexbearing/multibody/geometry.py, SPEC §2).

Expected values are hand-derived closed forms (stated in each test), not outputs of the code.
"""
import math

import numpy as np
import pytest

from flexbearing.multibody.bearing import PAPER_BEARING
from flexbearing.multibody import geometry as g

B = PAPER_BEARING
DM, DW, FE, FI, AD = B.pitch_diameter, B.ball_diameter, B.fe, B.fi, B.shim_angle


def centres(pd=0.0):
    xo, ro = g.outer_groove_centre(DM, DW, FE)
    xl, rl, xr, rr = g.inner_groove_centres(DM, DW, FI, AD, pd)
    return (xo, ro), (xl, rl), (xr, rr)


def test_nominal_ball_touches_all_three_races_at_zero_load():
    # SPEC §2 with Pd = 0: ball at (0, dm/2) is at distance (f - 0.5)Dw from each centre.
    (xo, ro), (xl, rl), (xr, rr) = centres()
    for (xc, rc), f, alpha in (((xo, ro), FE, 0.0), ((xl, rl), FI, AD), ((xr, rr), FI, -AD)):
        d, ca, sa = g.race_contact(0.0, 0.5 * DM, xc, rc, f, DW)
        assert abs(d) < 1e-15                     # round-off of an 8e-2 m coordinate
        assert math.atan2(sa, ca) == pytest.approx(alpha, abs=1e-12)


def seated_against_outer_and_left(pd):
    """Inner ring shifted +x until |Co - Ci_left| = B*Dw (axial play taken up), ball on the line of centres."""
    (xo, ro), (xl, rl), (xr, rr) = centres(pd)
    A = (FI + FE - 1.0) * DW
    x_ring = math.sqrt(A * A - (rl - ro) ** 2) - xl
    xl2, rl2 = g.ring_point_in_plane(0.7, xl, rl, x_ring, 0.0, 0.0, 0.0, 0.0)
    xr2, rr2 = g.ring_point_in_plane(0.7, xr, rr, x_ring, 0.0, 0.0, 0.0, 0.0)
    xb = xo + (FE - 0.5) * DW * (xl2 - xo) / A
    rb = ro + (FE - 0.5) * DW * (rl2 - ro) / A
    return (xb, rb), (xo, ro), (xl2, rl2), (xr2, rr2)


# Critical clearance: alpha0 = alphaD  <=>  Dr = B Dw cos(alphaD)  <=>  Pd = 2 (fe - 0.5) Dw (1 - cos alphaD).
PD_CRIT = 2.0 * (FE - 0.5) * DW * (1.0 - math.cos(AD))      # 88.4 um for the paper bearing


@pytest.mark.parametrize("pd", [0.0, 20e-6, PD_CRIT, 150e-6])
def test_free_contact_angle_when_seated_against_outer_and_left_half(pd):
    # The ball on the line of centres touches outer and left half with delta = 0 and the contact angle
    # alpha0 = acos(Dr/(B Dw)) (SPEC §2), Dr = (fi-0.5)Dw cos(alphaD) + (fe-0.5)Dw - Pd/2.
    bear = B.with_(radial_clearance=pd)
    (xb, rb), (xo, ro), (xl, rl), _ = seated_against_outer_and_left(pd)
    do, cao, sao = g.race_contact(xb, rb, xo, ro, FE, DW)
    di, cai, sai = g.race_contact(xb, rb, xl, rl, FI, DW)
    alpha0 = bear.free_contact_angle
    assert abs(do) < 1e-14 and abs(di) < 1e-14
    assert math.atan2(sao, cao) == pytest.approx(alpha0, rel=1e-12)
    assert math.atan2(sai, cai) == pytest.approx(alpha0, rel=1e-12)
    # +X shift of the inner ring loads the left half (x < 0 side of the ball): its contact is at x < xb
    nx, nr = g.contact_normal(xb, rb, xl, rl)
    assert nx < 0 and nr < 0


def test_right_half_clears_only_above_the_critical_clearance():
    # At Pd = PD_CRIT the seated ball lies on the line Co-Cl at alphaD, and b - Cr = (fi-0.5)Dw (sin aD, -cos aD)
    # exactly, so the right half just touches (delta_r = 0) and alpha0 = alphaD. Below it (the paper preset's
    # assumed Pd = 0 included) the seated position would overlap the right half: the ball cannot seat on two
    # races only, it stays held by all three (a true three-point contact). Above it the right half lifts off.
    assert B.with_(radial_clearance=PD_CRIT).free_contact_angle == pytest.approx(AD, rel=1e-12)
    for pd, sign in ((0.0, +1), (40e-6, +1), (PD_CRIT, 0), (120e-6, -1), (200e-6, -1)):
        (xb, rb), _, _, (xr, rr) = seated_against_outer_and_left(pd)
        d = g.race_contact(xb, rb, xr, rr, FI, DW)[0]
        if sign == 0:
            assert abs(d) < 1e-14
        else:
            assert d * sign > 1e-6


def test_pure_axial_displacement_equal_at_all_azimuths():
    (xo, ro), (xl, rl), (xr, rr) = centres()
    vals = []
    for psi in np.linspace(0, 2 * math.pi, 13):
        xc, rc = g.ring_point_in_plane(psi, xl, rl, 30e-6, 0.0, 0.0, 0.0, 0.0)
        vals.append(g.race_contact(0.0, 0.5 * DM, xc, rc, FI, DW)[0])
    vals = np.array(vals)
    assert np.ptp(vals) < 1e-18
    # exact: the left centre moves to (xl + u, rl); delta = |b - c| - (fi - 0.5) Dw
    assert vals[0] == pytest.approx(math.hypot(xl + 30e-6, rl - 0.5 * DM) - (FI - 0.5) * DW, rel=1e-9)


@pytest.mark.parametrize("which", ["left", "right"])
def test_pure_radial_displacement_gives_cos_psi_pattern(which):
    # delta(psi) = -n . dc = y cos(psi) cos(alphaD) to first order (y = 1 um => error O(y^2/A) ~ 3e-3 y)
    (xo, ro), (xl, rl), (xr, rr) = centres()
    x0, r0 = (xl, rl) if which == "left" else (xr, rr)
    y = 1e-6
    for psi in np.linspace(0, 2 * math.pi, 9):
        xc, rc = g.ring_point_in_plane(psi, x0, r0, 0.0, y, 0.0, 0.0, 0.0)
        d = g.race_contact(0.0, 0.5 * DM, xc, rc, FI, DW)[0]
        assert d == pytest.approx(y * math.cos(psi) * math.cos(AD), abs=5e-3 * y)
        # z displacement gives the sin pattern
        xc, rc = g.ring_point_in_plane(psi, x0, r0, 0.0, 0.0, y, 0.0, 0.0)
        d = g.race_contact(0.0, 0.5 * DM, xc, rc, FI, DW)[0]
        assert d == pytest.approx(y * math.sin(psi) * math.cos(AD), abs=5e-3 * y)


def test_tilt_pattern():
    # Tilt theta_z about Z: theta_psi = -theta_z cos(psi); the left centre moves by
    # dx = r0 theta_psi, dr = -x0 theta_psi; delta = -n.dc with n = -(sin aD, cos aD):
    # delta = theta_psi (r0 sin aD - x0 cos aD). Tilt about Y gives the same with sin(psi).
    (xo, ro), (xl, rl), (xr, rr) = centres()
    th = 2e-5
    amp = rl * math.sin(AD) - xl * math.cos(AD)
    for psi in np.linspace(0, 2 * math.pi, 9):
        xc, rc = g.ring_point_in_plane(psi, xl, rl, 0.0, 0.0, 0.0, 0.0, th)
        d = g.race_contact(0.0, 0.5 * DM, xc, rc, FI, DW)[0]
        assert d == pytest.approx(-th * math.cos(psi) * amp, abs=2e-2 * th * amp)
        xc, rc = g.ring_point_in_plane(psi, xl, rl, 0.0, 0.0, 0.0, th, 0.0)
        d = g.race_contact(0.0, 0.5 * DM, xc, rc, FI, DW)[0]
        assert d == pytest.approx(th * math.sin(psi) * amp, abs=2e-2 * th * amp)


def test_left_right_mirror_symmetry():
    # Mirror x -> -x: left and right halves swap, contact angles change sign, deltas equal.
    (xo, ro), (xl, rl), (xr, rr) = centres()
    rng = np.random.default_rng(1)
    for _ in range(20):
        xb, rb = rng.normal(0, 20e-6), 0.5 * DM + rng.normal(0, 20e-6)
        xi = rng.normal(0, 20e-6)
        xl1, rl1 = g.ring_point_in_plane(0.3, xl, rl, xi, 0, 0, 0, 0)
        xr1, rr1 = g.ring_point_in_plane(0.3, xr, rr, -xi, 0, 0, 0, 0)
        dl, cl, sl = g.race_contact(xb, rb, xl1, rl1, FI, DW)
        dr, cr, sr = g.race_contact(-xb, rb, xr1, rr1, FI, DW)
        assert dl == pytest.approx(dr, abs=1e-15) and cl == pytest.approx(cr, abs=1e-14)
        assert sl == pytest.approx(-sr, abs=1e-14)
        do1, co1, so1 = g.race_contact(xb, rb, xo, ro, FE, DW)
        do2, co2, so2 = g.race_contact(-xb, rb, xo, ro, FE, DW)
        assert do1 == pytest.approx(do2, abs=1e-15) and so1 == pytest.approx(-so2, abs=1e-14)


def test_contact_angle_sign_and_force_direction():
    # Ball pushed +x and outward: outer contact angle > 0, inner-left > 0, the outer race force -Q n
    # points inward and toward -x, the inner-left race force points outward and toward +x.
    (xo, ro), (xl, rl), _ = centres()
    xb, rb = 5e-6, 0.5 * DM + 3e-6
    _, ca, sa = g.race_contact(xb, rb, xo, ro, FE, DW)
    nx, nr = g.contact_normal(xb, rb, xo, ro)
    assert sa > 0 and (nx, nr) == pytest.approx((sa, ca))
    _, ca, sa = g.race_contact(xb, rb, xl, rl, FI, DW)
    nx, nr = g.contact_normal(xb, rb, xl, rl)
    assert sa > 0 and (nx, nr) == pytest.approx((-sa, -ca))


def test_contact_point_on_ball_and_race():
    (xo, ro), _, _ = centres()
    xb, rb = 0.0, 0.5 * DM + 10e-6                  # outer approach 10 um
    d, ca, sa = g.race_contact(xb, rb, xo, ro, FE, DW)
    nx, nr = g.contact_normal(xb, rb, xo, ro)
    xp, rp, rho = g.contact_point(xb, rb, nx, nr, d, DW)
    assert d == pytest.approx(10e-6, rel=1e-9)
    assert rho == pytest.approx(0.5 * DW - 5e-6)
    # the point is midway between the deformed-ball surface and the race bottom dm/2 + Dw/2
    assert rp == pytest.approx(0.5 * DM + 0.5 * DW + 5e-6, rel=1e-12)


@pytest.mark.parametrize("alpha_deg", [0.0, 25.0, 40.0])
def test_pure_rolling_kinematics(alpha_deg):
    # Outer ring fixed, inner ring at omega_i, both contacts on one line at angle alpha through the ball
    # centre (Harris & Kotzalas Vol. 1, ch. 8): cage speed omega_m = omega_i (1 - gamma)/2 (SPEC §6),
    # ball speed about its rolling axis tau = (cos a, -sin a) omega_R = -(dm/2Dw)(1 - gamma^2) omega_i in
    # the cage frame, entrainment speed U = dm omega_i (1 - gamma^2)/4 at both contacts, zero slide at
    # both contact centres, whatever spin about the contact line is added.
    a = math.radians(alpha_deg)
    wi = 1466.0
    gam = DW * math.cos(a) / DM
    wm = 0.5 * wi * (1 - gam)
    assert g.pitch_orbit_speed(wi, 0.0, DW, DM, a) == pytest.approx(wm, rel=1e-15)
    wR = -(DM / (2 * DW)) * (1 - gam * gam) * wi
    n = np.array([math.sin(a), math.cos(a)])          # ball centre -> outer contact
    tau = np.array([math.cos(a), -math.sin(a)])
    rb = 0.5 * DM
    U_expect = DM * wi * (1 - gam * gam) / 4
    for spin_about_n in (0.0, 300.0):
        w_rel = wR * tau + spin_about_n * n
        wbx, wbr = w_rel[0] + wm, w_rel[1]            # absolute = relative + orbital about e_x
        for sign, ring_speed in ((+1, 0.0), (-1, wi)):  # outer (+n), inner (-n)
            nx, nr = sign * n
            xp, rp, rho = g.contact_point(0.0, rb, nx, nr, 0.0, DW)
            vb = g.ball_surface_velocity(rho, nx, nr, 0.0, 0.0, rb * wm, wbx, wbr, 0.0)
            vr = g.ring_surface_velocity(0.4, rp, ring_speed, 0.0, 0.0, 0.0, 0.0, 0.0)
            U, ub, ur, s_roll, s_tr, appr, spin = g.contact_kinematics(
                nx, nr, rp, wm, *vb, *vr, wbx, wbr, 0.0, ring_speed)
            scale = U_expect
            assert abs(s_roll) < 1e-12 * scale and abs(s_tr) < 1e-12 * scale and abs(appr) < 1e-12 * scale
            # relative to the contact the outer race runs backwards (-e_t), the inner race forwards
            assert U == pytest.approx(-sign * U_expect, rel=1e-12)
            assert ub == pytest.approx(ur, rel=1e-12)
            # spin relative to the race about n: (omega_b - omega_ring e_x).n
            assert spin == pytest.approx(sign * spin_about_n + (wm - ring_speed) * nx, abs=1e-9)


def test_slide_and_approach_rate_components():
    # A ball centre moving with (vx, vr) and no rotation on a fixed race: slide = v resolved on
    # e_t, tau = (cos a, -sin a), approach rate = v.n (hand projection).
    a = math.radians(30)
    nx, nr = math.sin(a), math.cos(a)
    vx, vr, vt = 0.3, -0.2, 0.05
    vb = g.ball_surface_velocity(0.011, nx, nr, vx, vr, vt, 0.0, 0.0, 0.0)
    vr_ = g.ring_surface_velocity(0.0, 0.09, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    U, ub, ur, s_roll, s_tr, appr, spin = g.contact_kinematics(nx, nr, 0.09, 0.0, *vb, *vr_, 0, 0, 0, 0.0)
    assert s_roll == pytest.approx(vt)
    assert s_tr == pytest.approx(vx * math.cos(a) - vr * math.sin(a))
    assert appr == pytest.approx(vx * nx + vr * nr)


def test_ring_surface_velocity_with_offset_centre():
    # v = omega e_x x (p - c): the point at psi = 0, radius r_p, ring centre offset y: speed omega (r_p - y)
    v = g.ring_surface_velocity(0.0, 0.08, 1000.0, 1e-4, 0.0, 0.0, 2.0, 3.0)
    assert v == pytest.approx((0.0, 2.0, 1000.0 * (0.08 - 1e-4) + 3.0))
