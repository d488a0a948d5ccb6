"""Check of the race-control audit's statements (issue 46, item 3; docs/race_control.md).

The audit (a separate single-ball steady model with its own creep law) said: (1) no friction
level gives Table 5's sign at the model's contact angles: raising friction moves the pitch to
outer-race control and stops there; (2) what decides is the ratio of the two contacts' spin
resistance; (3) the oil state does change the sign at high speed: at 100 °C instead of the
validation's 150 °C the held state of case 6 goes to about +35 % (gross skid). This script runs
the same held-cage steady state as benchmarks/race_control_screening.py (steady_held_cage_state
with weight and the radial load, the validation's EHL-law model and cavity oil) with:

    friction   the EHL law's film strength (traction_scale 0.5, 1, 2: the declared range,
               flexbearing.multibody.traction.EHL_RANGES) and the paper's 4106 fit scaled as a whole
               (x0.5 ... x4, a diagnostic: x4 is beyond what any film gives);
    oil        the oil temperature (the validation's 150 °C, and 120, 100, 80 °C).

    python benchmarks/race_control_audit.py [--cases 1,6,12] [--variants ehl_x1,fit_x2,oil_100C]
        [--out benchmarks/results/race_control_audit.json]
    python benchmarks/race_control_audit.py --markdown benchmarks/results/race_control_audit.json

Per case: slip (the validation's definition), pitch beta of the ball's spin axis (cage frame),
Jones's ratio Q_i·a_i/(Q_o·a_o·cos(alpha_o − alpha_i)), the mean loaded contact angles, and the
inner/outer race-control brackets at those angles (flexbearing.studies.validation.kinematics.brackets).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import race_control_screening as S  # noqa: E402  (pitch_angles, semi_major_axes: the screening's own readers)

from flexbearing.studies.validation import slip_rate as V  # noqa: E402
from flexbearing.studies.validation import kinematics as RC  # noqa: E402
from flexbearing.multibody.steady import steady_held_cage_state  # noqa: E402

# name -> (traction law, traction scale, oil temperature °C or None for the validation's 150 °C)
VARIANTS = {
    "ehl_x0.5": ("ehl", 0.5, None),
    "ehl_x1": ("ehl", 1.0, None),
    "ehl_x2": ("ehl", 2.0, None),
    "fit_x0.5": ("fit", 0.5, None),
    "fit_x1": ("fit", 1.0, None),
    "fit_x2": ("fit", 2.0, None),
    "fit_x4": ("fit", 4.0, None),
    "oil_120C": ("ehl", 1.0, 120.0),
    "oil_100C": ("ehl", 1.0, 100.0),
    "oil_80C": ("ehl", 1.0, 80.0),
}


def case_row(case: dict, law: str, scale: float, oil_c) -> dict:
    """The held-cage steady state of one Table 5 case with the given traction law and oil temperature."""
    bearing = V.validation_bearing()
    oil = V.validation_oil(oil_c, V.case_oil_air_fraction(V.VALIDATION_OIL_AIR_FRACTION, case["speed_rpm"],
                                                          V.VALIDATION_OIL_AIR_SCALING))
    model = V.build_validation_model(bearing, oil, V.validation_model_options(), law, scale)
    omega = case["speed_rpm"] * 2.0 * math.pi / 60.0
    t0 = time.process_time()
    _, info = steady_held_cage_state(model, omega, (case["axial_load"], 0.0, -case["radial_load"]))
    out = info["outputs"]
    Q = out["contact_load"]
    ao = float(np.mean(np.abs(out["contact_angle_outer"])))
    ai = float(np.mean(np.abs(out["contact_angle_inner_loaded"])))
    br = RC.brackets(case["speed_rpm"], bearing.ball_diameter, bearing.pitch_diameter, math.degrees(ai),
                     math.degrees(ao), math.degrees(0.5 * (ao + ai)))
    q_o = float(np.mean(Q[:, 0]))
    q_i = float(np.mean(np.max(Q[:, 1:], axis=1)))
    a_o, a_i = S.semi_major_axes(model, out)
    return dict(case=case["case"], converged=bool(info["converged"]), slip_pct=100.0 * float(out["slip_rate"]),
                test_slip_pct=case["test_slip_pct"], inner_control_pct=br.inner_slip_percent,
                outer_control_pct=br.outer_slip_percent, alpha_o_deg=math.degrees(ao), alpha_i_deg=math.degrees(ai),
                beta_deg=math.degrees(float(np.mean(S.pitch_angles(out)))),
                beta_outer_control_deg=br.outer.pitch_angle_deg, beta_inner_control_deg=br.inner.pitch_angle_deg,
                q_outer=q_o, q_inner=q_i, jones_ratio=q_i * a_i / (q_o * a_o * math.cos(ao - ai)),
                cpu_s=time.process_time() - t0)


def markdown(path: str) -> str:
    d = json.loads(Path(path).read_text())
    lines = ["| variant | case | slip % | test % | outer / inner control % | pitch β, deg (outer / inner ctl) | Jones ratio | α_o / α_i, deg |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for name, rows in d["variants"].items():
        for r in rows:
            conv = "" if r["converged"] else " (not converged)"
            lines.append(f"| {name} | {r['case']} | {r['slip_pct']:+.2f}{conv} | {r['test_slip_pct']:+.2f} | "
                         f"{r['outer_control_pct']:+.2f} / {r['inner_control_pct']:+.2f} | "
                         f"{r['beta_deg']:.1f} ({r['beta_outer_control_deg']:.1f} / {r['beta_inner_control_deg']:.1f}) | "
                         f"{r['jones_ratio']:.2f} | {r['alpha_o_deg']:.1f} / {r['alpha_i_deg']:.1f} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="1,6,12")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--out", default=None)
    ap.add_argument("--markdown", default=None)
    a = ap.parse_args(argv)
    if a.markdown:
        print(markdown(a.markdown))
        return
    cases = [c for c in V.slip_rate_cases() if c["case"] in {int(v) for v in a.cases.split(",")}]
    result = dict(command="python benchmarks/race_control_audit.py " + " ".join(argv or sys.argv[1:]), variants={})
    for name in a.variants.split(","):
        law, scale, oil_c = VARIANTS[name]
        rows = [case_row(c, law, scale, oil_c) for c in cases]
        result["variants"][name] = rows
        for r in rows:
            print(f"{name:10s} case {r['case']:2d}: slip {r['slip_pct']:+7.2f} % (test {r['test_slip_pct']:+.2f}; "
                  f"outer/inner ctl {r['outer_control_pct']:+.2f}/{r['inner_control_pct']:+.2f})  "
                  f"beta {r['beta_deg']:5.1f} deg (outer ctl {r['beta_outer_control_deg']:.1f}, inner "
                  f"{r['beta_inner_control_deg']:.1f})  Jones {r['jones_ratio']:.2f}  converged {r['converged']}",
                  flush=True)
        if a.out:                                   # after every variant: a long one can be stopped
            Path(a.out).write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
