"""Independent FE check of the cage: the project's dolfinx FE against CalculiX on the same mesh.

Both codes solve the same discrete problem: the same curved quadratic tetrahedral .msh (C3D10 in
CalculiX, Lagrange P2 on the order-2 geometry here: the same isoparametric space), the same
material (E, nu, rho of the cage), the same loads and the same supports. Compared: the nodal
displacement, the nodal stress tensor and von Mises field (maximum, where it is, the field at the
hottest nodes) and the free–free frequencies.

Load cases (flexbearing.verification.calculix builds the decks):

* spin: the cage spinning at omega about its axis x. CalculiX computes its own body load
  (*DLOAD CENTRIF: rho omega^2 r_perp, integrated with its 4-point rule); the project uses the
  consistent load f = omega^2 M x_perp (flexbearing.fem_cage.reduction.centrifugal_load). Self-equilibrated
  by symmetry: both are held by the same statically determinate 3-2-1 support (support_dofs: six
  displacement components at three nodes far apart; it removes the six rigid motions and nothing
  else), whose reactions are reported: the out-of-balance of each code's discrete load (measured
  ~1e-7 of sum |f| for the project's consistent load, ~3e-5 for ccx's 4-point CENTRIF). The project's inertia-relief solution (K u = f - M R a, R^T M u = 0, as
  flexbearing.fem_cage.reduction_check.check_centrifugal) is solved as well: its stress must equal the 3-2-1 one.
* pocket: a ball force F (1 kN) on pocket k_load, pocket k_held's interface node held: the load
  case of flexbearing.fem_cage.reduction_check.check_stress, solved as it does (RBE3 coupling of both pockets,
  flexbearing.fem_cage.interface, the saddle LU of flexbearing.fem_cage.craig_bampton.full_static). Holding an RBE3 node
  only fixes the rigid motions: the held pocket takes a force and moment (mu) that the equilibrium
  of the free cage fixes, mu = (F, (x_load - x_held) x F) — so the same stress field is the free
  cage under F distributed on pocket k_load plus (-F, -(x_load - x_held) x F) distributed on
  pocket k_held, with any support that removes only the rigid motions. That is what CalculiX
  gets, with its OWN distributing couplings (*COUPLING + *DISTRIBUTING at both pockets: weights
  w_i = ∫ N_i dA / A from its own face integration, the bolt-pattern moment distribution; the
  same definition as the project's RBE3, flexbearing.fem_cage.interface Eq. (2), computed independently) and
  the 3-2-1 support. The project solves that form too (same 3-2-1 support) and its stress is
  checked equal to the held-RBE3 stress (to solver precision).

What is independent and what is shared. Independent: element matrices (shape functions,
Jacobians, quadrature), assembly, the centrifugal body load, the pocket couplings' weights and
load distribution, the linear and eigen solvers (SPOOLES + ARPACK vs MUMPS + SLEPc), stress
recovery (ccx: integration-point stresses extrapolated to the nodes; here: the cell's stress
interpolated at its nodes, flexbearing.fem_cage.stress_modes.NodalStress; both averaged over the cells at a
node). Shared: the mesh (the point of the check), the material constants, the load and support
definitions (the coupling formula, the 3-2-1 nodes, the force).

Where the two differ by construction, and how it shrinks. (1) Quadrature: ccx integrates C3D10
with 4 Gauss points (exact for the stiffness of a straight-sided element, not for its mass, nor
for a curved element); the project uses degree 2 x degree = 4 by default. With
quadrature_degree = 2 the project uses the same 4-point rule and its free–free frequencies equal
CalculiX's to its printed digits; with 4 they differ by the quadrature error, of the order of
the discretisation error itself (measured on the paper cage, 4 -> 2 mm: frequencies 0.085 % ->
0.009 %, ~h^3.2; displacements ~h^2.6..3.2). (2) Stress recovery: on a straight-sided element the P2 stress is
linear and 4 Gauss points sample it exactly, so ccx's extrapolation and the project's
interpolation give the same corner and mid-edge values (tests/test_calculix.py checks it to
round-off); they differ only in curved elements (pocket walls, bore, outside), whose stress is
not linear in x. Both recover a uniform stress exactly (x is in the isoparametric space), so the
difference scales with the stress gradient times the element's distortion: ~ h^2 kappa
|grad sigma| relative to sigma (kappa the wall curvature). Measured on the paper cage
(benchmarks/results/calculix_check.md): the whole-field difference falls as h^1.6..1.8 (spin
2.3 % at 4 mm, 0.67 % at 2 mm); at a single node, the peak, it fluctuates from mesh to mesh (up
to 3.3 % at 4 mm, 1.6 % at 2.5 mm, 1.4 % at 2 mm).
extrapolated_nodal_stress applies ccx's recovery to the project's solution and separates (2)
from the solutions' own difference.

Node matching: the dolfinx geometry and dof coordinates are the .msh node coordinates (the same
floating-point numbers); nodes are matched by coordinates (KD-tree, tolerance 1e-9 of the mesh
size), and every field is compared in the .msh node order.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from flexbearing.verification import calculix as cx
from flexbearing.fem_cage.stress_modes import von_mises
from flexbearing.fem_cage.stress_modes import NodalStress, VOIGT
from flexbearing.common.validation import InputError
from flexbearing.fem_cage.reduction import centrifugal_load
from flexbearing.fem_cage.modes import free_free_modes


# ------------------------------------------------------------------ project side

@dataclass
class ProjectModel:
    """The project's FE model of the mesh: P2 space V, K and M (scipy CSR), nodal-stress operator,
    facet tags, and the maps from V's dof blocks and the stress nodes to the .msh node order."""
    mesh: cx.Tet10Mesh
    V: object
    K: sp.csr_matrix
    M: sp.csr_matrix
    facet_tags: object
    stress_op: object
    dof_node: np.ndarray          # V dof block b sits on .msh node dof_node[b]
    stress_node: np.ndarray       # stress_op node j is .msh node stress_node[j]
    assemble_s: float
    material: object


