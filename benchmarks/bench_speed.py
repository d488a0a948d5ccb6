"""Before → after speed of whole runs (issue 21, item 3): CPU, wall, steps, and what moved.

`run` mode runs scenes with the code of a given source tree (a checkout of the "before" commit, or
this tree), one child process per scene (`python -m flexbearing.cli.main run`, PYTHONPATH = that tree, so
each tree keeps its own numba cache), and appends one JSON line per run to OUT/runs.jsonl: CPU
(user + sys of the child, getrusage), wall time, the machine's 1-min load at start and end, and
the run's summary (steps, rejected steps, integration wall time, setup time). The numba cache must
be warm (run any scene once with that tree first) or the CPU time includes the compilation (~25 s).
A directory written by a shell loop instead (`/usr/bin/time -f "SCENE %U user %S sys %e wall"`
appended to times.txt, with "== SCENE HH:MM:SS load L" lines before each run, and the run's own
RUN.summary.json) is read the same way.

`report` mode compares two such directories: the table of steps and CPU/wall per scene, and for
the paper scenes the report's whole-run statistics (flexbearing.analysis.windows.phase_table, settle 0.05 s as
the tolerance-scatter study) of AFTER against BEFORE as relative differences, beside the numerical
scatter of each statistic over five equally valid runs (benchmarks/results/study/
tolerance_scatter.json: the unsteady flexible scene at tolerances 0.6e-6 ... 1e-6). Criteria of the
issue: contact stresses within 1 %, p99 pocket/guiding force and max von Mises within 3 %;
single-collision peaks are shown against their scatter. Writes benchmarks/results/speed.{md,json}.

    .venv/bin/python benchmarks/bench_speed.py run --code /tmp/before --out out/speed/before \
        scenes/paper_steady_rigid.toml scenes/paper_unsteady_rigid.toml scenes/paper_steady.toml \
        scenes/paper_unsteady.toml scenes/startup_rigid.toml
    .venv/bin/python benchmarks/bench_speed.py run --code . --out out/speed/after  (same scenes)
    .venv/bin/python benchmarks/bench_speed.py report out/speed/before out/speed/after
"""
from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

# the statistics, the limits and the settle time of the work–precision benchmark, and its
# numerical scatter of each statistic (the tolerance-scatter study): one definition for both
from benchmarks.bench_work_precision import (CRITERIA, ERROR_STATS, FAMILIES, PEAK_STATS,  # noqa: E402
                                             SETTLE, scatter_levels)

STATS = ERROR_STATS + PEAK_STATS


def limit_of(stat: str) -> float | None:
    """The issue's relative limit for a statistic: its family's criterion (None: reported, not
    judged — film, slip and the single-collision peaks)."""
    family = next((f for f, stats in FAMILIES.items() if stat in stats), None)
    return CRITERIA.get(family)


def relative_difference(after: float, before: float) -> float:
    """(after − before)/|before| (NaN when before is 0 or either is missing)."""
    if before is None or after is None or not math.isfinite(before) or before == 0.0:
        return float("nan")
    return (after - before) / abs(before)


def run_scene(code: Path, scene: Path, out: Path) -> dict:
    """Run one scene with the code of `code` in a child process; CPU from getrusage."""
    env = dict(os.environ, PYTHONPATH=str(code))
    h5 = out / (scene.stem + ".h5")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "flexbearing.cli.main", "run", str(scene.resolve()), "-o", str(h5.resolve()),
                        "--force", "--quiet"], cwd=code, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    rec = {"scene": scene.stem, "code": str(code), "returncode": p.returncode,
           "cpu_s": round((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), 2),
           "wall_s": round(wall, 2), "load_start": round(load0, 2), "load_end": round(os.getloadavg()[0], 2),
           "date": time.strftime("%Y-%m-%d %H:%M:%S")}
    summ = h5.with_suffix(".summary.json")
    if p.returncode == 0 and summ.exists():
        s = json.loads(summ.read_text())
        rec.update(n_steps=s["n_steps"], n_rejected=s["n_rejected"], loop_wall_s=round(s["wall_time_s"], 2),
                   setup_s=round(s["setup_time_s"], 2), duration_s=s["duration_s"])
    else:
        rec["error"] = (p.stderr or p.stdout)[-500:]
    return rec


def cmd_run(a) -> None:
    code = Path(a.code).resolve()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    scenes = [Path(s) for s in a.scenes]
    for s in scenes:
        rec = run_scene(code, s, out)
        with open(out / "runs.jsonl", "a") as f:
            f.write(json.dumps(rec) + "\n")
        print(json.dumps(rec), flush=True)


