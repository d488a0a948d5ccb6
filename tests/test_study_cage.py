"""The cage study (flexbearing.studies.study, flexbearing.studies.cage_modes): a study over a list of
CAD files (paths relative to the study file, checked before any run) and the table of each
variant's first elastic cage modes.

The modes are checked on a synthetic reduced cage: a ring of nodes (the paper cage's pitch radius
and section) whose mode shapes are the analytic ring families (inextensional in-plane bending
u_r = cos nθ, u_t = −sin(nθ)/n; out-of-plane u_x = cos nθ; breathing u_r = 1; torsion, the
section turning about its centroid; Rao 2007 §11.4–11.5), so each family and wave number is
known without a FE solve; the frequencies are what the file says. The study runs are stand-ins
(the rigid-cage run of the same scene; the reduced cages the synthetic files): the FE build is
flexbearing.fem_cage's, tested there.
"""
import dataclasses
import json

import h5py
import numpy as np
import pytest

from flexbearing.common.validation import InputError
from flexbearing.verification.cad_test_cage import make_cad_cage

R0, WEB, WIDTH = 83.5e-3, 9e-3, 26e-3        # m: ring radius, radial web, axial width


def _ring_nodes(n_az=80):
    th = np.repeat(2 * np.pi * (np.arange(n_az) + 0.5) / n_az, 9)
    x = np.tile(np.repeat([-WIDTH / 2, 0.0, WIDTH / 2], 3), n_az)
    r = np.tile(np.tile([R0 - WEB / 2, R0, R0 + WEB / 2], 3), n_az)
    return np.stack([x, r * np.cos(th), r * np.sin(th)], axis=1), th, x, r


def _shapes(kinds):
    X, th, x, r = _ring_nodes()
    er = np.stack([0 * th, np.cos(th), np.sin(th)], axis=1)
    et = np.stack([0 * th, -np.sin(th), np.cos(th)], axis=1)
    ex = np.array([1.0, 0.0, 0.0])
    out = []
    for kind, n in kinds:
        if kind == "rigid":
            U = np.tile(ex, (len(th), 1))
        elif kind == "inplane":          # inextensional: u_r + du_t/dθ = 0
            U = np.cos(n * th)[:, None] * er + (-np.sin(n * th) / n)[:, None] * et
        elif kind == "outofplane":
            U = np.cos(n * th)[:, None] * ex
        elif kind == "breathing":
            U = er.copy()
        else:                            # torsion: the section turns by 1 rad about its centroid
            U = (-(r - R0))[:, None] * ex + x[:, None] * er
        out.append(U)
    return X, np.stack(out, axis=2)


ELASTIC = [("inplane", 2), ("outofplane", 2), ("inplane", 3), ("torsion", 0), ("outofplane", 3),
           ("breathing", 0), ("inplane", 4)]
FAMILIES = [("in-plane bending", 2), ("out-of-plane bending", 2), ("in-plane bending", 3),
            ("torsion", 0), ("out-of-plane bending", 3), ("in-plane breathing", 0)]


def synthetic_reduced_cage(path, scale=1.0):
    """The reduced cage file's three datasets the table reads: 6 rigid + 7 elastic modes."""
    X, U = _shapes([("rigid", 0)] * 6 + ELASTIC)
    f_hz = np.concatenate([np.zeros(6), scale * np.array([500.0, 600.0, 1400.0, 1500.0, 1700.0, 2100.0, 2600.0])])
    with h5py.File(path, "w") as f:
        f["modes/frequency_hz"] = f_hz
        f["mesh/vertices"] = X
        f["modes/vertex_displacement"] = U
    return str(path)


def test_cage_modes_name_the_ring_families(tmp_path):
    from flexbearing.studies.cage_modes import cage_modes, mode_cell
    modes = cage_modes(synthetic_reduced_cage(tmp_path / "rc.h5"))
    assert [m.mode for m in modes] == [7, 8, 9, 10, 11, 12]          # 6 elastic, after the 6 rigid
    assert [m.frequency_hz for m in modes] == [500.0, 600.0, 1400.0, 1500.0, 1700.0, 2100.0]
    assert [(m.family, m.n) for m in modes] == FAMILIES
    assert mode_cell(modes[0]._asdict()) == "500.0 Hz in-plane bending n=2"


BASE = """
name = "cagestudy"
[bearing]
n_balls = 14
inner_land_diameter = 157.25e-3
[cage]
model = "flexible"
cad = "cage14.step"
guidance = "inner"
[operation]
duration = 0.002
[operation.speed]
phases = [{ kind = "uniform", duration = 0.002, rpm = 14000 }]
[operation.load]
axial_load = 55e3
[integrator]
tolerance = 1e-6
initial_step = 1e-7
[output]
sample_interval = 1e-4
record = ["pocket_force", "guiding_force", "cage_speed"]
"""

