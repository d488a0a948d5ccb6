"""The EHL film-shear traction law (flexbearing.multibody.traction, "EHL film-shear law"; issue 25).

Checked against: its closed-form limits (the Newtonian–Maxwell creep slope at s -> 0, the Eyring
sinh law, the limiting-shear plateau), an independent numerical integration of the
Johnson–Tevaarwerk constitutive equation along a strip and of the Barus strip mean, and the one
published traction curve of 4106 oil available here (the paper's fit, Wang, Yang & Wang 2004,
inside its data range); and a sweep over load, speed and temperature that the law has no dead
zone: mu(0) = 0, a positive slope at s = 0 and mu rising monotonically to its maximum.
"""
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp, trapezoid

from flexbearing.multibody import traction as T
from flexbearing.multibody.bearing import PAPER_OIL
from flexbearing.multibody.hertz import effective_modulus, race_curvature_radii

E_EFF = effective_modulus(210e9, 0.3, 210e9, 0.3)
TAB = T.ehl_traction_table(PAPER_OIL.viscosity_temperature_coeff)
HUGE = 1e30


def _contact(q, alpha_deg, inner):
    return race_curvature_radii(0.022, 0.167, 0.52 if inner else 0.515, math.radians(alpha_deg), inner)


def test_barus_strip_mean_against_quadrature():
    # the closed form is exact at c = 0 and as c -> inf; in between within 6.5 % (its docstring)
    for c in (0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 30.0, 45.0):
        exact = quad(lambda x: math.exp(c * math.sqrt(1.0 - x * x)), 0.0, 1.0, limit=200)[0]
        assert T.barus_strip_mean(c) == pytest.approx(exact, rel=0.065)
    assert T.barus_strip_mean(0.0) == 1.0


def test_eyring_sinh_law_without_elasticity_heat_or_limit():
    # uniform pressure (alpha = 0), rigid film (G -> inf), no heating (k -> inf), no limit:
    # tau = tau0·asinh(eta·v/(h·tau0)) exactly (Eyring; Johnson & Tevaarwerk 1977, eq. 3)
    eta, h, tau0 = 0.01, 2e-7, 4e6
    for v in (1e-4, 1e-2, 0.1, 1.0, 10.0):
        tau = T.ehl_strip_shear(v, 1e9, 2e-4, h, 20.0, eta, 0.0, HUGE, tau0, HUGE, HUGE, HUGE, 1e-5, 0.03)
        assert tau == pytest.approx(tau0 * math.asinh(eta * v / (h * tau0)), rel=1e-9)


def test_newtonian_maxwell_creep_slope_at_zero_slip():
    # s -> 0: tau/v = (eta_a/h)·(1 − De·(1 − exp(−1/De))), De = eta_a·U/(G·2b) (linear Maxwell
    # element loaded from zero stress at the inlet); eta_a the Barus mean over the strip
    h, b, u, eta, alpha, p_c = 3e-7, 2e-4, 20.0, 2e-3, 1.85e-8, 0.7e9
    for g_mod in (1e7, 1e8, 1e9, 1e10):
        v = 1e-9
        tau = T.ehl_strip_shear(v, p_c, b, h, u, eta, alpha, 0.1, 4e6, 0.06, g_mod, 40.0, 1.1e-5, 0.03)
        eta_a = eta * T.barus_strip_mean(alpha * p_c)
        de = eta_a * u / (g_mod * 2.0 * b)
        expected = eta_a / h * (1.0 - de * (1.0 - math.exp(-1.0 / de)))
        assert tau / v == pytest.approx(expected, rel=1e-5)


