"""The adaptive Runge–Kutta integrator: accuracy against an analytic impact, convergence with the
tolerance, restartability and the instability diagnostic."""
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody import model as M
from flexbearing.multibody.model import build_model
from flexbearing.multibody.initial import initial_state
from flexbearing.multibody import integrator as I
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import outputs as O

OFF = {"traction": False, "drag": False, "damping": False, "hertz_fixed_angle": True}
IMP = np.zeros((0, 6))


def _impact_setup(v0):
    # K at the current angle (alpha stays 0 in a purely radial impact)
    m = build_model(PAPER_BEARING.with_(radial_clearance=100e-6), PAPER_OIL, dict(OFF, hertz_fixed_angle=False))
    y = np.zeros(m.n_state)
    z = m.n_balls
    dm, dw = m.p[M.P_DM], m.p[M.P_DW]
    for j in range(z):
        y[9 * j:9 * j + 3] = (0.0, 0.5 * dm - 5e-6, 2 * math.pi * j / z)
    # ball 0 just touching the outer race (alpha = 0), moving outwards at v0
    y[1] = m.p[M.P_RO] + (m.p[M.P_FE] - 0.5) * dw
    y[4] = v0
    return m, y


def test_hertz_impact_duration_and_rebound():
    """A ball hitting the fixed outer race at v0 (no orbit, pocket axis radial so Z = 0):
    Hertz impact (Johnson, Contact Mechanics §11.4): delta_max = (5·m·v0²/(4K))^(2/5),
    duration t_c = 2·(delta_max/v0)·∫0^1 dx/sqrt(1 − x^(5/2)) (= 2.9432·delta_max/v0), elastic
    rebound at −v0. K from the model's Hertz table (alpha = 0). Tolerances: contact still on at
    0.995·t_c and off at 1.005·t_c; rebound speed within 1e-6 (energy is conserved to the
    integrator's tolerance)."""
    v0 = 0.2
    m, y = _impact_setup(v0)
    K = D._hertz_lookup(m.hertz_table, 0, 1.0)[0]
    mb = m.p[M.P_MB]
    dmax = (5 * mb * v0 ** 2 / (4 * K)) ** 0.4
    integral = quad(lambda x: 1.0 / math.sqrt(1.0 - x ** 2.5), 0.0, 1.0)[0]
    tc = 2.0 * dmax / v0 * integral
    sp = np.array([[0.0, 0.0]])
    ld = np.array([[0.0, 0.0, 0.0, 0.0]])
    ws = I.Workspace(m)
    y, t, h, _, _ = I.advance(m, y, 0.0, 0.995 * tc, sp, ld, IMP, 1e-8, 1e-8, ws)
    out = O.evaluate_outputs(m, t, y, sp, ld, IMP)
    assert out["contact_load"][0, 0] > 0.0
    y, t, h, _, _ = I.advance(m, y, t, 1.005 * tc, sp, ld, IMP, 1e-8, h, ws)
    out = O.evaluate_outputs(m, t, y, sp, ld, IMP)
    assert out["contact_load"][0, 0] == 0.0
    assert y[4] == pytest.approx(-v0, rel=1e-6)
    # the maximum approach was reached at t_c/2
    m2, y2 = _impact_setup(v0)
    y2, t2, _, _, _ = I.advance(m2, y2, 0.0, 0.5 * tc, sp, ld, IMP, 1e-8, 1e-8)
    out = O.evaluate_outputs(m2, t2, y2, sp, ld, IMP)
    assert out["approach"][0, 0] == pytest.approx(dmax, rel=1e-4)


def _paper_state(rpm=14000.0, fa=55e3, fr=4e3):
    m = build_model(PAPER_BEARING, PAPER_OIL)
    w = rpm * math.pi / 30
    return m, initial_state(m, w, fa, fr), np.array([[0.0, w]]), np.array([[0.0, fa, 0.0, -fr]])


def test_error_decreases_with_tolerance():
    """2 ms of the paper's steady case (full model): the state error against a tol = 1e-10
    reference, in the integrator's own weighted norm, falls with the tolerance and stays within
    100·tol. Measured: 2e-4, 6e-5, 1e-6 at tol 1e-4, 1e-6, 1e-8 (the numbers move with every
    model change): the global error does not scale like tol here because the traction law has
    kinks (clipped curve, regularisation at s_lin) and the balls hit the pockets (soft linear
    spring, then Hertz at Z = Cp) within the 2 ms; required: a factor >= 2 per 100x."""
    m, y0, sp, ld = _paper_state()
    T = 2e-3
    ref, _, _, _, _ = I.advance(m, y0.copy(), 0.0, T, sp, ld, IMP, 1e-10, 1e-7)
    errs = []
    for tol in (1e-4, 1e-6, 1e-8):
        y, _, _, _, _ = I.advance(m, y0.copy(), 0.0, T, sp, ld, IMP, tol, 1e-7)
        w = m.scale + m.relmask * np.abs(ref)
        errs.append(np.sqrt(np.mean(((y - ref) / w) ** 2)))
    assert errs[1] < errs[0] / 2 and errs[2] < errs[1] / 2
    assert errs[1] < 100 * 1e-6