def read_runs(folder: Path) -> dict:
    """{scene: record} of a run directory's runs.jsonl: with several runs of a scene (repeats on a
    machine whose speed drifts), the run of median wall time, with every run's wall and CPU time
    in wall_s_runs, cpu_s_runs."""
    recs = {}
    p = Path(folder) / "runs.jsonl"
    if p.exists():
        runs: dict[str, list] = {}
        for line in p.read_text().splitlines():
            if line.strip():
                r = json.loads(line)
                runs.setdefault(r["scene"], []).append(r)
        for scene, rs in runs.items():
            by_wall = sorted(rs, key=lambda r: r["wall_s"])
            rec = dict(by_wall[(len(by_wall) - 1) // 2])
            rec["wall_s_runs"] = [r["wall_s"] for r in rs]
            rec["cpu_s_runs"] = [r["cpu_s"] for r in rs]
            recs[scene] = rec
        return recs
    t = Path(folder) / "times.txt"
    if t.exists():
        load = None
        for line in t.read_text().splitlines():
            w = line.split()
            if line.startswith("=="):
                load = float(w[-1])
            elif len(w) == 7 and w[2] == "user" and w[6] == "wall":
                rec = {"scene": w[0], "cpu_s": round(float(w[1]) + float(w[3]), 2), "wall_s": float(w[5]),
                       "load_start": load}
                summ = Path(folder) / f"{w[0]}.summary.json"
                if summ.exists():
                    sm = json.loads(summ.read_text())
                    rec.update(n_steps=sm["n_steps"], n_rejected=sm["n_rejected"],
                               loop_wall_s=round(sm["wall_time_s"], 2), setup_s=round(sm["setup_time_s"], 2))
                recs[w[0]] = rec
    return recs


def whole_run_stats(h5: Path) -> dict:
    from flexbearing.analysis.windows import phase_table
    row = phase_table(h5, include_impacts=False, settle=SETTLE)[0]
    return {k: row.get(k) for k in STATS if isinstance(row.get(k), (int, float))}


def cmd_report(a) -> dict:
    before, after = Path(a.before), Path(a.after)
    rb, ra = read_runs(before), read_runs(after)
    scatter = scatter_levels()
    result = {"before": str(before), "after": str(after), "scenes": {}}
    lines = ["| scene | steps before → after | CPU s before → after | wall s before → after (load) | "
             "wall s of every run, before; after | speed-up (wall) |",
             "|---|---:|---:|---:|---|---:|"]
    for scene in sorted(set(rb) | set(ra)):
        b, c = rb.get(scene, {}), ra.get(scene, {})
        entry = {"before": b, "after": c}
        sp = (b["wall_s"] / c["wall_s"]) if b.get("wall_s") and c.get("wall_s") else float("nan")
        every = f"{b.get('wall_s_runs', '–')}; {c.get('wall_s_runs', '–')}"
        lines.append(f"| {scene} | {b.get('n_steps', '–'):,} → {c.get('n_steps', '–'):,} | "
                     f"{b.get('cpu_s', '–')} → {c.get('cpu_s', '–')} | {b.get('wall_s', '–')} ({b.get('load_start', '–')}) → "
                     f"{c.get('wall_s', '–')} ({c.get('load_start', '–')}) | {every} | {sp:.2f}× |")
        hb, ha = before / f"{scene}.h5", after / f"{scene}.h5"
        if scene.startswith("paper_") and hb.exists() and ha.exists():
            sb, sa = whole_run_stats(hb), whole_run_stats(ha)
            entry["stats"] = {k: {"before": sb.get(k), "after": sa.get(k),
                                  "rel": relative_difference(sa.get(k), sb.get(k)),
                                  "limit": limit_of(k), "scatter": scatter.get(k)} for k in STATS}
        result["scenes"][scene] = entry
    lines += ["", "Whole-run statistics (after settle 0.05 s), relative difference after − before; limit: the "
              "issue's criterion; scatter: (max − min)/mean over the five tolerance-scatter runs (unsteady flexible).", ""]
    scenes = [s for s in result["scenes"] if "stats" in result["scenes"][s]]
    lines.append("| statistic | limit | scatter | " + " | ".join(scenes) + " |")
    lines.append("|---|---:|---:|" + "---:|" * len(scenes))
    for k in STATS:
        cells = []
        for s in scenes:
            r = result["scenes"][s]["stats"][k]["rel"]
            cells.append("–" if not math.isfinite(r) else f"{100 * r:+.2f} %")
        lim = limit_of(k)
        sc = scatter.get(k)
        lines.append(f"| {k} | {'–' if lim is None else f'{100 * lim:.0f} %'} | "
                     f"{'–' if sc is None else f'{100 * sc:.1f} %'} | " + " | ".join(cells) + " |")
    result["table_md"] = "\n".join(lines)
    print(result["table_md"])
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=2, default=float) + "\n")
    return result


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="run scenes with the code of a source tree")
    r.add_argument("--code", default=str(ROOT), help="source tree whose code runs (PYTHONPATH)")
    r.add_argument("--out", required=True, help="directory for the results and runs.jsonl")
    r.add_argument("scenes", nargs="+")
    p = sub.add_parser("report", help="compare two run directories")
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("--json", default=None, help="write the comparison as JSON")
    a = ap.parse_args(argv)
    if a.cmd == "run":
        cmd_run(a)
    else:
        cmd_report(a)


if __name__ == "__main__":
    main()
