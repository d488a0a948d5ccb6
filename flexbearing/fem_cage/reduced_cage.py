"""The reduced cage file (flexbearing's "modal neutral file"): schema, writer, reader, cache.

numpy + h5py only: a run that finds its reduced cage in the cache never imports dolfinx.

Schema "flexbearing.reduced_cage", version 6 (HDF5; SI units: m, kg, s, Pa, rad)
-------------------------------------------------------------------------------
Root attributes
  schema = "flexbearing.reduced_cage", schema_version = 6, content_hash (16 hex: cache key of
  every input, see cache_key()), parameters (JSON: geometry, material, mesh size/order/
  pocket_size, FE degree, coupling, n_fixed, centrifugal_vector, guide_load_vectors,
  inertia_relief_vectors), coupling ("rbe2" | "rbe3"),
  centrifugal_vector (bool: basis augmented with the fixed-interface centrifugal response),
  guide_load_vectors (bool: ... with the fixed-interface responses to the 3 unit land loads),
  inertia_relief_vectors (bool: ... with those to the 6 rigid-body inertia loads M R),
  n_modes (M = 6Z + n_fixed + 1 + 3 + 6 with all three augmentations (default; 160 on the paper
  cage), each one dropped removes its count),
  n_rigid = 6, default_n_keep = 26, created_by, units = "SI", notes (the truncation caveat below).
/mesh           vertices (Nn, 3) m: the geometry nodes (vertices + edge nodes of the curved
                quadratic mesh) where stress and displacement are given; tets (Nc, 4) int64:
                the corner nodes of each cell (a P1 tetrahedron skeleton for any XDMF writer);
                tets10 (Nc, 10): all nodes in VTK tetra10 order (quadratic mesh only); attrs: source_msh (path at build time),
                msh_sha256 (also the root attribute mesh_sha256, which the digest covers:
                the mesh it was built from, checked against the cache's mesh by
                check_provenance), n_dofs (of the full model), element (e.g. "P3 on curved order-2
                tetrahedra"), quality (JSON: the mesh's element quality — inverted cells, worst
                Jacobian ratio and scaled Jacobian — and what the repair of badly curved cells
                changed; flexbearing.mesh.cage_mesh.mesh_quality_of).
/interface      positions (Z, 3) m: interface node i at pocket i's centre; pocket (Z) int;
                dof_names = ux uy uz rx ry rz (node DOF order, body frame).
/modes          frequency_hz (M), omega (M) rad/s, ascending; modes 0–5 rigid (omega = 0):
                translations of the CoM along x, y, z, then rotations about the principal axes
                through the CoM (ascending principal moment); modes 6.. elastic.
                modal_mass (M, M) = identity, modal_stiffness (M) = omega^2 (diagonal);
                interface (Z, 6, M): mode k at interface node i, DOF d (translations m, rotations
                rad per unit q); vertex_displacement (Nn, 3, M) m per unit q at /mesh/vertices;
                rigid_twist (6, 6): (t, omega) about the body origin of each rigid mode.
/invariants     mass, center_of_mass (3), inertia_origin (3,3), inertia_com (3,3),
                I1..I9 (flexbearing.fem_cage.invariants docstring; I5 (3,M,M), I8 (3,3,M), I9 (3,3,M,M)),
                raw consistent-mass moments (what flexbearing.multibody.floating_frame contracts):
                first (3) = ∫rho x, second (3,3) = ∫rho x_a x_b, S1 (3,M) = ∫rho Phi,
                Sx (3,3,M) = ∫rho x_a Phi_k,b, SS (3,3,M,M) = ∫rho Phi_j,a Phi_k,b (Shabana's
                S_ab); Mff = I6 = identity.
/stress         modes (Nn, 6, M) Pa per unit q at /mesh/vertices (Voigt xx yy zz yz xz xy;
                averaged nodal stress, flexbearing.fem_cage.stress_modes); rigid columns are exactly 0.
/loads          guide_modal_loads (M, 3): G = Phi^T [f_y f_z f_t], the modal loads (N m per unit
                q, i.e. generalised forces) of the land (guide-surface) load per unit land force
                along body y, along body z (N) and per unit land torque about the cage axis x (N m),
                in the same full basis as /modes/interface and /stress/modes; the modal force of a
                land load L = (F_y, F_z, M_x) is G @ L. f_y, f_z, f_t: consistent nodal loads of
                a radial traction c cos(theta) e_r, c sin(theta) e_r and a uniform shear c_t
                e_theta on the guide surface (facet tag 200), theta = atan2(z, y), with exact unit
                resultant force / torque (flexbearing.fem_cage.reduction.guide_load_vectors: the equations,
                and the caveat that they keep the resultant and torque of the film load but not
                its local pressure peak near the minimum film). attrs: columns (JSON list
                ["land force y N", "land force z N", "land torque x N m"]), units,
                distribution, guide_area_m2.
/checks         attrs: JSON of the verification summary (static exactness, stress recovery,
                frequencies, invariants), when computed.

Version history: 1 = stress at mesh vertices only, /mesh/tets (Nc, 4); 2 = stress and displacement
at all geometry nodes, /mesh/tets (Nc, 4) corner skeleton + /mesh/tets10, FE degree in the key;
3 = the CB basis is augmented (default) with the fixed-interface static response to the
centrifugal load about the bearing axis, u_cf = K_ii^-1 M x_perp (interface held; fem_cage.
craig_bampton Eq. (2)) before the modified-CB orthonormalisation: one more mode, same datasets,
root attribute centrifugal_vector and the flag in parameters/cache key. Why: with constraint +
fixed-interface modes only, the full basis is statically exact for interface (pocket) loads but
not for body loads — the spinning cage's hoop stress was off by tens of percent on a thin test
ring; constraint modes + u_cf hold the exact free–free static centrifugal response
(tests/test_cb_centrifugal.py). 4 = /loads/guide_modal_loads, and the basis is augmented
(default) with the fixed-interface static responses to the three unit land loads and to the six
rigid-body inertia loads (flexbearing.fem_cage.reduction.reduce_model): nine more modes, root attributes
guide_load_vectors and inertia_relief_vectors, both flags in parameters/cache key. Why: the land
force of the outer-ring-guided cage acts on the guide surface, and it (like a single pocket
force) has a net force, so its quasi-static response in the free cage is the inertia-relief
solution; with these vectors the full basis holds it exactly (tests/test_guide_loads.py). Paper
cage, F_y = 100 N + M_x = 1 N m (`flexbearing reduce --check`, check_guide): full basis vs full
FE 1.8e-11 in displacement, 1.1e-10 in max von Mises; the schema-3 basis 1.7 % and +173 %. The
26 kept modes alone miss 99.6 % of that max von Mises: the land load is carried by the static
correction (static_correction with guide_modal_loads), not by the kept modes.
5 = /stress/modes and /modes/vertex_displacement stored as float32, chunked, with the HDF5
shuffle filter and gzip (level 1); read() returns them as float64 (see "Storage" below); same
datasets and shapes otherwise. 6 = the same two tables as 16-bit integers with per-(component,
mode) scales (datasets NAME_scale; "Storage" below); read() returns them as float64. read() also accepts version-5
files (float32 tables) and version-2, 3 and 4 files (same layout without /loads:
ReducedCage.guide_modal_loads is None; centrifugal_vector of a version-2 file reads False;
guide_load_vectors and inertia_relief_vectors read False).

Storage (version 6). The two mode-shape tables are 98 % of a float64 file (paper cage, 4 mm P3:
18,247 nodes x 9 x 160 modes, 210 MB of 216 MB). They are stored as 16-bit integers with one
float64 scale per (component, mode) (`quantise`; datasets stress/modes_scale (6, M) and
modes/vertex_displacement_scale (3, M)): each entry within half a step, max|column| / 65534 =
1.5e-5 of its column's largest entry. A stress sigma = S q sums M terms, so its error is bounded
by the sum of |q_k| times each mode's step, not by the result (`quantisation_bound`: the bound on
the maximum von Mises). Measured on the paper cage (benchmarks/results/reduce_design_loop.md,
round two): the bound is at most 6.4e-5 of the max von Mises of the stress-study load cases and
4.4e-5 of that of any sample of a 20 ms run, the actual change at most 1.3e-5; the default mesh's
max von Mises is held to 5 % (benchmarks/results/cage_stress_convergence.md), ~800 times the
bound. Every other dataset (frequencies, interface modes, invariants: what the integrator's
equations use) stays float64, so a run integrates the same equations (a 20 ms run: 60 of 61
outputs bit-identical to the float32 file's); only stress and displacement recovery see the
rounding.
The digest (data_digest) covers the stored integers and their scales.

Basis and truncation. The file holds the FULL orthonormalised Craig–Bampton basis (all 6Z
constraint modes + n_fixed fixed-interface modes + the centrifugal vector, M-orthonormalised,
sorted by frequency; version 4 adds the 3 land-load and 6 inertia-relief vectors). The
runtime keeps the first n_keep (default 26 = 6 rigid + 20 elastic, the paper's count of 26
"modal frequencies" with the rigid ones included, as ADAMS numbers them). Only the full basis is
statically exact for loads at the interface nodes and (version 3) for the centrifugal load and
(version 4) for land loads and, in the free cage, for loads with a net force (to solver
precision); a truncated basis is not — the file's /checks give the static error of both. Frame convention for the floating frame
of reference: the elastic modes (6..) are M-orthogonal to all rigid motions, i.e. they satisfy
the linearised mean-axis (Tisserand) conditions ∫rho Phi dV = 0 and ∫rho x × Phi dV = 0 about
the CoM; a runtime whose body frame carries the rigid motion drops modes 0–5 (`elastic()`).
Damping (paper: D = beta K): in modal coordinates D = beta diag(omega^2), see modal_damping().
Measured on the paper cage (benchmarks/results/reduce_paper.json): a 26-mode truncation under-reads
the quasi-static stress of a pocket load by ~97 %; keep 26 modes dynamic and add the quasi-static
coordinates of the other modes (static_correction(), mode-acceleration method) to recover the
full basis' static answer at no integrator cost.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import h5py

from flexbearing.common.cache import file_sha256   # noqa: F401 (rcf.file_sha256: the mesh file's digest)
from flexbearing.mesh.cage_mesh import MESH_VERSION, mesh_digest
from flexbearing.common.cache import cache_dir, content_hash
from flexbearing.common.safe_files import atomic_output
from flexbearing.common.validation import InputError, require_range

SCHEMA = "flexbearing.reduced_cage"
SCHEMA_VERSION = 6
READABLE_VERSIONS = (2, 3, 4, 5, 6)  # 2, 3: no /loads; 2: basis without the centrifugal vector
# the mode-shape tables stored as 16-bit integers, one scale per (component, mode) in the dataset
# NAME + SCALE_SUFFIX (schema 6; why: the module docstring, "Storage"); schema 5 stored them float32
QUANTISED_DATASETS = ("stress/modes", "modes/vertex_displacement")
SCALE_SUFFIX = "_scale"
_INT16_MAX = 32767
# HDF5 chunks of the quantised tables: whole rows of ~4096 nodes (about 8 MB at 160 modes)
_CHUNK_NODES = 4096
GUIDE_LOAD_COLUMNS = ("land force y N", "land force z N", "land torque x N m")
N_RIGID = 6
DEFAULT_N_KEEP = 26
# 30, not 20 or 24: those save 2.5-6 s CPU of a reduction but raise kept free-free frequencies by
# up to 0.4 % (benchmarks/results/reduce_design_loop.md, round two)
DEFAULT_N_FIXED = 30
DEFAULT_COUPLING = "rbe3"
COUPLINGS = ("rbe2", "rbe3")
TRUNCATION_NOTE = ("Full orthonormalised CB basis stored; statically exact for interface loads "
                   f"only with all modes. Truncation to n_keep (default {DEFAULT_N_KEEP}) is not statically "
                   "exact: see /checks static_error_truncated.")


def cache_key(geometry, mesh_size: float, order: int, pocket_size, coupling: str,
              n_fixed: int, degree: int = 3, centrifugal: bool = True, guide_loads: bool = True,
              inertia_relief: bool = True) -> dict:
    """Every input that changes the reduced cage (the dict hashed into the file name): geometry
    and material, mesh size / geometric order / pocket size, FE degree, coupling, n_fixed,
    centrifugal (basis augmented with the fixed-interface centrifugal response), guide_loads
    (... with the responses to the unit land loads), inertia_relief (... with the responses to
    the rigid-body inertia loads). The schema version is in the key, so a version-3 cache entry
    is never taken for a version-4 request (nor a version-4 entry for version 5)."""
    return {"schema_version": SCHEMA_VERSION, "geometry": geometry.to_dict(),
            "mesh_size": float(mesh_size), "order": int(order), "degree": int(degree),
            "pocket_size": None if pocket_size is None else float(pocket_size),
            "coupling": str(coupling), "n_fixed": int(n_fixed),
            "centrifugal_vector": bool(centrifugal), "guide_load_vectors": bool(guide_loads),
            "inertia_relief_vectors": bool(inertia_relief), "mesh_version": MESH_VERSION}


def cache_path(key: dict) -> Path:
    return cache_dir() / "reduced_cage" / f"{content_hash(key)}.h5"


def find_cached(key: dict, mesh=None) -> Path | None:
    """Path of the cached reduced cage for these inputs, or None (never builds anything); a file
    there is verified first (`verify`: InputError naming it and the fix if it is damaged or another
    cage's), then its provenance against what the caller is about to use (`check_provenance`: the
    parameters it records are `key`, and it was built from `mesh`, the cache's mesh for its key,
    when that mesh is there and whole). A whole file written before issue 36 (no digest to check)
    counts as absent: the caller builds it again, over it."""
    p = cache_path(key)
    if not p.exists() and not p.is_symlink():
        return None
    if _undigested(p):
        return None
    verify(p, expect_key=p.stem)
    check_provenance(p, key, mesh)
    return p


def _canonical(obj) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=repr)


def recorded_mesh_sha256(f) -> str | None:
    """The sha256 of the mesh a reduced cage (open file f) was built from: the root attribute
    mesh_sha256 (covered by its digest), else the /mesh group's msh_sha256 (older files)."""
    v = f.attrs.get("mesh_sha256")
    if v is None and "mesh" in f:
        v = f["mesh"].attrs.get("msh_sha256")
    return None if v is None else str(v)


