"""The bearing description of issue 35: free contact angle, clearance and shim angle (closed forms of
Harris & Kotzalas and of the split ring), the one-piece inner ring, ball materials, one ball diameter."""
import math

import numpy as np
import pytest

from flexbearing.common.validation import InputError
from flexbearing.multibody import clearance as CL
from flexbearing.multibody import geometry as geo
from flexbearing.multibody import quasi_static as qs
from flexbearing.multibody.bearing import PAPER_BEARING

FE, FI, DW = 0.515, 0.52, 22e-3
B = FE + FI - 1.0


def test_paper_design_clearance_is_the_hand_value():
    # 2·(fe − 0.5)·Dw·(1 − cos 30°) = 2·0.015·0.022·0.1339746 = 88.4232 um (flexbearing.studies.validation.slip_rate's value)
    assert CL.design_clearance(FE, DW, math.radians(30.0)) == pytest.approx(88.4232e-6, rel=1e-5)
    assert PAPER_BEARING.radial_clearance == pytest.approx(88.4232e-6, rel=1e-5)
    assert math.degrees(PAPER_BEARING.free_contact_angle) == pytest.approx(30.0, abs=1e-9)


@pytest.mark.parametrize("a0_deg", [10.0, 25.0, 40.0])
def test_one_piece_closed_form_and_its_inverse(a0_deg):
    # Harris & Kotzalas: Pd = 2·B·Dw·(1 − cos alpha0); e.g. 25°: 2·0.035·0.022·(1 − 0.906308) = 144.28 um
    a0 = math.radians(a0_deg)
    pd = CL.one_piece_clearance(FE, FI, DW, a0)
    assert pd == pytest.approx(2 * B * DW * (1 - math.cos(a0)), rel=1e-15)
    assert CL.one_piece_free_contact_angle(FE, FI, DW, pd) == pytest.approx(a0, rel=1e-12)
    if a0_deg == 25.0:
        assert pd == pytest.approx(144.28e-6, rel=1e-4)


@pytest.mark.parametrize("shim_deg,a0_deg", [(30.0, 30.0), (30.0, 35.0), (20.0, 26.0), (15.0, 40.0)])
def test_split_ring_closed_forms_are_mutual_inverses(shim_deg, a0_deg):
    sh, a0 = math.radians(shim_deg), math.radians(a0_deg)
    pd = CL.split_clearance(FE, FI, DW, sh, a0)
    assert pd >= 0.0
    assert CL.split_free_contact_angle(FE, FI, DW, sh, pd) == pytest.approx(a0, rel=1e-12)
    assert CL.split_shim_angle(FE, FI, DW, pd, a0) == pytest.approx(sh, rel=1e-10)
    if shim_deg == a0_deg:
        assert pd == pytest.approx(CL.design_clearance(FE, DW, sh), rel=1e-12)


def test_split_ring_with_zero_shim_is_the_one_piece_ring():
    for a0 in np.radians([5.0, 20.0, 38.0]):
        assert CL.split_clearance(FE, FI, DW, 0.0, a0) == pytest.approx(CL.one_piece_clearance(FE, FI, DW, a0),
                                                                        rel=1e-12)


@pytest.mark.parametrize("ring,shim_deg,pd", [("split", 30.0, None), ("split", 25.0, 150e-6),
                                              ("one_piece", None, 144.28e-6)])
def test_free_angle_is_where_the_ball_touches_both_grooves(ring, shim_deg, pd):
    # Independent of the closed forms: the geometry's groove centres (flexbearing.multibody.geometry) with
    # the ring shifted axially until the loaded pair of centres is B·Dw apart; the line through them
    # then makes the free contact angle with the radial direction (Harris & Kotzalas Vol. 1 ch. 2).
    kw = {"inner_ring": ring}
    if shim_deg is not None:
        kw["shim_angle"] = math.radians(shim_deg)
    if pd is not None:
        kw["radial_clearance"] = pd
    else:
        kw["radial_clearance"] = CL.design_clearance(FE, DW, kw["shim_angle"])
    b = PAPER_BEARING.with_(**kw).validate()
    xo, ro = geo.outer_groove_centre(b.pitch_diameter, DW, FE)
    xl, rl, _, _ = geo.inner_groove_centres(b.pitch_diameter, DW, FI, *b.groove_layout)
    dr = rl - ro
    assert dr < B * DW
    alpha = math.acos(dr / (B * DW))
    assert b.free_contact_angle == pytest.approx(alpha, rel=1e-10)


