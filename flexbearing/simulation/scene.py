"""Scenes: one TOML file says what to simulate and what to record; validated before any work.

A scene names the bearing (overrides of the paper preset), the oil, the cage model, the operating
spectra (speed and load versus time, impacts), the run duration, the integrator tolerance and the
outputs to record. Units: SI everywhere (m, kg, s, N, Pa, rad) except inner-ring speeds, which are
in rpm and say so in the key name (`start_rpm`, `end_rpm`, `rpm`, `table_rpm`).

    name = "paper_steady_rigid"
    description = "..."

    [bearing]                 # any scalar field of flexbearing.multibody.bearing.Bearing (PAPER_BEARING)
    fe = 0.515                # outer groove radius / Dw; must be > 0.5
    ball_diameter = 22e-3     # m, given here only (the cage's pockets take it from the bearing)
    inner_ring = "split"      # "split" (two halves, the paper's three-point type) | "one_piece"
    free_contact_angle = 0.5236  # rad; with shim_angle (rad) and radial_clearance (m, the diametral
                              #   clearance Pd) any two of the three give the third (split ring; the
                              #   angle alone: shim = angle and the design clearance); one-piece: the
                              #   angle or the clearance (flexbearing.multibody.clearance)
    ball_material = "steel"   # "steel" (M50) | "silicon_nitride": elastic and thermal constants
    [bearing.ball_material]   # or a table: density, youngs_modulus, poisson_ratio (also ring_material)

    [oil]
    preset = "paper"          # "paper" (20 °C, PAPER_OIL) | "engine" (100 °C, ENGINE_OIL)
    temperature_c = 20.0      # any field of flexbearing.multibody.bearing.Oil
    supply = "under_race"     # "unspecified" (fixed cavity oil fraction, the presets) | "jet" | "under_race":
                              #   the churning drag's oil fraction falls as oil_air_fraction·n_ref/n with
                              #   n_ref = oil_air_reference_rpm (flexbearing.multibody.oil_supply)

    [cage]
    model = "rigid"           # "rigid" | "flexible"
    pocket_diameter = 22.5e-3 # any scalar field of flexbearing.mesh.cage_geometry.CageGeometry
    guidance = "outer"        # "outer" | "inner" (ring lands: bearing.guide_land_diameter,
                              #   bearing.inner_land_diameter) | "balls" (no land contact)
    pocket_shape = "cylindrical"  # "cylindrical" | "spherical" (centred on the pitch circle) |
                              #   "conical" (tangent to that sphere; pocket_cone_angle = half-angle,
                              #   rad, in [-30°, 30°], > 0 wider at the outside) | "elliptical"
                              #   (pocket_circumferential_diameter: round; pocket_diameter: along x)
    cad = "my_cage.step"      # a CAD cage (STEP/BREP, relative to this file) instead of the
    cad_unit = "mm"           #   parametric one: pockets and land found in it and matched to the
                              #   bearing (flexbearing.mesh.cad_cage); a BREP file needs cad_unit
    n_modes = 26              # flexible only: modes kept (6 rigid + 20 elastic, as the paper),
    mesh_size = 5e-3          #   FE mesh size [m] (default flexbearing.mesh.cage_mesh.DEFAULT_MESH_SIZE),
    element_order = 3         #   FE degree on the curved mesh (default P3),
    damping_beta = 1e-5       #   stiffness-proportional damping D = damping_beta·K [s]
    yield_strength = 835e6    #   cage material's yield strength [Pa], for the report only
                              #   (default: 40CrNiMoA, GB/T 3077, unless [cage.material] is given)
    stress_monitor_interval = 1  # max von Mises evaluated every k-th accepted integrator step
                              #   (default 1 = every step, exact peak-hold; k in [1, 10000]; about
                              #   1/k of the monitor's cost, peaks between evaluations can be missed:
                              #   flexbearing.multibody.stress_peak, benchmarks/results/work_precision.md)
    [cage.material]           # density, youngs_modulus, poisson_ratio

    [model]                   # multibody options passed to flexbearing.multibody.model.build_model
    traction_law = "fit"      # "fit" (paper's 4106 fit) | "ehl" (EHL film-shear law, no dead zone at
                              #   light load; flexbearing.multibody.traction), with "ehl":
                              #   traction_scale = 1.0, contact_temperature_rise = 0.0 (K); default:
                              #   "fit" for the 4106 oil at 15–25 °C, "ehl" otherwise (a warning when
                              #   "fit" is given outside; flexbearing.simulation.derived.traction_law)

    [operation]
    duration = 0.6            # s
    [operation.speed]         # either phases (played one after the other from t = 0) ...
    phases = [{kind = "ramp", duration = 0.2, start_rpm = 10000, end_rpm = 14000},
              {kind = "uniform", duration = 0.2, rpm = 14000}]
    # ... or a table of (t [s], speed [rpm]) points, piecewise linear, constant after the last:
    # table_rpm = [[0.0, 10000], [0.2, 14000]]
    [operation.load]          # required (no load is axial_load = 0): either constant loads ...
    axial_load = 55e3         # N, along +x (up to MAX_LOAD here; the run's setup refuses a load whose
                              #   equilibrium is deeper than the contacts' limit, 2.3 MN axial for the
                              #   paper bearing: flexbearing.multibody.initial.check_contact_range)
    radial_load = 4e3         # N, in the y–z plane along radial_direction (default -z)
    radial_direction = [0.0, 0.0, -1.0]   # or radial_azimuth [rad] from +y towards +z
    # ... or points = [{t = 0.0, axial_load = 0, radial_load = 0}, {t = 0.1, ...}] (ramps)
    # ... or table = [[t, Fx, Fy, Fz], ...] (any piecewise-linear load, components in N)
    [[operation.load.impacts]]
    t_center = 0.1            # or t_start [s]
    duration = 0.02           # s
    magnitude = 50e3          # N
    shape = "half-sine"       # "half-sine" | "rectangular"
    # direction = [x, y, z] or azimuth [rad] (radial); default: the radial load direction

    [integrator]
    tolerance = 1e-6          # local error tolerance (relative), in [1e-12, 0.1]
    method = "dopri5"         # "dopri5" (Dormand–Prince 5(4)) | "bs32" (Bogacki–Shampine 3(2))
    initial_step = 1e-7       # s
    max_step = 1e-5           # s
    start = "quasi_static"    # the initial state: "quasi_static" (default: the equilibrium without
                              #   friction, pure rolling) | "steady" (the steady running state at the
                              #   speed and load of t = 0, quasi-static where none is found:
                              #   flexbearing.multibody.steady_start.steady_start)

    [output]
    sample_interval = 1e-4    # s: outputs are recorded at t = 0, dt, 2 dt, ...
    record = ["contact_stress", "pocket_force", "guiding_force", "cage_speed"]
    checkpoint_every = 100    # samples between checkpoints (resume points)

Every key with its unit, default or derivation rule and allowed range: docs/scene.md (generated from
SCENE_TABLES and flexbearing.simulation.scene_keys). What a scene does not give is derived by a stated
rule from the bearing's own geometry, or refused (flexbearing.simulation.derived; Scene.derived).

Loading converts the spectra to the arrays of `flexbearing.multibody.profiles`: speed_table (n, 2) in rad/s,
load_table (n, 4) in N, impacts (m, 6). Every refusal names the field, the value and the allowed
range (flexbearing.common.validation.InputError); unknown keys are refused with the list of allowed keys.
"""
from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from flexbearing.common.materials import YIELD_STRENGTH_40CrNiMoA, Material, ball_material_named
from flexbearing.multibody.clearance import INNER_RINGS, resolve_inner_ring
from flexbearing.multibody.oil_supply import SUPPLIES
from flexbearing.mesh.cage_geometry import GUIDANCES, POCKET_SHAPES, CageGeometry
from flexbearing.common.cache import content_hash
from flexbearing.common.validation import InputError, require_range, require_table
from flexbearing.multibody.bearing import ENGINE_OIL, PAPER_BEARING, PAPER_OIL, Bearing, Oil
from flexbearing.multibody.model import DEFAULT_OPTIONS
from flexbearing.multibody.output_registry import GROUPS
from flexbearing.multibody.profiles import HALF_SINE, RECTANGULAR, breakpoints, load_at
from flexbearing.mesh.cad_cage import UNITS, cad_cage_geometry, cad_geometry_from_dict
from flexbearing.simulation import derived as DV

