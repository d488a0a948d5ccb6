"""Calibration bookkeeping (fem_cage.calibrate) and the calibrated paper preset."""
import json
from pathlib import Path

import numpy as np
import pytest

from fem_cage.calibrate import BOUNDS, Evaluator, residuals, table8_vector
from fem_cage.modes import PAPER_TABLE8_HZ
from mesh.cage_geometry import CALIBRATED_CAGE, NOMINAL_CAGE

RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results"


def test_table8_transcription():
    # Paper Table 8: 21 values, modes 7..27, first elastic pair 484.77 Hz, last 7113.5 Hz.
    t = table8_vector()
    assert len(t) == 21 and t[0] == 484.77 and t[-1] == 7113.5
    assert np.all(np.diff(t) > -0.2)              # ascending (6692.1 then 6692.0 is a pair)
    assert PAPER_TABLE8_HZ[17] == 4226.1


def test_residuals_are_relative_errors_of_modes_7_to_27():
    f = np.concatenate([np.zeros(6), np.sort(table8_vector()) * 1.02])
    assert residuals(f) == pytest.approx(np.full(21, 0.02), rel=1e-12)
    # order of the input does not matter (both sides sorted)
    assert residuals(f[::-1]) == pytest.approx(np.full(21, 0.02), rel=1e-12)


def test_bounds_are_physically_reasonable_for_the_22mm_ball():
    lo, hi = BOUNDS["pocket_diameter"]
    # pocket clearance (Dp - Dw)/2 stays within 0.05..0.5 mm and inside (Dw, 1.1 Dw]
    assert 0.5 * (lo - 22e-3) == pytest.approx(0.05e-3) and 0.5 * (hi - 22e-3) == pytest.approx(0.5e-3)
    assert hi <= 1.1 * 22e-3
    # every corner of the box is a valid (meshable) cage
    for dp in BOUNDS["pocket_diameter"]:
        for ch in BOUNDS["chamfer"]:
            for lw in BOUNDS["land_width"]:
                for rd in BOUNDS["relief_depth"]:
                    NOMINAL_CAGE.with_(pocket_diameter=dp, chamfer=ch, land_width=lw,
                                       relief_depth=rd).validate()


def test_normalised_coordinates_round_trip():
    ev = Evaluator(list(BOUNDS))
    p = np.array([22.4e-3, 0.5e-3, 6e-3, 1e-3])
    assert ev.to_p(ev.to_z(p)) == pytest.approx(p, rel=1e-12)


def test_calibrated_preset_is_the_recorded_calibration():
    path = RESULTS / "modes_calibration.json"
    if not path.exists():
        pytest.skip("no calibration recorded yet")
    rec = json.loads(path.read_text())
    for name, value in rec["params"].items():
        assert getattr(CALIBRATED_CAGE, name) == pytest.approx(value, abs=0.5e-6), name   # 1 µm rounding
        lo, hi = BOUNDS[name]
        assert lo - 1e-12 <= value <= hi + 1e-12
    # nominal geometry (SPEC §1) is kept apart from the calibrated one
    assert NOMINAL_CAGE.pocket_diameter == 22.5e-3 and NOMINAL_CAGE.relief_depth == 0.0