def check_provenance(path, key: dict, mesh=None) -> None:
    """InputError naming `path` and the fix unless the reduced cage was built from `key` (its
    recorded parameters are that key, by content) and, when `mesh` (the mesh the caller would
    build from: the cache's entry for the key) is there and whole (its own digest,
    flexbearing.mesh.cage_mesh.mesh_digest), from that mesh (the sha256 the file records)."""
    path = Path(path)
    with h5py.File(path, "r") as f:
        raw = f.attrs.get("parameters")
        built_from = recorded_mesh_sha256(f)
    try:
        params = json.loads(raw) if raw is not None else None
    except (TypeError, ValueError):
        params = None
    if params is None or _canonical(params) != _canonical(json.loads(_canonical(key))):
        raise InputError(f"reduced cage file {path} records other parameters than the cage it is "
                         f"asked for (its content_hash names this cage, its parameters another one: "
                         f"an edited file): {_fix(path)}")
    if mesh is not None and built_from is not None:
        have = mesh_digest(mesh)
        if have is not None and have != built_from:
            raise InputError(f"reduced cage file {path} was built from mesh sha256 {built_from[:16]}, the "
                             f"cache's mesh {mesh} for its key is {have[:16]} (a mesh swapped or "
                             f"rebuilt differently): delete both and run again (flexbearing builds them anew)")


