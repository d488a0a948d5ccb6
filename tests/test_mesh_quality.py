"""Curved-element validity and quality (flexbearing.mesh.quality) and the repair every cage mesh goes through."""
import numpy as np
import pytest
from tolerances import assert_within, gamma

from flexbearing.mesh import quality as Q
from flexbearing.common.validation import InputError

REF = Q.reference_nodes(10)            # the reference quadratic tetrahedron, straight-sided


def _one_tet(mid_shift=None, edge=0):
    """The reference tetrahedron with the mid node of EDGES[edge] moved by mid_shift."""
    pts = REF.copy()
    if mid_shift is not None:
        pts[4 + edge] += mid_shift
    return pts, np.arange(10)[None, :]


def test_shape_functions_partition_of_unity_and_interpolate_nodes():
    """sum_i grad N_i = 0 (partition of unity) and sum_i x_i grad N_i^T = I for the reference
    element (the isoparametric map of a straight tet is affine), at random points."""
    xi = np.random.default_rng(0).dirichlet(np.ones(4), 50)[:, 1:]
    for n in (4, 10):
        G = Q.shape_gradients(xi, n)
        assert np.abs(G.sum(axis=1)).max() < 1e-13
        J = np.einsum("ni,pna->pia", Q.reference_nodes(n), G)
        assert np.abs(J - np.eye(3)).max() < 1e-13


def test_det_of_affine_tetrahedron_is_six_volumes():
    """det J of a straight tet (any node order that keeps the orientation) = 6 V, constant."""
    rng = np.random.default_rng(1)
    A = rng.standard_normal((3, 3)) + 3 * np.eye(3)
    pts = REF @ A.T + rng.standard_normal(3)
    cells = np.arange(10)[None, :]
    xi = rng.dirichlet(np.ones(4), 20)[:, 1:]
    d = Q.jacobian_determinants(pts, cells, xi)
    assert np.allclose(d, np.linalg.det(A), rtol=1e-13)


@pytest.mark.parametrize("t", [0.05, 0.2, 0.25, 0.4, 0.8])
def test_one_curved_edge_analytic_jacobian(t):
    """Mid node of edge (0, 1) moved by d = (0, t, 0): x = xi + 4 L0 L1 d, so
    J = I + 4 d (grad(L0 L1))^T and det J = 1 + 4 d . grad(L0 L1) = 1 - 4 t L1 (the matrix
    determinant lemma; grad L0 = -(1, 1, 1), grad L1 = e1). Hence min det J = 1 - 4 t (at vertex
    1, L1 = 1), det J(centroid) = 1 - t, ratio (1 - 4t)/|1 - t|: inverted for t > 1/4. The cubic's
    Bernstein coefficients are exact here, and the lower bound equals the minimum (attained at a
    vertex, where the Bernstein polynomial equals its coefficient)."""
    pts, cells = _one_tet(np.array([0.0, t, 0.0]), edge=0)
    q = Q.mesh_quality(pts, cells, fe_degree=3)
    assert q.min_det_sampled[0] == pytest.approx(1 - 4 * t, abs=1e-13)
    assert q.det_centroid[0] == pytest.approx(1 - t, abs=1e-13)
    assert q.jacobian_ratio[0] == pytest.approx((1 - 4 * t) / abs(1 - t), abs=1e-12)
    assert q.min_det_bernstein[0] == pytest.approx(1 - 4 * t, abs=1e-12)
    assert q.n_inverted == (1 if t >= 0.25 else 0)


def _det_rounding(pts, xi):
    """Round-off of det J at the points xi: J's entries are 10-term sums X^T grad N, within
    gamma_10 (|X|^T |grad N|); det (LU, 3 x 3, growth <= 2: backward |dJ| <= 2 gamma_3 |J|) moves
    by at most 3 such relative entry errors times the product of the rows' 1-norms of |X|^T |grad
    N| (each term of det is a product of one entry per row; Higham §3.1, Thm 9.3, §14.6)."""
    G = Q.shape_gradients(xi, 10)                                 # (P, 10, 3)
    Jabs = np.einsum("ni,pna->pia", np.abs(pts), np.abs(G))       # (P, 3, 3) rows i = x, y, z
    return 3 * (gamma(10) + 2 * gamma(3)) * np.prod(Jabs.sum(axis=2), axis=1)


def _bernstein_rounding(pts, lattice, to_b):
    """Round-off of the Bernstein coefficients T d(lattice): the lattice dets' own (_det_rounding)
    through |T|, the 20-term products (gamma_20 |T| |d|), and T = V^-1 computed to kappa_inf(V)
    gamma_60 relative (a 20 x 20 inverse by LU, 3 n roundings: Higham §14.3)."""
    V = np.linalg.inv(to_b)
    dl = np.abs(Q.jacobian_determinants(pts, np.arange(10)[None, :], lattice))[0]
    T = np.abs(to_b)
    kappa = np.linalg.cond(V, np.inf)
    return float((T @ _det_rounding(pts, lattice)).max()
                 + ((gamma(20) + kappa * gamma(60)) * (T @ dl)).max())


