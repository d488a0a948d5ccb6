"""Ball–cage-pocket normal force and hydrodynamic resistances."""
import math

import pytest
from scipy.integrate import dblquad, quad
from scipy.optimize import brentq

from flexbearing.multibody.hertz import effective_modulus, hertz_exact
from flexbearing.multibody.pocket import (MARTIN_LOAD, MARTIN_OUTLET, MARTIN_PRESSURE_CENTRE, bht_min_film,
                              pocket_curvature_radii, pocket_film_load, pocket_hertz_stiffness,
                              pocket_normal_force, pocket_rolling_resistance, pocket_sliding_resistance)

RB, RP = 0.011, 0.01125           # paper ball, assumed 22.5 mm pocket
CP = RP - RB
E_BC = effective_modulus(210e9, 0.3, 209e9, 0.295)   # M50 ball on 40CrNiMoA cage


def test_curvature_radii_and_hertz_constant():
    rxi, reta = pocket_curvature_radii(RB, RP)
    assert rxi == pytest.approx(RB * RP / (RP - RB), rel=1e-14)   # 0.495 m: conforming
    assert reta == RB
    ref = hertz_exact(rxi, reta, E_BC, 100.0)
    assert pocket_hertz_stiffness(RB, RP, E_BC) == pytest.approx(ref["stiffness"], rel=1e-6)


def test_normal_force_piecewise_paper_law():
    kn = pocket_hertz_stiffness(RB, RP, E_BC)
    # linear branch: Kc = 11/Cp, i.e. 11 N at the clearance; odd in Z
    assert pocket_normal_force(0.5 * CP, CP, kn) == pytest.approx(5.5, rel=1e-14)
    assert pocket_normal_force(-0.5 * CP, CP, kn) == pytest.approx(-5.5, rel=1e-14)
    # continuous at Cp, Hertzian beyond: Q − 11 N = Kn·(Z − Cp)^1.5
    assert pocket_normal_force(CP * (1 + 1e-12), CP, kn) == pytest.approx(11.0, rel=1e-9)
    d = 2e-6
    assert pocket_normal_force(CP + d, CP, kn) - 11.0 == pytest.approx(kn * d ** 1.5, rel=1e-12)


def test_martin_rigid_cylinder_constants():
    # Re-derive the Reynolds-outlet rigid cylinder solution by quadrature (Martin; Dowson &
    # Higginson): outlet X_e solves ∫_{-inf}^{X_e} (t² − X_e²)/(1 + t²)³ dt = 0; the load is
    # w = 24·∫P dX·eta·u·R/h0 (textbook 4.9); the pressure centre −∫P·X/∫P.
    f = lambda g: quad(lambda t: (t * t - g * g) / (1 + t * t) ** 3, -math.inf, g)[0]
    g = brentq(f, 0.1, 1.0, xtol=1e-14)
    assert g == pytest.approx(MARTIN_OUTLET, rel=1e-9)
    P = lambda X: quad(lambda t: (t * t - g * g) / (1 + t * t) ** 3, -math.inf, X, epsabs=1e-14)[0]
    ip = quad(P, -math.inf, g, epsabs=1e-13, limit=200)[0]
    ipx = quad(lambda X: P(X) * X, -math.inf, g, epsabs=1e-13, limit=200)[0]
    assert 24 * ip == pytest.approx(MARTIN_LOAD, rel=1e-7)
    assert 24 * ip == pytest.approx(4.9, abs=0.01)                  # published value 4.9
    assert -ipx / ip == pytest.approx(MARTIN_PRESSURE_CENTRE, rel=1e-7)
    # identity used by pocket_rolling_resistance: Poiseuille force (h/2)·dp/dx integrated equals
    # w·|x_p|/(2R) (per unit length, with u = eta = R = h0 = 1 in the X variable)
    direct = 6 * quad(lambda X: (X * X - g * g) / (1 + X * X) ** 2, -math.inf, g, epsabs=1e-13)[0] * math.sqrt(2)
    assert direct == pytest.approx(MARTIN_LOAD * MARTIN_PRESSURE_CENTRE * math.sqrt(2) / 2, rel=1e-7)


def test_bht_film_and_its_inversion():
    # Brewe, Hamrock & Taylor (1979) closed form, and pocket_film_load as its exact inverse;
    # scaling W ∝ u·h^(−1/2) (rigid, isoviscous).
    rx, ry, eta, u = 0.011, 0.495, 0.055, 5.0
    k = ry / rx
    lam = 1 / (1 + 2 / (3 * k))
    th = math.atan(k / 2)
    q = 20.0
    h = bht_min_film(q, u, rx, ry, eta)
    assert h == pytest.approx(rx * 128 * k * lam ** 2 * (0.131 * th + 1.683) ** 2 * (eta * u * rx / q) ** 2, rel=1e-14)
    assert pocket_film_load(h, u, rx, ry, eta) == pytest.approx(q, rel=1e-12)
    assert pocket_film_load(h / 4, u, rx, ry, eta) == pytest.approx(2 * q, rel=1e-12)
    assert pocket_film_load(h, 2 * u, rx, ry, eta) == pytest.approx(2 * q, rel=1e-12)