def test_limiting_shear_plateau():
    # a film far stronger in Eyring shear than its limit (tau0 -> inf, isothermal): the strip-mean
    # stress is tau_L = gamma_L·p_mean (Bair & Winer 1979); with the ester's tau0 the Bair–Winer
    # form tau_L·(1 − exp(−tau_E/tau_L)) of the Eyring stress tau_E
    p_c, v, b, h, u, eta, alpha = 1.5e9, 30.0, 3e-4, 3e-7, 20.0, 0.05, 1.85e-8
    tau_l = 0.06 * 0.25 * math.pi * p_c
    tau = T.ehl_strip_shear(v, p_c, b, h, u, eta, alpha, HUGE, 1e12, 0.06, HUGE, HUGE, 1e-5, 0.03)
    assert tau == pytest.approx(tau_l, rel=1e-9)
    no_limit = T.ehl_strip_shear(v, p_c, b, h, u, eta, alpha, HUGE, 4e6, HUGE, HUGE, HUGE, 1e-5, 0.03)
    tau = T.ehl_strip_shear(v, p_c, b, h, u, eta, alpha, HUGE, 4e6, 0.06, HUGE, HUGE, 1e-5, 0.03)
    assert tau == pytest.approx(tau_l * (1.0 - math.exp(-no_limit / tau_l)), rel=1e-9)


def test_maxwell_strip_mean_against_johnson_tevaarwerk_ode():
    # Johnson & Tevaarwerk (1977): d tau/dt = G·(v/h − (tau0/eta)·sinh(tau/tau0)), tau(0) = 0 at
    # the inlet, uniform properties along the strip; the law replaces the dashpot by its secant
    # viscosity at the steady flow stress. Measured worst error of the strip mean over this grid
    # (eta 1–1000 Pa·s, G 0.01–1 GPa, v 1 mm/s–1 m/s: De and flow stress over several decades):
    # 14.9 %, in the transition between the elastic and the non-linear viscous regime; the
    # tolerance 20 % is that worst case with margin.
    tau0, h, b, u = 4e6, 3e-7, 2e-4, 20.0
    t_tr = 2.0 * b / u
    worst = 0.0
    for eta in (1.0, 10.0, 100.0, 1e3):
        for g_mod in (1e7, 1e8, 1e9):
            for v in (1e-3, 1e-2, 0.1, 1.0):
                rate = v / h
                sol = solve_ivp(lambda t, s: [g_mod * (rate - tau0 / eta * math.sinh(min(s[0] / tau0, 700.0)))],
                                (0.0, t_tr), [0.0], method="LSODA", rtol=1e-9, atol=1.0, dense_output=True)
                tt = np.linspace(0.0, t_tr, 2001)
                exact = trapezoid(sol.sol(tt)[0], tt) / t_tr
                law = T.ehl_strip_shear(v, 1e9, b, h, u, eta, 0.0, HUGE, tau0, HUGE, g_mod, HUGE, 1e-5, 0.03)
                worst = max(worst, abs(law / exact - 1.0))
                assert law == pytest.approx(exact, rel=0.20)
    print(f"worst relative error of the strip mean against the J&T ODE: {worst:.3f}")


# the sweep of the allowed ranges: loads (light test contacts to the paper's heavy ones), rolling
# speeds, oil temperatures, and the ends of the declared parameter ranges
SWEEP = [(q, ur, tc) for q in (30.0, 200.0, 1500.0, 8000.0) for ur in (1.0, 10.0, 60.0) for tc in (20.0, 100.0, 200.0)]


@pytest.mark.parametrize("scale,rise", [(1.0, 0.0), (T.EHL_RANGES["traction_scale"][0], T.EHL_RANGES["contact_temperature_rise"][1]),
                                        (T.EHL_RANGES["traction_scale"][1], 0.0)])
def test_no_dead_zone_anywhere(scale, rise):
    s = np.concatenate([[0.0], np.geomspace(1e-7, 1.0, 160)])
    for inner in (False, True):
        rx, ry = _contact(0.0, 35.0 if inner else 20.0, inner)
        for q, ur, tc in SWEEP:
            oil = replace(PAPER_OIL, temperature_c=tc)
            tab = T.ehl_traction_table(oil.viscosity_temperature_coeff, scale, rise)
            mu = T.ehl_traction_curve(s, q, rx, ry, E_EFF, ur, oil, tab)
            assert mu[0] == 0.0
            assert mu[1] > 0.0                                     # positive slope at s = 0
            k = int(np.argmax(mu))
            assert np.all(np.diff(mu[:k + 1]) > 0.0)              # rises monotonically to its maximum
            assert s[k] >= 1e-3                                    # no jump near the origin
            assert mu[k] <= T.EHL_LIMITING_SHEAR_COEFF * scale     # bounded by gamma_L
            assert mu[-1] > 0.0


