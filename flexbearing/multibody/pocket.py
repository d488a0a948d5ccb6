"""Ball–cage-pocket interaction: normal force and the lubricated (hydrodynamic) resistances.

Geometry: a ball of radius Rb in a cylindrical pocket of radius Rp > Rb (axis radial). Across the
pocket (xi, around the cylinder) the contact is conforming, along the pocket axis (eta) the
pocket is straight:

    1/R_xi = 1/Rb − 1/Rp,   R_eta = Rb.

A spherical pocket (a sphere of radius Rp centred on the pitch circle) is conforming both ways,

    1/R_xi = 1/R_eta = 1/Rb − 1/Rp                (sphere in a spherical cup: Johnson, Contact
                                                    Mechanics, 1985, §4.2, concave radius < 0),

a circular Hertz contact (k = 1). Its approach Z is measured from the pocket's centre (the whole
offset d = b − p of the ball centre), a cylindrical pocket's from its axis (d less its axial
part): in both the gap closes at Z = Cp = Rp − Rb and the laws below apply unchanged.

A conical pocket (axis radial, half-angle beta, opening outwards for beta > 0) is the cone
tangent to the sphere of radius Rp about the pocket centre: its radius across the axis at the
axial coordinate s (along the pocket axis a, from the centre) is Rp/cos(beta) + s·tan(beta), so a
centred ball has the clearance Cp = Rp − Rb in every direction, as in the other shapes. A ball
whose centre is offset by (s, rho) (along a, and across it towards the unit e_rho) is at the
distance Rp − Z from the wall, along the wall's normal n (Euclid: the distance from a point to the
straight generator in the meridian plane),

    Z = rho·cos(beta) − s·sin(beta),   n = cos(beta)·e_rho − sin(beta)·a,

so the same law below applies to Z. Along the generator the wall is straight (R_eta = Rb, as the
cylinder's axis direction); across it the cone's normal curvature is cos(beta)/r (Meusnier's
theorem, r the wall's distance from the axis at the contact: do Carmo, Differential Geometry of
Curves and Surfaces, 1976, §3-2), a concave radius R_c = r/cos(beta) = Rp − Z + rho/cos(beta):
Rp for a ball on the normal through the tangent circle, Rp + t·tan(beta) for a ball moved by t
along a generator. The Hertz constant of the model is the nominal one, R_c = Rp (the same as the
cylinder's: the cone and the tangent sphere share the contact circle's normal curvature);
`conical_pocket_curvature_radii` gives R_c at any offset, to bound what that constant leaves out.

An elliptical-bore pocket is a radial cylinder of elliptical section: semi-axis A = Dp/2 along
the cage's axis (e1: the cage's axial direction k at the pocket less its part along the pocket
axis a) and B = Dp_t/2 >= A across it in the direction of rotation (e2 = a × e1;
cage.pocket_circumferential_diameter). The ball centre's
offset across the axis, (u, v) on (e1, e2), has its nearest wall point X on the ellipse, found by
Eberly's robust method (D. Eberly, "Distance from a point to an ellipse, an ellipsoid, or a
hyperellipsoid", Geometric Tools, 2011: in the first quadrant, with e0 >= e1 the semi-axes and
z_i = y_i/e_i, the root s of G(s) = (r0·z0/(s + r0))² + (z1/(s + 1))² − 1, r0 = (e0/e1)², is
unique in [z1 − 1, sqrt(r0²z0² + z1²) − 1] and G falls there: bisection to round-off, at most
BISECTION_STEPS halvings; X = (r0·y0/(s + r0), y1/(s + 1))·(e0, e1)/(e0, e1)). Its distance D and
the outward normal n ∝ (X0/e0², X1/e1²) give the approach Z = Rp − D with Rp = A (the gap is the
law's Cp − Z: Cp = (Dp − Dw)/2 is the smallest clearance, across the short axis); the linear
"lubricated gap" branch thus acts on the gap, Kc·(Cp − gap), from zero where the gap is Cp. The
contact is a point contact: straight along the pocket axis (R_eta = Rb), across it the ellipse's
concave radius of curvature at X, rho = (A²·sin²t + B²·cos²t)^1.5/(A·B) for X = (A cos t, B sin t)
(B²/A and A²/B at the vertices), 1/R_xi = 1/Rb − 1/rho. The model's Hertz constant is the nominal
one at the circumferential vertex (rho = A²/B, where the ball's lead or lag presses it);
`elliptical_pocket_curvature_radii` gives it at any X. The section's axes are machined in the cage
and turn with it: the frame (e1, e2, a) is the pocket's body frame (k and a both turned by the
cage's rotation and the interface node's elastic rotation: cage_body.pocket_axial_direction,
cage_body.pocket_pose), so the potential V(Z) depends on the ball only through its offset in that
frame, and the moment −(b − p) × F the dynamics put on the cage's node (pocket_kernels.ball_pocket)
is the potential's gradient for the cage's rotation. (With the axes taken from the bearing axis x
instead, a tilted cage's rotation about the pocket axis left Z unchanged while the node still
took that moment: the force was not the gradient of the potential, and a conservative run's
energy error did not fall with the integrator's tolerance; tests/test_energy.py.)

Normal force (seed paper §2.3.1 eq. for Q_cj, its ref. 26): with Z the ball–pocket approach
(signed: Z > 0 the pocket pushes the ball, Z < 0 the ball pushes the cage) and Cp = (Dp − Dw)/2,

    |Q| = Kc·|Z|                          for |Z| <= Cp,   Kc = 11/Cp  (N/m; 11 N at Cp),
    |Q| = Kc·Cp + Kn·(|Z| − Cp)^1.5       for |Z| >  Cp,   Kn = Hertz constant of (R_xi, R_eta),

sign(Q) = sign(Z). The linear branch is the paper's empirical "lubricated gap" law.

Hydrodynamic film in the gap h (rigid surfaces, isoviscous; Brewe, Hamrock & Taylor, J. Lubr.
Technol. 101(2):231, 1979), with x the entrainment direction (radius Rx) and y across (Ry):

    h/Rx = 128·k·lambda²·(0.131·theta + 1.683)²·(U/W)²,  k = Ry/Rx, theta = atan(k/2),
    lambda = 1/(1 + 2/(3k)), U/W = eta0·u·Rx/Q   (E' cancels: rigid),
    =>  W = eta0·u·Rx·lambda·(0.131·theta + 1.683)·sqrt(128·k·Rx/h).

Rolling (Poiseuille) resistance. Integrating the Poiseuille shear (h/2)·dp/dx over the film by
parts with h = h0 + x²/(2Rx) + y²/(2Ry) gives the exact identity F_R = W·|x_p|/(2·Rx), x_p the
centre of pressure. Taking x_p from the rigid-cylinder solution with Reynolds' outlet condition
(Martin 1916; Dowson & Higginson 1966): x_p = −C_XP·sqrt(2·Rx·h), C_XP = 1.32930 (load
4.894969·eta0·u·R/h per unit length, outlet at X = 0.475130; tests/test_pocket.py re-derives
these numbers by quadrature), and W from Brewe–Hamrock–Taylor:

    F_R = W·C_XP·sqrt(2h/Rx)/2 = 8·C_XP·lambda·(0.131·theta + 1.683)·eta0·u·sqrt(Rx·Ry),

independent of h, the same scaling eta0·u·sqrt(R_xi·R_eta) as the paper's ref. 27 (its C_O). This
is an assembled model (BHT load + line-contact pressure centre), not a published closed form: the
paper's P_R coefficient could not be read from the extracted text of the paper.

Sliding (Couette) resistance: integrating eta0·du/h over the wetted ellipse out to the gap h_edge,

    F_S = 2·pi·eta0·du·sqrt(Rx·Ry)·ln(h_edge/h0),

the scaling eta0·du·sqrt(R_xi·R_eta)·ln(·) of Houpert (J. Tribol. 109 (1987) 363) and Gupta
(Advanced Dynamics of Rolling Elements, 1984) (exact for the paraboloidal gap).
Forces act on the ball: F_R opposite to the entrainment speed u, F_S along du = u_cage − u_ball.
"""
from __future__ import annotations

