"""The named kernels of flexbearing.multibody.dynamics.rhs, one at a time, against closed forms, and the
state layout (flexbearing.multibody.state_layout) against the model's field names.

Tolerances: the kernels evaluate a handful of floating-point operations on O(1) inputs, so the
closed forms hold to a few ulps; 1e-12 relative leaves room for any evaluation order.
"""
import math

import numpy as np
import pytest

from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.drag import ball_drag_moment_coefficient, churning_drag

REL = 1e-12


@pytest.fixture(scope="module")
def model():
    return M.build_model(PAPER_BEARING, PAPER_OIL, {"traction": False, "drag": True, "damping": False})


def _ball(x=0.02, r=0.0835, psi=0.7, x_dot=0.0, r_dot=0.0, psi_dot=0.0, w=(0.0, 0.0, 0.0)):
    return D.BallState(x, r, psi, x_dot, r_dot, psi_dot, w[0], w[1], w[2], math.cos(psi), math.sin(psi),
                       r * psi_dot)


def _free(p=None):
    """Attitude of a free ball (no race controls it), no ring load."""
    return D.Attitude(-1, 0.0, 0.0, 0.0, 0.0, 0.0, D.RingLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))


def test_state_layout_names_the_model_fields(model):
    lay = M.state_layout(model)
    z = model.n_balls
    assert (lay["ring"], lay["cage"], lay["modes"]) == (SL.ring_offset(z), SL.cage_offset(z), SL.modal_offset(z))
    assert lay["n_state"] == model.n_state == SL.state_size(z, model.n_modes)
    for prefix, fields, size in (("BALL_", lay["ball_fields"], SL.BALL_STATE),
                                 ("RING_", lay["ring_fields"], SL.RING_STATE),
                                 ("CAGE_", lay["cage_fields"], SL.CAGE_STATE)):
        assert len(fields) == size
        for name in fields:
            key = prefix + name.upper()
            alias = {"RING_X_DOT": "RING_VX", "RING_Y_DOT": "RING_VY", "RING_Z_DOT": "RING_VZ",
                     "CAGE_X_DOT": "CAGE_VX", "CAGE_Y_DOT": "CAGE_VY", "CAGE_Z_DOT": "CAGE_VZ"}.get(key, key)
            assert fields[getattr(SL, alias)] == name, (alias, name)
    # the blocks tile the state: ball j ends where ball j+1 starts, the last ball where the ring starts
    assert SL.ball_offset(z - 1) + SL.BALL_STATE == SL.ring_offset(z)


def test_ball_state_reads_its_slots(model):
    y = np.arange(model.n_state, dtype=float) * 0.001
    j = 3
    b = D.ball_state(y, j)
    o = SL.ball_offset(j)
    assert b.psi == y[o + SL.BALL_PSI] and b.w_t == y[o + SL.BALL_W_T]
    assert b.v_t == y[o + SL.BALL_R] * y[o + SL.BALL_PSI_DOT]
    assert b.cos_psi == math.cos(y[o + SL.BALL_PSI])


def test_circular_orbit_needs_only_the_centripetal_force(model):
    """m·(r'' − r·psi'²) = F_r: with F_r = −m·r·psi'² and F_t = 0 the orbit is a circle at constant speed."""
    p = model.p
    mb = p[M.P_MB]
    b = _ball(psi_dot=650.0)
    load = D.BallLoad(0.0, -mb * b.r * b.psi_dot ** 2, 0.0, 0.0, 0.0, 0.0)
    dydt = np.zeros(model.n_state)
    D.ball_equations(0, b, load, _free(p), p, dydt)
    assert abs(dydt[SL.BALL_R_DOT]) <= REL * b.r * b.psi_dot ** 2
    assert dydt[SL.BALL_PSI_DOT] == 0.0
    assert dydt[SL.BALL_PSI] == b.psi_dot


def test_orbit_keeps_its_angular_momentum_without_tangential_force(model):
    """m·(r·psi'' + 2·r'·psi') = F_t = 0  <=>  d(r²·psi')/dt = r²·psi'' + 2·r·r'·psi' = 0 (Coriolis)."""
    p = model.p
    b = _ball(r_dot=0.3, psi_dot=650.0)
    dydt = np.zeros(model.n_state)
    D.ball_equations(0, b, D.BallLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), _free(p), p, dydt)
    dh = b.r ** 2 * dydt[SL.BALL_PSI_DOT] + 2.0 * b.r * b.r_dot * b.psi_dot
    assert abs(dh) <= REL * 2.0 * b.r * b.r_dot * b.psi_dot