def _undigested(path) -> bool:
    try:
        with h5py.File(path, "r") as f:
            return f.attrs.get("schema") == SCHEMA and "data_sha256" not in f.attrs
    except (OSError, IsADirectoryError):
        return False




@dataclass
class ReducedCage:
    """The file's content as arrays (see the schema). Slicing helpers return new objects."""
    frequency_hz: np.ndarray
    omega: np.ndarray
    interface_positions: np.ndarray
    interface_modes: np.ndarray          # (Z, 6, M)
    modal_stiffness: np.ndarray          # (M,)
    invariants: dict
    stress_modes: np.ndarray             # (Nv, 6, M)
    vertices: np.ndarray
    tets: np.ndarray
    vertex_displacement: np.ndarray      # (Nv, 3, M)
    attrs: dict = field(default_factory=dict)
    checks: dict = field(default_factory=dict)
    modes: np.ndarray = None             # indices of the kept modes in the file's full basis
    tets10: np.ndarray | None = None     # (Nc, 10) VTK tetra10 order, quadratic meshes
    guide_modal_loads: np.ndarray | None = None   # (M, 3) per unit land F_y, F_z (N), M_x (N m);
    #                                               None for schema 2-3 files

    def __post_init__(self):
        if self.modes is None:
            self.modes = np.arange(len(self.omega))

    @property
    def n_modes(self) -> int:
        return len(self.omega)

    def select(self, idx) -> "ReducedCage":
        """The same body with only the modes idx (indices into this object's modes)."""
        idx = np.asarray(idx)
        inv = dict(self.invariants)
        for k in ("I3", "I4", "Sx", "S1", "I8"):          # last axis = mode
            inv[k] = inv[k][..., idx]
        inv["I5"] = inv["I5"][:, idx][:, :, idx]
        inv["I6"] = inv["I6"][idx][:, idx]
        for k in ("I9", "SS"):                           # last two axes = modes
            inv[k] = inv[k][..., idx, :][..., idx]
        return ReducedCage(self.frequency_hz[idx], self.omega[idx], self.interface_positions,
                           self.interface_modes[:, :, idx], self.modal_stiffness[idx], inv,
                           self.stress_modes[:, :, idx], self.vertices, self.tets,
                           self.vertex_displacement[:, :, idx], self.attrs, self.checks,
                           self.modes[idx], self.tets10,
                           None if self.guide_modal_loads is None else self.guide_modal_loads[idx])

    def truncate(self, n_keep: int = DEFAULT_N_KEEP) -> "ReducedCage":
        """The first n_keep modes by frequency (rigid ones included)."""
        require_range("reduced_cage.n_keep", n_keep, 1, self.n_modes)
        return self.select(np.arange(int(n_keep)))

    def elastic(self) -> "ReducedCage":
        """Drop the rigid modes (mean-axis frame: the body frame carries the rigid motion)."""
        return self.select(np.flatnonzero(self.modes >= N_RIGID))


