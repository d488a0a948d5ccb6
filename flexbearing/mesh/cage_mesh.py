"""The cage as a tagged tetrahedral mesh (gmsh OpenCASCADE).

Construction: the ring's cross-section (bore, outside cylinder, optional central relief between
two guide lands, optional 45° edge chamfers, the bore edges' own size when bore_chamfer is set) is drawn in the x–r half plane and revolved 360°
about the bearing axis x; Z radial cylinders of diameter Dp are cut out at azimuths
theta_k = 2*pi*k/Z (from +y towards +z), centred on the mid-plane x = 0. The revolution seam
is turned half a pocket pitch away from pocket 0 so no pocket wall lies on it.

Mesh: global element size `size`, refined to `pocket_size` on and near the pocket walls
(gmsh Distance + Threshold fields), because the thin side rails and bridges between pockets
carry the bending of the cage. Order 2 means a *curved* quadratic mesh (gmsh setOrder(2)):
mid-side nodes sit on the true pocket cylinders, which is what P2 elasticity needs to converge
(a straight-sided quadratic mesh facets the pockets and runs 0.1–2 % stiff).

Physical groups (names and tags are part of the API that fem_cage and coupling rely on):
  volume "cage" = 1; surfaces "pocket_00".."pocket_{Z-1:02d}" = 101 + k; "guide" = 200
  (the guided surface: for cage.guidance = "outer" the outside cylinder, or the two lands when
  relieved; for "inner" the bore; none for "balls");
  "bore" = 201 (when it does not guide), "side_left" (x = -w/2) = 202, "side_right" (x = +w/2) = 203,
  "other" = 204 (relief floor and walls, chamfers), only when present; "outside" = 205 (the
  outside cylinder when it does not guide: "inner" and "balls").
Spherical pockets (cage.pocket_shape): spheres of diameter Dp centred on the pocket-centre
circle instead of the radial cylinders; conical pockets: radial cones tangent to that sphere
(half-angle cage.pocket_cone_angle; CageGeometry.cone_radius); elliptical pockets: radial
cylinders of elliptical section, Dp along x and cage.pocket_circumferential_diameter around.
"""
from __future__ import annotations

import math
from pathlib import Path
import errno
import json

import numpy as np

from .cage_geometry import CageGeometry
from flexbearing.common.validation import InputError, require_range
from . import quality as Q
from flexbearing.common.safe_files import atomic_output, write_text_atomic
from flexbearing.common.cache import cache_dir, content_hash, file_sha256, msh_is_whole

# Converged default: Lagrange P3 on a curved quadratic mesh of uniform 4 mm elements.
# Stress (benchmarks/results/cage_stress_convergence.md): the maximum von Mises stress of every
# load case the dynamics apply (spin, a pocket force in each direction, the land force) within
# 5 % of the extrapolated value at 4 mm, not at 5 mm (pocket radial force -5.1 %, and the 5 mm
# mesh needed two inverted cells repaired). Frequencies (flexbearing/fem_cage/mesh_study.py,
# benchmarks/results/modes_mesh_study.*): 5 -> 4 mm moves them <= 0.24 %. P3 rather than
# P2: P2 needs 2-3x the dofs for the same frequencies, and no uniform P2 mesh up to 138k dofs
# brings the stresses within 5 %.
DEFAULT_MESH_SIZE = 4.0e-3
DEFAULT_POCKET_SIZE = 4.0e-3
DEFAULT_ORDER = 2
DEFAULT_DEGREE = 3
# Distance (in global element sizes) over which the size grows from pocket_size to size.
REFINE_GROWTH = 1.5
# Version of the meshing procedure, in every mesh cache key (and the reduced cage's): 2 = curved
# elements checked and repaired (flexbearing.mesh.quality), so no version-1 mesh (with inverted elements) is
# ever reused.
MESH_VERSION = 2
# Half-width of the local refinement zone around a pocket's wall (stress studies), m: it covers
# the wall, its edges, the bars to the next pockets (2.7-5.4 mm wide) and the side rails (2.9 mm).
LOCAL_ZONE = 3.0e-3
# Smallest chamfer drawn, m (smaller ones are drawn as sharp edges; see _profile_points).
MIN_FEATURE = 1e-6

