"""Small vibrations of the inner ring and the balls about a quasi-static equilibrium at rest.

The linear model is assembled from a `flexbearing.multibody.quasi_static` result, independently of the
dynamics' equations. Each loaded ball–groove contact is a tensioned spring between the ball centre
b and the groove's curvature centre g in the ball's azimuthal plane (the approach is
delta = |b − g| − (f − 0.5)·Dw, the Hertz force Q = K·delta^1.5 pulls b towards g):

    K_e = k_n·n nᵀ + (Q/d)·(I − n nᵀ),   n = (b − g)/d,  d = |b − g|,  k_n = dQ/d(delta) = 1.5·Q/delta

(the Hertz tangent stiffness, Harris & Kotzalas, Rolling Bearing Analysis 5th ed. Vol. 1 ch. 6,
with K held at the current contact angle; plus the geometric stiffness of a member under tension Q,
Przemieniecki, Theory of Matrix Structural Analysis, 1968, ch. 15 / Bathe, Finite Element
Procedures, §6.3: turning the contact line by a transverse displacement u_t turns Q through
u_t/d). The relative displacement b − g is B·q: the ball's own (x, r), minus the inner groove
centre's motion under the ring's 5 DOF u = (x, y, z, theta_y, theta_z) projected into the plane
(`flexbearing.multibody.geometry.ring_point_in_plane`, linear in u); the outer groove is fixed. The balls'
tangential (orbit) motion does not change any approach (the grooves are tori) and is left out, as
are their rotations (no friction in this model). Then

    K = sum_contacts Bᵀ K_e B,   M = diag(m_ring ×3, I_d ×2, m_ball ×2Z),   K phi = w² M phi,

with 5 + 2Z DOFs (ring first, then each ball's x, r). Statically condensing the balls (Guyan
1965) gives the 5×5 bearing stiffness with the ball kinematics frozen
(`quasi_static.bearing_stiffness(kinematics="frozen")`, within 2e-4 on the translations: that one
also follows the change of K with the contact angle).

At speed (`lines_at_speed`) the balls orbit at Omega and the ring spins at Omega_i. Under a purely
axial load every ball is alike, so in the frame orbiting with the balls the system is
time-invariant, and K above (from the equilibrium at speed, frictionless: gyroscopic=False, as
the dynamics without traction) holds there. The ring's coordinates written in that frame add
(Meirovitch, Methods of Analytical Dynamics, 1970, ch. 4; J = [[0, −1], [1, 0]] acting on (y, z)
and on (theta_y, theta_z)):

    translations   M q'' + 2·m·Omega·J q' + (K − m·Omega²) q
    tilts          I_d th'' + (2·I_d·Omega − I_p·Omega_i)·J th' + (K + (I_p·Omega_i·Omega − I_d·Omega²)) th

(the last from the ring's own gyroscopic moment I_p·Omega_i, `flexbearing.multibody.dynamics`). The balls'
Coriolis and centrifugal terms (about 3·m_b·Omega², 3e4 N/m at 10,000 rpm, against contact
stiffnesses of 1e8) are left out. A mode of frequency w in the orbiting frame shows in the fixed
frame at w + Omega (its forward-circular part in (y, z)), |w − Omega| (backward) and w (axial).
With a radial load the balls differ around the orbit and the system is time-periodic: only the
frequencies at rest (`natural_modes`) then apply.
"""
from __future__ import annotations

import math

import numpy as np

from flexbearing.multibody.geometry import ring_point_in_plane
from flexbearing.multibody.model_layout import CONTACT_OUTER, RACE_CONTACTS

RING_DOFS = ("x", "y", "z", "theta_y", "theta_z")