def static_correction(interface_modes: np.ndarray, omega: np.ndarray, interface_loads: np.ndarray,
                      first: int, modal_load: np.ndarray | None = None) -> np.ndarray:
    """Quasi-static coordinates of the modes first.. (mode-acceleration / residual-flexibility
    method; Craig & Kurdila, "Fundamentals of Structural Dynamics", 2006, §14.3):

        q_k = (Phi_b,k^T F + g_k) / omega_k^2,   k >= first                           (S)

    interface_modes (Z, 6, M), omega (M), interface_loads (Z, 6) forces N / moments N m at the
    interface nodes in the body frame; modal_load (M,) optional distributed load already in modal
    form, g_k (e.g. centrifugal_modal_load: Omega^2 Q_k; a land load L = (F_y, F_z, M_x):
    guide_modal_loads @ L). Keeping modes < first dynamic and adding (S) for the rest
    restores the static exactness of the full basis (a static load has q_k = (S) for every
    elastic mode because the modal stiffness is diagonal) without putting the high frequencies
    (up to ~100 kHz on the paper cage) into the integrator. Rigid modes (omega = 0) are skipped."""
    Pb = interface_modes[:, :, first:].reshape(-1, interface_modes.shape[2] - first)
    w2 = np.asarray(omega[first:]) ** 2
    f = Pb.T @ np.asarray(interface_loads, dtype=float).ravel()
    if modal_load is not None:
        f = f + np.asarray(modal_load, dtype=float)[first:]
    return np.where(w2 > 0, f / np.where(w2 > 0, w2, 1.0), 0.0)


