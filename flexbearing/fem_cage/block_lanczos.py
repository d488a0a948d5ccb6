"""The lowest modes of a constrained structure by shift-and-invert block Lanczos.

The fixed-interface modes of the Craig–Bampton reduction (flexbearing.fem_cage.craig_bampton) are
the lowest eigenpairs of

    K phi = omega^2 M phi,   C phi = 0                                              (L1)

(K, M the cage's stiffness and mass, C the pocket interface's RBE3 rows). With the factorised
saddle matrix S = [[K, C^T], [C, 0]] the operator

    OP x = u,   [K C^T; C 0] [u; l] = [M x; 0]                                       (L2)

maps onto ker C and is self-adjoint in the M inner product there; its eigenvalues are
theta = 1 / omega^2, so the lowest modes are OP's largest, well separated eigenvalues (the
spectral transformation of Ericsson & Ruhe, Math. Comp. 35 (1980) 1251).

Block Lanczos (Golub & Underwood 1977; the shifted block Lanczos of Grimes, Lewis & Simon,
SIAM J. Matrix Anal. Appl. 15 (1994) 228, is how NASTRAN and ANSYS solve (L1)) builds an
M-orthonormal basis Q = [Q_1 ... Q_j] of the block Krylov space span{Q_1, OP Q_1, ..., OP^(j-1) Q_1}:

    OP Q_j = Q_1 H_1j + ... + Q_j H_jj + Q_(j+1) B_(j+1)                             (L3)

with H_ij = Q_i^T M OP Q_j (reorthogonalised against the whole basis, twice: classical
Gram–Schmidt "twice is enough", Giraud et al., Numer. Math. 101 (2005) 87) and Q_(j+1) B_(j+1) the
M-orthonormalised remainder. The Ritz pairs are T s = theta s with T = Q^T M OP Q; the
residual of y = Q s is, from (L3), without any further operator application,

    || OP y - theta y ||_M = || B_(j+1) s_j ||   (s_j: the last block rows of s)       (L4)

The iteration stops when the n_modes largest Ritz values have || r ||_M <= tol * theta.

Why a block method: each step applies OP to b columns at once, and a factorised solve with b
right-hand sides costs far less per column than b solves (MUMPS's dense fronts go through level-3
BLAS: on the paper cage with OpenBLAS 0.015 s per column for 10 columns, 0.012 s for 20, against
0.073 s for one; with the reference BLAS 0.035 and 0.034 s against 0.063 s). Block Lanczos needs
more columns than single-vector Krylov–Schur (252 against SLEPc's 170 for the paper cage's 30
modes) and its reorthogonalisation is O(n m^2) level-3 work, so it is the faster method only with
an optimised BLAS: 30 modes in 8.0 s against SLEPc's 14.0 s on OpenBLAS, 21.0 s against 14.3 s on
the reference BLAS (benchmarks/bench_eigensolver.py). craig_bampton picks by the BLAS loaded
(flexbearing.common.blas).

Staying on ker C. OP's output lies on ker C only to the solver's rounding, relative to its own
size; Gram–Schmidt then removes most of that size (the components along the converged modes), so
the rounding off ker C grows relative to what is left, by the cancellation ratio at every step,
and compounds through the basis (measured on a 120-node chain: C W / W from 6e-15 at the first
step to 1 at the thirtieth, and spurious directions beyond dim ker C). The same drift is why
shift-and-invert Lanczos "purifies" its vectors (Nour-Omid, Parlett, Ericsson & Jensen, Math.
Comp. 48 (1987) 663). Each new block is therefore projected back onto ker C after the
Gram–Schmidt passes (constraint_projection: W - C^T (C C^T)^-1 C W, C having a few hundred rows):

    W <- P_C W,   P_C = I - C^T (C C^T)^-1 C                                       (L5)

A block of b columns finds eigenvalues of multiplicity up to b (the cage's modes come in pairs
from its near-cyclic symmetry); the random start has a component along every eigenvector with
probability one.
"""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

