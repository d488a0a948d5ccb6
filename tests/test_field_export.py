"""The cage's stress field for ParaView (flexbearing.analysis.field_export) and its picture (flexbearing.analysis.stress_picture),
read back the way a user's tool reads them: meshio for the XDMF files (and ParaView itself in the
slow test when pvpython is installed), plain XML + h5py for what meshio's reader skips (per-step
geometry, units).

Synthetic runs: a Kuhn cube (6 tetrahedra, 10 nodes each: 27 nodes) as the "cage", random stress
and displacement modes, random modal coordinates; the recorded maximum of each sample is computed
here independently (sqrt(3/2 s:s) of the deviator of the full tensor). The placement is checked
against rotations built by scipy (intrinsic Z-Y-X Euler angles), independent of
flexbearing.multibody.cage_body.cage_rotation which the code uses.

Tolerances: fields 1e-12 relative (HDF5 keeps float64 unchanged; only the summation order of S q
differs); positions 1e-12 m (coordinates of 0.05 m, a few roundings); the brief's readback
criterion on the real run is 1e-9 relative.
"""
from __future__ import annotations

import json
import math
import shutil
import subprocess
import xml.etree.ElementTree as ET
from itertools import permutations
from pathlib import Path

import h5py
import numpy as np
from tolerances import U, assert_within, dot_bound, gamma, von_mises_bound
import pytest
from scipy.spatial.transform import Rotation

from flexbearing.analysis import field_export
from flexbearing.analysis.stress_picture import boundary_faces, face_normals
from flexbearing.common.validation import InputError
from test_report import _vm_by_deviator, write_run

R_POCKET = 0.05          # m, radius of the synthetic pockets' centres
Z = 4                    # synthetic pockets and balls
M = 3                    # synthetic modes
DT = 1e-3                # test_report's synthetic run


def kuhn_cube(h=1.0, origin=(0.0, 0.0, 0.0)):
    """(nodes (27, 3), tets10 (6, 10) in VTK order, tets (6, 4)): the unit cube's Kuhn
    triangulation (one tetrahedron per permutation of the axes), edge nodes at the midpoints."""
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    index = {tuple(c): n for n, c in enumerate(corners)}
    tets = []
    for p in permutations(range(3)):
        path = [np.zeros(3)]
        for axis in p:
            path.append(path[-1] + np.eye(3)[axis])
        tets.append([index[tuple(v)] for v in path])
    tets = np.array(tets)
    nodes = [*corners]
    edge_node = {}
    tets10 = []
    for t in tets:
        row = list(t)
        for a, b in ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)):
            key = tuple(sorted((t[a], t[b])))
            if key not in edge_node:
                edge_node[key] = len(nodes)
                nodes.append(0.5 * (corners[t[a]] + corners[t[b]]))
            row.append(edge_node[key])
        tets10.append(row)
    return np.asarray(origin) + h * np.array(nodes), np.array(tets10), tets


def rotation(phi, by, bz):
    """A = R_z(bz) R_y(by) R_x(phi) (scipy: intrinsic Z-Y-X)."""
    return Rotation.from_euler("ZYX", [bz, by, phi]).as_matrix()


def fake_cage(tmp_path, quadratic=True):
    from flexbearing.fem_cage.reduced_cage import read, write
    X, tets10, tets = kuhn_cube(0.01, (-0.005, R_POCKET - 0.005, -0.005))
    rng = np.random.default_rng(11)
    S = rng.normal(size=(len(X), 6, M)) * 1e7
    Phi = rng.normal(size=(len(X), 3, M)) * 1e-5
    az = 2 * np.pi * np.arange(Z) / Z
    data = {"mesh/vertices": X, "mesh/tets": tets, "stress/modes": S, "modes/vertex_displacement": Phi,
            "modes/frequency_hz": np.ones(M), "modes/omega": np.ones(M), "modes/modal_stiffness": np.ones(M),
            "modes/interface": rng.normal(size=(Z, 6, M)) * 1e-5,
            "interface/positions": np.stack([np.zeros(Z), R_POCKET * np.cos(az), R_POCKET * np.sin(az)], 1),
            "invariants/mass": 1.0}
    if quadratic:
        data["mesh/tets10"] = tets10
    path = write(tmp_path / "cage.h5", data, {"content_hash": "0123456789abcdef"})
    stored = read(path)           # the tables as the file holds them (16-bit, reduced_cage schema 6)
    return path, X, stored.stress_modes, stored.vertex_displacement, data["modes/interface"]


