"""EHL traction (4106 oil fit) and its slice integration over the contact ellipse."""
import math

import numpy as np
import pytest
from scipy.integrate import quad

from flexbearing.multibody.hertz import effective_modulus, hertz_point_contact, race_curvature_radii
from flexbearing.multibody.traction import (TRACTION_FIT_4106, slice_load_share, slip_polynomial_from_three_points,
                                sliced_traction, traction_coefficient, traction_coefficients,
                                traction_coefficients_table)

E_M50 = effective_modulus(210e9, 0.3, 210e9, 0.3)
K0 = 0.0965788


def check_case():
    # formulas.md check: paper bearing inner contact at alpha 25° (Dw 22 mm, dm 167 mm, fi 0.52),
    # Q 3 kN, 10,000 rpm -> UR = (dm/4)·omega_i·(1 − gamma²) = 43.1 m/s, oil at 373 K.
    rx, ry = race_curvature_radii(0.022, 0.167, 0.52, math.radians(25.0), True)
    omega = 10000 * 2 * math.pi / 60
    g = 0.022 * math.cos(math.radians(25.0)) / 0.167
    ur = 0.25 * 0.167 * omega * (1 - g * g)
    return rx, ry, ur


def test_formulas_md_check_values():
    # The check uses eta0 = 0.055 Pa·s (ambient, 20 °C, as the paper says) with T0 = 373 K:
    # A −0.0204, B 0.0698, C 6.23, D 0.0192, mu(0.1) = 0.0120, mu(0.5) = 0.0198 (printed to 3
    # significant figures; B comes out 0.06987, i.e. the printed 0.0698 is truncated, hence 0.2 %).
    rx, _, ur = check_case()
    assert ur == pytest.approx(43.1, abs=0.05)
    A, B, C, D = traction_coefficients(3000.0, ur, rx, E_M50, 0.055, 373.0, K0)
    assert A == pytest.approx(-0.0204, abs=0.00005)
    assert B == pytest.approx(0.0698, rel=0.002)
    assert C == pytest.approx(6.23, abs=0.005)
    assert D == pytest.approx(0.0192, abs=0.00005)
    assert traction_coefficient(0.1, A, B, C, D) == pytest.approx(0.0120, abs=0.00005)
    assert traction_coefficient(0.5, A, B, C, D) == pytest.approx(0.0198, abs=0.00005)
    # the plateau for large slip is D (the exponential term dies): mu(5) = D within 1e-6
    assert traction_coefficient(5.0, A, B, C, D) == pytest.approx(D, abs=1e-6)


def test_power_law_scalings_of_the_fit():
    # Each coefficient is a power law of Qb, Ub, Tb: doubling the load multiplies A by 2^0.5796 ...
    rx, _, ur = check_case()
    c1 = traction_coefficients(3000.0, ur, rx, E_M50, 0.055, 373.0, K0)
    c2 = traction_coefficients(6000.0, ur, rx, E_M50, 0.055, 373.0, K0)
    c3 = traction_coefficients(3000.0, 2 * ur, rx, E_M50, 0.055, 373.0, K0)
    for i in range(4):
        assert c2[i] / c1[i] == pytest.approx(2 ** TRACTION_FIT_4106[i, 1], rel=1e-12)
        assert c3[i] / c1[i] == pytest.approx(2 ** TRACTION_FIT_4106[i, 2], rel=1e-12)
    # a replaced table is used as given (user-supplied oil)
    table = TRACTION_FIT_4106.copy()
    table[3, 0] *= 2.0
    c4 = traction_coefficients_table(3000.0, ur, rx, E_M50, 0.055, 373.0, K0, table)
    assert c4[3] == pytest.approx(2 * c1[3], rel=1e-14) and c4[:3] == pytest.approx(c1[:3], rel=1e-14)


def test_traction_curve_odd_and_clipped():
    A, B, C, D = -0.0204, 0.0698, 6.23, 0.0192
    for s in np.linspace(0, 2, 41):
        assert traction_coefficient(-s, A, B, C, D) == -traction_coefficient(s, A, B, C, D)
    # A + D < 0: the raw curve is negative at small slip; clipped to zero there
    assert A + D < 0
    assert traction_coefficient(0.0, A, B, C, D) == 0.0
    assert traction_coefficient(1e-4, A, B, C, D) == 0.0
    s = np.linspace(0, 2, 201)
    mu = np.array([traction_coefficient(x, A, B, C, D) for x in s])
    assert np.all(mu >= 0) and mu.max() < 0.03


