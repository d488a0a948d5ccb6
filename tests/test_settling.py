"""The settled test (flexbearing.analysis.settling) on synthetic series whose answer is known.

- stationary AR(1) noise: "settled", with a false-alarm rate at the stated ALPHA (binomial bound);
- an exponential approach with a time constant a third of the window: "not settled";
- the MSER-5 truncation of a transient A·exp(−t/tau) on white noise at the analytic minimum of the
  MSER statistic, t* = tau·ln(A/sigma_b) (sigma_b = sigma/sqrt(5), the batch means' deviation).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from flexbearing.analysis import settling as S
from flexbearing.common import stationarity as ST

N, DT = 2400, 1e-4                 # samples, s: 0.24 s at the paper scenes' sample interval
T = np.arange(N) * DT


def ar1(n, phi, sigma, rng):
    """Stationary AR(1) x_i = phi·x_{i−1} + e_i of marginal standard deviation sigma."""
    e = rng.normal(0.0, sigma * math.sqrt(1.0 - phi * phi), n)
    x = np.empty(n)
    x[0] = rng.normal(0.0, sigma)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + e[i]
    return x


def test_stationary_ar1_is_settled_at_the_stated_false_alarm_rate():
    """phi = 0.8 (correlation time 9 samples, a batch of 120 samples is 13 of them: the batch means
    are nearly independent). Over 300 series the share called "not settled" must lie within the
    binomial 3-sigma band of ALPHA: at most ALPHA + 3·sqrt(ALPHA(1 − ALPHA)/300) = 2.7 %."""
    rng = np.random.default_rng(20261128)
    n_runs = 300
    alarms = sum(S.window_settling(T, {"guiding_force": 500.0 + ar1(N, 0.8, 5.0, rng)}, np.ones(N, bool))["settled"]
                 is False for _ in range(n_runs))
    assert alarms / n_runs <= ST.ALPHA + 3.0 * math.sqrt(ST.ALPHA * (1 - ST.ALPHA) / n_runs)


def test_exponential_approach_over_the_window_is_not_settled():
    """x = 100 + 20·exp(−t/tau) + AR(1) noise of sigma 1, tau = a third of the window: the run is
    still approaching its level (e^-3 = 5 % of the step, 1 sigma, left at the end)."""
    rng = np.random.default_rng(7)
    tau = T[-1] / 3.0
    for _ in range(20):
        x = 100.0 + 20.0 * np.exp(-T / tau) + ar1(N, 0.5, 1.0, rng)
        v = S.window_settling(T, {"pocket_force": x}, np.ones(N, bool))
        assert v["settled"] is False and v["verdict"] == "not settled"
        assert "pocket force" in v["reason"]


def test_slip_still_climbing_is_not_settled_and_a_flat_one_is():
    """The 7014 case of issue 41 in miniature: a slip rising from 10 % towards 28 % with tau = 0.2 s
    over a 0.2 s window (18 % at the end, still rising) on 0.2-point noise; and the same noise on a
    constant slip."""
    rng = np.random.default_rng(3)
    t = np.arange(2000) * 1e-4
    climbing = 0.28 - 0.18 * np.exp(-t / 0.2) + 0.002 * rng.standard_normal(len(t))
    v = S.window_settling(t, {"slip_rate": climbing}, np.ones(len(t), bool))
    assert v["settled"] is False
    flat = 0.18 + 0.002 * rng.standard_normal(len(t))
    assert S.window_settling(t, {"slip_rate": flat}, np.ones(len(t), bool))["settled"] is True


def test_mser5_finds_the_transients_end():
    """Minimum of MSER(d) for x = A·exp(−t/tau) + white noise sigma: where the transient equals the
    batch means' deviation, t* = tau·ln(A·sqrt(5)/sigma) (settling module docstring). The
    statistic is flat near its minimum: the estimate scatters by the time the transient takes to
    change by a factor 2 (tau·ln 2) plus one batch; the median of 100 series lies within half of that."""
    rng = np.random.default_rng(11)
    A, sigma, tau = 20.0, 1.0, 0.01
    expected = tau * math.log(A * math.sqrt(ST.MSER_BATCH) / sigma)
    ends = np.array([ST.mser(100.0 + A * np.exp(-T / tau) + rng.normal(0.0, sigma, N)).truncation * DT
                     for _ in range(100)])
    tol = tau * math.log(2.0) + ST.MSER_BATCH * DT
    assert abs(np.median(ends) - expected) <= 0.5 * tol
    assert np.mean(np.abs(ends - expected) <= tol) >= 0.9


def test_step_transient_is_cut_at_the_step():
    """A level shift of 50 sigma that ends at sample 300 (a batch boundary): MSER-5 never keeps a
    batch of the shift (each would dominate the remaining scatter), and beyond the step it cuts
    what it cuts on the noise alone (MSER's minimum over a stationary tail: mostly 0, a few batches
    at times). Over 100 series: every cut >= 300, the median 300, and the 90th percentile of the
    over-cut within that of MSER-5 on the same noise without the step plus one batch."""
    rng = np.random.default_rng(5)
    cut, alone = [], []
    for _ in range(100):
        x = rng.normal(0.0, 1.0, N)
        alone.append(ST.mser(x[300:]).truncation)
        x[:300] += 50.0
        cut.append(ST.mser(x).truncation)
    cut = np.array(cut)
    assert cut.min() >= 300 and np.median(cut) == 300
    assert np.percentile(cut - 300, 90) <= np.percentile(alone, 90) + ST.MSER_BATCH


def test_a_fixed_point_with_rounding_noise_is_settled():
    """A constant cage speed with noise at 1e-12 of it and a drift of 1e-9 of it over the window:
    the t statistic is large, but the drift is below the floor (1e-4 of the mean): settled."""
    rng = np.random.default_rng(1)
    x = 700.0 * (1.0 + 1e-9 * T / T[-1] + 1e-12 * rng.standard_normal(N))
    v = S.window_settling(T, {"cage_speed": x}, np.ones(N, bool))
    assert abs(v["signals"]["cage_speed"]["t"]) > v["signals"]["cage_speed"]["t_limit"]
    assert v["settled"] is True


def test_short_window_is_undecided():
    x = np.ones(30)
    v = S.window_settling(T[:30], {"slip_rate": x}, np.ones(30, bool))
    assert v["settled"] is None and "too few" in v["reason"]


def test_trend_slope_and_error_against_the_least_squares_formula():
    """The slope of batch means of a noiseless line is the line's slope; its error is 0."""
    tr = ST.trend(T, 3.0 + 2.5 * T)
    assert tr.slope == pytest.approx(2.5, rel=1e-9) and tr.n_batches == ST.N_BATCHES
    assert tr.standard_error == pytest.approx(0.0, abs=1e-9)


