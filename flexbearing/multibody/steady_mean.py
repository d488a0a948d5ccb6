"""The running state as the settled mean of the dynamics, where it is no fixed point.

The held-cage equations (`flexbearing.multibody.steady.steady_held_cage_state`) look for a state
that does not change with time once the balls are frozen at their azimuths. The bearing need not
run in such a state. The paper's steady scene at its design clearance (14,000 rpm, Fa 55 kN,
Fr 4 kN, 88.4 µm) is the measured case: its frozen-azimuth branch is a closed curve below the full
radial load, while the dynamics, integrated 2 s from the scene's start, settle within 0.06 s
(MSER-5) to a stationary motion: slip −2.37 %, batch means over 0.1 s within ±0.01 points, cage
held (whirl ratio 0.004). That motion is not periodic at the ball-pass frequency f_bp = 2127 Hz:
the cage speed's spectrum holds a line at 410.5 Hz and its combination tones with f_bp (1716.6 =
f_bp − 410.5, 1306.0 = f_bp − 2·410.5, 2537.1 = f_bp + 410.5 Hz), and the cage centre wanders over
40–150 Hz: a quasi-periodic (torus) or irregular motion about a steady mean.
For such a bearing the steady result a cage engineer reads is the mean of the running state with
its uncertainty, which is what this module computes.

Method (the statistics of a simulation's steady-state output; Law, *Simulation Modeling and
Analysis*, 5th ed., 2015, §9.5): integrate the bearing's own dynamics (`flexbearing.multibody.integrator`,
weight included, constant speed and load) from a start state in chunks of CHUNK seconds, sampling
the cage speed omega_c and the slip rate s every SAMPLE seconds. After each chunk:

1. settled: both series pass the test a run's report applies (`flexbearing.common.stationarity.signal_settling`:
   MSER-5 start-up truncation, White 1997, in the first half; no drift in the batch-means trend test,
   Schmeiser 1982, over the part after it and its second half; Bonferroni over the two signals);
2. precise: the batch-means confidence interval of the slip's mean after the truncation,

       s_bar ± t_{1 − ALPHA/2, b − 1} · S_b / sqrt(b),   b = N_BATCHES batch means, S_b their standard deviation,

   is no wider than ±SLIP_HALF_WIDTH (Law 2015 §9.5.3, eq. 9.12; the batches are long against the
   motion's correlation time when the trend test sees no drift, stationarity's docstring).

The run ends settled when both hold, and unsettled after MAX_TIME seconds. The reported state is
the last sample's: a snapshot of the running state, not a fixed point.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from flexbearing.common.stationarity import N_BATCHES, signal_settling
from flexbearing.multibody import integrator as I
from flexbearing.multibody.steady_hold import HELD_WHIRL_RATIO, cage_sample, constant_run, whirl_ratio

# the chunk integrated between two verdicts, the longest run, the sampling: 0.1 ms resolves the
# cage's motion up to 5 kHz (the paper case's 410 Hz line, the ball pass at 2.1 kHz aliases without
# biasing the mean: the sampling is not commensurate with it)
CHUNK = 0.05
MAX_TIME = 1.0
SAMPLE = 1e-4
# the slip's confidence half width at 95 %: 0.01 slip points, the slip's drift floor (a change below
# it does not alter a reported digit: flexbearing.common.stationarity SIGNALS)
SLIP_HALF_WIDTH = 1e-4
CONFIDENCE = 0.95


def batch_means_half_width(x, n_batches: int = N_BATCHES, confidence: float = CONFIDENCE) -> float:
    """Half width of the confidence interval of the mean of the series x by non-overlapping batch means
    (Law 2015 §9.5.3): x cut into b = n_batches batches of m = len(x) // b samples (the first ones
    left out), their means Y_i, half width = t_{(1 + confidence)/2, b − 1} · std(Y, ddof = 1) / sqrt(b).
    nan when there are fewer samples than batches."""
    from scipy.stats import t as student_t       # scipy: only where a settled mean is computed
    x = np.asarray(x, dtype=float)
    m = len(x) // n_batches
    if m < 1:
        return math.nan
    y = x[len(x) - n_batches * m:].reshape(n_batches, m).mean(axis=1)
    return float(student_t.ppf(0.5 * (1.0 + confidence), n_batches - 1) * np.std(y, ddof=1) / math.sqrt(n_batches))


@dataclass(frozen=True)
class SettledMean:
    """The dynamics' running state over a settled window (module docstring)."""
    settled: bool
    slip_rate: float               # mean after the start-up transient (1 = 100 %)
    slip_half_width: float         # its 95 % batch-means half width
    cage_speed: float              # mean, rad/s
    cage_speed_half_width: float
    transient_end: float           # s after the start: MSER-5's truncation (the later of the two signals)
    duration: float                # s integrated
    whirl_ratio: float             # of the cage centre after the transient (steady_hold.whirl_ratio)
    eccentricity_mean: float
    eccentricity_max: float
    held: bool                     # |W| < HELD_WHIRL_RATIO and off the rim
    cpu_s: float
    reason: str                    # why it is (not) settled
    end_state: np.ndarray | None = field(default=None, repr=False, compare=False)

    def describe(self) -> str:
        cage = ("the cage held" if self.held else "the cage not held") + \
            f" (whirl ratio {self.whirl_ratio:.2f}, eccentricity ratio {self.eccentricity_mean:.2f}, max {self.eccentricity_max:.2f})"
        head = "settled" if self.settled else "not settled"
        return (f"the dynamics {head} after {1e3 * self.duration:.0f} ms (start-up transient to "
                f"{1e3 * self.transient_end:.0f} ms): mean slip {100 * self.slip_rate:.3f} ± "
                f"{100 * self.slip_half_width:.3f} %, cage {self.cage_speed:.2f} ± {self.cage_speed_half_width:.2f} rad/s, "
                f"{cage}; {self.reason}")


