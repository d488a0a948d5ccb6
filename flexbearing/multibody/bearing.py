"""Bearing, oil and operating parameters: the paper preset and its validation.

Paper: Yang, Liu, Deng, Lubricants 2025, 13, 249, Tables 1, 3, 7. Values the paper leaves out
are marked "assumed". Every quantity is SI: m, kg, s, Pa, rad, K (temperatures in
the oil model are in °C where the name says so).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace, asdict

from flexbearing.common.materials import BEARING_STEEL_THERMAL, M50, Material, Thermal
from flexbearing.multibody import clearance as CL
from flexbearing.multibody.oil_supply import SUPPLIES, cavity_oil_fraction
from flexbearing.mesh.cage_geometry import PAPER_CAGE, CageGeometry, max_pockets_around
from flexbearing.common.validation import InputError, require_positive, require_range


@dataclass(frozen=True)
class Oil:
    """Lubricant: 4106 aviation oil (MIL-L-23699 class), paper Table 7.

    Viscosity–temperature law (exponential, Reynolds 1886; beta from paper Table 7): eta(T) = eta_ref * exp(-beta * (T - T_ref)).
    """
    density: float = 892.2                        # kg/m^3 at 20 °C
    viscosity_ref: float = 0.055                  # Pa·s at temperature_ref_c
    temperature_ref_c: float = 20.0               # °C
    viscosity_temperature_coeff: float = 0.031531  # 1/°C
    thermal_conductivity: float = 0.0965788        # W/(m·K)
    pressure_viscosity_coeff: float = 1.85e-8      # 1/Pa
    temperature_c: float = 20.0                    # operating oil temperature, °C (paper preset)
    oil_air_fraction: float = 0.05                 # assumed: oil volume fraction in the cavity (at the
                                                   # reference speed for a continuous supply)
    supply: str = "unspecified"                    # "unspecified" | "jet" | "under_race" (flexbearing.multibody.oil_supply)
    oil_air_reference_rpm: float = 4000.0          # rpm at which oil_air_fraction holds for jet / under_race

    def cavity_oil_fraction(self, speed_rpm: float) -> float:
        """Oil volume fraction of the cavity at inner-ring speed n, rpm: fixed, or X_ref·n_ref/n for a
        jet or under-race supply (flexbearing.multibody.oil_supply)."""
        return float(cavity_oil_fraction(self.oil_air_fraction, self.supply_reference_rpm, speed_rpm))

    @property
    def supply_reference_rpm(self) -> float:
        """n_ref of the 1/n law for a continuous supply, 0 for a fixed fraction (oil_supply.cavity_oil_fraction)."""
        return 0.0 if self.supply == "unspecified" else self.oil_air_reference_rpm

    def viscosity(self, temperature_c: float | None = None) -> float:
        """Dynamic viscosity at atmospheric pressure, Pa·s."""
        t = self.temperature_c if temperature_c is None else temperature_c
        return self.viscosity_ref * math.exp(-self.viscosity_temperature_coeff * (t - self.temperature_ref_c))

    @property
    def temperature_k(self) -> float:
        return self.temperature_c + 273.15

    def validate(self) -> "Oil":
        require_positive("oil.density", self.density, "kg/m^3")
        require_positive("oil.viscosity_ref", self.viscosity_ref, "Pa·s")
        require_range("oil.viscosity_temperature_coeff", self.viscosity_temperature_coeff, 0.0, 1.0)
        require_positive("oil.thermal_conductivity", self.thermal_conductivity, "W/(m·K)")
        require_range("oil.pressure_viscosity_coeff", self.pressure_viscosity_coeff, 0.0, 1e-7, unit="1/Pa")
        require_range("oil.temperature_c", self.temperature_c, -60.0, 250.0, unit="°C")
        require_range("oil.oil_air_fraction", self.oil_air_fraction, 0.0, 1.0)
        if self.supply not in SUPPLIES:
            raise InputError(f"oil.supply = {self.supply!r} must be one of {', '.join(map(repr, SUPPLIES))}")
        require_range("oil.oil_air_reference_rpm", self.oil_air_reference_rpm, 0.0, 1e5, lo_open=True, unit="rpm")
        return self


# The paper bearing's numbers that its clearance is derived from (Table 1; shim angle assumed, SPEC §1).
_PAPER_DW, _PAPER_FE, _PAPER_SHIM = 22e-3, 0.515, math.radians(30.0)
_PAPER_GUIDE_LAND = 179.2e-3             # assumed: the outer-ring land that guides the paper's cage
# Diametral land clearance relative to the cage surface it guides: the paper bearing's assumed outer
# land, (179.2 − 178.45)/178.45 = 0.4203 %. The rule for every land a scene does not give
# (flexbearing.simulation.derived): outer land = cage outside × (1 + this), inner = cage bore × (1 − this).
LAND_CLEARANCE_RATIO = (_PAPER_GUIDE_LAND - PAPER_CAGE.outside_diameter) / PAPER_CAGE.outside_diameter


@dataclass(frozen=True)
class Bearing:
    """Angular-contact ball bearing: the paper's three-point-contact type with a two-piece (split)
    inner ring (paper Table 1), or an ordinary one-piece inner ring (inner_ring = "one_piece").

    Clearance (SPEC §1 note; flexbearing.multibody.clearance): the shim angle alphaD is defined in the
    clearance-free state; the operating diametral clearance Pd (the field `radial_clearance`, the
    diametral value, as flexbearing.multibody.geometry uses it) is a separate input. The paper does not
    give it; the preset takes the split ring's design clearance 2·(fe − 0.5)·Dw·(1 − cos alphaD) =
    88.4 um, the smallest with which the ball runs in two-point contact under thrust (the free contact
    angle then equals the shim angle, 30°), as a split-ring bearing is designed to run. At Pd = 0 the
    ball is held by all three races at any load below ~the centrifugal split (flexbearing.studies.validation.slip_rate
    docstring). Declared unknown of the test bearing: Pd in 0–200 um (scenes/validation/yang2025_table5.toml).
    The paper scenes and the slip-rate validation use this one definition (issue 35).

    One-piece ring: one inner groove whose curvature centre is that of the split ring's loaded half at
    alphaD = alpha0 with the design clearance (the same radial distance B·Dw − Pd/2 from the outer
    centre), and the second half removed; `shim_angle` is not used (`groove_layout`)."""
    outside_diameter: float = 199e-3
    bore_diameter: float = 135e-3
    width: float = 29.5e-3
    pitch_diameter: float = 167e-3
    ball_diameter: float = _PAPER_DW
    n_balls: int = 20
    fe: float = _PAPER_FE                  # outer groove radius / ball diameter
    fi: float = 0.52                       # inner half-groove radius / ball diameter
    shim_angle: float = _PAPER_SHIM        # assumed: alpha_D, contact angle of each inner half (split ring)
    # diametral clearance Pd, m (class docstring): the design clearance of the 30° shim, 88.4 um
    radial_clearance: float = CL.design_clearance(_PAPER_FE, _PAPER_DW, _PAPER_SHIM)
    guide_land_diameter: float = _PAPER_GUIDE_LAND   # assumed: outer-ring land that guides the cage
    # inner-ring land under the cage bore (cage.guidance = "inner"); None: the cage bore less the
    # paper's relative land clearance, bore·(1 − LAND_CLEARANCE_RATIO)
    inner_land_diameter: float | None = None
    cage: CageGeometry = field(default=PAPER_CAGE)
    ball_material: Material = field(default=M50)
    ring_material: Material = field(default=M50)
    inner_ring: str = "split"               # "split" (two halves, three-point type) | "one_piece"
    ball_thermal: Thermal = BEARING_STEEL_THERMAL   # where the EHL traction law's flash temperature uses it
    ring_thermal: Thermal = BEARING_STEEL_THERMAL

    # -- derived geometry (paper §2.2.1) --
    @property
    def total_curvature(self) -> float:
        """B = fi + fe - 1."""
        return self.fi + self.fe - 1.0

    @property
    def free_contact_angle(self) -> float:
        """alpha0, rad (flexbearing.multibody.clearance): split ring acos(Dr/(B·Dw)),
        Dr = (fi-0.5)·Dw·cos(alphaD) + (fe-0.5)·Dw − Pd/2; one-piece acos(1 − Pd/(2·B·Dw))."""
        if self.inner_ring == "one_piece":
            return CL.one_piece_free_contact_angle(self.fe, self.fi, self.ball_diameter, self.radial_clearance)
        return CL.split_free_contact_angle(self.fe, self.fi, self.ball_diameter, self.shim_angle,
                                           self.radial_clearance)

    @property
    def groove_layout(self) -> tuple[float, float]:
        """(angle, clearance) that place the inner groove centres
        (flexbearing.multibody.geometry.inner_groove_centres(dm, Dw, fi, angle, clearance)): a split ring's
        shim angle and diametral clearance; a one-piece ring's free contact angle alpha0 with the design
        clearance of that angle, which puts its groove centre B·Dw − Pd/2 radially from the outer one
        (class docstring; tests/test_clearance.py)."""
        if self.inner_ring == "one_piece":
            a0 = self.free_contact_angle
            return a0, CL.design_clearance(self.fe, self.ball_diameter, a0)
        return self.shim_angle, self.radial_clearance

    @property
    def n_inner_halves(self) -> int:
        """Inner race contacts per ball: 2 (split ring), 1 (one-piece ring)."""
        return 1 if self.inner_ring == "one_piece" else 2

    @property
    def pocket_clearance(self) -> float:
        """Cp = 0.5·(Dp - Dw)."""
        return 0.5 * (self.cage.pocket_diameter - self.ball_diameter)

    @property
    def guide_clearance(self) -> float:
        """Radial clearance Cg of the land that guides the cage: the outer ring's land bore less
        the cage's outside diameter ("outer", and "balls", where no land touches the cage and Cg
        only scales the recorded eccentricity), or the cage bore less the inner ring's land
        diameter ("inner")."""
        if self.cage.guidance == "inner":
            return 0.5 * (self.cage.bore_diameter - self.inner_land_diameter_or_default)
        return 0.5 * (self.guide_land_diameter - self.cage.outside_diameter)

    @property
    def inner_land_diameter_or_default(self) -> float:
        """inner_land_diameter, or the cage bore less the paper's relative land clearance,
        bore·(1 − LAND_CLEARANCE_RATIO) (the rule of flexbearing.simulation.derived)."""
        if self.cage.pocket_shape == "spherical":
            # the dynamics put each pocket's centre at the ball centres' radius (the pitch circle)
            tol = 1e-6 * self.pitch_diameter
            require_range("cage.pocket_centre_diameter", self.cage.pocket_centre_diameter,
                          self.pitch_diameter - tol, self.pitch_diameter + tol, unit="m")
        if self.inner_land_diameter is not None:
            return self.inner_land_diameter
        return self.cage.bore_diameter * (1.0 - LAND_CLEARANCE_RATIO)

    @property
    def ball_mass(self) -> float:
        return self.ball_material.density * math.pi * self.ball_diameter ** 3 / 6.0

    def validate(self) -> "Bearing":
        require_positive("bearing.outside_diameter", self.outside_diameter, "m")
        require_range("bearing.bore_diameter", self.bore_diameter, 0.0, self.outside_diameter,
                      lo_open=True, hi_open=True, unit="m")
        require_range("bearing.pitch_diameter", self.pitch_diameter, self.bore_diameter,
                      self.outside_diameter, lo_open=True, hi_open=True, unit="m")
        require_positive("bearing.width", self.width, "m")
        require_range("bearing.ball_diameter", self.ball_diameter, 0.0,
                      0.5 * (self.outside_diameter - self.bore_diameter), lo_open=True, hi_open=True, unit="m")
        if int(self.n_balls) != self.n_balls or self.n_balls < 3:
            raise InputError(f"bearing.n_balls = {self.n_balls!r} must be an integer >= 3")
        # Z balls touch on the pitch circle when sin(pi/Z) = Dw/dm (neighbouring centres Dw apart)
        max_z = math.floor(math.pi / math.asin(min(1.0, self.ball_diameter / self.pitch_diameter)))
        if self.n_balls > max_z:
            gap = self.pitch_diameter * math.sin(math.pi / self.n_balls)
            raise InputError(f"bearing.n_balls = {self.n_balls}: the balls do not fit on the pitch circle "
                             f"({self.n_balls} balls of Ø{self.ball_diameter * 1e3:g} mm on Ø"
                             f"{self.pitch_diameter * 1e3:g} mm: neighbouring centres {gap * 1e3:.3g} mm apart, "
                             f"less than the ball diameter); allowed range [3, {max_z}]")
        require_range("bearing.fe", self.fe, 0.5, 0.6, lo_open=True)
        require_range("bearing.fi", self.fi, 0.5, 0.6, lo_open=True)
        if self.inner_ring not in CL.INNER_RINGS:
            raise InputError(f"bearing.inner_ring = {self.inner_ring!r} must be one of "
                             f"{', '.join(map(repr, CL.INNER_RINGS))}")
        require_range("bearing.shim_angle", self.shim_angle, 0.0, math.radians(45.0), hi_open=True, unit="rad")
        if self.inner_ring == "one_piece":   # free contact angle below 45°: Pd <= 2·B·Dw·(1 − cos 45°)
            require_range("bearing.radial_clearance", self.radial_clearance, 0.0,
                          CL.one_piece_clearance(self.fe, self.fi, self.ball_diameter, math.radians(45.0)),
                          lo_open=True, unit="m")
        else:
            require_range("bearing.radial_clearance", self.radial_clearance, 0.0, 0.01 * self.ball_diameter,
                          unit="m")
        for name in ("ball_thermal", "ring_thermal"):
            th = getattr(self, name)
            require_positive(f"bearing.{name}.conductivity", th.conductivity, "W/(m·K)")
            require_positive(f"bearing.{name}.diffusivity", th.diffusivity, "m²/s")
        c = self.cage
        if c.n_pockets == self.n_balls and 0.0 < c.bore_diameter and c.pocket_diameter > 0.0:
            # the pockets' radial axes converge: at the cage bore neighbouring ones are
            # bore·sin(pi/Z) apart, and Z pockets wider than that cannot be cut (Z·Dp against pi·bore)
            chord = c.bore_diameter * math.sin(math.pi / self.n_balls)
            if chord <= c.pocket_diameter:
                z_max = max_pockets_around(c.bore_diameter, c.pocket_diameter)
                raise InputError(f"bearing.n_balls = {self.n_balls}: the balls do not fit in the cage "
                                 f"({self.n_balls} pockets of Ø{c.pocket_diameter * 1e3:.4g} mm around the cage "
                                 f"bore Ø{c.bore_diameter * 1e3:.4g} mm: neighbouring pocket axes "
                                 f"{chord * 1e3:.4g} mm apart there); allowed range [3, {z_max}]")
        self.cage.validate()
        if self.cage.n_pockets != self.n_balls:
            raise InputError(f"cage.n_pockets = {self.cage.n_pockets} must equal bearing.n_balls = {self.n_balls}")
        require_range("cage.pocket_diameter", self.cage.pocket_diameter, self.ball_diameter,
                      1.1 * self.ball_diameter, lo_open=True, unit="m")
        # only the land the cage rides on is checked against it (a clearance of up to 1 % of the
        # diameter); the outer land of a ball-riding cage scales its recorded eccentricity only
        if self.cage.guidance == "outer":
            require_range("bearing.guide_land_diameter", self.guide_land_diameter, self.cage.outside_diameter,
                          self.cage.outside_diameter + 0.02 * self.cage.outside_diameter, lo_open=True, unit="m")
        elif self.cage.guidance == "balls":
            require_range("bearing.guide_land_diameter", self.guide_land_diameter, self.cage.outside_diameter,
                          self.outside_diameter, lo_open=True, hi_open=True, unit="m")
        else:
            require_range("bearing.guide_land_diameter", self.guide_land_diameter, self.pitch_diameter,
                          self.outside_diameter, lo_open=True, hi_open=True, unit="m")
        if self.cage.pocket_shape == "spherical":
            # the dynamics put each pocket's centre at the ball centres' radius (the pitch circle)
            tol = 1e-6 * self.pitch_diameter
            require_range("cage.pocket_centre_diameter", self.cage.pocket_centre_diameter,
                          self.pitch_diameter - tol, self.pitch_diameter + tol, unit="m")
        if self.inner_land_diameter is not None and self.cage.guidance == "inner":
            # the same band as the outer land's: a clearance of up to 1 % of the diameter
            require_range("bearing.inner_land_diameter", self.inner_land_diameter,
                          0.98 * self.cage.bore_diameter, self.cage.bore_diameter, hi_open=True, unit="m")
        self.ball_material.validate("bearing.ball_material")
        self.ring_material.validate("bearing.ring_material")
        return self

    def to_dict(self) -> dict:
        return asdict(self)

    def with_(self, **changes) -> "Bearing":
        return replace(self, **changes)


PAPER_BEARING = Bearing()
PAPER_OIL = Oil()                                  # 20 °C: the paper's evaluation temperature
ENGINE_OIL = Oil(temperature_c=100.0)              # engine-like second preset
