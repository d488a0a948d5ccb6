"""The bearing's rings for ParaView: their cross-sections revolved about the bearing axis.

A ring is drawn as the surface of revolution of its cross-section (the profile in the (x, r)
half-plane: x along the bearing axis, r the radius), from the bearing's dimensions
(flexbearing.multibody.bearing.Bearing, paper Table 1):

    outer ring   r from the guide land, d_land/2, to D/2 over the width B, with one circular
                 groove of radius r_o = f_e D_w whose bottom is at r_p + D_w/2:
                     r(x) = r_p + D_w/2 - r_o + sqrt(r_o^2 - x^2)
    inner ring   r from d/2 to the shoulder 2 r_p - d_land/2 (the outer ring's land mirrored about
                 the pitch circle), with the gothic arch of the two-piece ring: the half on the
                 side s = ±1 of the shim is an arc of radius r_i = f_i D_w about
                     (x_c, r_c) = (-s (f_i - 1/2) D_w sin(alpha_D), r_p + (f_i - 1/2) D_w cos(alpha_D))
                 so that a ball at rest on the pitch circle touches it at the shim angle alpha_D
                     r(x) = r_c - sqrt(r_i^2 - (x - x_c)^2),  s x >= 0

(the groove geometry of angular contact and split-inner-ring bearings: Harris & Kotzalas, Rolling
Bearing Analysis, 5th ed., 2007, vol. 1 ch. 2; the model's own contact geometry is
flexbearing.multibody.geometry, which this module does not replace). Radial clearance, ring
chamfers and the shim's gap are not drawn: the picture is for orientation, not for measuring.

Placement: the outer ring is fixed (the bearing frame); the inner ring's centre is at its
recorded displacement (/outputs/inner_ring_position, m) and its axis tilted by
/outputs/inner_ring_tilt (tilt_y, tilt_z, rad) as the cage's tilt is applied (R_z R_y,
flexbearing.multibody.cage_body.cage_rotation with no spin). A surface of revolution does not
change when the ring spins about its own axis, so its spin is not drawn.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

N_AZIMUTH = 144          # facets around the circumference: 2.5° each, a smooth silhouette
N_GROOVE = 24            # points on each groove arc


class RingProfile(NamedTuple):
    """A closed cross-section polygon, (n, 2) columns x [m], r [m], counter-clockwise in (x, r)."""
    x: np.ndarray
    r: np.ndarray


def outer_ring_profile(b) -> RingProfile:
    """The outer ring's cross-section (module doc) of a Bearing `b`."""
    B, R_out = 0.5 * b.width, 0.5 * b.outside_diameter
    land = 0.5 * b.guide_land_diameter
    ro = b.fe * b.ball_diameter
    rc = 0.5 * b.pitch_diameter + 0.5 * b.ball_diameter - ro      # groove centre radius
    if not rc < land < rc + ro:
        raise ValueError(f"guide land radius {land:g} m does not cut the outer groove (centre {rc:g} m, radius {ro:g} m)")
    half = math.acos((land - rc) / ro)                             # the groove's edges on the land
    a = np.linspace(half, -half, N_GROOVE)                         # equal angles along the arc
    xs, groove_r = ro * np.sin(a), rc + ro * np.cos(a)
    x = np.r_[-B, B, B, xs, -B]
    r = np.r_[R_out, R_out, land, groove_r, land]
    return RingProfile(x[::-1].copy(), r[::-1].copy())


def inner_ring_profile(b) -> RingProfile:
    """The inner ring's cross-section (module doc) of a Bearing `b`."""
    B, r_bore = 0.5 * b.width, 0.5 * b.bore_diameter
    rp = 0.5 * b.pitch_diameter
    shoulder = 2.0 * rp - 0.5 * b.guide_land_diameter
    ri = b.fi * b.ball_diameter
    off = (b.fi - 0.5) * b.ball_diameter
    xc, rc = off * math.sin(b.shim_angle), rp + off * math.cos(b.shim_angle)
    if not rc - ri < shoulder < rc:
        raise ValueError(f"inner shoulder radius {shoulder:g} m does not cut the inner groove")
    xg = -xc + math.sqrt(ri * ri - (shoulder - rc) ** 2)            # the +x half's edge, on the shoulder
    xs = np.linspace(0.0, xg, N_GROOVE)                            # +x half: centre at -xc
    half = rc - np.sqrt(ri * ri - (xs + xc) ** 2)
    x = np.r_[-B, B, B, xs[::-1], -xs[1:], -B]
    r = np.r_[r_bore, r_bore, shoulder, half[::-1], half[1:], shoulder]
    return RingProfile(x, r)


def profile_area(p: RingProfile) -> float:
    """Area of the cross-section (shoelace formula), m^2; > 0 for a counter-clockwise profile in (x, r)."""
    return 0.5 * float(np.sum(p.x * np.roll(p.r, -1) - np.roll(p.x, -1) * p.r))


class RingSurface(NamedTuple):
    points: np.ndarray       # (n_profile * n_azimuth, 3) m, bearing frame (x axis)
    quads: np.ndarray        # (n_profile * n_azimuth, 4) node indices


def revolve(p: RingProfile, n_azimuth: int = N_AZIMUTH) -> RingSurface:
    """The surface of revolution of a closed profile about the x axis, as quadrilaterals."""
    n = len(p.x)
    phi = 2.0 * np.pi * np.arange(n_azimuth) / n_azimuth
    pts = np.empty((n_azimuth, n, 3))
    pts[:, :, 0] = p.x[None, :]
    pts[:, :, 1] = np.cos(phi)[:, None] * p.r[None, :]
    pts[:, :, 2] = np.sin(phi)[:, None] * p.r[None, :]
    a = np.arange(n_azimuth)[:, None]
    j = np.arange(n)[None, :]
    i00 = a * n + j
    i01 = a * n + (j + 1) % n
    i11 = ((a + 1) % n_azimuth) * n + (j + 1) % n
    i10 = ((a + 1) % n_azimuth) * n + j
    quads = np.stack([i00, i10, i11, i01], axis=-1).reshape(-1, 4)
    return RingSurface(pts.reshape(-1, 3), quads.astype(np.int64))


def inner_ring_placement(position: np.ndarray, tilt: np.ndarray) -> np.ndarray:
    """[A | c] (3, 4) of the inner ring: a body point X is drawn at c + A X, A = R_z(tilt_z)
    R_y(tilt_y) (module doc), c its recorded centre."""
    from flexbearing.multibody.cage_body import cage_rotation
    A = np.empty((3, 3))
    cage_rotation(0.0, float(tilt[0]), float(tilt[1]), A)
    return np.c_[A, np.asarray(position, dtype=np.float64)]
