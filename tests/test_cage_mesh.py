"""Cage geometry validation and the gmsh cage mesh (physical groups, pocket placement)."""
import math

import numpy as np
import pytest
from tolerances import assert_within, dot_bound, gamma

from flexbearing.mesh.cage_geometry import PAPER_CAGE, NOMINAL_CAGE
from flexbearing.common.validation import InputError


@pytest.mark.parametrize("change, field", [
    (dict(pocket_diameter=30e-3), "cage.pocket_diameter"),      # wider than the cage / overlapping
    (dict(pocket_diameter=21.9e-3), "cage.pocket_diameter"),    # Dp <= Dw: the ball does not fit
    (dict(pocket_diameter=25e-3), "cage.pocket_diameter"),      # > 1.1 Dw
    (dict(n_pockets=40), "cage.n_pockets = 40: the balls do not fit"),  # 40 pockets of 22.5 mm overlap
    (dict(bore_diameter=0.18), "cage.bore_diameter"),           # bore >= outside diameter
    (dict(land_width=20e-3), "cage.land_width"),                # land wider than half the cage
    (dict(width=-1e-3), "cage.width"),
    (dict(relief_depth=9e-3), "cage.relief_depth"),             # deeper than the wall
    (dict(chamfer=-1e-4), "cage.chamfer"),
    (dict(relief_depth=1e-3, land_width=2e-3, chamfer=2.5e-3), "cage.chamfer"),  # eats the land
    (dict(bore_chamfer=-1e-4), "cage.bore_chamfer"),
    (dict(bore_chamfer=4.5e-3), "cage.bore_chamfer"),           # > half the 8.65 mm wall
    (dict(relief_depth=6e-3, land_width=5e-3, bore_chamfer=3e-3), "cage.bore_chamfer"),  # past the relief floor
])
def test_invalid_geometry_names_field_and_range(change, field):
    with pytest.raises(InputError) as err:
        NOMINAL_CAGE.with_(**change).validate()
    msg = str(err.value)
    assert field in msg
    assert "allowed range" in msg or "must" in msg


def test_presets_valid_and_pocket_clearance_reasonable():
    for g in (PAPER_CAGE, NOMINAL_CAGE):
        g.validate()
        # pocket clearance Cp = (Dp - Dw)/2 between 0.05 and 0.5 mm for the 22 mm ball
        assert 0.05e-3 <= 0.5 * (g.pocket_diameter - 22e-3) <= 0.5e-3


def test_mesh_sizes_are_checked():
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    with pytest.raises(InputError, match="mesh.size"):
        build_cage_mesh(NOMINAL_CAGE, -1.0, 2, "/tmp/never.msh")
    with pytest.raises(InputError, match="mesh.order"):
        build_cage_mesh(NOMINAL_CAGE, 5e-3, 3, "/tmp/never.msh")
    with pytest.raises(InputError, match="mesh.pocket_size"):
        build_cage_mesh(NOMINAL_CAGE, 5e-3, 2, "/tmp/never.msh", pocket_size=6e-3)


@pytest.fixture(scope="module")
def relieved_mesh(tmp_path_factory):
    """A coarse relieved, chamfered cage: every group kind present."""
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    g = NOMINAL_CAGE.with_(land_width=8e-3, relief_depth=1e-3, chamfer=0.5e-3)
    path = build_cage_mesh(g, 8e-3, 2, tmp_path_factory.mktemp("m") / "cage.msh", pocket_size=4e-3)
    return g, path


def _groups(path):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.merge(str(path))
    out = {}
    for d, t in gmsh.model.getPhysicalGroups():
        nodes, coords = gmsh.model.mesh.getNodesForPhysicalGroup(d, t)
        out[gmsh.model.getPhysicalName(d, t)] = (d, t, coords.reshape(-1, 3))
    types = gmsh.model.mesh.getElementTypes(3)
    gmsh.finalize()
    return out, types


def test_physical_groups_and_pocket_positions(relieved_mesh):
    from flexbearing.mesh.cage_mesh import mesh_quality_of
    g, path = relieved_mesh
    groups, types = _groups(path)
    # the repair of badly curved cells (flexbearing.mesh.quality) moves a few mid-edge nodes off the CAD
    # surface, by at most the shift it reports; every other node is on it
    repair = mesh_quality_of(path)["repair"]
    shift, n_moved = repair["max_node_shift_m"], repair["n_nodes_moved"]
    tol = 1e-9 + 1e-5 * g.outer_radius          # np.allclose's default: gmsh/OCC round-off
    off = 0
    assert list(types) == [11]                       # 10-node (curved quadratic) tetrahedra only
    assert groups["cage"][:2] == (3, 1)
    assert groups["guide"][:2] == (2, 200)
    for name in ("bore", "side_left", "side_right"):
        assert name in groups
    for k in range(g.n_pockets):
        d, t, X = groups[f"pocket_{k:02d}"]
        assert (d, t) == (2, 101 + k)
        # Every node of pocket k lies on the cylinder of radius Dp/2 about the radial axis at
        # theta_k = 2 pi k / Z (from +y towards +z), centred on x = 0. Tolerance: the curved
        # quadratic mesh puts all nodes on the CAD surface (gmsh/OCC round-off), except the few
        # the repair moved.
        th = 2 * math.pi * k / g.n_pockets
        axis = np.array([0.0, math.cos(th), math.sin(th)])
        dist = np.abs(np.linalg.norm(X - np.outer(X @ axis, axis), axis=1) - 0.5 * g.pocket_diameter)
        assert dist.max() <= shift + tol
        off += int(np.count_nonzero(dist > tol))
    # Guide nodes: on the outside cylinder r = D/2, within the two lands |x| >= relief/2.
    X = groups["guide"][2]
    dist = np.abs(np.hypot(X[:, 1], X[:, 2]) - g.outer_radius)
    assert dist.max() <= shift + tol
    off += int(np.count_nonzero(dist > tol))
    assert off <= n_moved
    assert np.all(np.abs(X[:, 0]) >= 0.5 * g.relief_width - 1e-9)


