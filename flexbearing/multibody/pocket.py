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

from flexbearing.multibody.hertz import hertz_stiffness

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


@njit(cache=True)
def pocket_contact_offset(dx, dy, dz, ax, ay, az, shape, cone_angle):
    """Where the ball presses on the pocket wall: (e (3), u (3), Z) for the ball centre's offset
    d = b − p from the pocket centre, a the pocket axis (unit), shape the index in
    flexbearing.mesh.cage_geometry.POCKET_SHAPES (0 cylindrical, 1 spherical, 2 conical).
    Z the approach (the gap is Cp − Z), u = Z·n with n the wall's normal through the ball centre,
    e = d − u the part of the offset the wall's nearest point p + e + Rp·n follows:
    cylinder e = (d·a)·a, Z = |d − e|; sphere e = 0, Z = |d|; cone Z = rho·cos(beta) −
    s·sin(beta) (module docstring; no contact, Z = 0, for a ball on the axis or Z <= 0)."""
    if shape == 1:
        return 0.0, 0.0, 0.0, dx, dy, dz, math.sqrt(dx * dx + dy * dy + dz * dz)
    s = dx * ax + dy * ay + dz * az
    ex = s * ax
    ey = s * ay
    ez = s * az
    ux = dx - ex
    uy = dy - ey
    uz = dz - ez
    rho = math.sqrt(ux * ux + uy * uy + uz * uz)
    if shape == 0:
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
    (the meridian plane's normal through the ball meets the axis there)."""
    if shape == 1:
        return 0.0
    s = dx * ax + dy * ay + dz * az
    if shape == 0:
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
def pocket_normal_force(Z, Cp, Kn):
    """Signed ball–pocket normal force Q(Z), N (paper eq. for Q_cj; Kc = 11/Cp; module docstring)."""
    z = abs(Z)
    kc = 11.0 / Cp
    if z <= Cp:
        q = kc * z
    else:
        q = kc * Cp + Kn * (z - Cp) ** 1.5
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
    F_R = 8·C_XP·lambda·(0.131·theta + 1.683)·eta0·|u|·sqrt(Rx·Ry) (module docstring)."""
    k = Ry / Rx
    f = 8.0 * MARTIN_PRESSURE_CENTRE * _bht_factor(k) * eta0 * abs(u_entrain) * math.sqrt(Rx * Ry)
    return -f if u_entrain > 0.0 else f


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
    F_S = 2·pi·eta0·du·sqrt(Rx·Ry)·ln(h_edge/h0), h0 the minimum gap, h_edge the wetted edge."""
    if h_edge <= h0:
        return 0.0
    return 2.0 * math.pi * eta0 * du * math.sqrt(Rx * Ry) * math.log(h_edge / h0)
