"""Analytic surfaces fitted to a CAD face's sampled points and normals: plane x = const, sphere,
circular cylinder, circular cone, elliptic cylinder (`fit_face`). The CAD cage reader
(flexbearing.mesh.cad_cage) names pockets and lands from these fits; the tolerance is the
reader's (FIT_TOL of the part's size)."""
from __future__ import annotations

import math

import numpy as np


def fit_face(P: np.ndarray, N: np.ndarray, tol: float) -> dict:
    """What analytic surface the samples lie on: {"kind": "plane_x" | "cylinder" | "sphere" |
    "cone" | "elliptic_cylinder" | "other", ...}; every fit is checked by its residual (point to
    surface) against `tol`.

    Sphere: all normal lines through one point c (least squares of sum |(I − n nᵀ)(c − p)|²),
    |p − c| constant. Cylinder: the axis a is the direction orthogonal to every normal (smallest
    eigenvector of sum n nᵀ), its point the same least squares (minimum-norm), |p − axis| constant.

    Cone (`_fit_cone`): every normal makes one angle with the axis, n·a = const, so the axis is the
    smallest eigenvector of the normals' scatter sum (n − n̄)(n − n̄)ᵀ; every tangent plane holds
    the apex v, n·(p − v) = 0, solved for v by least squares; with h = (p − v)·a (a oriented into
    the cone, h > 0) and ρ = |(p − v) − h a|, tan β = sum ρh / sum h² (least squares of ρ = h tan β),
    residual |ρ cos β − h sin β| (the distance to the cone).

    Elliptic cylinder (`_fit_ellipse`): the normals orthogonal to an axis a (as the cylinder) but
    |p − axis| not constant: in the plane normal to a (coordinates u, v), the conic
    Q = A u² + B uv + C v² + D u + E v + F = 0 through the points, whose gradient is parallel to the
    normal, (∂Q/∂u) n_v − (∂Q/∂v) n_u = 0 (both linear in (A … F): the smallest singular vector of
    the stacked rows, Fitzgibbon & Fisher's algebraic fit, BMVC 1995, with the normals added);
    centre, semi-axes and orientation from Q's quadratic part (eigen-decomposition), residual
    |Q| / |∇Q| (first-order distance to the ellipse)."""
    if np.all(np.abs(np.abs(N[:, 0]) - 1.0) < 1e-6) and np.ptp(P[:, 0]) < tol:
        return {"kind": "plane_x", "x": float(P[:, 0].mean())}
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for p, n in zip(P, N):
        Q = np.eye(3) - np.outer(n, n)
        A += Q
        b += Q @ p
    w, vecs = np.linalg.eigh(sum(np.outer(n, n) for n in N))
    c, *_ = np.linalg.lstsq(A, b, rcond=1e-10)
    r = np.linalg.norm(P - c, axis=1)
    if np.ptp(r) < tol and w[0] > 1e-3:                 # no direction orthogonal to all normals
        return {"kind": "sphere", "centre": c, "radius": float(r.mean())}
    a = vecs[:, 0]
    if w[0] < 1e-9:
        d = P - c
        dist = np.linalg.norm(d - np.outer(d @ a, a), axis=1)
        if np.ptp(dist) < tol:
            return {"kind": "cylinder", "axis": a, "point": c, "radius": float(dist.mean())}
        if w[1] > 1e-3:                                 # normals span the plane normal to a
            return _fit_ellipse(P, N, a, tol)
        return {"kind": "other"}
    return _fit_cone(P, N, tol)


def _fit_cone(P: np.ndarray, N: np.ndarray, tol: float) -> dict:
    """A circular cone through the samples (`fit_face`): {"kind": "cone", "apex", "axis" (unit,
    from the apex into the cone), "half_angle" (rad, > 0)} or {"kind": "other"}."""
    dn = N - N.mean(axis=0)
    wc, vc = np.linalg.eigh(dn.T @ dn)
    if not (wc[0] < 1e-9 and wc[1] > 1e-3):            # one angle to one axis; not a plane
        return {"kind": "other"}
    a = vc[:, 0]
    apex, *_ = np.linalg.lstsq(N, np.einsum("ij,ij->i", N, P), rcond=1e-12)
    d = P - apex
    h = d @ a
    if np.mean(h) < 0:
        a, h = -a, -h
    if np.any(h <= 0):                                  # both nappes: not a face of one cone
        return {"kind": "other"}
    rho = np.linalg.norm(d - np.outer(h, a), axis=1)
    beta = math.atan(float(rho @ h / (h @ h)))
    if beta <= 0 or np.max(np.abs(rho * math.cos(beta) - h * math.sin(beta))) >= tol:
        return {"kind": "other"}
    return {"kind": "cone", "apex": apex, "axis": a, "half_angle": beta}


