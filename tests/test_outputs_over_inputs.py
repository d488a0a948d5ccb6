"""Outputs never over inputs (issue 36, part 4): export, report and run refuse an output that is
their input (the same path, or the same file under another name) and never write through a
symbolic link planted in their output folder; the input is left byte for byte as it was."""
import hashlib
import os

import pytest

from flexbearing.cli.main import main
from flexbearing.simulation.run import run_scene
from test_run import fake_backend, fake_scene


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "r.h5"
    run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    return out


def _digest(p):
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _one_line_refusal(capsys, argv, *fragments):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for f in fragments:
        assert f in err, err


def test_export_netcdf_onto_its_own_input_is_refused(tmp_path, run_file, capsys):
    before = _digest(run_file)
    _one_line_refusal(capsys, ["export", str(run_file), "--netcdf", str(run_file)], "is the input file")
    link = tmp_path / "hard.nc"
    os.link(run_file, link)                                  # the same inode under another name
    _one_line_refusal(capsys, ["export", str(run_file), "--netcdf", str(link)], "is the input file")
    assert _digest(run_file) == before


def test_export_does_not_follow_links_planted_in_its_folder(tmp_path, run_file, capsys):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    csv_dir = tmp_path / "csv"
    csv_dir.mkdir()
    (csv_dir / "cage_speed.csv").symlink_to(victim)
    _one_line_refusal(capsys, ["export", str(run_file), "--csv", str(csv_dir)], "symbolic link")
    nc = tmp_path / "out.nc"
    nc.symlink_to(victim)
    _one_line_refusal(capsys, ["export", str(run_file), "--netcdf", str(nc)], "symbolic link")
    assert victim.read_text() == "precious"
    # without the links it writes, and the CSVs are whole files
    (csv_dir / "cage_speed.csv").unlink()
    assert main(["export", str(run_file), "--csv", str(csv_dir)]) == 0
    assert (csv_dir / "cage_speed.csv").read_text().startswith("time,cage_speed")


def test_report_into_the_folder_of_an_input_named_like_an_output_is_refused(tmp_path, run_file, capsys):
    d = tmp_path / "rep"
    d.mkdir()
    named = d / "von_mises.h5"                               # the case
    named.write_bytes(run_file.read_bytes())
    before = _digest(named)
    _one_line_refusal(capsys, ["report", str(named), "-o", str(d), "--quiet"], "would replace it")
    assert _digest(named) == before and sorted(p.name for p in d.iterdir()) == ["von_mises.h5"]


def test_report_does_not_follow_links_planted_in_its_folder(tmp_path, run_file, capsys):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    d = tmp_path / "rep"
    d.mkdir()
    for name in ("report.md", "overview.png"):
        (d / name).symlink_to(victim)
        _one_line_refusal(capsys, ["report", str(run_file), "-o", str(d), "--quiet"], "symbolic link", name)
        (d / name).unlink()
    linked_dir = tmp_path / "linked"
    linked_dir.symlink_to(d)
    _one_line_refusal(capsys, ["report", str(run_file), "-o", str(linked_dir), "--quiet"], "symbolic link")
    assert victim.read_text() == "precious"


def test_run_output_that_is_a_link_is_refused(tmp_path):
    from flexbearing.common.validation import InputError
    victim = tmp_path / "victim.h5"
    victim.write_bytes(b"precious")
    out = tmp_path / "run.h5"
    out.symlink_to(victim)
    for kw in ({}, {"force": True}, {"resume": True}):
        with pytest.raises(InputError, match="symbolic link"):
            run_scene(fake_scene(), out, quiet=True, backend=fake_backend(), **kw)
    assert victim.read_bytes() == b"precious"
