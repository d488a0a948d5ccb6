"""Scene loading: the paper scenes convert to the right arrays; bad scenes are refused before any
computation with the field, the value and the allowed range."""
import math
from pathlib import Path

import numpy as np
import pytest

from flexbearing.simulation.scene import RPM, load_scene, loads_scene
from flexbearing.common.validation import InputError

SCENES = Path(__file__).resolve().parents[1] / "scenes"

BASE = """
name = "t"
[operation]
duration = 0.1
[operation.speed]
phases = [{kind = "uniform", duration = 0.1, rpm = 10000}]
[operation.load]
axial_load = 1000.0
radial_load = 200.0
[output]
sample_interval = 1e-3
record = ["cage_speed"]
"""


def refused(text, *fragments):
    with pytest.raises(InputError) as exc:
        loads_scene(text)
    msg = str(exc.value)
    for f in fragments:
        assert f in msg, msg
    return msg


def test_paper_steady_rigid():
    s = load_scene(SCENES / "paper_steady_rigid.toml")
    assert s.cage_model == "rigid" and s.duration == 0.6
    # 14,000 rpm = 14,000·2·pi/60 rad/s = 1466.0766 rad/s
    np.testing.assert_allclose(s.speed_table[:, 1], 14000 * 2 * math.pi / 60, rtol=1e-15)
    np.testing.assert_allclose(s.load_table, [[0.0, 55e3, 0.0, -4e3]])
    assert s.impacts.shape == (0, 6)
    assert s.initial_loads() == (55e3, 4e3)
    assert s.n_samples == 6001 and s.sample_time(6000) == 0.6
    assert "von_mises" not in s.outputs


def test_paper_unsteady_spectra():
    s = load_scene(SCENES / "paper_unsteady.toml")
    assert s.cage_model == "flexible" and s.flexible["n_modes"] == 26
    np.testing.assert_allclose(s.speed_table, [[0.0, 10000 * RPM], [0.2, 14000 * RPM],
                                               [0.4, 14000 * RPM], [0.6, 10000 * RPM]], rtol=1e-15)
    # three 50 kN half-sine impacts of 0.02 s centred in each phase, along the radial load (-z)
    np.testing.assert_allclose(s.impacts, [[0.09, 0.02, 0, 0, -50e3, 0], [0.29, 0.02, 0, 0, -50e3, 0],
                                           [0.49, 0.02, 0, 0, -50e3, 0]], atol=1e-12)
    r = load_scene(SCENES / "paper_unsteady_rigid.toml")
    np.testing.assert_array_equal(r.speed_table, s.speed_table)
    np.testing.assert_array_equal(r.impacts, s.impacts)
    assert r.cage_model == "rigid"


def test_every_scene_in_scenes_dir_loads():
    from flexbearing.simulation.scene import load_case_set
    from flexbearing.studies.study import load_study
    for path in sorted(SCENES.glob("*.toml")):
        if "[unknowns." in path.read_text():        # the uncertainty study's unknowns (flexbearing.studies.uncertainty)
            from flexbearing.studies.uncertainty import load_unknowns
            with pytest.raises(InputError, match="flexbearing uncertainty"):
                load_scene(path)
            load_unknowns(path)
        elif "[case_set]" in path.read_text():
            with pytest.raises(InputError, match="is a case set"):
                load_scene(path)
            load_case_set(path)
        elif "[study]" in path.read_text():
            with pytest.raises(InputError, match="is a study"):
                load_scene(path)
            load_study(path)
        else:
            load_scene(path)


def test_unknown_keys_are_named_with_the_allowed_ones():
    refused("foo = 1\n" + BASE, "scene: unknown key 'foo'", "allowed:", "operation")
    refused(BASE + "\nfoo = 1\n", "output: unknown key 'foo'", "sample_interval")
    refused(BASE.replace("axial_load = 1000.0", "axial_lod = 1000.0"),
            "operation.load", "unknown key 'axial_lod'", "axial_load")
    refused(BASE + "\n[bearing]\nfe_ = 0.52\n", "bearing", "'fe_'", "fe, fi")
    refused(BASE.replace('rpm = 10000}', 'rpm = 10000, start_rpm = 1}'),
            "operation.speed.phases[0]", "'start_rpm'")


