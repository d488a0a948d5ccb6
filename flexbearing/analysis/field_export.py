"""The cage's stress field for ParaView, exactly as the run computed it (`flexbearing report`).

Two kinds of files, both XDMF 3 (light XML) with the heavy data in an HDF5 file beside them:

    von_mises.xdmf (+ .h5, .json)     the field at chosen instants (`--frames`: the peak of each
                                      phase and impact), cage at rest in its body frame
    series_cage.xdmf, series_points.xdmf (+ series.h5, series.json)
                                      a time series over a window (`--series T0:T1[:N]`): the
                                      cage placed and deformed at every N-th sample, and the balls
                                      and the cage centre as a point set at the same times

The field at a sample k is rebuilt from the recorded full-basis modal coordinates q_k
(/outputs/cage_modal_coordinates_full: the coordinates of the integrator step with the sample
interval's maximum stress, its time /outputs/von_mises_max_time; flexbearing.coupling.flexible_cage) with
the reduced cage file's nodal modes (flexbearing.fem_cage.reduced_cage):

    sigma(x_n, t) = S_n q_k       (S_n: (6, M) Voigt xx yy zz yz xz xy, Pa per unit q)
    u(x_n, t)     = Phi_n q_k     (Phi_n: (3, M), m per unit q; elastic, cage body frame)
    sigma_vM      = sqrt(1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2))

(von Mises 1913; flexbearing.fem_cage.stress_modes.von_mises) at every geometry node n of the mesh: the
vertices and, on the curved quadratic mesh, the edge nodes. The cells are the mesh's own 10-node
tetrahedra (XDMF "Tetrahedron_10", VTK quadratic tetra node order, /mesh/tets10 of the reduced
cage file), so every node belongs to a cell and ParaView draws every nodal value, the maximum
included: the field's maximum over the nodes is the recorded von_mises_max of the sample (the
run's search runs over the same nodes). A linear mesh (no tets10) is written as 4-node tetrahedra,
whose corners are then all its nodes.

Placement of the series (the bearing frame: x the bearing axis, y and z radial, origin the
bearing centre, outer ring fixed; the frame of every position the results file records). The
floating frame puts a cage node X (body frame) at

    x = c + A (X + u),   A = R_z(beta_z) R_y(beta_y) R_x(phi)     (flexbearing.multibody.cage_body.cage_rotation)

with c the recorded cage centre and (beta_y, beta_z) its tilt (/outputs/cage_centre, cage_tilt:
scene output "cage_orbit"), and a ball at (x_b, r_b cos psi_b, r_b sin psi_b) (ball_axial_position,
ball_radial_position, ball_azimuth: scene output "kinematics"). The cage's spin angle phi is not
among the recorded outputs; it is estimated from the balls, each in its own pocket (ball j in
pocket j, at body azimuth theta_j = atan2(Z_j, Y_j) of the pocket's interface node, deformed:
its position plus its translation Phi_j q_k, which reaches tens of µm in an impact):

    b'_j = R_y(beta_y)^T R_z(beta_z)^T (b_j - c),   psi'_j = atan2(b'_j,z, b'_j,y)
    phi  = arg sum_j exp(i (psi'_j - theta_j))                           (circular mean)

exact when every ball sits on its pocket's axis; a ball moves in its pocket by at most the
pocket clearance (plus the µm of the contact's approach), so |phi - phi_true| <= (D_p - D_w) /
(2 r_p) with r_p the pitch radius of the balls (0.17° for the paper bearing: 0.25 mm of
clearance at 83.5 mm), a placement error of at most 0.27 mm at the cage's outside radius. The cage is written
undeformed at its placed position; its elastic displacement as the point vector "displacement"
(true, m, bearing-frame components A u) for ParaView's Warp By Vector, and as
"displacement_scaled" = s·A u, magnified by the displacement scale s (default: the power-of-ten
multiple of 1, 2 or 5 that draws the series' largest displacement as about 1 % of the cage's
outside diameter).

Without "kinematics" the spin angle and the balls are unknown: the cage is then written in its
body frame (no rigid motion) and the point file is left out; without "cage_orbit" the cage
centre is taken at the bearing centre, untilted. Each case is said in the files' Information
elements, in series.json and in the report.

Units: every XDMF Attribute carries a Units attribute (SI) and every HDF5 dataset a `unit`
attribute, as the results file's datasets do.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
import xml.etree.ElementTree as ET

import numpy as np
import h5py

from flexbearing.common.validation import InputError
from flexbearing.fem_cage.stress_modes import von_mises
from flexbearing.fem_cage.reduced_cage import file_sha256, read, verify
from flexbearing.analysis.windows import window_mask, impact_windows, speed_phases
from flexbearing.simulation.results import opened
from flexbearing.common.safe_files import check_output_folder
from flexbearing.analysis import rings

SERIES_CAGE = "series_cage.xdmf"
SERIES_POINTS = "series_points.xdmf"
SERIES_RINGS = "series_rings.xdmf"
SERIES_H5 = "series.h5"
SERIES_JSON = "series.json"
PEAKS_XDMF = "von_mises.xdmf"
# every file this module writes into an output folder (checked before: flexbearing.common.safe_files)
FIELD_FILES = (SERIES_CAGE, SERIES_POINTS, SERIES_RINGS, SERIES_H5, SERIES_JSON, PEAKS_XDMF, "von_mises.h5",
               "von_mises.json")
# A series beyond this size is refused with the every-N-th hint: a whole demo run at every sample
# (6,000 frames of the 10,727-node cage) would be ~5 GB, more than ParaView plays comfortably.
SERIES_MAX_BYTES = 2e9
# Auto displacement scale: the largest displacement of the series drawn as this share of the cage's
# outside diameter (visible, still far from overlapping the pockets)
SCALE_TARGET = 0.01


# ---------------------------------------------------------------- the field of one sample

def cage_cells(rc) -> tuple[str, np.ndarray]:
    """(XDMF topology type, cells) of the reduced cage's mesh: its 10-node tetrahedra (VTK node
    order = XDMF's Tetrahedron_10 order) when the file has them, else the 4-node ones."""
    if getattr(rc, "tets10", None) is not None:
        return "Tetrahedron_10", np.ascontiguousarray(rc.tets10, dtype=np.int64)
    return "Tetrahedron", np.ascontiguousarray(rc.tets, dtype=np.int64)