DEFAULT_BLOCK = 12        # columns per step: about the fewest operator columns for 30 modes (paper
#                           cage, to 1e-8: blocks of 10, 12, 15, 20 needed 240, 252, 270, 320; 30 needed 420)
DEFAULT_TOL = 1e-8        # ||OP y - theta y||_M / theta: eigenvalue error ~ tol^2 relative


class LanczosModes(NamedTuple):
    """omega (n_modes,) rad/s ascending; Phi (n, n_modes) M-orthonormal Ritz vectors; M_Phi = M Phi;
    residual (n_modes,) the relative residuals (L4); basis_size; operator_columns (columns of OP
    applied, including the start); steps."""
    omega: np.ndarray
    Phi: np.ndarray
    M_Phi: np.ndarray
    residual: np.ndarray
    basis_size: int
    operator_columns: int
    steps: int


def m_orthonormalise(W: np.ndarray, MW: np.ndarray, drop: float = 1e-8,
                     size2: float | None = None):
    """An M-orthonormal basis of the columns of W (MW = M W): W = Q B, Q^T M Q = I.

    From the Gram matrix G = W^T M W = V diag(g) V^T: Q = W V_k g_k^(-1/2) over the directions
    with g > drop^2 size2 (size2: the squared M-norm the block had before it was orthogonalised
    against the basis, default max(g): what is left below drop of it is rounding, and a block that
    has become rank deficient loses those columns: an invariant subspace was reached), then one
    Cholesky pass on the result, which restores orthonormality lost to rounding. Returns
    (Q, M Q, B) with B (k x b)."""
    G = W.T @ MW
    g, V = np.linalg.eigh(0.5 * (G + G.T))
    floor = drop ** 2
    if size2 is None and g.size:
        # the block measured against itself: an exactly dependent column leaves g at the rounding
        # of forming G (n products per entry) and of its eigen solve, up to about (n + k)·eps·max(g)
        # (Higham, Accuracy and Stability of Numerical Algorithms, 2002, §3.5; Golub & Van Loan
        # 2013, §8.1.2); drop^2 = 1e-16 lies below it, so which of those directions was kept
        # followed the BLAS's rounding. Below the floor the Gram matrix cannot tell a direction
        # from zero. (Against a given size2 -- the Lanczos blocks, measured before their
        # orthogonalisation -- a dependent remainder is at eps^2·size2, far below drop^2.)
        size2 = max(g.max(), 0.0)
        floor = max(floor, (W.shape[0] + W.shape[1]) * np.finfo(float).eps)
    keep = g > floor * size2 if g.size else np.zeros(0, bool)
    if not np.any(keep):
        return W[:, :0], MW[:, :0], np.zeros((0, W.shape[1]))
    scale = 1.0 / np.sqrt(g[keep])
    Q, MQ = (W @ V[:, keep]) * scale, (MW @ V[:, keep]) * scale
    B = (V[:, keep] * np.sqrt(g[keep])).T                   # W = Q B (on the kept directions)
    G2 = Q.T @ MQ
    R = np.linalg.cholesky(0.5 * (G2 + G2.T)).T             # Q = Q' R
    Q = sla.solve_triangular(R, Q.T, trans="T").T
    MQ = sla.solve_triangular(R, MQ.T, trans="T").T
    return Q, MQ, R @ B


def constraint_projection(C) -> Callable[[np.ndarray], np.ndarray]:
    """W -> P_C W = W - C^T (C C^T)^-1 C W (L5), the Euclidean projection onto ker C (C: sparse,
    full row rank; C C^T factorised once by Cholesky)."""
    C = sp.csr_matrix(C)
    factor = sla.cho_factor((C @ C.T).toarray())

    def project(W):
        return W - C.T @ sla.cho_solve(factor, C @ W)
    return project


