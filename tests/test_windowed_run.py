"""flexbearing.simulation.windowed_run: the run loop of the steady validations, with a stand-in physics.

The integrator and the outputs are replaced by a state that is its own time (y = t): the sample at
t_k = k·dt then reads x = t_k, so the mean of a window (t0, t0 + W] sampled every dt is the mean of
an arithmetic sequence, t0 + (W + dt)/2, exact up to the rounding of t (1e-12 relative). The loop's
own decisions are checked exactly: where it samples, when it asks `stop`, where it stops.
"""
import numpy as np
import pytest

from flexbearing.simulation import windowed_run as WR


@pytest.fixture
def clock(monkeypatch):
    """advance: the state becomes the target time (one step per call); outputs: x = the state."""
    calls = []

    def advance(model, y, t, t_next, sp, ld, imp, tol, h, ws):
        calls.append((t, t_next))
        y[0] = t_next
        return y, t_next, h, 1, 0

    monkeypatch.setattr(WR.I, "Workspace", lambda model: None)
    monkeypatch.setattr(WR.I, "advance", advance)
    monkeypatch.setattr(WR.O, "evaluate_outputs", lambda model, t, y, sp, ld, imp: {"x": float(y[0]), "two": 2.0})
    return calls


def _run(t_max, stop, window=0.05, dt=0.01):
    return WR.run_in_windows(None, np.zeros(1), None, None, None, 1e-6, window, t_max, dt,
                             lambda out: (out["x"], out["two"]), stop)


def test_window_means_are_the_means_of_the_samples(clock):
    run = _run(0.2, lambda t, means: False)
    assert not run.stopped and run.t == pytest.approx(0.2, abs=1e-15)
    assert len(run.window_means) == 4 and run.n_steps == 20 and run.n_rejected == 0
    for k, (x, two) in enumerate(run.window_means):
        assert x == pytest.approx(0.05 * k + (0.05 + 0.01) / 2, rel=1e-12) and two == 2.0
    # each call ends on the next sample or on the window's end, never beyond
    assert all(b - a <= 0.01 + 1e-15 for a, b in clock)


def test_stop_is_asked_after_every_window_and_ends_the_run(clock):
    asked = []

    def stop(t, means):
        asked.append((round(t, 12), len(means)))
        return len(means) == 3

    run = _run(1.0, stop)
    assert run.stopped and asked == [(0.05, 1), (0.1, 2), (0.15, 3)]
    assert run.t == pytest.approx(0.15, abs=1e-15) and run.y[0] == run.t


def test_a_window_that_is_not_a_multiple_of_the_sample_interval_ends_on_its_end(clock):
    run = _run(0.05, lambda t, means: False, window=0.025, dt=0.01)
    # samples at 0.01, 0.02, 0.025 | 0.035, 0.045, 0.05
    assert [round(b, 12) for _, b in clock] == [0.01, 0.02, 0.025, 0.035, 0.045, 0.05]
    assert run.window_means[0][0] == pytest.approx((0.01 + 0.02 + 0.025) / 3, rel=1e-12)
