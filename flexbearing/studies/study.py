"""One scene run over a range of a parameter (the paper's §4.4 studies): the work of `flexbearing study`.

    flexbearing study STUDY.toml [-o DIR] [--workers N] [--scheduler ADDRESS] [--quiet]   (flexbearing.cli.study)

The paper (Yang, Liu & Deng 2025, §4.4, Figs. 23–34) varies one parameter of its unsteady case
at a time (axial load 45–65 kN, radial load 4–8 kN, speed 11,000–15,000 rpm, groove curvature
coefficients fe 0.51–0.53 and fi 0.515–0.535) and reads off the contact stresses, the pocket and
guiding forces, the cage's maximum von Mises stress and the film thickness. A study file says
the same thing:

    [study]
    name = "axial_load"
    description = "Paper §4.4.1: axial load 45-65 kN at Fr = 4 kN, unsteady case"
    scene = "paper_unsteady.toml"           # the base scene, relative to this file
    keys = ["operation.load.axial_load"]    # scene keys to set, dotted; [i] indexes a list
    values = [45e3, 50e3, 55e3, 60e3, 65e3] # one run each: a scalar (every key takes it) or a
                                            #   list with one value per key; a string for a
                                            #   string key (cage.cad: a CAD file relative to
                                            #   this file, checked to exist before any run)
    label = "Axial load"                    # of the parameter, for tables and plots
    unit = "N"                              # SI unit of the values (the scene's)
    display_unit = "kN"                     # optional: printed unit and its
    display_scale = 1e-3                    #   factor from SI (default: unit, 1)
    settle = 0.05                           # s left out of every statistic (start-up transient)

Each run is the base scene with the keys set (intermediate tables are created, list items must
exist); every run's scene is validated before anything is integrated, and a value that makes it
invalid is refused naming the value and the scene's own message. Runs stream to
DIR/<name>/<name>_<i>.h5 and resume like `flexbearing run --resume`: a finished run is reused, an
interrupted study continues where it stopped. The runs are jobs on Dask (flexbearing.simulation.jobs):
`--workers N` runs N at once on a LocalCluster (default: one per CPU; 1: one after the other in
this process), `--scheduler tcp://HOST:PORT` on an existing Dask cluster; each run is the same
deterministic integration wherever it runs. A flexible cage's reduced cage is built (or found in
the cache) once per distinct cage before the runs start and reaches them by path; its first
elastic modes (flexbearing.studies.cage_modes: frequency, family, wave number) go into the
study's table of cage modes, one row per variant. A run that fails is reported and the others go on.

A cage study varies the cage: `keys = ["cage.pocket_diameter"]`, `["cage.land_width"]`, a web
(`["cage.outside_diameter"]`, ...) or `keys = ["cage.cad"]` with `values = ["a.step", "b.step"]`
(each run's cage from its CAD file; the table's first column then names the file and the plots
put the runs side by side in the order given).

Results, in DIR/<name>/:

    study.json   every window statistic of every run (flexbearing.analysis.windows.phase_table: the whole run,
                 each phase of the speed profile, each impact; peak, p99 and mean of each quantity;
                 the cage's motion, flexbearing.analysis.windows.cage_motion_table, as cage_<key>: eccentricity
                 ratio, share on the rim, whirl ratio, centre speed, velocity dispersion, time held
                 at one azimuth), SI, with
                 the value of the parameter and the run's wall time; a flexible cage's first
                 elastic modes (cage_modes)
    study.md     per quantity, its peak, p99 and mean in each window against the parameter; the
                 cage motion per window
    study.html   the same with the plots, one self-contained page (flexbearing.analysis.html_page)
    <quantity>.png  the same as plots, one line per window (the paper's Figs. 23–34)

Windows are matched across runs by position (whole run, phase k of the speed profile, impact k),
since a phase's label carries its speed, which a speed study changes; a window the settle time
leaves empty is left out.
"""
from __future__ import annotations

import copy
import json
import math
import os
import re
import time
from dataclasses import dataclass
from pathlib import Path
import signal
import sys
import threading

