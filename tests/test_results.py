"""Results file pieces: checkpoint slots, statistics with NaN and named columns, units."""
import h5py
import numpy as np
import pytest

from flexbearing.simulation.results import (ResultsWriter, output_statistics, read_checkpoint, summary_path, unit_for)
from flexbearing.simulation.scene import loads_scene
from test_run import SCENE


def test_checkpoint_slots_alternate_and_newest_valid_wins(tmp_path):
    w = ResultsWriter.create(tmp_path / "r.h5", loads_scene(SCENE))
    for i in range(3):
        w.add_sample(0.1 * i, {"contact_stress": np.full((2, 3), float(i))})
        w.checkpoint(np.array([float(i)]), 0.1 * i, 1e-6 * (i + 1), 10 * i, i, 0.5 * i)
    f = w.f
    assert sorted(int(f["checkpoint"][s].attrs["seq"]) for s in ("slot0", "slot1")) == [1, 2]
    cp = read_checkpoint(f)
    assert (cp["seq"], cp["n_samples"], cp["n_steps"], cp["y"].tolist()) == (2, 3, 20, [2.0])
    # a write torn inside the newest slot (seq reset to -1 first): the older slot is used
    newest = [s for s in ("slot0", "slot1") if f["checkpoint"][s].attrs["seq"] == 2][0]
    f["checkpoint"][newest].attrs["seq"] = -1
    assert read_checkpoint(f)["n_samples"] == 2
    assert f["outputs/contact_stress"].attrs["unit"] == "Pa"
    assert f["outputs/contact_stress"].attrs["columns"] == "outer, inner_left, inner_right"
    w.close()


def test_statistics_skip_nan_and_split_columns(tmp_path):
    with h5py.File(tmp_path / "s.h5", "w") as f:
        o = f.create_group("outputs")
        o["time"] = np.array([0.0, 0.1, 0.2])
        a = np.array([[[1.0, 10.0], [2.0, np.nan]], [[3.0, 20.0], [4.0, 30.0]], [[0.5, 5.0], [6.0, 7.0]]])
        o["film_thickness_min"] = a
        o["film_thickness_min"].attrs["unit"] = "m"
        o["film_thickness_min"].attrs["columns"] = "outer, inner"
        st = output_statistics(f, block_rows=2)       # two blocks: the block logic is exercised
    s = st["film_thickness_min"]
    finite = a[np.isfinite(a)]
    assert (s["max"], s["min"], s["non_finite"], s["t_max"]) == (30.0, 0.5, 1, 0.1)
    assert s["mean"] == pytest.approx(finite.mean(), rel=1e-15)
    assert s["columns"]["outer"] == {"max": 6.0, "mean": pytest.approx(16.5 / 6), "min": 0.5, "t_max": 0.2,
                                     "non_finite": 0}
    assert s["columns"]["inner"]["max"] == 30.0 and s["columns"]["inner"]["non_finite"] == 1



def test_statistics_all_finite_path_matches_masked_sums():
    """An all-finite block skips the masked copies (issue 21); its sums are those of the masked
    path to the bit, for a whole output and for a strided column of it."""
    from flexbearing.simulation.results import _Stats
    a = np.random.default_rng(3).standard_normal((700, 20, 3)) * 1e3
    t = np.arange(700) * 1e-4
    for block in (a, a[..., 1]):
        st = _Stats()
        st.add(block, t)
        flat = block.reshape(block.shape[0], -1)
        ok = np.isfinite(flat)
        assert st.total == float(flat[ok].sum()) and st.count == flat.size
        assert (st.vmax, st.vmin) == (float(flat.max()), float(flat.min()))
        assert st.t_max == t[np.argmax(flat.max(axis=1))]

def test_units_and_summary_path():
    assert unit_for("contact_angle_inner_loaded") == "rad"      # not N although it says "load"
    assert unit_for("cage_eccentricity_ratio") == "1"
    assert unit_for("ball_angular_velocity") == "rad/s"
    assert unit_for("von_mises_max") == "Pa"
    assert unit_for("something_new") == "unknown"
    assert unit_for("x", {"x": "N"}) == "N"
    assert summary_path("out/run.h5").name == "run.summary.json"