RPM = 2.0 * math.pi / 60.0          # rad/s per rpm

CAGE_MODELS = ("rigid", "flexible")
# the run's initial states ([integrator] start; flexbearing.multibody.steady_start.START_KINDS, kept here
# so that reading a scene does not import the solvers; tests/test_steady_start.py checks they agree)
START_KINDS = ("quasi_static", "steady")
OIL_PRESETS = {"paper": PAPER_OIL, "engine": ENGINE_OIL}
IMPACT_SHAPES = {"half-sine": HALF_SINE, "rectangular": RECTANGULAR}
DEFAULT_RADIAL_DIRECTION = (0.0, 0.0, -1.0)   # radial load on the inner ring: vertical, downwards

# Ranges of the scene's own numbers (the bearing, oil and cage ranges live in their validate()).
MAX_SPEED_RPM = 60000.0      # above any aero-engine main-shaft bearing (DN ~ 3.6e6 for this one)
MAX_LOAD = 1e7               # N
MAX_DURATION = 1000.0        # s of simulated time
MIN_SAMPLE_INTERVAL = 1e-7   # s: 10 MHz, far above the fastest dynamics the model resolves (the
                             # balls' ~22 kHz contact modes); a smaller interval only multiplies the file
MAX_SAMPLES = 10**9          # samples a run may record (the output-size check bounds the bytes)
# the integrator's methods (flexbearing.multibody.integrator.METHODS; tests/test_scene.py checks they agree)
INTEGRATOR_METHODS = ("dopri5", "bs32")
# Below this the integrator's error estimate is at the rounding level of the state: at 1e-13 and
# 1e-14 the step collapses to 1e-12 s within 0.6 ms of the 14,000 rpm case with an impact, at 3e-13
# and 1e-12 it finishes (benchmarks/results/stress_test.md)
MIN_TOLERANCE = 1e-12

_MATERIAL_KEYS = tuple(f.name for f in dataclasses.fields(Material))
_BEARING_SCALARS = tuple(f.name for f in dataclasses.fields(Bearing)
                         if f.name not in ("cage", "ball_material", "ring_material", "inner_ring",
                                           "ball_thermal", "ring_thermal"))
# derived or given (flexbearing.multibody.clearance.resolve_inner_ring): any two of these for a split ring
_INNER_RING_KEYS = ("free_contact_angle", "shim_angle", "radial_clearance")
# the ball diameter is the bearing's (given once, in [bearing]); the cage takes it from there
_CAGE_SCALARS = tuple(f.name for f in dataclasses.fields(CageGeometry) if f.name not in ("material", "ball_diameter"))
_FLEXIBLE_KEYS = ("n_modes", "mesh_size", "element_order", "damping_beta", "yield_strength",
                  "stress_monitor_interval")
_OIL_KEYS = tuple(f.name for f in dataclasses.fields(Oil))
_CAD_KEYS = ("cad", "cad_unit")
_RAMP_KEYS = ("kind", "t_start", "duration", "start_rpm", "end_rpm")
_UNIFORM_KEYS = ("kind", "t_start", "duration", "rpm")

# The keys each scene table accepts: what the validation below checks against (require_table), and
# what docs/scene.md lists (flexbearing.simulation.scene_keys has one line per key; a key added here
# without its line fails tests/test_scene_docs.py).
SCENE_TABLES = {
    "scene": ("name", "description", "bearing", "oil", "cage", "model", "operation", "integrator", "output"),
    "bearing": _BEARING_SCALARS + ("ball_material", "ring_material", "inner_ring", "free_contact_angle"),
    "material": _MATERIAL_KEYS,
    "oil": ("preset",) + _OIL_KEYS,
    "cage": ("model",) + _CAGE_SCALARS + _FLEXIBLE_KEYS + ("material",) + _CAD_KEYS,
    "model": tuple(DEFAULT_OPTIONS),
    "operation": ("duration", "speed", "load"),
    "operation.speed": ("phases", "table_rpm"),
    "operation.speed.phases[]": tuple(dict.fromkeys(_RAMP_KEYS + _UNIFORM_KEYS)),
    "operation.load": ("axial_load", "radial_load", "radial_direction", "radial_azimuth", "points", "table",
                       "impacts"),
    "operation.load.points[]": ("t", "axial_load", "radial_load"),
    "operation.load.impacts[]": ("t_start", "t_center", "duration", "magnitude", "direction", "azimuth", "shape"),
    "integrator": ("tolerance", "method", "initial_step", "max_step", "start"),
    "output": ("sample_interval", "record", "checkpoint_every"),
}


