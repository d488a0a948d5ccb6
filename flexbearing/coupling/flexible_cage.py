"""The flexible cage body: the reduced cage file turned into floating-frame arrays.

`flexible_cage_body(rc, n_keep, beta, centrifugal_correction)` selects the modal basis the run
integrates and transforms every quantity the floating-frame equations (flexbearing.multibody.floating_frame),
the pocket coupling and the stress recovery need into that basis:

    Phi_run = Phi_full · T          (T: (M_elastic, n) — a selection plus an optional extra column)

The reduced cage file holds the full M-orthonormal Craig–Bampton basis sorted by frequency
(flexbearing.fem_cage.reduced_cage). The run keeps the paper's 26 modes — 6 rigid, carried by the floating
frame, and the 20 lowest elastic ones (n_keep counts the rigid ones, as the paper and ADAMS do).

Centrifugal correction (modal truncation augmentation, Dickens, Nakagawa & Wittbrodt, Comput.
Struct. 62 (1997) 985). The spinning cage's centrifugal load f = rho·Omega²·x_perp excites the
axisymmetric (n = 0) extensional deformation of the ring, whose first mode (~ sqrt(E/rho)/(2·pi·R)
≈ 9–10 kHz here) lies above the 26 kept modes: a plain truncation recovers no hoop stress at all.
The static response of the *discarded* modes to that load,

    q_k = Q_k / omega_k²,   Q_k = ∫rho Phi_k · x_perp dV = Sx[1,1,k] + Sx[2,2,k]   (k discarded)

normalised to unit modal mass, is appended as one more Ritz vector. It lives in the span of the
discarded modes, so it is M- and K-orthogonal to the kept ones: the modal mass stays the identity
and the modal stiffness diagonal, its own entry being the Rayleigh quotient Σ q_k² omega_k² / Σ q_k².
With it the kept basis reproduces the full basis's static centrifugal response exactly. Off by
default: the run (`backend`) instead treats every discarded mode quasi-statically in the stress
recovery (`StressRecovery`), which covers the centrifugal and the pocket loads alike.

Damping: D = beta·K (paper), i.e. modal damping beta·omega_k².
"""
from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np

import flexbearing.mesh.cage_mesh as cm
from flexbearing.common.cache import content_hash
from flexbearing.common.validation import InputError, require_range
from flexbearing.fem_cage import reduced_cage as rcf
from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP, N_RIGID, static_correction
from flexbearing.fem_cage.stress_modes import von_mises
from flexbearing.fem_cage.von_mises_search import TrackingMaxVonMises, load_space_blocks, load_space_stress
from flexbearing.multibody import initial, integrator, model as mb, outputs, stress_peak
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.cage_body import cage_body_angular_velocity, cage_rotation
from flexbearing.multibody.floating_frame import FlexibleBody
from flexbearing.multibody.run_backend import RunBackend, select_recorded
from flexbearing.multibody.stress_peak import new_monitor


class CageModalBasis(NamedTuple):
    body: FlexibleBody
    transform: np.ndarray        # (M_full, n): run modal coordinates -> full-basis coordinates
    frequency_hz: np.ndarray     # (n,) of the run's modes (the correction's Rayleigh frequency last)
    stress_modes: np.ndarray     # (Nv, 6, n) Pa per unit q
    vertex_displacement: np.ndarray  # (Nv, 3, n) m per unit q


def centrifugal_generalised_force(Sx: np.ndarray) -> np.ndarray:
    """Q_k = ∫rho Phi_k · x_perp dV (x the bearing axis): the modal centrifugal load per unit Omega²."""
    return Sx[1, 1, :] + Sx[2, 2, :]


def modal_transform(omega: np.ndarray, Sx: np.ndarray, n_keep: int, centrifugal_correction: bool,
                    n_rigid: int = N_RIGID) -> np.ndarray:
    """T (M_full, n): keep modes n_rigid..n_keep-1, plus the centrifugal Ritz vector if asked."""
    M = omega.shape[0]
    keep = np.arange(n_rigid, n_keep)
    cols = [np.eye(M)[:, keep]] if keep.size else [np.zeros((M, 0))]
    if centrifugal_correction and n_keep < M:
        rest = np.arange(n_keep, M)
        Q = centrifugal_generalised_force(Sx)
        q = np.zeros(M)
        q[rest] = Q[rest] / omega[rest] ** 2
        norm = np.linalg.norm(q)
        if norm > 0.0:
            cols.append((q / norm)[:, None])
    return np.hstack(cols)