@pytest.mark.parametrize("value,frag", [("-1000.0", "operation.load.axial_load = -1000 N is outside "
                                                     "the allowed range [0, 1e+07] N"),
                                        ("nan", "operation.load.axial_load = nan must be finite"),
                                        ("inf", "operation.load.axial_load = inf must be finite"),
                                        ("true", "operation.load.axial_load = True is not a number"),
                                        ('"55kN"', "is not a number")])
def test_bad_loads(value, frag):
    refused(BASE.replace("axial_load = 1000.0", f"axial_load = {value}"), frag)


def test_bad_impact():
    imp = '\n[[operation.load.impacts]]\nt_center = 0.05\nduration = 0.02\nmagnitude = {m}\n'
    refused(BASE + imp.format(m="-5"), "operation.load.impacts[0].magnitude = -5 N", "[0, 1e+07]")
    refused(BASE + imp.format(m="5") + 'shape = "triangle"\n', "impacts[0].shape", "'half-sine'")
    # centre too early: the impact would start before t = 0
    refused(BASE + imp.format(m="5").replace("0.05", "0.005"), "impacts[0].t_center = 0.005 s",
            "[0.01, 0.1)")


def test_groove_curvature_and_pocket_diameter():
    refused(BASE + "\n[bearing]\nfe = 0.5\n", "bearing.fe = 0.5 is outside the allowed range (0.5, 0.6]")
    refused(BASE + "\n[bearing]\nfi = 0.45\n", "bearing.fi = 0.45", "(0.5, 0.6]")
    refused(BASE + "\n[cage]\npocket_diameter = 22e-3\n", "cage.pocket_diameter = 0.022 m",
            "(0.022, 0.0242] m")


def test_speed_profile_gaps_overlaps_jumps():
    ph = ('phases = [{kind = "ramp", duration = 0.05, start_rpm = 0, end_rpm = 10000},'
          ' {kind = "uniform", t_start = %s, duration = 0.05, rpm = 10000}]')
    base = BASE.replace('phases = [{kind = "uniform", duration = 0.1, rpm = 10000}]', ph)
    loads_scene(base % "0.05")
    refused(base % "0.06", "phases[1].t_start = 0.06 s leaves a gap", "[0.05, 0.05] s")
    refused(base % "0.04", "phases[1].t_start = 0.04 s leaves an overlap", "[0.05, 0.05] s")
    refused(BASE.replace('rpm = 10000}]', 'rpm = 10000}, {kind = "uniform", duration = 0.1, rpm = 12000}]')
            .replace("duration = 0.1\n[operation.speed]", "duration = 0.2\n[operation.speed]"),
            "phases[1] starts at 12000 rpm but the previous phase ends at 10000 rpm")
    table = BASE.replace('phases = [{kind = "uniform", duration = 0.1, rpm = 10000}]',
                         'table_rpm = [[0, 1000], [0.05, 2000], [0.04, 3000]]')
    refused(table, "table_rpm[2][0] (t) = 0.04 s", "overlap")
    refused(table.replace("[0.04, 3000]", "[0.05, 3000]"), "table_rpm[2][0] (t) = 0.05 s", "jump")
    refused(table.replace("[[0, 1000]", "[[0.01, 1000]"), "must start at t = 0")
    refused(BASE.replace("rpm = 10000}", "rpm = -10}"), "phases[0].rpm = -10 rpm", "[0, 60000] rpm")