def test_advance_in_pieces_equals_one_call():
    """Stopping at output times does not change the solution beyond the tolerance."""
    m, y0, sp, ld = _paper_state(10000.0, 5000.0, 1000.0)
    a, _, _, _, _ = I.advance(m, y0.copy(), 0.0, 2e-3, sp, ld, IMP, 1e-8, 1e-7)
    ws = I.Workspace(m)
    y, t, h = y0.copy(), 0.0, 1e-7
    for k in range(1, 5):
        y, t, h, _, _ = I.advance(m, y, t, 5e-4 * k, sp, ld, IMP, 1e-8, h, ws)
    assert t == 2e-3
    w = m.scale + m.relmask * np.abs(a)
    assert np.sqrt(np.mean(((y - a) / w) ** 2)) < 1e-5


def test_max_step_bounds_every_step():
    """integrator.max_step: no accepted step is longer than h_max, so an interval T takes at least
    ceil(T / h_max) steps (exact lower bound); the cap binds here (the paper's steady state at a
    loose tolerance steps longer without it), and h_max = 1e-3 s is the default (H_MAX)."""
    m, y0, sp, ld = _paper_state()
    T, h_max = 1e-4, 2e-7
    n_min = math.ceil(T / h_max - 1e-9)       # 500 (T / h_max is 500.00000000000006 in binary)
    _, _, h_free, n_free, _ = I.advance(m, y0.copy(), 0.0, T, sp, ld, IMP, 1e-4, 1e-7)
    _, t, h, n, _ = I.advance(m, y0.copy(), 0.0, T, sp, ld, IMP, 1e-4, 1e-7, max_step=h_max)
    assert n_free < n_min <= n and t == T and h <= h_max
    # an initial step above the cap is clipped before the first attempt
    _, _, _, n_big, _ = I.advance(m, y0.copy(), 0.0, T, sp, ld, IMP, 1e-4, 1e-3, max_step=h_max)
    assert n_big >= n_min
    with pytest.raises(ValueError, match="max_step"):
        I.advance(m, y0.copy(), 0.0, T, sp, ld, IMP, 1e-4, 1e-7, max_step=0.0)


def test_unstable_run_names_ball_contact_and_time():
    """An absurd axial load ramp (to 1e9 N in 1 ms) drives the inner contacts beyond 0.01·Dw:
    SimulationUnstable names a ball, an inner-race contact and the time."""
    m, y0, sp, _ = _paper_state(10000.0, 5000.0, 1000.0)
    ld = np.array([[0.0, 5000.0, 0.0, -1000.0], [1e-3, 1e9, 0.0, -1000.0]])
    with pytest.raises(I.SimulationUnstable) as exc:
        I.advance(m, y0, 0.0, 2e-3, sp, ld, IMP, 1e-6, 1e-7)
    msg = str(exc.value)
    assert "ball" in msg and "race" in msg and "t =" in msg
    assert exc.value.ball is not None and 0 <= exc.value.ball < 20
    assert 0.0 < exc.value.t <= 1e-3


def _one_step_by_hand(method, Amat, y0, h):
    """One step of the tableau `method` on y' = Amat·y (stages by hand, as the compiled loop forms
    them): (y1, K) with K[-1] = f(y1) (FSAL)."""
    A, B, C, E, order = I.METHODS[method]
    s = A.shape[0]
    K = np.zeros((s, y0.size))
    for i in range(s):
        K[i] = Amat @ (y0 + h * (A[i, :i] @ K[:i]))
    return y0 + h * (B @ K), K, order


@pytest.mark.parametrize("method, local_order", [("dopri5", 5), ("bs32", 4)])
def test_continuous_extension_order_against_the_exact_solution(method, local_order):
    """The states the integrator writes at samples inside a step (integrator._dense_state): on the
    damped oscillator y' = A·y (eigenvalues -0.5 ± 3i, exact solution expm(A·θh)·y0) the error at
    θ in (0, 1) falls as h^5 for Dormand–Prince's continuous extension of order 4 (Hairer, Nørsett &
    Wanner, Solving ODEs I, §II.6) and as h^4 for BS32's cubic Hermite: halving h divides it by
    2^5 = 32 (2^4 = 16); asserted > 0.7 of that (the leading term dominates at these h: the ratio
    of the next pair of halvings is measured within 10 % of it). θ = 0 and 1 give y0 and y1."""
    from scipy.linalg import expm
    Amat = np.array([[-0.5, 3.0], [-3.0, -0.5]])
    y0 = np.array([1.0, 0.3])
    thetas = np.linspace(0.05, 0.95, 19)

    def err(h):
        y1, K, order = _one_step_by_hand(method, Amat, y0, h)
        out = np.zeros(2)
        worst = 0.0
        for th in thetas:
            I._dense_state(th, h, y0, y1, K, order, out)
            worst = max(worst, np.max(np.abs(out - expm(Amat * th * h) @ y0)))
        I._dense_state(0.0, h, y0, y1, K, order, out)
        assert np.allclose(out, y0, rtol=0, atol=1e-15)
        I._dense_state(1.0, h, y0, y1, K, order, out)
        assert np.allclose(out, y1, rtol=0, atol=1e-15)
        return worst

    e = [err(h) for h in (0.04, 0.02, 0.01)]
    assert e[0] / e[1] > 0.7 * 2 ** local_order
    assert e[1] / e[2] > 0.7 * 2 ** local_order


