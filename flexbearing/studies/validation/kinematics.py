"""Race-control kinematics: the cage speed of a ball rolling without slip at both raceways, and
its two brackets, pure inner- and pure outer-race control (issue 35, "Kinematics you can trust").

The one place of these relations: the series' brackets (flexbearing.studies.validation.brackets),
the series driver (flexbearing.studies.validation.series), the slip-rate validation's diagnostic
slips (flexbearing.studies.validation.slip_rate) and the gyroscopic demand
(flexbearing.studies.gyroscopic_demand) all call them. Pure Python; angles in degrees where the
name says ``_deg``, else radians.

Kinematics
==========
Outer ring stationary, inner ring rotating at n_i; a ball of diameter D on the pitch diameter d_m
touches the inner raceway at the contact angle alpha_i and the outer raceway at alpha_o. The ball
spins about an axis in the plane through the bearing axis and the ball centre, at the pitch angle
beta to the bearing axis (no gyroscopic yaw component). Rolling without slip at both contact
centres gives (Jones 1960; Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., Vol. 2,
ch. 'Ball and roller bearing kinematics' / 'High speed operation: ball speeds and cage speed')::

    n_c / n_i = 1 / (1 + (1 + gamma cos alpha_o) cos(alpha_i - beta)
                       / ((1 - gamma cos alpha_i) cos(alpha_o - beta)))          gamma = D / d_m

    omega_R / omega_i = (1 - n_c/n_i) (1 - gamma cos alpha_i) / (gamma cos(alpha_i - beta))

(omega_R: ball rotation relative to the cage). The pitch angle is fixed by the race-control
hypothesis (Jones 1960), i.e. the contact at which the ball does not spin:

* outer-race control (no spin at the outer contact)::

      tan beta = sin alpha_o / (cos alpha_o + gamma)

* inner-race control (no spin at the inner contact)::

      tan beta = sin alpha_i / (cos alpha_i - gamma)

With alpha_i = alpha_o = alpha both brackets reduce to the classical epicyclic cage speed
n_c = n_i/2 (1 - D cos alpha / d_m), whatever beta (proved in tests/test_race_control.py). The
brackets only separate when the two contact angles differ (at speed, the centrifugal force makes
alpha_o < alpha_i). Note on the sign of the split: with alpha_i > alpha_o, inner-race control gives
a cage slower than the epicyclic speed at the mean angle and outer-race control a faster one
(tests/test_race_control.py::test_bracket_signs_with_the_centrifugal_split).

The pitch angle in code: `race_control_pitch` (radians), the cage speed ratio at any pitch angle:
`cage_speed_ratio` (gamma form) and `pure_rolling_cage_speed_ratio` (the same rolling conditions
written with the contact radii, as the slip diagnosis of the dynamics uses them; the two agree to
rounding, tests/test_race_control.py). The race-control brackets reproduce Jones's vector
conditions (rolling at both contacts, no spin relative to the controlling race) to 1e-12
(tests/test_race_control.py::test_closed_form_matches_the_vector_contact_conditions).

References
----------
* A. B. Jones, "A General Theory for Elastically Constrained Ball and Radial Roller Bearings under
  Arbitrary Load and Speed Conditions", ASME J. Basic Eng. 82 (1960) 309-320.
* T. A. Harris, M. N. Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 2 (Advanced Concepts of
  Bearing Technology), CRC Press 2007: ball and cage speeds under outer-/inner-raceway control.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from flexbearing.common.validation import InputError

CONTROLS = ("inner", "outer")


@dataclass(frozen=True)
class RaceControlKinematics:
    """Ball and cage motion under one race-control hypothesis (outer ring stationary)."""
    control: str                 # "inner" or "outer"
    cage_speed_rpm: float        # n_c
    pitch_angle_deg: float       # beta: ball spin axis to bearing axis
    ball_spin_ratio: float       # omega_R / omega_i, ball rotation relative to the cage


@dataclass(frozen=True)
class Brackets:
    """The two race-control brackets and the epicyclic cage speed at a reference angle."""
    speed_rpm: float
    inner: RaceControlKinematics
    outer: RaceControlKinematics
    reference_angle_deg: float
    epicyclic_rpm: float         # n_m = n_i/2 (1 - D cos(reference angle)/d_m)

    @property
    def inner_slip_percent(self) -> float:
        return slip_percent(self.epicyclic_rpm, self.inner.cage_speed_rpm)

    @property
    def outer_slip_percent(self) -> float:
        return slip_percent(self.epicyclic_rpm, self.outer.cage_speed_rpm)


def _check_geometry(ball_diameter: float, pitch_diameter: float) -> float:
    if not (ball_diameter > 0 and pitch_diameter > ball_diameter):
        raise InputError(f"ball_diameter = {ball_diameter!r}, pitch_diameter = {pitch_diameter!r}: "
                         "need 0 < ball_diameter < pitch_diameter")
    return ball_diameter / pitch_diameter


def _check_angle(name: str, value_deg: float) -> float:
    if not (0.0 <= value_deg < 90.0):
        raise InputError(f"{name} = {value_deg!r}: allowed range [0, 90) deg")
    return math.radians(value_deg)


def _check_control(control: str) -> str:
    if control not in CONTROLS:
        raise InputError(f"control = {control!r}: allowed values {CONTROLS}")
    return control

def epicyclic_cage_speed(speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                         contact_angle_deg: float) -> float:
    """Classical epicyclic cage speed n_i/2 (1 - D cos alpha / d_m), outer ring stationary [rpm]."""
    gamma = _check_geometry(ball_diameter, pitch_diameter)
    alpha = _check_angle("contact_angle_deg", contact_angle_deg)
    return 0.5 * speed_rpm * (1.0 - gamma * math.cos(alpha))



def race_control_pitch(gamma: float, alpha_i: float, alpha_o: float, control: str) -> float:
    """Pitch angle beta (radians) of the ball's spin axis under pure ``control`` ("inner" or
    "outer"; Jones 1960, Harris & Kotzalas 5th ed. Vol. 2; module docstring)::

        outer:  tan beta = sin alpha_o / (cos alpha_o + gamma)
        inner:  tan beta = sin alpha_i / (cos alpha_i - gamma)          gamma = D / d_m
    """
    if _check_control(control) == "outer":
        return math.atan2(math.sin(alpha_o), math.cos(alpha_o) + gamma)
    return math.atan2(math.sin(alpha_i), math.cos(alpha_i) - gamma)


def race_control_kinematics(speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                            inner_contact_angle_deg: float, outer_contact_angle_deg: float,
                            control: str) -> RaceControlKinematics:
    """Cage speed, pitch angle and ball spin under pure inner- or outer-race control.

    Harris & Kotzalas (5th ed., Vol. 2) / Jones (1960), outer ring stationary, inner ring at
    ``speed_rpm``; rolling without slip at both contact centres; no spin at the controlling
    contact (`race_control_pitch`, `cage_speed_ratio`; formulas in the module docstring)."""
    _check_control(control)
    gamma = _check_geometry(ball_diameter, pitch_diameter)
    ai = _check_angle("inner_contact_angle_deg", inner_contact_angle_deg)
    ao = _check_angle("outer_contact_angle_deg", outer_contact_angle_deg)
    beta = race_control_pitch(gamma, ai, ao, control)
    ratio, spin = cage_speed_ratio(gamma, ai, ao, beta)
    return RaceControlKinematics(control, speed_rpm * ratio, math.degrees(beta), spin)

def cage_speed_ratio(gamma: float, alpha_i: float, alpha_o: float, beta: float) -> tuple[float, float]:
    """(n_c/n_i, omega_R/omega_i) for any ball pitch angle ``beta`` (radians throughout): rolling
    without slip at both contact centres, outer ring stationary (Harris & Kotzalas, 5th ed.,
    Vol. 2; the module docstring)."""
    ci, co = math.cos(alpha_i - beta), math.cos(alpha_o - beta)
    if ci <= 0 or co <= 0 or gamma * math.cos(alpha_i) >= 1:
        raise InputError(f"pitch angle {math.degrees(beta):.3f} deg leaves no rolling at a contact "
                         f"(alpha_i = {math.degrees(alpha_i)}, alpha_o = {math.degrees(alpha_o)} deg)")
    ratio = 1.0 / (1.0 + (1.0 + gamma * math.cos(alpha_o)) * ci / ((1.0 - gamma * math.cos(alpha_i)) * co))
    spin = (1.0 - ratio) * (1.0 - gamma * math.cos(alpha_i)) / (gamma * ci)
    return ratio, spin


def brackets(speed_rpm: float, ball_diameter: float, pitch_diameter: float,
             inner_contact_angle_deg: float, outer_contact_angle_deg: float,
             reference_angle_deg: float | None = None) -> Brackets:
    """Both race-control brackets; the epicyclic reference speed uses ``reference_angle_deg``
    (default: the mean of the two contact angles; pass the free contact angle to get the slip
    the way the test series define it)."""
    if reference_angle_deg is None:
        reference_angle_deg = 0.5 * (inner_contact_angle_deg + outer_contact_angle_deg)
    args = (speed_rpm, ball_diameter, pitch_diameter, inner_contact_angle_deg, outer_contact_angle_deg)
    return Brackets(speed_rpm, race_control_kinematics(*args, "inner"),
                    race_control_kinematics(*args, "outer"), reference_angle_deg,
                    epicyclic_cage_speed(speed_rpm, ball_diameter, pitch_diameter, reference_angle_deg))


def slip_percent(nominal_cage_rpm: float, cage_rpm: float) -> float:
    """Cage slip S = (n_m - n_c)/n_m x 100 (positive: the cage lags the nominal speed)."""
    if nominal_cage_rpm == 0:
        raise InputError("nominal_cage_rpm = 0: slip undefined")
    return 100.0 * (nominal_cage_rpm - cage_rpm) / nominal_cage_rpm


def pure_rolling_cage_speed_ratio(alpha_outer: float, alpha_inner: float, beta: float, ball_diameter: float,
                                  pitch_diameter: float) -> float:
    """omega_c/omega_i of a ball rolling without slip (rolling direction) on the fixed outer race and
    the inner race, its spin axis in the axial plane at the pitch angle beta from the bearing axis
    (beta > 0 turns the axis towards the normal of the contact line: beta = alpha_o makes it
    perpendicular to the outer contact normal, beta = alpha_i to the inner one).

    Rolling at the contact of angle alpha (contact point at Dw/2 from the ball centre along the
    contact normal), in the frame orbiting with the cage (ball spin omega_R about its axis):
        outer:  omega_c·r_o           = omega_R·(Dw/2)·cos(alpha_o − beta),  r_o = dm/2 + (Dw/2)·cos alpha_o
        inner:  (omega_i − omega_c)·r_i = omega_R·(Dw/2)·cos(alpha_i − beta),  r_i = dm/2 − (Dw/2)·cos alpha_i
    hence omega_c/omega_i = q/(1 + q), q = r_i·cos(alpha_o − beta)/(r_o·cos(alpha_i − beta))
    (Harris & Kotzalas, Rolling Bearing Analysis Vol. 1, ch. "Ball and roller kinematics": the
    race-control cases are beta from the gyroscopic balance; beta = 0 is the torque-free ball whose
    angular velocity stays parallel to the bearing axis; beta = alpha_i means no spin at the inner
    contact). For alpha_o = alpha_i = alpha it is nm/ni = (1 − Dw·cos alpha/dm)/2 for every beta."""
    r = 0.5 * ball_diameter
    ri = 0.5 * pitch_diameter - r * math.cos(alpha_inner)
    ro = 0.5 * pitch_diameter + r * math.cos(alpha_outer)
    q = ri * math.cos(alpha_outer - beta) / (ro * math.cos(alpha_inner - beta))
    return q / (1.0 + q)


def race_control_cage_speed_ratio(alpha_outer: float, alpha_inner: float, control: str, ball_diameter: float,
                                  pitch_diameter: float) -> tuple[float, float]:
    """(n_c/n_i, beta) under pure ``control``, angles in radians: the pitch of `race_control_pitch`
    and the pure-rolling cage speed at it (`pure_rolling_cage_speed_ratio`); the radian form of
    `race_control_kinematics` that the dynamics' diagnostics use (their angles are radians)."""
    beta = race_control_pitch(ball_diameter / pitch_diameter, alpha_inner, alpha_outer, control)
    return pure_rolling_cage_speed_ratio(alpha_outer, alpha_inner, beta, ball_diameter, pitch_diameter), beta


def split_for_slip(speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                   free_contact_angle_deg: float, slip: float, control: str) -> float | None:
    """Symmetric contact-angle split Delta (alpha_i = alpha_0 + Delta, alpha_o = alpha_0 - Delta)
    at which the pure ``control`` bracket gives the cage slip ``slip`` [%] against the epicyclic
    speed at the free angle alpha_0. None when no split in [0, alpha_0) reaches it (e.g. a
    positive slip under outer-race control, whose slip is <= 0 for alpha_i >= alpha_o)."""
    hi = min(free_contact_angle_deg, 89.0 - free_contact_angle_deg) - 1e-6

    def f(delta):
        b = brackets(speed_rpm, ball_diameter, pitch_diameter, free_contact_angle_deg + delta,
                     free_contact_angle_deg - delta, reference_angle_deg=free_contact_angle_deg)
        return (b.inner_slip_percent if control == "inner" else b.outer_slip_percent) - slip

    lo, flo, fhi = 0.0, f(0.0), f(hi)
    if flo == 0.0:
        return 0.0
    if flo * fhi > 0:
        return None
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if flo * fm <= 0:
            hi = mid
        else:
            lo, flo = mid, fm
    return 0.5 * (lo + hi)