from flexbearing.analysis.html_page import write_html
from flexbearing.analysis.windows import (cage_motion_table, impact_windows, MOTION_ROWS, phase_table,
                                          QUANTITIES, QUANTITY, speed_phases)
from flexbearing.common.validation import InputError, require_table
from flexbearing.coupling.flexible_cage import (backend as flexible_backend, reduced_cage_hash,
                                                reduced_cage_path)
from flexbearing.simulation.jobs import require_scheduler, require_workers, run_jobs, runs_in_this_process
from flexbearing.simulation.run import finished_run, run_scene
from flexbearing.simulation.scene import _number, parse_scene, read_toml
from flexbearing.simulation.stopped import Incomplete
from flexbearing.fem_cage.reduced_cage import find_cached
from flexbearing.studies.cage_modes import cage_modes, mode_cell

STUDY_KEYS = ("name", "description", "scene", "keys", "values", "label", "unit", "display_unit",
              "display_scale", "settle")
# keys whose string values name files, relative to the study file
FILE_KEYS = ("cage.cad",)
_PATH_PART = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)$")


class StudyIncomplete(Incomplete):
    """Some runs of a study failed (`run_study`, or its reduced cages); the others are finished and on
    disk, and running the study again reuses them (the family: flexbearing.simulation.stopped)."""


@dataclass(frozen=True)
class Study:
    name: str
    description: str
    scene_path: str
    keys: tuple            # dotted scene keys
    values: tuple          # per run: a tuple with one value per key
    label: str
    unit: str
    display_unit: str
    display_scale: float
    settle: float          # s
    scenes: tuple          # per run: the validated flexbearing.simulation.scene.Scene
    path: str = ""

    @property
    def parameter(self) -> list[float]:
        """The first key's value of each run (the plots' abscissa), SI; a string value (a file)
        has none: the run's index stands for it."""
        return [float(i) if isinstance(v[0], str) else float(v[0]) for i, v in enumerate(self.values)]

    def value_text(self, i: int) -> str:
        """The first key's value of run i as printed: in the display unit, or a file's name."""
        v = self.values[i][0]
        if isinstance(v, str):
            return Path(v).name
        return f"{v * self.display_scale:g}"

    @property
    def axis_label(self) -> str:
        """The parameter's name with its printed unit, for table heads and plot axes."""
        return f"{self.label} [{self.display_unit}]" if self.display_unit else self.label


def _split_key(key: str, where: str) -> list:
    """'operation.speed.phases[1].rpm' -> ['operation', 'speed', 'phases', 1, 'rpm']."""
    parts = []
    for part in key.split("."):
        m = _PATH_PART.match(part)
        if not m:
            raise InputError(f"{where} = {key!r} is not a scene key; allowed: names joined by '.', "
                             f"list items as name[i], e.g. 'operation.speed.phases[1].rpm'")
        parts.append(m.group(1))
        parts.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    return parts


def set_key(data: dict, parts: list, value, where: str) -> None:
    """Set data[p0][p1]... = value in a parsed scene: missing tables are created, list items must
    exist (a study changes values, not the number of phases or impacts)."""
    node = data
    for i, p in enumerate(parts[:-1]):
        nxt = parts[i + 1]
        if isinstance(p, int):
            if not isinstance(node, list) or p >= len(node):
                raise InputError(f"{where}: item [{p}] does not exist in the base scene")
            node = node[p]
            continue
        if not isinstance(node, dict):
            raise InputError(f"{where}: {p!r} is not inside a table of the base scene")
        if p not in node:
            if isinstance(nxt, int):
                raise InputError(f"{where}: list {p!r} does not exist in the base scene")
            node[p] = {}
        node = node[p]
    last = parts[-1]
    if isinstance(last, int):
        if not isinstance(node, list) or last >= len(node):
            raise InputError(f"{where}: item [{last}] does not exist in the base scene")
    elif not isinstance(node, dict):
        raise InputError(f"{where}: {last!r} is not inside a table of the base scene")
    node[last] = value