def test_bernstein_bound_brackets_det_on_random_curved_elements():
    """For randomly curved elements the Bernstein coefficients bound det J from below and above
    at 500 random points (the property the certification rests on), and reproduce det J exactly
    at the lattice (interpolation of a cubic)."""
    rng = np.random.default_rng(3)
    lattice, to_b = Q._cubic_lattice()
    xi = rng.dirichlet(np.ones(4), 500)[:, 1:]
    for _ in range(20):
        pts = REF + 0.15 * rng.standard_normal(REF.shape) * (np.arange(10) >= 4)[:, None]
        cells = np.arange(10)[None, :]
        c = Q.jacobian_determinants(pts, cells, lattice) @ to_b.T
        d = Q.jacobian_determinants(pts, cells, xi)
        slack = _det_rounding(pts, xi).max() + _bernstein_rounding(pts, lattice, to_b)
        # min c <= d <= max c, to the rounding of both sides
        assert_within(np.array([c.min() - d.min(), d.max() - c.max()]), slack, "Bernstein bracket",
                      effect=np.abs(c).max())


def test_scaled_jacobian_regular_and_flat():
    """Regular tetrahedron: 1; the reference right-corner tet: 1/sqrt(2)·... = sqrt(2)/2 at the
    corners opposite the right angle; a flattened (sliver) tet: -> 0."""
    P = np.array([[0, 0, 0], [1, 0, 0], [0.5, np.sqrt(3) / 2, 0], [0.5, np.sqrt(3) / 6, np.sqrt(2 / 3)]])
    assert Q.scaled_jacobian(P, np.array([[0, 1, 2, 3]]))[0] == pytest.approx(1.0, abs=1e-12)
    assert Q.scaled_jacobian(REF[:4], np.array([[0, 1, 2, 3]]))[0] == pytest.approx(np.sqrt(0.5), abs=1e-12)
    S = P.copy()
    S[3, 2] = 1e-4
    assert 0 < Q.scaled_jacobian(S, np.array([[0, 1, 2, 3]]))[0] < 1e-3


def test_repair_flattens_an_inverted_element_and_leaves_good_ones():
    """Two elements: one inverted by a mid node moved 0.6 (ratio (1-2.4)/0.4 < 0), one fine.
    After the repair both are valid and above the bound; only the bad element's curving shrank,
    the good element's nodes did not move."""
    bad, _ = _one_tet(np.array([0.0, 0.6, 0.0]))
    good = REF + np.array([5.0, 0, 0])
    pts = np.vstack([bad, good])
    cells = np.vstack([np.arange(10), 10 + np.arange(10)])
    new, log = Q.repair_curved_elements(pts, cells, bound=0.3)
    q = Q.mesh_quality(new, cells)
    assert q.n_inverted == 0 and q.jacobian_ratio.min() >= 0.3
    assert log.n_cells_flattened == 1 and log.quality_before["n_inverted"] == 1
    assert np.array_equal(new[10:], pts[10:])
    # the node moved towards the straight midpoint, by at most its curving
    assert 0 < log.max_node_shift <= 0.6 + 1e-12
    Q.require_valid(q, 0.3)


def test_require_valid_names_cells_and_position():
    pts, cells = _one_tet(np.array([0.0, 0.6, 0.0]))
    q = Q.mesh_quality(pts * 1e-3, cells)
    with pytest.raises(InputError, match=r"1 inverted element.*cell 0 \(ratio -3.5, at x = 0.25 mm"):
        Q.require_valid(q, 0.3, "test mesh")


def test_det_agrees_with_gmsh_on_a_real_curved_mesh(tmp_path):
    """Independent check: gmsh's own Jacobian determinants (gmsh.model.mesh.getJacobians) of every
    curved tetrahedron of a cage mesh, at the four vertices and the centroid, against ours from
    the file read by meshio (node order converted gmsh -> VTK): equal to 1e-12 relative."""
    import gmsh
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    path = build_cage_mesh(PAPER_CAGE.with_(n_pockets=10), 8e-3, 2,
                           tmp_path / "c.msh", 8e-3)
    pts, cells = Q.read_tetrahedra(path)
    loc = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.25, 0.25, 0.25]], dtype=float)
    ours = Q.jacobian_determinants(pts, cells, loc)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(path))
        et = gmsh.model.mesh.getElementType("Tetrahedron", 2)
        _, det, _ = gmsh.model.mesh.getJacobians(et, loc.ravel().tolist())
    finally:
        gmsh.finalize()
    det = np.asarray(det).reshape(len(cells), 5)
    assert np.abs(ours - det).max() <= 1e-12 * np.abs(det).max()


