"""The exact max-von-Mises evaluator (fem_cage.von_mises) against brute force and the textbook
formula. Synthetic stress modes with hot spots stand in for a cage (the real cage is checked by
`flexbearing reduce --json`, benchmarks/bench_von_mises.py)."""
import numpy as np
import pytest

from fem_cage.stress_modes import von_mises
from fem_cage.von_mises import MaxVonMises, MaxVonMisesSorted, L_VM


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
    assert np.allclose(np.linalg.norm(s @ L_VM.T, axis=1), von_mises(s), rtol=1e-14)


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
        assert fast[0] == pytest.approx(ref.max(), rel=1e-12)
        assert ref[fast[1]] == pytest.approx(ref.max(), rel=1e-12)


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
