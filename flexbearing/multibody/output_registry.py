"""Every quantity a run can record, written once: name, scene output, SI unit, dimensions, split.

A run evaluates its outputs at each sample (`flexbearing.multibody.outputs.evaluate_outputs`; the flexible
cage adds its stress and modal coordinates, flexbearing.coupling.flexible_cage), records those of the scene
outputs it asks for (`[output] record = [...]`, flexbearing.simulation.scene) and writes each as one dataset of
the results file (flexbearing.simulation.results), with the unit and the names of its dimensions as attributes;
the report (flexbearing.analysis.windows) reads its quantities' units from here. Every one of them reads this
table, and tests/test_output_registry.py checks it against what a run really records.

An entry describes one dataset of /outputs:

    name      the dataset's name
    groups    the scene outputs that record it (a dataset can belong to several); ALWAYS for the
              inner-ring speed and the external load, recorded by every run; () for a quantity the
              evaluation returns that no scene output records
    unit      SI unit ("1" dimensionless; "index" and "steps" for counts)
    dims      names of its dimensions after time (the time axis comes first in the file):
              ball (Z), contact (3: outer, inner_left, inner_right), axis (x, y, z of the bearing
              frame), radial_axis (y, z), tilt (tilt_y, tilt_z), ball_axis (x, r, t of the ball's
              orbiting frame), mode (the run's elastic modal coordinates), full_mode (the reduced
              cage file's full basis)
    columns   labels of the last dimension, written as the `columns` attribute (the run summary
              gives statistics per column), or None
    source    (evaluated key, index) when the evaluation returns a vector of mixed units that the
              run splits into SI datasets, e.g. ball_position (x m, r m, psi rad)

Adding a recorded quantity: compute it in the evaluation, add its entry here (and a Quantity in
flexbearing.analysis.windows if the report should tabulate it). Nothing else lists output names.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ALWAYS = "always"
CONTACTS = ("outer", "inner_left", "inner_right")

# the scene outputs (`[output] record`), in the order the scene's error message lists them
GROUPS = ("contact_stress", "ball_loads", "contact_angles", "pocket_force", "guiding_force",
          "cage_speed", "slip", "film_thickness", "von_mises", "kinematics", "cage_orbit",
          "cage_modes", "power_loss")


@dataclass(frozen=True)
class Output:
    name: str
    groups: tuple
    unit: str
    dims: tuple = ()
    columns: tuple | None = None
    source: tuple | None = None


def _o(name, groups, unit, dims=(), columns=None, source=None) -> Output:
    return Output(name, (groups,) if isinstance(groups, str) else tuple(groups), unit, tuple(dims),
                  columns, source)


_BC = ("ball", "contact")
OUTPUTS = (
    _o("inner_ring_speed", ALWAYS, "rad/s"),
    _o("external_load", ALWAYS, "N", ("axis",), ("x", "y", "z")),
    # ---- contacts (per ball and contact: outer, inner-left, inner-right)
    _o("contact_stress", "contact_stress", "Pa", _BC, CONTACTS),          # Hertz p0
    _o("contact_load", "ball_loads", "N", _BC, CONTACTS),
    _o("approach", "ball_loads", "m", _BC, CONTACTS),
    _o("contact_angle", "contact_angles", "rad", _BC, CONTACTS),
    _o("contact_angle_outer", "contact_angles", "rad", ("ball",)),
    _o("contact_angle_inner_loaded", "contact_angles", "rad", ("ball",)),
    _o("entrainment_speed", "kinematics", "m/s", _BC, CONTACTS),
    _o("slide_ratio", "slip", "1", _BC, CONTACTS),
    _o("traction_force", (), "N", _BC),
    _o("film_thickness_min", "film_thickness", "m", _BC, CONTACTS),
    _o("film_thickness_central", "film_thickness", "m", _BC, CONTACTS),
    # ---- pockets and guide land
    _o("pocket_force", "pocket_force", "N", ("ball",)),
    _o("pocket_force_tangential", "pocket_force", "N", ("ball",)),
    _o("pocket_offset", "pocket_force", "m", ("ball",)),
    _o("pocket_force_on_cage", "pocket_force", "N", ("ball", "axis")),
    _o("churning_drag", "kinematics", "N", ("ball",)),
    _o("cage_land_force", "guiding_force", "N", ("radial_axis",), ("y", "z")),
    _o("cage_land_force_magnitude", "guiding_force", "N"),
    _o("cage_land_torque", "guiding_force", "N·m"),
    _o("cage_rim_force", "guiding_force", "N"),
    # ---- cage speed and motion
    _o("cage_speed", "cage_speed", "rad/s"),
    _o("nominal_cage_speed", "cage_speed", "rad/s"),
    _o("slip_rate", "slip", "1"),
    _o("cage_centre", "cage_orbit", "m", ("axis",), ("x", "y", "z")),
    _o("cage_tilt", "cage_orbit", "rad", ("tilt",), ("tilt_y", "tilt_z")),
    _o("cage_eccentricity_ratio", "cage_orbit", "1"),
    _o("cage_guide_offset", "cage_orbit", "m", ("radial_axis",), ("y", "z")),
    # ---- kinematics of the balls and the inner ring
    _o("ball_axial_position", "kinematics", "m", ("ball",), source=("ball_position", 0)),
    _o("ball_radial_position", "kinematics", "m", ("ball",), source=("ball_position", 1)),
    _o("ball_azimuth", "kinematics", "rad", ("ball",), source=("ball_position", 2)),
    _o("ball_axial_velocity", "kinematics", "m/s", ("ball",), source=("ball_velocity", 0)),
    _o("ball_radial_velocity", "kinematics", "m/s", ("ball",), source=("ball_velocity", 1)),
    # (ball_velocity's third component is psi', recorded as ball_orbit_speed already)
    _o("ball_angular_velocity", "kinematics", "rad/s", ("ball", "ball_axis"), ("x", "r", "t")),
    _o("ball_orbit_speed", "kinematics", "rad/s", ("ball",)),
    _o("inner_ring_position", "kinematics", "m", ("axis",), ("x", "y", "z"),
       source=("inner_ring_displacement", slice(0, 3))),
    _o("inner_ring_tilt", "kinematics", "rad", ("tilt",), ("tilt_y", "tilt_z"),
       source=("inner_ring_displacement", slice(3, 5))),
    _o("ring_drive_torque", ("kinematics", "power_loss"), "N·m"),
    # ---- power balance (flexbearing.multibody.power_loss)
    _o("drive_power", "power_loss", "W"),
    _o("power_loss", "power_loss", "W"),
    _o("power_loss_traction", "power_loss", "W", _BC, CONTACTS),
    _o("power_loss_rolling", "power_loss", "W", _BC, CONTACTS),
    _o("power_loss_contact_damping", "power_loss", "W", _BC, CONTACTS),
    _o("power_loss_pocket", "power_loss", "W", ("ball",)),
    _o("power_loss_churning", "power_loss", "W", ("ball",)),
    _o("power_loss_guide_land", "power_loss", "W"),
    _o("power_loss_cage_damping", "power_loss", "W"),
    _o("mechanical_energy", "power_loss", "J"),
    _o("external_load_power", "power_loss", "W"),
    # ---- flexible cage (flexbearing.coupling.flexible_cage)
    _o("von_mises_max", "von_mises", "Pa"),
    _o("von_mises_max_vertex", "von_mises", "index"),
    _o("von_mises_max_time", "von_mises", "s"),
    _o("von_mises_steps", "von_mises", "steps"),
    _o("cage_modal_coordinates_full", "von_mises", "1", ("full_mode",)),
    _o("cage_modal_coordinates", "cage_modes", "1", ("mode",)),
)
OUTPUT = {o.name: o for o in OUTPUTS}

# The dimensions after time, each written once into the results file's /outputs as an HDF5
# dimension scale (flexbearing.simulation.results) so that xarray/netCDF readers see named dimensions: its
# coordinate values are the labels of the entries' `columns` where they have them (contact ->
# outer, inner_left, inner_right; axis -> x, y, z ...), else the index 0..n-1 (ball, mode).
DIMENSIONS = ("ball", "contact", "axis", "radial_axis", "tilt", "ball_axis", "mode", "full_mode")
DIMENSION_LABELS: dict[str, tuple] = {}
for _out in OUTPUTS:
    assert set(_out.dims) <= set(DIMENSIONS), _out.name
    if _out.columns:
        assert DIMENSION_LABELS.setdefault(_out.dims[-1], _out.columns) == _out.columns, _out.name
assert not set(DIMENSIONS) & set(OUTPUT) and "time" not in OUTPUT
del _out

# CF convention (udunits) spelling of the units that differ from ours; written as the `units`
# attribute beside `unit` (counts and indices are dimensionless, "1", in CF)
_CF_UNITS = {"N·m": "N m", "index": "1", "steps": "1"}


def cf_units(unit: str) -> str:
    """The CF/udunits `units` string of an SI unit of this registry ("N·m" -> "N m")."""
    return _CF_UNITS.get(unit, unit)

# the keys of the evaluation the entries come from (a split vector's key for its datasets)
EVALUATED = frozenset(o.source[0] if o.source else o.name for o in OUTPUTS)
# evaluated vectors of mixed units -> ((dataset, index along the last axis), ...)
SPLIT: dict[str, tuple] = {}
for _out in OUTPUTS:
    if _out.source is not None:
        SPLIT.setdefault(_out.source[0], ())
        SPLIT[_out.source[0]] += ((_out.name, _out.source[1]),)
del _out


def units() -> dict[str, str]:
    """{dataset name: SI unit} of every entry (and "time": "s")."""
    return {"time": "s", **{o.name: o.unit for o in OUTPUTS}}


def recorded_by(requested) -> set[str]:
    """Datasets the scene outputs `requested` record, the ALWAYS ones included."""
    want = set(requested) | {ALWAYS}
    return {o.name for o in OUTPUTS if want.intersection(o.groups)}


def evaluated_names(requested) -> set[str]:
    """Keys of the evaluation that `requested` records: the datasets, or the mixed vector they are
    split from."""
    return {OUTPUT[n].source[0] if OUTPUT[n].source else n for n in recorded_by(requested)}


def recorded_keys(requested, returned) -> list[str]:
    """The keys of `returned` (an evaluation's keys) to record for the requested scene outputs: those
    this table lists under them (and the ALWAYS ones); a key the table does not know (another
    backend's) is recorded when it starts with a requested output's name."""
    want = evaluated_names(requested)
    return [k for k in returned
            if k in want or (k not in EVALUATED and any(k.startswith(r) for r in requested))]


def split_mixed_units(values: dict) -> dict:
    """The evaluation's values with each mixed-unit vector replaced by its SI datasets (`SPLIT`)."""
    out = {}
    for k, v in values.items():
        if k in SPLIT:
            a = np.asarray(v)
            for name, idx in SPLIT[k]:
                out[name] = a[..., idx]
        else:
            out[k] = v
    return out
