"""CalculiX (ccx) as an independent FE code on the project's own cage mesh: input deck, run, results.

What this module does, and nothing more: read a gmsh curved quadratic tetrahedral mesh (.msh),
write a CalculiX input deck for it (C3D10 elements, isotropic elastic material, SI units),
run `ccx` in a temporary folder and read its results back: the nodal displacements and the nodal
stresses of the .frd file, the reaction forces, and the eigenfrequencies of the .dat file.
flexbearing.verification.calculix_check uses it to check the project's FE (dolfinx) against CalculiX.

Element. CalculiX's C3D10 is the 10-node isoparametric quadratic tetrahedron: the same
displacement space as the project's P2 Lagrange elements on the curved order-2 mesh. Its node
order (CalculiX manual, "C3D10"; the face table of ccx's e_c3d.f) is the 4 corners, then the
mid-edge nodes of the edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4 (1-based), which is VTK's quadratic
tetra order (VTK_QUADRATIC_TETRA: edges 0-1, 1-2, 2-0, 0-3, 1-3, 2-3). meshio returns a gmsh
"tetra10" block in VTK order (it swaps gmsh's last two mid-edge nodes), so the connectivity goes
to CalculiX unchanged: C3D10_FROM_VTK is the identity; `read_tet10_mesh` checks it on every mesh
(each mid-edge node lies near its edge's midpoint, the corner volume is positive).

Faces (for *SURFACE, TYPE=ELEMENT): face 1 = nodes 1-2-3, 2 = 1-2-4, 3 = 2-3-4, 4 = 1-3-4
(ccx e_c3d.f `ifacet`; CalculiX manual "Surface"), 1-based corner positions.

Integration in ccx (e_c3d.f, default scheme): 4 Gauss points per C3D10 for the stiffness, the mass
and the body loads (CENTRIF), i.e. a degree-2 rule; nodal stresses (*EL FILE, S) are the 4
integration-point stresses extrapolated linearly to the corners (extrapolate.f, matrix a4), the
mid-edge nodes taking the mean of their two corners, then averaged over the elements sharing a
node. Frequencies: ARPACK in shift-invert mode with SPOOLES (sigma = 1 (rad/s)^2), consistent
mass (CalculiX manual, "Frequency calculations").

.frd format (ASCII; CalculiX GraphiX manual, "Result Format"): fixed-width records. A nodal result
block starts with `  100C` (header with the step value, e.g. a frequency, and the format flag:
0 short = node numbers in 5 columns, 1 long = 10 columns), then ` -4  NAME ncomp`, one ` -5`
line per component, one ` -1` line per node (key I3, node I5 or I10, values E12.5; ` -2` lines
continue a node's values), ` -3` ends the block. STRESS components are SXX SYY SZZ SXY SYZ SZX;
read_frd returns them in flexbearing's Voigt order (xx, yy, zz, yz, xz, xy).

Units: SI throughout (m, N, Pa, kg/m^3, s); CalculiX itself is unit-free.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from flexbearing.common.validation import InputError

CCX = "ccx"
# meshio's tetra10 (VTK order) -> C3D10 order: identical (module docstring); kept explicit so the
# check in read_tet10_mesh documents the assumption.
C3D10_FROM_VTK = np.arange(10)
# mid-edge node k (4..9) sits on the edge between these two corners (0-based), C3D10/VTK order
TET10_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))
# C3D10 faces 1..4: their corner positions (0-based) in the element
TET_FACE_CORNERS = ((0, 1, 2), (0, 1, 3), (1, 2, 3), (0, 2, 3))
# frd STRESS order (xx, yy, zz, xy, yz, zx) -> Voigt (xx, yy, zz, yz, xz, xy)
FRD_STRESS_TO_VOIGT = (0, 1, 2, 4, 5, 3)


def ccx_available() -> bool:
    return shutil.which(CCX) is not None


# ------------------------------------------------------------------ mesh

@dataclass
class Tet10Mesh:
    """A curved quadratic tetrahedral mesh: nodes (N, 3) m, tets (Nc, 10) 0-based node indices in
    C3D10 order, facets: physical tag -> (n, 6) 0-based triangle6 node indices."""
    nodes: np.ndarray
    tets: np.ndarray
    facets: dict = field(default_factory=dict)


def read_tet10_mesh(path) -> Tet10Mesh:
    """Read a gmsh .msh with tetra10 cells (and triangle6 facets with physical tags) via meshio.

    Checks the C3D10 node order assumption: every mid-edge node within 25 % of its edge length of
    the edge's midpoint (a curved edge bends far less), and every element's corner tetrahedron
    has a positive volume (x2-x1)x(x3-x1).(x4-x1) > 0 (the orientation CalculiX requires)."""
    import meshio
    m = meshio.read(str(path))
    tets, facets = [], {}
    phys = m.cell_data.get("gmsh:physical")
    for i, block in enumerate(m.cells):
        if block.type == "tetra10":
            tets.append(block.data)
        elif block.type == "triangle6" and phys is not None:
            for tag in np.unique(phys[i]):
                rows = block.data[phys[i] == tag]
                facets[int(tag)] = np.vstack([facets[int(tag)], rows]) if int(tag) in facets else rows
    if not tets:
        raise ValueError(f"{path}: no tetra10 cells (CalculiX C3D10 needs a quadratic mesh, order 2)")
    tets = np.vstack(tets)[:, C3D10_FROM_VTK].astype(np.int64)
    mesh = Tet10Mesh(np.asarray(m.points, dtype=float), tets,
                     {k: v.astype(np.int64) for k, v in facets.items()})
    check_tet10_order(mesh)
    return mesh


def check_tet10_order(mesh: Tet10Mesh) -> None:
    """Raise ValueError if a mid-edge node is not near its edge's midpoint (wrong node order) or
    a corner tetrahedron is inverted (wrong orientation)."""
    X = mesh.nodes[mesh.tets]                                  # (Nc, 10, 3)
    for k, (a, b) in enumerate(TET10_EDGES):
        edge = X[:, b] - X[:, a]
        off = np.linalg.norm(X[:, 4 + k] - 0.5 * (X[:, a] + X[:, b]), axis=1)
        bad = off > 0.25 * np.linalg.norm(edge, axis=1)
        if bad.any():
            raise ValueError(f"tet10 node {4 + k} of {bad.sum()} cells is not on edge {a}-{b}: "
                             "the mesh is not in C3D10/VTK node order")
    vol = np.einsum("ij,ij->i", np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]), X[:, 3] - X[:, 0])
    if (vol <= 0).any():
        raise ValueError(f"{(vol <= 0).sum()} tetrahedra have a non-positive corner volume "
                         f"(first: cell {int(np.flatnonzero(vol <= 0)[0])})")


def facet_faces(mesh: Tet10Mesh, triangles: np.ndarray) -> np.ndarray:
    """(n, 2) array of (element index 0-based, CalculiX face number 1..4) of the boundary
    triangles (n, >=3 corner node indices)."""
    lookup = {}
    for f, corners in enumerate(TET_FACE_CORNERS):
        keys = np.sort(mesh.tets[:, corners], axis=1)
        for e, key in enumerate(map(tuple, keys)):
            lookup[key] = (e, f + 1)
    out = np.empty((len(triangles), 2), dtype=np.int64)
    for i, tri in enumerate(np.sort(np.asarray(triangles)[:, :3], axis=1)):
        try:
            out[i] = lookup[tuple(tri)]
        except KeyError:
            raise ValueError(f"boundary triangle {i} (nodes {tri.tolist()}) is no face of a tetrahedron") from None
    return out


# ------------------------------------------------------------------ input deck

@dataclass
class DistributingCoupling:
    """CalculiX *COUPLING + *DISTRIBUTING: a force (and moment) at a reference node at `point`
    spread over the nodes of the element faces `faces` ((n, 2): element 0-based, face 1..4) with
    the consistent area weights w_i = ∫ N_i dA / A and the bolt-pattern moment distribution
    f_i = w_i (F + (J^-1 M) x r_i), r_i from the weighted centroid, J = sum w_i (|r_i|^2 I - r_i r_i^T),
    M including the moment of F about that centroid (ccx couplings.f; Abaqus Theory Manual,
    "Distributing coupling elements"). rotations: also distribute moments (dofs 4-6)."""
    name: str
    point: np.ndarray
    faces: np.ndarray
    rotations: bool = False


def _fmt(x: float) -> str:
    # ccx reads real fields as F20.0: at most 20 characters, so 13 significant digits
    return f"{x:.12e}"


def deck_text(mesh: Tet10Mesh, material, *, analysis: str = "static", boundary=(), cloads=(),
              centrifugal=None, couplings=(), n_modes: int = 0, stress: bool = True,
              node_output: bool = True, title: str = "flexbearing") -> str:
    """A complete CalculiX input deck (one step) for the mesh.

    analysis: "static" (*STATIC, linear) or "frequency" (*FREQUENCY, n_modes lowest modes).
    boundary: iterable of (node index 0-based, dof 1..3): displacement held at zero.
    cloads: iterable of (node index 0-based, dof 1..6, value N or N m); the reference node of
      couplings[k] has index len(mesh.nodes) + k.
    centrifugal: None or (omega rad/s, point on the axis (3,), axis direction (3,)): body load
      rho omega^2 r_perp (*DLOAD CENTRIF; its first value is omega^2).
    stress, node_output: write the nodal stresses (*EL FILE S) / displacements and, for a static
      step, reaction forces (*NODE FILE U, RF) to the .frd.
    Node and element numbers in the deck are the 0-based indices + 1."""
    material.validate("calculix.material")
    if analysis not in ("static", "frequency"):
        raise InputError(f"calculix.analysis = {analysis!r} is outside the allowed set {{static, frequency}}")
    if analysis == "frequency" and n_modes < 1:
        raise InputError(f"calculix.n_modes = {n_modes} is outside the allowed range [1, inf)")
    n = len(mesh.nodes)
    out = [f"** {title}: written by flexbearing.verification.calculix (SI units: m, N, Pa, kg/m^3)", "*HEADING", title,
           "*NODE, NSET=NALL"]
    out += [f"{i + 1}, {_fmt(x)}, {_fmt(y)}, {_fmt(z)}" for i, (x, y, z) in enumerate(mesh.nodes)]
    for k, c in enumerate(couplings):
        p = np.asarray(c.point, dtype=float)
        out.append(f"{n + k + 1}, {_fmt(p[0])}, {_fmt(p[1])}, {_fmt(p[2])}")
    out.append("*ELEMENT, TYPE=C3D10, ELSET=EALL")
    out += [f"{e + 1}, " + ", ".join(str(int(v) + 1) for v in t) for e, t in enumerate(mesh.tets)]
    out += ["*MATERIAL, NAME=CAGE", "*ELASTIC",
            f"{_fmt(material.youngs_modulus)}, {_fmt(material.poisson_ratio)}",
            "*DENSITY", _fmt(material.density), "*SOLID SECTION, ELSET=EALL, MATERIAL=CAGE"]
    for k, c in enumerate(couplings):
        out.append(f"*SURFACE, NAME=S{c.name}, TYPE=ELEMENT")
        out += [f"{int(e) + 1}, S{int(f)}" for e, f in np.asarray(c.faces)]
        out += [f"*COUPLING, REF NODE={n + k + 1}, SURFACE=S{c.name}, CONSTRAINT NAME=C{c.name}",
                "*DISTRIBUTING"]
        if c.rotations:
            out.append("4, 6")
    out.append("*STEP")
    if analysis == "static":
        out.append("*STATIC")
    else:
        out += ["*FREQUENCY, SOLVER=SPOOLES", f"{int(n_modes)}"]
    bnd = list(boundary)
    if bnd:
        out.append("*BOUNDARY")
        out += [f"{int(i) + 1}, {int(d)}, {int(d)}, 0.0" for i, d in bnd]
    cl = list(cloads)
    if cl:
        out.append("*CLOAD")
        out += [f"{int(i) + 1}, {int(d)}, {_fmt(v)}" for i, d, v in cl]
    if centrifugal is not None:
        om, p, a = centrifugal
        p, a = np.asarray(p, float), np.asarray(a, float) / np.linalg.norm(a)
        out += ["*DLOAD", "EALL, CENTRIF, " + ", ".join(_fmt(v) for v in (om ** 2, *p, *a))]
    if node_output:
        out += ["*NODE FILE, NSET=NALL", "U" + (", RF" if analysis == "static" else "")]
    if stress:
        out += ["*EL FILE", "S"]
    out.append("*END STEP")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------ run

@dataclass
class CcxRun:
    """Results of one ccx run: frd blocks, .dat text, ccx's console output, wall time (s)."""
    blocks: list
    dat: str
    log: str
    wall_s: float

    def block(self, name: str, index: int = 0):
        found = [b for b in self.blocks if b.name == name]
        if len(found) <= index:
            raise KeyError(f"ccx results hold {len(found)} {name!r} block(s); asked for #{index}")
        return found[index]