def test_slice_shares_sum_to_one_and_match_hertz_line_load():
    for n in (1, 2, 7, 40):
        edges = np.linspace(-1, 1, n + 1)
        shares = [slice_load_share(lo, hi) for lo, hi in zip(edges[:-1], edges[1:])]
        assert sum(shares) == pytest.approx(1.0, abs=1e-14)
    # share of |y| < a/2 from the Hertz pressure integrated numerically over the ellipse
    a, b = 2.0, 0.3
    p = lambda y, x: max(0.0, 1 - (x / b) ** 2 - (y / a) ** 2) ** 0.5
    from scipy.integrate import dblquad
    total = dblquad(p, -b, b, -a, a)[0]
    inner = dblquad(p, -b, b, -a / 2, a / 2)[0]
    assert slice_load_share(-0.5, 0.5) == pytest.approx(inner / total, rel=1e-5)


def test_uniform_slip_equals_point_traction():
    A, B, C, D = -0.0204, 0.0698, 6.23, 0.0192
    ur = 43.1
    for s in (-0.3, 0.05, 0.1, 0.5):
        for n in (1, 5, 31):
            tx, ty, mz = sliced_traction(3000.0, 2.6e-3, ur, s * ur, 0.0, 0.0, 0.0, A, B, C, D, n, False)
            assert tx == pytest.approx(3000.0 * traction_coefficient(s, A, B, C, D), rel=1e-13)
            assert ty == 0.0
            assert abs(mz) < 1e-12 * abs(tx) * 2.6e-3 + 1e-15   # symmetric slices: no moment


def reference_integral(Q, a, ur, du0, du1, du2, coeffs):
    """T_x and M_z from the continuous line load (3Q/4a)(1 − y²/a²) (scipy quad)."""
    q = lambda y: 0.75 * Q / a * (1 - (y / a) ** 2)
    mu = lambda y: traction_coefficient((du0 + du1 * y + du2 * y * y) / ur, *coeffs)
    pts = None
    if du1 != 0 or du2 != 0:   # kinks where du = 0 and where the clipping starts
        r = np.roots([du2, du1, du0]) if du2 != 0 else np.array([-du0 / du1])
        pts = [float(x.real) for x in np.atleast_1d(r) if abs(x.imag) < 1e-12 and -a < x.real < a] or None
    tx = quad(lambda y: q(y) * mu(y), -a, a, points=pts, limit=400, epsabs=1e-12)[0]
    mz = quad(lambda y: -y * q(y) * mu(y), -a, a, points=pts, limit=400, epsabs=1e-14)[0]
    return tx, mz


def test_sliced_traction_converges_with_spin():
    # Spin omega_s of the race relative to the ball about the normal z: the relative surface
    # velocity omega_s·z × (x, y) has x-component du(y) = du0 − omega_s·y.
    # The midpoint slices converge to the continuous integral; error at n = 40 below 0.5 % and
    # falling with n (the curve has a kink where the slip changes sign, so O(1/n)–O(1/n²)).
    coeffs = (-0.0204, 0.0698, 6.23, 0.0192)
    Q, a, ur = 3000.0, 2.64e-3, 43.1
    du0, omega_s = 0.02 * ur, 400.0          # du1 = −omega_s: 1.06 m/s at the ellipse ends
    ref_tx, ref_mz = reference_integral(Q, a, ur, du0, -omega_s, 0.0, coeffs)
    errs = []
    for n in (5, 10, 20, 40, 80):
        tx, _, mz = sliced_traction(Q, a, ur, du0, -omega_s, 0.0, 0.0, *coeffs, n, False)
        errs.append((abs(tx / ref_tx - 1), abs(mz / ref_mz - 1)))
    assert errs[3][0] < 5e-3 and errs[3][1] < 5e-3
    assert errs[4][0] < errs[1][0] and errs[4][1] < errs[1][1]
    # the traction moment on the ball has the sign of omega_s: it drags the ball toward the race's
    # spin, i.e. it resists the relative spin
    assert ref_mz > 0


def test_three_point_profile_and_curvature_term():
    a = 2e-3
    du0, du1, du2 = slip_polynomial_from_three_points(a, 0.3, 0.1, 0.5)
    for y, v in ((-a, 0.3), (0.0, 0.1), (a, 0.5)):
        assert du0 + du1 * y + du2 * y * y == pytest.approx(v, rel=1e-12)
    coeffs = (-0.0204, 0.0698, 6.23, 0.0192)
    ref_tx, _ = reference_integral(3000.0, a, 43.1, du0, du1, du2, coeffs)
    tx, _, _ = sliced_traction(3000.0, a, 43.1, du0, du1, du2, 0.0, *coeffs, 80, False)
    assert tx == pytest.approx(ref_tx, rel=2e-3)


