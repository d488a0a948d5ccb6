"""A CAD cage input is data, never a program (issue 43, found items 1, 2 and 6).

gmsh's .geo is a scripting language (System runs a shell command, Printf > writes a file, Exit
ends the process, For loops, Include and Merge of any expression read any file). A cage .geo is
parsed by flexbearing.mesh.cad_cage.parse_cage_geo and only its subset is read (SetFactory
("OpenCASCADE"), one Merge of a STEP/BREP file in the .geo's own folder, named physical groups);
anything else is refused in one line naming the statement and its line, before gmsh runs, through
every entry point: `mesh --cad`, a scene's [cage] cad, a study's cage.cad list. `report` never
reads a CAD file a results file names: it rebuilds the CAD cage from what the run recorded.

Each attack leaves a mark if it runs (a file it would create), and the refusals need no gmsh.
"""
from __future__ import annotations

import json
import os
import socket

import h5py
import pytest

from flexbearing.cli.main import main
from flexbearing.common.validation import InputError
from flexbearing.mesh.cad_cage import parse_cage_geo, read_cad_source
from flexbearing.simulation.scene import load_scene

# the attack statement, the line the refusal names (with the .geo's header it is on line 3) and
# what the refusal quotes of it
ATTACKS = {
    "system": ('System "touch {mark}";', r'line 3: System "touch .* is not allowed'),
    "printf": ('Printf("owned") > "{mark}";', r'line 3: Printf\("owned"\) > ".* is not allowed \(character \'>\'\)'),
    "exit": ("Exit;", r"line 3: Exit; is not allowed"),
    "for": ("For i In {{1:1000000000}}\nEndFor", r"line 3: For i In \{1:1000000000\} is not allowed"),
    "include": ('Include "/dev/zero";', r'line 3: Include "/dev/zero"; is not allowed'),
    "strcat": ('Merge StrCat("/dev/","zero");', r'line 3: Merge StrCat\("/dev/","zero"\); is not allowed'),
}
HEADER = 'SetFactory("OpenCASCADE");\nMerge "cage14.step";\n'
STEP_STUB = b"ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n"


def _evil_geo(folder, attack: str):
    """A cage .geo holding the attack after a well-formed header; its mark is MARK in `folder`."""
    mark = folder / "MARK"
    stmt = ATTACKS[attack][0].format(mark=mark)
    if attack == "strcat":                     # the merged file itself is the expression
        text = 'SetFactory("OpenCASCADE");\n// the STEP file\n' + stmt + "\n"
    else:
        text = HEADER + stmt + '\nPhysical Surface("guide") = {1};\n'
    (folder / "cage14.step").write_bytes(STEP_STUB)
    geo = folder / "evil.geo"
    geo.write_text(text)
    return geo, mark


def _cli(capsys, *argv):
    """(exit status, stderr lines) of `flexbearing argv`."""
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    return code, err


@pytest.mark.parametrize("attack", sorted(ATTACKS))
def test_each_attack_is_refused_by_the_parser_naming_the_statement(tmp_path, attack):
    geo, mark = _evil_geo(tmp_path, attack)
    with pytest.raises(InputError, match=ATTACKS[attack][1]) as e:
        read_cad_source(geo)
    assert "read as data, never run" in str(e.value) and "\n" not in str(e.value)
    assert not mark.exists()


@pytest.mark.parametrize("attack", sorted(ATTACKS))
def test_mesh_cad_refuses_each_attack_in_one_line(tmp_path, capsys, attack):
    geo, mark = _evil_geo(tmp_path, attack)
    code, err = _cli(capsys, "mesh", "--cad", geo, "-o", tmp_path / "out.msh")
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(f"flexbearing mesh: invalid input: cage.cad = '{geo}': line 3: ")
    assert not mark.exists() and not (tmp_path / "out.msh").exists()


SCENE = """name = "evil"
[bearing]
n_balls = 14
inner_land_diameter = 157.25e-3
[cage]
model = "rigid"
cad = "evil.geo"
guidance = "inner"
[operation]
duration = 0.01
[operation.speed]
phases = [{ kind = "uniform", duration = 0.01, rpm = 14000 }]
[operation.load]
axial_load = 55e3
[output]
sample_interval = 1e-3
record = ["cage_speed"]
"""


