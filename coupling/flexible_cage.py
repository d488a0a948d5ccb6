"""The flexible cage body: the reduced cage file turned into floating-frame arrays.

`flexible_cage_body(rc, n_keep, beta, centrifugal_correction)` selects the modal basis the run
integrates and transforms every quantity the floating-frame equations (coupling.floating_frame),
the pocket coupling and the stress recovery need into that basis:

    Phi_run = Phi_full · T          (T: (M_elastic, n) — a selection plus an optional extra column)

The reduced cage file holds the full M-orthonormal Craig–Bampton basis sorted by frequency
(fem_cage.reduced_cage). The run keeps the paper's 26 modes — 6 rigid, carried by the floating
frame, and the 20 lowest elastic ones (n_keep counts the rigid ones, as the paper and ADAMS do).

Centrifugal correction (modal truncation augmentation, Dickens, Nakagawa & Wittbrodt, Comput.
Struct. 62 (1997) 985). The spinning cage's centrifugal load f = rho·Omega²·x_perp excites the
axisymmetric (n = 0) extensional deformation of the ring, whose first mode (~ sqrt(E/rho)/(2·pi·R)
≈ 9–10 kHz here) lies above the 26 kept modes: a plain truncation recovers no hoop stress at all.
The static response of the *discarded* modes to that load,

    q_k = Q_k / omega_k²,   Q_k = ∫rho Phi_k · x_perp dV = Sx[1,1,k] + Sx[2,2,k]   (k discarded)

normalised to unit modal mass, is appended as one more Ritz vector. It lives in the span of the
discarded modes, so it is M- and K-orthogonal to the kept ones: the modal mass stays the identity
and the modal stiffness diagonal, its own entry being the Rayleigh quotient Σ q_k² omega_k² / Σ q_k².
With it the kept basis reproduces the full basis's static centrifugal response exactly.

Damping: D = beta·K (paper), i.e. modal damping beta·omega_k².
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from coupling.floating_frame import FlexibleBody
from mesh.validation import require_range

N_RIGID = 6


class CageModalBasis(NamedTuple):
    body: FlexibleBody
    transform: np.ndarray        # (M_full, n): run modal coordinates -> full-basis coordinates
    frequency_hz: np.ndarray     # (n,) of the run's modes (the correction's Rayleigh frequency last)
    stress_modes: np.ndarray     # (Nv, 6, n) Pa per unit q
    vertex_displacement: np.ndarray  # (Nv, 3, n) m per unit q


def centrifugal_generalised_force(Sx: np.ndarray) -> np.ndarray:
    """Q_k = ∫rho Phi_k · x_perp dV (x the bearing axis): the modal centrifugal load per unit Omega²."""
    return Sx[1, 1, :] + Sx[2, 2, :]


def modal_transform(omega: np.ndarray, Sx: np.ndarray, n_keep: int, centrifugal_correction: bool,
                    n_rigid: int = N_RIGID) -> np.ndarray:
    """T (M_full, n): keep modes n_rigid..n_keep-1, plus the centrifugal Ritz vector if asked."""
    M = omega.shape[0]
    keep = np.arange(n_rigid, n_keep)
    cols = [np.eye(M)[:, keep]] if keep.size else [np.zeros((M, 0))]
    if centrifugal_correction and n_keep < M:
        rest = np.arange(n_keep, M)
        Q = centrifugal_generalised_force(Sx)
        q = np.zeros(M)
        q[rest] = Q[rest] / omega[rest] ** 2
        norm = np.linalg.norm(q)
        if norm > 0.0:
            cols.append((q / norm)[:, None])
    return np.hstack(cols)


def flexible_cage_body(rc, n_keep: int = 26, beta: float = 0.0,
                       centrifugal_correction: bool = True) -> CageModalBasis:
    """Floating-frame arrays of the reduced cage `rc` (fem_cage.reduced_cage.ReducedCage, full
    basis) for a run keeping n_keep modes (rigid included), damping D = beta·K."""
    M = rc.n_modes
    require_range("cage.n_modes", n_keep, N_RIGID, M)
    require_range("cage.damping_beta", beta, 0.0, 1.0, unit="s")
    inv = rc.invariants
    T = modal_transform(rc.omega, inv["Sx"], int(n_keep), centrifugal_correction)
    omega2 = rc.omega ** 2
    # modal stiffness in the run basis: Tᵀ diag(omega²) T (diagonal by construction)
    kdiag = np.einsum("kn,k,kn->n", T, omega2, T)
    Sx = inv["Sx"] @ T
    SS = np.einsum("abjk,jm,kn->abmn", inv["SS"], T, T, optimize=True)
    S1 = inv["S1"] @ T
    Mff = T.T @ inv["I6"] @ T
    mass = float(inv["mass"])
    first = np.asarray(inv["first"], dtype=float)
    second = np.asarray(inv["second"], dtype=float)
    body = FlexibleBody(mass, first, second, np.ascontiguousarray(S1), np.ascontiguousarray(Sx),
                        np.ascontiguousarray(SS), np.ascontiguousarray(Mff), kdiag, beta * kdiag,
                        np.ascontiguousarray(rc.interface_positions, dtype=float),
                        np.ascontiguousarray(rc.interface_modes @ T))
    return CageModalBasis(body, T, np.sqrt(np.maximum(kdiag, 0.0)) / (2 * np.pi),
                          np.ascontiguousarray(rc.stress_modes @ T),
                          np.ascontiguousarray(rc.vertex_displacement @ T))
