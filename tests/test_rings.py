"""The rings drawn for ParaView (flexbearing.analysis.rings) against their defining geometry: the
outer ring's cross-section area against the rectangle minus the circular segment of its groove
(exact for the polygon: each chord of angle theta leaves r^2 (theta - sin theta)/2 of the
segment uncut), the inner gothic arch tangent to a ball at rest at the shim angle, the surface of
revolution at the profile's radii, and the placement of the inner ring."""
import math

import numpy as np
import pytest
from tolerances import assert_within, dot_bound, gamma

from flexbearing.analysis import rings
from flexbearing.multibody.bearing import PAPER_BEARING as BEARING


def test_outer_ring_area_is_the_rectangle_minus_its_groove_segment():
    b = BEARING
    p = rings.outer_ring_profile(b)
    ro = b.fe * b.ball_diameter
    rc = 0.5 * b.pitch_diameter + 0.5 * b.ball_diameter - ro
    h = 0.5 * b.guide_land_diameter - rc                   # chord's distance from the arc centre
    half = math.acos(h / ro)
    segment = ro * ro * half - h * math.sqrt(ro * ro - h * h)
    n = rings.N_GROOVE - 1
    theta = 2.0 * half / n
    uncut = n * 0.5 * ro * ro * (theta - math.sin(theta))   # the polygon's chords leave this of the segment
    rect = b.width * 0.5 * (b.outside_diameter - b.guide_land_diameter)
    # the shoelace's n-term sum over coordinates ~0.09 m cancels to the area (its absolute terms
    # are 150 x the area here): dot_bound of those terms (+2 roundings a term), against the
    # closed form's chain of <= 15 roundings (acos, sqrt, sin within 4 ulp) on its three terms
    ab = np.abs(p.x * np.roll(p.r, -1)).sum() + np.abs(np.roll(p.x, -1) * p.r).sum()
    assert_within(abs(rings.profile_area(p) - (rect - segment + uncut)),
                  0.5 * dot_bound(len(p.x) + 2, ab) + 2 * gamma(15) * (abs(rect) + abs(segment) + abs(uncut)),
                  "ring profile area", effect=uncut)
    # the groove points lie on the arc whose bottom, rc + ro, touches the ball on the pitch circle
    groove = (p.r > 0.5 * b.guide_land_diameter) & (p.r < 0.5 * b.outside_diameter)
    assert groove.sum() == rings.N_GROOVE - 2
    assert np.allclose(np.hypot(p.x[groove], p.r[groove] - rc), ro, rtol=0, atol=1e-15)
    assert rc + ro == pytest.approx(0.5 * (b.pitch_diameter + b.ball_diameter), rel=1e-15)


def test_inner_gothic_arch_touches_a_ball_at_rest_at_the_shim_angle():
    b = BEARING
    p = rings.inner_ring_profile(b)
    ri, off = b.fi * b.ball_diameter, (b.fi - 0.5) * b.ball_diameter
    rp = 0.5 * b.pitch_diameter
    groove = (p.r > 0.5 * b.bore_diameter) & (p.r < p.r.max() - 1e-12)
    for side in (1, -1):
        xc, rc = -side * off * math.sin(b.shim_angle), rp + off * math.cos(b.shim_angle)
        pts = groove & (side * p.x >= 0)
        # every groove point of this half lies on its arc ...
        assert np.allclose(np.hypot(p.x[pts] - xc, p.r[pts] - rc), ri, rtol=0, atol=1e-15)
        # ... whose centre is (f_i - 1/2) D_w from the ball's centre: internally tangent to the ball
        assert math.hypot(xc, rc - rp) + 0.5 * b.ball_diameter == pytest.approx(ri, rel=1e-14)
        # the contact point, along the line from the arc centre through the ball centre, is at the
        # shim angle from the radial plane
        angle = math.atan2(abs(0.0 - xc), rc - rp)
        assert angle == pytest.approx(b.shim_angle, rel=1e-14)
    assert rings.profile_area(p) > 0


def test_surface_of_revolution_sits_at_the_profile_radii():
    p = rings.outer_ring_profile(BEARING)
    s = rings.revolve(p, n_azimuth=36)
    n = len(p.x)
    assert s.points.shape == (36 * n, 3) and s.quads.shape == (36 * n, 4)
    r = np.hypot(s.points[:, 1], s.points[:, 2]).reshape(36, n)
    assert np.allclose(r, p.r[None, :], rtol=1e-15, atol=0)
    assert np.array_equal(s.points[:, 0].reshape(36, n), np.broadcast_to(p.x, (36, n)))
    # every node belongs to four quads (a closed surface of revolution)
    assert np.all(np.bincount(s.quads.ravel(), minlength=len(s.points)) == 4)


def test_inner_ring_placement_moves_and_tilts_it():
    Ac = rings.inner_ring_placement(np.array([1e-5, -2e-5, 3e-5]), np.array([0.0, 0.0]))
    assert np.array_equal(Ac[:, :3], np.eye(3)) and np.array_equal(Ac[:, 3], [1e-5, -2e-5, 3e-5])
    Ac = rings.inner_ring_placement(np.zeros(3), np.array([1e-3, 0.0]))
    # a tilt about y turns the axis x towards -z (right-handed R_y)
    x = Ac[:, :3] @ np.array([1.0, 0.0, 0.0])
    assert x == pytest.approx([math.cos(1e-3), 0.0, -math.sin(1e-3)], abs=1e-15)
