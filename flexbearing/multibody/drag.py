"""Ball churning drag in the oil–air mixture and the EHL rolling resistance forces.

The seed paper's ball equations (§2.5.1) contain the churning drag F_d (along the orbit) and the
EHL rolling forces F_R (acting at the contact, with a moment arm Dw/2 in the ball's Euler equations)
and F_H (acting through the ball centre: it appears in the force equations only). It defers their
formulas to its ref. [31]; the forms below are the standard ones, each with its reference.

Churning drag (Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 2 — fluid drag on a
ball moving through the cavity mixture; Gupta, Advanced Dynamics of Rolling Elements, 1984):

    F_d = −(1/2)·C_d·rho_mix·(pi/4)·Dw²·V·|V|,   V = dm·omega_orbit/2 (mixture taken at rest),
    rho_mix = X·rho_oil + (1 − X)·rho_air,  eta_mix = X·eta_oil + (1 − X)·eta_air  (assumed
    linear mixing; X the oil volume fraction, paper preset 5 %, "assumed"),
    C_d(Re) = 24/Re·(1 + 0.15·Re^0.687) for Re < 1000, 0.44 above (sphere, Schiller & Naumann
    1933 as given by Clift, Grace & Weber, Bubbles, Drops and Particles, 1978, Table 5.2),
    Re = rho_mix·|V|·Dw/eta_mix.

EHL rolling resistance (Poiseuille part of the inlet pressure flow), the form quoted by the issue
from Houpert's fit as used in Harris & Kotzalas Vol. 2 (coefficients not re-checked against the
original text; see the report):

    F_R = 2.86·E'·Rx²·k^0.348·G^0.022·U^0.66·W^0.47,   U = eta0·u/(E'·Rx), G = alpha_p·E',
    W = Q/(E'·Rx²), k the contact ellipticity a/b,

opposing the entrainment velocity on each surface (isothermal; no inlet-heating reduction).

Pressure rolling force F_H on the ball (through its centre): the tangential component of the
film pressure on the ball surface. With x along the entrainment and the ball's outward normal
(x/r_bx, −1) near the contact, F_H = −∫p·x/r_bx dA = −W·x_p/r_bx, x_p < 0 the centre of pressure
(it lies in the inlet): F_H points ALONG the entrainment. Integrating the Poiseuille shear by parts
over the undeformed gap dh/dx = x/Rx gives |F_R| = W·|x_p|/(2·Rx), hence F_H = −2·(Rx/r_bx)·F_R
(r_bx = Dw/2 the ball's own radius in the rolling direction). Exact for a rigid gap, an
approximation for the EHL contact (tests/test_drag.py: Martin's rigid-cylinder solution, signs
included). The seed paper's ball equations (§2.5.1) carry F_R and F_H of one contact with
opposite signs, as here. Together they dissipate: in pure rolling on the fixed outer race the
pair's power is F_H·v_centre < 0 (flexbearing.multibody.power_loss); with F_H along F_R (an earlier
version of this module) it was a power source of the order of the traction losses.

Drag moment on a spinning ball (model option ball_drag_moment, off by default): the couple of a
viscous fluid at rest on a sphere of radius R turning at w (Stokes 1851; H. Lamb, Hydrodynamics,
6th ed., Cambridge 1932, §334, "rotating sphere"),

    M = −8·pi·eta·R³·w = −pi·eta_mix·Dw³·w,

exact for the rotational Reynolds number Re_w = rho·|w|·R²/eta << 1 (creeping flow; the
mixture's eta_mix and rho_mix as the churning drag). At the balls' spin Re_w is 3–5e4 at the
Table 5 cases (docs/race_control.md), where a boundary layer on the sphere makes the moment grow
faster than linearly with w: there the Stokes couple is a lower bound; docs/race_control.md bounds
the real one by magnitude (and by direction: along −w, no moment about the ball's e_t axis).
"""
from __future__ import annotations

import math

from numba import njit

from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
from flexbearing.multibody.kernel_state import BallLoad
from flexbearing.multibody.model_layout import F_BALL_DRAG_MOMENT, F_DRAG, W_DRAG, W_P_CHURNING

RHO_AIR = 1.2          # kg/m^3 at 20 °C, 1 atm
ETA_AIR = 1.8e-5       # Pa·s


@njit(cache=True)
def oil_air_mixture(oil_fraction, rho_oil, eta_oil):
    """(rho_mix, eta_mix) of the cavity oil–air mixture, linear in the oil volume fraction."""
    x = oil_fraction
    return x * rho_oil + (1.0 - x) * RHO_AIR, x * eta_oil + (1.0 - x) * ETA_AIR


