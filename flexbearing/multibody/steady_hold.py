"""Does the cage stay held? The dynamics integrated from a held-cage root.

`flexbearing.multibody.steady.steady_held_cage_state` solves for a frozen-azimuth state in which the
cage centre rests at one azimuth in its guide film. A root of those equations need not be the state
the bearing runs in: the held-cage equations can have several roots (an uncertainty-study run had
two, at slips of −5.1 % and +52 %, both with residual < 1e-10), and a root can be one the cage does
not stay in. The test here integrates the bearing's own dynamics (`flexbearing.multibody.integrator`,
the same model, speed and load, weight included) from the root for a few tens of milliseconds and
reads the cage centre's motion as a cage engineer does (Gupta, *Advanced Dynamics of Rolling
Elements*, Springer 1984; the same definitions as `flexbearing.analysis.cage_motion`):

    whirl ratio   W = [phi(t1) − phi(t0)] / [theta_c(t1) − theta_c(t0)],
                  phi = atan2(e_z, e_y) unwrapped (the whirl angle of the centre's offset e from its
                  guide), theta_c = ∫ omega_c dt (trapezoidal rule)

over the last two thirds of the window (the first third lets the frozen-azimuth state's lag settle:
its pocket-force harmonic lags the dynamic one by 42–56°, steady.py docstring). A held cage has
W ≈ 0 (the centre at a fixed azimuth, set by the weight and the radial load); a cage floating on its
land film whirls at W ≈ 0.5 (half-frequency whirl) and a cage driven by a force fixed on it at
W ≈ 1. The cage is read as held where |W| < HELD_WHIRL_RATIO = 0.1 (a fifth of half-frequency whirl)
and its eccentricity ratio stays below 1 (off the rim). Measured on the two roots of that run over
30 ms: W = 0.03 (+52 %, the centre stays at one azimuth, eccentricity 0.33–0.42) and W = 0.52
(−5.1 %, the centre whirls at half the cage speed, eccentricity 0.20 → 0.74).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from flexbearing.multibody import integrator as I
from flexbearing.multibody import model as M
from flexbearing.multibody import outputs as O
from flexbearing.multibody import state_layout as SL

HELD_WHIRL_RATIO = 0.1
# the window and its sampling: 30 ms (at 250–600 rad/s the cage turns 1–3 times, a half-frequency
# whirl 0.6–1.5 times); samples every 0.2 ms keep |Omega|·dt < pi for whirl rates up to 15,000 rad/s
HOLD_CHECK_DURATION = 0.03
HOLD_CHECK_SAMPLE = 2e-4


def whirl_ratio(t, centre_yz, cage_speed) -> float:
    """W (module docstring) of the samples t (s), centre_yz (m, shape (m, 2)), cage_speed (rad/s);
    nan where the cage does not turn."""
    t = np.asarray(t, dtype=float)
    c = np.asarray(centre_yz, dtype=float)
    w = np.asarray(cage_speed, dtype=float)
    phi = np.unwrap(np.arctan2(c[:, 1], c[:, 0]))
    theta = float(np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(t)))
    return float((phi[-1] - phi[0]) / theta) if theta != 0.0 else math.nan


@dataclass(frozen=True)
class CageHoldCheck:
    """The dynamics from a held-cage root (module docstring)."""
    duration: float                # s integrated
    cage_speed_start: float        # rad/s
    cage_speed_end: float
    slip_start: float              # slip rate (1 = 100 %), flexbearing.multibody.outputs
    slip_end: float
    eccentricity_start: float
    eccentricity_end: float
    eccentricity_max: float
    whirl_ratio: float             # over the last two thirds of the window
    held: bool
    cpu_s: float
    note: str = ""                 # why the integration stopped early, where it did
    end_state: np.ndarray | None = field(default=None, repr=False, compare=False)   # the state at its end

    def describe(self) -> str:
        what = "the cage stays held" if self.held else "the cage does not stay held"
        return (f"{what} in the dynamics integrated {1e3 * self.duration:.0f} ms from it (whirl ratio "
                f"{self.whirl_ratio:.2f}, |W| < {HELD_WHIRL_RATIO} is held; eccentricity ratio "
                f"{self.eccentricity_start:.2f} -> {self.eccentricity_end:.2f}, max {self.eccentricity_max:.2f}; "
                f"cage speed {self.cage_speed_start:.1f} -> {self.cage_speed_end:.1f} rad/s, slip "
                f"{100 * self.slip_start:.1f} -> {100 * self.slip_end:.1f} %){self.note}")


def constant_run(model, speed_rad_s: float, load, y) -> tuple:
    """(speed_table, load_table, impacts, cage offset in the state, a contiguous copy of y, a dopri5
    Workspace): what integrating the dynamics at a constant inner-ring speed (rad/s) and load
    (Fx, Fy, Fz; N) from y needs (flexbearing.multibody.integrator.advance)."""
    return (np.array([[0.0, float(speed_rad_s)]]), np.array([[0.0, *np.asarray(load, dtype=float)]]),
            np.zeros((0, 6)), M.state_layout(model)["cage"], np.ascontiguousarray(np.array(y, dtype=float)),
            I.Workspace(model, "dopri5"))


def cage_sample(model, t: float, y, sp, ld, imp, c0: int, centre: list, omega: list, eccentricity: list,
                slip: list) -> None:
    """Append the cage's guide offset (m, (y, z)), speed (rad/s), eccentricity ratio and the slip rate
    at state y and time t (flexbearing.multibody.outputs) to the four lists."""
    out = O.evaluate_outputs(model, t, y, sp, ld, imp)
    centre.append(np.asarray(out["cage_guide_offset"], dtype=float).copy())
    omega.append(float(y[c0 + SL.CAGE_OMEGA]))
    eccentricity.append(float(out["cage_eccentricity_ratio"]))
    slip.append(float(out["slip_rate"]))


def cage_hold_check(model, speed_rad_s: float, load, y, duration: float = HOLD_CHECK_DURATION,
                    sample: float = HOLD_CHECK_SAMPLE) -> CageHoldCheck:
    """Integrate the dynamics (model with its weight, constant speed and load = (Fx, Fy, Fz) N on the
    inner ring) from the state y for `duration` s and read whether the cage stays held (module
    docstring)."""
    t0 = time.process_time()
    sp, ld, imp, c0, y, ws = constant_run(model, speed_rad_s, load, y)
    ts, centre, omega, eps, slip = [], [], [], [], []
    t, h, note = 0.0, 1e-7, ""

    def record():
        ts.append(t)
        cage_sample(model, t, y, sp, ld, imp, c0, centre, omega, eps, slip)
    record()
    n = int(round(duration / sample))
    for k in range(1, n + 1):
        try:
            y, t, h, _, _ = I.advance(model, y, t, k * sample, sp, ld, imp, h=h, ws=ws)
        except I.SimulationUnstable as e:
            note = f"; the integration stopped at {1e3 * t:.1f} ms: {str(e).splitlines()[0]}"
            break
        record()
    k0 = len(ts) // 3
    w = whirl_ratio(ts[k0:], np.array(centre[k0:]), omega[k0:]) if len(ts) - k0 > 2 else math.nan
    held = bool(abs(w) < HELD_WHIRL_RATIO and max(eps) < 1.0 and not note)
    return CageHoldCheck(ts[-1], omega[0], omega[-1], slip[0], slip[-1], eps[0], eps[-1], float(max(eps)), w, held,
                         time.process_time() - t0, note, y.copy())
