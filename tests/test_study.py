"""`flexbearing study` (flexbearing.studies.study): a scene over a range of one parameter.

A two-run study of a short rigid-cage scene under pure thrust: each run carries its value (the
recorded external load), the study's tables are the runs' own report windows, and the mean
contact stresses follow the quasi-static solution at each load (the dynamic-vs-quasi-static
agreement of issue 4, here through the whole study pipeline). Then the input checks.
"""
import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from flexbearing.studies.study import load_study, run_study, study_table
from flexbearing.common.validation import InputError

BASE = """
name = "thrust"
description = "pure thrust, rigid cage"
[oil]
preset = "paper"
[cage]
model = "rigid"
[operation]
duration = 0.004
[operation.speed]
phases = [{ kind = "ramp", duration = 0.001, start_rpm = 13900, end_rpm = 14000 },
          { kind = "uniform", duration = 0.003, rpm = 14000 }]
[operation.load]
axial_load = 55e3
radial_load = 0.0
[integrator]
tolerance = 1e-6
initial_step = 1e-7
[output]
sample_interval = 1e-4
record = ["contact_stress", "ball_loads", "contact_angles", "pocket_force", "guiding_force", "cage_speed", "slip",
          "cage_orbit"]
"""

STUDY = """
[study]
name = "fa"
description = "axial load"
scene = "base.toml"
keys = ["operation.load.axial_load"]
values = [30e3, 55e3]
label = "Axial load"
unit = "N"
display_unit = "kN"
display_scale = 1e-3
settle = 0.0005
"""


def _write(folder: Path, study: str = STUDY, base: str = BASE) -> Path:
    (folder / "base.toml").write_text(base)
    p = folder / "study.toml"
    p.write_text(study)
    return p


@pytest.fixture(scope="module")
def thrust_study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    study = load_study(_write(folder))
    out = folder / "out"
    result = run_study(study, out, workers=1, quiet=True)
    return study, out, result


def test_each_run_carries_its_value(thrust_study):
    study, out, result = thrust_study
    assert [r["parameter"] for r in result["runs"]] == [30e3, 55e3]
    for r in result["runs"]:
        with h5py.File(r["results_file"], "r") as f:
            fx = f["outputs/external_load"][:, 0]
        assert np.all(fx == r["parameter"])
    for name in ("study.json", "study.md", "inner_contact_stress.png"):
        assert (out / "fa" / name).is_file()


def test_tables_are_the_runs_report_windows(thrust_study):
    """study.json holds flexbearing.analysis.windows.phase_table of each run unchanged (same settle), and the
    tables index the windows by position: whole run, phase 1 (the ramp), phase 2."""
    from flexbearing.analysis.windows import cage_motion_table, phase_table
    study, out, result = thrust_study
    saved = json.loads((out / "fa" / "study.json").read_text())
    for r in saved["runs"]:
        rows = phase_table(r["results_file"], include_impacts=True, settle=study.settle)
        motion = cage_motion_table(r["results_file"], include_impacts=True, settle=study.settle)
        assert [w["window"] for w in r["windows"]] == ["whole run", "phase 1: acceleration", "phase 2: uniform speed"]
        for w, row, m in zip(r["windows"], rows, motion):
            assert {k: v for k, v in w.items() if k != "window" and not k.startswith("cage_")} == pytest.approx(row)
            assert w["cage_eps_mean"] == pytest.approx(m["eps_mean"]) and m["eps_mean"] > 0.0
            assert w["cage_velocity_dispersion"] == pytest.approx(m["velocity_dispersion"])
    md = (out / "fa" / "study.md").read_text()
    assert "## Pocket force, p99 [N]" in md and "## Cage motion: Eccentricity ratio e/Cg, mean" in md
    assert (out / "fa" / "study.html").is_file()
    ids, rows = study_table(saved, "inner_contact_stress", "mean")
    assert rows[1][0] == saved["runs"][1]["windows"][0]["inner_contact_stress_mean"]