def block_lanczos_modes(apply_inverse: Callable[[np.ndarray], np.ndarray],
                        mass_times: Callable[[np.ndarray], np.ndarray], n: int, n_modes: int,
                        block: int = DEFAULT_BLOCK, tol: float = DEFAULT_TOL,
                        max_basis: int | None = None, seed: int = 20261127,
                        project: Callable[[np.ndarray], np.ndarray] | None = None) -> LanczosModes:
    """The n_modes lowest eigenpairs of (L1) by (L2)-(L5).

    apply_inverse(F) -> U: the u part of the saddle solve [K C^T; C 0][U; L] = [F; 0] for a block
    F (n x k); mass_times(X) -> M X; project: W -> P_C W (constraint_projection(C); None: no
    constraint). seed: the random start (fixed: the same modes every run).
    Raises RuntimeError when max_basis columns (default min(n, 20 n_modes + 4 block)) do not
    converge the n_modes."""
    if not 1 <= n_modes <= n:
        raise ValueError(f"block_lanczos_modes: n_modes = {n_modes} is outside 1..{n}")
    b = int(max(2, block))
    max_basis = int(max_basis or min(n, 20 * n_modes + 4 * b))
    rng = np.random.default_rng(seed)
    project = project or (lambda W: W)
    W = project(apply_inverse(mass_times(rng.standard_normal((n, b)))))   # the start, on ker C
    columns = b
    Q1, MQ1, _ = m_orthonormalise(W, mass_times(W))
    # column-major: a column is contiguous, and the columns never used are never touched (resident)
    Q = np.empty((n, max_basis + b), order="F")
    MQ = np.empty((n, max_basis + b), order="F")
    m = Q1.shape[1]
    Q[:, :m], MQ[:, :m] = Q1, MQ1
    last = slice(0, m)
    T = np.zeros((0, 0))
    steps = 0
    while True:
        steps += 1
        W = apply_inverse(MQ[:, last])                       # OP Q_j, (L2)
        columns += W.shape[1]
        H = np.zeros((m, W.shape[1]))
        for _ in range(2):                                   # CGS2 against the whole basis, (L3)
            h = MQ[:, :m].T @ W                              # M-inner products: M Q is kept
            W -= Q[:, :m] @ h
            H += h
        W = project(W)                                       # back onto ker C, (L5)
        MW = mass_times(W)                                   # after: two reads of the basis fewer
        # ||OP Q_j||_M^2 per column = ||H||^2 + ||remainder||_M^2 (Q is M-orthonormal)
        size2 = float(np.max(np.sum(H ** 2, axis=0) + np.einsum("ij,ij->j", W, MW)))
        m0 = T.shape[0]                                      # T = Q^T M OP Q grows by the new columns
        Tn = np.zeros((m, m))
        Tn[:m0, :m0] = T
        Tn[:, m0:m] = H
        Tn[m0:m, :] = H.T
        T = 0.5 * (Tn + Tn.T)
        Qn, MQn, Bn = m_orthonormalise(W, MW, size2=size2)
        theta, S = np.linalg.eigh(T)
        theta, S = theta[::-1], S[:, ::-1]                    # largest theta = lowest omega first
        k = min(n_modes, m)
        res = np.linalg.norm(Bn @ S[m0:m, :k], axis=0) / np.abs(theta[:k])      # (L4)
        done = m >= n_modes and np.all(res < tol)
        if done or Qn.shape[1] == 0:                          # converged, or an invariant subspace
            if m < n_modes:
                raise RuntimeError(f"block Lanczos: the Krylov space closed at {m} < {n_modes} modes")
            break
        if m + Qn.shape[1] > max_basis:
            raise RuntimeError(f"block Lanczos: {n_modes} modes not converged to {tol:g} in "
                               f"{max_basis} basis vectors (largest residual {res.max():.2e})")
        Q[:, m:m + Qn.shape[1]], MQ[:, m:m + Qn.shape[1]] = Qn, MQn
        last = slice(m, m + Qn.shape[1])
        m += Qn.shape[1]
    Sk = S[:, :n_modes]
    Phi, M_Phi = Q[:, :m] @ Sk, MQ[:, :m] @ Sk
    omega = 1.0 / np.sqrt(theta[:n_modes])
    return LanczosModes(omega, Phi, M_Phi, res[:n_modes], m, columns, steps)
