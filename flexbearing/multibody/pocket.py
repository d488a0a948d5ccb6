"""Ball–cage-pocket interaction: normal force and the lubricated (hydrodynamic) resistances.

Geometry: a ball of radius Rb in a cylindrical pocket of radius Rp > Rb (axis radial). Across the
pocket (xi, around the cylinder) the contact is conforming, along the pocket axis (eta) the
pocket is straight:

    1/R_xi = 1/Rb − 1/Rp,   R_eta = Rb.

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