def nodal_field(rc, q_full) -> tuple[np.ndarray, np.ndarray]:
    """(von Mises (Nn,) Pa, elastic displacement (Nn, 3) m, body frame) of full-basis modal
    coordinates q_full at the mesh's geometry nodes (module doc)."""
    q = np.asarray(q_full, dtype=np.float64)
    return von_mises(rc.stress_modes @ q), rc.vertex_displacement @ q


def open_reduced_cage(run_path, rc_path, rc_hash: str, n_modes: int):
    """(ReducedCage, note on its content hash) of the run's reduced cage file; InputError in one
    line if it is missing, not a reduced cage, another cage's than the run's (its key), not the
    content the run used (the sha256 the run recorded, reduced_cage_sha256: a file edited, swapped
    or rebuilt since, or `--reduced-cage OTHER`), or its basis size differs from the recorded
    modal coordinates'."""
    if rc_path is None or not Path(str(rc_path)).is_file():
        raise InputError(f"reduced cage file {rc_path!r} of {run_path} not found (pass its path: "
                         f"flexbearing report ... --reduced-cage FILE)")
    try:
        rc = read(rc_path)
    except (ValueError, OSError, KeyError) as exc:
        raise InputError(f"--reduced-cage {rc_path}: not a reduced cage file ({str(exc).splitlines()[0]}); "
                         f"give the reduced cage the run used (the run names it)") from None
    hash_note = "not recorded"
    if rc_hash:
        known = {str(rc.attrs.get("content_hash", "")), file_sha256(rc_path)}
        if not any(h and (h == rc_hash or h.startswith(rc_hash) or rc_hash.startswith(h)) for h in known):
            raise InputError(f"reduced cage file {rc_path} holds the cage of key "
                             f"{rc.attrs.get('content_hash', '?')}, the run {run_path} used {rc_hash}: give "
                             f"the reduced cage the run used (the run names it)")
        hash_note = "matches"
    # the key alone says which cage the file claims to be; its content is checked against the
    # digest stored in it (a flipped bit, or another cage's arrays under this key)
    if "data_sha256" in rc.attrs:
        verify(rc_path)
        if hash_note == "matches":
            hash_note = "matches (content verified against its digest)"
    elif hash_note == "matches":
        hash_note = "key matches; content not verifiable (file without a digest, written before issue 36)"
    used = _recorded_content(run_path)
    if used and str(rc.attrs.get("data_sha256", "")) != used:
        raise InputError(f"reduced cage file {rc_path} is not the content the run {run_path} used (its "
                         f"sha256 {str(rc.attrs.get('data_sha256', 'none'))[:16]}, the run recorded "
                         f"{used[:16]}): edited or rebuilt since the run; give the file the run used")
    if n_modes is not None and n_modes != rc.stress_modes.shape[2]:
        raise InputError(f"{run_path}: cage_modal_coordinates_full has {n_modes} modes, the reduced "
                         f"cage file {rc_path} has {rc.stress_modes.shape[2]} (allowed: equal); wrong "
                         f"reduced cage file?")
    return rc, hash_note


def check_given_reduced_cage(run_path, rc_path) -> None:
    """`report --reduced-cage FILE`, checked before any work: InputError in one line unless FILE
    is the reduced cage the run used (open_reduced_cage: a reduced cage file, of the run's key and
    of the content digest the run recorded). A run that recorded no reduced cage (a rigid cage)
    is left to the report."""
    try:
        with h5py.File(run_path, "r") as f:
            rc_hash = str(f.attrs.get("reduced_cage_hash", ""))
            n = f["outputs/cage_modal_coordinates_full"].shape[-1] if "outputs/cage_modal_coordinates_full" in f else None
    except (OSError, KeyError, TypeError):
        return                                   # the report names what is wrong with the run file
    if rc_hash:
        open_reduced_cage(run_path, rc_path, rc_hash, n)


