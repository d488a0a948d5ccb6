"""Race-control kinematic brackets of the cage speed, and the published test series they are
checked against (issue 35, "Kinematics you can trust").

Pure Python + numpy; no other project import, so the module survives the package move.

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

References
----------
* A. B. Jones, "A General Theory for Elastically Constrained Ball and Radial Roller Bearings under
  Arbitrary Load and Speed Conditions", ASME J. Basic Eng. 82 (1960) 309-320.
* T. A. Harris, M. N. Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 2 (Advanced Concepts of
  Bearing Technology), CRC Press 2007: ball and cage speeds under outer-/inner-raceway control.

Series files
============
``scenes/validation/<series_id>.toml``, one bearing per file. Every number is a *quantity*, an
inline table ``{ value = ..., source = "...", digitised = false, uncertainty = ... }`` (or, for a
number the source only bounds, ``{ low = ..., high = ..., source = "..." }``). Units are SI unless
the key names them (``*_rpm``, ``*_deg``, ``*_C``). Geometry the source leaves open goes to
``[[unknowns]]`` with a range and a reason; ``load_series`` checks all this and raises one
``ValueError`` line naming the file, the field, the value and the allowed range.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "Quantity", "Series", "Cage", "Bearing", "Oil", "Unknown", "Point", "Check", "ValidationSeries",
    "RaceControlKinematics", "Brackets", "BracketRange", "load_series", "load_all",
    "epicyclic_cage_speed", "race_control_kinematics", "cage_speed_ratio", "split_for_slip",
    "bracket_table", "brackets", "slip_percent",
    "point_brackets", "VALIDATION_DIR",
]

VALIDATION_DIR = Path(__file__).resolve().parents[2] / "scenes" / "validation"

# ---------------------------------------------------------------------------------------------
# kinematics
# ---------------------------------------------------------------------------------------------

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
        raise ValueError(f"ball_diameter = {ball_diameter!r}, pitch_diameter = {pitch_diameter!r}: "
                         "need 0 < ball_diameter < pitch_diameter")
    return ball_diameter / pitch_diameter


def _check_angle(name: str, value_deg: float) -> float:
    if not (0.0 <= value_deg < 90.0):
        raise ValueError(f"{name} = {value_deg!r}: allowed range [0, 90) deg")
    return math.radians(value_deg)


def epicyclic_cage_speed(speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                         contact_angle_deg: float) -> float:
    """Classical epicyclic cage speed n_i/2 (1 - D cos alpha / d_m), outer ring stationary [rpm]."""
    gamma = _check_geometry(ball_diameter, pitch_diameter)
    alpha = _check_angle("contact_angle_deg", contact_angle_deg)
    return 0.5 * speed_rpm * (1.0 - gamma * math.cos(alpha))


def race_control_kinematics(speed_rpm: float, ball_diameter: float, pitch_diameter: float,
                            inner_contact_angle_deg: float, outer_contact_angle_deg: float,
                            control: str) -> RaceControlKinematics:
    """Cage speed, pitch angle and ball spin under pure inner- or outer-race control.

    Harris & Kotzalas (5th ed., Vol. 2) / Jones (1960), outer ring stationary, inner ring at
    ``speed_rpm``; rolling without slip at both contact centres; no spin at the controlling
    contact (formulas in the module docstring)."""
    if control not in CONTROLS:
        raise ValueError(f"control = {control!r}: allowed values {CONTROLS}")
    gamma = _check_geometry(ball_diameter, pitch_diameter)
    ai = _check_angle("inner_contact_angle_deg", inner_contact_angle_deg)
    ao = _check_angle("outer_contact_angle_deg", outer_contact_angle_deg)
    if control == "outer":
        beta = math.atan2(math.sin(ao), math.cos(ao) + gamma)
    else:
        beta = math.atan2(math.sin(ai), math.cos(ai) - gamma)
    ratio, spin = cage_speed_ratio(gamma, ai, ao, beta)
    return RaceControlKinematics(control, speed_rpm * ratio, math.degrees(beta), spin)


def cage_speed_ratio(gamma: float, alpha_i: float, alpha_o: float, beta: float) -> tuple[float, float]:
    """(n_c/n_i, omega_R/omega_i) for any ball pitch angle ``beta`` (radians throughout): rolling
    without slip at both contact centres, outer ring stationary (Harris & Kotzalas, 5th ed.,
    Vol. 2; the module docstring)."""
    ci, co = math.cos(alpha_i - beta), math.cos(alpha_o - beta)
    if ci <= 0 or co <= 0 or gamma * math.cos(alpha_i) >= 1:
        raise ValueError(f"pitch angle {math.degrees(beta):.3f} deg leaves no rolling at a contact "
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
        raise ValueError("nominal_cage_rpm = 0: slip undefined")
    return 100.0 * (nominal_cage_rpm - cage_rpm) / nominal_cage_rpm


# ---------------------------------------------------------------------------------------------
# series files
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Quantity:
    """One published number: a value or only bounds (low, high), always with its source."""
    source: str
    value: float | None = None
    low: float | None = None
    high: float | None = None
    digitised: bool = False
    uncertainty: float | None = None     # reading uncertainty (same unit), digitised values
    note: str = ""

    @property
    def is_range(self) -> bool:
        return self.value is None

    def span(self) -> tuple[float, float]:
        return (self.value, self.value) if self.value is not None else (self.low, self.high)


@dataclass(frozen=True)
class Series:
    id: str
    title: str
    source: str
    what_was_measured: str
    full_text_read: bool
    notes: str = ""
    slip_definition: str = ""
    related_sources: tuple[str, ...] = ()


@dataclass(frozen=True)
class Cage:
    guidance: str | None                 # "outer" | "inner" | "balls" | None (not stated)
    guidance_source: str = ""
    material: str | None = None
    material_source: str = ""
    quantities: dict[str, Quantity] = field(default_factory=dict)


@dataclass(frozen=True)
class Bearing:
    quantities: dict[str, Quantity]
    inner_ring: str | None = None        # "split" | "one_piece"
    inner_ring_source: str = ""
    ball_material: str | None = None     # "steel" | "silicon_nitride"
    ball_material_source: str = ""
    ring_material: str | None = None
    ring_material_source: str = ""
    cage: Cage | None = None

    def get(self, key: str) -> Quantity | None:
        return self.quantities.get(key)


@dataclass(frozen=True)
class Oil:
    name: str | None
    supply: str | None                   # "jet" | "under_race" | "mist" | None
    source: str
    quantities: dict[str, Quantity] = field(default_factory=dict)


@dataclass(frozen=True)
class Unknown:
    name: str
    low: float
    high: float
    reason: str
    unit: str = ""


@dataclass(frozen=True)
class Point:
    id: str
    conditions: dict[str, Quantity]      # speed_rpm, axial_load, radial_load, oil_*, ...
    measured: dict[str, Quantity]        # measured_* keys
    reported_model: dict[str, Quantity]  # the source's own model results (not measurements)
    status: str = "measured"             # "measured" | "conditions_only"
    note: str = ""


@dataclass(frozen=True)
class Check:
    """A qualitative statement of the source, usable as a sign or trend check."""
    kind: str                            # "sign" | "trend" | "magnitude" | "agreement"
    statement: str
    source: str


@dataclass(frozen=True)
class ValidationSeries:
    path: Path
    series: Series
    bearing: Bearing
    oil: Oil | None
    unknowns: tuple[Unknown, ...]
    points: tuple[Point, ...]
    checks: tuple[Check, ...]

    def unknown(self, name: str) -> Unknown | None:
        return next((u for u in self.unknowns if u.name == name), None)

    def all_quantities(self):
        """(where, key, Quantity) for every number of the file."""
        for k, q in self.bearing.quantities.items():
            yield "bearing", k, q
        if self.bearing.cage is not None:
            for k, q in self.bearing.cage.quantities.items():
                yield "bearing.cage", k, q
        if self.oil is not None:
            for k, q in self.oil.quantities.items():
                yield "oil", k, q
        for p in self.points:
            for group in (p.conditions, p.measured, p.reported_model):
                for k, q in group.items():
                    yield f"points[{p.id}]", k, q


# allowed ranges, SI unless the key names the unit
BEARING_RANGES = {
    "bore": (1e-3, 2.0), "outside_diameter": (2e-3, 3.0), "width": (1e-3, 0.5),
    "pitch_diameter": (2e-3, 2.5), "ball_diameter": (1e-4, 0.2), "n_balls": (3, 200),
    "inner_groove_curvature": (0.5, 0.6), "outer_groove_curvature": (0.5, 0.6),
    "free_contact_angle_deg": (0.0, 60.0), "diametral_clearance": (0.0, 1e-3),
}
CAGE_RANGES = {
    "outside_diameter": (2e-3, 3.0), "bore": (1e-3, 3.0), "width": (1e-3, 0.5),
    "pocket_clearance": (0.0, 5e-3), "land_clearance": (0.0, 5e-3), "mass": (0.0, 100.0),
    "density": (500.0, 20000.0),
}
OIL_RANGES = {
    "density": (500.0, 2000.0), "dynamic_viscosity": (1e-4, 10.0),
    "viscosity_temperature_coefficient_per_C": (0.0, 0.2), "pressure_viscosity_coefficient": (0.0, 1e-7),
    "thermal_conductivity": (0.0, 1.0), "flow_rate": (0.0, 1e-2), "jet_velocity": (0.0, 200.0),
    "inlet_temperature_C": (-60.0, 400.0),
}
CONDITION_RANGES = {
    "speed_rpm": (0.0, 300000.0), "axial_load": (0.0, 1e6), "radial_load": (0.0, 1e6),
    "oil_inlet_temperature_C": (-60.0, 400.0), "oil_flow_rate": (0.0, 1e-2),
    "duration_s": (0.0, 1e6),
}
MEASURED_RANGES = {
    "measured_cage_speed_rpm": (0.0, 300000.0), "measured_cage_slip_percent": (-100.0, 100.0),
    "measured_contact_angle_deg": (0.0, 90.0), "measured_inner_contact_angle_deg": (0.0, 90.0),
    "measured_outer_contact_angle_deg": (0.0, 90.0), "measured_power_loss_W": (0.0, 1e6),
    "measured_outer_ring_temperature_C": (-60.0, 500.0),
    "measured_inner_ring_temperature_C": (-60.0, 500.0),
    "measured_ball_cage_force_max": (0.0, 1e6), "measured_cage_land_force_max": (0.0, 1e6),
}
MODEL_RANGES = {
    "reported_model_cage_slip_percent": (-100.0, 100.0),
    "reported_model_slip_error_percent": (-1000.0, 1000.0),
}
UNKNOWN_RANGES = {**BEARING_RANGES, **{f"cage_{k}": v for k, v in CAGE_RANGES.items()},
                  **{f"oil_{k}": v for k, v in OIL_RANGES.items()}, **CONDITION_RANGES}
SUPPLY = ("jet", "under_race", "mist")
GUIDANCE = ("outer", "inner", "balls")
INNER_RING = ("split", "one_piece")
BALL_MATERIAL = ("steel", "silicon_nitride")
CHECK_KINDS = ("sign", "trend", "magnitude", "agreement")
STATUS = ("measured", "conditions_only")


class _Ctx:
    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, value, allowed: str):
        raise ValueError(f"{self.path.name}: {where} = {value!r}: {allowed}")


def _string(ctx: _Ctx, table: dict, key: str, where: str, required: bool = True,
            choices: tuple[str, ...] | None = None) -> str | None:
    v = table.get(key)
    if v is None:
        if required:
            ctx.fail(f"{where}.{key}", None, "required (a non-empty string)")
        return None
    if not isinstance(v, str) or not v.strip():
        ctx.fail(f"{where}.{key}", v, "must be a non-empty string")
    if choices is not None and v not in choices:
        ctx.fail(f"{where}.{key}", v, f"allowed values {choices}")
    return v


def _number(ctx: _Ctx, v, where: str, lo_hi: tuple[float, float]) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        ctx.fail(where, v, f"must be a finite number in [{lo_hi[0]:g}, {lo_hi[1]:g}]")
    if not (lo_hi[0] <= v <= lo_hi[1]):
        ctx.fail(where, v, f"allowed range [{lo_hi[0]:g}, {lo_hi[1]:g}]")
    return float(v)


def _quantity(ctx: _Ctx, raw, where: str, lo_hi: tuple[float, float]) -> Quantity:
    if not isinstance(raw, dict):
        ctx.fail(where, raw, "must be an inline table { value = ..., source = \"...\" } "
                             "(or { low = ..., high = ..., source = \"...\" })")
    extra = set(raw) - {"value", "low", "high", "source", "digitised", "uncertainty", "note"}
    if extra:
        ctx.fail(f"{where}", sorted(extra), "unknown keys (allowed: value, low, high, source, "
                                            "digitised, uncertainty, note)")
    source = raw.get("source")
    if not isinstance(source, str) or len(source.strip()) < 8:
        ctx.fail(f"{where}.source", source, "required: the report, table/figure and page of the number")
    digitised = raw.get("digitised", False)
    if not isinstance(digitised, bool):
        ctx.fail(f"{where}.digitised", digitised, "must be true or false")
    unc = raw.get("uncertainty")
    if digitised and unc is None:
        ctx.fail(f"{where}.uncertainty", None, "required when digitised = true (reading uncertainty)")
    if unc is not None:
        unc = _number(ctx, unc, f"{where}.uncertainty", (0.0, abs(lo_hi[1] - lo_hi[0])))
    if "value" in raw:
        if "low" in raw or "high" in raw:
            ctx.fail(where, raw, "give either value or low/high, not both")
        return Quantity(source, _number(ctx, raw["value"], f"{where}.value", lo_hi),
                        digitised=digitised, uncertainty=unc, note=raw.get("note", ""))
    if "low" not in raw or "high" not in raw:
        ctx.fail(where, raw, "needs value, or both low and high")
    lo = _number(ctx, raw["low"], f"{where}.low", lo_hi)
    hi = _number(ctx, raw["high"], f"{where}.high", lo_hi)
    if not lo <= hi:
        ctx.fail(f"{where}.low", lo, f"must not exceed high = {hi!r}")
    return Quantity(source, None, lo, hi, digitised, unc, raw.get("note", ""))


def _quantities(ctx: _Ctx, table: dict, where: str, ranges: dict, skip: set[str]) -> dict[str, Quantity]:
    out = {}
    for key, raw in table.items():
        if key in skip:
            continue
        if key not in ranges:
            ctx.fail(f"{where}.{key}", raw, f"unknown key (allowed: {sorted(ranges)})")
        out[key] = _quantity(ctx, raw, f"{where}.{key}", ranges[key])
    return out


def load_series(path: str | Path) -> ValidationSeries:
    """Read and validate one ``scenes/validation/<id>.toml``; one-line ValueError on bad input."""
    path = Path(path)
    ctx = _Ctx(path)
    with open(path, "rb") as fh:
        try:
            raw = tomllib.load(fh)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"{path.name}: not valid TOML ({exc})") from None
    extra = set(raw) - {"series", "bearing", "oil", "unknowns", "points", "checks"}
    if extra:
        ctx.fail("top level", sorted(extra), "unknown tables (allowed: series, bearing, oil, unknowns, "
                                             "points, checks)")
    s = raw.get("series")
    if not isinstance(s, dict):
        ctx.fail("series", s, "required table")
    sid = _string(ctx, s, "id", "series")
    if sid != path.stem:
        ctx.fail("series.id", sid, f"must equal the file name stem {path.stem!r}")
    read = s.get("full_text_read")
    if not isinstance(read, bool):
        ctx.fail("series.full_text_read", read, "required: true or false")
    related = s.get("related_sources", [])
    if not isinstance(related, list) or not all(isinstance(r, str) for r in related):
        ctx.fail("series.related_sources", related, "must be a list of strings")
    series = Series(sid, _string(ctx, s, "title", "series"), _string(ctx, s, "source", "series"),
                    _string(ctx, s, "what_was_measured", "series"), read,
                    s.get("notes", ""), s.get("slip_definition", ""), tuple(related))

    b = raw.get("bearing")
    if not isinstance(b, dict):
        ctx.fail("bearing", b, "required table")
    cat = {"inner_ring": INNER_RING, "ball_material": BALL_MATERIAL, "ring_material": None}
    skip = set(cat) | {f"{k}_source" for k in cat} | {"cage"}
    bq = _quantities(ctx, b, "bearing", BEARING_RANGES, skip)
    if "n_balls" in bq and bq["n_balls"].value is not None and bq["n_balls"].value != int(bq["n_balls"].value):
        ctx.fail("bearing.n_balls.value", bq["n_balls"].value, "must be an integer")
    strings = {}
    for k, choices in cat.items():
        strings[k] = _string(ctx, b, k, "bearing", required=False, choices=choices)
        strings[k + "_source"] = _string(ctx, b, k + "_source", "bearing", required=strings[k] is not None)
    cage = None
    if "cage" in b:
        c = b["cage"]
        if not isinstance(c, dict):
            ctx.fail("bearing.cage", c, "must be a table")
        g = _string(ctx, c, "guidance", "bearing.cage", required=False, choices=GUIDANCE)
        m = _string(ctx, c, "material", "bearing.cage", required=False)
        cage = Cage(g, _string(ctx, c, "guidance_source", "bearing.cage", required=g is not None) or "",
                    m, _string(ctx, c, "material_source", "bearing.cage", required=m is not None) or "",
                    _quantities(ctx, c, "bearing.cage", CAGE_RANGES,
                                {"guidance", "guidance_source", "material", "material_source"}))
    bearing = Bearing(bq, strings["inner_ring"], strings["inner_ring_source"] or "",
                      strings["ball_material"], strings["ball_material_source"] or "",
                      strings["ring_material"], strings["ring_material_source"] or "", cage)

    oil = None
    if "oil" in raw:
        o = raw["oil"]
        if not isinstance(o, dict):
            ctx.fail("oil", o, "must be a table")
        oil = Oil(_string(ctx, o, "name", "oil", required=False),
                  _string(ctx, o, "supply", "oil", required=False, choices=SUPPLY),
                  _string(ctx, o, "source", "oil"),
                  _quantities(ctx, o, "oil", OIL_RANGES, {"name", "supply", "source"}))

    unknowns = []
    for i, u in enumerate(raw.get("unknowns", [])):
        where = f"unknowns[{i}]"
        name = _string(ctx, u, "name", where)
        if name not in UNKNOWN_RANGES:
            ctx.fail(f"{where}.name", name, f"allowed names {sorted(UNKNOWN_RANGES)}")
        if name in bq and bq[name].value is not None:
            ctx.fail(f"{where}.name", name, "is given in [bearing] already: an unknown is a value the "
                                            "source leaves open")
        lo = _number(ctx, u.get("low"), f"{where}.low", UNKNOWN_RANGES[name])
        hi = _number(ctx, u.get("high"), f"{where}.high", UNKNOWN_RANGES[name])
        if not lo < hi:
            ctx.fail(f"{where}.low", lo, f"must be below high = {hi!r}")
        reason = _string(ctx, u, "reason", where)
        if len(reason) < 20:
            ctx.fail(f"{where}.reason", reason, "give the reason for the range (>= 20 characters)")
        unknowns.append(Unknown(name, lo, hi, reason, u.get("unit", "")))
    names = [u.name for u in unknowns]
    if len(set(names)) != len(names):
        ctx.fail("unknowns", names, "names must be unique")

    # geometry consistency where both values are given
    def val(k):
        q = bq.get(k)
        return None if q is None else q.value
    d, dm, bd, od = val("bore"), val("pitch_diameter"), val("ball_diameter"), val("outside_diameter")
    if d is not None and od is not None and not d < od:
        ctx.fail("bearing.bore.value", d, f"must be below outside_diameter = {od!r}")
    if dm is not None and d is not None and od is not None and not d < dm < od:
        ctx.fail("bearing.pitch_diameter.value", dm, f"must lie in (bore, outside_diameter) = ({d}, {od})")
    if dm is not None and bd is not None and not bd < dm:
        ctx.fail("bearing.ball_diameter.value", bd, f"must be below pitch_diameter = {dm!r}")
    for key in ("pitch_diameter", "ball_diameter", "free_contact_angle_deg"):
        if val(key) is None and key not in names:
            ctx.fail(f"bearing.{key}", None, "neither given nor declared in [[unknowns]] "
                                             "(needed for the kinematic brackets)")

    points, ids = [], set()
    measured_keys = set()
    for i, p in enumerate(raw.get("points", [])):
        where = f"points[{i}]"
        pid = p.get("id")
        if not isinstance(pid, (str, int)) or isinstance(pid, bool):
            ctx.fail(f"{where}.id", pid, "required: a string or an integer")
        pid = str(pid)
        if pid in ids:
            ctx.fail(f"{where}.id", pid, "point ids must be unique")
        ids.add(pid)
        where = f"points[{pid}]"
        status = p.get("status", "measured")
        if status not in STATUS:
            ctx.fail(f"{where}.status", status, f"allowed values {STATUS}")
        conds, meas, model = {}, {}, {}
        for key, v in p.items():
            if key in ("id", "status", "note"):
                continue
            if key in CONDITION_RANGES:
                conds[key] = _quantity(ctx, v, f"{where}.{key}", CONDITION_RANGES[key])
            elif key in MEASURED_RANGES:
                meas[key] = _quantity(ctx, v, f"{where}.{key}", MEASURED_RANGES[key])
            elif key in MODEL_RANGES:
                model[key] = _quantity(ctx, v, f"{where}.{key}", MODEL_RANGES[key])
            else:
                ctx.fail(f"{where}.{key}", v, "unknown key (allowed: "
                         f"{sorted(CONDITION_RANGES) + sorted(MEASURED_RANGES) + sorted(MODEL_RANGES)})")
        if "speed_rpm" not in conds:
            ctx.fail(f"{where}.speed_rpm", None, "required")
        if status == "measured" and not meas:
            ctx.fail(f"{where}", "no measured_* value", "a 'measured' point needs one "
                     "(use status = \"conditions_only\" when the source's numbers are not readable)")
        if status == "conditions_only" and meas:
            ctx.fail(f"{where}.status", status, "has measured_* values: use status = \"measured\"")
        measured_keys |= set(meas)
        points.append(Point(pid, conds, meas, model, status, p.get("note", "")))
    if not points:
        ctx.fail("points", [], "at least one point is required")
    if "measured_cage_slip_percent" in measured_keys and len(series.slip_definition) < 20:
        ctx.fail("series.slip_definition", series.slip_definition,
                 "required when a point gives measured_cage_slip_percent: state the source's definition")

    checks = []
    for i, c in enumerate(raw.get("checks", [])):
        where = f"checks[{i}]"
        checks.append(Check(_string(ctx, c, "kind", where, choices=CHECK_KINDS),
                            _string(ctx, c, "statement", where), _string(ctx, c, "source", where)))
    return ValidationSeries(path, series, bearing, oil, tuple(unknowns), tuple(points), tuple(checks))


def load_all(directory: str | Path = VALIDATION_DIR) -> list[ValidationSeries]:
    """Every series file of ``directory``, sorted by file name."""
    return [load_series(p) for p in sorted(Path(directory).glob("*.toml"))]


# ---------------------------------------------------------------------------------------------
# brackets of a series point
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class BracketRange:
    """Brackets of one point over the box of the geometry unknowns (min, max of each)."""
    point_id: str
    speed_rpm: float
    angle_case: str                      # "free" or "measured"
    inner_rpm: tuple[float, float]
    outer_rpm: tuple[float, float]
    epicyclic_rpm: tuple[float, float]   # at the free contact angle
    inner_slip_percent: tuple[float, float]
    outer_slip_percent: tuple[float, float]
    geometry_known: bool                 # False: the ranges span the declared unknowns


def _span(vs: ValidationSeries, key: str) -> tuple[float, float]:
    q = vs.bearing.get(key)
    if q is not None and q.value is not None:
        return (q.value, q.value)
    u = vs.unknown(key)
    if u is not None:
        return (u.low, u.high)
    if q is not None:
        return q.span()
    raise ValueError(f"{vs.path.name}: bearing.{key} = None: neither given nor an unknown")


def point_brackets(vs: ValidationSeries, point: Point, angle_case: str = "free") -> BracketRange | None:
    """Inner-/outer-control cage speeds of a point at the free contact angle (both contacts), or
    at the measured operating angles (``angle_case = "measured"``: needs measured inner and
    outer contact angles, else None). Geometry unknowns are swept over their corners."""
    if angle_case not in ("free", "measured"):
        raise ValueError(f"angle_case = {angle_case!r}: allowed values ('free', 'measured')")
    speed_lo, speed_hi = point.conditions["speed_rpm"].span()
    if speed_lo != speed_hi:
        return None
    n = speed_lo
    dms, ds, a0s = _span(vs, "pitch_diameter"), _span(vs, "ball_diameter"), _span(vs, "free_contact_angle_deg")
    if angle_case == "measured":
        mi, mo = point.measured.get("measured_inner_contact_angle_deg"), point.measured.get(
            "measured_outer_contact_angle_deg")
        if mi is None or mo is None or mi.value is None or mo.value is None:
            return None
    res = {"i": [], "o": [], "e": [], "si": [], "so": []}
    for dm in sorted(set(dms)):
        for d in sorted(set(ds)):
            for a0 in sorted(set(a0s)):
                ai, ao = (a0, a0) if angle_case == "free" else (mi.value, mo.value)
                br = brackets(n, d, dm, ai, ao, reference_angle_deg=a0)
                res["i"].append(br.inner.cage_speed_rpm)
                res["o"].append(br.outer.cage_speed_rpm)
                res["e"].append(br.epicyclic_rpm)
                res["si"].append(br.inner_slip_percent)
                res["so"].append(br.outer_slip_percent)
    mm = {k: (float(np.min(v)), float(np.max(v))) for k, v in res.items()}
    known = len(set(dms)) == len(set(ds)) == len(set(a0s)) == 1
    return BracketRange(point.id, n, angle_case, mm["i"], mm["o"], mm["e"], mm["si"], mm["so"], known)


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


def _fmt_span(lo_hi: tuple[float, float], digits: int = 0) -> str:
    lo, hi = (0.0 if abs(v) < 0.5 * 10 ** (-digits) else v for v in lo_hi)
    if abs(hi - lo) <= 10 ** (-digits) / 2:
        return f"{lo:.{digits}f}"
    return f"{lo:.{digits}f}–{hi:.{digits}f}"


def bracket_table(vs: ValidationSeries) -> str:
    """Markdown table: per point the measured cage speed/slip and the two brackets at the free
    contact angle (and at measured operating angles where the source gives them), plus the
    symmetric contact-angle split each bracket would need to reproduce a measured slip."""
    head = ("| point | speed, rpm | measured | inner-control n_c, rpm (slip %) | "
            "outer-control n_c, rpm (slip %) | split for inner / outer control, deg |\n"
            "|---|---|---|---|---|---|\n")
    rows = []
    for p in vs.points:
        meas = []
        for key, q in p.measured.items():
            meas.append(f"{key.removeprefix('measured_')} = {q.value if q.value is not None else q.span()}")
        meas_s = "; ".join(meas) if meas else "not readable"
        br = point_brackets(vs, p, "free")
        slip = p.measured.get("measured_cage_slip_percent")
        if br is not None and slip is not None and slip.value is not None:
            n_r = tuple(e * (1.0 - slip.value / 100.0) for e in br.epicyclic_rpm)
            meas_s += f" (n_c = {_fmt_span(n_r)} rpm over the unknowns)"
        if br is None:
            rows.append(f"| {p.id} | {_fmt_span(p.conditions['speed_rpm'].span())} | {meas_s} | "
                        "— (speed only bounded) | — | — |")
            continue
        split = "—"
        if slip is not None and slip.value is not None:
            res = {}
            for control in CONTROLS:
                vals = []
                for dm in sorted(set(_span(vs, "pitch_diameter"))):
                    for d in sorted(set(_span(vs, "ball_diameter"))):
                        for a0 in sorted(set(_span(vs, "free_contact_angle_deg"))):
                            vals.append(split_for_slip(br.speed_rpm, d, dm, a0, slip.value, control))
                ok = [v for v in vals if v is not None]
                res[control] = ("none" if not ok else _fmt_span((min(ok), max(ok)), 1)
                                + ("" if len(ok) == len(vals) else " (not everywhere)"))
            split = f"{res['inner']} / {res['outer']}"
        rows.append(f"| {p.id} | {br.speed_rpm:.0f} | {meas_s} | {_fmt_span(br.inner_rpm)} "
                    f"({_fmt_span(br.inner_slip_percent, 2)}) | {_fmt_span(br.outer_rpm)} "
                    f"({_fmt_span(br.outer_slip_percent, 2)}) | {split} |")
        brm = point_brackets(vs, p, "measured")
        if brm is not None:
            rows.append(f"| {p.id} (measured angles) | {brm.speed_rpm:.0f} | | {_fmt_span(brm.inner_rpm)} "
                        f"({_fmt_span(brm.inner_slip_percent, 2)}) | {_fmt_span(brm.outer_rpm)} "
                        f"({_fmt_span(brm.outer_slip_percent, 2)}) | |")
    return head + "\n".join(rows) + "\n"


if __name__ == "__main__":  # python3 -m flexbearing.studies.race_control: the docs' bracket tables
    for _vs in load_all():
        print(f"### {_vs.series.id}\n")
        print(bracket_table(_vs))
