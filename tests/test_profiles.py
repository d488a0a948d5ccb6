"""Speed and load spectra (flexbearing.multibody.profiles) against hand-computed values."""
import math

import numpy as np
import pytest
from scipy.integrate import trapezoid     # numpy 2 has no np.trapz, numpy 1.24 no np.trapezoid

from flexbearing.multibody.profiles import (HALF_SINE, RECTANGULAR, breakpoints, impact_factor, load_at,
                                speed_angle_at, speed_at, speed_derivative_at)

RPM = 2.0 * math.pi / 60.0
# paper unsteady spectrum (SPEC §6): 10,000 -> 14,000 rpm in 0.2 s, 0.2 s uniform, back in 0.2 s
UNSTEADY = np.array([[0.0, 10000 * RPM], [0.2, 14000 * RPM], [0.4, 14000 * RPM], [0.6, 10000 * RPM]])


def test_speed_piecewise_linear_and_constant_outside():
    # exact arithmetic on a piecewise-linear function: tolerance is float rounding only
    assert speed_at(-1.0, UNSTEADY) == UNSTEADY[0, 1]
    assert speed_at(0.1, UNSTEADY) == pytest.approx(12000 * RPM, rel=1e-14)
    assert speed_at(0.2, UNSTEADY) == pytest.approx(14000 * RPM, rel=1e-14)
    assert speed_at(0.3, UNSTEADY) == pytest.approx(14000 * RPM, rel=1e-14)
    assert speed_at(0.55, UNSTEADY) == pytest.approx(11000 * RPM, rel=1e-14)
    assert speed_at(0.6, UNSTEADY) == UNSTEADY[-1, 1]
    assert speed_at(5.0, UNSTEADY) == UNSTEADY[-1, 1]


def test_speed_derivative_is_phase_acceleration():
    acc = 4000 * RPM / 0.2     # rad/s^2 of the linear acceleration phase
    assert speed_derivative_at(0.05, UNSTEADY) == pytest.approx(acc, rel=1e-13)
    assert speed_derivative_at(0.0, UNSTEADY) == pytest.approx(acc, rel=1e-13)   # right derivative
    assert speed_derivative_at(0.3, UNSTEADY) == 0.0
    assert speed_derivative_at(0.5, UNSTEADY) == pytest.approx(-acc, rel=1e-13)
    assert speed_derivative_at(-0.1, UNSTEADY) == 0.0
    assert speed_derivative_at(0.7, UNSTEADY) == 0.0


def test_speed_angle_is_integral_of_speed():
    # phi(0.6) = area of the trapezoid profile = 0.2*(10k+14k)/2 + 0.2*14k + 0.2*(14k+10k)/2 rpm*s
    expected = (0.2 * 12000 + 0.2 * 14000 + 0.2 * 12000) * RPM
    assert speed_angle_at(0.6, UNSTEADY) == pytest.approx(expected, rel=1e-13)
    # half-way up the ramp: 0.1 s at mean speed 11,000 rpm
    assert speed_angle_at(0.1, UNSTEADY) == pytest.approx(0.1 * 11000 * RPM, rel=1e-13)
    # beyond the table: constant last speed
    assert speed_angle_at(0.7, UNSTEADY) == pytest.approx(expected + 0.1 * 10000 * RPM, rel=1e-13)


def test_single_point_table_is_constant():
    table = np.array([[0.0, 14000 * RPM]])
    for t in (-1.0, 0.0, 0.3, 10.0):
        assert speed_at(t, table) == 14000 * RPM
        assert speed_derivative_at(t, table) == 0.0
    assert speed_angle_at(0.6, table) == pytest.approx(0.6 * 14000 * RPM, rel=1e-14)


def test_load_ramp_and_half_sine_impact():
    # axial ramp 0 -> 55 kN over 0.1 s, constant radial 4 kN along -z; 50 kN half-sine impact along
    # -z from 0.09 s for 0.02 s (paper §4.2)
    table = np.array([[0.0, 0.0, 0.0, -4000.0], [0.1, 55000.0, 0.0, -4000.0]])
    impacts = np.array([[0.09, 0.02, 0.0, 0.0, -50000.0, HALF_SINE]])
    out = np.zeros(3)
    load_at(0.05, table, impacts, out)
    np.testing.assert_allclose(out, [27500.0, 0.0, -4000.0], rtol=1e-14)
    load_at(0.10, table, impacts, out)   # impact peak at its centre
    np.testing.assert_allclose(out, [55000.0, 0.0, -54000.0], rtol=1e-12)
    load_at(0.095, table, impacts, out)  # quarter of the impact: sin(pi/4)
    np.testing.assert_allclose(out, [55000.0 * 0.95, 0.0, -4000.0 - 50000.0 * math.sin(math.pi / 4)],
                               rtol=1e-12)
    load_at(0.2, table, impacts, out)
    np.testing.assert_allclose(out, [55000.0, 0.0, -4000.0], rtol=1e-14)
    load_at(-0.2, table, impacts, out)
    np.testing.assert_allclose(out, [0.0, 0.0, -4000.0], rtol=1e-14)


def test_rectangular_impact_and_superposition():
    table = np.array([[0.0, 1000.0, 200.0, 0.0]])
    impacts = np.array([[0.1, 0.01, 0.0, 300.0, 400.0, RECTANGULAR],
                        [0.105, 0.01, 10.0, 0.0, 0.0, RECTANGULAR]])
    out = np.zeros(3)
    load_at(0.1, table, impacts, out)
    np.testing.assert_allclose(out, [1000.0, 500.0, 400.0])
    load_at(0.107, table, impacts, out)   # both active
    np.testing.assert_allclose(out, [1010.0, 500.0, 400.0])
    load_at(0.111, table, impacts, out)   # first ended, second active
    np.testing.assert_allclose(out, [1010.0, 200.0, 0.0])
    load_at(0.2, table, impacts, out)
    np.testing.assert_allclose(out, [1000.0, 200.0, 0.0])
    assert impact_factor(0.11, 0.1, 0.01, RECTANGULAR) == 0.0   # half-open [t0, t0+T)
    assert impact_factor(0.11, 0.1, 0.01, HALF_SINE) == pytest.approx(0.0, abs=1e-12)  # sin(pi) rounding


def test_half_sine_impulse():
    # integral of F·sin(pi t/T) over [0, T] = 2·F·T/pi (trapezoid on 20001 points: error ~ 1e-9)
    t = np.linspace(0.0, 0.02, 20001)
    f = np.array([impact_factor(ti, 0.0, 0.02, HALF_SINE) for ti in t])
    assert trapezoid(f, t) == pytest.approx(2 * 0.02 / math.pi, rel=1e-7)


def test_breakpoints():
    impacts = np.array([[0.09, 0.02, 0, 0, -1, 0]], dtype=float)
    bp = breakpoints(UNSTEADY, np.array([[0.0, 0, 0, 0]]), impacts)
    np.testing.assert_allclose(bp, [0.0, 0.09, 0.11, 0.2, 0.4, 0.6])
