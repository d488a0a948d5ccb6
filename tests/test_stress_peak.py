"""The per-step cage stress monitor (multibody.stress_peak) against an independent numpy evaluation.

Reference for one state: the full modal coordinates from fem_cage.reduced_cage.static_correction
(residual modes q_k = (Phi_b,k^T F + Omega^2 Q_k)/omega_k^2) and the von Mises stress of every node
from the stress modes by the textbook formula (von Mises 1913), maximum by brute force. The
monitor must return that maximum to round-off (the bounded search is exact by construction:
relative 1e-12 allows for the different summation order of the two sums) at the same node, and
hold the largest value over several accepted states with the time it occurred.
"""
import numpy as np
import pytest

from fem_cage.reduced_cage import static_correction
from fem_cage.von_mises import MaxVonMises
from multibody import stress_peak as sp

Z, NV, M, N_KEEP = 5, 400, 24, 12


def _von_mises(sig):
    sxx, syy, szz, syz, sxz, sxy = sig.T
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3.0 * (syz ** 2 + sxz ** 2 + sxy ** 2))


@pytest.fixture()
def setup():
    rng = np.random.default_rng(7)
    S = rng.normal(size=(NV, 6, M)) * 1e8
    S[:, :, :6] = 0.0                                     # rigid modes: no stress
    omega = np.r_[np.zeros(6), np.sort(rng.uniform(3e3, 3e5, M - 6))]
    phi_b = rng.normal(size=(Z, 6, M)) * 10.0
    q_cf = rng.normal(size=M) * 1e-3
    scale = np.r_[np.zeros(6), 1.0 / omega[6:]]
    ev = MaxVonMises(S, mode_scale=scale)
    # the state: cage block at 0 (12), modes at 12 (2·(N_KEEP-6))
    n_el = N_KEEP - 6
    mon = sp.new_monitor(ev, phi_b, omega, q_cf, N_KEEP, 0, 12, n_el)
    cage = tuple([np.zeros(1)] * 17 + [np.eye(3), np.zeros((8, 3)), np.zeros((Z, 6)),
                                           np.zeros((3, N_KEEP - 6))])
    return S, omega, phi_b, q_cf, mon, cage, rng, n_el


def _reference(S, omega, phi_b, q_cf, y, node_load, spin, n_el):
    q = np.zeros(M)
    q[6:N_KEEP] = y[12:12 + n_el]
    q[N_KEEP:] = static_correction(phi_b, omega, node_load, N_KEEP,
                                   modal_load=spin ** 2 * q_cf)
    vm = _von_mises(np.einsum("nsm,m->ns", S, q))
    return vm.max(), int(vm.argmax()), q


def _state(rng, n_el, spin):
    y = np.zeros(12 + 2 * n_el)
    y[3] = rng.uniform(0, 2 * np.pi)          # spin angle; tilts zero: body spin = phi'
    y[9] = spin
    y[12:12 + n_el] = rng.normal(size=n_el) * 1e-6
    return y


def test_monitor_equals_brute_force_and_holds_the_peak(setup):
    S, omega, phi_b, q_cf, mon, cage, rng, n_el = setup
    values = []
    for i, t in enumerate((1e-4, 2e-4, 3e-4, 4e-4)):
        y = _state(rng, n_el, 1500.0 + 100 * i)
        cage[19][:] = rng.normal(size=(Z, 6)) * 100.0
        ref, node, q = _reference(S, omega, phi_b, q_cf, y, cage[19], y[9], n_el)
        sp.reset(mon)
        sp.stress_peak_step(t, y, cage, mon)
        vm, row, t_pk, n_eval, q_pk = sp.peak(mon)
        assert vm == pytest.approx(ref, rel=1e-12)
        assert int(mon[1].shape[0]) == NV and ev_node(mon, row, S) == node
        assert t_pk == t and n_eval == 1
        np.testing.assert_allclose(q_pk, q, rtol=1e-12, atol=1e-18)
        values.append((ref, t, y.copy(), cage[19].copy()))
    # peak-hold over the four states
    sp.reset(mon)
    assert sp.peak(mon) is None
    for ref, t, y, nl in values:
        cage[19][:] = nl
        sp.stress_peak_step(t, y, cage, mon)
    vm, row, t_pk, n_eval, _ = sp.peak(mon)
    best = max(values, key=lambda v: v[0])
    assert vm == pytest.approx(best[0], rel=1e-12) and t_pk == best[1] and n_eval == 4


def ev_node(mon, row, S):
    """Node of an evaluator row: the evaluator reorders nodes; match its A row to S."""
    A_row = mon[1][row]                     # (m, 6) = (L S_n)^T
    from fem_cage.von_mises import L_VM
    cand = np.einsum("rs,nsm->nmr", L_VM, S)
    return int(np.argmin(np.abs(cand - A_row[None]).reshape(len(S), -1).max(axis=1)))


def test_disabled_monitor_does_nothing():
    mon = sp.disabled_monitor()
    cage = tuple([np.zeros(1)] * 17 + [np.eye(3), np.zeros((8, 3)), np.zeros((1, 6)),
                                           np.zeros((3, 0))])
    sp.stress_peak_step(0.1, np.zeros(12), cage, mon)
    assert sp.peak(mon) is None