def centrifugal_modal_load(invariants: dict, spin: float) -> np.ndarray:
    """Modal centrifugal load of the cage spinning at Omega = spin (rad/s) about its axis x:

        Omega^2 Q_k,  Q_k = ∫rho Phi_k · x_perp dV = Sx[1,1,k] + Sx[2,2,k],  x_perp = (0, y, z)

    (N m per unit q; the generalised force of the body force rho Omega^2 x_perp; Shabana,
    "Dynamics of Multibody Systems", ch. 5, the centrifugal term of the elastic equations). With a
    version-3 file (centrifugal vector in the basis) the full basis' static answer
    q_k = Omega^2 Q_k / omega_k^2 is the exact free–free FE response (tests/test_cb_centrifugal.py)."""
    Sx = np.asarray(invariants["Sx"])
    return float(spin) ** 2 * (Sx[1, 1, :] + Sx[2, 2, :])


def modal_damping(omega: np.ndarray, beta: float) -> np.ndarray:
    """Stiffness-proportional damping in modal coordinates, D = beta K = beta diag(omega^2)
    (paper Eq. of the flexible cage, D = beta K); returns the diagonal, N s/m per unit q."""
    return beta * np.asarray(omega) ** 2


def write(path, data: dict, attrs: dict, checks: dict | None = None,
          group_attrs: dict | None = None) -> Path:
    """Write atomically (flexbearing.common.safe_files.atomic_output: a unique temporary in the
    cache folder, created exclusively, fsynced, renamed over the target; removed on every failure,
    a full disk included): a concurrent reader never sees half a file. The digest of the content
    (`data_digest`) is stored with it (`data_sha256`) and checked by `read`. group_attrs:
    {group: {name: value}} attributes of groups of `data` (the mesh's provenance)."""

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # its whole size reserved first: a full cache disk is one line before HDF5 writes anything
    size = sum(np.asarray(a).nbytes for a in data.values()) + (1 << 20)
    with atomic_output(path, suffix=".h5", reserve=size) as tmp:
        with h5py.File(tmp, "w") as f:
            f.attrs["schema"] = SCHEMA
            f.attrs["schema_version"] = SCHEMA_VERSION
            f.attrs["units"] = "SI"
            f.attrs["n_rigid"] = N_RIGID
            f.attrs["default_n_keep"] = DEFAULT_N_KEEP
            f.attrs["notes"] = TRUNCATION_NOTE
            for k, v in attrs.items():
                f.attrs[k] = json.dumps(v) if isinstance(v, (dict, list)) else v
            for name, arr in data.items():
                a = np.asarray(arr)
                if name in QUANTISED_DATASETS:
                    a, scale = quantise(a)
                    filters = _COMPRESSION[name]
                    chunks = (min(len(a), _CHUNK_NODES),) + a.shape[1:] if filters else None
                    f.create_dataset(name, data=a, chunks=chunks, **filters)
                    f.create_dataset(name + SCALE_SUFFIX, data=scale)
                else:
                    f.create_dataset(name, data=a)
            for group, values in (group_attrs or {}).items():
                for k, v in values.items():
                    f[group].attrs[k] = v
            g = f.require_group("checks")
            g.attrs["summary"] = json.dumps(checks or {}, default=_jsonable)
            f.attrs["data_sha256"] = data_digest(f)
    return path


