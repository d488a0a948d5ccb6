"""The Craig–Bampton reduction of the cage: build the reduced cage file (our modal neutral file).

Pipeline (fem_cage modules in brackets):
  mesh (flexbearing.mesh.cage_mesh, cached) -> K, M (elasticity) -> pocket interface nodes and RBE2/RBE3
  coupling (interface) -> constraint + fixed-interface modes + the fixed-interface static
  response to the centrifugal load (default), to the three unit land (guide-surface) loads and to
  the six rigid-body inertia loads, modified CB orthonormalisation (craig_bampton) -> invariants
  (invariants) -> vertex stress modes (stress_modes) -> HDF5 file (reduced_cage), cached under
  a hash of every input. `build` does it all and, with checks=True, verifies the result
  (flexbearing.fem_cage.reduction_check). Command line: `flexbearing reduce` (flexbearing.cli.reduce).
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP
from flexbearing.mesh.cage_mesh import TAG_GUIDE
from .stress_modes import stress_modes
from flexbearing.common.validation import InputError
from flexbearing.mesh.cage_mesh import cached_cage_mesh, mesh_quality_of
from . import reduced_cage as rcf
from flexbearing.common.progress import Stages


# ------------------------------------------------------------------ the reduction

# The parts of `build` with their wall times on the paper cage (s; P3, 4 mm mesh, 160,572 dofs,
# OpenBLAS, a quiet 2-core machine: benchmarks/results/reduce_design_loop.json "round_three", 22.5 s
# in all; "K and M" and "write" share the 3.1 s outside the reduction): the progress bar's estimate
# (flexbearing.common.progress). "checks" was not measured: a guess.
REDUCE_STAGES = {"mesh": 1.3, "K and M": 2.1, "interface": 0.3, "Craig-Bampton modes": 13.6,
                 "invariants": 0.7, "stress modes": 3.4, "checks": 300.0, "write": 1.0}


def centrifugal_load(M, X: np.ndarray) -> np.ndarray:
    """Consistent nodal centrifugal load of the cage spinning about its axis x, per unit Omega^2:

        f_cf = M x_perp,   x_perp = (0, y, z)   (N per (rad/s)^2; body force rho Omega^2 x_perp)

    M: blocked vector mass matrix (dof = 3 node + component), X (N, 3) node coordinates (the FE
    interpolant of x_perp is exact: the coordinate field is in the FE space)."""
    xp = np.zeros(3 * len(X))
    xp[1::3], xp[2::3] = X[:, 1], X[:, 2]
    return M @ xp


def resultant(f: np.ndarray, X: np.ndarray) -> np.ndarray:
    """(F, M) = (sum_i f_i, sum_i x_i × f_i), 6-vector (N, N m about the body origin): the work
    of nodal load f on the unit rigid motions t + omega × x (flexbearing.fem_cage.interface.rigid_field), R^T f.
    For a consistent load f_i = ∫ N_i t dA it equals (∫ t dA, ∫ x × t dA) exactly when the
    coordinate field is in the FE space (isoparametric / superparametric Lagrange, degree >= the
    geometry order)."""
    from .interface import rigid_field
    return rigid_field(X).T @ f


def guide_load_vectors(V, facet_tags, tag: int = TAG_GUIDE, quadrature_degree: int | None = None):
    """Consistent nodal loads on the guide surface (facet tag 200: the outside cylinder r = R_out,
    or the two lands of a relieved cage) statically equivalent to a unit land force along y, along
    z, and a unit land torque about the cage axis x; body frame, theta = atan2(z, y),
    e_r = (0, cos theta, sin theta), e_theta = (0, -sin theta, cos theta):

        f_y,i = ∫_guide N_i c cos(theta) e_r dA,   c = 1 / ∫_guide cos^2(theta) dA     (G1)
        f_z,i = ∫_guide N_i c sin(theta) e_r dA,   c = 1 / ∫_guide sin^2(theta) dA     (G2)
        f_t,i = ∫_guide N_i c_t e_theta dA,        c_t = 1 / ∫_guide r dA              (G3)

    i.e. for a full cylinder of radius R and axial length L, c = 1/(pi R L) and
    c_t = 1/(2 pi R^2 L). Resultants: (G1) (0, 1, 0) N, (G2) (0, 0, 1) N, both with zero moment
    (a radial traction has no moment about the axis; the axial moments vanish by the mirror
    symmetry x -> -x); (G3) a moment of 1 N m about x and no force. c and c_t are fixed from the
    assembled vectors (resultant()), not from the formulas, so the nodal resultants hold to rounding.

    Model. The land's hydrodynamic film (short-bearing theory: Ocvirk's film pressure
    p(theta, x) ∝ (L^2/4 - x^2) e sin(theta) / (1 + e cos(theta))^3; Harnoy, "Bearing Design in
    Machinery" (2002) ch. 7) pushes radially inward on the cage's outside near the minimum film and
    drags it by the Petroff/Couette shear tau = eta U / h; the multibody model (multibody.
    guide_land.guide_land_force, and its hard rim contact) reduces them to a resultant force
    (F_y, F_z) and a drag torque M_x in the cage body frame. Of that pressure
    only its first circumferential harmonic (cos theta, sin theta) has a resultant force; (G1, G2)
    keep exactly that harmonic and (G3) a uniform shear, so F_y f_y + F_z f_z + M_x f_t has the exact
    resultant force and torque of the land load (the overall deformation of the ring, its
    ovalisation by the land force and the twist by the drag, Saint-Venant) but NOT the local
    pressure peak: the real film pressure is concentrated over a few tens of degrees around the
    minimum film and crushes the cage surface locally there, which these distributions spread
    round the circumference. Radial cosine traction: Roark's Formulas for Stress and Strain, 8th
    ed. (2012), Table 9.2 (ring loaded by a cosine-distributed pressure balanced elsewhere), same idea.

    Made exact on the mesh: the discrete integrals of the off-axis components (for (G1) the z force
    and the y, z moments, ~mesh asymmetry) are not exactly zero; each vector gets the least-squares
    rigid-field correction t_c = a + w × x on the guide surface with (a, w) chosen so that the full
    6-vector resultant is exactly the target (F = e_y, M = 0 for f_y, ...):

        f <- f + G alpha,  G_ij = ∫_guide N_i R_j dA,  (R^T G) alpha = target - R^T f    (G4)

    (R the nodal rigid fields; R^T G is the guide surface's 6x6 "area-inertia" matrix, SPD). The
    correction is reported in info["correction_rel"] (its norm relative to the vector's: the mesh
    asymmetry; measured 8e-9 on the 6-pocket test cage, 4e-8 on the paper cage).

    V: blocked vector Lagrange space (dof = 3 node + component), serial; facet_tags: the mesh's
    facet tags. Returns (F (n, 3) columns f_y f_z f_t, info dict with c, c_t, area, raw off-axis
    resultants and correction sizes)."""
    import ufl
    from flexbearing.common.fe_stack import fem, assemble_vector, element_degree
    from .interface import rigid_field
    domain = V.mesh
    if not np.any(facet_tags.values == tag):
        raise ValueError(f"mesh has no facets tagged guide ({tag})")
    deg = element_degree(V)
    md = {"quadrature_degree": int(quadrature_degree or 2 * deg + 2)}   # integrand not polynomial
    ds = ufl.Measure("ds", domain=domain, subdomain_data=facet_tags, metadata=md)(tag)
    x = ufl.SpatialCoordinate(domain)
    r = ufl.sqrt(x[1] ** 2 + x[2] ** 2)
    cs, sn = x[1] / r, x[2] / r
    e_r = ufl.as_vector((0.0, cs, sn))
    e_t = ufl.as_vector((0.0, -sn, cs))
    # one compiled form for all nine tractions: p = (cos, sin, shear, a_x, a_y, a_z, w_x, w_y, w_z)
    p = fem.Constant(domain, np.zeros(9))
    t = (p[0] * cs * e_r + p[1] * sn * e_r + p[2] * e_t + ufl.as_vector((p[3], p[4], p[5]))
         + ufl.cross(ufl.as_vector((p[6], p[7], p[8])), x))
    form = fem.form(ufl.inner(t, ufl.TestFunction(V)) * ds)

    def vec(j):
        p.value[:] = 0.0
        p.value[j] = 1.0
        b = assemble_vector(form)
        out = b.getArray().copy()
        b.destroy()
        return out

    X = V.tabulate_dof_coordinates()[:, :3]
    R = rigid_field(X)
    raw = [vec(0), vec(1), vec(2)]
    targets = np.zeros((6, 3))
    targets[1, 0] = targets[2, 1] = targets[3, 2] = 1.0
    norm_idx = (1, 2, 3)                     # the component each column is scaled on
    # rigid-field tractions a + w × x on the guide: G (n, 6) = ∫ N_i R_j dA
    G = np.column_stack([vec(j) for j in range(3, 9)])
    A = R.T @ G
    F = np.zeros((len(X) * 3, 3))
    info = {"area_m2": float(fem.assemble_scalar(fem.form(1.0 * ds))), "quadrature_degree":
            md["quadrature_degree"], "scale": [], "raw_offaxis_resultant": [],
            "correction_rel": []}
    for j, f in enumerate(raw):
        res = R.T @ f
        c = 1.0 / res[norm_idx[j]]
        f = c * f
        off = R.T @ f - targets[:, j]
        alpha = np.linalg.solve(A, -off)
        corr = G @ alpha
        F[:, j] = f + corr
        info["scale"].append(float(c))
        info["raw_offaxis_resultant"].append(off.tolist())
        info["correction_rel"].append(float(np.linalg.norm(corr) / np.linalg.norm(f)))
    return F, info


def pencil_conditioning(K_cb: np.ndarray, M_cb: np.ndarray, omega_max: float) -> dict:
    """Conditioning of the reduced pencil (K_cb, M_cb) as craig_bampton.orthonormalise solves it
    (Jacobi-scaled, Ms = D M_cb D, Ks = D K_cb D, D = diag(M_cb)^-1/2):

        mass_condition = kappa_2(Ms) = lambda_max(Ms) / lambda_min(Ms)
        stiffness_condition = ||Ks||_2 ||Ms^-1||_2 / omega_max^2

    The round-off of the modal basis follows from them (Golub & Van Loan, "Matrix Computations",
    4th ed. (2013), §8.7.2; Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.
    (2002), Thm 10.3 and ch. 7): N^T M_cb N - I is within ~ n u kappa_2(Ms) and an eigenvalue
    within ~ n u ||Ks||_2 ||Ms^-1||_2, i.e. n u stiffness_condition relative to omega_max^2
    (u = eps/2, n the order of the pencil). K_cb is singular (the rigid modes), so its own
    condition number is infinite; the stiffness factor is the one the eigenvalue bound needs.
    omega_max: the largest modal frequency (rad/s) of the pencil. Two symmetric eigenvalue solves
    of the small dense matrices: negligible next to the reduction."""
    d = 1.0 / np.sqrt(np.diag(M_cb))
    Ms = d[:, None] * M_cb * d[None, :]
    Ks = d[:, None] * K_cb * d[None, :]
    m = np.linalg.eigvalsh(0.5 * (Ms + Ms.T))
    k = np.linalg.eigvalsh(0.5 * (Ks + Ks.T))
    return {"mass_condition": float(m[-1] / m[0]),
            "stiffness_condition": float(np.abs(k).max() / m[0] / omega_max ** 2),
            "pencil_order": int(len(d))}


def reduce_model(domain, facet_tags, V, K_petsc, M_petsc, geometry, coupling: str = "rbe3",
                 n_fixed: int = 30, quiet: bool = True, centrifugal: bool = True,
                 guide_loads: bool = True, inertia_relief: bool = True, stage=None,
                 eigensolver: str = "auto") -> dict:
    """Run the reduction on an assembled model; return a dict of arrays and operators
    (the in-memory reduced cage plus what the checks need: Kz, C, T, Phi_full, stress op).

    centrifugal: augment the CB basis with the fixed-interface static response to the
    centrifugal load f_cf (centrifugal_load; flexbearing.fem_cage.craig_bampton Eq. (2)), so the full basis
    is statically exact for the spinning cage's centrifugal load as well as for pocket loads
    (one more mode).

    guide_loads: augment with the fixed-interface responses to the three unit land loads on the
    guide surface, f_y, f_z, f_t (guide_load_vectors), three more modes.

    inertia_relief: augment with the fixed-interface responses to the six rigid-body inertia
    loads M R_j (R the unit rigid fields t + w × x about the origin), six more modes. Why: a load
    with a net force or moment (a land force, a single ball's pocket force) does not leave the
    free cage in static equilibrium; its quasi-static deformation is the inertia-relief solution

        K u = f - M R a,   R^T M u = 0,   a = (R^T M R)^-1 R^T f                       (IR)

    and, writing u = Psi C u + w (C w = 0; flexbearing.fem_cage.craig_bampton Eq. (1)), w is the
    fixed-interface static response to f - M R a: the basis holds u exactly only if it holds the
    fixed-interface responses to f (zero for interface loads; U for body and surface loads) AND to
    the inertia loads M R a. Measured (check_guide, F_y = 100 N + M_x = 1 N m, full basis vs full
    FE): paper cage 1.8e-11 in displacement, 1.1e-10 in max von Mises with both augmentations;
    without them 1.7 % and 173 % (stress 18.5 %); on the 6-pocket test cage the land-load vectors
    alone still leave 7.2 % (tests/test_guide_loads.py). A single pocket force with a net force
    needs the inertia-relief vectors too (test cage: 2.0e-3 -> 4.8e-13), and the centrifugal load,
    whose mesh resultant is not exactly zero, gains as well (paper cage 6.8e-6 -> 1.7e-11). The
    free–free static answer of self-equilibrated loads (the older tests) never needed them.
    These are the "inertia-relief attachment modes" of component-mode synthesis (Craig & Kurdila,
    "Fundamentals of Structural Dynamics" (2006) ch. 19; MSC Nastran's inertia relief) computed
    with the interface held, i.e. flexbearing.fem_cage.craig_bampton Eq. (2) with f = M R_j.

    M = 6Z + n_fixed + (1 if centrifugal) + (3 if guide_loads) + (6 if inertia_relief).
    The result also carries the guide load vectors f_guide (n, 3) and their modal form
    guide_modal_loads = Phi_full^T f_guide (M, 3), whatever the flags. stage: called with the name
    of each part as it starts (flexbearing.common.progress.Stages; REDUCE_STAGES). eigensolver:
    the fixed-interface modes' method (flexbearing.fem_cage.craig_bampton.fixed_interface_modes;
    "auto" picks by the BLAS; the choice changes the modes within the solvers' tolerances only)."""
    from . import interface as itf
    from .craig_bampton import petsc_to_scipy, craig_bampton, orthonormalise, kron_mass_times
    from .invariants import scalar_mass_matrix, mass_moments, rigid_properties, ffrf_invariants

    if coupling not in ("rbe2", "rbe3"):
        raise InputError(f"reduce.coupling = {coupling!r} is outside the allowed set {{rbe2, rbe3}}")
    timings = {}
    t_start = time.perf_counter()
    stage = stage or (lambda name: None)
    stage("interface")

    def log(msg):
        if not quiet:
            print(f"[reduce {time.perf_counter() - t_start:7.1f} s] {msg}", flush=True)

    t0 = time.perf_counter()
    K, M = petsc_to_scipy(K_petsc), petsc_to_scipy(M_petsc)
    X = V.tabulate_dof_coordinates()[:, :3].copy()
    Z = geometry.n_pockets
    walls = itf.pocket_wall_nodes(V, facet_tags, Z)
    xm = itf.pocket_centres(geometry)
    n = K.shape[0]
    if coupling == "rbe2":
        T, keep = itf.rbe2_transformation(n, walls, X, xm)
        Tt = T.T.tocsr()
        Kz, Mz = (Tt @ K @ T).tocsr(), (Tt @ M @ T).tocsr()
        C = itf.selection_matrix(Kz.shape[0], np.arange(len(keep), len(keep) + 6 * Z))
    else:
        T = None
        weights = itf.pocket_wall_weights(V, facet_tags, walls)
        C = itf.rbe3_constraint(n, walls, weights, X, xm)
        Kz, Mz = K, M
    timings["interface_s"] = time.perf_counter() - t0
    f_cf = centrifugal_load(M, X)                # physical DOFs; kept for the checks
    if geometry.guidance == "balls":
        # no land touches a ball-riding cage: its land load is zero, the vectors too
        f_guide, guide_info = np.zeros((n, 3)), {"area_m2": 0.0, "guidance": "balls"}
    else:
        f_guide, guide_info = guide_load_vectors(V, facet_tags)     # (n, 3): f_y f_z f_t
    loads = []
    if centrifugal:
        loads.append(f_cf[:, None])
    if guide_loads:
        loads.append(f_guide)
    if inertia_relief:
        from .interface import rigid_field
        loads.append(M @ rigid_field(X))
    body = None
    if loads:
        body = np.hstack(loads)
        body = T.T @ body if T is not None else body     # the same virtual work in the DOFs z
    log(f"{n} dofs, {Z} pocket interface nodes ({coupling}); factorising and solving "
        f"{6 * Z} constraint modes + {n_fixed} fixed-interface modes ({eigensolver} eigensolver)"
        + (" + the centrifugal vector" if centrifugal else "")
        + (" + 3 land-load vectors" if guide_loads else "")
        + (" + 6 inertia-relief vectors" if inertia_relief else ""))
    t0 = time.perf_counter()
    stage("Craig-Bampton modes")
    # the vector mass is Ms ⊗ I3 (RBE3 keeps the physical DOFs); RBE2's T^T M T is not
    Ms = scalar_mass_matrix(M)                   # also the invariants' (below)
    mass_times = kron_mass_times(Ms) if T is None else None
    cb = craig_bampton(Kz, Mz, C, n_fixed, body_loads=body, eigensolver=eigensolver,
                       mass_times=mass_times)
    timings["craig_bampton_s"] = time.perf_counter() - t0
    G = itf.rigid_interface_matrix(xm)
    N, omega, tw = orthonormalise(cb["K_cb"], cb["M_cb"], G)
    B = np.hstack([cb["Psi"], cb["Phi"], cb["U"]]) @ N
    Phi_full = T @ B if T is not None else B
    phi_b = N[:6 * Z]
    log(f"orthonormalised {N.shape[1]} modes; invariants")
    stage("invariants")
    t0 = time.perf_counter()
    mom = mass_moments(Ms, X, Phi_full)
    rigid = rigid_properties(mom)
    inv = ffrf_invariants(mom)
    timings["invariants_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    stage("stress modes")
    bar = tqdm(total=N.shape[1], desc="stress modes", disable=quiet)
    S, vdisp, op = stress_modes(V, geometry.material, Phi_full, zero_columns=range(6),
                                progress=bar)
    bar.close()
    timings["stress_modes_s"] = time.perf_counter() - t0
    Mi = N.T @ cb["M_cb"] @ N
    Ki = N.T @ cb["K_cb"] @ N
    ortho = {"modal_mass_identity_error": float(np.abs(Mi - np.eye(len(Mi))).max()),
             **pencil_conditioning(cb["K_cb"], cb["M_cb"], float(omega.max())),
             "modal_stiffness_offdiag_rel": float(np.abs(Ki - np.diag(np.diag(Ki))).max()
                                                  / max(np.abs(np.diag(Ki)).max(), 1e-300)),
             "rigid_modal_stiffness_rel": float(np.abs(np.diag(Ki)[:6]).max()
                                                / np.diag(Ki)[6:].max())}
    return {"omega": omega, "frequency_hz": omega / (2 * np.pi), "phi_b": phi_b,
            "interface_positions": xm, "Phi_full": Phi_full, "stress": S, "stress_op": op,
            "vertex_displacement": vdisp, "invariants": inv, "moments": mom, "rigid": rigid,
            "rigid_twist": tw, "Kz": Kz, "Mz": Mz, "K": K, "M": M, "C": C, "T": T,
            "omega_fixed": cb["omega_fixed"], "info": cb["info"], "orthogonality": ortho,
            "timings": timings, "n_dofs": n, "coupling": coupling, "n_fixed": n_fixed,
            "centrifugal": bool(centrifugal), "Bz": B, "f_cf": f_cf,
            "guide_loads": bool(guide_loads), "inertia_relief": bool(inertia_relief),
            "f_guide": f_guide, "guide_info": guide_info,
            "guide_modal_loads": Phi_full.T @ f_guide}


def file_arrays(red: dict) -> dict:
    """The datasets of the reduced cage file (schema in flexbearing.fem_cage.reduced_cage)."""
    Z = len(red["interface_positions"])
    m = len(red["omega"])
    inv = red["invariants"]
    data = {"mesh/vertices": red["stress_op"].coords,
            "mesh/tets": red["stress_op"].vtk_cells[:, :4],          # P1 skeleton (corners)
            "mesh/tets10": red["stress_op"].vtk_cells,
            "interface/positions": red["interface_positions"],
            "interface/pocket": np.arange(Z),
            "modes/frequency_hz": red["frequency_hz"], "modes/omega": red["omega"],
            "modes/modal_mass": np.eye(m), "modes/modal_stiffness": red["omega"] ** 2,
            "modes/interface": red["phi_b"].reshape(Z, 6, m),
            "modes/vertex_displacement": red["vertex_displacement"],
            "modes/rigid_twist": red["rigid_twist"],
            "stress/modes": red["stress"],
            "loads/guide_modal_loads": red["guide_modal_loads"],
            "invariants/mass": red["rigid"]["mass"],
            "invariants/center_of_mass": red["rigid"]["center_of_mass"],
            "invariants/inertia_origin": red["rigid"]["inertia_origin"],
            "invariants/inertia_com": red["rigid"]["inertia_com"],
            "invariants/first": red["moments"]["first"],
            "invariants/second": red["moments"]["second"],
            "invariants/S1": red["moments"]["S1"],
            "invariants/Sx": red["moments"]["Sx"], "invariants/SS": red["moments"]["SS"]}
    for k in ("I1", "I2", "I3", "I4", "I5", "I6", "I7", "I8", "I9"):
        data[f"invariants/{k}"] = inv[k]
    return data


def build(geometry, size, order, pocket_size, coupling, n_fixed, quiet=True, checks=False,
          n_keep=DEFAULT_N_KEEP, degree=3, centrifugal=True, guide_loads=True, inertia_relief=True,
          mesh=None, cad_key=None):
    """Mesh, assemble, reduce, optionally verify; write the cache file. Returns (path, red, checks).

    mesh: a ready .msh instead of the parametric cage's cached mesh (a CAD cage,
    flexbearing.mesh.cad_cage.cached_cad_cage_mesh), with cad_key, the content key it was made
    from, added to the reduced cage's key."""
    from mpi4py import MPI
    from .elasticity import load_cage_mesh, assemble_stiffness_mass
    if MPI.COMM_WORLD.size > 1:
        raise RuntimeError("flexbearing reduce runs in serial")
    key = rcf.cache_key(geometry, size, order, pocket_size, coupling, n_fixed, degree, centrifugal,
                        guide_loads, inertia_relief)
    stage = Stages("reduce the cage", {k: w for k, w in REDUCE_STAGES.items() if k != "checks" or checks},
                   quiet)
    if cad_key is not None:
        key["cad"] = cad_key
    stage("mesh")
    msh = Path(mesh) if mesh is not None else cached_cage_mesh(geometry, size, order, pocket_size)
    stage("K and M")
    domain, _, facet_tags, _ = load_cage_mesh(msh, MPI.COMM_SELF)
    V, K, M = assemble_stiffness_mass(domain, geometry.material, degree)
    t0 = time.perf_counter()
    red = reduce_model(domain, facet_tags, V, K, M, geometry, coupling, n_fixed, quiet, centrifugal,
                       guide_loads, inertia_relief, stage=stage)
    red["timings"]["reduce_total_s"] = time.perf_counter() - t0
    summary = summarize(red)
    if checks:
        stage("checks")
        from .reduction_check import run_checks
        summary.update(run_checks(red, domain, geometry, degree, n_keep))
    stage("write")
    attrs = {"content_hash": rcf.cache_path(key).stem, "parameters": key, "coupling": coupling,
             "mesh_sha256": rcf.file_sha256(msh),          # provenance: checked by rcf.check_provenance
             "n_modes": int(len(red["omega"])), "created_by": "flexbearing reduce",
             "centrifugal_vector": bool(centrifugal), "guide_load_vectors": bool(guide_loads),
             "inertia_relief_vectors": bool(inertia_relief)}
    data = file_arrays(red)
    path = rcf.cache_path(key)
    # every attribute goes into the file before it is renamed into the cache (written once, whole)
    group_attrs = {
        "mesh": {"source_msh": str(msh), "msh_sha256": rcf.file_sha256(msh), "n_dofs": int(red["n_dofs"]),
                 "element": f"P{degree} on order-{order} tetrahedra",
                 "quality": json.dumps(mesh_quality_of(msh, degree))},
        "interface": {"dof_names": "ux uy uz rx ry rz"},
        "loads/guide_modal_loads": {
            "columns": json.dumps(list(rcf.GUIDE_LOAD_COLUMNS)),
            "units": ("generalised force (N m per unit q) per unit land force (N) in columns "
                      "0, 1 and per unit land torque (N m) in column 2"),
            "distribution": ("f_y, f_z: radial traction c cos(theta) e_r, c sin(theta) e_r; "
                             "f_t: uniform shear c_t e_theta; on the guide surface (facet "
                             "tag 200), scaled to unit resultant (flexbearing.fem_cage.reduction."
                             "guide_load_vectors)"),
            "guide_area_m2": red["guide_info"]["area_m2"]}}
    rcf.write(path, data, dict(attrs), summary, group_attrs)
    stage(None)
    return path, red, summary


def summarize(red: dict) -> dict:
    return {"frequencies_hz": red["frequency_hz"].tolist(), "n_modes": int(len(red["omega"])),
            "coupling": red["coupling"], "n_fixed": int(red["n_fixed"]), "n_dofs": int(red["n_dofs"]),
            "centrifugal_vector": bool(red.get("centrifugal", False)),
            "guide_load_vectors": bool(red.get("guide_loads", False)),
            "inertia_relief_vectors": bool(red.get("inertia_relief", False)),
            "guide_loads": red.get("guide_info"),
            "n_stress_vertices": int(red["stress"].shape[0]), "orthogonality": red["orthogonality"],
            "timings": red["timings"], "solver": red["info"]}
