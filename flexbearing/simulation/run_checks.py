"""Is a finished run bounded and physical? Checks of a results file against independent bounds.

Used by the stability stress test (benchmarks/stress_test.py, tests/test_stress.py). Each check
returns a dict with its measured value, its bound and `ok`; `check_run(path, scene)` runs those the
file's recorded outputs allow.

finite         every recorded dataset finite (the summary's non_finite count, flexbearing.simulation.results).
energy         the work–energy theorem of the model (flexbearing.multibody.power_loss module docstring) over the
               run, with E the mechanical energy without the load's potential (outputs mechanical_energy):
                   E(T) − E(0) = ∫ (P_drive + P_load − P_loss) dt
               the integral by the trapezoidal rule over the samples; residual relative to the
               largest of ∫|P_loss| dt, ∫|P_load| dt, ∫|P_drive| dt and |ΔE| (the scale of the terms).
               Bound 5 %: the sampled powers are trapezoid-integrated at the sample interval while
               pocket collisions and impacts vary within it (the balance itself holds to 9e-6 of
               the loss at a state, tests/test_power_loss.py); a broken integration or a
               non-conservative force misses by the whole loss.
approach       the deepest race contact against the energy bound of a Hertz contact loaded suddenly
               by the whole peak external load plus the ball's centrifugal force: a load F applied
               at once to an undamped Hertz spring Q = K·delta^1.5 stops at F·delta = (2/5)·K·delta^2.5,
                   delta_bound = (2.5·(|F|max + F_c)/K_min)^(2/3),   F_c = m_b·(omega_i,max/2)²·dm/2
               (the orbit speed of a ball is below half the inner ring's with the outer ring fixed;
               K_min the softest race contact of the model's Hertz tables, Harris & Kotzalas Vol. 1
               eq. 6.41); and the dynamics' plausibility limit DELTA_MAX_FRAC·Dw.
cage_clearance the cage centre in its guide clearance: the eccentricity ratio e/Cg at most
               1 + the rim's elastic penetration at the largest recorded rim force, F_rim/(K_rim·Cg),
               plus 1 % (the film and rim forces are sampled; the cage may touch the rim between
               samples with a larger force than recorded).
"""
from __future__ import annotations

import numpy as np

from flexbearing.multibody import model as M
from flexbearing.multibody.dynamics import DELTA_MAX_FRAC
from flexbearing.multibody.model import build_model
from flexbearing.simulation.results import read_outputs

ENERGY_TOLERANCE = 0.05      # module docstring
RIM_MARGIN = 0.01


def _trapz(y, t) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t))) if len(t) > 1 else 0.0


def check_finite(out: dict) -> dict:
    bad = {k: int(np.size(v) - np.isfinite(v).sum()) for k, v in out.items()}
    bad = {k: n for k, n in bad.items() if n}
    return {"ok": not bad, "value": sum(bad.values()), "bound": 0, "detail": bad or ""}


def check_energy(out: dict) -> dict | None:
    need = ("mechanical_energy", "drive_power", "power_loss", "external_load_power")
    if not all(k in out for k in need) or len(out["time"]) < 2:
        return None
    t = out["time"]
    e = out["mechanical_energy"]
    de = float(e[-1] - e[0])
    net = _trapz(out["drive_power"] + out["external_load_power"] - out["power_loss"], t)
    scale = max(_trapz(np.abs(out["power_loss"]), t), _trapz(np.abs(out["external_load_power"]), t),
                _trapz(np.abs(out["drive_power"]), t), abs(de), 1e-12)
    r = abs(de - net) / scale
    return {"ok": bool(r <= ENERGY_TOLERANCE), "value": r, "bound": ENERGY_TOLERANCE,
            "detail": f"dE = {de:.4g} J, integrated balance {net:.4g} J, scale {scale:.4g} J"}


def hertz_approach_bound(model, peak_load: float, max_speed: float) -> float:
    """delta_bound of the module docstring, m."""
    kmin = float(model.hertz_table[:2, :, M.H_K].min())
    p = model.p
    fc = p[M.P_MB] * (0.5 * max_speed) ** 2 * 0.5 * p[M.P_DM]
    return (2.5 * (peak_load + fc) / kmin) ** (2.0 / 3.0)


def check_approach(out: dict, model, max_speed: float) -> dict | None:
    if "approach" not in out:
        return None
    deepest = float(np.max(out["approach"]))
    peak = float(np.max(np.linalg.norm(out["external_load"], axis=-1)))
    bound = min(hertz_approach_bound(model, peak, max_speed), DELTA_MAX_FRAC * model.p[M.P_DW])
    return {"ok": bool(deepest <= bound), "value": deepest, "bound": bound,
            "detail": f"peak |F| {peak:.4g} N"}


def check_cage_clearance(out: dict, model) -> dict | None:
    if "cage_eccentricity_ratio" not in out:
        return None
    e = float(np.max(out["cage_eccentricity_ratio"]))
    rim = float(np.max(out["cage_rim_force"])) if "cage_rim_force" in out else 0.0
    bound = 1.0 + rim / (model.p[M.P_KRIM] * model.p[M.P_CG]) + RIM_MARGIN
    return {"ok": bool(e <= bound), "value": e, "bound": bound, "detail": f"max rim force {rim:.4g} N"}


def check_run(path, scene, model=None) -> dict:
    """{check name: result} for the results file `path` of `scene` (module docstring); `model` the
    run's multibody model (built from the scene's bearing if not given)."""
    if model is None:
        model = build_model(scene.bearing, scene.oil, dict(scene.model_options))
    out = read_outputs(path)
    max_speed = float(np.max(np.abs(scene.speed_table[:, 1])))
    checks = {"finite": check_finite(out), "energy": check_energy(out),
              "approach": check_approach(out, model, max_speed),
              "cage_clearance": check_cage_clearance(out, model)}
    return {k: v for k, v in checks.items() if v is not None}
