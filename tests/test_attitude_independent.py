"""An independent check of the ball attitude and cage speed under friction (issue 25, item 2).

A compact single-ball model of a thrust-loaded bearing, written without flexbearing.multibody.steady or
flexbearing.multibody.dynamics: Coulomb-type friction integrated over both Hertz ellipses with the sliding
field of the ball's spin relative to each race and Heathcote's slip (the contact surface curved
across the groove, radius R_d = 2·f·Dw/(2f + 1), Harris & Kotzalas, Rolling Bearing Analysis,
5th ed., Vol. 2 §2.2), the centrifugal force and the gyroscopic couple of a ball that keeps its
spin vector in the frame turning with the cage. In that frame, with the ball centre fixed,
absolute ball angular velocity w = (w_x, w_r, w_t) on (e_x, e_r, e_t) and orbit speed omega_c:

    sum_k (−Q_k·n_k + F_k) + m_b·r_b·omega_c²·e_r = 0            (3 force equations)
    sum_k M_k = I_b·omega_c·e_x × w = I_b·omega_c·(0, −w_t, w_r)   (3 moment equations)
    F_a + Z·(Q_i·n_i − F_i)·e_x = 0                                (inner ring, axial)

F_k, M_k: the friction force and its moment about the ball centre, integral over the Hertz
ellipse of mu(|v_s|/U)·p·v_s/|v_s|, v_s the race-minus-ball sliding velocity projected on the
contact surface, p the Hertz pressure, mu(s) = mu_0·(1 − exp(−2000·s)) (Coulomb with a creep
slip of 5e-4, the same curve the model gets through its traction table). Seven unknowns: ball
centre (x, r), ring axial position, omega_c, w. Geometry primitives (groove centres, Hertz
stiffness and ellipse) come from flexbearing.multibody.geometry and flexbearing.multibody.hertz, which have their own
checks against published tables; the kinematics, the friction integral and the equilibrium are
written here from scratch.

Compared with `flexbearing.multibody.steady.steady_thrust_state` and with the dynamics integrated from that
state (drag, gravity and radial load off: the pure thrust state Harris's analysis solves): the
pitch beta of the spin relative to the cage, atan(|w_r|/|w_x − omega_c|), within 0.5° and the cage
speed within 0.3 % (0.2 % in three of the four runs; see the assertions), Table 4 cases 1 and 6 at
mu_0 = 0.03 and 0.1. The model slices the ellipse with a linear slip across it (du2 = 0, without
Heathcote's curvature term) and evaluates each slice at its centre line; with this near-Coulomb
curve it needs 32 slices (N_SLICES) for its cage speed to converge.
"""
import math

import numpy as np
import pytest
from scipy.optimize import root

from flexbearing.studies.validation import slip_rate as V
from flexbearing.multibody import traction as TR
from flexbearing.multibody.geometry import inner_groove_centres, outer_groove_centre
from flexbearing.multibody.hertz import effective_modulus, hertz_point_contact, hertz_stiffness, race_curvature_radii
from flexbearing.multibody.model import with_traction_table

CREEP = 2000.0      # 1/slip: mu reaches 63 % of mu_0 at s = 5e-4
# The Coulomb-like curve makes the traction a near-step across the ellipse: the model's default 8
# slices put case 6's cage 0.23 % below the converged integral (32 slices: 0.06 %; case 1: 0.02 %
# with either), so the comparison runs the model at 32 slices (measured: benchmarks/results/traction_law.md)
N_SLICES = 32



def coulomb_table(mu0: float) -> np.ndarray:
    """The model's traction table for mu(s) = mu0·(1 − exp(−CREEP·s)) (origin law with B = 0, no
    load, speed or temperature exponents; flexbearing.multibody.traction "Origin law")."""
    tab = TR.bounded_traction_table((0.0, math.inf), (0.0, math.inf), 0.0)
    tab[:TR.FIT_TABLE_ROWS] = 0.0
    tab[TR.FIT_ROW_C, TR.FIT_C_FACTOR] = CREEP
    tab[TR.FIT_ROW_D, TR.FIT_C_FACTOR] = mu0
    tab[TR.FIT_ROW_LIMIT, TR.FIT_C_ORIGIN] = 1.0
    return tab


