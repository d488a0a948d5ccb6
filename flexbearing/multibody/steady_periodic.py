"""The steady running state under a combined load as a periodic orbit of the dynamics (shooting).

Under a space-fixed radial load (or weight) the Z identical balls meet the load at different
azimuths, so the running state is not an equilibrium in any frame: it is periodic at the ball-pass
period. After T = (2 pi / Z) / |mean cage speed| every ball is where its neighbour was, the cage
has turned one pocket pitch and the inner ring (axisymmetric, its spin angle cyclic) is back:

    Phi_T(y0) = S(y0),                                                              (1)

Phi_T the flow of `flexbearing.multibody.dynamics.rhs` over T (constant speed and load), S the
ball-pass shift (`ball_pass_shift`): ball j takes ball j+d's state (d = sign of the cage speed),
its azimuth advanced by one pitch, the cage angle advanced by d·2 pi/Z. This is a periodic orbit
of a system with a discrete symmetry (a relative periodic orbit of the Z_Z action that renumbers
the balls): Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer 2010,
§7.1–7.3 (shooting, the monodromy matrix, Floquet multipliers); Doedel, Keller & Kernevez,
"Numerical analysis and control of bifurcation problems (II)", Int. J. Bifurcation Chaos 1(4):745,
1991 (boundary-value formulation with a phase condition).

Unknowns: the state y0 without the cyclic inner-ring spin angle (RING_PHI: no force depends on it,
`dynamics.rhs` only integrates it) and without the cage angle CAGE_PHI, which is fixed to its start
value (the phase condition: it removes the time translation; it is transversal because the cage
turns, d(CAGE_PHI)/dt = omega_c != 0), plus the period T. Equations: (1) in every component but
RING_PHI. As many equations as unknowns (n − 1).

Phi_T is a fixed-step Dormand–Prince 5(4) of N steps, h = T/N (its 5th-order weights; Hairer,
Nørsett & Wanner, Solving ODEs I, §II.5), so that the map (y0, T) -> Phi_T(y0) is smooth (an
adaptive step choice is not differentiable in y0). N comes from the project's adaptive integrator
over one period at the same state and tolerance (its accepted steps, with a margin); the residual
of the orbit at 2N steps says how far the discretisation moves it (`PeriodicOrbit.residual_2n`).

Solved by a trust-region Gauss–Newton method on |R|² (`shoot`; Branch, Coleman & Li 1999; Allgower
& Georg, *Introduction to Numerical Continuation Methods*, SIAM 2003, for Newton on shooting
equations). The Jacobian's columns are those of the monodromy matrix M = dPhi_T/dy0 (forward
differences), minus the linear part P of S, and dPhi_T/dT.

Stability: the Floquet multipliers are the eigenvalues of P^-1 M (Seydel §7.2; for an orbit with a
symmetry S the return map is S^-1 ∘ Phi_T). One multiplier is 1 (the time shift: the orbit's own
direction f(y0)); the orbit attracts nearby states when every other |mu| < 1, i.e. it is the held
running state the dynamics settle to; any |mu| > 1 means the bearing does not stay there.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from flexbearing.multibody import dynamics as D
from flexbearing.multibody import integrator as I
from flexbearing.multibody import model as M
from flexbearing.multibody import outputs as O
from flexbearing.multibody import state_layout as SL

# the orbit's convergence: the largest scaled component of Phi_T(y0) − S(y0) (scale: the integrator's
# error scales, model._error_scales, 1e-4 m for positions). 1e-8 puts the solver's error far below the
# fixed-step discretisation's own (the residual at 2N steps, 1.3e-4 on the clearance-free paper case),
# so the orbit is that of the discretised flow to its accuracy; the Newton budget; the FD step (scaled)
ORBIT_TOL = 1e-8
ORBIT_MAX_ITER = 15    # Jacobians (the paper case reaches its floor within 8)
FD_STEP = 1e-6
# the trivial multiplier (exactly 1 on the orbit) must come out within this of 1, else the monodromy
# matrix is too inaccurate to judge stability: central differences of step FD_STEP have an error
# O(FD_STEP²·|d³Phi|), measured 1e-4 on the clearance-free paper case (forward differences: 1e-3)
TRIVIAL_TOL = 1e-3


@njit(cache=True, nogil=True)
def _rk_fixed(y, h, n_steps, A, C, p, flags, htab, ttab, sp, ld, imp, work, cage, K, ytmp, Ys):
    """N fixed steps of an explicit FSAL Runge–Kutta (A: its tableau, last row = the weights) of
    `dynamics.rhs` from t = 0, in place; Ys[k] receives the state after k steps when Ys has rows.
    Returns 0, or 1 where a state is non-finite (no error control: Hairer, Nørsett & Wanner §II.1)."""
    n = y.shape[0]
    s = A.shape[0]
    t = 0.0
    if Ys.shape[0] > 0:
        Ys[0, :] = y
    D.rhs(t, y, K[0], p, flags, htab, ttab, sp, ld, imp, work, cage)
    for k in range(n_steps):
        for i in range(1, s):
            for q in range(n):
                acc = y[q]
                for j in range(i):
                    if A[i, j] != 0.0:
                        acc += h * A[i, j] * K[j, q]
                ytmp[q] = acc
            D.rhs(t + C[i] * h, ytmp, K[i], p, flags, htab, ttab, sp, ld, imp, work, cage)
        for q in range(n):
            y[q] = ytmp[q]
            K[0, q] = K[s - 1, q]
            if not math.isfinite(y[q]):
                return 1
        t += h
        if Ys.shape[0] > 0:
            Ys[k + 1, :] = y
    return 0


def fixed_step_flow(f, n_steps: int):
    """flow(y0, T) -> Phi_T(y0) of the autonomous ODE y' = f(y) by N fixed steps of Dormand–Prince's
    5th-order tableau (the arithmetic of `_rk_fixed`, in Python: for small systems and tests)."""
    A = I._DP_A

    def flow(y0, T):
        h = T / n_steps
        y = np.array(y0, dtype=float)
        K = [None] * A.shape[0]
        K[0] = f(y)
        for _ in range(n_steps):
            for i in range(1, A.shape[0]):
                yt = y + h * sum(A[i, j] * K[j] for j in range(i) if A[i, j] != 0.0)
                K[i] = f(yt)
            y, K[0] = yt, K[-1]
        return y
    return flow


def bearing_flow(model, speed_rad_s: float, load, n_steps: int):
    """flow(y0, T, keep=False) -> Phi_T(y0) (and the N + 1 states when keep): `_rk_fixed` with
    Dormand–Prince's 5th-order tableau over [0, T] at constant speed and load = (Fx, Fy, Fz) N."""
    sp = np.array([[0.0, float(speed_rad_s)]])
    ld = np.array([[0.0, *np.asarray(load, dtype=float)]])
    imp = np.zeros((0, 6))
    A, C = I._DP_A, I._DP_C
    K = np.zeros((A.shape[0], model.n_state))
    ytmp = np.zeros(model.n_state)
    work = D.new_work(model)
    none = np.zeros((0, model.n_state))

    def flow(y0, T, keep=False):
        y = np.array(y0, dtype=float)
        Ys = np.zeros((n_steps + 1, y.size)) if keep else none
        code = _rk_fixed(y, T / n_steps, n_steps, A, C, model.p, model.flags, model.hertz_table,
                         model.traction_table, sp, ld, imp, work, model.cage, K, ytmp, Ys)
        if code != 0:
            raise FloatingPointError(f"the fixed-step flow over T = {T:.4e} s in {n_steps} steps left the finite range")
        return (y, Ys) if keep else y
    return flow