def test_zero_duration_and_mismatch():
    refused(BASE.replace("duration = 0.1\n[operation.speed]", "duration = 0\n[operation.speed]"),
            "operation.duration = 0 s is outside the allowed range (0, 1000] s")
    refused(BASE.replace("duration = 0.1, rpm", "duration = 0.0, rpm"),
            "phases[0].duration = 0 s", "(0, 1000] s")
    refused(BASE.replace("duration = 0.1, rpm", "duration = 0.2, rpm"),
            "operation.duration = 0.1 s differs from the sum of the speed phases, 0.2 s")


def test_cage_and_output_consistency():
    refused(BASE.replace('record = ["cage_speed"]', 'record = ["cage_speed", "von_mises"]'),
            "'von_mises'", "cage.model = 'flexible'")
    refused(BASE + '\n[cage]\nmodel = "rigid"\nn_modes = 10\n', "cage.n_modes applies only to")
    refused(BASE + '\n[cage]\nmodel = "flexible"\nn_modes = 0\n', "cage.n_modes = 0", "[1, 500]")
    refused(BASE + '\n[cage]\nmodel = "elastic"\n', "cage.model = 'elastic'", "'rigid', 'flexible'")
    flex = BASE + '\n[cage]\nmodel = "flexible"\nstress_monitor_interval = %s\n'
    assert loads_scene(flex % "5").flexible["stress_monitor_interval"] == 5
    assert "stress_monitor_interval" not in loads_scene(BASE + '\n[cage]\nmodel = "flexible"\n').flexible
    refused(flex % "0", "cage.stress_monitor_interval = 0", "[1, 10000]")
    refused(flex % "2.5", "cage.stress_monitor_interval = 2.5", "integer in [1, 10000]")
    refused(flex % "10001", "cage.stress_monitor_interval = 10001", "[1, 10000]")
    refused(BASE + '\n[cage]\nmodel = "rigid"\nstress_monitor_interval = 2\n',
            "cage.stress_monitor_interval applies only to")
    refused(BASE.replace('record = ["cage_speed"]', 'record = ["cage_sped"]'),
            "output.record[0] = 'cage_sped'", "'cage_speed'")
    refused(BASE.replace("sample_interval = 1e-3", "sample_interval = 1.0"),
            "output.sample_interval = 1 s", "[1e-07, 0.1] s")   # issue 36: bounded below
    refused(BASE.replace("[operation]", "[operatio]"), "unknown key 'operatio'")


def test_load_points_table_and_directions():
    s = loads_scene(BASE.replace("axial_load = 1000.0\nradial_load = 200.0",
                                 "points = [{t = 0.0, axial_load = 0.0, radial_load = 0.0},"
                                 " {t = 0.05, axial_load = 1000.0, radial_load = 200.0}]\n"
                                 "radial_azimuth = 0.0"))
    np.testing.assert_allclose(s.load_table, [[0, 0, 0, 0], [0.05, 1000, 200, 0]])
    s = loads_scene(BASE.replace("axial_load = 1000.0\nradial_load = 200.0",
                                 "table = [[0.0, 10.0, -20.0, 30.0]]"))
    np.testing.assert_allclose(s.load_table, [[0, 10, -20, 30]])
    refused(BASE.replace("radial_load = 200.0", "radial_load = 200.0\nradial_direction = [1, 0, 0]"),
            "must be radial")
    s = loads_scene(BASE + '[[operation.load.impacts]]\nt_start = 0.01\nduration = 0.01\nmagnitude = 100.0\n'
                    'direction = [1.0, 0.0, 0.0]\nshape = "rectangular"\n')
    np.testing.assert_allclose(s.impacts, [[0.01, 0.01, 100, 0, 0, 1]])
    refused(BASE.replace("axial_load = 1000.0", "axial_load = 1000.0\npoints = [{t = 0}]"),
            "either points or axial_load/radial_load")


