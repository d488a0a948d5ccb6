"""Materials of the bearing's parts (SI): linear elastic isotropic, with the presets the paper names.

Paper (Yang, Liu, Deng, Lubricants 2025, 13, 249, Tables 1, 3, 7): balls and rings M50, cage
40CrNiMoA (7870 kg/m^3, 209 GPa, 0.295).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from flexbearing.common.validation import InputError, require_positive, require_range


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material (SI)."""
    density: float          # kg/m^3
    youngs_modulus: float   # Pa
    poisson_ratio: float    # -

    def validate(self, name: str = "material") -> "Material":
        require_positive(f"{name}.density", self.density, "kg/m^3")
        require_positive(f"{name}.youngs_modulus", self.youngs_modulus, "Pa")
        require_range(f"{name}.poisson_ratio", self.poisson_ratio, -1.0, 0.5, lo_open=True, hi_open=True)
        return self


M50 = Material(density=7810.0, youngs_modulus=210e9, poisson_ratio=0.3)
STEEL_40CrNiMoA = Material(density=7870.0, youngs_modulus=209e9, poisson_ratio=0.295)
# Hot-pressed silicon nitride balls of hybrid bearings (Harris & Kotzalas, Rolling Bearing Analysis,
# 5th ed., Vol. 1, ch. 5; 3150-3250 kg/m^3, 300-320 GPa, 0.26-0.27 in manufacturers' data): the
# alternative ball material of the slip-rate uncertainty study (scenes/slip_rate_unknowns.toml).
SI3N4 = Material(density=3200.0, youngs_modulus=310e9, poisson_ratio=0.26)


class Thermal(NamedTuple):
    """Thermal constants of a contact body where the EHL traction law's flash temperature uses them
    (flexbearing.multibody.traction.ehl_traction_table): conductivity k, W/(m·K), and diffusivity
    kappa = k/(rho·c), m²/s."""
    conductivity: float
    diffusivity: float

    @property
    def effusivity(self) -> float:
        """e = k/sqrt(kappa) = sqrt(k·rho·c), W·s^0.5/(m²·K): the surface temperature of a body under a
        moving heat source at Peclet >> 1 is proportional to 1/e (Jaeger 1942)."""
        return self.conductivity / self.diffusivity ** 0.5


# Through-hardened bearing steel (M50, 52100): k ~ 40 W/(m·K), rho·c ~ 7800·460 J/(m³·K); the values the
# EHL traction law has always used for both bodies.
BEARING_STEEL_THERMAL = Thermal(conductivity=40.0, diffusivity=1.1e-5)
# Hot-pressed / gas-pressure-sintered Si3N4 of bearing balls: k 20–35 W/(m·K), c 650–800 J/(kg·K) in
# manufacturers' data sheets (no single table read here; the middle taken): k = 30, c = 700, rho = 3200,
# kappa = 30/(3200·700) = 1.34e-5 m²/s. Effusivity 8.2e3 against steel's 1.21e4: a ceramic ball takes
# less of the frictional heat, the flash temperature of a hybrid contact is ~19 % higher.
SI3N4_THERMAL = Thermal(conductivity=30.0, diffusivity=30.0 / (3200.0 * 700.0))


class BallMaterial(NamedTuple):
    """A ball material by name: its elastic constants and its thermal ones."""
    name: str
    material: Material
    thermal: Thermal


# The ball materials a scene (`[bearing] ball_material = "..."`) and a study's unknowns can name.
BALL_MATERIALS = {"steel": BallMaterial("steel", M50, BEARING_STEEL_THERMAL),
                  "silicon_nitride": BallMaterial("silicon_nitride", SI3N4, SI3N4_THERMAL)}


def ball_material_named(name: str, field: str = "bearing.ball_material") -> BallMaterial:
    """The BallMaterial of a name in BALL_MATERIALS; one InputError line otherwise."""
    if name not in BALL_MATERIALS:
        raise InputError(f"{field} = {name!r} is not known; allowed: {', '.join(map(repr, BALL_MATERIALS))}")
    return BALL_MATERIALS[name]


# Minimum yield strength sigma_s of 40CrNiMoA quenched (850 °C, oil) and tempered (600 °C), GB/T 3077
# (25 mm test blank; tensile strength >= 980 MPa). Not a model input: the report compares the
# cage's elastic von Mises stress with it (flexbearing.analysis.windows.cage_strength_rows, the report's "Cage stress against the yield strength").
YIELD_STRENGTH_40CrNiMoA = 835e6    # Pa
