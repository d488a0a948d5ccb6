"""Peak-hold of the cage's maximum von Mises stress over every accepted integrator step.

The integrator (`flexbearing.multibody.integrator._rk_loop`) calls `stress_peak_step` after each accepted
step with the state it accepted. The step's stress over the full Craig–Bampton basis is

    sigma_n = S_n,kept q_kept + S_n,res diag(1/omega^2)(Phi_b,res^T F_nodes + Omega_x^2 Q_cf,res)
            = W_n y,     y = (Omega_x^2, q_kept, F_nodes)

i.e. the integrated elastic modes q_kept (y_modes) plus the quasi-static residual coordinates of
the discarded ones, q_k = (Phi_b,k^T F_nodes + Omega_x^2 Q_cf,k)/omega_k^2 (mode acceleration /
residual flexibility, Craig & Kurdila, "Fundamentals of Structural Dynamics", 2006, §14.3; the
same coordinates as flexbearing.fem_cage.reduced_cage.static_correction and flexbearing.coupling.flexible_cage.
StressRecovery), written in load space (flexbearing.fem_cage.von_mises_search.load_space_stress). F_nodes: the node
loads the right-hand side wrote into the cage arrays (cage.node_load: the Z pocket nodes and, as load
point Z, the guide-surface land load) when it evaluated the FSAL stage at exactly this state;
Omega_x the cage's spin about its own axis (body frame). The maximum von Mises value over every
node of the mesh comes from the exact tracking search flexbearing.fem_cage.von_mises.tracking_max_sq
(no node can be missed; bitwise the brute-force value of the same node kernel).

The monitor keeps the largest value since its last reset, the node and the time where it occurred
and the load-space vector y of that step (StressRecovery.full_coordinates_of turns it into the
full modal coordinates, to draw the field at the peak). The run resets it at every output
sample, so each recorded value is the maximum over all integrator steps of the sample interval,
not a value at the sampling instant: a pocket impact shorter than the sample interval is not
missed. The search starts from the interval's peak (a node that cannot beat it cannot change the
record) and first evaluates the node of the last new maximum (by time coherence close to this
step's maximum), so most nodes are dismissed by their bounds.

Monitor tuple (all arrays, allocation-free kernel; `disabled_monitor()` for runs without stress):

    (on (1,) int64, search (flexbearing.fem_cage.von_mises_search.TrackingMaxVonMises.arrays),
     idx (6,) int64 = [cage block offset, modes block offset, n integrated elastic modes,
                       n load points P, interval k, accepted steps since the last evaluation],
     y (K,) scratch, K = 1 + n_el + 6 P,
     peak (4,) = [vm^2 (Pa^2; -1 = empty), row, t, number of steps], y_peak (K,),
     w (3,) scratch, seed (1,) int64 (row of the last new maximum),
     trace (n_trace, 1 + K), trace_n (1,) int64)   -- trace: t and y of the first n_trace steps
                                                      (tests and benchmarks; n_trace = 0 in runs)

Interval (the scene's `cage.stress_monitor_interval` = k, default 1): the monitor evaluates the
stress at every k-th accepted step only (the count runs on across samples; a sample interval in
which no step was evaluated gets its value at the sample's own state, flexbearing.coupling.flexible_cage). k = 1
is the exact peak-hold above; k > 1 trades the monitor's cost (about 1/k of it) for peaks that can
fall between two evaluated steps (benchmarks/bench_work_precision.py measures the error).

numpy + numba only; imports no FE package.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from flexbearing.common.validation import InputError, require_range
from flexbearing.fem_cage.von_mises import empty_tracking_arrays, tracking_max_sq
from flexbearing.multibody.dynamics import cage_body_angular_velocity, cage_rotation
from flexbearing.multibody.state_layout import CAGE_PHI, CAGE_TILT_Y, CAGE_TILT_Z

# the monitor tuple's slots (module docstring; compile-time constants inside the compiled kernels)
(MON_ON, MON_SEARCH, MON_IDX, MON_Y, MON_PEAK, MON_Y_PEAK, MON_W, MON_SEED, MON_TRACE,
 MON_TRACE_N) = range(10)
PEAK_VM_SQ, PEAK_ROW, PEAK_T, PEAK_N = 0, 1, 2, 3
EMPTY_PEAK = (-1.0, -1.0, np.nan, 0.0)   # no step since the last reset (vm^2 < 0)
# the monitor's integer slots (`new_monitor`): the cage's and the modes' offsets in the state, the
# elastic modes and load points of the load space, the evaluation interval, the steps since the last evaluation
IDX_CAGE, IDX_MODES, IDX_N_MODES, IDX_N_LOAD_POINTS, IDX_INTERVAL, IDX_COUNT = 0, 1, 2, 3, 4, 5
MAX_INTERVAL = 10_000        # accepted steps (the paper's 0.6 s runs take ~80,000 steps)


@njit(cache=True)
def stress_peak_step(t, y, cage, mon):
    """Evaluate the max von Mises stress at the accepted state (t, y) and keep it if it is the
    largest since the last reset (module docstring). No-op when mon[0][0] == 0."""
    on, search, idx, yv, peak, y_peak, w, seed, trace, trace_n = mon
    if on[0] == 0:
        return
    if idx[IDX_INTERVAL] > 1:
        idx[IDX_COUNT] += 1
        if idx[IDX_COUNT] < idx[IDX_INTERVAL]:
            return
        idx[IDX_COUNT] = 0
    c0 = idx[IDX_CAGE]
    m0 = idx[IDX_MODES]
    n_el = idx[IDX_N_MODES]
    R = cage.A
    cage_rotation(y[c0 + CAGE_PHI], y[c0 + CAGE_TILT_Y], y[c0 + CAGE_TILT_Z], R)
    cage_body_angular_velocity(R, y, c0, w)
    yv[0] = w[0] * w[0]
    for k in range(n_el):
        yv[1 + k] = y[m0 + k]
    node_load = cage.node_load
    o = 1 + n_el
    for j in range(idx[IDX_N_LOAD_POINTS]):
        for i in range(6):
            yv[o + 6 * j + i] = node_load[j, i]
    i = trace_n[0]
    if i < trace.shape[0]:
        trace[i, 0] = t
        for k in range(yv.shape[0]):
            trace[i, 1 + k] = yv[k]
        trace_n[0] = i + 1
    v, row = tracking_max_sq(search, yv, peak[PEAK_VM_SQ], seed)
    peak[PEAK_N] += 1.0
    if row >= 0:
        peak[PEAK_VM_SQ] = v
        peak[PEAK_ROW] = row
        peak[PEAK_T] = t
        seed[0] = row
        for k in range(yv.shape[0]):
            y_peak[k] = yv[k]


def new_monitor(search_arrays: tuple, n_load_points: int, cage_offset: int, modes_offset: int,
                n_integrated: int, trace: int = 0, interval: int = 1) -> tuple:
    """The monitor tuple for the arrays of a flexbearing.fem_cage.von_mises_search.TrackingMaxVonMises built on the
    load-space stress (Omega^2, n_integrated elastic modes, 6 components of n_load_points load
    points: the pockets, then the guide land); trace: how many steps to record (0 in runs);
    interval: evaluate every interval-th accepted step (1 = every step; module doc)."""
    require_range("cage.stress_monitor_interval", interval, 1, MAX_INTERVAL)
    if int(interval) != interval:
        raise InputError(f"cage.stress_monitor_interval = {interval!r} must be an integer in "
                         f"[1, {MAX_INTERVAL}] (accepted steps)")
    K = 1 + int(n_integrated) + 6 * int(n_load_points)
    if search_arrays[0].shape[1] != K:
        raise ValueError(f"stress monitor: the search has {search_arrays[0].shape[1]} load-space "
                         f"coordinates, the state gives {K}")
    idx = np.zeros(IDX_COUNT + 1, dtype=np.int64)
    idx[[IDX_CAGE, IDX_MODES, IDX_N_MODES, IDX_N_LOAD_POINTS, IDX_INTERVAL]] = (cage_offset, modes_offset, n_integrated,
                                                                         n_load_points, int(interval))
    return (np.ones(1, dtype=np.int64), search_arrays, idx, np.zeros(K),
            np.array(EMPTY_PEAK), np.zeros(K), np.zeros(3),
            -np.ones(1, dtype=np.int64), np.zeros((int(trace), K + 1)), np.zeros(1, dtype=np.int64))


def disabled_monitor() -> tuple:
    """A monitor with the same numba types that does nothing (rigid cage, no stress recorded)."""
    f1 = np.zeros(1)
    return (np.zeros(1, dtype=np.int64), empty_tracking_arrays(), np.zeros(IDX_COUNT + 1, dtype=np.int64), f1,
            np.array(EMPTY_PEAK), f1, np.zeros(3), -np.ones(1, dtype=np.int64),
            np.zeros((0, 2)), np.zeros(1, dtype=np.int64))


def reset(mon) -> None:
    """Empty the peak (start of a sample interval)."""
    mon[MON_PEAK][:] = EMPTY_PEAK


@njit(cache=True, nogil=True)
def take_peak(peak, y_peak, peak_out, y_peak_out):
    """Copy the peak since the previous sample (peak (4,), its y (K,)) out and empty it: the next
    sample's peak starts here (the compiled loop of flexbearing.multibody.integrator, at a sample inside a
    step; `reset` is the same emptying from Python)."""
    for i in range(peak_out.shape[0]):
        peak_out[i] = peak[i]
    for i in range(y_peak_out.shape[0]):
        y_peak_out[i] = y_peak[i]
    for i in range(peak.shape[0]):
        peak[i] = EMPTY_PEAK[i]


class StressPeak(NamedTuple):
    """The largest von Mises stress over the steps of a sample interval (`peak`)."""
    von_mises: float            # Pa
    row: int                    # the search's row (StressRecovery.vertex turns it into the mesh vertex)
    time: float                 # s, the step where it occurred
    steps: int                  # accepted steps evaluated in the interval
    load_space: np.ndarray      # (K,) y of that step (StressRecovery.full_coordinates_of)


def peak(mon) -> StressPeak | None:
    """The StressPeak since the last reset, or None if no step was evaluated since."""
    return peak_of(mon[MON_PEAK], mon[MON_Y_PEAK])


def peak_of(p, y_peak) -> StressPeak | None:
    """`peak` of a peak array (4,) and its y (K,) (the monitor's, or the copies the integrator
    takes at a sample inside a step, flexbearing.multibody.integrator.advance_sampled)."""
    if p[PEAK_VM_SQ] < 0.0:
        return None
    return StressPeak(float(np.sqrt(p[PEAK_VM_SQ])), int(p[PEAK_ROW]), float(p[PEAK_T]), int(p[PEAK_N]),
                      y_peak.copy())


def trace(mon) -> tuple[np.ndarray, np.ndarray]:
    """(t (n,), y (n, K)) of the steps recorded since the monitor was made (new_monitor trace=)."""
    n = int(mon[MON_TRACE_N][0])
    return mon[MON_TRACE][:n, 0].copy(), mon[MON_TRACE][:n, 1:].copy()
