"""Every output path, one rule (issue 43): each command declares every file it writes before any
work (`planned_outputs` of its command module, flexbearing.analysis.report.report_outputs,
flexbearing.studies.study.study_outputs), one check refuses an input, a link, a file of another
kind, and the files are written in a staging folder and renamed into place.

The enumeration tests run each command on a tiny case, list what appeared in its output folder
and check it against the command's declared list (printed: `pytest -s` shows the list per
command). A file a command writes without declaring it fails there, and at run time the staged
file is refused (test_an_undeclared_output_is_refused_and_nothing_lands)."""
import hashlib
import os
from pathlib import Path

import pytest

from flexbearing.cli.main import build_parser, main
from flexbearing.common.safe_files import OutputPlan
from flexbearing.common.validation import InputError
import flexbearing.simulation.run as simulation_run
from test_run import SCENE, fake_backend

TINY_MESH = ["--size", "0.02", "--pocket-size", "0.02", "--order", "1"]


def _files(folder: Path) -> set[Path]:
    return {p for p in folder.rglob("*") if p.is_file() or p.is_symlink()}


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _enumerate(folder: Path, argv: list[str], plan: OutputPlan, label: str) -> list[str]:
    """Run the command; every file that appeared in `folder` must be declared by `plan`, and no
    staging folder may be left. Returns (and prints) the names written."""
    before = _files(folder)
    assert main([str(a) for a in argv]) == 0
    appeared = sorted(_files(folder) - before)
    assert appeared, f"{label} wrote nothing"
    undeclared = [str(p) for p in appeared if not plan.covers(p)]
    assert not undeclared, f"{label} wrote files it did not declare: {undeclared}"
    assert not any(".flexbearing-staging-" in str(p) for p in folder.rglob("*")), "staging folder left"
    names = [str(p.relative_to(folder)) for p in appeared]
    print(f"\n{label}: {', '.join(names)}")
    return names


def _one_line(capsys, argv, *fragments, code=2) -> str:
    assert main([str(a) for a in argv]) == code
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for f in fragments:
        assert f in err, err
    return err


def _args(argv):
    return build_parser().parse_args([str(a) for a in argv])


# ---------------------------------------------------------------- every file each command writes

def test_mesh_and_modes_write_only_what_they_declare(tmp_path):
    from flexbearing.cli import mesh as cli_mesh, modes as cli_modes
    argv = ["mesh", "-o", tmp_path / "cage.msh", *TINY_MESH, "--quiet"]
    names = _enumerate(tmp_path, argv, cli_mesh.planned_outputs(_args(argv)), "mesh")
    assert sorted(names) == ["cage.h5", "cage.msh", "cage.quality.json", "cage.xdmf"]
    out = tmp_path / "modes"
    out.mkdir()
    argv = ["modes", "--mesh", tmp_path / "cage.msh", "--degree", "1", "--n-modes", "8", "--no-classify",
            "--quiet", "--json", out / "modes.json", "--xdmf", out / "shapes.xdmf"]
    names = _enumerate(out, argv, cli_modes.planned_outputs(_args(argv)), "modes")
    assert sorted(names) == ["modes.json", "shapes.h5", "shapes.json", "shapes.xdmf"]


def test_run_report_export_write_only_what_they_declare(tmp_path, fake_runs):
    from flexbearing.cli import export as cli_export, run as cli_run
    from flexbearing.analysis.report import report_outputs
    scene = tmp_path / "fake.toml"
    scene.write_text(SCENE)
    out = tmp_path / "out"
    out.mkdir()
    argv = ["run", scene, "-o", out / "r.h5", "--quiet"]
    assert sorted(_enumerate(out, argv, cli_run.planned_outputs(_args(argv)), "run")) == \
        ["r.h5", "r.summary.json"]
    rep = out / "rep"
    names = _enumerate(out, ["report", out / "r.h5", "-o", rep, "--quiet"],
                       report_outputs(out / "r.h5", rep), "report (rigid cage)")
    assert {"rep/report.md", "rep/report.html", "rep/report.json"} <= set(names)
    argv = ["export", out / "r.h5", "--netcdf", out / "r.nc", "--csv", out / "csv", "--quiet"]
    names = _enumerate(out, argv, cli_export.planned_outputs(_args(argv)), "export")
    assert "r.nc" in names and "csv/cage_speed.csv" in names


