"""The file format of a published test series: ``scenes/validation/<series_id>.toml``, read and
checked by `load_series` (issue 35, "Kinematics you can trust"; issue 45, validation in its own place).

One bearing per file. Every number is a *quantity*, an inline table
``{ value = ..., source = "...", digitised = false, uncertainty = ... }`` (or, for a number the
source only bounds, ``{ low = ..., high = ..., source = "..." }``). Units are SI unless the key names
them (``*_rpm``, ``*_deg``, ``*_C``). Geometry the source leaves open goes to ``[[unknowns]]`` with a
range and a reason. Tables::

    [series]         id (= the file stem), title, source, full_text_read, what_was_measured,
                     notes, slip_definition (required with a measured slip), related_sources
    [bearing]        quantities (BEARING_RANGES), inner_ring, ball_material, ring_material (each
                     with its *_source); [bearing.cage]: quantities (CAGE_RANGES), guidance, material
    [oil]            quantities (OIL_RANGES), name, supply, source
    [[unknowns]]     name (UNKNOWN_RANGES), low, high, reason, unit
    [[points]]       id, status, note, conditions (CONDITION_RANGES), measured_* (MEASURED_RANGES),
                     reported_model_* (MODEL_RANGES)
    [[checks]]       kind, statement, source

Every table is read through flexbearing.common.validation.require_table (an unknown key is named
with the allowed ones), every number through require_range (its allowed range), and every other
refusal is the same kind of line: a bad file raises one InputError naming the file, the field, the
value and the allowed range or values; the command line prints it and exits non-zero.

Records, not the model's types
------------------------------
`SeriesBearing`, `SeriesCage` and `SeriesOil` are what a source published, not the model's
flexbearing.multibody.bearing.Bearing and Oil: each number may be absent or only bounded, carries
its source and reading uncertainty, and the model's bearing needs every number. The series driver
builds the model's Bearing and Oil from a record, its unknowns and stated rules
(flexbearing.studies.validation.series.series_bearing, series_oil).
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from flexbearing.common.validation import InputError, require_range, require_table

VALIDATION_DIR = Path(__file__).resolve().parents[3] / "scenes" / "validation"


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
class SeriesCage:
    """The cage as a series records it (module docstring, "Records, not the model's types")."""
    guidance: str | None                 # "outer" | "inner" | "balls" | None (not stated)
    guidance_source: str = ""
    material: str | None = None
    material_source: str = ""
    quantities: dict[str, Quantity] = field(default_factory=dict)


@dataclass(frozen=True)
class SeriesBearing:
    """The bearing as a series records it: the published numbers with their sources, each a value or
    only bounds, and the stated categories (module docstring, "Records, not the model's types")."""
    quantities: dict[str, Quantity]
    inner_ring: str | None = None        # "split" | "one_piece"
    inner_ring_source: str = ""
    ball_material: str | None = None     # "steel" | "silicon_nitride"
    ball_material_source: str = ""
    ring_material: str | None = None
    ring_material_source: str = ""
    cage: SeriesCage | None = None

    def get(self, key: str) -> Quantity | None:
        return self.quantities.get(key)


@dataclass(frozen=True)
class SeriesOil:
    """The oil and its supply as a series records them (module docstring)."""
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
    bearing: SeriesBearing
    oil: SeriesOil | None
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

# the keys of each table (module docstring)
FILE_KEYS = ("series", "bearing", "oil", "unknowns", "points", "checks")
SERIES_KEYS = ("id", "title", "source", "full_text_read", "what_was_measured", "notes", "slip_definition",
               "related_sources")
BEARING_CATEGORIES = {"inner_ring": INNER_RING, "ball_material": BALL_MATERIAL, "ring_material": None}
BEARING_KEYS = (*BEARING_RANGES, *BEARING_CATEGORIES, *(f"{k}_source" for k in BEARING_CATEGORIES), "cage")
CAGE_KEYS = (*CAGE_RANGES, "guidance", "guidance_source", "material", "material_source")
OIL_KEYS = (*OIL_RANGES, "name", "supply", "source")
UNKNOWN_KEYS = ("name", "low", "high", "reason", "unit")
POINT_KEYS = ("id", "status", "note", *CONDITION_RANGES, *MEASURED_RANGES, *MODEL_RANGES)
CHECK_KEYS = ("kind", "statement", "source")
QUANTITY_KEYS = ("value", "low", "high", "source", "digitised", "uncertainty", "note")


class _Reader:
    """The checks of one file; every refusal is one InputError line starting with the file name."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, value, allowed: str):
        raise InputError(f"{self.path.name}: {where} = {value!r}: {allowed}")

    def table(self, where: str, value, allowed) -> dict:
        return require_table(f"{self.path.name}: {where}", value, allowed)

    def array(self, where: str, value) -> list:
        if not isinstance(value, list):
            self.fail(where, value, "must be an array of tables [[" + where + "]]")
        return value

    def tables(self, where: str, value, allowed) -> list[dict]:
        """An array of tables ([[where]]), each checked with `table`."""
        return [self.table(f"{where}[{i}]", v, allowed) for i, v in enumerate(self.array(where, value))]

    def string(self, table: dict, key: str, where: str, required: bool = True,
               choices: tuple[str, ...] | None = None) -> str | None:
        v = table.get(key)
        if v is None:
            if required:
                self.fail(f"{where}.{key}", None, "required (a non-empty string)")
            return None
        if not isinstance(v, str) or not v.strip():
            self.fail(f"{where}.{key}", v, "must be a non-empty string")
        if choices is not None and v not in choices:
            self.fail(f"{where}.{key}", v, f"allowed values {choices}")
        return v

    def text(self, table: dict, key: str, where: str) -> str:
        """An optional free text (notes): a string, empty when absent."""
        v = table.get(key, "")
        if not isinstance(v, str):
            self.fail(f"{where}.{key}", v, "must be a string")
        return v

    def number(self, v, where: str, lo_hi: tuple[float, float]) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.fail(where, v, f"must be a number in [{lo_hi[0]:g}, {lo_hi[1]:g}]")
        return require_range(f"{self.path.name}: {where}", v, lo_hi[0], lo_hi[1])

    def quantity(self, raw, where: str, lo_hi: tuple[float, float]) -> Quantity:
        if not isinstance(raw, dict):
            self.fail(where, raw, "must be an inline table { value = ..., source = \"...\" } "
                                  "(or { low = ..., high = ..., source = \"...\" })")
        self.table(where, raw, QUANTITY_KEYS)
        source = raw.get("source")
        if not isinstance(source, str) or len(source.strip()) < 8:
            self.fail(f"{where}.source", source, "required: the report, table/figure and page of the number")
        digitised = raw.get("digitised", False)
        if not isinstance(digitised, bool):
            self.fail(f"{where}.digitised", digitised, "must be true or false")
        unc = raw.get("uncertainty")
        if digitised and unc is None:
            self.fail(f"{where}.uncertainty", None, "required when digitised = true (reading uncertainty)")
        if unc is not None:
            unc = self.number(unc, f"{where}.uncertainty", (0.0, abs(lo_hi[1] - lo_hi[0])))
        note = self.text(raw, "note", where)
        if "value" in raw:
            if "low" in raw or "high" in raw:
                self.fail(where, raw, "give either value or low/high, not both")
            return Quantity(source, self.number(raw["value"], f"{where}.value", lo_hi),
                            digitised=digitised, uncertainty=unc, note=note)
        if "low" not in raw or "high" not in raw:
            self.fail(where, raw, "needs value, or both low and high")
        lo = self.number(raw["low"], f"{where}.low", lo_hi)
        hi = self.number(raw["high"], f"{where}.high", lo_hi)
        if not lo <= hi:
            self.fail(f"{where}.low", lo, f"must not exceed high = {hi!r}")
        return Quantity(source, None, lo, hi, digitised, unc, note)

    def quantities(self, table: dict, where: str, ranges: dict) -> dict[str, Quantity]:
        """The quantities of a table whose keys were checked (`table`): every key of `ranges` it has."""
        return {key: self.quantity(raw, f"{where}.{key}", ranges[key]) for key, raw in table.items()
                if key in ranges}

    # ------------------------------------------------------------------------------ the tables
    def series(self, raw) -> Series:
        s = self.table("series", raw.get("series"), SERIES_KEYS)
        sid = self.string(s, "id", "series")
        if sid != self.path.stem:
            self.fail("series.id", sid, f"must equal the file name stem {self.path.stem!r}")
        read = s.get("full_text_read")
        if not isinstance(read, bool):
            self.fail("series.full_text_read", read, "required: true or false")
        related = s.get("related_sources", [])
        if not isinstance(related, list) or not all(isinstance(r, str) for r in related):
            self.fail("series.related_sources", related, "must be a list of strings")
        return Series(sid, self.string(s, "title", "series"), self.string(s, "source", "series"),
                      self.string(s, "what_was_measured", "series"), read, self.text(s, "notes", "series"),
                      self.text(s, "slip_definition", "series"), tuple(related))

    def bearing(self, raw) -> SeriesBearing:
        b = self.table("bearing", raw.get("bearing"), BEARING_KEYS)
        bq = self.quantities(b, "bearing", BEARING_RANGES)
        n = bq.get("n_balls")
        if n is not None and n.value is not None and n.value != int(n.value):
            self.fail("bearing.n_balls.value", n.value, "must be an integer")
        strings = {}
        for k, choices in BEARING_CATEGORIES.items():
            strings[k] = self.string(b, k, "bearing", required=False, choices=choices)
            strings[k + "_source"] = self.string(b, k + "_source", "bearing", required=strings[k] is not None)
        cage = None
        if "cage" in b:
            c = self.table("bearing.cage", b["cage"], CAGE_KEYS)
            g = self.string(c, "guidance", "bearing.cage", required=False, choices=GUIDANCE)
            m = self.string(c, "material", "bearing.cage", required=False)
            cage = SeriesCage(g, self.string(c, "guidance_source", "bearing.cage", required=g is not None) or "",
                              m, self.string(c, "material_source", "bearing.cage", required=m is not None) or "",
                              self.quantities(c, "bearing.cage", CAGE_RANGES))
        return SeriesBearing(bq, strings["inner_ring"], strings["inner_ring_source"] or "",
                             strings["ball_material"], strings["ball_material_source"] or "",
                             strings["ring_material"], strings["ring_material_source"] or "", cage)

    def oil(self, raw) -> SeriesOil | None:
        if "oil" not in raw:
            return None
        o = self.table("oil", raw["oil"], OIL_KEYS)
        return SeriesOil(self.string(o, "name", "oil", required=False),
                         self.string(o, "supply", "oil", required=False, choices=SUPPLY),
                         self.string(o, "source", "oil"), self.quantities(o, "oil", OIL_RANGES))

    def unknowns(self, raw, bearing: SeriesBearing) -> tuple[Unknown, ...]:
        out = []
        for i, u in enumerate(self.tables("unknowns", raw.get("unknowns", []), UNKNOWN_KEYS)):
            where = f"unknowns[{i}]"
            name = self.string(u, "name", where)
            if name not in UNKNOWN_RANGES:
                self.fail(f"{where}.name", name, f"allowed names {sorted(UNKNOWN_RANGES)}")
            given = bearing.get(name)
            if given is not None and given.value is not None:
                self.fail(f"{where}.name", name, "is given in [bearing] already: an unknown is a value the "
                                                 "source leaves open")
            lo = self.number(u.get("low"), f"{where}.low", UNKNOWN_RANGES[name])
            hi = self.number(u.get("high"), f"{where}.high", UNKNOWN_RANGES[name])
            if not lo < hi:
                self.fail(f"{where}.low", lo, f"must be below high = {hi!r}")
            reason = self.string(u, "reason", where)
            if len(reason) < 20:
                self.fail(f"{where}.reason", reason, "give the reason for the range (>= 20 characters)")
            out.append(Unknown(name, lo, hi, reason, self.text(u, "unit", where)))
        names = [u.name for u in out]
        if len(set(names)) != len(names):
            self.fail("unknowns", names, "names must be unique")
        return tuple(out)

    def geometry(self, bearing: SeriesBearing, unknowns: tuple[Unknown, ...]) -> None:
        """The geometry's consistency where both values are given, and what the brackets need."""
        def val(k):
            q = bearing.get(k)
            return None if q is None else q.value
        d, dm, bd, od = val("bore"), val("pitch_diameter"), val("ball_diameter"), val("outside_diameter")
        if d is not None and od is not None and not d < od:
            self.fail("bearing.bore.value", d, f"must be below outside_diameter = {od!r}")
        if dm is not None and d is not None and od is not None and not d < dm < od:
            self.fail("bearing.pitch_diameter.value", dm, f"must lie in (bore, outside_diameter) = ({d}, {od})")
        if dm is not None and bd is not None and not bd < dm:
            self.fail("bearing.ball_diameter.value", bd, f"must be below pitch_diameter = {dm!r}")
        names = [u.name for u in unknowns]
        for key in ("pitch_diameter", "ball_diameter", "free_contact_angle_deg"):
            if val(key) is None and key not in names:
                self.fail(f"bearing.{key}", None, "neither given nor declared in [[unknowns]] "
                                                  "(needed for the kinematic brackets)")

    def points(self, raw, series: Series) -> tuple[Point, ...]:
        points, ids, measured_keys = [], set(), set()
        for i, p in enumerate(self.array("points", raw.get("points", []))):
            if not isinstance(p, dict):
                self.table(f"points[{i}]", p, POINT_KEYS)             # refuses it, naming the keys
            pid = p.get("id")
            if not isinstance(pid, (str, int)) or isinstance(pid, bool):
                self.fail(f"points[{i}].id", pid, "required: a string or an integer")
            pid = str(pid)
            if pid in ids:
                self.fail(f"points[{i}].id", pid, "point ids must be unique")
            ids.add(pid)
            where = f"points[{pid}]"
            self.table(where, p, POINT_KEYS)
            status = p.get("status", "measured")
            if status not in STATUS:
                self.fail(f"{where}.status", status, f"allowed values {STATUS}")
            conds = self.quantities(p, where, CONDITION_RANGES)
            meas = self.quantities(p, where, MEASURED_RANGES)
            model = self.quantities(p, where, MODEL_RANGES)
            if "speed_rpm" not in conds:
                self.fail(f"{where}.speed_rpm", None, "required")
            if status == "measured" and not meas:
                self.fail(f"{where}", "no measured_* value", "a 'measured' point needs one "
                          "(use status = \"conditions_only\" when the source's numbers are not readable)")
            if status == "conditions_only" and meas:
                self.fail(f"{where}.status", status, "has measured_* values: use status = \"measured\"")
            measured_keys |= set(meas)
            points.append(Point(pid, conds, meas, model, status, self.text(p, "note", where)))
        if not points:
            self.fail("points", [], "at least one point is required")
        if "measured_cage_slip_percent" in measured_keys and len(series.slip_definition) < 20:
            self.fail("series.slip_definition", series.slip_definition,
                      "required when a point gives measured_cage_slip_percent: state the source's definition")
        return tuple(points)

    def checks(self, raw) -> tuple[Check, ...]:
        return tuple(Check(self.string(c, "kind", f"checks[{i}]", choices=CHECK_KINDS),
                           self.string(c, "statement", f"checks[{i}]"), self.string(c, "source", f"checks[{i}]"))
                     for i, c in enumerate(self.tables("checks", raw.get("checks", []), CHECK_KEYS)))