def test_transverse_option():
    coeffs = (-0.0204, 0.0698, 6.23, 0.0192)
    ur = 43.1
    # pure transverse slip: T_x = 0, T_y = Q·mu(dv/UR)
    tx, ty, mz = sliced_traction(3000.0, 2e-3, ur, 0.0, 0.0, 0.0, 0.1 * ur, *coeffs, 10, True)
    assert tx == pytest.approx(0.0, abs=1e-12)
    assert ty == pytest.approx(3000.0 * traction_coefficient(0.1, *coeffs), rel=1e-12)
    # combined slip: the force is along the slip vector with mu(|s|)
    du, dv = 0.3 * ur, 0.4 * ur
    tx, ty, _ = sliced_traction(3000.0, 2e-3, ur, du, 0.0, 0.0, dv, *coeffs, 10, True)
    mu = traction_coefficient(0.5, *coeffs)
    assert (tx, ty) == pytest.approx((3000.0 * mu * 0.6, 3000.0 * mu * 0.8), rel=1e-12)
    # the default (transverse off) ignores dv
    tx0, ty0, _ = sliced_traction(3000.0, 2e-3, ur, du, 0.0, 0.0, dv, *coeffs, 10, False)
    assert ty0 == 0.0 and tx0 == pytest.approx(3000.0 * traction_coefficient(0.3, *coeffs), rel=1e-12)


def test_real_contact_end_to_end():
    # The paper-bearing inner contact at 3 kN: with the exact Hertz a, a 2 % uniform slip gives
    # T = Q·mu(0.02) and the traction is well below Coulomb-like values (mu < 0.03).
    rx, ry, ur = check_case()
    a, b, p0, delta = hertz_point_contact(rx, ry, E_M50, 3000.0)
    c = traction_coefficients(3000.0, ur, rx, E_M50, 0.055, 373.0, K0)
    tx, _, _ = sliced_traction(3000.0, a, ur, 0.3 * ur, 0.0, 0.0, 0.0, *c, 20, False)
    assert tx == pytest.approx(3000.0 * traction_coefficient(0.3, *c), rel=1e-13)
    assert 0 < tx < 0.03 * 3000.0


def test_origin_law_passes_through_zero_with_the_fits_plateau():
    """Origin law (module docstring): A = −D, so mu(s) = D·(1 − e^{−Cs}) + B·s·e^{−Cs} in closed
    form (1e-12), mu(0) = 0, mu'(0) = B + C·D (central difference of the closed form, step 1e-7:
    truncation ~1e-7 relative), odd, and the fit's plateau D at large slip (C = 5.9 here: e^{−5C} ≈ 2e-13). Conditions: the light outer contact of slip-rate test case 1 (Q 205 N, UR 18.6 m/s,
    Rx 12.4 mm), where the fit itself has a dead zone (mu = 0 for s < 0.03)."""
    from flexbearing.multibody.traction import TRACTION_ORIGIN_4106
    args = (205.3, 18.55, 0.012407, E_M50, 0.055, 413.15, K0)
    A, B, C, D = traction_coefficients_table(*args, TRACTION_FIT_4106)
    assert A + D < 0 and traction_coefficient(0.02, A, B, C, D) == 0.0      # the fit's dead zone
    a0, b0, c0, d0 = traction_coefficients_table(*args, TRACTION_ORIGIN_4106)
    assert (b0, c0, d0) == pytest.approx((B, C, D), rel=1e-14) and a0 == -d0
    for s in (1e-4, 1e-3, 0.01, 0.05, 0.3, 1.0):
        closed = d0 * (1 - math.exp(-c0 * s)) + b0 * s * math.exp(-c0 * s)
        assert traction_coefficient(s, a0, b0, c0, d0) == pytest.approx(closed, rel=1e-12)
        assert traction_coefficient(-s, a0, b0, c0, d0) == -traction_coefficient(s, a0, b0, c0, d0)
    assert traction_coefficient(0.0, a0, b0, c0, d0) == 0.0
    h = 1e-7
    slope = (traction_coefficient(h, a0, b0, c0, d0) - traction_coefficient(-h, a0, b0, c0, d0)) / (2 * h)
    assert slope == pytest.approx(b0 + c0 * d0, rel=1e-6)
    assert traction_coefficient(5.0, a0, b0, c0, d0) == pytest.approx(d0, rel=1e-9)