import math

from numba import njit

from flexbearing.common.validation import require_range
from flexbearing.mesh.cage_geometry import POCKET_CYLINDRICAL, POCKET_ELLIPTICAL, POCKET_SHAPES, POCKET_SPHERICAL
from flexbearing.multibody.hertz import hertz_stiffness
from flexbearing.multibody.model_layout import (
    P_CP, P_KC, P_KN, P_MUPOCKET, P_POCKET_B, P_POCKET_CONE, P_RCAGE_POCKET, P_RPOCKET,
)

# The paper's "lubricated gap" law: the linear branch carries this force at the pocket clearance,
# Kc = POCKET_GAP_FORCE/Cp (module docstring)
POCKET_GAP_FORCE = 11.0                 # N

# Rigid cylinder, isoviscous, Reynolds outlet condition (Martin 1916 / Dowson & Higginson):
MARTIN_OUTLET = 0.4751299200930563      # X_e = x_e/sqrt(2Rh0)
MARTIN_LOAD = 4.894968493913369         # w·h0/(eta0·u·R)
MARTIN_PRESSURE_CENTRE = 1.3293048414702417   # −x_p/sqrt(2Rh0)


@njit(cache=True)
def pocket_curvature_radii(ball_radius, pocket_radius):
    """(R_xi, R_eta): 1/R_xi = 1/Rb − 1/Rp (conforming, across the pocket), R_eta = Rb, m."""
    return 1.0 / (1.0 / ball_radius - 1.0 / pocket_radius), ball_radius