def linear_model(grooves, result, ring_mass: float, ring_diametral_inertia: float) -> tuple[np.ndarray, np.ndarray]:
    """(K, M), (5 + 2Z) square, SI: stiffness and mass of the ring (x, y, z, theta_y, theta_z) and
    the balls (x, r each, ball j at rows 5 + 2j, 6 + 2j) about the equilibrium `result`
    (flexbearing.multibody.quasi_static.solve_quasi_static at zero speed; module docstring)."""
    g, r = grooves, result
    z = g.n_balls
    n = 5 + 2 * z
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    M[0, 0] = M[1, 1] = M[2, 2] = ring_mass
    M[3, 3] = M[4, 4] = ring_diametral_inertia
    u = r.ring_displacement
    for j in range(z):
        psi = r.psi[j]
        M[5 + 2 * j, 5 + 2 * j] = M[6 + 2 * j, 6 + 2 * j] = g.ball_mass
        for k in range(len(RACE_CONTACTS)):
            q = r.load[j, k]
            if not g.active[k] or q <= 0.0:
                continue
            x0, r0 = g.groove_x[k], g.groove_r[k]
            B = np.zeros((2, n))
            B[0, 5 + 2 * j] = B[1, 6 + 2 * j] = 1.0
            if k == CONTACT_OUTER:
                gx, gr = x0, r0                          # outer ring fixed
            else:
                gx, gr = ring_point_in_plane(psi, x0, r0, *u)
                # ring_point_in_plane is linear in the ring's 5 DOF: its columns are the moves under unit DOFs
                base = ring_point_in_plane(psi, x0, r0, 0.0, 0.0, 0.0, 0.0, 0.0)
                for a, unit in enumerate(np.eye(5)):
                    moved = ring_point_in_plane(psi, x0, r0, *unit)
                    B[0, a] -= moved[0] - base[0]
                    B[1, a] -= moved[1] - base[1]
            dvec = np.array([r.ball_x[j] - gx, r.ball_r[j] - gr])
            d = float(np.linalg.norm(dvec))
            e = dvec / d
            delta = d - (g.groove_f[k] - 0.5) * g.ball_diameter
            k_n = 1.5 * q / delta
            ke = k_n * np.outer(e, e) + (q / d) * (np.eye(2) - np.outer(e, e))
            K += B.T @ ke @ B
    return K, M


def condensed_stiffness(K: np.ndarray) -> np.ndarray:
    """The ring's 5×5 stiffness with the balls condensed out (Guyan): K_rr − K_rb K_bb⁻¹ K_br."""
    return K[:5, :5] - K[:5, 5:] @ np.linalg.solve(K[5:, 5:], K[5:, :5])


def natural_modes(K: np.ndarray, M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(frequencies Hz ascending, mass-normalised mode shapes (columns), ring participation (5, n)):
    the ring participation of mode i in DOF a is |phi_ai|·sqrt(M_aa), the share of that DOF in
    the mode's unit modal mass (the squares over all DOFs sum to 1)."""
    from scipy.linalg import eigh
    w2, phi = eigh(K, M)
    freq = np.sqrt(np.clip(w2, 0.0, None)) / (2.0 * math.pi)
    part = np.abs(phi[:5, :]) * np.sqrt(np.diag(M)[:5, None])
    return freq, phi, part


def lines_at_speed(K: np.ndarray, M: np.ndarray, ring_mass: float, ring_diametral_inertia: float,
                   ring_polar_inertia: float, ring_speed: float, orbit_speed: float,
                   min_weight: float = 1e-3) -> list[tuple[float, float, str]]:
    """The frequencies (Hz) at which the ring moves in the fixed frame, from the modes in the frame
    orbiting with the balls (module docstring): (frequency, weight, kind) with kind "axial" (ring
    x), "forward" or "backward" (circular parts of the ring's (y, z)); weight = that part's share of
    the mode's unit displacement vector. Sorted by frequency; parts below min_weight left out.
    K, M from `linear_model` at the equilibrium at speed (pure axial load); speeds in rad/s."""
    n = K.shape[0]
    J = np.array([[0.0, -1.0], [1.0, 0.0]])
    C = np.zeros((n, n))
    Kr = K.copy()
    w_o, w_i = orbit_speed, ring_speed
    C[1:3, 1:3] = 2.0 * ring_mass * w_o * J
    Kr[1:3, 1:3] -= ring_mass * w_o ** 2 * np.eye(2)
    C[3:5, 3:5] = (2.0 * ring_diametral_inertia * w_o - ring_polar_inertia * w_i) * J
    Kr[3:5, 3:5] += (ring_polar_inertia * w_i * w_o - ring_diametral_inertia * w_o ** 2) * np.eye(2)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, Kr), -np.linalg.solve(M, C)]])
    lam, V = np.linalg.eig(A)
    lines = []
    for k in np.flatnonzero(lam.imag > 0.0):
        w = lam[k].imag
        v = V[:n, k] / np.linalg.norm(V[:n, k])
        forward, backward = abs(v[1] + 1j * v[2]) / 2.0, abs(v[1] - 1j * v[2]) / 2.0
        for f, weight, kind in ((w, abs(v[0]), "axial"), (w + w_o, forward, "forward"),
                                (abs(w - w_o), backward, "backward")):
            if weight >= min_weight:
                lines.append((f / (2.0 * math.pi), float(weight), kind))
    return sorted(lines)
