"""Benchmark: the paper cage's 27 free-free modes at the default (converged) mesh.

Measures wall time of `flexbearing modes` (calibrated paper cage, default mesh, P3 on curved quadratic
tets), serial and under `mpirun -n 2`, with the mesh built once beforehand (cached) and the
mesh build timed separately. Writes benchmarks/results/modes_bench.json and .md.
The machine load at the time is recorded (os.getloadavg) because the box is shared.
Usage: .venv/bin/python benchmarks/bench_modes.py [--repeat N] [--no-mpi]
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
EXE = str(Path(sys.executable).with_name("flexbearing"))


def run(cmd, json_path):
    import resource
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_mpi_yield_when_idle="1")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd + ["--json", str(json_path), "--quiet"], check=True, env=env, cwd=ROOT)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = json.loads(Path(json_path).read_text())
    # CPU seconds of the child processes (all ranks): on a shared box this, not the wall time,
    # is what a serial run would take with a core to itself.
    res["cpu_s"] = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return wall, res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--no-mpi", action="store_true")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT))
    from flexbearing.mesh.cage_geometry import CALIBRATED_CAGE
    from flexbearing.mesh.cage_mesh import (cached_cage_mesh, DEFAULT_MESH_SIZE, DEFAULT_POCKET_SIZE, DEFAULT_ORDER,
                                DEFAULT_DEGREE)
    from flexbearing.fem_cage.modes import PAPER_TABLE8_HZ
    import numpy as np

    RESULTS.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp())
    # 1. mesh build (fresh, into a private cache so it is really built)
    os.environ["FLEXBEARING_CACHE"] = str(tmp / "cache")
    t0 = time.perf_counter()
    cached_cage_mesh(CALIBRATED_CAGE, DEFAULT_MESH_SIZE, DEFAULT_ORDER, DEFAULT_POCKET_SIZE)
    t_mesh = time.perf_counter() - t0
    out = {"mesh_build_s": t_mesh, "default_mesh": {"size_m": DEFAULT_MESH_SIZE,
           "pocket_size_m": DEFAULT_POCKET_SIZE, "order": DEFAULT_ORDER, "degree": DEFAULT_DEGREE},
           "loadavg_before": os.getloadavg(), "runs": []}
    cmd = [EXE, "modes", "--preset", "calibrated", "--no-classify"]
    configs = [("serial", cmd)]
    mpirun = shutil.which("mpirun")
    if mpirun and not args.no_mpi:
        configs.append(("mpirun -n 2", [mpirun, "-n", "2", "--allow-run-as-root", "--oversubscribe"] + cmd))
    for name, c in configs:
        for i in range(args.repeat):
            wall, res = run(c, tmp / f"{name.replace(' ', '_')}_{i}.json")
            f = np.array(res["frequencies_hz"])
            err = np.array([(f[m - 1] - PAPER_TABLE8_HZ[m]) / PAPER_TABLE8_HZ[m] for m in range(7, 28)])
            out["runs"].append({"config": name, "process_wall_s": wall, "cpu_s": res["cpu_s"],
                                "reported_wall_s": res["wall_s"],
                                "timing_s": res["timing_s"], "ndofs": res["ndofs"],
                                "rms_err_table8": float(np.sqrt(np.mean(err ** 2))),
                                "max_err_table8": float(np.max(np.abs(err))),
                                "loadavg": os.getloadavg(), "frequencies_hz": res["frequencies_hz"]})
            print(f"{name}: {wall:.1f} s process wall, {res['cpu_s']:.1f} s CPU ({res['ndofs']} dofs; "
                  f"assemble {res['timing_s']['assemble']:.1f} s, eigensolve {res['timing_s']['eigensolve']:.1f} s; "
                  f"load avg {os.getloadavg()[0]:.1f})", flush=True)
    (RESULTS / "modes_bench.json").write_text(json.dumps(out, indent=1))
    lines = ["# bench_modes: 27 free-free modes of the paper cage, default mesh", "",
             f"Mesh: size {DEFAULT_MESH_SIZE * 1e3:g} mm, pocket size {DEFAULT_POCKET_SIZE * 1e3:g} mm, "
             f"curved order {DEFAULT_ORDER}, P{DEFAULT_DEGREE}. Mesh build (gmsh, serial): {t_mesh:.1f} s (cached afterwards).",
             "", "| config | dofs | process wall (s) | CPU, all ranks (s) | assemble (s) | eigensolve (s) | load avg |",
             "|---|---|---|---|---|---|---|"]
    for r in out["runs"]:
        lines.append(f"| {r['config']} | {r['ndofs']} | {r['process_wall_s']:.1f} | {r['cpu_s']:.1f} | "
                     f"{r['timing_s']['assemble']:.1f} | {r['timing_s']['eigensolve']:.1f} | {r['loadavg'][0]:.1f} |")
    lines += ["", "Process wall = the whole `flexbearing modes` command with the mesh cached "
              "(Python start-up, imports, JIT-cache lookup, mesh read, assembly, SLEPc solve). "
              "The machine has 2 cores shared with other jobs: the load average column is the "
              "1-minute load when the run ended; with load > 2 the runs share cores."]
    (RESULTS / "modes_bench.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