@njit(cache=True)
def spherical_pocket_curvature_radii(ball_radius, pocket_radius):
    """(R_xi, R_eta) of a ball in a spherical pocket: both 1/(1/Rb − 1/Rp), m (module docstring)."""
    r = 1.0 / (1.0 / ball_radius - 1.0 / pocket_radius)
    return r, r


@njit(cache=True)
def conical_pocket_curvature_radii(ball_radius, pocket_radius, cone_angle, axial_offset, radial_offset):
    """(R_xi, R_eta) of a ball in a conical pocket, m: across, 1/R_xi = 1/Rb − 1/R_c with
    R_c = Rp − Z + rho/cos(beta) (Z = rho·cos(beta) − s·sin(beta); s, rho the ball centre's offset
    along the axis and across it); along the straight generator R_eta = Rb (module docstring)."""
    cb = math.cos(cone_angle)
    z = radial_offset * cb - axial_offset * math.sin(cone_angle)
    rc = pocket_radius - z + radial_offset / cb
    return 1.0 / (1.0 / ball_radius - 1.0 / rc), ball_radius


BISECTION_STEPS = 200      # bound of Eberly's bisection (round-off is reached in ~60 for doubles)


@njit(cache=True)
def ellipse_nearest_point(e0, e1, y0, y1):
    """(x0, x1, D): the point of the ellipse (x0/e0)² + (x1/e1)² = 1 nearest to (y0, y1) and its
    distance, e0 >= e1 > 0, y0, y1 >= 0 (first quadrant; module docstring, Eberly 2011)."""
    if y1 > 0.0:
        if y0 > 0.0:
            z0 = y0 / e0
            z1 = y1 / e1
            r0 = (e0 / e1) ** 2
            lo = z1 - 1.0
            hi = math.sqrt(r0 * r0 * z0 * z0 + z1 * z1) - 1.0
            s = lo
            for _ in range(BISECTION_STEPS):
                s = 0.5 * (lo + hi)
                if s == lo or s == hi:
                    break
                g = (r0 * z0 / (s + r0)) ** 2 + (z1 / (s + 1.0)) ** 2 - 1.0
                if g > 0.0:
                    lo = s
                elif g < 0.0:
                    hi = s
                else:
                    break
            x0 = r0 * y0 / (s + r0)
            x1 = y1 / (s + 1.0)
            return x0, x1, math.sqrt((x0 - y0) ** 2 + (x1 - y1) ** 2)
        return 0.0, e1, abs(y1 - e1)
    numer = e0 * y0
    denom = e0 * e0 - e1 * e1
    if numer < denom:
        xd = numer / denom
        x0 = e0 * xd
        x1 = e1 * math.sqrt(1.0 - xd * xd)
        return x0, x1, math.sqrt((x0 - y0) ** 2 + x1 * x1)
    return e0, 0.0, abs(y0 - e0)


