"""Screening of the race-control candidates over Table 5's 15 cases (issue 35, item 4).

For each candidate mechanism a physically bounded setting (docs/race_control.md gives the source
of every bound) is run through the steady solver (flexbearing.multibody.steady) on the 15 cases of
the seed paper's Table 5, and each case's slip is put beside the two race-control brackets at the
model's own contact angles (flexbearing.studies.race_control.brackets) and the measured slip.

    python benchmarks/race_control_screening.py [--state held|thrust] [--variants a,b] [--cases 1,6]
        [--out benchmarks/results/race_control_screening.json]

--state held (default): `steady_held_cage_state` with weight and the radial load (the uncertainty
study's fast path, 2–60 s a case); thrust: `steady_thrust_state` under the axial load alone, no
weight (0.2–0.5 s a case; the radial load is left out, so only trends are read from it).

Per case it records: slip (the validation's definition, nm at the mean loaded angle), the mean
loaded contact angles, the ball's pitch beta (spin axis to bearing axis, in the cage frame), the
brackets, the loads and semi-major axes of both contacts, the load on the second (unloaded) inner
half, the mean pocket force, the spin at each contact (rad/s, relative to its race, along the
normal) and Jones's control ratio Q_i·a_i / (Q_o·a_o·cos(alpha_o − alpha_i)) (> 1: inner-race
control by Jones's criterion). The spin-resistance section (`spin_resistance`) evaluates the EHL
law's spin moment of each contact against spin on its own (flexbearing.multibody.traction).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from flexbearing.studies import validate as V
from flexbearing.studies import race_control as RC
from flexbearing.multibody import model as M
from flexbearing.multibody.steady import steady_held_cage_state, steady_thrust_state

# name -> (model options, oil-air fraction at 4000 rpm or None for the validation's, description)
VARIANTS = {
    "baseline": ({}, None, "the validation model (EHL law, free balls, X_ref 0.2 % falling as 1/n)"),
    "pocket_mu_0.1": ({"pocket_friction": 0.1}, None, "Coulomb pocket friction 0.1 (boundary-lubricated steel)"),
    "pocket_mu_0.3": ({"pocket_friction": 0.3}, None, "Coulomb pocket friction 0.3 (dry steel, upper bound)"),
    "cavity_oil_5pct": ({}, 0.05, "cavity oil 5 % at 4000 rpm (flooded under-race supply)"),
    "cavity_oil_20pct": ({}, 0.20, "cavity oil 20 % at 4000 rpm (upper bound)"),
    "ball_drag_moment": ({"ball_drag_moment": True}, None, "viscous drag moment on the spinning ball (new term)"),
    "ball_drag_moment_flooded": ({"ball_drag_moment": True}, 0.20, "drag moment with cavity oil 20 %"),
    # what it would take (a diagnostic factor, not physics): the inner contacts' spin moment x k
    "inner_spin_x3": ({"spin_moment_scale_inner": 3.0}, None, "inner spin moment x3 (diagnostic)"),
    "inner_spin_x10": ({"spin_moment_scale_inner": 10.0}, None, "inner spin moment x10 (diagnostic)"),
    "inner_spin_x30": ({"spin_moment_scale_inner": 30.0}, None, "inner spin moment x30 (diagnostic)"),
    "inner_spin_x100": ({"spin_moment_scale_inner": 100.0}, None, "inner spin moment x100 (diagnostic)"),
}


def pitch_angles(out: dict) -> np.ndarray:
    """Pitch beta of every ball's spin axis to the bearing axis, in the frame that orbits with it (rad)."""
    w = out["ball_angular_velocity"]
    rel_x = w[:, 0] - out["ball_orbit_speed"]
    return np.arctan2(np.abs(w[:, 1]), np.abs(rel_x))


def contact_spins(out: dict) -> tuple[np.ndarray, np.ndarray]:
    """Spin of the ball relative to the outer and to the more loaded inner race about the contact
    normal (rad/s), per ball: outer normal (sin a, cos a), inner (−sin a, −cos a) in (e_x, e_r)
    (flexbearing.multibody.dynamics), the inner race turning at omega_i about e_x."""
    w = out["ball_angular_velocity"]
    ang = out["contact_angle"]
    Q = out["contact_load"]
    ao = ang[:, 0]
    pick = np.where(Q[:, 1] >= Q[:, 2], 1, 2)
    ai = ang[np.arange(len(pick)), pick]
    s_o = w[:, 0] * np.sin(ao) + w[:, 1] * np.cos(ao)
    s_i = -(w[:, 0] - out["inner_ring_speed"]) * np.sin(ai) - w[:, 1] * np.cos(ai)
    return s_o, s_i