def test_rolling_resistance_formula_and_scaling():
    # F_R = W·|x_p|/(2Rx) with W from BHT at any gap: independent of h, ∝ eta·u·sqrt(Rx·Ry).
    rx, ry, eta, u = 0.011, 0.495, 0.055, 5.0
    fr = pocket_rolling_resistance(u, rx, ry, eta)
    for h in (1e-6, 1e-5):
        w = pocket_film_load(h, u, rx, ry, eta)
        assert -fr == pytest.approx(w * MARTIN_PRESSURE_CENTRE * math.sqrt(2 * rx * h) / (2 * rx), rel=1e-12)
    assert pocket_rolling_resistance(-u, rx, ry, eta) == -fr       # opposes the entrainment
    assert pocket_rolling_resistance(2 * u, rx, ry, eta) == pytest.approx(2 * fr, rel=1e-14)
    assert fr < 0


def test_sliding_resistance_is_the_couette_integral():
    # F_S = eta·du·∫∫ dA/h over the wetted ellipse h <= h_edge, h = h0 + x²/2Rx + y²/2Ry:
    # compare the closed form with a numerical double integral.
    rx, ry, eta, du, h0, h_edge = 0.011, 0.05, 0.055, 2.0, 5e-6, 100e-6
    ymax = math.sqrt(2 * ry * (h_edge - h0))
    def xlim(y):
        return math.sqrt(max(0.0, 2 * rx * (h_edge - h0 - y * y / (2 * ry))))
    num = dblquad(lambda x, y: 1 / (h0 + x * x / (2 * rx) + y * y / (2 * ry)), -ymax, ymax,
                  lambda y: -xlim(y), xlim, epsabs=1e-9, epsrel=1e-10)[0]
    assert pocket_sliding_resistance(du, h0, h_edge, rx, ry, eta) == pytest.approx(eta * du * num, rel=1e-6)
    assert pocket_sliding_resistance(du, h0, h0 / 2, rx, ry, eta) == 0.0


def test_the_model_runs_the_tested_pocket_law():
    """The law above is the one the dynamics run: the paper model's pocket constants come from it
    (Kc = 11 N/Cp, Kn = the Hertz constant of (R_xi, R_eta) against the exact Hertz solution), the
    kernel's normal force (pocket_kernels._pocket_interface, no drag or damping) is
    pocket_normal_force of them on both branches, and pocket_potential is the force's potential
    (its centred difference at h = 1 nm: truncation h²·V'''/6 and round-off both below 1e-7 of
    the force here)."""
    from flexbearing.multibody import dynamics as D, model as M
    from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
    from flexbearing.multibody.pocket import pocket_elastic_force, pocket_potential
    model = M.build_model(PAPER_BEARING, PAPER_OIL, {"traction": False, "drag": False, "damping": False})
    p = model.p
    cp, kc, kn = p[M.P_CP], p[M.P_KC], p[M.P_KN]
    assert kc * cp == pytest.approx(11.0, rel=1e-14)
    rb, rp = 0.5 * PAPER_BEARING.ball_diameter, 0.5 * PAPER_BEARING.cage.pocket_diameter
    e_bc = effective_modulus(PAPER_BEARING.ball_material.youngs_modulus, PAPER_BEARING.ball_material.poisson_ratio,
                             PAPER_BEARING.cage.material.youngs_modulus, PAPER_BEARING.cage.material.poisson_ratio)
    rxi, reta = pocket_curvature_radii(rb, rp)
    assert kn == pytest.approx(hertz_exact(rxi, reta, e_bc, 100.0)["stiffness"], rel=1e-6)
    for zz in (0.5 * cp, cp + 2e-6):
        out = D._pocket_interface(0.0, 0.0835, zz, 0, 0, 0, 0, 0, 0, 0.0, 0.0835, 0.0, 0.0, 1.0, 0.0,
                                  0, 0, 0, 0, 0, 0, 0, 0, 0, p, model.flags)
        assert out.q == pocket_normal_force(zz, cp, kn) == pocket_elastic_force(zz, cp, kc, kn)
        h = 1e-9
        dv = (pocket_potential(zz + h, cp, kc, kn) - pocket_potential(zz - h, cp, kc, kn)) / (2 * h)
        assert dv == pytest.approx(out.q, rel=1e-6)
