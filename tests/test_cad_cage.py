"""A cage the project has not seen, from CAD (flexbearing.mesh.cad_cage): drawn with gmsh's
OpenCASCADE API (flexbearing.verification.cad_test_cage) and written as STEP (mm) or BREP:
inner-ring guided, 14 spherical pockets, turned 7° so that no pocket sits at +y.

References are the numbers the test cage was drawn with (outside 176 mm, bore 158 mm, width
26 mm, pockets 22.4 mm on the 167 mm pitch circle); tolerances from the CAD kernel's precision
(1e-7 of the part's size: 1e-9 m here, 1e-6 relative). The slow test compares its free–free
modes on the same mesh with CalculiX (flexbearing.verification.calculix_check).
"""
import math

import numpy as np
import pytest

from flexbearing.common.validation import InputError

from flexbearing.verification.cad_test_cage import BORE, DP, OD, PITCH, TURN, WIDTH, Z, make_cad_cage


@pytest.fixture(scope="module")
def step_file(tmp_path_factory):
    return make_cad_cage(tmp_path_factory.mktemp("cad") / "cage14.step")


def _read(path, n_balls=Z, guidance="inner", unit=None, pitch=PITCH * 1e-3):
    import gmsh
    from flexbearing.mesh.cad_cage import read_cad_cage
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        return read_cad_cage(path, n_balls, pitch, 22e-3, guidance, unit)
    finally:
        gmsh.finalize()


def test_pockets_and_land_found(step_file):
    cad = _read(step_file)
    g = cad.geometry
    assert len(cad.pockets) == Z
    assert (g.outside_diameter, g.bore_diameter, g.width, g.pocket_diameter) == pytest.approx(
        (OD * 1e-3, BORE * 1e-3, WIDTH * 1e-3, DP * 1e-3), rel=1e-6)
    assert (g.guidance, g.pocket_shape, g.n_pockets) == ("inner", "spherical", Z)
    assert g.pocket_centre_diameter == PITCH * 1e-3
    assert cad.turned_by == pytest.approx(-math.radians(TURN), abs=1e-9)
    for k, p in enumerate(cad.pockets):
        assert p.azimuth == pytest.approx(2 * math.pi * k / Z, abs=1e-9)
        c = np.array(p.centre)
        assert c == pytest.approx([0.0, 0.5 * PITCH * 1e-3 * math.cos(p.azimuth),
                                   0.5 * PITCH * 1e-3 * math.sin(p.azimuth)], abs=1e-9)
    assert len(cad.guide_faces) >= 1 and set(cad.guide_faces) == set(cad.groups["guide"])
    assert "bore" not in cad.groups and "outside" in cad.groups
    lines = cad.report_lines(PITCH * 1e-3, 22e-3)
    assert "14 spherical pockets of 22.400 mm (clearance 200.0 µm" in lines[1]
    g.validate()


def test_outer_guidance_takes_the_outside(step_file):
    cad = _read(step_file, guidance="outer")
    assert "bore" in cad.groups and "outside" not in cad.groups
    assert cad.geometry.land_width == pytest.approx(0.5 * WIDTH * 1e-3, rel=1e-6)


def test_units_brep_and_step(tmp_path, step_file):
    """A BREP has no unit: refused without one; with it, the same cage as the STEP (drawn in m
    here). A STEP file declares its own (mm here): reported; a unit given overrides it, with a
    printed note (issue 43: a STEP whose declared unit is wrong, metres for numbers in mm, is
    read right with --cad-unit mm); a wrong unit makes a cage of the wrong size, refused by its
    size against the pitch circle."""
    brep = make_cad_cage(tmp_path / "cage14.brep", scale=1e-3)
    with pytest.raises(InputError, match="BREP file carries no unit"):
        _read(brep)
    assert _read(brep, unit="m").geometry.outside_diameter == pytest.approx(OD * 1e-3, rel=1e-6)
    with pytest.raises(InputError, match=r"is the unit right"):
        _read(brep, unit="mm")
    with pytest.raises(InputError, match=r"is the unit right"):
        _read(step_file, unit="in")                 # the mm numbers read as inches: 25.4 times too big
    assert _read(step_file, unit="mm").unit == "mm (from the file)"
    wrong = tmp_path / "declared_metres.step"
    wrong.write_bytes(step_file.read_bytes().replace(b"SI_UNIT(.MILLI.,.METRE.)", b"SI_UNIT($,.METRE.)"))
    with pytest.raises(InputError, match=r"the cage is 176 m across.*is the unit right \(--cad-unit\)"):
        _read(wrong)
    cad = _read(wrong, unit="mm")
    assert cad.geometry.outside_diameter == pytest.approx(OD * 1e-3, rel=1e-6)
    assert cad.unit == "mm (given, over the file's m unit)"
    assert ("note: cad unit 'mm' overrides the STEP file's declared length unit m: its numbers are read as mm"
            in cad.report_lines(PITCH * 1e-3, 22e-3))


