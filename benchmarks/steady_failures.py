"""The uncertainty study's runs without a steady state: is there another held-cage root?

For each run (point/case of `scenes/slip_rate_unknowns.toml`, point 0-based, case 1-based) this runs
the solver as the study does (`flexbearing.studies.uncertainty.steady_case_slip`'s model and call),
then, at the full load (lambda = 1):

1. deflated Newton (flexbearing.multibody.steady_root_search.held_cage_root_search) from the branch's
   last root, the direct solve's end, the dynamics settled 30 ms from the last root (the hold
   check's end state) and the physical grid of starts (`physical_starts`: cage speed 0.05-0.8 of the
   inner ring's, spins by either race's rolling law, pocket offsets on either wall);
2. the cage-speed reduction (`cage_speed_scan`): g(omega_c/omega_i) over 0.05-0.8;

and, for a run without a thrust root (no branch), the same two at lambda = 0 (thrust alone, no weight:
the equations that hold the symmetric thrust state). Writes benchmarks/results/steady_failures.json
(one record per run, appended/replaced by run) and steady_failures.md (the table).

    python benchmarks/steady_failures.py 23/6 38/6 52/11 0/11 11/3 25/6
    python benchmarks/steady_failures.py +45/6 +20/11      # calibration: runs that converge
"""
from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from flexbearing.multibody.steady import steady_held_cage_state
from flexbearing.multibody.steady_root_search import cage_speed_scan, held_cage_root_search
from flexbearing.multibody.steady_search_starts import START_FRACTIONS, physical_starts, unknowns_of_state
from flexbearing.studies.uncertainty import load_unknowns, point_bearing_oil, sample_points
from flexbearing.studies.validation import slip_rate as V
from flexbearing.studies.validation.slip_rate import slip_rate_cases

RESULTS = Path(__file__).resolve().parent / "results"


def run_problem(point_case: str):
    """(model, omega, load) of study run 'p/c', as steady_case_slip builds them."""
    p, c = (int(s) for s in point_case.split("/"))
    point = sample_points(load_unknowns("scenes/slip_rate_unknowns.toml"))[p]
    case = slip_rate_cases()[c - 1]
    bearing, oil, scale = point_bearing_oil(point, case["speed_rpm"])
    model = V.build_validation_model(bearing, oil, V.validation_model_options(), "ehl", scale)
    omega = case["speed_rpm"] * 2.0 * math.pi / 60.0
    return model, omega, np.array([case["axial_load"], 0.0, -case["radial_load"]])


def start_labels(extra_labels):
    """Names of the starts in the order search_at passes them (physical_starts' loop order)."""
    return list(extra_labels) + [f"omega_c {f:.2f} omega_i, {law}-race rolling, wall {side}"
                                 for f in START_FRACTIONS for law in ("outer", "inner") for side in ("+", "-")]


def search_at(model, omega, load, lam, u_ref, lam_ref, extra_starts, extra_labels):
    """The deflated search and the scan at lambda, as a JSON-able dict. The scan's reference: the first
    root the search found (at lam), else u_ref (a root at lam_ref, or not a root where lam_ref = lam)."""
    starts = list(extra_starts) + physical_starts(model, omega, u_ref)
    labels = start_labels(extra_labels)
    rs = held_cage_root_search(model, omega, load, u_ref, starts, lam=lam)
    scan_ref, scan_lam_ref = (rs.roots[0]["unknowns"], lam) if rs.roots else (u_ref, lam_ref)
    sc = cage_speed_scan(model, omega, load, scan_ref, scan_lam_ref, lam=lam)
    lo, hi = sc.scan.g_range
    return dict(lam=lam, starts=rs.search.starts_tried, roots=[dict(cage_speed=r["cage_speed"], slip_pct=100 * r["slip"],
                residual=r["residual"], held=r["held"], whirl=None if r["hold"] is None else r["hold"].whirl_ratio,
                eccentricity=r["eccentricity"], start=labels[k]) for r, k in zip(rs.roots, rs.search.root_starts)],
                stalls=sum(1 for r in rs.search.runs if not r.converged), search_cpu_s=rs.cpu_s,
                search=rs.describe(), scan=sc.describe(), g_min=lo, g_max=hi, brackets=list(sc.scan.brackets),
                unsolved=list(sc.scan.unsolved), unexcluded=list(sc.scan.unexcluded), no_root=sc.scan.no_root,
                scan_points=len(sc.scan.x), scan_x=sc.scan.x.tolist(), scan_g=sc.scan.g.tolist(),
                scan_reference="the search's root" if rs.roots else f"a root at lambda {lam_ref:.4f}" if lam_ref != lam
                else "the direct solve's end (not a root)",
                scan_roots=[{k: v for k, v in r.items() if k != "unknowns"} for r in sc.roots], scan_cpu_s=sc.cpu_s)


