"""A run's results for other tools: an xarray Dataset, netCDF-4, or CSV for spreadsheets.

    flexbearing export RUN.h5 [--netcdf FILE.nc] [--csv DIR]            (flexbearing.cli.export)

A results file (flexbearing.simulation.results, format 2) opens in xarray as it is:

    import xarray as xr
    ds = xr.open_dataset("out/paper_steady.h5", group="outputs")
    ds.contact_stress.sel(contact="outer").max("ball")      # Pa, against time [s]

with named dimensions (time, ball, contact, axis, mode, ... from flexbearing.multibody.output_registry),
`time` as a coordinate and each variable's unit in `units` (CF spelling) and `unit`.
`results_dataset` gives the same Dataset for files of format 1 too (written before the dimension
scales), from their `dims` attributes, with the run's attributes (scene name, hash, status,
duration, sample interval, the scene's text) as the Dataset's.

CSV: one file per output, `<name>.csv`: a row per sample, the first column the time, then one
column per component, named `<name>[ball=3,contact=outer]` (the dimension and its label), the
header's second line the unit; full precision (17 significant digits), so the numbers read back
are the file's.
"""
from __future__ import annotations

import csv
import itertools
from pathlib import Path

import numpy as np
from tqdm import tqdm

from flexbearing.common.validation import InputError
from flexbearing.simulation.results import opened, output_items
from flexbearing.multibody import output_registry as R
from flexbearing.common.progress import Stages
from flexbearing.common.safe_files import (atomic_output, refuse_overwriting_inputs, check_output_folder)

RUN_ATTRS = ("scene_name", "scene_hash", "scene_path", "cage_model", "status", "duration",
             "sample_interval", "n_samples_expected", "format_version")


def results_dataset(run):
    """The run's /outputs as an xarray.Dataset (loaded into memory), with the run's attributes
    (run: an open flexbearing.simulation.results.Run or a path). xarray reads format 2 through
    its own netCDF-4 reader."""
    import xarray as xr
    with opened(run) as r:
        path, f = r.path, r.file
        version = int(f.attrs.get("format_version", 1))
        attrs = {k: _plain(f.attrs[k]) for k in RUN_ATTRS if k in f.attrs}
        if "scene" in f:
            text = f["scene"][()]
            attrs["scene"] = text.decode() if isinstance(text, bytes) else str(text)
        if version < 2:
            ds = _dataset_from_dims(f["outputs"])
    if version >= 2:
        with xr.open_dataset(path, group="outputs") as lazy:
            ds = lazy.load()
    ds.attrs.update(attrs)
    return ds


def _plain(v):
    if isinstance(v, bytes):
        return v.decode()
    return v.item() if hasattr(v, "item") else v


def _dataset_from_dims(out):
    """A format-1 /outputs group (no dimension scales) as a Dataset, dimensions from `dims`."""
    import xarray as xr
    variables, coords = {}, {}
    for name, ds in output_items(out):
        if name == "time":
            continue
        names = [d.strip() for d in str(ds.attrs.get("dims", "")).split(",") if d.strip()]
        if len(names) != ds.ndim:
            names = ["time"] + [f"{name}_dim{i}" for i in range(1, ds.ndim)]
        attrs = {k: _plain(v) for k, v in ds.attrs.items()}
        attrs.setdefault("units", R.cf_units(str(attrs.get("unit", ""))))
        variables[name] = xr.Variable(names, ds[...], attrs)
        for d, n in zip(names[1:], ds.shape[1:]):
            labels = R.DIMENSION_LABELS.get(d)
            coords.setdefault(d, np.array(labels, dtype=object) if labels and len(labels) == n else np.arange(n))
    t = out["time"]
    coords["time"] = xr.Variable("time", t[...], {"unit": "s", "units": "s"})
    return xr.Dataset(variables, coords=coords)


def write_netcdf(path, target, quiet: bool = True) -> Path:
    """The run as one netCDF-4 file (deflate level 1 + shuffle per variable, as the results file);
    quiet=False: a progress bar (read, then write)."""
    target = Path(target)
    refuse_overwriting_inputs(target, [getattr(path, "path", path)], "--netcdf")
    stage = Stages(f"netCDF of {Path(str(getattr(path, 'path', path))).name}", {"read": 1.0, "write": 2.0}, quiet)
    stage("read")
    ds = results_dataset(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    encoding = {k: {"zlib": True, "complevel": 1, "shuffle": True} for k in ds.data_vars}
    size = int(ds.nbytes) + (1 << 20)              # uncompressed: an upper bound, reserved first
    stage("write")
    with atomic_output(target, suffix=".nc", reserve=size) as tmp:   # never through a link, never half a file
        ds.to_netcdf(tmp, format="NETCDF4", encoding=encoding)
    stage(None)
    return target


def _column_names(name: str, da) -> list[str]:
    dims = da.dims[1:]
    if not dims:
        return [name]
    labels = [[str(x) for x in da[d].values] for d in dims]
    return [f"{name}[" + ",".join(f"{d}={x}" for d, x in zip(dims, combo)) + "]"
            for combo in itertools.product(*labels)]


def write_csv(path, folder, quiet: bool = True) -> list[Path]:
    """One CSV per output in `folder` (module docstring: the layout). Returns the files.
    quiet=False: a progress bar over the values written, with the output being written."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir() and not folder.is_symlink():
        raise InputError(f"--csv {folder} is a file: give a folder for the CSV files")
    check_output_folder(folder, (), [getattr(path, "path", path)], "--csv", patterns=("*.csv",))
    ds = results_dataset(path)
    folder.mkdir(parents=True, exist_ok=True)
    t = ds["time"].values
    written = []
    names = [n for n in sorted(ds.data_vars) if ds[n].dims[:1] == ("time",)]
    bar = tqdm(total=sum(ds[n].size for n in names), desc="CSV", unit=" values", unit_scale=True,
               disable=quiet, mininterval=0.5, dynamic_ncols=True)
    for name in names:
        da = ds[name]
        bar.set_description_str(f"CSV {name}")
        values = np.asarray(da.values, dtype=np.float64).reshape(len(t), -1)
        unit = str(da.attrs.get("unit", da.attrs.get("units", "")))
        p = folder / f"{name}.csv"
        # ~26 characters a value written with repr: reserved first, ENOSPC is then one line
        with atomic_output(p, reserve=26 * (values.size + len(t)) + 4096) as tmp, tmp.open("w", newline="") as fh:
            w = csv.writer(fh)
            cols = _column_names(name, da)
            w.writerow(["time"] + cols)
            w.writerow(["s"] + [unit] * len(cols))
            for i in range(len(t)):
                w.writerow([repr(float(t[i]))] + [repr(float(x)) for x in values[i]])
        written.append(p)
        bar.update(da.size)
    bar.close()
    return written

