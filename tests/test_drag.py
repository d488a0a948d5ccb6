"""Churning drag and EHL rolling resistance forces."""
import math

import pytest
from scipy.integrate import quad

from flexbearing.multibody.drag import (churning_drag, ehl_pressure_rolling_force, ehl_rolling_resistance,
                            oil_air_mixture, sphere_drag_coefficient)
from flexbearing.multibody.hertz import effective_modulus
from flexbearing.multibody.pocket import MARTIN_OUTLET

E_M50 = effective_modulus(210e9, 0.3, 210e9, 0.3)


def test_sphere_drag_coefficient_against_standard_curve():
    # Standard drag curve of a sphere (Clift, Grace & Weber 1978, Table 5.2 / Lapple & Shepherd):
    # C_d(100) = 1.09, C_d(1000) ≈ 0.47 (Schiller–Naumann within its quoted 5 %), Newton regime 0.44.
    assert sphere_drag_coefficient(100.0) == pytest.approx(1.09, rel=0.01)
    assert sphere_drag_coefficient(999.0) == pytest.approx(0.47, rel=0.08)
    assert sphere_drag_coefficient(1e4) == 0.44 and sphere_drag_coefficient(2e5) == 0.44


def test_churning_drag_limits():
    # Stokes limit (Re -> 0): F = 3·pi·eta·D·V (Stokes 1851); the correlation's correction at
    # Re = 1e-4 is 0.15·Re^0.687 = 2.7e-4, hence the 1e-3 tolerance.
    d, eta, rho = 0.022, 10.0, 900.0
    v = 1e-4 * eta / (rho * d)
    assert churning_drag(d, v, rho, eta) == pytest.approx(-3 * math.pi * eta * d * v, rel=1e-3)
    # Newton regime: F = 0.5·0.44·rho·(pi/4)·D²·V², opposite to V
    rho_mix, eta_mix = oil_air_mixture(0.05, 892.2, 0.055)
    assert rho_mix == pytest.approx(0.05 * 892.2 + 0.95 * 1.2, rel=1e-14)
    v = 200.0
    assert rho_mix * v * d / eta_mix > 1000
    assert churning_drag(d, v, rho_mix, eta_mix) == pytest.approx(-0.5 * 0.44 * rho_mix * math.pi / 4 * d * d * v * v, rel=1e-14)
    assert churning_drag(d, -v, rho_mix, eta_mix) == -churning_drag(d, v, rho_mix, eta_mix)
    assert churning_drag(d, 0.0, rho_mix, eta_mix) == 0.0


def test_ehl_rolling_resistance_scalings():
    # Published exponents: F_R ∝ u^0.66 · Q^0.47 · alpha_p^0.022 · k^0.348, and
    # F_R/(E'Rx²) = 2.86 k^0.348 G^0.022 U^0.66 W^0.47 with U, G, W of Hamrock–Dowson.
    rx, k, q, u, eta, ap = 0.0097, 8.79, 3000.0, 43.1, 0.055, 1.85e-8
    f = ehl_rolling_resistance(q, u, rx, k, E_M50, eta, ap)
    U, G, W = eta * u / (E_M50 * rx), ap * E_M50, q / (E_M50 * rx ** 2)
    assert -f == pytest.approx(2.86 * E_M50 * rx ** 2 * k ** 0.348 * G ** 0.022 * U ** 0.66 * W ** 0.47, rel=1e-12)
    assert ehl_rolling_resistance(q, 2 * u, rx, k, E_M50, eta, ap) / f == pytest.approx(2 ** 0.66, rel=1e-12)
    assert ehl_rolling_resistance(2 * q, u, rx, k, E_M50, eta, ap) / f == pytest.approx(2 ** 0.47, rel=1e-12)
    assert ehl_rolling_resistance(q, -u, rx, k, E_M50, eta, ap) == -f      # opposes entrainment
    assert ehl_rolling_resistance(0.0, u, rx, k, E_M50, eta, ap) == 0.0
    # magnitude for the paper-bearing inner contact at 3 kN, 10,000 rpm, ambient viscosity:
    # a few newtons, i.e. about 0.1 % of the load (rolling resistance << traction)
    assert 0.5 < -f < 10.0


def test_pressure_rolling_force_identity_on_rigid_cylinder():
    # For a rigid cylinder of radius R on a flat (Martin solution, Reynolds outlet), both surfaces
    # entraining along +x: the Poiseuille shear on either surface is F_R = −∫(h/2)·dp/dx dx (it
    # opposes the entrainment), the tangential pressure force on the cylinder (outward normal
    # (x/R, −1)) is F_H = −∫p·x/R dx. With the inlet pressure at x < 0, F_H points along the
    # entrainment: F_H = −2·(Rx/r_b)·F_R with Rx = r_b = R. Per unit length, eta = u = R = h0 = 1,
    # X = x/sqrt(2). (The signs matter: with F_H along F_R the pair would feed energy into the
    # balls, tests/test_power_loss.py; the paper's ball equations, §2.5.1, also carry F_H and F_R
    # of one contact with opposite signs.)
    g = MARTIN_OUTLET
    dpdx = lambda X: 12 * (X * X - g * g) / (1 + X * X) ** 3          # dp/dx = 12(h − h_e)/h³
    p = lambda X: quad(lambda t: dpdx(t) * math.sqrt(2), -math.inf, X, epsabs=1e-14)[0]
    poiseuille = quad(lambda X: 0.5 * (1 + X * X) * dpdx(X) * math.sqrt(2), -math.inf, g, epsabs=1e-13)[0]
    pressure = quad(lambda X: p(X) * X * math.sqrt(2) * math.sqrt(2), -math.inf, g, epsabs=1e-12, limit=200)[0]
    f_r = -poiseuille
    f_h = -pressure
    assert f_r < 0.0 < f_h
    assert f_h == pytest.approx(-2 * f_r, rel=1e-6)
    assert ehl_pressure_rolling_force(f_r, 1.0, 1.0) == pytest.approx(f_h, rel=1e-6)
    assert ehl_pressure_rolling_force(-1.5, 0.0097, 0.011) == pytest.approx(1.5 * 2 * 0.0097 / 0.011, rel=1e-14)