@njit(cache=True)
def ellipse_curvature_radius(a, b, x0, x1):
    """Radius of curvature of the ellipse (x0/a)² + (x1/b)² = 1 at its point (x0, x1), m:
    (a²·sin²t + b²·cos²t)^1.5/(a·b) with cos t = x0/a, sin t = x1/b (b²/a at (a, 0), a²/b at (0, b))."""
    return (a * a * (x1 / b) ** 2 + b * b * (x0 / a) ** 2) ** 1.5 / (a * b)


@njit(cache=True)
def elliptical_pocket_curvature_radii(ball_radius, semi_axial, semi_circumferential, x_axial, x_circumferential):
    """(R_xi, R_eta) of a ball on the elliptical pocket's wall at the wall point (x_axial,
    x_circumferential) of its section: 1/R_xi = 1/Rb − 1/rho (rho the ellipse's radius of
    curvature there), R_eta = Rb along the straight pocket axis (module docstring)."""
    rho = ellipse_curvature_radius(semi_axial, semi_circumferential, x_axial, x_circumferential)
    return 1.0 / (1.0 / ball_radius - 1.0 / rho), ball_radius


@njit(cache=True)
def _elliptical_offset(dx, dy, dz, ax, ay, az, semi_axial, semi_circumferential, kx, ky, kz):
    """`pocket_contact_offset` of the elliptical pocket (module docstring); k the cage's axial
    direction at the pocket (unit)."""
    # e1: the cage's axis k less its part along a; e2 = a × e1
    ka = kx * ax + ky * ay + kz * az
    e1x = kx - ka * ax
    e1y = ky - ka * ay
    e1z = kz - ka * az
    n1 = math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z)
    e1x /= n1
    e1y /= n1
    e1z /= n1
    e2x = ay * e1z - az * e1y
    e2y = az * e1x - ax * e1z
    e2z = ax * e1y - ay * e1x
    u = dx * e1x + dy * e1y + dz * e1z
    v = dx * e2x + dy * e2y + dz * e2z
    # the major axis (circumferential, B >= A) first, as Eberly's method takes it
    x0, x1, dist = ellipse_nearest_point(semi_circumferential, semi_axial, abs(v), abs(u))
    z = semi_axial - dist
    if z <= 0.0:
        return dx, dy, dz, 0.0, 0.0, 0.0, 0.0
    nv = math.copysign(x0 / (semi_circumferential * semi_circumferential), v)
    nu = math.copysign(x1 / (semi_axial * semi_axial), u)
    nn = math.sqrt(nu * nu + nv * nv)
    nu /= nn
    nv /= nn
    nx = nu * e1x + nv * e2x
    ny = nu * e1y + nv * e2y
    nz = nu * e1z + nv * e2z
    return dx - z * nx, dy - z * ny, dz - z * nz, z * nx, z * ny, z * nz, z


