"""Race-control mechanisms of issue 35 item 4: the ball's drag moment, the inner-spin diagnostic
and the gyroscopic demand of a measured slip (docs/race_control.md)."""
import math

import numpy as np
import pytest
from tolerances import U, assert_within, gamma
from scipy.integrate import quad

from flexbearing.common.validation import InputError
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.drag import ball_drag_moment_coefficient, oil_air_mixture
from flexbearing.studies.validation import kinematics as RC
from flexbearing.studies.validation import slip_rate as V
from flexbearing.studies.gyroscopic_demand import gyroscopic_demand, pitch_for_slip


def test_drag_moment_is_the_stokes_couple_of_the_rotating_sphere_flow():
    # Creeping flow round a sphere of radius R turning at w (Lamb §334): u_phi = w·R³·sin(th)/r²,
    # wall shear tau_r_phi = eta·r·d(u_phi/r)/dr = −3·eta·w·sin(th) at r = R; the couple is the
    # integral of its moment R·sin(th) over the sphere: 8·pi·eta·R³·w, independently of the formula
    eta, dw, w = 0.0123, 0.022, 1700.0
    r = 0.5 * dw
    couple, _ = quad(lambda th: 3.0 * eta * w * math.sin(th) * r * math.sin(th) * 2.0 * math.pi * r * r * math.sin(th),
                     0.0, math.pi)
    assert ball_drag_moment_coefficient(dw, eta) * w == pytest.approx(couple, rel=1e-12)


def _model_and_state(options):
    bearing = V.validation_bearing()
    oil = V.validation_oil(None, 0.05)
    model = M.build_model(bearing, oil, {"gravity": 0.0, "traction_law": "ehl", **options})
    omega, y, sp, ld, imp = V.steady_case_start(model, {"axial_load": 1100.0, "radial_load": 200.0,
                                                        "speed_rpm": 4000.0})
    y = y.copy()
    z = model.n_balls
    for j in range(z):                 # a yaw and a pitch, so every component of w is exercised
        y[9 * j + 7] += 40.0
        y[9 * j + 8] -= 15.0
    return model, y, sp, ld, imp


def _rhs(model, y, sp, ld, imp):
    work = D.new_work(model)
    dydt = np.zeros_like(y)
    D.rhs(0.0, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld, imp, work,
          model.cage)
    return dydt, work


def test_drag_moment_in_the_equations_of_motion_and_in_the_power_balance():
    off, y, sp, ld, imp = _model_and_state({})
    on = M.build_model(V.validation_bearing(), V.validation_oil(None, 0.05),
                       {"gravity": 0.0, "traction_law": "ehl", "ball_drag_moment": True})
    d_off, w_off = _rhs(off, y, sp, ld, imp)
    d_on, w_on = _rhs(on, y, sp, ld, imp)
    p = off.p
    _, eta_mix = oil_air_mixture(p[M.P_OILFRAC], p[M.P_RHO_OIL], p[M.P_ETA0])
    c = math.pi * eta_mix * p[M.P_DW] ** 3
    for j in range(off.n_balls):
        w = y[9 * j + 6:9 * j + 9]
        # free ball: I_b·dw/dt gains −c·w on every component (Euler's equations, dynamics docstring)
        np.testing.assert_allclose(d_on[9 * j + 6:9 * j + 9] - d_off[9 * j + 6:9 * j + 9], -c * w / p[M.P_IB],
                                   rtol=1e-9, atol=1e-9 * np.abs(d_off[9 * j + 6:9 * j + 9]).max())
        # and it dissipates c·|w|², counted with the churning loss
        # the kernel adds c |w|^2 (<= 5 roundings) to the translational drag power, the same
        # operations with the option off: the sum rounds by u |w_on|, the difference here by u
        # (Higham §2.2), so 2 gamma_5 c |w|^2 + u (|w_on| + |w_on - w_off|) + u |w_on|
        won, woff = w_on[j, M.W_P_CHURNING], w_off[j, M.W_P_CHURNING]
        dw = c * float(w @ w)
        assert_within(abs(won - woff - dw), 2 * gamma(5) * dw + U * (2 * abs(won) + abs(won - woff)),
                      "churning power of the drag moment", effect=dw)
    # nothing else moves: translations and the other bodies
    np.testing.assert_array_equal(np.delete(d_on, [9 * j + k for j in range(off.n_balls) for k in (6, 7, 8)]),
                                  np.delete(d_off, [9 * j + k for j in range(off.n_balls) for k in (6, 7, 8)]))


