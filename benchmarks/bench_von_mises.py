"""Cost of the exact max-von-Mises search on the paper cage (flexbearing.fem_cage.von_mises), per mesh.

For each reduction mesh (default: today's default mesh and 4 mm, the valid mesh of issue 24;
pocket size min(default, size) as flexbearing.coupling.flexible_cage.reduced_cage_path does):

1. Real states. The paper's unsteady scene (scenes/paper_unsteady.toml on that mesh) is run from
   0 to T_REAL = 0.11 s (acceleration ramp and the first 50 kN impact) with the run's monitor
   tracing every accepted step's load-space vector y = (Omega^2, q_kept, node loads)
   (flexbearing.multibody.stress_peak). The trace is replayed through a fresh search exactly as the run calls
   it (threshold = the peak of the current 0.1 ms sample interval, seed = the node of the last
   new maximum), in a compiled loop: CPU time per call and the search's counts per call (groups
   opened, leaves refreshed, leaves scanned, exact node evaluations). Exactness: the recorded
   maximum of every sample interval against brute force (every node, the same node kernel) over
   every step of the interval; must be bitwise equal. The stateless modal search of the previous
   version (MaxVonMises: leaf/group centre bounds over the modal coordinates) on every 50th
   state, for comparison.
2. Random states (independent vectors: the worst case for a search built on time coherence):
   'typical' (Omega^2 ~ U(0, 5e5) rad^2/s^2, kept modes ~ N(0, (1e-6)^2), node loads ~ N(0, 50^2)
   N and N m) and 'unit' (every coordinate N(0, 1)); mismatches against brute force (must be 0),
   cost per call, counts.
3. With --scenes: the full unsteady scene (0.6 s) on each mesh, recording everything (von Mises
   included) and without von Mises: loop wall time and steps (flexbearing.simulation.run summary).

Timer: CPU time of this process for the replays (the machine is shared), wall time for the
scenes. Writes benchmarks/results/von_mises.json and von_mises.md.

    nice -n 5 .venv/bin/python benchmarks/bench_von_mises.py [--mesh-sizes 5e-3,4e-3] [--scenes]
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results"
T_REAL = 0.11
N_RANDOM = 300


def scene_text(mesh_size: float, duration: float | None = None, von_mises: bool = True) -> str:
    """scenes/paper_unsteady.toml on another mesh; cut to its first `duration` s (<= 0.2: the
    acceleration ramp at the same rate, the impacts inside it) and without von Mises if asked."""
    text = (ROOT / "scenes" / "paper_unsteady.toml").read_text()
    text = text.replace("n_modes = 26 ", f"mesh_size = {mesh_size!r}\nn_modes = 26 ", 1)
    if not von_mises:
        text = text.replace(', "von_mises"]', "]")
    if duration is not None:
        lines = []
        for line in text.splitlines():
            if line.startswith("duration = 0.6"):
                line = f"duration = {duration!r}"
            elif 'kind = "ramp",    duration = 0.2, start_rpm = 10000' in line:
                line = (f'  {{ kind = "ramp", duration = {duration!r}, start_rpm = 10000, '
                        f'end_rpm = {10000 + 20000 * duration!r} }},')
            elif 'kind = "uniform"' in line or "start_rpm = 14000, end_rpm = 10000" in line:
                continue
            lines.append(line)
        head, *impacts = "\n".join(lines).split("[[operation.load.impacts]]")
        kept = [head]
        for block in impacts:
            if float(block.split("t_center =")[1].split()[0]) < duration:
                kept.append(block)
            elif "\n[" in block:                          # keep the sections after the impacts
                kept[-1] += "\n[" + block.split("\n[", 1)[1]
        text = "[[operation.load.impacts]]".join(kept)
    return text


def traced_run(mesh_size: float, tmp: Path):
    """Run the first T_REAL s with the monitor tracing every step: (StressRecovery, t, y, dt)."""
    from flexbearing.coupling import flexible_cage as fc
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    from flexbearing.multibody.stress_peak import trace
    scene = loads_scene(scene_text(mesh_size, T_REAL), f"paper_unsteady_{mesh_size}.toml")
    made = []
    monitor = fc.StressRecovery.monitor

    def traced(self, cage_offset, modes_offset, trace=0):
        mon = monitor(self, cage_offset, modes_offset, trace=int(T_REAL * 4e5))
        made.append((self, mon))
        return mon

    fc.StressRecovery.monitor = traced
    try:
        run_scene(scene, tmp / f"trace_{mesh_size}.h5", force=True, quiet=True)
    finally:
        fc.StressRecovery.monitor = monitor
    rec, mon = made[0]
    t, y = trace(mon)
    return rec, t, y, scene.sample_interval


def _replay_loop():
    from numba import njit
    from flexbearing.fem_cage.von_mises import tracking_max_sq

    @njit(cache=True)
    def replay(arrays, Y, interval, out, counts, seed):
        """The monitor's calls: threshold = the interval's peak, seed = last new maximum."""
        peak = -1.0
        for i in range(Y.shape[0]):
            if i > 0 and interval[i] != interval[i - 1]:
                peak = -1.0
            b, a = tracking_max_sq(arrays, Y[i], peak, seed)
            if a >= 0:
                peak = b
                seed[0] = a
            out[i] = peak
            for j in range(4):
                counts[i, j] = arrays[-1][j]
    return replay


def _brute_all(A, Y):
    from numba import njit
    from flexbearing.fem_cage.von_mises import brute_force_max_sq

    @njit(cache=True)
    def run(A, Y, out):
        for i in range(Y.shape[0]):
            out[i] = brute_force_max_sq(A, Y[i])[0]
    out = np.zeros(len(Y))
    run(A, Y, out)
    return out


def bench_mesh(mesh_size: float, tmp: Path, quiet: bool) -> dict:
    from flexbearing.coupling.flexible_cage import StressRecovery
    from flexbearing.fem_cage.von_mises_search import MaxVonMises
    rec, t, Y, dt = traced_run(mesh_size, tmp)
    rc = rec.rc
    t0 = time.perf_counter()
    rec = StressRecovery(rc, rec.n_keep)                  # a fresh search (setup timed)
    setup = time.perf_counter() - t0
    ev = rec.search
    interval = np.floor(t / dt - 1e-9).astype(np.int64)
    replay = _replay_loop()
    out = np.zeros(len(Y))
    counts = np.zeros((len(Y), 4), dtype=np.int64)
    seed = -np.ones(1, dtype=np.int64)
    replay(ev.arrays, Y[:20], interval[:20], out[:20], counts[:20], seed)     # compile
    ev.reset()
    seed[:] = -1
    c0 = time.process_time()
    replay(ev.arrays, Y, interval, out, counts, seed)
    cpu = time.process_time() - c0
    brute = _brute_all(ev.A, Y)
    ends = np.r_[np.nonzero(np.diff(interval))[0], len(Y) - 1]
    starts = np.r_[0, ends[:-1] + 1]
    mism = sum(brute[a:b + 1].max() != out[b] for a, b in zip(starts, ends))
    c0 = time.process_time()
    _brute_all(ev.A, Y[:100])
    brute_us = (time.process_time() - c0) / 100 * 1e6
    # the previous version's stateless modal search on the same states
    scale = np.zeros_like(rec.omega)
    scale[6:] = 1.0 / rec.omega[6:]
    t0 = time.perf_counter()
    old = MaxVonMises(rc.stress_modes, mode_scale=scale)
    old_setup = time.perf_counter() - t0
    Q = np.array([rec.full_coordinates_of(y) for y in Y[::50]])
    old(Q[0])
    c0 = time.process_time()
    old_vals = [old(q)[0] for q in Q]
    old_us = (time.process_time() - c0) / len(Q) * 1e6
    old_exact = float(np.mean([old.visits(q)[1] for q in Q]))
    old_ok = all(v == old.brute_force(q)[0] for v, q in zip(old_vals, Q[:20]))
    row = {"mesh_size_m": mesh_size, "n_nodes": int(ev.A.shape[0]),
           "n_coordinates": int(ev.n_coordinates), "n_leaves": ev.n_leaves,
           "n_groups": ev.n_groups, "setup_s": setup,
           "real": {"t_end_s": T_REAL, "steps": int(len(Y)), "intervals": int(len(ends)),
                    "cpu_us_per_call": cpu / len(Y) * 1e6,
                    "mean_counts": dict(zip(("groups_opened", "leaves_refreshed", "leaves_scanned",
                                             "exact_evaluations"),
                                            counts.mean(axis=0).round(2).tolist())),
                    "max_exact_evaluations": int(counts[:, 3].max()),
                    "interval_mismatches_vs_brute": int(mism),
                    "brute_force_us_per_call": brute_us,
                    "previous_modal_search": {"setup_s": old_setup, "states": int(len(Q)),
                                              "cpu_us_per_call": old_us,
                                              "mean_exact_evaluations": old_exact,
                                              "equal_to_brute_on_20": bool(old_ok)}}}
    rng = np.random.default_rng(0)
    K, n_el = ev.n_coordinates, ev.n_tracked - 1
    for family in ("typical", "unit"):
        if family == "typical":
            Yr = np.c_[rng.uniform(0, 5e5, N_RANDOM), rng.normal(size=(N_RANDOM, n_el)) * 1e-6,
                       rng.normal(size=(N_RANDOM, K - 1 - n_el)) * 50.0]
        else:
            Yr = rng.normal(size=(N_RANDOM, K))
        ev.reset()
        c = []
        c0 = time.process_time()
        vals = []
        for y in Yr:
            vals.append(ev.row(y)[0])
            c.append(ev.count.copy())
        cpu = time.process_time() - c0
        b = _brute_all(ev.A, Yr)
        row[f"random_{family}"] = {"n": N_RANDOM, "mismatches_vs_brute": int(np.sum(np.array(vals) != b)),
                                   "cpu_us_per_call": cpu / N_RANDOM * 1e6,
                                   "mean_exact_evaluations": float(np.mean([x[3] for x in c])),
                                   "mean_leaves_refreshed": float(np.mean([x[1] for x in c]))}
    if not quiet:
        print(json.dumps(row, indent=1), flush=True)
    return row


def run_scenes(mesh_size: float, tmp: Path, quiet: bool) -> dict:
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    out = {}
    for label, vm in (("with_von_mises", True), ("without_von_mises", False)):
        scene = loads_scene(scene_text(mesh_size, von_mises=vm), f"paper_unsteady_{mesh_size}.toml")
        s = run_scene(scene, tmp / f"scene_{mesh_size}_{label}.h5", force=True, quiet=True)
        out[label] = {"loop_wall_s": s["wall_time_s"], "steps": s["n_steps"],
                      "setup_s": s["setup_time_s"]}
        if not quiet:
            print(mesh_size, label, out[label], flush=True)
    return out


def write_md(res: dict) -> None:
    lines = ["# Exact max von Mises search (flexbearing.fem_cage.von_mises), paper cage", "",
             "`nice -n 5 .venv/bin/python benchmarks/bench_von_mises.py"
             + (" --scenes" if res.get("scenes") else "") + "` (CPU time per call; one core)", "",
             "Real states: the run's own calls (threshold = the interval's peak, seed = the last "
             "maximum's node) replayed over every accepted step of the unsteady scene's first "
             f"{T_REAL} s (ramp + first 50 kN impact).", "",
             "| mesh | nodes | setup s | real: us/call | groups opened / leaves refreshed / exact "
             "per call | intervals exact vs brute | brute force us | previous modal search us "
             "(exact evals) | random typical us | random unit us |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["meshes"]:
        m, re_ = r["mesh_size_m"], r["real"]
        c = re_["mean_counts"]
        lines.append(
            f"| {m * 1e3:g} mm | {r['n_nodes']} | {r['setup_s']:.1f} | {re_['cpu_us_per_call']:.1f} "
            f"| {c['groups_opened']:.0f} / {c['leaves_refreshed']:.0f} / {c['exact_evaluations']:.1f} "
            f"| {re_['intervals'] - re_['interval_mismatches_vs_brute']}/{re_['intervals']} "
            f"| {re_['brute_force_us_per_call']:.0f} "
            f"| {re_['previous_modal_search']['cpu_us_per_call']:.0f} "
            f"({re_['previous_modal_search']['mean_exact_evaluations']:.0f}) "
            f"| {r['random_typical']['cpu_us_per_call']:.0f} | {r['random_unit']['cpu_us_per_call']:.0f} |")
    if res.get("scenes"):
        lines += ["", "Unsteady flexible scene (0.6 s), loop wall time:", "",
                  "| mesh | with von Mises s (steps) | without s (steps) |", "|---|---|---|"]
        for m, s in res["scenes"].items():
            w, wo = s["with_von_mises"], s["without_von_mises"]
            lines.append(f"| {float(m) * 1e3:g} mm | {w['loop_wall_s']:.1f} ({w['steps']}) | "
                         f"{wo['loop_wall_s']:.1f} ({wo['steps']}) |")
    (OUT / "von_mises.md").write_text("\n".join(lines) + "\n")


def main(argv=None):
    import tempfile
    import flexbearing.mesh.cage_mesh as cm
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mesh-sizes", default=f"{cm.DEFAULT_MESH_SIZE!r},4e-3")
    p.add_argument("--scenes", action="store_true")
    p.add_argument("--quiet", action="store_true")
    a = p.parse_args(argv)
    sizes = [float(s) for s in a.mesh_sizes.split(",")]
    res = {"meshes": [], "t_real_s": T_REAL}
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for m in sizes:
            res["meshes"].append(bench_mesh(m, tmp, a.quiet))
        if a.scenes:
            res["scenes"] = {repr(m): run_scenes(m, tmp, a.quiet) for m in sizes}
    OUT.mkdir(exist_ok=True)
    (OUT / "von_mises.json").write_text(json.dumps(res, indent=1))
    write_md(res)
    return res


if __name__ == "__main__":
    main()
