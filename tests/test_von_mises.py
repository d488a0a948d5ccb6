"""The exact max-von-Mises searches (flexbearing.fem_cage.von_mises) against brute force and the textbook
formula. Synthetic stress modes with hot spots stand in for a cage (the real cage: the stateless
search by `flexbearing reduce --json`; the run's tracking search over a real run by
tests/test_stress_peak.py (slow) and benchmarks/bench_von_mises.py)."""
import numpy as np
import pytest
from tolerances import assert_within, dot_bound, norm_bound

from flexbearing.fem_cage.stress_modes import von_mises
from flexbearing.fem_cage.von_mises import L_VM
from flexbearing.fem_cage.von_mises_search import MaxVonMises, MaxVonMisesSorted


def _modes(n=3000, m=20, seed=0):
    rng = np.random.default_rng(seed)
    # a few hot spots on a smooth background: the structure of a real cage's stress modes
    S = rng.standard_normal((n, 6, m)) * np.exp(-4.0 * rng.random(n))[:, None, None]
    S[rng.integers(0, n, 10)] *= 8.0
    return S


def test_textbook_states():
    """Uniaxial sigma -> vm = |sigma|; pure shear tau -> sqrt(3)|tau|; hydrostatic -> 0."""
    assert von_mises(np.array([2.0, 0, 0, 0, 0, 0])) == pytest.approx(2.0, rel=1e-15)
    assert von_mises(np.array([0, 0, 0, 0, 0, 3.0])) == pytest.approx(3.0 * np.sqrt(3), rel=1e-15)
    assert von_mises(np.array([5.0, 5.0, 5.0, 0, 0, 0])) == pytest.approx(0.0, abs=1e-14)
    # |L sigma| is the same quadratic form (the evaluator's factorisation)
    s = np.random.default_rng(3).standard_normal((50, 6))
    # the two forms round differently where sxx ~ syy (cancellation): within 2 gamma_10 of
    # || |L| |s| || (tests/tolerances.py), not a fraction of vm
    vm = von_mises(s)
    assert_within(np.abs(np.linalg.norm(s @ L_VM.T, axis=1) - vm),
                  dot_bound(10, np.linalg.norm(np.abs(s) @ np.abs(L_VM).T, axis=1)), "two forms",
                  effect=vm.min())


def _assert_same_maximum(fast, ref, S, q):
    """The search's (max, node) against the textbook von Mises of S q at every node (another
    summation order: S q then L s, against (L S) q): per node within norm_bound of the m + 6
    products of |L| |S| |q| (+1 for the rounded entries of L); the maxima within the largest of
    these, the value at the node found within twice it of the maximum."""
    w = np.einsum("nsm,m->ns", np.abs(S), np.abs(q)) @ np.abs(L_VM).T
    b = norm_bound(S.shape[2] + 7, w, ref).max()
    assert_within(abs(fast[0] - ref.max()), b, "max von Mises", effect=ref.max())
    assert_within(ref.max() - ref[fast[1]], 2 * b, "node of the maximum", effect=ref.max())


@pytest.mark.parametrize("cls", [MaxVonMises, MaxVonMisesSorted])
@pytest.mark.parametrize("scaled", [False, True])
def test_exact_vs_brute_force_1000_random(scaled, cls):
    """Same maximum, bitwise, on 1000 random modal vectors (the node may differ only on an exact
    tie, so it is checked by its value); the value equals the textbook von Mises of S q to
    rounding (1e-12 relative: different summation order)."""
    S = _modes()
    ev = cls(S)
    rng = np.random.default_rng(1)
    scale = 1.0 / np.arange(1, S.shape[2] + 1) ** 2 if scaled else 1.0
    for q in rng.standard_normal((1000, S.shape[2])) * scale:
        fast, brute = ev(q), ev.brute_force(q)
        assert fast[0] == brute[0]
        ref = von_mises(np.einsum("nsm,m->ns", S, q))
        _assert_same_maximum(fast, ref, S, q)


