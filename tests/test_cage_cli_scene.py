"""`mesh`/`modes` --scene: a bearing's own parametric cage (derived from its dimensions,
flexbearing.simulation.derived), and `modes --mesh FILE` records the geometry of the mesh it was
given (measured from its nodes) and the material it assumed, not the paper cage's numbers."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from flexbearing.cli.main import main
from flexbearing.simulation.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "catalogue_7014_rigid.toml"


def test_mesh_and_modes_of_a_scene_cage(tmp_path, capsys):
    msh = tmp_path / "c7014.msh"
    assert main(["mesh", "--scene", str(SCENE), "-o", str(msh), "--size", "8e-3", "--pocket-size", "6e-3",
                 "--order", "1"]) == 0
    out = capsys.readouterr().out
    assert "derived: cage.outside_diameter = 96.6098 mm" in out and "outer-land guided" in out
    from flexbearing.cli.modes import measured_mesh_geometry
    cage = load_scene(SCENE).bearing.cage
    geo = measured_mesh_geometry(msh)
    # the nodes lie on the cylinders and side faces (order 1: no curved-node repair); 1 µm is far
    # above the CAD kernel's tolerance and far below any paper value (178.45 / 161.15 / 28.3 mm)
    for k in ("outside_diameter", "bore_diameter", "width"):
        assert geo[k] == pytest.approx(getattr(cage, k), abs=1e-6), k
    assert geo["n_pockets"] == 20
    js = tmp_path / "modes.json"
    assert main(["modes", "--mesh", str(msh), "--order", "1", "--degree", "1", "--n-modes", "8",
                 "--no-classify", "--json", str(js)]) == 0
    out = capsys.readouterr().out
    res = json.loads(js.read_text())
    assert res["mesh"]["geometry"]["outside_diameter"] == pytest.approx(cage.outside_diameter, abs=1e-6)
    assert res["mesh"]["geometry"]["width"] == pytest.approx(cage.width, abs=1e-6)
    assert res["material"]["density"] == 7870.0 and "40CrNiMoA" in res["material"]["source"]
    assert "cage: outside Ø 96.61 mm, bore Ø 86.62 mm, width 19.19 mm, 20 pockets (measured" in out
    assert "material: 7870 kg/m³" in out


def test_scene_and_geometry_options_refused(capsys):
    assert main(["mesh", "--scene", str(SCENE), "--pocket-diameter-mm", "13", "-o", "x.msh"]) == 2
    err = capsys.readouterr().err
    assert "--pocket-diameter-mm: --scene" in err and "\n" == err[-1] and err.count("\n") == 1