def _quadrature(n_r=20, n_t=64):
    """Points (rho, theta) and weights on the unit disc for the integral of f·rho d rho d theta."""
    g, w = np.polynomial.legendre.leggauss(n_r)
    rho = 0.5 * (g + 1.0)
    wr = 0.5 * w * rho
    th = (np.arange(n_t) + 0.5) * 2.0 * math.pi / n_t
    R, TH = np.meshgrid(rho, th, indexing="ij")
    W = np.outer(wr, np.full(n_t, 2.0 * math.pi / n_t))
    return R.ravel(), TH.ravel(), W.ravel()


QUAD = _quadrature()


class SingleBall:
    """The equations of the module docstring for one bearing, speed, thrust and friction level."""

    heathcote = True    # False: a flat contact, for diagnosis
    strips = False      # True: each strip slides as its centre line (the model's slices), for diagnosis

    def __init__(self, bearing, speed_rad_s, axial_load, mu0):
        self.b = bearing
        self.dw, self.dm, self.z = bearing.ball_diameter, bearing.pitch_diameter, bearing.n_balls
        self.m = bearing.ball_mass
        self.ib = 0.1 * self.m * self.dw ** 2
        bm, rm = bearing.ball_material, bearing.ring_material
        self.e_eff = effective_modulus(bm.youngs_modulus, bm.poisson_ratio, rm.youngs_modulus, rm.poisson_ratio)
        self.omega_i, self.fa, self.mu0 = speed_rad_s, axial_load, mu0
        self.outer = outer_groove_centre(self.dm, self.dw, bearing.fe)
        xl, rl, xr, rr = inner_groove_centres(self.dm, self.dw, bearing.fi, bearing.shim_angle,
                                              bearing.radial_clearance)
        self.inner = ((xl, rl), (xr, rr))

    def contact(self, xb, rb, centre, f, inner, ring_speed, omega_c, w):
        """(Q, n, F, M) of one race on the ball: load, unit normal (groove centre -> ball), friction
        force and its moment about the ball centre (cage frame, components x, r, t)."""
        dx, dr = xb - centre[0], rb - centre[1]
        d = math.hypot(dx, dr)
        delta = d - (f - 0.5) * self.dw
        n = np.array([dx / d, dr / d, 0.0])
        if delta <= 0.0:
            return 0.0, n, np.zeros(3), np.zeros(3)
        alpha = math.acos(min(1.0, abs(n[1])))
        rx, ry = race_curvature_radii(self.dw, self.dm, f, alpha, inner)
        q = hertz_stiffness(rx, ry, self.e_eff) * delta ** 1.5
        a, b, p0, _ = hertz_point_contact(rx, ry, self.e_eff, q)
        et = np.array([0.0, 0.0, 1.0])
        tau = np.cross(et, n)                       # across the groove, in the ball plane
        rd = 2.0 * f * self.dw / (2.0 * f + 1.0) if self.heathcote else 1e3   # Heathcote: pressure surface radius
        rho, th, wq = QUAD
        xi = b * rho * np.cos(th)                   # along e_t (rolling)
        eta = a * rho * np.sin(th)                  # across the groove
        phi = eta / rd
        nrm = np.cos(phi)[:, None] * n + np.sin(phi)[:, None] * tau
        centre_d = (0.5 * self.dw - rd) * n         # centre of the pressure surface, from the ball centre
        rel = centre_d + rd * nrm + xi[:, None] * et    # contact points relative to the ball centre
        if self.strips:                               # sliding of each strip taken at its centre line
            rel_v = centre_d + rd * nrm
        else:
            rel_v = rel
        pos_r = rb + rel_v[:, 1]                    # distance from the bearing axis (e_r component)
        # race: rotation (ring_speed − omega_c) about the bearing axis, v = Om·(r·e_t − xi·e_r)
        om = ring_speed - omega_c
        v_race = np.stack([np.zeros_like(pos_r), -om * rel_v[:, 2], om * pos_r], axis=1)
        w_rel = np.array([w[0] - omega_c, w[1], w[2]])
        v_ball = np.cross(w_rel, rel_v)
        vs = v_race - v_ball
        vs -= np.sum(vs * nrm, axis=1)[:, None] * nrm
        speed = np.linalg.norm(vs, axis=1)
        # rolling speed at the contact centre: mean surface speed along e_t (cage frame)
        centre_pt = 0.5 * self.dw * n
        u = 0.5 * abs(om * (rb + centre_pt[1]) + np.cross(w_rel, centre_pt)[2])
        mu = self.mu0 * (1.0 - np.exp(-CREEP * speed / max(u, 1e-9)))
        pr = p0 * np.sqrt(np.clip(1.0 - rho ** 2, 0.0, None))
        dfa = (wq * a * b * pr * mu / np.maximum(speed, 1e-300))[:, None] * vs
        F = dfa.sum(axis=0)
        M = np.cross(rel, dfa).sum(axis=0)
        return q, n, F, M

    def residual(self, u):
        xb, rb, ring_x, omega_c, wx, wr, wt = u
        w = np.array([wx, wr, wt])
        f_tot = np.array([0.0, self.m * rb * omega_c ** 2, 0.0])
        m_tot = np.zeros(3)
        q_o, n_o, F_o, M_o = self.contact(xb, rb, self.outer, self.b.fe, False, 0.0, omega_c, w)
        f_tot += -q_o * n_o + F_o
        m_tot += M_o
        ring_ax = 0.0
        for centre in self.inner:
            c = (centre[0] + ring_x, centre[1])
            q_i, n_i, F_i, M_i = self.contact(xb, rb, c, self.b.fi, True, self.omega_i, omega_c, w)
            f_tot += -q_i * n_i + F_i
            m_tot += M_i
            ring_ax += q_i * n_i[0] - F_i[0]
        gyro = self.ib * omega_c * np.array([0.0, -wt, wr])
        per_ball = self.fa / self.z
        # scaled: forces per ball load, moments as forces at the ball radius
        return np.concatenate([f_tot / per_ball, (m_tot - gyro) / (0.5 * self.dw) / per_ball,
                               [(self.fa + self.z * ring_ax) / self.fa]])

    def solve(self, start):
        """Root of `residual` from start (7 unknowns, scaled); returns (u, converged)."""
        start = np.asarray(start, float)
        scale = np.array([1e-6, 1e-6, 1e-6, 1e-3 * abs(start[3]), 1e-3 * abs(start[4]) + 1.0,
                          1e-3 * abs(start[4]) + 1.0, 1e-3 * abs(start[4]) + 1.0])
        sol = root(lambda v: self.residual(start + v * scale), np.zeros(7), method="hybr", options={"xtol": 1e-12})
        u = start + sol.x * scale
        return u, bool(np.max(np.abs(self.residual(u))) < 1e-7)