def ball_pass_shift(y: np.ndarray, z: int, direction: int, c0: int) -> np.ndarray:
    """S(y) of (1): ball j's slots take ball (j + d) mod Z's, its azimuth psi wrapped to the one nearest
    psi_j + d·2 pi/Z (the ball behind moves into this ball's place), the cage angle advanced by
    d·2 pi/Z; every other slot unchanged. d = ±1, the sense of the cage's rotation. Balls are numbered
    in the sense of increasing azimuth (pocket j at cage angle + 2 pi j/Z)."""
    out = np.array(y, dtype=float)
    pitch = 2.0 * math.pi / z
    for j in range(z):
        src = (j + direction) % z
        o, s = SL.ball_offset(j), SL.ball_offset(src)
        out[o:o + SL.BALL_STATE] = y[s:s + SL.BALL_STATE]
        psi = y[s + SL.BALL_PSI]
        expected = y[o + SL.BALL_PSI] + direction * pitch
        out[o + SL.BALL_PSI] = psi + 2.0 * math.pi * round((expected - psi) / (2.0 * math.pi))
    out[c0 + SL.CAGE_PHI] += direction * pitch
    return out


@dataclass
class Shooting:
    """The shooting problem (1) in scaled coordinates: flow(y, T), shift(y), the scale of each state
    slot, the slots held fixed (phase condition, cyclic) and the equations left out (cyclic)."""
    flow: object
    shift: object
    scale: np.ndarray
    fixed: np.ndarray         # indices of y not solved for
    ignored: np.ndarray       # indices of y whose equation is dropped

    def __post_init__(self):
        n = self.scale.size
        self.eqs = np.setdiff1d(np.arange(n), self.ignored)
        self.free = np.setdiff1d(np.arange(n), self.fixed)

    def residual(self, y, T):
        """(R, Phi_T(y)): R = (Phi_T(y) − S(y)) / scale over the equations kept."""
        yT = self.flow(y, T)
        return (yT - self.shift(y))[self.eqs] / self.scale[self.eqs], yT

    def linearisation(self, y, T, yT, central: bool = False):
        """(Mon, P, dT) in scaled coordinates over the kept slots (self.eqs): the monodromy matrix
        dPhi_T/dy0 and the linear part of S by forward differences (step FD_STEP·scale; central
        differences, error O(FD_STEP²) instead of O(FD_STEP), for the monodromy where `central`), and
        dPhi_T/dT."""
        idx = self.eqs
        m = idx.size
        mon, pm = np.empty((m, m)), np.empty((m, m))
        s0 = self.shift(y)
        for k, i in enumerate(idx):
            e = y.copy()
            e[i] += FD_STEP * self.scale[i]
            if central:
                b = y.copy()
                b[i] -= FD_STEP * self.scale[i]
                mon[:, k] = (self.flow(e, T) - self.flow(b, T))[idx] / self.scale[idx] / (2.0 * FD_STEP)
            else:
                mon[:, k] = (self.flow(e, T) - yT)[idx] / self.scale[idx] / FD_STEP
            pm[:, k] = (self.shift(e) - s0)[idx] / self.scale[idx] / FD_STEP
        dT = FD_STEP * T
        d_t = (self.flow(y, T + dT) - yT)[idx] / self.scale[idx] / dT
        return mon, pm, d_t

    def jacobian(self, mon, pm, d_t, T):
        """dR/d(free slots (scaled), T/T_k) from the linearisation at period T."""
        cols = np.searchsorted(self.eqs, self.free)
        return np.column_stack([(mon - pm)[:, cols], d_t * T])


