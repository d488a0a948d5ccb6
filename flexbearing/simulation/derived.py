"""What a scene does not give: derived by a stated rule from the user's own geometry, or refused.

One rule for every bearing, cage and oil input (issue 41): a value is *given* in the scene,
*derived* by one of the rules below from the bearing's own dimensions (bore, outside diameter,
width, pitch diameter, ball diameter) or from the CAD cage's measured faces, or *refused* in one
line naming the key to give. A bearing or cage that differs from the paper's never inherits a
paper dimension: the rules carry the paper bearing's *proportions* (ratios of its Table 1/3
dimensions and of the assumed values the paper leaves out), and they give the paper's own numbers
back, exactly, for the paper's geometry (tests/test_derived.py), so the paper scenes are unchanged.

Rules (paper: Yang, Liu, Deng, Lubricants 2025, 13, 249, Tables 1 and 3; dm = pitch diameter,
Dw = ball diameter, B = bearing width; the paper bearing dm 167 mm, Dw 22 mm, B 29.5 mm, cage
178.45 × 161.15 × 28.3 mm, outer land 179.2 mm assumed, pocket 22.5 mm assumed):

    bearing.pitch_diameter       dm = (d + D)/2                      (bore d, outside D; 167 mm for the paper's 135/199)
    cage.outside_diameter        dm + 0.5205·Dw                      (the paper cage's (178.45 − 167)/22)
    cage.bore_diameter           dm − 0.2659·Dw                      (the paper cage's (167 − 161.15)/22)
    cage.width                   0.9593·B                            (the paper's 28.3/29.5)
    cage.pocket_diameter         1.0227·Dw                           (the paper's assumed 22.5/22: Cp = 1.14 % of Dw)
    cage.land_width              width/2                             (the whole outside cylinder is the land, no relief)
    cage.pocket_centre_diameter  dm                                  (spherical pockets centred on the pitch circle)
    cage.n_pockets               bearing.n_balls                     (one pocket per ball)
    bearing.guide_land_diameter  cage outside × (1 + 0.4203 %)       (outer land: the paper's assumed diametral
                                                                      clearance 0.75 mm of 178.45 mm)
    bearing.inner_land_diameter  cage bore × (1 − 0.4203 %)          (inner land, inner guidance only: the same
                                                                      relative clearance)

A CAD cage's diameters, width, pockets and land width are measured from its faces
(flexbearing.mesh.cad_cage); the lands above then follow the measured diameters. The land the
cage does not ride on is not checked against the cage (flexbearing.multibody.bearing.Bearing.validate).

Refused (no sound rule): a bearing whose bore or outside diameter is given without the other,
whose ring sizes are given without its width, ball diameter or number of balls, and a non-paper
bearing without its contact angle (free_contact_angle, or the clearance/shim angle).

Dimensionless ratios that fit any bearing keep their paper values and are listed as *defaults*
(groove radii fe, fi; the cage material 40CrNiMoA), printed beside the derived values.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from flexbearing.common.validation import InputError
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.multibody.bearing import LAND_CLEARANCE_RATIO, PAPER_BEARING

_P, _C = PAPER_BEARING, PAPER_CAGE
# the paper bearing's proportions (module doc)
CAGE_OUTSIDE_OFFSET = (_C.outside_diameter - _P.pitch_diameter) / _P.ball_diameter   # × Dw above dm
CAGE_BORE_OFFSET = (_P.pitch_diameter - _C.bore_diameter) / _P.ball_diameter         # × Dw below dm
CAGE_WIDTH_RATIO = _C.width / _P.width
POCKET_RATIO = _C.pocket_diameter / _P.ball_diameter
# the bearing's own ring-size keys: given one, the paper's others no longer fit
RING_SIZE_KEYS = ("outside_diameter", "bore_diameter", "pitch_diameter", "width", "ball_diameter", "n_balls")


@dataclass(frozen=True)
class Derived:
    """One value the scene did not give: its dotted key, value (SI, or a name), unit and rule.
    kind: "derived" (a rule from the user's geometry), "measured" (from the CAD cage) or "default"
    (a dimensionless paper value that fits any bearing)."""
    key: str
    value: float | str
    unit: str
    rule: str
    kind: str = "derived"

    def line(self) -> str:
        """'derived: <key> = <value> from <rule>' in the engineer's units (mm for lengths)."""
        if isinstance(self.value, str):
            v = self.value
        elif self.unit == "m":
            v = f"{self.value * 1e3:.6g} mm"
        elif self.unit == "rad":
            v = f"{math.degrees(self.value):.4g}°"
        else:
            v = f"{self.value:.6g}" + (f" {self.unit}" if self.unit else "")
        return f"{self.kind}: {self.key} = {v} from {self.rule}"


def _same(a: float, b: float) -> bool:
    return a == b


def ring_sizes(given: dict) -> tuple[dict, list[Derived]]:
    """The bearing's ring sizes from the given [bearing] keys (SI numbers): the derived ones added to
    a copy of `given`, with their records. Refuses (one line naming the key) where no rule is sound."""
    out, rec = dict(given), []
    rings = [k for k in ("outside_diameter", "bore_diameter") if k in given]
    if len(rings) == 1:
        other = "bore_diameter" if rings[0] == "outside_diameter" else "outside_diameter"
        raise InputError(f"bearing.{other} is missing: bearing.{rings[0]} = {given[rings[0]]:g} m is given, and "
                         f"the paper's {getattr(_P, other) * 1e3:g} mm would not fit it (give both ring "
                         f"diameters, m)")
    if rings:
        for k, what in (("width", "the bearing's width, m"), ("ball_diameter", "the ball diameter Dw, m"),
                        ("n_balls", "the number of balls")):
            if k not in given:
                raise InputError(f"bearing.{k} is missing: a bearing given by its ring diameters needs {what} "
                                 f"(no rule derives it from the other dimensions)")
        if "pitch_diameter" not in given:
            d, D = given["bore_diameter"], given["outside_diameter"]
            out["pitch_diameter"] = _P.pitch_diameter if (_same(d, _P.bore_diameter) and
                                                          _same(D, _P.outside_diameter)) else 0.5 * (d + D)
            rec.append(Derived("bearing.pitch_diameter", out["pitch_diameter"], "m",
                               "(bore_diameter + outside_diameter)/2"))
    return out, rec


def is_paper_size(b: dict) -> bool:
    """True when the bearing's sizes (given or not) are the paper's."""
    return all(b.get(k, getattr(_P, k)) == getattr(_P, k) for k in RING_SIZE_KEYS)


def needs_contact_angle(given: dict, inner_keys: dict) -> None:
    """A non-paper bearing must say its contact angle (no paper shim angle is inherited)."""
    if not is_paper_size(given) and any(k in given for k in ("outside_diameter", "bore_diameter")) and not inner_keys:
        raise InputError("bearing.free_contact_angle is missing: a bearing other than the paper's needs its "
                         "contact angle (rad; or radial_clearance, or for a split ring shim_angle)")


def cage_dimensions(b: dict, given_cage: dict) -> tuple[dict, list[Derived]]:
    """The parametric cage's dimensions not given in [cage], from the bearing's dm, Dw, B (module doc).
    `b`: the bearing's numbers (given or derived; paper values where absent)."""
    dm = b.get("pitch_diameter", _P.pitch_diameter)
    dw = b.get("ball_diameter", _P.ball_diameter)
    width_b = b.get("width", _P.width)
    paper_dm_dw = dm == _P.pitch_diameter and dw == _P.ball_diameter
    out, rec = {}, []

    def put(key, value, rule, paper_value, paper):
        v = paper_value if paper else value
        out[key] = v
        rec.append(Derived(f"cage.{key}", v, "m", rule))

    if "outside_diameter" not in given_cage:
        put("outside_diameter", dm + CAGE_OUTSIDE_OFFSET * dw,
            f"pitch_diameter + {CAGE_OUTSIDE_OFFSET:.4f}·ball_diameter (the paper cage's proportion)",
            _C.outside_diameter, paper_dm_dw)
    if "bore_diameter" not in given_cage:
        put("bore_diameter", dm - CAGE_BORE_OFFSET * dw,
            f"pitch_diameter − {CAGE_BORE_OFFSET:.4f}·ball_diameter (the paper cage's proportion)",
            _C.bore_diameter, paper_dm_dw)
    if "width" not in given_cage:
        put("width", CAGE_WIDTH_RATIO * width_b, f"{CAGE_WIDTH_RATIO:.4f}·bearing.width (the paper cage's proportion)",
            _C.width, width_b == _P.width)
    if "pocket_diameter" not in given_cage:
        put("pocket_diameter", POCKET_RATIO * dw,
            f"{POCKET_RATIO:.4f}·ball_diameter (the paper's assumed pocket clearance, 1.14 % of D_w)",
            _C.pocket_diameter, dw == _P.ball_diameter)
    if "land_width" not in given_cage:
        w = given_cage.get("width", out.get("width"))
        put("land_width", 0.5 * w, "cage.width/2 (the whole outside cylinder is the land, no relief)",
            _C.land_width, w == _C.width)
    return out, rec


def land_diameters(guidance: str, cage_outside: float, cage_bore: float, given: dict) -> tuple[dict, list[Derived]]:
    """The ring lands not given: the outer land always (the eccentricity scale of a cage that does not
    ride on it), the inner land for guidance "inner"; from the cage's own diameters (module doc)."""
    out, rec = {}, []
    pct = f"{100 * LAND_CLEARANCE_RATIO:.4g} %"
    if "guide_land_diameter" not in given:
        v = (_P.guide_land_diameter if cage_outside == _C.outside_diameter
             else cage_outside * (1.0 + LAND_CLEARANCE_RATIO))
        out["guide_land_diameter"] = v
        rec.append(Derived("bearing.guide_land_diameter", v, "m",
                           f"cage.outside_diameter × (1 + {pct}) (the paper's relative outer-land clearance)"
                           + ("" if guidance == "outer" else "; not ridden on, not checked against the cage")))
    if guidance == "inner" and "inner_land_diameter" not in given:
        v = cage_bore * (1.0 - LAND_CLEARANCE_RATIO)
        out["inner_land_diameter"] = v
        rec.append(Derived("bearing.inner_land_diameter", v, "m",
                           f"cage.bore_diameter × (1 − {pct}) (the paper's relative land clearance)"))
    return out, rec


# ---------------------------------------------------------------- the traction law follows the oil

# Where the paper's 4106 traction fit (flexbearing.multibody.traction.TRACTION_FIT_4106; Wang, Yang &
# Wang, Tribology 24(2):156, 2004) is the default: the 4106 oil (the paper's Table 7 properties) near
# the temperature at which the paper evaluates it. The fit's own data range is not known here (its
# article was not readable, traction.py); the paper applies it with eta0 "at atmospheric pressure
# and ambient temperature" (§2.2.2) and runs every simulation at 20 °C (Table 7's 0.055 Pa·s), and
# the rig's room-temperature oil circuit supplies from 23 °C (the paper's test-rig table: oil supply
# 23–200 °C). The window is that ambient range, 20 ± 5 °C; outside it (the "engine" preset is the
# same oil at 100 °C, where the fit with the ambient eta0 gives mu ~ 0.8, traction.py) and for any
# other oil the EHL film-shear law with the oil's own properties is the default.
FIT_OIL_KEYS = ("density", "viscosity_ref", "temperature_ref_c", "viscosity_temperature_coeff",
                "thermal_conductivity", "pressure_viscosity_coeff")
FIT_TEMPERATURE_WINDOW_C = (15.0, 25.0)


def fit_applies(oil) -> bool:
    """True for the 4106 oil (PAPER_OIL's properties, FIT_OIL_KEYS) inside FIT_TEMPERATURE_WINDOW_C."""
    from flexbearing.multibody.bearing import PAPER_OIL
    lo, hi = FIT_TEMPERATURE_WINDOW_C
    return (all(getattr(oil, k) == getattr(PAPER_OIL, k) for k in FIT_OIL_KEYS)
            and lo <= oil.temperature_c <= hi)


def oil_words(oil) -> str:
    """'the 4106 oil at 100 °C' or 'an oil other than 4106 (η ... ) at T °C'."""
    from flexbearing.multibody.bearing import PAPER_OIL
    is_4106 = all(getattr(oil, k) == getattr(PAPER_OIL, k) for k in FIT_OIL_KEYS)
    return (f"the 4106 oil at {oil.temperature_c:g} °C" if is_4106 else
            f"an oil other than 4106 (η_ref {oil.viscosity_ref:g} Pa·s at {oil.temperature_ref_c:g} °C) at "
            f"{oil.temperature_c:g} °C")


def traction_law(model_options: dict, oil) -> tuple[dict, list[Derived], list[str]]:
    """The model options with the traction law decided: given, or "fit" where the fit applies
    (`fit_applies`) and "ehl" elsewhere; a record of the default, and one warning when the fit is
    chosen outside its oil and temperature."""
    out, rec, warn = dict(model_options), [], []
    lo, hi = FIT_TEMPERATURE_WINDOW_C
    where = f"the 4106 oil at {lo:g}–{hi:g} °C"
    if "traction_law" not in out:
        law = "fit" if fit_applies(oil) else "ehl"
        out["traction_law"] = law
        rec.append(Derived("model.traction_law", law, "",
                           f"the oil: {oil_words(oil)} ("
                           + ("the paper's 4106 traction fit, fitted for " + where if law == "fit" else
                              f"the EHL film-shear law with this oil's properties; the 4106 fit is the "
                              f"default only for {where}") + ")"))
    elif out["traction_law"] == "fit" and not fit_applies(oil):
        warn.append(f"warning: model.traction_law = 'fit' (the paper's 4106 traction fit) is used for "
                    f"{oil_words(oil)}, outside where it was fitted ({where}); the EHL film-shear law "
                    f"(traction_law = 'ehl') uses this oil's own properties")
    return out, rec, warn


# ---------------------------------------------------------------- what is said about it

def guidance_words(bearing) -> str:
    """The guidance and the land actually used, with its diameter and radial clearance, e.g.
    'inner-land guided: inner-ring land Ø 154.5 mm, radial clearance 326 µm'."""
    c = bearing.cage
    if c.guidance == "balls":
        return "ball-riding (no land contact; the outer land Ø " \
               f"{bearing.guide_land_diameter * 1e3:.4g} mm only scales the recorded eccentricity)"
    if c.guidance == "inner":
        land = bearing.inner_land_diameter_or_default
        return (f"inner-land guided: inner-ring land Ø {land * 1e3:.5g} mm under the cage bore Ø "
                f"{c.bore_diameter * 1e3:.5g} mm, radial clearance {bearing.guide_clearance * 1e6:.0f} µm")
    return (f"outer-land guided: outer-ring land Ø {bearing.guide_land_diameter * 1e3:.5g} mm over the cage "
            f"outside Ø {c.outside_diameter * 1e3:.5g} mm, radial clearance {bearing.guide_clearance * 1e6:.0f} µm")


def traction_words(scene) -> str:
    """'EHL film-shear law, the 4106 oil at 100 °C (η = ... Pa·s)' for the summary."""
    law = scene.model_options.get("traction_law", "fit")
    name = {"fit": "the paper's 4106 traction fit (Wang, Yang & Wang 2004)",
            "ehl": "EHL film-shear law with the oil's own properties"}.get(law, law)
    how = "default for this oil" if any(d.key == "model.traction_law" for d in scene.derived) else "given"
    return f"{name} ({how}); {oil_words(scene.oil)}, η = {scene.oil.viscosity():.4g} Pa·s"


def cage_mass_line(bearing) -> str:
    """'derived: cage mass = 0.3 kg from ...' (the rigid body's mass, flexbearing.multibody.model)."""
    from flexbearing.multibody.model import cage_mass_properties
    m = cage_mass_properties(bearing.cage)[0]
    return (f"derived: cage mass = {m:.4g} kg from the cage's geometry (ring less pockets) × "
            f"cage.material density {bearing.cage.material.density:g} kg/m³")


def run_start_lines(scene) -> list[str]:
    """What is printed before a run: every derived, measured and default value, the guidance, the
    traction law, and the warnings."""
    lines = [d.line() for d in scene.derived]
    lines.append(cage_mass_line(scene.bearing))
    lines.append(f"cage guidance: {guidance_words(scene.bearing)}")
    lines.append(f"traction: {traction_words(scene)}")
    return lines + list(scene.warnings)