def load_study(path) -> Study:
    """Read and validate a study file and build (and validate) the scene of every run."""
    path = Path(path)
    data = read_toml(path, "study file")
    require_table("study file", data, ("study",))
    s = require_table("study", data.get("study", {}), STUDY_KEYS)
    for k in ("name", "scene", "keys", "values"):
        if k not in s:
            raise InputError(f"study.{k} is missing")
    name = s["name"]
    # the name is a folder under the output directory: '.' and '..' would put the runs outside it
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.-]+", name) or set(name) == {"."}:
        raise InputError(f"study.name = {name!r} is not allowed; allowed: letters, digits, '_', '-', '.' "
                         f"(not '.' or '..' alone: the name is the study's folder under the output directory)")
    keys = s["keys"]
    if isinstance(keys, str):
        keys = [keys]
    if not isinstance(keys, list) or not keys or not all(isinstance(k, str) for k in keys):
        raise InputError(f"study.keys = {s['keys']!r} is not allowed; allowed: a scene key or a non-empty list of them")
    split = [_split_key(k, f"study.keys[{i}]") for i, k in enumerate(keys)]
    values = s["values"]
    if not isinstance(values, list) or not values:
        raise InputError(f"study.values = {values!r} is not allowed; allowed: a non-empty list, one entry per run")
    runs = []
    for i, v in enumerate(values):
        where = f"study.values[{i}]"
        if isinstance(v, list):
            if len(v) != len(keys):
                raise InputError(f"{where} = {v!r} has {len(v)} entries; allowed: one per key ({len(keys)})")
            runs.append(tuple(_value(f"{where}[{j}]", x, keys[j], path) for j, x in enumerate(v)))
        else:
            runs.append(tuple(_value(where, v, k, path) for k in keys))
    unit = s.get("unit", "")
    scale = _number("study.display_scale", s.get("display_scale", 1.0), 0.0, None, lo_open=True)
    settle = _number("study.settle", s.get("settle", 0.0), 0.0, None, unit="s")
    scene_file = (path.parent / s["scene"]).resolve()
    base = read_toml(scene_file, f"study.scene = {s['scene']!r}: scene")
    scenes = []
    for i, v in enumerate(runs):
        d = copy.deepcopy(base)
        for j, (k, parts) in enumerate(zip(keys, split)):
            set_key(d, parts, v[j], f"study.keys[{j}] = {k!r}")
        d["name"] = f"{name}_{i}"
        setting = ", ".join(f"{k} = {_text(x)}" for k, x in zip(keys, v))
        d["description"] = f"{s.get('description', name)}: {setting}"
        try:
            # no TOML text: the results file then keeps the run's own parsed scene (as JSON), which
            # `flexbearing report` reads back, so each file says exactly what ran
            sc = parse_scene(d, text="", path=f"{scene_file} with {setting}")
        except InputError as exc:
            raise InputError(f"study.values[{i}] ({setting}) makes the scene invalid: {exc}") from None
        if sc.duration <= settle:
            raise InputError(f"study.settle = {settle:g} s leaves nothing of run {i} "
                             f"(duration {sc.duration:g} s); allowed: [0, {sc.duration:g}) s")
        scenes.append(sc)
    return Study(name=name, description=str(s.get("description", "")), scene_path=str(scene_file),
                 keys=tuple(keys), values=tuple(runs), label=str(s.get("label", keys[0])),
                 unit=str(unit), display_unit=str(s.get("display_unit", unit)), display_scale=float(scale),
                 settle=float(settle), scenes=tuple(scenes), path=str(path))


def _value(where: str, x, key: str, study_path: Path):
    """A study value: a number, or a string for a string key; a file key's string is a file
    relative to the study file, which must exist (refused before any run)."""
    if not isinstance(x, str):
        return _number(where, x)
    if key not in FILE_KEYS:
        return x                     # a string key (cage.guidance, ...): the scene validates it
    f = Path(x)
    if not f.is_absolute():
        f = (study_path.parent / f).resolve()
    if not f.is_file():
        raise InputError(f"{where} = {x!r}: no such file (for {key}, relative to the study file "
                         f"{str(study_path)!r})")
    return str(f)


def _text(x) -> str:
    return Path(x).name if isinstance(x, str) and ("/" in x or "\\" in x) else (x if isinstance(x, str) else f"{x:g}")


# ---------------------------------------------------------------- running

