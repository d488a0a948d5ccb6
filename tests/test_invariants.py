"""Mass properties and FFRF inertia invariants (flexbearing.fem_cage.invariants).

1. The nine invariants from the consistent-mass moments equal their defining sums with cross
   products, evaluated independently on a lumped point-mass body (exact to rounding).
2. On a curved P2 mesh of a plain ring: M-weighted sums equal the directly integrated mass,
   first and second moments (same quadrature: 1e-10), and the analytic ring values to within the
   mesh's own volume error (the only discretisation error left)."""
import numpy as np
import pytest

from flexbearing.fem_cage.interface import skew, rigid_field
from flexbearing.fem_cage.invariants import (mass_moments, ffrf_invariants, rigid_properties, ring_analytic,
                                 scalar_mass_matrix)
import scipy.sparse as sp
from tolerances import assert_within, dot_bound, sum_roundoff


def test_invariants_match_point_mass_definitions():
    rng = np.random.default_rng(0)
    n, m = 40, 5
    X = rng.standard_normal((n, 3))
    mp = rng.random(n) + 0.5
    Phi = rng.standard_normal((3 * n, m))
    inv = ffrf_invariants(mass_moments(sp.diags(mp), X, Phi))
    ph = Phi.reshape(n, 3, m)               # blocked numbering: dof 3p + c

    def sums(X, ph, sk):
        """I4, I5, I7, I8, I9 as point sums; with |X|, |ph| and |skew| they are the sums of the
        absolute terms that bound the round-off (cross(a, b) = skew(a) b)."""
        I4 = sum(mp[p] * sk(X[p]) @ ph[p] for p in range(n))
        I5 = np.zeros((3, m, m))
        I8 = np.zeros((3, 3, m))
        I9 = np.zeros((3, 3, m, m))
        for p in range(n):
            for j in range(m):
                I8[:, :, j] += mp[p] * sk(X[p]) @ sk(ph[p, :, j])
                for k in range(m):
                    I5[:, j, k] += mp[p] * sk(ph[p, :, j]) @ ph[p, :, k]
                    I9[:, :, j, k] += mp[p] * sk(ph[p, :, j]).T @ sk(ph[p, :, k])
        I7 = sum(mp[p] * sk(X[p]).T @ sk(X[p]) for p in range(n))
        return {"I4": I4, "I5": I5, "I7": I7, "I8": I8, "I9": I9}
    ref, terms = sums(X, ph, skew), sums(np.abs(X), np.abs(ph), lambda v: np.abs(skew(v)))
    # sums over the n points in another order and blocking (the moments come from sparse products
    # and einsum): within 2 gamma_(3n) of the absolute terms (tests/tolerances.py)
    k = 3 * n + 6
    assert_within(abs(inv["I1"] - mp.sum()), sum_roundoff(mp), "I1", effect=mp.sum())
    assert_within(np.abs(inv["I2"] - mp @ X), dot_bound(k, mp @ np.abs(X)), "I2", effect=1.0)
    assert_within(np.abs(inv["I3"] - np.einsum("p,pck->ck", mp, ph)),
                  dot_bound(k, np.einsum("p,pck->ck", mp, np.abs(ph))), "I3", effect=1.0)
    for name in ref:
        assert_within(np.abs(inv[name] - ref[name]), dot_bound(k, terms[name]), name, effect=1.0)
    aPhi = np.abs(Phi)
    assert_within(np.abs(inv["I6"] - Phi.T @ (np.repeat(mp, 3)[:, None] * Phi)),
                  dot_bound(k, aPhi.T @ (np.repeat(mp, 3)[:, None] * aPhi)), "I6", effect=1.0)


def test_rigid_properties_steiner():
    """Inertia about the CoM of point masses vs the direct sum about the CoM."""
    rng = np.random.default_rng(1)
    X = rng.standard_normal((30, 3)) + [0.1, -0.2, 0.3]
    mp = rng.random(30)
    r = rigid_properties(mass_moments(sp.diags(mp), X))
    c = mp @ X / mp.sum()
    Jc = sum(mp[p] * skew(X[p] - c).T @ skew(X[p] - c) for p in range(30))
    # the centre: two sums of 30 terms and a division (tests/tolerances.py); the inertia comes
    # through the origin (Steiner), so its round-off is that of the absolute terms about the
    # origin, not a fraction of Jc (4: two sums and the shift of the same size)
    assert_within(np.abs(r["center_of_mass"] - c), dot_bound(2 * 30 + 2, mp @ np.abs(X) / mp.sum()),
                  "centre of mass", effect=np.abs(c).max())
    terms = np.array([mp[p] * np.abs(skew(X[p])).T @ np.abs(skew(X[p])) for p in range(30)])
    assert_within(np.abs(r["inertia_com"] - Jc), 4 * sum_roundoff(terms, axis=0), "inertia at the CoM",
                  effect=np.abs(Jc).max())


