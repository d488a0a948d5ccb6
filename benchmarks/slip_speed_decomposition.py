"""How much of the test's cage slip can be drag-induced skid? (paper Table 5, session 13)

The model's skid grows steeply with speed. Runs at a small contact-angle split (shim angle 15°), with
the bounded traction law and free balls, put the kinematic part near zero: at X_ref = 0.002 the
4000 rpm slips are 0.01 / −0.09 / −0.24 % for the three load groups (load independent). In those
runs the skid of group 1 grows from 4000 to 12,000 rpm by 17.5× at X_ref = 0.01 (0.75 → 13.12 %)
and by 11.5× at X_ref = 0.03 (2.21 → 25.52 %), i.e. as n^p with p = 2.6 and 2.2. Those numbers are in
benchmarks/results/slip_rate.md, "Session 13".

Split each test group's slips as S(n) = S0 + k·(n/4000 rpm)^p: S0 does not depend on speed (a kinematic
offset: ball attitude, contact angles, the alpha in nm), and k·n^p is the skid. For a given p, S0
and k follow by linear least squares over the group's speeds. A skid that grows at least as fast as
the model's (p >= 2) leaves S0 of about 4–5 % in every group. That share cannot come from drag. In
the model, only an attitude near inner-race control gives it
(benchmarks/slip_kinematic_bracket.py), and that needs transverse traction of about 0.1–0.2
(flexbearing.studies.validation.slip_rate docstring). Even a linear skid (p = 1) leaves 1.4–2.6 %. The exponent is not
fitted freely: over 4–6 speeds per group, S0 and p trade off against each other.

    .venv/bin/python -m benchmarks.slip_speed_decomposition
"""
from __future__ import annotations

import numpy as np

from flexbearing.studies.validation.slip_rate import slip_rate_cases

EXPONENTS = (1.0, 2.0, 2.2, 2.6)


def split_offset_and_skid(speed_rpm, slip_pct, p: float):
    """Least-squares S = S0 + k·(n/4000)^p over one group: (S0 %, k %, rms residual %)."""
    x = (np.asarray(speed_rpm, float) / 4000.0) ** p
    a = np.column_stack([np.ones_like(x), x])
    (s0, k), *_ = np.linalg.lstsq(a, np.asarray(slip_pct, float), rcond=None)
    rms = float(np.sqrt(np.mean((a @ [s0, k] - slip_pct) ** 2)))
    return float(s0), float(k), rms


def table() -> str:
    cases = slip_rate_cases()
    lines = ["| group | Fa/Fr N | speeds rpm | " + " | ".join(f"p = {p:g}: S0 / k / rms %" for p in EXPONENTS) + " |",
             "|---:|---|---|" + "---|" * len(EXPONENTS)]
    for g in sorted({c["group"] for c in cases}):
        sel = [c for c in cases if c["group"] == g]
        n = [c["speed_rpm"] for c in sel]
        s = [c["test_slip_pct"] for c in sel]
        cells = []
        for p in EXPONENTS:
            s0, k, rms = split_offset_and_skid(n, s, p)
            cells.append(f"{s0:.2f} / {k:.2f} / {rms:.2f}")
        lines.append(f"| {g} | {sel[0]['axial_load']:.0f}/{sel[0]['radial_load']:.0f} | "
                     f"{min(n)}–{max(n)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(table())