def test_new_options_off_by_default_are_bit_identical():
    base, y, sp, ld, imp = _model_and_state({})
    assert base.flags[M.F_BALL_DRAG_MOMENT] == 0 and base.p[M.P_SPIN_SCALE_INNER] == 1.0
    explicit, *_ = _model_and_state({"ball_drag_moment": False, "spin_moment_scale_inner": 1.0})
    np.testing.assert_array_equal(_rhs(base, y, sp, ld, imp)[0], _rhs(explicit, y, sp, ld, imp)[0])


def test_inner_spin_scale_multiplies_one_term():
    # the diagnostic multiplies the inner contacts' spin couple only: the ball's angular
    # accelerations are affine in the factor, everything else is unchanged
    d = {}
    for k in (1.0, 3.0, 5.0):
        model, y, sp, ld, imp = _model_and_state({"spin_moment_scale_inner": k})
        d[k] = _rhs(model, y, sp, ld, imp)[0]
    assert np.abs(d[3.0] - d[1.0]).max() > 0.0
    np.testing.assert_allclose(d[5.0] - d[1.0], 2.0 * (d[3.0] - d[1.0]), rtol=1e-8,
                               atol=1e-9 * np.abs(d[1.0]).max())
    with pytest.raises(InputError, match="spin_moment_scale_inner"):
        _model_and_state({"spin_moment_scale_inner": 0.0})


GEOM = dict(ball_diameter=0.022, pitch_diameter=0.167)


def test_pitch_for_slip_recovers_jones_inner_race_control():
    # the slip of Jones's inner-race control (Harris: tan beta = sin a_i/(cos a_i − gamma)) gives back its pitch
    a_i, a_o, n = 39.0, 13.5, 4000.0
    br = RC.brackets(n, GEOM["ball_diameter"], GEOM["pitch_diameter"], a_i, a_o)
    beta = pitch_for_slip(br.inner_slip_percent, n, GEOM["ball_diameter"], GEOM["pitch_diameter"],
                          math.radians(a_i), math.radians(a_o))
    assert math.degrees(beta) == pytest.approx(br.inner.pitch_angle_deg, abs=1e-9)
    gamma = GEOM["ball_diameter"] / GEOM["pitch_diameter"]
    assert math.tan(beta) == pytest.approx(math.sin(math.radians(a_i)) / (math.cos(math.radians(a_i)) - gamma),
                                           rel=1e-9)
    with pytest.raises(ValueError, match="slip_percent"):
        pitch_for_slip(-60.0, n, GEOM["ball_diameter"], GEOM["pitch_diameter"], math.radians(a_i), math.radians(a_o))


def test_gyroscopic_demand_against_long_hand_values():
    # beta = 0 (slip of pure rolling with the axis on the bearing axis): no couple
    a_i, a_o, n, mb = math.radians(39.0), math.radians(13.5), 4000.0, 0.0435
    gamma = GEOM["ball_diameter"] / GEOM["pitch_diameter"]
    r0, _ = RC.cage_speed_ratio(gamma, a_i, a_o, 0.0)
    nm = 0.5 * (1.0 - gamma * math.cos(0.5 * (a_i + a_o)))
    g0 = gyroscopic_demand(100.0 * (1.0 - r0 / nm), n, GEOM["ball_diameter"], GEOM["pitch_diameter"], mb,
                           a_i, a_o, 230.0, 87.0)
    assert abs(g0.gyroscopic_couple) < 1e-9 and g0.pitch_deg < 1e-9
    # beta = 30°: M_g = (m Dw²/10)·omega_R·omega_c·sin 30°, mu = M_g/((Dw/2)(Q_o + Q_i)), by hand
    beta = math.radians(30.0)
    ratio, spin = RC.cage_speed_ratio(gamma, a_i, a_o, beta)
    g = gyroscopic_demand(100.0 * (1.0 - ratio / nm), n, GEOM["ball_diameter"], GEOM["pitch_diameter"], mb,
                          a_i, a_o, 230.0, 87.0)
    wi = n * math.pi / 30.0
    couple = 0.1 * mb * 0.022 ** 2 * (spin * wi) * (ratio * wi) * 0.5
    assert g.pitch_deg == pytest.approx(30.0, abs=1e-9)
    assert g.gyroscopic_couple == pytest.approx(couple, rel=1e-9)
    assert g.friction_needed == pytest.approx(couple / (0.011 * 317.0), rel=1e-9)
