"""S–N curves of cage materials for the fatigue damage (flexbearing.analysis.fatigue).

Stress–life (Basquin 1910, "The exponential law of endurance tests", Proc. ASTM 10:625):

    sigma_ar = sigma_f' (2 N)^b        <=>        N = 1/2 (sigma_ar / sigma_f')^(1/b)

sigma_ar the fully reversed (R = -1) stress amplitude that gives N cycles to failure of an
unnotched, polished axial specimen; sigma_f' the fatigue strength coefficient, b < 0 the exponent.
No endurance limit: the power law is continued below the knee (Miner's "elementary" form, the
conservative choice for variable-amplitude loading whose large cycles keep propagating cracks that
small cycles then extend; Haibach, "Betriebsfestigkeit", 3rd ed., Springer 2006, §3.2).

Presets (`SN_CURVES`), each with its published source. Only what a source was found for is here:

- "40CrNiMoA" (the paper's cage, Yang, Liu, Deng, Lubricants 2025, Table 7): 40CrNiMoA (GB/T 3077)
  is the Chinese designation of the Ni-Cr-Mo steel AISI/SAE 4340. Its constants are those of AISI
  4340 "aircraft quality", quenched and tempered, sigma_u = 1172 MPa, from N. E. Dowling,
  "Mechanical Behavior of Materials", 4th ed., Pearson 2013, Table 9.1 ("Constants for stress-life
  curves for various ductile engineering metals, from tests on unnotched axial specimens"):
  sigma_f' = 1758 MPa, b = -0.0977. Tabulated values, not digitised; re-checked against the
  same book's strain-life table (Table 14.1, AISI 4340 aircraft quality: sigma_u 1172 MPa,
  sigma_f' 1758 MPa, b -0.0977, the same specimens), which carries the same three numbers. The paper gives no heat
  treatment; GB/T 3077 asks sigma_b >= 980 MPa of quenched-and-tempered 40CrNiMoA, so the table's
  steel is at the strong end of what the cage may be. Mean-stress corrections use the same
  table's sigma_u (a fact of the tested steel, kept with its curve).
- brass, bronze and PEEK (the other usual cage materials): left out. No stress–life constants
  with a citable table or figure were at hand when this module was written; a user adds a curve
  with `SNCurve(...)` and its source.

The curve is for polished specimens: surface finish, size and reliability factors are not applied
(a machined cage pocket lies below it), and the nodal stress it is compared with is the FE stress
at the mesh node (the notch is in the stress field as far as the mesh resolves it).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from flexbearing.common.validation import InputError, require_positive, require_range


@njit(cache=True)
def damage_per_cycle(amplitude: float, coefficient: float, slope: float) -> float:
    """1/N = 2 (sigma_ar / sigma_f')^k, k = -1/b: Basquin's law solved for the damage of one
    cycle (module doc). Compiled: the damage kernels of flexbearing.analysis.fatigue call it."""
    return 2.0 * (amplitude / coefficient) ** slope


@dataclass(frozen=True)
class SNCurve:
    """Basquin stress–life curve (module doc), SI. source: author, title, table or figure."""
    name: str
    fatigue_strength_coefficient: float     # sigma_f', Pa
    fatigue_strength_exponent: float        # b, < 0
    ultimate_strength: float                # sigma_u, Pa (of the tested material; mean-stress corrections)
    source: str

    def validate(self) -> "SNCurve":
        require_positive(f"sn_curve[{self.name}].fatigue_strength_coefficient", self.fatigue_strength_coefficient, "Pa")
        require_range(f"sn_curve[{self.name}].fatigue_strength_exponent", self.fatigue_strength_exponent,
                      -1.0, 0.0, lo_open=True, hi_open=True)
        require_positive(f"sn_curve[{self.name}].ultimate_strength", self.ultimate_strength, "Pa")
        return self

    @property
    def slope(self) -> float:
        """k = -1/b: N proportional to sigma_ar^-k."""
        return -1.0 / self.fatigue_strength_exponent

    def cycles_to_failure(self, amplitude) -> np.ndarray:
        """N = 1/2 (sigma_ar / sigma_f')^(1/b) for fully reversed amplitudes sigma_ar (Pa);
        inf for amplitude 0 (no damage), 0 for an infinite one."""
        a = np.asarray(amplitude, dtype=np.float64)
        with np.errstate(divide="ignore"):
            return 1.0 / (2.0 * (a / self.fatigue_strength_coefficient) ** self.slope)

    def amplitude_at(self, cycles) -> np.ndarray:
        """sigma_ar = sigma_f' (2 N)^b: the fully reversed amplitude that fails in N cycles (Pa)."""
        return self.fatigue_strength_coefficient * (2.0 * np.asarray(cycles, dtype=np.float64)) ** \
            self.fatigue_strength_exponent


SN_CURVES = {
    "40CrNiMoA": SNCurve(
        name="40CrNiMoA",
        fatigue_strength_coefficient=1758e6,
        fatigue_strength_exponent=-0.0977,
        ultimate_strength=1172e6,
        source="AISI 4340 (= 40CrNiMoA), aircraft quality, Q&T, sigma_u 1172 MPa: N. E. Dowling, Mechanical "
               "Behavior of Materials, 4th ed., Pearson 2013, Table 9.1 (unnotched axial specimens, R = -1)"),
}
DEFAULT_SN_CURVE = "40CrNiMoA"


def sn_curve(name: str) -> SNCurve:
    """The preset of that name; InputError naming the allowed ones."""
    try:
        return SN_CURVES[name]
    except KeyError:
        raise InputError(f"fatigue material = {name!r} has no S-N curve (allowed: {', '.join(SN_CURVES)}; "
                         f"brass, bronze and PEEK are left out: no published curve at hand, "
                         f"flexbearing.analysis.sn_curves)") from None
