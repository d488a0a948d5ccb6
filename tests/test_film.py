"""Hamrock–Dowson EHL film thickness."""
import math

import pytest

from flexbearing.multibody.film import film_parameters, film_thickness
from flexbearing.multibody.hertz import effective_modulus, race_curvature_radii

E_M50 = effective_modulus(210e9, 0.3, 210e9, 0.3)


def test_formulas_md_check_values():
    # formulas.md: inner contact of the paper bearing (alpha 25°, fi 0.52), 3 kN, 10,000 rpm
    # (u = 43.1 m/s), alpha_p 1.85e-8 1/Pa: h_min ≈ 3.2 um, h_c ≈ 3.9 um. These hold with the
    # ambient viscosity eta0 = 0.055 Pa·s (the paper preset, SPEC §1); printed to 2 digits and
    # computed here as 3.18 and 3.85 um, so the tolerance is 0.06 um (a rounding of 3.85 to 3.9).
    rx, ry = race_curvature_radii(0.022, 0.167, 0.52, math.radians(25.0), True)
    g = 0.022 * math.cos(math.radians(25.0)) / 0.167
    u = 0.25 * 0.167 * (10000 * math.pi / 30) * (1 - g * g)
    h_min, h_c = film_thickness(rx, ry, E_M50, 3000.0, u, 0.055, 1.85e-8)
    assert h_min == pytest.approx(3.2e-6, abs=0.06e-6)
    assert h_c == pytest.approx(3.9e-6, abs=0.06e-6)


def test_hamrock_dowson_closed_form_and_scalings():
    # Direct evaluation of eqs 21/22 of Hamrock & Dowson (1977) for one set of groups, and the
    # published exponents: h ∝ u^0.68 (min) / u^0.67 (central), ∝ Q^−0.073 / Q^−0.067,
    # ∝ alpha_p^0.49 / alpha_p^0.53.
    rx, ry = 0.01, 0.2
    base = film_thickness(rx, ry, E_M50, 2000.0, 20.0, 0.01, 2e-8)
    U, G, W, k = film_parameters(rx, ry, E_M50, 2000.0, 20.0, 0.01, 2e-8)
    assert k == pytest.approx(1.03 * 20 ** 0.64, rel=1e-14)
    assert base[0] == pytest.approx(rx * 3.63 * U ** 0.68 * G ** 0.49 * W ** -0.073 * (1 - math.exp(-0.68 * k)), rel=1e-14)
    assert base[1] == pytest.approx(rx * 2.69 * U ** 0.67 * G ** 0.53 * W ** -0.067 * (1 - 0.61 * math.exp(-0.73 * k)), rel=1e-14)
    two_u = film_thickness(rx, ry, E_M50, 2000.0, 40.0, 0.01, 2e-8)
    two_q = film_thickness(rx, ry, E_M50, 4000.0, 20.0, 0.01, 2e-8)
    two_a = film_thickness(rx, ry, E_M50, 2000.0, 20.0, 0.01, 4e-8)
    assert two_u[0] / base[0] == pytest.approx(2 ** 0.68, rel=1e-12)
    assert two_u[1] / base[1] == pytest.approx(2 ** 0.67, rel=1e-12)
    assert two_q[0] / base[0] == pytest.approx(2 ** -0.073, rel=1e-12)
    assert two_q[1] / base[1] == pytest.approx(2 ** -0.067, rel=1e-12)
    assert two_a[0] / base[0] == pytest.approx(2 ** 0.49, rel=1e-12)
    assert two_a[1] / base[1] == pytest.approx(2 ** 0.53, rel=1e-12)


def test_central_thicker_than_minimum_and_limits():
    # The central film is thicker than the minimum (side constriction), the more so for near-
    # circular contacts: with these groups h_c/h_min = 1.75 (k = 1.03), 1.33 (rho 5), 1.24 (rho 30),
    # and h_min grows with ellipticity (less side leakage). Zero load or speed gives no film.
    ratios = []
    for rho in (1.0, 5.0, 30.0):
        h_min, h_c = film_thickness(0.01, 0.01 * rho, E_M50, 2000.0, 20.0, 0.01, 2e-8)
        ratios.append((h_min, h_c / h_min))
    assert all(r > 1.1 for _, r in ratios) and ratios[0][1] > ratios[1][1] > ratios[2][1]
    assert ratios[0][0] < ratios[1][0] < ratios[2][0]
    assert film_thickness(0.01, 0.2, E_M50, 0.0, 20.0, 0.01, 2e-8) == (0.0, 0.0)
    assert film_thickness(0.01, 0.2, E_M50, 2000.0, 0.0, 0.01, 2e-8) == (0.0, 0.0)
