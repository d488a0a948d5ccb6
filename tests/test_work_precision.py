"""The work–precision benchmark's pure functions (benchmarks/bench_work_precision.py) on hand-made
cases whose answers are worked out by hand: relative errors, family maxima, the accuracy score
against the issue's limits (1 % contact stresses, 3 % cage forces and von Mises), the Pareto front
in (cost, error), the cut of a scene for the --quick run, and the plan of runs."""
import math

import numpy as np
import pytest

from benchmarks.bench_work_precision import (CRITERIA, FAMILIES, accuracy_score, family_errors, plan,
                                             pareto_front, relative_errors, truncate_scene)


def test_relative_errors_by_hand():
    ref = {"a": 200.0, "b": -4.0, "c": 0.0, "d": 10.0}
    run = {"a": 202.0, "b": -3.0, "c": 5.0}
    e = relative_errors(run, ref, ("a", "b", "c", "d", "e"))
    # a: 2/200 = 1 %; b: 1/4 = 25 % (sign of the reference does not matter); c: reference 0 has no
    # relative error -> left out; d: the run lacks it -> NaN; e: neither has it -> left out
    assert e["a"] == pytest.approx(0.01, rel=1e-12)
    assert e["b"] == pytest.approx(0.25, rel=1e-12)
    assert "c" not in e and "e" not in e and math.isnan(e["d"])


def test_family_errors_take_the_largest_and_propagate_nan():
    fams = {"x": ("a", "b"), "y": ("c",), "z": ("q",)}
    assert family_errors({"a": 0.01, "b": 0.03, "c": 0.5}, fams) == {"x": 0.03, "y": 0.5}
    out = family_errors({"a": 0.01, "b": float("nan")}, fams)
    assert math.isnan(out["x"]) and set(out) == {"x"}


def test_accuracy_score_against_the_issue_limits():
    assert CRITERIA == {"contact": 0.01, "cage_force": 0.03, "von_mises": 0.03}
    ref_fams = {"contact", "cage_force", "von_mises", "film"}
    # 0.5 % contact -> 0.5; 2.4 % cage force -> 0.8; 0.3 % von Mises -> 0.1; film has no limit
    assert accuracy_score({"contact": 0.005, "cage_force": 0.024, "von_mises": 0.003, "film": 0.9},
                          ref_fams) == pytest.approx(0.8, rel=1e-12)
    # 1.5 % contact fails: 1.5
    assert accuracy_score({"contact": 0.015, "cage_force": 0.0, "von_mises": 0.0}, ref_fams) == pytest.approx(1.5)
    # a run without von Mises (rigid cage) against a reference with it cannot meet the criteria
    assert accuracy_score({"contact": 0.0, "cage_force": 0.0}, ref_fams) == math.inf
    # a rigid reference has no von Mises: only contact and cage force count
    assert accuracy_score({"contact": 0.002, "cage_force": 0.03}, {"contact", "cage_force"}) == pytest.approx(1.0)


def test_pareto_front_by_hand():
    # (cost, error): A(1, 10) B(2, 5) C(3, 5) D(3, 1) E(4, 2) F(0.5, nan) G(5, 1)
    cost = [1, 2, 3, 3, 4, 0.5, 5]
    err = [10, 5, 5, 1, 2, float("nan"), 1]
    # C is dominated by B (same error, cheaper), E by D, G by D (same error, cheaper); F is NaN
    np.testing.assert_array_equal(pareto_front(cost, err), [True, True, False, True, False, False, False])
    # equal points do not dominate each other
    np.testing.assert_array_equal(pareto_front([1, 1], [2, 2]), [True, True])
    assert pareto_front([], []).size == 0
    # with a 10 % margin a run 4 % cheaper and less accurate does not push another off the front,
    # one 20 % cheaper and as accurate does, one at the same cost and more accurate does
    np.testing.assert_array_equal(pareto_front([100, 96], [0.3, 0.5], 0.1), [True, True])
    np.testing.assert_array_equal(pareto_front([100, 96], [0.3, 0.3], 0.1), [True, True])
    np.testing.assert_array_equal(pareto_front([100, 80], [0.3, 0.3], 0.1), [False, True])
    np.testing.assert_array_equal(pareto_front([100, 100], [0.3, 0.2], 0.1), [False, True])