# ---------------------------------------------------------------- in the report

SCENE = """
name = "slip_{name}"
[operation]
duration = 0.2
[operation.speed]
phases = [{{ kind = "uniform", duration = 0.2, rpm = 10000 }}]
[operation.load]
axial_load = 1e3
[output]
sample_interval = 1e-4
record = ["slip", "cage_speed", "guiding_force"]
"""


def _slip_run(path, climbing: bool):
    """A 0.2 s uniform-speed run whose slip climbs as in issue 41's 7014 case (10 % towards 28 %,
    tau 0.2 s) or stays at 18 %, on 0.2-point noise; cage speed and guiding force follow the slip."""
    from flexbearing.simulation.results import ResultsWriter
    from flexbearing.simulation.scene import loads_scene
    rng = np.random.default_rng(2)
    w = ResultsWriter.create(path, loads_scene(SCENE.format(name="climbing" if climbing else "flat"), "s.toml"))
    nm = 450.0
    for k in range(2001):
        t = k * 1e-4
        s = (0.28 - 0.18 * math.exp(-t / 0.2) if climbing else 0.18) + 0.002 * rng.standard_normal()
        w.add_sample(t, {"slip_rate": s, "cage_speed": nm * (1 - s), "nominal_cage_speed": nm,
                         "cage_land_force_magnitude": 40.0 + rng.standard_normal()})
    w.write_block()
    w.set_status("complete")
    w.close()
    return path


