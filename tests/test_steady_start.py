"""A run that starts from the steady running state ([integrator] start = "steady";
flexbearing.multibody.steady_start.steady_start), and its fallback to the quasi-static start.

What must hold: the steady start is the steady solver's state itself (the thrust state: the same
call, bit for bit); where the solver reports no root or raises, the run starts from the
quasi-static state unchanged and says so in one line; a flexible cage's centrifugal deformation
follows the cage speed squared; the scene key is read, refused in one line when wrong, and absent
from the paper scenes (their start, and so their results, unchanged).
"""
from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from flexbearing.common.validation import InputError
from flexbearing.multibody import initial, steady, steady_start
from flexbearing.multibody import model as M
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.simulation import scene as S

W = 14000 * math.pi / 30
FA = 55e3


@pytest.fixture(scope="module")
def thrust():
    model = M.build_model(PAPER_BEARING, PAPER_OIL, {})
    y_qs = initial.initial_state(model, W, FA, 0.0)
    return model, y_qs


def test_scene_key(tmp_path):
    base = S.load_scene("scenes/paper_steady.toml")
    assert base.start == "quasi_static" and "start" not in base.data.get("integrator", {})
    assert S.START_KINDS == steady_start.START_KINDS
    text = base.text.replace("[integrator]", '[integrator]\nstart = "steady"')
    assert S.loads_scene(text).start == "steady"
    with pytest.raises(InputError, match=r"^integrator.start = 'warm' must be one of 'quasi_static', 'steady'$"):
        S.loads_scene(base.text.replace("[integrator]", '[integrator]\nstart = "warm"'))
    for name in ("paper_steady", "paper_unsteady", "paper_steady_rigid", "paper_unsteady_rigid"):
        assert S.load_scene(f"scenes/{name}.toml").start == "quasi_static"


def test_steady_start_is_the_thrust_state(thrust):
    model, y_qs = thrust
    y, info = steady_start.steady_start(model, W, (FA, 0.0, 0.0), y_qs)
    y_ref, s = steady.steady_thrust_state(model, W, FA)
    assert info["start"] == "steady" and info["solver"] == "steady_thrust_state" and s["converged"]
    np.testing.assert_array_equal(y, y_ref)
    assert info["cage_speed"] == s["cage_speed"]
    assert steady_start.start_line(info).startswith("start: steady state of the first phase (steady_thrust_state")


class NoRoot(RuntimeError):
    """Stands for the solvers' non-convergence exception."""


@pytest.mark.parametrize("how", ["raises", "not converged"])
def test_fallback_to_the_quasi_static_start(thrust, monkeypatch, how):
    model, y_qs = thrust

    def solver(*a, **k):
        if how == "raises":
            raise NoRoot("no root in reach")
        return y_qs * 0.0 + 1.0, {"converged": False, "residual": 0.3, "reason": ""}
    monkeypatch.setattr(steady, "steady_thrust_state", solver)
    y, info = steady_start.steady_start(model, W, (FA, 0.0, 0.0), y_qs)
    np.testing.assert_array_equal(y, y_qs)
    assert info["start"] == "quasi_static"
    line = steady_start.start_line(info)
    assert "\n" not in line and line.endswith("falling back to the quasi-static start")
    assert ("NoRoot: no root in reach" if how == "raises" else "residual 3.00e-01") in line


def test_flexible_cage_modes_follow_the_spin_squared(thrust):
    """The modal block (q, then q_dot) of a flexible state: q scaled by (omega_s/omega_qs)², q_dot
    left at its value (0 at the start); the rigid part the steady state's."""
    model, y_qs = thrust
    q = np.array([1e-6, -2e-7, 3e-8])
    y_flex = np.concatenate([y_qs, q, np.zeros(3)])
    y, info = steady_start.steady_start(model, W, (FA, 0.0, 0.0), y_flex)
    c = M.state_layout(model)["cage"] + SL.CAGE_OMEGA
    n = len(y_qs)
    ratio = (y[c] / y_qs[c]) ** 2
    assert info["start"] == "steady" and ratio != 1.0
    np.testing.assert_allclose(y[n:n + 3], q * ratio, rtol=1e-15)
    assert np.all(y[n + 3:] == 0.0)


def test_a_run_from_the_steady_state(tmp_path, capsys):
    """A 1 ms rigid run of the thrust case with start = "steady": the file records the start, and
    the first sample is the steady state (cage speed equal to the solver's, within rounding of the
    output's evaluation)."""
    from flexbearing.simulation.run import run_scene
    text = """name = "steady_start"
[operation]
duration = 1e-3
[operation.speed]
phases = [{ kind = "uniform", duration = 1e-3, rpm = 14000 }]
[operation.load]
axial_load = 55e3
[integrator]
tolerance = 1e-4
start = "steady"
[output]
sample_interval = 1e-4
record = ["cage_speed", "slip"]
"""
    (tmp_path / "s.toml").write_text(text)
    scene = S.load_scene(tmp_path / "s.toml")
    run_scene(scene, tmp_path / "r.h5", quiet=True)
    err = capsys.readouterr().err
    assert "start: steady state of the first phase (steady_thrust_state" in err
    _, s = steady.steady_thrust_state(M.build_model(scene.bearing, scene.oil, {}), W, FA)
    with h5py.File(tmp_path / "r.h5", "r") as f:
        assert str(f.attrs["initial_state"]).startswith("steady state of the first phase")
        assert f["outputs/cage_speed"][0] == pytest.approx(s["cage_speed"], rel=1e-12)