@pytest.fixture(scope="module")
def ring():
    from mpi4py import MPI
    from flexbearing.mesh.cage_geometry import NOMINAL_CAGE   # plain rectangular section (no relief, chamfer)
    from flexbearing.mesh.cage_mesh import cached_ring_mesh
    from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass
    from flexbearing.fem_cage.craig_bampton import petsc_to_scipy
    path = cached_ring_mesh(NOMINAL_CAGE, 6e-3, 2)
    domain, _, _, _ = load_cage_mesh(path, MPI.COMM_SELF)
    V, K, M = assemble_stiffness_mass(domain, NOMINAL_CAGE.material, 2)
    X = V.tabulate_dof_coordinates()[:, :3]
    return domain, X, petsc_to_scipy(M), NOMINAL_CAGE


def test_ring_moments_vs_direct_integration(ring):
    """Quadrature degree 4 = the mass matrix's (flexbearing.fem_cage.elasticity): the same integrals,
    so agreement to the rounding of the two sums: 1^T M x over the nodes (n + the longest row of M
    terms) against the cell-by-cell assembly (cells + the <= 64 points of a degree-4 rule: 14 in
    Basix) — each within gamma_k of its absolute terms, k the sum of those counts (Higham §4.2;
    dot_bound, two evaluations). The absolute terms: |1|^T |M| |x| for the first, and the
    integral of rho |x|, <= mass max|x|, for the second: the larger of the two is the scale."""
    from flexbearing.fem_cage.invariants import direct_mass_properties
    domain, X, M, g = ring
    Ms = scalar_mass_matrix(M)
    mom = mass_moments(Ms, X)
    d = direct_mass_properties(domain, g.material.density, 4)
    A = abs(sp.csr_matrix(Ms))
    k = Ms.shape[0] + int(np.diff(A.indptr).max()) + domain.topology.index_map(3).size_local + 64
    one, aX = np.ones(Ms.shape[0]), np.abs(X)
    m_abs = one @ (A @ one)
    assert_within(abs(mom["mass"] - d["mass"]), dot_bound(k, max(m_abs, d["mass"])), "mass",
                  effect=d["mass"])
    first_abs = np.maximum(one @ (A @ aX), d["mass"] * aX.max(axis=0))
    assert_within(np.abs(mom["first"] - d["first"]), dot_bound(k, first_abs), "first moment",
                  effect=d["mass"] * g.outer_radius)
    second_abs = np.maximum(aX.T @ (A @ aX), d["mass"] * np.outer(aX.max(axis=0), aX.max(axis=0)))
    assert_within(np.abs(mom["second"] - d["second"]), dot_bound(k, second_abs), "second moment",
                  effect=np.abs(d["second"]).max())


def test_ring_vs_analytic(ring):
    """m, CoM and J_com vs the hollow cylinder; tolerance: 3x the mesh's relative volume error
    (the faceting of the curved surfaces is the only error; J weights the outer surface by r^2,
    ~1.1x the mean, hence a small factor) plus 1e-12."""
    from flexbearing.fem_cage.invariants import direct_mass_properties
    domain, X, M, g = ring
    a = ring_analytic(g.outer_radius, g.inner_radius, g.width, g.material.density)
    r = rigid_properties(mass_moments(scalar_mass_matrix(M), X))
    vol = direct_mass_properties(domain, 1.0, 4)["mass"]
    ev = abs(vol / a["volume"] - 1.0)
    tol = 3.0 * ev + 1e-12
    assert ev < 1e-3
    assert abs(r["mass"] / a["mass"] - 1) <= tol
    assert np.linalg.norm(r["center_of_mass"]) <= tol * g.outer_radius
    assert np.abs(r["inertia_com"] - a["inertia_com"]).max() <= tol * a["inertia_com"].max()


def test_rigid_field_is_rigid():
    """u = t + omega x x for the six unit motions (used by RBE checks and rigid modes)."""
    X = np.random.default_rng(2).standard_normal((7, 3))
    R = rigid_field(X)
    tw = np.random.default_rng(3).standard_normal(6)
    u = (R @ tw).reshape(7, 3)
    # R tw (6 terms per row) against t + omega x x: round-off of the absolute terms
    scale = np.abs(tw[:3]) + np.abs(X) @ np.abs(skew(tw[3:])).T
    assert_within(np.abs(u - (tw[:3] + np.cross(tw[3:], X))), dot_bound(8, scale), "rigid field",
                  effect=np.abs(u).max())
