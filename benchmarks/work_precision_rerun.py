"""Re-run chosen runs of the work–precision benchmark into another JSONL, reusing its references.

After issue 21's change of the error norm (ball velocities against 0.3 m/s instead of 0.1 m/s) the
defaults and the tolerance-1e-4 runs were re-run against the same tolerance-1e-9 references
(a converged reference does not depend on the norm's weights):

    grep '"setting": "reference"' benchmarks/results/work_precision.jsonl > OUT/work_precision.jsonl
    .venv/bin/python benchmarks/work_precision_rerun.py OUT "paper_steady_rigid|default=" ...

Prints each run and then every analysed row (score = error / the issue's limit, <= 1 passes).
Results: benchmarks/results/work_precision_after_norm.{jsonl,md}.
"""
import sys, json, os
ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks")); sys.path.insert(0, str(ROOT))
import bench_work_precision as B
from pathlib import Path
if len(sys.argv) < 3 or sys.argv[1] in ("-h", "--help"):
    sys.exit("usage: work_precision_rerun.py OUT_DIR KEY [KEY ...]\n" + __doc__)
out = Path(sys.argv[1]); scratch = out / "scratch"; scratch.mkdir(parents=True, exist_ok=True)
jsonl = out / "work_precision.jsonl"
keys = sys.argv[2:]
for r in B.plan():
    if r["key"] not in keys or r["key"] in B.read_jsonl(jsonl):
        continue
    spec = {**r, "h5": str(scratch / (r["key"].replace("|", "__").replace("=", "-") + ".h5")),
            "duration": None, "settle": B.SETTLE, "keep": False, "jsonl": str(jsonl)}
    rec = B.run_one(spec, 3600)
    with open(jsonl, "a") as f:
        f.write(json.dumps(rec) + "\n")
    print(r["key"], rec["status"][:60], rec.get("cpu_s"), rec.get("n_steps"), flush=True)
done = B.read_jsonl(jsonl)
rows = B.analyse(done, B.SCENES)
for row in rows:
    print(json.dumps({k: row.get(k) for k in ("key", "scene", "setting", "value", "score", "n_steps", "cpu_s")}, default=str))
