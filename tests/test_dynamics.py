"""Equations of motion and force assembly of flexbearing.multibody.dynamics against closed forms.

Each test sets up a state where one term acts alone and compares dy/dt with its analytic value.
"""
import math

import numpy as np
import pytest
from tolerances import U, assert_within, gamma

from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody import model as M
from flexbearing.multibody.model import build_model, state_layout
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import outputs as O
from flexbearing.multibody.hertz import hertz_exact, race_curvature_radii, effective_modulus
from flexbearing.multibody.initial import initial_state

OFF = {"traction": False, "drag": False, "damping": False}
SP = np.array([[0.0, 0.0]])
LD = np.array([[0.0, 0.0, 0.0, 0.0]])
IMP = np.zeros((0, 6))


def _rhs(model, y, t=0.0, sp=SP, ld=LD):
    dy = np.zeros_like(y)
    work = D.new_work(model)
    D.rhs(t, y, dy, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld, IMP, work, model.cage)
    return dy, work


@pytest.fixture(scope="module")
def clear_model():
    # 100 um radial clearance: a ball slightly inside the pitch circle touches no race
    return build_model(PAPER_BEARING.with_(radial_clearance=100e-6), PAPER_OIL, OFF)


def _free_state(model, r_off=-5e-6):
    lay = state_layout(model)
    y = np.zeros(lay["n_state"])
    z = model.n_balls
    dm = model.p[M.P_DM]
    for j in range(z):
        y[9 * j:9 * j + 3] = (0.0, 0.5 * dm + r_off, 2 * math.pi * j / z)
    return y


def test_state_layout_sizes(clear_model):
    lay = state_layout(clear_model)
    assert lay["ring"] == 9 * 20 and lay["cage"] == lay["ring"] + 11
    assert lay["n_state"] == clear_model.n_state == 9 * 20 + 23
    assert len(lay["ball_fields"]) == 9 and len(lay["cage_fields"]) == 12


def test_free_ball_centrifugal_coriolis_gyroscopic(clear_model):
    """A ball touching nothing (pocket centred on it): dy/dt = the kinematic terms alone.

    r'' = r·psi'², psi'' = −2·r'·psi'/r, w_r' = psi'·w_t, w_t' = −psi'·w_r, w_x' = 0 (model docstring).
    The cage rotates with the ball so the pocket stays centred.
    """
    m = clear_model
    y = _free_state(m)
    j = 3
    o = 9 * j
    psid, rdot = 300.0, 0.02
    y[o + 4], y[o + 5] = rdot, psid
    y[o + 6:o + 9] = (50.0, 800.0, -120.0)
    dy, work = _rhs(m, y)
    assert np.all(work[j, [0, M.N_WC, 2 * M.N_WC]] == 0.0), "no race contact expected"
    assert work[j, M.W_POCKET_Q] == pytest.approx(0.0, abs=1e-12)
    r = y[o + 1]
    assert dy[o + 4] == pytest.approx(r * psid ** 2, rel=1e-12)
    assert dy[o + 5] == pytest.approx(-2.0 * rdot * psid / r, rel=1e-12)
    assert dy[o + 6] == pytest.approx(0.0, abs=1e-9)
    assert dy[o + 7] == pytest.approx(psid * (-120.0), rel=1e-12)
    assert dy[o + 8] == pytest.approx(-psid * 800.0, rel=1e-12)
    # the inertial angular velocity is constant: d/dt of its Y component = 0
    psi = y[o + 2]
    wy_dot = (dy[o + 7] * math.cos(psi) - dy[o + 8] * math.sin(psi)
              - psid * (y[o + 7] * math.sin(psi) + y[o + 8] * math.cos(psi)))
    assert wy_dot == pytest.approx(0.0, abs=1e-9)


def test_outer_race_hertz_load_matches_exact_solution(clear_model):
    """Ball pushed radially into the outer race (alpha = 0): m·r'' = −Q, Q from the exact Hertz
    solution (scipy elliptic integrals) at the same approach; tolerance 1e-4 (table interpolation
    in cos alpha and the A&S elliptic integrals are ~1e-6)."""
    m = clear_model
    y = _free_state(m)
    j = 0
    delta = 12e-6
    r_o = m.p[M.P_RO]
    y[1] = r_o + (m.p[M.P_FE] - 0.5) * m.p[M.P_DW] + delta
    # move the pocket with the ball (pocket axis is radial: a radial shift leaves Z = 0)
    dy, work = _rhs(m, y)
    rx, ry = race_curvature_radii(0.022, 0.167, 0.515, 0.0, False)
    e = effective_modulus(210e9, 0.3, 210e9, 0.3)
    ref = hertz_exact(rx, ry, e, 1000.0)
    q_ref = ref["stiffness"] * delta ** 1.5
    assert work[j, M.WC_Q] == pytest.approx(q_ref, rel=1e-4)
    assert m.p[M.P_MB] * dy[4] == pytest.approx(-q_ref + m.p[M.P_MB] * y[1] * 0.0, rel=1e-4)
    # contact stress p0 = 3Q/(2 pi a b) of the exact solution at that load
    ref_q = hertz_exact(rx, ry, e, q_ref)
    assert work[j, M.WC_P0] == pytest.approx(ref_q["p0"], rel=1e-4)


