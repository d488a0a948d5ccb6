"""What a measured cage slip asks of the balls: the pitch, the gyroscopic couple, the friction.

Issue 35, item 4 (docs/race_control.md). A cage slip that lies between the two race-control
brackets can be read kinematically: rolling without slip at both contact centres with the ball's
spin axis pitched by beta from the bearing axis gives the cage speed (Jones 1960; Harris &
Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 2; `flexbearing.studies.validation.kinematics.cage_speed_ratio`)

    n_c/n_i = 1 / (1 + (1 + gamma·cos a_o)·cos(a_i − beta) / ((1 − gamma·cos a_i)·cos(a_o − beta))),

so the measured slip fixes beta (`pitch_for_slip`). A ball pitched by beta and orbiting at
omega_c needs the gyroscopic couple (Jones 1960; Harris & Kotzalas Vol. 2, "gyroscopic moment")

    M_g = J·omega_R·omega_c·sin(beta),   J = m_b·Dw²/10,

omega_R the ball's spin relative to the cage, about the bearing's tangential axis e_t. Only
friction across the rolling direction at the race contacts can supply it, with a lever of at most
Dw/2 at each contact, so it needs at least the friction coefficient

    mu_needed = M_g / ((Dw/2)·(Q_o + Q_i))

(both contacts sliding sideways at the same coefficient, each force at the full lever). If that
exceeds what the oil film can carry (the limiting-shear coefficient tau_L/p of an EHL contact,
flexbearing.multibody.traction.EHL_RANGES), the balls cannot hold the pitch the measurement
implies, and pure rolling at that pitch is not what the test bearing did.

Units: SI, angles in radians unless the name says _deg; speeds in rpm where named.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from flexbearing.studies.validation.kinematics import cage_speed_ratio, epicyclic_cage_speed


@dataclass(frozen=True)
class GyroscopicDemand:
    """The pitch a cage slip implies under pure rolling, and what holding it takes."""
    pitch_deg: float               # beta: spin axis to bearing axis, in the cage frame
    ball_spin_rad_s: float         # omega_R, relative to the cage
    cage_speed_rad_s: float        # omega_c
    gyroscopic_couple: float       # M_g, N·m
    friction_needed: float         # mu_needed (with both contacts at the full lever)


def pitch_for_slip(slip_percent: float, speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                   inner_angle: float, outer_angle: float, reference_angle: float | None = None) -> float:
    """Pitch beta (rad) at which pure rolling at both contacts gives the cage slip
    S = (n_m − n_c)/n_m·100, n_m the epicyclic speed at `reference_angle` (default the mean of the
    two contact angles, the validation's definition). With a_i > a_o the ratio
    cos(a_i − beta)/cos(a_o − beta) grows monotonically with beta (its derivative is
    sin(a_i − a_o)/cos²(a_o − beta) > 0), so the cage speed falls monotonically from beta = 0 to
    beta → a_o + 90° (where it vanishes); beta is found by bisection there (Jones's inner-race
    control lies inside, at tan beta = sin a_i/(cos a_i − gamma), beta > a_i). ValueError if the
    slip is below that of beta = 0."""
    gamma = ball_diameter / pitch_diameter
    ref = 0.5 * (inner_angle + outer_angle) if reference_angle is None else reference_angle
    nm = epicyclic_cage_speed(speed_rpm, ball_diameter, pitch_diameter, math.degrees(ref)) / speed_rpm
    target = nm * (1.0 - slip_percent / 100.0)

    def excess(beta):
        return cage_speed_ratio(gamma, inner_angle, outer_angle, beta)[0] - target

    lo, hi = 0.0, outer_angle + 0.5 * math.pi - 1e-9
    f_lo, f_hi = excess(lo), excess(hi)
    if f_lo == 0.0:
        return 0.0
    if f_lo * f_hi > 0.0:
        raise ValueError(f"slip_percent = {slip_percent!r}: outside the pure-rolling range "
                         f"{100 * (1 - (f_lo + target) / nm):.2f} … {100 * (1 - (f_hi + target) / nm):.2f} % "
                         "for pitches between 0 and the outer contact angle + 90°")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        f_mid = excess(mid)
        if f_mid == 0.0 or hi - lo < 1e-14:
            break
        if f_lo * f_mid < 0.0:
            hi = mid
        else:
            lo, f_lo = mid, f_mid
    return 0.5 * (lo + hi)


def gyroscopic_demand(slip_percent: float, speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                      ball_mass: float, inner_angle: float, outer_angle: float, outer_load: float,
                      inner_load: float, reference_angle: float | None = None) -> GyroscopicDemand:
    """The pitch of `pitch_for_slip`, the gyroscopic couple M_g = J·omega_R·omega_c·sin(beta) and
    the least friction coefficient that carries it (module docstring). Loads in N, mass in kg."""
    if not (outer_load > 0.0 and inner_load >= 0.0):
        raise ValueError(f"outer_load = {outer_load!r}, inner_load = {inner_load!r}: need outer_load > 0, inner_load >= 0")
    beta = pitch_for_slip(slip_percent, speed_rpm, ball_diameter, pitch_diameter, inner_angle, outer_angle,
                          reference_angle)
    ratio, spin = cage_speed_ratio(ball_diameter / pitch_diameter, inner_angle, outer_angle, beta)
    omega_i = speed_rpm * 2.0 * math.pi / 60.0
    omega_c, omega_r = ratio * omega_i, spin * omega_i
    couple = 0.1 * ball_mass * ball_diameter ** 2 * omega_r * omega_c * math.sin(beta)
    mu = couple / (0.5 * ball_diameter * (outer_load + inner_load))
    return GyroscopicDemand(math.degrees(beta), omega_r, omega_c, couple, mu)
