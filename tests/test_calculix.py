"""CalculiX (ccx) as an independent FE code: deck writer and .frd reader against analytic answers
(flexbearing.verification.calculix), and the project's FE against CalculiX on the same meshes
(flexbearing.verification.calculix_check; the paper cage end to end is the slow test)."""
import numpy as np
import pytest

from flexbearing.common.materials import Material

needs_ccx = pytest.mark.skipif(
    not __import__("shutil").which("ccx"),
    reason="CalculiX 'ccx' is not on PATH (Debian package calculix-ccx; `make setup` installs it)")

STEEL = Material(density=7870.0, youngs_modulus=209e9, poisson_ratio=0.295)
BAR = (0.1, 0.02, 0.01)          # L (x), B (y), H (z), m
END_TAG, ROOT_TAG = 2, 3


def _gmsh_mesh(path, kind: str, size: float):
    """A quadratic (order 2) tetrahedral test mesh written by gmsh: 'bar' = the box BAR with the
    end faces x = L (tag 2) and x = 0 (tag 3) as physical surfaces (straight-sided elements);
    'ring' = a short thick ring about x (R 50/40 mm, 20 mm wide): curved elements."""
    import gmsh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(kind)
        occ = gmsh.model.occ
        if kind == "bar":
            vol = occ.addBox(0, 0, 0, *BAR)
        else:
            a = occ.addCylinder(-0.01, 0, 0, 0.02, 0, 0, 0.05)
            b = occ.addCylinder(-0.01, 0, 0, 0.02, 0, 0, 0.04)
            vol = occ.cut([(3, a)], [(3, b)])[0][0][1]
        occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [vol], 1)
        if kind == "bar":
            e = 1e-6
            for tag, x in ((END_TAG, BAR[0]), (ROOT_TAG, 0.0)):
                faces = gmsh.model.getEntitiesInBoundingBox(x - e, -e, -e, x + e, BAR[1] + e, BAR[2] + e, 2)
                gmsh.model.addPhysicalGroup(2, [f[1] for f in faces], tag)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


@pytest.fixture(scope="module")
def bar_msh(tmp_path_factory):
    return _gmsh_mesh(tmp_path_factory.mktemp("bar") / "bar.msh", "bar", 6e-3)


@pytest.fixture(scope="module")
def ring_msh(tmp_path_factory):
    return _gmsh_mesh(tmp_path_factory.mktemp("ring") / "ring.msh", "ring", 8e-3)


def _bar_support(mesh):
    """x = 0 face: u_x = 0 at every node; u_y = u_z = 0 at the origin; u_z = 0 at (0, B, 0):
    removes the rigid motions and leaves the Poisson contraction free."""
    X = mesh.nodes
    root = np.flatnonzero(np.abs(X[:, 0]) < 1e-12)
    o = int(np.argmin(np.linalg.norm(X, axis=1)))
    c = int(np.argmin(np.linalg.norm(X - [0, BAR[1], 0], axis=1)))
    return [(int(i), 1) for i in root] + [(o, 2), (o, 3), (c, 3)]


def _bar_exact(X, P):
    """Uniform tension sigma_xx = P/A of the bar held as in _bar_support (Saint-Venant, exact for
    an end load that is uniform: u_x = sigma x/E, u_y = -nu sigma y/E, u_z = -nu sigma z/E)."""
    E, nu = STEEL.youngs_modulus, STEEL.poisson_ratio
    s = P / (BAR[1] * BAR[2])
    return s, np.column_stack([s * X[:, 0] / E, -nu * s * X[:, 1] / E, -nu * s * X[:, 2] / E])


def _check_tension(run, mesh, P):
    from flexbearing.verification import calculix as cx
    s, u_exact = _bar_exact(mesh.nodes, P)
    u = cx.nodal_field(run.block("DISP"), len(mesh.nodes))
    S = cx.nodal_field(run.block("STRESS"), len(mesh.nodes))
    # The P2 space holds the linear exact field: the FE answer is exact up to round-off and the
    # .frd's 6 significant digits (E12.5): 2e-5 of the largest value.
    assert np.abs(u - u_exact).max() < 2e-5 * np.abs(u_exact).max()
    assert u[:, 0].max() == pytest.approx(P * BAR[0] / (STEEL.youngs_modulus * BAR[1] * BAR[2]), rel=2e-5)
    assert np.abs(S[:, 0] - s).max() < 2e-5 * s                 # sigma_xx = F/A at every node
    assert np.abs(S[:, 1:]).max() < 2e-5 * s                    # nothing else


