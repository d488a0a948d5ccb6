"""Analytic ring frequencies (flexbearing.fem_cage.ring_theory) against closed forms and their limits."""
import math

import numpy as np
import pytest

from flexbearing.fem_cage.ring_theory import (thin_ring_inplane_hz, thin_ring_outofplane_hz,
                                  thick_ring_inplane_hz, torsion_constant_rectangle,
                                  cowper_shear_coefficient)
from flexbearing.common.materials import Material

STEEL = Material(density=7850.0, youngs_modulus=200e9, poisson_ratio=0.3)


def test_thin_ring_hoppe_coefficients():
    # Hoppe (1871) / Blevins Table 9-2: f_n / sqrt(EI/(rho A R^4)) * 2 pi = n(n^2-1)/sqrt(n^2+1):
    # n=2: 6/sqrt(5) = 2.683282, n=3: 24/sqrt(10) = 7.589466, n=4: 60/sqrt(17) = 14.552138.
    ro, ri, b = 0.105, 0.095, 0.01
    R, h = 0.1, 0.01
    scale = math.sqrt(STEEL.youngs_modulus * (b * h ** 3 / 12) / (STEEL.density * b * h * R ** 4)) / (2 * math.pi)
    f = thin_ring_inplane_hz([2, 3, 4], ro, ri, b, STEEL) / scale
    assert f == pytest.approx([2.683282, 7.589466, 14.552138], rel=1e-6)


def test_thick_ring_tends_to_thin_ring_as_h_over_R_squared():
    # The shear / rotary-inertia / extension corrections are O((h/R)^2): ten times more slender
    # must shrink the deviation from the thin-ring formula ~100 times (tolerance: 80..120).
    dev = []
    for h in (0.01, 0.001):
        ro, ri, b = 0.1 + h / 2, 0.1 - h / 2, h
        thin = thin_ring_inplane_hz([2, 3, 4], ro, ri, b, STEEL)
        thick = thick_ring_inplane_hz([2, 3, 4], ro, ri, b, STEEL)
        dev.append(np.abs(thick / thin - 1))
    assert np.all(dev[1] < 1e-3)
    assert np.all((dev[0] / dev[1] > 80) & (dev[0] / dev[1] < 120))


def test_thick_ring_rigid_translation_and_softening():
    ro, ri, b = 0.0892, 0.0806, 0.0283
    # n = 1 in-plane flexural branch is a rigid translation: zero frequency up to the round-off of the
    # generalized eigen solve. A symmetric-definite pencil solved through M's Cholesky factor (scipy eigh,
    # LAPACK sygv) returns each eigenvalue within about p(n)·eps·|K|_2·|M^-1|_2 (Golub & Van Loan, Matrix
    # Computations, 4th ed., §8.7.2), p(n) = n = 3 here; so f1 <= sqrt(3·eps·|K|·|M^-1|)/(2·pi) = 0.16 Hz
    # whatever the BLAS (measured 0.0017 Hz on OpenBLAS's Cooperlake kernels, below 1e-6 Hz on others),
    # against f2 = 737 Hz: the branch is rigid to 2e-4 of the first flexural mode.
    from flexbearing.fem_cage.ring_theory import timoshenko_ring_matrices
    k1, m1 = timoshenko_ring_matrices(1, ro, ri, b, STEEL, None, True)
    roundoff = 3 * np.finfo(float).eps * np.linalg.norm(k1, 2) * np.linalg.norm(np.linalg.inv(m1), 2)
    f1 = thick_ring_inplane_hz(1, ro, ri, b, STEEL)
    f2 = thick_ring_inplane_hz(2, ro, ri, b, STEEL)
    assert f1 <= math.sqrt(roundoff) / (2 * math.pi)
    assert math.sqrt(roundoff) / (2 * math.pi) < 1e-3 * f2
    # Shear and rotary inertia only soften: thick < thin, and more so for higher n.
    thin = thin_ring_inplane_hz([2, 3, 4], ro, ri, b, STEEL)
    thick = thick_ring_inplane_hz([2, 3, 4], ro, ri, b, STEEL)
    ratio = thick / thin
    assert np.all(ratio < 1.0) and np.all(np.diff(ratio) < 0)


def test_extensible_kirchhoff_ring_closed_form():
    # Shear-rigid, no rotary inertia, extensible centre line (Hoppe 1871; Rao 2007 §11.4):
    # omega^4 - (1 + n^2)(a + c n^2) omega^2 + a c n^2 (n^2 - 1)^2 = 0,
    # a = E/(rho R^2), c = E I/(rho A R^4); the flexural mode is the lower root.
    ro, ri, b = 0.105, 0.095, 0.01
    R, h = 0.1, 0.01
    a = STEEL.youngs_modulus / (STEEL.density * R ** 2)
    c = STEEL.youngs_modulus * (h ** 2 / 12) / (STEEL.density * R ** 4)
    for n in (2, 3, 4):
        p, q = (1 + n ** 2) * (a + c * n ** 2), a * c * n ** 2 * (n ** 2 - 1) ** 2
        lam = 0.5 * (p - math.sqrt(p * p - 4 * q))
        got = thick_ring_inplane_hz(n, ro, ri, b, STEEL, shear_coefficient=1e6, rotary_inertia=False)
        # k = 1e6: shear flexibility 1e-6 of nominal (nominal effect ~1e-2): < 1e-7 relative.
        assert got == pytest.approx(math.sqrt(lam) / (2 * math.pi), rel=1e-6)


def test_torsion_constant_square_and_thin_strip():
    # Square: J = 0.1406 a^4 (Roark Table 10.7, exact 0.1406); thin strip: J -> a b^3 / 3.
    assert torsion_constant_rectangle(1.0, 1.0) == pytest.approx(0.1406, rel=0.01)
    assert torsion_constant_rectangle(1.0, 0.001) == pytest.approx(1e-9 / 3, rel=1e-3)


def test_cowper_coefficient():
    # Cowper (1966): rectangle, nu = 0.3: k = 13/15.3 = 0.8497.
    assert cowper_shear_coefficient(0.3) == pytest.approx(0.8497, rel=1e-3)


def test_out_of_plane_thin_ring_formula():
    # Blevins Table 9-2 case 2, circular-like check: with E I / (G J) = 1 + nu the n=2 factor is
    # 6/sqrt(4 + 1 + nu). For a square section J = 0.1406 a^4 and I = a^4/12: EI/GJ = 2(1+nu)/(12*0.1406).
    a, R = 0.01, 0.1
    ro, ri = R + a / 2, R - a / 2
    f = thin_ring_outofplane_hz(2, ro, ri, a, STEEL)
    I, A = a ** 4 / 12, a * a
    G = STEEL.youngs_modulus / 2.6
    J = torsion_constant_rectangle(a, a)
    ref = math.sqrt(STEEL.youngs_modulus * I / (STEEL.density * A * R ** 4)) * 6 / math.sqrt(
        4 + STEEL.youngs_modulus * I / (G * J)) / (2 * math.pi)
    assert f == pytest.approx(ref, rel=1e-12)
    assert STEEL.youngs_modulus * I / (G * J) == pytest.approx(2.6 / (12 * 0.1406), rel=0.01)