def run_ccx(deck: str, workdir=None, jobname: str = "job", threads: int = 1,
            timeout_s: float = 3600.0) -> CcxRun:
    """Run `ccx -i jobname` on the deck text in workdir (default: a temporary folder, removed
    afterwards) and read the .frd and .dat back. threads: OMP_NUM_THREADS for ccx (1 = serial, a
    like-for-like timing with the serial project solve). Raises RuntimeError with ccx's own
    messages when it fails or prints *ERROR."""
    if not ccx_available():
        raise RuntimeError(f"CalculiX '{CCX}' is not on PATH (Debian: apt-get install calculix-ccx)")
    tmp = None
    if workdir is None:
        tmp = tempfile.TemporaryDirectory(prefix="ccx-")
        workdir = tmp.name
    try:
        wd = Path(workdir)
        wd.mkdir(parents=True, exist_ok=True)
        (wd / f"{jobname}.inp").write_text(deck)
        env = dict(os.environ, OMP_NUM_THREADS=str(int(threads)),
                   CCX_NPROC_STIFFNESS=str(int(threads)), CCX_NPROC_EQUATION_SOLVER=str(int(threads)),
                   CCX_NPROC_RESULTS=str(int(threads)))
        t0 = time.perf_counter()
        p = subprocess.run([CCX, "-i", jobname], cwd=wd, env=env, capture_output=True, text=True,
                           timeout=timeout_s)
        wall = time.perf_counter() - t0
        log = p.stdout + p.stderr
        errors = [ln.strip() for ln in log.splitlines() if "*ERROR" in ln]
        frd = wd / f"{jobname}.frd"
        if p.returncode != 0 or errors or not frd.exists():
            tail = "\n".join(log.splitlines()[-25:])
            raise RuntimeError(f"ccx failed (exit {p.returncode}) in {wd}:\n{tail}")
        dat = wd / f"{jobname}.dat"
        return CcxRun(read_frd(frd), dat.read_text() if dat.exists() else "", log, wall)
    finally:
        if tmp is not None:
            tmp.cleanup()