def shoot(problem: Shooting, y0: np.ndarray, T0: float, tol: float = ORBIT_TOL, max_iter: int = ORBIT_MAX_ITER,
          cpu_budget: float = math.inf, log=None) -> dict:
    """Solve (1) from (y0, T0) in the unknowns v = ((y − y0)/scale on the free slots, T/T0 − 1) by a
    trust-region Gauss–Newton (scipy's "trf": Branch, Coleman & Li, SIAM J. Sci. Comput. 21(1):1–23,
    1999; Moré 1978 for the trust-region step) with the finite-difference Jacobian of
    `Shooting.linearisation` at every iteration; it stops where max |R| <= tol, after max_iter Jacobians
    or past cpu_budget CPU-s. A line-searched Newton with Broyden updates was tried first: on the paper
    bearing it stalled at max |R| 0.17 where the trust region reaches 1.5e-3. Returns dict(converged, y,
    period, residual (max |R|), iterations (residual evaluations), jacobians, history (max |R| of each
    evaluation), cpu_s)."""
    from scipy.optimize import least_squares
    t0 = time.process_time()
    y0, T0 = np.array(y0, dtype=float), float(T0)
    free, sc = problem.free, problem.scale[problem.free]
    hist, best, flows, n_jac = [], [math.inf, None], {}, [0]

    class Done(Exception):
        pass

    def unpack(v):
        y = y0.copy()
        y[free] += v[:-1] * sc
        return y, T0 * (1.0 + v[-1])

    def fun(v):
        y, T = unpack(v)
        try:
            R, yT = problem.residual(y, T)
        except FloatingPointError:
            return np.full(problem.eqs.size, 1e6)
        flows[v.tobytes()] = yT
        r = float(np.max(np.abs(R)))
        hist.append(r)
        if r < best[0]:
            best[:] = [r, v.copy()]
        if log is not None:
            log(len(hist), r, T)
        if r <= tol or time.process_time() - t0 > cpu_budget:
            raise Done
        return R

    def jac(v):
        if n_jac[0] >= max_iter:
            raise Done
        n_jac[0] += 1
        y, T = unpack(v)
        yT = flows.get(v.tobytes())
        mon, pm, d_t = problem.linearisation(y, T, problem.flow(y, T) if yT is None else yT)
        return problem.jacobian(mon, pm, d_t, T0)

    try:
        least_squares(fun, np.zeros(free.size + 1), jac=jac, method="trf", x_scale=1.0, xtol=1e-15, ftol=1e-15,
                      gtol=1e-15, max_nfev=20 * max_iter)
    except Done:
        pass
    y, T = unpack(best[1]) if best[1] is not None else (y0, T0)
    return dict(converged=best[0] <= tol, y=y, period=T, residual=best[0], iterations=len(hist),
                jacobians=n_jac[0], history=hist, cpu_s=time.process_time() - t0)