def test_quasi_static_writes_only_what_it_declares(tmp_path):
    from flexbearing.cli import quasi_static as cli_qs
    scene = Path(__file__).resolve().parents[1] / "scenes" / "paper_steady_rigid.toml"
    argv = ["quasi-static", scene, "--json", tmp_path / "qs" / "q.json"]
    assert _enumerate(tmp_path, argv, cli_qs.planned_outputs(_args(argv)), "quasi-static") == ["qs/q.json"]


def test_study_writes_only_what_it_declares(tmp_path, monkeypatch):
    import flexbearing.studies.study as S
    real = S._run_one
    monkeypatch.setattr(S, "_run_one", lambda scene, path, quiet, cage=None: simulation_run.run_scene(
        scene, Path(path), resume=True, quiet=True, backend=fake_backend()))
    (tmp_path / "fake.toml").write_text(SCENE)
    (tmp_path / "study.toml").write_text('[study]\nname = "fa"\nscene = "fake.toml"\n'
                                         'keys = ["integrator.tolerance"]\nvalues = [1e-9, 1e-8]\n'
                                         'label = "Tolerance"\nunit = "1"\n')
    out = tmp_path / "out"
    out.mkdir()
    study = S.load_study(tmp_path / "study.toml")
    try:
        names = _enumerate(out, ["study", tmp_path / "study.toml", "-o", out, "--workers", "1", "--quiet"],
                           S.study_outputs(study, out), "study")
    finally:
        monkeypatch.setattr(S, "_run_one", real)
    assert {"fa/study.md", "fa/study.json", "fa/study.html", "fa/fa_0.h5", "fa/fa_1.h5"} <= set(names)


@pytest.mark.slow
def test_reduce_writes_only_what_it_declares(tmp_path):
    """A coarse reduced cage (order-1 mesh, P1, 10 fixed-interface modes: ~1 min with dolfinx)."""
    from flexbearing.cli import reduce as cli_reduce
    small = [*TINY_MESH, "--degree", "1", "--n-fixed", "10", "--n-keep", "16", "--quiet"]
    assert main(["reduce", *small]) == 0                 # into the cache (the test session's own)
    argv = ["reduce", *small, "-o", tmp_path / "cage.h5", "--json", tmp_path / "cage.json",
            "--xdmf", tmp_path / "shapes.xdmf"]
    names = _enumerate(tmp_path, argv, cli_reduce.planned_outputs(_args(argv)), "reduce")
    assert sorted(names) == ["cage.h5", "cage.json", "shapes.h5", "shapes.xdmf"]
    # -o onto the cache entry it reads: refused (an input)
    import json
    cached = Path(json.loads((tmp_path / "cage.json").read_text())["file"])
    assert main(["reduce", *small, "-o", str(cached)]) == 2


# ---------------------------------------------------------------- the rule

def test_mesh_named_after_a_run_does_not_touch_its_results(tmp_path, run_file, capsys):
    """The issue's case: `mesh -o out/paper_steady.msh` beside out/paper_steady.h5 truncated the
    results file (the XDMF's heavy data). Refused before any meshing; the file byte for byte."""
    res = tmp_path / "paper_steady.h5"
    res.write_bytes(run_file.read_bytes())
    before = _digest(res)
    _one_line(capsys, ["mesh", "-o", tmp_path / "paper_steady.msh", *TINY_MESH],
              "paper_steady.h5", "results file of a run")
    assert _digest(res) == before and sorted(p.name for p in tmp_path.iterdir()) == ["paper_steady.h5"]


