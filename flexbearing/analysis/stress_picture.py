"""A picture of the cage's von Mises field at the run's maximum, for the report (matplotlib only).

The field is the one ParaView gets (flexbearing.analysis.field_export.nodal_field): sigma_vM at every
geometry node of the reduced cage's mesh, from the recorded full-basis modal coordinates of the
sample interval with the run's largest von_mises_max, at the integrator step where it occurred.
Its maximum over the nodes is that recorded maximum; the picture marks and labels it.

The cage's skin is drawn unrolled, three panels:

    outside surface   boundary faces with outward normal n . e_r > 1/2    azimuth theta vs axial x
    bore              boundary faces with n . e_r < -1/2                   azimuth theta vs axial x
    one pocket wall   the pocket whose wall holds the highest nodal stress: angle alpha about the
                      pocket's (radial) axis vs the radial position r along it

theta = atan2(z, y) (the frame of flexbearing.mesh.cage_geometry: pocket k at 360 k / Z degrees), drawn from
-180/Z to 360 - 180/Z degrees so every pocket is whole; alpha = atan2(t, x), t the tangential
offset from the pocket axis (alpha = 0 towards +x, 90° towards increasing theta). Chamfers (45°)
fall into the outside or bore panels; the side faces (n = ±e_x) are not drawn (a maximum there is
still labelled). Pockets show as holes. Each boundary face of a 10-node tetrahedron is a 6-node
triangle, drawn as its 4 linear sub-triangles with the nodal values interpolated linearly
(Gouraud shading), so every nodal value, the maximum included, is drawn where it is.
Boundary faces: the tetrahedron faces that belong to one cell only; outward: away from the
cell's fourth vertex.
"""
from __future__ import annotations

import json
import math
from collections import namedtuple
from pathlib import Path

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.analysis.field_export import (_require_modal_coordinates, nodal_field, open_reduced_cage)
from flexbearing.simulation.results import opened
from flexbearing.analysis.plots import plot_style

PICTURE = "von_mises_peak.png"

# Faces of a VTK tetra10 (corners 0-3; edge nodes 4:(0,1) 5:(1,2) 6:(2,0) 7:(0,3) 8:(1,3) 9:(2,3)):
# (a, b, c, ab, bc, ca), with the opposite corner
_FACES10 = np.array([[0, 1, 2, 4, 5, 6], [0, 1, 3, 4, 8, 7], [1, 2, 3, 5, 9, 8], [2, 0, 3, 6, 7, 9]])
_OPPOSITE = np.array([3, 2, 0, 1])
# 6-node triangle (a, b, c, ab, bc, ca) -> 4 linear sub-triangles
_SUB = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])


