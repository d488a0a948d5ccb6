"""Paper preset and edge validation of bearing, oil and cage parameters."""
import math

import pytest

from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.common.validation import InputError
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL, ENGINE_OIL


def test_paper_preset_is_valid():
    PAPER_BEARING.validate()
    PAPER_OIL.validate()
    assert PAPER_BEARING.cage is PAPER_CAGE


def test_free_contact_angle_matches_spec_formula():
    # alpha0 = acos(Dr/(B·Dw)), Dr = (fi-0.5)·Dw·cos(30°) + (fe-0.5)·Dw, B = fi+fe-1 (SPEC §2):
    # Dr/(B·Dw) = (0.02·cos30° + 0.015)/0.035 = 0.923495...
    # for the clearance-free ring (Pd = 0); the preset takes the design clearance, where alpha0 = alphaD = 30°
    expected = math.acos((0.02 * math.cos(math.radians(30)) + 0.015) / 0.035)
    assert PAPER_BEARING.with_(radial_clearance=0.0).free_contact_angle == pytest.approx(expected, rel=1e-12)
    assert math.degrees(expected) == pytest.approx(22.565, abs=1e-3)
    # with Pd: Dr − Pd/2 (SPEC §2, "plus the radial-clearance share"); 88.4232 um gives exactly 30°
    assert math.degrees(PAPER_BEARING.free_contact_angle) == pytest.approx(30.0, abs=1e-9)


def test_oil_viscosity_law():
    # eta(100 °C) = 0.055·exp(-0.031531·80) = 4.414 mPa·s (SPEC §1: "4.4 mPa·s at 100 °C")
    assert ENGINE_OIL.viscosity() == pytest.approx(0.055 * math.exp(-0.031531 * 80), rel=1e-12)
    assert ENGINE_OIL.viscosity() == pytest.approx(4.414e-3, rel=1e-3)
    assert PAPER_OIL.viscosity() == 0.055


@pytest.mark.parametrize("change, field", [
    (dict(fi=0.5), "bearing.fi"),
    (dict(fe=0.49), "bearing.fe"),
    (dict(ball_diameter=-1.0), "bearing.ball_diameter"),
    (dict(cage=PAPER_CAGE.with_(pocket_diameter=21e-3)), "cage.pocket_diameter"),
    (dict(cage=PAPER_CAGE.with_(bore_diameter=0.2)), "cage.bore_diameter"),
    (dict(guide_land_diameter=170e-3), "bearing.guide_land_diameter"),
])
def test_invalid_bearing_is_refused_naming_the_field(change, field):
    with pytest.raises(InputError) as err:
        PAPER_BEARING.with_(**change).validate()
    assert field in str(err.value)
    assert "allowed range" in str(err.value) or "must" in str(err.value)
