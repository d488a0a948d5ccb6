"""A five-run study on a Dask LocalCluster of 2 workers against the same runs one after the other.

The study: the paper's axial-load study (§4.4.1, 45–65 kN, scenes/study_axial_load.toml) on the
paper's steady flexible-cage scene (scenes/paper_steady.toml: 14,000 rpm, Fr 4 kN, 26 modes, every
output incl. von Mises), shortened to `--duration` s of simulated time so that the five runs take
minutes, not an hour. Each repetition runs `flexbearing study` twice in fresh output folders,
A/B interleaved (serial `--workers 1`, then `--workers 2`, then serial ...), each under
/usr/bin/time (wall, and user + sys CPU of the command and every process it waited for: the
LocalCluster's worker processes are its children). The load average of the machine before each
command is recorded: on a shared machine the wall times say how much the cluster gains *under
that load*; the CPU times say what the cluster costs (start-up, imports and numba loads in each
worker process).

    .venv/bin/python -m benchmarks.bench_study_dask [--duration 0.05] [--repeat 2] [--out DIR]

Writes benchmarks/results/study_dask.{json,md}. Needs the 4 mm reduced cage in the cache
(FLEXBEARING_CACHE; built once if missing, before the timings).
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


def write_study(folder: Path, duration: float) -> Path:
    base = (ROOT / "scenes" / "paper_steady.toml").read_text()
    base = re.sub(r"^duration = 0\.6\b", f"duration = {duration!r}", base, flags=re.M)
    base = base.replace('{ kind = "uniform", duration = 0.6, rpm = 14000 }',
                        f'{{ kind = "uniform", duration = {duration!r}, rpm = 14000 }}')
    assert f"duration = {duration!r}" in base
    (folder / "base.toml").write_text(base)
    study = folder / "study.toml"
    study.write_text(f"""[study]
name = "bench"
description = "paper §4.4.1 axial loads on the steady flexible scene, {duration} s each"
scene = "base.toml"
keys = ["operation.load.axial_load"]
values = [45e3, 50e3, 55e3, 60e3, 65e3]
label = "Axial load"
unit = "N"
display_unit = "kN"
display_scale = 1e-3
settle = 0.0
""")
    return study


def timed(argv: list[str]) -> dict:
    load = os.getloadavg()[0]
    fmt = "TIME %U %S %e"
    p = subprocess.run(["/usr/bin/time", "-f", fmt, *argv], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed:\n{p.stderr[-3000:]}")
    user, sys_, wall = (float(x) for x in p.stderr.strip().splitlines()[-1].split()[1:])
    return {"wall_s": wall, "cpu_s": user + sys_, "user_s": user, "sys_s": sys_, "load_before": load,
            "load_after": os.getloadavg()[0]}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=0.05, help="simulated time per run, s (default 0.05)")
    ap.add_argument("--repeat", type=int, default=2, help="A/B pairs (default 2)")
    ap.add_argument("--out", default=None, help="scratch folder (default: a temporary one)")
    a = ap.parse_args(argv)
    scratch = Path(a.out or tempfile.mkdtemp(prefix="bench_study_dask_"))
    scratch.mkdir(parents=True, exist_ok=True)
    study = write_study(scratch, a.duration)
    cli = [str(Path(sys.executable).with_name("flexbearing"))]
    # the reduced cage, once, outside the timings
    subprocess.run([sys.executable, "-c", "from flexbearing.simulation.scene import load_scene; from flexbearing.coupling.flexible_cage "
                    f"import reduced_cage_path; reduced_cage_path(load_scene({str(scratch / 'base.toml')!r}))"],
                   check=True)
    rows = []
    for rep in range(a.repeat):
        for workers in (1, 2):
            out = scratch / f"out_{rep}_{workers}"
            shutil.rmtree(out, ignore_errors=True)
            r = timed(cli + ["study", str(study), "-o", str(out), "--workers", str(workers), "--quiet"])
            saved = json.loads((out / "bench" / "study.json").read_text())
            r.update(repetition=rep, workers=workers,
                     run_wall_s=[run["wall_time_s"] for run in saved["runs"]])
            rows.append(r)
            print(f"rep {rep} workers {workers}: wall {r['wall_s']:.1f} s, cpu {r['cpu_s']:.1f} s, "
                  f"load {r['load_before']:.1f} -> {r['load_after']:.1f}", flush=True)
    # the two ways give the same study (each run one deterministic integration)
    a_json = json.loads((scratch / "out_0_1" / "bench" / "study.json").read_text())
    b_json = json.loads((scratch / "out_0_2" / "bench" / "study.json").read_text())
    same = all(x["windows"] == y["windows"] for x, y in zip(a_json["runs"], b_json["runs"]))
    summary = {}
    for workers in (1, 2):
        sel = [r for r in rows if r["workers"] == workers]
        summary[workers] = {k: statistics.median(r[k] for r in sel) for k in ("wall_s", "cpu_s", "load_before")}
    speedup = summary[1]["wall_s"] / summary[2]["wall_s"]
    result = {"command": " ".join(["python -m benchmarks.bench_study_dask", f"--duration {a.duration}",
                                   f"--repeat {a.repeat}"]),
              "cpu_count": os.cpu_count(), "duration_s": a.duration, "rows": rows,
              "median": {str(k): v for k, v in summary.items()}, "speedup_wall": speedup,
              "same_windows": same}
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / "study_dask.json").write_text(json.dumps(result, indent=1) + "\n")
    lines = ["# A five-run study: Dask LocalCluster of 2 workers against serial", "",
             f"`{result['command']}` (benchmarks/bench_study_dask.py docstring: what is run). "
             f"{os.cpu_count()} CPUs; the load average (1 min) before each command is given: the "
             f"machine was shared with other jobs.", "",
             "| rep | workers | wall s | CPU s (user+sys) | load before → after | per-run wall s |",
             "|---:|---:|---:|---:|---|---|"]
    for r in rows:
        lines.append(f"| {r['repetition']} | {r['workers']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} | "
                     f"{r['load_before']:.1f} → {r['load_after']:.1f} | "
                     + ", ".join(f"{w:.1f}" for w in r["run_wall_s"]) + " |")
    lines += ["", f"Median wall: serial {summary[1]['wall_s']:.1f} s, 2 workers {summary[2]['wall_s']:.1f} s "
              f"(×{speedup:.2f}); median CPU: {summary[1]['cpu_s']:.1f} s against {summary[2]['cpu_s']:.1f} s. "
              f"Same windows in both ways, to the bit: {same}.", ""]
    (RESULTS / "study_dask.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