def test_resolve_inner_ring_rules_and_one_line_refusals():
    r = CL.resolve_inner_ring("split", FE, FI, DW, free_contact_angle=math.radians(28.0))
    assert r.shim_angle == pytest.approx(math.radians(28.0)) and r.diametral_clearance == pytest.approx(
        CL.design_clearance(FE, DW, math.radians(28.0)))
    r = CL.resolve_inner_ring("one_piece", FE, FI, DW, diametral_clearance=144.28e-6)
    assert math.degrees(r.free_contact_angle) == pytest.approx(25.0, abs=0.01)
    bad = [dict(inner_ring="split", free_contact_angle=0.5, shim_angle=0.5, diametral_clearance=1e-4),
           dict(inner_ring="one_piece", shim_angle=0.5, free_contact_angle=0.4),
           dict(inner_ring="one_piece", free_contact_angle=0.4, diametral_clearance=1e-4),
           dict(inner_ring="split", free_contact_angle=math.radians(10.0), shim_angle=math.radians(30.0)),
           dict(inner_ring="conical", free_contact_angle=0.4),
           dict(inner_ring="split", free_contact_angle=math.radians(95.0))]
    for kw in bad:
        ring = kw.pop("inner_ring")
        with pytest.raises(InputError) as e:
            CL.resolve_inner_ring(ring, FE, FI, DW, **kw)
        assert "\n" not in str(e.value) and "bearing" in str(e.value)


def _harris_thrust_angle(fa, z, k_n, a0):
    """Harris & Kotzalas Vol. 1 ch. 7 (pure thrust, no speed): Fa/(Z·K_n·(B·Dw)^1.5) = sin a·(cos a0/cos a − 1)^1.5,
    solved for a by bisection; K_n the combined Hertz constant of the pair."""
    lhs = fa / (z * k_n * (B * DW) ** 1.5)
    lo, hi = a0 + 1e-12, math.radians(89.0)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if math.sin(mid) * (math.cos(a0) / math.cos(mid) - 1.0) ** 1.5 < lhs:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def test_one_piece_ring_in_pure_thrust_follows_harris():
    # One-piece ring, free angle 25°, Fa = 10 kN, no speed: the quasi-static contact angle and ball load
    # against the closed form, with K_n from the loads and approaches the solver returns (Q = K·delta^1.5
    # per contact, combined as (K_i^-2/3 + K_o^-2/3)^-1.5). Also: the second inner half carries nothing.
    b = PAPER_BEARING.with_(inner_ring="one_piece",
                            radial_clearance=CL.one_piece_clearance(FE, FI, DW, math.radians(25.0))).validate()
    r = qs.solve_quasi_static(qs.grooves_from_bearing(b), 0.0, fx=10e3)
    assert r.converged
    assert np.all(r.load[:, 2] == 0.0)
    q_o, q_i = r.load[:, 0], r.load[:, 1]
    assert q_o == pytest.approx(q_i, rel=1e-6)
    k_o = q_o[0] / r.delta[0, 0] ** 1.5
    k_i = q_i[0] / r.delta[0, 1] ** 1.5
    k_n = (k_o ** (-2 / 3) + k_i ** (-2 / 3)) ** -1.5
    a = _harris_thrust_angle(10e3, b.n_balls, k_n, b.free_contact_angle)
    assert abs(r.contact_angle[0, 1]) == pytest.approx(a, abs=1e-6)
    assert q_i[0] == pytest.approx(10e3 / (b.n_balls * math.sin(a)), rel=1e-6)