def test_modes_xdmf_beside_a_run_and_json_sidecar_collisions_are_refused(tmp_path, run_file, capsys):
    res = tmp_path / "r.h5"
    res.write_bytes(run_file.read_bytes())
    _one_line(capsys, ["modes", "--xdmf", tmp_path / "r.xdmf", "--mesh", tmp_path / "none.msh"],
              "--xdmf", "results file of a run")
    # --json naming the XDMF's own frequency sidecar: two outputs at one name
    _one_line(capsys, ["modes", "--xdmf", tmp_path / "s.xdmf", "--json", tmp_path / "s.json"], "two of its outputs")
    link = tmp_path / "m.json"
    link.symlink_to(tmp_path / "victim.json")
    _one_line(capsys, ["modes", "--json", link], "symbolic link")
    assert not (tmp_path / "victim.json").exists()


def test_reduce_outputs_are_checked_before_any_work(tmp_path, run_file, capsys):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    for opt, name in (("-o", "c.h5"), ("--json", "c.json"), ("--xdmf", "c.xdmf")):
        (tmp_path / name).symlink_to(victim)
        _one_line(capsys, ["reduce", opt, tmp_path / name], "symbolic link")
    res = tmp_path / "run.h5"
    res.write_bytes(run_file.read_bytes())
    _one_line(capsys, ["reduce", "-o", res], "results file of a run")
    _one_line(capsys, ["reduce", "--xdmf", tmp_path / "run.xdmf"], "results file of a run")
    assert victim.read_text() == "precious"


@pytest.mark.parametrize("name", ["von_mises_peak.json", "paraview_scene.json", "bearing.pvsm",
                                  "fatigue.h5", "fatigue.json", "series_rings.xdmf", "report.pdf"])
def test_report_refuses_links_at_every_name_it_can_write_before_writing(tmp_path, run_file, capsys, name):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    d = tmp_path / "rep"
    d.mkdir()
    (d / name).symlink_to(victim)
    _one_line(capsys, ["report", run_file, "-o", d, "--quiet"], "symbolic link", name)
    assert victim.read_text() == "precious" and [p.name for p in d.iterdir()] == [name]


def test_report_refuses_a_hard_link_to_its_run_under_an_output_name(tmp_path, run_file, capsys):
    d = tmp_path / "rep"
    d.mkdir()
    os.link(run_file, d / "von_mises_peak.json")
    before = _digest(run_file)
    _one_line(capsys, ["report", run_file, "-o", d, "--quiet"], "is the input file")
    assert _digest(run_file) == before and [p.name for p in d.iterdir()] == ["von_mises_peak.json"]


def test_study_refuses_a_linked_study_folder_and_links_at_its_pages(tmp_path, capsys):
    import flexbearing.studies.study as S
    (tmp_path / "fake.toml").write_text(SCENE)
    (tmp_path / "study.toml").write_text('[study]\nname = "fa"\nscene = "fake.toml"\n'
                                         'keys = ["integrator.tolerance"]\nvalues = [1e-9]\n'
                                         'label = "Tolerance"\nunit = "1"\n')
    study = S.load_study(tmp_path / "study.toml")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    (out / "fa").symlink_to(elsewhere)
    with pytest.raises(InputError, match="symbolic link"):
        S.run_study(study, out, workers=1, quiet=True)
    (out / "fa").unlink()
    (out / "fa").mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    for name in ("study.md", "study.html", "cage_speed.png", "fa_0.summary.json"):
        (out / "fa" / name).symlink_to(victim)
        with pytest.raises(InputError, match="symbolic link"):
            S.run_study(study, out, workers=1, quiet=True)
        (out / "fa" / name).unlink()
    assert victim.read_text() == "precious" and list(elsewhere.iterdir()) == []