TAG_CAGE = 1
TAG_POCKET0 = 101
TAG_GUIDE = 200
TAG_BORE = 201
TAG_SIDE_LEFT = 202
TAG_SIDE_RIGHT = 203
TAG_OTHER = 204
TAG_OUTSIDE = 205


def pocket_tag(k: int) -> int:
    return TAG_POCKET0 + k


def pocket_name(k: int) -> str:
    return f"pocket_{k:02d}"


def _check_sizes(geometry: CageGeometry, size: float, order: int, pocket_size: float | None,
                 local=None):
    # Upper bound: one element across the cage width; lower bound: beyond ~0.5 mm the mesh has
    # millions of dofs, far past convergence (mesh study), and would exhaust memory.
    require_range("mesh.size", size, 0.5e-3, geometry.width, unit="m")
    if pocket_size is not None:
        require_range("mesh.pocket_size", pocket_size, 0.25e-3, size, unit="m")
    if order not in (1, 2):
        raise InputError(f"mesh.order = {order!r} is outside the allowed set {{1, 2}}")
    if local is not None:
        pockets, h = local
        for k in pockets:
            if int(k) != k or not 0 <= k < geometry.n_pockets:
                raise InputError(f"mesh.local pocket = {k!r} is outside the allowed range "
                                 f"[0, {geometry.n_pockets - 1}]")
        require_range("mesh.local size", h, 0.1e-3, size, unit="m")


def _profile_points(g: CageGeometry, pockets: bool = True) -> list[tuple[float, float]]:
    """Closed polygon (x, r) of the ring's cross-section, counter-clockwise in the x–r plane."""
    w2, ri, ro = 0.5 * g.width, g.inner_radius, g.outer_radius
    # Chamfers below MIN_FEATURE are drawn as absent: OCC cannot make the sub-tolerance edge
    # ("Could not create line"), and a 1 µm break is below any machining tolerance.
    c = g.chamfer if g.chamfer >= MIN_FEATURE else 0.0
    cb = g.bore_edge_chamfer                 # bore edges: bore_chamfer, or chamfer when unset
    cb = cb if cb >= MIN_FEATURE else 0.0
    pts = [(-w2 + cb, ri), (w2 - cb, ri)] if cb > 0 else [(-w2, ri), (w2, ri)]
    if cb > 0:
        pts += [(w2, ri + cb)]
    pts += [(w2, ro - c), (w2 - c, ro)] if c > 0 else [(w2, ro)]
    if g.relief_depth > 0 and g.relief_width > 0:
        wr2, rr = 0.5 * g.relief_width, ro - g.relief_depth
        pts += [(wr2, ro), (wr2, rr), (-wr2, rr), (-wr2, ro)]
    pts += [(-w2 + c, ro), (-w2, ro - c)] if c > 0 else [(-w2, ro)]
    if cb > 0:
        pts += [(-w2, ri + cb)]
    return pts