STUDY = """
[study]
name = "cad"
description = "two CAD cages"
scene = "base.toml"
keys = ["cage.cad"]
values = {values}
label = "Cage"
"""


@pytest.fixture(scope="module")
def cad_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cadstudy")
    make_cad_cage(folder / "cage14.step")
    (folder / "variants").mkdir()
    make_cad_cage(folder / "variants" / "cage14_wide.step", dp=22.6)
    (folder / "base.toml").write_text(BASE)
    return folder


def _study(folder, values):
    p = folder / "study.toml"
    p.write_text(STUDY.format(values=json.dumps(values)))
    return p


def test_a_study_over_cad_files(cad_folder, monkeypatch):
    """Each run's cage is its file's (relative to the study file); the parameter is the file."""
    from flexbearing.studies.study import load_study
    monkeypatch.setenv("FLEXBEARING_CACHE", str(cad_folder / "cache"))
    study = load_study(_study(cad_folder, ["cage14.step", "variants/cage14_wide.step"]))
    assert [sc.bearing.cage.pocket_diameter for sc in study.scenes] == pytest.approx([22.4e-3, 22.6e-3], rel=1e-6)
    assert [sc.cad["file"] for sc in study.scenes] == [str(cad_folder / "cage14.step"),
                                                         str(cad_folder / "variants" / "cage14_wide.step")]
    assert [study.value_text(i) for i in range(2)] == ["cage14.step", "cage14_wide.step"]
    assert study.parameter == [0.0, 1.0]


def test_a_missing_cad_file_is_refused_before_any_run(cad_folder):
    from flexbearing.studies.study import load_study
    with pytest.raises(InputError, match=r"study.values\[1\] = 'variants/nope.step': no such file "
                                         r"\(for cage.cad, relative to the study file"):
        load_study(_study(cad_folder, ["cage14.step", "variants/nope.step"]))


def test_the_study_table_has_each_variants_cage_modes(cad_folder, monkeypatch):
    """Two CAD cages, their reduced cages (synthetic: frequencies 1x and 1.1x) built once each;
    study.json carries each run's first 6 elastic modes and study.md their table, row by file."""
    import flexbearing.studies.study as S
    from flexbearing.simulation.run import run_scene
    monkeypatch.setenv("FLEXBEARING_CACHE", str(cad_folder / "cache"))
    study = S.load_study(_study(cad_folder, ["cage14.step", "variants/cage14_wide.step"]))
    scale = {S.reduced_cage_hash(sc): 1.0 + 0.1 * i for i, sc in enumerate(study.scenes)}

    def build(scene, quiet):
        h = S.reduced_cage_hash(scene)
        return synthetic_reduced_cage(cad_folder / f"rc_{h}.h5", scale[h])

    def run(scene, path, quiet, cage=None):       # the same scene with a rigid cage: no FE here
        return run_scene(dataclasses.replace(scene, cage_model="rigid"), path, resume=True, quiet=True)

    monkeypatch.setattr(S, "_build_reduced_cage", build)
    monkeypatch.setattr(S, "_run_one", run)
    out = cad_folder / "out"
    result = S.run_study(study, out, workers=1, quiet=True)
    for r, s in zip(result["runs"], (1.0, 1.1)):
        assert [m["frequency_hz"] for m in r["cage_modes"]] == pytest.approx(
            [s * f for f in (500.0, 600.0, 1400.0, 1500.0, 1700.0, 2100.0)], rel=1e-12)
        assert [(m["family"], m["n"]) for m in r["cage_modes"]] == FAMILIES
    md = (out / "cad" / "study.md").read_text()
    table = md[md.index("## Cage modes"):].splitlines()
    assert table[4].startswith("| Cage | mode 7 | mode 8 |")
    assert table[6] == ("| cage14.step | 500.0 Hz in-plane bending n=2 | 600.0 Hz out-of-plane bending n=2 | "
                        "1400.0 Hz in-plane bending n=3 | 1500.0 Hz torsion n=0 | 1700.0 Hz out-of-plane "
                        "bending n=3 | 2100.0 Hz in-plane breathing n=0 |")
    assert table[7].startswith("| cage14_wide.step | 550.0 Hz in-plane bending n=2 |")
    assert "| cage14_wide.step |" in md[md.index("Pocket"):]              # the force tables, row by file
    assert json.loads((out / "cad" / "study.json").read_text())["runs"][1]["parameter_text"] == "cage14_wide.step"