def test_mean_contact_stress_follows_the_quasi_static_solution(thrust_study):
    """Under pure thrust every ball carries the same load; the dynamic mean contact stresses of each
    run in its uniform-speed phase (the last 3 ms; free balls, traction and drag on) equal the quasi-static ones
    (outer-race control) at its load within 1.5 % (measured: outer −1.0 / −0.5 %, inner +0.1 / −0.2 %
    at 30 / 55 kN; the free balls' skid and the pockets shift the loads by that much), and they rise
    with the axial load as the paper's Fig. 23 shows."""
    from flexbearing.multibody.bearing import PAPER_BEARING
    from flexbearing.multibody.quasi_static import grooves_from_bearing, solve_quasi_static
    study, out, result = thrust_study
    g = grooves_from_bearing(PAPER_BEARING)
    means = []
    for r in result["runs"]:
        w = next(w for w in r["windows"] if w["window"] == "phase 2: uniform speed")
        q = solve_quasi_static(g, 14000 * math.pi / 30, fx=r["parameter"], control="outer")
        p_outer = q.p0[:, 0].mean()
        p_inner = np.max(q.p0[:, 1:], axis=1).mean()
        assert w["outer_contact_stress_mean"] == pytest.approx(p_outer, rel=0.015)
        assert w["inner_contact_stress_mean"] == pytest.approx(p_inner, rel=0.015)
        means.append((w["outer_contact_stress_mean"], w["inner_contact_stress_mean"]))
    assert means[1][0] > means[0][0] and means[1][1] > means[0][1]


def test_parallel_runs_and_resume_give_the_same_study(thrust_study, tmp_path):
    """--workers 2 (a Dask LocalCluster) gives the same windows to the last bit; running the study
    again reuses the finished runs (nothing is integrated twice); a study changed under the same
    output folder is refused instead of mixing old runs into it."""
    study, out, result = thrust_study
    again = run_study(study, out, workers=1, quiet=True)
    assert again["runs"] == result["runs"] or all(
        a["windows"] == b["windows"] for a, b in zip(again["runs"], result["runs"]))
    study2 = load_study(_write(tmp_path))
    par = run_study(study2, tmp_path / "out", workers=2, quiet=True)
    for a, b in zip(par["runs"], result["runs"]):
        assert [{k: v for k, v in w.items()} for w in a["windows"]] == b["windows"]
    changed = load_study(_write(tmp_path, STUDY.replace("values = [30e3, 55e3]", "values = [31e3, 55e3]")))
    with pytest.raises(InputError, match="different scene"):
        run_study(changed, tmp_path / "out", workers=1, quiet=True)


def test_keys_into_lists_and_paired_values(tmp_path):
    """A key may index a list (the speed phases) and several keys may move together: a speed study
    sets the ramp's end, the plateau and the next ramp's start to one value; a groove study sets
    fe and fi from one list per run."""
    base = BASE.replace("""phases = [{ kind = "ramp", duration = 0.001, start_rpm = 13900, end_rpm = 14000 },
          { kind = "uniform", duration = 0.003, rpm = 14000 }]""",
                        """phases = [{ kind = "ramp", duration = 0.002, start_rpm = 10000, end_rpm = 14000 },
          { kind = "uniform", duration = 0.001, rpm = 14000 },
          { kind = "ramp", duration = 0.001, start_rpm = 14000, end_rpm = 10000 }]""")
    speed = STUDY.replace('keys = ["operation.load.axial_load"]',
                          'keys = ["operation.speed.phases[0].end_rpm", "operation.speed.phases[1].rpm", '
                          '"operation.speed.phases[2].start_rpm"]').replace("values = [30e3, 55e3]",
                                                                           "values = [11000, 15000]")
    s = load_study(_write(tmp_path, speed, base))
    for v, sc in zip((11000, 15000), s.scenes):
        top = max(sc.speed_table[:, 1]) * 30 / math.pi
        assert top == pytest.approx(v, rel=1e-12)
    groove = STUDY.replace('keys = ["operation.load.axial_load"]', 'keys = ["bearing.fe", "bearing.fi"]').replace(
        "values = [30e3, 55e3]", "values = [[0.51, 0.515], [0.53, 0.535]]")
    s = load_study(_write(tmp_path, groove))
    assert [(sc.bearing.fe, sc.bearing.fi) for sc in s.scenes] == [(0.51, 0.515), (0.53, 0.535)]
    assert s.parameter == [0.51, 0.53]


