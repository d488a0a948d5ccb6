"""The per-step cage stress monitor (flexbearing.multibody.stress_peak) against an independent numpy evaluation.

Reference for one state: the full modal coordinates from flexbearing.fem_cage.reduced_cage.static_correction
(residual modes q_k = (Phi_b,k^T F + Omega^2 Q_k)/omega_k^2) and the von Mises stress of every node
from the stress modes by the textbook formula (von Mises 1913), maximum by brute force. The
monitor must return that maximum to round-off (relative 1e-12: the monitor sums in load space,
the reference over the modes) at the same node, and hold the largest value over several accepted
states with the time it occurred. Over a real run (slow): the recorded maximum of every sample
interval equals, bitwise, the brute-force maximum (same node kernel, every node) over every
accepted step of that interval, at the same step and vertex.
"""
import numpy as np
import pytest
from tolerances import assert_within, von_mises_bound

from flexbearing.fem_cage.reduced_cage import static_correction
from flexbearing.fem_cage.von_mises import L_VM, brute_force_max_sq
from flexbearing.fem_cage.von_mises_search import TrackingMaxVonMises, load_space_blocks, load_space_stress
from flexbearing.multibody import stress_peak as sp

P, NV, M, N_KEEP = 6, 400, 24, 12          # P load points: 5 pockets + the land row


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
    phi_b = rng.normal(size=(P, 6, M)) * 10.0
    q_cf = rng.normal(size=M) * 1e-3
    n_el = N_KEEP - 6
    tracked, loads = load_space_blocks(n_el, P)
    ev = TrackingMaxVonMises(load_space_stress(S, omega, phi_b, q_cf, N_KEEP), 1 + n_el, tracked,
                             loads, coords=rng.normal(size=(NV, 3)))
    # the state: cage block at 0 (12), modes at 12 (2·(N_KEEP-6)); trace the first 10 steps
    mon = sp.new_monitor(ev.arrays, P, 0, 12, n_el, trace=10)
    cage = _cage_arrays(P, N_KEEP - 6)
    return S, omega, phi_b, q_cf, mon, cage, rng, n_el, ev


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
    S, omega, phi_b, q_cf, mon, cage, rng, n_el, ev = setup
    values = []
    for i, t in enumerate((1e-4, 2e-4, 3e-4, 4e-4)):
        y = _state(rng, n_el, 1500.0 + 100 * i)
        cage.node_load[:] = rng.normal(size=(P, 6)) * 100.0
        ref, node, q = _reference(S, omega, phi_b, q_cf, y, cage.node_load, y[9], n_el)
        sp.reset(mon)
        sp.stress_peak_step(t, y, cage, mon)
        pk = sp.peak(mon)
        assert pk.von_mises == pytest.approx(ref, rel=1e-12)
        assert int(ev.node_ids[pk.row]) == node
        assert pk.time == t and pk.steps == 1
        # the kept load-space vector: (Omega^2, q_kept, node loads)
        np.testing.assert_array_equal(pk.load_space, np.r_[y[9] ** 2, y[12:12 + n_el], cage.node_load.ravel()])
        values.append((ref, t, y.copy(), cage.node_load.copy()))
    # peak-hold over the four states
    sp.reset(mon)
    assert sp.peak(mon) is None
    for ref, t, y, nl in values:
        cage.node_load[:] = nl
        sp.stress_peak_step(t, y, cage, mon)
    pk = sp.peak(mon)
    best = max(values, key=lambda v: v[0])
    assert pk.von_mises == pytest.approx(best[0], rel=1e-12) and pk.time == best[1] and pk.steps == 4
    t_tr, y_tr = sp.trace(mon)
    assert len(t_tr) == 8 and t_tr[-1] == values[-1][1]


def _cage_arrays(n_nodes, n_modes):
    """The monitor reads only the rotation A, the scratch rows and node_load of the cage arrays."""
    from flexbearing.multibody.floating_frame import CageArrays
    fields = dict.fromkeys(CageArrays._fields, np.zeros(1))
    fields.update(A=np.eye(3), scratch=np.zeros((8, 3)), node_load=np.zeros((n_nodes, 6)),
                  land_modes=np.zeros((3, n_modes)))
    return CageArrays(**fields)


