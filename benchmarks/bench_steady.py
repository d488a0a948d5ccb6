"""Work of the steady thrust state (flexbearing.multibody.steady) on the slip-rate cases and the paper case.

For each case: wall time of `steady_thrust_state` (numba warm; the quasi-static start included),
function evaluations, residual, and the slip it gives, at the validation's oil state with the
axial load alone and no gravity (the fixed point's own assumptions). How the dynamics behave from
this start with the radial load and the weight on is in benchmarks/results/slip_rate.md ("The
steady thrust state"): within 0.3 points of it for cases 5 and 6 after 1 s.

Without the weight the dynamics do not stay at the centred-cage fixed point at these light
loads: the outer-ring-guided cage whirls out to its rim (tests/test_cage_whirl.py) and the land
torque changes the skid. Case 4 from the quasi-static start, no gravity, no radial load, 15 s:
cage 198.1 rad/s against the fixed point's 266.9 (measured once, 185 s of wall time; run with
`--dynamics 4`).

    .venv/bin/python -m benchmarks.bench_steady [--dynamics CASES]
"""
from __future__ import annotations

import argparse
import math
import time

from flexbearing.studies.validation import slip_rate as V
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.model import build_model
from flexbearing.multibody.steady import steady_thrust_state


def solve_timed(model, w, fa) -> tuple[dict, float]:
    steady_thrust_state(model, w, fa, strict=False)                # warm
    t0 = time.perf_counter()
    _, info = steady_thrust_state(model, w, fa, strict=False)
    return info, time.perf_counter() - t0


def case_model(case):
    oil = V.validation_oil(None, V.case_oil_air_fraction(V.VALIDATION_OIL_AIR_FRACTION, case["speed_rpm"],
                                                        V.VALIDATION_OIL_AIR_SCALING))
    return V.build_validation_model(V.VALIDATION_BEARING, oil, {"gravity": 0.0}), oil


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dynamics", default="", help="cases to integrate as well (gravity and radial load off), e.g. 4")
    ap.add_argument("--t-max", type=float, default=15.0)
    a = ap.parse_args(argv)
    print("| case | rpm | Fa N | converged | residual | nfev | wall ms | slip % |")
    print("|---|---:|---:|---|---:|---:|---:|---:|")
    info, dt = solve_timed(build_model(PAPER_BEARING, PAPER_OIL, {}), 14000 * math.pi / 30, 55e3)
    print(f"| paper | 14000 | 55000 | {info['converged']} | {info['residual']:.1e} | {info['nfev']} | {1e3 * dt:.0f} | "
          f"{100 * info['slip_rate']:.2f} |")
    for case in V.slip_rate_cases():
        model, _ = case_model(case)
        info, dt = solve_timed(model, case["speed_rpm"] * math.pi / 30, case["axial_load"])
        print(f"| {case['case']} | {case['speed_rpm']} | {case['axial_load']:.0f} | {info['converged']} | "
              f"{info['residual']:.1e} | {info['nfev']} | {1e3 * dt:.0f} | {100 * info['slip_rate']:.2f} |")
    for c in (int(x) for x in a.dynamics.split(",") if x):
        case = dict([k for k in V.slip_rate_cases() if k["case"] == c][0], radial_load=0.0)
        model, oil = case_model(case)
        info, _ = solve_timed(model, case["speed_rpm"] * math.pi / 30, case["axial_load"])
        row = V.run_slip_case(case, V.VALIDATION_BEARING, oil, {"gravity": 0.0}, t_max=a.t_max)
        print(f"case {c}, dynamics without gravity or radial load from the quasi-static start: cage "
              f"{row['cage_speed']:.3f} rad/s after {row['t_end']:.2f} s (settled {row['settled']}, "
              f"{row['wall_s']:.0f} s wall); fixed point {info['cage_speed']:.3f} rad/s")


if __name__ == "__main__":
    main()
