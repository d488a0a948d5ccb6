"""Fault injection across the commands (issue 36): SIGKILL at random instants and ENOSPC on small
tmpfs disks; writes benchmarks/results/fault_injection.md.

    .venv/bin/python benchmarks/fault_injection.py [--kills-scale 1.0] [--seed 36]   (root for tmpfs)

Per command, each trial starts the command in a process group of its own, kills the whole group
(workers included) with SIGKILL at an instant drawn uniformly over an uninterrupted run's wall
time, then checks what it left:

- run (the fake backend of tests/fault_injection.py, in a subprocess; and `flexbearing run` on a
  0.05 s rigid-cage paper scene): every row below the newest valid checkpoint reads back and equals
  the uninterrupted run's bit for bit (samples lost), then `--resume` and the whole file compared
  with the uninterrupted run's (bit-identical);
- study (`flexbearing study`, 3 runs of that scene, `--workers 2`): the same for every run file
  the study left, then the same command again and every run file compared;
- reduce: a synthetic stand-in (a real reduction takes minutes; the stand-in writes a reduced cage
  file of the paper cage's size through the same writer, flexbearing.fem_cage.reduced_cage.write,
  into the cache path): the cache entry is absent or verifies against its digest, and a rerun
  writes one that verifies;
- report and export of a finished run: the input is unchanged (SHA-256), every output present is
  whole (netCDF opens and equals the run, each CSV has every row), a rerun succeeds.

Temporaries a SIGKILL leaves (it allows no cleanup) are counted; every other exit path removes
them (tests/test_cache_integrity.py).
ENOSPC: the fake run on tmpfs disks of several sizes (the disk fills at different checkpoints),
the stand-in reduce and the export on a disk too small for them.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import random
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests"), str(ROOT)]

import fault_injection as FI  # noqa: E402

PY = sys.executable
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "tests"), str(ROOT)]))

RIGID = """
name = "fi_rigid"
[cage]
model = "rigid"
[operation]
duration = 0.05
[operation.speed]
phases = [{ kind = "uniform", duration = 0.05, rpm = 14000 }]
[operation.load]
axial_load = 55e3
radial_load = 4e3
radial_direction = [0.0, 0.0, -1.0]
[integrator]
tolerance = 1e-4
initial_step = 1e-7
[output]
sample_interval = 1e-4
record = ["contact_stress", "ball_loads", "pocket_force", "guiding_force", "cage_speed", "slip",
          "film_thickness", "cage_orbit"]
