"""Round-off bounds for comparisons whose operation order depends on the BLAS, LAPACK, instruction set
or numba's code generation (matrix products, solves, factorizations, eigen solves, long sums).

Two computations of the same quantity by different operation orders (an OpenBLAS kernel with FMA
against the reference BLAS, a numba kernel against a numpy expression) agree only to the sum of their
rounding errors; a fixed tiny number measured on one processor is not a bound. Each function below
returns an a-priori bound from the standard error analysis (u = eps/2 the unit round-off,
gamma_k = k u / (1 - k u)):

- Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., SIAM (2002):
  Lemma 3.1 (gamma_k), eq. (3.4)/(3.5) (inner products), §3.5 eq. (3.13) (matrix products),
  §4.2 (recursive summation, any order), Thm 7.2 (forward error of a perturbed solve), Thm 9.4 (LU).
- Golub & Van Loan, "Matrix Computations", 4th ed. (2013): §2.7 (perturbation of Ax = b),
  §3.3.2 (GEPP backward error), §8.1.2 / Thm 8.1.4 (Weyl: symmetric eigenvalues within
  ||E||_2), §8.7.2 (symmetric-definite pencils via Cholesky: eps ||A||_2 ||B^-1||_2).
- Yamamoto, Nakatsukasa, Yanagisawa & Fukaya, "Roundoff error analysis of the CholeskyQR2
  algorithm", ETNA 44 (2015) 306-326, Thm 3.3: ||Q^T Q - I||_F <= 6 (m n u + n (n + 1) u).

The bounds are worst-case (every rounding in the same direction); on any IEEE-754 double machine
with any summation order the error stays below them. A test using one also asserts that the bound
lies far below the effect it proves (`assert_within(..., effect=...)`), so it keeps its power.

FLEXBEARING_TOLERANCE_LOG=<file>: every assert_within appends one JSON line (test, name, error,
bound) to the file; benchmarks/tolerance_audit.py --measured tabulates them per environment.
"""
from __future__ import annotations

import json
import os

import numpy as np
import scipy.sparse as sp

EPS = float(np.finfo(float).eps)
U = EPS / 2                       # unit round-off of IEEE-754 double (round to nearest)


def gamma(k: int) -> float:
    """gamma_k = k u / (1 - k u) (Higham Lemma 3.1): the relative error of k roundings."""
    k = max(int(k), 1)
    return k * U / (1.0 - k * U)


def _abs(A):
    return abs(A) if sp.issparse(A) else np.abs(np.asarray(A))


def dot_bound(n: int, scale) -> float | np.ndarray:
    """|fl(x^T y) - x^T y| <= gamma_n |x|^T |y| (Higham eq. (3.5)); scale = |x|^T |y| (the sum of
    the absolute terms, not the result, which may cancel). Twice that for two computations of
    the same sum in different orders."""
    return 2.0 * gamma(n) * scale


def sum_roundoff(values, axis=None) -> float | np.ndarray:
    """A sum of n terms in any order is within gamma_(n-1) sum |x_i| of the exact sum (Higham
    §4.2, eq. (4.4)); twice that between two orders (a vectorised or fastmath reduction against a
    loop)."""
    v = np.asarray(values, dtype=float)
    n = v.size if axis is None else v.shape[axis]
    return 2.0 * gamma(max(n - 1, 1)) * np.abs(v).sum(axis=axis)