@pytest.mark.parametrize("attack", sorted(ATTACKS))
def test_a_scenes_cage_cad_refuses_each_attack_and_run_exits_2(tmp_path, capsys, attack):
    geo, mark = _evil_geo(tmp_path, attack)
    (tmp_path / "s.toml").write_text(SCENE)
    with pytest.raises(InputError, match=ATTACKS[attack][1]):
        load_scene(tmp_path / "s.toml")
    code, err = _cli(capsys, "run", tmp_path / "s.toml", "-o", tmp_path / "r.h5", "--quiet")
    assert code == 2 and len(err) == 1 and "line 3: " in err[0], err
    assert not mark.exists() and not (tmp_path / "r.h5").exists()


@pytest.mark.parametrize("attack", sorted(ATTACKS))
def test_a_studys_cage_cad_list_refuses_each_attack(tmp_path, capsys, attack):
    from flexbearing.studies.study import load_study
    geo, mark = _evil_geo(tmp_path, attack)
    (tmp_path / "base.toml").write_text(SCENE.replace('cad = "evil.geo"\n', ""))
    (tmp_path / "study.toml").write_text('[study]\nname = "cad"\nscene = "base.toml"\nkeys = ["cage.cad"]\n'
                                         'values = ["evil.geo"]\n')
    with pytest.raises(InputError, match=ATTACKS[attack][1]):
        load_study(tmp_path / "study.toml")
    code, err = _cli(capsys, "study", tmp_path / "study.toml", "-o", tmp_path / "out", "--quiet")
    assert code == 2 and len(err) == 1 and "line 3: " in err[0], err
    assert not mark.exists()


def _forged_run(tmp_path, cad_name: str):
    """A complete rigid run whose stored scene is edited to name `cad_name` beside it (a results
    file received from someone else: it names whatever it likes, and records no CAD cage)."""
    from flexbearing.simulation.results import ResultsWriter
    from flexbearing.simulation.scene import loads_scene
    clean = "\n".join(line for line in SCENE.splitlines()
                      if not line.startswith(("n_balls", "inner_land", "cad =", "guidance"))) + "\n"
    path = tmp_path / "received.h5"
    w = ResultsWriter.create(path, loads_scene(clean, str(tmp_path / "s.toml")))
    for k in range(11):
        w.add_sample(k * 1e-3, {"cage_speed": 450.0 + k})
    w.write_block()
    w.set_status("complete")
    w.close()
    with h5py.File(path, "r+") as f:
        del f["scene"]
        f.create_dataset("scene", data=clean.replace('model = "rigid"', f'model = "rigid"\ncad = "{cad_name}"'))
    return path


@pytest.mark.parametrize("attack", sorted(ATTACKS))
def test_report_never_reads_the_cad_file_a_results_file_names(tmp_path, capsys, attack):
    """The stored scene names evil.geo beside the file: `report` does not read it (no mark, no
    hang, no early exit); the scene's table says it could not be read, the report is written."""
    from flexbearing.simulation.results import Run
    geo, mark = _evil_geo(tmp_path, attack)
    run = _forged_run(tmp_path, geo.name)
    with Run(run) as r:
        assert r.scene is None
    code, err = _cli(capsys, "report", run, "-o", tmp_path / "rep", "--quiet")
    assert code == 0, err
    assert "scene could not be read" in (tmp_path / "rep" / "report.md").read_text()
    assert not mark.exists()


