"""The cage orbit relative to what guides the cage (flexbearing.multibody.cage_offset; the report's
cage-motion table, flexbearing.analysis.cage_motion): the outer ring's centre for the outer land,
the inner ring's for the inner land (the land turns and moves with the ring), the balls' pitch
circle's for ball guidance.

Hand-constructed cases: balls on an exactly offset circle, spaced about its centre or about the
bearing axis (the fitted centre is the circle's either way: Kåsa's fit is exact for points on a
circle; round-off of |p|² ~ R² leaves ~1e-17 m); a cage whirling at half the cage speed about an
inner ring that sits 0.5 mm off the axis (whirl ratio 0.5 about the ring, none about the axis).
"""
import math

import numpy as np
import pytest

from flexbearing.multibody.cage_offset import GUIDE_REFERENCE, ball_set_centre, cage_offset_from_guide

R = 83.5e-3        # m, pitch radius of the paper bearing


def test_offset_from_each_guide():
    c, i = np.array([1.2e-4, -0.9e-4]), np.array([2e-5, -3e-5])
    z = 14
    b = np.array([3e-5, -2e-5])
    theta = 2 * np.pi * np.arange(z) / z + 0.3
    for spacing in ("about the circle's centre", "about the axis"):
        u = np.stack([np.cos(theta), np.sin(theta)], axis=1)
        if spacing == "about the axis":           # |b + rho u'| along u: rho from the circle
            s = u @ b
            rho = s + np.sqrt(s * s - b @ b + R * R)
            p = rho[:, None] * u
        else:
            p = b + R * u
        r, psi_abs = np.hypot(p[:, 0], p[:, 1]), np.arctan2(p[:, 1], p[:, 0])
        assert np.linalg.norm(p - b, axis=1) == pytest.approx(R, rel=1e-14)
        assert ball_set_centre(r, psi_abs) == pytest.approx(b, abs=1e-15)
    assert cage_offset_from_guide("outer", c, i, r, psi_abs) == pytest.approx(c, abs=0)
    assert cage_offset_from_guide("inner", c, i, r, psi_abs) == pytest.approx(c - i, abs=1e-20)
    assert cage_offset_from_guide(2, c, i, r, psi_abs) == pytest.approx(c - b, abs=1e-15)


def test_recorded_offset_is_relative_to_the_inner_ring():
    """evaluate_outputs of an inner-guided bearing with the ring and the cage displaced: the
    recorded offset is cage − ring (the orbit about the ring's centre), and the model's
    eccentricity ratio is the offset from the land's axis in the cage's plane over Cg: the axis
    moves with the ring's tilt, by (tilt_z·l, −tilt_y·l) at the lever l = x_cage − x_ring
    (guide_land.inner_land_offset; ~1e-4 of the offset here)."""
    from flexbearing.multibody.bearing import PAPER_OIL
    from flexbearing.multibody import model as M
    from flexbearing.multibody.model import build_model
    from flexbearing.multibody.outputs import evaluate_outputs
    from test_guidance import OMEGA, _bearing, _displaced_state
    m = build_model(_bearing("inner"), PAPER_OIL)
    y = _displaced_state(m, dy_cage=(1.2e-4, -0.9e-4), ring_offset=(2e-5, -3e-5))
    out = evaluate_outputs(m, 0.0, y, np.array([[0.0, OMEGA]]), np.array([[0.0, 55e3, 0.0, -4e3]]), np.zeros((0, 6)))
    assert out["cage_guide_offset"] == pytest.approx([1.2e-4, -0.9e-4], abs=1e-18)
    from flexbearing.multibody.state_layout import (CAGE_X, RING_TILT_Y, RING_TILT_Z, RING_X, cage_offset,
                                                    ring_offset)
    r0, c0 = ring_offset(m.n_balls), cage_offset(m.n_balls)
    lever = y[c0 + CAGE_X] - y[r0 + RING_X]
    e_land = (1.2e-4 - y[r0 + RING_TILT_Z] * lever, -0.9e-4 + y[r0 + RING_TILT_Y] * lever)
    assert out["cage_eccentricity_ratio"] == pytest.approx(math.hypot(*e_land) / m.p[M.P_CG], rel=1e-12)


def _inner_guided_outputs(with_offset=True):
    """A cage whirling at Omega = omega_c/2 on a circle of 0.3·Cg about an inner ring held 0.5 mm
    off the axis, 4 whirl periods sampled 400 times."""
    cg, wc = 0.375e-3, 600.0
    t = np.linspace(0.0, 4 * 2 * np.pi / (0.5 * wc), 401)
    ring = np.array([0.5e-3, 0.0])
    e = 0.3 * cg * np.stack([np.cos(0.5 * wc * t), np.sin(0.5 * wc * t)], axis=1)
    centre = np.column_stack([np.zeros_like(t), ring + e])
    out = {"time": t, "cage_centre": centre, "cage_speed": np.full_like(t, wc),
           "cage_eccentricity_ratio": np.full_like(t, 0.3)}
    if with_offset:
        out["cage_guide_offset"] = np.array([cage_offset_from_guide("inner", c[1:], ring, None, None) for c in centre])
    return out


def test_orbit_table_of_an_inner_guided_cage_is_about_the_ring():
    """About the ring: whirl ratio 0.5 (the net whirl angle, exact up to rounding: 4 whole whirl
    turns over 8 cage turns by the trapezoidal rule of a constant speed); about the axis it would be 0."""
    from flexbearing.analysis.cage_motion import motion_arrays, window_motion
    m = motion_arrays(_inner_guided_outputs(), "inner")
    assert m["reference"] == GUIDE_REFERENCE["inner"]
    row = window_motion(m["t"], m["centre_yz"], m["cage_speed"], eccentricity_ratio=m["eccentricity_ratio"])
    assert row["whirl_ratio"] == pytest.approx(0.5, abs=1e-12)
    old = motion_arrays(_inner_guided_outputs(with_offset=False), "inner")
    assert "recorded without the offset" in old["reference"]
    row_abs = window_motion(old["t"], old["centre_yz"], old["cage_speed"], eccentricity_ratio=old["eccentricity_ratio"])
    assert abs(row_abs["whirl_ratio"]) < 1e-12
