"""The fit's low-rolling-speed regularisation (flexbearing.multibody.traction, "Low rolling speed"; issue 21).

The dynamics evaluate the 4106 fit at UR_eff = max(|UR|, u_reg). Checked on the compiled
right-hand side (flexbearing.multibody.dynamics.rhs) of the paper bearing:

* below u_reg the outer contact's rolling traction is Q·mu(du/u_reg) with the coefficients of
  Ub(u_reg), recomputed here by hand from the fit's power laws (TRACTION_FIT_4106) and the curve
  mu(s) = (A + B·s)·exp(−C·s) + D with its straight line below s_lin, to 1e-9 relative
  (one slice, transverse traction and the drag-side forces off, so the contact's tangential force
  is that traction alone);
* the creep slope dT/d(du) near zero sliding is Q·mu(s_lin)/(s_lin·u_reg), bounded by u_reg, not by
  the rolling speed (finite difference of the same rhs against the analytic slope, 1e-6);
* at the paper's speed (UR 40–60 m/s > u_reg) the option changes nothing: dy/dt bit-identical for
  u_reg = 10 m/s and u_reg = 1e-3 m/s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.initial import initial_state
from flexbearing.multibody.traction import TRACTION_FIT_4106

U_REG = 10.0
S_LIN = 2e-3


def _rhs(model, y, omega):
    sp = np.array([[0.0, omega]])
    ld = np.array([[0.0, 55e3, 0.0, -4e3]])
    work = D.new_work(model)
    dydt = np.zeros(model.n_state)
    D.rhs(0.0, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld,
          np.zeros((0, 6)), work, model.cage)
    return dydt, work


def _fit_by_hand(Q, ur, rx, p):
    """mu-curve coefficients of the fit at rolling speed ur (traction module docstring)."""
    e_rx = p[M.P_EBR] * rx
    qb = Q / (e_rx * rx)
    ub = p[M.P_ETA_TRACTION] * ur / e_rx
    tb = p[M.P_ETA_TRACTION] * p[M.P_K0] * p[M.P_T0K] / e_rx ** 2
    return [r[0] * qb ** r[1] * ub ** r[2] * tb ** r[3] for r in TRACTION_FIT_4106]


def _mu(s, A, B, C, Dd):
    x = abs(s)
    if x < S_LIN:
        return _mu(S_LIN, A, B, C, Dd) * x / S_LIN * math.copysign(1.0, s)
    m = max((A + B * x) * math.exp(-C * x) + Dd, 0.0)
    return math.copysign(m, s)


@pytest.fixture(scope="module")
def slow_case():
    opts = dict(n_slices=1, transverse_traction=False, drag=False, damping=False,
                traction_slip_linear=S_LIN, slip_regularisation_speed=U_REG)
    model = M.build_model(PAPER_BEARING, PAPER_OIL, opts)
    omega = 300.0 * math.pi / 30.0                       # 300 rpm: UR ~ 1.3 m/s << u_reg
    y = initial_state(model, omega, 55e3, 4e3, load=(55e3, 0.0, -4e3))
    return model, y, omega


def test_below_u_reg_the_fit_is_taken_at_u_reg(slow_case):
    model, y, omega = slow_case
    y = y.copy()
    y[6] += 40.0                                          # ball 0 spin about X: ~0.3 m/s of sliding
    _, work = _rhs(model, y, omega)
    Q, ur, slip, ft, rx = (work[0, M.WC_Q], work[0, M.WC_UR], work[0, M.WC_SLIP], work[0, M.WC_FT],
                           work[0, M.WC_RX])
    assert Q > 100.0 and 0.0 < abs(ur) < U_REG
    du = slip * abs(ur)                                   # WC_SLIP = du/|UR| (unregularised)
    assert abs(du) > 0.05
    A, B, C, Dd = _fit_by_hand(Q, U_REG, rx, model.p)
    expected = Q * _mu(du / U_REG, A, B, C, Dd)
    assert ft == pytest.approx(expected, rel=1e-9)
    # and not the fit at the true rolling speed (which is what the option replaces)
    A2, B2, C2, D2 = _fit_by_hand(Q, abs(ur), rx, model.p)
    assert abs(Q * _mu(du / abs(ur), A2, B2, C2, D2) - ft) > 0.1 * abs(ft)


def test_creep_slope_is_bounded_by_u_reg(slow_case):
    model, y, omega = slow_case
    _, w0 = _rhs(model, y, omega)
    Q, rx = w0[0, M.WC_Q], w0[0, M.WC_RX]
    rho = 0.5 * model.p[M.P_DW] - 0.5 * w0[0, M.WC_DELTA]
    nr = w0[0, M.WC_COS]                                  # outer normal n = (sin a, cos a)
    # ball spin about X at which the outer contact does not slide: du = rho·nr·(w_x0 − w_x)
    w_stick = y[6] + w0[0, M.WC_SLIP] * abs(w0[0, M.WC_UR]) / (rho * nr)
    fts = []
    d = 1e-4 / (rho * nr)                                 # 1e-4 m/s of sliding, inside s_lin·u_reg
    for dw in (-d, d):
        yy = y.copy()
        yy[6] = w_stick + dw
        fts.append(_rhs(model, yy, omega)[1][0, M.WC_FT])
    slope = (fts[0] - fts[1]) / (2e-4)                    # dT/d(du), du = −rho·nr·dw
    A, B, C, Dd = _fit_by_hand(Q, U_REG, rx, model.p)
    analytic = Q * _mu(S_LIN, A, B, C, Dd) / (S_LIN * U_REG)
    assert slope == pytest.approx(analytic, rel=1e-6)


def test_no_effect_above_u_reg():
    omega = 14000.0 * math.pi / 30.0
    out = []
    for u_reg in (U_REG, 1e-3):
        model = M.build_model(PAPER_BEARING, PAPER_OIL, {"slip_regularisation_speed": u_reg})
        y = initial_state(model, omega, 55e3, 4e3, load=(55e3, 0.0, -4e3))
        y[6::9][:model.n_balls] += 5.0                    # some sliding at every contact
        dydt, work = _rhs(model, y, omega)
        assert np.all(np.abs(work[:-1, M.WC_UR]) > 3 * U_REG)
        out.append(dydt)
    assert np.array_equal(out[0], out[1])


def test_out_of_range_is_refused():
    from flexbearing.common.validation import InputError
    with pytest.raises(InputError, match="slip_regularisation_speed"):
        M.build_model(PAPER_BEARING, PAPER_OIL, {"slip_regularisation_speed": 0.0})