def guide_modal_loads(rc):
    """(M, 3) modal loads of the guide-surface land load per unit body-frame force y, z (N) and
    torque about x (N m) in the file's full basis (flexbearing.fem_cage.reduced_cage, schema >= 4), or None
    for an older file (its land load then acts on the floating frame only)."""
    G = getattr(rc, "guide_modal_loads", None)
    return None if G is None else np.asarray(G, dtype=float)


def load_point_modes(rc) -> np.ndarray:
    """(Z + 1, 6, M): the interface modes of the Z pockets and, as load point Z, the guide
    surface: rows 0..2 its modal loads per unit land force y, z and torque x (rows 3..5 zero),
    so the residual static correction Phi_bᵀ·F covers the pocket and the land loads alike with
    the node-load array of the model (flexbearing.multibody.model: row Z = the land load)."""
    Z, _, M = rc.interface_modes.shape
    out = np.zeros((Z + 1, 6, M))
    out[:Z] = rc.interface_modes
    G = guide_modal_loads(rc)
    if G is not None:
        out[Z, :3] = G.T
    return out


def flexible_cage_body(rc, n_keep: int = DEFAULT_N_KEEP, beta: float = 0.0,
                       centrifugal_correction: bool = False) -> CageModalBasis:
    """Floating-frame arrays of the reduced cage `rc` (flexbearing.fem_cage.reduced_cage.ReducedCage, full
    basis) for a run keeping n_keep modes (rigid included), damping D = beta·K."""
    M = rc.n_modes
    require_range("cage.n_modes", n_keep, N_RIGID, M)
    require_range("cage.damping_beta", beta, 0.0, 1.0, unit="s")
    inv = rc.invariants
    T = modal_transform(rc.omega, inv["Sx"], int(n_keep), centrifugal_correction)
    omega2 = rc.omega ** 2
    # modal stiffness in the run basis: Tᵀ diag(omega²) T (diagonal by construction)
    kdiag = np.einsum("kn,k,kn->n", T, omega2, T)
    Sx = inv["Sx"] @ T
    SS = np.einsum("abjk,jm,kn->abmn", inv["SS"], T, T, optimize=True)
    S1 = inv["S1"] @ T
    Mff = T.T @ inv["I6"] @ T
    mass = float(inv["mass"])
    first = np.asarray(inv["first"], dtype=float)
    second = np.asarray(inv["second"], dtype=float)
    G = guide_modal_loads(rc)
    body = FlexibleBody(mass, first, second, np.ascontiguousarray(S1), np.ascontiguousarray(Sx),
                        np.ascontiguousarray(SS), np.ascontiguousarray(Mff), kdiag, beta * kdiag,
                        np.ascontiguousarray(rc.interface_positions, dtype=float),
                        np.ascontiguousarray(rc.interface_modes @ T),
                        None if G is None else np.ascontiguousarray((T.T @ G).T))
    return CageModalBasis(body, T, np.sqrt(np.maximum(kdiag, 0.0)) / (2 * np.pi),
                          np.ascontiguousarray(rc.stress_modes @ T),
                          np.ascontiguousarray(rc.vertex_displacement @ T))


# stiffness-proportional modal damping D = beta K of a scene that does not set cage.damping_beta, s
DEFAULT_DAMPING_BETA = 1e-5


# --------------------------------------------------------------------------- the run's backend
def _mesh_inputs(scene) -> tuple[float, float, int]:
    """(element size, pocket element size, FE degree) of the scene's reduced cage mesh."""
    size = scene.flexible.get("mesh_size", cm.DEFAULT_MESH_SIZE)
    return size, min(cm.DEFAULT_POCKET_SIZE, size), scene.flexible.get("element_order", cm.DEFAULT_DEGREE)


def reduced_cage_key(scene) -> dict:
    """Every input that changes the scene's reduced cage (flexbearing.fem_cage.reduced_cage.cache_key); its
    content hash names the cached file (flexbearing.fem_cage.reduced_cage.cache_path)."""
    size, pocket, degree = _mesh_inputs(scene)
    key = rcf.cache_key(scene.bearing.cage, size, cm.DEFAULT_ORDER, pocket, rcf.DEFAULT_COUPLING,
                        rcf.DEFAULT_N_FIXED, degree, True)
    if scene.cad:
        key["cad"] = scene.cad["key"]          # the CAD file by its content (flexbearing.mesh.cad_cage)
    return key