def test_split_ring_with_thrust_uses_its_second_half_only_when_pushed_back():
    # the split ring at its design clearance runs on one half under thrust (two-point), the one-piece
    # ring has no second half at all: under the reversed thrust the split ring loads the other half
    split = PAPER_BEARING
    r = qs.solve_quasi_static(qs.grooves_from_bearing(split), 0.0, fx=-5e3)
    assert r.converged and r.load[:, 2].min() > 0.0 and r.load[:, 1].max() == 0.0


def test_dynamics_of_a_one_piece_ring_never_loads_the_removed_half():
    from flexbearing.multibody.bearing import PAPER_OIL
    from flexbearing.multibody.model import build_model, F_INNER_HALVES
    from flexbearing.multibody.initial import initial_state
    from flexbearing.multibody.outputs import evaluate_outputs
    one = PAPER_BEARING.with_(inner_ring="one_piece",
                              radial_clearance=CL.one_piece_clearance(FE, FI, DW, math.radians(25.0))).validate()
    omega = 6000 * math.pi / 30
    speed, load = np.array([[0.0, omega]]), np.array([[0.0, 5e3, 0.0, -1e3]])
    for bearing, halves in ((one, 1), (PAPER_BEARING, 2)):
        m = build_model(bearing, PAPER_OIL)
        assert m.flags[F_INNER_HALVES] == halves
        y = initial_state(m, omega, 5e3, 1e3)
        # the ring pushed back 0.3 mm against the thrust: the balls now sit on the second half's side
        y[9 * bearing.n_balls] -= 3e-4
        q = evaluate_outputs(m, 0.0, y, speed, load, np.zeros((0, 6)))["contact_load"]
        if halves == 1:
            assert np.all(q[:, 2] == 0.0)
        else:
            assert q[:, 2].max() > 0.0


# ---------------------------------------------------------------- scene keys
def _scene(bearing: str = "", cage: str = ""):
    from flexbearing.simulation.scene import loads_scene
    text = ('name = "t"\n[operation]\nduration = 0.1\n[operation.speed]\n'
            'phases = [{kind = "uniform", duration = 0.1, rpm = 10000}]\n[operation.load]\naxial_load = 1000.0\n'
            '[output]\nsample_interval = 1e-3\nrecord = ["cage_speed"]\n'
            f'[bearing]\n{bearing}\n[cage]\n{cage}\n')
    return loads_scene(text)


def _refused(fragment: str, **kw):
    with pytest.raises(InputError) as e:
        _scene(**kw)
    assert fragment in str(e.value) and "\n" not in str(e.value), str(e.value)


def test_scene_free_contact_angle_derives_shim_or_clearance():
    a = math.radians(26.0)
    s = _scene(f"free_contact_angle = {a!r}")              # split ring, the angle alone: the design rule
    assert s.bearing.shim_angle == pytest.approx(a) and s.bearing.free_contact_angle == pytest.approx(a)
    assert s.bearing.radial_clearance == pytest.approx(CL.design_clearance(FE, DW, a))
    s = _scene(f"free_contact_angle = {a!r}\nshim_angle = {math.radians(20.0)!r}")
    assert s.bearing.radial_clearance == pytest.approx(CL.split_clearance(FE, FI, DW, math.radians(20.0), a))
    assert s.bearing.free_contact_angle == pytest.approx(a, rel=1e-12)
    s = _scene(f"free_contact_angle = {a!r}\nradial_clearance = 150e-6")
    assert s.bearing.radial_clearance == 150e-6 and s.bearing.free_contact_angle == pytest.approx(a, rel=1e-12)
    s = _scene(f'inner_ring = "one_piece"\nfree_contact_angle = {a!r}')
    assert s.bearing.radial_clearance == pytest.approx(2 * B * DW * (1 - math.cos(a)))
    s = _scene('inner_ring = "one_piece"\nradial_clearance = 144.28e-6')
    assert math.degrees(s.bearing.free_contact_angle) == pytest.approx(25.0, abs=0.01)
    # the design clearance follows the groove radii when only they change (the groove-curvature study)
    s = _scene("fe = 0.525\nfi = 0.53")
    assert math.degrees(s.bearing.free_contact_angle) == pytest.approx(30.0, abs=1e-9)
    assert _scene().bearing == PAPER_BEARING