def _build_model(g: CageGeometry, size: float, order: int, pocket_size: float | None,
                 with_pockets: bool = True, verbose: bool = False, local=None):
    """Build geometry + mesh in the current gmsh model; return physical name -> tag."""
    import gmsh

    gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
    occ = gmsh.model.occ
    pts = [occ.addPoint(x, r, 0.0) for x, r in _profile_points(g)]
    lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    face = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    out = occ.revolve([(2, face)], 0, 0, 0, 1, 0, 0, 2 * math.pi)
    ring = [dt for dt in out if dt[0] == 3]
    Z = g.n_pockets
    # Seam (profile drawn at azimuth 0 = +y) turned to half a pocket pitch.
    occ.rotate(ring, 0, 0, 0, 1, 0, 0, math.pi / Z)
    if with_pockets:
        margin = 0.5 * (g.outer_radius - g.inner_radius)
        r0, length = g.inner_radius - margin, (g.outer_radius - g.inner_radius) + 2 * margin
        tools = []
        rc = 0.5 * g.pocket_centre_diameter
        for th in g.pocket_azimuths():
            cy, cz = math.cos(th), math.sin(th)
            if g.pocket_shape == "spherical":
                # OCC's sphere has its poles on its z axis: turned radial (rotation about x by
                # theta − pi/2 takes z to (0, cos, sin)), they fall outside the ring and are cut
                # away; left tangential they sit on the pocket wall, whose periodic patch with
                # two degenerate edges gmsh 4.8 cannot mesh
                ball = occ.addSphere(0.0, 0.0, 0.0, 0.5 * g.pocket_diameter)
                occ.rotate([(3, ball)], 0, 0, 0, 1, 0, 0, th - 0.5 * math.pi)
                occ.translate([(3, ball)], 0.0, rc * cy, rc * cz)
                tools.append((3, ball))
            elif g.pocket_shape == "elliptical":  # the section (A along x, B around) swept along the axis
                # OCC's disk wants its major radius along x: B along x, turned to y, A along x
                disk = occ.addDisk(0.0, 0.0, 0.0, 0.5 * g.pocket_circumferential_diameter, 0.5 * g.pocket_diameter)
                occ.rotate([(2, disk)], 0, 0, 0, 0, 0, 1, 0.5 * math.pi)
                occ.rotate([(2, disk)], 0, 0, 0, 1, 0, 0, th - 0.5 * math.pi)    # normal z -> the axis
                occ.translate([(2, disk)], 0.0, r0 * cy, r0 * cz)
                swept = occ.extrude([(2, disk)], 0.0, length * cy, length * cz)
                tools.extend(dt for dt in swept if dt[0] == 3)
            elif g.pocket_shape == "conical":     # the cone from r0 to r0 + length along the axis
                tools.append((3, occ.addCone(0.0, r0 * cy, r0 * cz, 0.0, length * cy, length * cz,
                                             g.cone_radius(r0 - rc), g.cone_radius(r0 + length - rc))))
            else:
                tools.append((3, occ.addCylinder(0.0, r0 * cy, r0 * cz, 0.0, length * cy, length * cz,
                                                 0.5 * g.pocket_diameter)))
        ring, _ = occ.cut(ring, tools)
    occ.synchronize()
    vols = [t for d, t in ring if d == 3]
    if len(vols) != 1:
        raise InputError(f"cage geometry produced {len(vols)} solids instead of one "
                         "(pockets cut the ring apart): reduce cage.pocket_diameter")

    # Classify the boundary surfaces geometrically (robust to OCC's face numbering and to
    # faces that the pockets split into pieces): sample points of each face and test which
    # analytic surface they all lie on.
    groups: dict[str, list[int]] = {}
    ri, ro, w2 = g.inner_radius, g.outer_radius, 0.5 * g.width
    tol = 1e-6 * ro
    azim = g.pocket_azimuths()
    for _, s in gmsh.model.getBoundary([(3, vols[0])], oriented=False):
        P = _sample_face(s)
        x, rho = P[:, 0], np.hypot(P[:, 1], P[:, 2])
        name = "other"
        if with_pockets:
            th = float(np.arctan2(P[:, 2].mean(), P[:, 1].mean()) % (2 * math.pi))
            k = min(range(Z), key=lambda j: abs(math.remainder(th - azim[j], 2 * math.pi)))
            axis = np.array([0.0, math.cos(azim[k]), math.sin(azim[k])])
            wall = 0.5 * g.pocket_diameter
            if g.pocket_shape == "spherical":     # distance to the sphere's centre
                d_axis = np.linalg.norm(P - 0.5 * g.pocket_centre_diameter * axis, axis=1)
            else:                                 # distance to the cylinder's (cone's) axis
                d_axis = np.linalg.norm(P - np.outer(P @ axis, axis), axis=1)
                if g.pocket_shape == "conical":
                    wall = g.cone_radius(P @ axis - 0.5 * g.pocket_centre_diameter)
                elif g.pocket_shape == "elliptical":  # the ellipse's level (x/A)² + (t/B)² = 1, scaled by A
                    tang = np.array([0.0, -axis[2], axis[1]])
                    lev = np.hypot(P[:, 0] / wall, (P @ tang) / (0.5 * g.pocket_circumferential_diameter))
                    d_axis = wall * lev
            if np.all(np.abs(d_axis - wall) < tol):
                name = pocket_name(k)
        if name == "other":
            if np.all(np.abs(x + w2) < tol):
                name = "side_left"
            elif np.all(np.abs(x - w2) < tol):
                name = "side_right"
            elif np.all(np.abs(rho - ro) < tol):
                name = "guide" if g.guidance == "outer" else "outside"
            elif np.all(np.abs(rho - ri) < tol):
                name = "guide" if g.guidance == "inner" else "bore"
        groups.setdefault(name, []).append(s)
    if with_pockets and sum(1 for n in groups if n.startswith("pocket_")) != Z:
        raise RuntimeError("cage_mesh: could not find one wall per pocket")

    return tag_and_mesh(vols, groups, Z, size, order, pocket_size if with_pockets else None,
                        local if with_pockets else None)