def run_path(out_dir, study: Study, i: int) -> Path:
    return Path(out_dir) / study.name / f"{study.name}_{i}.h5"


def _run_one(scene, path: str, quiet: bool, reduced_cage: str | None = None) -> dict:
    """One run of a study (a job of flexbearing.simulation.jobs.run_jobs, on a Dask worker): run or resume it;
    a flexible cage's reduced cage comes from the file built once for the study (by path)."""
    backend = None
    if reduced_cage is not None:
        backend = flexible_backend(scene, reduced_cage=reduced_cage)
    return run_scene(scene, path, resume=True, quiet=quiet, backend=backend)


def _import_gmsh_off_the_main_thread() -> None:
    """Import gmsh on a Dask worker's task thread. gmsh 4.8 sets SIGINT with signal.signal when it
    is imported and puts the old handler back in finalize(), and Python allows signal.signal in
    the main thread only ("signal only works in main thread"): so it is imported here with
    signal.signal a no-op, and with no handler to restore; the worker's own SIGINT stays as it is.
    Later `import gmsh` statements find the module imported."""
    if "gmsh" in sys.modules:
        sys.modules["gmsh"].oldsig = None
        return
    real = signal.signal
    signal.signal = lambda *args: None
    try:
        import gmsh
    finally:
        signal.signal = real
    gmsh.oldsig = None


def _build_reduced_cage(scene, quiet: bool) -> str:
    """The reduced cage of the scene: from the cache or built (a job: on a worker, which imports the
    FE stack; the file lock of the cache makes a second builder wait). Returns its path."""
    if threading.current_thread() is not threading.main_thread():
        _import_gmsh_off_the_main_thread()
    return str(Path(reduced_cage_path(scene, quiet=quiet)).resolve())


def _prepare_reduced_cages(study: Study, todo: list[int], quiet: bool, workers, scheduler) -> dict:
    """Each distinct reduced cage of the runs `todo` (by content hash, flexbearing.coupling.flexible_cage.
    reduced_cage_hash) built or found in the cache once, before the runs start (otherwise every
    worker would build the same one). Returns {hash: path}: the runs reach it by path."""
    distinct = {}
    for i in todo:
        sc = study.scenes[i]
        if sc.cage_model == "flexible":
            distinct.setdefault(reduced_cage_hash(sc), sc)
    if not distinct:
        return {}
    hashes = list(distinct)
    paths = {}
    failures = run_jobs(_build_reduced_cage, [(distinct[h], quiet) for h in hashes],
                        lambda k, p: paths.__setitem__(hashes[k], p),
                        workers=workers,
                        scheduler=scheduler, names=[f"reduced cage {h}" for h in hashes],
                        description="reduced cages", progress=False)
    if failures:
        raise StudyIncomplete("building the reduced cage failed: " + "; ".join(map(str, failures)),
                              failures=failures)
    return paths


STUDY_FILES = ("study.json", "study.md", "study.html")
STUDY_PLOT_PATTERNS = ("*.png",)     # write_study_plots: one per quantity


def study_outputs(study: Study, out_dir, option: str = "-o"):
    """Every file `run_study` writes (flexbearing.common.safe_files.OutputPlan): in out_dir/<name>
    each run's results file and summary (run_path; a results file there is continued), the study's
    page (STUDY_FILES) and its plots. The inputs: the study file and its base scene. Both folders
    are declared: neither may be a link or a file."""
    from flexbearing.common.safe_files import OutputPlan
    from flexbearing.simulation.results import summary_path
    plan = OutputPlan("flexbearing study", inputs=[study.path or None, study.scene_path or None]
                      + [sc.path or None for sc in study.scenes])
    plan.folder(out_dir, option)
    plan.folder(Path(out_dir) / study.name, option, names=STUDY_FILES, patterns=STUDY_PLOT_PATTERNS)
    for i in range(len(study.scenes)):
        plan.file(run_path(out_dir, study, i), option, h5_kind="results file of a run")
        plan.file(summary_path(run_path(out_dir, study, i)), option)
    return plan