def _recorded_content(run_path) -> str:
    """The reduced cage content digest a run recorded (reduced_cage_sha256), '' if none."""
    try:
        with h5py.File(run_path, "r") as f:
            return str(f.attrs.get("reduced_cage_sha256", ""))
    except (OSError, TypeError):
        return ""


def _run_cage_file(f, reduced_cage):
    return reduced_cage or f.attrs.get("reduced_cage_file"), str(f.attrs.get("reduced_cage_hash", ""))


def _require_modal_coordinates(path, f):
    if "cage_modal_coordinates_full" not in f["outputs"]:
        raise InputError(f"{path}: no /outputs/cage_modal_coordinates_full (a flexible-cage run "
                         f"recording von_mises has it; cage model of this run: "
                         f"{f.attrs.get('cage_model', '?')!r})")


# ---------------------------------------------------------------- peaks: --frames

def auto_frames(t: np.ndarray, vm: np.ndarray, phases: list[dict], impacts: list[dict],
                dt: float) -> list[tuple[int, str]]:
    """Sample indices of the default frames with the reason: the instant of maximum von Mises in
    each impact window (the impact's stress peak) and in each phase of the speed profile outside
    the impact windows (the phase's own running peak, which an impact would otherwise hide); the
    whole run's maximum when the scene has neither. Sorted by time, duplicates merged."""
    picks: dict[int, list[str]] = {}
    ok = np.isfinite(vm)
    in_impact = np.zeros(len(t), bool)
    for imp in impacts:
        in_impact |= window_mask(t, imp["t_start"], imp["t_end"], True, dt)
    windows = []
    for i, ph in enumerate(phases):
        m = window_mask(t, ph["t_start"], ph["t_end"], i == len(phases) - 1, dt) & ok
        outside = m & ~in_impact
        windows.append((f"{ph['label']}" + (" (outside impacts)" if outside.any() and
                                            outside.sum() < m.sum() else ""), outside if outside.any() else m))
    for imp in impacts:
        windows.append((imp["label"], window_mask(t, imp["t_start"], imp["t_end"], True, dt) & ok))
    if not windows:
        windows = [("whole run", ok)]
    for label, m in windows:
        idx = np.flatnonzero(m)
        if idx.size:
            k = int(idx[np.argmax(vm[idx])])
            picks.setdefault(k, []).append(f"max von Mises in {label}")
    return [(k, "; ".join(picks[k])) for k in sorted(picks)]


def parse_frames(frames, t: np.ndarray, dt: float):
    """'auto' | 't1,t2,...' | sequence of floats -> None (auto) or sorted unique sample indices."""
    if frames is None or (isinstance(frames, str) and frames.strip() == "auto"):
        return None
    if isinstance(frames, str):
        try:
            times = [float(s) for s in frames.split(",") if s.strip()]
        except ValueError:
            raise InputError(f"--frames = {frames!r} must be 'auto' or times in s separated by "
                             f"commas, e.g. 0.1,0.3") from None
    else:
        times = [float(x) for x in frames]
    if not times:
        raise InputError(f"--frames = {frames!r} lists no time (give 'auto' or t1,t2,... in s)")
    out = []
    for x in times:
        if not (t[0] - 0.5 * dt <= x <= t[-1] + 0.5 * dt):
            raise InputError(f"--frames: t = {x:g} s is outside the run (allowed range "
                             f"[{t[0]:g}, {t[-1]:g}] s)")
        out.append(int(np.argmin(np.abs(t - x))))
    return sorted(set(out))


