"""Mean-stress corrections: a cycle (amplitude sigma_a, mean sigma_m) -> the fully reversed
amplitude sigma_ar that gives the same life on the R = -1 S–N curve (flexbearing.analysis.sn_curves).

    goodman   sigma_ar = sigma_a / (1 - sigma_m/sigma_u)          (Goodman 1899)
    gerber    sigma_ar = sigma_a / (1 - (sigma_m/sigma_u)^2)      (Gerber 1874)
    swt       sigma_ar = sqrt(sigma_max sigma_a), sigma_max = sigma_m + sigma_a > 0, else 0
              (Smith, Watson, Topper, J. Materials 5(4):767, 1970)
    none      sigma_ar = sigma_a

(the forms of Dowling, "Mechanical Behavior of Materials", 4th ed., 2013, §9.7). Goodman and
Gerber are applied to tensile means only: a compressive mean keeps sigma_ar = sigma_a (no credit
taken, the usual conservative practice; Gerber's parabola would otherwise penalise compression).
A cycle whose mean reaches sigma_u fails at once (sigma_ar = inf).

Every correction keeps sigma_ar <= max(|sigma_max|, |sigma_min|) of the cycle when that is below
sigma_u (Goodman and Gerber: sigma_a/(1 - g(sigma_m)) grows with sigma_a at fixed peak
sigma_m + sigma_a, so its largest value is at sigma_m = 0; SWT: sqrt(sigma_max sigma_a) <=
sigma_max), which bounds the damage of a history by its largest |stress|.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from flexbearing.common.validation import InputError

CORRECTIONS = ("goodman", "gerber", "swt", "none")
DEFAULT_CORRECTION = "goodman"


def check_correction(name: str) -> str:
    if name not in CORRECTIONS:
        raise InputError(f"fatigue mean-stress correction = {name!r} is not one of {', '.join(CORRECTIONS)}")
    return name


@njit(cache=True)
def equivalent_amplitude_of(a: float, m: float, code: int, ultimate_strength: float) -> float:
    """sigma_ar of one cycle (module doc); code = CORRECTIONS.index(name). Compiled: the damage
    kernels of flexbearing.analysis.fatigue call it."""
    if code == 3:                       # none
        return a
    if code == 2:                       # swt
        smax = m + a
        return math.sqrt(smax * a) if smax > 0.0 else 0.0
    r = max(m, 0.0) / ultimate_strength
    g = r if code == 0 else r * r       # goodman, gerber
    return a / (1.0 - g) if g < 1.0 else math.inf


@njit(cache=True)
def _equivalent_amplitude_array(a, m, code, ultimate_strength, out):
    for i in range(a.shape[0]):
        out[i] = equivalent_amplitude_of(a[i], m[i], code, ultimate_strength)


def equivalent_amplitude(amplitude, mean, correction: str, ultimate_strength: float) -> np.ndarray:
    """sigma_ar (Pa) of cycles with amplitude sigma_a >= 0 and mean sigma_m (Pa) (module doc)."""
    code = CORRECTIONS.index(check_correction(correction))
    a, m = np.broadcast_arrays(np.asarray(amplitude, dtype=np.float64), np.asarray(mean, dtype=np.float64))
    out = np.empty(a.shape)
    _equivalent_amplitude_array(np.ascontiguousarray(a).reshape(-1), np.ascontiguousarray(m).reshape(-1), code,
                                float(ultimate_strength), out.reshape(-1))
    return out
