"""Results files open in xarray (flexbearing.simulation.results format 2: dimension scales, CF units, compressed
chunks) and `flexbearing export` writes the same numbers as netCDF and CSV. The reference values
are read with h5py from the same file: a different reader of the same bytes."""
import csv
import subprocess
import sys
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest

from flexbearing.cli import main as cli
from flexbearing.simulation.run import run_scene
from flexbearing.simulation.scene import loads_scene

xr = pytest.importorskip("xarray")
ROOT = Path(__file__).resolve().parents[1]

SCENE = """
name = "xr"
[cage]
model = "rigid"
[operation]
duration = 1e-3
[operation.speed]
phases = [{ kind = "uniform", duration = 1e-3, rpm = 10000 }]
[operation.load]
axial_load = 10e3
radial_load = 2e3
[output]
sample_interval = 1e-4
record = ["contact_stress", "ball_loads", "guiding_force", "cage_orbit", "kinematics", "cage_speed"]
"""


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("xr") / "xr.h5"
    run_scene(loads_scene(SCENE, "xr.toml"), path, quiet=True)
    return path


@pytest.mark.parametrize("engine", ["netcdf4", "h5netcdf"])
def test_the_results_file_opens_in_xarray(run_file, engine):
    """Named dimensions from the registry, time a coordinate in s, CF units beside `unit`, the
    contacts labelled, and a value equal to h5py's (ball 3, inner-left contact, 6th sample)."""
    pytest.importorskip({"netcdf4": "netCDF4", "h5netcdf": "h5netcdf"}[engine])
    with xr.open_dataset(run_file, group="outputs", engine=engine) as ds, h5py.File(run_file, "r") as f:
        cs = ds["contact_stress"]
        assert cs.dims == ("time", "ball", "contact")
        assert ds["external_load"].dims == ("time", "axis")
        assert ds["cage_land_force"].dims == ("time", "radial_axis")
        assert "time" in ds.coords and ds["time"].attrs["units"] == "s"
        assert np.array_equal(ds["time"].values, f["outputs/time"][...])
        assert list(ds["contact"].values) == ["outer", "inner_left", "inner_right"]
        assert list(ds["axis"].values) == ["x", "y", "z"]
        assert ds.sizes["ball"] == f["outputs/contact_stress"].shape[1]
        assert cs.attrs["units"] == "Pa" and cs.attrs["unit"] == "Pa"
        assert ds["ring_drive_torque"].attrs["units"] == "N m" and ds["ring_drive_torque"].attrs["unit"] == "N·m"
        assert cs.sel(contact="inner_left").isel(time=5, ball=3).item() == f["outputs/contact_stress"][5, 3, 1]
        assert f["outputs/contact_stress"].compression == "gzip" and f["outputs/contact_stress"].shuffle


def test_export_netcdf_and_csv_hold_the_same_numbers(run_file, tmp_path, capsys):
    assert cli.main(["export", str(run_file), "--netcdf", str(tmp_path / "r.nc"), "--csv", str(tmp_path / "csv")]) == 0
    with h5py.File(run_file, "r") as f:
        ref = f["outputs/contact_stress"][...]
        t = f["outputs/time"][...]
        with xr.open_dataset(tmp_path / "r.nc") as nc:
            assert np.array_equal(nc["contact_stress"].values, ref)
            assert nc.attrs["scene_name"] == "xr" and nc.attrs["status"] == "complete"
            assert nc["contact_stress"].attrs["units"] == "Pa"
        with (tmp_path / "csv" / "contact_stress.csv").open() as fh:
            rows = list(csv.reader(fh))
    head, units, data = rows[0], rows[1], np.array(rows[2:], dtype=float)
    assert head[0] == "time" and head[1 + 3 * 3 + 1] == "contact_stress[ball=3,contact=inner_left]"
    assert units[0] == "s" and set(units[1:]) == {"Pa"}
    assert np.array_equal(data[:, 0], t)
    assert np.array_equal(data[:, 1:], ref.reshape(len(t), -1))


def test_export_reads_a_format_1_file(run_file, tmp_path):
    """A file written before the dimension scales (format 1: `dims` attributes only) exports with
    the same dimension names."""
    from flexbearing.analysis.export import results_dataset
    old = tmp_path / "old.h5"
    with h5py.File(run_file, "r") as src, h5py.File(old, "w") as dst:
        for k, v in src.attrs.items():
            dst.attrs[k] = v
        dst.attrs["format_version"] = 1
        g = dst.create_group("outputs")
        for k, ds in src["outputs"].items():
            if k in ("ball", "contact", "axis", "radial_axis", "tilt", "ball_axis", "mode", "full_mode"):
                continue
            new = g.create_dataset(k, data=ds[...])
            for a in ("unit", "dims", "columns"):
                if a in ds.attrs:
                    new.attrs[a] = ds.attrs[a]
    ds = results_dataset(old)
    assert ds["contact_stress"].dims == ("time", "ball", "contact")
    assert list(ds["contact"].values) == ["outer", "inner_left", "inner_right"]
    assert ds["contact_stress"].attrs["units"] == "Pa"
    assert np.array_equal(ds["contact_stress"].values, results_dataset(run_file)["contact_stress"].values)


def test_export_needs_a_target_and_a_results_file(tmp_path, capsys):
    assert cli.main(["export", str(tmp_path / "missing.h5"), "--csv", str(tmp_path)]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert cli.main(["export", str(tmp_path / "missing.h5")]) == 2
    assert "give --netcdf FILE and/or --csv DIR" in capsys.readouterr().err


def test_version_and_python_m():
    """`flexbearing --version` and `python -m flexbearing --version` print pyproject's version."""
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    out = subprocess.run([sys.executable, "-m", "flexbearing", "--version"], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    assert out.strip() == f"flexbearing {version}"
    with pytest.raises(SystemExit) as exc:
        cli.main(["--version"])
    assert exc.value.code == 0