@pytest.mark.parametrize("change, message", [
    (("[study]", "[study]\nbogus = 1"), "bogus"),
    (('scene = "base.toml"', 'scene = "missing.toml"'), "missing.toml"),
    (("values = [30e3, 55e3]", "values = []"), "study.values"),
    (("values = [30e3, 55e3]", "values = [30e3, -5.0]"), r"study.values\[1\].*axial_load"),
    (("values = [30e3, 55e3]", 'values = [30e3, "a lot"]'), r"study.values\[1\]"),
    (("values = [30e3, 55e3]", "values = [[30e3, 1.0]]"), "one per key"),
    (('keys = ["operation.load.axial_load"]', 'keys = ["operation.load.axial-load"]'), "not a scene key"),
    (('keys = ["operation.load.axial_load"]', 'keys = ["operation.speed.phases[5].rpm"]'), r"item \[5\]"),
    (('keys = ["operation.load.axial_load"]', 'keys = ["operation.load.bogus"]'), "bogus"),
    (("settle = 0.0005", "settle = 0.01"), "study.settle"),
    (('name = "fa"', 'name = "a b"'), "study.name"),
    (('name = "fa"', 'name = ".."'), "study.name"),     # the runs would land beside the output folder
    (('name = "fa"', 'name = "a/b"'), "study.name"),
])
def test_bad_study_files_are_refused_naming_the_field(tmp_path, change, message):
    with pytest.raises(InputError, match=message):
        load_study(_write(tmp_path, STUDY.replace(*change)))


def test_paper_studies_load():
    """The four studies of the paper's §4.4 (scenes/study_*.toml) and the numerical-scatter study
    beside them are valid, five runs each."""
    scenes = Path(__file__).resolve().parents[1] / "scenes"
    files = sorted(scenes.glob("study_*.toml"))
    assert [f.stem for f in files] == ["study_axial_load", "study_groove_curvature", "study_radial_load",
                                       "study_speed", "study_tolerance_scatter"]
    for f in files:
        s = load_study(f)
        assert len(s.scenes) == 5


def test_trend_verdict_false_alarm_rate():
    """benchmarks.study_trends.verdict: for a trendless statistic (every order of five values equally
    likely) a rank correlation |rho| >= 0.9 is reached by the monotone order and the four single
    adjacent swaps in each direction, 5 + 5 of the 120 orders (Spearman's rho = 1 - sum d^2 / 20
    for n = 5, so sum d^2 <= 2)."""
    import itertools
    from benchmarks.study_trends import verdict
    x = [1.0, 2.0, 3.0, 4.0, 5.0]
    counts = {"agrees": 0, "disagrees": 0, "no trend": 0}
    for order in itertools.permutations(range(5)):
        counts[verdict(x, [10.0 + k for k in order], +1)] += 1
    assert counts == {"agrees": 5, "disagrees": 5, "no trend": 110}
    assert verdict(x, [100, 101, 100.5, 100.2, 101.5], 0) == "agrees"         # 1.5 % change: flat
    assert verdict(x, [100, 103, 101, 100.2, 101.5], 2) == "agrees"           # inner 103 > both ends + 1 %
    assert verdict(x, [100, 100.5, 101, 101.5, 102], 2) == "disagrees"        # monotone


def test_trend_noise_from_the_scatter_study():
    """benchmarks.study_trends: the spread (max - min)/|mean| of each whole-run statistic over the
    scatter study's runs is its noise; a change first to last within it is "within noise"."""
    from benchmarks.study_trends import noise_levels, trend_lines

    def result(values, guiding):
        return {"study": {"description": "d", "label": "Axial load", "unit": "N"},
                "runs": [{"parameter": v, "windows": [{"window": "whole run", "guiding_force_mean": g,
                                                       "cage_eps_mean": 0.4 + 0.01 * i}]}
                         for i, (v, g) in enumerate(zip(values, guiding))]}
    noise = noise_levels(result([1, 2, 3, 4, 5], [95.0, 105.0, 100.0, 100.0, 100.0]))
    assert noise["guiding_force_mean"] == pytest.approx(0.10)
    assert noise["cage_eps_mean_abs"] == pytest.approx(0.04)
    rising = result([45e3, 50e3, 55e3, 60e3, 65e3], [100.0, 102.0, 104.0, 106.0, 108.0])   # +8 %, monotone
    row = next(l for l in trend_lines(rising, "axial_load", noise) if l.startswith("| Guiding force [N] | mean"))
    assert row.endswith("| 10.0 % | falls | within noise |")
    row = next(l for l in trend_lines(rising, "axial_load", {"guiding_force_mean": 0.05})
               if l.startswith("| Guiding force [N] | mean"))
    assert row.endswith("| 5.0 % | falls | disagrees |")


def test_a_study_on_a_cluster_of_separate_processes(thrust_study, dask_cluster, tmp_path, capsys):
    """`flexbearing study --scheduler ADDRESS` on a scheduler and two worker processes started as a
    cluster's are (tests/conftest.py DaskCluster): the same windows to the last bit as the runs
    one after the other in this process (each run is one deterministic integration)."""
    from flexbearing.cli import main as cli
    study, out, result = thrust_study
    path = _write(tmp_path)
    code = cli.main(["study", str(path), "-o", str(tmp_path / "out"), "--scheduler", dask_cluster.address,
                     "--quiet"])
    assert code == 0, capsys.readouterr().err
    saved = json.loads((tmp_path / "out" / "fa" / "study.json").read_text())
    for a, b in zip(saved["runs"], result["runs"]):
        assert a["windows"] == b["windows"]
    logs = " ".join((dask_cluster.folder / f"worker{i}.log").read_text() for i in range(2))
    assert "Traceback" not in logs


