"""Cage motion in its guide-land clearance: orbit, whirl ratio and stability index of a run.

A cage engineer reads a run's cage motion from the orbit of the cage centre and a few numbers
per time window (Gupta, Advanced Dynamics of Rolling Elements, 1984; Ghaisas, Wassgren & Sadeghi,
J. Tribol. 126 (2004) 681–689), computed here from the recorded cage centre
c(t) = (y, z), its offset from the guiding ring's centre in the plane normal to the bearing
axis x (the outer ring's for the outer land, the inner ring's for the inner land, the balls'
pitch circle's for ball guidance: flexbearing.multibody.cage_offset), and the cage speed
omega_c(t) about +x:

    eccentricity ratio   eps(t) = |c(t)| / Cg          (Cg: radial guide clearance; eps >= 1: on the rim)

    whirl ratio          W = [phi(t1) − phi(t0)] / [theta_c(t1) − theta_c(t0)],
                         phi = atan2(z, y) unwrapped (the whirl angle of the centre about +x),
                         theta_c = ∫ omega_c dt (the cage's own rotation, trapezoidal rule)

        whirl revolutions per cage revolution over the window, signed (> 0: forward whirl, in
        the cage's sense of rotation). 1 = synchronous whirl: the centre orbits once per cage
        revolution, the stable outer-ring-guided cage driven round by a rotating force fixed on
        it (pocket forces of an uneven ball set, unbalance); 0.5 = half-frequency whirl of a
        cage floating on its land film without a static load (tests/test_cage_whirl.py); near 0
        = the centre held at a fixed azimuth by a static load (weight, a radial load on the
        balls); a ratio that changes from window to window, with a large dispersion below, is
        irregular motion.

    velocity dispersion  R_v = std(|v|) / mean(|v|),   v = dc/dt over the window's samples

        the stability index of Ghaisas et al. (2004): 0 for a steady circular whirl (constant
        centre speed), small for a smooth whirl, of order 1 for the irregular, collision-driven
        motion of an unstable cage. As a stability index it assumes a steady motion: a whirl that
        decays to rest inside the window (a cage knocked off by an impact that settles again at
        one azimuth) also gives values of order 1, from a centre speed falling to zero; read it
        beside the orbit and the eccentricity history (cage_orbit.png). v is the central difference of the recorded centre,
        v_k = (c_{k+1} − c_{k−1}) / (t_{k+1} − t_{k−1}), exact in magnitude for a circular orbit
        sampled evenly, O((Omega·dt)²) otherwise (Omega: whirl rate, dt: sample interval).

    held fraction        share of the samples with |v_k| < HELD_SPEED · ½|omega_c,k| · Cg

        the time the centre is at rest at one azimuth. ½·omega_c·e is the centre speed of a
        half-frequency whirl at eccentricity e, so the threshold (HELD_SPEED = 0.1) is that whirl
        at e = 0.1·Cg: a whirling cage (e/Cg 0.5–0.8) moves 5–8 times faster, a cage held by a
        static load only vibrates (measured 0.01–0.06 of ½·omega_c·Cg in the paper's unsteady case
        at 65 kN). Cg is the clearance given, else |c|/eps at the samples off centre (median).

The whirl angle needs |Omega|·dt < pi between samples (unwrapping) and is undefined at a centred
cage: windows where the mean eccentricity ratio is below `min_eps` (default 0.02) report no whirl
ratio. All inputs and outputs are SI (m, s, rad/s) or ratios.
"""
from __future__ import annotations

import math

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.multibody.cage_offset import GUIDE_REFERENCE

MIN_EPS = 0.02        # below this mean eccentricity ratio the whirl angle is noise, not a whirl
HELD_SPEED = 0.1      # centre speed, in units of a half-frequency whirl at full clearance, below which it is held


def whirl_angle(centre_yz: np.ndarray) -> np.ndarray:
    """phi(t) = atan2(z, y) of the cage centre, unwrapped (rad, about +x). centre_yz: (n, 2)."""
    c = np.asarray(centre_yz, dtype=np.float64)
    return np.unwrap(np.arctan2(c[:, 1], c[:, 0]))


def cage_rotation_angle(t: np.ndarray, cage_speed: np.ndarray) -> np.ndarray:
    """theta_c(t) = ∫_{t0}^{t} omega_c dt (rad), trapezoidal rule on the samples."""
    t = np.asarray(t, dtype=np.float64)
    w = np.asarray(cage_speed, dtype=np.float64).ravel()
    out = np.zeros_like(t)
    if t.size > 1:
        out[1:] = np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))
    return out


def centre_speed(t: np.ndarray, centre_yz: np.ndarray) -> np.ndarray:
    """|v_k| = |c_{k+1} − c_{k−1}| / (t_{k+1} − t_{k−1}) at the interior samples k = 1 … n−2 (m/s)."""
    t = np.asarray(t, dtype=np.float64)
    c = np.asarray(centre_yz, dtype=np.float64)
    if t.size < 3:
        return np.zeros(0)
    d = c[2:] - c[:-2]
    return np.hypot(d[:, 0], d[:, 1]) / (t[2:] - t[:-2])


