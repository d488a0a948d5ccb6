"""Bearing, oil and operating parameters: the paper preset and its validation.

Paper: Yang, Liu, Deng, Lubricants 2025, 13, 249, Tables 1, 3, 7. Values the paper leaves out
are marked "assumed". Every quantity is SI: m, kg, s, Pa, rad, K (temperatures in
the oil model are in °C where the name says so).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace, asdict

from flexbearing.common.materials import M50, Material
from flexbearing.mesh.cage_geometry import PAPER_CAGE, CageGeometry
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
    oil_air_fraction: float = 0.05                 # assumed: oil volume fraction in the cavity

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
        return self


@dataclass(frozen=True)
class Bearing:
    """Three-point-contact ball bearing with a two-piece inner ring (paper Table 1)."""
    outside_diameter: float = 199e-3
    bore_diameter: float = 135e-3
    width: float = 29.5e-3
    pitch_diameter: float = 167e-3
    ball_diameter: float = 22e-3
    n_balls: int = 20
    fe: float = 0.515                      # outer groove radius / ball diameter
    fi: float = 0.52                       # inner half-groove radius / ball diameter
    shim_angle: float = math.radians(30.0)  # assumed: alpha_D, contact angle of each inner half
    radial_clearance: float = 0.0           # assumed: "clearance-free natural state"
    guide_land_diameter: float = 179.2e-3   # assumed: outer-ring land that guides the cage
    cage: CageGeometry = field(default=PAPER_CAGE)
    ball_material: Material = field(default=M50)
    ring_material: Material = field(default=M50)

    # -- derived geometry (paper §2.2.1) --
    @property
    def total_curvature(self) -> float:
        """B = fi + fe - 1."""
        return self.fi + self.fe - 1.0

    @property
    def free_contact_angle(self) -> float:
        """alpha0 = acos(Dr / (B·Dw)), Dr = (fi-0.5)·Dw·cos(alphaD) + (fe-0.5)·Dw, B = fi + fe − 1 (Harris & Kotzalas Vol. 1, ch. 2)."""
        dw = self.ball_diameter
        dr = (self.fi - 0.5) * dw * math.cos(self.shim_angle) + (self.fe - 0.5) * dw - 0.5 * self.radial_clearance
        return math.acos(min(1.0, dr / (self.total_curvature * dw)))

    @property
    def pocket_clearance(self) -> float:
        """Cp = 0.5·(Dp - Dw)."""
        return 0.5 * (self.cage.pocket_diameter - self.ball_diameter)

    @property
    def guide_clearance(self) -> float:
        """Radial clearance between the cage outside cylinder and the guide land, Cg."""
        return 0.5 * (self.guide_land_diameter - self.cage.outside_diameter)

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
        max_z = math.pi / math.asin(min(1.0, self.ball_diameter / self.pitch_diameter))
        require_range("bearing.n_balls", self.n_balls, 3, math.floor(max_z))
        require_range("bearing.fe", self.fe, 0.5, 0.6, lo_open=True)
        require_range("bearing.fi", self.fi, 0.5, 0.6, lo_open=True)
        require_range("bearing.shim_angle", self.shim_angle, 0.0, math.radians(45.0), hi_open=True, unit="rad")
        require_range("bearing.radial_clearance", self.radial_clearance, 0.0, 0.01 * self.ball_diameter, unit="m")
        self.cage.validate()
        if self.cage.n_pockets != self.n_balls:
            raise InputError(f"cage.n_pockets = {self.cage.n_pockets} must equal bearing.n_balls = {self.n_balls}")
        require_range("cage.pocket_diameter", self.cage.pocket_diameter, self.ball_diameter,
                      1.1 * self.ball_diameter, lo_open=True, unit="m")
        require_range("bearing.guide_land_diameter", self.guide_land_diameter, self.cage.outside_diameter,
                      self.cage.outside_diameter + 0.02 * self.cage.outside_diameter, lo_open=True, unit="m")
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
