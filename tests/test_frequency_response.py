"""Frequency response (flexbearing.verification.frequency_response): direct full FE vs modal superposition.

Exact statements on a generic free spring chain (all modes kept = the direct solve, undamped and
with D = beta K), then the small test cage (P2, coarse): the reduced cage's harmonic pocket
response with 26 modes, with and without the residual static correction, vs the full FE.
"""
import numpy as np
import pytest
import scipy.linalg as sla
from tolerances import assert_within, product_bound

from flexbearing.verification import frequency_response as fr


@pytest.mark.parametrize("beta", [0.0, 0.05])
def test_direct_equals_modal_superposition_all_modes(beta, spring_chain):
    """(K - w^2 M + i w beta K) u = f solved directly equals sum_k phi_k phi_k^T f /
    (omega_k^2 - w^2 + i w beta omega_k^2) with every mode (rounding: 1e-9 relative); the elastic
    response (rigid translations removed) at w = 0 is the inertia-relief static solution."""
    K, M = spring_chain(30, 7)
    n = K.shape[0]
    lam, Phi = sla.eigh(K.toarray(), M.toarray())
    lam[:3] = 0.0                                      # three free translations
    R = Phi[:, :3]
    f = np.random.default_rng(8).standard_normal(n)
    obs = np.eye(n)[[0, 1, 2, 13]]
    wk = np.sqrt(lam[3:])
    gaps = np.argsort(np.diff(wk))[-3:]                # mid-way in the three widest gaps (rad/s)
    w = np.r_[0.0, 0.5 * (wk[gaps] + wk[gaps + 1])]
    assert np.min(np.abs(wk[:, None] / w[None, 1:] - 1)) > 0.02
    full = fr.full_frf(K, M, f[:, None], w, obs, beta, rigid=R)
    # modal superposition written out (modal_frf takes a 6-DOF interface load; here f is general)
    h = np.zeros((len(w), n), dtype=complex)
    for i, wi in enumerate(w):
        h[i, 3:] = 1.0 / (lam[3:] - wi ** 2 + 1j * wi * beta * lam[3:])
    ref = np.einsum("on,wn,n->wo", obs @ Phi, h, Phi.T @ f)
    assert np.abs(full[:, :, 0] - ref).max() <= 1e-9 * np.abs(ref).max()


def test_modal_frf_interface_form():
    """modal_frf with a 6-DOF interface load equals the written-out superposition, and the
    residual static correction adds exactly Phi_k Phi_k^T F / omega_k^2 of the discarded modes."""
    rng = np.random.default_rng(9)
    m = 12
    omega = np.r_[np.zeros(6), np.sort(rng.random(m - 6)) * 10 + 1]
    P = rng.standard_normal((6, m))
    F = rng.standard_normal((6, 2))
    w = np.array([0.0, 0.5, 3.3])
    a = fr.modal_frf(P, P, omega, w, F, n_keep=9, residual=False)
    b = fr.modal_frf(P, P, omega, w, F, n_keep=9, residual=True)
    for i, wi in enumerate(w):
        ha = np.r_[np.zeros(6), 1 / (omega[6:9] ** 2 - wi ** 2), np.zeros(3)]
        hb = ha + np.r_[np.zeros(9), 1 / omega[9:] ** 2]
        # the same chain of products P diag(h) P^T F in another order: gamma_k |P| |h| |P^T| |F|
        # (tests/tolerances.py), entrywise; the terms are O(1), the bound ~1e-14 of them
        for got, h in ((a[i], ha), (b[i], hb)):
            ref = P @ (h[:, None] * (P.T @ F))
            assert_within(np.abs(got - ref), product_bound(P, h, P.T, F), "modal superposition",
                          effect=np.abs(ref).max())
    g = fr.frequency_grid(10.0, [5.0], n=10, exclude=0.1)
    assert 5.0 not in g and 0.0 in g and 10.0 in g


# ------------------------------------------------------------------ the small test cage

@pytest.fixture(scope="module")
def small_cage():
    from mpi4py import MPI
    from flexbearing.mesh.cage_geometry import CageGeometry
    from flexbearing.mesh.cage_mesh import cached_cage_mesh
    from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass
    from flexbearing.fem_cage.reduction import reduce_model
    from tests.test_craig_bampton import SMALL
    g = CageGeometry(**SMALL).validate()
    domain, _, ft, _ = load_cage_mesh(cached_cage_mesh(g, 3e-3, 2, 2e-3), MPI.COMM_SELF)
    V, K, M = assemble_stiffness_mass(domain, g.material, 2)
    return reduce_model(domain, ft, V, K, M, g, "rbe3", 20)


def test_small_cage_pocket_frf_below_first_mode(small_cage):
    """Small test cage (6 pockets of 8 mm, 3 mm P2 mesh, 21,405 DOFs; 36 constraint + 20
    fixed-interface modes + centrifugal vector = 57 modes; first elastic pair 3653 Hz). Unit
    circumferential, radial and axial force on pocket 1; elastic response of its interface node;
    undamped; w = 0 (inertia-relief static), 0.45 f_1, 0.9 f_1 (>= 10 % from the resonance).
    (b) 26 modes + residual static correction within 1 % of the full FE (measured <= 0.49 %; at
    w = 0 0.46 %, set by the inertia-relief body load M R a, which the CB basis holds only
    approximately: 2.2e-4 with 60 fixed-interface modes); (a) 26 modes alone are off by up to
    5.1 % (measured).
    Above the first modes the small cage's 26-mode set is not enough: measured (b) 0.9 % at 7.1 kHz,
    3-5 % near 8-9 kHz, i.e. the 1 % claim up to the 10th elastic mode does NOT hold on this toy
    cage (benchmarks/bench_frf.py measures the paper cage)."""
    red = small_cage
    f1 = red["frequency_hz"][6]
    w = 2 * np.pi * np.array([0.0, 0.45 * f1, 0.9 * f1])
    node = 1
    Fd = fr.pocket_directions(red["interface_positions"][node])
    loads = np.column_stack([fr.pocket_load(red["C"], node, Fd[:, j]) for j in range(3)])
    obs = red["C"][6 * node:6 * node + 6].toarray()
    full = fr.full_frf(red["K"], red["M"], loads, w, obs, 0.0, rigid=red["Phi_full"][:, :6])
    phi = red["phi_b"][6 * node:6 * node + 6]
    a = fr.relative_error(fr.modal_frf(phi, phi, red["omega"], w, Fd, 26, residual=False), full)
    b = fr.relative_error(fr.modal_frf(phi, phi, red["omega"], w, Fd, 26, residual=True), full)
    assert b.max() <= 0.01
    assert a.max() > 0.02 and a.max() > 5 * b.max()
    # total response (rigid modes in both, w > 0): within 1 % at 0.45 f_1 (measured 5e-4); at
    # 0.9 f_1 the circumferential total is 3.0 % off (measured; the rigid part is the same in
    # both models, so its error is the elastic one over a smaller total amplitude) — not asserted
    full_tot = full[1:] - ((obs @ red["Phi_full"][:, :6]) @ (red["Phi_full"][:, :6].T @ loads))[None] \
        / (w[1:] ** 2)[:, None, None]
    tot = fr.modal_frf(phi, phi, red["omega"], w[1:], Fd, 26, residual=True, elastic=False)
    assert fr.relative_error(tot, full_tot)[0].max() <= 0.01
