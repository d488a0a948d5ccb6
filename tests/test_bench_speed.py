"""benchmarks/bench_speed.py: the pure helpers of the before → after table (issue 21)."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_speed as B  # noqa: E402


def test_relative_difference_and_limits():
    assert B.relative_difference(101.0, 100.0) == 0.01
    assert B.relative_difference(-99.0, -100.0) == 0.01        # signed by the change, scaled by |before|
    assert math.isnan(B.relative_difference(1.0, 0.0))
    assert math.isnan(B.relative_difference(None, 1.0))
    # the criteria: 1 % on every contact stress statistic, 3 % on the p99 cage forces and
    # von Mises p99/mean; single-collision peaks are not judged
    assert B.limit_of("outer_contact_stress_peak") == 0.01
    assert B.limit_of("inner_contact_stress_mean") == 0.01
    assert B.limit_of("pocket_force_p99") == 0.03
    assert B.limit_of("von_mises_max_mean") == 0.03
    assert B.limit_of("pocket_force_peak") is None


def test_read_runs_from_a_shell_loop(tmp_path):
    (tmp_path / "times.txt").write_text(
        "== paper_steady_rigid 11:06:38 load 1.99\n"
        "paper_steady_rigid 57.77 user 1.91 sys 169.34 wall\n"
        "   end 11:09:28 load 4.95\n"
        "== paper_steady_rigid 11:31:18 load 9.68\n"
        "paper_steady_rigid 32.01 user 0.25 sys 170.10 wall\n")
    (tmp_path / "paper_steady_rigid.summary.json").write_text(json.dumps(
        {"n_steps": 81583, "n_rejected": 7713, "wall_time_s": 163.4, "setup_time_s": 3.85}))
    r = B.read_runs(tmp_path)["paper_steady_rigid"]
    # the last run of a scene counts (the first one compiled the numba cache)
    assert r["cpu_s"] == 32.26 and r["wall_s"] == 170.10 and r["load_start"] == 9.68
    assert r["n_steps"] == 81583 and r["n_rejected"] == 7713


def test_scatter_levels_of_the_tolerance_study():
    s = B.scatter_levels()
    # benchmarks/results/study/README.md: pocket force p99 spread 4.1 %, contact stresses <= 0.1 %
    assert 0.03 < s["pocket_force_p99"] < 0.05
    assert s["outer_contact_stress_mean"] < 0.002


def test_read_runs_takes_the_median_of_repeated_runs(tmp_path):
    """Repeats of a scene in runs.jsonl: the record of median wall time is the scene's (a machine
    whose speed drifts between runs), every run's times are kept beside it."""
    rows = [{"scene": "s", "wall_s": w, "cpu_s": w + 1, "n_steps": 10} for w in (14.5, 10.7, 11.9)]
    (tmp_path / "runs.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    r = B.read_runs(tmp_path)["s"]
    assert r["wall_s"] == 11.9 and r["cpu_s"] == 12.9
    assert r["wall_s_runs"] == [14.5, 10.7, 11.9] and r["cpu_s_runs"] == [15.5, 11.7, 12.9]