def reduced_cage_hash(scene) -> str:
    """The content hash of the scene's reduced cage (the cached file's stem): two scenes share a
    reduced cage exactly when their hashes are equal."""
    return content_hash(reduced_cage_key(scene))


def scene_mesh_path(scene) -> Path:
    """Where the cache keeps the mesh the scene's reduced cage is built from (the parametric
    cage's, or the CAD cage's by its files' content): what a cached reduced cage's provenance is
    checked against (flexbearing.fem_cage.reduced_cage.check_provenance)."""
    size, pocket, _ = _mesh_inputs(scene)
    if scene.cad:
        from flexbearing.mesh.cad_cage import cad_mesh_cache_path
        return cad_mesh_cache_path(scene.cad["key"], size, pocket, cm.DEFAULT_ORDER)[0]
    return cm.cache_path(scene.bearing.cage, size, cm.DEFAULT_ORDER, pocket)


def reduced_cage_path(scene, quiet: bool = False):
    """The reduced cage file for the scene's cage: from the cache, or built once (imports the FE
    stack only then). Key = every input that changes it (reduced_cage_key); a cached file is used
    only when it was built from that key and the cache's mesh (rcf.find_cached)."""
    size, pocket, degree = _mesh_inputs(scene)
    key = reduced_cage_key(scene)
    path = rcf.find_cached(key, scene_mesh_path(scene))
    if path is None:
        from flexbearing.fem_cage.reduction import build      # the FE stack: only to build it
        if not quiet:
            print(f"building the reduced cage (mesh {size * 1e3:g} mm, P{degree}, Craig–Bampton; "
                  "~25 s at the default mesh with OpenBLAS, ~40 s without; once): "
                  + str(rcf.cache_path(key)), flush=True)
        mesh = cad_key = None
        if scene.cad:
            from flexbearing.mesh.cad_cage import cached_cad_cage_mesh
            b = scene.bearing
            mesh, _ = cached_cad_cage_mesh(scene.cad["file"], b.n_balls, b.pitch_diameter, b.ball_diameter,
                                           b.cage.guidance, scene.cad["unit"], b.cage.material, size, pocket,
                                           cm.DEFAULT_ORDER, expect_key=scene.cad["key"])
            cad_key = scene.cad["key"]
        path, _, _ = build(scene.bearing.cage, size, cm.DEFAULT_ORDER, pocket, rcf.DEFAULT_COUPLING,
                           rcf.DEFAULT_N_FIXED, quiet=quiet, degree=degree, centrifugal=True,
                           mesh=mesh, cad_key=cad_key)
    return path


