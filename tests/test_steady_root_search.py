"""Other held-cage roots where the steady solver found none (flexbearing.multibody.steady_root_search)."""
import math

import numpy as np
import pytest

from flexbearing.multibody.steady_search_starts import load_at, physical_starts


def test_the_starts_follow_the_rolling_laws():
    # a stand-in model: 2 balls, pocket clearance angle cp/R = 1e-3 (only n_balls and p are read)
    from types import SimpleNamespace
    from flexbearing.multibody import model as M
    p = np.zeros(max(M.P_CP, M.P_RCAGE_POCKET) + 1)
    p[M.P_CP], p[M.P_RCAGE_POCKET] = 2e-5, 2e-2
    model = SimpleNamespace(n_balls=2, p=p)
    omega_i, omega_ref = 1000.0, 400.0
    u_ref = np.zeros(6 * 2 + 11)
    u_ref[3:12:6], u_ref[4:12:6], u_ref[5:12:6] = 3000.0, -500.0, 20.0
    u_ref[12] = omega_ref
    starts = physical_starts(model, omega_i, u_ref, fractions=(0.2,))
    assert len(starts) == 4                                   # 2 rolling laws x 2 walls
    outer, inner = starts[0], starts[2]
    assert outer[12] == 200.0 and inner[12] == 200.0
    # outer race at rest: the spin scales with the cage speed, 200/400
    assert np.array_equal(outer[3:6], np.array([3000.0, -500.0, 20.0]) * 0.5)
    # inner race turning: (w - omega_i e_x) scales with (omega_i - omega_c), 800/600
    assert np.allclose(inner[3:6], np.array([1000.0 + 2000.0 * 800 / 600, -500.0 * 800 / 600, 20.0 * 800 / 600]),
                       rtol=4 * np.finfo(float).eps)
    # the same operations in the same order as the code: equal bits
    assert starts[0][2] == 0.6 * 2e-5 / 2e-2 and starts[1][2] == -(0.6 * 2e-5 / 2e-2)
    assert np.array_equal(load_at([1.0, 2.0, -3.0], 0.5), [1.0, 1.0, -1.5])


@pytest.mark.slow
def test_study_run_25_6_has_a_held_root_at_the_full_load():
    """Study run 25/6 (no thrust root in reach of the solver): deflated Newton from the start at omega_c
    = 0.05 omega_i, spins by the outer race's rolling law, pocket offsets on the trailing wall, built on
    the direct solve's end, reaches a root of the held-cage equations at the full load (tolerance: the
    solver's, 1e-9) in which the cage stays held in the dynamics (benchmarks/steady_failures.py)."""
    from flexbearing.multibody.steady import _held_cage_solve
    from flexbearing.multibody.steady_root_search import held_cage_root_search
    from flexbearing.studies.uncertainty import load_unknowns, point_bearing_oil, sample_points
    from flexbearing.studies.validation import slip_rate as V

    point = sample_points(load_unknowns("scenes/slip_rate_unknowns.toml"))[25]
    case = V.slip_rate_cases()[6 - 1]
    bearing, oil, scale = point_bearing_oil(point, case["speed_rpm"])
    model = V.build_validation_model(bearing, oil, V.validation_model_options(), "ehl", scale)
    omega = case["speed_rpm"] * 2.0 * math.pi / 60.0
    load = np.array([case["axial_load"], 0.0, -case["radial_load"]])
    _, direct = _held_cage_solve(model, omega, load, 0.0, 1e-9)
    assert not direct["converged"]
    u_ref = direct["unknowns"]
    found = held_cage_root_search(model, omega, load, u_ref, [physical_starts(model, omega, u_ref)[1]])
    assert len(found.roots) == 1
    root = found.roots[0]
    assert root["converged"] and root["residual"] <= 1e-9 and root["held"]


def test_the_bracketed_root_by_illinois_regula_falsi():
    # a stand-in reduced problem whose torque balance is g(omega) = omega³ − 2: the root 2^(1/3) in [1, 2]
    from flexbearing.multibody.steady_root_search import _root_in_bracket

    class Cubic:
        def solve(self, lam, omega, u):
            return np.array([omega]), omega ** 3 - 2.0
    w, u, g = _root_in_bracket(Cubic(), 1.0, (1.0, (np.array([1.0]), -1.0)), (2.0, (np.array([2.0]), 6.0)), 1e-12)
    assert abs(g) <= 1e-12
    # |w − w*| <= |g| / g'(w*), g'(w*) = 3·2^(2/3) > 4.7, plus the rounding of w³ (a few ulp of 2)
    assert abs(w - 2.0 ** (1.0 / 3.0)) <= 1e-12 / 4.7 + 8 * np.finfo(float).eps