# HDF5 filters of the quantised tables (schema 6), paper cage (benchmarks/results/
# reduce_design_loop.md, round two): shuffle + gzip 1 takes the stress 35.0 -> 31.0 MB for 0.6 s
# of the write; the displacement only 17.5 -> 17.1 MB for 0.3 s, so it is stored plain
_COMPRESSION = {"stress/modes": {"shuffle": True, "compression": "gzip", "compression_opts": 1},
                "modes/vertex_displacement": {}}


def quantise(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A mode table T (N, C, M) as 16-bit integers and one scale per (component c, mode k):

        s_ck = max_n |T_nck| / 32767,   I_nck = round(T_nck / s_ck),   T~_nck = s_ck I_nck
        |T~_nck - T_nck| <= s_ck / 2 = max_n |T_nck| / 65534                                 (Q)

    (uniform scalar quantisation with rounding to nearest, e.g. Gray & Neuhoff, "Quantization",
    IEEE Trans. Inf. Theory 44 (1998), §I; the bound is half a step). A column that is all zero
    (a rigid mode's stress) gets s = 0 and reads back exactly 0. Returns (I int16, s float64 (C, M))."""
    t = np.asarray(table, dtype=np.float64)
    peak = np.abs(t).max(axis=0)
    scale = peak / _INT16_MAX
    safe = np.where(scale > 0, scale, 1.0)
    return np.rint(t / safe).astype(np.int16), scale


def dequantise(ints: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """T~ = s I (float64) of `quantise`'s (I, s)."""
    return ints * np.asarray(scale, dtype=np.float64)


def quantisation_bound(scale: np.ndarray, q: np.ndarray) -> float:
    """Largest change of the maximum von Mises stress over the mesh (Pa) that the 16-bit storage
    of the stress modes (`quantise`, scale (6, M) of stress/modes) can make to sigma = S q:

        e_c = 1/2 sum_k s_ck |q_k|       (|delta sigma_nc| <= e_c at every node n, from (Q))
        |max_n vm(S~ q) - max_n vm(S q)| <= max_n vm(delta sigma_n)
          <= sqrt(1/2 [(e_xx+e_yy)^2 + (e_yy+e_zz)^2 + (e_zz+e_xx)^2] + 3 (e_yz^2 + e_xz^2 + e_xy^2))

    (von Mises is a seminorm of the Voigt vector, so the triangle inequality moves the maximum by
    at most the von Mises of the error; each square is bounded term by term by the e_c). It grows
    with sum_k |q_k| max|S_k|, not with the result: cancellation between modes is what it covers."""
    e = 0.5 * np.asarray(scale, dtype=np.float64) @ np.abs(np.asarray(q, dtype=np.float64))
    xx, yy, zz, yz, xz, xy = e
    return float(np.sqrt(0.5 * ((xx + yy) ** 2 + (yy + zz) ** 2 + (zz + xx) ** 2)
                         + 3.0 * (yz ** 2 + xz ** 2 + xy ** 2)))


# the root attributes the digest covers: what the file is (its cache key) and its parameters; and,
# when the file has it (written since issue 43), the sha256 of the mesh it was built from
_DIGEST_ATTRS = ("schema_version", "content_hash", "parameters", "n_modes")
_DIGEST_ATTRS_IF_PRESENT = ("mesh_sha256",)


def data_digest(f) -> str:
    """SHA-256 of an open reduced cage file's content: every dataset (name, dtype, shape, bytes,
    in name order) and the root attributes that say what the file is (_DIGEST_ATTRS), so that a
    flipped bit anywhere in the arrays, or a valid file of another cage copied over the key, does
    not match the digest stored in it."""
    h = hashlib.sha256()
    names = []
    f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    for name in sorted(names):
        a = np.ascontiguousarray(f[name][()])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes() if a.dtype != object else repr(a.tolist()).encode())
    for k in _DIGEST_ATTRS:
        v = f.attrs.get(k)
        # as a Python value: numpy 2 writes a scalar's repr as "np.int64(26)", numpy 1 as "26", and
        # a file written on one FE stack (docs/install.md) is read on the other
        v = v.item() if isinstance(v, np.generic) else v
        h.update(f"{k}={v!r};".encode())
    for k in _DIGEST_ATTRS_IF_PRESENT:
        if k in f.attrs:
            v = f.attrs.get(k)
            v = v.item() if isinstance(v, np.generic) else v
            h.update(f"{k}={v!r};".encode())
    return h.hexdigest()


class DamagedCacheFile(ValueError):
    """A cache file whose content does not match what it says it is (or cannot be read)."""


def _fix(path) -> str:
    return (f"delete {path} and run again (flexbearing builds it anew; `flexbearing reduce --force` "
            f"does it now)")


def verify(path, expect_key: str | None = None) -> None:
    """InputError naming `path` and the fix if the file cannot be read, is not a reduced cage, its
    content does not match its stored digest (data_sha256), or it is not the cage of cache key
    `expect_key` (its content_hash)."""

    path = Path(path)
    if path.is_dir():
        raise InputError(f"reduced cage file {path} is a folder, not a file: remove it (the cache "
                         f"builds the file again)")
    try:
        if not h5py.is_hdf5(path):
            raise InputError(f"reduced cage file {path} is not an HDF5 file "
                             f"({path.stat().st_size} bytes): {_fix(path)}")
        with h5py.File(path, "r") as f:
            stored = f.attrs.get("data_sha256")
            key = str(f.attrs.get("content_hash", ""))
            if f.attrs.get("schema") != SCHEMA:
                raise InputError(f"{path} is not a reduced cage file (schema {f.attrs.get('schema')!r}): "
                                 f"{_fix(path)}")
            actual = data_digest(f) if stored is not None else None
    except OSError as exc:
        raise InputError(f"reduced cage file {path} is damaged or truncated ({exc}): {_fix(path)}") from None
    if stored is None:
        raise InputError(f"reduced cage file {path} carries no content digest (written before "
                         f"issue 36), so it cannot be checked: {_fix(path)}")
    if actual != str(stored):
        raise InputError(f"reduced cage file {path} is damaged: its content does not match the digest "
                         f"stored in it: {_fix(path)}")
    if expect_key is not None and key != expect_key:
        raise InputError(f"reduced cage file {path} holds the cage of key {key}, not {expect_key} "
                         f"(a file copied over the cache entry): {_fix(path)}")


def _jsonable(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    return repr(x)


def _mode_table(f, name) -> np.ndarray:
    """A mode table as float64: dequantised (schema 6), or float32 / float64 widened (5 and older)."""
    if name + SCALE_SUFFIX in f:
        return dequantise(f[name][()], f[name + SCALE_SUFFIX][()])
    return f[name][()].astype(float, copy=False)


def read(path) -> ReducedCage:
    """Load a reduced cage file (checks schema and version)."""
    with h5py.File(path, "r") as f:
        if f.attrs.get("schema") != SCHEMA:
            raise ValueError(f"{path}: not a {SCHEMA} file")
        ver = int(f.attrs["schema_version"])
        if ver not in READABLE_VERSIONS:
            raise ValueError(f"{path}: schema_version {ver}, this flexbearing reads "
                             f"{', '.join(map(str, READABLE_VERSIONS))}")
        attrs = {k: (json.loads(v) if k == "parameters" else v) for k, v in f.attrs.items()}
        attrs.setdefault("centrifugal_vector", False)
        attrs.setdefault("guide_load_vectors", False)
        attrs.setdefault("inertia_relief_vectors", False)
        # None for version 2-3 (and for a hand-made file without /loads, e.g. a test's synthetic
        # cage): the runtime then applies the land load to the floating frame only
        gml = f["loads/guide_modal_loads"][()] if "loads/guide_modal_loads" in f else None
        inv = {k: (f["invariants"][k][()]) for k in f["invariants"]}
        checks = json.loads(f["checks"].attrs.get("summary", "{}"))
        return ReducedCage(
            frequency_hz=f["modes/frequency_hz"][()], omega=f["modes/omega"][()],
            interface_positions=f["interface/positions"][()],
            interface_modes=f["modes/interface"][()],
            modal_stiffness=f["modes/modal_stiffness"][()], invariants=inv,
            stress_modes=_mode_table(f, "stress/modes"), vertices=f["mesh/vertices"][()],
            tets=f["mesh/tets"][()],
            vertex_displacement=_mode_table(f, "modes/vertex_displacement"),
            attrs=attrs, checks=checks,
            tets10=f["mesh/tets10"][()] if "tets10" in f["mesh"] else None,
            guide_modal_loads=gml)