# ------------------------------------------------------------------ results

@dataclass
class FrdBlock:
    """One nodal result block: name (DISP, STRESS, FORC, ...), step value (time or frequency),
    components, nodes (0-based indices = frd node number - 1), data (n, ncomp)."""
    name: str
    value: float
    components: list
    nodes: np.ndarray
    data: np.ndarray


def read_frd(path) -> list[FrdBlock]:
    """The nodal result blocks of an ASCII .frd file (format in the module docstring). STRESS
    data are returned in Voigt order (xx, yy, zz, yz, xz, xy) with components renamed so."""
    blocks = []
    with open(path) as f:
        lines = iter(f.read().splitlines())
    for line in lines:
        if not line.startswith("  100C"):
            continue
        # header: '  100C' setname A6, value E12.5, numnod I12, text A20, ictype I2, numstp I5,
        # analys A10, format I2 (columns 0-4, 5, 6-11, 12-23, 24-35, 36-55, 56-57, 58-62, 63-72, 73-74)
        value = float(line[12:24])
        fmt = int(line[73:75]) if line[73:75].strip() else 0
        if fmt not in (0, 1):
            raise ValueError(f"{path}: binary frd results (format {fmt}) are not supported; "
                             "use *NODE FILE / *EL FILE")
        wn = 10 if fmt == 1 else 5
        head = next(lines)
        if not head.startswith(" -4"):
            raise ValueError(f"{path}: result header not followed by a ' -4' record: {head!r}")
        name = head[5:13].strip()
        comps, nodes, rows = [], [], []
        for ln in lines:
            key = ln[:3]
            if key == " -5":
                comps.append(ln[5:13].strip())
            elif key == " -1":
                nodes.append(int(ln[3:3 + wn]))
                rows.append(_e12(ln[3 + wn:]))
            elif key == " -2":
                rows[-1] = rows[-1] + _e12(ln[3 + wn:])
            elif key == " -3":
                break
        # 'ALL' is a derived magnitude: listed as a component, its values are not stored
        comps = [c for c in comps if c != "ALL"]
        data = np.array([r[:len(comps)] for r in rows], dtype=float).reshape(len(rows), len(comps))
        if name == "STRESS":
            data = data[:, FRD_STRESS_TO_VOIGT]
            comps = ["Sxx", "Syy", "Szz", "Syz", "Sxz", "Sxy"]
        blocks.append(FrdBlock(name, value, comps, np.asarray(nodes, dtype=np.int64) - 1, data))
    return blocks


