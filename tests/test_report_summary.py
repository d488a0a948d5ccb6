"""The report as a deliverable: one results reader (the run file opened once), the summary block and
the inputs table (against the scene and the hand-made data of tests/test_report.py), figure
captions, and the stage progress bar's estimate."""
from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

from flexbearing.analysis import plots, report, summary
from flexbearing.common.progress import Stages
from flexbearing.simulation.results import Run, opened, read_outputs

from test_report import A, B, write_run


def test_run_reads_once_and_opened_passes_an_open_run_through(tmp_path):
    path = write_run(tmp_path / "run.h5")
    with Run(path) as run:
        assert np.array_equal(run.t, read_outputs(path)["time"])
        assert run.dt == pytest.approx(1e-3) and run.scene.name == "synthetic_rigid"
        assert run.scene is run.scene                          # parsed once
        with opened(run) as same:
            assert same is run
        assert run.file.id.valid                               # opened() left it open
        assert not run.flexible and "contact_stress" in run
    assert not run.file.id.valid
    with opened(path) as own:
        assert own.path == path
    assert not own.file.id.valid


def test_write_report_opens_each_results_file_once(tmp_path, monkeypatch):
    """Issue 31: the results file was opened 21 times across 8 modules; now the report opens the
    run and the compared run once each and hands them on."""
    run, other = write_run(tmp_path / "run.h5"), write_run(tmp_path / "other.h5")
    opened_files = []
    real = h5py.File

    def counting(name, mode="r", *a, **k):
        opened_files.append((str(name), mode))
        return real(name, mode, *a, **k)
    monkeypatch.setattr(h5py, "File", counting)
    report.write_report(run, tmp_path / "rep", compare=other)
    reads = [n for n, mode in opened_files if mode == "r"]
    assert reads.count(str(run)) == 1 and reads.count(str(other)) == 1, opened_files


def test_summary_block_states_the_scene_and_the_headline_results(tmp_path):
    out = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep")
    md = out["report"].read_text()
    # the summary comes first, right under the title
    assert md.index("## Summary") < md.index("- results file:") < md.index("## synthetic_rigid: per phase")
    rows = dict(line.strip("|").split("|")[:2] for line in md.split("## Summary")[1].split("\n\n")[1].splitlines()[2:])
    rows = {k.strip(): v.strip() for k, v in rows.items()}
    assert "0–0.2 s acceleration 10,000→14,000 rpm" in rows["Speed spectrum (inner ring)"]
    assert "F_a = 55 kN, F_r = 4 kN (constant)" in rows["Load spectrum (on the inner ring)"]
    assert "50 kN for 20 ms at 0.3 s" in rows["Load spectrum (on the inner ring)"]
    assert rows["Bearing"].startswith("20 balls of D_w = 22 mm on a pitch diameter of 167 mm")
    assert rows["Cage"].startswith("rigid;")
    assert "flexbearing" in rows["Program"] and "git" in rows["Program"]
    # headline: the whole run's peak outer-race stress = the largest A + B of the synthetic run (MPa)
    peak = max(a + b for a, b in zip(A, B)) * 1e-6
    assert rows["Outer-race contact stress, max. (MPa)"].startswith(f"**{peak:,.0f} MPa**")
    # the same numbers as the per-phase table (one source)
    whole = json.loads(out["json"].read_text())["phases"][0]
    assert whole["outer_contact_stress_peak"] * 1e-6 == pytest.approx(peak, rel=1e-12)


def test_inputs_table_lists_every_scene_value(tmp_path):
    out = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep")
    md = out["report"].read_text()
    table = md.split("## Inputs")[1]
    assert "| `operation.load.axial_load` | 55000 |" in table
    assert "| `operation.speed.phases[1]` | kind = \"uniform\", duration = 0.2, rpm = 14000 |" in table
    assert "| `cage.model` | \"rigid\" |" in table


def test_input_rows_flatten_nested_tables():
    rows = dict(summary.input_rows({"a": {"b": 1.5, "c": [1, 2]}, "d": [{"x": 1}, {"x": 2}], "e": True}))
    assert rows == {"a.b": "1.5", "a.c": "[1, 2]", "d[0]": "x = 1", "d[1]": "x = 2", "e": "true"}


