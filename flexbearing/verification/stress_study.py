"""Static stress of the free cage under the loads the dynamics apply, and its mesh convergence.

Load cases (body frame: x the bearing axis, pocket k at azimuth theta_k = 2 pi k / Z from +y):

    spin              the cage spinning at Omega about x: body force rho Omega^2 x_perp, nodal load
                      f = Omega^2 M x_perp (flexbearing.fem_cage.reduction.centrifugal_load)
    pocket_circ/_axial/_radial
                      a force F on pocket k's interface node, circumferential e_theta, axial e_x or
                      radial e_r, spread over the pocket wall by the RBE3 distributing coupling the
                      reduced cage uses: f = C_k^T (F, 0) (flexbearing.fem_cage.interface, Eq. (2))
    land              a radial land force F along body z on the guide surface, the sine
                      traction of flexbearing.fem_cage.reduction.guide_load_vectors (G2), centred on pocket 5
                      (azimuth 90 deg), so the refined zone of the study holds its maximum

Each is solved for the FREE cage by inertia relief, the quasi-static answer of an unsupported body
to a load with a net force or moment (Craig & Kurdila, "Fundamentals of Structural Dynamics"
(2006) §14.3; MSC Nastran "inertia relief"):

    K u = f - M R a,   R^T M u = 0,   a = (R^T M R)^-1 R^T f                     (IR)

(R the nodal rigid fields), as the saddle-point system [K, M R; (M R)^T, 0]. The stress is the
project's nodal stress (flexbearing.fem_cage.stress_modes, Eq. (1): each cell's Hooke stress at its geometry
nodes, averaged over the cells sharing the node) and its maximum von Mises value over the nodes is
what the run reports for the dynamic state; the same operator here makes the study speak of the
reported number.

Convergence: the maximum and its location for a sequence of meshes, Richardson-extrapolated with
h = ndofs^(-1/3) (flexbearing.fem_cage.mesh_study.richardson, Roache 1998 ch. 5). A maximum that sits on a
sharp re-entrant edge grows without bound under refinement (Williams, J. Appl. Mech. 19 (1952)
526); on the cage's convex edges (pocket/bore, pocket/outside) it converges.
"""
from __future__ import annotations

import time

import numpy as np
from flexbearing.fem_cage.reduction import centrifugal_load, guide_load_vectors
from flexbearing.fem_cage.stress_modes import von_mises, NodalStress
from flexbearing.mesh.cage_mesh import cached_cage_mesh, mesh_quality_of
from flexbearing.mesh.quality import MIN_JACOBIAN_RATIO
from flexbearing.fem_cage.mesh_study import richardson

# The paper case's cage spin: 14,000 rpm inner ring, cage at ~0.46 of it (Table 5 kinematics).
SPIN_RAD_S = 645.0
POCKET_FORCE_N = 1000.0
LAND_FORCE_N = 1000.0
POCKET = 5                    # the loaded pocket (azimuth 90 deg: off the revolution seam)
# Half-width (deg of azimuth) of the zone around a locally refined pocket over which the
# study's zone maxima are taken: the pocket (+-8 deg at the bore) and half the bars next to it.
ZONE_DEG = 9.0
CASES = ("spin", "pocket_circ", "pocket_axial", "pocket_radial", "land")


def pocket_direction(theta: float, kind: str) -> np.ndarray:
    """Unit vector of a pocket force at azimuth theta: circumferential e_theta, axial e_x, radial e_r."""
    c, s = np.cos(theta), np.sin(theta)
    return {"circ": np.array([0.0, -s, c]), "axial": np.array([1.0, 0.0, 0.0]),
            "radial": np.array([0.0, c, s])}[kind]


def load_vectors(V, facet_tags, M, geometry, cases=CASES, pocket: int = POCKET) -> dict:
    """Nodal load vector (n,) of each case (module docstring), body frame, N."""
    from flexbearing.fem_cage import interface as itf
    X = V.tabulate_dof_coordinates()[:, :3]
    n = 3 * len(X)
    out = {}
    if "spin" in cases:
        out["spin"] = SPIN_RAD_S ** 2 * centrifugal_load(M, X)
    pocket_cases = [c for c in cases if c.startswith("pocket_")]
    if pocket_cases:
        walls = itf.pocket_wall_nodes(V, facet_tags, geometry.n_pockets)
        weights = itf.pocket_wall_weights(V, facet_tags, walls)
        C = itf.rbe3_constraint(n, walls, weights, X, itf.pocket_centres(geometry)).tocsr()
        theta = geometry.pocket_azimuths()[pocket]
        Ck = C[6 * pocket:6 * pocket + 3]
        for c in pocket_cases:
            out[c] = Ck.T @ (POCKET_FORCE_N * pocket_direction(theta, c.split("_")[1]))
    if "land" in cases:
        F, _ = guide_load_vectors(V, facet_tags)
        out["land"] = LAND_FORCE_N * F[:, 1]
    return out


def solve_free(K, M, X, loads: dict) -> dict:
    """Inertia-relief displacements (IR) of each load (one saddle-point factorisation)."""
    import scipy.sparse as sp
    from flexbearing.fem_cage.craig_bampton import SaddleSolver
    from flexbearing.fem_cage.interface import rigid_field
    R = rigid_field(X)
    solver = SaddleSolver(sp.csr_matrix(K), sp.csr_matrix((M @ R).T))
    try:
        names = list(loads)
        U, _ = solver.solve(np.column_stack([loads[k] for k in names]), None)
    finally:
        solver.destroy()
    return {k: U[:, j] for j, k in enumerate(names)}


def max_von_mises(op, u, mask=None) -> dict:
    """Max nodal von Mises of displacement u (op: stress_modes.NodalStress), its node, position
    (m), radius and azimuth, and the five highest nodal values (Pa)."""
    vm = von_mises(op(u))
    if mask is not None:
        vm = np.where(mask, vm, -1.0)
    order = np.argsort(-vm)
    n = int(order[0])
    x = op.coords[n]
    return {"vm_max_Pa": float(vm[n]), "node": n, "position_m": x.tolist(),
            "radius_m": float(np.hypot(x[1], x[2])),
            "azimuth_deg": float(np.degrees(np.arctan2(x[2], x[1])) % 360.0),
            "top5_Pa": vm[order[:5]].tolist()}


def run_level(geometry, size: float, pocket_size: float, degree: int, order: int = 2,
              cases=CASES, quiet: bool = True, local=None) -> dict:
    """One mesh level: mesh (cached, validated and repaired by flexbearing.mesh.cage_mesh), then run_mesh.
    Sizes in m. local = (pockets, h): refine around the edges of those pockets
    (flexbearing.mesh.cage_mesh.build_cage_mesh)."""
    msh = cached_cage_mesh(geometry, size, order, pocket_size, local)
    out = run_mesh(geometry, msh, degree, cases, quiet, None if local is None else local[0])
    out.update({"size_m": size, "pocket_size_m": pocket_size, "order": order,
                "local": None if local is None else [sorted(int(k) for k in local[0]), float(local[1])]})
    if not quiet:
        print(f"  {size * 1e3:g}/{pocket_size * 1e3:g} mm"
              + ("" if local is None else f", {local[1] * 1e3:g} mm at pockets {list(local[0])}")
              + f" P{degree}: {out['ndofs']} dofs, "
              + ", ".join(f"{k} {v['vm_max_Pa'] / 1e6:.2f} MPa" for k, v in out["cases"].items())
              + f" ({sum(out['timing_s'].values()):.0f} s)", flush=True)
    return out


def run_mesh(geometry, msh, degree: int, cases=CASES, quiet: bool = True, zone_pockets=None,
             min_quality: float | None = None, check: bool = True) -> dict:
    """Assemble the mesh file msh (P-degree), solve each case free–free (IR), the max von Mises and
    where. zone_pockets: also the maxima over the nodes within ZONE_DEG of those pockets'
    azimuths (`cases_zone`). min_quality: the Jacobian-ratio bound the mesh must pass (default
    flexbearing.mesh.quality.MIN_JACOBIAN_RATIO; the quality-bound study passes a lower one to measure what
    badly curved elements do to the stress; check=False reads even inverted ones)."""
    from mpi4py import MPI
    from flexbearing.fem_cage.craig_bampton import petsc_to_scipy
    from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass, global_ndofs
    t0 = time.perf_counter()
    quality = mesh_quality_of(msh, degree)
    bound = MIN_JACOBIAN_RATIO if min_quality is None else min_quality
    domain, _, facet_tags, _ = load_cage_mesh(msh, MPI.COMM_SELF, min_quality=bound, check=check)
    V, Kp, Mp = assemble_stiffness_mass(domain, geometry.material, degree)
    K, M = petsc_to_scipy(Kp), petsc_to_scipy(Mp)
    Kp.destroy()
    Mp.destroy()
    t1 = time.perf_counter()
    loads = load_vectors(V, facet_tags, M, geometry, cases)
    X = V.tabulate_dof_coordinates()[:, :3]
    U = solve_free(K, M, X, loads)
    t2 = time.perf_counter()
    op = NodalStress(V, geometry.material)
    res = {k: max_von_mises(op, U[k]) for k in cases}
    zone = None
    if zone_pockets is not None:
        az = np.degrees(np.arctan2(op.coords[:, 2], op.coords[:, 1]))
        zone = np.zeros(len(az), dtype=bool)
        for k in zone_pockets:
            th = np.degrees(geometry.pocket_azimuths()[k])
            zone |= np.abs((az - th + 180.0) % 360.0 - 180.0) <= ZONE_DEG
    return {"mesh_file": str(msh), "degree": degree, "ndofs": global_ndofs(V),
            "n_cells": int(domain.topology.index_map(3).size_local),
            "n_stress_nodes": int(len(op.nodes)), "mesh_quality": quality, "cases": res,
            "cases_zone": None if zone is None else {k: max_von_mises(op, U[k], zone) for k in cases},
            "timing_s": {"mesh_assemble": t1 - t0, "solve": t2 - t1,
                         "stress": time.perf_counter() - t2}}


def extrapolate(levels: list[dict], case: str) -> dict:
    """Richardson limit of the max von Mises of `case` from the three finest levels (h = ndofs^-1/3),
    and each level's error against it."""
    lv = sorted(levels, key=lambda r: r["ndofs"])
    f = [r["cases"][case]["vm_max_Pa"] for r in lv]
    h = [r["ndofs"] ** (-1.0 / 3.0) for r in lv]
    if len(lv) < 3:
        return {"limit_Pa": None, "observed_order": None}
    finf, p = richardson(f[-3], f[-2], f[-1], h[-3], h[-2], h[-1])
    return {"limit_Pa": float(finf), "observed_order": None if p is None else float(p),
            "errors": [float(v / finf - 1.0) for v in f], "ndofs": [r["ndofs"] for r in lv]}
