"""The bounded traction law (flexbearing.multibody.traction, module docstring "Bounded law") and the curve maximum.

What is checked, and why these tolerances:
* `traction_curve_maximum` against the analytic stationary point s* = 1/C − A/B of
  (A + B·s)·exp(−C·s) + D and a dense numerical maximum (grid 1e-5 in s: 1e-9 relative);
* inside its data range the bounded law IS the fit (same coefficients to round-off, 1e-12);
* below Qb_min the coefficients are those of Qb_min (load-independent traction coefficient,
  the limiting-shear picture), exactly;
* the peak of the bounded curve never exceeds mu_lim and equals it when the cap is active (1e-12);
* the formulas.md check point (inner contact, 3 kN, 10,000 rpm, 373 K: A −0.0204, B 0.0698,
  C 6.23, D 0.0192) is inside the range and is reproduced by the bounded table (3 significant
  digits, as formulas.md gives them).
No published numerical traction curve of 4106 oil was available, so the law's level is not tested
against measured data (docstring).
"""
import math

import numpy as np
import pytest

from flexbearing.multibody import traction as T
from flexbearing.multibody.hertz import effective_modulus, race_curvature_radii

E_EFF = effective_modulus(210e9, 0.3, 210e9, 0.3)
ETA0, K0 = 0.055, 0.0965788


def _coeffs(Q, ur, rx, temp_k, table):
    return T.traction_coefficients_table(Q, ur, rx, E_EFF, ETA0, temp_k, K0, table)


def test_curve_maximum_matches_stationary_point_and_dense_grid():
    for A, B, C, D in ((-0.0204, 0.0698, 6.23, 0.0192), (-0.002, 0.05, 20.0, 0.003), (0.01, 0.0, 5.0, 0.02)):
        s = np.linspace(0.0, 5.0, 500001)
        dense = np.max((A + B * s) * np.exp(-C * s) + D)
        assert T.traction_curve_maximum(A, B, C, D) == pytest.approx(dense, rel=1e-9)
    # analytic: s* = 1/C − A/B
    A, B, C, D = -0.0204, 0.0698, 6.23, 0.0192
    s_star = 1.0 / C - A / B
    assert T.traction_curve_maximum(A, B, C, D) == pytest.approx((A + B * s_star) * math.exp(-C * s_star) + D, rel=1e-15)


def test_bounded_law_is_the_fit_inside_its_range_and_reproduces_the_formulas_check():
    rx, _ = race_curvature_radii(0.022, 0.167, 0.52, math.radians(25.0), True)
    Q, ur, tk = 3000.0, 43.1, 373.15
    assert Q / (E_EFF * rx * rx) > T.QB_MIN_4106  # inside the range
    fit = _coeffs(Q, ur, rx, tk, T.TRACTION_FIT_4106)
    bnd = _coeffs(Q, ur, rx, tk, T.TRACTION_BOUNDED_4106)
    assert np.allclose(bnd, fit, rtol=1e-12, atol=0.0)
    for got, want in zip(bnd, (-0.0204, 0.0698, 6.23, 0.0192)):
        assert got == pytest.approx(want, rel=5e-3)


def test_bounded_law_holds_the_load_group_below_qb_min():
    rx, _ = race_curvature_radii(0.022, 0.167, 0.52, math.radians(40.0), True)
    q_min = T.QB_MIN_4106 * E_EFF * rx * rx          # 542 N for this contact
    at_min = _coeffs(q_min, 20.0, rx, 393.15, T.TRACTION_BOUNDED_4106)
    for q in (50.0, 100.0, 300.0):
        assert _coeffs(q, 20.0, rx, 393.15, T.TRACTION_BOUNDED_4106) == pytest.approx(at_min, rel=1e-12)
        # and the fit itself extrapolates below: its plateau D ∝ Qb^0.7423
        d_fit = _coeffs(q, 20.0, rx, 393.15, T.TRACTION_FIT_4106)[3]
        assert d_fit / at_min[3] == pytest.approx((q / q_min) ** 0.7423, rel=1e-12)


def test_bounded_law_peak_never_exceeds_the_limiting_shear_coefficient():
    rx, _ = race_curvature_radii(0.022, 0.167, 0.515, math.radians(10.0), False)
    low_cap = T.bounded_traction_table((T.QB_MIN_4106, 1.0), (0.0, 1.0), 0.01)
    for q, ur in ((500.0, 10.0), (3000.0, 5.0), (10000.0, 2.0)):
        A, B, C, D = _coeffs(q, ur, rx, 293.15, low_cap)
        uncapped = _coeffs(q, ur, rx, 293.15, T.bounded_traction_table((T.QB_MIN_4106, 1.0), (0.0, 1.0), 0.0))
        peak = T.traction_curve_maximum(A, B, C, D)
        if T.traction_curve_maximum(*uncapped) > 0.01:
            assert peak == pytest.approx(0.01, rel=1e-12)
            # the shape in s is kept: C unchanged, A, B, D scaled by the same factor
            assert C == uncapped[2]
            assert A / uncapped[0] == pytest.approx(D / uncapped[3], rel=1e-12)
        else:
            assert peak <= 0.01