def product_bound(*factors) -> np.ndarray:
    """Entrywise bound on the difference of two evaluations of a chain of products A1 A2 ... Ap in
    any order and blocking: |fl(A1...Ap) - A1...Ap| <= gamma_k |A1| |A2| ... |Ap| with k the sum
    of the inner dimensions (Higham §3.5, eq. (3.13), applied p - 1 times, first order); twice
    that between two evaluations. Vectors are columns; a 1-d array between two matrices is a
    diagonal. Sparse factors count their largest row length, not their dimension."""
    mats, k = [], 0
    for i, f in enumerate(factors):
        if not sp.issparse(f):
            f = np.asarray(f, dtype=complex if np.iscomplexobj(f) else float)
            if f.ndim == 1 and 0 < i < len(factors) - 1:
                f = np.diag(f)
            elif f.ndim == 1:
                f = f[:, None] if i == len(factors) - 1 else f[None, :]
        mats.append(f)
    for i, f in enumerate(mats[:-1]):
        if sp.issparse(f):
            k += int(np.diff(sp.csr_matrix(f).indptr).max(initial=1))
        else:
            k += f.shape[1]
    out = _abs(mats[0])
    for f in mats[1:]:
        out = out @ _abs(f)
    out = out.toarray() if sp.issparse(out) else np.asarray(out)
    return 2.0 * gamma(k) * out


def solve_error_bound(A, n_rhs_ops: int = 0) -> float:
    """Relative forward error ||x_hat - x||_inf / ||x||_inf of a backward-stable solve of A x = b
    (LU with partial pivoting, Cholesky; growth factor taken as 2 for these small, well-scaled
    matrices): with backward error ||dA|| <= 3 n u rho ||A|| (Golub & Van Loan Thm 3.3.2, Higham
    Thm 9.4) the forward error is at most 2 kappa_inf(A) 3 n u rho / (1 - kappa 3 n u rho) (GVL
    §2.7.3, Higham Thm 7.2); n_rhs_ops roundings in forming b add kappa gamma(n_rhs_ops). Twice that
    between two solvers."""
    A = np.asarray(A.toarray() if sp.issparse(A) else A, dtype=float)
    n = A.shape[0]
    kappa = np.linalg.cond(A, np.inf)
    e = 3 * n * U * 2.0 + (gamma(n_rhs_ops) if n_rhs_ops else 0.0)
    if kappa * e >= 0.5:
        return np.inf
    return 2.0 * 2.0 * kappa * e / (1.0 - kappa * e)


def orthonormality_bound(n: int, k: int, cond_M: float = 1.0) -> float:
    """Loss of (M-)orthonormality ||Q^T M Q - I||_max of k columns of length n produced by a
    Cholesky-QR2-type pass (Gram matrix, eigen or Cholesky factor, one repeat, as
    flexbearing.fem_cage.block_lanczos.m_orthonormalise and a Rayleigh-Ritz on its basis):
    6 (n k + k (k + 1)) u (Yamamoto et al. 2015, Thm 3.3, ||.||_max <= ||.||_F), times the
    condition of the inner product's matrix M (the M-weighted analysis carries kappa(M)), plus
    the rounding of the test's own Q^T M Q, gamma_n kappa(M). The same number bounds, relative to
    max |M Q|, a tracked M Q (the same combinations applied to M W) against a fresh M @ Q."""
    return 6.0 * (n * k + k * (k + 1)) * U * cond_M + 2.0 * gamma(n) * cond_M


def eigenvalue_bound(A_norm2: float, Binv_norm2: float = 1.0, n: int = 1) -> float:
    """Absolute error of an eigenvalue of a symmetric (definite) pencil A x = lambda B x computed by
    a backward-stable solver: p(n) eps ||A||_2 ||B^-1||_2 with p(n) = n (Weyl's theorem, Golub &
    Van Loan Thm 8.1.4 with the backward error of the symmetric QR/divide-and-conquer; §8.7.2 for
    the Cholesky reduction of the pencil). Twice that between two solvers."""
    return 2.0 * n * EPS * A_norm2 * Binv_norm2


