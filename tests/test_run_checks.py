"""The physical checks of a finished run (flexbearing.simulation.run_checks) against independent values."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexbearing.simulation import run_checks as C
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL


def test_hertz_energy_bound_is_the_peak_of_a_suddenly_loaded_hertz_oscillator():
    """m·delta'' = F − K·delta^1.5 from rest at delta = 0 (undamped): the peak delta from the
    integrated motion equals (2.5·F/K)^(2/3), the bound's formula (energy: F·delta = 2/5·K·delta^2.5)."""
    K, F, m = 1.0e10, 5.0e4, 0.05
    stop = lambda t, y: y[1]                                  # velocity back to zero: the peak
    stop.terminal, stop.direction = True, -1
    sol = solve_ivp(lambda t, y: [y[1], (F - K * max(y[0], 0.0) ** 1.5) / m], (0, 1e-2), [0.0, 0.0],
                    events=stop, rtol=1e-11, atol=1e-16)
    peak = sol.y_events[0][0][0]
    assert peak == pytest.approx((2.5 * F / K) ** (2 / 3), rel=1e-6)
    # and the function: with the model's softest contact and no speed, the same formula
    model = M.build_model(PAPER_BEARING, PAPER_OIL, {})
    kmin = model.hertz_table[:2, :, M.H_K].min()
    assert C.hertz_approach_bound(model, F, 0.0) == pytest.approx((2.5 * F / kmin) ** (2 / 3), rel=1e-12)


def test_energy_check_passes_a_balanced_record_and_fails_a_broken_one():
    t = np.linspace(0.0, 1e-3, 101)
    loss = 1e3 + 200 * np.sin(2e4 * t)                         # W
    drive = np.full_like(t, 1.1e3)
    load = np.zeros_like(t)
    # E(t) = ∫ (drive − loss) dt exactly (closed form of the sine's integral)
    e = 1.1e3 * t - 1e3 * t + 200 * (np.cos(2e4 * t) - 1) / 2e4
    out = {"time": t, "mechanical_energy": e, "drive_power": drive, "power_loss": loss, "external_load_power": load}
    ok = C.check_energy(out)
    assert ok["ok"] and ok["value"] < 1e-3                     # trapezoid error of 100 samples only
    bad = dict(out, power_loss=2 * loss)                       # a source counted twice
    assert not C.check_energy(bad)["ok"]


def test_cage_clearance_check_allows_the_rims_elastic_penetration_only():
    model = M.build_model(PAPER_BEARING, PAPER_OIL, {})
    pen = 0.02                                                  # 2 % of Cg into the rim
    f_rim = pen * model.p[M.P_KRIM] * model.p[M.P_CG]
    inside = {"cage_eccentricity_ratio": np.array([0.3, 1.0 + pen]), "cage_rim_force": np.array([0.0, f_rim])}
    assert C.check_cage_clearance(inside, model)["ok"]
    beyond = {"cage_eccentricity_ratio": np.array([0.3, 1.0 + pen + 0.02]), "cage_rim_force": np.array([0.0, f_rim])}
    assert not C.check_cage_clearance(beyond, model)["ok"]
