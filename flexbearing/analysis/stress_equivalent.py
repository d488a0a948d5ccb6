"""Scalar stress histories of a multiaxial stress-tensor history, for cycle counting.

Voigt order (xx, yy, zz, yz, xz, xy), Pa (flexbearing.fem_cage.stress_modes), histories (..., T, 6).

Signed von Mises (the equivalent of the durability codes for proportional loading):

    sigma_svM(t) = sign(sigma_p(t)) sigma_vM(t),   sigma_p the principal stress of largest magnitude

sigma_vM = sqrt(1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2)) (von Mises
1913). The sign keeps tension and compression apart, so a fully reversed uniaxial stress stays
fully reversed (von Mises alone would count it as a pulsating stress at twice the frequency). For
a uniaxial state sigma_svM = sigma_xx exactly. Its known weakness is non-proportional loading:
for tension sigma_a sin(wt) with torsion tau_a cos(wt), tau_a = sigma_a, the sign follows sigma_x
and flips where sigma_vM = sqrt(3) sigma_a is largest, so the signed von Mises jumps from
+sqrt(3) sigma_a to -sqrt(3) sigma_a: a range of 2 sqrt(3) sigma_a, while no plane of the material
sees a normal-stress amplitude above 2/sqrt(3) sigma_a (below) — hence the critical plane at the
candidate nodes.

Normal stress on the critical plane (the stress-based critical-plane approach for tensile,
mode-I cracks: Socie & Marquis, "Multiaxial Fatigue", SAE 2000, ch. 5; the "normal stress"
criterion of the critical-plane durability codes):

    sigma_n(t; n) = n . sigma(t) n ,   D = max over unit normals n of D(sigma_n(.; n))

the damage of the normal-stress history of each plane, counted and corrected as a uniaxial
history, maximised over the plane orientation. For a proportional history sigma(t) = s(t) S the
critical plane is the principal direction of S with the largest |principal value|; for tension
sigma_x = sigma_a sin(wt) with torsion tau_xy = tau_a sin(wt + phi) the normal stress on the plane
at angle theta to x (in the x-y plane) is
    sigma_n = sigma_a cos^2(theta) sin(wt) + tau_a sin(2 theta) sin(wt + phi)
whose amplitude, maximised over theta, is sigma_a/2 + sqrt(sigma_a^2/4 + tau_a^2) for phi = 0 and
sqrt(max_c (sigma_a^2 c^2 + 4 tau_a^2 c (1 - c))), c = cos^2 theta, for phi = 90 degrees
(2/sqrt(3) sigma_a at tau_a = sigma_a) (tests/test_fatigue.py).

Plane search (cage_fatigue.critical_plane): the normals of a Fibonacci lattice on the half sphere
(`plane_normals`, covering radius h ~ 2/sqrt(n)), then a local grid of spacing h/8 around the
best of them; on each, the planes of largest normal-stress range are counted exactly and the
worst is taken. Near the maximising plane the amplitude of n . sigma n is stationary, so a plane
at angle e from it loses at most sin^2(e) (f* + ||C|| + ||S||) of the amplitude f* (C, S the cos
and sin tensors of a sinusoidal history): the tolerance of tests/test_fatigue.py.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit


def von_mises(sigma: np.ndarray) -> np.ndarray:
    s = np.asarray(sigma, dtype=np.float64)
    a, b, c, d, e, f = (s[..., i] for i in range(6))
    return np.sqrt(0.5 * ((a - b) ** 2 + (b - c) ** 2 + (c - a) ** 2) + 3.0 * (d * d + e * e + f * f))


def largest_principal(sigma: np.ndarray) -> np.ndarray:
    """The principal stress of largest magnitude, signed (..., ) Pa (eigenvalues of the tensor by
    LAPACK: the independent reference of signed_von_mises_of's closed form in the tests)."""
    s = np.asarray(sigma, dtype=np.float64)
    T = np.empty(s.shape[:-1] + (3, 3))
    T[..., 0, 0], T[..., 1, 1], T[..., 2, 2] = s[..., 0], s[..., 1], s[..., 2]
    T[..., 1, 2] = T[..., 2, 1] = s[..., 3]
    T[..., 0, 2] = T[..., 2, 0] = s[..., 4]
    T[..., 0, 1] = T[..., 1, 0] = s[..., 5]
    w = np.linalg.eigvalsh(T)                       # ascending
    return np.where(np.abs(w[..., 0]) > np.abs(w[..., 2]), w[..., 0], w[..., 2])


@njit(cache=True)
def signed_von_mises_of(sxx, syy, szz, syz, sxz, sxy) -> float:
    """sigma_svM of one stress state without an eigen-solver: with q = tr/3, p = sqrt(J2/3) and
    phi = acos(det((sigma - q I)/p)/2)/3 (Smith, Comm. ACM 4(4):168, 1961) the extreme principal
    stresses are q + 2p cos(phi) and q + 2p cos(phi + 2 pi/3), whose sum 2q + 2p cos(phi + pi/3)
    has the sign of the principal stress of largest magnitude; sigma_vM = sqrt(3 J2) = 3p.
    The sign of an exact tie (sum 0) is +."""
    q = (sxx + syy + szz) / 3.0
    a, b, c = sxx - q, syy - q, szz - q
    p = math.sqrt((a * a + b * b + c * c + 2.0 * (syz * syz + sxz * sxz + sxy * sxy)) / 6.0)
    if p == 0.0:
        return 0.0
    det = a * (b * c - syz * syz) - sxy * (sxy * c - syz * sxz) + sxz * (sxy * syz - b * sxz)
    r = min(1.0, max(-1.0, det / (2.0 * p * p * p)))
    phi = math.acos(r) / 3.0
    return -3.0 * p if q + p * math.cos(phi + math.pi / 3.0) < 0.0 else 3.0 * p


@njit(cache=True)
def _signed_von_mises_rows(s, out):
    for i in range(s.shape[0]):
        out[i] = signed_von_mises_of(s[i, 0], s[i, 1], s[i, 2], s[i, 3], s[i, 4], s[i, 5])


def signed_von_mises(sigma: np.ndarray) -> np.ndarray:
    """sigma_svM (module doc) of Voigt stresses (..., 6), Pa."""
    s = np.ascontiguousarray(sigma, dtype=np.float64)
    out = np.empty(s.shape[:-1])
    _signed_von_mises_rows(s.reshape(-1, 6), out.reshape(-1))
    return out


@njit(cache=True)
def signed_von_mises_block(sig, out):
    """out[i, t] = sigma_svM of sig[i, :, t] for a block of node histories sig (nodes, 6, T) (the
    layout of S_n q_t from one matrix product); allocation-free."""
    for i in range(sig.shape[0]):
        for t in range(sig.shape[2]):
            out[i, t] = signed_von_mises_of(sig[i, 0, t], sig[i, 1, t], sig[i, 2, t], sig[i, 3, t],
                                            sig[i, 4, t], sig[i, 5, t])


def plane_normals(n: int) -> np.ndarray:
    """n unit normals of a Fibonacci lattice on the half sphere x >= 0 (a plane and its opposite
    normal are the same plane), (n, 3)."""
    k = np.arange(n, dtype=np.float64)
    x = 1.0 - (k + 0.5) / n                          # uniform in [0, 1): equal areas on the half sphere
    r = np.sqrt(np.maximum(0.0, 1.0 - x * x))
    phi = k * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([x, r * np.cos(phi), r * np.sin(phi)], axis=1)


def lattice_spacing(n: int) -> float:
    """Angular covering radius (rad) of plane_normals(n), a safe estimate: every direction of the
    half sphere is within this angle of a lattice normal (area per point 2 pi/n, a disc of
    radius h covers it for h = sqrt(2 (2 pi / n) / pi) ~ 2 / sqrt(n))."""
    return 2.0 / math.sqrt(n)


def normal_stress(sigma: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """sigma_n = n . sigma n for histories (T, 6) and normals (P, 3): (P, T) Pa."""
    s = np.asarray(sigma, dtype=np.float64)
    nx, ny, nz = normals[:, 0:1], normals[:, 1:2], normals[:, 2:3]
    return (nx * nx * s[:, 0] + ny * ny * s[:, 1] + nz * nz * s[:, 2]
            + 2.0 * (ny * nz * s[:, 3] + nx * nz * s[:, 4] + nx * ny * s[:, 5]))
