"""The fast path of the uncertainty study against the dynamic validation (issue 23, item 2).

flexbearing.studies.uncertainty predicts each (point, case) by the steady fixed point with weight
(flexbearing.multibody.steady.steady_held_cage_state). Independent check: the dynamic validation run
(flexbearing.studies.validation.slip_rate.run_slip_case: integrate until the cage speed settles) on
- the nominal point, all 15 cases: the session-14 Table 5 rows (benchmarks/results/
  slip_rate_session14_ehl.json, same inputs: 30°, design clearance, 150 °C, EHL ×1, X_ref 0.2 %, steel);
- a few (case, point) pairs of the sample far from it, run here (minutes each).

    nice -n 10 .venv/bin/python -m benchmarks.uncertainty_fast_path_check [--pairs 1:1,12:1,1:0,12:0] [--t-max 6]

writes benchmarks/results/slip_rate_uncertainty_check.json (rows: case, point, dynamic slip, steady slip,
difference), which `flexbearing uncertainty --report-dir` tabulates. The steady slips come from the
study's rows file (out/uncertainty/slip_rate_unknowns/rows.jsonl), or are computed here if missing.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
CHECK_FILE = RESULTS / "slip_rate_uncertainty_check.json"


def dynamic_slip(point: dict, case: dict, t_max: float) -> dict:
    """The dynamic validation run of `case` at `point` (flexbearing.studies.validation.slip_rate.run_slip_case, steady start)."""
    from flexbearing.studies import uncertainty as U
    from flexbearing.studies.validation import slip_rate as V
    bearing, oil, scale = U.point_bearing_oil(point, case["speed_rpm"])
    t0 = time.process_time()
    row = V.run_slip_case(case, bearing, oil, V.validation_model_options(), t_max=t_max, traction_law="ehl",
                          traction_scale=scale, start="steady")
    return dict(slip_pct=row["slip_pct"], settled=row["settled"], t_end=row["t_end"], start=row["start"],
                cpu_s=time.process_time() - t0)


def main(argv=None) -> None:
    from flexbearing.studies import uncertainty as U
    from flexbearing.studies.validation.slip_rate import slip_rate_cases
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--unknowns", default="scenes/slip_rate_unknowns.toml")
    ap.add_argument("--rows", default="out/uncertainty/slip_rate_unknowns/rows.jsonl")
    ap.add_argument("--pairs", default="1:1,12:1,1:0,12:0", help="case:point pairs run dynamically")
    ap.add_argument("--t-max", type=float, default=6.0)
    a = ap.parse_args(argv)
    study = U.load_unknowns(a.unknowns)
    points = U.sample_points(study)
    cases = {c["case"]: c for c in slip_rate_cases()}
    steady = {(r["point"], r["case"]): r for r in U.read_rows(a.rows)}
    out = json.loads(CHECK_FILE.read_text()) if CHECK_FILE.exists() else {"rows": []}
    have = {(r["point"], r["case"]) for r in out["rows"]}
    # nominal point: session 14's dynamic Table 5
    s14 = json.loads((RESULTS / "slip_rate_session14_ehl.json").read_text())["rows"]
    for r in s14:
        key = ("nominal", r["case"])
        if key in have:
            continue
        st = steady.get(key) or U.steady_case_slip(study.nominal(), cases[r["case"]])
        out["rows"].append(dict(point="nominal", case=r["case"], dynamic_slip_pct=r["slip_pct"],
                                dynamic_settled=r["settled"], dynamic_source="slip_rate_session14_ehl.json (quasi-static start)",
                                steady_slip_pct=st["slip_pct"], steady_converged=st["converged"]))
    for pair in a.pairs.split(","):
        c, p = (int(x) for x in pair.split(":"))
        if (p, c) in have:
            continue
        st = steady.get((p, c)) or U.steady_case_slip(points[p], cases[c])
        dyn = dynamic_slip(points[p], cases[c], a.t_max)
        out["rows"].append(dict(point=p, case=c, values=points[p], dynamic_slip_pct=dyn["slip_pct"],
                                dynamic_settled=dyn["settled"], dynamic_t_end=dyn["t_end"], dynamic_start=dyn["start"],
                                dynamic_cpu_s=dyn["cpu_s"], dynamic_source=f"run_slip_case, t_max {a.t_max} s",
                                steady_slip_pct=st["slip_pct"], steady_converged=st["converged"]))
        print(out["rows"][-1], flush=True)
        CHECK_FILE.write_text(json.dumps(out, indent=1) + "\n")
    CHECK_FILE.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
