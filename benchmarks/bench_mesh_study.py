"""Benchmark: mesh convergence of the cage's free-free modes (frequency vs dofs vs time).

Runs `flexbearing mesh-study` (flexbearing/fem_cage/mesh_study.py: curved P3 and P2 families, one linear
P1 and one straight-sided P2 level; Richardson extrapolation) and copies the CSV/JSON/PNG to
benchmarks/results/modes_mesh_study.*. Takes ~10-20 min on the shared 2-core box.
Usage: .venv/bin/python benchmarks/bench_mesh_study.py [--preset paper|nominal]
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--preset", default="paper", choices=("paper", "nominal"))
    args = ap.parse_args()
    out = Path(tempfile.mkdtemp())
    exe = str(Path(sys.executable).with_name("flexbearing"))
    subprocess.run([exe, "mesh-study", "--preset", args.preset, "-o", str(out)], check=True, cwd=ROOT,
                   env=dict(os.environ, OMP_NUM_THREADS="1"))
    RESULTS.mkdir(parents=True, exist_ok=True)
    for ext in ("csv", "json", "png"):
        shutil.copy(out / f"mesh_study.{ext}", RESULTS / f"modes_mesh_study.{ext}")
    print(f"results in {RESULTS}/modes_mesh_study.*")


if __name__ == "__main__":
    main()