def test_cached_mesh_is_reused(tmp_path, monkeypatch):
    from flexbearing.mesh import cage_mesh
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path))
    p1 = cage_mesh.cached_cage_mesh(NOMINAL_CAGE, 10e-3, 1, 10e-3)
    mtime = p1.stat().st_mtime_ns
    p2 = cage_mesh.cached_cage_mesh(NOMINAL_CAGE, 10e-3, 1, 10e-3)
    assert p1 == p2 and p2.stat().st_mtime_ns == mtime and p1.parent == tmp_path / "meshes"


def test_bore_chamfer_unset_keeps_the_cache_identity():
    # Cache keys (meshes, reduced cages) hash to_dict(): a geometry that does not set the newer
    # bore_chamfer field must give the same dict (same keys) as before the field existed.
    before = {"outside_diameter", "bore_diameter", "width", "n_pockets", "pocket_diameter",
              "land_width", "relief_depth", "chamfer", "material", "ball_diameter"}
    assert set(NOMINAL_CAGE.to_dict()) == before
    assert NOMINAL_CAGE.bore_edge_chamfer == NOMINAL_CAGE.chamfer
    g = NOMINAL_CAGE.with_(chamfer=0.5e-3, bore_chamfer=2e-3)
    assert g.to_dict()["bore_chamfer"] == 2e-3 and g.bore_edge_chamfer == 2e-3


def test_section_profile_with_bore_chamfer():
    # Shoelace area of the section polygon = W h - 2 c^2/2 (outside edges) - 2 cb^2/2 (bore edges)
    # - relief (W - 2 L) d: closed form of the drawn section (45° chamfers are right isosceles).
    from flexbearing.mesh.cage_mesh import _profile_points
    c, cb, L, d = 0.5e-3, 2e-3, 5e-3, 1e-3
    g = NOMINAL_CAGE.with_(chamfer=c, bore_chamfer=cb, land_width=L, relief_depth=d).validate()
    P = np.array(_profile_points(g))
    area = 0.5 * abs(np.dot(P[:, 0], np.roll(P[:, 1], -1)) - np.dot(P[:, 1], np.roll(P[:, 0], -1)))
    h = g.outer_radius - g.inner_radius
    terms = np.array([g.width * h, c ** 2, cb ** 2, (g.width - 2 * L) * d])
    # the two n-term sums of the shoelace (their absolute terms; n + 3 roundings: the corner
    # coordinates are sums of <= 3 lengths), against the closed form's chain of <= 8 roundings
    x, y = P[:, 0], P[:, 1]
    absterms = np.abs(x * np.roll(y, -1)).sum() + np.abs(y * np.roll(x, -1)).sum()
    assert_within(abs(area - (terms[0] - terms[1:].sum())),
                  0.5 * dot_bound(len(P) + 3, absterms) + 2 * gamma(8) * np.abs(terms).sum(),
                  "shoelace area", effect=min(c ** 2, cb ** 2, (g.width - 2 * L) * d))
    # bore corners at x = ±(W/2 - cb), outside corners at x = ±(W/2 - c)
    ri, ro = g.inner_radius, g.outer_radius
    assert sorted(abs(x) for x, r in P if r == ri) == pytest.approx([0.5 * g.width - cb] * 2)
    assert sorted(abs(x) for x, r in P if r == ro and abs(x) > 0.5 * g.relief_width + 1e-9) == \
        pytest.approx([0.5 * g.width - c] * 2)


def test_bore_chamfer_mesh_nodes(tmp_path):
    # Meshed with a 2 mm bore chamfer and no outside chamfer: bore nodes stay within
    # |x| <= W/2 - cb, side-face nodes at r >= ri + cb (1e-9 m: nodes on the CAD surfaces).
    from flexbearing.mesh.cage_mesh import build_cage_mesh
    cb = 2e-3
    g = NOMINAL_CAGE.with_(bore_chamfer=cb)
    path = build_cage_mesh(g, 10e-3, 1, tmp_path / "c.msh", pocket_size=10e-3)
    groups, _ = _groups(path)
    Xb = groups["bore"][2]
    assert np.all(np.abs(Xb[:, 0]) <= 0.5 * g.width - cb + 1e-9)
    for side in ("side_left", "side_right"):
        r = np.hypot(groups[side][2][:, 1], groups[side][2][:, 2])
        assert r.min() >= g.inner_radius + cb - 1e-9 and r.max() <= g.outer_radius + 1e-9
    assert "other" in groups            # the chamfer faces


def test_sub_micrometre_chamfer_is_drawn_as_a_sharp_edge():
    # An optimiser may push a chamfer to ~1e-9 m; OCC cannot draw that edge, and it is no
    # feature of a machined part: below MIN_FEATURE (1 µm) the corner is drawn sharp.
    from flexbearing.mesh.cage_mesh import _profile_points, MIN_FEATURE
    sharp = _profile_points(NOMINAL_CAGE)
    assert _profile_points(NOMINAL_CAGE.with_(chamfer=1e-9, bore_chamfer=0.3 * MIN_FEATURE)) == sharp
    assert len(_profile_points(NOMINAL_CAGE.with_(chamfer=MIN_FEATURE))) == len(sharp) + 4
