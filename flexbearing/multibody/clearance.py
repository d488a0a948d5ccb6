"""Free (unloaded) contact angle, diametral clearance and shim angle: the closed forms that tie them.

One implementation for the bearing preset, the scene's `[bearing]` keys and the validation studies.
Symbols (SI; angles in rad): ball diameter Dw, outer/inner groove radius ratios fe, fi (groove radius
f·Dw), total curvature B = fe + fi − 1, diametral clearance Pd, free contact angle alpha0, shim angle
alphaD of a split inner ring (the contact angle of each inner half in the unloaded, clearance-free
state, flexbearing.multibody.geometry).

One-piece inner ring (two-point contact; Harris & Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 1,
ch. 2, "Contact angle"): the groove curvature centres are B·Dw − Pd/2 apart radially, so

    Pd = 2·B·Dw·(1 − cos alpha0),        alpha0 = acos(1 − Pd/(2·B·Dw)).

Split inner ring (SPEC §2; the layout of flexbearing.multibody.geometry.inner_groove_centres): the
radial distance of the outer centre and a half-groove centre is
Dr = (fi − 0.5)·Dw·cos alphaD + (fe − 0.5)·Dw − Pd/2, and the loaded pair behaves as a two-point
bearing with

    alpha0 = acos(Dr/(B·Dw)),
    Pd     = 2·[(fi − 0.5)·Dw·cos alphaD + (fe − 0.5)·Dw − B·Dw·cos alpha0],
    alphaD = acos([B·Dw·cos alpha0 + Pd/2 − (fe − 0.5)·Dw]/((fi − 0.5)·Dw)).

The design clearance of a split ring, Pd = 2·(fe − 0.5)·Dw·(1 − cos alphaD), is the one at which
alpha0 = alphaD: the smallest with which the ball clears the unloaded half under thrust (two-point
running, as a split-ring bearing is designed to run; below it the ball is held by all three races).
With alphaD = 0 the split formulas become the one-piece ones (tests/test_clearance.py).
"""
from __future__ import annotations

import math
from typing import NamedTuple

from flexbearing.common.validation import InputError, require_range

INNER_RINGS = ("split", "one_piece")


def _cos_to_angle(field: str, c: float, what: str) -> float:
    """acos(c) for a cosine that must be in [0, 1] (angle in [0, 90°]); one line naming the field."""
    if not (0.0 <= c <= 1.0 + 1e-12):
        raise InputError(f"{field}: {what} has cos = {c:.6g}, outside the allowed range [0, 1] "
                         f"(no such bearing: the given angles and clearance contradict each other)")
    return math.acos(min(1.0, c))


def one_piece_clearance(fe: float, fi: float, ball_diameter: float, free_contact_angle: float) -> float:
    """Pd = 2·B·Dw·(1 − cos alpha0), m (module docstring; Harris & Kotzalas Vol. 1 ch. 2)."""
    return 2.0 * (fe + fi - 1.0) * ball_diameter * (1.0 - math.cos(free_contact_angle))


def one_piece_free_contact_angle(fe: float, fi: float, ball_diameter: float, diametral_clearance: float) -> float:
    """alpha0 = acos(1 − Pd/(2·B·Dw)), rad (module docstring)."""
    b = fe + fi - 1.0
    return _cos_to_angle("bearing.radial_clearance", 1.0 - diametral_clearance / (2.0 * b * ball_diameter),
                         "the free contact angle of this clearance")


def split_free_contact_angle(fe: float, fi: float, ball_diameter: float, shim_angle: float,
                             diametral_clearance: float) -> float:
    """alpha0 = acos(Dr/(B·Dw)), Dr = (fi − 0.5)·Dw·cos alphaD + (fe − 0.5)·Dw − Pd/2, rad (SPEC §2).
    Below the design clearance Dr > B·Dw: the ball is held by three races at zero load, alpha0 = 0
    by this formula's clip (the two-point angle does not exist)."""
    dw = ball_diameter
    dr = (fi - 0.5) * dw * math.cos(shim_angle) + (fe - 0.5) * dw - 0.5 * diametral_clearance
    return math.acos(min(1.0, dr / ((fe + fi - 1.0) * dw)))


def split_clearance(fe: float, fi: float, ball_diameter: float, shim_angle: float,
                    free_contact_angle: float) -> float:
    """Pd = 2·[(fi − 0.5)·Dw·cos alphaD + (fe − 0.5)·Dw − B·Dw·cos alpha0], m (module docstring)."""
    dw = ball_diameter
    return 2.0 * ((fi - 0.5) * dw * math.cos(shim_angle) + (fe - 0.5) * dw
                  - (fe + fi - 1.0) * dw * math.cos(free_contact_angle))