def test_a_failed_run_is_reported_the_others_finish_and_a_rerun_does_only_it(tmp_path, monkeypatch):
    """A run that raises does not stop the study: the other run finishes (its file complete), the
    study stops with StudyIncomplete naming the failed run; run again, only the failed run is sent
    out (a finished run is read back, flexbearing.simulation.run.finished_run) and the study completes."""
    import flexbearing.studies.study as S
    from flexbearing.simulation.run import finished_run
    real = S._run_one
    calls = []

    def first_fails(scene, path, quiet, cage=None):
        calls.append(scene.name)
        if scene.name == "fa_0":
            raise RuntimeError("disk full (simulated)")
        return real(scene, path, quiet, cage)

    monkeypatch.setattr(S, "_run_one", first_fails)
    study = load_study(_write(tmp_path))
    out = tmp_path / "out"
    with pytest.raises(S.StudyIncomplete, match=r"1 of 2 runs failed \(run 0 \(fa_0\): RuntimeError: disk full"):
        run_study(study, out, workers=1, quiet=True)
    assert finished_run(study.scenes[1], S.run_path(out, study, 1))["status"] == "complete"
    assert finished_run(study.scenes[0], S.run_path(out, study, 0)) is None
    calls.clear()
    monkeypatch.setattr(S, "_run_one", lambda *a: (calls.append(a[0].name), real(*a))[1])
    result = run_study(study, out, workers=1, quiet=True)
    assert calls == ["fa_0"]
    assert [r["parameter"] for r in result["runs"]] == [30e3, 55e3]


def test_the_reduced_cage_is_built_once_per_distinct_cage_and_reaches_the_runs_by_path(tmp_path, monkeypatch):
    """Three flexible-cage runs over two distinct cages (mesh sizes 6, 6 and 7 mm): two builds,
    before any run; each run gets the path of its own cage (content hash,
    flexbearing.coupling.flexible_cage.reduced_cage_hash). No FE work here: the build and the runs are
    stand-ins that record what they were given."""
    import flexbearing.studies.study as S
    from flexbearing.coupling.flexible_cage import reduced_cage_hash
    base = BASE.replace('model = "rigid"', 'model = "flexible"')
    study_text = STUDY.replace('keys = ["operation.load.axial_load"]', 'keys = ["cage.mesh_size"]').replace(
        "values = [30e3, 55e3]", "values = [6e-3, 6e-3, 7e-3]")
    study = load_study(_write(tmp_path, study_text, base))
    built, given = [], []

    def build(scene, quiet):
        built.append(reduced_cage_hash(scene))
        return f"/cache/{built[-1]}.h5"

    def run(scene, path, quiet, cage=None):
        given.append((scene.name, cage))
        raise RuntimeError("not run here")

    monkeypatch.setattr(S, "_build_reduced_cage", build)
    monkeypatch.setattr(S, "_run_one", run)
    with pytest.raises(S.StudyIncomplete, match="3 of 3 runs failed"):
        run_study(study, tmp_path / "out", workers=1, quiet=True)
    h = [reduced_cage_hash(sc) for sc in study.scenes]
    assert h[0] == h[1] != h[2]
    assert sorted(built) == sorted({h[0], h[2]})
    assert given == [(f"fa_{i}", f"/cache/{h[i]}.h5") for i in range(3)]


def test_gmsh_on_a_worker_thread(tmp_path):
    """A reduced cage built on a Dask worker's task thread meshes with gmsh: its import and its
    finalize() call signal.signal, which Python refuses off the main thread (every flexible study
    on --workers N failed with 'signal only works in main thread' before)."""
    import threading
    from flexbearing.studies.study import _import_gmsh_off_the_main_thread
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.mesh.cage_mesh import build_ring_mesh
    errors = []

    def job():
        try:
            _import_gmsh_off_the_main_thread()
            build_ring_mesh(PAPER_CAGE, 20e-3, 1, tmp_path / "ring.msh")
        except Exception as exc:        # noqa: BLE001 - the test reports it
            errors.append(repr(exc))
    t = threading.Thread(target=job)
    t.start()
    t.join()
    assert errors == [] and (tmp_path / "ring.msh").exists()
