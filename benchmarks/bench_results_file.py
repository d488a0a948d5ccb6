"""Size and write/read speed of a results file with and without chunk compression.

Input: a complete run of the paper's steady flexible-cage scene (scenes/paper_steady.toml: 0.6 s,
6,001 samples, every output incl. von Mises and the full modal coordinates; `--run FILE`, else it
is made with `flexbearing run`, ~4 min). Its outputs are written again through
flexbearing.simulation.results.ResultsWriter exactly as a run writes them (one sample at a time with
add_sample, a block written and the file flushed every `checkpoint_every` samples), once per
filter setting, the settings interleaved over `--repeat` rounds; CPU time (process_time) of the
writing and of reading every output back (what a report does), and the file's size. Each
rewritten file is checked to hold the same numbers as the input, bit for bit.

    .venv/bin/python -m benchmarks.bench_results_file [--run RUN.h5] [--repeat 3]

Writes benchmarks/results/results_file.{json,md}.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

from flexbearing.simulation import results as RS

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
SETTINGS = {
    "none": {},
    "gzip1+shuffle": {"compression": "gzip", "compression_opts": 1, "shuffle": True},
    "gzip4+shuffle": {"compression": "gzip", "compression_opts": 4, "shuffle": True},
    "gzip4": {"compression": "gzip", "compression_opts": 4, "shuffle": False},
}


def rewrite(src: Path, dst: Path, setting: dict, every: int) -> float:
    """Write src's outputs to dst through ResultsWriter with `setting`; CPU seconds of the writing."""
    from flexbearing.simulation.results import scene_of_run
    with h5py.File(src, "r") as f:
        scene = scene_of_run(f)
        names = [k for k, _ in RS.output_items(f["outputs"])]
        data = {k: f["outputs"][k][...] for k in names}
        units = {k: str(f["outputs"][k].attrs.get("unit")) for k in names}
    n = data["time"].shape[0]
    saved = RS.COMPRESSION
    RS.COMPRESSION = setting
    try:
        t0 = time.process_time()
        w = RS.ResultsWriter.create(dst, scene, units)
        for i in range(n):
            w.add_sample(data["time"][i], {k: v[i] for k, v in data.items() if k != "time"})
            if (i + 1) % every == 0 or i + 1 == n:
                w.write_block()
                w.f.flush()
        w.close()
        cpu = time.process_time() - t0
    finally:
        RS.COMPRESSION = saved
    with h5py.File(dst, "r") as g:                 # the same numbers, bit for bit
        for k, v in data.items():
            assert np.array_equal(g["outputs"][k][...], v, equal_nan=True), k
    return cpu


def xarray_readback(path: Path) -> dict:
    """What a user sees opening the file in xarray, and one value against h5py's."""
    import xarray as xr
    with xr.open_dataset(path, group="outputs") as ds, h5py.File(path, "r") as f:
        cs = ds["contact_stress"]
        k = cs.sizes["time"] // 2
        return {"sizes": {k_: int(v) for k_, v in ds.sizes.items()}, "contact_stress_dims": list(cs.dims),
                "contact_stress_units": cs.attrs["units"], "t": float(ds["time"][k]),
                "value": float(cs.sel(contact="outer").isel(time=k, ball=3)),
                "h5py": float(f["outputs/contact_stress"][k, 3, 0])}