def motion(t):
    """(spin phi, tilt (by, bz), centre (3,)) of the synthetic cage at t."""
    return (0.3 + 400.0 * t, (1e-3 * math.sin(300 * t), -2e-3 * math.cos(200 * t)),
            np.array([2e-5, 1e-4 * math.cos(900 * t), 1e-4 * math.sin(900 * t)]))


def fake_run(tmp_path, cage=True, balls=True, orbit=True, quadratic=True, n=21, offsets=None):
    """A run of n samples: modal coordinates and their maxima (cage), the balls exactly on their
    pockets' deformed centres (+ the interface translations of the modal coordinates) plus
    `offsets` (Z,) tangential metres (balls), the cage centre and tilt (orbit)."""
    rc, X, S, Phi, interface = fake_cage(tmp_path, quadratic)
    run = write_run(tmp_path / "run.h5", cage="flexible" if cage else "rigid", n=n)
    t = np.arange(n) * DT
    rng = np.random.default_rng(5)
    q = rng.normal(size=(n, M))
    az = 2 * np.pi * np.arange(Z) / Z
    with h5py.File(run, "r+") as f:
        o = f["outputs"]
        if cage:
            o["cage_modal_coordinates_full"] = q
            o["von_mises_max"] = np.array([_vm_by_deviator(S @ qi).max() for qi in q])
            o["von_mises_max_time"] = t - 0.5 * DT
            f.attrs["reduced_cage_file"] = str(rc)
            f.attrs["reduced_cage_hash"] = "0123456789abcdef"
        b = np.zeros((n, Z, 3))
        for k, tk in enumerate(t):
            phi, (by, bz), c = motion(tk)
            d = np.zeros(Z) if offsets is None else offsets
            local = np.stack([np.zeros(Z), R_POCKET * np.cos(az) - d * np.sin(az),
                              R_POCKET * np.sin(az) + d * np.cos(az)], 1)
            if cage:
                local = local + interface[:, :3, :] @ q[k]
            b[k] = c + local @ rotation(phi, by, bz).T
        if balls:
            o["ball_axial_position"] = b[:, :, 0]
            o["ball_radial_position"] = np.hypot(b[:, :, 1], b[:, :, 2])
            o["ball_azimuth"] = np.unwrap(np.arctan2(b[:, :, 2], b[:, :, 1]), axis=0)
        if orbit:
            o["cage_centre"] = np.array([motion(tk)[2] for tk in t])
            o["cage_tilt"] = np.array([motion(tk)[1] for tk in t])
    return run, X, S, Phi, q, b


def _assert_frame_fields(pdata, vm_recorded, S, q, Phi=None):
    """A written frame against the run: its largest von Mises against the recorded maximum (two
    closed forms, two summation orders of S q: von_mises_bound, the largest over the nodes), and
    (Phi given) the displacement against Phi q (another summation order: 2 gamma_m |Phi| |q|
    entrywise, dot_bound)."""
    vm = pdata["von_mises"]
    assert_within(abs(vm.max() - vm_recorded), von_mises_bound(S, q, vm.max()).max(),
                  "frame von Mises maximum", effect=vm_recorded)
    if Phi is not None:
        u = Phi @ q
        assert_within(np.abs(pdata["displacement"] - u), dot_bound(len(q), np.abs(Phi) @ np.abs(q)),
                      "displacement = Phi q", effect=np.abs(u).max())


def xdmf_grids(xdmf: Path):
    """Per time grid: (time, geometry array, {attribute name: (array, Units)}), read from the XML
    and the HDF5 file it names, as any XDMF consumer does."""
    root = ET.parse(xdmf).getroot()
    out = []
    for g in root.iter("Grid"):
        if g.get("GridType") != "Uniform":
            continue

        def load(item):
            name, path = item.text.strip().split(":")
            with h5py.File(xdmf.parent / name, "r") as f:
                return f[path][()]
        geo = load(g.find("Geometry/DataItem"))
        attrs = {a.get("Name"): (load(a.find("DataItem")), a.get("Units")) for a in g.findall("Attribute")}
        out.append((float(g.find("Time").get("Value")), geo, attrs))
    return out


