"""`flexbearing reduce`: build (or find in the cache) the reduced cage file and verify it.

Pipeline (fem_cage modules in brackets):
  mesh (mesh.cage_mesh, cached) -> K, M (elasticity) -> pocket interface nodes and RBE2/RBE3
  coupling (interface) -> constraint + fixed-interface modes + the fixed-interface static
  response to the centrifugal load (default; --no-centrifugal-vector drops it), to the three
  unit land (guide-surface) loads (--no-guide-vectors) and to the six rigid-body inertia loads
  (--no-inertia-relief-vectors), modified CB orthonormalisation (craig_bampton) -> invariants
  (invariants) -> vertex stress modes (stress_modes) -> HDF5 file (reduced_cage), cached under
  a hash of every input.
Checks (--json, --check): static exactness at several pockets (full basis and n_keep
truncation), stress recovery of a pocket load case vs the full FE solution, the free–free
(inertia-relief) static response to a centrifugal load and to a land load vs the full FE
(check_centrifugal, check_guide), free–free frequencies vs the full model, mass properties vs direct integration, the max-von-Mises
evaluator vs brute force and its cost per call.

The command imports dolfinx only when it must build; `--xdmf` and `--json` on a cached file
without `--check` read the HDF5 file only.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np


# ------------------------------------------------------------------ the reduction

def centrifugal_load(M, X: np.ndarray) -> np.ndarray:
    """Consistent nodal centrifugal load of the cage spinning about its axis x, per unit Omega^2:

        f_cf = M x_perp,   x_perp = (0, y, z)   (N per (rad/s)^2; body force rho Omega^2 x_perp)

    M: blocked vector mass matrix (dof = 3 node + component), X (N, 3) node coordinates (the FE
    interpolant of x_perp is exact: the coordinate field is in the FE space)."""
    xp = np.zeros(3 * len(X))
    xp[1::3], xp[2::3] = X[:, 1], X[:, 2]
    return M @ xp


GUIDE_TAG = 200            # mesh.cage_mesh.TAG_GUIDE: the outer-ring-guided surface(s)


def resultant(f: np.ndarray, X: np.ndarray) -> np.ndarray:
    """(F, M) = (sum_i f_i, sum_i x_i × f_i), 6-vector (N, N m about the body origin): the work
    of nodal load f on the unit rigid motions t + omega × x (fem_cage.interface.rigid_field), R^T f.
    For a consistent load f_i = ∫ N_i t dA it equals (∫ t dA, ∫ x × t dA) exactly when the
    coordinate field is in the FE space (isoparametric / superparametric Lagrange, degree >= the
    geometry order)."""
    from .interface import rigid_field
    return rigid_field(X).T @ f


def guide_load_vectors(V, facet_tags, tag: int = GUIDE_TAG, quadrature_degree: int | None = None):
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
    from dolfinx import fem
    from dolfinx.fem.petsc import assemble_vector
    from .interface import rigid_field
    domain = V.mesh
    if not np.any(facet_tags.values == tag):
        raise ValueError(f"mesh has no facets tagged guide ({tag})")
    deg = V.ufl_element().degree()
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


def reduce_model(domain, facet_tags, V, K_petsc, M_petsc, geometry, coupling: str = "rbe3",
                 n_fixed: int = 30, quiet: bool = True, centrifugal: bool = True,
                 guide_loads: bool = True, inertia_relief: bool = True) -> dict:
    """Run the reduction on an assembled model; return a dict of arrays and operators
    (the in-memory reduced cage plus what the checks need: Kz, C, T, Phi_full, stress op).

    centrifugal: augment the CB basis with the fixed-interface static response to the
    centrifugal load f_cf (centrifugal_load; fem_cage.craig_bampton Eq. (2)), so the full basis
    is statically exact for the spinning cage's centrifugal load as well as for pocket loads
    (one more mode).

    guide_loads: augment with the fixed-interface responses to the three unit land loads on the
    guide surface, f_y, f_z, f_t (guide_load_vectors), three more modes.

    inertia_relief: augment with the fixed-interface responses to the six rigid-body inertia
    loads M R_j (R the unit rigid fields t + w × x about the origin), six more modes. Why: a load
    with a net force or moment (a land force, a single ball's pocket force) does not leave the
    free cage in static equilibrium; its quasi-static deformation is the inertia-relief solution

        K u = f - M R a,   R^T M u = 0,   a = (R^T M R)^-1 R^T f                       (IR)

    and, writing u = Psi C u + w (C w = 0; fem_cage.craig_bampton Eq. (1)), w is the
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
    with the interface held, i.e. fem_cage.craig_bampton Eq. (2) with f = M R_j.

    M = 6Z + n_fixed + (1 if centrifugal) + (3 if guide_loads) + (6 if inertia_relief).
    The result also carries the guide load vectors f_guide (n, 3) and their modal form
    guide_modal_loads = Phi_full^T f_guide (M, 3), whatever the flags."""
    from tqdm import tqdm
    from . import interface as itf
    from .craig_bampton import petsc_to_scipy, craig_bampton, orthonormalise
    from .invariants import scalar_mass_matrix, mass_moments, rigid_properties, ffrf_invariants
    from .stress_modes import stress_modes
    from common.validation import InputError

    if coupling not in ("rbe2", "rbe3"):
        raise InputError(f"reduce.coupling = {coupling!r} is outside the allowed set {{rbe2, rbe3}}")
    timings = {}
    t_start = time.perf_counter()

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
        f"{6 * Z} constraint modes + {n_fixed} fixed-interface modes (SLEPc)"
        + (" + the centrifugal vector" if centrifugal else "")
        + (" + 3 land-load vectors" if guide_loads else "")
        + (" + 6 inertia-relief vectors" if inertia_relief else ""))
    t0 = time.perf_counter()
    cb = craig_bampton(Kz, Mz, C, n_fixed, body_loads=body)
    timings["craig_bampton_s"] = time.perf_counter() - t0
    G = itf.rigid_interface_matrix(xm)
    N, omega, tw = orthonormalise(cb["K_cb"], cb["M_cb"], G)
    B = np.hstack([cb["Psi"], cb["Phi"], cb["U"]]) @ N
    Phi_full = T @ B if T is not None else B
    phi_b = N[:6 * Z]
    log(f"orthonormalised {N.shape[1]} modes; invariants")
    t0 = time.perf_counter()
    mom = mass_moments(scalar_mass_matrix(M), X, Phi_full)
    rigid = rigid_properties(mom)
    inv = ffrf_invariants(mom)
    timings["invariants_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    bar = tqdm(total=N.shape[1], desc="stress modes", disable=quiet)
    S, vdisp, op = stress_modes(V, geometry.material, Phi_full, zero_columns=range(6),
                                progress=bar)
    bar.close()
    timings["stress_modes_s"] = time.perf_counter() - t0
    Mi = N.T @ cb["M_cb"] @ N
    Ki = N.T @ cb["K_cb"] @ N
    ortho = {"modal_mass_identity_error": float(np.abs(Mi - np.eye(len(Mi))).max()),
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
    """The datasets of the reduced cage file (schema in fem_cage.reduced_cage)."""
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


# ------------------------------------------------------------------ verification

def _rel(a, b):
    return float(np.linalg.norm(a - b) / max(np.linalg.norm(b), 1e-300))


def check_static(red: dict, load_nodes, fixed_node: int = 0, n_keep: int = 26) -> dict:
    """Unit forces and moments (6 per load node) with interface node fixed_node clamped: full
    saddle-point solve vs the reduced model (full basis and first n_keep modes). Error per case:
    max of the relative errors of the interface translations and rotations (6Z vector)."""
    from .craig_bampton import full_static, reduced_static_interface
    C = red["C"]
    loads = [(j, e) for j in load_nodes for e in np.eye(6)]
    u_full = full_static(red["Kz"], C, fixed_node, loads)
    out = {"fixed_node": fixed_node, "load_nodes": list(map(int, load_nodes)), "cases": len(loads)}
    for label, m in (("full", len(red["omega"])), ("truncated", n_keep)):
        errs = []
        for (j, F), u in zip(loads, u_full):
            ub = C @ u
            ur, _ = reduced_static_interface(red["phi_b"][:, :m], red["omega"][:m], fixed_node, j, F)
            t = np.r_[[i for k in range(len(ub) // 6) for i in range(6 * k, 6 * k + 3)]]
            r = np.setdiff1d(np.arange(len(ub)), t)
            errs.append(max(_rel(ur[t], ub[t]), _rel(ur[r], ub[r])))
        out[f"max_rel_error_{label}"] = float(max(errs))
        out[f"n_modes_{label}"] = int(m)
    return out


def check_stress(red: dict, load_node: int, fixed_node: int = 0, force_n: float = 1000.0,
                 n_keep: int = 26) -> dict:
    """A circumferential ball force on one pocket (node fixed_node clamped): max von Mises and its
    vertex from the full FE displacement (same vertex-averaging operator) vs modal recovery."""
    from .craig_bampton import full_static, reduced_static_interface
    from .stress_modes import von_mises
    from .von_mises import MaxVonMises
    xm = red["interface_positions"][load_node]
    th = np.arctan2(xm[2], xm[1])
    F = np.zeros(6)
    F[0:3] = force_n * np.array([0.0, -np.sin(th), np.cos(th)])     # circumferential
    u = full_static(red["Kz"], red["C"], fixed_node, [(load_node, F)])[0]
    u_phys = red["T"] @ u if red["T"] is not None else u
    vm_full = von_mises(red["stress_op"](u_phys))
    n_full = int(np.argmax(vm_full))
    out = {"load_node": int(load_node), "force_N": force_n, "vm_max_full_Pa": float(vm_full.max()),
           "vertex_full": n_full, "position_full_m": red["stress_op"].coords[n_full].tolist()}
    for label, m in (("full", len(red["omega"])), ("truncated", n_keep)):
        _, q = reduced_static_interface(red["phi_b"][:, :m], red["omega"][:m], fixed_node,
                                        load_node, F)
        ev = MaxVonMises(red["stress"][:, :, :m], mode_scale=_mode_scale(red["omega"][:m]))
        v, node = ev(q)
        out[f"vm_max_{label}_Pa"] = v
        out[f"rel_error_{label}"] = abs(v - vm_full.max()) / vm_full.max()
        out[f"vertex_{label}"] = node
        out[f"location_distance_{label}_m"] = float(np.linalg.norm(
            red["stress_op"].coords[node] - red["stress_op"].coords[n_full]))
    return out


def check_centrifugal(red: dict, spin: float = 1000.0, n_keep: int = 26) -> dict:
    """The spinning cage's static centrifugal response, free–free full FE vs the modal basis.

    Full FE (inertia relief, so a load that is not exactly self-equilibrated on the mesh is still
    well posed): K u = Omega^2 f_cf - M R a, R^T M u = 0 (R the exact rigid modes), by the saddle
    LU; f_cf = M x_perp (centrifugal_load). Modal: the elastic quasi-static coordinates
    q_k = Omega^2 Q_k / omega_k^2, Q_k = Phi_k^T f_cf = Sx[1,1,k] + Sx[2,2,k] (the rigid
    accelerations project to zero on the mean-axis elastic modes), stress = stress_modes @ q.
    Errors: Frobenius norm of the nodal stress difference over all stress nodes, relative, for
    the full basis and for the first n_keep modes alone. (The runtime's residual static
    correction — n_keep modes plus the discarded modes' quasi-static coordinates — is, for a
    static load, the full basis: the same q.)"""
    import scipy.sparse as sp
    from .craig_bampton import SaddleSolver
    from .stress_modes import von_mises
    K, M, Bz = red["Kz"], red["Mz"], red["Bz"]
    f = spin ** 2 * (red["T"].T @ red["f_cf"] if red["T"] is not None else red["f_cf"])
    R = Bz[:, :6]
    solver = SaddleSolver(sp.csr_matrix(K), sp.csr_matrix((M @ R).T))
    u, _ = solver.solve(f, None)
    solver.destroy()
    u_phys = red["T"] @ u if red["T"] is not None else u
    S_full = red["stress_op"](u_phys)
    omega = red["omega"]
    Q = Bz.T @ f
    q = np.zeros_like(Q)
    q[6:] = Q[6:] / omega[6:] ** 2
    out = {"spin_rad_s": spin, "vm_max_fe_Pa": float(von_mises(S_full).max()),
           "centrifugal_vector": bool(red.get("centrifugal", False))}
    qk = q.copy()
    qk[n_keep:] = 0.0
    for label, qq in (("full", q), ("truncated", qk)):
        S = red["stress"] @ qq
        out[f"stress_rel_error_{label}"] = _rel(S, S_full)
        out[f"vm_max_{label}_basis_Pa"] = float(von_mises(S).max())
    return out


def check_guide(red: dict, force_y: float = 100.0, force_z: float = 0.0, torque_x: float = 1.0,
                n_keep: int = 26) -> dict:
    """Static exactness for the land (guide-surface) load L = (F_y, F_z, M_x): free–free full FE
    vs the modal basis.

    Full FE, inertia relief (the land load has a net force: the free cage accelerates and the
    static deformation is the one in the accelerating frame; Craig & Kurdila 2006 §14.3, MSC
    Nastran "inertia relief"):
        K u = f - M R a,  R^T M u = 0,  f = F_y f_y + F_z f_z + M_x f_t (guide_load_vectors)
    by the saddle LU (R the exact rigid modes). Modal (what the runtime's static correction does
    for every mode): q_k = G_k · L / omega_k^2 for the elastic modes, G = Phi^T [f_y f_z f_t]
    (the file's guide_modal_loads); the rigid accelerations project to zero on the mean-axis
    elastic modes. Errors, relative: displacement at all DOFs (2-norm), nodal stress at all
    stress nodes (Frobenius), max von Mises over the nodes; full basis and the first n_keep modes."""
    import scipy.sparse as sp
    from .craig_bampton import SaddleSolver
    from .stress_modes import von_mises
    L = np.array([force_y, force_z, torque_x], dtype=float)
    f_phys = red["f_guide"] @ L
    K, M, Bz, T = red["Kz"], red["Mz"], red["Bz"], red["T"]
    f = T.T @ f_phys if T is not None else f_phys
    R = Bz[:, :6]
    solver = SaddleSolver(sp.csr_matrix(K), sp.csr_matrix((M @ R).T))
    u, _ = solver.solve(f, None)
    solver.destroy()
    u_phys = T @ u if T is not None else u
    S_full = red["stress_op"](u_phys)
    vm_full = float(von_mises(S_full).max())
    omega = red["omega"]
    Q = red["guide_modal_loads"] @ L
    q = np.zeros_like(Q)
    q[6:] = Q[6:] / omega[6:] ** 2
    out = {"land_force_y_N": force_y, "land_force_z_N": force_z, "land_torque_x_Nm": torque_x,
           "guide_vectors": bool(red.get("guide_loads", False)), "vm_max_fe_Pa": vm_full,
           "max_displacement_fe_m": float(np.abs(u_phys).max())}
    qk = q.copy()
    qk[n_keep:] = 0.0
    for label, qq in (("full", q), ("truncated", qk)):
        S = red["stress"] @ qq
        vm = float(von_mises(S).max())
        out[f"displacement_rel_error_{label}"] = _rel(red["Phi_full"] @ qq, u_phys)
        out[f"stress_rel_error_{label}"] = _rel(S, S_full)
        out[f"vm_max_{label}_basis_Pa"] = vm
        out[f"vm_max_rel_error_{label}"] = abs(vm - vm_full) / vm_full
    return out


def _mode_scale(omega):
    """Typical modal amplitude 1/omega (rigid modes: 1) for grouping the evaluator's nodes."""
    return np.where(omega > 0, 1.0 / np.maximum(omega, 1e-300), 1.0)


def check_frequencies(red: dict, n_elastic: int = 10) -> dict:
    """Reduced free–free elastic frequencies vs the full model's (fem_cage.modes), and for RBE2
    vs the full model with the same rigid pocket walls (T^T K T)."""
    from .modes import free_free_modes
    from .craig_bampton import scipy_to_petsc
    n = 6 + n_elastic
    f_full, _ = free_free_modes(scipy_to_petsc(red["K"]), scipy_to_petsc(red["M"]), n)
    f_red = red["frequency_hz"][6:n]
    out = {"full_hz": f_full[6:n].tolist(), "reduced_hz": f_red.tolist(),
           "max_rel_error_vs_full": float(np.max(np.abs(f_red / f_full[6:n] - 1)))}
    if red["T"] is not None:
        f_c, _ = free_free_modes(scipy_to_petsc(red["Kz"]), scipy_to_petsc(red["Mz"]), n)
        out["coupled_full_hz"] = f_c[6:n].tolist()
        out["max_rel_error_vs_coupled_full"] = float(np.max(np.abs(f_red / f_c[6:n] - 1)))
    return out


def check_invariants(red: dict, domain, density: float, quadrature_degree: int) -> dict:
    from .invariants import direct_mass_properties, rigid_properties
    d = rigid_properties(direct_mass_properties(domain, density, quadrature_degree))
    r = red["rigid"]
    inv = red["invariants"]
    scale_c = np.abs(red["interface_positions"]).max()
    return {"mass_rel": abs(r["mass"] - d["mass"]) / d["mass"],
            "com_rel": float(np.linalg.norm(r["center_of_mass"] - d["center_of_mass"]) / scale_c),
            "inertia_rel": float(np.abs(r["inertia_origin"] - d["inertia_origin"]).max()
                                 / np.abs(d["inertia_origin"]).max()),
            "mass_kg": r["mass"], "center_of_mass_m": r["center_of_mass"].tolist(),
            "inertia_com_kgm2": r["inertia_com"].tolist(),
            "elastic_I3_max": float(np.abs(inv["I3"][:, 6:]).max()),
            "elastic_I4_max": float(np.abs(inv["I4"][:, 6:]).max()),
            "I6_identity_error": float(np.abs(inv["I6"] - np.eye(len(inv["I6"]))).max()),
            "quadrature_degree": quadrature_degree}


def check_von_mises(S: np.ndarray, omega: np.ndarray, n_random: int = 1000, seed: int = 1) -> dict:
    """Exactness vs brute force on random elastic modal vectors, three families: "energy"
    q_k ~ N(0, 1/omega_k^2) (equal modal energy), "unit" N(0, 1) (worst case for the bounds),
    "static" N(0, 1/omega_k^4) (quasi-static response to interface forces, q = Phi^T F/omega^2);
    same maximum value as brute force required; cost per call = best of 5 loops (CPU time)."""
    from .von_mises import MaxVonMises
    t0 = time.perf_counter()
    ev = MaxVonMises(S, mode_scale=_mode_scale(omega))
    build_s = time.perf_counter() - t0
    rng = np.random.default_rng(seed)
    m = S.shape[2]
    w = np.where(omega > 0, 1.0 / np.maximum(omega, 1e-300), 0.0)
    out = {"n_nodes": int(S.shape[0]), "n_modes": int(m), "n_random": n_random,
           "setup_s": build_s, "timer": "time.process_time (CPU s of this process), per call"}
    for label, scale in (("energy", w), ("unit", (omega > 0).astype(float)),
                         ("static", w ** 2)):
        Q = rng.standard_normal((n_random, m)) * scale
        mismatches = sum(ev(q)[0] != ev.brute_force(q)[0] for q in Q)
        visits = np.array([ev.visits(q) for q in Q])
        ev(Q[0]); ev.brute_force(Q[0])
        t_fast = min(_time(lambda: [ev(q) for q in Q]) for _ in range(5)) / n_random
        t_brute = min(_time(lambda: [ev.brute_force(q) for q in Q[:100]]) for _ in range(3)) / 100
        out[label] = {"mismatches": int(mismatches), "cost_per_call_us": t_fast * 1e6,
                      "brute_force_us": t_brute * 1e6,
                      "mean_exact_node_evaluations": float(visits[:, 1].mean()),
                      "mean_centre_evaluations": float(visits[:, 0].mean())}
    return out


def _time(f) -> float:
    t = time.process_time()        # CPU time: the machine is shared, wall time is noise
    f()
    return time.process_time() - t


# ------------------------------------------------------------------ ParaView

def write_xdmf(rc, path, n_keep: int | None = None) -> Path:
    """Mode shapes (vertex displacement, m per unit q) and von Mises of each kept mode on the
    vertex mesh, one XDMF (+ .h5) readable by ParaView. Reads only the reduced cage object."""
    import meshio
    from .stress_modes import von_mises
    m = rc.n_modes if n_keep is None else min(n_keep, rc.n_modes)
    pd = {}
    for k in range(m):
        tag = f"mode_{k + 1:03d}_{rc.frequency_hz[k]:.1f}Hz"
        pd[f"{tag}_displacement"] = rc.vertex_displacement[:, :, k]
        pd[f"{tag}_von_mises"] = von_mises(rc.stress_modes[:, :, k])
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    cells = rc.tets10 if rc.tets10 is not None else rc.tets
    kind = {4: "tetra", 10: "tetra10"}[cells.shape[1]]
    meshio.write(path, meshio.Mesh(rc.vertices, [(kind, cells)], point_data=pd))
    return path


# ------------------------------------------------------------------ command

def register(subparsers):
    p = subparsers.add_parser("reduce", help="build the reduced (Craig–Bampton) cage file, or find it in the cache",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=float, default=None, help="global element size, m (default: mesh default)")
    p.add_argument("--pocket-size", type=float, default=None, help="element size on the pocket walls, m")
    p.add_argument("--order", type=int, default=None, help="geometric mesh order 1|2 (default 2, curved)")
    p.add_argument("--degree", type=int, default=None, help="Lagrange degree of the FE space (default: mesh.cage_mesh.DEFAULT_DEGREE)")
    p.add_argument("--coupling", choices=("rbe2", "rbe3"), default=None,
                   help="pocket coupling: rbe3 distributing (default, adds no stiffness) or rbe2 rigid")
    p.add_argument("--n-fixed", type=int, default=None, help="fixed-interface normal modes (default 30)")
    p.add_argument("--no-centrifugal-vector", dest="centrifugal", action="store_false",
                   help="do not augment the basis with the fixed-interface centrifugal response "
                        "(then the full basis is statically exact for pocket loads only)")
    p.add_argument("--no-guide-vectors", dest="guide_loads", action="store_false",
                   help="do not augment the basis with the fixed-interface responses to the unit "
                        "land (guide-surface) loads")
    p.add_argument("--no-inertia-relief-vectors", dest="inertia_relief", action="store_false",
                   help="do not augment the basis with the fixed-interface responses to the six "
                        "rigid-body inertia loads (then loads with a net force are not statically "
                        "exact in the free cage)")
    p.add_argument("--n-keep", type=int, default=26, help="modes the runtime keeps, rigid included (default 26)")
    p.add_argument("--force", action="store_true", help="rebuild even if cached")
    p.add_argument("--check", action="store_true", help="run the verification (needs dolfinx)")
    p.add_argument("--json", type=Path, default=None, help="write the summary (checks, frequencies, costs) here")
    p.add_argument("--xdmf", type=Path, default=None, help="write kept modes' shapes and von Mises for ParaView")
    p.add_argument("-o", "--output", type=Path, default=None, help="also copy the reduced cage file here")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=run)


def build(geometry, size, order, pocket_size, coupling, n_fixed, quiet=True, checks=False,
          n_keep=26, degree=3, centrifugal=True, guide_loads=True, inertia_relief=True):
    """Mesh, assemble, reduce, optionally verify; write the cache file. Returns (path, red, checks)."""
    from mpi4py import MPI
    from mesh.cage_mesh import cached_cage_mesh
    from .elasticity import load_cage_mesh, assemble_stiffness_mass
    from . import reduced_cage as rcf
    if MPI.COMM_WORLD.size > 1:
        raise RuntimeError("flexbearing reduce runs in serial")
    key = rcf.cache_key(geometry, size, order, pocket_size, coupling, n_fixed, degree, centrifugal,
                        guide_loads, inertia_relief)
    msh = cached_cage_mesh(geometry, size, order, pocket_size)
    domain, _, facet_tags, _ = load_cage_mesh(msh, MPI.COMM_SELF)
    V, K, M = assemble_stiffness_mass(domain, geometry.material, degree)
    t0 = time.perf_counter()
    red = reduce_model(domain, facet_tags, V, K, M, geometry, coupling, n_fixed, quiet, centrifugal,
                       guide_loads, inertia_relief)
    red["timings"]["reduce_total_s"] = time.perf_counter() - t0
    summary = summarize(red)
    if checks:
        summary.update(run_checks(red, domain, geometry, degree, n_keep))
    attrs = {"content_hash": rcf.cache_path(key).stem, "parameters": key, "coupling": coupling,
             "n_modes": int(len(red["omega"])), "created_by": "flexbearing reduce",
             "centrifugal_vector": bool(centrifugal), "guide_load_vectors": bool(guide_loads),
             "inertia_relief_vectors": bool(inertia_relief)}
    data = file_arrays(red)
    path = rcf.cache_path(key)
    data_attrs = dict(attrs)
    rcf.write(path, data, data_attrs, summary)
    import h5py
    with h5py.File(path, "a") as f:
        f["mesh"].attrs["source_msh"] = str(msh)
        f["mesh"].attrs["msh_sha256"] = rcf.file_sha256(msh)
        f["mesh"].attrs["n_dofs"] = int(red["n_dofs"])
        f["mesh"].attrs["element"] = f"P{degree} on order-{order} tetrahedra"
        from mesh.cage_mesh import mesh_quality_of
        f["mesh"].attrs["quality"] = json.dumps(mesh_quality_of(msh, degree))
        f["interface"].attrs["dof_names"] = "ux uy uz rx ry rz"
        g = f["loads/guide_modal_loads"]
        g.attrs["columns"] = json.dumps(list(rcf.GUIDE_LOAD_COLUMNS))
        g.attrs["units"] = ("generalised force (N m per unit q) per unit land force (N) in columns "
                            "0, 1 and per unit land torque (N m) in column 2")
        g.attrs["distribution"] = ("f_y, f_z: radial traction c cos(theta) e_r, c sin(theta) e_r; "
                                   "f_t: uniform shear c_t e_theta; on the guide surface (facet "
                                   "tag 200), scaled to unit resultant (fem_cage.reduce_cli."
                                   "guide_load_vectors)")
        g.attrs["guide_area_m2"] = red["guide_info"]["area_m2"]
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


def run_checks(red: dict, domain, geometry, degree: int, n_keep: int = 26) -> dict:
    """All checks; mass properties integrated with quadrature degree 2*degree, the one
    fem_cage.elasticity assembles M with (so the comparison is like for like)."""
    Z = len(red["interface_positions"])
    load_nodes = sorted({Z // 4, Z // 2, (3 * Z) // 4, Z - 1} - {0})
    out = {"static": check_static(red, load_nodes, 0, n_keep),
           # the neighbouring pocket: a local load case (the opposite pocket would bend the
           # whole ring as a cantilever from the clamped pocket, stresses of GPa per kN)
           "stress": check_stress(red, 1, 0, 1000.0, n_keep),
           "frequencies": check_frequencies(red, 10),
           "centrifugal": check_centrifugal(red, 1000.0, n_keep),
           "guide": check_guide(red, 100.0, 0.0, 1.0, n_keep),
           "invariants": check_invariants(red, domain, geometry.material.density, 2 * degree)}
    m = min(n_keep, len(red["omega"]))
    out["von_mises_evaluator"] = check_von_mises(red["stress"][:, :, :m], red["omega"][:m])
    out["von_mises_evaluator_all_modes"] = check_von_mises(red["stress"], red["omega"], 200)
    return out


def run(args) -> int:
    from mesh.cage_geometry import PAPER_CAGE
    from common.validation import require_range, InputError
    from . import reduced_cage as rcf
    import mesh.cage_mesh as cm      # light: gmsh is imported inside its functions
    size = cm.DEFAULT_MESH_SIZE if args.size is None else args.size
    pocket = cm.DEFAULT_POCKET_SIZE if args.pocket_size is None else args.pocket_size
    order = cm.DEFAULT_ORDER if args.order is None else args.order
    degree = getattr(cm, "DEFAULT_DEGREE", 2) if args.degree is None else args.degree
    coupling = args.coupling or rcf.DEFAULT_COUPLING
    n_fixed = rcf.DEFAULT_N_FIXED if args.n_fixed is None else args.n_fixed
    require_range("reduce.n_fixed", n_fixed, 0, 2000)
    geometry = PAPER_CAGE.validate()
    centrifugal = getattr(args, "centrifugal", True)
    guide_loads = getattr(args, "guide_loads", True)
    inertia_relief = getattr(args, "inertia_relief", True)
    key = rcf.cache_key(geometry, size, order, pocket, coupling, n_fixed, degree, centrifugal,
                        guide_loads, inertia_relief)
    path = None if args.force else rcf.find_cached(key)
    summary = None
    if path is None or args.check:
        path, red, summary = build(geometry, size, order, pocket, coupling, n_fixed,
                                   quiet=args.quiet, checks=args.check or args.json is not None,
                                   n_keep=args.n_keep, degree=degree, centrifugal=centrifugal,
                                   guide_loads=guide_loads, inertia_relief=inertia_relief)
    rc = rcf.read(path)
    if rc.n_modes < args.n_keep:
        raise InputError(f"reduce.n_keep = {args.n_keep} is outside the allowed range [1, {rc.n_modes}]")
    if not args.quiet:
        print(f"reduced cage: {path}")
        print(f"  {rc.n_modes} modes stored ({coupling}, {n_fixed} fixed-interface"
              f"{', centrifugal vector' if centrifugal else ''}"
              f"{', land-load vectors' if guide_loads else ''}"
              f"{', inertia-relief vectors' if inertia_relief else ''}); "
              f"kept {args.n_keep}: elastic {np.round(rc.frequency_hz[6:args.n_keep], 1).tolist()} Hz")
    if args.output:
        import shutil
        shutil.copyfile(path, args.output)
    if args.json:
        out = summary if summary is not None else dict(rc.checks)
        out = dict(out)
        out["file"] = str(path)
        out["content_hash"] = str(rc.attrs.get("content_hash"))
        out["n_keep"] = args.n_keep
        out["kept_frequencies_hz"] = rc.frequency_hz[:args.n_keep].tolist()
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=1, default=rcf._jsonable))
    if args.xdmf:
        write_xdmf(rc, args.xdmf, args.n_keep)
    return 0