def norm_bound(k: int, w, value, axis: int = -1):
    """Two evaluations of a Euclidean norm ||v|| (a von Mises stress ||L s||, a displacement
    magnitude) whose d entries are each a k-term sum with absolute terms w (entrywise, |v_r| <=
    w_r): | ||v1|| - ||v2|| | <= ||v1 - v2|| <= 2 gamma_k ||w||_2 (Higham eq. (3.5) per entry),
    plus the rounding of the squares, their d-term sum and the square root in each evaluation,
    2 gamma_(d+2) ||v|| (Higham Lemma 3.1, §3.1). value = ||v|| (either evaluation). Along axis."""
    w = np.asarray(w, dtype=float)
    d = w.shape[axis]
    return dot_bound(k, np.linalg.norm(w, axis=axis)) + 2.0 * gamma(d + 2) * np.abs(value)


def von_mises_bound(S, q, value):
    """Two evaluations of the von Mises stress of s = S q (S (..., 6, m) Voigt rows per unit q, q
    (m,)) in any of its closed forms (the textbook differences, ||L s||, 3 sqrt(J2/3) or
    sqrt(3/2 s:s) of the deviator): each form's <= 9 entries are combinations of the 6
    components with absolute coefficients summing to <= 2 (4/3 sqrt(3/2) = 1.63 for a deviator
    entry, sqrt(3) for a shear), each component an m-term sum within gamma_m (|S| |q|); so
    w <= 2 sum_i (|S| |q|)_i for every entry, k = m + 6 roundings (norm_bound, d = 9)."""
    a = np.abs(np.asarray(S)) @ np.abs(np.asarray(q))
    w = np.repeat(2.0 * a.sum(axis=-1, keepdims=True), 9, axis=-1)
    return norm_bound(np.asarray(S).shape[-1] + 6, w, value)


def pencil_orthonormality_bound(n: int, cond_M: float) -> float:
    """||N^T M N - I||_max for the eigenvectors N of a symmetric-definite pencil (K, M) of order n
    solved through a Cholesky factor of M (Golub & Van Loan §8.7.2; flexbearing.fem_cage.
    craig_bampton.orthonormalise, M Jacobi-scaled), kappa = kappa_2(M) (reduce_model returns it as
    orthogonality["mass_condition"]). With X = L^-T Q, X^T M X - I = Q^T L^-1 E L^-T Q + (Q^T Q - I):
    - the Cholesky backward error |E| <= gamma_(n+1) |L| |L^T| (Higham Thm 10.3) with
      || |L| |L^T| ||_2 <= n ||M||_2 (|| |B| ||_2 <= sqrt(rank) ||B||_2, Higham Lemma 6.6), so
      ||L^-1 E L^-T||_2 <= n gamma_(n+1) kappa;
    - Q^T Q - I of the symmetric eigensolver and the null-space / basis products around it (Z Y,
      the rigid block): each within n gamma_(n+1) kappa (Higham §19.3, Lemma 19.3);
    - the check's own product N^T M N: gamma_n |N|^T |M| |N| <= n gamma_n ||M||_2 ||N||_2^2
      = n gamma_n kappa (||N||_2^2 = ||M^-1||_2 for M-orthonormal N).
    Four terms: 4 n gamma_(n+1) kappa (the max entry is below the 2-norm)."""
    return 4.0 * n * gamma(n + 1) * cond_M


def pencil_stiffness_bound(n: int, stiffness_condition: float) -> float:
    """||N^T K N - diag(omega^2)||_max / omega_max^2 for the same pencil solve as
    pencil_orthonormality_bound: the reduced matrix C = L^-1 K L^-T is formed within
    n gamma_(n+1) ||K||_2 ||M^-1||_2 (Golub & Van Loan §8.7.2, the Cholesky error as above), the
    symmetric eigensolver adds n gamma_(n+1) ||C||_2 <= the same, the basis products one more, and
    the check's N^T K N gamma_n ||K||_2 ||N||_2^2 = n gamma_n ||K||_2 ||M^-1||_2 (Weyl, Golub & Van
    Loan Thm 8.1.4, for the eigenvalues): 4 n gamma_(n+1) s with s = ||K||_2 ||M^-1||_2 / omega_max^2
    (reduce_model's orthogonality["stiffness_condition"])."""
    return 4.0 * n * gamma(n + 1) * stiffness_condition