checkpoint_every = 20
"""

STUDY = """
[study]
name = "fi_study"
scene = "fi_rigid.toml"
keys = ["operation.load.axial_load"]
values = [45e3, 55e3, 65e3]
label = "Axial load"
unit = "N"
"""

STAND_IN = """
import sys
import numpy as np
sys.path[:0] = [{tests!r}]
from flexbearing.fem_cage import reduced_cage as rcf
from test_reduced_cage import _synthetic
# the paper cage's size: 18,247 nodes, 160 modes -> stress modes 140 MB; here 1/4 of it
data = _synthetic(m=160, nv=4600, seed=int(sys.argv[2]))
rcf.write(sys.argv[1], data, {{"content_hash": "standin", "parameters": {{"seed": int(sys.argv[2])}}}})
"""


def cli(*args) -> list[str]:
    return [PY, "-m", "flexbearing", *map(str, args)]


def popen(cmd, cwd=None):
    return subprocess.Popen([str(c) for c in cmd], env=ENV, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True)


def timed(cmd, cwd=None) -> float:
    t0 = time.perf_counter()
    p = popen(cmd, cwd)
    err = p.communicate()[1]
    if p.returncode != 0:
        raise RuntimeError(f"{cmd}: exit {p.returncode}: {err.decode()[-2000:]}")
    return time.perf_counter() - t0


def sha(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def new_row(command: str) -> dict:
    return {"command": command, "kills": 0, "landed": 0, "checkpointed": 0, "lost": 0,
            "resumes": 0, "identical": 0, "inputs_changed": 0, "outputs_damaged": 0,
            "temporaries_left": 0, "failures": []}


def kill_run(row, rng, work: Path, n: int, start, resume, reference: Path, duration: float):
    """Kill-then-resume trials of one results-file writer."""
    from flexbearing.simulation.results import read_outputs
    R = read_outputs(reference)
    for i in range(n):
        out = work / f"k{i}.h5"
        landed = FI.kill_after(start(out), rng.uniform(0, duration))
        row["kills"] += 1
        row["landed"] += landed
        c = FI.check_file(out, R)
        row["checkpointed"] += max(c.n_checkpoint, 0)
        row["lost"] += max(c.lost, 0) + (1 if c.n_checkpoint < 0 else 0)
        if c.lost or c.n_checkpoint < 0:
            row["failures"].append(f"kill {i}: {c} ({out.stat().st_size} bytes)")
        left = [n for n in FI.leftover_temporaries(work) if n.startswith(f".k{i}.")]
        row["temporaries_left"] += len(left)
        try:
            resume(out)
            row["resumes"] += 1
            row["temporaries_after_rerun"] = row.get("temporaries_after_rerun", 0) + len(
                [n for n in FI.leftover_temporaries(work) if n.startswith(f".k{i}.")])
            same = FI.same_results(reference, out)
            row["identical"] += same
            if not same:
                row["failures"].append(f"kill {i}: resume differs ({c})")
        except Exception as exc:                      # noqa: BLE001 - the table reports it
            why = getattr(exc, "stderr", None)
            why = why.decode()[-300:] if isinstance(why, bytes) else str(exc)[:300]
            row["failures"].append(f"kill {i}: resume failed: {why} ({c})")
        for p in [*work.glob(f"k{i}*"), *work.glob(f".k{i}.*")]:
            p.unlink()


def bench_fake_run(rng, work, n):
    row = new_row("run (fake backend, subprocess)")
    work.mkdir(parents=True)
    ref = work / "ref.h5"
    FI.run(ref)
    duration = timed([PY, str(ROOT / "tests" / "fault_injection.py"), "run", str(work / "timing.h5"), "0.02"])
    kill_run(row, rng, work, n, lambda out: FI.start(out, 0.02), lambda out: FI.run(out, resume=True),
             ref, duration)
    row["wall_s"] = duration
    return row


def bench_real_run(rng, work, n):
    row = new_row("run (`flexbearing run`, rigid paper scene 0.05 s)")
    work.mkdir(parents=True)
    scene = work / "fi_rigid.toml"
    scene.write_text(RIGID)
    ref = work / "ref.h5"
    timed(cli("run", scene, "-o", work / "warm.h5", "--quiet"))     # compiles the kernels once
    duration = timed(cli("run", scene, "-o", ref, "--quiet"))
    kill_run(row, rng, work, n, lambda out: popen(cli("run", scene, "-o", out, "--quiet")),
             lambda out: subprocess.run(cli("run", scene, "-o", out, "--resume", "--quiet"), env=ENV,
                                        check=True, capture_output=True),
             ref, duration)
    row["wall_s"] = duration
    return row


def bench_study(rng, work, n):
    from flexbearing.simulation.results import read_outputs
    row = new_row("study (`flexbearing study`, 3 runs, --workers 2)")
    work.mkdir(parents=True)
    (work / "fi_rigid.toml").write_text(RIGID)
    (work / "fi_study.toml").write_text(STUDY)
    ref_dir = work / "ref"
    timed(cli("study", work / "fi_study.toml", "-o", work / "warm", "--workers", 2, "--quiet"))
    duration = timed(cli("study", work / "fi_study.toml", "-o", ref_dir, "--workers", 2, "--quiet"))
    refs = sorted((ref_dir / "fi_study").glob("fi_study_*.h5"))
    R = {p.name: read_outputs(p) for p in refs}
    for i in range(n):
        out = work / f"k{i}"
        landed = FI.kill_after(popen(cli("study", work / "fi_study.toml", "-o", out, "--workers", 2, "--quiet")),
                               rng.uniform(0, duration))
        row["kills"] += 1
        row["landed"] += landed
        for p in sorted((out / "fi_study").glob("fi_study_*.h5")) if (out / "fi_study").exists() else []:
            c = FI.check_file(p, R[p.name])
            row["checkpointed"] += max(c.n_checkpoint, 0)
            row["lost"] += max(c.lost, 0) + (1 if c.n_checkpoint < 0 else 0)
            if c.lost or c.n_checkpoint < 0:
                row["failures"].append(f"kill {i}: {p.name}: {c} ({p.stat().st_size} bytes)")
        if (out / "fi_study").exists():
            row["temporaries_left"] += len(FI.leftover_temporaries(out / "fi_study"))
        r = subprocess.run(cli("study", work / "fi_study.toml", "-o", out, "--workers", 2, "--quiet"), env=ENV,
                           capture_output=True, text=True)
        if r.returncode != 0:
            row["failures"].append(f"kill {i}: rerun exit {r.returncode}: {r.stderr[-300:]}")
        else:
            row["resumes"] += 1
            same = all(FI.same_results(ref, out / "fi_study" / ref.name) for ref in refs)
            row["identical"] += same
            if not same:
                row["failures"].append(f"kill {i}: a run file differs after the rerun")
        shutil.rmtree(out)
    row["wall_s"] = duration
    return row


def bench_reduce(rng, work, n):
    from flexbearing.fem_cage import reduced_cage as rcf
    from flexbearing.common.validation import InputError
    row = new_row("reduce (synthetic stand-in, the reduced cage writer into the cache)")
    work.mkdir(parents=True)
    script = work / "standin.py"
    script.write_text(STAND_IN.format(tests=str(ROOT / "tests")))
    target = work / "cache" / "reduced_cage" / "standin.h5"
    target.parent.mkdir(parents=True)
    duration = timed([PY, script, target, 0])
    target.unlink()
    for i in range(n):
        if target.exists():
            target.unlink()
        landed = FI.kill_after(popen([PY, script, target, i]), rng.uniform(0, duration))
        row["kills"] += 1
        row["landed"] += landed
        if target.exists():
            try:
                rcf.verify(target)
                row["checkpointed"] += 1
            except InputError as exc:
                row["outputs_damaged"] += 1
                row["failures"].append(f"kill {i}: {exc}")
        row["temporaries_left"] += len([p for p in target.parent.iterdir() if p.name.startswith(".")])
        for p in target.parent.iterdir():
            if p.name.startswith("."):
                p.unlink()
        try:
            subprocess.run([PY, str(script), str(target), str(i)], env=ENV, check=True, capture_output=True)
            rcf.verify(target)
            row["resumes"] += 1
            row["identical"] += 1
        except Exception as exc:                      # noqa: BLE001
            row["failures"].append(f"kill {i}: rerun: {exc}")
    row["wall_s"] = duration
    return row


def _check_exports(out: Path, ref_csv: dict, nc_ok) -> bool:
    """True if every output present is whole."""
    ok = True
    nc = out / "r.nc"
    if nc.exists():
        ok &= nc_ok(nc)
    if (out / "csv").exists():
        for p in (out / "csv").iterdir():
            if p.name.endswith(".csv"):
                ok &= p.read_text() == ref_csv.get(p.name)
    return ok


def bench_report_export(rng, work, n_report, n_export):
    import xarray as xr
    rows = []
    work.mkdir(parents=True)
    run = work / "r.h5"
    FI.run(run)
    digest = sha(run)
    ref_dir = work / "ref"
    ref_dir.mkdir()
    d_export = timed(cli("export", run, "--netcdf", ref_dir / "r.nc", "--csv", ref_dir / "csv"))
    ref_csv = {p.name: p.read_text() for p in (ref_dir / "csv").iterdir()}
    ref_nc = xr.open_dataset(ref_dir / "r.nc").load()

    def nc_ok(p):
        try:
            with xr.open_dataset(p) as ds:
                return ds.load().equals(ref_nc)
        except Exception:                             # noqa: BLE001
            return False

    d_report = timed(cli("report", run, "-o", ref_dir / "report", "--quiet"))
    for command, n, duration, argv in (
            ("report (`flexbearing report`)", n_report, d_report, lambda o: ("report", run, "-o", o / "report", "--quiet")),
            ("export (`flexbearing export --netcdf --csv`)", n_export, d_export,
             lambda o: ("export", run, "--netcdf", o / "r.nc", "--csv", o / "csv"))):
        row = new_row(command)
        for i in range(n):
            out = work / f"k{i}"
            out.mkdir()
            landed = FI.kill_after(popen(cli(*argv(out))), rng.uniform(0, duration))
            row["kills"] += 1
            row["landed"] += landed
            row["inputs_changed"] += sha(run) != digest
            if command.startswith("export") and not _check_exports(out, ref_csv, nc_ok):
                row["outputs_damaged"] += 1
            row["temporaries_left"] += sum(len(FI.leftover_temporaries(d)) for d in [out, *out.iterdir()] if d.is_dir())
            r = subprocess.run([str(a) for a in cli(*argv(out))], env=ENV, capture_output=True, text=True)
            if r.returncode == 0 and (not command.startswith("export") or _check_exports(out, ref_csv, nc_ok)):
                row["resumes"] += 1
                row["identical"] += 1
            else:
                row["failures"].append(f"kill {i}: rerun exit {r.returncode}: {r.stderr[-300:]}")
            shutil.rmtree(out)
        row["wall_s"] = duration
        rows.append(row)
    return rows


def _mount(path: Path, size: str) -> bool:
    path.mkdir(parents=True, exist_ok=True)
    return subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)],
                          capture_output=True).returncode == 0


def bench_enospc(work):
    """ENOSPC points: the fake run at five disk sizes, the stand-in reduce and the export."""
    from flexbearing.simulation.results import read_outputs
    from flexbearing.simulation.run import RunInterrupted
    work.mkdir(parents=True)
    ref = work / "ref.h5"
    FI.run(ref)
    R = read_outputs(ref)
    rows = []
    disk = work / "disk"
    for size in ("300k", "450k", "600k", "750k", "1500k"):
        if not _mount(disk, size):
            return [{"command": "ENOSPC", "size": "-", "outcome": "skipped (mounting a tmpfs needs root)"}]
        try:
            out = disk / "r.h5"
            try:
                FI.run(out)
                outcome = "finished"
            except RunInterrupted as exc:
                outcome = f"stopped: {exc}"
            c = FI.check_file(out, R)
            temps = FI.leftover_temporaries(disk)
            moved = work / f"r_{size}.h5"
            shutil.copy(out, moved)
        finally:
            subprocess.run(["umount", str(disk)])
        FI.run(moved, resume=True)
        rows.append({"command": "run (fake backend)", "size": size, "outcome": outcome,
                     "checkpoint": c.n_checkpoint, "lost": c.lost, "temporaries_left": len(temps),
                     "resume_identical": FI.same_results(ref, moved)})
    # the stand-in reduce and the export onto a disk too small for them
    script = work / "standin.py"
    script.write_text(STAND_IN.format(tests=str(ROOT / "tests")))
    for command, size, argv in (("reduce (stand-in)", "2m", lambda d: [PY, script, d / "cage.h5", 0]),
                                ("export --netcdf", "64k", lambda d: cli("export", ref, "--netcdf", d / "r.nc")),
                                ("export --csv", "64k", lambda d: cli("export", ref, "--csv", d / "csv"))):
        _mount(disk, size)
        try:
            r = subprocess.run([str(a) for a in argv(disk)], env=ENV, capture_output=True, text=True)
            left = [p.name for p in disk.rglob(".*")]
            err = r.stderr.strip().splitlines()
            rows.append({"command": command, "size": size, "outcome": f"exit {r.returncode}: "
                         f"{(err[-1] if err else '')[:160]}", "stderr_lines": len(err),
                         "temporaries_left": len(left)})
        finally:
            subprocess.run(["umount", str(disk)])
    return rows


def write_table(rows, enospc, seed, wall, out: Path) -> Path:
    lines = ["# Fault injection: SIGKILL at random instants, ENOSPC on small disks (issue 36)", "",
             f"`python benchmarks/fault_injection.py --seed {seed}` ({time.strftime('%Y-%m-%d')}, "
             f"{wall / 60:.1f} min, load {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs). Each kill is a "
             "SIGKILL of the command's whole process group at an instant drawn uniformly over an "
             "uninterrupted run's wall time (imports and setup included); `landed`: the process was "
             "still running. `checkpointed`: samples the newest valid checkpoints covered (run, study), "
             "or cache entries present and verified (reduce); `lost`: of those, rows that did not read "
             "back bit-identical to the uninterrupted run. `resumed`/`identical`: the same command "
             "again (`--resume` for run), and its result equal to the uninterrupted run's (every "
             "dataset bit for bit; reduce: the entry verifies; export: netCDF and CSV equal the "
             "reference). `temporaries`: unique temporaries a SIGKILL left (no process can clean up "
             "after SIGKILL; every other exit path removes them).", "",
             "| command | kills | landed | checkpointed | lost | resumed | identical | inputs changed | outputs damaged | temporaries left (after the rerun) | uninterrupted wall s |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['command']} | {r['kills']} | {r['landed']} | {r['checkpointed']} | {r['lost']} | "
                     f"{r['resumes']} | {r['identical']} | {r['inputs_changed']} | {r['outputs_damaged']} | "
                     f"{r['temporaries_left']} ({r.get('temporaries_after_rerun', '-')}) | {r.get('wall_s', 0):.1f} |")
    tot = {k: sum(r[k] for r in rows) for k in ("kills", "landed", "lost", "resumes", "identical")}
    lines += ["", f"Total: {tot['kills']} kills ({tot['landed']} landed while running), {tot['lost']} samples "
              f"lost, {tot['identical']} of {tot['resumes']} reruns identical.", ""]
    fails = [f"- {r['command']}: {f}" for r in rows for f in r["failures"]]
    if fails:
        lines += ["Failures:", *fails, ""]
    lines += ["## ENOSPC", "", "| command | disk | outcome | checkpoint | lost | temporaries left | resume identical |",
              "|---|---|---|---|---|---|---|"]
    for e in enospc:
        lines.append(f"| {e['command']} | {e.get('size', '')} | {e.get('outcome', '')} | {e.get('checkpoint', '')} | "
                     f"{e.get('lost', '')} | {e.get('temporaries_left', '')} | {e.get('resume_identical', '')} |")
    out.write_text("\n".join(lines) + "\n")
    (out.with_suffix(".json")).write_text(json.dumps({"rows": rows, "enospc": enospc}, indent=1, default=str))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=36)
    ap.add_argument("--kills-scale", type=float, default=1.0, help="multiply every command's kill count")
    ap.add_argument("--work", default="/tmp/flexbearing-fault-injection")
    ap.add_argument("--only", nargs="*", default=None, help="some of: fake real study reduce report enospc")
    ap.add_argument("--table", default=str(ROOT / "benchmarks" / "results" / "fault_injection.md"))
    a = ap.parse_args()
    rng = random.Random(a.seed)
    work = Path(a.work)
    shutil.rmtree(work, ignore_errors=True)
    n = {k: max(1, round(v * a.kills_scale)) for k, v in
         {"fake": 40, "real": 20, "study": 15, "reduce": 15, "report": 10, "export": 10}.items()}
    t0 = time.perf_counter()
    rows = []
    for name, fn in (("fake", lambda: [bench_fake_run(rng, work / "fake", n["fake"])]),
                     ("real", lambda: [bench_real_run(rng, work / "real", n["real"])]),
                     ("study", lambda: [bench_study(rng, work / "study", n["study"])]),
                     ("reduce", lambda: [bench_reduce(rng, work / "reduce", n["reduce"])]),
                     ("report", lambda: bench_report_export(rng, work / "report", n["report"], n["export"]))):
        if a.only is not None and name not in a.only:
            continue
        print(f"fault injection: {name} ...", flush=True)
        rows += fn()
        print(json.dumps(rows[-1], default=str)[:400], flush=True)
    enospc = [] if a.only is not None and "enospc" not in a.only else bench_enospc(work / "enospc") if os.geteuid() == 0 else [
        {"command": "ENOSPC", "outcome": "skipped (mounting a tmpfs needs root)"}]
    print(write_table(rows, enospc, a.seed, time.perf_counter() - t0, Path(a.table)))


if __name__ == "__main__":
    main()