def read_all(path: Path) -> float:
    t0 = time.process_time()
    with h5py.File(path, "r") as f:
        for _, ds in RS.output_items(f["outputs"]):
            ds[...]
    return time.process_time() - t0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--run", default=None, help="a complete run of scenes/paper_steady.toml (default: made here)")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args(argv)
    scratch = Path(tempfile.mkdtemp(prefix="bench_results_file_"))
    run = Path(a.run) if a.run else scratch / "paper_steady.h5"
    if not a.run:
        subprocess.run([str(Path(sys.executable).with_name("flexbearing")), "run",
                        str(ROOT / "scenes" / "paper_steady.toml"), "-o", str(run), "--quiet"], check=True)
    with h5py.File(run, "r") as f:
        every = int(RS.scene_of_run(f).checkpoint_every)
        n = int(f["outputs/time"].shape[0])
        raw = int(sum(ds.nbytes for _, ds in RS.output_items(f["outputs"])))
    rows = {k: {"write_cpu_s": [], "read_cpu_s": []} for k in SETTINGS}
    for rep in range(a.repeat):
        for name, setting in SETTINGS.items():
            dst = scratch / f"{name}.h5"
            dst.unlink(missing_ok=True)
            rows[name]["write_cpu_s"].append(rewrite(run, dst, setting, every))
            rows[name]["read_cpu_s"].append(read_all(dst))
            rows[name]["size_bytes"] = int(dst.stat().st_size)
            print(f"round {rep} {name}: {rows[name]['size_bytes'] / 1e6:.1f} MB, write "
                  f"{rows[name]['write_cpu_s'][-1]:.2f} s, read {rows[name]['read_cpu_s'][-1]:.2f} s", flush=True)
    for r in rows.values():
        r["write_cpu_median_s"] = statistics.median(r["write_cpu_s"])
        r["read_cpu_median_s"] = statistics.median(r["read_cpu_s"])
    chosen = next(k for k, v in SETTINGS.items() if v == RS.COMPRESSION)
    readback = xarray_readback(scratch / f"{chosen}.h5")
    result = {"command": f"python -m benchmarks.bench_results_file --run RUN.h5 --repeat {a.repeat}",
              "run": str(run), "n_samples": n, "outputs_raw_bytes": raw, "checkpoint_every": every,
              "load_average": os.getloadavg(), "settings": SETTINGS, "rows": rows, "chosen": chosen,
              "xarray_readback": readback}
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / "results_file.json").write_text(json.dumps(result, indent=1) + "\n")
    base = rows["none"]
    lines = ["# Results file: chunk compression", "",
             f"`{result['command']}` on a complete run of scenes/paper_steady.toml ({n} samples, "
             f"{raw / 1e6:.1f} MB of float64 outputs), its outputs written again through "
             f"flexbearing.simulation.results.ResultsWriter as a run writes them (a block every {every} samples). "
             f"CPU times (process_time, median of {a.repeat} interleaved rounds; load average "
             f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs). Chunks: {RS.chunk_rows(every)} samples (a checkpoint interval).", "",
             "| filters | size MB | × of none | write CPU s | read-all CPU s |", "|---|---:|---:|---:|---:|"]
    for name, r in rows.items():
        lines.append(f"| {name}{' (chosen)' if name == chosen else ''} | {r['size_bytes'] / 1e6:.1f} | "
                     f"{r['size_bytes'] / base['size_bytes']:.2f} | {r['write_cpu_median_s']:.2f} | "
                     f"{r['read_cpu_median_s']:.2f} |")
    c, g4 = rows[chosen], rows["gzip4+shuffle"]
    lines += ["", f"Chosen: {chosen} (flexbearing.simulation.results.COMPRESSION): {c['size_bytes'] / base['size_bytes']:.2f} of the "
              f"uncompressed size for {c['write_cpu_median_s'] - base['write_cpu_median_s']:.2f} s more CPU over the "
              f"whole run's writing and {c['read_cpu_median_s'] - base['read_cpu_median_s']:.2f} s more to read every "
              f"output back; level 4 saves another {(c['size_bytes'] - g4['size_bytes']) / 1e6:.1f} MB for "
              f"{g4['write_cpu_median_s'] - c['write_cpu_median_s']:.2f} s more CPU, and without the byte shuffle "
              f"the file is larger. Deflate is the filter every HDF5 and netCDF-4 reader has (lzf or blosc "
              f"would need a plugin outside h5py). A run does this writing in a writer thread beside "
              f"the integration (flexbearing.simulation.results.ResultsWriter.checkpoint_in_background), on the "
              f"second core of a 2-core machine.", ""]
    lines += ["## xarray readback of the chosen file", "",
              "`xarray.open_dataset(FILE, group=\"outputs\")` (default engine): dimensions "
              + ", ".join(f"{k} {v}" for k, v in readback["sizes"].items())
              + f"; `contact_stress` {readback['contact_stress_dims']} in {readback['contact_stress_units']}; "
              f"the outer contact stress of ball 3 at t = {readback['t']:g} s: {readback['value']!r} Pa through "
              f"xarray, {readback['h5py']!r} Pa through h5py (equal: {readback['value'] == readback['h5py']}).", ""]
    (RESULTS / "results_file.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
