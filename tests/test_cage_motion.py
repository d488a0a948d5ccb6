"""flexbearing.analysis.cage_motion against orbits whose whirl ratio and velocity dispersion are known in
closed form.

- Circle of radius r whirling at Omega, cage speed omega(t) = w0 + a·t: the whirl ratio is
  Omega·T/(w0·T + a·T²/2) (the trapezoidal rule is exact on a linear speed; the unwrapped angle
  is exact while Omega·dt < pi), and the central-difference centre speed is r·sin(Omega·dt)/dt at
  every sample, so the dispersion is 0 (rounding: 1e-12).
- Ellipse y = a·cos(Omega t), z = b·sin(Omega t): |v| = Omega·sqrt(a² sin² + b² cos²), whose
  mean over a period is (2/pi)·Omega·a·E(m), m = 1 − b²/a² (complete elliptic integral of the
  second kind), and mean square Omega²(a² + b²)/2. The central difference scales every velocity
  component of a sinusoid by the same sin(Omega·dt)/(Omega·dt), so the dispersion std/mean is
  exact at any dt, and the mean over whole periods of uniform samples is the periodic trapezoidal
  rule (spectrally accurate): tolerance 1e-10.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ellipe

from flexbearing.analysis import cage_motion as CM
from flexbearing.common.validation import InputError


def _circle(r=20e-6, omega=300.0, w0=600.0, a=2000.0, dt=1e-4, n=2001, sense=1.0):
    t = np.arange(n) * dt
    c = r * np.stack([np.cos(sense * omega * t + 0.3), np.sin(sense * omega * t + 0.3)], axis=1)
    return t, c, w0 + a * t


def test_circular_whirl_ratio_and_zero_dispersion():
    r, omega, w0, a = 20e-6, 300.0, 600.0, 2000.0
    t, c, w = _circle(r, omega, w0, a)
    T = t[-1]
    row = CM.window_motion(t, c, w, clearance=100e-6)
    assert row["whirl_ratio"] == pytest.approx(omega * T / (w0 * T + 0.5 * a * T * T), rel=1e-12)
    assert row["whirl_rate_mean"] == pytest.approx(omega, rel=1e-12)
    assert row["cage_revolutions"] == pytest.approx((w0 * T + 0.5 * a * T * T) / (2 * math.pi), rel=1e-12)
    assert row["velocity_dispersion"] == pytest.approx(0.0, abs=1e-12)
    dt = t[1] - t[0]
    assert row["centre_speed_mean"] == pytest.approx(r * math.sin(omega * dt) / dt, rel=1e-12)
    assert row["eps_mean"] == pytest.approx(0.2, rel=1e-12) and row["eps_max"] == pytest.approx(0.2, rel=1e-12)
    assert row["rim_fraction"] == 0.0


def test_backward_whirl_is_negative_and_the_rim_fraction_counts_samples():
    t, c, w = _circle(sense=-1.0)
    row = CM.window_motion(t, c, w, clearance=100e-6)
    assert row["whirl_ratio"] < 0.0
    eps = np.where(t < t[1000], 0.5, 1.0)        # samples 1000 … 2000 on the rim: 1001 of 2001
    row = CM.window_motion(t, c, w, eccentricity_ratio=eps)
    assert row["rim_fraction"] == pytest.approx(1001 / 2001, rel=1e-12)
    assert row["eps_max"] == 1.0


@pytest.mark.parametrize("b_over_a", [1.0, 0.6, 0.2])
def test_elliptic_orbit_dispersion_equals_the_elliptic_integral(b_over_a):
    a, omega = 30e-6, 250.0
    b = b_over_a * a
    period = 2 * math.pi / omega
    m_per = 400
    dt = period / m_per                                  # interior samples: 3 whole periods
    t = (np.arange(3 * m_per + 2) - 1) * dt
    c = np.stack([a * np.cos(omega * t), b * np.sin(omega * t)], axis=1)
    row = CM.window_motion(t, c, np.full(t.size, 500.0), clearance=100e-6)
    m = 1.0 - b_over_a ** 2
    mean_v = 2.0 / math.pi * omega * a * ellipe(m)
    rms2 = 0.5 * omega ** 2 * (a * a + b * b)
    expected = math.sqrt(max(rms2 - mean_v ** 2, 0.0)) / mean_v
    assert row["velocity_dispersion"] == pytest.approx(expected, abs=1e-10)
    sinc = math.sin(omega * dt) / (omega * dt)
    assert row["centre_speed_mean"] == pytest.approx(mean_v * sinc, rel=1e-10)
    if b_over_a == 0.2:
        assert expected > 0.3              # a flat orbit: far from a steady whirl


def test_centred_cage_has_no_whirl_ratio():
    t, c, w = _circle(r=1e-7)
    row = CM.window_motion(t, c, w, clearance=100e-6)     # eps 0.001 < MIN_EPS
    assert row["whirl_ratio"] is None and row["whirl_rate_mean"] is None
    assert row["eps_mean"] == pytest.approx(1e-3, rel=1e-9)


def test_normalised_orbit_is_centre_over_clearance():
    t, c, w = _circle()
    eps = np.hypot(c[:, 0], c[:, 1]) / 80e-6
    np.testing.assert_allclose(CM.normalised_orbit(c, eps), c / 80e-6, rtol=1e-14)
    assert np.all(CM.normalised_orbit(np.zeros((3, 2)), np.zeros(3)) == 0.0)


def test_bad_input_is_refused():
    t, c, w = _circle(n=10)
    with pytest.raises(InputError, match=r"centre_yz has shape \(10, 3\)"):
        CM.window_motion(t, np.zeros((10, 3)), w, clearance=1e-4)
    with pytest.raises(InputError, match="cage_speed has 9 values"):
        CM.window_motion(t, c, w[:9], clearance=1e-4)
    with pytest.raises(InputError, match=r"clearance = -1.*> 0 m"):
        CM.window_motion(t, c, w, clearance=-1.0)
    with pytest.raises(InputError, match="increase strictly"):
        CM.window_motion(t[::-1], c, w, clearance=1e-4)


def test_held_fraction_counts_the_samples_at_rest():
    """A half-frequency whirl at e = 0.5 Cg (centre speed ½·omega_c·e = 5 × the threshold
    HELD_SPEED·½·omega_c·Cg) that stops at sample 999 and stays there: the central-difference speed
    is zero at the interior samples 1000 … 1999, so 1000 of the 1999 interior samples are held;
    the clearance is recovered from eps = |c|/Cg when it is not given. A centre vibrating at 0.02 Cg
    at the whirl frequency (speed 0.2 of the threshold) is held throughout."""
    cg, w_c, n, dt = 100e-6, 600.0, 2001, 1e-4
    t = np.arange(n) * dt
    phase = 0.5 * w_c * np.minimum(t, t[999])
    c = 0.5 * cg * np.stack([np.cos(phase), np.sin(phase)], axis=1)
    w = np.full(n, w_c)
    row = CM.window_motion(t, c, w, clearance=cg)
    assert row["held_fraction"] == pytest.approx(1000 / 1999, rel=1e-12)
    eps = np.hypot(c[:, 0], c[:, 1]) / cg
    assert CM.window_motion(t, c, w, eccentricity_ratio=eps)["held_fraction"] == pytest.approx(1000 / 1999, rel=1e-12)
    whirl = 0.5 * cg * np.stack([np.cos(0.5 * w_c * t), np.sin(0.5 * w_c * t)], axis=1)
    assert CM.window_motion(t, whirl, w, clearance=cg)["held_fraction"] == 0.0
    shake = np.stack([0.3 * cg + 0.02 * cg * np.cos(0.5 * w_c * t), np.full(n, 0.1 * cg)], axis=1)
    assert CM.window_motion(t, shake, w, clearance=cg)["held_fraction"] == 1.0