@njit(cache=True)
def pocket_contact_offset(dx, dy, dz, ax, ay, az, shape, cone_angle, semi_axial=0.0, semi_circumferential=0.0,
                          kx=1.0, ky=0.0, kz=0.0):
    """Where the ball presses on the pocket wall: (e (3), u (3), Z) for the ball centre's offset
    d = b − p from the pocket centre, a the pocket axis (unit), shape the index in
    flexbearing.mesh.cage_geometry.POCKET_SHAPES (0 cylindrical, 1 spherical, 2 conical,
    3 elliptical: semi-axes along the cage's axis k (unit; flexbearing.multibody.cage_body.
    pocket_axial_direction, the bearing axis by default) and across it, `_elliptical_offset`).
    Z the approach (the gap is Cp − Z), u = Z·n with n the wall's normal through the ball centre,
    e = d − u the part of the offset the wall's nearest point p + e + Rp·n follows:
    cylinder e = (d·a)·a, Z = |d − e|; sphere e = 0, Z = |d|; cone Z = rho·cos(beta) −
    s·sin(beta) (module docstring; no contact, Z = 0, for a ball on the axis or Z <= 0)."""
    if shape == POCKET_SPHERICAL:
        return 0.0, 0.0, 0.0, dx, dy, dz, math.sqrt(dx * dx + dy * dy + dz * dz)
    if shape == POCKET_ELLIPTICAL:
        return _elliptical_offset(dx, dy, dz, ax, ay, az, semi_axial, semi_circumferential, kx, ky, kz)
    s = dx * ax + dy * ay + dz * az
    ex = s * ax
    ey = s * ay
    ez = s * az
    ux = dx - ex
    uy = dy - ey
    uz = dz - ez
    rho = math.sqrt(ux * ux + uy * uy + uz * uz)
    if shape == POCKET_CYLINDRICAL:
        return ex, ey, ez, ux, uy, uz, rho
    if rho < 1e-15:
        return dx, dy, dz, 0.0, 0.0, 0.0, 0.0
    cb = math.cos(cone_angle)
    sb = math.sin(cone_angle)
    z = rho * cb - s * sb
    if z <= 0.0:
        return dx, dy, dz, 0.0, 0.0, 0.0, 0.0
    nx = cb * ux / rho - sb * ax
    ny = cb * uy / rho - sb * ay
    nz = cb * uz / rho - sb * az
    return dx - z * nx, dy - z * ny, dz - z * nz, z * nx, z * ny, z * nz, z


@njit(cache=True)
def pocket_axis_point(dx, dy, dz, ax, ay, az, shape, cone_angle):
    """Where the pocket force's line of action (through the ball centre along n,
    `pocket_contact_offset`) crosses the pocket axis, as its coordinate along a from the pocket
    centre, m: the cylinder's d·a, the sphere's 0 (its centre), the cone's s + rho·tan(beta)
    (the meridian plane's normal through the ball meets the axis there). The elliptical pocket's
    normal misses the axis: d·a, the axis point level with the ball (the node moment −(b − p)×F
    − M_b the dynamics apply does not depend on the point; only the recorded lever does)."""
    if shape == POCKET_SPHERICAL:
        return 0.0
    s = dx * ax + dy * ay + dz * az
    if shape == POCKET_CYLINDRICAL or shape == POCKET_ELLIPTICAL:
        return s
    ux = dx - s * ax
    uy = dy - s * ay
    uz = dz - s * az
    return s + math.sqrt(ux * ux + uy * uy + uz * uz) * math.tan(cone_angle)


@njit(cache=True)
def pocket_hertz_stiffness(ball_radius, pocket_radius, E_eff):
    """Kn of the ball–cylindrical-pocket Hertz contact, N/m^1.5 (exact ellipticity, flexbearing.multibody.hertz)."""
    rxi, reta = pocket_curvature_radii(ball_radius, pocket_radius)
    return hertz_stiffness(rxi, reta, E_eff)


@njit(cache=True)
def pocket_gap_stiffness(Cp):
    """Kc = POCKET_GAP_FORCE/Cp of the linear "lubricated gap" branch, N/m (module docstring)."""
    return POCKET_GAP_FORCE / Cp


@njit(cache=True)
def pocket_film_radii(shape, ball_radius, pocket_radius, semi_circumferential):
    """(R_xi, R_eta) of the pocket contact at its nominal point for the shape code (POCKET_SHAPES):
    a cylinder's and a cone's (`pocket_curvature_radii`, module docstring: the cone's nominal
    concave radius is Rp), a sphere's (`spherical_pocket_curvature_radii`), an ellipse's at its
    circumferential vertex (concave radius A²/B, A = Rp). The film resistances (rhs) and the
    Hertz constant (`pocket_hertz_constant`) are taken there."""
    if shape == POCKET_SPHERICAL:
        return spherical_pocket_curvature_radii(ball_radius, pocket_radius)
    if shape == POCKET_ELLIPTICAL:
        return pocket_curvature_radii(ball_radius, pocket_radius ** 2 / semi_circumferential)
    return pocket_curvature_radii(ball_radius, pocket_radius)