def test_against_the_published_4106_fit_inside_its_data_range():
    # Wang, Yang & Wang (2004): the paper's 4106 fit, a regression of measured traction curves;
    # inside its data range (p0 >= 1 GPa, flexbearing.multibody.traction "Bounded law"): the paper's steady
    # scene (55 kN, 14,000 rpm, 20 °C; inner 4.5 kN at 36°, outer 5 kN at 30°, UR ~50 m/s) and
    # reference/formulas.md's check contact (3 kN at 25°, 43.1 m/s, 100 °C). The curves differ in
    # shape (the law peaks at s ~ 0.003–0.01 as disc-machine EHL curves do, the fit at s ~ 0.3–0.5),
    # so the maxima are compared: within a factor 1.8 (measured 1.01, 0.77, 1.68), the spread of
    # the limiting-shear coefficient in the literature (0.03–0.10) being a factor 3.
    s = np.geomspace(1e-5, 1.0, 200)
    for q, alpha, inner, ur, tc in ((4500.0, 36.0, True, 50.0, 20.0), (5000.0, 30.0, False, 50.0, 20.0),
                                    (3000.0, 25.0, True, 43.1, 100.0)):
        rx, ry = _contact(q, alpha, inner)
        oil = replace(PAPER_OIL, temperature_c=tc)
        mu = T.ehl_traction_curve(s, q, rx, ry, E_EFF, ur, oil, T.ehl_traction_table(oil.viscosity_temperature_coeff))
        A, B, C, D = T.traction_coefficients(q, ur, rx, E_EFF, PAPER_OIL.viscosity(20.0), oil.temperature_k,
                                             oil.thermal_conductivity)
        fit_max = T.traction_curve_maximum(A, B, C, D)
        assert 1.0 / 1.8 < mu.max() / fit_max < 1.8


def test_model_option_and_scene_key_select_the_law():
    from flexbearing.common.validation import InputError
    from flexbearing.multibody.bearing import PAPER_BEARING
    from flexbearing.multibody.model import build_model
    assert build_model(PAPER_BEARING, PAPER_OIL, {}).traction_table.shape == (4, 4)      # the paper's fit
    tab = build_model(PAPER_BEARING, PAPER_OIL, {"traction_law": "ehl", "traction_scale": 1.5,
                                                 "contact_temperature_rise": 20.0}).traction_table
    assert T.is_ehl_table(tab) and tab[T.EHL_ROW_FILM, T.EHL_C_SCALE] == 1.5
    assert tab[T.EHL_ROW_THERMAL, T.EHL_C_TEMPERATURE_RISE] == 20.0
    assert tab[T.EHL_ROW_THERMAL, T.EHL_C_BETA_T] == PAPER_OIL.viscosity_temperature_coeff
    with pytest.raises(InputError, match="traction_law"):
        build_model(PAPER_BEARING, PAPER_OIL, {"traction_law": "dry"})
    with pytest.raises(InputError, match=r"traction.traction_scale.*0.5"):
        build_model(PAPER_BEARING, PAPER_OIL, {"traction_law": "ehl", "traction_scale": 5.0})
    with pytest.raises(InputError, match="applies to traction_law = 'ehl' only"):
        build_model(PAPER_BEARING, PAPER_OIL, {"traction_scale": 1.5})
    from flexbearing.simulation.scene import loads_scene
    text = open("scenes/paper_steady_rigid.toml").read().replace("[cage]", '[model]\ntraction_law = "ehl"\n\n[cage]', 1)
    assert loads_scene(text).model_options["traction_law"] == "ehl"