def tag_and_mesh(vols, groups: dict, Z: int, size: float, order: int, pocket_size: float | None,
                 local=None) -> dict:
    """Physical groups of the classified boundary faces `groups` (name -> surface tags, names
    of the module docstring) and the cage volume(s), then the mesh: `size` everywhere,
    `pocket_size` on the pocket walls, a `local` refinement zone, curved order 2. Used by the
    parametric cage and by the CAD cage (flexbearing.mesh.cad_cage). Returns name -> tag."""
    import gmsh
    names = {"cage": TAG_CAGE}
    gmsh.model.addPhysicalGroup(3, vols, TAG_CAGE)
    gmsh.model.setPhysicalName(3, TAG_CAGE, "cage")
    fixed = {"guide": TAG_GUIDE, "bore": TAG_BORE, "side_left": TAG_SIDE_LEFT,
             "side_right": TAG_SIDE_RIGHT, "other": TAG_OTHER, "outside": TAG_OUTSIDE}
    for k in range(Z):
        fixed[pocket_name(k)] = pocket_tag(k)
    for name, surfs in sorted(groups.items()):
        tag = fixed[name]
        gmsh.model.addPhysicalGroup(2, surfs, tag)
        gmsh.model.setPhysicalName(2, tag, name)
        names[name] = tag

    # Mesh size: `size` everywhere, `pocket_size` on the pocket walls, growing linearly to
    # `size` over one global element size away from them.
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.1 * (pocket_size or size))
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    pocket_surfs = [s for n, ss in groups.items() if n.startswith("pocket_") for s in ss]
    f = gmsh.model.mesh.field
    fields = []

    def threshold(surfs, lc, dist_min, dist_max):
        fd = f.add("Distance")
        f.setNumbers(fd, "FacesList", surfs)
        f.setNumber(fd, "NNodesByEdge", 60)
        ft = f.add("Threshold")
        f.setNumber(ft, "IField", fd)
        f.setNumber(ft, "LcMin", lc)
        f.setNumber(ft, "LcMax", size)
        f.setNumber(ft, "DistMin", dist_min)
        f.setNumber(ft, "DistMax", dist_max)
        fields.append(ft)

    if pocket_size is not None and pocket_size < size:
        threshold(pocket_surfs, pocket_size, 0.25 * pocket_size, 0.25 * pocket_size + REFINE_GROWTH * size)
    if local is not None:
        # a refinement zone around some pockets (stress convergence studies): element size h within
        # LOCAL_ZONE of their walls: the pockets, the bars between them and the rails
        pockets, h = local
        walls = [s_ for k in pockets for s_ in groups[pocket_name(int(k))]]
        threshold(walls, h, LOCAL_ZONE, LOCAL_ZONE + REFINE_GROWTH * size)
    if len(fields) == 1:
        f.setAsBackgroundMesh(fields[0])
    elif fields:
        fm = f.add("Min")
        f.setNumbers(fm, "FieldsList", fields)
        f.setAsBackgroundMesh(fm)
    # Resolve the curvature of bore, outside and pockets (elements per 2*pi of arc).
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.model.mesh.generate(3)
    if order == 2:
        gmsh.model.mesh.setOrder(2)          # curved: mid-side nodes on the CAD surfaces
    return names


