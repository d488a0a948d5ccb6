"""`flexbearing demo`: the paper's case end to end, on its built-in defaults.

1. the reduced flexible cage (Craig–Bampton, 26 modes) of the paper cage — built once, then cached;
2. the paper's steady scene (14,000 rpm, Fa 55 kN, Fr 4 kN, 0.6 s) and unsteady scene
   (10,000 -> 14,000 -> 14,000 -> 10,000 rpm in three 0.2 s phases, a 50 kN half-sine radial
   impact of 0.02 s centred in each phase), both with the flexible cage;
3. the report: per-phase tables (unsteady beside steady), time-history plots, the cage's von
   Mises field at the peaks and the ParaView scene of the second impact (cage, balls, rings).

Each step resumes: a run that was interrupted continues from its last checkpoint, a finished one
is reused. `--rigid` runs the rigid-cage scenes instead (no FE stack needed).
"""
from __future__ import annotations

import time
from pathlib import Path
from importlib.resources import files
from flexbearing.analysis.report import report_outputs, write_report
from flexbearing.common.safe_files import OutputPlan

SETTLE_S = 0.05
# the ParaView series of the report: the unsteady run's second impact (50 kN half-sine centred at
# 0.3 s, 0.02 s long), every 4th sample (51 frames, ~45 MB with the flexible cage)
SERIES = "0.29:0.31:4"
def _scenes_folder() -> Path:
    """The example scenes shipped with the package (pyproject.toml maps scenes/ to flexbearing.scenes)."""
    return Path(str(files("flexbearing.scenes")))


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "demo", help="the paper's steady and unsteady cases end to end (reduced cage, runs, report)",
        description=__doc__.split("\n\n")[0])
    p.add_argument("-o", "--output", default="out/demo", help="output folder (default out/demo)")
    p.add_argument("--rigid", action="store_true", help="rigid cage (skips the FE reduction)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=run)


def _scene_path(name: str, rigid: bool) -> Path:
    return _scenes_folder() / (f"{name}_rigid.toml" if rigid else f"{name}.toml")


NAMES = ("paper_steady", "paper_unsteady")


def planned_outputs(args) -> OutputPlan:
    """Every file `flexbearing demo -o DIR` writes: DIR/<scene>.h5 and its summary for each scene
    (flexbearing.simulation.run; a results file there is continued) and the report in DIR/report
    (flexbearing.analysis.report.report_outputs)."""
    from flexbearing.simulation.results import summary_path
    out = Path(args.output)
    scene_names = [f"{n}_rigid" if args.rigid else n for n in NAMES]    # the scenes' own names
    plan = OutputPlan("flexbearing demo", inputs=[_scene_path(n, bool(args.rigid)) for n in NAMES])
    plan.folder(out, "-o")
    for name in scene_names:
        plan.file(out / f"{name}.h5", "-o", h5_kind="results file of a run")
        plan.file(summary_path(out / f"{name}.h5"), "-o")
    rep = report_outputs(out / f"{scene_names[-1]}.h5", out / "report", out / f"{scene_names[0]}.h5")
    rep.inputs = []          # the runs are this command's own outputs, continued
    return plan.include(rep)


def run(args) -> int:
    from flexbearing.simulation.run import RunInterrupted, run_scene
    from flexbearing.simulation.scene import load_scene

    planned_outputs(args).check()                      # before any work: the one output rule
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    rigid = bool(args.rigid)
    t0 = time.perf_counter()
    results = {}
    for name in NAMES:
        scene = load_scene(_scene_path(name, rigid))
        path = out / f"{scene.name}.h5"
        print(f"== {scene.name}: {scene.duration:g} s simulated -> {path}", flush=True)
        try:
            summary = run_scene(scene, path, resume=True, quiet=args.quiet)
        except RunInterrupted as exc:
            print(f"flexbearing demo: {exc}")
            return 130 if isinstance(exc.__cause__, KeyboardInterrupt) else 1
        print(f"   wall {summary.get('wall_time_s', float('nan')):.1f} s, "
              f"{summary.get('n_steps', 0)} steps", flush=True)
        results[name] = path
    report_dir = out / "report"
    # the first 0.05 s is the start-up transient from the quasi-static initial state: not a result
    res = write_report(results["paper_unsteady"], report_dir, compare=results["paper_steady"],
                       settle=SETTLE_S, quiet=args.quiet, series=SERIES)
    print(f"== report: {report_dir}/report.html (and report.md: plots, tables"
          f"{'' if rigid else ', von Mises XDMF'}); ParaView series of impact 2 ({SERIES} s)")
    pv = res["paraview"] or {}
    print(f"== ParaView: {pv['state']} (File > Load State)" if pv.get("state") else f"== ParaView: {pv.get('note')}")
    print(f"flexbearing demo finished in {time.perf_counter() - t0:.0f} s")
    return 0