class StressRecovery:
    """Maximum von Mises stress of the cage from a state of the run, exact over the mesh nodes.

    The run integrates the kept modes q (n_keep − 6 elastic); the discarded modes of the full
    Craig–Bampton basis follow quasi-statically (residual flexibility / mode acceleration, Craig &
    Kurdila 2006 §14.3; flexbearing.fem_cage.reduced_cage.static_correction):

        q_k = (Phi_b,kᵀ·F_nodes + G_kᵀ·L + Omega_x²·Q_cf,k) / omega_k²,   k >= n_keep

    F_nodes the pocket-node loads (body frame), L the guide-land force y, z and torque x (body
    frame) with G its modal loads (load_point_modes), Omega_x the cage's spin, Q_cf the
    centrifugal modal load. The stress field is sigma = S·q_full (stress modes of the full basis).

    The run evaluates it in load space, sigma_n = W_n·y with y = (Omega_x², q_kept, F_nodes and L)
    (flexbearing.fem_cage.von_mises_search.load_space_stress, built here from the reduced cage: ~0.9 s on the 4 mm paper cage), by the
    exact tracking search flexbearing.fem_cage.von_mises_search.TrackingMaxVonMises inside a compiled peak-hold the
    integrator runs after every accepted step (`monitor`, flexbearing.multibody.stress_peak). `__call__`
    evaluates a full modal vector directly (numpy, every vertex: the textbook formula, an
    independent path for the first sample of a run and for checks).
    """

    def __init__(self, rc, n_keep: int, cache: str | Path | None = None):
        """cache: a file for the search (built once per reduced cage and mode count, then read:
        `search_cache_path`); None builds it every time."""
        self.rc = rc
        self.n_keep = int(n_keep)
        self.omega = np.asarray(rc.omega, dtype=float)
        self.q_cf = centrifugal_generalised_force(rc.invariants["Sx"])
        self.M = rc.n_modes
        self.load_modes = load_point_modes(rc)     # pockets + the guide surface (row Z)
        self.n_elastic = self.n_keep - N_RIGID
        # the reduced cage's content digest (flexbearing.fem_cage.reduced_cage.data_digest): a search
        # file built from another file's content is not read
        self.source = str(getattr(rc, "attrs", {}).get("data_sha256", ""))
        # the load-space stress, from the reduced cage every time (~1 s on the 4 mm paper cage):
        # the search file keeps only the tree, not this second copy of the stress modes
        W = load_space_stress(self.rc.stress_modes, self.omega, self.load_modes, self.q_cf, self.n_keep)
        self.search = self._read_search(cache, W)
        if self.search is None:
            self.search = self._build_search(W)
            if cache is not None:
                try:
                    self.search.save(cache, self.source)
                except OSError:            # a read-only or full cache folder: build it each run
                    pass
        # made now, before any search: a copy of the search's state taken while the monitor
        # mutates it in the other thread could be torn
        self._own = self.search.with_own_state()

    def _build_search(self, W):
        tracked, loads = load_space_blocks(self.n_elastic, self.load_modes.shape[0])
        return TrackingMaxVonMises(W, 1 + self.n_elastic, tracked, loads, coords=self.rc.vertices)

    def _read_search(self, cache, W):
        if cache is None or not Path(cache).is_file():
            return None
        try:
            search = TrackingMaxVonMises.load(cache, W, self.source)
        except Exception:          # damaged or partial (a bad zip, CRC, truncated array...): rebuilt and
            return None            # written again by __init__

        K = 1 + self.n_elastic + 6 * self.load_modes.shape[0]
        if search is None or search.n_coordinates != K or search.A.shape[0] != self.rc.stress_modes.shape[0]:
            return None
        return search

    def full_coordinates(self, q_kept, node_load, spin) -> np.ndarray:
        q = np.zeros(self.M)
        q[N_RIGID:self.n_keep] = q_kept[: self.n_keep - N_RIGID]
        w2 = self.omega[self.n_keep:] ** 2
        nl = np.zeros((self.load_modes.shape[0], 6))
        nl[:len(node_load)] = node_load                # (Z, 6) pockets only, or (Z + 1, 6) with the land
        q[self.n_keep:] = (static_correction(self.load_modes, self.omega, nl, self.n_keep)
                           + spin ** 2 * self.q_cf[self.n_keep:] / w2)
        return q

    def load_vector(self, q_kept, node_load, spin) -> np.ndarray:
        """y = (Omega_x², q_kept, node loads) of the load-space form (what the monitor builds)."""
        nl = np.zeros((self.load_modes.shape[0], 6))
        nl[:len(node_load)] = node_load
        return np.concatenate([[spin * spin], np.asarray(q_kept, dtype=float)[:self.n_elastic],
                               nl.ravel()])

    def full_coordinates_of(self, y) -> np.ndarray:
        """The full modal coordinates of a load-space vector y (inverse of load_vector)."""
        e = self.n_elastic
        return self.full_coordinates(y[1:1 + e], y[1 + e:].reshape(-1, 6), np.sqrt(max(y[0], 0.0)))

    def __call__(self, q_full) -> tuple[float, int]:
        """(max von Mises Pa, vertex) of the full modal vector q_full: sigma = S·q_full at every
        vertex, von Mises by the textbook formula (numpy)."""
        vm = von_mises(np.einsum("nsm,m->ns", self.rc.stress_modes, q_full))
        k = int(np.argmax(vm))
        return float(vm[k]), k

    def vertex(self, row: int) -> int:
        """Mesh vertex of a search row (what the compiled monitor returns)."""
        return int(self.search.node_ids[row])

    def at_state(self, q_kept, node_load, spin) -> tuple[float, int]:
        """(max von Mises Pa, vertex) at one state by the exact tracking search in load space, on a
        search of its own (`TrackingMaxVonMises.with_own_state`: the compiled monitor mutates the
        shared one in the integrating thread while the writer thread evaluates samples). ~0.1 ms
        against ~13 ms for `__call__`'s every-vertex formula: what a sample that no monitored step
        reached costs (`cage.stress_monitor_interval` > 1)."""
        return self._own(self.load_vector(q_kept, node_load, spin))

    def monitor(self, cage_offset: int, modes_offset: int, trace: int = 0, interval: int = 1) -> tuple:
        """The compiled peak-hold (flexbearing.multibody.stress_peak), evaluated every `interval`-th accepted step."""
        return new_monitor(self.search.arrays, self.load_modes.shape[0], cage_offset,
                           modes_offset, self.n_elastic, trace, interval)