def settled_mean(model, speed_rad_s: float, load, y, chunk: float = CHUNK, max_time: float = MAX_TIME,
                 sample: float = SAMPLE, slip_half_width: float = SLIP_HALF_WIDTH) -> SettledMean:
    """Integrate the dynamics (model with its weight; constant inner-ring speed, rad/s, and load
    (Fx, Fy, Fz), N, on the inner ring) from the state y until the cage speed and slip have settled
    and the slip's mean is known to ±slip_half_width, or max_time has passed (module docstring)."""
    t0 = time.process_time()
    sp, ld, imp, c0, y, ws = constant_run(model, speed_rad_s, load, y)
    per_chunk = int(round(chunk / sample))
    ts, omega, slip, centre, eps = [], [], [], [], []
    t, h, k, note = 0.0, 1e-7, 0, ""
    while k * sample < max_time - 0.5 * sample:
        times = (k + np.arange(1, per_chunk + 1)) * sample
        try:
            # to half a sample past the chunk's last sample: the sample times lie strictly inside
            y, t, h, _, _, Ys, _ = I.advance_sampled(model, y, t, times[-1] + 0.5 * sample, times, sp, ld, imp,
                                                     h=h, ws=ws)
        except I.SimulationUnstable as e:
            note = f"the integration stopped at {1e3 * t:.1f} ms: {str(e).splitlines()[0]}"
            break
        for ti, yi in zip(times, Ys):
            ts.append(ti)
            cage_sample(model, ti, yi, sp, ld, imp, c0, centre, omega, eps, slip)
        k += per_chunk
        verdict = _verdict(np.array(ts), np.array(omega), np.array(slip), slip_half_width)
        if verdict.settled:
            break
    if not ts:
        return SettledMean(False, math.nan, math.nan, math.nan, math.nan, 0.0, t, math.nan, math.nan, math.nan,
                           False, time.process_time() - t0, note, y.copy())
    # the last chunk's verdict holds for every sample taken (a failed chunk adds none)
    settled, cut, reason, hw_slip, hw_omega = verdict
    if note:
        settled, reason = False, note
    tt, cc, ww = np.array(ts[cut:]), np.array(centre[cut:]), np.array(omega[cut:])
    w = whirl_ratio(tt, cc, ww) if len(tt) > 2 else math.nan
    e = np.array(eps[cut:])
    held = bool(abs(w) < HELD_WHIRL_RATIO and float(np.max(eps)) < 1.0)
    return SettledMean(bool(settled), float(np.mean(slip[cut:])), hw_slip, float(np.mean(ww)), hw_omega,
                       float(ts[cut] - sample), float(t), w, float(np.mean(e)), float(np.max(e)), held,
                       time.process_time() - t0, reason, y.copy())


class _Verdict(NamedTuple):
    """The settled test after a chunk (module docstring)."""
    settled: bool
    cut: int                       # the first sample after the start-up transient
    reason: str
    slip_half_width: float
    cage_speed_half_width: float


def _verdict(t, omega, slip, slip_half_width: float) -> _Verdict:
    """The verdict on the series so far (module docstring, items 1 and 2)."""
    tests = [signal_settling(name, t, x, n_signals=2) for name, x in (("cage_speed", omega), ("slip_rate", slip))]
    ends = [r["transient_end"] for r in tests if r["transient_end"] is not None]
    cut = int(np.searchsorted(t, max(ends))) if ends else 0
    hw_slip = batch_means_half_width(slip[cut:])
    hw_omega = batch_means_half_width(omega[cut:])
    if not all(r["settled"] for r in tests):
        return _Verdict(False, cut, "; ".join(r["reason"] for r in tests if not r["settled"]), hw_slip, hw_omega)
    if not hw_slip <= slip_half_width:
        return _Verdict(False, cut, (f"settled, but the mean slip is known to ±{100 * hw_slip:.3f} points only "
                                     f"(±{100 * slip_half_width:.3f} asked)"), hw_slip, hw_omega)
    return _Verdict(True, cut, "; ".join(r["reason"] for r in tests), hw_slip, hw_omega)