def floquet_multipliers(mon: np.ndarray, pm: np.ndarray, vectors: bool = False):
    """(mu, k): the eigenvalues of P^-1·M (module docstring), sorted by decreasing modulus, and the
    index of the trivial one (nearest 1); with `vectors`, (mu, k, V) with the eigenvectors V[:, i]."""
    mu, V = np.linalg.eig(np.linalg.solve(pm, mon))
    o = np.argsort(-np.abs(mu))
    mu, V = mu[o], V[:, o]
    k = int(np.argmin(np.abs(mu - 1.0)))
    return (mu, k, V) if vectors else (mu, k)


_BALL_SLOTS = ("x", "r", "azimuth", "x'", "r'", "orbital speed", "w_x", "w_r", "w_t")
_RING_SLOTS = ("x", "y", "z", "tilt y", "tilt z", "x'", "y'", "z'", "tilt y'", "tilt z'", "spin angle")
_CAGE_SLOTS = ("x", "y", "z", "angle", "tilt y", "tilt z", "x'", "y'", "z'", "speed", "tilt y'", "tilt z'")


def slot_name(z: int, i: int) -> str:
    """The bearing engineer's name of state slot i (state_layout) of a rigid-cage bearing of z balls."""
    if i < SL.ring_offset(z):
        return f"ball {i // SL.BALL_STATE} {_BALL_SLOTS[i % SL.BALL_STATE]}"
    if i < SL.cage_offset(z):
        return f"inner ring {_RING_SLOTS[i - SL.ring_offset(z)]}"
    return f"cage {_CAGE_SLOTS[i - SL.cage_offset(z)]}"


