"""The oil supply of the bearing and the oil content of its cavity, which the churning drag reads.

Supplies (`Oil.supply`): "unspecified" (the paper's scenes: a fixed cavity oil fraction X, Oil.oil_air_fraction),
"jet" (oil jets at the side faces) and "under_race" (oil fed through the inner ring, flung through the
contacts), both a continuous supply at a constant flow rate. For a continuous supply the oil volume
fraction of the cavity's oil–air mixture falls as the speed rises (the oil is thrown out faster):
Parker's correlation for jet-lubricated ball bearings, X ∝ w^0.37/(n·dm^1.7) (R. J. Parker, "Comparison of
Predicted and Experimental Thermal Performance of Angular-Contact Ball Bearings", NASA TP-2275, 1984;
w the oil flow, n the shaft speed, dm the pitch diameter), of which only the 1/n law is used:

    X(n) = min(1, X_ref·n_ref/|n|),   X_ref = Oil.oil_air_fraction at n_ref = Oil.oil_air_reference_rpm,

since the flow w and the constant of the correlation are not known for the test bearings (X_ref is a
declared unknown: scenes/validation/*.toml, scenes/slip_rate_unknowns.toml). The lumped cavity of the
drag model (flexbearing.multibody.drag: one mixture for every ball) does not resolve where the oil
enters, so "jet" and "under_race" give the same law here; the key records the published supply and
decides the speed law. What it changes: the churning drag on every ball, F_d = ½·C_d·rho_mix·(pi/4)·Dw²·V²
with rho_mix, eta_mix of X (flexbearing.multibody.drag.oil_air_mixture), evaluated at the inner ring's
speed at each instant (a run through a speed ramp sees X change); the guide-land film and the EHL
contacts take the oil itself and do not change.
"""
from __future__ import annotations

from numba import njit

SUPPLIES = ("unspecified", "jet", "under_race")


@njit(cache=True)
def cavity_oil_fraction(fraction_ref, speed_ref, speed):
    """X = min(1, X_ref·n_ref/|n|) for a continuous supply (speed_ref > 0), X_ref for speed_ref = 0
    (a fixed fraction); speeds in any one unit (module docstring). At rest (n = 0) X = 1 is the cap."""
    if speed_ref <= 0.0:
        return fraction_ref
    n = abs(speed)
    if n * 1.0 <= fraction_ref * speed_ref:
        return 1.0
    return fraction_ref * speed_ref / n
