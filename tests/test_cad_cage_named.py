"""Named groups in a CAD cage (flexbearing.mesh.cad_cage, `named_groups`): the test cage of
flexbearing.verification.cad_test_cage written as STEP and a gmsh .geo that merges it and names
its faces (`make_named_cad_cage`; gmsh 4.8 keeps no face names in STEP or BREP). The names win
over the geometric search (a spherical dimple the search takes for a fifteenth pocket is left
out); a name that disagrees with the geometry is refused in one line naming the group.

References are the numbers the cage is drawn with (as tests/test_cad_cage.py): 14 pockets of
22.4 mm on the 167 mm pitch circle, bore 158 mm; tolerances the CAD kernel's (1e-9 m here).
"""
import math

import numpy as np
import pytest

from flexbearing.common.validation import InputError
from flexbearing.verification.cad_test_cage import BORE, DP, PITCH, Z, make_cad_cage, make_named_cad_cage


def _read(path, guidance="inner", n_balls=Z):
    import gmsh
    from flexbearing.mesh.cad_cage import read_cad_cage
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        return read_cad_cage(path, n_balls, PITCH * 1e-3, 22e-3, guidance)
    finally:
        gmsh.finalize()


def test_names_win_over_the_geometric_search(tmp_path):
    """With a dimple on the outside the search finds 15 spheres and refuses; the named groups
    take the 14 pockets, each on its sphere, and the named bore as the land; the report says how."""
    step = make_cad_cage(tmp_path / "dimpled.step", dimple=True)
    with pytest.raises(InputError, match=r"15 pockets found, the bearing has bearing.n_balls = 14"):
        _read(step)
    cad = _read(make_named_cad_cage(tmp_path / "named.geo", dimple=True))
    assert len(cad.pockets) == Z
    for k, p in enumerate(cad.pockets):
        assert p.azimuth == pytest.approx(2 * math.pi * k / Z, abs=1e-9)
        assert np.hypot(p.centre[1], p.centre[2]) == pytest.approx(0.5 * PITCH * 1e-3, abs=1e-9)
        assert p.diameter == pytest.approx(DP * 1e-3, rel=1e-6)
    assert cad.geometry.bore_diameter == pytest.approx(BORE * 1e-3, rel=1e-6)
    assert set(cad.guide_faces) == set(cad.groups["guide"]) and len(cad.guide_faces) == 1
    assert len(cad.groups["other"]) == 1                      # the dimple
    assert cad.unit == "mm (from the file)"
    lines = "\n".join(cad.report_lines(PITCH * 1e-3, 22e-3))
    assert "pockets found by the file's named groups pocket_1 … pocket_14" in lines
    assert "guide found by the file's named group 'guide'" in lines
    assert "not used" not in lines


def test_names_off_the_convention_are_reported(tmp_path):
    geo = make_named_cad_cage(tmp_path / "named.geo")
    geo.write_text(geo.read_text() + 'Physical Surface("pocket_3x") = {1};\n')
    cad = _read(geo)
    assert "named groups not used (not pocket_<n>, pockets, guide or land): pocket_3x" in \
        cad.report_lines(PITCH * 1e-3, 22e-3)


def test_without_names_the_geometry_says_so(tmp_path):
    cad = _read(make_cad_cage(tmp_path / "plain.step"))
    assert cad.found_by["pockets"].startswith("geometry")
    assert cad.found_by["guide"] == "geometry (the ring cylinder at the smallest radius)"


@pytest.mark.parametrize("wrong, cage, match", [
    ("count", {}, r"13 named pocket groups \(pocket_1 … pocket_13\), the bearing has bearing.n_balls = 14"),
    ("side_as_pocket", {}, r"named group 'pocket_4': face \d+ is not a pocket wall by its geometry"),
    ("outside_as_guide", {}, r"named group 'guide': face \d+ at radius 88.0000 mm is outside the pitch "
                             r"circle; cage.guidance = 'inner' needs the bore"),
    ("pocket_as_guide", {}, r"named group 'guide': face \d+ is not a cylinder about the bearing axis"),
    ("", {"sphere_offset_mm": 0.1}, r"pocket 3 \(named group 'pocket_4'\) is centred at radius 83.6000 mm"),
])
def test_names_that_disagree_with_the_geometry_are_refused(tmp_path, wrong, cage, match):
    with pytest.raises(InputError, match=match):
        _read(make_named_cad_cage(tmp_path / "named.geo", wrong=wrong, **cage))


def test_named_cage_meshes_and_enters_a_scene(tmp_path, monkeypatch):
    """The .geo meshes with the model's own groups only (the file's are replaced), and a scene's
    cage.cad may be the .geo: its cache key holds the merged STEP's content too."""
    import gmsh
    from flexbearing.mesh.cad_cage import build_cad_cage_mesh
    from flexbearing.simulation.scene import load_scene
    geo = make_named_cad_cage(tmp_path / "named.geo", dimple=True)
    out = tmp_path / "named.msh"
    build_cad_cage_mesh(geo, out, Z, PITCH * 1e-3, 22e-3, "inner", size=12e-3, pocket_size=10e-3)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(out))
        names = {gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
    finally:
        gmsh.finalize()
    assert names == {"cage", "guide", "outside", "side_left", "side_right", "other"} | {f"pocket_{k:02d}" for k in range(Z)}
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path / "cache"))
    from test_cad_cage import SCENE
    (tmp_path / "s.toml").write_text(SCENE.format(extra="").replace("cage14.step", "named.geo"))
    s = load_scene(tmp_path / "s.toml")
    assert s.bearing.cage.n_pockets == Z
    assert "named.step" in s.cad["key"]["merged_sha256"]
    assert any("named groups" in line for line in s.cad["report"])
