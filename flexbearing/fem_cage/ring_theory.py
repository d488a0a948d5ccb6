"""Analytic natural frequencies of a complete free circular ring of rectangular cross-section.

Ring: centroidal radius R, radial thickness h, axial width b, material (E, nu, rho).
Section: A = b h; in-plane bending I_in = b h^3 / 12 (bending in the ring plane);
out-of-plane bending I_out = h b^3 / 12; Saint-Venant torsion constant J (rectangle).
Mode number n = number of circumferential waves.

1. Thin ring, in-plane inextensional bending (Hoppe 1871; Blevins, "Formulas for Natural
   Frequency and Mode Shape", 1979, Table 9-2 case 1; Rao, "Vibration of Continuous Systems",
   2007, §11.4):
       f_n = 1/(2 pi) sqrt(E I_in / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + 1).
2. Thin ring, out-of-plane bending–torsion (Blevins Table 9-2 case 2; Rao §11.5), rotary
   inertia neglected:
       f_n = 1/(2 pi) sqrt(E I_out / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + E I_out / (G J)).
3. Thick ring, in-plane, Timoshenko-type (shear deformation with coefficient k, rotary
   inertia, extensible centre line; Kirkhope, J. Acoust. Soc. Am. 59 (1976) 86–89; Rao §11.4.3).
   Strains of a curved Timoshenko beam with radial w, tangential v, section rotation psi:
       eps = (v' + w)/R,  kappa = psi'/R,  gamma = (w' - v)/R - psi   (' = d/dtheta).
   With w = W cos n theta, v = V sin n theta, psi = Psi sin n theta the energies per unit
   pi R are
       U = 1/2 [E A (n V + W)^2 / R^2 + E I n^2 Psi^2 / R^2 + k G A ((n W + V)/R + Psi)^2],
       T = 1/2 omega^2 rho [A (W^2 + V^2) + I Psi^2],
   so omega^2 are the eigenvalues of the 3x3 pencil (K_n, M_n) below. Its lowest root is the
   bending mode; it tends to formula 1 as h/R -> 0 (inextensible, shear-rigid limit), gives
   omega = 0 for n = 1 (rigid translation) and omega^2 = E/(rho R^2) for the n = 0 breathing
   mode (Love, "Mathematical Theory of Elasticity", §294).
Shear coefficient of a rectangle: k = 10 (1 + nu) / (12 + 11 nu) (Cowper, J. Appl. Mech. 33,
1966, 335–340).
"""
from __future__ import annotations

import math

import numpy as np


def _section(outer_radius: float, inner_radius: float, width: float):
    h = outer_radius - inner_radius
    R = 0.5 * (outer_radius + inner_radius)
    A = width * h
    return R, h, A


def torsion_constant_rectangle(a: float, b: float) -> float:
    """Saint-Venant J of an a x b rectangle (a >= b): J = a b^3 [1/3 - 0.21 (b/a)(1 - b^4/(12 a^4))]
    (Roark's Formulas for Stress and Strain, 7th ed., Table 10.7 case 4; error < 4 %)."""
    a, b = max(a, b), min(a, b)
    return a * b ** 3 * (1.0 / 3.0 - 0.21 * (b / a) * (1.0 - b ** 4 / (12.0 * a ** 4)))


def cowper_shear_coefficient(nu: float) -> float:
    """k = 10 (1 + nu) / (12 + 11 nu), rectangular section (Cowper 1966)."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


def thin_ring_inplane_hz(n, outer_radius, inner_radius, width, material):
    """Formula 1 (Hoppe / Blevins): in-plane inextensional bending, Hz."""
    R, h, A = _section(outer_radius, inner_radius, width)
    I = width * h ** 3 / 12.0
    n = np.asarray(n, dtype=float)
    return (np.sqrt(material.youngs_modulus * I / (material.density * A * R ** 4))
            * n * (n ** 2 - 1) / np.sqrt(n ** 2 + 1) / (2 * math.pi))


def thin_ring_outofplane_hz(n, outer_radius, inner_radius, width, material):
    """Formula 2 (Blevins Table 9-2): out-of-plane bending–torsion, Hz."""
    R, h, A = _section(outer_radius, inner_radius, width)
    E, nu = material.youngs_modulus, material.poisson_ratio
    G = E / (2 * (1 + nu))
    I = h * width ** 3 / 12.0
    J = torsion_constant_rectangle(width, h)
    n = np.asarray(n, dtype=float)
    return (np.sqrt(E * I / (material.density * A * R ** 4))
            * n * (n ** 2 - 1) / np.sqrt(n ** 2 + E * I / (G * J)) / (2 * math.pi))


def timoshenko_ring_matrices(n: int, outer_radius, inner_radius, width, material,
                             shear_coefficient: float | None = None, rotary_inertia: bool = True):
    """(K_n, M_n), 3x3, unknowns (W, V, Psi): the energies of formula 3 as quadratic forms."""
    R, h, A = _section(outer_radius, inner_radius, width)
    E, nu, rho = material.youngs_modulus, material.poisson_ratio, material.density
    G = E / (2 * (1 + nu))
    k = cowper_shear_coefficient(nu) if shear_coefficient is None else shear_coefficient
    I = width * h ** 3 / 12.0
    # strain vectors as linear maps of (W, V, Psi):
    e_m = np.array([1.0, n, 0.0]) / R            # membrane  (n V + W)/R
    e_b = np.array([0.0, 0.0, n]) / R            # bending   n Psi / R
    e_s = np.array([n / R, 1.0 / R, 1.0])        # shear     (n W + V)/R + Psi
    K = E * A * np.outer(e_m, e_m) + E * I * np.outer(e_b, e_b) + k * G * A * np.outer(e_s, e_s)
    M = rho * np.diag([A, A, I])
    if not rotary_inertia:
        # No inertia on Psi: condense it statically, K_c = K_aa - K_ap K_pp^-1 K_pa.
        K = K[:2, :2] - np.outer(K[:2, 2], K[2, :2]) / K[2, 2]
        M = M[:2, :2]
    return K, M


def thick_ring_inplane_hz(n, outer_radius, inner_radius, width, material,
                          shear_coefficient: float | None = None, branch: int = 0,
                          rotary_inertia: bool = True):
    """Formula 3: in-plane frequencies of the Timoshenko ring, Hz. branch 0 = flexural (lowest)."""
    from scipy.linalg import eigh
    out = []
    for ni in np.atleast_1d(n):
        if int(ni) < 1:
            raise ValueError("thick_ring_inplane_hz: n >= 1 (n = 0 is the breathing mode, "
                             "omega^2 = E/(rho R^2))")
        K, M = timoshenko_ring_matrices(int(ni), outer_radius, inner_radius, width, material,
                                        shear_coefficient, rotary_inertia)
        lam = eigh(K, M, eigvals_only=True)
        out.append(math.sqrt(max(lam[branch], 0.0)) / (2 * math.pi))
    return np.array(out) if np.ndim(n) else out[0]