def test_disabled_monitor_does_nothing():
    mon = sp.disabled_monitor()
    cage = _cage_arrays(1, 0)
    sp.stress_peak_step(0.1, np.zeros(12), cage, mon)
    assert sp.peak(mon) is None


def test_monitor_interval_evaluates_every_kth_step(setup):
    """cage.stress_monitor_interval = k: of 8 accepted steps only the 3rd and the 6th are evaluated
    (the count runs on across resets), the peak is the brute-force maximum of those two states (the
    same reference as above, 1e-12) and the steps in between leave the peak untouched."""
    S, omega, phi_b, q_cf, _, cage, rng, n_el, ev = setup
    mon = sp.new_monitor(ev.arrays, P, 0, 12, n_el, trace=10, interval=3)
    refs = {}
    for i in range(8):
        y = _state(rng, n_el, 1000.0 + 50 * i)
        cage.node_load[:] = rng.normal(size=(P, 6)) * 100.0
        refs[i + 1] = _reference(S, omega, phi_b, q_cf, y, cage.node_load, y[9], n_el)[0]
        if i == 4:
            sp.reset(mon)               # a sample boundary between the evaluated steps 3 and 6
        sp.stress_peak_step(1e-4 * (i + 1), y, cage, mon)
    t_tr, _ = sp.trace(mon)
    np.testing.assert_allclose(t_tr, [3e-4, 6e-4], rtol=0, atol=1e-15)
    pk = sp.peak(mon)
    assert pk.steps == 1 and pk.time == pytest.approx(6e-4, abs=1e-15)
    assert pk.von_mises == pytest.approx(refs[6], rel=1e-12)


@pytest.mark.parametrize("bad", [0, -2, 10_001, 2.5])
def test_monitor_interval_refused_outside_its_range(setup, bad):
    *_, ev = setup
    with pytest.raises(Exception, match="stress_monitor_interval"):
        sp.new_monitor(ev.arrays, P, 0, 12, N_KEEP - 6, interval=bad)


def test_monitor_refuses_a_mismatched_search(setup):
    *_, ev = setup
    with pytest.raises(ValueError):
        sp.new_monitor(ev.arrays, P + 1, 0, 12, N_KEEP - 6)