def test_syntax_errors_and_other_statements_are_one_line(tmp_path):
    cases = {
        'Merge "cage14.step"\n': r"line 1: Merge \"cage14.step\" is not ended by ';'",
        'Merge "cage14.step"\nPhysical Surface("guide") = {1};\n': r"line 1: Merge \"cage14.step\" is not ended by ';'",
        'Merge "cage14.step;\n': r"line 1: a string not closed on its line",
        'Merge "cage14.step"; /* open\n': r"line 1: a /\* comment never closed",
        'Merge "a.step"; Merge "b.step";': r"line 1: Merge \"b.step\"; is a second Merge \(the first on line 1\)",
        'Merge "cage14.step";\nPoint(1) = {0, 0, 0};': r"line 2: Point\(1\) = \{0, 0, 0\}; is not allowed",
        'Merge "cage14.step";\nPhysical Surface("a") = {1, x};': r"line 2: .*'x' is not a face number",
        'Merge "cage14.step";\nPhysical Surface(1) = {1};': r"line 2: .*a group needs a name",
        'Merge "cage14.step";\nPhysical Surface("a") = {1};\nPhysical Surface("a") = {2};':
            r"line 3: .*group name 'a' given twice",
        'Merge "cage14.step";\nMesh.CharacteristicLengthMax = 1;': r"line 2: Mesh.CharacteristicLengthMax = 1; is not allowed \(character '\.'\)",
        'SetFactory("Built-in");\nMerge "cage14.step";': r'line 1: SetFactory\("Built-in"\); is not allowed',
        "// only a comment\n": r"merges no STEP or BREP file",
    }
    for text, match in cases.items():
        with pytest.raises(InputError, match=match):
            parse_cage_geo(text, "x.geo")


def test_merged_paths_stay_in_the_geos_folder_no_links_no_devices(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "cage.step").write_bytes(STEP_STUB)
    os.symlink(tmp_path / "sub" / "cage.step", tmp_path / "link.step")
    os.mkfifo(tmp_path / "fifo.step")
    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(tmp_path / "sock.step"))
    cases = {
        "../cage.step": r"Merge '../cage.step' is not allowed \(a STEP or BREP file name of the .geo's own folder",
        "/dev/zero": r"Merge '/dev/zero' is not allowed",
        "sub/cage.step": r"Merge 'sub/cage.step' is not allowed",
        "other.geo": r"Merge 'other.geo' is not allowed",
        "link.step": r"the merged file '.*link.step' is a symbolic link",
        "fifo.step": r"the merged file '.*fifo.step' is not a regular file",
        "sock.step": r"the merged file '.*sock.step' (is not a regular file|cannot be read)",
        "missing.step": r"the merged file '.*missing.step': no such file",
    }
    try:
        for name, match in cases.items():
            geo = tmp_path / "g.geo"
            geo.write_text(f'Merge "{name}";\n')
            with pytest.raises(InputError, match=match):
                read_cad_source(geo)
    finally:
        sock.close()
    with pytest.raises(InputError, match=r"cage.cad = '/dev/zero': not a CAD file"):
        read_cad_source("/dev/zero")
    os.mkfifo(tmp_path / "pipe.geo")
    with pytest.raises(InputError, match=r"the .geo '.*pipe.geo' is not a regular file"):
        read_cad_source(tmp_path / "pipe.geo")                # a FIFO: refused, not waited on


@pytest.mark.parametrize("content, match", [
    (b"", r"the file is empty"),
    (b"\n\n", r"the file is empty"),
    (b"solid cage\nendsolid\n", r"the file is not a STEP file \(it does not begin with ISO-10303-21;\)"),
    (STEP_STUB[:40], r"the file is truncated or damaged: a STEP file ends with END-ISO-10303-21;"),
])
def test_an_empty_or_truncated_step_is_one_line(tmp_path, capsys, content, match):
    step = tmp_path / "cage.step"
    step.write_bytes(content)
    with pytest.raises(InputError, match=match):
        read_cad_source(step)
    code, err = _cli(capsys, "mesh", "--cad", step, "-o", tmp_path / "out.msh")
    assert code == 2 and len(err) == 1, err
    geo = tmp_path / "named.geo"
    geo.write_text('Merge "cage.step";\n')
    with pytest.raises(InputError, match=match.replace("the file", "the merged file 'cage.step'")):
        read_cad_source(geo)