def test_truncate_scene_cuts_phases_and_impacts():
    data = {"operation": {"duration": 0.6, "speed": {"phases": [
        {"kind": "ramp", "duration": 0.2, "start_rpm": 10000, "end_rpm": 14000},
        {"kind": "uniform", "duration": 0.2, "rpm": 14000}]},
        "load": {"axial_load": 1.0, "impacts": [{"t_center": 0.02, "duration": 0.02, "magnitude": 1.0},
                                               {"t_start": 0.1, "duration": 0.02, "magnitude": 1.0}]}}}
    d = truncate_scene(data, 0.05)
    ph, = d["operation"]["speed"]["phases"]
    # a quarter of the 0.2 s ramp: 10000 + 0.25 * 4000 = 11000 rpm
    assert ph["duration"] == 0.05 and ph["end_rpm"] == pytest.approx(11000.0)
    # the impact [0.01, 0.03] s stays, the one at [0.1, 0.12] s is dropped
    assert [i.get("t_center") for i in d["operation"]["load"]["impacts"]] == [0.02]
    assert data["operation"]["duration"] == 0.6            # the input is not modified
    from flexbearing.simulation.scene import parse_scene
    full = {"operation": d["operation"], "output": {"sample_interval": 1e-3, "record": ["cage_speed"]}}
    assert parse_scene(full).duration == 0.05               # a valid scene


def test_plan_varies_one_setting_at_a_time():
    runs = plan()
    keys = [r["key"] for r in runs]
    assert len(keys) == len(set(keys))
    for r in runs:
        assert len(r["overrides"]) <= 1
    rigid = [r for r in runs if r["scene"] == "paper_steady_rigid"]
    flex = [r for r in runs if r["scene"] == "paper_steady"]
    assert not any(r["setting"].startswith("cage.") for r in rigid)
    assert {r["setting"] for r in flex} >= {"cage.n_modes", "cage.stress_monitor_interval"}
    assert sum(r["setting"] == "reference" for r in runs) == 4
    assert set(FAMILIES) == {"contact", "cage_force", "von_mises", "film", "slip"}


def test_claims_let_several_benchmark_processes_share_the_runs(tmp_path):
    """A run finished in the JSONL is not run again; a run claimed by a live process is left to it;
    a claim whose process is gone is taken over; a finished record wins over a later failure."""
    import json
    import os
    import subprocess
    import sys
    from benchmarks.bench_work_precision import claim, read_jsonl
    jsonl = tmp_path / "wp.jsonl"
    spec = {"key": "s|a=1", "h5": str(tmp_path / "a.h5"), "jsonl": str(jsonl)}
    assert claim(spec) is None                                   # free: claimed for this process
    assert (tmp_path / "a.h5.claim").read_text() == str(os.getpid())
    assert claim(spec) == f"claimed by process {os.getpid()}"    # live claim
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True).stdout.strip()
    (tmp_path / "a.h5.claim").write_text(dead)                   # its process has exited
    assert claim(spec) is None
    ok = {"key": "s|a=1", "status": "ok", "stats": {}}
    jsonl.write_text(json.dumps(ok) + "\n" + json.dumps({"key": "s|a=1", "status": "failed (exit 1)"}) + "\n"
                     + json.dumps({"key": "s|a=1", "status": "failed (exit 3): SKIPPED: finished"}) + "\n")
    assert read_jsonl(jsonl)["s|a=1"]["status"] == "ok"
    assert claim({**spec, "h5": str(tmp_path / "b.h5")}) == "finished"


def test_tolerance_ensembles_bias_and_family_table():
    """benchmarks/tolerance_ensembles: family mean, sample std (ddof 1), spread; the bias of a family's
    mean against the tightest with Welch's standard error sqrt(s_a²/n_a + s_b²/n_b) (by hand: runs
    10, 11 and 9, 10, 11: means 10.5 and 10, variances 0.5 and 1, bias 5 %, s.e.
    sqrt(0.5/2 + 1/3)/10), and the pass rule (within 2 s.e. or within the limit)."""
    from benchmarks import tolerance_ensembles as T
    recs = [{"status": "ok", "scene": "s", "family": fam, "stats": {"pocket_force_p99": v}}
            for fam, vals in ((1e-4, (10.0, 11.0)), (1e-8, (9.0, 10.0, 11.0))) for v in vals]
    tab = T.family_table(recs, stats=("pocket_force_p99",))
    m, s, spread, n = tab["s"][1e-4]["pocket_force_p99"]
    assert (m, n) == (10.5, 2) and abs(s - math.sqrt(0.5)) < 1e-12 and abs(spread - 1 / 10.5) < 1e-12
    b, se = T.bias(tab["s"][1e-4]["pocket_force_p99"], tab["s"][1e-8]["pocket_force_p99"])
    assert abs(b - 0.05) < 1e-12
    assert abs(se - math.sqrt(0.5 / 2 + 1.0 / 3) / 10.0) < 1e-12
    assert T.passes(0.05, 0.03, 0.03) and not T.passes(0.05, 0.02, 0.03) and T.passes(0.02, 0.0, 0.03)
