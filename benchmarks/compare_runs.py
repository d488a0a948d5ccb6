"""Compare two results files dataset by dataset: are the /outputs of a run unchanged?

Written for issue 20 (a refactoring with "no behaviour change"): the paper's four scenes run before
and after, every recorded output compared. Reusable for any change that must not move results.

For every dataset under /outputs of BEFORE (and AFTER) it prints the shape, the unit attribute of
each file and the largest difference relative to the dataset's own scale,

    rel = max_i |after_i − before_i| / max_i |before_i|        (0 for two all-zero datasets)

and whether the two are identical to the bit. A dataset present in only one file, a different
shape or unit is reported as a mismatch. Exit status 0 when every dataset's rel <= --tol (default
1e-12: "identical to round-off"), 1 otherwise.

    .venv/bin/python benchmarks/compare_runs.py BEFORE.h5 AFTER.h5 [--tol 1e-12] [--json OUT]
    .venv/bin/python benchmarks/compare_runs.py BEFORE_DIR AFTER_DIR      (every *.h5 of BEFORE_DIR)
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import h5py
import numpy as np


def compare_files(before, after) -> dict:
    """{name: {shape, unit_before, unit_after, rel, identical, problem}} for the /outputs datasets."""
    out = {}
    with h5py.File(before, "r") as fb, h5py.File(after, "r") as fa:
        gb, ga = fb["outputs"], fa["outputs"]
        for name in sorted(set(gb) | set(ga)):
            row = {"problem": None}
            if name not in gb or name not in ga:
                row["problem"] = "only in " + ("after" if name not in gb else "before")
                out[name] = row
                continue
            b, a = gb[name][...], ga[name][...]
            row.update(shape=list(b.shape), unit_before=str(gb[name].attrs.get("unit", "")),
                       unit_after=str(ga[name].attrs.get("unit", "")))
            if a.shape != b.shape:
                row["problem"] = f"shape {b.shape} -> {a.shape}"
            elif row["unit_before"] != row["unit_after"]:
                row["problem"] = f"unit {row['unit_before']!r} -> {row['unit_after']!r}"
            if a.shape == b.shape and not (np.issubdtype(a.dtype, np.number) and np.issubdtype(b.dtype, np.number)):
                row["identical"] = bool(np.array_equal(a, b))     # labels of a dimension scale
                row["max_abs"] = row["rel"] = 0.0 if row["identical"] else float("inf")
            elif a.shape == b.shape:
                row["identical"] = bool(np.array_equal(a, b, equal_nan=True))
                scale = float(np.nanmax(np.abs(b))) if b.size else 0.0
                diff = np.abs(a - b)
                both_nan = np.isnan(a) & np.isnan(b)
                diff = np.where(both_nan, 0.0, diff)
                d = float(np.nanmax(diff)) if diff.size else 0.0
                if np.isnan(diff).any():
                    d = float("inf")
                row["max_abs"] = d
                row["rel"] = 0.0 if d == 0.0 else (d / scale if scale > 0 else float("inf"))
            out[name] = row
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--tol", type=float, default=1e-12, help="largest accepted rel (default 1e-12)")
    ap.add_argument("--json", help="write every row here")
    a = ap.parse_args(argv)
    b, af = Path(a.before), Path(a.after)
    pairs = ([(p, af / p.name) for p in sorted(b.glob("*.h5"))] if b.is_dir() else [(b, af)])
    ok, report = True, {}
    for pb, pa in pairs:
        rows = compare_files(pb, pa)
        report[pb.name] = rows
        worst = max((r.get("rel", float("inf")) if r["problem"] is None else float("inf")
                     for r in rows.values()), default=0.0)
        n_id = sum(1 for r in rows.values() if r.get("identical"))
        print(f"== {pb.name}: {len(rows)} datasets, {n_id} bit-identical, max rel {worst:.3g}")
        for name, r in rows.items():
            bad = r["problem"] is not None or r.get("rel", 0.0) > a.tol
            ok &= not bad
            if bad or not r.get("identical"):
                what = r["problem"] or f"rel {r['rel']:.3g} (abs {r['max_abs']:.3g} {r['unit_before']})"
                print(f"   {'MISMATCH ' if bad else ''}{name}: {what}")
    if a.json:
        Path(a.json).write_text(json.dumps(report, indent=1))
    print("all datasets within tol" if ok else "SOME DATASETS DIFFER", f"(tol {a.tol:g})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