def test_free_ball_spin_is_constant_in_space(model):
    """No moment: w is constant in the inertial frame, so on the triad turning at psi'·e_x
    w' = −psi'·e_x × w: w_x' = 0, w_r' = psi'·w_t, w_t' = −psi'·w_r."""
    p = model.p
    b = _ball(psi_dot=650.0, w=(-4800.0, 1500.0, -300.0))
    dydt = np.zeros(model.n_state)
    D.ball_equations(0, b, D.BallLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), _free(p), p, dydt)
    assert dydt[SL.BALL_W_X] == 0.0
    assert dydt[SL.BALL_W_R] == pytest.approx(b.psi_dot * b.w_t, rel=REL)
    assert dydt[SL.BALL_W_T] == pytest.approx(-b.psi_dot * b.w_r, rel=REL)


def test_race_control_holds_a_satisfied_constraint(model):
    """Outer-race control with (w − 0·e_x)·n = 0 and w_t = 0 already held and no moment: the
    relaxation terms vanish, the ball keeps rolling about u = e_t × n."""
    p = model.p
    a = math.radians(30.0)
    n = (math.sin(a), math.cos(a))                      # outer contact normal
    u = (-n[1], n[0])
    b = _ball(psi_dot=650.0, w=(-3000.0 * u[0], -3000.0 * u[1], 0.0))
    att = D.Attitude(0, n[0], n[1], 0.0, u[0], u[1], D.RingLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    dydt = np.zeros(model.n_state)
    D.ball_equations(0, b, D.BallLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), att, p, dydt)
    wdot = np.array([dydt[SL.BALL_W_X], dydt[SL.BALL_W_R]])
    assert abs(wdot @ np.array(n)) <= 1e-9 * np.linalg.norm([b.w_x, b.w_r]) * p[M.P_ATT_RATE]
    assert dydt[SL.BALL_W_T] == 0.0


def test_churning_drag_kernel_force_moment_and_power(model):
    """F_d along e_t (drag.churning_drag), P = −F_d·v; with ball_drag_moment M = −c·w and
    P += c·|w|² (drag.ball_drag_moment_coefficient)."""
    p = model.p
    flags = model.flags.copy()
    b = _ball(psi_dot=650.0, w=(-4800.0, 1500.0, -300.0))
    rho, eta = 20.0, 0.01
    dw = p[M.P_DW]
    work = D.new_work(model)
    zero = D.BallLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    flags[M.F_BALL_DRAG_MOMENT] = 0
    load = D.ball_churning_drag(2, b, rho, eta, dw, flags, work, zero)
    fd = churning_drag(dw, b.v_t, rho, eta)
    assert fd < 0.0 and load.ft == fd and (load.mx, load.mr, load.mt) == (0.0, 0.0, 0.0)
    assert work[2, M.W_P_CHURNING] == pytest.approx(-fd * b.v_t, rel=REL)
    flags[M.F_BALL_DRAG_MOMENT] = 1
    load = D.ball_churning_drag(2, b, rho, eta, dw, flags, work, zero)
    c = ball_drag_moment_coefficient(dw, eta)
    assert (load.mx, load.mr, load.mt) == pytest.approx((-c * b.w_x, -c * b.w_r, -c * b.w_t), rel=REL)
    w2 = b.w_x ** 2 + b.w_r ** 2 + b.w_t ** 2
    assert work[2, M.W_P_CHURNING] == pytest.approx(-fd * b.v_t + c * w2, rel=REL)
    flags[M.F_DRAG] = 0
    assert D.ball_churning_drag(2, b, rho, eta, dw, flags, work, zero) == zero
    assert work[2, M.W_DRAG] == 0.0 and work[2, M.W_P_CHURNING] == 0.0


