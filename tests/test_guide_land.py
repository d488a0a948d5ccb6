"""Cage–guide land: short journal bearing (Ocvirk) film, Petroff torque, rim contact."""
import math

import pytest
from scipy.integrate import quad

from flexbearing.multibody.guide_land import guide_land_force, ocvirk_forces, rim_stiffness

ETA, R1, L, CG = 0.055, 0.089, 0.0283, 0.375e-3
K_RIM = rim_stiffness(230.8e9, L)


def half_sommerfeld_forces(eps, ws, epsdot=0.0, phidot=0.0, fixed_limits=True):
    """Forces on the journal by integrating the short-bearing pressure (reference).

    Reynolds, short-bearing limit: d/dz(h³ dp/dz) = 6·eta·w·dh/dtheta + 12·eta·dh/dt, with
    h = Cg·(1 + eps·cos(theta)) (theta from the thickest film, thinnest at theta = pi),
    w = ws − 2·phidot and dh/dt = Cg·epsdot·cos(theta) in the frame of the line of centres.
    p = S(theta)·(z² − L²/4)/(2h³); integrated over z: ∫(L²/4 − z²)dz = L³/6. The pi-film keeps
    p over theta in (0, pi), the half where the pressure is positive for pure rotation with
    w > 0, and over (pi, 2pi) for w < 0.
    """
    def pbar(t):          # pressure integrated over the width, per unit R·dtheta
        h = CG * (1 + eps * math.cos(t))
        S = 6 * ETA * w * (-CG * eps * math.sin(t)) + 12 * ETA * CG * epsdot * math.cos(t)
        p = -S / (2 * h ** 3) * L ** 3 / 6
        return p if fixed_limits else max(p, 0.0)
    w = ws - 2 * phidot
    if not fixed_limits:
        lo, hi = 0.0, 2 * math.pi
    else:
        lo, hi = (0.0, math.pi) if w > 0 else (math.pi, 2 * math.pi)
    # force on the journal = −∫ p n dA, n = outward journal normal at theta; e_hat points to the
    # thinnest film (theta = pi), the tangential axis x_hat × e_hat is at theta = 3pi/2 here
    # because theta runs with the surface motion (w > 0).
    f_along_e = -quad(lambda t: pbar(t) * -math.cos(t) * R1, lo, hi, limit=200, epsabs=0)[0]
    f_perp = -quad(lambda t: pbar(t) * -math.sin(t) * R1, lo, hi, limit=200, epsabs=0)[0]
    return f_along_e, f_perp


def test_petroff_limit_at_zero_eccentricity():
    # Petroff: M = 2·pi·eta·omega·R³·L/C on the cage, opposing its spin; no film force.
    fy, fz, mx = guide_land_force(0.0, 0.0, 0.0, 0.0, 700.0, 0.0, R1, L, CG, ETA, 0.95, False, K_RIM, 0.1)
    assert (fy, fz) == (0.0, 0.0)
    assert mx == pytest.approx(-2 * math.pi * ETA * 700.0 * R1 ** 3 * L / CG, rel=1e-14)


@pytest.mark.parametrize("eps", [0.1, 0.4, 0.7, 0.9])
def test_ocvirk_closed_forms_against_integrated_pressure(eps):
    # The closed forms are the integrals of the half-Sommerfeld short-bearing pressure; the
    # quadrature reference agrees to 1e-8.
    ws = 700.0
    wr, wt = ocvirk_forces(eps, R1 * ws, ETA, L, CG)
    f_e, f_perp = half_sommerfeld_forces(eps, ws)
    assert f_e == pytest.approx(-wr, rel=1e-8)      # restoring, along −e_hat
    assert abs(f_perp) == pytest.approx(wt, rel=1e-8)


def test_short_bearing_sommerfeld_number_textbook():
    # Textbook short-bearing relation (Ocvirk; Hamrock 1994 ch. 13; Shigley): with
    # S = (eta·N/P)·(R/C)², N in rev/s, P = W/(L·D):
    #   S·(L/D)² = (1 − eps²)² / (pi·eps·sqrt(pi²·(1 − eps²) + 16·eps²)),
    # attitude angle tan(phi) = pi·sqrt(1 − eps²)/(4·eps).
    omega = 700.0
    n = omega / (2 * math.pi)
    for eps in (0.2, 0.5, 0.8):
        fy, fz, _ = guide_land_force(eps * CG, 0.0, 0.0, 0.0, omega, 0.0, R1, L, CG, ETA, 0.99, False, K_RIM, 0.1)
        w = math.hypot(fy, fz)
        s = ETA * n / (w / (L * 2 * R1)) * (R1 / CG) ** 2
        expected = (1 - eps ** 2) ** 2 / (math.pi * eps * math.sqrt(math.pi ** 2 * (1 - eps ** 2) + 16 * eps ** 2))
        assert s * (L / (2 * R1)) ** 2 == pytest.approx(expected, rel=1e-12)
        phi = math.atan2(abs(fz), abs(fy))
        assert math.tan(phi) == pytest.approx(math.pi * math.sqrt(1 - eps ** 2) / (4 * eps), rel=1e-12)
        # direction: radial force restoring (−y), tangential along x_hat × y_hat = +z for omega > 0
        assert fy < 0 and fz > 0