def _fit_ellipse(P: np.ndarray, N: np.ndarray, a: np.ndarray, tol: float) -> dict:
    """An elliptic cylinder of axis direction a through the samples (`fit_face`): {"kind":
    "elliptic_cylinder", "axis", "point" (the ellipse's centre), "semi_axes" (major, minor),
    "major" (unit direction of the major semi-axis, normal to a)} or {"kind": "other"}."""
    e1 = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    u, v, nu, nv = P @ e1, P @ e2, N @ e1, N @ e2
    u0, v0 = u.mean(), v.mean()
    L = max(np.ptp(u), np.ptp(v))
    if L <= 0:
        return {"kind": "other"}
    x, y = (u - u0) / L, (v - v0) / L                   # centred and scaled: a conditioned fit
    one = np.ones_like(x)
    rows = np.vstack([np.column_stack([x * x, x * y, y * y, x, y, one]),
                      np.column_stack([2 * x * nv, y * nv - x * nu, -2 * y * nu, nv, -nu, 0 * one])])
    _, sv, vt = np.linalg.svd(rows)
    Ac, Bc, Cc, Dc, Ec, Fc = vt[-1]
    M = np.array([[Ac, 0.5 * Bc], [0.5 * Bc, Cc]])
    g = 0.5 * np.array([Dc, Ec])
    if np.linalg.det(M) <= 0:                           # not an ellipse (hyperbola, parabola)
        return {"kind": "other"}
    ctr = -np.linalg.solve(M, g)
    F0 = Fc + g @ ctr
    lam, vec = np.linalg.eigh(M)
    semi = -F0 / lam
    if np.any(semi <= 0):
        return {"kind": "other"}
    semi = np.sqrt(semi) * L
    # residual: first-order distance |Q|/|grad Q|, in the model's length
    Qv = Ac * x * x + Bc * x * y + Cc * y * y + Dc * x + Ec * y + Fc
    grad = np.column_stack([2 * Ac * x + Bc * y + Dc, Bc * x + 2 * Cc * y + Ec])
    gn = np.linalg.norm(grad, axis=1)
    if np.any(gn <= 0) or np.max(np.abs(Qv) / gn) * L >= tol:
        return {"kind": "other"}
    cos_n = np.abs(grad[:, 0] * nu + grad[:, 1] * nv) / gn
    if np.min(cos_n) < 1.0 - 1e-9:                      # the normals agree with the conic's
        return {"kind": "other"}
    point = (u0 + L * ctr[0]) * e1 + (v0 + L * ctr[1]) * e2 + a * float(np.mean(P @ a))
    k = int(np.argmax(semi))                            # the major axis: the smaller eigenvalue
    major = vec[0, k] * e1 + vec[1, k] * e2
    return {"kind": "elliptic_cylinder", "axis": a, "point": point,
            "semi_axes": (float(semi[k]), float(semi[1 - k])), "major": major / np.linalg.norm(major),
            "conditioning": _ellipse_conditioning(sv, lam, F0, ctr, M, L)}


def _ellipse_conditioning(sv, lam, F0, ctr, M, L) -> dict:
    """Condition numbers of the elliptic-cylinder fit (`_fit_ellipse`), for round-off bounds:

    - "conic" = sigma_1 / sigma_5 of the (2m x 6) design: the unit null vector v moves by
      ||dv|| <= ||dA||_2 / (sigma_5 - ||dA||_2) under a perturbation dA of the design (Wedin's
      sin-theta theorem; Golub & Van Loan, "Matrix Computations", 4th ed. (2013), §8.6.1), i.e.
      by ~ conic x (relative size of dA);
    - per unit ||dv|| (first order, ||v|| = 1): M moves by <= ||dv|| (||.||_2 <= ||.||_F), so an
      eigenvalue by as much (Weyl) and the centre ctr = -M^-1 g by ||M^-1||_2 (1 + |ctr|); F0 =
      F + g.ctr by sqrt(2) (1 + |ctr|)^2; semi_i = L sqrt(-F0 / lam_i) relatively by
      (dF0/|F0| + dlam/lam_i)/2, and the major direction turns by 1/|lam_2 - lam_1|
      (Golub & Van Loan Thm 8.1.12 without its factor 4, which the caller applies). Returned:
      "semi_axes" (relative), "point" (m: times L), "major" (rad); "scale" L (m)."""
    c = float(np.linalg.norm(ctr))
    return {"conic": float(sv[0] / sv[-2]),
            "semi_axes": float(0.5 * (math.sqrt(2.0) * (1.0 + c) ** 2 / abs(F0) + 1.0 / np.min(np.abs(lam)))),
            "point": float(L * np.linalg.norm(np.linalg.inv(M), 2) * (1.0 + c)),
            "major": float(1.0 / abs(lam[1] - lam[0])),
            "scale": float(L)}