@dataclass(frozen=True)
class Scene:
    """A validated scene. Arrays are float64 and ready for flexbearing.multibody.profiles."""
    name: str
    description: str
    bearing: Bearing
    oil: Oil
    cage_model: str                   # "rigid" | "flexible"
    flexible: dict                    # reduced-cage parameters given in the scene (flexible only),
                                      # and the cage's yield_strength, which only the report reads
    model_options: dict               # passed to flexbearing.multibody.model.build_model
    duration: float                   # s
    speed_table: np.ndarray           # (n, 2): t [s], omega [rad/s]
    load_table: np.ndarray            # (n, 4): t [s], Fx, Fy, Fz [N]
    impacts: np.ndarray               # (m, 6): t_start, duration, Fx, Fy, Fz amplitudes, shape
    tolerance: float
    initial_step: float               # s
    max_step: float | None            # s
    sample_interval: float            # s
    outputs: tuple                    # scene outputs (flexbearing.multibody.output_registry.GROUPS), in the scene's order
    checkpoint_every: int             # samples
    method: str = "dopri5"            # integrator method (flexbearing.multibody.integrator.METHODS)
    start: str = "quasi_static"       # initial state ([integrator] start; flexbearing.multibody.steady_start.START_KINDS)
    text: str = ""                    # the TOML text as loaded (stored in the results file)
    data: dict = field(default_factory=dict, repr=False)   # the parsed TOML
    path: str = ""
    cad: dict = field(default_factory=dict)   # cage.cad: {"file", "unit", "key"} (flexbearing.mesh.cad_cage)
    # what the scene did not give (flexbearing.simulation.derived.Derived: derived, measured or default),
    # printed at run start and in the report's summary
    derived: tuple = ()
    warnings: tuple = ()                      # one line each, printed at run start and in the report

    @property
    def n_samples(self) -> int:
        """Samples at t_k = k·dt, k = 0..N, N = round(duration/dt) (the last one clipped to the
        duration when dt does not divide it)."""
        return int(math.ceil(self.duration / self.sample_interval - 1e-9)) + 1

    def sample_time(self, k: int) -> float:
        """t_k computed from the integer k (never accumulated, so resumed runs hit the same times)."""
        return min(k * self.sample_interval, self.duration)

    def breakpoints(self) -> np.ndarray:
        return breakpoints(self.speed_table, self.load_table, self.impacts)

    def initial_loads(self) -> tuple[float, float]:
        """(Fa, Fr) at t = 0 without impacts: Fa = Fx, Fr = |(Fy, Fz)| (for the quasi-static start)."""
        out = np.zeros(3)
        load_at(0.0, self.load_table, self.impacts[:0], out)
        return float(out[0]), float(math.hypot(out[1], out[2]))

    def content_hash(self) -> str:
        """Hash of the parsed scene (comments and layout do not count) and, for a CAD cage, of the
        content of every file its geometry reads (cage.cad's key): a resume after the CAD file
        changed is another scene."""
        return content_hash(self.data) if not self.cad else content_hash([self.data, self.cad["key"]])


# ---------------------------------------------------------------- small strict readers

def _number(field_: str, value, lo=None, hi=None, lo_open=False, hi_open=False, unit="") -> float:
    if isinstance(value, bool):
        raise InputError(f"{field_} = {value!r} is not a number")
    return require_range(field_, value, lo, hi, lo_open, hi_open, unit)


