import math
import subprocess
import sys

import numpy as np
import pytest


def test_cli_help_lists_commands_without_loading_fe_stack():
    code = ("import sys; from flexbearing.cli.main import build_parser; build_parser(); "
            "print('dolfinx' in sys.modules, 'gmsh' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_quasi_static_command_writes_an_equilibrium(tmp_path):
    # paper steady scene (55 kN / 4 kN, 14,000 rpm), outer race control with all the gyroscopic friction on the
    # outer race: the inner contacts carry no friction, so the ring's axial balance from the written loads and
    # angles is Fa = sum Q·sin(alpha) over the inner contacts (signed angles; flexbearing.multibody.quasi_static docstring)
    import json
    import math
    import numpy as np
    from flexbearing.cli.main import main
    out = tmp_path / "qs.json"
    assert main(["quasi-static", "scenes/paper_steady_rigid.toml", "--stiffness", "updated", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["converged"] and d["diagnostic"] == ""
    k = np.array(d["stiffness"])
    assert k.shape == (5, 5) and np.all(np.diag(k) > 0) and d["stiffness_kinematics"] == "updated"
    assert d["inputs"]["inner_speed"] == pytest.approx(14000 * math.pi / 30, rel=1e-12)
    q, a = np.array(d["load"]), np.array(d["contact_angle"])
    assert np.sum(q[:, 1:] * np.sin(a[:, 1:])) == pytest.approx(55e3, rel=1e-7)


def test_quasi_static_command_takes_the_load_of_the_instant(tmp_path, capsys):
    # paper unsteady scene: 4 kN radial plus a 50 kN half-sine radial impact centred in the uniform phase
    # (t = 0.3 s, the scene's own comment): the solve sees 54 kN there, 4 kN before the impact starts
    import json
    import math
    from flexbearing.cli.main import main
    for t, fr in ((0.3, 54e3), (0.0, 4e3)):
        out = tmp_path / f"qs{t}.json"
        assert main(["quasi-static", "scenes/paper_unsteady_rigid.toml", "--time", str(t), "--json", str(out)]) == 0
        fx, fy, fz = json.loads(out.read_text())["inputs"]["load"]
        assert math.hypot(fy, fz) == pytest.approx(fr, rel=1e-12) and fx == pytest.approx(55e3)
    assert main(["quasi-static", "scenes/paper_steady_rigid.toml", "--time", "5"]) == 2
    assert "--time = 5" in capsys.readouterr().err


def test_quasi_static_sweep_follows_the_profile(tmp_path, capsys):
    # --times along the unsteady scene (10,000 -> 14,000 -> 10,000 rpm, three 50 kN half-sine impacts centred at
    # 0.1, 0.3, 0.5 s): each warm-started row equals the cold solve of that instant (solver tolerance 1e-9 of the
    # load scale; measured 9e-10 over 61 instants), the impacts show as 54 kN rows, and the stiffness rows are
    # those of bearing_stiffness at the same equilibria
    import json
    import numpy as np
    from flexbearing.cli.main import main
    from flexbearing.simulation.scene import load_scene
    from flexbearing.simulation.quasi_static_scene import solve_scene
    from flexbearing.multibody.quasi_static import bearing_stiffness, grooves_from_bearing
    out = tmp_path / "sweep.json"
    assert main(["quasi-static", "scenes/paper_unsteady_rigid.toml", "--times", "0:0.6:7", "--stiffness", "updated",
                 "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert len(d["rows"]) == 7 and all(r["converged"] for r in d["rows"])
    scene = load_scene("scenes/paper_unsteady_rigid.toml")
    for r in d["rows"]:
        cold, inputs = solve_scene(scene, r["time"])
        assert r["inner_speed"] == pytest.approx(inputs["inner_speed"], rel=1e-12)
        np.testing.assert_allclose(r["max_load"], cold.load.max(axis=0), rtol=1e-7, atol=1e-7 * cold.load.max())
        k = bearing_stiffness(grooves_from_bearing(scene.bearing), cold, kinematics="updated")
        np.testing.assert_allclose(np.diag(r["stiffness"]), np.diag(k), rtol=1e-4)
    fr = [np.hypot(*r["load"][1:]) for r in d["rows"]]
    np.testing.assert_allclose(fr, [4e3, 54e3, 4e3, 54e3, 4e3, 54e3, 4e3], rtol=1e-12)
    for bad, field in (("0:0.7:5", "--times T1"), ("0.3:0.1:5", "--times T1"), ("0:0.6:1", "--times N"),
                       ("0:0.6", "--times")):
        assert main(["quasi-static", "scenes/paper_unsteady_rigid.toml", "--times", bad]) == 2
        assert field in capsys.readouterr().err
    for extra in (["--control", "friction"], ["--balls"]):
        assert main(["quasi-static", "scenes/paper_unsteady_rigid.toml", "--times", "0:0.6:3"] + extra) == 2
        assert "--times cannot be combined" in capsys.readouterr().err


def test_quasi_static_modes(tmp_path, capsys):
    # --modes: at rest the natural frequencies of flexbearing.multibody.vibration about the scene's equilibrium (the paper
    # case: 2090 Hz radial-tilt, 4028 Hz axial, 7326 Hz; tests/test_vibration.py strikes the dynamics there);
    # at speed with the paper's radial load refused before any solve (time-periodic system), naming the load
    import json
    from flexbearing.cli.main import main
    rest = tmp_path / "rest.toml"
    # the clearance-free paper bearing these frequencies are for (the preset's design clearance, issue 35,
    # gives 1520 / 3563 Hz: a softer two-point bearing)
    rest.write_text(open("scenes/paper_steady_rigid.toml").read().replace("rpm = 14000", "rpm = 0")
                    .replace("[bearing]", "[bearing]\nradial_clearance = 0.0", 1))
    out = tmp_path / "modes.json"
    assert main(["quasi-static", str(rest), "--modes", "6", "--json", str(out)]) == 0
    modes = json.loads(out.read_text())["modes"]
    assert modes["kind"] == "at rest" and len(modes["frequency"]) == 6
    f = modes["frequency"]
    for expect in (2089.9, 4028.4, 7326.0):
        assert min(abs(v / expect - 1) for v in f) < 1e-4
    capsys.readouterr()
    assert main(["quasi-static", "scenes/paper_steady_rigid.toml", "--modes", "4"]) == 2
    captured = capsys.readouterr()
    assert "radial load of 4000 N" in captured.err and "Qmax" not in captured.out


def test_quasi_static_friction_control_without_a_steady_state_says_why(monkeypatch, capsys):
    # a solve without a root: exit 1 and the solver's own reason on stderr (here a fold), not a generic guess;
    # the state printed is a stand-in (one ball), the solve is not what this tests
    from flexbearing.cli.main import main
    from flexbearing.simulation import quasi_static_scene as QS
    reason = "fold: the held-cage branch turns back at lambda* = 0.9754 of the radial load"
    info = dict(converged=False, residual=1e-4, reason=reason, cage_speed=600.0, slip_rate=0.02,
                ball_w_x=1.0, ball_w_r=2.0, ball_w_t=3.0)
    out = dict(contact_load=np.ones((1, 3)), contact_angle=np.full((1, 3), 0.5), contact_stress=np.ones((1, 3)))
    inputs = dict(state="thrust", load=[55e3, 0.0, 0.0], inner_speed=1466.0)
    monkeypatch.setattr(QS, "steady_scene", lambda scene, time=0.0: (None, info, out, inputs))
    assert main(["quasi-static", "scenes/paper_steady_rigid.toml", "--control", "friction"]) == 1
    err = capsys.readouterr().err
    assert reason in err and "flexbearing run" in err


def test_quasi_static_json_writes_a_solver_s_named_results_by_name(monkeypatch, tmp_path):
    # info holds dataclasses (a hold check) and NamedTuples: the file has their fields by name, and a
    # field kept out of the repr (the hold check's end state, a whole state vector) stays out
    import json
    from flexbearing.cli.main import main
    from flexbearing.simulation import quasi_static_scene as QS
    from flexbearing.multibody.steady_hold import CageHoldCheck
    from flexbearing.studies.uncertainty import SteadyCase
    hold = CageHoldCheck(0.03, 600.0, 601.0, 0.02, 0.021, 0.3, 0.31, 0.35, 0.01, True, 1.2, "", np.zeros(200))
    info = dict(converged=True, residual=1e-10, reason="", cage_speed=600.0, slip_rate=0.02, ball_w_x=1.0,
                ball_w_r=2.0, ball_w_t=3.0, cage_hold=hold, case=SteadyCase("model", 1466.0, (55e3, 0.0, 0.0)))
    out = dict(contact_load=np.ones((1, 3)), contact_angle=np.full((1, 3), 0.5), contact_stress=np.ones((1, 3)))
    inputs = dict(state="thrust", load=[55e3, 0.0, 0.0], inner_speed=1466.0)
    monkeypatch.setattr(QS, "steady_scene", lambda scene, time=0.0: (np.zeros(3), info, out, inputs))
    path = tmp_path / "s.json"
    assert main(["quasi-static", "scenes/paper_steady_rigid.toml", "--control", "friction", "--json", str(path)]) == 0
    d = json.loads(path.read_text())
    assert d["cage_hold"]["whirl_ratio"] == 0.01 and d["cage_hold"]["held"] is True
    assert "end_state" not in d["cage_hold"]
    assert d["case"] == {"model": "model", "speed_rad_s": 1466.0, "load": [55e3, 0.0, 0.0]}


def test_quasi_static_friction_control_is_the_steady_running_state(tmp_path, capsys):
    # --control friction runs flexbearing.multibody.steady on the scene (rigid cage, the scene's oil): the paper's steady scene
    # with its radial load removed gives the state of tests/test_steady.py; with its radial load the frozen-azimuth
    # held-cage state, whose film force carries the pockets' resultant (Newton's third law, 1e-6 N)
    import json
    import math
    from flexbearing.cli.main import main
    from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
    from flexbearing.multibody.model import build_model
    from flexbearing.multibody.steady import steady_thrust_state
    text = open("scenes/paper_steady_rigid.toml").read().replace("radial_load = 4e3", "radial_load = 0.0")
    scene = tmp_path / "thrust.toml"
    scene.write_text(text)
    out = tmp_path / "fr.json"
    assert main(["quasi-static", str(scene), "--control", "friction", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    _, info = steady_thrust_state(build_model(PAPER_BEARING, PAPER_OIL, {}), 14000 * math.pi / 30, 55e3)
    assert d["converged"] and d["slip_rate"] == pytest.approx(info["slip_rate"], rel=1e-9, abs=1e-12)
    assert d["inputs"]["state"] == "thrust"
    held = tmp_path / "held.json"
    # the clearance-free bearing: with the preset's design clearance the frozen-azimuth branch of this case
    # folds below the full radial load (tests/test_steady.py, slow) and the run is minutes long
    clear0 = tmp_path / "steady_rigid_pd0.toml"
    clear0.write_text(open("scenes/paper_steady_rigid.toml").read().replace("[bearing]", "[bearing]\nradial_clearance = 0.0", 1))
    assert main(["quasi-static", str(clear0), "--control", "friction", "--balls",
                 "--json", str(held)]) == 0
    text = capsys.readouterr().out
    d = json.loads(held.read_text())
    assert d["converged"] and d["inputs"]["state"] == "held_cage" and len(d["pocket_force"]) == 20
    np.testing.assert_allclose(np.add(d["cage_land_force"], d["pocket_resultant"][1:]), 0.0, atol=1e-6)
    assert "held-cage state" in text and "against the pockets' resultant" in text
    assert text.count("\n") > 20                     # --balls: one line per ball




def test_quasi_static_prints_a_settled_mean_as_a_mean(monkeypatch, capsys):
    # no held-cage root: the steady solver's settled mean of the dynamics is printed as a mean with its
    # 95 % half widths (rpm = rad/s * 30/pi), not as a frozen-azimuth state; the state is a stand-in
    from flexbearing.cli.main import main
    from flexbearing.multibody.steady_mean import SettledMean
    from flexbearing.simulation import quasi_static_scene as QS
    sm = SettledMean(True, -0.0238, 4e-5, 668.22, 0.025, 0.03, 0.1, 0.001, 0.24, 0.26, True, 4.0, "settled")
    info = dict(converged=True, residual=float("nan"), reason="settled mean: ...", kind="settled mean",
                settled_mean=sm, cage_speed=668.22, slip_rate=-0.0238, cage_centre=np.zeros(3),
                cage_eccentricity_ratio=0.24, cage_land_force=np.ones(2), pocket_resultant=np.ones(3))
    out = dict(contact_load=np.ones((1, 3)), contact_angle=np.full((1, 3), 0.5), contact_stress=np.ones((1, 3)),
               pocket_force=np.ones(1), pocket_force_tangential=np.ones(1))
    inputs = dict(state="held_cage", load=[55e3, 0.0, -4e3], inner_speed=1466.0)
    monkeypatch.setattr(QS, "steady_scene", lambda scene, time=0.0: (np.zeros(3), info, out, inputs))
    assert main(["quasi-static", "scenes/paper_steady_rigid.toml", "--control", "friction"]) == 0
    text = capsys.readouterr().out
    assert "settled mean" in text and "frozen-azimuth held-cage state" not in text
    assert "slip -2.380 ± 0.004 %" in text and f"{668.22 * 30 / math.pi:.2f} ± {0.025 * 30 / math.pi:.2f} rpm" in text
