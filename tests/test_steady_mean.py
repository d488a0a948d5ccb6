"""The settled mean of the dynamics (flexbearing.multibody.steady_mean): the batch-means confidence
interval against its formula with a published Student-t value, and the verdict on synthetic series
whose mean, transient and drift are known."""
import math

import numpy as np

from flexbearing.multibody import steady_mean as SM


def test_batch_means_half_width_is_student_t_times_the_batch_means_standard_error():
    # 20 batches of 7 samples whose means alternate 0 and 1: std(ddof=1) = sqrt(20 * 0.25 / 19);
    # t_{0.975, 19} = 2.093 (Student-t table, e.g. Law 2015, Table T.1; 4 digits)
    y = np.repeat(np.tile([0.0, 1.0], 10), 7)
    expected = 2.093 * math.sqrt(5.0 / 19.0) / math.sqrt(20.0)
    assert abs(SM.batch_means_half_width(y) / expected - 1.0) < 5e-4      # the table's rounding: 0.5e-3/2.093
    # samples that do not fill the batches: the first ones are left out, the last ones kept
    assert SM.batch_means_half_width(np.concatenate([[99.0, 99.0], y])) == SM.batch_means_half_width(y)
    assert math.isnan(SM.batch_means_half_width(np.ones(5)))


def _series(n, transient, drift, seed):
    # a cage speed and slip with an exponential start-up (tau = 20 ms, 5 rad/s and 2e-4) on white noise:
    # the means after the transient are 600 rad/s and -0.02, the noise's standard deviations 0.5 rad/s and 5e-4
    rng = np.random.default_rng(seed)
    t = (np.arange(n) + 1) * 1e-4
    omega = 600.0 + transient * 5.0 * np.exp(-t / 0.02) + drift * 400.0 * t + 0.5 * rng.standard_normal(n)
    slip = -0.02 - transient * 2e-4 * np.exp(-t / 0.02) - drift * 0.1 * t + 5e-4 * rng.standard_normal(n)
    return t, omega, slip


def test_verdict_settles_after_the_transient_with_the_true_mean_inside_its_interval():
    # 0.4 s of samples: MSER-5 cuts the start-up (A/sigma_b = 5/0.22 on the cage speed's batch means of 5:
    # t* ~ tau ln 22 = 62 ms, stationarity's docstring); the mean after it lies within its interval of the true -0.02 (a 95 %
    # interval: one seed of twenty may miss; the seeds are fixed)
    misses = 0
    for seed in range(20):
        t, omega, slip = _series(4000, 1.0, 0.0, seed)
        settled, cut, reason, hw, _ = SM._verdict(t, omega, slip, 1e-4)
        assert settled, reason
        assert 0.02 < t[cut] < 0.2
        misses += abs(np.mean(slip[cut:]) + 0.02) > hw
    assert misses <= 4      # binomial(20, 0.05): P(more than 4) = 0.003


def test_verdict_does_not_settle_on_a_drift_or_an_imprecise_mean():
    t, omega, slip = _series(4000, 0.0, 1.0, 0)          # the cage speed gains 160 rad/s over 0.4 s
    settled, _, reason, _, _ = SM._verdict(t, omega, slip, 1e-4)
    assert not settled and ("drifts" in reason or "past half" in reason)     # MSER or the trend test
    t, omega, slip = _series(4000, 0.0, 0.0, 1)           # settled, but the slip asked to 1e-6
    settled, _, reason, hw, _ = SM._verdict(t, omega, slip, 1e-6)
    assert not settled and "known to" in reason and hw > 1e-6
