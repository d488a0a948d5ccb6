"""Materials of the bearing's parts (SI): linear elastic isotropic, with the presets the paper names.

Paper (Yang, Liu, Deng, Lubricants 2025, 13, 249, Tables 1, 3, 7): balls and rings M50, cage
40CrNiMoA (7870 kg/m^3, 209 GPa, 0.295).
"""
from __future__ import annotations

from dataclasses import dataclass

from flexbearing.common.validation import require_positive, require_range


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
# Minimum yield strength sigma_s of 40CrNiMoA quenched (850 °C, oil) and tempered (600 °C), GB/T 3077
# (25 mm test blank; tensile strength >= 980 MPa). Not a model input: the report compares the
# cage's elastic von Mises stress with it (flexbearing.analysis.windows.cage_strength_rows, the report's "Cage stress against the yield strength").
YIELD_STRENGTH_40CrNiMoA = 835e6    # Pa