def _leading_mode(z: int, eqs: np.ndarray, v: np.ndarray) -> str:
    """The slots that carry a Floquet mode (|component| >= half the largest, at most four)."""
    a = np.abs(v) / np.max(np.abs(v))
    top = [i for i in np.argsort(-a)[:4] if a[i] >= 0.5]
    return ", ".join(slot_name(z, int(eqs[i])) for i in top)


# fixed steps per period: the adaptive integrator's accepted steps over one period at its default
# tolerance, times this margin (its steps vary over the period; the fixed step must stay inside the
# explicit method's stability region everywhere)
STEP_MARGIN = 2.0


@dataclass(frozen=True)
class PeriodicOrbit:
    """The ball-pass periodic orbit (module docstring) and what the bearing does on it."""
    converged: bool
    stable: bool                   # every nontrivial |mu| < 1
    period: float                  # s
    state: np.ndarray = field(repr=False)   # y0: a state of the dynamics on the orbit (start a run from it)
    residual: float = math.nan     # max scaled |Phi_T(y0) − S(y0)|
    residual_2n: float = math.nan  # the same with 2N steps: the discretisation's share
    steps: int = 0                 # N fixed steps per period
    iterations: int = 0            # Newton iterations
    jacobians: int = 0             # finite-difference Jacobians
    floquet_multipliers: np.ndarray = field(default=None, repr=False)   # sorted by decreasing |mu|
    trivial_multiplier: complex = math.nan      # the one nearest 1 (the time shift: a check)
    largest_multiplier: float = math.nan        # the largest nontrivial |mu|
    cage_speed_mean: float = math.nan          # rad/s, over the period
    cage_speed_range: tuple = (math.nan, math.nan)
    slip_rate_mean: float = math.nan           # outputs' slip_rate (1 = 100 %), mean over the period
    eccentricity_mean: float = math.nan        # cage eccentricity ratio
    eccentricity_range: tuple = (math.nan, math.nan)
    pocket_force_mean: float = math.nan        # N, over balls and period
    pocket_force_max: float = math.nan
    leading_mode: str = ""                      # the slots of the largest nontrivial multiplier's mode
    cpu_s: float = 0.0
    note: str = ""

    def describe(self) -> str:
        if not self.converged:
            return f"no ball-pass periodic orbit found ({self.note})"
        what = "a stable" if self.stable else "an unstable (or, within the monodromy's accuracy, neutral)"
        return (f"{what} ball-pass periodic orbit: period {1e3 * self.period:.4f} ms, residual {self.residual:.1e} "
                f"({self.residual_2n:.1e} at 2N = {2 * self.steps} steps), largest nontrivial Floquet multiplier "
                f"|mu| = {self.largest_multiplier:.4f} ({self.leading_mode}), trivial {abs(self.trivial_multiplier):.5f}; cage "
                f"{self.cage_speed_mean:.2f} rad/s ({self.cage_speed_range[0]:.2f}–{self.cage_speed_range[1]:.2f}), "
                f"slip {100 * self.slip_rate_mean:.3f} %, eccentricity ratio {self.eccentricity_mean:.3f}; "
                f"{self.iterations} residual evaluations, {self.jacobians} Jacobians, {self.cpu_s:.1f} CPU-s")


def _normalised(model, y) -> np.ndarray:
    """y with every ball azimuth and the cage angle shifted by the same multiple of 2 pi (the cage angle
    into [0, 2 pi)) and the inner ring's cyclic spin angle set to 0: the same state for the dynamics."""
    lay = M.state_layout(model)
    y = np.array(y, dtype=float)
    k = 2.0 * math.pi * math.floor(y[lay["cage"] + SL.CAGE_PHI] / (2.0 * math.pi))
    y[SL.BALL_PSI:lay["ring"]:SL.BALL_STATE] -= k
    y[lay["cage"] + SL.CAGE_PHI] -= k
    y[lay["ring"] + SL.RING_PHI] = 0.0
    return y