@pytest.mark.parametrize("case, match", [
    ("balls", r"14 pockets found, the bearing has bearing.n_balls = 20; a cage needs one pocket per ball"),
    ("offset", r"pocket 3 is centred at radius 83.6000 mm.*off the pitch circle"),
    ("suffix", r"not a CAD file; allowed: STEP"),
])
def test_refusals_name_what_is_missing(tmp_path, step_file, case, match):
    with pytest.raises(InputError, match=match):
        if case == "balls":
            _read(step_file, n_balls=20)
        elif case == "offset":
            _read(make_cad_cage(tmp_path / "off.step", sphere_offset_mm=0.1))
        else:
            _read(tmp_path / "cage.igs")


def test_mesh_of_the_cad_cage(tmp_path, step_file):
    """`build_cad_cage_mesh`: tagged like the parametric cage (one group per pocket, guide = the
    bore), every node of pocket k on its sphere (CAD precision or the repair's reported shift)."""
    from flexbearing.mesh.cad_cage import build_cad_cage_mesh
    from flexbearing.mesh.cage_mesh import mesh_quality_of
    from flexbearing.verification.cad_test_cage import mesh_groups
    out = tmp_path / "cage14.msh"
    cad = build_cad_cage_mesh(step_file, out, Z, PITCH * 1e-3, 22e-3, "inner", size=8e-3, pocket_size=6e-3)
    shift = mesh_quality_of(out)["repair"]["max_node_shift_m"]
    groups = mesh_groups(out)
    assert groups["cage"][:2] == (3, 1) and groups["guide"][:2] == (2, 200)
    for k in range(Z):
        d, t, X = groups[f"pocket_{k:02d}"]
        assert t == 101 + k
        c = np.array(cad.pockets[k].centre)
        dist = np.abs(np.linalg.norm(X - c, axis=1) - 0.5 * DP * 1e-3)
        assert dist.max() <= shift + 1e-8


@pytest.mark.slow
def test_cad_cage_modes_against_calculix(tmp_path, step_file):
    """The first 20 elastic free–free frequencies of the CAD cage, project P2 against CalculiX
    C3D10 on the same 5 mm curved mesh: within 0.5 % (the quadrature difference, as the paper
    cage's check in tests/test_calculix.py), and 1e-5 with CalculiX's own 4-point rule."""
    import shutil
    if shutil.which("ccx") is None:
        pytest.skip("CalculiX (ccx) not installed")
    from flexbearing.verification.cad_test_cage import calculix_modes_check
    r = calculix_modes_check(step_file, tmp_path / "cage14.msh")
    assert r["max_abs_rel_diff"] < 0.005
    assert r["max_abs_rel_diff_quadrature2"] < 1e-5


SCENE = """name = "cad14"
[bearing]
n_balls = 14
inner_land_diameter = 157.25e-3
[cage]
model = "flexible"
cad = "cage14.step"
guidance = "inner"
{extra}
[operation]
duration = 0.01
[operation.speed]
phases = [{{ kind = "uniform", duration = 0.01, rpm = 14000 }}]
[operation.load]
axial_load = 55e3
[output]
sample_interval = 1e-3
record = ["cage_speed"]
"""