@needs_ccx
def test_bar_tension_consistent_loads(bar_msh):
    """Consistent nodal loads of a uniform end traction (6-node triangle: corners 0, mid-edge
    nodes t A/3) by *CLOAD: sigma = F/A and u = F L/(E A), exact."""
    from flexbearing.verification import calculix as cx
    mesh = cx.read_tet10_mesh(bar_msh)
    P = 1000.0
    tris = mesh.facets[END_TAG]
    X = mesh.nodes
    area = 0.5 * np.linalg.norm(np.cross(X[tris[:, 1]] - X[tris[:, 0]], X[tris[:, 2]] - X[tris[:, 0]]), axis=1)
    assert area.sum() == pytest.approx(BAR[1] * BAR[2], rel=1e-12)
    f = np.zeros(len(X))
    np.add.at(f, tris[:, 3:].ravel(), np.repeat(P / area.sum() * area / 3, 3))
    loads = [(int(i), 1, float(f[i])) for i in np.flatnonzero(f)]
    run = cx.run_ccx(cx.deck_text(mesh, STEEL, boundary=_bar_support(mesh), cloads=loads))
    _check_tension(run, mesh, P)
    rf = cx.nodal_field(run.block("FORC"), len(X))
    assert rf[np.abs(X[:, 0]) < 1e-12, 0].sum() == pytest.approx(-P, rel=1e-5)     # the root reacts


@needs_ccx
def test_bar_tension_distributing_coupling(bar_msh):
    """The same end load as a force at a reference node on the end face's centroid, spread by
    ccx's *COUPLING + *DISTRIBUTING (deck_text couplings, facet_faces): its weights are the
    consistent area weights, so the bar is in exact uniform tension again."""
    from flexbearing.verification import calculix as cx
    mesh = cx.read_tet10_mesh(bar_msh)
    P = 1000.0
    cpl = cx.DistributingCoupling("END", np.array([BAR[0], BAR[1] / 2, BAR[2] / 2]),
                                  cx.facet_faces(mesh, mesh.facets[END_TAG]))
    n = len(mesh.nodes)
    run = cx.run_ccx(cx.deck_text(mesh, STEEL, boundary=_bar_support(mesh), couplings=[cpl],
                                  cloads=[(n, 1, P)]))
    _check_tension(run, mesh, P)


def test_frd_reader_short_and_long_format(tmp_path):
    """Fixed-width records (CalculiX GraphiX manual, 'Result Format'): short (I5) and long (I10)
    node numbers, fields touching at a minus sign, ' -2' continuation, the stored 'ALL'
    component skipped, STRESS reordered to Voigt (xx, yy, zz, yz, xz, xy)."""
    from flexbearing.verification.calculix import read_frd
    long_hdr = "  100CL  101 1.000000000           2                     0    1           1"
    short_hdr = "  100CL  102 5.000000000           2                     0    1           0"
    text = "\n".join([
        "    1C", long_hdr, " -4  DISP        4    1", " -5  D1          1    2    1    0",
        " -5  D2          1    2    2    0", " -5  D3          1    2    3    0",
        " -5  ALL         1    2    0    0    1ALL",
        " -1         1 1.00000E-03-2.00000E-03 3.00000E-03",
        " -1         7-4.00000E+00 5.00000E+00-6.00000E+00", " -3",
        short_hdr, " -4  STRESS      6    1", *[f" -5  {c:<8}    1    4    1    1" for c in
                                                 ("SXX", "SYY", "SZZ", "SXY", "SYZ", "SZX")],
        " -1    3 1.00000E+00 2.00000E+00 3.00000E+00 4.00000E+00",
        " -2      5.00000E+00 6.00000E+00", " -3", "9999"])
    p = tmp_path / "t.frd"
    p.write_text(text + "\n")
    disp, stress = read_frd(p)
    assert disp.name == "DISP" and disp.components == ["D1", "D2", "D3"] and disp.value == 1.0
    assert disp.nodes.tolist() == [0, 6]
    assert np.array_equal(disp.data, [[1e-3, -2e-3, 3e-3], [-4.0, 5.0, -6.0]])
    assert stress.value == 5.0 and stress.nodes.tolist() == [2]
    # frd (xx, yy, zz, xy, yz, zx) = (1..6) -> Voigt (xx, yy, zz, yz, xz, xy) = (1, 2, 3, 5, 6, 4)
    assert np.array_equal(stress.data, [[1.0, 2.0, 3.0, 5.0, 6.0, 4.0]])