def _orbit_scale(model, y) -> np.ndarray:
    """The integrator's error scale at y (model._error_scales plus the relative part), the same for
    every ball (mean over the balls, slot by slot), so that S is a permutation in scaled coordinates."""
    z = model.n_balls
    s = model.scale + model.relmask * np.abs(y)
    b = s[:SL.ring_offset(z)].reshape(z, SL.BALL_STATE)
    s[:SL.ring_offset(z)] = np.tile(b.mean(axis=0), z)
    return s


def _first_guess(model, speed_rad_s, load, y) -> tuple[float, int, int]:
    """(T0, N, d) from the adaptive integrator over one ball-pass period from y: T0 = pitch / mean cage
    speed (from the cage angle's advance), N = STEP_MARGIN × its accepted steps, d the rotation sense."""
    lay = M.state_layout(model)
    c = lay["cage"]
    z = model.n_balls
    sp = np.array([[0.0, float(speed_rad_s)]])
    ld = np.array([[0.0, *np.asarray(load, dtype=float)]])
    w = y[c + SL.CAGE_OMEGA]
    t_guess = 2.0 * math.pi / z / abs(w)
    y1, _, _, n_acc, _ = I.advance(model, y.copy(), 0.0, t_guess, sp, ld, np.zeros((0, 6)))
    w_mean = (y1[c + SL.CAGE_PHI] - y[c + SL.CAGE_PHI]) / t_guess
    return 2.0 * math.pi / z / abs(w_mean), int(math.ceil(STEP_MARGIN * n_acc)), 1 if w_mean > 0.0 else -1


def bearing_shooting(model, speed_rad_s: float, load, n_steps: int, direction: int, y_ref) -> Shooting:
    """The shooting problem (1) of the bearing (rigid cage) at constant speed and load: fixed slots
    RING_PHI (cyclic) and CAGE_PHI (the phase condition), the RING_PHI equation dropped."""
    lay = M.state_layout(model)
    r, c = lay["ring"], lay["cage"]
    return Shooting(flow=bearing_flow(model, speed_rad_s, load, n_steps),
                    shift=lambda y: ball_pass_shift(y, model.n_balls, direction, c),
                    scale=_orbit_scale(model, y_ref), fixed=np.array([r + SL.RING_PHI, c + SL.CAGE_PHI]),
                    ignored=np.array([r + SL.RING_PHI]))