def pitch_deg(omega_c, wx, wr):
    return math.degrees(math.atan2(abs(wr), abs(wx - omega_c)))


def _model(mu0, n_slices=N_SLICES):
    return with_traction_table(V.build_validation_model(V.VALIDATION_BEARING, V.validation_oil(None, None),
                                                        {"gravity": 0.0, "drag": False, "n_slices": n_slices}),
                               coulomb_table(mu0), "fit")


def independent_state(case, mu0):
    """The single-ball roots from three starting attitudes (pitch 0, 0.5 and 0.7 rad): the geometry
    and the spin magnitude of the quasi-static start (flexbearing.multibody.initial), the pitch set."""
    from flexbearing.multibody.initial import initial_state
    model = _model(mu0)
    omega = case["speed_rpm"] * math.pi / 30.0
    y = initial_state(model, omega, case["axial_load"], 0.0)
    ring_x = y[9 * model.n_balls]
    ball = SingleBall(V.VALIDATION_BEARING, omega, case["axial_load"], mu0)
    xb, rb, omega_c = y[0], y[1], y[5]
    w_rel = math.hypot(y[6] - omega_c, y[7])       # spin magnitude of the quasi-static start
    roots = []
    for beta0 in (0.0, 0.5, 0.7):                   # rad: axis on the bearing axis, near alpha_i, beyond
        start = [xb, rb, ring_x, omega_c, omega_c - w_rel * math.cos(beta0), w_rel * math.sin(beta0), 0.0]
        u, ok = ball.solve(start)
        if ok:
            roots.append(u)
    assert roots, "the single-ball model found no root"
    return roots