def test_scene_refusals_are_one_line():
    _refused("give at most two", bearing="free_contact_angle = 0.5\nshim_angle = 0.5\nradial_clearance = 1e-4")
    _refused("shim_angle applies to inner_ring = 'split'", bearing='inner_ring = "one_piece"\nshim_angle = 0.4')
    _refused("bearing.inner_ring", bearing='inner_ring = "three_piece"')
    _refused("bearing.free_contact_angle", bearing="free_contact_angle = 0.1\nshim_angle = 0.6")
    _refused("bearing.ball_material = 'glass'", bearing='ball_material = "glass"')
    _refused("give the ball diameter once, as bearing.ball_diameter", cage="ball_diameter = 20e-3")


def test_scene_ball_diameter_once_and_ball_materials():
    from flexbearing.common.materials import M50, SI3N4, SI3N4_THERMAL, BEARING_STEEL_THERMAL
    s = _scene("ball_diameter = 21e-3", "pocket_diameter = 21.5e-3")
    assert s.bearing.cage.ball_diameter == 21e-3 == s.bearing.ball_diameter
    s = _scene('ball_material = "silicon_nitride"')
    assert s.bearing.ball_material == SI3N4 and s.bearing.ball_thermal == SI3N4_THERMAL
    assert s.bearing.ring_material == M50 and s.bearing.ring_thermal == BEARING_STEEL_THERMAL
    assert s.bearing.ball_mass == pytest.approx(3200.0 * math.pi * DW ** 3 / 6)
    assert _scene('ball_material = "steel"').bearing == PAPER_BEARING


# ---------------------------------------------------------------- ball thermal constants in the traction law
def test_flash_constants_of_a_hybrid_contact():
    from flexbearing.common.materials import BEARING_STEEL_THERMAL as ST, SI3N4_THERMAL as SN
    from flexbearing.multibody import traction as TR
    # steel on steel: the law's own constants, to the bit
    assert TR.flash_constants(None, None) == (TR.EHL_STEEL_CONDUCTIVITY, TR.EHL_STEEL_DIFFUSIVITY)
    assert TR.flash_constants(ST, ST) == (ST.conductivity, ST.diffusivity)
    # Blok's partition, worked by hand: surface temperatures T = C·q_i/e_i equal, q_1 + q_2 = q, so
    # T = C·q/(e_1 + e_2); the law writes T = C·q·sqrt(kappa)/(2·k), hence sqrt(kappa)/k = 2/(e_1 + e_2)
    e_st = 40.0 / math.sqrt(1.1e-5)                      # 12,060 W·s^0.5/(m²·K)
    e_sn = 30.0 / math.sqrt(30.0 / (3200.0 * 700.0))     # sqrt(k·rho·c) = sqrt(30·3200·700) = 8,198
    assert e_sn == pytest.approx(math.sqrt(30.0 * 3200.0 * 700.0), rel=1e-12)
    k, kappa = TR.flash_constants(SN, ST)
    assert math.sqrt(kappa) / k == pytest.approx(2.0 / (e_st + e_sn), rel=1e-12)
    # the hybrid contact's flash temperature is e_st/e_mean = 1.19 times the steel one
    ratio = (math.sqrt(kappa) / k) / (math.sqrt(1.1e-5) / 40.0)
    assert ratio == pytest.approx(2 * e_st / (e_st + e_sn), rel=1e-12) and 1.18 < ratio < 1.20
    tab = TR.ehl_traction_table(0.03, ball_thermal=SN, race_thermal=ST)
    assert tuple(tab[TR.EHL_ROW_THERMAL, [TR.EHL_C_K_SOLID, TR.EHL_C_KAPPA_SOLID]]) == (k, kappa)