def periodic_orbit(model, speed_rad_s: float, load, y_start, tol: float = ORBIT_TOL,
                   max_iter: int = ORBIT_MAX_ITER, cpu_budget: float = 300.0) -> PeriodicOrbit:
    """The ball-pass periodic orbit (1) of the bearing (rigid cage, model with its weight) at constant
    speed and load = (Fx, Fy, Fz) N on the inner ring, by shooting from y_start (a state on or near
    the orbit, e.g. the dynamics settled: the shooting's Newton converges from inside its basin):
    module docstring. The Floquet multipliers come from a finite-difference monodromy matrix at the
    converged orbit; cpu_budget (s) bounds the Newton iterations."""
    t0 = time.process_time()
    if model.n_modes != 0:
        raise ValueError("the periodic orbit is for a rigid cage (n_modes = 0)")
    y = _normalised(model, y_start)
    try:
        T0, n_steps, d = _first_guess(model, speed_rad_s, load, y)
    except I.SimulationUnstable as e:
        return PeriodicOrbit(False, False, math.nan, y, note=f"the dynamics from the start: {str(e).splitlines()[0]}",
                             cpu_s=time.process_time() - t0)
    problem = bearing_shooting(model, speed_rad_s, load, n_steps, d, y)
    try:
        sol = shoot(problem, y, T0, tol, max_iter, cpu_budget)
    except FloatingPointError as e:
        return PeriodicOrbit(False, False, T0, y, steps=n_steps, note=str(e), cpu_s=time.process_time() - t0)
    if not sol["converged"]:
        stats = _along_orbit(model, speed_rad_s, load, problem.flow, sol["y"], sol["period"])
        return PeriodicOrbit(False, False, sol["period"], sol["y"], sol["residual"], steps=n_steps,
                             iterations=sol["iterations"], jacobians=sol["jacobians"], cpu_s=time.process_time() - t0,
                             **stats, note=f"the trust-region solve of the shooting equations ended at residual "
                                           f"{sol['residual']:.1e} (tolerance {tol:.0e}; the start's {sol['history'][0]:.1e}) "
                                           f"after {sol['jacobians']} Jacobians; there the state's mean slip over a period "
                                           f"is {100 * stats['slip_rate_mean']:.3f} %, cage {stats['cage_speed_mean']:.2f} rad/s")
    y0, T = sol["y"], sol["period"]
    _, yT = problem.residual(y0, T)
    mon, pm, _ = problem.linearisation(y0, T, yT, central=True)
    mu, k, V = floquet_multipliers(mon, pm, vectors=True)
    others = np.delete(np.abs(mu), k)
    lead = 1 if k == 0 else 0
    mode = _leading_mode(model.n_balls, problem.eqs, V[:, lead])
    # the monodromy's own error, read off the trivial multiplier (exactly 1 on the orbit): a multiplier
    # within it of the unit circle is not judged stable
    err = abs(mu[k] - 1.0)
    fine = bearing_shooting(model, speed_rad_s, load, 2 * n_steps, d, y)
    res2 = float(np.max(np.abs(fine.residual(y0, T)[0])))
    stats = _along_orbit(model, speed_rad_s, load, problem.flow, y0, T)
    trivial_ok = err < TRIVIAL_TOL
    return PeriodicOrbit(True, bool(others.max() < 1.0 - err and trivial_ok), T, y0, sol["residual"], res2, n_steps,
                         sol["iterations"], sol["jacobians"] + 1, mu, complex(mu[k]), float(others.max()),
                         cpu_s=time.process_time() - t0, **stats, leading_mode=mode,
                         note="" if trivial_ok else f"the trivial multiplier is {mu[k]:.4f}, not 1: the monodromy "
                                                    "matrix is not accurate enough to judge stability")


def _along_orbit(model, speed_rad_s: float, load, flow, y0, T) -> dict:
    """Means and ranges over the period of the outputs at the N states of the fixed-step flow
    (uniform in time: their plain mean is the trapezoidal rule of a periodic function)."""
    sp = np.array([[0.0, float(speed_rad_s)]])
    ld = np.array([[0.0, *np.asarray(load, dtype=float)]])
    imp = np.zeros((0, 6))
    _, Ys = flow(y0, T, keep=True)
    w, slip, eps, pk = [], [], [], []
    for k in range(Ys.shape[0] - 1):
        out = O.evaluate_outputs(model, k * T / (Ys.shape[0] - 1), Ys[k], sp, ld, imp)
        w.append(out["cage_speed"])
        slip.append(out["slip_rate"])
        eps.append(out["cage_eccentricity_ratio"])
        pk.append(np.asarray(out["pocket_force"], dtype=float))
    pk = np.array(pk)
    return dict(cage_speed_mean=float(np.mean(w)), cage_speed_range=(float(min(w)), float(max(w))),
                slip_rate_mean=float(np.mean(slip)), eccentricity_mean=float(np.mean(eps)),
                eccentricity_range=(float(min(eps)), float(max(eps))), pocket_force_mean=float(pk.mean()),
                pocket_force_max=float(pk.max()))
