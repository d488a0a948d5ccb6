"""Peak-hold of the cage's maximum von Mises stress over every accepted integrator step.

The integrator (`multibody.integrator._rk_loop`) calls `stress_peak_step` after each accepted
step with the state it accepted. The step's modal coordinates of the full Craig–Bampton basis are

    q_k = y_modes,k                                              k = 6 .. n_keep-1 (integrated)
    q_k = (Phi_b,k^T · F_nodes + Omega_x^2 · Q_cf,k) / omega_k^2   k >= n_keep (residual, quasi-static)

(F_nodes: the Z pocket nodes and, as load point Z, the guide-surface land load; Phi_b then holds
the land load's modal loads in its row Z, coupling.flexible_cage.load_point_modes)

(mode acceleration / residual flexibility, Craig & Kurdila, "Fundamentals of Structural Dynamics",
2006, §14.3; the same formula as fem_cage.reduced_cage.static_correction and
coupling.flexible_cage.StressRecovery), with F_nodes the pocket-node loads in the cage body frame
that the right-hand side wrote into the cage tuple (cage[19]) when it evaluated the FSAL stage at
exactly this state, and Omega_x the cage's spin about its own axis (body frame). The rigid modes
carry no stress. Then sigma = S·q (nodal stress modes) and its maximum von Mises value over every
node of the mesh comes from the exact bounded search fem_cage.von_mises.max_von_mises_leaves_sq
(no node can be missed; bitwise the brute-force value).

The monitor keeps the largest value since its last reset, the node and the time where it occurred
and the full modal coordinates of that step (to draw the field at the peak). The run resets it at
every output sample, so each recorded value is the maximum over all integrator steps of the
sample interval, not a value at the sampling instant: a pocket impact shorter than the sample
interval is not missed.

Monitor tuple (all arrays, allocation-free kernel; `disabled_monitor()` for runs without stress):

    (on (1,) int64, A, gcentres, group_start, group_radius, centres, leaf_start, leaf_radius,
     node_radius, block_starts, vm_work, vm_qb, vm_count      -- fem_cage.von_mises.MaxVonMises arrays
     phi_res (Z + 1, 6, M - n_keep), w2_res (M - n_keep,), qcf_res (M - n_keep,),
     idx (4,) int64 = [cage block offset, modes block offset, n integrated elastic modes, n_keep],
     q_full (M,), peak (4,) = [vm^2 (Pa^2; -1 = empty), row, t, number of steps], q_peak (M,),
     w (3,) scratch)

numpy + numba only; imports no FE package.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from fem_cage.von_mises import max_von_mises_leaves_sq
from multibody.dynamics import cage_body_angular_velocity, cage_rotation

PEAK_VM_SQ, PEAK_ROW, PEAK_T, PEAK_N = 0, 1, 2, 3


@njit(cache=True)
def stress_peak_step(t, y, cage, mon):
    """Evaluate the max von Mises stress at the accepted state (t, y) and keep it if it is the
    largest since the last reset (module docstring). No-op when mon[0][0] == 0."""
    (on, A, gcentres, group_start, group_radius, centres, leaf_start, leaf_radius, node_radius,
     block_starts, vm_work, vm_qb, vm_count, phi_res, w2_res, qcf_res, idx, q_full, peak, q_peak,
     w) = mon
    if on[0] == 0:
        return
    c0 = idx[0]
    m0 = idx[1]
    n_el = idx[2]
    first = idx[3]
    R = cage[17]
    cage_rotation(y[c0 + 3], y[c0 + 4], y[c0 + 5], R)
    cage_body_angular_velocity(R, y, c0, w)
    spin2 = w[0] * w[0]
    for k in range(first):
        q_full[k] = 0.0
    for k in range(n_el):
        q_full[6 + k] = y[m0 + k]
    node_load = cage[19]
    n_res = w2_res.shape[0]
    for r in range(n_res):
        s = spin2 * qcf_res[r]
        for j in range(node_load.shape[0]):
            for i in range(6):
                s += phi_res[j, i, r] * node_load[j, i]
        q_full[first + r] = s / w2_res[r]
    v, row = max_von_mises_leaves_sq(A, gcentres, group_start, group_radius, centres, leaf_start,
                                     leaf_radius, node_radius, block_starts, q_full, vm_work,
                                     vm_qb, vm_count)
    peak[PEAK_N] += 1.0
    if v > peak[PEAK_VM_SQ]:
        peak[PEAK_VM_SQ] = v
        peak[PEAK_ROW] = row
        peak[PEAK_T] = t
        for k in range(q_full.shape[0]):
            q_peak[k] = q_full[k]


def new_monitor(evaluator, interface_modes, omega, q_cf, n_keep: int, cage_offset: int,
                modes_offset: int, n_integrated: int) -> tuple:
    """The monitor tuple for a fem_cage.von_mises.MaxVonMises `evaluator` over the full basis
    (M modes): interface_modes (Z + 1, 6, M) (load points: pockets, then the guide surface), omega (M,) rad/s, q_cf (M,) centrifugal modal load per
    unit Omega^2, n_keep (rigid included) the first residual mode, n_integrated the elastic modes
    in the state (n_keep - 6)."""
    ev = evaluator
    m = int(np.asarray(omega).shape[0])
    if ev.n_modes != m:
        raise ValueError(f"stress monitor: evaluator has {ev.n_modes} modes, the basis {m}")
    idx = np.array([cage_offset, modes_offset, n_integrated, n_keep], dtype=np.int64)
    w2 = np.asarray(omega, dtype=float)[n_keep:] ** 2
    return (np.ones(1, dtype=np.int64), ev.A, ev.gcentres, ev.group_start, ev.group_radius,
            ev.centres, ev.leaf_start, ev.leaf_radius, ev.node_radius, ev.block_starts, ev.work,
            ev.qb, ev.count, np.ascontiguousarray(np.asarray(interface_modes, dtype=float)[:, :, n_keep:]),
            np.ascontiguousarray(w2), np.ascontiguousarray(np.asarray(q_cf, dtype=float)[n_keep:]),
            idx, np.zeros(m), np.array([-1.0, -1.0, np.nan, 0.0]), np.zeros(m), np.zeros(3))


def disabled_monitor() -> tuple:
    """A monitor with the same numba types that does nothing (rigid cage, no stress recorded)."""
    i1, f1 = np.zeros(1, dtype=np.int64), np.zeros(1)
    f3 = np.zeros((1, 1, 6))
    f2 = np.zeros((1, 1))
    return (np.zeros(1, dtype=np.int64), f3, f3, np.zeros(2, dtype=np.int64), f2, f3,
            np.zeros(2, dtype=np.int64), f2, f2, np.zeros(2, dtype=np.int64), f1, f1,
            np.zeros(2, dtype=np.int64), np.zeros((1, 6, 1)), f1, f1, np.zeros(4, dtype=np.int64),
            f1, np.array([-1.0, -1.0, np.nan, 0.0]), f1, np.zeros(3))


def reset(mon) -> None:
    """Empty the peak (start of a sample interval)."""
    mon[18][:] = (-1.0, -1.0, np.nan, 0.0)


def peak(mon):
    """(max von Mises Pa, evaluator row, time s, steps evaluated, q_full at the peak) or None if
    no step was evaluated since the last reset."""
    p = mon[18]
    if p[PEAK_VM_SQ] < 0.0:
        return None
    return float(np.sqrt(p[PEAK_VM_SQ])), int(p[PEAK_ROW]), float(p[PEAK_T]), int(p[PEAK_N]), mon[19].copy()