def run_study(study: Study, out_dir, workers: int | None = None, quiet: bool = False,
              scheduler: str | None = None) -> dict:
    """Run (or resume) every run of the study and write study.json, study.md and the plots.
    Returns the study.json content.

    The runs are jobs of flexbearing.simulation.jobs.run_jobs: `workers` at once on a LocalCluster (None: one per
    CPU; 1: one after the other in this process) or on the Dask cluster at `scheduler`. A finished
    run (its results file complete, flexbearing.simulation.run.finished_run) is not sent out again. A run that
    fails does not stop the others: StudyIncomplete is raised once they are done."""
    workers = require_workers((os.cpu_count() or 1) if workers is None else workers)
    require_scheduler(scheduler)
    plan = study_outputs(study, out_dir).check()        # before any run: the one output rule
    folder = Path(out_dir) / study.name
    folder.mkdir(parents=True, exist_ok=True)
    n = len(study.scenes)
    summaries = {}
    t0 = time.perf_counter()

    def done(i, summary):
        summaries[i] = summary
        if not quiet:
            v = f"{study.value_text(i)} {study.display_unit}".rstrip()
            print(f"   run {i + 1}/{n} ({study.label} {v}): "
                  f"wall {summary.get('wall_time_s', float('nan')):.1f} s", flush=True)

    todo = []
    for i, sc in enumerate(study.scenes):
        summary = finished_run(sc, run_path(out_dir, study, i))
        if summary is None:
            todo.append(i)
        else:
            summaries[i] = summary
    if not quiet and len(todo) < n:
        print(f"   {n - len(todo)} of {n} runs already finished in {folder}: reused", flush=True)
    here = runs_in_this_process(workers, scheduler, len(todo))
    cages = _prepare_reduced_cages(study, todo, quiet, workers, scheduler) if todo else {}
    jobs = []
    for i in todo:
        sc = study.scenes[i]
        cage = cages.get(reduced_cage_hash(sc)) if sc.cage_model == "flexible" else None
        # on a cluster each run is quiet (one progress bar per process would garble the terminal);
        # the bar of run_jobs counts the runs instead (in this process it stands above each run's own)
        jobs.append((sc, str(run_path(out_dir, study, i)), quiet or not here, cage))
    failures = run_jobs(_run_one, jobs, lambda k, summary: done(todo[k], summary), workers=workers,
                        scheduler=scheduler, names=[f"run {i} ({sc.name})" for i, sc in
                                                    ((i, study.scenes[i]) for i in todo)],
                        description=f"study {study.name}", progress=not quiet)
    if failures:
        raise StudyIncomplete(f"{len(failures)} of {n} runs failed ({'; '.join(map(str, failures))}); "
                              f"the other runs are finished in {folder}: run the study again to retry "
                              f"the failed ones", failures=failures)
    result = collect(study, out_dir, summaries, _variant_cage_modes(study, cages))
    result["wall_time_s"] = time.perf_counter() - t0
    plan.check()                         # again: the runs took a while; then staged, renamed when whole
    with plan.writing():
        stage = plan.staging(folder)
        (stage / "study.json").write_text(json.dumps(result, indent=1, allow_nan=False, default=_json_default))
        plots = write_study_plots(study, result, stage)
        (stage / "study.md").write_text(study_markdown(study, result) + "\n## Plots\n\n"
                                        + "\n".join(f"![{p.stem}]({p.name})" for p in plots) + "\n")
        write_html(stage / "study.md")   # the tables and the plots in one self-contained page
    return result


def _variant_cage_modes(study: Study, cages: dict) -> dict:
    """Run index -> the first elastic modes of its reduced cage (flexbearing.studies.cage_modes),
    for the flexible-cage runs: the file built for this study, or (a run finished before) the
    cache's, not rebuilt when it is gone (the table then shows none)."""
    from flexbearing.coupling.flexible_cage import reduced_cage_key
    out, seen = {}, {}
    for i, sc in enumerate(study.scenes):
        if sc.cage_model != "flexible":
            continue
        h = reduced_cage_hash(sc)
        if h not in seen:
            path = cages.get(h) or find_cached(reduced_cage_key(sc))
            seen[h] = None if path is None else [m._asdict() for m in cage_modes(path)]
        if seen[h] is not None:
            out[i] = seen[h]
    return out