def search_cache_path(reduced_cage_file, rc, n_keep: int) -> Path:
    """Where the stress search of a reduced cage and mode count is kept: beside the reduced cage
    file, named by its content hash, the mode count and the search's file version (a changed cage,
    mode count or search code never reads an old file)."""
    key = str(rc.attrs.get("content_hash", Path(reduced_cage_file).stem))
    return Path(reduced_cage_file).with_name(
        f"{key}.stress-search.k{int(n_keep)}.v{TrackingMaxVonMises.FILE_VERSION}.npz")


_NOW = object()      # evaluate_outputs: take the stress snapshot at the call (no sample_snapshot before)


def _scene_reduced_cage(scene, reduced_cage):
    """(path, ReducedCage) of the scene's cage (`backend`): the given file, verified and checked
    to be the scene's cage by its content hash, or the cache's (built if missing)."""
    if reduced_cage is None:
        path = reduced_cage_path(scene)
    else:
        path = Path(reduced_cage)
        if not path.is_file():
            raise InputError(f"reduced cage file {path} does not exist here: the cache folder "
                             f"(FLEXBEARING_CACHE) must be one every worker sees, at the same path")
    if reduced_cage is not None:
        rcf.verify(path)           # (the cache's own file was verified by find_cached)
    rc = rcf.read(path)
    if reduced_cage is not None and str(rc.attrs.get("content_hash")) != reduced_cage_hash(scene):
        raise InputError(f"reduced cage file {path} (hash {rc.attrs.get('content_hash')}) is not the "
                         f"cage of scene {scene.name} (hash {reduced_cage_hash(scene)})")
    if reduced_cage is not None:   # and built from the scene's parameters and the cache's mesh
        rcf.check_provenance(path, reduced_cage_key(scene), scene_mesh_path(scene))
    return path, rc


def _add_stress_outputs(stress, model, t, y, q, c0, snapshot, out) -> None:
    """The cage stress outputs of a sample into out (`backend`'s evaluate_outputs): von_mises_max,
    its vertex, time and step count, and the full modal coordinates of that step, from the
    monitor's snapshot, or at (t, y) itself (the first sample, or one no step led to)."""
    if snapshot is None:
        A = model.cage.A
        cage_rotation(y[c0 + SL.CAGE_PHI], y[c0 + SL.CAGE_TILT_Y], y[c0 + SL.CAGE_TILT_Z], A)
        w = np.zeros(3)
        cage_body_angular_velocity(A, y, c0, w)
        spin = w[0]                                         # body-frame spin component
        qf = stress.full_coordinates(q, model.cage.node_load, spin)
        # the first sample by the every-vertex formula (an independent check of the
        # search's first value); later ones no monitored step reached by the search
        vm, node = stress(qf) if t == 0.0 else stress.at_state(q, model.cage.node_load, spin)
        t_peak, n_eval = t, 1
    else:
        vm, t_peak, n_eval = snapshot.von_mises, snapshot.time, snapshot.steps
        node = stress.vertex(snapshot.row)
        qf = stress.full_coordinates_of(snapshot.load_space)
    out["von_mises_max"] = float(vm)
    out["von_mises_max_vertex"] = int(node)
    out["von_mises_max_time"] = float(t_peak)
    out["von_mises_steps"] = int(n_eval)
    out["cage_modal_coordinates_full"] = qf