def test_output_of_the_wrong_kind_is_refused_in_one_line_before_any_work(tmp_path, capsys):
    """Issue 41 item 5: `demo -o FILE`, `mesh -o EXISTING_DIR`, a run's -o under a file."""
    a_file = tmp_path / "notadir"
    a_file.write_text("x")
    _one_line(capsys, ["demo", "-o", a_file], "is a file, and this output is a folder")
    folder = tmp_path / "cage.msh"
    folder.mkdir()
    _one_line(capsys, ["mesh", "-o", folder, *TINY_MESH], "is a directory")
    _one_line(capsys, ["mesh", "-o", a_file / "cage.msh", *TINY_MESH], "is a file, not a folder")
    dangling = tmp_path / "gone"
    dangling.symlink_to(tmp_path / "missing")
    _one_line(capsys, ["mesh", "-o", dangling / "cage.msh", *TINY_MESH], "symbolic link")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cage.msh", "gone", "notadir"]


def test_an_undeclared_output_is_refused_and_nothing_lands(tmp_path):
    plan = OutputPlan("test", inputs=[])
    plan.folder(tmp_path, "-o", names=["a.txt"], patterns=["*.png"])
    with pytest.raises(RuntimeError, match="did not declare"):
        with plan.writing():
            stage = plan.staging(tmp_path)
            (stage / "a.txt").write_text("a")
            (stage / "b.png").write_text("b")
            (stage / "sneaky.json").write_text("c")
    assert list(tmp_path.iterdir()) == []               # neither the declared nor the staging folder
    with pytest.raises(RuntimeError, match="not declared"):
        plan.staged(tmp_path / "other.txt")
    with plan.writing():
        plan.staged(tmp_path / "a.txt").write_text("a")
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"] and (tmp_path / "a.txt").read_text() == "a"


def test_the_staged_commit_replaces_an_old_file_whole_and_a_failure_leaves_it(tmp_path):
    target = tmp_path / "x.json"
    target.write_text("old")
    plan = OutputPlan("test")
    plan.file(target, "--json")
    plan.check()
    with pytest.raises(ZeroDivisionError):
        with plan.writing():
            plan.staged(target).write_text("half")
            1 / 0
    assert target.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["x.json"]
    with plan.writing():
        plan.staged(target).write_text("new")
    assert target.read_text() == "new"


def test_the_report_declares_the_fatigue_files_by_their_writers_names():
    from flexbearing.analysis import cage_fatigue, report
    assert report.FATIGUE_FILES == (cage_fatigue.FATIGUE_H5, cage_fatigue.FATIGUE_XDMF, cage_fatigue.FATIGUE_JSON)


# the function that declares each command's outputs (a new command with an output option must add one)
DECLARED_BY = {
    "mesh": "flexbearing.cli.mesh:planned_outputs", "modes": "flexbearing.cli.modes:planned_outputs",
    "mesh-study": "flexbearing.cli.modes:planned_mesh_study_outputs",
    "calibrate-cage": "flexbearing.cli.modes:planned_calibrate_outputs",
    "reduce": "flexbearing.cli.reduce:planned_outputs", "run": "flexbearing.cli.run:planned_outputs",
    "quasi-static": "flexbearing.cli.quasi_static:planned_outputs",
    "report": "flexbearing.analysis.report:report_outputs", "study": "flexbearing.studies.study:study_outputs",
    "export": "flexbearing.cli.export:planned_outputs", "uncertainty": "flexbearing.cli.uncertainty:planned_outputs",
    "demo": "flexbearing.cli.demo:planned_outputs", "validate series": "flexbearing.cli.validate_series:planned_outputs",
}


