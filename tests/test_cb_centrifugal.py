"""The Craig–Bampton basis augmented with the fixed-interface centrifugal response (fem_cage.
craig_bampton Eq. (2), flexbearing.fem_cage.reduction.reduce_model(centrifugal=True)).

Claim: constraint modes + the fixed-interface static response to a body load hold the exact
free–free static response to that load (the plain CB basis holds it only for interface loads).
Checked on generic matrices (algebra), then on a thin 6-pocket ring (outside 60 mm, bore 50 mm,
width 12 mm, 1.5 mm pockets) spinning at 1000 rad/s: full basis vs the free–free full FE solution,
the hoop stress vs the rotating ring (plane-stress annular disc; Timoshenko & Goodier, "Theory
of Elasticity", 3rd ed., §32), and the runtime's residual static correction for a combined
pocket + centrifugal load.
"""
import numpy as np
import pytest
import scipy.sparse as sp
from tolerances import (U, assert_within, dot_bound, mean_axis_bound, orthonormality_bound,
                        pencil_orthonormality_bound, product_bound)

from flexbearing.fem_cage import interface as itf
from flexbearing.fem_cage.craig_bampton import craig_bampton

RING = dict(outside_diameter=60e-3, bore_diameter=50e-3, width=12e-3, n_pockets=6,
            pocket_diameter=1.5e-3, ball_diameter=1.4e-3, land_width=6e-3)
# the small test cage of tests/test_craig_bampton.py (8 mm pockets, 3 mm mesh, 21,405 P2 DOFs):
# the exactness statements hold for any mesh, so the fast tests use the cheap one
SMALL = dict(RING, pocket_diameter=8e-3, ball_diameter=7.5e-3)
SPIN = 1000.0          # rad/s