CASES = [(1, 0.03), (1, 0.1), (6, 0.03), (6, 0.1)]


@pytest.mark.parametrize("case_no,mu0", CASES)
def test_attitude_and_cage_speed_independent_vs_steady_and_dynamics(case_no, mu0):
    from flexbearing.multibody import integrator as I
    from flexbearing.multibody.steady import steady_thrust_state
    case = V.slip_rate_cases()[case_no - 1]
    roots = independent_state(case, mu0)
    ref = roots[0]
    for u in roots[1:]:                      # one root from every starting attitude
        assert pitch_deg(u[3], u[4], u[5]) == pytest.approx(pitch_deg(ref[3], ref[4], ref[5]), abs=0.05)
    beta_ind, cage_ind = pitch_deg(ref[3], ref[4], ref[5]), ref[3]
    model = _model(mu0)
    omega = case["speed_rpm"] * math.pi / 30.0
    # steady: from its own start, else from the independent root (the root is then still the
    # dynamics' own fixed point: its residual is what is solved)
    y_s, info = steady_thrust_state(model, omega, case["axial_load"], strict=False)
    if not info["converged"]:
        from flexbearing.multibody.initial import initial_state
        y0 = initial_state(model, omega, case["axial_load"], 0.0)
        for j in range(model.n_balls):
            y0[9 * j], y0[9 * j + 1] = ref[0], ref[1]
            y0[9 * j + 5], y0[9 * j + 6], y0[9 * j + 7], y0[9 * j + 8] = ref[3], ref[4], ref[5], ref[6]
        y0[9 * model.n_balls] = ref[2]
        y0[9 * model.n_balls + 11 + 9] = ref[3]
        y_s, info = steady_thrust_state(model, omega, case["axial_load"], y_start=y0)
    assert info["converged"]
    beta_st = pitch_deg(y_s[5], y_s[6], y_s[7])
    # dynamics: 20 ms from the steady state (the ball and cage time constants are 0.1–1 ms here)
    sp, ld = np.array([[0.0, omega]]), np.array([[0.0, case["axial_load"], 0.0, 0.0]])
    y_d, t, _, _, _ = I.advance(model, y_s.copy(), 0.0, 0.02, sp, ld, np.zeros((0, 6)), 1e-6, 1e-7, I.Workspace(model))
    z = model.n_balls
    beta_dy = float(np.mean([pitch_deg(y_d[9 * j + 5], y_d[9 * j + 6], y_d[9 * j + 7]) for j in range(z)]))
    cage_dy = float(np.mean(y_d[[9 * j + 5 for j in range(z)]]))
    print(f"case {case_no} mu {mu0}: beta independent {beta_ind:.2f}°, steady {beta_st:.2f}°, dynamics {beta_dy:.2f}°; "
          f"cage {cage_ind:.3f} / {info['cage_speed']:.3f} / {cage_dy:.3f} rad/s")
    # the tolerances: 0.5° on the pitch (measured ≤ 0.18°); 0.2 % on the cage speed, met by
    # cases 1 (0.01, 0.02 %) and 6 at mu = 0.03 (0.06 %); case 6 at mu = 0.1 is 0.24 %, the size of
    # Heathcote's slip there (this model with a flat contact: +0.27 %), which the model's slices
    # leave out (du2 = 0): hence 0.3 % (benchmarks/results/traction_law.md, attitude table)
    assert beta_st == pytest.approx(beta_ind, abs=0.5)
    assert beta_dy == pytest.approx(beta_ind, abs=0.5)
    assert info["cage_speed"] == pytest.approx(cage_ind, rel=3e-3)
    assert cage_dy == pytest.approx(cage_ind, rel=3e-3)
