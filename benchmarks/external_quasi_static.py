"""Run a public rolling-bearing code's quasi-static solver on one case and print its equilibrium
(docs/equilibrium_check.md). Nothing of that code is in this repository: this script writes its
input file (Data.txt, the fields below), runs its own two programs (Input.py, then Quasi_statics.py
as __main__) in a directory that holds a copy of it, and reads the state they leave.

    git clone https://github.com/Baomaokuan/Bearing /tmp/ext && cp /tmp/ext/Data.txt /tmp/ext/Data.orig.txt
    python benchmarks/external_quasi_static.py /tmp/ext Dw=0.022 Z=20 dm=0.1669116 free_deg=30 fo=0.515 \
        fi=0.52 shim=0.00044 rpm_o=0 T=293.15 fits=0 Do=0.199 Di=0.135 mat=2 rpm_i=14000 Fx=55000 Fz=-4000

One case per directory and per process (the code keeps its state in module globals and files in
its working directory). The fields written (the code's Data.txt rows; everything else keeps the
code's example values): ball diameter Dw and number Z, pitch diameter dm and free contact angle
free_deg (the code places the groove centres from them: outer at dm/2 − (fo − 1/2)·Dw·cos(free),
inner at dm/2 + (fi − 1/2)·Dw·cos(free)), groove factors fo, fi, the inner ring's shim thickness
(its two half-groove centres at ±shim/2), ring speeds rpm_o, rpm_i, the material code mat (2 =
its M50: 7830 kg/m³, 203 GPa, 0.28) of balls and rings, all seven temperatures T (K; equal: no
thermal growth), the housing and shaft fits (0), the outer ring's outside diameter Do and the inner
ring's bore Di (used only for its rings' centrifugal growth), and the loads Fx, Fy, Fz (N) on the
inner ring. Printed: per-ball loads and contact angles of the outer and both inner halves (the code
measures the inner angle from the opposite radial direction: 180° − |angle| is the contact angle),
the ring displacement, the cage speed (mean orbit speed, rad/s), the solver's final cost, and the
inner ring's radial centrifugal growth it applied (race_exp_i, m).
"""
from __future__ import annotations

import json
import os
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np

CASE = dict(Dw=22.225e-3, Z=20, dm=167.5375e-3, free_deg=27.0, fo=0.515, fi=0.52, shim=2.16e-4,
            rpm_o=4000.0, rpm_i=12000.0, Fx=2000.0, Fy=0.0, Fz=0.0, T=None, fits=None, mat=2,
            Do=201.725e-3, Di=133.35e-3)
# (row, column) of each field in the code's Data.txt (row 0 is its bearing type)
FIELDS = {"Dw": (2, 1), "Z": (2, 2), "dm": (3, 1), "free_deg": (3, 2), "Do": (4, 1), "fo": (4, 3),
          "rpm_o": (4, 9), "Di": (5, 1), "fi": (5, 3), "shim": (5, 5), "rpm_i": (5, 9),
          "Fx": (13, 7), "Fy": (13, 8), "Fz": (13, 9)}
MATERIAL_FIELDS = ((2, 3), (4, 6), (5, 6))
TEMPERATURE_FIELDS = tuple((1, k) for k in range(1, 8))
FIT_FIELDS = ((8, 3), (8, 4))


def write_input(directory: Path, case: dict) -> None:
    lines = (directory / "Data.orig.txt").read_text().split("\n")

    def put(row, col, value):
        items = lines[row].rstrip().rstrip(";").split(",")
        items[col] = repr(float(value))
        lines[row] = ",".join(items) + ";"

    for key, (row, col) in FIELDS.items():
        put(row, col, case[key])
    for row, col in MATERIAL_FIELDS:
        put(row, col, case["mat"])
    if case["T"] is not None:
        for row, col in TEMPERATURE_FIELDS:
            put(row, col, case["T"])
    if case["fits"] is not None:
        for row, col in FIT_FIELDS:
            put(row, col, case["fits"])
    (directory / "Data.txt").write_text("\n".join(lines))


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    directory = Path(argv[0]).resolve()
    case = dict(CASE)
    for a in argv[1:]:
        k, v = a.split("=")
        if k not in case:
            raise SystemExit(f"{k} is not a field; allowed: {', '.join(case)}")
        case[k] = float(v)
    write_input(directory, case)
    os.chdir(directory)
    sys.path.insert(0, str(directory))          # its Quasi_statics.py imports its Input.py
    subprocess.run([sys.executable, "Input.py"], check=True, stdout=subprocess.DEVNULL)
    g = runpy.run_path("Quasi_statics.py", run_name="__main__")
    x, n = g["x"], int(g["n"])
    q = {k: np.asarray(g[k])[:, 0, 0] for k in ("Q_b_o", "Q_b_i", "Q_b_o_", "Q_b_i_")}
    strain, strain_ = g["Info_brcs"], g["Info_brcs_"]
    out = dict(case=case, cost=float(g["result"].cost),
               ring_displacement=[float(x[0]), float(x[2]), float(x[4])],
               Q_outer=q["Q_b_o"].tolist(), Q_inner=q["Q_b_i"].tolist(), Q_inner_second=q["Q_b_i_"].tolist(),
               alpha_outer_deg=np.degrees(np.asarray(strain[20])[:, 0, 0]).tolist(),
               alpha_inner_deg=np.degrees(np.asarray(strain[22])[:, 0, 0]).tolist(),
               alpha_inner_second_deg=np.degrees(np.asarray(strain_[6])[:, 0, 0]).tolist(),
               cage_speed=float(x[19]), orbit_speed=x[29:24 + 12 * n:12].tolist(),
               race_exp_i=float(g["Info_es"][10]), race_exp_o=float(g["Info_es"][9]))
    print(json.dumps(out))


if __name__ == "__main__":
    main()
