"""Our quasi-static equilibrium beside a public code's (docs/equilibrium_check.md, issue 46 item 2).

For each case of CASES it solves flexbearing.multibody.quasi_static.solve_quasi_static (Jones's race
control per ball, the ring's tilt held: the external solve has only the ring's x, y, z) twice:

    ours      the model as it is: its M50 (7810 kg/m³, 210 GPa, 0.30), the gyroscopic moment, no
              centrifugal growth of the inner ring;
    matched   the external code's assumptions: its M50 (7830 kg/m³, 203 GPa, 0.28), no gyroscopic
              moment (its friction force for it is R_b·M_g where M_g/R_b is meant, a factor
              R_b² ≈ 1.2e-4: in effect none), the inner ring's radial centrifugal growth u_i
              (race_exp_i of the external run; u_i ∝ speed²) added to the inner groove centres;

and puts them beside the external code's run (benchmarks/external_quasi_static.py output, one JSON
per case in DIR/<case name>.json) as a markdown table.

    python benchmarks/equilibrium_check.py --external DIR [--json OUT]
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from flexbearing.common.materials import Material
from flexbearing.multibody.bearing import PAPER_BEARING
from flexbearing.multibody.quasi_static import angular_contact_grooves, grooves_from_bearing, solve_quasi_static

EXTERNAL_M50 = Material(density=7830.0, youngs_modulus=2.03e11, poisson_ratio=0.28)
# Harris's 218 angular-contact bearing as usually quoted (tests/test_quasi_static.py): Dw 22.23 mm,
# dm 125.3 mm, Z 16, fi = fo = 0.5232, alpha0 40°. In the external code's layout (groove centres
# aligned axially, clearance from the free angle) the ring's axial position differs from ours
# (contact at alpha0 at zero load) by B·Dw·sin(alpha0):
B218 = dict(dm=0.1253, dw=0.02223, z=16, f=0.5232, alpha0=math.radians(40.0))
AXIAL_DATUM_218 = (2.0 * B218["f"] - 1.0) * B218["dw"] * math.sin(B218["alpha0"])

# name -> (bearing, inner speed rpm, Fa N, Fr N)
CASES = {
    "paper_4000_55_4": ("paper", 4000.0, 55e3, 4e3),
    "paper_10000_55_4": ("paper", 10000.0, 55e3, 4e3),
    "paper_14000_55_4": ("paper", 14000.0, 55e3, 4e3),
    "paper_14000_55_0": ("paper", 14000.0, 55e3, 0.0),
    "paper_14000_55_54": ("paper", 14000.0, 55e3, 54e3),
    "paper_12000_2_0": ("paper", 12000.0, 2e3, 0.0),
    "b218_10000_4.45_0": ("218", 10000.0, 4450.0, 0.0),
    "b218_10000_4.45_2": ("218", 10000.0, 4450.0, 2000.0),
    "b218_1000_22.25_0": ("218", 1000.0, 22250.0, 0.0),
    "b218_1000_4.45_8": ("218", 1000.0, 4450.0, 8000.0),
}


def grooves(kind: str, matched: bool, ring_growth: float = 0.0):
    """Grooves of the paper bearing (its preset, design clearance) or the 218; matched: the external
    code's M50 and the inner groove centres moved out by ring_growth (m)."""
    if kind == "paper":
        b = PAPER_BEARING.with_(ball_material=EXTERNAL_M50, ring_material=EXTERNAL_M50) if matched else PAPER_BEARING
        g = grooves_from_bearing(b)
    else:
        kw = dict(youngs_modulus=EXTERNAL_M50.youngs_modulus, poisson_ratio=EXTERNAL_M50.poisson_ratio,
                  density=EXTERNAL_M50.density) if matched else {}
        g = angular_contact_grooves(B218["dm"], B218["dw"], B218["z"], B218["f"], B218["f"], B218["alpha0"], **kw)
    if ring_growth:
        r = g.groove_r
        g = dataclasses.replace(g, groove_r=(r[0], r[1] + ring_growth, r[2] + ring_growth))
    return g