def _json_default(o):
    if hasattr(o, "item"):
        return o.item()
    raise TypeError(f"{type(o).__name__} is not JSON serialisable")


def window_ids(scene) -> dict:
    """Names of a run's report windows that are the same in every run of a study, by position:
    'whole run', 'phase k: <kind>' (k-th phase of the speed profile), 'impact k'; keyed by
    (kind group, t_end), which the settle time does not change (it moves t_start)."""
    ids = {}
    for k, ph in enumerate(speed_phases(scene), 1):
        ids[("phase", round(ph["t_end"], 12))] = f"phase {k}: {ph['kind']}"
    for k, imp in enumerate(impact_windows(scene), 1):
        ids[("impact", round(imp["t_end"], 12))] = f"impact {k}"
    return ids


def window_id(row: dict, ids: dict) -> str:
    if row["kind"] == "run":
        return "whole run"
    group = "impact" if row["kind"] == "impact" else "phase"
    return ids.get((group, round(row["t_end"], 12)), row["label"])


def collect(study: Study, out_dir, summaries: dict | None = None, cage_modes: dict | None = None) -> dict:
    """study.json content from the runs' results files (flexbearing.analysis.windows.phase_table each);
    `cage_modes`: run index -> its cage's first elastic modes (_variant_cage_modes)."""
    runs = []
    for i, (v, x) in enumerate(zip(study.values, study.parameter)):
        path = run_path(out_dir, study, i)
        ids = window_ids(study.scenes[i])
        windows = [{"window": window_id(row, ids), **row}
                   for row in phase_table(path, include_impacts=True, settle=study.settle)]
        # the cage's motion in its clearance over the same windows (same report_windows, same order)
        for w, m in zip(windows, cage_motion_table(path, include_impacts=True, settle=study.settle)):
            w.update({f"cage_{key}": m.get(key) for _, key, _, _ in MOTION_ROWS})
        s = (summaries or {}).get(i, {})
        runs.append({"index": i, "values": dict(zip(study.keys, v)), "parameter": x,
                     "parameter_text": study.value_text(i),
                     "results_file": str(path), "wall_time_s": s.get("wall_time_s"), "windows": windows,
                     **({"cage_modes": cage_modes[i]} if cage_modes and i in cage_modes else {})})
    return {"study": {"name": study.name, "description": study.description, "scene": study.scene_path,
                      "keys": list(study.keys), "label": study.label, "unit": study.unit,
                      "settle_s": study.settle},
            "runs": runs}


def _quantity_columns(result: dict) -> list[tuple[str, str]]:
    """(quantity key, statistic suffix) present in every run, in flexbearing.analysis.windows's order."""
    out = []
    for q in QUANTITIES:
        for stat in q.stats:
            col = f"{q.key}_{stat}"
            if all(any(w.get(col) is not None for w in r["windows"]) for r in result["runs"]):
                out.append((q.key, stat))
    return out


def study_table(result: dict, key: str, stat: str) -> tuple[list[str], list[list[float | None]]]:
    """(window ids, one row per run of the statistic in each window), SI."""
    return study_column(result, f"{key}_{stat}")


def study_column(result: dict, column: str) -> tuple[list[str], list[list[float | None]]]:
    """(window ids, one row per run of the window value `column`, e.g. "pocket_force_p99" or
    "cage_velocity_dispersion"), SI."""
    ids = list(dict.fromkeys(w["window"] for r in result["runs"] for w in r["windows"]))
    rows = []
    for r in result["runs"]:
        by_id = {w["window"]: w for w in r["windows"]}
        rows.append([by_id.get(i, {}).get(column) for i in ids])
    return ids, rows


def _markdown_rows(study: Study, result: dict, title: str, column: str, cell) -> list[str]:
    ids, rows = study_column(result, column)
    lines = [f"## {title}", "", "| " + " | ".join([study.axis_label] + ids) + " |", "|" + "---:|" * (len(ids) + 1)]
    for r, vals in zip(result["runs"], rows):
        cells = [r["parameter_text"]] + ["–" if x is None else cell(x) for x in vals]
        lines.append("| " + " | ".join(cells) + " |")
    return lines + [""]