def test_every_command_with_an_output_option_declares_its_outputs():
    """Every command (and `validate` subcommand) whose parser takes an output option has its
    declaring function, and calls it (its source names it): a new output option cannot skip the
    rule without this test failing."""
    import importlib
    import inspect
    outputs = {"-o", "--output", "--json", "--xdmf", "--netcdf", "--csv", "--out", "--page", "--report-dir"}
    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    commands = {}
    for name, parser in sub.choices.items():
        inner = [a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction"]
        for sname, sparser in (inner[0].choices.items() if inner else ()):
            commands[f"{name} {sname}"] = sparser
        commands[name] = parser
    missing = []
    for name, parser in commands.items():
        if not {o for a in parser._actions for o in a.option_strings} & outputs:
            continue
        if name == "validate slip-rate":
            continue                       # its --json and --case-set: an OutputPlan in cmd_validate_slip_rate
        if name not in DECLARED_BY:
            missing.append(name)
            continue
        module, func = DECLARED_BY[name].split(":")
        assert callable(getattr(importlib.import_module(module), func)), name
        handler = parser.get_default("func")
        # called by the command (cli module) or, for report and study, by the library writer
        # itself (write_report, run_study: the definition and a call in that module)
        called = func in inspect.getsource(inspect.getmodule(handler)) or \
            inspect.getsource(importlib.import_module(module)).count(f"{func}(") >= 2
        assert handler is not None and called, name
    assert not missing, f"commands with an output option and no declared outputs: {missing}"


@pytest.mark.slow
def test_a_flexible_cage_report_with_series_and_fatigue_writes_only_what_it_declares(
        paper_reduced_cage, short_flexible_impact, tmp_path):
    """The report's every side file (von Mises frames, the stress picture and its facts, the
    series, the fatigue files and picture) on a 3 ms flexible-cage run of the paper bearing."""
    from flexbearing.analysis.report import report_outputs
    run = tmp_path / "run.h5"
    record = ["pocket_force", "cage_speed", "von_mises", "kinematics", "cage_orbit"]
    simulation_run.run_scene(short_flexible_impact("short_flexible_outputs", record), run, quiet=True)
    out = tmp_path / "rep"
    names = _enumerate(tmp_path, ["report", run, "-o", out, "--series", "0:0.003", "--fatigue", "--quiet"],
                       report_outputs(run, out), "report (flexible cage, --series, --fatigue)")
    assert {"rep/von_mises_peak.json", "rep/von_mises.h5", "rep/series.h5", "rep/series_rings.xdmf",
            "rep/fatigue.h5", "rep/fatigue_damage.png"} <= set(names)


def test_a_sigkilled_command_s_staging_folder_is_removed_by_the_next_one(tmp_path):
    """A command killed by SIGKILL inside OutputPlan.writing() leaves its staging folder (nothing
    runs at SIGKILL); the next command staging in the same folder removes it, because its owner's
    pid is gone, and commits its own file. A live owner's folder (this process's pid) and another
    host's are kept: their command may still be writing."""
    import signal
    import socket
    import subprocess
    import sys
    out = tmp_path / "out"
    killed = subprocess.Popen([sys.executable, "-c", f"""
import os, signal
from flexbearing.common.safe_files import OutputPlan
plan = OutputPlan("killed", inputs=[])
plan.file({str(out / 'a.txt')!r}, "-o")
plan.check()
with plan.writing():
    plan.staged({str(out / 'a.txt')!r}).write_text("half")
    os.kill(os.getpid(), signal.SIGKILL)
"""], stderr=subprocess.PIPE, text=True)
    _, err = killed.communicate()
    assert killed.returncode == -signal.SIGKILL, err
    left = [p for p in out.iterdir() if p.name.startswith(".flexbearing-staging-")]
    assert len(left) == 1 and (left[0] / "a.txt").read_text() == "half"
    live = out / f".flexbearing-staging-{socket.gethostname()}-{os.getpid()}-live0000"
    # the dead pid itself, but on another host: that host's process may be alive
    other_host = out / f".flexbearing-staging-{socket.gethostname()}x-{killed.pid}-other000"
    live.mkdir()
    other_host.mkdir()
    plan = OutputPlan("next", inputs=[])
    plan.file(out / "a.txt", "-o")
    plan.check()
    with plan.writing():
        plan.staged(out / "a.txt").write_text("whole")
    assert (out / "a.txt").read_text() == "whole"
    assert not left[0].exists(), "the dead owner's staging folder was left"
    assert live.is_dir() and other_host.is_dir(), "a live owner's or another host's staging folder was removed"