def test_augmented_basis_holds_the_free_free_static_body_load_response(spring_chain):
    """Generic algebra: a self-equilibrated distributed load f on a free chain (6 interface DOFs,
    3 fixed-interface modes of 54). The exact response u (K u = f, u M-orthogonal to the rigid
    translations) lies in span[Psi Phi U] to rounding (1e-10 relative), not in span[Psi Phi]
    (> 1e-2: the 51 dropped fixed-interface modes carry it). The U column is M-orthonormal to Phi."""
    K, M = spring_chain(60, 4)
    n = K.shape[0]
    C = itf.selection_matrix(n, np.array([0, 1, 2, 30, 31, 32]))
    rng = np.random.default_rng(5)
    f = rng.standard_normal(n)
    f -= np.repeat(f.reshape(-1, 3).mean(axis=0)[None, :], n // 3, axis=0).ravel()  # zero net force
    u = np.linalg.lstsq(K.toarray(), f, rcond=None)[0]            # K is singular: minimum norm
    Md = M.toarray()

    def span_residual(B):
        c = np.linalg.lstsq(B, u, rcond=None)[0]
        return np.linalg.norm(B @ c - u) / np.linalg.norm(u)

    cb0 = craig_bampton(K, M, C, 3)
    cb1 = craig_bampton(K, M, C, 3, body_loads=f)
    # u + rigid motion: add the translations to both spans (they are in span(Psi) anyway)
    assert span_residual(np.hstack([cb1["Psi"], cb1["Phi"], cb1["U"]])) < 1e-10
    assert span_residual(np.hstack([cb0["Psi"], cb0["Phi"]])) > 1e-2
    U, Phi = cb1["U"], cb1["Phi"]
    # M-orthonormalisation of 3 + 1 columns of length n, kappa(M) <= 2 (tests/tolerances.py)
    ortho = orthonormality_bound(n, 4, cond_M=2.0)
    assert_within(abs(U[:, 0] @ Md @ U[:, 0] - 1.0), ortho, "U M-normal", effect=1.0)
    assert_within(np.abs(Phi.T @ Md @ U).max(), ortho, "U M-orthogonal to Phi", effect=1.0)
    assert cb1["info"]["augmentation_coupling_max"] < 1e-10       # Phi^T K U = Psi^T K U = 0
    # the augmented reduced model gives the exact static answer: min energy on span[Psi Phi U]
    B = np.hstack([cb1["Psi"], cb1["Phi"], cb1["U"]])
    R = np.zeros((n, 3))
    for c in range(3):
        R[c::3, c] = 1.0
    Rc = np.linalg.lstsq(B, R, rcond=None)[0]                     # rigid motions in CB coords
    A = np.block([[cb1["K_cb"], cb1["M_cb"] @ Rc], [(cb1["M_cb"] @ Rc).T, np.zeros((3, 3))]])
    q = np.linalg.solve(A, np.r_[B.T @ f, np.zeros(3)])[:B.shape[1]]
    u_ma = u - R @ np.linalg.solve(R.T @ Md @ R, R.T @ Md @ u)     # mean-axis (M-orthogonal)
    assert np.linalg.norm(B @ q - u_ma) <= 1e-9 * np.linalg.norm(u_ma)


# ------------------------------------------------------------------ the thin ring

def _ring(size, pocket_size, degree=2, geometry=RING):
    from mpi4py import MPI
    from flexbearing.mesh.cage_geometry import CageGeometry
    from flexbearing.mesh.cage_mesh import cached_cage_mesh
    from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass
    g = CageGeometry(**geometry).validate()
    domain, _, ft, _ = load_cage_mesh(cached_cage_mesh(g, size, 2, pocket_size), MPI.COMM_SELF)
    V, K, M = assemble_stiffness_mass(domain, g.material, degree)
    return g, domain, ft, V, K, M


@pytest.fixture(scope="module")
def coarse_ring():
    """The small test cage (8 mm pockets) at 3 mm, pockets 2 mm, P2: for the exactness statements."""
    return _ring(3e-3, 2e-3, geometry=SMALL)


@pytest.fixture(scope="module")
def coarse_reduced(coarse_ring):
    from flexbearing.fem_cage.reduction import reduce_model
    g, domain, ft, V, K, M = coarse_ring
    # the centrifugal vector alone (the schema-3 basis): the land-load and inertia-relief vectors
    # (schema 4, tests/test_guide_loads.py) are switched off to isolate its effect
    return {cf: reduce_model(domain, ft, V, K, M, g, "rbe3", 10, centrifugal=cf, guide_loads=False,
                             inertia_relief=False)
            for cf in (True, False)}


def test_full_basis_static_centrifugal_exact(coarse_reduced, coarse_ring):
    """Full basis q_k = Omega^2 Q_k / omega_k^2 vs the free–free full FE (inertia-relief saddle
    solve), stress at every geometry node, Frobenius-relative: <= 1e-6 with the centrifugal vector
    (measured 4.0e-9 here, 2.3e-9 on the 2.5 mm thin ring); without it > 3 % (measured 8.9 %
    here) — the
    defect this augmentation removes. The augmentation keeps the rest: one more mode, interface
    loads still exact (check_static <= 1e-6), mean-axis elastic modes, identity modal mass."""
    from flexbearing.fem_cage.reduction_check import check_centrifugal, check_static
    on, off = coarse_reduced[True], coarse_reduced[False]
    assert len(on["omega"]) == len(off["omega"]) + 1 == 6 * 6 + 10 + 1
    r_on, r_off = check_centrifugal(on, SPIN), check_centrifugal(off, SPIN)
    assert r_on["stress_rel_error_full"] <= 1e-6
    assert r_off["stress_rel_error_full"] > 0.03
    assert check_static(on, [1, 3], 0)["max_rel_error_full"] <= 1e-6
    # identity modal mass and mean-axis elastic modes to the round-off of the reduced pencil
    # (order n, kappa_2 of the Jacobi-scaled M_cb, both returned by reduce_model; measured here
    # n = 47, kappa = 32) and of the mesh sums (tests/tolerances.py)
    o = on["orthogonality"]
    e = pencil_orthonormality_bound(o["pencil_order"], o["mass_condition"])
    assert_within(o["modal_mass_identity_error"], e, "modal mass identity", effect=1.0)
    inv = on["invariants"]
    X = coarse_ring[3].tabulate_dof_coordinates()[:, :3]
    b, tM = mean_axis_bound(on["M"], itf.rigid_field(X), on["Phi_full"], e)
    assert_within(np.abs(inv["I3"][:, 6:]), b[:3], "I3 mean axis", effect=tM[:3].min())
    assert_within(np.abs(inv["I4"][:, 6:]), b[3:], "I4 mean axis", effect=tM[3:].min())
    assert np.all(np.diff(on["omega"]) >= 0)
    # the modal load from the stored invariants is Phi^T M x_perp Omega^2 (what the runtime uses):
    # the same sums x_perp^T M Phi in another order (product_bound), then a sum and a product
    from flexbearing.fem_cage.reduced_cage import centrifugal_modal_load
    Q = centrifugal_modal_load(on["moments"], SPIN)
    xp = np.zeros(len(on["f_cf"]))
    xp[1::3], xp[2::3] = X[:, 1], X[:, 2]
    assert_within(np.abs(Q - SPIN ** 2 * on["Phi_full"].T @ on["f_cf"]),
                  SPIN ** 2 * product_bound(xp, on["M"], on["Phi_full"]).ravel() + 4 * U * np.abs(Q),
                  "modal centrifugal load", effect=np.abs(Q).max())


def _free_free_static(red, f):
    """Full FE free–free static response with inertia relief: K u = f - M R a, R^T M u = 0."""
    from flexbearing.fem_cage.craig_bampton import SaddleSolver
    R = red["Phi_full"][:, :6]
    s = SaddleSolver(sp.csr_matrix(red["K"]), sp.csr_matrix((red["M"] @ R).T))
    u, _ = s.solve(f, None)
    s.destroy()
    return u


def test_residual_static_correction_combined_load(coarse_reduced):
    """Pockets 1 and 4 pulled apart by 100 N (self-equilibrated) + centrifugal load at 1000 rad/s.
    The runtime's recipe — the 20 kept elastic modes solved statically, the discarded ones by
    q_k = (Phi_b,k^T F + Omega^2 Q_k) / omega_k^2 (reduced_cage.static_correction with
    centrifugal_modal_load) — equals the full basis (algebraically the same statically: the modal
    stiffness is diagonal; asserted to 1e-12) and so the full FE (<= 1e-6, measured 2.6e-9); the 26
    kept modes alone are far off (> 3 %, measured 9.8 %)."""
    from flexbearing.fem_cage.reduced_cage import static_correction, centrifugal_modal_load
    red = coarse_reduced[True]
    xm = red["interface_positions"]
    e = (xm[1] - xm[4]) / np.linalg.norm(xm[1] - xm[4])
    F = np.zeros((6, 6))
    F[1, :3], F[4, :3] = 100.0 * e, -100.0 * e
    f = red["C"].T @ F.ravel() + SPIN ** 2 * red["f_cf"]
    S_full = red["stress_op"](_free_free_static(red, f))

    omega, modes = red["omega"], red["phi_b"].reshape(6, 6, -1)
    g = centrifugal_modal_load(red["moments"], SPIN)
    n_keep = 26
    gk = modes[:, :, 6:n_keep].reshape(36, -1).T @ F.ravel() + g[6:n_keep]
    q_kept = gk / omega[6:n_keep] ** 2                          # kept modes, static
    q_rest = static_correction(modes, omega, F, n_keep, g)       # discarded modes
    q_recipe = np.r_[np.zeros(6), q_kept, q_rest]
    q_full = np.zeros_like(omega)
    q_full[6:] = (red["phi_b"][:, 6:].T @ F.ravel() + g[6:]) / omega[6:] ** 2
    rel = lambda a, b: np.linalg.norm(a - b) / np.linalg.norm(b)
    # the same 36-term dot products Phi_b,k^T F + g_k (blocked differently) over omega_k^2:
    # round-off of the absolute terms (tests/tolerances.py), not a fraction of q
    terms = np.zeros_like(omega)
    terms[6:] = (np.abs(red["phi_b"][:, 6:]).T @ np.abs(F.ravel()) + np.abs(g[6:])) / omega[6:] ** 2
    assert_within(np.abs(q_recipe - q_full), dot_bound(36 + 2, terms), "static modal coordinates",
                  effect=np.abs(q_full).max())
    S_recipe = red["stress"] @ q_recipe
    assert rel(S_recipe, S_full) <= 1e-6
    assert rel(red["stress"] @ np.r_[np.zeros(6), q_kept, 0 * q_rest], S_full) > 0.03


# ------------------------------------------------------------------ vs the rotating ring

def hoop_stress(S, X):
    """sigma_theta at points X (N, 3) from Voigt stress (xx yy zz yz xz xy), theta from +y to +z:
    e_theta = (0, -sin, cos), sigma_tt = s_yy sin^2 + s_zz cos^2 - 2 s_yz sin cos."""
    th = np.arctan2(X[:, 2], X[:, 1])
    c, s = np.cos(th), np.sin(th)
    return S[:, 1] * s * s + S[:, 2] * c * c - 2 * S[:, 3] * s * c


def rotating_disc_hoop(r, a, b, rho, nu, spin):
    """Plane-stress rotating annular disc, free at r = a and r = b (Timoshenko & Goodier §32):
    sigma_theta = (3+nu)/8 rho Omega^2 [a^2 + b^2 + a^2 b^2 / r^2 - (1+3nu)/(3+nu) r^2]."""
    return (3 + nu) / 8 * rho * spin ** 2 * (a * a + b * b + a * a * b * b / r ** 2
                                            - (1 + 3 * nu) / (3 + nu) * r ** 2)


@pytest.mark.slow
def test_thin_ring_hoop_stress_vs_rotating_disc():
    """The lead's thin ring at 2.5 mm (pockets 1 mm), P2 (65,121 DOFs), 20 fixed-interface modes:
    (1) full basis vs full FE static centrifugal stress at all geometry nodes <= 1e-6
        (measured 2.3e-9; the plain CB basis was -33 %...+24 % off in hoop stress);
    (2) hoop stress at the nodes between pockets (azimuth within 10° of mid-way) vs the
        plane-stress rotating disc within 2 %, the four circumferential edges of the ring left out.
        Measured (full FE = full basis): -1.84 %...+0.85 %; on the edges -2.14 %. Why not tighter:
        the disc formula is plane stress, the ring is 12 mm wide for 5 mm radial thickness — the
        same pattern appears at P3 on a 4 mm mesh (-2.05 %...+0.68 % all nodes, edges included),
        i.e. it is the 3D ring vs the plane-stress model, not discretisation. ~90 s: slow."""
    from flexbearing.fem_cage.reduction import reduce_model
    from flexbearing.fem_cage.reduction_check import check_centrifugal
    g, domain, ft, V, K, M = _ring(2.5e-3, 1.0e-3)
    red = reduce_model(domain, ft, V, K, M, g, "rbe3", 20, centrifugal=True)
    assert check_centrifugal(red, SPIN)["stress_rel_error_full"] <= 1e-6
    omega = red["omega"]
    q = np.zeros_like(omega)
    q[6:] = SPIN ** 2 * (red["Phi_full"][:, 6:].T @ red["f_cf"]) / omega[6:] ** 2
    S = red["stress"] @ q
    X = red["stress_op"].coords
    r = np.hypot(X[:, 1], X[:, 2])
    th = np.arctan2(X[:, 2], X[:, 1])
    between = np.abs(th % (2 * np.pi / 6) - np.pi / 6) < np.radians(10)
    a, b = g.inner_radius, g.outer_radius
    edge = ((np.abs(r - a) < 1e-7) | (np.abs(r - b) < 1e-7)) & \
           (np.abs(np.abs(X[:, 0]) - g.width / 2) < 1e-7)
    ref = rotating_disc_hoop(r, a, b, g.material.density, g.material.poisson_ratio, SPIN)
    err = hoop_stress(S, X) / ref - 1
    sel = between & ~edge
    assert sel.sum() > 1000
    assert np.abs(err[sel]).max() <= 0.02
    assert np.abs(err[between & edge]).max() <= 0.025       # the edges: measured 2.14 %