def test_dynamic_terms_against_integrated_pressure():
    # Childs' pi-film forces with whirl and squeeze equal the integrals of the short-bearing
    # pressure over the fixed half (theta in (0, pi)); with zero centre velocity = static forces.
    eps, ws = 0.5, 700.0
    static = guide_land_force(eps * CG, 0.0, 0.0, 0.0, ws, 0.0, R1, L, CG, ETA, 0.95, False, K_RIM, 0.1)
    dyn0 = guide_land_force(eps * CG, 0.0, 0.0, 0.0, ws, 0.0, R1, L, CG, ETA, 0.95, True, K_RIM, 0.1)
    assert dyn0 == pytest.approx(static, rel=1e-12)
    vy, vz = 0.02, 0.01            # m/s: epsdot = vy/CG, phidot = vz/e (centre on +y)
    e = eps * CG
    epsdot, phidot = vy / CG, vz / e
    fy, fz, _ = guide_land_force(e, 0.0, vy, vz, ws, 0.0, R1, L, CG, ETA, 0.95, True, K_RIM, 0.1)
    f_e, f_perp = half_sommerfeld_forces(eps, ws, epsdot=epsdot, phidot=phidot)
    assert fy == pytest.approx(f_e, rel=1e-8)
    # tangential: compare magnitudes including the squeeze part computed separately
    c = ETA * R1 * L ** 3 / (2 * CG ** 2)
    ft = c * (math.pi * eps * (ws - 2 * phidot) / (2 * (1 - eps ** 2) ** 1.5) + 4 * eps * epsdot / (1 - eps ** 2) ** 2)
    assert fz == pytest.approx(ft, rel=1e-12)
    assert abs(f_perp) == pytest.approx(ft, rel=1e-8)
    # squeeze resists approach: moving outward (vy > 0) increases the restoring force
    assert fy < static[0]


@pytest.mark.parametrize("whirl_ratio", [0.9, 1.0, 1.5])
def test_dynamic_terms_when_the_whirl_outruns_half_the_spin(whirl_ratio):
    """w = ws − 2·phidot < 0 (a cage whirling at more than half its spin, e.g. synchronously on
    its land): the pi-film lies on (pi, 2pi) and both dynamic forces equal the integral of the
    short-bearing pressure over that half, the squeeze's tangential part with the opposite sign
    to Childs' w > 0 form (relative 1e-8: the quadrature). Found by tests/test_symmetry.py: the
    mirror that reverses the rotation broke the cage's equations by 1.5e-5 of their scale."""
    eps, ws = 0.6, 700.0
    e = eps * CG
    vy = 0.03                                   # outward: epsdot > 0
    phidot = whirl_ratio * ws
    vz = phidot * e
    fy, fz, _ = guide_land_force(e, 0.0, vy, vz, ws, 0.0, R1, L, CG, ETA, 0.95, True, K_RIM, 0.1)
    f_e, f_perp = half_sommerfeld_forces(eps, ws, epsdot=vy / CG, phidot=phidot)
    assert fy == pytest.approx(f_e, rel=1e-8)
    # the sign between the reference's perpendicular component and F_z, from the w > 0 case
    fz_pos = guide_land_force(e, 0.0, vy, 0.0, ws, 0.0, R1, L, CG, ETA, 0.95, True, K_RIM, 0.1)[1]
    sign = math.copysign(1.0, fz_pos * half_sommerfeld_forces(eps, ws, epsdot=vy / CG)[1])
    assert fz == pytest.approx(sign * f_perp, rel=1e-8)
    squeeze = 4 * eps * (vy / CG) / (1 - eps ** 2) ** 2 * ETA * R1 * L ** 3 / (2 * CG ** 2)
    rotation = ETA * R1 * L ** 3 / (2 * CG ** 2) * math.pi * eps * (ws - 2 * phidot) / (2 * (1 - eps ** 2) ** 1.5)
    assert fz == pytest.approx(rotation - squeeze, rel=1e-12)


def test_rim_contact_takes_over_continuously():
    # The film is capped at eps_max; the rim penalty starts at |e| = Cg with zero force, so the
    # total force is continuous; beyond it grows with k_rim.
    args = (0.0, 0.0, 700.0, 0.0, R1, L, CG, ETA, 0.95, False, K_RIM, 0.1)
    below = guide_land_force(CG * (1 - 1e-12), 0.0, *args)
    above = guide_land_force(CG * (1 + 1e-12), 0.0, *args)
    assert below == pytest.approx(above, rel=1e-6, abs=1e-6)
    at_cap = guide_land_force(0.95 * CG, 0.0, *args)
    just_over = guide_land_force(0.9500001 * CG, 0.0, *args)
    assert at_cap[:2] == pytest.approx(just_over[:2], rel=1e-5)
    deep = guide_land_force(CG + 1e-6, 0.0, *args)
    assert deep[0] - above[0] == pytest.approx(-K_RIM * 1e-6, rel=1e-6)
    # rim friction opposes the cage's spin relative to the land
    assert deep[2] < below[2]
