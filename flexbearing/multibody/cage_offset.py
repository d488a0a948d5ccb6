"""The cage centre's offset from what guides it: the orbit a cage engineer reads.

What matters for the cage's motion in its clearance is the centre relative to the guiding
surface's centre, in the plane normal to the bearing axis x (y, z; m):

    outer land:  e = c − o = c                 (the outer ring is fixed: its centre is the origin)
    inner land:  e = c − i                     (i: the inner ring's centre; its land turns and
                                                moves with it: the film's gap is Cg + e·n,
                                                flexbearing.multibody.dynamics `_cage_guidance`)
    balls:       e = c − b,  b the centre of the balls' pitch circle

b is the circle through the ball centres p_j = r_j·(cos psi_j, sin psi_j) (r_j, psi_j: radial
position and azimuth from +y towards +z about the bearing axis) by Kåsa's algebraic fit: the
linear least squares of |p_j|² = 2·p_j·b + k (k = rho² − |b|²), exact for balls on any circle,
whatever their spacing (Z ≥ 3, not collinear; Kåsa, "A circle fitting procedure and its error
analysis", IEEE Trans. Instrum. Meas. IM-25 (1976) 8–14). The balls of an offset cage are not
equally spaced about the axis (the pockets space them about the cage centre), so neither the
centroid of the balls nor the first Fourier bin of r(psi) is their circle's centre; the fit is.
"""
from __future__ import annotations

import numpy as np

from flexbearing.mesh.cage_geometry import GUIDANCES

# what the offset is measured from, for tables and captions (index: GUIDANCES)
GUIDE_REFERENCE = {
    "outer": "the outer ring's centre (the outer land's; fixed)",
    "inner": "the inner ring's centre (the inner land turns and moves with it)",
    "balls": "the centre of the balls' pitch circle (no land: the balls guide the cage)",
}


def ball_set_centre(ball_radius: np.ndarray, ball_azimuth: np.ndarray) -> np.ndarray:
    """b (y, z), m: the centre of the circle through the ball centres (Kåsa's fit, module
    docstring)."""
    r = np.asarray(ball_radius, dtype=np.float64)
    psi = np.asarray(ball_azimuth, dtype=np.float64)
    y, z = r * np.cos(psi), r * np.sin(psi)
    A = np.column_stack([2.0 * y, 2.0 * z, np.ones_like(y)])
    sol, *_ = np.linalg.lstsq(A, y * y + z * z, rcond=None)
    return sol[:2]


def cage_offset_from_guide(guidance: str | int, cage_yz, ring_yz, ball_radius, ball_azimuth) -> np.ndarray:
    """e (y, z) of the cage centre from the guiding surface's centre (module docstring), m;
    guidance a name of GUIDANCES or its index."""
    g = GUIDANCES[guidance] if isinstance(guidance, (int, np.integer)) else guidance
    c = np.asarray(cage_yz, dtype=np.float64)
    if g == "outer":
        return c.copy()
    if g == "inner":
        return c - np.asarray(ring_yz, dtype=np.float64)
    return c - ball_set_centre(ball_radius, ball_azimuth)