def _validate_and_repair(fe_degree: int = DEFAULT_DEGREE) -> dict:
    """Check every tetrahedron of the current gmsh model (flexbearing.mesh.quality) and flatten the curved
    ones below MIN_JACOBIAN_RATIO (quality.repair_curved_elements); refuse the mesh if anything is
    still invalid. Returns {"quality": summary after, "repair": log}.

    Why here: gmsh's curving (setOrder(2)) puts the mid-side nodes of thin slivers that touch a
    curved surface on that surface and can invert them (the paper cage at 5 mm: cells 4467/4468,
    det J < 0 at every Gauss point); gmsh 4.8's own high-order optimisers do not fix them
    (measured: "HighOrder" fails, "HighOrderElastic" leaves min det J / det J(centroid) = -0.002,
    benchmarks/results/mesh_quality.md)."""
    import gmsh
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.asarray(coords).reshape(-1, 3)
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags] = np.arange(len(tags))
    types = gmsh.model.mesh.getElementTypes(3)
    t10 = gmsh.model.mesh.getElementType("Tetrahedron", 2)
    t4 = gmsh.model.mesh.getElementType("Tetrahedron", 1)
    et = t10 if t10 in types else t4
    _, enodes = gmsh.model.mesh.getElementsByType(et)
    n = 10 if et == t10 else 4
    cells = index[np.asarray(enodes, dtype=np.int64).reshape(-1, n)]
    if n == 10:
        cells = cells[:, GMSH_TO_VTK_TET10]
    Xr, log = Q.repair_curved_elements(X, cells, Q.MIN_JACOBIAN_RATIO, fe_degree)
    moved = np.flatnonzero(np.any(Xr != X, axis=1))
    for i in moved:
        gmsh.model.mesh.setNode(int(tags[i]), Xr[i].tolist(), [])
    q = Q.mesh_quality(Xr, cells, fe_degree)
    Q.require_valid(q, Q.MIN_JACOBIAN_RATIO, "cage mesh after repair")
    return {"quality": q.summary(), "repair": log.as_dict()}


# gmsh's 10-node tetrahedron lists the edges (2,3) and (1,3) the other way round from VTK/meshio
GMSH_TO_VTK_TET10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]


def _sample_face(tag: int, m: int = 5) -> np.ndarray:
    """m x m points of a face's parametric domain mapped to 3-D and then projected onto the
    face (parametric points outside a trimmed face would otherwise be off the solid)."""
    import gmsh
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    u = np.linspace(lo[0], hi[0], m + 2)[1:-1]
    v = np.linspace(lo[1], hi[1], m + 2)[1:-1]
    uv = np.array([(a, b) for a in u for b in v]).ravel()
    return np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3)


def _write(path: Path):
    import gmsh
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    path.parent.mkdir(parents=True, exist_ok=True)
    # Written atomically (a unique temporary beside it, renamed; removed on any failure): a
    # concurrent reader of the cache never sees half a file; permissions those of the umask
    # and only when whole: gmsh does not report a write that a full disk cut short, so the
    # file's end is checked before the rename (a truncated mesh never reaches the cache)
    with atomic_output(path, suffix=".msh") as tmp:
        gmsh.write(str(tmp))
        if not msh_is_whole(tmp):
            raise OSError(errno.EIO, f"the mesh gmsh wrote is incomplete ({tmp.stat().st_size:,} bytes, no "
                          f"$End line at its end: is the disk full?); nothing was written", str(path))


def build_cage_mesh(geometry: CageGeometry, size: float, order: int, path,
                    pocket_size: float | None = None, verbose: bool = False, local=None,
                    repair: bool = True) -> Path:
    """Mesh the cage and write a gmsh .msh (v4.1) to `path`; return the path.

    size: global element size, m; pocket_size: element size on the pocket walls, m (None = size);
    order: 1 (linear tetrahedra) or 2 (curved quadratic tetrahedra, gmsh setOrder(2));
    local: None, or (pockets, element size h m): a refinement zone of size h within LOCAL_ZONE of
    the walls of those pockets (stress convergence studies, flexbearing.verification.stress_study).
    Every mesh is checked and its badly curved elements repaired (_validate_and_repair); the
    quality and the repair are written beside it (quality_path). repair=False writes gmsh's mesh
    as it is (only for studies of what bad elements do: flexbearing.fem_cage.elasticity refuses to read it).
    """
    geometry.validate()
    _check_sizes(geometry, size, order, pocket_size, local)
    return _mesh_to_file(geometry, size, order, Path(path), pocket_size, True, verbose, local, repair)


def build_ring_mesh(geometry: CageGeometry, size: float, order: int, path,
                    verbose: bool = False) -> Path:
    """A plain ring (the cage's cross-section revolved, no pockets): the analytic-check body."""
    _check_sizes(geometry, size, order, None)
    return _mesh_to_file(geometry, size, order, Path(path), None, False, verbose)