def case_row(case: dict, options: dict, oil_fraction_ref, state: str) -> dict:
    bearing = V.validation_bearing()
    x_ref = V.VALIDATION_OIL_AIR_FRACTION if oil_fraction_ref is None else oil_fraction_ref
    oil = V.validation_oil(None, V.case_oil_air_fraction(x_ref, case["speed_rpm"], "inverse_speed"))
    opts = {**V.validation_model_options(), **options}
    omega = case["speed_rpm"] * 2.0 * math.pi / 60.0
    t0 = time.process_time()
    if state == "held":
        model = V.build_validation_model(bearing, oil, opts, "ehl", 1.0)
        _, info = steady_held_cage_state(model, omega, (case["axial_load"], 0.0, -case["radial_load"]))
    else:
        model = V.build_validation_model(bearing, oil, {**opts, "gravity": 0.0}, "ehl", 1.0)
        _, info = steady_thrust_state(model, omega, case["axial_load"])
    out = info["outputs"]
    Q = out["contact_load"]
    ang = np.abs(out["contact_angle"])
    ao = float(np.mean(np.abs(out["contact_angle_outer"])))
    ai = float(np.mean(np.abs(out["contact_angle_inner_loaded"])))
    ref = math.degrees(0.5 * (ao + ai))
    br = RC.brackets(case["speed_rpm"], bearing.ball_diameter, bearing.pitch_diameter, math.degrees(ai),
                     math.degrees(ao), ref)
    from flexbearing.multibody.dynamics import new_work  # noqa: F401  (the work array is not needed)
    q_o = float(np.mean(Q[:, 0]))
    q_i = float(np.mean(np.max(Q[:, 1:], axis=1)))
    q_third = float(np.max(np.min(Q[:, 1:], axis=1)))
    a_o, a_i = semi_major_axes(model, out)
    s_o, s_i = contact_spins(out)
    jones = q_i * a_i / (q_o * a_o * math.cos(ao - ai))
    return dict(case=case["case"], converged=bool(info["converged"]), slip_pct=100.0 * float(out["slip_rate"]),
                test_slip_pct=case["test_slip_pct"], inner_control_pct=br.inner_slip_percent,
                outer_control_pct=br.outer_slip_percent, alpha_o_deg=math.degrees(ao), alpha_i_deg=math.degrees(ai),
                beta_deg=math.degrees(float(np.mean(pitch_angles(out)))),
                beta_outer_control_deg=br.outer.pitch_angle_deg, beta_inner_control_deg=br.inner.pitch_angle_deg,
                q_outer=q_o, q_inner=q_i, q_third_contact_max=q_third, a_outer=a_o, a_inner=a_i,
                spin_outer=float(np.mean(s_o)), spin_inner=float(np.mean(s_i)), jones_ratio=jones,
                pocket_force_mean=float(np.mean(out["pocket_force"])), cpu_s=time.process_time() - t0,
                max_contact_angle_deg=float(np.degrees(ang.max())))


def semi_major_axes(model, out) -> tuple[float, float]:
    """Mean Hertz semi-major axes (m) of the outer and the more loaded inner contact (exact Hertz,
    flexbearing.multibody.hertz, at each ball's load and angle)."""
    from flexbearing.multibody.hertz import hertz_point_contact, race_curvature_radii
    p = model.p
    Q = out["contact_load"]
    ang = np.abs(out["contact_angle"])
    a_o, a_i = [], []
    for j in range(Q.shape[0]):
        k = 1 if Q[j, 1] >= Q[j, 2] else 2
        for c, inner, f, acc in ((0, False, p[M.P_FE], a_o), (k, True, p[M.P_FI], a_i)):
            rx, ry = race_curvature_radii(p[M.P_DW], p[M.P_DM], f, ang[j, c], inner)
            acc.append(hertz_point_contact(rx, ry, p[M.P_EBR], Q[j, c])[0] if Q[j, c] > 0 else 0.0)
    return float(np.mean(a_o)), float(np.mean(a_i))


def summary(rows: list[dict]) -> dict:
    ok = [r for r in rows if r["converged"]]
    err = [100.0 * abs(r["slip_pct"] - r["test_slip_pct"]) / r["test_slip_pct"] for r in ok]
    return dict(n=len(rows), converged=len(ok), mean_error_pct=float(np.mean(err)) if err else math.nan,
                max_error_pct=float(np.max(err)) if err else math.nan,
                right_sign=sum(1 for r in ok if r["slip_pct"] > 0.0),
                slip_range_pct=(min(r["slip_pct"] for r in ok), max(r["slip_pct"] for r in ok)) if ok else None)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--state", default="held", choices=["held", "thrust"])
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--cases", default=None)
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    cases = V.slip_rate_cases()
    if a.cases:
        keep = {int(c) for c in a.cases.split(",")}
        cases = [c for c in cases if c["case"] in keep]
    result = {"state": a.state, "command": "python benchmarks/race_control_screening.py " + " ".join(argv or sys.argv[1:]),
              "variants": {}}
    for name in a.variants.split(","):
        options, x_ref, text = VARIANTS[name]
        rows = []
        for c in cases:
            try:
                rows.append(case_row(c, options, x_ref, a.state))
            except Exception as exc:       # a failed solve is a row, not the end of the screening
                rows.append(dict(case=c["case"], converged=False, error=str(exc), test_slip_pct=c["test_slip_pct"]))
            r = rows[-1]
            if r.get("error"):
                print(f"{name:26s} case {r['case']:2d}  failed: {r['error']}", flush=True)
            else:
                print(f"{name:26s} case {r['case']:2d} {'ok ' if r['converged'] else 'NC '} slip {r['slip_pct']:+7.2f} "
                      f"(test {r['test_slip_pct']:+6.2f}; inner {r['inner_control_pct']:+6.2f} outer {r['outer_control_pct']:+6.2f}) "
                      f"a_o {r['alpha_o_deg']:5.1f} a_i {r['alpha_i_deg']:5.1f} beta {r['beta_deg']:5.1f} "
                      f"(outer {r['beta_outer_control_deg']:5.1f}) Jones {r['jones_ratio']:.2f} "
                      f"Q3 {r['q_third_contact_max']:.1f} N pocket {r['pocket_force_mean']:.2f} N {r['cpu_s']:.1f}s",
                      flush=True)
        s = summary([r for r in rows if not r.get("error")])
        print(f"{name}: {s}", flush=True)
        result["variants"][name] = {"description": text, "options": options, "oil_air_fraction_ref": x_ref,
                                    "rows": rows, "summary": s}
        if a.out:
            tmp = Path(a.out + ".part")
            tmp.write_text(json.dumps(result, indent=1, default=float) + "\n")
            tmp.replace(a.out)


if __name__ == "__main__":
    main()