@pytest.mark.parametrize("cls", [MaxVonMises, MaxVonMisesSorted])
def test_pruning_visits_few_nodes_and_zero_vector(cls):
    S = _modes()
    ev = cls(S, node_ids=np.arange(S.shape[0]) + 100)
    q = np.zeros(S.shape[2])
    q[0] = 1.0
    _, exact = ev.visits(q)
    assert exact < S.shape[0] // 4          # the bounds prune most nodes
    v, node = ev(np.zeros(S.shape[2]))
    assert v == 0.0 and node >= 100         # caller's node ids are returned


def test_bad_shape():
    for cls in (MaxVonMises, MaxVonMisesSorted):
        with pytest.raises(ValueError):
            cls(np.zeros((10, 3, 4)))


# ------------------------------------------------------------------ the run's tracking search
from flexbearing.fem_cage.reduced_cage import static_correction                     # noqa: E402
from flexbearing.fem_cage.von_mises import brute_force_max_sq  # noqa: E402
from flexbearing.fem_cage.von_mises_search import (TrackingMaxVonMises, load_space_blocks,  # noqa: E402
                                                   load_space_stress)

N_KEEP, P = 12, 5


def _cage_like(n=3000, m=40, seed=2):
    """A synthetic reduced cage: stress modes with hot spots (rigid columns zero), frequencies,
    the modal loads of P load points and a centrifugal modal load; node positions on a ring."""
    rng = np.random.default_rng(seed)
    S = _modes(n, m, seed)
    S[:, :, :6] = 0.0
    omega = np.r_[np.zeros(6), np.sort(rng.uniform(3e3, 3e5, m - 6))]
    phi_b = rng.normal(size=(P, 6, m))
    q_cf = rng.normal(size=m) * 1e-3
    th = rng.uniform(0, 2 * np.pi, n)
    coords = np.c_[rng.uniform(-0.01, 0.01, n), 0.085 * np.cos(th), 0.085 * np.sin(th)]
    return S, omega, phi_b, q_cf, coords


def _search(S, omega, phi_b, q_cf, coords, **kw):
    W = load_space_stress(S, omega, phi_b, q_cf, N_KEEP)
    tracked, loads = load_space_blocks(N_KEEP - 6, P)
    return W, TrackingMaxVonMises(W, N_KEEP - 5, tracked, loads, coords=coords, **kw)


def _load_vector(rng, n_el, scale_q=1e-6, scale_f=10.0):
    return np.r_[rng.uniform(1e5, 4e5), rng.normal(size=n_el) * scale_q,
                 rng.normal(size=6 * P) * scale_f]


def test_load_space_stress_is_the_residual_static_correction():
    """W y equals S q_full with q_full = (0, q_kept, flexbearing.fem_cage.reduced_cage.static_correction(F,
    Omega^2 Q_cf)) (an independent numpy path): 1e-12 of the largest stress (summation order)."""
    S, omega, phi_b, q_cf, _ = _cage_like()
    W = load_space_stress(S, omega, phi_b, q_cf, N_KEEP)
    assert W.shape == (S.shape[0], 6, 1 + (N_KEEP - 6) + 6 * P)
    rng = np.random.default_rng(4)
    for _ in range(5):
        y = _load_vector(rng, N_KEEP - 6)
        q = np.zeros(S.shape[2])
        q[6:N_KEEP] = y[1:N_KEEP - 5]
        q[N_KEEP:] = static_correction(phi_b, omega, y[N_KEEP - 5:].reshape(P, 6), N_KEEP,
                                       modal_load=y[0] * q_cf)
        ref = np.einsum("nsm,m->ns", S, q)
        # both are sums of the products S_nsm T_mk y_k (T: y -> q, the quotients by omega^2), in
        # two orders: entrywise 2 gamma_k |S| |T| |y| (product_bound), |T| |y| by the same
        # formula on absolute values; k = M + the 6P loads + the centrifugal term + the quotient
        qa = np.zeros(S.shape[2])
        qa[6:N_KEEP] = np.abs(y[1:N_KEEP - 5])
        qa[N_KEEP:] = static_correction(np.abs(phi_b), omega, np.abs(y[N_KEEP - 5:]).reshape(P, 6),
                                        N_KEEP, modal_load=abs(y[0]) * np.abs(q_cf))
        assert_within(np.abs(np.einsum("nsk,k->ns", W, y) - ref),
                      dot_bound(S.shape[2] + 6 * P + 2, np.einsum("nsm,m->ns", np.abs(S), qa)),
                      "W y = S q", effect=np.abs(ref).max())


