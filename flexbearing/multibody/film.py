"""EHL film thickness of an elliptical ball–race contact: Hamrock & Dowson (1977).

Hamrock & Dowson, "Isothermal elastohydrodynamic lubrication of point contacts, Part III — fully
flooded results", J. Lubr. Technol. 99(2):264–276, 1977 (eqs 21 and 22 there; also Hamrock &
Dowson, Ball Bearing Lubrication, Wiley 1981, ch. 8):

    U = eta0·u/(E'·Rx),  u = (u_a + u_b)/2 (mean entrainment speed),  G = alpha_p·E',
    W = Q/(E'·Rx²),      k = 1.03·(Ry/Rx)^0.64,
    h_min/Rx = 3.63·U^0.68·G^0.49·W^(−0.073)·(1 − exp(−0.68·k)),
    h_c/Rx   = 2.69·U^0.67·G^0.53·W^(−0.067)·(1 − 0.61·exp(−0.73·k)).

Isothermal, fully flooded, smooth surfaces; the fit covers k = 1–8 and the hard-EHL range of
U, G, W of their numerical solutions (quoted fit error ≤ 5 %). eta0 is the viscosity at the inlet
temperature and atmospheric pressure (the paper preset evaluates it at 20 °C, as the paper's eta0 "at atmospheric pressure and
ambient temperature", §2.2.2).
"""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def film_parameters(Rx, Ry, E_eff, Q, u_entrain, eta0, alpha_p):
    """Dimensionless groups (U, G, W, k) of Hamrock & Dowson (1977); speeds as |u|."""
    U = eta0 * abs(u_entrain) / (E_eff * Rx)
    G = alpha_p * E_eff
    W = Q / (E_eff * Rx * Rx)
    k = 1.03 * (Ry / Rx) ** 0.64
    return U, G, W, k


@njit(cache=True)
def film_thickness(Rx, Ry, E_eff, Q, u_entrain, eta0, alpha_p):
    """(h_min, h_c) in m, Hamrock & Dowson (1977) (equations in the module docstring).

    Rx, Ry effective radii (m), E_eff = E' (Pa), Q load (N), u_entrain = mean surface speed (m/s),
    eta0 inlet viscosity (Pa·s), alpha_p pressure–viscosity coefficient (1/Pa). Zero load or
    speed gives (0, 0): the formula has no meaning there and no film is reported.
    """
    if Q <= 0.0 or u_entrain == 0.0:
        return 0.0, 0.0
    U, G, W, k = film_parameters(Rx, Ry, E_eff, Q, u_entrain, eta0, alpha_p)
    h_min = Rx * 3.63 * U ** 0.68 * G ** 0.49 * W ** -0.073 * (1.0 - math.exp(-0.68 * k))
    h_c = Rx * 2.69 * U ** 0.67 * G ** 0.53 * W ** -0.067 * (1.0 - 0.61 * math.exp(-0.73 * k))
    return h_min, h_c
