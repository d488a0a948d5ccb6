"""Quasi-static (Jones–Harris) equilibrium of a ball bearing with up to three contacts per ball.

References: A. B. Jones, "A general theory for elastically constrained ball and radial roller
bearings under arbitrary load and speed conditions", J. Basic Eng. 82 (1960) 309–320;
T. A. Harris & M. N. Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 2 (2007), ch. 3.

Model (geometry and sign conventions of `flexbearing.multibody.geometry`)
--------------------------------------------------------------
Every ball j sits in its azimuthal plane at psi_j = psi_0 + 2·pi·j/Z; its centre (x_j, r_j) is
unknown. It can touch up to three grooves k (0 = outer, 1 = inner-left, 2 = inner-right) whose
curvature centres c_k move with the inner ring's five displacements u = (x, y, z, theta_y,
theta_z) (`geometry.ring_point_in_plane`; the outer ring is fixed). For each contact

    delta_k = |b − c_k| − (f_k − 0.5)·Dw,   n_k = (b − c_k)/|b − c_k|,
    Q_k = K_k·max(delta_k, 0)^1.5              (Hertz, K_k = flexbearing.multibody.hertz.hertz_stiffness at the
                                                current contact angle, curvatures of hertz.race_curvature_radii)

Ball equilibrium in its plane (x, r), with the centrifugal force F_c = m·r_j·omega_m² (= 0.5·m·dm·
omega_m² at r_j = dm/2) and the friction forces f_k along the transverse direction
tau_k = (cos a_k, −sin a_k) that carry the gyroscopic moment:

    sum_k (−Q_k·n_k + f_k·tau_k) + (0, F_c) = 0.

Gyroscopic moment (about e_t): a ball whose angular velocity omega_b is constant in the frame that
orbits at omega_m about X needs M_g = omega_m·e_x × (J·omega_b) = J·omega_m·omega_b,r·e_t
(J = m·Dw²/10; Harris's J·omega_R·omega_m·sin(beta)). Friction at the contact points balances it:
(Dw/2)·(f_inner − f_outer) = M_g. With Jones's race-control factors lambda_o + lambda_i = 2:
f_outer = −lambda_o·M_g/Dw, f_inner = +lambda_i·M_g/Dw (shared among the loaded inner contacts in
proportion to their loads). Outer-race control: lambda_o = 2; inner-race control: lambda_i = 2.
The sign of M_g here follows from Euler's equation in this module's frame (tested by rotating
J·omega_b with the orbit); texts that draw the ball differently may print the friction terms with
the opposite sign.

Ball kinematics (race control, Jones 1959/1960): per ball the orbital speed omega_m and the absolute
angular velocity (omega_x, omega_r) solve three linear conditions: no rolling slip at the outer
contact centre, none at the (most loaded) inner contact centre, and no spin about the normal of the
controlling race: (omega_b − omega_race·e_x)·n = 0 (`geometry.contact_kinematics` defines slip and spin).
The controlling race is the outer or the inner one for every ball, or chosen per ball by Jones's
criterion (larger Q·a·E(k) controls; control = "jones").
At zero speed the kinematics are irrelevant (F_c = M_g = 0).

Inner-ring equilibrium: F_ext + sum_j sum_k∈inner (Q_k·n_k − f_k·tau_k) = 0 as forces in X, Y, Z
and moments about Y and Z (moments of the contact-point forces about the ring centre).

Solution: for given u each ball is solved by a damped 2×2 Newton iteration (compiled:
flexbearing.multibody.quasi_static_ball) to 1e-3 of the ring tolerance (never below its round-off
floor); u by Newton's method with the exact ring Jacobian (5 unknowns, or 3 with the tilts held at
zero; the implicit-function theorem over the balls, quasi_static_ball.ring_jacobian, with the kinematics
held; at a singular one the minimum-norm least-squares step, Dennis & Schnabel, Numerical Methods for
Unconstrained Optimization and Nonlinear Equations, SIAM 1996, §6.5) globalised by Armijo
backtracking on the 2-norm of the residual scaled by the load
(forces by the load scale, moments by it times dm/2); the kinematics (omega_m, omega_b, hence F_c
and M_g) by fixed-point iteration around that. Every convergence test is relative to the load and
never below the residual's round-off floor, so the iteration stops at the same place on every
processor and BLAS. The cold start is a bracketed 1-D solve of the axial (then radial) ring
displacement at zero speed, followed by continuation in the speed (steps of 1/4, halved on
failure); a warm start (`initial`) that fails falls back to it. A converged state at or near a
fold (ring Jacobian condition above 1/sqrt(eps)) says so in `notes`. Where the kinematics iteration
cycles because a ball's inner contact loads and unloads in turn (its orbit speed jumping between the
race-controlled and the epicyclic value), the diagnostic names the ball "on the edge of the load zone"
(`_LoadZoneEdge`): the model has no state there.

Geometry input: `grooves_from_bearing` (split inner ring, geometry of flexbearing.multibody.geometry) or `angular_contact_grooves`
(ordinary angular-contact bearing: one inner groove, used for the textbook comparisons).
Output: `QuasiStaticResult` (see its docstring): per-ball arrays, SI units.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, asdict

import numpy as np

from flexbearing.common.convergence import SolverNotConverged
from flexbearing.common.validation import InputError, require_range, require_positive, require_finite
from flexbearing.multibody import geometry as geo
from flexbearing.multibody.hertz import race_curvature_radii, hertz_point_contact, effective_modulus
from flexbearing.multibody.model_layout import (
    ATTITUDE_JONES, CONTACT_INNER_LEFT, CONTACT_INNER_RIGHT, CONTACT_OUTER, RACE_INNER, RACE_OUTER,
)
from flexbearing.multibody import quasi_static_ball as qb
from flexbearing.multibody.quasi_static_ball import solve_all_balls

OUTER, INNER_LEFT, INNER_RIGHT = 0, 1, 2
CONTACT_NAMES = ("outer", "inner_left", "inner_right")
CONTROL = {"outer": 0, "inner": 1, "jones": 2}
JONES_REVISIONS = 20    # outer iterations per speed step in which Jones's choice may still change
# condition number of the ring Jacobian above which a solution is reported as at or near a fold:
# 1/sqrt(eps), where a Newton step's own round-off error is as large as the step it resolves
FOLD_CONDITION = 1.0 / math.sqrt(float(np.finfo(float).eps))
NO_RACE_CONTROL = "race control is not possible"     # how _failure_diagnostic's physical verdict reads


class QuasiStaticNotConverged(SolverNotConverged):
    """solve_quasi_static did not find the equilibrium (raised unless strict=False): .result is the
    QuasiStaticResult it ended with, .residual its ring residual (relative to the load scale),
    .iterations the Newton iterations made, .diagnostic why."""


@dataclass(frozen=True)
class Grooves:
    """Ball-bearing description for the quasi-static solver (SI).

    groove_x, groove_r: nominal curvature centres (ring frame, ball plane) of the outer, inner-left
    and inner-right grooves; groove_f: radius/Dw; active: which of the three exist (an ordinary
    angular-contact bearing has no inner-right groove).
    """
    pitch_diameter: float
    ball_diameter: float
    n_balls: int
    groove_x: tuple
    groove_r: tuple
    groove_f: tuple
    active: tuple
    effective_modulus: float          # E' = 2/[(1-nu1²)/E1 + (1-nu2²)/E2], Pa
    ball_mass: float                  # kg
    ball_inertia: float               # J = m·Dw²/10, kg·m²


def grooves_from_bearing(bearing) -> Grooves:
    """The grooves of a `flexbearing.multibody.bearing.Bearing`: split inner ring (three-point
    type, both halves active) or one-piece ring (the second half inactive, Bearing docstring)."""
    b = bearing.validate()
    xo, ro = geo.outer_groove_centre(b.pitch_diameter, b.ball_diameter, b.fe)
    xl, rl, xr, rr = geo.inner_groove_centres(b.pitch_diameter, b.ball_diameter, b.fi,
                                              *b.groove_layout)
    m = b.ball_mass
    e = effective_modulus(b.ball_material.youngs_modulus, b.ball_material.poisson_ratio,
                          b.ring_material.youngs_modulus, b.ring_material.poisson_ratio)
    return Grooves(b.pitch_diameter, b.ball_diameter, int(b.n_balls), (xo, xl, xr), (ro, rl, rr),
                   (b.fe, b.fi, b.fi), (True, True, b.n_inner_halves == 2), e, m, 0.1 * m * b.ball_diameter ** 2)


def angular_contact_grooves(pitch_diameter, ball_diameter, n_balls, fi, fe, contact_angle,
                            youngs_modulus=207.0e9, poisson_ratio=0.3, density=7850.0) -> Grooves:
    """Ordinary angular-contact ball bearing with free contact angle alpha0 (one inner groove).

    Ball centre (0, dm/2) touches both grooves at zero load at alpha0
    (`geometry.angular_contact_outer_centre` / `angular_contact_inner_centre`).
    """
    require_positive("pitch_diameter", pitch_diameter, "m")
    require_range("ball_diameter", ball_diameter, 0.0, pitch_diameter, lo_open=True, hi_open=True, unit="m")
    require_range("fi", fi, 0.5, 0.6, lo_open=True)
    require_range("fe", fe, 0.5, 0.6, lo_open=True)
    require_range("contact_angle", contact_angle, 0.0, 0.5 * math.pi, hi_open=True, unit="rad")
    xo, ro = geo.angular_contact_outer_centre(pitch_diameter, ball_diameter, fe, contact_angle)
    xi, ri = geo.angular_contact_inner_centre(pitch_diameter, ball_diameter, fi, contact_angle)
    m = density * math.pi * ball_diameter ** 3 / 6.0
    e = effective_modulus(youngs_modulus, poisson_ratio, youngs_modulus, poisson_ratio)
    return Grooves(pitch_diameter, ball_diameter, int(n_balls), (xo, xi, -xi), (ro, ri, ri),
                   (fe, fi, fi), (True, True, False), e, m, 0.1 * m * ball_diameter ** 2)




# ---------------------------------------------------------------- result
@dataclass
class QuasiStaticResult:
    """Quasi-static state of the bearing (SI; per-ball arrays indexed by ball j, contact k).

    Contacts k: 0 outer, 1 inner-left (x < 0 half), 2 inner-right.
    psi (Z,)                ball azimuths, from +Y towards +Z, rad
    ball_x, ball_r (Z,)     ball centre in its plane: axial, radial position, m
    load (Z, 3)             normal contact loads Q, N
    contact_angle (Z, 3)    signed contact angles (geometry module convention), rad; 0 where unloaded
    delta (Z, 3)            approaches (negative = gap), m
    p0, a, b (Z, 3)         Hertz max pressure (Pa), semi-major, semi-minor axes (m)
    orbit_speed (Z,)        ball orbital (cage) speed, rad/s; cage_speed = its mean
    ball_omega (Z, 3)       ball absolute angular velocity (x, r, t) in its plane, rad/s
    centrifugal_force (Z,)  F_c, N;  gyroscopic_moment (Z,) M_g about e_t, N·m
    ring_displacement (5,)  inner ring (x, y, z, theta_y, theta_z), m and rad
    applied_load (5,)       (Fx, Fy, Fz, My, Mz) on the inner ring, N and N·m
    inner_speed             rad/s; control "outer" / "inner" / "jones"
    residual_ring           max |ring residual| / load scale; residual_ball: max ball residual, N
    converged, iterations   iterations: ring Newton iterations over all speed steps and kinematic updates
    controlling_race (Z,)   race that controls each ball: 0 outer, 1 inner (all equal unless control="jones")
    friction_share          (lambda_o, lambda_i) as given to the solver (None: all on the controlling race)
    diagnostic              why the solve failed (empty when converged), e.g. race control that would
                            need a friction coefficient above 1 at the controlling race
    jacobian_condition      2-norm condition number of the ring Jacobian at the solution (kinematics held,
                            tilts as displacements at the pitch radius); nan when not converged
    notes                   what a converged solution's user should know: at or near a fold (condition
                            above FOLD_CONDITION), where the equilibrium is not unique; empty otherwise
    """
    psi: np.ndarray
    ball_x: np.ndarray
    ball_r: np.ndarray
    load: np.ndarray
    contact_angle: np.ndarray
    delta: np.ndarray
    p0: np.ndarray
    a: np.ndarray
    b: np.ndarray
    orbit_speed: np.ndarray
    ball_omega: np.ndarray
    centrifugal_force: np.ndarray
    gyroscopic_moment: np.ndarray
    ring_displacement: np.ndarray
    applied_load: np.ndarray
    inner_speed: float
    control: str
    residual_ring: float
    residual_ball: float
    converged: bool
    iterations: int
    diagnostic: str = ""
    controlling_race: np.ndarray | None = None
    friction_share: tuple | None = None
    jacobian_condition: float = math.nan
    notes: str = ""

    @property
    def cage_speed(self) -> float:
        return float(np.mean(self.orbit_speed))

    def to_dict(self) -> dict:
        d = asdict(self)
        d["cage_speed"] = self.cage_speed
        return d

    def summary(self) -> str:
        """Printed table (MPa and degrees only here)."""
        lines = [f"ring displacement x,y,z = {self.ring_displacement[:3] * 1e6} um, "
                 f"tilts = {self.ring_displacement[3:] * 1e3} mrad; cage speed "
                 f"{self.cage_speed * 30 / math.pi:.1f} rpm; converged={self.converged}"]
        for k, name in enumerate(CONTACT_NAMES):
            q = self.load[:, k]
            if q.max() <= 0:
                lines.append(f"{name:12s}: unloaded")
                continue
            j = int(np.argmax(q))
            lines.append(f"{name:12s}: Qmax {q.max():9.1f} N  Qmin {q.min():9.1f} N  "
                         f"p0max {self.p0[:, k].max() / 1e6:7.1f} MPa  alpha(Qmax) "
                         f"{math.degrees(self.contact_angle[j, k]):6.2f} deg")
        return "\n".join(lines)


# ---------------------------------------------------------------- solver
class _State:
    def __init__(self, g: Grooves, psi):
        z = len(psi)
        self.psi = psi
        self.xb = np.zeros(z)
        self.rb = np.full(z, 0.5 * g.pitch_diameter)
        self.q = np.zeros((z, 3))
        self.nrm = np.zeros((z, 3, 5))
        self.ball_res = np.zeros(z)
        self.m_w2 = np.zeros(z)
        self.mg = np.zeros(z)
        self.wm = np.zeros(z)
        self.wb = np.zeros((z, 3))
        self.ctrl = np.zeros(z, dtype=np.int64)     # controlling race per ball: 0 outer, 1 inner
        self.work = np.zeros(200)                   # scratch of quasi_static_ball.ring_jacobian


def _ring_residual(u, g, st, arr, lam, fext, ball_tol):
    """F_ext + the balls' force on the ring at ring displacement u, every ball re-seated to its
    residual tolerance ball_tol (N)."""
    rf = np.zeros(5)
    solve_all_balls(u, st.psi, arr[0], arr[1], arr[2], arr[3], g.ball_diameter, g.pitch_diameter,
                     g.effective_modulus, st.m_w2, st.mg, lam[0], lam[1], ball_tol,
                     st.xb, st.rb, st.q, st.nrm, rf, st.ball_res)
    return fext + rf


def _ring_force_jacobian(u, g, st, arr, lam):
    """dF/du (5×5) of the balls' force on the ring at the balls' current seats, kinematics held:
    the implicit-function-theorem Jacobian of quasi_static_ball.ring_jacobian (exact, no re-solve)."""
    jac = np.empty((5, 5))
    qb.ring_jacobian(u, st.psi, arr[0], arr[1], arr[2], arr[3], g.ball_diameter, g.pitch_diameter,
                     g.effective_modulus, st.m_w2, st.mg, lam[0], lam[1], st.xb, st.rb, jac,
                     st.work)
    return jac


def _kinematics(g, st, inner_speed, u):
    """Race-control kinematics per ball (module docstring): omega_m, omega_b (x, r), each ball
    controlled by the race st.ctrl[j] (0 outer, 1 inner)."""
    dw, dm = g.ball_diameter, g.pitch_diameter
    for j in range(len(st.psi)):
        q = st.q[j]
        ki = CONTACT_INNER_LEFT if q[CONTACT_INNER_LEFT] >= q[CONTACT_INNER_RIGHT] else CONTACT_INNER_RIGHT
        if q[CONTACT_OUTER] <= 0.0 or q[ki] <= 0.0:
            # not carrying load between the races: take the epicyclic pure-rolling value
            st.wm[j] = geo.pitch_orbit_speed(inner_speed, 0.0, dw, dm, 0.0)
            st.wb[j] = (-(dm / (2 * dw)) * (1 - (dw / dm) ** 2) * inner_speed + st.wm[j], 0.0, 0.0)
            continue
        A = np.zeros((3, 3))
        rhs = np.zeros(3)
        for row, (k, wr) in enumerate(((CONTACT_OUTER, 0.0), (ki, inner_speed))):
            nx, nr, delta = st.nrm[j, k, 0], st.nrm[j, k, 1], st.nrm[j, k, 4]
            xp, rp, rho = geo.contact_point(st.xb[j], st.rb[j], nx, nr, delta, dw)
            c, s = math.cos(st.psi[j]), math.sin(st.psi[j])
            # race speed at the contact: omega·(r_p − ring-centre offset) (geometry.ring_surface_velocity)
            r_rel = rp - (u[1] * c + u[2] * s) if k != CONTACT_OUTER else rp
            # v_ball,t = r_b·omega_m + rho·(omega_x·n_r − omega_r·n_x) ; v_race,t = w_ring·r_rel
            A[row] = (st.rb[j], rho * nr, -rho * nx)
            rhs[row] = wr * r_rel
        kc = CONTACT_OUTER if st.ctrl[j] == RACE_OUTER else ki
        wr = 0.0 if st.ctrl[j] == RACE_OUTER else inner_speed
        nx, nr = st.nrm[j, kc, 0], st.nrm[j, kc, 1]
        A[2] = (0.0, nx, nr)                 # (omega_b − omega_race e_x)·n = 0
        rhs[2] = wr * nx
        wm, wx, wr_ = np.linalg.solve(A, rhs)
        st.wm[j] = wm
        st.wb[j] = (wx, wr_, 0.0)


class _RingSolve:
    """One solve_quasi_static call: its fixed data (grooves, loads, residual scaling, tolerances,
    options) and the per-ball state (`_State`, friction shares) its iterations update in place. The
    methods are the solver's steps (solve_quasi_static's docstring and the module docstring)."""

    def __init__(self, g, psi, inner_speed, fext, fscale, control, gyroscopic, centrifugal, fix_tilt, tol,
                 max_iter, friction_share):
        z = g.n_balls
        self.g, self.z, self.inner_speed, self.fext, self.fscale = g, z, inner_speed, fext, fscale
        self.control, self.gyroscopic, self.centrifugal = control, gyroscopic, centrifugal
        self.tol, self.max_iter, self.friction_share = tol, max_iter, friction_share
        self.arr = (np.array(g.groove_x, float), np.array(g.groove_r, float), np.array(g.groove_f, float),
                    np.array(g.active, np.bool_))
        # residual scaling: forces by fscale, moments by fscale·dm/2
        self.rscale = np.array([1, 1, 1, 2 / g.pitch_diameter, 2 / g.pitch_diameter]) / fscale
        self.free = free = np.array([0, 1, 2] if fix_tilt else [0, 1, 2, 3, 4])
        # the balls are solved to 1e-3 of the ring tolerance shared among them (never below their
        # round-off floor, quasi_static_ball._solve_ball), so the ring residual the Newton iteration sees
        # is its own and not the balls' stopping noise: with the balls at a fixed 1e-11 of the load, a
        # ring tolerance of 1e-12 was met or missed depending on the processor's rounding (issue 42)
        self.ball_tol = 1e-3 * tol * fscale / z
        self.st = _State(g, psi)
        # Jones's choice starts every ball on the outer race and is revised from the loads (speed_step)
        self.st.ctrl[:] = RACE_INNER if control == "inner" else RACE_OUTER
        self.lam = np.zeros((2, z))          # (lambda_o, lambda_i) per ball, updated in place
        _set_friction_shares(self.lam, self.st.ctrl, friction_share)
        self.lim = np.where(free < 3, 20e-6, 1e-3)     # largest Newton step, m and rad
        # tilts as displacements at the pitch radius
        self.dpitch = np.where(free < 3, 1.0, 0.5 * g.pitch_diameter)
        # the kinematics are iterated to the precision the ring equilibrium is solved to: with a ring
        # residual of tol the orbit speeds carry noise of about tol relative, and a tighter test would
        # chase a 2-cycle at that level (found at light load, 6000 rpm, inner control)
        self.kin_tol = max(1e-11, 10.0 * tol)

    def resid(self, uf, u_full):
        g, st, arr, lam, fext, free = self.g, self.st, self.arr, self.lam, self.fext, self.free
        u_full[free] = uf
        return (_ring_residual(u_full, g, st, arr, lam, fext, self.ball_tol) * self.rscale)[free]

    def tol_now(self):
        """The ring tolerance, raised to the residual's round-off floor where tol lies below it: the
        ring force sums the inner contacts' loads, so it cannot cancel the load to better than a few
        eps of their sum (plus the balls' own stopping tolerance)."""
        st, z, ball_tol, fscale, tol = self.st, self.z, self.ball_tol, self.fscale, self.tol
        floor = (qb.ROUNDOFF_FACTOR * qb.EPS * float(np.sum(st.q[:, 1:])) + z * ball_tol) / fscale
        return max(tol, floor)

    def jacobian(self, u_full):
        """Jacobian of the scaled ring residual in the free directions (kinematics held), exact by the
        implicit-function theorem at the balls' current seats (`_ring_force_jacobian`)."""
        jf = _ring_force_jacobian(u_full, self.g, self.st, self.arr, self.lam)
        return (self.rscale[:, None] * jf)[np.ix_(self.free, self.free)]

    def newton(self, u_full, maxit):
        """Newton's method on the ring residual with the kinematics held, globalised by Armijo
        backtracking on the scaled residual's 2-norm (Dennis & Schnabel, Numerical Methods for
        Unconstrained Optimization and Nonlinear Equations, SIAM 1996, §6.3): a step is accepted
        where |r(u + a·s)| <= (1 − 1e-4·a)·|r(u)|. Returns (u_free, r, converged, iterations)."""
        st, free, dpitch, lim = self.st, self.free, self.dpitch, self.lim
        uf = u_full[free].copy()
        r = self.resid(uf, u_full)
        for it in range(maxit):
            if np.max(np.abs(r)) <= self.tol_now():
                return uf, r, True, it
            J = self.jacobian(u_full)
            jd = J / dpitch[None, :]
            sv = np.linalg.svd(jd, compute_uv=False)
            if not sv[-1] * FOLD_CONDITION > sv[0]:
                # at a fold or a neutral direction (e.g. one ball carrying the load, the ring free across
                # it): the Newton step along the null directions is round-off; take the minimum-norm
                # least-squares step with those singular values dropped (Dennis & Schnabel §6.5)
                step = -np.linalg.lstsq(jd, r, rcond=1.0 / FOLD_CONDITION)[0] / dpitch
            else:
                step = -np.linalg.solve(J, r)
            s = np.max(np.abs(step) / lim)
            if s > 1:
                step /= s
            n0 = np.linalg.norm(r)
            xb0, rb0 = st.xb.copy(), st.rb.copy()
            a = 1.0
            reduced = False
            for _ in range(40):
                rn = self.resid(uf + a * step, u_full)
                if np.linalg.norm(rn) <= (1.0 - 1e-4 * a) * n0 or np.max(np.abs(rn)) <= self.tol_now():
                    reduced = True
                    break
                st.xb[:], st.rb[:] = xb0, rb0
                a *= 0.5
            if not reduced:
                # no step along the Newton direction lowers the residual: more iterations would only
                # repeat this search (stagnation), so report the state as it is
                r = self.resid(uf, u_full)
                return uf, r, np.max(np.abs(r)) <= self.tol_now(), it + 1
            uf = uf + a * step
            r = rn
        return uf, r, np.max(np.abs(r)) <= self.tol_now(), maxit

    def speed_step(self, u, w, cold):
        """Ring equilibrium and race-control kinematics at inner-ring speed w by fixed-point
        iteration of the kinematics around the ring Newton. Returns (ok, iterations, diagnostic)."""
        g, st, lam, free, control = self.g, self.st, self.lam, self.free, self.control
        centrifugal, gyroscopic, kin_tol, max_iter = self.centrifugal, self.gyroscopic, self.kin_tol, self.max_iter
        friction_share = self.friction_share
        if cold:
            st.wm[:] = geo.pitch_orbit_speed(w, 0.0, g.ball_diameter, g.pitch_diameter, 0.0)
        kin_ok = w == 0.0
        failed_newtons = 0
        its = 0
        ok = False
        dwm = math.inf
        edge = _LoadZoneEdge(len(st.psi))
        for outer_it in range(50):
            wm_old = st.wm.copy()
            mg_old = st.mg.copy()
            st.m_w2[:] = g.ball_mass * st.wm ** 2 if centrifugal else 0.0
            uf, r, ok, it = self.newton(u, max_iter)
            its += it
            u[free] = uf
            changed = False
            if control == "jones" and w != 0.0 and outer_it < JONES_REVISIONS:
                new = _jones_controlling_race(g, st)
                changed = bool(np.any(new != st.ctrl))
                st.ctrl[:] = new
                _set_friction_shares(lam, st.ctrl, friction_share)
            _kinematics(g, st, w, u)
            st.mg[:] = g.ball_inertia * st.wm * st.wb[:, 1] if gyroscopic else 0.0
            if w == 0.0:
                break
            edge.record(st, wm_old, outer_it >= 40)
            dwm = np.max(np.abs(st.wm - wm_old)) / max(abs(w), 1e-30)
            dmg = np.max(np.abs(st.mg - mg_old)) / max(np.max(np.abs(st.mg)), 1e-30)
            if ok and not changed and dwm < kin_tol and (dmg < max(1e-9, kin_tol) or not gyroscopic):
                kin_ok = True
                break
            failed_newtons = 0 if ok else failed_newtons + 1
            if failed_newtons >= 3:
                why = _failure_diagnostic(g, st, w, control, lam)
                return False, its, why
        if not kin_ok:
            why = _failure_diagnostic(g, st, w, control, lam)
            if NO_RACE_CONTROL in why:
                # the kinematics cycle because the controlling race would need a friction coefficient
                # above 1 at the state they reached: the physical reason, not a numerical one
                return False, its, why
            if np.any(edge.switched):
                return False, its, edge.diagnostic(st, w)
            return False, its, (f"the race-control kinematics did not settle in 50 iterations at inner-ring "
                                f"speed {w:.6g} rad/s (last orbit-speed change {dwm:.3g} relative, "
                                f"needed {kin_tol:.3g})")
        return ok, its, ""

    def snapshot(self, u):
        return (u.copy(), self.st.xb.copy(), self.st.rb.copy(), self.st.wm.copy(), self.st.wb.copy(), self.st.mg.copy(),
                self.st.ctrl.copy(), self.lam.copy())

    def restore(self, snap, u):
        st = self.st
        u[:], st.xb[:], st.rb[:], st.wm[:], st.wb[:], st.mg[:], st.ctrl[:], self.lam[:] = snap

    def cold_path(self, u):
        """From rest to inner_speed by natural-parameter continuation in the speed (Allgower & Georg,
        Introduction to Numerical Continuation Methods, SIAM 2003, ch. 1-2): the zero-speed
        bracketed start, then steps of a quarter of the speed, each started from the last state; a
        failed step is halved (down to 1/64 of the speed), a converged one enlarged by 1.5."""
        g, st, arr, lam, free, control = self.g, self.st, self.arr, self.lam, self.free, self.control
        inner_speed, friction_share, ball_tol, fext = self.inner_speed, self.friction_share, self.ball_tol, self.fext
        u[:] = _initial_guess(g, st, arr, lam, fext, ball_tol, free)
        st.wm[:] = 0.0
        st.wb[:] = 0.0
        st.mg[:] = 0.0
        st.ctrl[:] = RACE_INNER if control == "inner" else RACE_OUTER
        _set_friction_shares(lam, st.ctrl, friction_share)
        if inner_speed == 0.0:
            return self.speed_step(u, 0.0, True)
        its = 0
        done, step, first = 0.0, 0.25, True
        good = self.snapshot(u)
        while done < 1.0:
            trial = min(1.0, done + step)
            ok, it, why = self.speed_step(u, trial * inner_speed, first)
            its += it
            if ok:
                done, first = trial, False
                good = self.snapshot(u)
                step *= 1.5
                continue
            if NO_RACE_CONTROL in why:
                # a physical limit, not a numerical one: a smaller speed step reaches the same speed
                return False, its, why
            self.restore(good, u)
            step *= 0.5
            if step < 1.0 / 64.0:
                return False, its, why
        return True, its, ""

    def fold_check(self, u):
        """(condition, notes) of a converged state: the 2-norm condition number of the ring Jacobian
        in the free directions, and a note where it is above FOLD_CONDITION."""
        notes = ""
        # the conditioning of the ring equilibrium (kinematics held; tilts as the displacement
        # they cause at the pitch radius): near a fold (a limit point of the load–displacement
        # curve) the Jacobian is singular and a second equilibrium lies close
        J = self.jacobian(u)
        sv = np.linalg.svd(J / self.dpitch[None, :], compute_uv=False)
        cond = float(sv[0] / sv[-1]) if sv[-1] > 0.0 else math.inf
        if cond > FOLD_CONDITION:
            notes = (f"the ring Jacobian's condition number is {cond:.3g} (> {FOLD_CONDITION:.0e}): the state is "
                     "at or near a fold of the load-displacement curve, where the equilibrium is not unique "
                     "(another one lies close, and a small change of load or speed may jump to it)")
        return cond, notes


def solve_quasi_static(grooves: Grooves, inner_speed: float = 0.0, fx: float = 0.0, fy: float = 0.0,
                       fz: float = 0.0, my: float = 0.0, mz: float = 0.0, control: str = "outer",
                       gyroscopic: bool = True, centrifugal: bool = True, fix_tilt: bool = False,
                       psi0: float = 0.0, tol: float = 1e-9, max_iter: int = 60,
                       initial: QuasiStaticResult | None = None,
                       friction_share: tuple[float, float] | None = None,
                       strict: bool = True) -> QuasiStaticResult:
    """Quasi-static equilibrium (module docstring) under loads on the inner ring and inner-ring speed.

    fx, fy, fz (N), my, mz (N·m): external load on the inner ring; inner_speed (rad/s, about +X);
    control: "outer" or "inner" race control for every ball, or "jones": each ball controlled by the
    race Jones's criterion picks at the current loads (`_jones_controlling_race`; the choice may
    change during the first JONES_REVISIONS iterations of each speed step, then it is held, so a
    ball on the criterion's boundary cannot make the iteration cycle; the result's
    `controlling_race` says which race won); gyroscopic / centrifugal switch those terms;
    fix_tilt holds theta_y = theta_z = 0 (no moment equilibrium, as in the textbook examples that
    apply the load "without tilting"); psi0 the azimuth of ball 0; tol the ring residual relative
    to the load scale. `initial` warm-starts from a previous result. friction_share = (lambda_o,
    lambda_i), lambda_o + lambda_i = 2: how the gyroscopic moment's friction is shared between the
    races (module docstring); None = all of it on the controlling race, (1, 1) = equal and opposite
    friction forces at the two contacts (the pure couple of flexbearing.multibody.dynamics' race-control balls).

    Convergence: the ring residual (max over the free directions, relative to the load scale) at or
    below tol, or below its round-off floor where tol is smaller (32·eps of the inner contacts' summed
    load: the tolerance cannot ask for cancellation finer than that on any processor), and the
    kinematics settled (orbit speeds to 10·tol relative). A cold start, or a warm start that fails,
    follows the speed up from rest (continuation, steps halved on failure). strict (default): a
    solve that does not converge raises QuasiStaticNotConverged (result, residual, iterations and
    diagnostic attached); strict=False returns the result with converged False, for callers that
    check it themselves.
    """
    for name, v in (("fx", fx), ("fy", fy), ("fz", fz), ("my", my), ("mz", mz), ("psi0", psi0)):
        require_finite(name, v)
    require_range("inner_speed", inner_speed, -1e5, 1e5, unit="rad/s")
    if control not in CONTROL:
        raise InputError(f"control = {control!r} must be one of {sorted(CONTROL)}")
    g = grooves
    z = g.n_balls
    psi = psi0 + 2.0 * math.pi * np.arange(z) / z
    if friction_share is not None:
        lo, li = (float(v) for v in friction_share)
        if not (0.0 <= lo <= 2.0 and 0.0 <= li <= 2.0 and abs(lo + li - 2.0) < 1e-12):
            raise InputError(f"friction_share = {friction_share!r}: needs lambda_o, lambda_i in [0, 2] "
                             "with lambda_o + lambda_i = 2")
        friction_share = (lo, li)
    fext = np.array([fx, fy, fz, my, mz], float)
    fscale = max(abs(fx), math.hypot(fy, fz), 2.0 * math.hypot(my, mz) / g.pitch_diameter, 1.0)
    if abs(fx) + math.hypot(fy, fz) <= 0.0 and inner_speed == 0.0:
        raise InputError("the bearing carries no load: give fx, fy or fz (N) or a speed")
    require_range("tol", tol, 0.0, 1e-3, lo_open=True)
    rs = _RingSolve(g, psi, inner_speed, fext, fscale, control, gyroscopic, centrifugal, fix_tilt, tol,
                    max_iter, friction_share)
    st, free = rs.st, rs.free
    u = np.zeros(5)
    total_it = 0
    if initial is not None:
        u[:] = initial.ring_displacement
        st.xb[:], st.rb[:] = initial.ball_x, initial.ball_r
        st.wm[:], st.wb[:] = initial.orbit_speed, initial.ball_omega
        if control == "jones" and initial.controlling_race is not None:
            st.ctrl[:] = initial.controlling_race
            _set_friction_shares(rs.lam, st.ctrl, friction_share)
        ok, total_it, diagnostic = rs.speed_step(u, inner_speed, False)
        if not ok:
            # a warm start too far from this load or speed: the cold path (continuation from rest)
            ok, it, diagnostic = rs.cold_path(u)
            total_it += it
    else:
        ok, total_it, diagnostic = rs.cold_path(u)
    # final consistent evaluation
    st.m_w2[:] = g.ball_mass * st.wm ** 2 if centrifugal else 0.0
    rfin = rs.resid(u[free], u)
    ok = ok and np.max(np.abs(rfin)) <= 10 * rs.tol_now()
    if not ok and not diagnostic:
        diagnostic = (f"ring equilibrium not reached: residual {np.max(np.abs(rfin)):.3g} of the load scale "
                      f"(tol {tol:.3g})")
    cond, notes = rs.fold_check(u) if ok else (math.nan, "")
    res = _result(g, st, u, fext, inner_speed, control, float(np.max(np.abs(rfin))), ok, total_it,
                  diagnostic, friction_share)
    res.jacobian_condition = cond
    res.notes = notes
    if strict and not ok:
        raise QuasiStaticNotConverged(f"quasi-static equilibrium not found: {diagnostic}", result=res,
                                      residual=res.residual_ring, iterations=total_it, diagnostic=diagnostic)
    return res


def _set_friction_shares(lam, ctrl, friction_share):
    """lam[:, j] = (lambda_o, lambda_i) of ball j: friction_share for every ball, or, when None, all
    of the gyroscopic friction on the ball's controlling race (2, 0) / (0, 2) (module docstring)."""
    if friction_share is not None:
        lam[0, :], lam[1, :] = friction_share
    else:
        lam[0, :] = np.where(ctrl == RACE_OUTER, 2.0, 0.0)
        lam[1, :] = 2.0 - lam[0, :]


def _jones_controlling_race(g, st) -> np.ndarray:
    """Jones's criterion per ball (J. Basic Eng. 82 (1960) 309; Harris & Kotzalas Vol. 2, ch. 2): the
    race whose contact can resist the larger spinning moment, Q·a·E(k), controls the ball; the outer
    contact enters with cos(alpha_o − alpha_i). The same rule as the dynamics' ball_attitude =
    "jones" (flexbearing.multibody.dynamics.control_race, E(k) ratio taken as 1); a from Hertz at the current
    loads (flexbearing.multibody.hertz.hertz_point_contact). Returns 0 (outer) / 1 (inner) per ball."""
    from flexbearing.multibody.dynamics import control_race
    out = st.ctrl.copy()
    o = CONTACT_OUTER
    for j in range(len(st.psi)):
        ki = CONTACT_INNER_LEFT if st.q[j, CONTACT_INNER_LEFT] >= st.q[j, CONTACT_INNER_RIGHT] else CONTACT_INNER_RIGHT
        a = [0.0, 0.0]
        for n, k in enumerate((o, ki)):
            q = st.q[j, k]
            if q > 0.0:
                a[n] = _hertz_ellipse(g, k, st.nrm[j, k, 2], q)[0]
        c = control_race(ATTITUDE_JONES, st.q[j, o], a[0], st.nrm[j, o, 0], st.nrm[j, o, 1],
                         st.q[j, ki], a[1], st.nrm[j, ki, 0], st.nrm[j, ki, 1])
        if c in (RACE_OUTER, RACE_INNER):
            out[j] = c
    return out


LOAD_ZONE_EDGE = "on the edge of the load zone"     # how _LoadZoneEdge's verdict reads


def _carrying_load(st) -> np.ndarray:
    """Per ball: True where it carries load between the races (its outer and its more loaded inner
    contact both loaded), the test by which `_kinematics` gives it race-controlled kinematics rather
    than the epicyclic pure-rolling ones."""
    q_inner = np.maximum(st.q[:, CONTACT_INNER_LEFT], st.q[:, CONTACT_INNER_RIGHT])
    return (st.q[:, CONTACT_OUTER] > 0.0) & (q_inner > 0.0)


class _LoadZoneEdge:
    """The balls whose load-carrying state (`_carrying_load`) switches between the kinematics
    iterations of one speed step (recorded over its last iterations), with the largest inner-contact
    load and orbit-speed jump seen there.

    `_kinematics` is discontinuous at a contact's zero load: a ball carrying load between the races
    orbits at its controlling race's speed, an unloaded one at the epicyclic pure-rolling speed
    (race control, Jones 1959/1960, and `_kinematics`: module docstring). Where
    the orbit-speed law a ball's state selects moves its centrifugal force and gyroscopic moment so that
    the ring equilibrium then selects the other law, the fixed-point iteration cycles and has no fixed
    point with that ball either loaded or unloaded: the ball is on the edge of the load zone, where the
    quasi-static model's race control cannot say at which speed it orbits."""

    def __init__(self, z: int):
        self.carrying = None
        self.switched = np.zeros(z, dtype=np.bool_)
        self.q_inner = np.zeros(z)
        self.jump = np.zeros(z)

    def record(self, st, wm_old, late: bool):
        now = _carrying_load(st)
        if late and self.carrying is not None:
            self.switched |= now != self.carrying
            q_inner = np.maximum(st.q[:, CONTACT_INNER_LEFT], st.q[:, CONTACT_INNER_RIGHT])
            self.q_inner = np.maximum(self.q_inner, q_inner)
            self.jump = np.maximum(self.jump, np.abs(st.wm - wm_old))
        self.carrying = now

    def diagnostic(self, st, inner_speed) -> str:
        balls = np.flatnonzero(self.switched)
        which = ", ".join(f"{j} (azimuth {math.degrees(st.psi[j]) % 360.0:.1f}°, inner-contact load between 0 and "
                          f"{self.q_inner[j]:.3g} N)" for j in balls)
        jump = float(np.max(self.jump[balls])) / abs(inner_speed)
        return (f"the race-control kinematics have no fixed point at inner-ring speed {inner_speed:.6g} rad/s: "
                f"{'ball' if len(balls) == 1 else 'balls'} {which} {'is' if len(balls) == 1 else 'are'} "
                f"{LOAD_ZONE_EDGE}, loaded and unloaded in turn: carrying load a ball orbits at its "
                f"controlling race's speed, unloaded at the epicyclic pure-rolling speed (a jump of "
                f"{jump:.3g} of the inner-ring speed), and each speed's centrifugal force and gyroscopic moment "
                "give the ring equilibrium that selects the other, so the iteration cycles; quasi-static race "
                "control cannot say how fast such a ball orbits (the steady or dynamic solution, whose orbit "
                "speeds follow from the traction, can)")


def _failure_diagnostic(g, st, inner_speed, control, lam) -> str:
    """Why the equilibrium under race control fails, in the engineer's terms.

    Race control needs friction at the controlling race to carry the gyroscopic moment,
    f = lambda·M_g/Dw (module docstring). A friction force larger than the normal load of that contact
    (coefficient above 1; EHL traction stays below about 0.1) cannot exist: the race cannot control
    the ball there, and Jones's criterion (flexbearing.multibody.dynamics.control_race) would pick the other race.
    Otherwise the ring equilibrium itself is reported as not found."""
    q_race = np.where(st.ctrl == RACE_OUTER, st.q[:, CONTACT_OUTER], st.q[:, CONTACT_INNER_LEFT] + st.q[:, CONTACT_INNER_RIGHT])
    f_race = np.abs(np.where(st.ctrl == RACE_OUTER, lam[0], lam[1]) * st.mg) / g.ball_diameter
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(q_race > 0.0, f_race / q_race, np.where(f_race > 0.0, np.inf, 0.0))
    j = int(np.argmax(mu))
    if mu[j] > 1.0:
        race = "outer" if st.ctrl[j] == RACE_OUTER else "inner"
        other = "inner" if race == "outer" else "outer"
        hint = "" if control == "jones" else f"; try control='{other}' or 'jones' (Jones's criterion per ball)"
        return (f"{race} {NO_RACE_CONTROL} at inner-ring speed {inner_speed:.6g} rad/s: "
                f"ball {j} needs a friction force of {f_race[j]:.3g} N at its {race} contact to carry "
                f"the gyroscopic moment {abs(st.mg[j]):.3g} N·m, but that contact's normal load is "
                f"{q_race[j]:.3g} N (friction coefficient {mu[j]:.3g} > 1){hint}")
    return (f"ring equilibrium not found at inner-ring speed {inner_speed:.6g} rad/s under {control} race "
            f"control (Newton stagnated 3 times; largest friction coefficient needed {mu[j]:.3g}, ball {j})")


def _initial_guess(g, st, arr, lam, fext, ball_tol, free):
    """Zero-speed bracketed 1-D solves: axial displacement, then radial along the load direction."""
    from scipy.optimize import brentq
    u = np.zeros(5)
    fr = math.hypot(fext[1], fext[2])
    dirs = []
    if fext[0] != 0.0:
        dirs.append((np.array([1.0, 0, 0, 0, 0]), fext[0]))
    if fr > 0.0:
        dirs.append((np.array([0, fext[1] / fr, fext[2] / fr, 0, 0]), fr))
    st.m_w2[:] = 0.0
    st.mg[:] = 0.0
    for d, fd in dirs:
        base = u.copy()

        def h(t):
            st.xb[:] = 0.0
            st.rb[:] = 0.5 * g.pitch_diameter
            return float(np.dot(_ring_residual(base + t * d, g, st, arr, lam, fext, ball_tol), d))
        sgn = math.copysign(1.0, fd)
        lo, hlo = 0.0, h(0.0)
        step = 2e-6
        hi = sgn * step
        hhi = h(hi)
        n = 0
        while hlo * hhi > 0 and n < 40:
            lo, hlo = hi, hhi
            step *= 1.6
            hi = hi + sgn * step
            hhi = h(hi)
            n += 1
        if hlo * hhi < 0:
            t = brentq(h, min(lo, hi), max(lo, hi), xtol=1e-12)
            u = base + t * d
    st.xb[:] = 0.0
    st.rb[:] = 0.5 * g.pitch_diameter
    _ring_residual(u, g, st, arr, lam, fext, ball_tol)
    return u


def _hertz_ellipse(g, k, cos_alpha, q):
    """(a, b, p0, delta) of contact k (0 outer, 1/2 inner) at |cos(contact angle)| cos_alpha and load q
    (flexbearing.multibody.hertz.hertz_point_contact with the groove's curvature radii)."""
    rx, ry = race_curvature_radii(g.ball_diameter, g.pitch_diameter, g.groove_f[k],
                                  math.acos(min(1.0, abs(cos_alpha))), k != CONTACT_OUTER)
    return hertz_point_contact(rx, ry, g.effective_modulus, q)


def _result(g, st, u, fext, inner_speed, control, rres, ok, iters, diagnostic="",
            friction_share=None) -> QuasiStaticResult:
    z = len(st.psi)
    load = st.q.copy()
    ang = np.zeros((z, 3))
    delta = np.zeros((z, 3))
    p0 = np.zeros((z, 3))
    a = np.zeros((z, 3))
    b = np.zeros((z, 3))
    for j in range(z):
        for k in range(3):
            if not g.active[k]:
                delta[j, k] = -np.inf
                continue
            ca, sa, dl = st.nrm[j, k, 2], st.nrm[j, k, 3], st.nrm[j, k, 4]
            delta[j, k] = dl
            if load[j, k] > 0:
                ang[j, k] = math.atan2(sa, ca)
                a[j, k], b[j, k], p0[j, k], _ = _hertz_ellipse(g, k, ca, load[j, k])
    fc = g.ball_mass * st.wm ** 2 * st.rb
    return QuasiStaticResult(st.psi.copy(), st.xb.copy(), st.rb.copy(), load, ang, delta, p0, a, b,
                             st.wm.copy(), st.wb.copy(), fc, st.mg.copy(), u.copy(), fext.copy(),
                             float(inner_speed), control, rres, float(np.max(st.ball_res)), bool(ok), iters,
                             diagnostic, st.ctrl.copy(), friction_share)


# ---------------------------------------------------------------- stiffness
def ring_jacobian(grooves: Grooves, result: QuasiStaticResult) -> np.ndarray:
    """The ring Jacobian dF/du (5×5, SI) of the balls' force on the inner ring at a quasi-static
    state, each ball in its own equilibrium and the kinematics held (orbit speeds, gyroscopic
    moments, controlling races and friction shares of `result`): exact, by the implicit-function
    theorem over the balls (flexbearing.multibody.quasi_static_ball.ring_jacobian states the
    equation). It is what the solver's Newton iteration uses and what its fold flag's condition
    number is taken of; −dF/du is the stiffness with the kinematics held, what
    `bearing_stiffness(kinematics="frozen")` computes by central differences."""
    g = grooves
    st, lam, arr = _state_of(g, result)
    fscale = max(abs(result.applied_load[0]), math.hypot(result.applied_load[1], result.applied_load[2]), 1.0)
    u0 = np.array(result.ring_displacement, float)
    _ring_residual(u0, g, st, arr, lam, np.zeros(5), 1e-14 * fscale)
    return _ring_force_jacobian(u0, g, st, arr, lam)


def _state_of(g, result):
    """Solver state (balls seated as in `result`, its kinematics, races and friction shares)."""
    z = g.n_balls
    st = _State(g, np.array(result.psi, float))
    st.xb[:], st.rb[:] = result.ball_x, result.ball_r
    if result.controlling_race is not None:
        st.ctrl[:] = result.controlling_race
    else:
        st.ctrl[:] = RACE_INNER if result.control == "inner" else RACE_OUTER
    lam = np.zeros((2, z))
    _set_friction_shares(lam, st.ctrl, result.friction_share)
    arr = (np.array(g.groove_x, float), np.array(g.groove_r, float), np.array(g.groove_f, float),
           np.array(g.active, np.bool_))
    st.wm[:], st.wb[:] = result.orbit_speed, result.ball_omega
    st.mg[:] = result.gyroscopic_moment
    st.m_w2[:] = g.ball_mass * st.wm ** 2 if np.any(result.centrifugal_force != 0.0) else 0.0
    return st, lam, arr


def bearing_stiffness(grooves: Grooves, result: QuasiStaticResult, kinematics: str = "updated",
                      step: tuple[float, float] = (1e-8, 1e-7)) -> np.ndarray:
    """Stiffness matrix of the bearing at a quasi-static equilibrium, 5×5, SI (N/m, N/rad, N·m/m,
    N·m/rad), in the ring coordinates u = (x, y, z, theta_y, theta_z) of `QuasiStaticResult`:

        K_ij = −∂F_i/∂u_j,   F = (Fx, Fy, Fz, My, Mz) of the balls on the inner ring,

    each ball re-seated in its own equilibrium at every perturbed u (the balls are massless springs
    between the races, as in the quasi-static model) and the controlling races held (Jones 1960; the
    5×5 form of T. C. Lim & R. Singh, J. Sound Vib. 139 (1990) 179). kinematics: "updated" (default)
    re-solves the race-control kinematics at every perturbed u (orbit speeds, hence centrifugal
    forces and gyroscopic moments follow the contact angles): the tangent of the quasi-static
    load–displacement curve, what other quasi-static codes report as the stiffness at speed.
    "frozen" holds the kinematics at the operating point: the stiffness for vibrations faster than
    the balls' orbit can follow. At speed the two differ because the centrifugal force changes with
    the orbit speed, which moves with the contact angles: measured 7–34 % on the translational
    diagonal of the 218 bearing at 10,000 rpm, Fa 4450 N, Fr 0–2000 N. Central differences with
    steps step[0] (m) for x, y, z and step[1] (rad) for the tilts; truncation error of order step²
    (benchmarks/bench_quasi_static.py: 4e-6 on the diagonal at the default steps, 28 ms).

    Checks (tests/test_quasi_static.py): the axial and radial terms against the two-force-member
    formulas of a preloaded bearing, K_xx also against the derivative of Jones's thrust equation,
    symmetry at rest (the contact forces derive from a potential there)."""
    if kinematics not in ("frozen", "updated"):
        raise InputError(f"kinematics = {kinematics!r} must be 'frozen' or 'updated'")
    g = grooves
    st, lam, arr = _state_of(g, result)
    xb0, rb0 = np.array(result.ball_x, float), np.array(result.ball_r, float)
    fscale = max(abs(result.applied_load[0]), math.hypot(result.applied_load[1], result.applied_load[2]), 1.0)
    # the balls to their round-off floor (quasi_static_ball._solve_ball): the central difference
    # divides their residual by the step
    ball_tol = 1e-14 * fscale
    zero = np.zeros(5)
    centrifugal = bool(np.any(result.centrifugal_force != 0.0))
    gyroscopic = bool(np.any(result.gyroscopic_moment != 0.0))
    w = result.inner_speed

    def ring_force(u):
        st.xb[:], st.rb[:] = xb0, rb0
        st.wm[:], st.wb[:] = result.orbit_speed, result.ball_omega
        st.mg[:] = result.gyroscopic_moment
        st.m_w2[:] = g.ball_mass * st.wm ** 2 if centrifugal else 0.0
        f = _ring_residual(u, g, st, arr, lam, zero, ball_tol)
        if kinematics == "frozen" or w == 0.0:
            return f
        for _ in range(100):
            wm_old = st.wm.copy()
            _kinematics(g, st, w, u)
            st.m_w2[:] = g.ball_mass * st.wm ** 2 if centrifugal else 0.0
            st.mg[:] = g.ball_inertia * st.wm * st.wb[:, 1] if gyroscopic else 0.0
            f = _ring_residual(u, g, st, arr, lam, zero, ball_tol)
            if np.max(np.abs(st.wm - wm_old)) < 1e-13 * abs(w):
                break
        return f

    u0 = np.array(result.ring_displacement, float)
    k = np.empty((5, 5))
    for j in range(5):
        du = np.zeros(5)
        du[j] = step[0] if j < 3 else step[1]
        k[:, j] = -(ring_force(u0 + du) - ring_force(u0 - du)) / (2.0 * du[j])
    return k