@pytest.mark.parametrize("family", ["typical", "unit", "spin_only", "loads_only", "huge_loads"])
def test_tracking_exact_vs_brute_force_random(family):
    """Independent random load-space vectors (the worst case for a search built on time
    coherence: every call sees a new vector): the same maximum as brute force, bitwise, and the
    textbook von Mises of W y to 1e-12 (summation order); with best_in set to the true maximum
    nothing beats it, just below it the maximum is found again."""
    S, omega, phi_b, q_cf, coords = _cage_like()
    W, ev = _search(S, omega, phi_b, q_cf, coords)
    rng = np.random.default_rng(5)
    n_el = N_KEEP - 6
    for _ in range(200):
        if family == "typical":
            y = _load_vector(rng, n_el)
        elif family == "unit":
            y = rng.normal(size=ev.n_coordinates)
        elif family == "spin_only":
            y = np.r_[rng.uniform(0, 5e5), np.zeros(ev.n_coordinates - 1)]
        elif family == "loads_only":
            y = np.r_[np.zeros(1 + n_el), rng.normal(size=6 * P) * 100.0]
        else:
            y = _load_vector(rng, n_el, scale_f=1e5)
        fast, brute = ev(y), ev.brute_force(y)
        assert fast[0] == brute[0]
        ref = von_mises(np.einsum("nsk,k->ns", W, y))
        _assert_same_maximum(fast, ref, W, y)
        v2 = brute_force_max_sq(ev.A, y)[0]
        assert ev.row(y, v2)[1] == -1
        assert ev.row(y, v2 * (1 - 1e-12))[0] == v2


@pytest.mark.parametrize("ring", [2, 16])
def test_tracking_exact_along_a_trajectory_with_peak_hold(ring):
    """A smooth trajectory (spin ramp, kept modes ringing at their frequencies, small loads with
    occasional collision spikes), evaluated as the run does: best_in = the peak of the current
    sample interval (10 steps), seed = the row of the last new maximum. Every interval's recorded
    maximum equals the brute-force maximum over its steps, bitwise, and a step reports a new value
    exactly when its own maximum beats the interval's peak. ring = 2 overwrites reference slots at
    almost every step (the slack path). The bounds must prune: on average fewer than 10 % of the
    nodes are evaluated exactly per step (measured 0.6 % with ring = 2, 0.1 % with 16)."""
    S, omega, phi_b, q_cf, coords = _cage_like()
    W, ev = _search(S, omega, phi_b, q_cf, coords, ring=ring)
    rng = np.random.default_rng(6)
    n_el = N_KEEP - 6
    amp, w = rng.normal(size=n_el) * 2e-6, omega[6:N_KEEP]
    base = rng.normal(size=6 * P) * 5.0
    peak, seed, exact = -1.0, -1, []
    for i in range(600):
        t = i * 2e-6
        x = base * (1 + 0.1 * np.sin(2e3 * t)) + rng.normal(size=6 * P) * 0.2
        if i % 97 == 50:
            x[6 * (i % P):6 * (i % P) + 3] += 2e3                     # a collision
        y = np.r_[(400 + 1e4 * t) ** 2, amp * np.cos(w * t), x]
        if i % 10 == 0:
            peak = -1.0
        v, row = ev.row(y, peak, seed)
        brute = brute_force_max_sq(ev.A, y)[0]
        if brute > peak:
            assert row >= 0 and v == brute
            peak, seed = v, row
        else:
            assert row == -1
        exact.append(ev.count[3])
    assert np.mean(exact[1:]) < 0.1 * S.shape[0]