def match_nodes(X: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """Index i into `nodes` of each point of X (same coordinates); ValueError if one is missing."""
    from scipy.spatial import cKDTree
    scale = np.ptp(nodes, axis=0).max()
    d, i = cKDTree(nodes).query(X)
    if d.max() > 1e-9 * scale:
        raise ValueError(f"{int((d > 1e-9 * scale).sum())} points match no mesh node (worst {d.max():.3g} m)")
    return i


def project_model(msh_path, material, degree: int = 2, quadrature_degree: int | None = None) -> ProjectModel:
    """Load the .msh into dolfinx (serial), assemble K and M (flexbearing.fem_cage.elasticity), build the
    nodal-stress operator (flexbearing.fem_cage.stress_modes.NodalStress) and the node maps."""
    from mpi4py import MPI
    from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass
    from flexbearing.fem_cage.craig_bampton import petsc_to_scipy
    if degree != 2:
        raise InputError(f"calculix_check.degree = {degree} is outside the allowed set {{2}} "
                         "(C3D10 is the P2 isoparametric element)")
    mesh = cx.read_tet10_mesh(msh_path)
    t0 = time.perf_counter()
    domain, _, facet_tags, _ = load_cage_mesh(msh_path, MPI.COMM_SELF)
    V, Kp, Mp = assemble_stiffness_mass(domain, material, degree, quadrature_degree)
    K, M = petsc_to_scipy(Kp), petsc_to_scipy(Mp)
    Kp.destroy()
    Mp.destroy()
    op = NodalStress(V, material)
    dt = time.perf_counter() - t0
    X = V.tabulate_dof_coordinates()[:, :3]
    return ProjectModel(mesh, V, K, M, facet_tags, op, match_nodes(X, mesh.nodes),
                        match_nodes(op.coords, mesh.nodes), dt, material)


def _to_mesh_order(values: np.ndarray, index: np.ndarray, n: int) -> np.ndarray:
    out = np.full((n,) + values.shape[1:], np.nan)
    out[index] = values
    return out


def support_dofs(nodes: np.ndarray, radius: float, azimuth0: float) -> list[tuple[int, int]]:
    """A statically determinate 3-2-1 support: (node index, dof 1..3) at the three mesh nodes
    nearest to (0, radius cos phi, radius sin phi), phi = azimuth0 + 0, 120, 240 deg: node A all
    three components, node B two, node C one, the components chosen to make the 6 x 6 map from
    the rigid motions (t, omega) to the held components best conditioned (largest smallest
    singular value, rotations scaled by the radius). It removes the rigid motions and nothing else
    (6 constraints, non-singular): a self-equilibrated load gives zero reactions."""
    from flexbearing.fem_cage.interface import rigid_field
    phi = azimuth0 + np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
    targets = np.column_stack([np.zeros(3), radius * np.cos(phi), radius * np.sin(phi)])
    from scipy.spatial import cKDTree
    _, idx = cKDTree(nodes).query(targets)
    a, b, c = (int(i) for i in idx)
    R = rigid_field(nodes[[a, b, c]])
    R[:, 3:] *= radius
    best, best_s = None, -1.0
    for db in ((1, 2), (1, 3), (2, 3)):
        for dc in (1, 2, 3):
            dofs = [(a, 1), (a, 2), (a, 3), (b, db[0]), (b, db[1]), (c, dc)]
            rows = [3 * [a, b, c].index(n) + d - 1 for n, d in dofs]
            s = np.linalg.svd(R[rows], compute_uv=False).min()
            if s > best_s:
                best, best_s = dofs, s
    return best


def project_static(model: ProjectModel, f: np.ndarray, support) -> dict:
    """K u = f with the 3-2-1 support (saddle LU, flexbearing.fem_cage.craig_bampton.SaddleSolver). Returns
    u (.msh node order, (N, 3)), nodal stress ((N, 6) Voigt), the support reactions (N) and the
    raw dof vector."""
    from flexbearing.fem_cage.craig_bampton import SaddleSolver
    from flexbearing.fem_cage.interface import selection_matrix
    inv = np.empty(len(model.dof_node), dtype=np.int64)
    inv[model.dof_node] = np.arange(len(model.dof_node))         # .msh node -> V dof block
    C = selection_matrix(model.K.shape[0], [3 * int(inv[nd]) + d - 1 for nd, d in support])
    t0 = time.perf_counter()
    solver = SaddleSolver(model.K, C)
    u, lam = solver.solve(f, None)
    solver.destroy()
    t_solve = time.perf_counter() - t0
    return _fields(model, u) | {"reactions_N": (-lam).tolist(), "solve_s": t_solve}


def _fields(model: ProjectModel, u: np.ndarray) -> dict:
    n = len(model.mesh.nodes)
    t0 = time.perf_counter()
    S = model.stress_op(u)
    dt = time.perf_counter() - t0
    return {"u_dofs": u, "u": _to_mesh_order(u.reshape(-1, 3), model.dof_node, n),
            "stress": _to_mesh_order(S, model.stress_node, n), "stress_recovery_s": dt}


# the 4-point Gauss rule of ccx's C3D10 (degree 2): barycentric (b, a, a, a) and permutations,
# a = (5 - sqrt 5)/20, b = 1 - 3a (Keast; ccx gauss.f gauss3d5); point k lies nearest vertex k
GAUSS4_A = (5.0 - np.sqrt(5.0)) / 20.0


def extrapolated_nodal_stress(model: ProjectModel, u: np.ndarray) -> np.ndarray:
    """CalculiX's nodal stress recovery applied to the project's displacement u (dof array):
    the cell stress at the 4 Gauss points, extrapolated linearly to the 4 corners (the linear
    field through the 4 values: corner = B^-1 sigma_gp with B[k, j] = lambda_j(point k), the
    barycentric coordinates; B^-1 has 1.92705 on its diagonal and -0.30902 elsewhere, ccx
    extrapolate.f's a4), each mid-edge node the mean of its two corners, then averaged over the
    cells at each node. (N, 6) Voigt, .msh node order. Used to separate the two codes' recovery
    from their solutions (module docstring)."""
    from flexbearing.common.fe_stack import fem, evaluate_expression
    from flexbearing.fem_cage.elasticity import stress
    op = model.stress_op
    op.u.x.array[:] = u
    expr = fem.Expression(stress(op.u, model.material), _ref_points())
    ncell = len(op.vtk_cells)
    sig = evaluate_expression(expr, op.u.function_space.mesh, np.arange(ncell)).reshape(ncell, 4, 9)[:, :, VOIGT]
    lam = np.column_stack([1 - _ref_points().sum(1), _ref_points()])     # (point, vertex)
    corners = np.einsum("kj,cjv->ckv", np.linalg.inv(lam), sig)          # (cell, vertex, 6)
    mids = [0.5 * (corners[:, a] + corners[:, b]) for a, b in cx.TET10_EDGES]
    nodal = np.concatenate([corners, np.stack(mids, axis=1)], axis=1)    # VTK order
    out = np.zeros((len(op.nodes), 6))
    np.add.at(out, op.vtk_cells.ravel(), nodal.reshape(-1, 6))
    out /= op.count[:, None]
    return _to_mesh_order(out, model.stress_node, len(model.mesh.nodes))


def _ref_points() -> np.ndarray:
    """The Gauss points as reference coordinates (xi, eta, zeta) of the reference tetrahedron
    (0,0,0), (1,0,0), (0,1,0), (0,0,1): point k nearest vertex k."""
    a, b = GAUSS4_A, 1 - 3 * GAUSS4_A
    return np.array([[a, a, a], [b, a, a], [a, b, a], [a, a, b]])


def inertia_relief(model: ProjectModel, f: np.ndarray) -> dict:
    """Free–free quasi-static response K u = f - M R a, R^T M u = 0 (R the rigid fields), as
    flexbearing.fem_cage.reduction_check.check_centrifugal solves it."""
    from flexbearing.fem_cage.craig_bampton import SaddleSolver
    from flexbearing.fem_cage.interface import rigid_field
    X = model.V.tabulate_dof_coordinates()[:, :3]
    solver = SaddleSolver(model.K, sp.csr_matrix((model.M @ rigid_field(X)).T))
    u, _ = solver.solve(f, None)
    solver.destroy()
    return _fields(model, u)


# ------------------------------------------------------------------ comparison

def symmetric_distance(p, q, pitch: float | None = None, mirror: bool = False) -> float:
    """|p - q| with q first mapped by the symmetry of the load case that brings it nearest p:
    rotations by multiples of `pitch` (rad) about x, and the mirror x -> -x if `mirror`."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    images = [q] + ([q * [-1.0, 1.0, 1.0]] if mirror else [])
    if pitch is None:
        return float(min(np.linalg.norm(p - im) for im in images))
    best = np.inf
    for im in images:
        k = np.round((np.arctan2(p[2], p[1]) - np.arctan2(im[2], im[1])) / pitch)
        c, s = np.cos(k * pitch), np.sin(k * pitch)
        rot = np.array([im[0], c * im[1] - s * im[2], s * im[1] + c * im[2]])
        best = min(best, np.linalg.norm(p - rot))
    return float(best)


def compare_fields(mesh: cx.Tet10Mesh, u_p, s_p, u_c, s_c, n_top: int = 20,
                   pitch: float | None = None, mirror: bool = False) -> dict:
    """Project (p) vs CalculiX (c) nodal fields in .msh node order: the max von Mises of each, its
    node and coordinates, the relative difference of the maxima, the distance between the peak
    nodes (also modulo the load case's symmetry: pitch, mirror; symmetric_distance), each code's
    value at the other's peak node relative to its own max (1 = the same hot spot); the von Mises
    and tensor differences at the n_top hottest nodes of the project; the whole-field stress and
    displacement differences."""
    vm_p, vm_c = von_mises(s_p), von_mises(s_c)
    ip, ic = int(np.nanargmax(vm_p)), int(np.nanargmax(vm_c))
    top = np.argsort(-np.nan_to_num(vm_p, nan=-1.0))[:n_top]
    ds = np.linalg.norm(s_c[top] - s_p[top], axis=1) / np.linalg.norm(s_p[top], axis=1)
    du = u_c - u_p
    return {
        "vm_max_project_Pa": float(vm_p[ip]), "vm_max_calculix_Pa": float(vm_c[ic]),
        "vm_max_rel_diff": float(vm_c[ic] / vm_p[ip] - 1.0),
        "node_project": ip, "node_calculix": ic,
        "position_project_m": mesh.nodes[ip].tolist(), "position_calculix_m": mesh.nodes[ic].tolist(),
        "peak_distance_m": float(np.linalg.norm(mesh.nodes[ip] - mesh.nodes[ic])),
        "peak_distance_symmetric_m": symmetric_distance(mesh.nodes[ip], mesh.nodes[ic], pitch, mirror),
        "calculix_at_project_peak_rel": float(vm_c[ip] / vm_c[ic]),
        "project_at_calculix_peak_rel": float(vm_p[ic] / vm_p[ip]),
        "n_top": int(n_top),
        "top_vm_rel_diff_max": float(np.max(np.abs(vm_c[top] / vm_p[top] - 1.0))),
        "top_tensor_rel_diff_max": float(ds.max()),
        "top_vm_range_Pa": [float(vm_p[top].min()), float(vm_p[top].max())],
        "vm_abs_diff_max_rel": float(np.nanmax(np.abs(vm_c - vm_p)) / vm_p[ip]),
        "stress_rel_diff_fro": float(np.linalg.norm(s_c - s_p) / np.linalg.norm(s_p)),
        "u_max_project_m": float(np.linalg.norm(u_p, axis=1).max()),
        "u_rel_diff_l2": float(np.linalg.norm(du) / np.linalg.norm(u_p)),
        "u_abs_diff_max_rel": float(np.linalg.norm(du, axis=1).max() / np.linalg.norm(u_p, axis=1).max()),
    }


def recovery_split(model: ProjectModel, p: dict, u_c, s_c) -> dict:
    """The project's solution with CalculiX's stress recovery (extrapolated_nodal_stress) vs
    CalculiX: what is left is the difference of the two solutions alone."""
    s_pe = extrapolated_nodal_stress(model, p["u_dofs"])
    c = compare_fields(model.mesh, p["u"], s_pe, u_c, s_c)
    keys = ("vm_max_project_Pa", "vm_max_rel_diff", "node_project", "node_calculix",
            "top_vm_rel_diff_max", "top_tensor_rel_diff_max", "vm_abs_diff_max_rel", "stress_rel_diff_fro")
    return {k: c[k] for k in keys}


def _ccx_fields(run: cx.CcxRun, n: int):
    u = cx.nodal_field(run.block("DISP"), n)
    s = cx.nodal_field(run.block("STRESS"), n)
    return u, s


def _ccx_reactions(run: cx.CcxRun, n: int, support) -> list[float]:
    rf = cx.nodal_field(run.block("FORC"), n)
    return [float(rf[nd, d - 1]) for nd, d in support]


def spin_case(model: ProjectModel, material, omega: float, support, threads: int = 1, workdir=None,
              n_pockets: int | None = None) -> dict:
    """The spinning cage (module docstring): project 3-2-1 and inertia relief vs CalculiX CENTRIF.
    n_pockets: the cage's Z-fold symmetry (with the mirror x -> -x) for the peak distance."""
    X = model.V.tabulate_dof_coordinates()[:, :3]
    f = omega ** 2 * centrifugal_load(model.M, X)
    p = project_static(model, f, support)
    ir = inertia_relief(model, f)
    deck = cx.deck_text(model.mesh, material, boundary=support,
                        centrifugal=(omega, np.zeros(3), np.array([1.0, 0.0, 0.0])),
                        title=f"cage spinning at {omega} rad/s about x")
    run = cx.run_ccx(deck, workdir=workdir, threads=threads)
    n = len(model.mesh.nodes)
    u_c, s_c = _ccx_fields(run, n)
    out = compare_fields(model.mesh, p["u"], p["stress"], u_c, s_c,
                         pitch=None if n_pockets is None else 2 * np.pi / n_pockets, mirror=True)
    scale = float(np.abs(f).sum())
    out["same_recovery"] = recovery_split(model, p, u_c, s_c)
    out.update({"case": "spin", "omega_rad_s": omega, "load_abs_sum_N": scale,
                "reactions_project_N": p["reactions_N"],
                "reactions_calculix_N": _ccx_reactions(run, n, support),
                "inertia_relief_stress_rel_diff": float(
                    np.linalg.norm(ir["stress"] - p["stress"]) / np.linalg.norm(p["stress"])),
                "project_solve_s": p["solve_s"], "project_stress_recovery_s": p["stress_recovery_s"],
                "calculix_wall_s": run.wall_s})
    return out


def pocket_case(model: ProjectModel, geometry, force_n: float, direction: str, support,
                k_load: int = 1, k_held: int = 0, threads: int = 1, workdir=None) -> dict:
    """Ball force on pocket k_load, pocket k_held held (module docstring). direction:
    'circumferential' (e_theta of the pocket), 'axial' (x) or 'radial' (e_r)."""
    from flexbearing.fem_cage import interface as itf
    from flexbearing.fem_cage.craig_bampton import full_static
    th = geometry.pocket_azimuths()[k_load]
    dirs = {"circumferential": (0.0, -np.sin(th), np.cos(th)), "axial": (1.0, 0.0, 0.0),
            "radial": (0.0, np.cos(th), np.sin(th))}
    if direction not in dirs:
        raise InputError(f"calculix_check.direction = {direction!r} is outside the allowed set {set(dirs)}")
    F = force_n * np.array(dirs[direction])
    xm = itf.pocket_centres(geometry)
    moment = np.cross(xm[k_load] - xm[k_held], F)          # of F about the held pocket's node
    # project: RBE3 of the two pockets (flexbearing.fem_cage.interface), held as check_stress holds it
    V, ft = model.V, model.facet_tags
    walls = itf.pocket_wall_nodes(V, ft, geometry.n_pockets)
    weights = itf.pocket_wall_weights(V, ft, walls)
    X = V.tabulate_dof_coordinates()[:, :3]
    pick = [k_load, k_held]
    C = itf.rbe3_constraint(model.K.shape[0], [walls[k] for k in pick], [weights[k] for k in pick],
                            X, xm[pick])
    t0 = time.perf_counter()
    u_held = full_static(model.K, C, 1, [(0, np.r_[F, 0.0, 0.0, 0.0])])[0]
    t_held = time.perf_counter() - t0
    held = _fields(model, u_held)
    f = C[0:6].T @ np.r_[F, 0, 0, 0] + C[6:12].T @ np.r_[-F, -moment]
    p = project_static(model, np.asarray(f).ravel(), support)
    # CalculiX: its own distributing couplings at both pockets, the same 3-2-1 support
    n = len(model.mesh.nodes)
    cpl = [cx.DistributingCoupling(f"P{k:02d}", xm[k], cx.facet_faces(model.mesh, model.mesh.facets[itf.POCKET_TAG0 + k]),
                                   rotations=(k == k_held)) for k in pick]
    cloads = [(n, d + 1, F[d]) for d in range(3) if F[d] != 0.0]
    cloads += [(n + 1, d + 1, -F[d]) for d in range(3) if F[d] != 0.0]
    cloads += [(n + 1, d + 4, -moment[d]) for d in range(3) if moment[d] != 0.0]
    deck = cx.deck_text(model.mesh, geometry.material, boundary=support, cloads=cloads, couplings=cpl,
                        title=f"{force_n} N {direction} on pocket {k_load}, pocket {k_held} reacting")
    run = cx.run_ccx(deck, workdir=workdir, threads=threads)
    u_c, s_c = _ccx_fields(run, n)
    out = compare_fields(model.mesh, p["u"], p["stress"], u_c, s_c)
    out["same_recovery"] = recovery_split(model, p, u_c, s_c)
    out.update({"case": f"pocket_{direction}", "force_N": force_n, "direction": direction,
                "pocket_loaded": k_load, "pocket_held": k_held,
                "vm_max_project_held_rbe3_Pa": float(np.nanmax(von_mises(held["stress"]))),
                "held_vs_equilibrated_stress_rel_diff": float(
                    np.linalg.norm(held["stress"] - p["stress"]) / np.linalg.norm(p["stress"])),
                "reactions_project_N": p["reactions_N"],
                "reactions_calculix_N": _ccx_reactions(run, n, support),
                "project_solve_s": p["solve_s"], "project_held_solve_s": t_held,
                "calculix_wall_s": run.wall_s})
    return out


def frequency_case(model: ProjectModel, material, n_elastic: int = 20, threads: int = 1,
                   workdir=None, msh_path=None) -> dict:
    """Free–free modes: the n_elastic lowest elastic frequencies of CalculiX (*FREQUENCY, no
    support) and of the project (flexbearing.fem_cage.modes.free_free_modes) on the model's K and M, and
    with the project's K and M integrated by ccx's 4-point rule (quadrature degree 2) when
    msh_path is given."""
    from flexbearing.fem_cage.craig_bampton import scipy_to_petsc
    n = 6 + n_elastic
    t0 = time.perf_counter()
    f_p, _ = free_free_modes(scipy_to_petsc(model.K), scipy_to_petsc(model.M), n)
    t_p = time.perf_counter() - t0
    deck = cx.deck_text(model.mesh, material, analysis="frequency", n_modes=n, stress=False,
                        node_output=False, title="free-free modes")
    run = cx.run_ccx(deck, workdir=workdir, threads=threads)
    f_c = cx.read_eigenfrequencies(run.dat)
    if len(f_c) < n:
        raise RuntimeError(f"ccx returned {len(f_c)} of {n} eigenfrequencies")
    fp, fc = f_p[6:n], f_c[6:n]
    out = {"n_elastic": n_elastic, "project_hz": fp.tolist(), "calculix_hz": fc.tolist(),
           "rel_diff": (fc / fp - 1).tolist(), "max_abs_rel_diff": float(np.max(np.abs(fc / fp - 1))),
           "rigid_project_hz": f_p[:6].tolist(), "rigid_calculix_hz": f_c[:6].tolist(),
           "project_solve_s": t_p, "calculix_wall_s": run.wall_s}
    if msh_path is not None:
        q2 = project_model(msh_path, material, 2, quadrature_degree=2)
        f_q, _ = free_free_modes(scipy_to_petsc(q2.K), scipy_to_petsc(q2.M), n)
        out["project_quadrature2_hz"] = f_q[6:n].tolist()
        out["max_abs_rel_diff_quadrature2"] = float(np.max(np.abs(fc / f_q[6:n] - 1)))
    return out


# ------------------------------------------------------------------ the whole check

SPIN_RAD_S = 645.0          # the paper scene's top speed, ~6,160 rpm of the cage
POCKET_FORCE_N = 1000.0
DIRECTIONS = ("circumferential", "axial", "radial")


def check_mesh(msh_path, geometry, omega: float = SPIN_RAD_S, force_n: float = POCKET_FORCE_N,
               directions=DIRECTIONS, n_elastic: int = 20, threads: int = 1, workdir=None,
               quadrature_degree: int | None = None) -> dict:
    """Every comparison on one mesh: spin, a pocket force in each direction, free–free
    frequencies (with the project at its default quadrature and at ccx's 4-point rule). The 3-2-1
    support nodes sit on the outside diameter half a pocket pitch past the opposite side of the
    loaded pockets (pi + pi/Z), and 120° and 240° from there. quadrature_degree: the project's
    (None: flexbearing.fem_cage.elasticity's default, 4 for P2; 2 is ccx's own 4-point rule). Returns a dict
    (JSON-ready)."""
    t0 = time.perf_counter()
    model = project_model(msh_path, geometry.material, quadrature_degree=quadrature_degree)
    support = support_dofs(model.mesh.nodes, 0.5 * geometry.outside_diameter,
                           np.pi + np.pi / geometry.n_pockets)
    sub = (lambda name: None if workdir is None else str(Path(workdir) / name))
    out = {"quadrature_degree": quadrature_degree,
           "mesh": {"file": str(msh_path), "nodes": int(len(model.mesh.nodes)),
                    "elements": int(len(model.mesh.tets)), "dofs": int(3 * len(model.mesh.nodes))},
           "project_assembly_s": model.assemble_s,
           "support": [{"node": int(n), "dof": int(d), "position_m": model.mesh.nodes[n].tolist()}
                       for n, d in support],
           "cases": {}}
    out["cases"]["spin"] = spin_case(model, geometry.material, omega, support, threads, sub("spin"),
                                     geometry.n_pockets)
    for d in directions:
        out["cases"][f"pocket_{d}"] = pocket_case(model, geometry, force_n, d, support,
                                                  threads=threads, workdir=sub(f"pocket_{d}"))
    if n_elastic:
        out["frequencies"] = frequency_case(model, geometry.material, n_elastic, threads,
                                            sub("frequency"), msh_path=msh_path)
    out["total_s"] = time.perf_counter() - t0
    return out