def backend(scene, reduced_cage=None):
    """The flexible-cage physics for flexbearing.simulation.run: the multibody model with the reduced cage as
    its floating-frame body (the scene's cage.n_modes, by default DEFAULT_N_KEEP = 26), its initial
    state with the cage's quasi-static centrifugal deformation, and outputs extended by the cage
    stress.

    reduced_cage: the reduced cage file to use (a study's jobs get the path of the file built once
    for them, flexbearing.studies.study); it must be the scene's cage (its content hash is checked). Default:
    from the cache, built if missing (reduced_cage_path)."""
    path, rc = _scene_reduced_cage(scene, reduced_cage)
    n_keep = int(scene.flexible.get("n_modes", DEFAULT_N_KEEP))
    beta = float(scene.flexible.get("damping_beta", DEFAULT_DAMPING_BETA))
    basis = flexible_cage_body(rc, n_keep, beta, centrifugal_correction=False)
    stress = (StressRecovery(rc, n_keep, cache=search_cache_path(path, rc, n_keep))
              if "von_mises" in scene.outputs else None)
    monitor_interval = int(scene.flexible.get("stress_monitor_interval", 1))
    n = basis.body.n_modes
    file_attrs = {"reduced_cage_file": str(Path(path).resolve()),
                  "reduced_cage_hash": str(rc.attrs.get("content_hash", Path(path).stem)),
                  # its content digest: `report` uses only the reduced cage of this content
                  "reduced_cage_sha256": str(rc.attrs.get("data_sha256", "")),
                  "cage_n_modes": n_keep}

    def build_model(bearing, oil, options):
        return mb.build_model(bearing, oil, options, cage_body=basis.body)

    def initial_state(model, speed_rad_s, Fa, Fr, load=None):
        y = np.array(initial.initial_state(model, speed_rad_s, Fa, Fr, load=load), dtype=np.float64)
        lay = mb.state_layout(model)
        # start on the static centrifugal deformation of the spinning cage (no breathing transient)
        spin = y[lay["cage"] + SL.CAGE_OMEGA]
        y[lay["modes"]:lay["modes"] + n] = spin ** 2 * (basis.body.Sx[1, 1] + basis.body.Sx[2, 2]) / basis.body.stiffness
        return y

    monitors = {}          # one compiled peak-hold per model (flexbearing.multibody.stress_peak)

    def monitor_of(model):
        key = id(model)
        if key not in monitors:
            lay = mb.state_layout(model)
            monitors[key] = (model, stress.monitor(lay["cage"], lay["modes"], interval=monitor_interval))
        return monitors[key][1]

    def advance(model, y, t, t_next, speed_table, load_table, impacts, tol=integrator.DEFAULT_TOL,
                h=1e-6, ws=None, max_steps=10_000_000, method="dopri5", max_step=integrator.H_MAX):
        mon = monitor_of(model) if stress is not None else None
        return integrator.advance(model, y, t, t_next, speed_table, load_table, impacts, tol, h, ws,
                                  max_steps, method, monitor=mon, max_step=max_step)

    def advance_sampled(model, y, t, t_next, sample_times, speed_table, load_table, impacts,
                        tol=integrator.DEFAULT_TOL, h=1e-6, ws=None, max_steps=10_000_000, method="dopri5",
                        max_step=integrator.H_MAX):
        """`advance` writing the states at sample_times on the way; each sample's snapshot is the
        monitor's peak since the previous sample (flexbearing.multibody.integrator.advance_sampled)."""
        mon = monitor_of(model) if stress is not None else None
        return integrator.advance_sampled(model, y, t, t_next, sample_times, speed_table, load_table, impacts,
                                          tol, h, ws, max_steps, method, monitor=mon, max_step=max_step)

    def sample_snapshot(model):
        """What a sample must take when it is reached (flexbearing.simulation.run evaluates the rest later): the
        stress monitor's peak since the previous sample, the monitor then emptied; None without
        stress or when no step was evaluated since."""
        if stress is None:
            return None
        mon = monitor_of(model)
        pk = stress_peak.peak(mon)
        stress_peak.reset(mon)
        return pk

    def evaluate_outputs(model, t, y, request, snapshot=_NOW):
        """Outputs at the sample (t, y). With stress recorded, von_mises_max is the largest value
        over every integrator step since the previous sample (the compiled monitor: `snapshot`, the
        peak `sample_snapshot` took at the sample, or taken now), with the vertex, the time it
        occurred and the full modal coordinates of that step; at a sample no step led to (the
        first) it is evaluated at (t, y) itself."""
        if snapshot is _NOW:
            snapshot = sample_snapshot(model)
        out = outputs.evaluate_outputs(model, t, y, request.speed_table, request.load_table, request.impacts,
                                       film=request.film, energy=request.energy)
        lay = mb.state_layout(model)
        q = y[lay["modes"]:lay["modes"] + n]
        out["cage_modal_coordinates"] = q.copy()
        if stress is not None:
            _add_stress_outputs(stress, model, t, y, q, lay["cage"], snapshot, out)
        return select_recorded(out, request)

    # the units of these outputs: flexbearing.multibody.output_registry (groups "von_mises", "cage_modes")
    return RunBackend(build_model=build_model, initial_state=initial_state,
                      advance=advance, advance_sampled=advance_sampled,
                      evaluate_outputs=evaluate_outputs, sample_snapshot=sample_snapshot,
                      new_workspace=integrator.Workspace, file_attrs=file_attrs, reduced_cage=rc)