def test_bearing_overrides_and_oil_preset():
    s = loads_scene(BASE + '\n[bearing]\nfe = 0.52\nfi = 0.53\n[bearing.ball_material]\ndensity = 3200.0\n'
                    '[oil]\npreset = "engine"\ntemperature_c = 90.0\n[cage]\npocket_diameter = 22.6e-3\n')
    assert (s.bearing.fe, s.bearing.fi, s.bearing.ball_material.density) == (0.52, 0.53, 3200.0)
    assert s.bearing.cage.pocket_diameter == 22.6e-3 and s.oil.temperature_c == 90.0
    refused(BASE + '\n[oil]\npreset = "castor"\n', "oil.preset = 'castor'", "'paper', 'engine'")
    refused(BASE + '\n[oil]\ntemperature_c = 400.0\n', "oil.temperature_c = 400", "[-60, 250]")


def test_scene_hash_ignores_comments():
    a = loads_scene(BASE)
    b = loads_scene("# a comment\n" + BASE)
    c = loads_scene(BASE.replace("1000.0", "1001.0"))
    assert a.content_hash() == b.content_hash() != c.content_hash()


def test_toml_syntax_error_is_input_error():
    refused("name = ", "not valid TOML")


def test_integrator_method_key():
    """[integrator] method: the integrator's methods, named in the refusal; dopri5 by default."""
    from flexbearing.simulation.scene import INTEGRATOR_METHODS
    from flexbearing.multibody.integrator import METHODS
    assert tuple(sorted(INTEGRATOR_METHODS)) == tuple(sorted(METHODS))
    assert loads_scene(BASE).method == "dopri5"
    assert loads_scene(BASE + '[integrator]\nmethod = "bs32"\n').method == "bs32"
    refused(BASE + '[integrator]\nmethod = "rk4"\n', "integrator.method", "'rk4'", "'dopri5'", "'bs32'")


def test_a_scene_run_with_bs32_integrates_with_bs32(tmp_path):
    """The scene's method reaches the integrator: 2 ms of the paper's steady rigid scene with bs32
    take the steps of flexbearing.multibody.integrator.advance_sampled with method bs32 from the same initial
    state (21 samples: one call of the run loop, flexbearing.simulation.run.SAMPLES_PER_CALL), and not dopri5's,
    which are fewer (3rd against 5th order at the same tolerance)."""
    import tomllib
    from flexbearing.simulation.run import SAMPLES_PER_CALL, default_backend, run_scene
    from flexbearing.simulation.scene import parse_scene
    from flexbearing.multibody import integrator as I
    data = tomllib.loads((SCENES / "paper_steady_rigid.toml").read_text())
    data["operation"]["duration"] = 0.002
    data["operation"]["speed"]["phases"][0]["duration"] = 0.002
    data["integrator"]["method"] = "bs32"
    data["output"]["record"] = ["cage_speed"]
    scene = parse_scene(data, path="bs32.toml")
    s = run_scene(scene, tmp_path / "bs32.h5", quiet=True)
    assert s["integrator_method"] == "bs32"
    be = default_backend(scene)
    model = be.build_model(scene.bearing, scene.oil, dict(scene.model_options))
    f0 = np.zeros(3)
    from flexbearing.multibody.profiles import load_at, speed_at
    load_at(0.0, scene.load_table, scene.impacts, f0)
    Fa, Fr = scene.initial_loads()
    steps = {}
    for method in ("bs32", "dopri5"):
        y = np.array(be.initial_state(model, speed_at(0.0, scene.speed_table), Fa, Fr, load=f0))
        times = np.array([scene.sample_time(k) for k in range(1, scene.n_samples - 1)])
        _, _, _, n, _, _, _ = I.advance_sampled(model, y, 0.0, scene.duration, times, scene.speed_table,
                                                scene.load_table, scene.impacts, scene.tolerance,
                                                scene.initial_step, I.Workspace(model, method))
        steps[method] = n
    assert scene.n_samples <= SAMPLES_PER_CALL
    assert s["n_steps"] == steps["bs32"] > steps["dopri5"]