def test_figure_captions_say_what_is_drawn(tmp_path):
    out = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep")
    md = out["report"].read_text()
    images = [line for line in md.splitlines() if line.startswith("![")]
    assert len(images) == len(out["plots"]) > 0
    for line, png in zip(images, out["plots"]):
        assert line == f"![{plots.caption(png)}]({png.name})"
        assert f"![{png.stem}]" not in line                   # a caption, not the file name
    assert plots.caption(tmp_path / "outer_contact_stress.png").startswith(
        "Outer-race contact stress against time, MPa: the worst ball")


def test_sections_are_a_list_the_caller_can_extend(tmp_path):
    def extra(r):
        return ["## Extra", "", f"{len(r.rows)} windows", ""]
    out = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep",
                              sections=report.SECTIONS + [extra])
    assert out["report"].read_text().rstrip().endswith("## Extra\n\n5 windows")


def test_time_left_scales_the_measured_weights_by_this_machine_s_speed():
    from flexbearing.common.progress import time_left
    w = {"a": 10.0, "b": 30.0, "c": 60.0}
    # nothing finished: the weights themselves (reference seconds)
    assert time_left(w, [], "a", 0.0, 4.0) == 6.0 + 90.0
    # "a" took 20 s instead of 10: this machine runs at half the reference speed
    assert time_left(w, ["a"], "b", 20.0, 15.0) == 60.0 - 15.0 + 120.0
    # a stage over its estimate counts as finished; the rest stays
    assert time_left(w, ["a"], "b", 20.0, 100.0) == 120.0
    assert time_left(w, ["a", "b", "c"], None, 200.0, 0.0) == 0.0


def test_stages_advance_by_their_weights():
    """The bar's total is the sum of the weights and a finished stage advances it by its own, so
    the estimate of the time left is elapsed × (weights left / weights done)."""
    s = Stages("task", {"a": 2.0, "b": 5.0, "c": 3.0}, quiet=False)
    assert s.bar.total == 10.0
    s("a")
    assert s.bar.n == 0.0 and "a (1/3)" in s.bar.desc
    s("b")
    assert s.bar.n == 2.0
    s("c")
    assert s.bar.n == 7.0
    bar = s.bar
    s(None)
    assert s.bar is None and bar.n == 10.0 and s.done == ["a", "b", "c"]
    quiet = Stages("task", ["x", "y"], quiet=True)
    quiet("x"), quiet("y"), quiet(None)                         # silent, no bar
    assert quiet.bar is None and quiet.weights == {"x": 1.0, "y": 1.0}


def test_movie_without_a_series_is_refused_before_any_file(tmp_path):
    from flexbearing.common.validation import InputError
    with pytest.raises(InputError, match="--movie needs --series"):
        report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep", movie=True)
    assert not (tmp_path / "rep").exists()


def test_missing_viewers_are_named_not_failed(tmp_path, monkeypatch):
    """Without pvpython the series is written and the report says the state file needs ParaView;
    --pdf and --movie without their tool stop before any file, naming what to install."""
    from flexbearing.analysis import paraview_state, pdf
    from flexbearing.common.validation import InputError
    monkeypatch.setattr(paraview_state.shutil, "which", lambda name: None)
    monkeypatch.setattr(pdf.shutil, "which", lambda name: None)
    run = write_run(tmp_path / "run.h5")
    with pytest.raises(InputError, match="apt-get install chromium"):
        report.write_report(run, tmp_path / "a", pdf=True)
    with pytest.raises(InputError, match="apt-get install paraview"):
        report.write_report(run, tmp_path / "b", series="0:0.01", movie=True)
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
    from test_field_export import fake_run
    run, *_ = fake_run(tmp_path / "fake")
    out = report.write_report(run, tmp_path / "c", series="0:0.02:5")
    assert out["series"]["cage"].is_file() and out["series"]["rings"].is_file()
    assert out["paraview"] == {"note": f"bearing.pvsm not written: it needs {paraview_state.NEEDS}"}
    assert out["paraview"]["note"] + "." in out["report"].read_text()