def study_markdown(study: Study, result: dict) -> str:
    lines = [f"# Study {study.name}", "", study.description, "",
             f"Base scene `{study.scene_path}`; varied: {', '.join(f'`{k}`' for k in study.keys)}; "
             f"statistics after {study.settle:g} s (flexbearing.analysis.windows: peak = worst ball and instant, "
             f"p99 = 99th percentile over the window's samples of the worst ball (p1 of the "
             f"thinnest film), mean = over balls and time; cage motion as flexbearing.analysis.cage_motion: "
             f"eccentricity ratio, whirl ratio, velocity dispersion std/mean of the centre's speed, "
             f"time held at one azimuth).", ""]
    for key, stat in _quantity_columns(result):
        q = QUANTITY[key]
        lines += _markdown_rows(study, result, f"{q.label}, {stat} [{q.display_unit}]", f"{key}_{stat}",
                                lambda x, q=q: f"{x * q.scale:.4g}")
    for label, key, scale, fmt in MOTION_ROWS:      # the cage's motion in its clearance (flexbearing.analysis.cage_motion)
        if any(w.get(f"cage_{key}") is not None for r in result["runs"] for w in r["windows"]):
            lines += _markdown_rows(study, result, f"Cage motion: {label}", f"cage_{key}",
                                    lambda x, s=scale, f=fmt: f.format(x * s))
    lines += cage_modes_markdown(study, result)
    return "\n".join(lines)


def cage_modes_markdown(study: Study, result: dict) -> list[str]:
    """The table of each variant's first elastic cage modes (frequency, family, n), when the runs
    have a flexible cage."""
    runs = [r for r in result["runs"] if r.get("cage_modes")]
    if not runs:
        return []
    numbers = list(dict.fromkeys(m["mode"] for r in runs for m in r["cage_modes"]))
    lines = ["## Cage modes", "",
             "First elastic modes of each variant's reduced cage (free–free, Craig–Bampton Ritz values; "
             "numbered with the 6 rigid modes; family and circumferential wave number n, "
             "flexbearing.fem_cage.classify).", "",
             "| " + " | ".join([study.axis_label] + [f"mode {k}" for k in numbers]) + " |",
             "|" + "---:|" * (len(numbers) + 1)]
    for r in runs:
        by = {m["mode"]: m for m in r["cage_modes"]}
        lines.append("| " + " | ".join([r["parameter_text"]] + [mode_cell(by[k]) if k in by else "–"
                                                                for k in numbers]) + " |")
    return lines + [""]


def write_study_plots(study: Study, result: dict, folder) -> list[Path]:
    """One PNG per quantity: peak, p99 and mean (left to right) against the parameter, one line
    per window (whole run, phases, impacts)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    folder = Path(folder)
    files = any(isinstance(v[0], str) for v in study.values)
    x = [r["parameter"] * (1.0 if files else study.display_scale) for r in result["runs"]]
    paths = []
    cols = _quantity_columns(result)
    for key in dict.fromkeys(k for k, _ in cols):
        q = QUANTITY[key]
        stats = [s for k, s in cols if k == key]
        fig, axes = plt.subplots(1, len(stats), figsize=(5.2 * len(stats), 3.8), squeeze=False)
        for ax, stat in zip(axes[0], stats):
            ids, rows = study_table(result, key, stat)
            for j, wid in enumerate(ids):
                y = [math.nan if r[j] is None else r[j] * q.scale for r in rows]
                style = dict(lw=2.2, color="k") if wid == "whole run" else dict(lw=1.2, marker="o", ms=3)
                ax.plot(x, y, label=wid, **style)
            ax.set_xlabel(study.axis_label)
            if files:                                   # the runs side by side, named by their file
                ax.set_xticks(x, [r["parameter_text"] for r in result["runs"]], rotation=20, fontsize=7)
            ax.set_ylabel(f"{q.label}, {stat} [{q.display_unit}]")
            ax.grid(alpha=0.3)
        axes[0][0].legend(fontsize=7)
        fig.suptitle(f"{study.name}: {q.label}", fontsize=10)
        fig.tight_layout()
        p = folder / f"{key}.png"
        fig.savefig(p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths
