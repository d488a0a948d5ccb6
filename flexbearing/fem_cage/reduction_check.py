"""Verification of a reduction (flexbearing.fem_cage.reduction) against the full finite-element model.

Static exactness at several pockets (full basis and n_keep truncation), stress recovery of a pocket
load case vs the full FE solution, the free–free (inertia-relief) static response to a centrifugal
load and to a land load vs the full FE (check_centrifugal, check_guide), free–free frequencies vs
the full model, mass properties vs direct integration, the max-von-Mises evaluator vs brute force
and its cost per call. `run_checks` runs them all (`flexbearing reduce --check`).
"""
from __future__ import annotations

import time

import numpy as np

from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP
from .stress_modes import von_mises
from .modes import free_free_modes


def _rel(a, b):
    return float(np.linalg.norm(a - b) / max(np.linalg.norm(b), 1e-300))


def check_static(red: dict, load_nodes, fixed_node: int = 0, n_keep: int = DEFAULT_N_KEEP) -> dict:
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
                 n_keep: int = DEFAULT_N_KEEP) -> dict:
    """A circumferential ball force on one pocket (node fixed_node clamped): max von Mises and its
    vertex from the full FE displacement (same vertex-averaging operator) vs modal recovery."""
    from .craig_bampton import full_static, reduced_static_interface
    from .von_mises_search import MaxVonMises
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


def check_centrifugal(red: dict, spin: float = 1000.0, n_keep: int = DEFAULT_N_KEEP) -> dict:
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
                n_keep: int = DEFAULT_N_KEEP) -> dict:
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
    """Reduced free–free elastic frequencies vs the full model's (flexbearing.fem_cage.modes), and for RBE2
    vs the full model with the same rigid pocket walls (T^T K T)."""
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
    from .von_mises_search import MaxVonMises
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


def run_checks(red: dict, domain, geometry, degree: int, n_keep: int = DEFAULT_N_KEEP) -> dict:
    """All checks; mass properties integrated with quadrature degree 2*degree, the one
    flexbearing.fem_cage.elasticity assembles M with (so the comparison is like for like)."""
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