def pocket_hertz_constant(shape, ball_radius, pocket_radius, semi_circumferential, E_eff):
    """Kn of the pocket's Hertz branch, N/m^1.5 (flexbearing.multibody.hertz.hertz_stiffness), for the
    shape code: sphere both radii conforming; cylinder, cone and ellipse a point contact of
    R_eta = Rb along the pocket axis and the conforming R_xi across it at the nominal contact
    (`pocket_film_radii`), the larger radius first. The parameter fill of the model
    (flexbearing.multibody.model.build_model)."""
    r_across, rb = pocket_film_radii(shape, ball_radius, pocket_radius, semi_circumferential)
    if shape == POCKET_SPHERICAL:
        return hertz_stiffness(r_across, r_across, E_eff)
    return hertz_stiffness(rb, r_across, E_eff) if r_across > rb else hertz_stiffness(r_across, rb, E_eff)


@njit(cache=True, inline="always")
def pocket_elastic_force(Z, Cp, Kc, Kn):
    """Elastic ball–pocket normal force Q_el(Z) >= 0 for the approach Z >= 0, N (paper §2.3.1,
    eq. for Q_cj; module docstring): Kc·Z up to the clearance Cp, Kc·Cp + Kn·(Z − Cp)^1.5 beyond.
    The law the dynamics run (flexbearing.multibody.pocket_kernels)."""
    if Z <= Cp:
        return Kc * Z
    pen = Z - Cp
    return Kc * Cp + Kn * pen * math.sqrt(pen)


@njit(cache=True)
def pocket_potential(Z, Cp, Kc, Kn):
    """Potential of `pocket_elastic_force`, J: Kc·Z²/2 (Z <= Cp), Kc·Cp²/2 + Kc·Cp·(Z − Cp) +
    (2/5)·Kn·(Z − Cp)^2.5 beyond (flexbearing.multibody.energy)."""
    if Z <= Cp:
        return 0.5 * Kc * Z * Z
    return 0.5 * Kc * Cp * Cp + Kc * Cp * (Z - Cp) + 0.4 * Kn * (Z - Cp) ** 2.5


@njit(cache=True)
def pocket_normal_force(Z, Cp, Kn):
    """Signed ball–pocket normal force Q(Z), N: `pocket_elastic_force` of |Z| with Kc =
    `pocket_gap_stiffness`, the sign of Z (paper eq. for Q_cj; module docstring)."""
    q = pocket_elastic_force(abs(Z), Cp, pocket_gap_stiffness(Cp), Kn)
    return q if Z >= 0.0 else -q


@njit(cache=True)
def _bht_factor(k):
    """lambda·(0.131·theta + 1.683) of Brewe, Hamrock & Taylor (1979)."""
    lam = 1.0 / (1.0 + 2.0 / (3.0 * k))
    theta = math.atan(0.5 * k)
    return lam * (0.131 * theta + 1.683)


@njit(cache=True)
def bht_min_film(Q, u_entrain, Rx, Ry, eta0):
    """h_min of a rigid isoviscous point contact, m (Brewe, Hamrock & Taylor 1979):
    h/Rx = 128·k·lambda²·(0.131·theta + 1.683)²·(eta0·u·Rx/Q)²."""
    k = Ry / Rx
    f = _bht_factor(k)
    r = eta0 * abs(u_entrain) * Rx / Q
    return Rx * 128.0 * k * f * f * r * r


@njit(cache=True)
def pocket_film_load(h, u_entrain, Rx, Ry, eta0):
    """Hydrodynamic load W carried at the gap h > 0, N (BHT 1979 inverted; module docstring)."""
    k = Ry / Rx
    return eta0 * abs(u_entrain) * Rx * _bht_factor(k) * math.sqrt(128.0 * k * Rx / h)


@njit(cache=True)
def pocket_rolling_resistance(u_entrain, Rx, Ry, eta0):
    """Poiseuille rolling resistance on the ball, N, signed opposite to u_entrain:
    F_R = 8·C_XP·lambda·(0.131·theta + 1.683)·eta0·|u|·sqrt(Rx·Ry) (module docstring;
    `pocket_rolling_force` of `pocket_resistance_coefficients`)."""
    c_roll, _, c_root = pocket_resistance_coefficients(Rx, Ry, eta0)
    f = pocket_rolling_force(c_roll, c_root, u_entrain)
    return -f if u_entrain > 0.0 else f


