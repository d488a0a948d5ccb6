"""Time integration of the bearing equations: adaptive explicit Runge–Kutta, compiled with numba.

`advance(model, y, t, t_next, speed_table, load_table, impacts, tol, h)` integrates
`flexbearing.multibody.dynamics.rhs` from t to t_next and returns (y, t, h, n_steps, n_rejected); h is the
step size to continue with. `advance_sampled(..., sample_times, ...)` also returns the states at
sample times inside (t, t_next): the run loop (flexbearing.simulation.run) calls it for a few dozen samples at a
time and stops only at a checkpoint, a breakpoint of the spectra or the end.

Samples. The states at the sample times come from the method's continuous extension over the
step that passes them (`_dense_state`: Dormand–Prince's of order 4, Hairer, Nørsett & Wanner,
Solving ODEs I, §II.6; the cubic Hermite for BS32); the steps are not shortened to land on them.
Stopping at every sample instead cost the paper's steady scenes ~20 % more steps at tol 1e-4 (a
shortened step per 0.1 ms sample interval on ~6.6 steps, and a fresh step-size ramp after it;
benchmarks/results/speed.md). With the stress monitor, each sample receives the peak
over the steps that ended after the previous sample and up to it.

Method (chosen by measurement, benchmarks/bench_integrator.py, results in
benchmarks/results/integrator_work_precision.md): Dormand–Prince 5(4) with FSAL and a PI
step-size controller (Hairer, Nørsett & Wanner, Solving ODEs I, §II.4–5; Gustafsson's PI
controller, beta = 0.04). Kept for comparison: Bogacki–Shampine 3(2) (method="bs32").

Why explicit and not implicit / splitting: the system is stiff only mildly. Its fastest modes are
the ball–race Hertz vibrations (~10–15 kHz at kN loads, 4 kHz at 100 N), the inner-ring and
tilt modes on the same contacts (comparable), the ball–pocket impacts (the pocket turns from
the soft linear spring Kc = 11/Cp to a stiff Hertz contact at Z = Cp) and the relaxation of the
ball spin under EHL traction (1e-4–1e-3 s with the regularised curve, model docstring). An
explicit RK whose stability bound sits at h ~ 2e-5 s is therefore limited by physics that must
be resolved anyway (ball load oscillations and pocket impacts are outputs; an implicit method
would take larger steps only by damping them out), while one RHS costs ~60 us and a Newton
iteration with a 203x203 Jacobian would cost tens of RHS evaluations per step. A semi-explicit
splitting (contact forces frozen over a step, as in SKF-style codes) needs the same step for the
same contact frequencies and gives up error control. Measured (0.005 s of the paper's steady
case, full model, against a tol-1e-10 reference that a BS32 tol-1e-9 run confirms to 2e-5):
at the default tol 1e-6 DOPRI5 takes 465 steps (0.19 s) for a weighted state error 2.5e-3 and a
ball-load error 4e-4 of the mean outer load; BS32 needs tol 1e-5 and 678 steps for the same
accuracy (0.18 s): equal cost at engineering accuracy. At tighter tolerances BS32 reaches
6e-5 with 3214 steps (1.05 s) where DOPRI5 gives 4e-4 at tol 1e-8 (1275 steps, 0.62 s): the
pocket impacts and the kinks of the traction law (clipping, regularisation) cost DOPRI5 its
high order. DOPRI5 stays the default for its fewer steps at the tolerances used for runs
(1e-6 ... 1e-5) and its smoother step sequence through ramps and impacts; the paper's
0.6-s steady scene takes 66.6k steps (~28 s wall, benchmarks/results/steady_rigid.md).

Error norm: RMS over the state of err_i/(tol·(scale_i + relmask_i·max(|y_i|, |y_new,i|))), with
the absolute scales of `flexbearing.multibody.model._error_scales` (1e-4 m for positions, ...), so `tol` is
a single dimensionless number (default 1e-6).

Instability: after each accepted step the state must be finite and the RHS evaluated there must
not flag a contact beyond its plausible range (dynamics.STATUS_*); the step size must stay above
1e-12 s. Otherwise `advance` raises `SimulationUnstable` naming the ball, the contact and the time.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from flexbearing.multibody import dynamics as D
from flexbearing.multibody import outputs as O
from flexbearing.multibody import model as M
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.stress_peak import (MON_PEAK, MON_Y_PEAK, disabled_monitor, peak_of, stress_peak_step,
                                              take_peak)

DEFAULT_TOL = 1e-6
H_MIN = 1e-12
H_MAX = 1e-3

# ---- Dormand–Prince 5(4) tableau
_DP_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_DP_A = np.zeros((7, 7))
_DP_A[1, 0] = 1 / 5
_DP_A[2, :2] = [3 / 40, 9 / 40]
_DP_A[3, :3] = [44 / 45, -56 / 15, 32 / 9]
_DP_A[4, :4] = [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729]
_DP_A[5, :5] = [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656]
_DP_A[6, :6] = [35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84]
_DP_B = _DP_A[6].copy()
_DP_E = _DP_B - np.array([5179 / 57600, 0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40])
# ---- Bogacki–Shampine 3(2) tableau (FSAL, 4 stages)
_BS_C = np.array([0.0, 0.5, 0.75, 1.0])
_BS_A = np.zeros((4, 4))
_BS_A[1, 0] = 0.5
_BS_A[2, :2] = [0.0, 0.75]
_BS_A[3, :3] = [2 / 9, 1 / 3, 4 / 9]
_BS_B = _BS_A[3].copy()
_BS_E = _BS_B - np.array([7 / 24, 1 / 4, 1 / 3, 1 / 8])
METHODS = {"dopri5": (_DP_A, _DP_B, _DP_C, _DP_E, 5), "bs32": (_BS_A, _BS_B, _BS_C, _BS_E, 3)}

# return codes of the compiled loop
OK, UNSTABLE_STATUS, UNSTABLE_NONFINITE, STEP_TOO_SMALL, TOO_MANY_STEPS = 0, 1, 2, 3, 4


class SimulationUnstable(RuntimeError):
    """The integration left the physically plausible range; the message names ball, contact, time."""

    repeats_on_resume = True     # deterministic: a resume from the last checkpoint meets it again

    def __init__(self, message: str, t: float, ball: int | None, contact: str | None):
        super().__init__(message)
        self.t = t
        self.ball = ball
        self.contact = contact


@njit(cache=True, nogil=True)
def _error_norm(y, ytmp, K, E, h, tol, scale, relmask):
    """(err, finite) of a step from y to ytmp (`_rk_loop`): the RMS over the state of the error
    estimate h·Σ_j E_j·K_j scaled by tol·(scale + relmask·max(|y|, |ytmp|)) (Hairer, Nørsett &
    Wanner, Solving ODE I, 1993, §II.4, eq. 4.11), and whether ytmp and the last stage are finite
    (err = 1e10 when not)."""
    n = y.shape[0]
    s = K.shape[0]
    err = 0.0
    finite = True
    for q in range(n):
        e = 0.0
        for j in range(s):
            if E[j] != 0.0:
                e += E[j] * K[j, q]
        e *= h
        a = abs(y[q])
        b = abs(ytmp[q])
        if b > a:
            a = b
        sc = tol * (scale[q] + relmask[q] * a)
        r = e / sc
        err += r * r
        if not math.isfinite(ytmp[q]) or not math.isfinite(K[s - 1, q]):
            finite = False
    err = math.sqrt(err / n)
    if not finite:
        err = 1e10
    return err, finite


@njit(cache=True, nogil=True)
def _rk_loop(y, t, t_end, h, tol, A, B, C, E, order, p, flags, htab, ttab, sp, ld, imp,
             work, scale, relmask, K, ytmp, ynew, max_steps, cage, mon, ts, Ys, Pk, Ypk, n_out, h_max):
    """Adaptive explicit RK (FSAL tableau A, weights B, error weights E) from t to t_end, in place.

    h_max: the largest step, s (the error controller's new step is clipped to it, as the
    `hmax` of Hairer & Wanner's DOPRI5; the scene's integrator.max_step, else H_MAX).

    K: (n_stages, n) stage derivatives; K[0] must hold f(t, y) on entry (FSAL) and holds f at the
    returned state on exit. mon: the cage stress monitor (flexbearing.multibody.stress_peak), evaluated at
    every accepted state. Returns (t, h, n_acc, n_rej, code).

    Samples inside the interval (module docstring, "Samples"): ts, ascending times in (t, t_end);
    the step that passes ts[i] writes the state there by the method's continuous extension
    (`_dense_state`) into Ys[i] and the monitor's peak since the previous sample into Pk[i]
    (peak (4,)) and Ypk[i] (its load-space y), then empties the peak; n_out[0] counts them. The
    steps are not shortened to land on a sample: only t_end is hit exactly.
    """
    n = y.shape[0]
    s = A.shape[0]
    zb = work.shape[0] - 1
    n_acc = 0
    n_rej = 0
    err_old = 1e-4
    expo = 1.0 / order
    beta = 0.04
    n_ts = ts.shape[0]
    i_s = 0
    n_out[0] = 0
    peak = mon[MON_PEAK]
    y_peak = mon[MON_Y_PEAK]
    if h > h_max:
        h = h_max
    while t < t_end:
        if n_acc + n_rej >= max_steps:
            return t, h, n_acc, n_rej, TOO_MANY_STEPS
        last = False
        if t + h >= t_end:
            h = t_end - t
            last = True
        for i in range(1, s):
            for q in range(n):
                acc = y[q]
                for j in range(i):
                    aij = A[i, j]
                    if aij != 0.0:
                        acc += h * aij * K[j, q]
                ytmp[q] = acc
            if i == s - 1:
                work[zb, M.WR_STATUS] = 0.0  # reset the status before the FSAL stage (at the new state)
            D_rhs(t + C[i] * h, ytmp, K[i], p, flags, htab, ttab, sp, ld, imp, work, cage)
        # the last stage state is the 5th-order solution (FSAL): ytmp
        err, finite = _error_norm(y, ytmp, K, E, h, tol, scale, relmask)
        if err <= 1.0:
            # accept
            t_new = t_end if last else t + h
            # samples this step passed: the continuous extension between y and ytmp (before y
            # and K[0] are overwritten); a sample's stress peak ends before this step's state
            while i_s < n_ts and ts[i_s] < t_new:
                _dense_state((ts[i_s] - t) / h, h, y, ytmp, K, order, Ys[i_s])
                take_peak(peak, y_peak, Pk[i_s], Ypk[i_s])
                i_s += 1
            for q in range(n):
                y[q] = ytmp[q]
                K[0, q] = K[s - 1, q]
            t = t_new
            n_acc += 1
            # the FSAL stage was evaluated at this state: the cage's node loads are current
            stress_peak_step(t, y, cage, mon)
            while i_s < n_ts and ts[i_s] <= t:        # a sample exactly at this step's end
                for q in range(n):
                    Ys[i_s, q] = y[q]
                take_peak(peak, y_peak, Pk[i_s], Ypk[i_s])
                i_s += 1
            n_out[0] = i_s
            if work[zb, M.WR_STATUS] != 0.0:
                return t, h, n_acc, n_rej, UNSTABLE_STATUS
            e1 = err if err > 1e-10 else 1e-10
            fac = 0.9 * e1 ** (-(expo - 0.75 * beta)) * err_old ** beta
            if fac > 4.0:
                fac = 4.0
            if fac < 0.2:
                fac = 0.2
            err_old = e1
            if not last:
                h = h * fac
            if h > h_max:
                h = h_max
        else:
            n_rej += 1
            fac = 0.9 * err ** (-expo)
            if fac < 0.1 or not math.isfinite(fac):
                fac = 0.1
            if fac > 0.9:
                fac = 0.9
            h = h * fac
            if h < 1e-12:
                if not finite:
                    return t, h, n_acc, n_rej, UNSTABLE_NONFINITE
                return t, h, n_acc, n_rej, STEP_TOO_SMALL
    return t, h, n_acc, n_rej, OK


# Dormand–Prince's continuous extension of order 4 (Hairer, Nørsett & Wanner, Solving ODEs I,
# §II.6, and their code DOPRI5, CONTD5): the coefficients of the stages in the θ²(1−θ)² term
_DP_D = np.array([-12715105075.0 / 11282082432.0, 0.0, 87487479700.0 / 32700410799.0,
                  -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0,
                  -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0])


@njit(cache=True, nogil=True)
def _dense_state(theta, h, y0, y1, K, order, out):
    """The state at t + θh, 0 <= θ <= 1, of the step y0 → y1 of size h with stages K (K[-1] = f(y1)).

    Order 5 (Dormand–Prince, 7 stages), the continuous extension of order 4 (Hairer, Nørsett &
    Wanner, Solving ODEs I, 2nd ed., §II.6, dense output of DOPRI5):

        y(t + θh) = y0 + θ(Δ + (1−θ)(r3 + θ(r4 + (1−θ) r5))),
        Δ = y1 − y0,  r3 = h k1 − Δ,  r4 = Δ − h k7 − r3,  r5 = h Σ d_i k_i  (_DP_D);

    otherwise (Bogacki–Shampine 3(2)) the cubic Hermite interpolant of y0, y1, f(y0) = k1 and
    f(y1) = k_last (ibid. eq. (6.7)), of order 3:

        y(t + θh) = (1−θ) y0 + θ y1 + θ(θ−1)((1−2θ)Δ + (θ−1) h k1 + θ h k_last).
    """
    n = y0.shape[0]
    s = K.shape[0]
    th1 = 1.0 - theta
    if order == 5:
        for q in range(n):
            d = y1[q] - y0[q]
            r3 = h * K[0, q] - d
            r4 = d - h * K[6, q] - r3
            r5 = h * (_DP_D[0] * K[0, q] + _DP_D[2] * K[2, q] + _DP_D[3] * K[3, q]
                      + _DP_D[4] * K[4, q] + _DP_D[5] * K[5, q] + _DP_D[6] * K[6, q])
            out[q] = y0[q] + theta * (d + th1 * (r3 + theta * (r4 + th1 * r5)))
    else:
        for q in range(n):
            d = y1[q] - y0[q]
            out[q] = (y0[q] + theta * d
                      + theta * (theta - 1.0) * ((1.0 - 2.0 * theta) * d + (theta - 1.0) * h * K[0, q]
                                                 + theta * h * K[s - 1, q]))


D_rhs = D.rhs
_DISABLED = disabled_monitor()


class Workspace:
    """Scratch arrays of one integration (allocated once per run, reused every call)."""

    def __init__(self, model, method: str = "dopri5"):
        if method not in METHODS:
            raise ValueError(f"integrator method {method!r} not in {sorted(METHODS)}")
        self.method = method
        A, B, C, E, order = METHODS[method]
        self.A, self.B, self.C, self.E, self.order = A, B, C, E, order
        n = model.n_state
        self.K = np.zeros((A.shape[0], n))
        self.ytmp = np.zeros(n)
        self.ynew = np.zeros(n)
        self.work = D.new_work(model)
        self.fsal_t = None   # time at which K[0] = f(t, y) is valid
        self.fsal_y = None
        self.n_out = np.zeros(1, dtype=np.int64)
        self._samples = (np.zeros((0, n)), np.zeros((0, 4)), np.zeros((0, 1)))

    def sample_buffers(self, m: int, k_peak: int) -> tuple:
        """(Ys (m, n), Pk (m, 4), Ypk (m, k_peak)): advance_sampled's outputs, views of buffers
        reused between calls (grown when a call needs more rows)."""
        Ys, Pk, Ypk = self._samples
        if Ys.shape[0] < m or Ypk.shape[1] != k_peak:
            cap = max(int(m), Ys.shape[0])
            Ys, Pk, Ypk = np.zeros((cap, Ys.shape[1])), np.zeros((cap, 4)), np.zeros((cap, int(k_peak)))
            self._samples = (Ys, Pk, Ypk)
        return Ys[:m], Pk[:m], Ypk[:m]


def advance(model, y, t, t_next, speed_table, load_table, impacts, tol: float = DEFAULT_TOL,
            h: float = 1e-6, ws: Workspace | None = None, max_steps: int = 10_000_000,
            method: str = "dopri5", monitor: tuple | None = None, max_step: float = H_MAX):
    """Advance the state from t to t_next (module docstring). Returns (y, t, h, n_steps, n_rejected).

    `y` is updated in place and returned. Pass the same Workspace between calls of one run to
    reuse the FSAL derivative and the scratch arrays. `monitor`: a cage stress monitor
    (flexbearing.multibody.stress_peak.new_monitor) evaluated after every accepted step. `max_step`:
    the largest step, s (H_MAX unless the scene sets integrator.max_step). Raises
    SimulationUnstable.
    """
    y, t1, h1, n_acc, n_rej, _, _ = advance_sampled(model, y, t, t_next, _NO_SAMPLES, speed_table,
                                                       load_table, impacts, tol, h, ws, max_steps,
                                                       method, monitor, max_step)
    return y, t1, h1, n_acc, n_rej


_NO_SAMPLES = np.zeros(0)


def advance_sampled(model, y, t, t_next, sample_times, speed_table, load_table, impacts,
                    tol: float = DEFAULT_TOL, h: float = 1e-6, ws: Workspace | None = None,
                    max_steps: int = 10_000_000, method: str = "dopri5", monitor: tuple | None = None,
                    max_step: float = H_MAX):
    """`advance` from t to t_next, writing the states at `sample_times` on the way (module
    docstring, "Samples"). sample_times: ascending, each in (t, t_next). Returns
    (y, t, h, n_steps, n_rejected, Ys, peaks): Ys (m, n) the states at the m sample times (the
    method's continuous extension inside a step; a view of the workspace's buffer: copy what must
    outlive the next call), peaks the stress monitor's peak over the steps since the previous
    sample for each (flexbearing.multibody.stress_peak.peak_of; None without a monitor or step)."""
    if not max_step > 0.0:
        raise ValueError(f"max_step must be > 0 s: {max_step!r}")
    if ws is None:
        ws = Workspace(model, method)
    y = np.ascontiguousarray(y, dtype=np.float64)
    ts = np.ascontiguousarray(sample_times, dtype=np.float64)
    if ts.size and not (ts[0] > t and ts[-1] < t_next and np.all(np.diff(ts) > 0.0)):
        raise ValueError(f"sample times must ascend strictly inside ({t!r}, {t_next!r}): "
                         f"{ts[0]!r} ... {ts[-1]!r}")
    mon = _DISABLED if monitor is None else monitor
    Ys, Pk, Ypk = ws.sample_buffers(ts.size, mon[MON_Y_PEAK].shape[0])
    if ws.fsal_t != t or ws.fsal_y is None or not np.array_equal(ws.fsal_y, y):
        ws.work[-1, M.WR_STATUS] = 0.0
        D.rhs(t, y, ws.K[0], model.p, model.flags, model.hertz_table, model.traction_table,
              speed_table, load_table, impacts, ws.work, model.cage)
    t1, h1, n_acc, n_rej, code = _rk_loop(y, float(t), float(t_next), float(h), float(tol), ws.A, ws.B, ws.C,
                                          ws.E, ws.order, model.p, model.flags, model.hertz_table,
                                          model.traction_table, speed_table, load_table, impacts,
                                          ws.work, model.scale, model.relmask, ws.K, ws.ytmp, ws.ynew,
                                          int(max_steps), model.cage, mon, ts, Ys, Pk, Ypk, ws.n_out,
                                          float(max_step))
    if code != OK:
        n = int(ws.n_out[0])
        try:
            _raise_unstable(model, code, y, ws, t1, h1, speed_table, load_table, impacts)
        except SimulationUnstable as exc:
            # the samples passed before the failure, for the run to keep: (times, states, peaks)
            exc.samples = (ts[:n].copy(), Ys[:n].copy(), [peak_of(Pk[i], Ypk[i]) for i in range(n)])
            raise
    if ws.n_out[0] != ts.size:          # every sample lies before t_next, which the loop reached
        raise RuntimeError(f"integrator wrote {ws.n_out[0]} of {ts.size} samples")
    ws.fsal_t = t1
    ws.fsal_y = y.copy()
    return y, t1, h1, n_acc, n_rej, Ys, [peak_of(Pk[i], Ypk[i]) for i in range(ts.size)]


def _raise_unstable(model, code, y, ws, t, h, speed_table, load_table, impacts):
    w = ws.work[-1]
    if code == UNSTABLE_STATUS:
        status = int(w[M.WR_STATUS])
        ball = int(w[M.WR_BAD_BALL])
        contact = D.CONTACT_NAMES[int(w[M.WR_BAD_CONTACT])]
        val = w[M.WR_BAD_VALUE]
        what = {D.STATUS_DEEP_RACE: f"approach {val * 1e6:.1f} um exceeds {D.DELTA_MAX_FRAC:g}·Dw",
                D.STATUS_DEEP_POCKET: f"penetration beyond the pocket clearance {val * 1e6:.1f} um",
                D.STATUS_RIM: f"cage eccentricity ratio {val:.2f} beyond the guide clearance"}.get(status, "")
        bname = f"ball {ball}" if ball >= 0 else "cage"
        raise SimulationUnstable(f"simulation unstable at t = {t:.6e} s: {bname}, {contact}: {what}; "
                                 f"{_likely_cause(status, t, load_table, impacts)}",
                                 t, ball if ball >= 0 else None, contact)
    # non-finite or step collapse: find the worst contact at the last accepted state
    ball, contact, detail = _worst_contact(model, t, y, speed_table, load_table, impacts)
    reason = {UNSTABLE_NONFINITE: "non-finite state", STEP_TOO_SMALL: f"step size collapsed to {h:.1e} s",
              TOO_MANY_STEPS: "step budget exhausted"}[code]
    raise SimulationUnstable(f"simulation unstable at t = {t:.6e} s ({reason}); most suspicious: ball {ball}, "
                             f"{contact} ({detail}); {_likely_cause(-code, t, load_table, impacts)}",
                             t, ball, contact)


def _likely_cause(status: int, t: float, load_table, impacts) -> str:
    """The likely cause of an instability, for the user (status: dynamics.STATUS_*, or minus the
    loop's return code for a non-finite state, a collapsed step or an exhausted step budget)."""
    from flexbearing.multibody.profiles import load_at
    f = np.zeros(3)
    load_at(t, load_table, impacts, f)
    load = f"the load on the inner ring is |F| = {np.linalg.norm(f):.4g} N at this instant"
    return "likely cause: " + {
        D.STATUS_DEEP_RACE: f"{load}, beyond what the Hertz contacts carry within the model "
                            f"(flexbearing.multibody.initial.check_contact_range gives a load's limit), or an impact too "
                            f"short for the integrator tolerance (tighten integrator.tolerance / max_step)",
        D.STATUS_DEEP_POCKET: "a ball–pocket collision too violent for the pocket law at this speed: tighten "
                              "integrator.tolerance or set integrator.max_step, or reduce the speed change rate",
        D.STATUS_RIM: "the cage left its guide clearance (the guide land's film cannot hold it at this speed, "
                      "oil and clearance)",
        -UNSTABLE_NONFINITE: f"a force beyond the explicit integrator's stability at this step; {load}: "
                             f"tighten integrator.tolerance or set integrator.max_step",
        -STEP_TOO_SMALL: f"a discontinuity or a contact too stiff for the step; {load}: "
                         f"check the load and speed profiles for jumps, tighten integrator.tolerance",
        -TOO_MANY_STEPS: "the step budget of one call of the integrator (up to flexbearing.simulation.run.SAMPLES_PER_CALL "
                         "samples) was exhausted: a stiff contact forces tiny steps (see the step rate), or "
                         "shorten output.sample_interval",
    }.get(status, "unknown")


def _worst_contact(model, t, y, speed_table, load_table, impacts):
    """Ball and contact with the largest approach relative to Dw (or the first non-finite value)."""
    z = model.n_balls
    if not np.all(np.isfinite(y)):
        bad = int(np.flatnonzero(~np.isfinite(y))[0])
        if bad < SL.ring_offset(z):
            return bad // SL.BALL_STATE, "ball state", f"state component {bad % SL.BALL_STATE} non-finite"
        return -1, "ring/cage state", f"state index {bad} non-finite"
    try:
        out = O.evaluate_outputs(model, t, y, speed_table, load_table, impacts)
    except Exception as exc:  # pragma: no cover - diagnostic path
        return -1, "unknown", repr(exc)
    rel = out["approach"] / model.p[M.P_DW]
    j, c = np.unravel_index(np.argmax(rel), rel.shape)
    pocket = (out["pocket_offset"] - model.p[M.P_CP]) / model.p[M.P_DW]
    jp = int(np.argmax(pocket))
    if pocket[jp] > rel[j, c]:
        return jp, "pocket", f"offset beyond clearance {pocket[jp] * model.p[M.P_DW] * 1e6:.1f} um"
    return int(j), D.CONTACT_NAMES[int(c)], f"approach {out['approach'][j, c] * 1e6:.1f} um, load {out['contact_load'][j, c]:.0f} N"