def split_shim_angle(fe: float, fi: float, ball_diameter: float, diametral_clearance: float,
                     free_contact_angle: float) -> float:
    """alphaD = acos([B·Dw·cos alpha0 + Pd/2 − (fe − 0.5)·Dw]/((fi − 0.5)·Dw)), rad (module docstring)."""
    dw = ball_diameter
    c = ((fe + fi - 1.0) * dw * math.cos(free_contact_angle) + 0.5 * diametral_clearance
         - (fe - 0.5) * dw) / ((fi - 0.5) * dw)
    return _cos_to_angle("bearing.shim_angle", c, "the shim angle of this free contact angle and clearance")


def design_clearance(fe: float, ball_diameter: float, shim_angle: float) -> float:
    """Pd = 2·(fe − 0.5)·Dw·(1 − cos alphaD), m: the split ring's clearance at which alpha0 = alphaD
    (module docstring; 88.4 um for the paper bearing's 30° shim)."""
    return 2.0 * (fe - 0.5) * ball_diameter * (1.0 - math.cos(shim_angle))


class InnerRingLayout(NamedTuple):
    """The three coupled quantities of the inner ring, all given or derived (SI, rad)."""
    shim_angle: float             # split ring only (one-piece: the free contact angle, the layout of
                                  # its single groove, flexbearing.multibody.bearing.Bearing.groove_layout)
    diametral_clearance: float    # Pd, m
    free_contact_angle: float     # alpha0, rad


def resolve_inner_ring(inner_ring: str, fe: float, fi: float, ball_diameter: float,
                       free_contact_angle: float | None = None, shim_angle: float | None = None,
                       diametral_clearance: float | None = None) -> InnerRingLayout:
    """Complete the inner ring's description from what is given (None = not given).

    split:     any two of (alpha0, alphaD, Pd) give the third; alpha0 alone takes the design rule
               alphaD = alpha0 (Pd = design clearance); alphaD alone takes its design clearance;
               Pd alone is refused (which shim?); all three are refused (one is derived).
    one_piece: alpha0 or Pd, not both; no shim angle.
    Each refusal is one InputError line naming the fields."""
    if inner_ring not in INNER_RINGS:
        raise InputError(f"bearing.inner_ring = {inner_ring!r} must be one of {', '.join(map(repr, INNER_RINGS))}")
    given = {k: v for k, v in (("free_contact_angle", free_contact_angle), ("shim_angle", shim_angle),
                               ("radial_clearance", diametral_clearance)) if v is not None}
    if "free_contact_angle" in given:
        require_range("bearing.free_contact_angle", free_contact_angle, 0.0, 0.5 * math.pi, hi_open=True,
                      unit="rad")
    if inner_ring == "one_piece":
        if shim_angle is not None:
            raise InputError("bearing.shim_angle applies to inner_ring = 'split' only (a one-piece ring has one "
                             "groove; give free_contact_angle or radial_clearance)")
        if len(given) == 2:
            raise InputError("bearing: give free_contact_angle or radial_clearance of a one-piece inner ring, "
                             "not both (one is derived from the other)")
        if free_contact_angle is not None:
            pd = one_piece_clearance(fe, fi, ball_diameter, free_contact_angle)
            return InnerRingLayout(free_contact_angle, pd, free_contact_angle)
        if diametral_clearance is None:
            raise InputError("bearing: a one-piece inner ring needs free_contact_angle or radial_clearance")
        a0 = one_piece_free_contact_angle(fe, fi, ball_diameter, diametral_clearance)
        return InnerRingLayout(a0, diametral_clearance, a0)
    if len(given) == 3:
        raise InputError("bearing: give at most two of free_contact_angle, shim_angle, radial_clearance of a split "
                         "inner ring (the third is derived)")
    if free_contact_angle is not None:
        if shim_angle is not None:
            pd = split_clearance(fe, fi, ball_diameter, shim_angle, free_contact_angle)
            if pd < 0.0:
                lo = split_free_contact_angle(fe, fi, ball_diameter, shim_angle, 0.0)
                raise InputError(f"bearing.free_contact_angle = {free_contact_angle:g} rad is outside the allowed "
                                 f"range [{lo:g}, {0.5 * math.pi:g}) rad for shim_angle = {shim_angle:g} rad "
                                 f"(a smaller angle needs a negative clearance)")
            return InnerRingLayout(shim_angle, pd, free_contact_angle)
        if diametral_clearance is not None:
            sa = split_shim_angle(fe, fi, ball_diameter, diametral_clearance, free_contact_angle)
            return InnerRingLayout(sa, diametral_clearance, free_contact_angle)
        pd = design_clearance(fe, ball_diameter, free_contact_angle)
        return InnerRingLayout(free_contact_angle, pd, free_contact_angle)
    if shim_angle is None:
        raise InputError("bearing: a split inner ring needs shim_angle or free_contact_angle")
    pd = design_clearance(fe, ball_diameter, shim_angle) if diametral_clearance is None else diametral_clearance
    return InnerRingLayout(shim_angle, pd, split_free_contact_angle(fe, fi, ball_diameter, shim_angle, pd))