def _study_and_calibration_levels():
    """(size, pocket size, order) of every mesh the mesh study and the calibration build."""
    from flexbearing.fem_cage.calibrate import CALIBRATION_MESH
    from flexbearing.fem_cage.mesh_study import DEFAULT_STUDY
    from flexbearing.mesh.cage_mesh import DEFAULT_MESH_SIZE, DEFAULT_POCKET_SIZE, DEFAULT_ORDER
    levels = {(s * 1e-3, p * 1e-3, o) for s, p, o, _ in DEFAULT_STUDY}
    levels.add(tuple(CALIBRATION_MESH[:3]))
    levels.add((DEFAULT_MESH_SIZE, DEFAULT_POCKET_SIZE, DEFAULT_ORDER))
    return sorted(levels, reverse=True)


# The mesh study's fine levels take minutes to mesh: those run in the slow suite.
_FINE = 3e-3


@pytest.mark.parametrize("fine", [False, pytest.param(True, marks=pytest.mark.slow)])
@pytest.mark.parametrize("preset", ["paper", "calibrated", "table8"])
def test_every_preset_at_every_study_size_has_no_invalid_element(preset, fine, tmp_path):
    """Each preset meshed at each size the mesh study, the calibration and the default use: no
    inverted element and none below the quality bound, read back from the written file (the
    before-repair counts are in the sidecar; e.g. the paper cage at 5 mm had 2 inverted cells,
    the calibrated one 48)."""
    from flexbearing.mesh.cage_geometry import PAPER_CAGE, CALIBRATED_CAGE, TABLE8_EQUIVALENT_CAGE
    from flexbearing.mesh.cage_mesh import build_cage_mesh, mesh_quality_of
    g = {"paper": PAPER_CAGE, "calibrated": CALIBRATED_CAGE, "table8": TABLE8_EQUIVALENT_CAGE}[preset]
    for size, pocket, order in _study_and_calibration_levels():
        if (pocket < _FINE) != fine:
            continue
        path = build_cage_mesh(g, size, order, tmp_path / f"{preset}_{size}_{pocket}_{order}.msh", pocket)
        q = Q.mesh_file_quality(path)
        assert q.n_inverted == 0 and q.n_uncertified == 0, (preset, size, pocket, order)
        assert q.jacobian_ratio.min() >= Q.MIN_JACOBIAN_RATIO, (preset, size, pocket, order)
        side = mesh_quality_of(path)
        assert side["quality"]["n_inverted"] == 0


def test_calibration_trial_geometries_mesh_validly(tmp_path):
    """Trial geometries of the calibration (corners of its parameter box, flexbearing.fem_cage.calibrate) at the
    calibration mesh: valid after the repair."""
    from flexbearing.fem_cage import calibrate as cal
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    size, pocket, order, _ = cal.CALIBRATION_MESH
    names = list(cal.DEFAULT_PARAMS)
    box = cal.BOXES["stated"]
    lo = np.array([box[n][0] for n in names])
    hi = np.array([box[n][1] for n in names])
    rng = np.random.default_rng(0)
    trials = [lo, hi] + [lo + (hi - lo) * rng.random(len(names)) for _ in range(2)]
    for i, p in enumerate(trials):
        try:
            g = cal.geometry_of(names, p)
        except InputError:            # a corner of the box outside the geometry's own limits
            continue
        path = build_cage_mesh(g, size, order, tmp_path / f"trial{i}.msh", pocket)
        q = Q.mesh_file_quality(path)
        assert q.n_inverted == 0 and q.jacobian_ratio.min() >= Q.MIN_JACOBIAN_RATIO


def test_reading_an_invalid_mesh_is_refused_naming_the_cells(tmp_path):
    """The paper cage at 5 mm as gmsh curves it (repair off) holds the two inverted cells the issue
    found (4467 and 4468, x = +-2.08 mm, r = 82.73 mm); the FE layer refuses to read it and names
    them; the same mesh built normally is repaired and read."""
    from mpi4py import MPI
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    from flexbearing.fem_cage.elasticity import load_cage_mesh
    bad = build_cage_mesh(PAPER_CAGE, 5e-3, 2, tmp_path / "bad.msh", 5e-3, repair=False)
    with pytest.raises(InputError, match=r"2 inverted element.*cell 446[78] .*r = 82.73 mm"):
        load_cage_mesh(bad, MPI.COMM_SELF)
    good = build_cage_mesh(PAPER_CAGE, 5e-3, 2, tmp_path / "good.msh", 5e-3)
    domain, *_ = load_cage_mesh(good, MPI.COMM_SELF)
    assert domain.topology.index_map(3).size_local == 4733


def test_cache_keys_carry_the_mesh_version():
    """A mesh or reduced cage built before the quality check (mesh version 1) is never reused."""
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh import cage_mesh as cm
    from flexbearing.fem_cage import reduced_cage as rcf
    assert cm.MESH_VERSION >= 2
    assert cm.mesh_key(PAPER_CAGE, 4e-3, 2, 4e-3)["version"] == cm.MESH_VERSION
    assert rcf.cache_key(PAPER_CAGE, 4e-3, 2, 4e-3, "rbe3", 30)["mesh_version"] == cm.MESH_VERSION