def test_guide_land_short_bearing_forces_match_formulas():
    """Ocvirk forces and Petroff torque (formulas.md) at whirl = squeeze = 0, eps = 0.5."""
    model = build_model(PAPER_BEARING, PAPER_OIL)
    p = model.p
    cg, r1, eta = p[M.P_CG], p[M.P_R1], p[M.P_ETA0]
    cage = PAPER_BEARING.cage
    # two guide lands of width w beside the relief (or one land over the full width)
    n, L = (2, cage.land_width) if cage.relief_depth > 0 else (1, cage.width)
    eps, om = 0.5, 600.0
    fy, fz, mx, e_out, frim, fx = D._guide_land(eps * cg, 0.0, 0.0, 0.0, om, p, model.flags)
    U = r1 * om
    wr = n * eta * U * L ** 3 * eps ** 2 / (cg ** 2 * (1 - eps ** 2) ** 2)
    wt = n * math.pi * eta * U * L ** 3 * eps / (4 * cg ** 2 * (1 - eps ** 2) ** 1.5)
    assert fy == pytest.approx(-wr, rel=1e-12)       # towards the centre
    assert fz == pytest.approx(wt, rel=1e-12)        # 90° ahead in the sense of rotation
    m_ref = -2 * math.pi * eta * om * r1 ** 3 * n * L / (cg * math.sqrt(1 - eps ** 2))
    assert mx == pytest.approx(m_ref, rel=1e-12)
    assert e_out == pytest.approx(eps) and frim == 0.0 and fx == 0.0      # the outer land is not tilted
    # a whirl at half the spin speed cancels the wedge effect: w = omega − 2·whirl = 0
    e = eps * cg
    fy2, fz2, _, _, _, _ = D._guide_land(e, 0.0, 0.0, e * 0.5 * om, om, p, model.flags)
    assert abs(fy2) < 1e-9 * wr and abs(fz2) < 1e-9 * wt


def test_pocket_force_linear_then_hertz():
    """Paper §2.3.1: Q = Kc·Z up to Cp (Kc = 11/Cp), Kc·Cp + Kn·(Z − Cp)^1.5 beyond."""
    model = build_model(PAPER_BEARING, PAPER_OIL, OFF)
    p = model.p
    cp = p[M.P_CP]
    assert p[M.P_KC] * cp == pytest.approx(11.0)
    for zz, ref in ((0.5 * cp, 5.5), (cp + 2e-6, 11.0 + p[M.P_KN] * (2e-6) ** 1.5)):
        # pocket at (0, R, 0) with radial axis +Y, ball offset along +Z (circumferential)
        out = D._pocket_interface(0.0, 0.0835, zz, 0, 0, 0, 0, 0, 0, 0.0, 0.0835, 0.0, 0.0, 1.0, 0.0,
                                  0, 0, 0, 0, 0, 0, 0, 0, 0, p, model.flags)
        assert out[9] == pytest.approx(ref, rel=1e-12)
        assert out[2] == pytest.approx(-ref, rel=1e-12) and out[0] == 0.0 and out[1] == 0.0


def test_cage_tilt_gyroscopic_coupling():
    """I_d·beta_y'' = −I_p·Omega·beta_z', I_d·beta_z'' = +I_p·Omega·beta_y' for the free cage."""
    m = build_model(PAPER_BEARING.with_(radial_clearance=100e-6), PAPER_OIL, OFF)
    y = _free_state(m)
    c0 = state_layout(m)["cage"]
    y[c0 + 9] = 500.0
    y[c0 + 10], y[c0 + 11] = 0.3, -0.2
    dy, _ = _rhs(m, y)
    ip, idm = m.p[M.P_ICP], m.p[M.P_ICD]
    assert dy[c0 + 10] == pytest.approx(-ip * 500.0 * (-0.2) / idm, rel=1e-9)
    assert dy[c0 + 11] == pytest.approx(ip * 500.0 * 0.3 / idm, rel=1e-9)