# ---------------------------------------------------------------- oil supply
def test_oil_supply_sets_the_cavity_fraction_law():
    from flexbearing.multibody.bearing import PAPER_OIL
    from flexbearing.multibody.oil_supply import cavity_oil_fraction
    from flexbearing.studies.validation.slip_rate import case_oil_air_fraction
    fixed = PAPER_OIL
    assert fixed.cavity_oil_fraction(4000.0) == fixed.cavity_oil_fraction(12000.0) == fixed.oil_air_fraction
    jet = PAPER_OIL.__class__(supply="jet", oil_air_fraction=0.002, oil_air_reference_rpm=4000.0).validate()
    # Parker's 1/n at a constant flow: three times the speed, a third of the oil
    assert jet.cavity_oil_fraction(12000.0) == pytest.approx(0.002 / 3, rel=1e-15)
    assert jet.cavity_oil_fraction(0.0) == 1.0                       # capped at a full cavity
    # the slip-rate validation's law is this one
    assert case_oil_air_fraction(0.002, 10000.0, "inverse_speed") == jet.cavity_oil_fraction(10000.0)
    # the model: fixed fraction has no reference speed; the rhs evaluates X at the ring's speed
    assert cavity_oil_fraction(0.05, 0.0, 1234.0) == 0.05
    from flexbearing.simulation.scene import loads_scene
    base = ('name = "t"\n[operation]\nduration = 0.1\n[operation.speed]\n'
            'phases = [{kind = "uniform", duration = 0.1, rpm = 10000}]\n[operation.load]\naxial_load = 1000.0\n'
            '[output]\nsample_interval = 1e-3\nrecord = ["cage_speed"]\n')
    sc = loads_scene(base + '[oil]\nsupply = "under_race"\noil_air_fraction = 0.004\n')
    assert sc.oil.supply == "under_race" and sc.oil.cavity_oil_fraction(8000.0) == pytest.approx(0.002)
    with pytest.raises(InputError) as e:
        loads_scene(base + '[oil]\nsupply = "splash"\n')
    assert "oil.supply = 'splash'" in str(e.value)


def test_churning_drag_follows_the_supply_law_in_the_dynamics():
    # same state, same speed: a jet supply whose X_ref·n_ref/n equals a fixed fraction gives the same
    # right-hand side to round-off; doubling n_ref doubles the oil and changes the balls' drag
    from flexbearing.multibody.bearing import PAPER_OIL
    from flexbearing.multibody.model import build_model
    from flexbearing.multibody.initial import initial_state
    from flexbearing.multibody.outputs import evaluate_outputs
    omega = 8000 * math.pi / 30
    speed, load = np.array([[0.0, omega]]), np.array([[0.0, 2e3, 0.0, -500.0]])
    fixed = PAPER_OIL.__class__(oil_air_fraction=0.002).validate()
    jet = PAPER_OIL.__class__(supply="jet", oil_air_fraction=0.004, oil_air_reference_rpm=4000.0).validate()
    jet2 = PAPER_OIL.__class__(supply="jet", oil_air_fraction=0.004, oil_air_reference_rpm=8000.0).validate()
    m0 = build_model(PAPER_BEARING, fixed)
    y = initial_state(m0, omega, 2e3, 500.0)
    out = [evaluate_outputs(build_model(PAPER_BEARING, o), 0.0, y, speed, load, np.zeros((0, 6)))["power_loss_churning"]
           for o in (fixed, jet, jet2)]
    assert np.allclose(out[1], out[0], rtol=1e-12, atol=0.0)
    assert np.all(out[2] > 1.5 * out[0])