def _integer(field_: str, value, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{field_} = {value!r} must be an integer in [{lo}, {hi}]")
    return int(require_range(field_, value, lo, hi))


def _string(field_: str, value, choices) -> str:
    if value not in choices:
        raise InputError(f"{field_} = {value!r} must be one of {', '.join(repr(c) for c in choices)}")
    return value


def _vector3(field_: str, value) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 3:
        raise InputError(f"{field_} = {value!r} must be a list of 3 numbers [x, y, z]")
    v = np.array([_number(f"{field_}[{i}]", c) for i, c in enumerate(value)])
    # scaled by its largest component first: the norm of [0, 1e200, 1e200] overflows to inf (and
    # v / inf = 0 dropped the load), that of [0, 1e-200, 0] underflows to 0
    big = float(np.max(np.abs(v)))
    if big == 0.0:
        raise InputError(f"{field_} = {value!r} must not be the zero vector")
    v = v / big
    return v / float(np.linalg.norm(v))


def _file_name(field_: str, value) -> str:
    """A name that becomes a file name (the default results file is out/<name>.h5): one path
    component, so a scene cannot write outside its output folder."""
    if not isinstance(value, str) or not value.strip():
        raise InputError(f"{field_} = {value!r} must be a non-empty string")
    bad = [c for c in ("/", "\\") if c in value]
    if bad or value in (".", "..") or any(ord(c) < 32 for c in value):
        why = f"contains {bad[0]!r}" if bad else "is not a file name"
        raise InputError(f"{field_} = {value!r} {why}: the name becomes the results file's name "
                         f"(out/<name>.h5), so it must be one plain file name without '/', '\\', "
                         f"control characters, '.' or '..' (give the folder with -o instead)")
    return value


def _one_of(d: dict, where: str, keys) -> str | None:
    given = [k for k in keys if k in d]
    if len(given) > 1:
        raise InputError(f"{where}: give only one of {', '.join(keys)} (got {', '.join(given)})")
    return given[0] if given else None


# ---------------------------------------------------------------- sections

def _material(base: Material, d, where: str) -> Material:
    d = require_table(where, d, SCENE_TABLES["material"])
    return dataclasses.replace(base, **{k: _number(f"{where}.{k}", v) for k, v in d.items()})


def _bearing_and_cage(b: dict, c: dict, scene_path: str = "") -> tuple[Bearing, str, dict, dict, tuple]:
    """The bearing with its cage, the cage model, the flexible cage's parameters, the CAD cage's
    record and the derived values (flexbearing.simulation.derived: what the scene does not give is
    derived by a stated rule from the bearing's own geometry, or refused)."""
    b = require_table("bearing", b, SCENE_TABLES["bearing"])
    if isinstance(c, dict) and "ball_diameter" in c:
        raise InputError("cage.ball_diameter: give the ball diameter once, as bearing.ball_diameter "
                         "(the cage's pockets take it from the bearing)")
    c = require_table("cage", c, SCENE_TABLES["cage"])
    c, cad = dict(c), {}
    for k in _CAD_KEYS:
        if k in c:
            cad[k] = c.pop(k)
    changes = {}
    inner = {}
    for k, v in b.items():
        if k == "ball_material" and isinstance(v, str):
            named = ball_material_named(v)            # elastic and thermal constants together
            changes["ball_material"], changes["ball_thermal"] = named.material, named.thermal
        elif k in ("ball_material", "ring_material"):
            changes[k] = _material(getattr(PAPER_BEARING, k), v, f"bearing.{k}")
        elif k == "n_balls":
            changes[k] = _integer("bearing.n_balls", v, 3, 200)
        elif k == "inner_ring":
            changes[k] = _string("bearing.inner_ring", v, INNER_RINGS)
        elif k in _INNER_RING_KEYS:
            inner[k] = _number(f"bearing.{k}", v)
        else:
            changes[k] = _number(f"bearing.{k}", v)
    # the ring sizes: a bearing given by its rings derives its pitch diameter, or is refused
    sized, derived = DV.ring_sizes({k: changes[k] for k in DV.RING_SIZE_KEYS if k in changes})
    changes.update(sized)
    DV.needs_contact_angle(changes, inner)
    # free contact angle, shim angle and clearance: what is not given is derived (a split ring given
    # nothing keeps the preset's shim angle and clearance)
    # (a split ring's clearance follows its fe and Dw by the design rule unless given)
    ring = changes.get("inner_ring", PAPER_BEARING.inner_ring)
    if inner or ring != PAPER_BEARING.inner_ring or changes.keys() & {"fe", "fi", "ball_diameter"}:
        fe, fi = changes.get("fe", PAPER_BEARING.fe), changes.get("fi", PAPER_BEARING.fi)
        dw = changes.get("ball_diameter", PAPER_BEARING.ball_diameter)
        if ring == "split" and not inner.keys() & {"free_contact_angle", "shim_angle"}:
            inner["shim_angle"] = PAPER_BEARING.shim_angle
            derived.append(DV.Derived("bearing.shim_angle", PAPER_BEARING.shim_angle, "rad",
                                      "the paper's assumed shim angle (give shim_angle or free_contact_angle)",
                                      "default"))
        layout = resolve_inner_ring(ring, fe, fi, dw, inner.get("free_contact_angle"), inner.get("shim_angle"),
                                    inner.get("radial_clearance"))
        changes["radial_clearance"] = layout.diametral_clearance
        if ring == "split":
            changes["shim_angle"] = layout.shim_angle
        if "radial_clearance" not in inner:
            derived.append(DV.Derived("bearing.radial_clearance", layout.diametral_clearance, "m",
                                      f"the {ring} inner ring's layout (flexbearing.multibody.clearance)"))
        if ring == "split" and "shim_angle" not in inner:
            derived.append(DV.Derived("bearing.shim_angle", layout.shim_angle, "rad",
                                      "the split inner ring's layout (flexbearing.multibody.clearance)"))
    if not DV.is_paper_size(changes):
        for k in ("fe", "fi"):
            if k not in changes:
                derived.append(DV.Derived(f"bearing.{k}", getattr(PAPER_BEARING, k), "",
                                          "the paper's groove radius ratio (× D_w; give it if yours differs)",
                                          "default"))
    cage_model = _string("cage.model", c.get("model", "rigid"), CAGE_MODELS)
    cage_changes = {}
    for k, v in c.items():
        if k in ("model",) + _FLEXIBLE_KEYS:
            continue
        if k == "material":
            cage_changes[k] = _material(PAPER_BEARING.cage.material, v, "cage.material")
        elif k == "n_pockets":
            cage_changes[k] = _integer("cage.n_pockets", v, 3, 200)
        elif k == "guidance":
            cage_changes[k] = _string("cage.guidance", v, GUIDANCES)
        elif k == "pocket_shape":
            cage_changes[k] = _string("cage.pocket_shape", v, POCKET_SHAPES)
        else:
            cage_changes[k] = _number(f"cage.{k}", v)
    given_cage = set(cage_changes)
    # the cage has one pocket per ball unless the scene says otherwise
    if "n_balls" in changes and "n_pockets" not in cage_changes:
        cage_changes["n_pockets"] = changes["n_balls"]
        derived.append(DV.Derived("cage.n_pockets", changes["n_balls"], "", "bearing.n_balls (one pocket per ball)"))
    cage_changes["ball_diameter"] = changes.get("ball_diameter", PAPER_BEARING.ball_diameter)
    # and its spherical pockets are centred on the bearing's pitch circle unless it says otherwise
    if "pitch_diameter" in changes and "pocket_centre_diameter" not in cage_changes:
        cage_changes["pocket_centre_diameter"] = changes["pitch_diameter"]
        if cage_changes.get("pocket_shape", PAPER_BEARING.cage.pocket_shape) != "cylindrical":
            derived.append(DV.Derived("cage.pocket_centre_diameter", changes["pitch_diameter"], "m",
                                      "bearing.pitch_diameter (pockets centred on the pitch circle)"))
    cad_info = {}
    if not cad:
        # the parametric cage's dimensions not given: the paper cage's proportions to the bearing's own
        dims, rec = DV.cage_dimensions(changes, cage_changes)
        cage_changes.update(dims)
        derived += rec
    if "material" not in cage_changes:
        derived.append(DV.Derived("cage.material", "40CrNiMoA (7870 kg/m³, 209 GPa, ν 0.295)", "",
                                  "the paper's cage steel (default; give [cage.material] for another)", "default"))
    changes["cage"] = dataclasses.replace(PAPER_BEARING.cage, **cage_changes)
    if cad:
        changes["cage"], cad_info = _cad_cage(cad, changes, {k: c[k] for k in c if k in given_cage},
                                              scene_path)
        g = changes["cage"]
        for k in ("outside_diameter", "bore_diameter", "width", "pocket_diameter", "land_width"):
            derived.append(DV.Derived(f"cage.{k}", getattr(g, k), "m", f"the faces of cage.cad = {cad['cad']!r}",
                                      "measured"))
    # the ring lands the scene does not give: from the cage's own diameters
    g = changes["cage"]
    lands, rec = DV.land_diameters(g.guidance, g.outside_diameter, g.bore_diameter, changes)
    changes.update(lands)
    derived += rec
    bearing = dataclasses.replace(PAPER_BEARING, **changes).validate()

    flexible = {}
    for k in _FLEXIBLE_KEYS:
        if k not in c:
            continue
        if cage_model != "flexible":
            raise InputError(f"cage.{k} applies only to cage.model = 'flexible' (this scene's cage "
                             f"is '{cage_model}')")
        v = c[k]
        if k == "n_modes":
            flexible[k] = _integer("cage.n_modes", v, 1, 500)
        elif k == "stress_monitor_interval":
            from flexbearing.multibody.stress_peak import MAX_INTERVAL   # the compiled monitor: flexible only
            flexible[k] = _integer("cage.stress_monitor_interval", v, 1, MAX_INTERVAL)
        elif k == "element_order":
            flexible[k] = _integer("cage.element_order", v, 1, 3)   # FE degree (default P3)
        elif k == "mesh_size":
            flexible[k] = _number("cage.mesh_size", v, 0.0, 0.5 * bearing.cage.width, lo_open=True,
                                  unit="m")
        elif k == "yield_strength":
            flexible[k] = _number("cage.yield_strength", v, 0.0, 1e10, lo_open=True, unit="Pa")
        else:
            flexible[k] = _number("cage.damping_beta", v, 0.0, 1e-2, unit="s")
    if cage_model == "flexible":
        # the paper keeps 26 modes (§4.1); imported here: a rigid scene loads nothing of fem_cage
        from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP
        flexible.setdefault("n_modes", DEFAULT_N_KEEP)
        if "material" not in c:              # the paper's 40CrNiMoA; another material names its own
            flexible.setdefault("yield_strength", YIELD_STRENGTH_40CrNiMoA)
    return bearing, cage_model, flexible, cad_info, tuple(derived)


# what a CAD cage's file decides; the scene gives only what the file cannot say
_CAD_OWN = tuple(k for k in _CAGE_SCALARS if k not in ("guidance", "material"))


def _cad_cage(cad: dict, changes: dict, given_cage: dict, scene_path: str):
    """The equivalent geometry of cage.cad (flexbearing.mesh.cad_cage, cached by the file's
    content): the file is found relative to the scene; its pockets and land are matched to the
    scene's bearing; the cage's geometry keys are the file's, so the scene may not give them."""
    given = sorted(k for k in given_cage if k in _CAD_OWN)
    if given:
        raise InputError(f"cage.{given[0]} = {given_cage[given[0]]!r}: the geometry of this cage is read "
                         f"from cage.cad = {cad.get('cad')!r}; give only guidance and material beside it")
    f = cad.get("cad")
    if not isinstance(f, str) or not f:
        raise InputError(f"cage.cad = {f!r} must be the file name of a STEP or BREP cage")
    unit = cad.get("cad_unit")
    if unit is not None:
        _string("cage.cad_unit", unit, tuple(UNITS))
    path = Path(f)
    if not path.is_absolute() and scene_path:
        path = Path(scene_path).resolve().parent / path
    base = dataclasses.replace(PAPER_BEARING, **{k: v for k, v in changes.items() if k != "cage"})
    cage = changes["cage"]
    recorded = _RECORDED_CAD.get()
    if recorded is not None:                 # a results file's scene: its CAD file is never read
        return _recorded_cad_cage(recorded, f)
    geometry, report, key = cad_cage_geometry(path, base.n_balls, base.pitch_diameter, base.ball_diameter,
                                              cage.guidance, unit, cage.material)
    return geometry, {"file": str(path), "unit": unit, "key": key, "report": report,
                      "geometry": dataclasses.asdict(geometry)}


# The CAD cage of a scene stored in a results file (flexbearing.simulation.results.scene_of_run):
# the run records it (cad_record) and the scene is rebuilt from that record, never from the file
# the stored scene names (a results file received from someone else names whatever it likes).
_RECORDED_CAD: contextvars.ContextVar = contextvars.ContextVar("recorded_cad", default=None)


def cad_record(scene) -> str:
    """JSON of what a run records of its scene's CAD cage: the file as given, the unit, the cache
    key (every file's content digest), the equivalent geometry and the report lines."""
    c = scene.cad
    return json.dumps({"file": c["file"], "unit": c["unit"], "key": c["key"], "report": c["report"],
                       "geometry": c.get("geometry") or dataclasses.asdict(scene.bearing.cage)})


@contextlib.contextmanager
def cad_from_record(record):
    """Within: a scene's cage.cad is not read; its geometry is `record`'s (cad_record's JSON, as
    a results file stores it). A missing record (a run recorded before it was kept) refuses the
    cage in one line rather than reading the file."""
    token = _RECORDED_CAD.set(record if record else "")
    try:
        yield
    finally:
        _RECORDED_CAD.reset(token)


def _recorded_cad_cage(record, named: str):
    if not record:
        raise InputError(f"cage.cad = {named!r}: the results file records no CAD cage (a run made "
                         f"before it was recorded); the CAD file it names is not read")
    try:
        rec = json.loads(record)
        geometry = cad_geometry_from_dict(rec["geometry"]).validate()
        info = {"file": str(rec["file"]), "unit": rec["unit"], "key": dict(rec["key"]),
                "report": [str(x) for x in rec["report"]], "geometry": dataclasses.asdict(geometry)}
    except InputError:
        raise
    except Exception:
        raise InputError(f"cage.cad = {named!r}: the results file's CAD cage record is damaged") from None
    return geometry, info


def _oil(d: dict) -> Oil:
    d = require_table("oil", d, SCENE_TABLES["oil"])
    preset = _string("oil.preset", d.get("preset", "paper"), tuple(OIL_PRESETS))
    changes = {k: _number(f"oil.{k}", v) for k, v in d.items() if k not in ("preset", "supply")}
    if "supply" in d:
        changes["supply"] = _string("oil.supply", d["supply"], SUPPLIES)
    return dataclasses.replace(OIL_PRESETS[preset], **changes).validate()


def _speed_table(d: dict, duration: float | None) -> tuple[np.ndarray, float]:
    d = require_table("operation.speed", d, SCENE_TABLES["operation.speed"])
    form = _one_of(d, "operation.speed", ("phases", "table_rpm"))
    if form is None:
        raise InputError("operation.speed needs either phases = [...] or table_rpm = [[t, rpm], ...]")
    rpm = lambda f, v: _number(f, v, 0.0, MAX_SPEED_RPM, unit="rpm")  # noqa: E731
    if form == "table_rpm":
        rows = d["table_rpm"]
        if not isinstance(rows, list) or not rows:
            raise InputError(f"operation.speed.table_rpm = {rows!r} must be a non-empty list of [t, rpm]")
        pts = []
        for i, row in enumerate(rows):
            f = f"operation.speed.table_rpm[{i}]"
            if not isinstance(row, list) or len(row) != 2:
                raise InputError(f"{f} = {row!r} must be [t_s, rpm]")
            t = _number(f"{f}[0] (t)", row[0], 0.0, MAX_DURATION, unit="s")
            if i == 0 and t != 0.0:
                raise InputError(f"{f}[0] (t) = {t:g} s: the speed profile must start at t = 0 "
                                 f"(allowed range [0, 0] s)")
            if i > 0 and t <= pts[-1][0]:
                kind = "overlap" if t < pts[-1][0] else "jump (two speeds at one time)"
                raise InputError(f"{f}[0] (t) = {t:g} s: times must increase strictly "
                                 f"(allowed range ({pts[-1][0]:g}, {MAX_DURATION:g}] s); this is an {kind}")
            pts.append((t, rpm(f"{f}[1] (rpm)", row[1])))
        if duration is None:
            if len(pts) == 1:
                raise InputError("operation.duration is missing (a one-point speed table does not "
                                 "define a duration)")
            duration = pts[-1][0]
        return np.array([(t, w * RPM) for t, w in pts], dtype=np.float64), duration

    phases = d["phases"]
    if not isinstance(phases, list) or not phases:
        raise InputError(f"operation.speed.phases = {phases!r} must be a non-empty list of phases")
    t = 0.0
    pts: list[tuple[float, float]] = []
    for i, ph in enumerate(phases):
        where = f"operation.speed.phases[{i}]"
        kind = _string(f"{where}.kind", (ph or {}).get("kind") if isinstance(ph, dict) else None,
                       ("ramp", "uniform"))
        keys = _RAMP_KEYS if kind == "ramp" else _UNIFORM_KEYS
        ph = require_table(where, ph, keys)
        if "t_start" in ph:
            t0 = _number(f"{where}.t_start", ph["t_start"], 0.0, MAX_DURATION, unit="s")
            if t0 != t:
                gap = "a gap" if t0 > t else "an overlap"
                raise InputError(f"{where}.t_start = {t0:g} s leaves {gap} after the previous phase, "
                                 f"which ends at {t:g} s (allowed range [{t:g}, {t:g}] s)")
        if "duration" not in ph:
            raise InputError(f"{where}.duration is missing (s, > 0)")
        dt = _number(f"{where}.duration", ph["duration"], 0.0, MAX_DURATION, lo_open=True, unit="s")
        if kind == "ramp":
            for k in ("start_rpm", "end_rpm"):
                if k not in ph:
                    raise InputError(f"{where}.{k} is missing (rpm, [0, {MAX_SPEED_RPM:g}])")
            w0 = rpm(f"{where}.start_rpm", ph["start_rpm"])
            w1 = rpm(f"{where}.end_rpm", ph["end_rpm"])
        else:
            if "rpm" not in ph:
                raise InputError(f"{where}.rpm is missing (rpm, [0, {MAX_SPEED_RPM:g}])")
            w0 = w1 = rpm(f"{where}.rpm", ph["rpm"])
        if pts and w0 != pts[-1][1]:
            # a speed step would need an infinite torque: refuse it rather than smooth it silently
            raise InputError(f"{where} starts at {w0:g} rpm but the previous phase ends at "
                             f"{pts[-1][1]:g} rpm: the speed must be continuous (allowed range "
                             f"[{pts[-1][1]:g}, {pts[-1][1]:g}] rpm)")
        if not pts:
            pts.append((t, w0))
        t = round(t + dt, 12)   # snap to 1 ps: 0.2 + 0.2 + 0.2 is 0.6, not 0.6000000000000001
        pts.append((t, w1))
    total = t
    if duration is None:
        duration = total
    elif abs(duration - total) > 1e-9 * max(1.0, total):
        raise InputError(f"operation.duration = {duration:g} s differs from the sum of the speed "
                         f"phases, {total:g} s (allowed range [{total:g}, {total:g}] s)")
    return np.array([(ti, w * RPM) for ti, w in pts], dtype=np.float64), duration


def _radial_direction(d: dict, where: str, prefix: str) -> np.ndarray:
    form = _one_of(d, where, (f"{prefix}direction", f"{prefix}azimuth"))
    if form is None:
        return np.array(DEFAULT_RADIAL_DIRECTION)
    if form.endswith("azimuth"):
        a = _number(f"{where}.{form}", d[form], -2 * math.pi, 2 * math.pi, unit="rad")
        return np.array([0.0, math.cos(a), math.sin(a)])
    v = _vector3(f"{where}.{form}", d[form])
    if prefix == "radial_" and abs(v[0]) > 1e-12:
        raise InputError(f"{where}.{form} = {d[form]!r} must be radial: x component 0 "
                         f"(allowed range [0, 0]); put axial load in axial_load")
    return v


def _load(d: dict, duration: float) -> tuple[np.ndarray, np.ndarray]:
    d = require_table("operation.load", d, SCENE_TABLES["operation.load"])
    load = lambda f, v: _number(f, v, 0.0, MAX_LOAD, unit="N")  # noqa: E731
    const = [k for k in ("axial_load", "radial_load") if k in d]
    form = _one_of(d, "operation.load", ("points", "table"))
    if form and const:
        raise InputError(f"operation.load: give either {form} or axial_load/radial_load, not both")
    if form == "table" and ("radial_direction" in d or "radial_azimuth" in d):
        raise InputError("operation.load: table = [[t, Fx, Fy, Fz], ...] gives components; "
                         "radial_direction/radial_azimuth do not apply")
    if form is None and not const:
        raise InputError("operation.load gives no static load: give axial_load and/or radial_load in N "
                         "(0 for none, explicitly), points = [...] or table = [...]")
    radial = _radial_direction(d, "operation.load", "radial_")
    if form is None:
        fa = load("operation.load.axial_load", d.get("axial_load", 0.0))
        fr = load("operation.load.radial_load", d.get("radial_load", 0.0))
        table = np.array([[0.0, fa, fr * radial[1], fr * radial[2]]], dtype=np.float64)
    else:
        rows = d[form]
        if not isinstance(rows, list) or not rows:
            raise InputError(f"operation.load.{form} = {rows!r} must be a non-empty list")
        out = []
        for i, row in enumerate(rows):
            f = f"operation.load.{form}[{i}]"
            if form == "points":
                row = require_table(f, row, SCENE_TABLES["operation.load.points[]"])
                if "t" not in row:
                    raise InputError(f"{f}.t is missing (s)")
                t = _number(f"{f}.t", row["t"], 0.0, MAX_DURATION, unit="s")
                fa = load(f"{f}.axial_load", row.get("axial_load", 0.0))
                fr = load(f"{f}.radial_load", row.get("radial_load", 0.0))
                vals = (fa, fr * radial[1], fr * radial[2])
            else:
                if not isinstance(row, list) or len(row) != 4:
                    raise InputError(f"{f} = {row!r} must be [t_s, Fx_N, Fy_N, Fz_N]")
                t = _number(f"{f}[0] (t)", row[0], 0.0, MAX_DURATION, unit="s")
                vals = tuple(_number(f"{f}[{j}]", row[j], -MAX_LOAD, MAX_LOAD, unit="N") for j in (1, 2, 3))
            if out and t <= out[-1][0]:
                raise InputError(f"{f} t = {t:g} s: times must increase strictly (allowed range "
                                 f"({out[-1][0]:g}, {MAX_DURATION:g}] s)")
            out.append((t, *vals))
        table = np.array(out, dtype=np.float64)

    impacts = []
    rows = d.get("impacts", [])
    if not isinstance(rows, list):
        raise InputError(f"operation.load.impacts = {rows!r} must be a list of tables ([[operation.load.impacts]])")
    for i, imp in enumerate(rows):
        where = f"operation.load.impacts[{i}]"
        imp = require_table(where, imp, SCENE_TABLES["operation.load.impacts[]"])
        for k in ("duration", "magnitude"):
            if k not in imp:
                raise InputError(f"{where}.{k} is missing")
        T = _number(f"{where}.duration", imp["duration"], 0.0, duration, lo_open=True, unit="s")
        tk = _one_of(imp, where, ("t_start", "t_center"))
        if tk is None:
            raise InputError(f"{where}: give t_start or t_center (s)")
        if tk == "t_start":
            t0 = _number(f"{where}.t_start", imp["t_start"], 0.0, duration, hi_open=True, unit="s")
        else:
            tc = _number(f"{where}.t_center", imp["t_center"], 0.5 * T, duration, hi_open=True, unit="s")
            t0 = tc - 0.5 * T
        mag = load(f"{where}.magnitude", imp["magnitude"])
        shape = IMPACT_SHAPES[_string(f"{where}.shape", imp.get("shape", "half-sine"), tuple(IMPACT_SHAPES))]
        if "direction" in imp or "azimuth" in imp:
            direction = _radial_direction(imp, where, "")
        else:
            direction = radial
        impacts.append((t0, T, *(mag * direction), float(shape)))
    impacts = np.array(impacts, dtype=np.float64).reshape(-1, 6)
    return table, impacts


def _model_options(d: dict) -> dict:
    """[model] keys are checked against flexbearing.multibody.model.DEFAULT_OPTIONS."""
    if not isinstance(d, dict):
        raise InputError(f"model = {d!r} must be a table")
    require_table("model", d, SCENE_TABLES["model"])
    out = {}
    for k, v in d.items():
        if isinstance(v, (bool, str)):
            out[k] = v
        elif isinstance(v, int):
            out[k] = int(_number(f"model.{k}", v))
        else:
            out[k] = _number(f"model.{k}", v)
    return out


def parse_scene(data: dict, text: str = "", path: str = "") -> Scene:
    """Validate the parsed TOML `data` and build the Scene (no computation, no heavy imports)."""
    if isinstance(data, dict) and "case_set" in data:
        raise InputError(f"{path or 'scene'} is a case set ([case_set] with [[cases]]), not a scene: "
                         f"it is run by `flexbearing validate`")
    if isinstance(data, dict) and "unknowns" in data:
        raise InputError(f"{path or 'scene'} is an unknowns file ([unknowns.NAME] ranges), not a scene: "
                         f"it is run by `flexbearing uncertainty`")
    if isinstance(data, dict) and "study" in data:
        raise InputError(f"{path or 'scene'} is a study ([study] with a base scene and values), not a "
                         f"scene: it is run by `flexbearing study`")
    d = require_table("scene", data, SCENE_TABLES["scene"])
    name = _file_name("name", d.get("name", Path(path).stem if path else "scene"))
    description = d.get("description", "")
    if not isinstance(description, str):
        raise InputError(f"description = {description!r} must be a string")
    bearing, cage_model, flexible, cad, derived = _bearing_and_cage(d.get("bearing", {}), d.get("cage", {}), path)
    oil = _oil(d.get("oil", {}))
    model_options = _model_options(d.get("model", {}))
    # the traction law follows the oil (flexbearing.simulation.derived.traction_law)
    model_options, rec, warnings = DV.traction_law(model_options, oil)
    derived = derived + tuple(rec)

    if "operation" not in d:
        raise InputError("[operation] is missing (duration, [operation.speed], [operation.load])")
    op = require_table("operation", d["operation"], SCENE_TABLES["operation"])
    duration = None
    if "duration" in op:
        duration = _number("operation.duration", op["duration"], 0.0, MAX_DURATION, lo_open=True, unit="s")
    if "speed" not in op:
        raise InputError("operation.speed is missing ([operation.speed] with phases or table_rpm)")
    speed_table, duration = _speed_table(op["speed"], duration)
    if "load" not in op:
        # refused rather than read as zero: an unloaded bearing is a rare scene and a forgotten
        # table looks the same; zero load is one explicit line
        raise InputError("operation.load is missing: give the loads on the inner ring, [operation.load] "
                         "with axial_load and/or radial_load in N (axial_load = 0 for an unloaded bearing), "
                         "points = [...] or table = [...]")
    load_table, impacts = _load(op["load"], duration)

    integ = require_table("integrator", d.get("integrator", {}), SCENE_TABLES["integrator"])
    start = _string("integrator.start", integ.get("start", "quasi_static"), START_KINDS)
    tolerance = _number("integrator.tolerance", integ.get("tolerance", 1e-6), MIN_TOLERANCE, 1e-1)
    method = _string("integrator.method", integ.get("method", "dopri5"), INTEGRATOR_METHODS)
    max_step = None
    if "max_step" in integ:
        max_step = _number("integrator.max_step", integ["max_step"], 0.0, duration, lo_open=True, unit="s")
    initial_step = _number("integrator.initial_step", integ.get("initial_step", min(1e-7, max_step or 1e-7)),
                           0.0, max_step or duration, lo_open=True, unit="s")

    out = require_table("output", d.get("output", {}), SCENE_TABLES["output"])
    if "sample_interval" not in out:
        raise InputError("output.sample_interval is missing (s, in (0, operation.duration])")
    dt = _number("output.sample_interval", out["sample_interval"],
                 max(MIN_SAMPLE_INTERVAL, duration / MAX_SAMPLES), duration, unit="s")
    record = out.get("record", [])
    if not isinstance(record, list) or not record:
        raise InputError(f"output.record = {record!r} must be a non-empty list of outputs from: "
                         f"{', '.join(GROUPS)}")
    for i, r in enumerate(record):
        _string(f"output.record[{i}]", r, GROUPS)
    if len(set(record)) != len(record):
        raise InputError(f"output.record = {record!r} lists an output twice")
    if "von_mises" in record and cage_model != "flexible":
        raise InputError("output.record: 'von_mises' (cage stress) needs cage.model = 'flexible' "
                         f"(this scene's cage is '{cage_model}')")
    checkpoint_every = _integer("output.checkpoint_every", out.get("checkpoint_every", 100), 1, 10**9)

    return Scene(name=name, description=description, bearing=bearing, oil=oil, cage_model=cage_model,
                 flexible=flexible, model_options=model_options, duration=duration,
                 speed_table=speed_table, load_table=load_table, impacts=impacts,
                 tolerance=tolerance, initial_step=initial_step, max_step=max_step,
                 sample_interval=dt, outputs=tuple(record), checkpoint_every=checkpoint_every,
                 method=method, start=start, text=text, data=data, path=str(path), cad=cad, derived=derived,
                 warnings=tuple(warnings))


def load_scene(path) -> Scene:
    """Read and validate a scene file. TOML syntax errors are reported with their line."""
    path = Path(path)
    return loads_scene(_read_text(path, "scene file"), str(path))


def _read_text(path: Path, what: str) -> str:
    """The UTF-8 text of `path` (TOML is UTF-8 by definition); InputError naming the file otherwise."""
    try:
        return path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{what} {str(path)!r} cannot be read: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise InputError(f"{what} {str(path)!r} is not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at "
                         f"offset {exc.start}): a TOML file must be UTF-8; save it as UTF-8 (or it is "
                         f"not a {what})") from None


def loads_scene(text: str, path: str = "") -> Scene:
    try:
        data = tomllib.loads(text)
        return parse_scene(data, text=text, path=path)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"scene {path or '<text>'} is not valid TOML: {exc}") from None
    except RecursionError:
        raise _too_deep("scene", path or "<text>") from None