def one_run(point_case: str) -> dict:
    model, omega, load = run_problem(point_case)
    t0 = time.process_time()
    _, info = steady_held_cage_state(model, omega, load, strict=False)
    rec = dict(run=point_case, solver_converged=info["converged"], verdict=info.get("verdict"),
               solver_cpu_s=time.process_time() - t0, omega=omega, reason=info.get("reason", ""))
    if info.get("traction_drag_bound") is not None:
        rec["traction_drag_bound"] = info["traction_drag_bound"].describe()
    extra, labels, u_ref, lam_ref = [], [], np.asarray(info["unknowns"], dtype=float), 1.0
    if "branch_last_root" in info:
        lam_ref, u_ref = info["branch_last_root"]
        rec["branch_last_lambda"] = lam_ref
        extra.append(u_ref)
        labels.append(f"the branch's last root (lambda {lam_ref:.4f})")
    extra.append(np.asarray(info["unknowns"], dtype=float))       # the direct solve's end at lambda = 1
    labels.append("the direct solve's end")
    hold = info.get("cage_hold")
    if hold is not None and hold.end_state is not None:
        extra.append(unknowns_of_state(model, hold.end_state))
        labels.append("the dynamics 30 ms from the last root")
    rec["at_full_load"] = search_at(model, omega, load, 1.0, u_ref, lam_ref, extra, labels)
    if "branch_last_root" not in info:                               # no thrust root: the thrust equations too
        rec["at_thrust_only"] = search_at(model, omega, load, 0.0, u_ref, 0.0, extra, labels)
    rec["total_cpu_s"] = time.process_time() - t0
    return rec


def calibration_run(point_case: str) -> dict:
    """The same search at lambda = 1 on a run that converges: the solver's root is the reference for the
    ball and ring positions, not deflated; how many starts find it (or another root), and does g change sign?"""
    model, omega, load = run_problem(point_case)
    t0 = time.process_time()
    _, info = steady_held_cage_state(model, omega, load, strict=False)
    rec = dict(run="+" + point_case, solver_converged=info["converged"], verdict=info.get("verdict", "converged"),
               solver_cpu_s=time.process_time() - t0, omega=omega, calibration=True,
               solver_slip_pct=100 * float(info["outputs"]["slip_rate"]), solver_cage_speed=info["cage_speed"])
    rec["at_full_load"] = search_at(model, omega, load, 1.0, np.asarray(info["unknowns"], dtype=float), 1.0, [], [])
    rec["total_cpu_s"] = time.process_time() - t0
    return rec


def table(records: list[dict]) -> str:
    lines = ["| run | solver | lambda | starts | roots found (slip %, residual, held) | stalls | search CPU-s | "
             "g range over omega_c/omega_i 0.05-0.8 | sign change | scan points (unsolved) | scan CPU-s |",
             "|---|---|---:|---:|---|---:|---:|---|---|---|---:|"]
    for r in records:
        for key in ("at_full_load", "at_thrust_only"):
            s = r.get(key)
            if s is None:
                continue
            roots = "; ".join(f"{x['slip_pct']:.2f} %, {x['residual']:.0e}, {'held' if x['held'] else 'not held'}"
                              for x in s["roots"]) or "none"
            sign = ", ".join(f"[{a:.3f}, {b:.3f}]" for a, b in s["brackets"]) or \
                ("none, all intervals excluded" if s["no_root"] else f"none ({len(s['unexcluded'])} intervals open)")
            lines.append(f"| {r['run']} | {r['verdict']} | {s['lam']:g} | {s['starts']} | {roots} | {s['stalls']} | "
                         f"{s['search_cpu_s']:.0f} | {s['g_min']:.3g} to {s['g_max']:.3g} | {sign} | "
                         f"{s['scan_points']} ({len(s['unsolved'])}) | {s['scan_cpu_s']:.0f} |")
    return "\n".join(lines) + "\n"


def main(runs: list[str]) -> None:
    path = RESULTS / "steady_failures.json"
    load = lambda: {r["run"]: r for r in json.loads(path.read_text())} if path.exists() else {}
    for pc in runs:
        rec = calibration_run(pc[1:]) if pc.startswith("+") else one_run(pc)
        print(json.dumps(rec, default=float), flush=True)
        records = load()                        # re-read: another process may have added runs meanwhile
        records[rec["run"]] = rec
        path.write_text(json.dumps(list(records.values()), indent=1, default=float) + "\n")
    (RESULTS / "steady_failures_table.md").write_text(table(list(load().values())))


if __name__ == "__main__":
    main(sys.argv[1:])
