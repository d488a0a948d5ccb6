"""Cost of the cage's fatigue step (issue 34) beside the run it reads.

    .venv/bin/python benchmarks/fatigue_cost.py [RUN.h5]      (default out/unsteady.h5)

The run: `flexbearing run scenes/paper_unsteady.toml -o out/unsteady.h5` (its own wall and CPU
time are measured by `/usr/bin/time -v`, not here). This script times
flexbearing.analysis.cage_fatigue.cage_fatigue on it (default settings: Goodman, 40CrNiMoA, the
run repeated back to back) in a fresh child process: wall time, CPU time (user + system, the
fairer number on a shared machine) and peak resident memory (ru_maxrss of the child), its
phases (reading, the field pass over every node, the candidates with their critical planes),
and the number of nodes counted after screening. Writes benchmarks/results/fatigue_cost.json
(with the load average before and after: the machine is shared).
"""
from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

CHILD = """
import json, sys, time
from flexbearing.analysis.cage_fatigue import cage_fatigue, facts, FatigueSettings
t0 = time.process_time()
r = cage_fatigue(sys.argv[1], FatigueSettings())
f = facts(r)
print(json.dumps({"timing": r.timing, "cpu_in_step": time.process_time() - t0, "nodes_counted": f["nodes_counted"],
                  "worst_node": f["worst_node"], "worst_life_h": f["worst_life"] / 3600.0,
                  "min_safety_factor": f["min_safety_factor"], "worst": f["candidates"][0]}))
"""


def main(argv=None) -> int:
    run = Path((argv or sys.argv[1:] or ["out/unsteady.h5"])[0])
    if not run.is_file():
        print(f"{run} not found: run `flexbearing run scenes/paper_unsteady.toml -o {run}` first", file=sys.stderr)
        return 2
    load0 = os.getloadavg()
    w0 = time.perf_counter()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", CHILD, str(run)], check=True, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = json.loads(out.stdout.strip().splitlines()[-1])
    res.update({"run": str(run), "wall_s": time.perf_counter() - w0,
                "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
                "peak_rss_MB": after.ru_maxrss / 1024.0, "load_average_before": load0,
                "load_average_after": os.getloadavg()})
    dest = Path(__file__).parent / "results" / "fatigue_cost.json"
    dest.write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps({k: res[k] for k in ("wall_s", "cpu_s", "peak_rss_MB", "nodes_counted", "worst_node",
                                          "worst_life_h", "min_safety_factor", "load_average_before")}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