def test_inner_race_reaction_is_newtons_third_law(model):
    """Without the lean term the ring takes −F of the ball's contact force (inertial components),
    and the moment of −F about the ring centre at the contact point, less the spin couple
    (Cx, Cr) and the couple that moves F_H onto the line through the ball centre."""
    res = D.RaceContact(q=4000.0, cos_a=math.cos(0.6), sin_a=math.sin(0.6), p0=2e9, ur=40.0, rx=5e-3, ry=0.1,
                        a=2e-3, slip=0.01, delta=2e-5, fx=-2300.0, fr=-3300.0, ft=45.0, mx=0.1, mr=-0.2,
                        mt=0.05, x_p=0.016, r_p=0.075, cx=0.0, cr=0.0, p_traction=0.0, p_rolling=0.0,
                        p_damping=0.0, f_h=0.0)
    b = _ball(x=0.02, r=0.0835, psi=0.7)
    ring = D.RingState(1e-4, 2e-5, -3e-5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    rl = D.inner_race_reaction(res, res.ft, 0.0, b, ring, 0.01, 0.07, D.RingLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    cs, sn = b.cos_psi, b.sin_psi
    f_ball = np.array([res.fx, res.fr * cs - res.ft * sn, res.fr * sn + res.ft * cs])
    np.testing.assert_allclose([rl.fx, rl.fy, rl.fz], -f_ball, rtol=0, atol=REL * np.abs(f_ball).max())
    # the moment about X (the drive torque): the normal force Q·n lies in the ball plane, through
    # the bearing axis; the rest of −F acts at the contact point p with its lever from the ring centre
    qn = -res.q * np.array([res.sin_a, res.cos_a * cs, res.cos_a * sn])     # n = (−sin a, −cos a)
    lever = np.array([res.x_p - ring.x, res.r_p * cs - ring.y, res.r_p * sn - ring.z])
    assert rl.mx == pytest.approx(np.cross(lever, -f_ball - qn)[0], rel=1e-9)


def test_guidance_reaction_on_an_inner_land(model):
    """flags[F_GUIDANCE] = 1: the ring takes −F at the cage centre and −M_x; an outer land none.
    The axial part −F_x (a tilted land) is left out of the moments (linearised ring kinematics:
    the moments are the rim potential's tilt gradients l·F_z, −l·F_y, guide_land.inner_land_offset)."""
    flags = model.flags.copy()
    g = D.GuidanceLoad(120.0, -80.0, -3.0, 0.4, 0.0, 0.05)
    ring = D.RingState(1e-4, 2e-5, -3e-5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    zero = D.RingLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    flags[M.F_GUIDANCE] = 0
    assert D.guidance_reaction_on_ring(g, 0.02, 1e-4, 5e-5, ring, flags, zero) == zero
    flags[M.F_GUIDANCE] = 1
    rl = D.guidance_reaction_on_ring(g, 0.02, 1e-4, 5e-5, ring, flags, zero)
    assert (rl.fx, rl.fy, rl.fz) == (-g.fx, -g.fy, -g.fz)
    m = np.cross([0.02 - ring.x, 1e-4 - ring.y, 5e-5 - ring.z], [0.0, -g.fy, -g.fz])
    np.testing.assert_allclose([rl.mx, rl.my, rl.mz], [m[0] - g.mx, m[1], m[2]], rtol=REL)


def test_inner_ring_gyroscopic_coupling(model):
    """I_d·theta_y'' = M_y − I_p·omega·theta_z', I_d·theta_z'' = M_z + I_p·omega·theta_y', phi' = omega,
    m_i·x'' = F_ext + F_balls."""
    p = model.p
    z = model.n_balls
    r0 = SL.ring_offset(z)
    y = np.zeros(model.n_state)
    y[r0 + SL.RING_TILT_Y_DOT] = 0.02
    y[r0 + SL.RING_TILT_Z_DOT] = -0.01
    dydt = np.zeros_like(y)
    work = D.new_work(model)
    work[z, M.WR_FX] = 1000.0
    omega = 1466.0
    D.inner_ring_equations(y, dydt, r0, omega, D.RingLoad(-400.0, 0.0, 0.0, 7.0, 0.0, 0.0), work, z, p)
    ipw = p[M.P_IIP] * omega / p[M.P_IID]
    assert dydt[r0 + SL.RING_TILT_Y_DOT] == pytest.approx(-ipw * (-0.01), rel=REL)
    assert dydt[r0 + SL.RING_TILT_Z_DOT] == pytest.approx(ipw * 0.02, rel=REL)
    assert dydt[r0 + SL.RING_VX] == pytest.approx(600.0 / p[M.P_MI], rel=REL)
    assert dydt[r0 + SL.RING_PHI] == omega and work[z, M.WR_RING_TORQUE] == 7.0
    assert dydt[r0 + SL.RING_TILT_Y] == 0.02