def write_von_mises_xdmf(run, out_dir, frames="auto", reduced_cage=None) -> Path:
    """ParaView frames of the cage's von Mises field: <out_dir>/von_mises.xdmf (+ .h5, + .json).

    The mesh's 10-node tetrahedra (cage_cells) in the cage's body frame, at rest; point data
    "von_mises" (Pa) and "displacement" (m, elastic, body frame) rebuilt from the recorded modal
    coordinates (module doc); one grid per frame, time value = the time of the integrator step
    with the interval's maximum stress (von_mises_max_time; the sample time for older runs).
    frames: "auto" (auto_frames: each impact's peak and each phase's peak outside the impacts),
    "t1,t2,..." or a list of times in s (nearest samples).
    reduced_cage: path of the reduced cage file (default: the run's attribute reduced_cage_file).
    The JSON sidecar lists each frame's time, reason, the recorded max von Mises and the field's
    maximum over the nodes (equal: the run searches the same nodes). run: an open
    flexbearing.simulation.results.Run or a path."""

    with opened(run) as r:
        path, f = r.path, r.file
        _require_modal_coordinates(path, f)
        out = r.outputs
        t = r.t
        vm_rec = out["von_mises_max"][...] if "von_mises_max" in out else None
        vtx_rec = out["von_mises_max_vertex"][...] if "von_mises_max_vertex" in out else None
        # the step of the sample interval where the maximum occurred (runs since the per-step
        # monitor): its modal coordinates are what cage_modal_coordinates_full holds
        t_peak = out["von_mises_max_time"][...] if "von_mises_max_time" in out else None
        rc_path, rc_hash = _run_cage_file(f, reduced_cage)
        scene, dt = r.scene, r.dt
        idx = parse_frames(frames, t, dt)
        reasons = {}
        if idx is None:
            if vm_rec is None:
                raise InputError(f"--frames auto needs /outputs/von_mises_max in {path}; give times "
                                 f"instead (--frames t1,t2,...)")
            picks = auto_frames(t, vm_rec, speed_phases(scene) if scene else [],
                                impact_windows(scene) if scene else [], dt)
            idx = [k for k, _ in picks]
            reasons = dict(picks)
        M = out["cage_modal_coordinates_full"].shape[1]
        q_full = out["cage_modal_coordinates_full"][idx, :] if idx else np.zeros((0, M))
    rc, hash_note = open_reduced_cage(path, rc_path, rc_hash, M)
    out_dir = Path(out_dir)
    check_output_folder(out_dir, FIELD_FILES, [getattr(run, "path", run), reduced_cage])
    out_dir.mkdir(parents=True, exist_ok=True)
    xdmf = out_dir / PEAKS_XDMF
    h5 = xdmf.with_suffix(".h5")
    topo_type, cells = cage_cells(rc)
    meta = {"run": str(path), "reduced_cage_file": str(rc_path), "reduced_cage_hash": hash_note,
            "cells": topo_type, "frame": "cage body frame (x the cage axis, pocket 0 at +y), cage at rest",
            "fields": {"von_mises": "Pa", "displacement": "m (elastic, cage body frame)"}, "frames": []}
    grids = []
    with h5py.File(h5, "w") as g:
        _dataset(g, "mesh/geometry", rc.vertices, "m")
        _dataset(g, "mesh/topology", cells, "1")
        for i, (k, q) in enumerate(zip(idx, q_full)):
            vm, u = nodal_field(rc, q)
            tk = float(t[k]) if t_peak is None or not np.isfinite(t_peak[k]) else float(t_peak[k])
            _dataset(g, f"von_mises/{i}", vm, "Pa")
            _dataset(g, f"displacement/{i}", u, "m")
            grids.append({"time": tk, "geometry": "/mesh/geometry", "attributes": [
                ("von_mises", "Scalar", f"/von_mises/{i}", "Pa"),
                ("displacement", "Vector", f"/displacement/{i}", "m")]})
            meta["frames"].append({"time": tk, "sample": int(k), "sample_time": float(t[k]),
                                   "reason": reasons.get(k, "requested"),
                                   "field_max_von_mises": float(vm.max()), "field_max_vertex": int(vm.argmax()),
                                   "recorded_von_mises_max": None if vm_rec is None else float(vm_rec[k]),
                                   "recorded_max_vertex": None if vtx_rec is None else int(vtx_rec[k])})
    write_xdmf(xdmf, h5.name, "cage_von_mises", topo_type, "/mesh/topology", cells.shape, len(rc.vertices),
               grids, {"frame": meta["frame"], "run": str(path)})
    xdmf.with_suffix(".json").write_text(json.dumps(meta, indent=1) + "\n")
    return xdmf


def series_markdown(result: dict | None, spec: str | None) -> str:
    """The report's paragraph on the time series (write_series' result, or None: not asked for)."""
    if result is None:
        return ("Time series over a window: not asked for (`flexbearing report RUN.h5 --series T0:T1[:N]` "
                "writes the deformed cage coloured by von Mises, the balls and the rings; docs/paraview.md).")
    files = [f"`{Path(result[k]).name}`" for k in ("cage", "points", "rings") if result.get(k)]
    meta = json.loads(Path(result["json"]).read_text())
    text = (f"Time series {spec}: {' and '.join(files)} (+ `{SERIES_H5}`, facts in `{SERIES_JSON}`), "
            f"{result['n_frames']} frames, {meta['frame']}")
    if "displacement_scale" in meta:
        text += f"; displacement_scaled = {meta['displacement_scale']:g} × displacement"
    if "cage_spin_angle" in meta:
        text += f"; the cage's spin angle is {meta['cage_spin_angle']}"
    text += "."
    if result["notes"]:
        text += " Not written: " + "; ".join(result["notes"]) + "."
    return text


# ---------------------------------------------------------------- XDMF writer

def _dataset(g, name, data, unit):
    d = g.create_dataset(name, data=np.ascontiguousarray(data))
    d.attrs["unit"] = unit
    return d