def test_tracking_bad_input():
    S, omega, phi_b, q_cf, coords = _cage_like(n=200)
    W = load_space_stress(S, omega, phi_b, q_cf, N_KEEP)
    tracked, loads = load_space_blocks(N_KEEP - 6, P)
    with pytest.raises(ValueError):
        TrackingMaxVonMises(W[:, :3], N_KEEP - 5, tracked, loads)
    with pytest.raises(ValueError):
        TrackingMaxVonMises(W, N_KEEP - 4, tracked, loads)


def test_a_saved_search_reads_back_and_finds_the_same_maxima(tmp_path, monkeypatch):
    """TrackingMaxVonMises.save/load (the run's cache beside the reduced cage): the search read
    back returns the same (max, node) as the one built, bit for bit, on 50 load vectors, each
    checked against the brute-force maximum over every node; a file of another FILE_VERSION is
    not used. The file holds the tree, not W (the caller passes W again): its tables rebuilt from
    W are equal to the built ones, and the file is smaller than W alone."""
    S, omega, phi_b, q_cf, coords = _cage_like()
    W, built = _search(S, omega, phi_b, q_cf, coords)
    f = tmp_path / "search.npz"
    built.save(f)
    assert f.stat().st_size < W.nbytes
    read = TrackingMaxVonMises.load(f, W)
    assert len(read.arrays) == len(built.arrays)
    for a, b in zip(read.arrays, built.arrays):
        assert a.dtype == b.dtype and np.array_equal(a, b)
    assert TrackingMaxVonMises.load(f, W[:, :, :-1]) is None          # W of another mode count
    rng = np.random.default_rng(7)
    for _ in range(50):
        y = _load_vector(rng, N_KEEP - 6)
        a, b = built(y), read(y)
        assert a == b
        assert a[0] == pytest.approx(read.brute_force(y)[0], rel=1e-12)
    monkeypatch.setattr(TrackingMaxVonMises, "FILE_VERSION", TrackingMaxVonMises.FILE_VERSION + 1)
    assert TrackingMaxVonMises.load(f, W) is None


def test_a_search_with_its_own_state_shares_the_tables_and_stays_exact():
    """TrackingMaxVonMises.with_own_state (flexbearing.coupling.flexible_cage: the writer thread's search beside
    the compiled monitor's): the tables are the same objects (no copy of the large arrays), the
    scratch and references are not; two trajectories searched alternately, one on each, with the
    peak-hold of the run, give bitwise the brute-force maximum at every step on both, and the first
    search's references are untouched by the second's calls."""
    S, omega, phi_b, q_cf, coords = _cage_like()
    _, ev = _search(S, omega, phi_b, q_cf, coords)
    other = ev.with_own_state()
    n_tab = TrackingMaxVonMises.N_TABLES
    assert all(a is b for a, b in zip(ev.arrays[:n_tab], other.arrays[:n_tab]))
    assert not any(np.shares_memory(a, b) for a, b in zip(ev.arrays[n_tab:], other.arrays[n_tab:]))
    rng = np.random.default_rng(8)
    n_el = N_KEEP - 6
    base = [rng.normal(size=6 * P) * 5.0 for _ in range(2)]
    for i in range(200):
        for s, (search, b) in enumerate(zip((ev, other), base)):
            y = np.r_[(400 + 10.0 * i + 50 * s) ** 2, rng.normal(size=n_el) * 1e-6,
                      b * (1 + 0.1 * np.sin(0.05 * i)) + rng.normal(size=6 * P) * 0.2]
            before = [a.copy() for a in (ev if s else other).arrays[n_tab:]]
            v, row = search.row(y)
            assert row >= 0 and v == brute_force_max_sq(search.A, y)[0]
            after = (ev if s else other).arrays[n_tab:]
            assert all(np.array_equal(x, z, equal_nan=True) for x, z in zip(before, after))
