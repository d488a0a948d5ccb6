"""What a failed steady solve proves (flexbearing/multibody/steady_existence.py).

The turning-point test is checked against folds whose turning point is known in closed form:
F(u, lambda) = u² − (lambda* − lambda) (its branch u = sqrt(lambda* − lambda) turns at lambda*; the
quadratic model of the test is exact there, so lambda* is recovered to the round-off of the central
differences, ~1e-12 of F's scale), a rotated two-unknown fold with a cubic term (the model's error
is then measured and lambda* is recovered to second order: |error| <= (model error)·(lambda* −
lambda_k)), a regular branch (F = u − lambda: no fold, nothing certified) and a minimum of lambda (a
fold turning the other way: not a maximum, nothing certified). Soundness on the bearing: on the
paper bearing's held-cage branch (14,000 rpm, Fa 55 kN, Fr 4 kN), which reaches the full load, the
test must not certify a turning point below lambda = 1, neither at the symmetric state (lambda = 0)
nor at the converged state (lambda = 1). The traction–drag bound uses the EHL law's limit mu <=
gamma_L·scale, checked against the law itself over a sweep of slips.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from flexbearing.multibody import traction as T
from flexbearing.multibody.bearing import PAPER_BEARING as PRESET, PAPER_OIL
from flexbearing.multibody.hertz import effective_modulus, race_curvature_radii
from flexbearing.multibody.model import build_model
from flexbearing.multibody.steady_existence import traction_drag_bound, turning_point

LAM_STAR = 0.9


@pytest.mark.parametrize("lam_k", [0.5, 0.85, 0.899])
def test_quadratic_fold_is_certified_at_its_turning_point(lam_k):
    u_k = math.sqrt(LAM_STAR - lam_k)
    tp = turning_point(lambda v, lam: np.array([(u_k + v[0]) ** 2 - (LAM_STAR - lam)]), lam_k, 1)
    assert tp.certified and tp.is_maximum
    assert tp.lam_star == pytest.approx(LAM_STAR, abs=1e-10)
    assert tp.quadratic_model_error < 1e-10          # the model is exact for a quadratic
    assert "certified turning point" in tp.describe()


def test_rotated_fold_with_a_cubic_term():
    # p² + 0.3·p³ = lambda* − lambda, q = p²/2, (u1, u2) = R(0.7)·(p, q): lambda has its maximum
    # lambda* at p = 0. The quadratic model neglects the cubic term, so its lambda* is an estimate:
    # certified a maximum below 1 from every root, the estimate between the root and 1, and closer
    # to lambda* the closer the root (a local expansion: its error falls with lambda* − lambda_k)
    rot = np.array([[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]])

    def f(u, lam):
        p, q = rot.T @ u
        return np.array([p ** 2 + 0.3 * p ** 3 - (LAM_STAR - lam), 3.0 * (q - 0.5 * p ** 2)])
    errors = []
    for d in (0.3, 0.1, 0.03, 0.01, 0.003):
        p_k = brentq(lambda p: p ** 2 + 0.3 * p ** 3 - d, 0.0, 2.0)
        u_k = rot @ np.array([p_k, 0.5 * p_k ** 2])
        tp = turning_point(lambda v, lam: f(u_k + v, lam), LAM_STAR - d, 2)
        assert tp.is_maximum and tp.certified and 0.0 < tp.quadratic_model_error < 0.5
        assert LAM_STAR - d < tp.lam_star < 1.0
        errors.append(abs(tp.lam_star - LAM_STAR))
    assert all(b < a for a, b in zip(errors, errors[1:]))


def test_regular_branch_and_a_minimum_are_not_certified():
    tp = turning_point(lambda v, lam: np.array([v[0] + 0.5 - lam]), 0.5, 1)
    assert not tp.certified and tp.b == pytest.approx(0.0, abs=1e-6)
    assert "no turning point certified" in tp.describe()
    tp = turning_point(lambda v, lam: np.array([(0.3 + v[0]) ** 2 - (lam - 0.2)]), 0.29, 1)
    assert not tp.is_maximum and not tp.certified
    # a maximum beyond the full load proves nothing about lambda = 1
    tp = turning_point(lambda v, lam: np.array([(0.3 + v[0]) ** 2 - (1.2 - lam)]), 1.11, 1)
    assert tp.is_maximum and tp.lam_star == pytest.approx(1.2, abs=1e-10) and not tp.certified


def test_ehl_traction_never_exceeds_its_bound():
    # the law itself (not the bound's formula) over slips 1e-6 .. 1, light to heavy contacts
    e_eff = effective_modulus(210e9, 0.3, 210e9, 0.3)
    s = np.geomspace(1e-6, 1.0, 120)
    for scale in T.EHL_RANGES["traction_scale"]:
        tab = T.ehl_traction_table(PAPER_OIL.viscosity_temperature_coeff, scale)
        bound = T.ehl_traction_coefficient_bound(tab)
        assert bound == pytest.approx(T.EHL_LIMITING_SHEAR_COEFF * scale, rel=1e-15)
        for q in (50.0, 500.0, 5000.0):
            rx, ry = race_curvature_radii(0.022, 0.167, 0.52, math.radians(30.0), True)
            mu = T.ehl_traction_curve(s, q, rx, ry, e_eff, 40.0, PAPER_OIL, tab)
            assert np.all(np.abs(mu) <= bound)


def test_traction_drag_bound_fires_only_where_the_drag_exceeds_the_capacity():
    q_in, q_out = np.full((10, 2), [50.0, 0.0]), np.full(10, 60.0)
    b = traction_drag_bound(0.06, q_in, q_out, 0.1, drag_at_state=0.5)
    assert b.traction_capacity == pytest.approx(0.06 * 1100.0 * 0.1)
    assert not b.proves_no_steady_state and "does not exclude" in b.describe()
    b = traction_drag_bound(0.06, q_in, q_out, 0.1, drag_at_state=9.0, drag_at_rest=8.0)
    assert b.proves_no_steady_state and b.describe().startswith("no steady state")


@pytest.fixture(scope="module")
def paper_branch():
    from flexbearing.multibody.steady import _held_cage_solve, _symmetric_start, steady_held_cage_state
    model = build_model(PRESET.with_(radial_clearance=0.0), PAPER_OIL, {})
    w, load = 14000 * math.pi / 30, np.array([55e3, 0.0, -4e3])
    p = model.p.copy()
    p[model_layout_grav()] = 0.0
    _, at0 = _held_cage_solve(model._replace(p=p), w, np.array([55e3, 0.0, 0.0]), 0.0, 1e-9,
                              start=_symmetric_start(model, w, 55e3, 0.0))
    _, at1 = steady_held_cage_state(model, w, load)
    return model, w, load, at0, at1


def model_layout_grav():
    from flexbearing.multibody.model import P_GRAV
    return P_GRAV


def test_certificate_is_sound_on_a_branch_that_reaches_the_full_load(paper_branch):
    from flexbearing.multibody.steady import _branch_turning_point
    model, w, load, at0, at1 = paper_branch
    assert at0["converged"] and at1["converged"]
    for lam, info in ((0.0, at0), (1.0, at1)):
        tp = _branch_turning_point(model, w, load, 0.0, lam, info["unknowns"])
        assert not tp.certified, tp.describe()
        assert not (tp.is_maximum and tp.lam_star < 1.0)


@pytest.mark.slow
def test_uncertainty_run_whose_branch_folds_gets_a_certified_turning_point():
    """Point 23 of the uncertainty study, slip-rate case 6 (Fa 1100 N, Fr 200 N, 12,000 rpm, Si3N4 balls,
    oil at 75 °C): the held-cage continuation stops at lambda = 0.0507 (no root at 0.0519) with the
    Jacobian's condition rising as 1/sqrt(lambda* − lambda). The branch's verdict must be a certified
    fold: lambda has a maximum between the last root and the first lambda that failed, and its reason
    must say what that does not exclude. What it does not exclude is there: the deflated search finds
    a root at the full load on another branch (slip 71.9 %), where the cage stays held; the dynamics
    from the fold's last root drift towards it (slip 70.0 % after 5 s, still rising). 100–200 CPU-s: slow."""
    from flexbearing.multibody.steady import steady_held_cage_state
    from flexbearing.studies.uncertainty import case_problem, load_unknowns, sample_points
    from flexbearing.studies.validation import slip_rate as V
    point = sample_points(load_unknowns("scenes/slip_rate_unknowns.toml"))[23]
    _, info = steady_held_cage_state(*case_problem(point, V.slip_rate_cases()[5]), strict=False)
    # the branch through the symmetric thrust state: a certified fold below the full load
    failed = info["failed_continuation"]
    assert info["failed_verdict"] == "fold" and failed.startswith("fold: ") and "not excluded" in failed
    tp = info["turning_point"]
    lam_last, lam_fail = info["continuation"][-1], float(failed.split("residual ")[1].split(" at ")[1][:6])
    assert tp.certified and tp.is_maximum and tp.lam == lam_last
    assert lam_last < tp.lam_star <= lam_fail
    # what the fold did not exclude: another branch, found by the deflated search, with the cage held
    assert info["converged"] and info["residual"] <= 1e-9 and info["held"], info["reason"]
    assert info["root_search"]["roots"]