def mean_axis_bound(M, R, Phi, pencil_error: float, n_rigid: int = 6):
    """Bound on |R^T M Phi_e| (the mean-axis conditions of the elastic modes Phi_e = Phi[:, n_rigid:]:
    I3 = int rho Phi_e over translations, I4 = int rho x x Phi_e over rotations about the origin),
    R (n, 6) the exact unit rigid fields, M the (sparse) mass matrix, Phi M-orthonormal with its
    first n_rigid columns the rigid modes. Writing r_a = t_a - Phi_r c_a (c_a = Phi_r^T M t_a, the
    part of the exact rigid field the computed rigid modes do not hold):

        t_a^T M phi_k = c_a^T (Phi_r^T M phi_k) + r_a^T M phi_k
        |.| <= sqrt(n_rigid) ||t_a||_M e + ||r_a||_M (1 + e) + 2 gamma_k (|t_a|^T |M| |phi_k|)

    e = pencil_error (pencil_orthonormality_bound: the off-diagonal of Phi^T M Phi; ||c_a||_2 =
    ||t_a||_M), Cauchy-Schwarz for the second term, and the rounding of the mesh sums that
    compute the invariants (product_bound). Returns (bound (6, m - n_rigid), ||t_a||_M (6,)): the
    latter is the size of the effect (a mode that is not mean-axis has |t^T M phi| ~ ||t||_M)."""
    MR = M @ R
    tM = np.sqrt(np.einsum("ij,ij->j", R, MR))
    P = Phi[:, :n_rigid]
    c = P.T @ MR
    r = R - P @ c
    rM = np.sqrt(np.abs(np.einsum("ij,ij->j", r, M @ r)))
    rounding = product_bound(np.asarray(R).T, M, Phi[:, n_rigid:])
    bound = (np.sqrt(n_rigid) * tM * pencil_error + rM * (1.0 + pencil_error))[:, None] + rounding
    return bound, tM


def _log(name, error, bound):
    path = os.environ.get("FLEXBEARING_TOLERANCE_LOG")
    if not path:
        return
    cur = os.environ.get("PYTEST_CURRENT_TEST", "?::? (call)").split(" ")[0]
    file, _, test = cur.partition("::")
    with open(path, "a") as f:
        f.write(json.dumps({"file": file, "test": test, "name": name, "error": float(error),
                            "bound": float(bound)}) + "\n")


def assert_within(error, bound, name: str, effect: float | None = None, power: float = 1e-3):
    """Assert error <= bound entrywise (arrays broadcast) and, if effect is given, that the bound stays below power * effect (the test still proves what it claims). The
    worst error/bound ratio is logged (FLEXBEARING_TOLERANCE_LOG)."""
    err = np.asarray(error, dtype=float)
    bnd = np.broadcast_to(np.asarray(bound, dtype=float), err.shape)
    ratio = np.where(bnd > 0, err / np.where(bnd > 0, bnd, 1.0), np.where(err > 0, np.inf, 0.0))
    # the entry with the largest error/bound ratio (all errors 0: the entry with the largest bound)
    pick = ratio if ratio.size and np.max(ratio) > 0 else bnd
    i = np.unravel_index(np.argmax(pick), pick.shape) if ratio.size else ()
    worst_err = float(err[i]) if err.size else 0.0
    worst_bnd = float(bnd[i]) if err.size else 0.0
    _log(name, worst_err, worst_bnd)
    assert np.all(err <= bnd), (f"{name}: error {worst_err:.3e} above its round-off bound "
                                f"{worst_bnd:.3e}")
    if effect is not None:
        top = float(np.max(bnd)) if bnd.size else 0.0
        assert top <= power * effect, (f"{name}: the bound {top:.3e} is not below {power:g} x the "
                                       f"effect {effect:.3e}: the test would no longer prove it")