def test_eigenfrequency_table():
    """f = sqrt(lambda)/(2 pi) from the .dat eigenvalue column (rigid modes: signed)."""
    from flexbearing.verification.calculix import read_eigenfrequencies
    dat = """
     E I G E N V A L U E   O U T P U T

 MODE NO    EIGENVALUE                       FREQUENCY
                                     REAL PART            IMAGINARY PART
                           (RAD/TIME)      (CYCLES/TIME     (RAD/TIME)

      1  -0.2720821E-03   0.0000000E+00   0.0000000E+00   0.1649491E-01
      2   0.1439817E+08   0.3794492E+04   0.6039122E+03   0.0000000E+00

     P A R T I C I P A T I O N   F A C T O R S
"""
    f = read_eigenfrequencies(dat)
    assert f[1] == pytest.approx(603.9122, rel=1e-6)        # the table's own cycles/time column
    assert f[0] < 0 and abs(f[0]) < 1e-2


def test_mesh_order_check_refuses_wrong_order(bar_msh):
    """read_tet10_mesh's C3D10/VTK order check: swapping two mid-edge nodes, or two corners
    (an inverted element), is refused with the cells named."""
    from flexbearing.verification import calculix as cx
    mesh = cx.read_tet10_mesh(bar_msh)
    bad = cx.Tet10Mesh(mesh.nodes, mesh.tets[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]])
    with pytest.raises(ValueError, match="not on edge"):
        cx.check_tet10_order(bad)
    inv = cx.Tet10Mesh(mesh.nodes, mesh.tets[:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]])
    with pytest.raises(ValueError, match="non-positive corner volume"):
        cx.check_tet10_order(inv)


def test_deck_refuses_bad_input(bar_msh):
    from flexbearing.verification import calculix as cx
    from flexbearing.common.validation import InputError
    mesh = cx.read_tet10_mesh(bar_msh)
    with pytest.raises(InputError, match="calculix.analysis"):
        cx.deck_text(mesh, STEEL, analysis="buckle")
    with pytest.raises(InputError, match="calculix.n_modes"):
        cx.deck_text(mesh, STEEL, analysis="frequency", n_modes=0)


def test_stress_recovery_same_on_straight_cells_not_on_curved(bar_msh, ring_msh):
    """CalculiX's recovery (Gauss-point stresses extrapolated to the corners, mid-edge = mean of
    corners) equals the project's interpolation at the nodes on straight-sided P2 cells (the cell
    stress is linear there, 4 Gauss points sample it exactly: round-off), not on curved cells
    (the ring): why the two codes' nodal stresses differ only in curved elements."""
    from flexbearing.verification.calculix_check import project_model, extrapolated_nodal_stress
    rng = np.random.default_rng(3)
    diffs = []
    for msh in (bar_msh, ring_msh):
        model = project_model(msh, STEEL)
        u = rng.standard_normal(model.K.shape[0]) * 1e-6
        s_own = model.stress_op(u)
        own = np.full((len(model.mesh.nodes), 6), np.nan)
        own[model.stress_node] = s_own
        ext = extrapolated_nodal_stress(model, u)
        diffs.append(np.abs(ext - own).max() / np.abs(own).max())
    assert diffs[0] < 1e-11
    assert diffs[1] > 1e-4


@needs_ccx
def test_frequencies_equal_with_the_same_quadrature(ring_msh):
    """Free–free modes of a curved ring mesh: the project's P2 K and M integrated with ccx's own
    4-point rule (quadrature degree 2) give CalculiX's C3D10 eigenvalues to its printed digits:
    same mesh, node order, orientation, material, element. Tolerance 2e-6: the .dat prints 7
    significant digits of the eigenvalue. With the project's default quadrature (degree 4) they
    differ by the quadrature error only: within 0.5 % even on this coarse mesh."""
    from flexbearing.verification.calculix_check import project_model, frequency_case
    model = project_model(ring_msh, STEEL, quadrature_degree=2)
    r = frequency_case(model, STEEL, n_elastic=8)
    assert r["max_abs_rel_diff"] < 2e-6
    assert max(abs(f) for f in r["rigid_calculix_hz"]) < 1e-3 * r["calculix_hz"][0]
    r4 = frequency_case(project_model(ring_msh, STEEL), STEEL, n_elastic=8)
    assert r4["max_abs_rel_diff"] < 5e-3