def solve(kind, rpm, fa, fr, matched: bool, ring_growth: float = 0.0) -> dict:
    r = solve_quasi_static(grooves(kind, matched, ring_growth), rpm * math.pi / 30.0, fx=fa, fz=-fr,
                           control="jones", fix_tilt=True, gyroscopic=not matched)
    load, angle = r.load, np.degrees(np.abs(r.contact_angle))
    k = np.argmax(load[:, 1:], axis=1)
    inner, alpha_i = load[np.arange(len(k)), 1 + k], angle[np.arange(len(k)), 1 + k]
    x = r.ring_displacement[0] + (AXIAL_DATUM_218 if kind == "218" else 0.0)
    return dict(converged=bool(r.converged), residual_ring=float(r.residual_ring), iterations=int(r.iterations),
                alpha_o=[float(angle[:, 0][load[:, 0] > 0].min()), float(angle[:, 0].max())],
                alpha_i=[float(alpha_i[inner > 0].min()), float(alpha_i.max())],
                q_o=[float(load[:, 0].min()), float(load[:, 0].max())], q_i=[float(inner.min()), float(inner.max())],
                q_third=float(load[:, 1:].min(axis=1).max()), ring_x_um=x * 1e6, ring_z_um=r.ring_displacement[2] * 1e6,
                cage_rpm=float(r.orbit_speed.mean() * 30.0 / math.pi))


def external(path: Path) -> dict:
    """The external run's numbers in the same form (its inner angle: 180° − |angle|)."""
    d = json.loads(path.read_text())
    qo, qi, qi2 = (np.array(d[k]) for k in ("Q_outer", "Q_inner", "Q_inner_second"))
    ao = np.abs(np.array(d["alpha_outer_deg"]))
    ai = 180.0 - np.abs(np.array(d["alpha_inner_deg"]))
    ai2 = 180.0 - np.abs(np.array(d["alpha_inner_second_deg"]))
    inner = np.maximum(qi, qi2)
    alpha_i = np.where(qi >= qi2, ai, ai2)
    return dict(cost=d["cost"], alpha_o=[float(ao[qo > 0].min()), float(ao[qo > 0].max())],
                alpha_i=[float(alpha_i[inner > 0].min()), float(alpha_i[inner > 0].max())],
                q_o=[float(qo.min()), float(qo.max())], q_i=[float(inner.min()), float(inner.max())],
                q_third=float(np.minimum(qi, qi2).max()), ring_x_um=d["ring_displacement"][0] * 1e6,
                ring_z_um=d["ring_displacement"][2] * 1e6, cage_rpm=d["cage_speed"] * 30.0 / math.pi,
                ring_growth_um=d["race_exp_i"] * 1e6)


def _span(v, fmt):
    a, b = (fmt.format(x) for x in v)
    return a if a == b else f"{a}–{b}"


def row(name, label, r) -> str:
    return (f"| {name} | {label} | {_span(r['alpha_o'], '{:.2f}')} | {_span(r['alpha_i'], '{:.2f}')} | "
            f"{_span(r['q_o'], '{:.0f}')} | {_span(r['q_i'], '{:.0f}')} | {r['q_third']:.0f} | {r['ring_x_um']:.1f} | "
            f"{r['ring_z_um']:.2f} | {r['cage_rpm']:.0f} |")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--external", required=True, help="directory of the external runs, <case>.json")
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    lines = ["| case | code | α_o, deg | α_i (loaded half), deg | Q_o, N | Q_i, N | third contact, N | ring x, µm | "
             "ring z, µm | cage, rpm |", "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    out = {}
    for name, (kind, rpm, fa, fr) in CASES.items():
        path = Path(a.external) / f"{name}.json"
        ext = external(path) if path.exists() else None
        growth = ext["ring_growth_um"] * 1e-6 if ext else 0.0
        ours, matched = solve(kind, rpm, fa, fr, False), solve(kind, rpm, fa, fr, True, growth)
        out[name] = dict(external=ext, ours=ours, matched=matched)
        title = f"{'paper' if kind == 'paper' else '218'} {rpm:.0f} rpm, Fa {fa / 1e3:g} kN, Fr {fr / 1e3:g} kN"
        if ext:
            lines.append(row(title, f"external (u_i {ext['ring_growth_um']:.1f} µm)", ext))
        lines.append(row(title, "ours, matched" + ("" if matched["converged"] else " (flag: not converged)"), matched))
        lines.append(row(title, "ours" + ("" if ours["converged"] else " (flag: not converged)"), ours))
    print("\n".join(lines))
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