@njit(cache=True)
def sphere_drag_coefficient(reynolds):
    """C_d of a sphere: 24/Re·(1 + 0.15·Re^0.687) below Re = 1000, 0.44 above (Clift et al. 1978)."""
    if reynolds <= 0.0:
        return 0.0
    if reynolds < 1000.0:
        return 24.0 / reynolds * (1.0 + 0.15 * reynolds ** 0.687)
    return 0.44


@njit(cache=True)
def churning_drag(ball_diameter, velocity, rho_mix, eta_mix):
    """Drag force on a ball moving at `velocity` (m/s, signed) through the mixture, N (signed,
    opposite to the velocity): F_d = −(1/2)·C_d(Re)·rho·(pi/4)·Dw²·V·|V| (module docstring)."""
    v = abs(velocity)
    if v == 0.0:
        return 0.0
    re = rho_mix * v * ball_diameter / eta_mix
    cd = sphere_drag_coefficient(re)
    return -0.5 * cd * rho_mix * 0.25 * math.pi * ball_diameter ** 2 * velocity * v


@njit(cache=True)
def ehl_rolling_resistance(Q, u_entrain, Rx, k, E_eff, eta0, alpha_p):
    """EHL rolling resistance F_R, N, signed opposite to u_entrain:
    F_R = 2.86·E'·Rx²·k^0.348·G^0.022·U^0.66·W^0.47 (module docstring). Zero without load or speed."""
    if Q <= 0.0 or u_entrain == 0.0:
        return 0.0
    U = eta0 * abs(u_entrain) / (E_eff * Rx)
    G = alpha_p * E_eff
    W = Q / (E_eff * Rx * Rx)
    f = 2.86 * E_eff * Rx * Rx * k ** 0.348 * G ** 0.022 * U ** 0.66 * W ** 0.47
    return -f if u_entrain > 0.0 else f


@njit(cache=True)
def ehl_pressure_rolling_force(F_R, Rx, ball_radius):
    """F_H = −2·(Rx/r_bx)·F_R, the pressure rolling force on the ball through its centre, N
    (opposite to F_R, i.e. along the entrainment velocity; rigid-gap identity, module docstring)."""
    return -2.0 * Rx / ball_radius * F_R


@njit(cache=True)
def ball_drag_moment_coefficient(ball_diameter, eta_mix):
    """c of the viscous drag moment M = −c·w on a ball spinning at w in the mixture at rest,
    c = 8·pi·eta·R³ = pi·eta·Dw³, N·m·s (Stokes–Lamb couple, module docstring)."""
    return math.pi * eta_mix * ball_diameter ** 3


@njit(cache=True, _nrt=False, inline="always")
def ball_churning_drag(j, b, rho_mix, eta_mix, dw, flags, work, load):
    """The kernel of `rhs` (flexbearing.multibody.dynamics): churning drag on the orbiting ball j in the
    oil–air mixture at rest (`churning_drag`, `ball_drag_moment_coefficient`):
    F_d = ½·rho_mix·C_d(Re)·(pi·Dw²/4)·v², v = r·psi', along −e_t; with the option ball_drag_moment the
    mixture's viscous moment on the spinning ball, M = −c·w, c = pi·eta_mix·Dw³ (Stokes–Lamb), and
    the power they dissipate, −F_d·v + c·|w|². Added to the ball load, recorded into work."""
    if not flags[F_DRAG]:
        work[j, W_DRAG] = 0.0
        work[j, W_P_CHURNING] = 0.0
        return load
    vbt = b.v_t
    fd = churning_drag(dw, vbt, rho_mix, eta_mix)
    work[j, W_DRAG] = -fd
    work[j, W_P_CHURNING] = -fd * vbt
    if not flags[F_BALL_DRAG_MOMENT]:
        return BallLoad(load.fx, load.fr, load.ft + fd, load.mx, load.mr, load.mt)
    c_spin = ball_drag_moment_coefficient(dw, eta_mix)
    work[j, W_P_CHURNING] += c_spin * (b.w_x * b.w_x + b.w_r * b.w_r + b.w_t * b.w_t)
    return BallLoad(load.fx, load.fr, load.ft + fd, load.mx - c_spin * b.w_x, load.mr - c_spin * b.w_r,
                    load.mt - c_spin * b.w_t)