def _check(t, centre_yz, cage_speed, eccentricity_ratio):
    t = np.asarray(t, dtype=np.float64)
    c = np.asarray(centre_yz, dtype=np.float64)
    if c.ndim != 2 or c.shape[1] != 2 or c.shape[0] != t.size:
        raise InputError(f"centre_yz has shape {c.shape}; allowed: ({t.size}, 2), the (y, z) of each sample")
    for name, a in (("cage_speed", cage_speed), ("eccentricity_ratio", eccentricity_ratio)):
        if a is not None and np.asarray(a).size != t.size:
            raise InputError(f"{name} has {np.asarray(a).size} values; allowed: {t.size}, one per sample")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        raise InputError("t must increase strictly from sample to sample")
    return t, c


def window_motion(t, centre_yz, cage_speed, eccentricity_ratio=None, clearance=None,
                  min_eps: float = MIN_EPS) -> dict:
    """Cage-motion statistics of one window of samples (module doc).

    t (n,) s; centre_yz (n, 2) m; cage_speed (n,) rad/s; eccentricity_ratio (n,) or, if None,
    |c|/clearance (clearance in m; one of the two is needed). Returns SI values:
    eps_mean, eps_max, rim_fraction (share of samples with eps >= 1), whirl_ratio (None when
    eps_mean < min_eps or the cage did not turn), whirl_rate_mean (rad/s, net angle over time),
    centre_speed_mean (m/s), velocity_dispersion (None with fewer than 3 samples or a still centre),
    held_fraction (None with fewer than 3 samples or an unknown clearance), cage_revolutions,
    n_samples."""
    t, c = _check(t, centre_yz, cage_speed, eccentricity_ratio)
    if eccentricity_ratio is None:
        if clearance is None or not clearance > 0.0:
            raise InputError(f"clearance = {clearance!r}; allowed: > 0 m (or give eccentricity_ratio)")
        eps = np.hypot(c[:, 0], c[:, 1]) / clearance
    else:
        eps = np.asarray(eccentricity_ratio, dtype=np.float64).ravel()
    row = {"n_samples": int(t.size), "eps_mean": None, "eps_max": None, "rim_fraction": None,
           "whirl_ratio": None, "whirl_rate_mean": None, "centre_speed_mean": None,
           "velocity_dispersion": None, "held_fraction": None, "cage_revolutions": None}
    if t.size == 0:
        return row
    row.update(eps_mean=float(eps.mean()), eps_max=float(eps.max()), rim_fraction=float(np.mean(eps >= 1.0)))
    if t.size < 2:
        return row
    theta = cage_rotation_angle(t, cage_speed)
    row["cage_revolutions"] = float(theta[-1] / (2.0 * math.pi))
    if row["eps_mean"] >= min_eps:
        phi = whirl_angle(c)
        row["whirl_rate_mean"] = float((phi[-1] - phi[0]) / (t[-1] - t[0]))
        if abs(theta[-1]) > 0.0:
            row["whirl_ratio"] = float((phi[-1] - phi[0]) / theta[-1])
    v = centre_speed(t, c)
    if v.size:
        vm = float(v.mean())
        row["centre_speed_mean"] = vm
        if vm > 0.0:
            row["velocity_dispersion"] = float(v.std() / vm)
        cg = clearance
        if cg is None:
            off = eps > 1e-3
            cg = float(np.median(np.hypot(c[off, 0], c[off, 1]) / eps[off])) if off.any() else None
        if cg is not None:
            w = np.abs(np.asarray(cage_speed, dtype=np.float64).ravel()[1:-1])
            row["held_fraction"] = float(np.mean(v < HELD_SPEED * 0.5 * w * cg))
    return row


def motion_arrays(outputs, guidance: str = "outer") -> dict | None:
    """(t, centre_yz, cage_speed, eccentricity_ratio, reference) of a run's /outputs group (or
    dict), or None when the run did not record the cage orbit (scene output "cage_orbit") and the
    cage speed. centre_yz is the centre's offset from the guiding ring's centre
    (flexbearing.multibody.cage_offset: the outer ring's, the inner ring's or the balls' pitch
    circle's, by the cage's `guidance`), `reference` says which; a run recorded before that offset
    existed gives its absolute centre, which is the offset for the outer land only."""
    need = ("time", "cage_centre", "cage_speed", "cage_eccentricity_ratio")
    if not all(k in outputs for k in need):
        return None
    if "cage_guide_offset" in outputs:
        centre = np.asarray(outputs["cage_guide_offset"][...], dtype=np.float64)
        reference = GUIDE_REFERENCE[guidance]
    else:
        centre = np.asarray(outputs["cage_centre"][...], dtype=np.float64)
        reference = GUIDE_REFERENCE["outer"] + ("" if guidance == "outer" else
                                                " (a run recorded without the offset from its guide)")
    return {"t": np.asarray(outputs["time"][...], dtype=np.float64), "reference": reference,
            "centre_yz": centre[:, 1:3] if centre.shape[1] == 3 else centre,
            "cage_speed": np.asarray(outputs["cage_speed"][...], dtype=np.float64).ravel(),
            "eccentricity_ratio": np.asarray(outputs["cage_eccentricity_ratio"][...], dtype=np.float64).ravel()}


def normalised_orbit(centre_yz: np.ndarray, eccentricity_ratio: np.ndarray) -> np.ndarray:
    """The orbit in units of the guide clearance, c·eps/|c| = c/Cg (the rim is the unit circle)."""
    c = np.asarray(centre_yz, dtype=np.float64)
    e = np.hypot(c[:, 0], c[:, 1])
    scale = np.divide(np.asarray(eccentricity_ratio, dtype=np.float64).ravel(), e,
                      out=np.zeros_like(e), where=e > 0.0)
    return c * scale[:, None]