def load_series(path: str | Path) -> ValidationSeries:
    """Read and check one ``scenes/validation/<id>.toml`` (module docstring); a bad file raises one
    InputError line naming the file, the field, the value and the allowed range."""
    path = Path(path)
    r = _Reader(path)
    try:
        with open(path, "rb") as fh:
            raw = tomllib.load(fh)
    except OSError as exc:
        raise InputError(f"series file = {str(path)!r}: cannot be read ({exc.strerror})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{path.name}: not valid TOML ({exc})") from None
    require_table(f"{path.name}: top level", raw, FILE_KEYS)
    series = r.series(raw)
    bearing = r.bearing(raw)
    oil = r.oil(raw)
    unknowns = r.unknowns(raw, bearing)
    r.geometry(bearing, unknowns)
    points = r.points(raw, series)
    return ValidationSeries(path, series, bearing, oil, unknowns, points, r.checks(raw))


def load_all(directory: str | Path = VALIDATION_DIR) -> list[ValidationSeries]:
    """Every series file of ``directory``, sorted by file name."""
    d = Path(directory)
    if not d.is_dir():
        raise InputError(f"series directory = {str(d)!r}: not a folder (allowed: a folder of <series_id>.toml files)")
    return [load_series(p) for p in sorted(d.glob("*.toml"))]