def test_a_geo_that_names_faces_the_step_does_not_have_is_one_line(tmp_path):
    """The groups are applied by face number to the imported STEP: a number it does not have is
    refused naming the line and the group (gmsh runs here: the import only)."""
    import gmsh
    from flexbearing.mesh.cad_cage import read_cad_cage
    from flexbearing.verification.cad_test_cage import PITCH, Z, make_cad_cage
    make_cad_cage(tmp_path / "cage14.step")
    geo = tmp_path / "named.geo"
    geo.write_text(HEADER + 'Physical Surface("guide") = {9999};\n')
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        with pytest.raises(InputError, match=r"line 3: group 'guide' names face 9999, which 'cage14.step' "
                                             r"does not have \(its faces: 1 … \d+\)"):
            read_cad_cage(geo, Z, PITCH * 1e-3, 22e-3, "inner")
    finally:
        gmsh.finalize()


def test_a_step_gmsh_cannot_parse_is_one_line_with_occs_reason(tmp_path):
    """Past the envelope check, a damaged body: OpenCASCADE's own error line is quoted, its
    console output caught (not printed)."""
    import gmsh
    from flexbearing.mesh.cad_cage import read_cad_cage
    bad = tmp_path / "bad.step"
    bad.write_bytes(b"ISO-10303-21;\nHEADER;\nthis is not STEP;\nENDSEC;\nEND-ISO-10303-21;\n")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        with pytest.raises(InputError, match=r"gmsh cannot read the file as STEP \(.*\)") as e:
            read_cad_cage(bad, 14, 167e-3, 22e-3, "inner")
        assert "\n" not in str(e.value)
    finally:
        gmsh.finalize()


def test_the_cad_record_of_a_results_file_is_data_too(tmp_path):
    """A forged record (not JSON, a geometry that is no cage) leaves the scene unread, in one
    line, without reading any file."""
    from flexbearing.simulation.scene import cad_from_record, loads_scene
    geo, mark = _evil_geo(tmp_path, "system")
    text = SCENE
    for record, match in (("", r"records no CAD cage"), ("{not json", r"record is damaged"),
                          (json.dumps({"file": "x", "unit": None, "key": {}, "report": [],
                                       "geometry": {"outside_diameter": -1}}), r"record is damaged")):
        with cad_from_record(record):
            with pytest.raises(InputError, match=match):
                loads_scene(text, str(tmp_path / "s.toml"))
    assert not mark.exists()


def test_a_cad_runs_report_uses_the_recorded_cage_not_the_file(tmp_path, monkeypatch):
    """A run of a CAD scene records its CAD cage (the files' digests, the equivalent geometry);
    its file then replaced by a hostile .geo-like text and garbage: the results file's scene still
    has the CAD cage, rebuilt from the record, and nothing was read from the file."""
    from flexbearing.simulation.results import ResultsWriter, Run
    from flexbearing.verification.cad_test_cage import BORE, Z, make_cad_cage
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path / "cache"))
    make_cad_cage(tmp_path / "cage14.step")
    (tmp_path / "s.toml").write_text(SCENE.replace("evil.geo", "cage14.step"))
    scene = load_scene(tmp_path / "s.toml")
    path = tmp_path / "cad_run.h5"
    w = ResultsWriter.create(path, scene)
    for k in range(11):
        w.add_sample(k * 1e-3, {"cage_speed": 450.0 + k})
    w.write_block()
    w.set_status("complete")
    w.close()
    with h5py.File(path, "r") as f:
        rec = json.loads(f.attrs["cad_cage"])
    assert rec["key"] == scene.cad["key"] and rec["file"].endswith("cage14.step")
    (tmp_path / "cage14.step").write_bytes(b'System "touch MARK";\n')
    with Run(path) as r:
        got = r.scene
    assert got.bearing.cage == scene.bearing.cage and got.bearing.cage.n_pockets == Z
    assert got.bearing.cage.bore_diameter == pytest.approx(BORE * 1e-3, rel=1e-6)
    assert got.cad["key"] == scene.cad["key"]
    assert not (tmp_path / "MARK").exists()
    # the scene's hash (what --resume checks) holds the CAD files' content, the same when rebuilt
    from flexbearing.common.cache import content_hash
    assert got.content_hash() == scene.content_hash() != content_hash(scene.data)