@pytest.mark.slow
def test_recorded_maximum_is_the_exhaustive_maximum_over_a_real_run(paper_reduced_cage, tmp_path):
    """The paper's steady scene (flexible cage, 14,000 rpm, 55 kN / 4 kN) cut to 3 ms with a 1 ms,
    50 kN impact, run by flexbearing.simulation.run (30 samples of 0.1 ms), every accepted step traced by the
    monitor: for
    each sample interval the recorded maximum, its time and vertex and the step count equal those
    of brute force (flexbearing.fem_cage.von_mises.brute_force_max_sq, every node, the same node kernel) over
    the traced steps of that interval, bitwise; the peak's full modal coordinates give the same
    maximum by the textbook formula over every vertex (1e-12: summation order)."""
    import h5py
    from flexbearing.coupling import flexible_cage as fc
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    from pathlib import Path
    # the paper's steady scene cut to 3 ms, with a 1 ms, 50 kN impact in the middle
    path = Path(__file__).resolve().parents[1] / "scenes" / "paper_steady.toml"
    scene = loads_scene(path.read_text().replace("duration = 0.6", "duration = 0.003")
                        + "\n[[operation.load.impacts]]\nt_center = 0.0015\nduration = 0.001\n"
                        "magnitude = 50e3\n", str(path))
    made = []
    monitor = fc.StressRecovery.monitor

    def traced(self, cage_offset, modes_offset, trace=0, interval=1):
        mon = monitor(self, cage_offset, modes_offset, trace=100_000, interval=interval)
        made.append((self, mon))
        return mon

    fc.StressRecovery.monitor = traced
    try:
        run_scene(scene, tmp_path / "run.h5", quiet=True)
    finally:
        fc.StressRecovery.monitor = monitor
    (rec, mon), = made
    t, Y = sp.trace(mon)
    with h5py.File(tmp_path / "run.h5", "r") as f:
        o = {k: f["outputs"][k][()] for k in ("time", "von_mises_max", "von_mises_max_time",
                                             "von_mises_max_vertex", "von_mises_steps",
                                             "cage_modal_coordinates_full")}
    assert len(o["time"]) == 31 and len(t) == o["von_mises_steps"][1:].sum()
    S = paper_reduced_cage.stress_modes
    for k in range(1, len(o["time"])):
        steps = np.where((t > o["time"][k - 1]) & (t <= o["time"][k]))[0]
        vals = [brute_force_max_sq(rec.search.A, Y[i]) for i in steps]
        j = int(np.argmax([v for v, _ in vals]))
        assert o["von_mises_steps"][k] == len(steps)
        assert o["von_mises_max"][k] == np.sqrt(vals[j][0])
        assert o["von_mises_max_time"][k] == t[steps[j]]
        assert o["von_mises_max_vertex"][k] == rec.vertex(vals[j][1])
        sig = np.einsum("nsm,m->ns", S, o["cage_modal_coordinates_full"][k])
        vm = np.sqrt((np.einsum("rs,ns->nr", L_VM, sig) ** 2).sum(axis=1))
        # S q then L s against the search's (L S) q: von_mises_bound (tests/tolerances.py)
        assert_within(abs(vm.max() - o["von_mises_max"][k]),
                      von_mises_bound(S, o["cage_modal_coordinates_full"][k], vm.max()).max(),
                      "max von Mises of the recorded q", effect=vm.max())


def test_stress_recovery_load_space_round_trip():
    """flexbearing.coupling.flexible_cage.StressRecovery on a synthetic reduced cage: the load-space vector
    y = (Omega^2, q_kept, node loads) the monitor builds maps back to the same full modal
    coordinates as the direct formula (full_coordinates_of vs full_coordinates, exact up to the
    square root of Omega^2: 1e-15), and the search's maximum on y equals the textbook evaluation
    of S q_full over every vertex (__call__, numpy) at the same vertex (1e-12: summation order)."""
    from types import SimpleNamespace
    from flexbearing.coupling.flexible_cage import StressRecovery
    rng = np.random.default_rng(11)
    Z, m, n = 4, 30, 500
    S = rng.normal(size=(n, 6, m)) * 1e8
    S[:, :, :6] = 0.0
    omega = np.r_[np.zeros(6), np.sort(rng.uniform(3e3, 3e5, m - 6))]
    Sx = np.zeros((3, 3, m))
    Sx[1, 1], Sx[2, 2] = rng.normal(size=m) * 1e-3, rng.normal(size=m) * 1e-3
    rc = SimpleNamespace(stress_modes=S, omega=omega, n_modes=m, invariants={"Sx": Sx},
                         interface_modes=rng.normal(size=(Z, 6, m)),
                         guide_modal_loads=rng.normal(size=(m, 3)), vertices=rng.normal(size=(n, 3)))
    rec = StressRecovery(rc, 14)
    q_kept, spin = rng.normal(size=8) * 1e-6, 700.0
    node_load = rng.normal(size=(Z + 1, 6)) * 50.0
    node_load[Z, 3:] = 0.0                        # the land row carries force y, z and torque x
    qf = rec.full_coordinates(q_kept, node_load, spin)
    y = rec.load_vector(q_kept, node_load, spin)
    np.testing.assert_allclose(rec.full_coordinates_of(y), qf, rtol=1e-15, atol=0)
    vm, vertex = rec(qf)
    v2, row = rec.search.row(y)
    assert np.sqrt(v2) == pytest.approx(vm, rel=1e-12) and rec.vertex(row) == vertex