def _e12(s: str) -> list[float]:
    """Fixed-width E12.5 fields, left to right (a minus sign may touch the previous field)."""
    s = s.rstrip()
    return [float(s[i:i + 12]) for i in range(0, len(s), 12)]


def nodal_field(block: FrdBlock, n_nodes: int) -> np.ndarray:
    """Block data as an (n_nodes, ncomp) array indexed by 0-based node (missing nodes: NaN)."""
    out = np.full((n_nodes, block.data.shape[1]), np.nan)
    keep = block.nodes < n_nodes
    out[block.nodes[keep]] = block.data[keep]
    return out


def read_eigenfrequencies(dat: str) -> np.ndarray:
    """Eigenfrequencies (Hz: cycles per unit time in SI) of the ccx .dat table
    'E I G E N V A L U E   O U T P U T' (columns: mode, eigenvalue omega^2, then omega and f, real
    and imaginary parts in a layout that varies between versions), recomputed from the eigenvalue:
    f = sign(lambda) sqrt(|lambda|) / (2 pi); the near-zero rigid modes may come out negative."""
    lam = []
    section = False
    for ln in dat.splitlines():
        if "E I G E N V A L U E   O U T P U T" in ln:
            section = True
            lam = []
            continue
        if section:
            parts = ln.split()
            if len(parts) >= 3 and parts[0].isdigit():
                lam.append(float(parts[1]))
            elif lam and not parts:
                section = False
    lam = np.asarray(lam)
    return np.sign(lam) * np.sqrt(np.abs(lam)) / (2 * np.pi)