def test_samples_inside_steps_are_as_accurate_as_stopping_at_them():
    """advance_sampled writes the samples from the continuous extension instead of ending a step at
    each: 2 ms of the paper's steady rigid case from a settled state at t = 2 ms, 19 samples at
    0.1 ms, against a tol-1e-11 run stopping at every sample. Error: the RMS over the state in the
    integrator's scales (model.scale) of the worst sample.

    The error of one run at one tolerance is a random draw: the ball–pocket contacts switch on and
    off inside steps, so two equally valid step sequences differ by a factor of up to ~3 either
    way (the ratio inside/stopping at 3e-7 was 0.42 on one processor and 6.49 on another, the same
    code and inputs, only the last digits of the arithmetic differing: issue 36). The comparison is
    therefore statistical, over 25 tolerances 1e-4 ... 1e-7 (an eighth of a decade apart): the
    geometric mean of error inside / error stopping is at most 1.5. Order 4 dense output inside an
    order-5 step adds an interpolation error of the step's own order, so a mean a little above 1
    is expected; 1.5 is the accuracy a tolerance 1.4x tighter buys back (error ~ tol^(5/4)).
    Measured mean log ratio ± its standard error: +0.14 ± 0.13 (AVX-512 host; numba for generic
    x86-64: the same), +0.04 ± 0.10 (numba for AVX2+FMA, numpy's AVX-512 kernels off): the bound
    log 1.5 = 0.41 is 2 and 3.6 standard errors away. And the runs inside steps take fewer steps in
    all: that is their purpose (not every single one: the step count follows the error estimate,
    which the same contact switches scatter; at 3.2e-6 one instruction set took 311 steps inside
    against 303 stopping)."""
    from flexbearing.simulation.run import default_backend
    from flexbearing.simulation.scene import load_scene
    from flexbearing.multibody.profiles import load_at, speed_at
    import dataclasses
    scene = load_scene(Path(__file__).resolve().parents[1] / "scenes" / "paper_steady_rigid.toml")
    # the clearance-free bearing the statistics above were measured on (issue 35 moved the preset to the
    # design clearance, 88.4 um; there one of the 25 tolerances takes as many steps inside as stopping)
    scene = dataclasses.replace(scene, bearing=scene.bearing.with_(radial_clearance=0.0))
    be = default_backend(scene)
    model = be.build_model(scene.bearing, scene.oil, dict(scene.model_options))
    f0 = np.zeros(3)
    load_at(0.0, scene.load_table, scene.impacts, f0)
    Fa, Fr = scene.initial_loads()
    y = np.array(be.initial_state(model, speed_at(0.0, scene.speed_table), Fa, Fr, load=f0))
    tabs = (scene.speed_table, scene.load_table, scene.impacts)
    y, _, _, _, _ = I.advance(model, y, 0.0, 2e-3, *tabs, 1e-9, 1e-7)
    times = 2e-3 + 1e-4 * np.arange(1, 20)
    t_end = 4e-3

    def stopping(tol):
        yy, ws, h, t, out, n = y.copy(), I.Workspace(model), 1e-7, 2e-3, [], 0
        for ts in list(times) + [t_end]:
            yy, _, h, ns, _ = I.advance(model, yy, t, ts, *tabs, tol, h, ws)
            t = ts
            out.append(yy.copy())
            n += ns
        return np.array(out[:-1]), n

    ref, _ = stopping(1e-11)
    rms = lambda a: float(np.max(np.sqrt(np.mean(((a - ref) / model.scale) ** 2, axis=1))))  # noqa: E731
    log_ratios, steps_inside, steps_stopping = [], [], []
    for tol in 10.0 ** -(4.0 + 0.125 * np.arange(25)):
        a, n_stop = stopping(tol)
        _, _, _, n_in, _, b, _ = I.advance_sampled(model, y.copy(), 2e-3, t_end, times, *tabs, tol, 1e-7,
                                                   I.Workspace(model))
        log_ratios.append(math.log(rms(b) / rms(a)))
        steps_inside.append(n_in)
        steps_stopping.append(n_stop)
    log_ratios = np.array(log_ratios)
    assert sum(steps_inside) < sum(steps_stopping), (steps_inside, steps_stopping)
    standard_error = log_ratios.std(ddof=1) / math.sqrt(len(log_ratios))
    assert log_ratios.mean() <= math.log(1.5), (
        f"mean log ratio {log_ratios.mean():+.3f} ± {standard_error:.3f}; ratios {np.exp(log_ratios).round(2)}")
