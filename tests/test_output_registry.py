"""The output registry (flexbearing.multibody.output_registry) against what a run really records.

One table says, for every dataset a run can write, its scene output, SI unit and dimensions; the
recording (flexbearing.simulation.run), the results file (flexbearing.simulation.results), the scene validation
(flexbearing.simulation.scene) and the report (flexbearing.analysis.windows) read it. These tests tie it to the code that
produces the values: every key the evaluation returns is in the registry with the shape its
dimensions say, and a real run that records every scene output writes exactly the registry's
datasets, each with the registry's unit and dimension names.
"""
from __future__ import annotations

import h5py
import numpy as np
import pytest

from flexbearing.simulation.results import output_items
from flexbearing.multibody import output_registry as R
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL

Z = PAPER_BEARING.n_balls
# the sizes of the dimension names (module docstring of the registry); the modal ones come from the
# flexible-cage run and are checked there
SIZES = {"ball": Z, "contact": 3, "axis": 3, "radial_axis": 2, "tilt": 2, "ball_axis": 3}
RIGID_GROUPS = tuple(g for g in R.GROUPS if g not in ("von_mises", "cage_modes"))


def _rigid_evaluation() -> dict:
    from flexbearing.multibody.initial import initial_state
    from flexbearing.multibody.model import build_model
    from flexbearing.multibody.outputs import evaluate_outputs
    model = build_model(PAPER_BEARING, PAPER_OIL, {})
    w = 10000 * np.pi / 30
    y = initial_state(model, w, 10e3, 2e3)
    return evaluate_outputs(model, 0.0, y, np.array([[0.0, w]]), np.array([[0.0, 10e3, 0.0, -2e3]]),
                            np.zeros((0, 6)), film=True, energy=True)


def test_every_evaluated_key_is_registered_with_its_shape():
    values = R.split_mixed_units(_rigid_evaluation())
    missing = sorted(set(values) - set(R.OUTPUT))
    assert missing == [], f"evaluated but not in the registry: {missing}"
    for name, v in values.items():
        dims = R.OUTPUT[name].dims
        assert np.shape(v) == tuple(SIZES[d] for d in dims), name


def test_registry_entries_are_consistent():
    assert len(R.OUTPUT) == len(R.OUTPUTS)                       # one entry per name
    for o in R.OUTPUTS:
        assert all(g in R.GROUPS or g == R.ALWAYS for g in o.groups), o.name
        assert o.unit and o.unit != "unknown", o.name
        if o.columns is not None:
            assert o.dims and SIZES.get(o.dims[-1], len(o.columns)) == len(o.columns), o.name
    for g in R.GROUPS:                                           # every scene output records something
        assert R.recorded_by([g]) - R.recorded_by([]), g
    # the scene validation accepts exactly the registry's groups
    from flexbearing.simulation.scene import loads_scene
    from flexbearing.common.validation import InputError
    with pytest.raises(InputError, match=", ".join(repr(g) for g in R.GROUPS)):
        loads_scene('[operation]\nduration = 0.1\n[operation.speed]\ntable_rpm = [[0.0, 1000]]\n'
                    '[operation.load]\naxial_load = 0\n'
                    '[output]\nsample_interval = 0.01\nrecord = ["no_such_output"]\n')


def _check_file(path, groups) -> set[str]:
    """Every dataset of the results file is the registry's, with its unit and dims; returns the names."""
    with h5py.File(path, "r") as f:
        out = f["outputs"]
        names = {k for k, _ in output_items(out)} - {"time"}
        for name in names:
            o = R.OUTPUT[name]
            ds = out[name]
            assert ds.attrs["unit"] == o.unit, name
            assert ds.attrs["dims"] == ", ".join(("time",) + o.dims), name
            assert ds.ndim == 1 + len(o.dims), name
            for d, n in zip(o.dims, ds.shape[1:]):
                assert SIZES.get(d, n) == n, (name, d)
            if o.columns:
                assert ds.attrs["columns"] == ", ".join(o.columns), name
    assert names == R.recorded_by(groups), (sorted(names - R.recorded_by(groups)),
                                            sorted(R.recorded_by(groups) - names))
    return names


RIGID_SCENE = """
name = "registry"
[cage]
model = "rigid"
[operation]
duration = 2e-4
[operation.speed]
phases = [{ kind = "uniform", duration = 2e-4, rpm = 10000 }]
[operation.load]
axial_load = 10e3
radial_load = 2e3
[output]
sample_interval = 1e-4
record = %s
"""


def test_a_rigid_run_records_exactly_the_registry(tmp_path):
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    scene = loads_scene(RIGID_SCENE % str(list(RIGID_GROUPS)).replace("'", '"'), "registry.toml")
    run_scene(scene, tmp_path / "r.h5", quiet=True)
    _check_file(tmp_path / "r.h5", RIGID_GROUPS)


@pytest.mark.slow
def test_a_flexible_run_records_exactly_the_registry(tmp_path, paper_reduced_cage):
    """The flexible cage's own outputs (von Mises, modal coordinates) too; 0.2 ms of the paper cage."""
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    text = (RIGID_SCENE % str(list(R.GROUPS)).replace("'", '"')).replace('model = "rigid"',
                                                                            'model = "flexible"')
    run_scene(loads_scene(text, "registry.toml"), tmp_path / "f.h5", quiet=True)
    names = _check_file(tmp_path / "f.h5", R.GROUPS)
    assert {"von_mises_max", "cage_modal_coordinates", "cage_modal_coordinates_full"} <= names
