"""Shift-and-invert block Lanczos for the fixed-interface modes (flexbearing.fem_cage.block_lanczos),
the eigensolver choice by BLAS (flexbearing.common.blas) and the Kronecker mass product.

The analytic case: a chain of N + 2 unit masses joined by springs k, each node moving in x, y, z
(three identical chains), its two end nodes held by constraint rows C (as the pocket interface
holds the cage). Its fixed–fixed eigenvalues are known in closed form (e.g. Géradin & Rixen,
"Mechanical Vibrations", 3rd ed. (2015), §2.x, the discrete string; Strang's second difference
matrix):

    omega_j^2 = (4 k / m) sin^2( j pi / (2 (N + 1)) ),   j = 1..N,   each three times (x, y, z)

with modes u_i = sin(i j pi / (N + 1)) along any fixed direction. Tolerances: the solver stops
at a relative residual 1e-8 (L4), which bounds the eigenvalue error by ~1e-16 relative; what is
left is rounding, eps times the condition number of the constrained chain ((N + 1)^2 ~ 1e4): 1e-9
allows a hundredfold margin.
"""
import numpy as np
import pytest
import scipy.sparse as sp
from tolerances import assert_within, orthonormality_bound, product_bound

from flexbearing.fem_cage import interface as itf
from flexbearing.fem_cage.block_lanczos import (block_lanczos_modes, constraint_projection,
                                                m_orthonormalise)
from flexbearing.fem_cage.craig_bampton import (SaddleSolver, craig_bampton,
                                                fixed_interface_modes, kron_mass_times)

N, K_SPRING, MASS = 120, 3.0e6, 0.02


def _chain():
    """K, M (lumped), C for N + 2 nodes, 3 dof each (dof = 3 node + component); C holds nodes 0
    and N + 1 (6 rows)."""
    nn = N + 2
    n = 3 * nn
    rows, cols, vals = [], [], []
    for i in range(nn - 1):
        for c in range(3):
            a, b = 3 * i + c, 3 * (i + 1) + c
            rows += [a, b, a, b]
            cols += [a, b, b, a]
            vals += [K_SPRING, K_SPRING, -K_SPRING, -K_SPRING]
    K = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    M = sp.identity(n, format="csr") * MASS
    C = itf.selection_matrix(n, np.r_[0:3, 3 * (N + 1):3 * (N + 2)])
    return K, M, C


def _analytic(n_modes):
    j = np.arange(1, N + 1)
    w = np.sqrt(4 * K_SPRING / MASS) * np.sin(j * np.pi / (2 * (N + 1)))
    return np.repeat(w, 3)[:n_modes]


@pytest.mark.parametrize("n_modes, block", [(12, 12), (30, 4), (30, 3)])
def test_fixed_fixed_chain_against_closed_form(n_modes, block):
    """Eigenvalues of multiplicity 3 with blocks of 3, 4 and 12: omega to 1e-9, M-orthonormal,
    on ker C, Rayleigh quotient = omega^2, each mode a sine of the chain along some direction."""
    K, M, C = _chain()
    solver = SaddleSolver(K, C)
    modes = block_lanczos_modes(lambda F: solver.solve(F, None)[0], lambda X: M @ X, K.shape[0],
                                n_modes, block=block, project=constraint_projection(C))
    solver.destroy()
    assert np.allclose(modes.omega, _analytic(n_modes), rtol=1e-9)
    Phi = modes.Phi
    # M-orthonormality of a Rayleigh-Ritz on an M-orthonormalised basis (M = m I, kappa 1): round-off
    # bound of Cholesky-QR2 on the basis (tests/tolerances.py), far below the O(1) it proves
    ortho = orthonormality_bound(K.shape[0], modes.basis_size)
    assert_within(np.abs(Phi.T @ (M @ Phi) - np.eye(n_modes)).max(), ortho,
                  "M-orthonormality", effect=1.0)
    assert_within(np.abs(modes.M_Phi - M @ Phi).max(), ortho * np.abs(modes.M_Phi).max(),
                  "tracked M Phi", effect=np.abs(modes.M_Phi).max())
    assert np.abs(C @ Phi).max() < 1e-12 * np.abs(Phi).max()
    rq = np.einsum("ij,ij->j", Phi, K @ Phi)
    assert np.allclose(rq, modes.omega ** 2, rtol=1e-9)
    assert modes.residual.max() < 1e-8
    # mode j (counted without the triple) is sin(i j pi / (N + 1)) times a direction
    i = np.arange(N + 2)
    for m in range(0, n_modes, 3):
        j = m // 3 + 1
        shape = np.sin(i * j * np.pi / (N + 1))
        S = np.kron(shape[:, None], np.eye(3))              # (3 (N+2), 3): along x, y, z
        P = S @ np.linalg.lstsq(S, Phi[:, m:m + 3], rcond=None)[0]
        assert np.abs(P - Phi[:, m:m + 3]).max() < 1e-6 * np.abs(Phi[:, m:m + 3]).max()