def write_xdmf(xdmf, h5_name: str, name: str, topology_type: str, topology_path: str, topology_shape,
               n_nodes: int, grids: list[dict], info: dict) -> Path:
    """XDMF 3 temporal collection over heavy data in the HDF5 file `h5_name` beside `xdmf`.

    grids: [{"time", "geometry": HDF5 path of the (n_nodes, 3) node coordinates, "attributes":
    [(name, "Scalar" | "Vector", HDF5 path, SI unit[, "Int"]), ...]}] (float64 unless "Int");
    all of them point data. Every time
    grid carries its own Topology and Geometry items (plain XDMF, no XInclude), so ParaView's XDMF
    readers and meshio.xdmf.TimeSeriesReader both read it; `info` goes into Information elements
    of the Domain. Written by hand: meshio 5.0's TimeSeriesWriter puts the .h5 in the current
    directory instead of beside the .xdmf, and writes neither units nor per-step geometry."""
    xdmf = Path(xdmf)

    def item(parent, path, shape, dtype="Float", precision="8"):
        d = ET.SubElement(parent, "DataItem", DataType=dtype, Dimensions=" ".join(map(str, shape)),
                          Format="HDF", Precision=precision)
        d.text = f"{h5_name}:{path}"

    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    for key, value in info.items():
        ET.SubElement(domain, "Information", Name=key, Value=str(value))
    coll = ET.SubElement(domain, "Grid", Name=name, GridType="Collection", CollectionType="Temporal")
    n_cells = int(topology_shape[0])
    extra = {"NodesPerElement": "1"} if topology_type == "Polyvertex" else {}
    for gr in grids:
        g = ET.SubElement(coll, "Grid", Name=f"t={gr['time']:.9g}", GridType="Uniform")
        topo = ET.SubElement(g, "Topology", TopologyType=topology_type, NumberOfElements=str(n_cells), **extra)
        item(topo, topology_path, topology_shape, "Int", "8")
        item(ET.SubElement(g, "Geometry", GeometryType="XYZ"), gr["geometry"], (n_nodes, 3))
        ET.SubElement(g, "Time", Value=repr(float(gr["time"])))
        for aname, atype, apath, unit, *kind in gr["attributes"]:
            a = ET.SubElement(g, "Attribute", Name=aname, AttributeType=atype, Center="Node", Units=unit)
            item(a, apath, (n_nodes, 3) if atype == "Vector" else (n_nodes,), *(("Int", "8") if kind else ()))
    ET.indent(root)
    xdmf.write_text('<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n")
    return xdmf


# ---------------------------------------------------------------- series: --series T0:T1[:N]

def parse_series(spec: str, t: np.ndarray, dt: float) -> np.ndarray:
    """'T0:T1[:N]' -> indices of every N-th sample with T0 <= t <= T1 (s; N >= 1, default 1)."""
    parts = str(spec).split(":")
    try:
        if len(parts) not in (2, 3):
            raise ValueError
        t0, t1 = float(parts[0]), float(parts[1])
        every = int(parts[2]) if len(parts) == 3 else 1
    except ValueError:
        raise InputError(f"--series = {spec!r} must be T0:T1 or T0:T1:N (times in s, N an integer: "
                         f"every N-th sample), e.g. 0.29:0.31 or 0:0.6:10") from None
    if every < 1:
        raise InputError(f"--series: N = {every} must be >= 1 (every N-th sample)")
    if not t0 <= t1:
        raise InputError(f"--series: T0 = {t0:g} s must not exceed T1 = {t1:g} s")
    eps = 1e-6 * dt
    if t1 < t[0] - eps or t0 > t[-1] + eps:
        raise InputError(f"--series: the window [{t0:g}, {t1:g}] s is outside the run (allowed range "
                         f"[{t[0]:g}, {t[-1]:g}] s)")
    idx = np.flatnonzero((t >= t0 - eps) & (t <= t1 + eps))[::every]
    if idx.size == 0:
        raise InputError(f"--series: no sample in [{t0:g}, {t1:g}] s (sample interval {dt:g} s)")
    return idx


def cage_spin_angle(ball_positions: np.ndarray, centre: np.ndarray, A_tilt: np.ndarray,
                    pocket_azimuths: np.ndarray) -> float:
    """The cage's spin angle phi (rad, in (-pi, pi]) estimated from its balls (module doc):
    ball_positions (Z, 3) and centre (3,) in the bearing frame, A_tilt = R_z(beta_z) R_y(beta_y)
    the cage's tilt, pocket_azimuths (Z,) the pockets' body-frame azimuths (ball j in pocket j)."""
    b = (np.asarray(ball_positions) - centre) @ A_tilt          # rows: A_tilt^T (b_j - c)
    d = np.arctan2(b[:, 2], b[:, 1]) - pocket_azimuths
    return float(math.atan2(np.sin(d).sum(), np.cos(d).sum()))


def _rotation(phi, by, bz) -> np.ndarray:
    from flexbearing.multibody.cage_body import cage_rotation
    A = np.empty((3, 3))
    cage_rotation(float(phi), float(by), float(bz), A)
    return A


def nice_scale(target: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above `target` (> 0)."""
    e = math.floor(math.log10(target))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0 ** e <= target * (1 + 1e-12):
            return m * 10.0 ** e
    return 10.0 ** e


def write_series(run, out_dir, series: str, reduced_cage=None, displacement_scale=None) -> dict:
    """The time series of `--series T0:T1[:N]` (module doc): <out_dir>/series_cage.xdmf (the
    cage, placed and deformed, coloured by von Mises), series_points.xdmf (the balls and the cage
    centre), their heavy data series.h5 and series.json (frame, placement, scale, per-frame
    recorded and written maxima, and what the run did not record). Either part is left out, with
    the reason in "notes", when the run lacks what it needs; InputError when both are.
    displacement_scale: s of "displacement_scaled" (None: auto, module doc).
    Returns {"cage", "points", "rings", "json", "notes", "n_frames"} (paths None when not written)."""
    if displacement_scale is not None and not (displacement_scale > 0 and math.isfinite(displacement_scale)):
        raise InputError(f"--displacement-scale = {displacement_scale!r} must be a finite number > 0")
    d = _read_series(run, series, reduced_cage)
    n = len(d["idx"])
    rc = d["rc"]
    size = n * (0 if rc is None else len(rc.vertices)) * 8 * 10     # 10 float64 per node and frame
    if size > SERIES_MAX_BYTES:
        raise InputError(f"--series {series}: {n} frames of the {len(rc.vertices):,}-node cage make "
                         f"{size / 1e9:.1f} GB of files (allowed up to {SERIES_MAX_BYTES / 1e9:g} GB); take "
                         f"every N-th sample (--series T0:T1:N with N >= {math.ceil(size / SERIES_MAX_BYTES)}) "
                         f"or a shorter window")
    inertial = d["balls"] is not None
    frame = ("bearing frame (x the bearing axis, y and z radial, origin the bearing centre, outer ring "
             "fixed)") if inertial else "cage body frame (x the cage axis, pocket 0 at +y), cage at rest"
    meta = {"run": str(d["path"]), "series": series, "frame": frame, "n_frames": n,
            "samples": [int(k) for k in d["idx"]], "times": [float(x) for x in d["t"]], "notes": d["notes"],
            "fields": {"von_mises": "Pa", "displacement": "m (elastic, true, frame components)",
                       "displacement_scaled": "m (displacement times displacement_scale)",
                       "diameter": "m (balls: D_w; cage centre: 0)", "ball": "1 (ball number 1..Z; 0 = cage centre)"}}
    rot = np.tile(np.eye(3), (n, 1, 1))
    if inertial:
        rot, phi = _placement(d)
        meta["cage_spin_angle"] = ("estimated from the balls' azimuths (circular mean of each ball's azimuth "
                                   "about the cage centre minus its pocket's), not recorded by the run")
        if d["bearing"] is not None:
            b = d["bearing"]
            bound = (b.cage.pocket_diameter - b.ball_diameter) / (2.0 * float(np.mean(d["ball_radius"])))
            meta["cage_spin_angle"] += f"; error bound (D_p - D_w)/(2 r_p) = {math.degrees(bound):.3g} deg"
        meta["cage_spin_angle_rad"] = [float(p) for p in phi]
    else:           # the body frame: no rigid motion
        d["centre"] = np.zeros_like(d["centre"])
    out_dir = Path(out_dir)
    check_output_folder(out_dir, FIELD_FILES, [getattr(run, "path", run), reduced_cage])
    out_dir.mkdir(parents=True, exist_ok=True)
    for stale in (SERIES_CAGE, SERIES_POINTS, SERIES_RINGS):     # of an earlier series in the same folder
        (out_dir / stale).unlink(missing_ok=True)
    paths = {"cage": None, "points": None, "rings": None, "json": out_dir / SERIES_JSON, "notes": d["notes"],
             "n_frames": n}
    with h5py.File(out_dir / SERIES_H5, "w") as g:
        if rc is not None:
            paths["cage"] = _write_series_cage(g, out_dir, d, rot, displacement_scale, meta)
        if inertial:
            paths["points"] = _write_series_points(g, out_dir, d, meta)
        if d["bearing"] is not None:
            paths["rings"] = _write_series_rings(g, out_dir, d, meta, inertial)
    paths["json"].write_text(json.dumps(meta, indent=1) + "\n")
    return paths


def _read_series(run, series: str, reduced_cage) -> dict:
    """What the series needs from the run (an open Run or a path), with a note for each part it
    did not record."""
    notes = []
    with opened(run) as r:
        path, f, out, t = r.path, r.file, r.outputs, r.t
        idx = parse_series(series, t, r.dt)
        d = {"path": path, "idx": idx, "t": t[idx], "notes": notes, "rc": None, "balls": None,
             "bearing": getattr(r.scene, "bearing", None)}
        if "cage_modal_coordinates_full" in out:
            d["q_full"] = out["cage_modal_coordinates_full"][idx, :]
            d["vm_rec"] = out["von_mises_max"][idx] if "von_mises_max" in out else None
            d["t_peak"] = out["von_mises_max_time"][idx] if "von_mises_max_time" in out else t[idx]
            rc_path, rc_hash = _run_cage_file(f, reduced_cage)
        else:
            notes.append("the cage is not written: the run has no /outputs/cage_modal_coordinates_full "
                         "(a flexible-cage run recording \"von_mises\" has it; cage model of this run: "
                         f"{f.attrs.get('cage_model', '?')!r})")
        if all(k in out for k in ("ball_axial_position", "ball_radial_position", "ball_azimuth")):
            rb, psi = out["ball_radial_position"][idx], out["ball_azimuth"][idx]
            d["balls"] = np.stack([out["ball_axial_position"][idx], rb * np.cos(psi), rb * np.sin(psi)], -1)
            d["ball_radius"] = rb
        else:
            notes.append("the balls are not written and the cage stays in its body frame: the run did not "
                         "record \"kinematics\" (ball positions; the cage's spin angle is estimated from "
                         "them); add it to [output] record of the scene")
        if "inner_ring_position" in out and "inner_ring_tilt" in out:
            d["ring_position"], d["ring_tilt"] = out["inner_ring_position"][idx], out["inner_ring_tilt"][idx]
        if "cage_centre" in out and "cage_tilt" in out:
            d["centre"], d["tilt"], d["orbit"] = out["cage_centre"][idx], out["cage_tilt"][idx], True
        else:
            d["centre"], d["tilt"], d["orbit"] = np.zeros((len(idx), 3)), np.zeros((len(idx), 2)), False
            if d["balls"] is not None:
                notes.append("the cage centre is taken at the bearing centre, untilted: the run did not "
                             "record \"cage_orbit\" (cage_centre, cage_tilt); add it to [output] record")
    if "q_full" not in d and d["balls"] is None:
        raise InputError(f"--series: {path} holds neither the cage's modal coordinates nor the balls' "
                         f"positions; " + "; ".join(notes))
    if "q_full" in d:
        d["rc"], d["hash_note"] = open_reduced_cage(path, rc_path, rc_hash, d["q_full"].shape[1])
        d["rc_path"] = str(rc_path)
    return d


def _placement(d) -> tuple[np.ndarray, np.ndarray]:
    """(A (n, 3, 3), phi (n,) unwrapped) of the cage in the bearing frame at each frame (module
    doc): the recorded tilt, the spin angle from the balls in the pockets' deformed centres."""
    n, Z = d["balls"].shape[:2]
    rc = d["rc"]
    rot = np.empty((n, 3, 3))
    phi = np.empty(n)
    for i in range(n):
        if rc is not None:      # the pockets' centres, deformed (interface node translations)
            P = rc.interface_positions + rc.interface_modes[:, :3, :] @ d["q_full"][i]
            pa = np.arctan2(P[:, 2], P[:, 1])
        else:                   # a rigid cage's pocket j at azimuth 2 pi j / Z
            pa = 2.0 * np.pi * np.arange(Z) / Z
        by, bz = d["tilt"][i]
        phi[i] = cage_spin_angle(d["balls"][i], d["centre"][i], _rotation(0.0, by, bz), pa)
        rot[i] = _rotation(phi[i], by, bz)
    return rot, np.unwrap(phi)


def _write_series_cage(g, out_dir: Path, d: dict, rot, displacement_scale, meta) -> Path:
    """The cage part of write_series: datasets in the open HDF5 file g, series_cage.xdmf."""
    rc, q_full, centre = d["rc"], d["q_full"], d["centre"]
    topo_type, cells = cage_cells(rc)
    _dataset(g, "cage/topology", cells, "1")
    umax = max(float(np.linalg.norm(rc.vertex_displacement @ q, axis=1).max()) for q in q_full)
    outside_d = 2.0 * float(np.hypot(rc.vertices[:, 1], rc.vertices[:, 2]).max())
    if displacement_scale is not None:
        s, source = float(displacement_scale), "--displacement-scale"
    else:
        s = nice_scale(SCALE_TARGET * outside_d / umax) if umax > 0 else 1.0
        source = (f"auto: the largest displacement ({umax * 1e6:.4g} µm) drawn as about {SCALE_TARGET:.0%} "
                  f"of the cage's outside diameter ({outside_d * 1e3:.5g} mm)")
    meta["displacement_scale"], meta["displacement_scale_source"] = s, source
    meta["cage"] = {"file": SERIES_CAGE, "cells": topo_type, "n_nodes": len(rc.vertices), "n_cells": len(cells),
                    "reduced_cage_file": d["rc_path"], "reduced_cage_hash": d["hash_note"], "frames": []}
    grids = []
    for i, (q, R) in enumerate(zip(q_full, rot)):
        vm, u = nodal_field(rc, q)
        u = u @ R.T
        _dataset(g, f"cage/geometry/{i}", centre[i] + rc.vertices @ R.T, "m")
        _dataset(g, f"cage/von_mises/{i}", vm, "Pa")
        _dataset(g, f"cage/displacement/{i}", u, "m")
        _dataset(g, f"cage/displacement_scaled/{i}", s * u, "m")
        grids.append({"time": float(d["t"][i]), "geometry": f"/cage/geometry/{i}", "attributes": [
            ("von_mises", "Scalar", f"/cage/von_mises/{i}", "Pa"),
            ("displacement_scaled", "Vector", f"/cage/displacement_scaled/{i}", "m"),
            ("displacement", "Vector", f"/cage/displacement/{i}", "m")]})
        meta["cage"]["frames"].append({
            "time": float(d["t"][i]), "field_time": float(d["t_peak"][i]),
            "field_max_von_mises": float(vm.max()), "field_max_node": int(vm.argmax()),
            "recorded_von_mises_max": None if d["vm_rec"] is None else float(d["vm_rec"][i])})
    info = {"frame": meta["frame"], "units": "SI (m, Pa)", "displacement_scale": s,
            "field_time": "von_mises and displacement at the integrator step with the sample interval's "
                          "maximum stress (series.json field_time), placement at the sample time",
            "run": meta["run"]}
    if "cage_spin_angle" in meta:
        info["cage_spin_angle"] = meta["cage_spin_angle"]
    return write_xdmf(out_dir / SERIES_CAGE, SERIES_H5, "cage", topo_type, "/cage/topology", cells.shape,
                      len(rc.vertices), grids, info)


def _write_series_points(g, out_dir: Path, d: dict, meta) -> Path:
    """The point part of write_series: the balls and the cage centre, series_points.xdmf."""
    balls, centre = d["balls"], d["centre"]
    n, Z = balls.shape[:2]
    pts = np.concatenate([balls, centre[:, None, :]], axis=1)        # (n, Z + 1, 3)
    _dataset(g, "points/topology", np.arange(Z + 1, dtype=np.int64).reshape(-1, 1), "1")
    dw = getattr(d["bearing"], "ball_diameter", float("nan"))
    _dataset(g, "points/diameter", np.r_[np.full(Z, dw), 0.0], "m")
    _dataset(g, "points/ball", np.r_[np.arange(1, Z + 1), 0].astype(np.int64), "1")
    grids = []
    for i in range(n):
        _dataset(g, f"points/geometry/{i}", pts[i], "m")
        grids.append({"time": float(d["t"][i]), "geometry": f"/points/geometry/{i}", "attributes": [
            ("diameter", "Scalar", "/points/diameter", "m"), ("ball", "Scalar", "/points/ball", "1", "Int")]})
    meta["points"] = {"file": SERIES_POINTS, "n_balls": Z,
                      "cage_centre": "recorded (cage_orbit)" if d["orbit"] else "not recorded: the bearing centre"}
    return write_xdmf(out_dir / SERIES_POINTS, SERIES_H5, "balls_and_cage_centre", "Polyvertex",
                      "/points/topology", (Z + 1, 1), Z + 1, grids,
                      {"frame": meta["frame"], "units": "SI (m)", "run": meta["run"],
                       "points": f"balls 1..{Z} (ball = number, diameter = D_w), then the cage centre "
                                 f"(ball = 0, diameter = 0)"})


def _write_series_rings(g, out_dir: Path, d: dict, meta, inertial: bool) -> Path:
    """The rings of write_series (flexbearing.analysis.rings): the outer ring fixed, the inner
    ring at its recorded position and tilt (at rest when the run did not record "kinematics"), one
    quadrilateral surface with point data "ring" (1 outer, 2 inner), series_rings.xdmf."""
    b = d["bearing"]
    outer = rings.revolve(rings.outer_ring_profile(b))
    inner = rings.revolve(rings.inner_ring_profile(b))
    n_out = len(outer.points)
    quads = np.r_[outer.quads, inner.quads + n_out]
    _dataset(g, "rings/topology", quads, "1")
    _dataset(g, "rings/ring", np.r_[np.full(n_out, 1), np.full(len(inner.points), 2)].astype(np.int64), "1")
    moved = inertial and "ring_position" in d
    grids = []
    for i in range(len(d["t"])):
        if moved or i == 0:
            Ac = rings.inner_ring_placement(d["ring_position"][i], d["ring_tilt"][i]) if moved else np.c_[np.eye(3), np.zeros(3)]
            _dataset(g, f"rings/geometry/{i}", np.r_[outer.points, inner.points @ Ac[:, :3].T + Ac[:, 3]], "m")
        grids.append({"time": float(d["t"][i]), "geometry": f"/rings/geometry/{i if moved else 0}",
                      "attributes": [("ring", "Scalar", "/rings/ring", "1", "Int")]})
    meta["rings"] = {"file": SERIES_RINGS, "outer": "fixed (the bearing frame)",
                     "inner": "at its recorded position and tilt (inner_ring_position, inner_ring_tilt)" if moved
                     else "at rest: the run did not record \"kinematics\" (inner_ring_position)",
                     "profile": "flexbearing.analysis.rings (grooves drawn, clearance and chamfers not)"}
    return write_xdmf(out_dir / SERIES_RINGS, SERIES_H5, "rings", "Quadrilateral", "/rings/topology", quads.shape,
                      n_out + len(inner.points), grids,
                      {"frame": "bearing frame (x the bearing axis), outer ring fixed", "units": "SI (m)",
                       "run": meta["run"], "ring": "1 = outer ring, 2 = inner ring"})