def _report_rows(path):
    from flexbearing.analysis import windows
    from flexbearing.simulation.results import Run
    with Run(path) as run:
        t, arrays, scene, dt = windows.read_run(run)
        rows = windows.phase_rows(t, arrays, scene, dt, True, 0.0)
        masks = [m for _, m in windows.report_windows(t, scene, dt, True, 0.0)]
        return S.attach_settling(rows, masks, t, S.settling_signals(run.outputs), 1)


def test_report_says_a_climbing_slip_has_not_settled(tmp_path):
    """The summary does not give the mean slip of a run whose slip still climbs as if settled: the
    settled line says NOT settled and names the slip, the slip's mean is marked, and so are the
    tables' means and p99 (not the peaks)."""
    from flexbearing.analysis import report, summary
    rows = _report_rows(_slip_run(tmp_path / "climb.h5", True))
    assert [r["settling"]["settled"] for r in rows] == [False, False]       # whole run = its one phase
    (_, start), (label, text) = summary.settled_rows(rows)
    assert "**NOT settled**" in text and "slip rate" in text
    marked = summary.mark_unsettled(summary.headline_rows(rows[0], None, None), rows[0])
    slip = [v for k, v in marked if k.startswith("Cage slip rate, mean")][0]
    assert S.MARK in slip and "not settled" in slip
    table = report._markdown_table([("whole run", rows[0])], ["slip_rate"])
    lines = {ln.split(" |")[0].lstrip("| "): ln for ln in table.splitlines()}
    assert S.MARK in lines["Cage slip rate, mean (%)"] and S.MARK in lines["Cage slip rate, p99 (%)"]
    assert S.MARK not in lines["Cage slip rate, peak (%)"]


def test_report_says_a_flat_slip_has_settled(tmp_path):
    from flexbearing.analysis import report, summary
    rows = _report_rows(_slip_run(tmp_path / "flat.h5", False))
    assert rows[1]["settling"]["settled"] is True
    (_, start), (label, text) = summary.settled_rows(rows)
    assert "**settled**" in text
    assert S.MARK not in report._markdown_table([("whole run", rows[0])], ["slip_rate"])


def test_summary_gives_the_slip_after_a_start_up_inside_the_window(tmp_path):
    """A flat 18 % slip after a start-up from 5 % (tau 5 ms) at the start of the window: settled,
    and the summary's mean slip says it includes the start-up and gives the mean after it (the
    mean of the samples after MSER-5's cut: 18 % within 3 standard errors of a mean of >= 1,000
    samples of 0.2-point noise, 0.02 points)."""
    from flexbearing.analysis import summary
    from flexbearing.simulation.results import ResultsWriter
    from flexbearing.simulation.scene import loads_scene
    rng = np.random.default_rng(8)
    w = ResultsWriter.create(tmp_path / "r.h5", loads_scene(SCENE.format(name="startup"), "s.toml"))
    for k in range(2001):
        t = k * 1e-4
        s = 0.18 - 0.13 * math.exp(-t / 0.005) + 0.002 * rng.standard_normal()
        w.add_sample(t, {"slip_rate": s, "cage_speed": 450.0 * (1 - s), "nominal_cage_speed": 450.0,
                         "cage_land_force_magnitude": 40.0 + rng.standard_normal()})
    w.write_block()
    w.set_status("complete")
    w.close()
    rows = _report_rows(tmp_path / "r.h5")
    st = rows[0]["settling"]
    assert st["settled"] is True and 0.0 < st["transient_end"] < 0.1
    slip = [v for k, v in summary.mark_unsettled(summary.headline_rows(rows[0], None, None), rows[0])
            if k.startswith("Cage slip rate, mean")][0]
    assert f"includes the start-up transient to t = {st['transient_end']:.4g} s" in slip
    assert st["signals"]["slip_rate"]["mean_after"] == pytest.approx(0.18, abs=3 * 0.002 / math.sqrt(1000))