@njit(cache=True, inline="always")
def pocket_rolling_force(c_roll, c_root, u_entrain):
    """|F_R| = (c_R·|u|)·r of `pocket_resistance_coefficients`, N: the rolling resistance the
    dynamics apply on each side of the ball (flexbearing.multibody.pocket_kernels)."""
    return c_roll * abs(u_entrain) * c_root


@njit(cache=True, inline="always")
def pocket_sliding_force(c_slide, c_root, du, h0, h_edge):
    """F_S = ((c_S·du)·r)·ln(h_edge/h0) of `pocket_resistance_coefficients`, N (0 for h_edge <=
    h0): the sliding resistance the dynamics apply on each side of the ball."""
    if h_edge <= h0:
        return 0.0
    return c_slide * du * c_root * math.log(h_edge / h0)


@njit(cache=True)
def pocket_resistance_coefficients(Rx, Ry, eta0):
    """(c_R, c_S, r) with F_R = (c_R·|u|)·r (`pocket_rolling_resistance`) and
    F_S = ((c_S·du)·r)·ln(h_edge/h0) (`pocket_sliding_resistance`): c_R = 8·C_XP·lambda·(0.131·theta
    + 1.683)·eta0, c_S = 2·pi·eta0, r = sqrt(Rx·Ry) (products in the order of those functions, so
    the forces are bit-identical). They depend on the geometry and the oil only, so the dynamics
    evaluate them once per right-hand side instead of per pocket and side (the atan and sqrt of
    the factor were ~10 % of a pocket's cost)."""
    k = Ry / Rx
    return 8.0 * MARTIN_PRESSURE_CENTRE * _bht_factor(k) * eta0, 2.0 * math.pi * eta0, math.sqrt(Rx * Ry)


@njit(cache=True)
def pocket_sliding_resistance(du, h0, h_edge, Rx, Ry, eta0):
    """Couette sliding force on the ball along du (cage − ball surface speed), N:
    F_S = 2·pi·eta0·du·sqrt(Rx·Ry)·ln(h_edge/h0), h0 the minimum gap, h_edge the wetted edge
    (`pocket_sliding_force` of `pocket_resistance_coefficients`)."""
    _, c_slide, c_root = pocket_resistance_coefficients(Rx, Ry, eta0)
    return pocket_sliding_force(c_slide, c_root, du, h0, h_edge)


def fill_pocket_parameters(p, bearing, E_eff, friction):
    """The pocket law's slots of the model's parameter vector p (flexbearing.multibody.model_layout;
    flexbearing.multibody.model.build_model): the clearance Cp = (Dp − Dw)/2, the linear Kc
    (`pocket_gap_stiffness`), the Hertz Kn at the shape's nominal contact (`pocket_hertz_constant`,
    E_eff the ball–cage E'), the pocket radius, the cone's half-angle, the ellipse's circumferential
    semi-axis, the radius of the pocket centres (dm/2) and the Coulomb coefficient mu_p (model
    option pocket_friction, in [0, 1])."""
    cage = bearing.cage
    cp = bearing.pocket_clearance
    rb, rp = 0.5 * bearing.ball_diameter, 0.5 * cage.pocket_diameter
    p[P_CP], p[P_KC] = cp, pocket_gap_stiffness(cp)
    p[P_KN] = pocket_hertz_constant(POCKET_SHAPES.index(cage.pocket_shape), rb, rp,
                                    0.5 * cage.pocket_circumferential_diameter, E_eff)
    p[P_RPOCKET] = rp
    p[P_POCKET_CONE] = cage.pocket_cone_angle
    p[P_POCKET_B] = 0.5 * cage.pocket_circumferential_diameter
    p[P_RCAGE_POCKET] = 0.5 * bearing.pitch_diameter
    p[P_MUPOCKET] = require_range("model.pocket_friction", friction, 0.0, 1.0)