def _too_deep(what: str, path) -> InputError:
    """The one line for TOML nested deeper than Python's parser recurses (arrays in arrays ...)."""
    return InputError(f"{what} {path} is nested too deeply (arrays or tables inside one another, more "
                      f"levels than a {what} has): not a {what} flexbearing reads")


def merge(base: dict, override: dict) -> dict:
    """Deep-merge two parsed scenes (tables merge key by key, everything else is replaced).
    Used by case sets and sweeps: a case is the base scene plus its overrides."""
    out = dict(base)
    for k, v in override.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = merge(out[k], v)
        else:
            out[k] = v
    return out


# ---------------------------------------------------------------- case sets (validation runs)

CASE_KEYS = ("id", "group", "axial_load", "radial_load", "speed_rpm", "test_slip_percent",
             "paper_slip_percent")


@dataclass(frozen=True)
class CaseSet:
    """Steady test cases sharing one base scene (scenes/slip_rate_table4.toml)."""
    name: str
    description: str
    duration: float              # s simulated per case
    average_from: float          # s: start of the averaging window of the slip rate
    cases: tuple                 # dicts with CASE_KEYS (slip rates in %, as published)
    scenes: dict                 # case id -> Scene
    path: str = ""


def read_toml(path, what: str) -> dict:
    """The parsed TOML file `path`; an unreadable file or a syntax error is an InputError that
    names `what` it was meant to be (e.g. "case set") and the path."""
    path = Path(path)
    text = _read_text(path, what)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{what} {path} is not valid TOML: {exc}") from None
    except RecursionError:
        raise _too_deep(what, path) from None