# ------------------------------------------------------------------ the paper cage, end to end

def _paper_mesh(tmp_path_factory, size):
    """The paper cage, curved quadratic, global and pocket size `size` (explicit: the check must
    not follow flexbearing.mesh.cage_mesh's defaults). 4 mm and finer hold no inverted element (issue 24)."""
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    return build_cage_mesh(PAPER_CAGE, size, 2, tmp_path_factory.mktemp("cage") / "cage.msh", size)


@pytest.mark.slow
@needs_ccx
def test_paper_cage_frequencies_against_calculix(tmp_path_factory):
    """First 20 free–free elastic frequencies of the paper cage, 4 mm mesh, project P2 vs CalculiX
    C3D10 (measured 0.085 %; issue 24 asks 0.5 %). With ccx's own 4-point rule the project's K and
    M are CalculiX's: 2e-7 measured, 1e-5 allowed (the .dat's 7 digits, ARPACK/SLEPc tolerances)."""
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.verification.calculix_check import project_model, frequency_case
    msh = _paper_mesh(tmp_path_factory, 4e-3)
    r = frequency_case(project_model(msh, PAPER_CAGE.material), PAPER_CAGE.material, 20, msh_path=msh)
    assert r["max_abs_rel_diff"] < 0.005
    assert r["max_abs_rel_diff_quadrature2"] < 1e-5
    assert max(abs(f) for f in r["rigid_calculix_hz"]) < 1e-3 * r["calculix_hz"][0]


@pytest.mark.slow
@needs_ccx
def test_paper_cage_stress_against_calculix(tmp_path_factory):
    """Spin at 645 rad/s and a 1 kN ball force on pocket 1 (circumferential, axial, radial; pocket
    0 reacting) on the paper cage, 2.5 mm mesh (138k dofs), each code with its own nodal stress
    recovery: max von Mises within 2 % and the peak of each code inside the other's 2 % hot spot
    (its von Mises there within 2 % of its own maximum; issue 24's acceptance). Measured: max
    within 1.6 %, hot spots 98.5 % or more; on the 4 mm mesh the recovery difference reaches
    3.2 % (benchmarks/results/calculix_check.md). The solutions themselves agree much closer: with
    CalculiX's recovery applied to the project's displacement the maxima differ by <= 0.11 %
    (0.5 % allowed: the quadrature difference, degree 4 vs ccx's 4 points, largest on coarse
    meshes: 0.4 % at 4 mm) and the displacements by <= 3e-4 (1e-3 allowed)."""
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.verification.calculix_check import check_mesh
    r = check_mesh(_paper_mesh(tmp_path_factory, 2.5e-3), PAPER_CAGE, n_elastic=0)
    assert set(r["cases"]) == {"spin", "pocket_circumferential", "pocket_axial", "pocket_radial"}
    for name, c in r["cases"].items():
        assert abs(c["vm_max_rel_diff"]) < 0.02, name
        assert c["calculix_at_project_peak_rel"] > 0.98, name
        assert c["project_at_calculix_peak_rel"] > 0.98, name
        assert abs(c["same_recovery"]["vm_max_rel_diff"]) < 0.005, name
        assert c["u_rel_diff_l2"] < 1e-3, name
    spin = r["cases"]["spin"]
    # 3-2-1 support of a self-equilibrated load: reactions are the mesh's out-of-balance only
    # (ccx's 4-point CENTRIF: 3.5e-5 of the load at 4 mm); inertia relief gives the same stress
    assert np.abs(spin["reactions_calculix_N"]).max() < 1e-4 * spin["load_abs_sum_N"]
    assert spin["inertia_relief_stress_rel_diff"] < 1e-4
    for d in ("circumferential", "axial", "radial"):
        c = r["cases"][f"pocket_{d}"]
        # the held-RBE3 case of `reduce --check` is the equilibrated free cage (docstring)
        assert c["held_vs_equilibrated_stress_rel_diff"] < 1e-8
        assert np.abs(c["reactions_calculix_N"]).max() < 1e-6 * c["force_N"]