def test_scene_with_a_cad_cage(tmp_path, monkeypatch, step_file):
    """[cage] cad = "cage14.step" (relative to the scene): the bearing's cage is the file's
    equivalent geometry, found once and then read from the cache (checked against its key: the
    file's content); the scene may not give the geometry the file decides; the reduced cage's key
    names the file by its content."""
    import shutil
    from flexbearing.simulation.scene import load_scene
    from flexbearing.coupling.flexible_cage import reduced_cage_key
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path / "cache"))
    shutil.copy(step_file, tmp_path / "cage14.step")
    (tmp_path / "s.toml").write_text(SCENE.format(extra=""))
    s = load_scene(tmp_path / "s.toml")
    g = s.bearing.cage
    assert (g.n_pockets, g.pocket_shape, g.guidance) == (Z, "spherical", "inner")
    assert g.bore_diameter == pytest.approx(BORE * 1e-3, rel=1e-6)
    assert s.bearing.guide_clearance == pytest.approx(0.375e-3, rel=1e-6)
    assert list((tmp_path / "cache" / "meshes").glob("*.cad.json"))
    assert load_scene(tmp_path / "s.toml").bearing.cage == g           # from the cache
    assert reduced_cage_key(s)["cad"]["cad_sha256"] == s.cad["key"]["cad_sha256"]
    (tmp_path / "s2.toml").write_text(SCENE.format(extra="pocket_diameter = 22.5e-3"))
    with pytest.raises(InputError, match=r"cage.pocket_diameter = 0.0225: the geometry of this cage is read from cage.cad"):
        load_scene(tmp_path / "s2.toml")
    (tmp_path / "s3.toml").write_text(SCENE.format(extra="").replace('n_balls = 14', 'n_balls = 16'))
    with pytest.raises(InputError, match=r"14 pockets found, the bearing has bearing.n_balls = 16"):
        load_scene(tmp_path / "s3.toml")


def test_modes_table_compares_with_table8_only_for_the_paper_cage():
    """flexbearing modes: Table 8 beside the frequencies for the paper's cage; for another cage
    its frequencies and families alone, no paper error."""
    from flexbearing.fem_cage.modes import PAPER_TABLE8_HZ, mode_table
    freqs = [0.0] * 6 + [PAPER_TABLE8_HZ[7] * 1.01] + [100.0 * k for k in range(8, 28)]
    paper = mode_table(freqs, paper=True)
    assert "Table 8" in paper and "+1.00%" in paper and "RMS relative error" in paper
    other = mode_table(freqs, ["rigid"] * 6 + ["x"] * 21, paper=False)
    assert "Table 8" not in other and "%" not in other and len(other.splitlines()) == 28


def test_untagged_mesh_is_refused_in_one_line(tmp_path):
    """A mesh without the cage's physical groups (what `modes --mesh` once met as an IndexError)."""
    import gmsh
    from flexbearing.fem_cage.elasticity import load_cage_mesh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.addBox(0, 0, 0, 0.01, 0.01, 0.01)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.005)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.SaveAll", 1)
        gmsh.write(str(tmp_path / "box.msh"))
    finally:
        gmsh.finalize()
    with pytest.raises(InputError, match=r"has no physical volume group \(groups: none\): make it with `flexbearing mesh`"):
        load_cage_mesh(tmp_path / "box.msh")


def test_cylindrical_pockets_found(tmp_path):
    """Radial cylindrical pockets: found by their axes (radial, in the mid-plane), outer guidance."""
    cad = _read(make_cad_cage(tmp_path / "cyl.step", shape="cylindrical"), guidance="outer")
    g = cad.geometry
    assert (g.pocket_shape, g.n_pockets, g.guidance) == ("cylindrical", Z, "outer")
    assert g.pocket_diameter == pytest.approx(DP * 1e-3, rel=1e-6)
    for k, p in enumerate(cad.pockets):
        assert p.azimuth == pytest.approx(2 * math.pi * k / Z, abs=1e-9)
        assert abs(p.centre[0]) < 1e-9