def load_case_set(path) -> CaseSet:
    """Read a case set: [case_set] (name, description, duration, average_from), [base] (a scene
    without operation) and [[cases]] (id, group, axial_load, radial_load, speed_rpm and the published
    slip rates). Each case becomes the base scene with a uniform speed and constant loads."""
    path = Path(path)
    data = read_toml(path, "case set")
    require_table("case set", data, ("case_set", "base", "cases"))
    head = require_table("case_set", data.get("case_set", {}), ("name", "description", "duration", "average_from"))
    duration = _number("case_set.duration", head.get("duration"), 0.0, MAX_DURATION, lo_open=True, unit="s")
    average_from = _number("case_set.average_from", head.get("average_from", 0.5 * duration), 0.0, duration,
                           hi_open=True, unit="s")
    base = require_table("base", data.get("base", {}), ("description", "bearing", "oil", "cage", "model",
                                                 "integrator", "output"))
    rows = data.get("cases")
    if not isinstance(rows, list) or not rows:
        raise InputError(f"{path}: [[cases]] is missing")
    cases, scenes = [], {}
    for i, c in enumerate(rows):
        where = f"cases[{i}]"
        c = require_table(where, c, CASE_KEYS)
        missing = [k for k in CASE_KEYS if k not in c]
        if missing:
            raise InputError(f"{where}: missing {', '.join(missing)}")
        cid = _integer(f"{where}.id", c["id"], 1, 10**6)
        if cid in scenes:
            raise InputError(f"{where}.id = {cid} appears twice")
        case = {"id": cid, "group": _integer(f"{where}.group", c["group"], 1, 10**6),
                "axial_load": _number(f"{where}.axial_load", c["axial_load"], 0.0, MAX_LOAD, unit="N"),
                "radial_load": _number(f"{where}.radial_load", c["radial_load"], 0.0, MAX_LOAD, unit="N"),
                "speed_rpm": _number(f"{where}.speed_rpm", c["speed_rpm"], 0.0, MAX_SPEED_RPM,
                                     lo_open=True, unit="rpm"),
                "test_slip_percent": _number(f"{where}.test_slip_percent", c["test_slip_percent"], 0.0, 100.0,
                                             lo_open=True, unit="%"),
                "paper_slip_percent": _number(f"{where}.paper_slip_percent", c["paper_slip_percent"], 0.0,
                                              100.0, unit="%")}
        name = head.get("name", path.stem)
        scene_data = merge(base, {
            "name": f"{name}_case{cid:02d}",
            "operation": {"duration": duration,
                          "speed": {"phases": [{"kind": "uniform", "duration": duration,
                                                "rpm": case["speed_rpm"]}]},
                          "load": {"axial_load": case["axial_load"], "radial_load": case["radial_load"]}}})
        scenes[cid] = parse_scene(scene_data, text="", path=f"{path}#case{cid}")
        cases.append(case)
    return CaseSet(name=str(head.get("name", path.stem)), description=str(head.get("description", "")),
                   duration=duration, average_from=average_from, cases=tuple(cases), scenes=scenes,
                   path=str(path))