def test_closed_krylov_space_returns_every_mode():
    """Asking for all N modes of one direction's chain (3N with x, y, z): the Krylov space closes
    on ker C (an invariant subspace) and every mode is exact."""
    K, M, C = _chain()
    solver = SaddleSolver(K, C)
    n_all = 3 * N
    modes = block_lanczos_modes(lambda F: solver.solve(F, None)[0], lambda X: M @ X, K.shape[0],
                                n_all, block=12, project=constraint_projection(C))
    solver.destroy()
    assert modes.basis_size == n_all
    assert np.allclose(modes.omega, _analytic(n_all), rtol=1e-9)


def test_m_orthonormalise_drops_dependent_columns():
    """W with a repeated and a combined column: 3 independent directions kept, Q^T M Q = I,
    W = Q B."""
    rng = np.random.default_rng(3)
    M = sp.diags(rng.random(50) + 0.5).tocsr()
    W = rng.standard_normal((50, 3))
    W = np.hstack([W, W[:, :1], W[:, 1:2] - 2 * W[:, 2:3]])
    Q, MQ, B = m_orthonormalise(W, M @ W)
    assert Q.shape[1] == 3
    # Cholesky-QR2 round-off (kappa(M) <= 3 for diag in [0.5, 1.5]); the reconstruction W = Q B also
    # carries the rounding of the two dependent columns as they were formed (gamma_2 |W|)
    bound = orthonormality_bound(*W.shape, cond_M=3.0)
    assert_within(np.abs(Q.T @ (M @ Q) - np.eye(3)).max(), bound, "M-orthonormality", effect=1.0)
    assert_within(np.abs(MQ - M @ Q).max(), bound * np.abs(MQ).max(), "tracked M Q",
                  effect=np.abs(MQ).max())
    assert_within(np.abs(Q @ B - W).max(), (bound + product_bound(Q, B).max()) * np.abs(W).max(),
                  "W = Q B", effect=np.abs(W).max())


def test_block_lanczos_and_slepc_give_the_same_craig_bampton_model():
    """The two eigensolvers on the same constrained chain with body-load augmentation: the same
    fixed-interface frequencies (1e-9) and the same reduced eigenvalues (the subspace, not the
    basis: 1e-9). 21 modes: whole triples (a cut through a triple leaves the subspace free)."""
    K, M, C = _chain()
    rng = np.random.default_rng(4)
    body = M @ rng.standard_normal((K.shape[0], 2))
    out = {m: craig_bampton(K, M, C, 21, body_loads=body, eigensolver=m)
           for m in ("block-lanczos", "slepc")}
    assert out["block-lanczos"]["info"]["eigensolver"] == "block Lanczos"
    assert out["slepc"]["info"]["eigensolver"] == "SLEPc Krylov-Schur"
    a, b = (out[m]["omega_fixed"] for m in ("block-lanczos", "slepc"))
    assert np.allclose(a, b, rtol=1e-9)
    import scipy.linalg as sla
    la, lb = (sla.eigh(out[m]["K_cb"], out[m]["M_cb"], eigvals_only=True)
              for m in ("block-lanczos", "slepc"))
    assert np.allclose(la, lb, rtol=1e-9, atol=1e-9 * lb.max())


def test_unknown_eigensolver_is_refused():
    K, M, C = _chain()
    solver = SaddleSolver(K, C)
    with pytest.raises(ValueError, match="reduce.eigensolver = 'arpack'"):
        fixed_interface_modes(solver, K, M, 5, method="arpack")
    solver.destroy()


def test_auto_follows_the_blas():
    """auto: block Lanczos on an optimised BLAS, SLEPc on the reference one."""
    from flexbearing.common.blas import blas_info
    K, M, C = _chain()
    solver = SaddleSolver(K, C)
    _, _, info = fixed_interface_modes(solver, K, M, 6)
    solver.destroy()
    want = "block Lanczos" if blas_info().optimised else "SLEPc Krylov-Schur"
    assert info["eigensolver"] == want


def test_kron_mass_times_equals_the_vector_mass_product():
    """M = Ms ⊗ I3 (dof = 3 node + component): the scalar product equals M X (same sums)."""
    rng = np.random.default_rng(5)
    A = sp.random(40, 40, density=0.2, random_state=6)
    Ms = (A + A.T + 40 * sp.identity(40)).tocsr()
    M = sp.kron(Ms, sp.identity(3)).tocsr()
    X = rng.standard_normal((120, 7))
    mt = kron_mass_times(Ms)
    # the same sums, possibly in another order: gamma_(row length) |M| |X| (tests/tolerances.py)
    assert_within(np.abs(mt(X) - M @ X), product_bound(M, X), "Ms (x) I3 product",
                  effect=np.abs(M @ X).max())
    x = X[:, 0].copy()
    assert_within(np.abs(mt(x) - M @ x), product_bound(M, x)[:, 0], "Ms (x) I3 product",
                  effect=np.abs(M @ x).max())