def test_the_model_takes_the_ehl_law_once_into_named_slots():
    # the law's parameters are taken once, at build_model, into the slots P_EHL_* of Model.p:
    # tau0 and gamma_L scaled by traction_scale, bearing steel's k and kappa (flash term), the
    # oil's beta_T, and the inlet viscosity eta(T_oil)·exp(−beta_T·ΔT) (module docstring)
    import test_power_loss as P
    from flexbearing.multibody import dynamics as D
    from flexbearing.multibody import model as M
    from flexbearing.multibody.bearing import PAPER_BEARING
    beta = PAPER_OIL.viscosity_temperature_coeff
    opts = {"traction_law": "ehl", "drag": False, "damping": False, **P.FIXED}
    model = M.build_model(PAPER_BEARING, PAPER_OIL, {**opts, "traction_scale": 1.5, "contact_temperature_rise": 20.0})
    p = model.p
    assert p[M.P_EHL_TAU0] == pytest.approx(1.5 * 4.0e6, rel=1e-15)
    assert p[M.P_EHL_GAMMA_L] == pytest.approx(1.5 * 0.06, rel=1e-15)
    assert p[M.P_EHL_SHEAR_MODULUS] == 1.0e9
    assert (p[M.P_EHL_K_SOLID], p[M.P_EHL_KAPPA_SOLID]) == (40.0, 1.1e-5)
    assert p[M.P_EHL_BETA_T] == beta
    assert p[M.P_EHL_ETA_INLET] == pytest.approx(PAPER_OIL.viscosity() * math.exp(-beta * 20.0), rel=1e-15)
    # the fit leaves them zero; with_traction_table fills and clears them with the table
    fit = M.build_model(PAPER_BEARING, PAPER_OIL, {})
    slots = list(T.EHL_SLOTS)
    assert not np.any(fit.p[slots])
    swapped = M.with_traction_table(fit, model.traction_table, "ehl")
    assert np.array_equal(swapped.p[slots], p[slots])
    assert not np.any(M.with_traction_table(swapped, T.TRACTION_FIT_4106, "fit").p[slots])

    # the right-hand side runs on the slots, not on the table: a model of scale 1 given the slots
    # of scale 1.5 (its own table unchanged) has the right-hand side of the scale-1.5 model
    def rhs(m, y):
        dydt, work = np.zeros_like(y), D.new_work(m)
        D.rhs(0.0, y, dydt, m.p, m.flags, m.hertz_table, m.traction_table, P.SP, P.LD, P.IMP, work, m.cage)
        return dydt
    one = M.build_model(PAPER_BEARING, PAPER_OIL, opts)
    strong = M.build_model(PAPER_BEARING, PAPER_OIL, {**opts, "traction_scale": 1.5})
    y = P._perturbed_state(one)
    given = one.p.copy()
    given[slots] = strong.p[slots]
    assert np.array_equal(rhs(one._replace(p=given), y), rhs(strong, y))
    assert not np.array_equal(rhs(one, y), rhs(strong, y))


def test_power_balance_closes_with_the_ehl_law():
    # the slices' forces lie along their slip at the slice centre, so P = T_t·du0 − M_n·du1 +
    # T_tau·dv is still the exact traction power (flexbearing.multibody.dynamics._race): the work–energy
    # balance of the paper case's disturbed state closes as with the fit (tests/test_power_loss.py)
    import test_power_loss as P
    from flexbearing.multibody.bearing import PAPER_BEARING
    from flexbearing.multibody.model import build_model
    from flexbearing.multibody.power_loss import power_balance
    model = build_model(PAPER_BEARING, PAPER_OIL, {"traction": True, "drag": False, "damping": False,
                                                   "traction_law": "ehl", **P.FIXED})
    y = P._perturbed_state(model)
    b = power_balance(model, 0.0, y, P.SP, P.LD, P.IMP)
    assert float(np.sum(b["sources"]["traction"])) > 1.0
    assert np.all(b["sources"]["traction"] >= 0.0)
    assert abs(b["residual"]) < 1e-6 * b["loss"]
