"""The run's modal basis of the flexible cage (flexbearing.coupling.flexible_cage)."""
import numpy as np
import pytest
from tolerances import assert_within, orthonormality_bound, product_bound

from flexbearing.coupling.flexible_cage import centrifugal_generalised_force, modal_transform


def synthetic_full_basis(M=40, seed=0):
    rng = np.random.default_rng(seed)
    omega = np.concatenate([np.zeros(6), np.sort(rng.uniform(1e3, 1e5, M - 6))])
    Sx = rng.normal(size=(3, 3, M))
    Sx[:, :, :6] = 0.0
    return omega, Sx


def test_centrifugal_correction_reproduces_the_full_basis_static_response():
    """Modal truncation augmentation: for the centrifugal load Q (per unit Omega²), the static
    response of the kept basis + correction vector equals that of the full basis in every
    full-basis coordinate (so stresses and interface displacements agree to round-off), while
    the plain truncation misses the discarded modes' share."""
    omega, Sx = synthetic_full_basis()
    Q = centrifugal_generalised_force(Sx)
    q_full = np.zeros_like(Q)
    q_full[6:] = Q[6:] / omega[6:] ** 2
    for corr, expect_exact in ((True, True), (False, False)):
        T = modal_transform(omega, Sx, 26, corr)
        k = np.einsum("kn,k,kn->n", T, omega ** 2, T)
        q_run = (T.T @ Q) / k
        err = np.linalg.norm(T @ q_run - q_full) / np.linalg.norm(q_full)
        assert (err < 1e-13) if expect_exact else (err > 1e-4)  # here 7.6e-4


def test_run_basis_is_orthonormal_and_its_stiffness_diagonal():
    omega, Sx = synthetic_full_basis(seed=3)
    T = modal_transform(omega, Sx, 26, True)
    assert T.shape == (40, 21)                      # 20 elastic + 1 correction
    assert_within(np.abs(T.T @ T - np.eye(21)).max(), orthonormality_bound(*T.shape), "orthonormal",
                  effect=1.0)                       # round-off of an orthonormalisation, tests/tolerances.py
    K = T.T @ np.diag(omega ** 2) @ T
    # the kept columns are identity columns, so K_ab = omega_a^2 (T^T T)_ab: off the diagonal
    # within omega_max^2 times the loss of orthonormality (above), plus the rounding of the
    # product itself (product_bound, entrywise)
    off = np.abs(K - np.diag(np.diag(K)))
    bound = product_bound(T.T, omega ** 2, T) + orthonormality_bound(*T.shape) * (omega ** 2).max()
    assert_within(off, bound, "modal stiffness diagonal", effect=np.diag(K).max())
    # the correction's Rayleigh frequency lies above the kept modes (it lives in the discarded span)
    assert np.sqrt(K[-1, -1]) >= omega[25]


@pytest.mark.parametrize("n_keep", [6, 12, 26])
def test_rigid_modes_are_never_in_the_run_basis(n_keep):
    omega, Sx = synthetic_full_basis()
    T = modal_transform(omega, Sx, n_keep, False)
    assert T.shape[1] == n_keep - 6
    assert np.all(T[:6] == 0.0)
