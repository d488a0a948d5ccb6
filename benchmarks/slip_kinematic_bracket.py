"""Skid-free cage slip of the race-control idealisations against the shim angle (paper Table 5 cases).

For each shim angle alphaD (with its design clearance, flexbearing.studies.validation.slip_rate.design_clearance) and each
of the 15 steady test cases, the quasi-static solver (flexbearing.multibody.quasi_static, outer-race control,
friction_share (1, 1), centrifugal and gyroscopic terms) gives the running contact angles alpha_o,
alpha_i (means over the balls loaded at both races). At those angles the cage speed of a ball that
rolls without slip on both races is, for three attitudes of its spin axis:

* outer control: the quasi-static solution itself (no spin on the outer race, Jones 1960);
* inner control: flexbearing.studies.validation.kinematics.race_control_cage_speed_ratio(..., "inner") (no spin on the inner race);
* beta = alpha_i: flexbearing.studies.validation.kinematics.pure_rolling_cage_speed_ratio (spin axis normal to the inner
  contact line in the cage frame).

Slip S = (nm − nc)/nm with the paper's nm = ½·ni·(1 − Dw·cos alpha/dm), alpha = (alpha_o + alpha_i)/2,
compared with the test slips (relative error, mean and max over cases 1–8 and 9–15). No skid, no
drag: a bracket of what the ball attitude alone can give, not a model of the test. Seconds to run:

    .venv/bin/python -m benchmarks.slip_kinematic_bracket [--shim-angles 30,25,20,15,10]
"""
from __future__ import annotations

import argparse
import math
from dataclasses import replace

import numpy as np

from flexbearing.studies.validation import kinematics as K, slip_rate as V
from flexbearing.multibody.geometry import nominal_cage_speed
from flexbearing.multibody import quasi_static as QS
from flexbearing.multibody.bearing import PAPER_BEARING

ATTITUDES = ("outer control", "inner control", "beta = alpha_i")


def bracket(shim_angle_deg: float) -> dict:
    """Slips (%) of the three attitudes for the 15 cases at one shim angle, and the angles (deg)."""
    b = replace(PAPER_BEARING, shim_angle=math.radians(shim_angle_deg))
    b = replace(b, radial_clearance=V.design_clearance(b))
    g = QS.grooves_from_bearing(b)
    slips = {k: [] for k in ATTITUDES}
    angles = []
    for c in V.slip_rate_cases():
        w = c["speed_rpm"] * math.pi / 30.0
        r = QS.solve_quasi_static(g, inner_speed=w, fx=c["axial_load"], fz=-c["radial_load"], control="outer",
                                  friction_share=(1.0, 1.0))
        if not r.converged:
            raise RuntimeError(f"case {c['case']}, shim {shim_angle_deg}°: {r.diagnostic}")
        q = r.load
        both = (q[:, 0] > 0) & (q[:, 1] + q[:, 2] > 0)
        ki = np.where(q[:, 1] >= q[:, 2], 1, 2)
        ao = float(np.mean(np.abs(r.contact_angle[both, 0])))
        ai = float(np.mean(np.abs(r.contact_angle[np.arange(len(q)), ki][both])))
        nm = nominal_cage_speed(w, b.ball_diameter, b.pitch_diameter, 0.5 * (ao + ai))
        ratio_inner, _ = K.race_control_cage_speed_ratio(ao, ai, "inner", b.ball_diameter, b.pitch_diameter)
        ratio_beta = K.pure_rolling_cage_speed_ratio(ao, ai, ai, b.ball_diameter, b.pitch_diameter)
        for k, nc in zip(ATTITUDES, (r.cage_speed, ratio_inner * w, ratio_beta * w)):
            slips[k].append(100.0 * (nm - nc) / nm)
        angles.append((math.degrees(ao), math.degrees(ai)))
    return dict(shim_angle_deg=shim_angle_deg, slips={k: np.array(v) for k, v in slips.items()},
                angles=np.array(angles))


def table(shim_angles) -> str:
    test = np.array([c["test_slip_pct"] for c in V.slip_rate_cases()])
    lines = ["| alphaD ° | alpha_o/alpha_i case 1 ° | attitude | err 1–8 mean % | max % | err 9–15 mean % | max % |",
             "|---:|---|---|---:|---:|---:|---:|"]
    for a in shim_angles:
        res = bracket(a)
        ao, ai = res["angles"][0]
        for k in ATTITUDES:
            e = 100.0 * np.abs(res["slips"][k] - test) / test
            lines.append(f"| {a:g} | {ao:.1f}/{ai:.1f} | {k} | {e[:8].mean():.1f} | {e[:8].max():.1f} | "
                         f"{e[8:].mean():.1f} | {e[8:].max():.1f} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--shim-angles", default="30,27.5,25,22.5,20,15,10", help="degrees, comma separated")
    args = p.parse_args(argv)
    print(table([float(s) for s in args.shim_angles.split(",")]))


if __name__ == "__main__":
    main()
