"""Contact stress under a radial impact against the quasi-static equilibrium (flexbearing.analysis.amplification).

References:
* the shock spectrum of the undamped oscillator under a half-sine pulse (Biggs 1964 ch. 2; Clough &
  Penzien ch. 6), here against a direct integration of x'' + w² x = w² x_st sin(pi t/t_d) (scipy, rtol
  1e-11) and its known values: pi/2 at t_d/T_n = 1/2, the maximum 1.768 near t_d/T_n = 0.81, -> 1 for
  long pulses;
* the quasi-static limit: a pulse that lasts ~130 natural periods of the ring on the bearing must give
  the quasi-static contact stress of the peak load (amplification 1), the dynamics and the independent
  quasi-static solver agreeing at 54 kN radial + 55 kN axial at 14,000 rpm.
"""
import math

import h5py
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexbearing.analysis.amplification import half_sine_daf, impact_amplification, pulse_scene
from flexbearing.simulation.results import scene_of_run as run_scene
from flexbearing.analysis.windows import quantity_arrays


def _integrated_daf(r):
    w = 2 * math.pi
    f = lambda t, y: [y[1], w * w * ((math.sin(math.pi * t / r) if t < r else 0.0) - y[0])]
    s = solve_ivp(f, [0, r], [0, 0], max_step=1 / 2000, rtol=1e-11, atol=1e-13)
    residual = math.hypot(s.y[0, -1], s.y[1, -1] / w)       # free-vibration amplitude after the pulse
    return max(np.max(np.abs(s.y[0])), residual)


@pytest.mark.parametrize("r", [0.1, 0.25, 0.4, 0.6, 0.81, 1.0, 1.3, 2.0, 3.7, 10.0])
def test_half_sine_shock_spectrum_against_integration(r):
    # measured agreement 6e-7 (the integration's accuracy)
    assert half_sine_daf(r) == pytest.approx(_integrated_daf(r), rel=1e-5)


def test_half_sine_shock_spectrum_known_values():
    assert half_sine_daf(0.5) == pytest.approx(math.pi / 2, rel=1e-12)
    rs = np.linspace(0.3, 2.0, 1701)
    d = np.array([half_sine_daf(r) for r in rs])
    assert d.max() == pytest.approx(1.768, abs=1e-3) and rs[d.argmax()] == pytest.approx(0.81, abs=0.01)
    assert half_sine_daf(1000.0) == pytest.approx(1.0, abs=1e-3)
    with pytest.raises(ValueError):
        half_sine_daf(0.0)


def _amplification(tmp_path, td, duration, t_center):
    from flexbearing.cli.main import main
    scene = tmp_path / f"impact_{td}.toml"
    scene.write_text(pulse_scene(td, t_center, duration))
    run = tmp_path / f"impact_{td}.h5"
    assert main(["run", str(scene), "-o", str(run), "--quiet", "--force"]) == 0
    with h5py.File(run, "r") as f:
        items = impact_amplification(run_scene(f), f["outputs/time"][...], quantity_arrays(f["outputs"]))
    assert len(items) == 1 and items[0]["converged"]
    return items[0]


def test_a_long_impact_is_quasi_static_for_the_contacts(tmp_path):
    # The paper's 20 ms, 50 kN radial pulse at 14,000 rpm (55 kN axial, 4 kN radial). The ring's radial natural
    # period on the bearing is ~0.22 ms (ring mass 0.94 kg on the secant stiffness 7.7e8 N/m from 4 to 54 kN), so
    # t_d/T_n ~ 90 and the one-DOF shock spectrum gives 1.006. The run's worst-ball peak must equal the quasi-static equilibrium at the pulse's
    # peak: measured 1.002 (outer), 1.001 (inner). Tolerance [0.995, 1.01]: a ball passes the load line within
    # ±0.24 ms of the peak (20 balls at the cage's ~6300 rpm), where the pulse is within 0.1 % of its peak, plus
    # the small dynamic overshoot of the one-DOF estimate.
    a = _amplification(tmp_path, 0.02, 0.05, 0.03)
    assert 50 < a["duration_over_period"] < 200
    assert a["one_dof_amplification"] == pytest.approx(1.0, abs=0.01)
    for key in ("outer_contact_stress", "inner_contact_stress"):
        assert 0.995 < a[f"{key}_amplification"] < 1.01
    assert a["quasi_static_outer_contact_stress"] == pytest.approx(2.69e9, rel=0.02)   # paper-scale check (Hertz)


def test_a_short_impact_amplifies_the_contact_stress(tmp_path):
    # A 0.3 ms pulse (t_d/T_n ~ 1.4): the ring overshoots the static position, so the worst contact stress
    # exceeds the quasi-static one (measured 1.09 outer, 1.05 inner), unlike the 20 ms pulse. The one-DOF estimate
    # (1.57, for the displacement) is not the stress ratio: p0 grows as Q^(1/3) and most of the contact load is the
    # 55 kN axial preload, so only a lower bound of 3 % is asserted.
    a = _amplification(tmp_path, 0.0003, 0.012, 0.01)
    assert a["outer_contact_stress_amplification"] > 1.03
    assert a["inner_contact_stress_amplification"] > 1.03
    assert a["response_window"][1] > a["t_end"]
