"""Calibration bookkeeping (flexbearing.fem_cage.calibrate) and the calibrated paper preset."""
import json
from pathlib import Path

import numpy as np
import pytest

from flexbearing.fem_cage.calibrate import (BOUNDS, BOXES, Evaluator, geometry_of, linearised_fit, residuals,
                                table8_vector)
from flexbearing.fem_cage.modes import PAPER_TABLE8_HZ
from flexbearing.mesh.cage_geometry import CALIBRATED_CAGE, NOMINAL_CAGE

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


@pytest.mark.parametrize("box", sorted(BOXES))
def test_every_corner_of_every_box_is_a_valid_cage(box):
    import itertools
    names = list(BOXES[box])
    for corner in itertools.product(*(BOXES[box][n] for n in names)):
        geometry_of(names, corner)           # raises InputError if not a valid cage


def test_plausible_box_keeps_a_guide_land_and_a_reasonable_pocket():
    b = BOXES["plausible"]
    assert b["guide_flat"][0] >= 2e-3 and b["chamfer"][1] <= 1e-3
    assert 0.5 * (b["pocket_diameter"][0] - 22e-3) == pytest.approx(0.05e-3)       # clearance 0.05 mm
    assert 0.5 * (b["pocket_diameter"][1] - 22e-3) == pytest.approx(0.5e-3)        # ... 0.5 mm
    # the bore chamfer stays inside the side rail (W - Dp)/2 of the smallest pocket's neighbour
    assert b["bore_chamfer"][1] < 0.5 * (28.3e-3 - b["pocket_diameter"][1])


def test_guide_flat_is_land_minus_chamfer():
    g = geometry_of(["chamfer", "guide_flat", "relief_depth"], [1e-3, 2e-3, 1e-3])
    assert g.land_width == pytest.approx(3e-3, abs=1e-15)


def test_linearised_fit_recovers_a_uniform_scale_and_respects_bounds():
    # Every frequency 5 % high and d f / d z = -0.1 f_table: the exact optimum is z = 0.5, r = 0;
    # with z <= 0.3 the residual is 0.05 - 0.03 = 0.02 for every mode (closed form).
    t = np.sort(table8_vector())
    f0, J = 1.05 * t, (-0.1 * t)[:, None]
    z, r = linearised_fit(f0, J, np.zeros(1), np.zeros(1), np.ones(1), n_starts=3)
    assert z[0] == pytest.approx(0.5, abs=1e-6) and np.abs(r).max() < 1e-6
    z, r = linearised_fit(f0, J, np.zeros(1), np.zeros(1), np.full(1, 0.3), n_starts=3)
    assert z[0] == pytest.approx(0.3, abs=1e-9) and r == pytest.approx(np.full(21, 0.02), abs=1e-9)


def test_linearised_fit_guide_flat_constraint_is_active():
    # Narrower land (lower z_land) and larger chamfer both lower every frequency, which are 10 %
    # high: the fit wants land -> chamfer; with land - chamfer >= 1 mm the constraint is active.
    t = np.sort(table8_vector())
    names, lo, hi = ["chamfer", "land_width"], np.array([0.0, 0.5e-3]), np.array([3e-3, 14e-3])
    f0 = 1.10 * t
    J = np.stack([-0.02 * t, 0.02 * t], axis=1)
    z0 = np.array([0.0, 1.0])
    z, r = linearised_fit(f0, J, z0, np.zeros(2), np.ones(2), 1e-3, names, lo, hi, n_starts=10)
    p = lo + z * (hi - lo)
    assert p[1] - p[0] == pytest.approx(1e-3, abs=1e-7)
    assert np.all(r > 0)                 # the constraint stops it short of the table


def test_log_records_of_another_base_geometry_are_not_reused(tmp_path):
    log = tmp_path / "e.jsonl"
    f = list(np.concatenate([np.zeros(6), table8_vector()]))
    rec = {"params": {"pocket_diameter": 22.5e-3, "bore_diameter": 164e-3}, "mesh": [0.008, 0.008, 2, 3],
           "frequencies_hz": f, "base": "0000000000000000"}
    log.write_text(json.dumps(rec) + "\n")
    ev = Evaluator(["pocket_diameter", "bore_diameter"], log_path=log, bounds=BOXES["envelope"])
    assert ev.memo == {}
    rec.pop("base")                      # no "base": an evaluation on the nominal cage
    log.write_text(json.dumps(rec) + "\n")
    ev = Evaluator(["pocket_diameter", "bore_diameter"], log_path=log, bounds=BOXES["envelope"])
    assert list(ev.memo) == [(0.0225, 0.164)]


def test_equivalent_ring_thickness_inverts_the_timoshenko_ring():
    # Round trip on the analytic ring (not on FE output): the frequency of the 8.65 mm solid ring
    # of the cage's envelope gives back 8.65 mm for n = 2..5 (bisection to 1e-12 m).
    from flexbearing.fem_cage.calibrate import equivalent_ring_thickness
    from flexbearing.fem_cage.ring_theory import thick_ring_inplane_hz
    g = NOMINAL_CAGE
    for n in (2, 3, 4, 5):
        f = thick_ring_inplane_hz(n, g.outer_radius, g.inner_radius, g.width, g.material)
        h = equivalent_ring_thickness(f, n, g.mean_radius, g.width, g.material)
        assert h == pytest.approx(g.outer_radius - g.inner_radius, rel=1e-9)
    # thin-ring scaling: half the frequency -> about half the thickness (within the
    # shear/rotary-inertia correction, < 1 % for n = 2 at h/R ~ 0.05)
    f2 = thick_ring_inplane_hz(2, g.outer_radius, g.inner_radius, g.width, g.material)
    h = equivalent_ring_thickness(0.5 * f2, 2, g.mean_radius, g.width, g.material)
    assert h == pytest.approx(0.5 * (g.outer_radius - g.inner_radius), rel=0.01)


@pytest.mark.slow
def test_table8_equivalent_preset_meets_the_table8_target():
    """The 7.0 mm-wall stand-in (flexbearing.mesh.cage_geometry.TABLE8_EQUIVALENT_CAGE, outside Table 3's
    bore) at the default mesh: RMS over modes 7-27 <= 3 % and every mode <= 6 % (issue 2's
    target; measured 2.31 % / 4.55 %), and the calibrated preset inside the envelope stays at its
    reported 4.42 % / 7.86 % (within 0.05 points: mesh cache and solver tolerance)."""
    from flexbearing.fem_cage.calibrate import verify
    from flexbearing.mesh.cage_geometry import TABLE8_EQUIVALENT_CAGE, CALIBRATED_CAGE
    r = verify(TABLE8_EQUIVALENT_CAGE, classify=False)
    assert r["rms"] <= 0.03 and r["max"] <= 0.06
    c = verify(CALIBRATED_CAGE, classify=False)
    assert c["rms"] == pytest.approx(0.0442, abs=5e-4)
    assert c["max"] == pytest.approx(0.0786, abs=5e-4)