def _mesh_to_file(geometry, size, order, path, pocket_size, with_pockets, verbose, local=None,
                  repair: bool = True) -> Path:
    import gmsh
    from flexbearing.common.fe_stack import gmsh_initialize
    gmsh_initialize(gmsh)  # gmsh 4.8 has no isInitialized(): own the session for this call
    try:
        gmsh.model.add("cage")
        _build_model(geometry, size, order, pocket_size, with_pockets, verbose, local)
        report = _validate_and_repair() if repair else None
        _write(path)
    finally:
        gmsh.finalize()
    if report is not None:
        write_quality(path, report)
    return path


def write_quality(msh_path, report: dict) -> Path:
    """The quality sidecar of a mesh just written (quality_path), with the mesh's sha256
    ("msh_sha256": what verified_mesh checks), written by temporary file and rename (a link
    planted at its name is replaced, never written through)."""
    return write_text_atomic(quality_path(msh_path), json.dumps({**report, "msh_sha256": file_sha256(msh_path)},
                                                                indent=1))


def mesh_digest(msh_path) -> str | None:
    """The sha256 of a mesh that verified_mesh accepts, else None."""
    p, side = Path(msh_path), quality_path(msh_path)
    try:
        if p.is_symlink() or not p.is_file() or side.is_symlink():
            return None
        rec = json.loads(side.read_text(encoding="utf-8"))
        have = file_sha256(p)
        return have if isinstance(rec, dict) and rec.get("msh_sha256") == have else None
    except (OSError, ValueError):
        return None


def verified_mesh(msh_path) -> bool:
    """True when a cached mesh is whole and the one built for its key: the file exists (not a
    link) and its sha256 is the one its quality sidecar recorded when it was built. False (the
    caller builds it again, over it) for a missing, truncated, swapped or edited mesh, or one
    without a digest (cached before the digest was kept)."""
    return mesh_digest(msh_path) is not None


def quality_path(msh_path) -> Path:
    """The sidecar JSON beside a mesh built here: its quality and what the repair changed."""
    p = Path(msh_path)
    return p.with_name(p.stem + ".quality.json")


def mesh_quality_of(msh_path, fe_degree: int = DEFAULT_DEGREE) -> dict:
    """{"quality": ..., "repair": ...} of a mesh: the sidecar written when it was built, else
    computed from the file (no repair information then)."""
    side = quality_path(msh_path)
    if side.exists():
        return json.loads(side.read_text())
    return {"quality": Q.mesh_file_quality(msh_path, fe_degree).summary(), "repair": None}


def mesh_key(geometry: CageGeometry, size: float, order: int, pocket_size: float | None,
             kind: str = "cage", local=None) -> dict:
    key = {"kind": kind, "geometry": geometry.to_dict(), "size": float(size), "order": int(order),
           "pocket_size": None if pocket_size is None else float(pocket_size),
           "version": MESH_VERSION}
    if local is not None:
        key["local"] = [sorted(int(k) for k in local[0]), float(local[1]), LOCAL_ZONE]
    return key


def cache_path(geometry: CageGeometry, size: float, order: int, pocket_size: float | None,
               local=None) -> Path:
    key = mesh_key(geometry, size, order, pocket_size, local=local)
    return cache_dir() / "meshes" / f"{content_hash(key)}.msh"


def cached_cage_mesh(geometry: CageGeometry, size: float = DEFAULT_MESH_SIZE,
                     order: int = DEFAULT_ORDER, pocket_size: float | None = DEFAULT_POCKET_SIZE,
                     local=None) -> Path:
    """build_cage_mesh into cache_dir()/meshes/<content_hash>.msh, reused when present."""
    geometry.validate()
    _check_sizes(geometry, size, order, pocket_size, local)
    path = cache_path(geometry, size, order, pocket_size, local)
    if not verified_mesh(path):
        build_cage_mesh(geometry, size, order, path, pocket_size, local=local)
    return path


def cached_ring_mesh(geometry: CageGeometry, size: float, order: int = DEFAULT_ORDER) -> Path:
    path = cache_dir() / "meshes" / f"{content_hash(mesh_key(geometry, size, order, None, 'ring'))}.msh"
    if not path.exists():
        build_ring_mesh(geometry, size, order, path)
    return path