def boundary_faces(cells: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Boundary faces of a tetrahedral mesh, outward: (F, 6) node indices (a, b, c, ab, bc, ca) for
    10-node cells, (F, 3) for 4-node cells."""
    cells = np.asarray(cells)
    quadratic = cells.shape[1] == 10
    faces = cells[:, _FACES10 if quadratic else _FACES10[:, :3]]          # (Nc, 4, k)
    opp = cells[:, _OPPOSITE]                                             # (Nc, 4)
    faces = faces.reshape(-1, faces.shape[2])
    opp = opp.reshape(-1)
    key = np.sort(faces[:, :3], axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    outer = counts[inverse.reshape(-1)] == 1
    faces, opp = faces[outer], opp[outer]
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    n = np.cross(b - a, c - a)
    flip = np.einsum("ij,ij->i", n, vertices[opp] - a) > 0.0
    faces = faces.copy()
    faces[flip, 1], faces[flip, 2] = faces[flip, 2], faces[flip, 1].copy()
    if quadratic:      # swapping b and c swaps ab <-> ca; bc stays
        faces[flip, 3], faces[flip, 5] = faces[flip, 5], faces[flip, 3].copy()
    return faces


def face_normals(faces: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Unit outward normals of the faces' corner triangles (F, 3)."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    n = np.cross(b - a, c - a)
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def _triangles(faces: np.ndarray) -> np.ndarray:
    """Linear triangles to draw: the 4 sub-triangles of 6-node faces, or the faces themselves."""
    return faces[:, _SUB].reshape(-1, 3) if faces.shape[1] == 6 else faces


def _unroll(u: np.ndarray, tri: np.ndarray, lo: float, period: float = 360.0):
    """(u per triangle corner, tri) with every triangle inside [lo, lo + period) or straddling its
    right edge once, plus a copy one period to the left of those that straddle (so both ends of
    the panel are covered). u: angle of every node in [lo, lo + period)."""
    U = u[tri]                                                   # (T, 3)
    wrap = U.max(axis=1) - U.min(axis=1) > 0.5 * period
    U = np.where(wrap[:, None] & (U < lo + 0.5 * period), U + period, U)
    return np.vstack([U, U[wrap] - period]), np.concatenate([tri, tri[wrap]])


def _panel(ax, u_corners, v_corners, tri, values, norm, cmap):
    import matplotlib.tri as mtri
    n = len(tri)
    if n == 0:          # a mesh without such faces (e.g. a test's few tetrahedra)
        ax.text(0.5, 0.5, "no faces of this kind in the mesh", transform=ax.transAxes, ha="center")
        return None
    x = u_corners.reshape(-1)
    y = v_corners.reshape(-1)
    z = values[tri].reshape(-1)
    t = mtri.Triangulation(x, y, np.arange(3 * n).reshape(n, 3))
    return ax.tripcolor(t, z, shading="gouraud", norm=norm, cmap=cmap, rasterized=True)


def peak_sample(run, settle: float = 0.0):
    """(sample index, t of the peak step, recorded max, recorded node or None, q_full, reduced
    cage path, recorded hash) of the run's largest von_mises_max at t >= settle (run: an open
    flexbearing.simulation.results.Run or a path)."""
    with opened(run) as r:
        path, f = r.path, r.file
        _require_modal_coordinates(path, f)
        out = r.outputs
        if "von_mises_max" not in out:
            raise InputError(f"{path}: no /outputs/von_mises_max (scene output \"von_mises\")")
        t = r.t
        vm = np.where(t >= settle - 1e-12, out["von_mises_max"][...], np.nan)
        if not np.isfinite(vm).any():
            raise InputError(f"{path}: no finite von_mises_max at t >= {settle:g} s")
        k = int(np.nanargmax(vm))
        tk = float(out["von_mises_max_time"][k]) if "von_mises_max_time" in out else float(t[k])
        node = int(out["von_mises_max_vertex"][k]) if "von_mises_max_vertex" in out else None
        q = out["cage_modal_coordinates_full"][k, :]
        return (k, tk, float(vm[k]), node, q, f.attrs.get("reduced_cage_file"),
                str(f.attrs.get("reduced_cage_hash", "")))


def cage_skin(rc) -> dict:
    """The reduced cage's boundary faces sorted for the picture (module doc): {"faces" (F, 6|3),
    "outside", "bore", "wall" (F,) bool, "pocket" (F,) the nearest pocket by azimuth (0-based),
    "pocket_azimuth" (Z,) rad}. A face is on a pocket wall when its outward normal points towards
    that pocket's axis (n . (-rho_hat) > 1/2, rho the face centre's offset from the axis in the
    plane normal to it) and, when the file's geometry gives the pocket diameter, rho < 0.55 D_p
    (so a relief groove's wall near a pocket is not taken for it)."""
    X = np.asarray(rc.vertices, dtype=np.float64)
    faces = boundary_faces(rc.tets10 if rc.tets10 is not None else rc.tets, X)
    nrm = face_normals(faces, X)
    cen = X[faces[:, :3]].mean(axis=1)
    theta_c = np.arctan2(cen[:, 2], cen[:, 1])
    n_r = nrm[:, 1] * np.cos(theta_c) + nrm[:, 2] * np.sin(theta_c)
    pa = np.arctan2(rc.interface_positions[:, 2], rc.interface_positions[:, 1])
    Z = len(pa)
    j = np.mod(np.rint((theta_c - pa[0]) / (2.0 * math.pi / Z)).astype(int), Z)
    tj = pa[j]
    t_off = -cen[:, 1] * np.sin(tj) + cen[:, 2] * np.cos(tj)
    rho = np.hypot(cen[:, 0], t_off)
    n_t = -nrm[:, 1] * np.sin(tj) + nrm[:, 2] * np.cos(tj)
    wall = -(nrm[:, 0] * cen[:, 0] + n_t * t_off) / np.maximum(rho, 1e-30) > 0.5
    params = rc.attrs.get("parameters")
    geom = params.get("geometry", {}) if isinstance(params, dict) else {}
    if "pocket_diameter" in geom:
        wall &= rho < 0.55 * geom["pocket_diameter"]
    return {"faces": faces, "outside": (n_r > 0.5) & ~wall, "bore": (n_r < -0.5) & ~wall, "wall": wall,
            "pocket": j, "pocket_azimuth": pa}


UnrolledCage = namedtuple("UnrolledCage", "fig gs axes theta r")
UnrolledCage.__doc__ = ("The three-panel figure of `draw_unrolled_cage`: the figure, its grid (the label goes in "
                        "gs[2, 1]), the panels (outside, bore, pocket wall), theta (°, the panels' azimuth) and r (m) "
                        "of every node.")


def draw_unrolled_cage(plt, rc, skin, values, norm, cmap, node: int, pocket: int, pocket_note: str,
                       surface_note: str, marker_colour: str) -> UnrolledCage:
    """The cage's skin unrolled (module doc: outside and bore over azimuth theta and axial x, the
    wall of `pocket` over alpha and r), coloured by `values` at every node (norm, cmap), `node`
    starred (in `marker_colour`) on each panel that holds it; the colour bar and the label are the
    caller's. pocket_note ends the wall panel's title, surface_note the two surface panels'."""
    X = np.asarray(rc.vertices, dtype=np.float64)
    faces, wall, j, pa = skin["faces"], skin["wall"], skin["pocket"], skin["pocket_azimuth"]
    Z = len(pa)
    pitch = 2.0 * math.pi / Z
    theta0 = -0.5 * pitch
    theta = np.degrees(np.mod(np.arctan2(X[:, 2], X[:, 1]) - theta0, 2 * math.pi) + theta0)
    r = np.hypot(X[:, 1], X[:, 2])
    star = dict(marker="*", ms=14, mfc="none", mec=marker_colour, mew=1.2)
    fig = plt.figure(figsize=(10.0, 8.4), layout="constrained")
    gs = fig.add_gridspec(3, 2, height_ratios=[1.0, 1.0, 1.25], width_ratios=[1.0, 0.5])
    axes = [fig.add_subplot(gs[0, :]), fig.add_subplot(gs[1, :]), fig.add_subplot(gs[2, 0])]
    lo = math.degrees(theta0)
    for ax, name in zip(axes[:2], ("outside", "bore")):
        tri = _triangles(faces[skin[name]])
        U, tri2 = _unroll(theta, tri, lo)
        _panel(ax, U, X[:, 0][tri2] * 1e3, tri2, values, norm, cmap)
        ax.set_xticks(np.arange(0.0, 360.0 + lo, 2 * math.degrees(pitch)))
        ax.set_xlim(lo, lo + 360.0)
        top = ax.secondary_xaxis("top")
        top.set_xticks(np.degrees(np.mod(pa - theta0, 2 * math.pi) + theta0), [str(p) for p in range(Z)])
        top.tick_params(labelsize=7, length=2)
        ax.set_ylabel("Axial position x (mm)")
        ax.set_xlabel("Azimuth θ (°)")
        ax.set_title(f"{name.capitalize()} surface, unrolled; {surface_note}", loc="left", fontsize=9)
        ax.grid(False)
        if np.isin(node, faces[skin[name]]).any():
            ax.plot([theta[node]], [X[node, 0] * 1e3], **star)
    # the pocket's wall, about its axis
    ax = axes[2]
    tj = pa[pocket]
    m = wall & (j == pocket)
    tri = _triangles(faces[m])
    t_n = -X[:, 1] * math.sin(tj) + X[:, 2] * math.cos(tj)
    alpha = np.degrees(np.arctan2(t_n, X[:, 0]))
    U, tri2 = _unroll(alpha, tri, -180.0)
    _panel(ax, U, r[tri2] * 1e3, tri2, values, norm, cmap)
    ax.set_xticks(np.arange(-180.0, 181.0, 45.0))
    ax.set_xlim(-180.0, 180.0)
    ax.set_xlabel("Angle about the pocket axis α (°):\n0 towards +x, 90 towards increasing θ")
    ax.set_ylabel("Radius r (mm)")
    ax.set_title(f"Wall of pocket {pocket} (θ = {math.degrees(tj) % 360:.0f}°), {pocket_note}",
                 loc="left", fontsize=9)
    ax.grid(False)
    if np.isin(node, faces[m]).any():
        ax.plot([alpha[node]], [r[node] * 1e3], **star)
    return UnrolledCage(fig, gs, axes, theta, r)


def write_stress_picture(run, out_dir, reduced_cage=None, settle: float = 0.0,
                         yield_strength: float | None = None) -> tuple[Path, dict]:
    """<out_dir>/von_mises_peak.png (module doc) and its facts (von_mises_peak.json): {"time",
    "sample", "von_mises_max", "recorded_von_mises_max", "node", "recorded_node", "position" (m,
    body frame), "azimuth_deg", "radius", "surface", "hottest_pocket"}. yield_strength (Pa):
    marked on the colour bar when the field reaches it. run: an open Run or a path."""
    k, tk, vm_rec, node_rec, q, rc_path, rc_hash = peak_sample(run, settle)
    rc, _ = open_reduced_cage(getattr(run, "path", run), reduced_cage or rc_path, rc_hash, len(q))
    vm, _ = nodal_field(rc, q)
    X = np.asarray(rc.vertices, dtype=np.float64)
    skin = cage_skin(rc)
    faces, wall, j = skin["faces"], skin["wall"], skin["pocket"]
    groups = {"outside": skin["outside"], "bore": skin["bore"]}
    Z = len(skin["pocket_azimuth"])
    wall_nodes = [np.unique(faces[wall & (j == p)]) for p in range(Z)]
    hot = int(np.argmax([vm[w].max() if w.size else -1.0 for w in wall_nodes]))
    n_max = int(np.argmax(vm))
    x_m = X[n_max]
    where = [name for name, m in groups.items() if np.isin(n_max, faces[m]).any()]
    in_wall = [p for p in range(Z) if np.isin(n_max, wall_nodes[p]).any()]
    surface = ", ".join(where + [f"wall of pocket {p} (pocket_{p:02d})" for p in in_wall]) or "side face"

    plt = plot_style()
    from matplotlib.colors import Normalize
    cmap = plt.get_cmap("turbo")
    norm = Normalize(0.0, float(vm[n_max]) * 1e-6)
    fig, gs, axes, theta, r = draw_unrolled_cage(plt, rc, skin, vm * 1e-6, norm, cmap, n_max, hot,
                                                 "the most stressed pocket",
                                                 "pocket numbers (mesh groups pocket_00 ...) on top", "k")
    facts = {"time": tk, "sample": k, "von_mises_max": float(vm[n_max]), "recorded_von_mises_max": vm_rec,
             "node": n_max, "recorded_node": node_rec, "position": [float(v) for v in x_m],
             "azimuth_deg": float(theta[n_max]), "radius": float(r[n_max]), "surface": surface,
             "hottest_pocket": hot}
    from matplotlib.cm import ScalarMappable
    cb = fig.colorbar(ScalarMappable(norm, cmap), ax=axes[:2], location="right", fraction=0.03, pad=0.01)
    cb.set_label("von Mises stress (MPa)")
    if yield_strength is not None and yield_strength <= vm[n_max]:
        cb.ax.axhline(yield_strength * 1e-6, color="k", lw=1.2)
        cb.ax.text(-0.2, yield_strength * 1e-6, "R_e", va="center", ha="right",
                   transform=cb.ax.get_yaxis_transform(), fontsize=8)
    # the label of the maximum
    cax = fig.add_subplot(gs[2, 1])
    cax.axis("off")
    label = (f"★ maximum {vm[n_max] * 1e-6:,.1f} MPa\n"
             f"at t = {tk * 1e3:.4g} ms (sample {k})\n"
             f"node {n_max}: {surface}\n"
             f"x = {x_m[0] * 1e3:.2f} mm, θ = {theta[n_max] % 360:.1f}°, r = {r[n_max] * 1e3:.2f} mm\n"
             f"(y, z) = ({x_m[1] * 1e3:.2f}, {x_m[2] * 1e3:.2f}) mm\n"
             f"recorded by the run: {vm_rec * 1e-6:,.1f} MPa"
             + (f" at node {node_rec}" if node_rec is not None else "")
             + (f"\nR_e = {yield_strength * 1e-6:,.0f} MPa (utilization {vm[n_max] / yield_strength:.2f})"
                if yield_strength else ""))
    cax.text(0.02, 0.5, label, transform=cax.transAxes, va="center", ha="left", fontsize=9,
             bbox=dict(boxstyle="round", fc="white", ec="0.6"))
    fig.suptitle("Cage von Mises stress at the run's maximum (elastic; averaged nodal stress at every mesh node, "
                 "cage body frame)", fontsize=10)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    png = out_dir / PICTURE
    fig.savefig(png, dpi=120)       # the Gouraud panels are raster: 150 dpi doubles the page weight
    plt.close(fig)
    png.with_suffix(".json").write_text(json.dumps(facts, indent=1) + "\n")
    return png, facts


def picture_markdown(png: Path, facts: dict) -> list[str]:
    """The report's section with the picture and its maximum in words (Markdown lines)."""
    x, y, z = (v * 1e3 for v in facts["position"])
    return ["## Cage von Mises stress at the run's maximum", "",
            f"![{Path(png).stem}]({Path(png).name})", "",
            f"The field at t = {facts['time']:.6g} s (sample {facts['sample']}, the sample interval with the run's "
            f"largest maximum), rebuilt from the recorded modal coordinates at every mesh node: maximum "
            f"**{facts['von_mises_max'] / 1e6:,.1f} MPa** at node {facts['node']} ({facts['surface']}; "
            f"x = {x:.2f} mm, θ = {facts['azimuth_deg'] % 360:.1f}°, r = {facts['radius'] * 1e3:.2f} mm; "
            f"(x, y, z) = ({x:.2f}, {y:.2f}, {z:.2f}) mm in the cage's body frame), the run recorded "
            f"{facts['recorded_von_mises_max'] / 1e6:,.1f} MPa. Outside and bore surfaces unrolled (pockets are "
            f"the holes) and the wall of the most stressed pocket (pocket {facts['hottest_pocket']}) unrolled "
            "about its axis; the star marks the maximum. Facts in `von_mises_peak.json`.", ""]