# ---------------------------------------------------------------- geometry helpers

@pytest.mark.parametrize("quadratic", [True, False])
def test_boundary_faces_of_a_cube_are_its_outward_skin(quadratic):
    """The Kuhn cube's 6 tetrahedra: 12 boundary triangles (2 per cube face), outward, and by the
    divergence theorem (1/3)∮ x·n dA = V = 1 exactly; each face's 6 nodes (quadratic) are its
    corners and their midpoints in (a, b, c, ab, bc, ca) order."""
    X, tets10, tets = kuhn_cube()
    faces = boundary_faces(tets10 if quadratic else tets, X)
    assert faces.shape == (12, 6 if quadratic else 3)
    a, b, c = (X[faces[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    n = face_normals(faces, X)
    centroid = (a + b + c) / 3
    # a sum of 12 faces' x·n A / 3 (3 products each): round-off of the absolute terms
    assert_within(abs(np.einsum("ij,ij->i", centroid, n) @ area / 3 - 1.0),
                  dot_bound(12 + 3 + 2, np.einsum("ij,ij->i", np.abs(centroid), np.abs(n)) @ area / 3),
                  "divergence theorem", effect=1.0)
    assert np.all(np.einsum("ij,ij->i", centroid - 0.5, n) > 0)          # away from the cube's centre
    if quadratic:
        for m, (i, j) in zip((3, 4, 5), ((0, 1), (1, 2), (2, 0))):
            assert np.allclose(X[faces[:, m]], 0.5 * (X[faces[:, i]] + X[faces[:, j]]), atol=0)


def test_cage_skin_matches_the_mesh_tags():
    """On the default cage mesh (gmsh, curved 10-node tetrahedra) of the nominal geometry, the
    boundary faces found from the cells alone are the mesh's tagged facets (their corner sets),
    outward: (1/3)∮ x·n dA over the corner triangles equals the volume of the corner tetrahedra
    (the same polyhedron; 1e-12 relative); and the picture's classes agree with the tags: each
    pocket's wall = its facets "pocket_k", the guide surface within "outside", the bore within
    "bore" (flexbearing.mesh.cage_mesh physical groups, an independent labelling by gmsh's geometry)."""
    from types import SimpleNamespace

    import meshio

    from flexbearing.analysis.stress_picture import cage_skin
    from flexbearing.mesh import cage_mesh
    from flexbearing.mesh.cage_geometry import CageGeometry
    g = CageGeometry()
    msh = meshio.read(cage_mesh.cached_cage_mesh(g))
    X = msh.points
    tets10 = np.vstack([c.data for c in msh.cells if c.type == "tetra10"])
    tags = {}
    for c, tag in zip(msh.cells, msh.cell_data["gmsh:physical"]):
        if c.type == "triangle6":
            for corners, t in zip(np.sort(c.data[:, :3], axis=1), tag):
                tags[tuple(corners)] = int(t)
    az = 2 * np.pi * np.arange(g.n_pockets) / g.n_pockets
    rc = SimpleNamespace(vertices=X, tets10=tets10, tets=tets10[:, :4], attrs={"parameters": {"geometry": g.to_dict()}},
                         interface_positions=np.stack([0 * az, g.mean_radius * np.cos(az), g.mean_radius * np.sin(az)], 1))
    skin = cage_skin(rc)
    faces = skin["faces"]
    keys = [tuple(k) for k in np.sort(faces[:, :3], axis=1)]
    assert sorted(keys) == sorted(tags)
    a, b, c = (X[faces[:, i]] for i in range(3))
    flux = np.einsum("ij,ij->", (a + b + c) / 3, 0.5 * np.cross(b - a, c - a)) / 3
    t = X[tets10[:, :4]]
    volume = np.abs(np.einsum("ij,ij->i", t[:, 1] - t[:, 0], np.cross(t[:, 2] - t[:, 0], t[:, 3] - t[:, 0]))).sum() / 6
    # both sides are sums (faces, tets) of triple products of coordinate differences (a
    # difference is one correctly rounded operation): each within gamma_(count + 8) of its
    # absolute terms (2 roundings a cross component, 3 a dot, the centroid 3; Higham §3.1, §4.2)
    def cross_abs(u, v):
        return np.abs(u[:, [1, 2, 0]] * v[:, [2, 0, 1]]) + np.abs(u[:, [2, 0, 1]] * v[:, [1, 2, 0]])
    flux_abs = np.einsum("ij,ij->", np.abs(a + b + c) / 3, 0.5 * cross_abs(b - a, c - a)) / 3
    vol_abs = np.einsum("ij,ij->", np.abs(t[:, 1] - t[:, 0]),
                        cross_abs(t[:, 2] - t[:, 0], t[:, 3] - t[:, 0])) / 6
    assert_within(abs(flux - volume), gamma(len(faces) + 8) * flux_abs + gamma(len(t) + 8) * vol_abs,
                  "divergence theorem on the cage skin", effect=volume)
    tag = np.array([tags[k] for k in keys])
    for k in range(g.n_pockets):
        assert np.array_equal(skin["wall"] & (skin["pocket"] == k), tag == cage_mesh.pocket_tag(k))
    assert np.all(skin["outside"][tag == cage_mesh.TAG_GUIDE]) and np.all(skin["bore"][tag == cage_mesh.TAG_BORE])


def _spin_angle_bound(c):
    """Round-off of cage_spin_angle for balls on their pockets' axes placed at c + P A^T with the
    test's rotation (scipy: ~30 roundings an entry, against the writer's; <= 20 more for the
    subtraction, the tilt product and, in a run file, the balls stored as axial/radial/azimuth):
    the local (y, z) of each ball within 2 gamma_50 (R + |c|), so its atan2 within that over R
    (+4 u of libm); the mean direction of 20 equal unit vectors within 2 gamma_20 (+4 u)
    (Higham §3.1)."""
    return 2 * gamma(50) * (1 + np.linalg.norm(c) / R_POCKET) + 2 * gamma(20) + 10 * U


def test_cage_spin_angle_from_the_balls():
    """Balls on their pockets' axes: phi recovered to round-off at any tilt and centre; balls
    moved tangentially in their pockets by up to c: |error| <= c / R (the module's bound)."""
    rng = np.random.default_rng(3)
    az = 2 * np.pi * np.arange(20) / 20
    P = np.stack([np.zeros(20), R_POCKET * np.cos(az), R_POCKET * np.sin(az)], 1)
    for _ in range(20):
        phi, by, bz = rng.uniform(-np.pi, np.pi), *rng.normal(scale=2e-3, size=2)
        c = rng.normal(scale=2e-4, size=3)
        A_tilt = rotation(0.0, by, bz)
        got = field_export.cage_spin_angle(c + P @ rotation(phi, by, bz).T, c, A_tilt, az)
        assert_within(abs(math.remainder(got - phi, 2 * np.pi)), _spin_angle_bound(c), "spin angle",
                      effect=1e-3 / R_POCKET)
        clearance = 2.5e-4
        d = rng.uniform(-clearance, clearance, 20)
        Pd = P + d[:, None] * np.stack([np.zeros(20), -np.sin(az), np.cos(az)], 1)
        got = field_export.cage_spin_angle(c + Pd @ rotation(phi, by, bz).T, c, A_tilt, az)
        assert abs(math.remainder(got - phi, 2 * np.pi)) <= clearance / R_POCKET


def test_parse_series():
    t = np.arange(601) * DT
    assert list(field_export.parse_series("0.29:0.31", t, DT)) == list(range(290, 311))
    assert list(field_export.parse_series("0.29:0.31:5", t, DT)) == [290, 295, 300, 305, 310]
    for bad, msg in (("0.3", "must be T0:T1"), ("a:b", "must be T0:T1"), ("0.3:0.2", "must not exceed"),
                     ("0:0.1:0", "N = 0 must be >= 1"), ("0.7:0.8", r"outside the run \(allowed range"),
                     ("0.1005:0.1006", "no sample")):
        with pytest.raises(InputError, match=msg):
            field_export.parse_series(bad, t, DT)


# ---------------------------------------------------------------- peaks file

def test_peak_frames_have_quadratic_cells_every_node_and_units(tmp_path):
    """von_mises.xdmf of a quadratic mesh: meshio reads tetra10 cells holding every node, each
    frame's maximum over the nodes equals the recorded maximum, every attribute has its SI unit."""
    import meshio
    run, X, S, Phi, q, _ = fake_run(tmp_path)
    xdmf = field_export.write_von_mises_xdmf(run, tmp_path / "rep", "0.005,0.012")
    with h5py.File(run, "r") as f:
        vm_rec = f["outputs/von_mises_max"][...]
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as r:
        points, cells = r.read_points_cells()
        assert [c.type for c in cells] == ["tetra10"]
        assert np.array_equal(np.unique(cells[0].data), np.arange(len(points)))
        for step, k in enumerate((5, 12)):
            tk, pdata, _ = r.read_data(step)
            _assert_frame_fields(pdata, vm_rec[k], S, q[k], Phi)
    for _, _, attrs in xdmf_grids(xdmf):
        assert {name: u for name, (_, u) in attrs.items()} == {"von_mises": "Pa", "displacement": "m"}
    with h5py.File(xdmf.with_suffix(".h5"), "r") as f:
        assert f["von_mises/0"].attrs["unit"] == "Pa" and f["mesh/geometry"].attrs["unit"] == "m"


# ---------------------------------------------------------------- series

def test_series_places_the_cage_and_the_balls_in_the_bearing_frame(tmp_path):
    """write_series over samples 4..16, every 3rd: meshio reads tetra10 cells with every node; per
    frame the von Mises maximum equals the recorded one, the geometry is c + A X with the true
    spin angle (balls on the pocket axes: exact), displacement = A Phi q, displacement_scaled =
    s·displacement; the points are the balls as recorded and the cage centre last."""
    import meshio
    run, X, S, Phi, q, b = fake_run(tmp_path)
    res = field_export.write_series(run, tmp_path / "rep", "0.004:0.016:3", displacement_scale=500.0)
    assert res["notes"] == [] and res["n_frames"] == 5
    samples = [4, 7, 10, 13, 16]
    with h5py.File(run, "r") as f:
        vm_rec = f["outputs/von_mises_max"][...]
    with meshio.xdmf.TimeSeriesReader(str(res["cage"])) as r:
        points, cells = r.read_points_cells()
        assert [c.type for c in cells] == ["tetra10"]
        assert np.array_equal(np.unique(cells[0].data), np.arange(len(points)))
        assert r.num_steps == 5
        for step, k in enumerate(samples):
            tk, pdata, _ = r.read_data(step)
            assert tk == pytest.approx(k * DT, abs=1e-15)
            _assert_frame_fields(pdata, vm_rec[k], S, q[k])
    for (tk, geo, attrs), k in zip(xdmf_grids(res["cage"]), samples):
        phi, (by, bz), c = motion(k * DT)
        A = rotation(phi, by, bz)
        # the writer's rotation (its spin angle from the balls, _spin_angle_bound) against scipy's:
        # the products X A^T (3 terms, ~30 roundings an entry of A) and the turn by d_phi
        geo_bound = (dot_bound(3 + 30, np.abs(X) @ np.abs(A).T + np.abs(c))
                     + np.linalg.norm(X, axis=1)[:, None] * _spin_angle_bound(c))
        assert_within(np.abs(geo - (c + X @ A.T)), geo_bound, "cage geometry", effect=1e-3)
        u = (Phi @ q[k]) @ A.T
        # A Phi q with the writer's rotation matrix against scipy's (Euler angles -> quaternion ->
        # matrix: up to ~30 roundings per entry of A, and 1-4 ulp sin/cos where numpy uses SIMD):
        # round-off of the absolute terms, not a fraction of each (possibly cancelling) component
        bound = dot_bound(Phi.shape[-1] + 3 + 30, (np.abs(Phi) @ np.abs(q[k])) @ np.abs(A).T)
        assert_within(np.abs(attrs["displacement"][0] - u), bound, "A Phi q", effect=np.abs(u).max())
        assert_within(np.abs(attrs["displacement_scaled"][0] - 500.0 * u), 500.0 * bound + 500.0 * U *
                      np.abs(u), "scaled A Phi q", effect=500.0 * np.abs(u).max())
        assert {n: un for n, (_, un) in attrs.items()} == {"von_mises": "Pa", "displacement": "m",
                                                          "displacement_scaled": "m"}
    with meshio.xdmf.TimeSeriesReader(str(res["points"])) as r:
        _, cells = r.read_points_cells()
        assert cells[0].type == "vertex" and len(cells[0].data) == Z + 1
        _, pdata, _ = r.read_data(0)
        assert list(pdata["ball"]) == [1, 2, 3, 4, 0]
    # the balls as the run stores them (axial, radial = hypot, azimuth = unwrapped atan2) and back:
    # <= 10 roundings on |b|, and the azimuth's own rounding u |az| (unwrapped: it grows) times r
    azimuth = np.unwrap(np.arctan2(b[:, :, 2], b[:, :, 1]), axis=0)
    for (tk, geo, attrs), k in zip(xdmf_grids(res["points"]), samples):
        r = np.hypot(b[k, :, 1], b[k, :, 2])
        assert_within(np.abs(geo[:Z] - b[k]),
                      (2 * gamma(10) * np.linalg.norm(b[k], axis=1) + 2 * U * np.abs(azimuth[k]) * r)[:, None],
                      "ball centres", effect=1e-3)
        assert np.abs(geo[Z] - motion(k * DT)[2]).max() < 1e-15
        assert attrs["diameter"][1] == "m"
    meta = json.loads(res["json"].read_text())
    assert meta["frame"].startswith("bearing frame") and meta["displacement_scale"] == 500.0
    assert [fr["recorded_von_mises_max"] for fr in meta["cage"]["frames"]] == list(vm_rec[samples])


def test_series_auto_scale_and_balls_off_their_pocket_axes(tmp_path):
    """Balls moved tangentially by up to 0.2 mm: the placed cage is off by at most the bound
    (offset / R) times the distance from the axis; the auto scale draws the largest displacement
    as 0.5–1 % of the outside diameter (a 1-2-5 step below 1 %)."""
    off = np.array([2e-4, -1e-4, 0.5e-4, 1.5e-4])
    run, X, S, Phi, q, b = fake_run(tmp_path, offsets=off)
    res = field_export.write_series(run, tmp_path / "rep", "0:0.02:4")
    bound = np.abs(off).max() / R_POCKET * np.hypot(X[:, 1], X[:, 2]).max()
    for tk, geo, attrs in xdmf_grids(res["cage"]):
        phi, (by, bz), c = motion(tk)
        assert np.abs(geo - (c + X @ rotation(phi, by, bz).T)).max() <= bound
    meta = json.loads(res["json"].read_text())
    umax = max(np.linalg.norm(a["displacement"][0], axis=1).max() for *_, a in xdmf_grids(res["cage"]))
    share = meta["displacement_scale"] * umax / (2 * np.hypot(X[:, 1], X[:, 2]).max())
    assert 0.004 < share <= 0.01 * (1 + 1e-12)


def test_series_says_what_the_run_did_not_record(tmp_path):
    """No kinematics: the cage alone in its body frame (geometry = X) with a note naming the output;
    no cage_orbit: the centre taken at the origin, with a note; a rigid cage: the points alone;
    neither: refused."""
    for d in "abcd":
        (tmp_path / d).mkdir()
    run, X, *_ = fake_run(tmp_path / "a", balls=False)
    res = field_export.write_series(run, tmp_path / "a" / "rep", "0:0.01")
    assert res["points"] is None and "kinematics" in res["notes"][0]
    assert all(np.array_equal(geo, X) for _, geo, _ in xdmf_grids(res["cage"]))
    run, *_ = fake_run(tmp_path / "b", orbit=False)
    res = field_export.write_series(run, tmp_path / "b" / "rep", "0:0.01")
    assert res["cage"] and res["points"] and "cage_orbit" in res["notes"][0]
    run, *_ = fake_run(tmp_path / "c", cage=False)
    res = field_export.write_series(run, tmp_path / "c" / "rep", "0:0.01")
    assert res["cage"] is None and res["points"] and "cage_modal_coordinates_full" in res["notes"][0]
    run, *_ = fake_run(tmp_path / "d", cage=False, balls=False)
    with pytest.raises(InputError, match="neither the cage's modal coordinates nor the balls"):
        field_export.write_series(run, tmp_path / "d" / "rep", "0:0.01")


def test_series_size_is_capped(tmp_path, monkeypatch):
    """Beyond SERIES_MAX_BYTES the series is refused with the every-N-th hint (here a cap of 8
    frames of the 27-node cube: 21 frames need N >= 3); a scale <= 0 is refused."""
    monkeypatch.setattr(field_export, "SERIES_MAX_BYTES", 8 * 27 * 80.0)
    run, *_ = fake_run(tmp_path)
    with pytest.raises(InputError, match=r"--series 0:0.02: 21 frames .* N >= 3"):
        field_export.write_series(run, tmp_path / "rep", "0:0.02")
    assert field_export.write_series(run, tmp_path / "rep", "0:0.02:3")["n_frames"] == 7
    with pytest.raises(InputError, match="--displacement-scale"):
        field_export.write_series(run, tmp_path / "rep", "0:0.01", displacement_scale=-1.0)


# ---------------------------------------------------------------- the real thing (slow)



@pytest.mark.slow
def test_report_series_of_a_real_flexible_run(paper_reduced_cage, short_flexible_impact, tmp_path):
    """A 3 ms run of the paper bearing with the flexible cage (default reduced cage) through a
    50 kN impact, then `flexbearing report --series 0:0.003`. Read back with meshio: tetra10 cells
    holding every node, each frame's von Mises maximum = the run's von_mises_max of that sample
    (1e-9 relative), units on every attribute; the balls where the run put them; the picture's
    maximum = the run's largest von_mises_max at the node the run recorded. With ParaView
    installed (pvpython and xvfb-run on PATH), docs/paraview_open.py opens the series and finds
    the same data ranges (its exit status) and saves the screenshot."""
    import meshio

    from flexbearing.cli.main import main
    from flexbearing.simulation.run import run_scene
    run = tmp_path / "run.h5"
    record = ["pocket_force", "cage_speed", "von_mises", "kinematics", "cage_orbit"]
    run_scene(short_flexible_impact("short_flexible_series", record), run, quiet=True)
    out = tmp_path / "report"
    assert main(["report", str(run), "-o", str(out), "--series", "0:0.003", "--quiet"]) == 0
    with h5py.File(run, "r") as f:
        o = f["outputs"]
        vm_rec, node_rec = o["von_mises_max"][...], o["von_mises_max_vertex"][...]
        psi, rb, xb = o["ball_azimuth"][...], o["ball_radial_position"][...], o["ball_axial_position"][...]
    n_nodes = len(paper_reduced_cage.vertices)
    with meshio.xdmf.TimeSeriesReader(str(out / "series_cage.xdmf")) as r:
        points, cells = r.read_points_cells()
        assert [c.type for c in cells] == ["tetra10"] and len(points) == n_nodes
        assert np.array_equal(np.unique(cells[0].data), np.arange(n_nodes))
        assert r.num_steps == len(vm_rec) == 31
        for k in range(r.num_steps):
            tk, pdata, _ = r.read_data(k)
            assert pdata["von_mises"].max() == pytest.approx(vm_rec[k], rel=1e-9)
            assert int(pdata["von_mises"].argmax()) == node_rec[k]
    for _, geo, attrs in xdmf_grids(out / "series_cage.xdmf"):
        assert {n: u for n, (_, u) in attrs.items()} == {"von_mises": "Pa", "displacement": "m",
                                                         "displacement_scaled": "m"}
    ball = np.stack([xb, rb * np.cos(psi), rb * np.sin(psi)], -1)
    for k, (_, geo, _) in enumerate(xdmf_grids(out / "series_points.xdmf")):
        assert np.abs(geo[:-1] - ball[k]).max() < 1e-15
    facts = json.loads((out / "von_mises_peak.json").read_text())
    k = int(np.argmax(vm_rec))
    assert facts["sample"] == k and facts["node"] == node_rec[k]
    assert facts["von_mises_max"] == pytest.approx(vm_rec[k], rel=1e-9)
    assert "von_mises_peak.png" in (out / "report.md").read_text()
    with meshio.xdmf.TimeSeriesReader(str(out / "von_mises.xdmf")) as r:
        _, cells = r.read_points_cells()
        assert cells[0].type == "tetra10"
    pv = shutil.which("pvpython")
    if pv and shutil.which("xvfb-run"):
        script = Path(__file__).resolve().parents[1] / "docs" / "paraview_open.py"
        done = subprocess.run(["xvfb-run", "-a", pv, str(script), str(out), "--png", str(tmp_path / "pv.png")],
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stdout + done.stderr
        assert (tmp_path / "pv.png").stat().st_size > 10_000