def test_cage_mass_properties_against_annulus():
    """Without pockets the quadrature must give the annulus: m = rho·pi·(Ro² − Ri²)·w,
    I_p = m(Ro² + Ri²)/2 (1e-3: midpoint rule in r); the pockets remove a plausible 40–60 %."""
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    tiny = PAPER_CAGE.with_(pocket_diameter=1e-9)
    m, ip, idm = M.cage_mass_properties(tiny)
    ro, ri, w = PAPER_CAGE.outer_radius, PAPER_CAGE.inner_radius, PAPER_CAGE.width
    m_ref = 7870 * math.pi * (ro ** 2 - ri ** 2) * w
    assert m == pytest.approx(m_ref, rel=1e-3)
    assert ip == pytest.approx(0.5 * m_ref * (ro ** 2 + ri ** 2), rel=1e-3)
    assert idm == pytest.approx(m_ref * ((ro ** 2 + ri ** 2) / 4 + w ** 2 / 12), rel=2e-3)
    mp, _, _ = M.cage_mass_properties(PAPER_CAGE)
    assert 0.4 < mp / m_ref < 0.6


def test_quasi_static_state_is_an_equilibrium_of_the_rhs():
    """At the quasi-static initial state (friction and drag off) the ball and ring accelerations
    vanish: the RHS force assembly agrees with the independent quasi-static assembly.
    Tolerance: ring force residual < 1e-4 of the axial load; the unbalanced in-plane force on
    each ball at most the pocket force + 1e-4 of its centrifugal force: the quasi-static model has
    no pocket, and the dynamics' linear pocket spring Kc·Z (44 N/mm) sees the few-micrometre
    axial spread of the balls under the radial load (< 1 N on a 770 N centrifugal force)."""
    m = build_model(PAPER_BEARING, PAPER_OIL, OFF)
    w = 10000 * math.pi / 30
    y = initial_state(m, w, 20e3, 3e3)
    sp = np.array([[0.0, w]])
    ld = np.array([[0.0, 20e3, 0.0, -3e3]])
    dy, work = _rhs(m, y, sp=sp, ld=ld)
    r0 = state_layout(m)["ring"]
    assert np.max(np.abs(dy[r0 + 5:r0 + 8])) * m.p[M.P_MI] < 1e-4 * 20e3
    acc_c = 0.5 * m.p[M.P_DM] * y[5] ** 2
    for j in range(m.n_balls):
        # everything but the pocket spring balances: |m·a| <= Q_pocket + 1e-4·m·a_centrifugal
        slack = work[j, M.W_POCKET_Q] + 1e-4 * m.p[M.P_MB] * acc_c
        assert m.p[M.P_MB] * math.hypot(dy[9 * j + 3], dy[9 * j + 4]) <= slack
        assert work[j, M.W_POCKET_Q] < 1.0


def test_evaluate_outputs_keys_and_slip_definition():
    m = build_model(PAPER_BEARING, PAPER_OIL)
    w = 6000 * math.pi / 30
    y = initial_state(m, w, 1500.0, 500.0)
    sp = np.array([[0.0, w]])
    ld = np.array([[0.0, 1500.0, 0.0, -500.0]])
    out = O.evaluate_outputs(m, 0.0, y, sp, ld, IMP, film=True)
    for k in ("contact_load", "contact_angle", "contact_stress", "pocket_force", "cage_land_force",
              "cage_speed", "slip_rate", "film_thickness_min", "film_thickness_central",
              "ball_position", "inner_ring_displacement", "cage_centre"):
        assert k in out
    assert out["contact_load"].shape == (20, 3)
    alpha = 0.5 * (np.mean(out["contact_angle_outer"]) + np.mean(np.abs(out["contact_angle_inner_loaded"])))
    nm = 0.5 * w * (1 - 0.022 * math.cos(alpha) / 0.167)
    # slip = 1 - cage/nm: nm from the contact angles' means (20-term sums) and a libm cosine in
    # the outputs and here, <= 30 roundings each: absolute 2 gamma_30 |cage/nm| + u (Higham §3.1)
    ref = (nm - out["cage_speed"]) / nm
    assert_within(abs(out["slip_rate"] - ref), 2 * gamma(30) * abs(out["cage_speed"] / nm) + U,
                  "slip rate", effect=abs(ref))
    # film thickness is positive where loaded and of the micrometre order of formulas.md
    hm = out["film_thickness_min"][out["contact_load"] > 0]
    assert np.all(hm > 1e-8) and np.all(hm < 1e-5)
