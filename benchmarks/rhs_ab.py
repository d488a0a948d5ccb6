"""A/B of one right-hand side (issue 21, speed): the value and the cost, part by part, of the code
on PYTHONPATH at fixed running states, for comparing two checkouts.

1. `states`: the running states — the paper steady rigid scene at t = 0.02 s (integrator tolerance
   1e-4, as the scene), the paper unsteady flexible scene (26 modes) at t = 0.02 s (tolerance
   1e-6), and the rigid scene under the EHL film-shear law (`rigid_ehl`: model option traction_law
   = "ehl", traction_scale 1.2, contact_temperature_rise 15 K) at t = 0.02 s — written to one .npz
   (make them once, with either checkout, and use them for both).
2. `measure`: at each state dy/dt and the work array of `flexbearing.multibody.dynamics.rhs`, and the CPU time
   per call of the whole rhs and of its parts (benchmarks.cost_model's compiled loops: contacts
   with and without traction, pockets, guide land, drag, floating frame; minimum of `--repeats`
   repeats of ~0.02 s each), written to a .npz (values) and printed/appended as JSON (times).
3. `compare`: dy/dt of two `measure` outputs, per state-vector block and field (ball x, r, psi,
   ..., ring, cage, modal q, q'): max |new − old| / max |old| over the block's components.

Interleave the checkouts (the machine is shared; contention only adds time, take the minimum):

    PYTHONPATH=/tmp/old .venv/bin/python /tmp/old/benchmarks/rhs_ab.py states /tmp/ab/states.npz
    for i in 1 2 3; do
      PYTHONPATH=/tmp/old .venv/bin/python /tmp/old/benchmarks/rhs_ab.py measure /tmp/ab/states.npz /tmp/ab/old
      PYTHONPATH=. .venv/bin/python benchmarks/rhs_ab.py measure /tmp/ab/states.npz /tmp/ab/new
    done
    .venv/bin/python benchmarks/rhs_ab.py compare /tmp/ab/old.npz /tmp/ab/new.npz
    .venv/bin/python benchmarks/rhs_ab.py table /tmp/ab/old.jsonl /tmp/ab/new.jsonl
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

EHL = {"model.traction_law": "ehl", "model.traction_scale": 1.2, "model.contact_temperature_rise": 15.0}
# (label, scene, t, integrator tolerance, scene overrides)
SCENES = (("rigid", "paper_steady_rigid", 0.02, 1e-4, {}), ("flexible", "paper_unsteady", 0.02, 1e-6, {}),
          ("rigid_ehl", "paper_steady_rigid", 0.02, 1e-4, EHL))
PARTS = ("rhs_full_us", "contacts_us", "traction_slices_us", "pockets_us", "land_us", "drag_us",
         "floating_frame_us", "rest_us")


def _models():
    from benchmarks import cost_model as CM
    return {label: CM.scene_model(name, overrides) for label, name, _, _, overrides in SCENES}


def make_states(path):
    from benchmarks import cost_model as CM
    out = {}
    for label, name, t1, tol, overrides in SCENES:
        scene, be, model, y0 = CM.scene_model(name, overrides)
        y, h, n, cpu = CM.advance_to(scene, be, model, y0, 0.0, t1, tol=tol)
        out[f"{label}_y"] = y
        out[f"{label}_t"] = np.array(t1)
        print(f"{label}: {n} steps to t = {t1} s, {cpu:.1f} s CPU")
    np.savez(path, **out)


def parts(model, t, y, sp, ld, imp, repeats):
    """cost_model.split_parts without the switched-off and slice scans: µs per call of each part."""
    from benchmarks import cost_model as CM
    from flexbearing.multibody import dynamics as D
    from flexbearing.multibody import model as M
    from flexbearing.multibody.profiles import speed_at
    cpc = CM.cpu_per_call
    work = D.new_work(model)
    dydt = np.zeros_like(y)
    base = (t, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld, imp, work,
            model.cage)
    res = {}
    res["rhs_full_us"] = cpc(CM.loop_rhs, base, CM.calls_for(CM.loop_rhs, base), repeats) * 1e6
    D.rhs(*base)
    omega_i = speed_at(t, sp)
    a = (y, model.p, model.flags, model.hertz_table, model.traction_table, omega_i, work.copy())
    res["contacts_us"] = cpc(CM.loop_contacts, a, CM.calls_for(CM.loop_contacts, a), repeats) * 1e6
    fl = model.flags.copy()
    fl[M.F_TRACTION] = 0
    a0 = (y, model.p, fl, model.hertz_table, model.traction_table, omega_i, work.copy())
    res["contacts_no_traction_us"] = cpc(CM.loop_contacts, a0, CM.calls_for(CM.loop_contacts, a0), repeats) * 1e6
    res["traction_slices_us"] = res["contacts_us"] - res["contacts_no_traction_us"]
    a = (y, model.p, model.flags, model.cage, work.copy())
    res["pockets_us"] = cpc(CM.loop_pockets, a, CM.calls_for(CM.loop_pockets, a), repeats) * 1e6
    a = (y, model.p, model.flags)
    res["land_us"] = cpc(CM.loop_land, a, CM.calls_for(CM.loop_land, a), repeats) * 1e6
    a = (y, model.p, model.flags, work.copy())
    res["drag_us"] = cpc(CM.loop_drag, a, CM.calls_for(CM.loop_drag, a), repeats) * 1e6
    D.rhs(*base)
    zb = model.n_balls
    a = (y, dydt.copy(), model.p, model.cage, work[zb, M.WR_LAND_FY], work[zb, M.WR_LAND_FZ], work[zb, M.WR_LAND_M])
    res["floating_frame_us"] = cpc(CM.loop_cage_equations, a, CM.calls_for(CM.loop_cage_equations, a), repeats) * 1e6
    res["rest_us"] = res["rhs_full_us"] - sum(res[k] for k in ("contacts_us", "pockets_us", "land_us", "drag_us",
                                                                "floating_frame_us"))
    return res


def measure(states, out, repeats):
    from flexbearing.multibody import dynamics as D
    st = np.load(states)
    values = {}
    row = {"code": str(ROOT), "load": os.getloadavg()[0], "date": time.strftime("%H:%M:%S")}
    for label, (scene, be, model, _) in _models().items():
        y = st[f"{label}_y"].copy()
        t = float(st[f"{label}_t"])
        sp, ld, imp = scene.speed_table, scene.load_table, scene.impacts
        work = D.new_work(model)
        dydt = np.zeros_like(y)
        D.rhs(t, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld, imp, work,
              model.cage)
        values[f"{label}_dydt"] = dydt
        values[f"{label}_work"] = work
        values[f"{label}_nballs"] = np.array(model.n_balls)
        values[f"{label}_nmodes"] = np.array(model.n_modes)
        row[label] = parts(model, t, y, sp, ld, imp, repeats)
    np.savez(out + ".npz", **values)
    with open(out + ".jsonl", "a") as f:
        f.write(json.dumps(row) + "\n")
    for label in row:
        if isinstance(row[label], dict):
            print(label, " ".join(f"{k[:-3]} {row[label][k]:.2f}" for k in PARTS))


def blocks(z, nm):
    """(name, index array) of every field of the state vector (flexbearing.multibody.state_layout)."""
    from flexbearing.multibody import state_layout as SL
    out = []
    r0 = SL.ring_offset(z)
    for f, name in enumerate(("x", "r", "psi", "x'", "r'", "psi'", "w_x", "w_r", "w_t")):
        out.append((f"ball {name}", np.arange(f, r0, SL.BALL_STATE)))
    out.append(("ring pos", np.arange(r0, r0 + SL.RING_POSITIONS)))
    out.append(("ring vel", np.arange(r0 + SL.RING_POSITIONS, r0 + SL.RING_STATE)))
    c0 = SL.cage_offset(z)
    out.append(("cage pos", np.arange(c0, c0 + SL.CAGE_POSITIONS)))
    out.append(("cage vel", np.arange(c0 + SL.CAGE_POSITIONS, c0 + SL.CAGE_STATE)))
    m0 = SL.modal_offset(z)
    if nm:
        out.append(("modal q", np.arange(m0, m0 + nm)))
        out.append(("modal q'", np.arange(m0 + nm, m0 + 2 * nm)))
    return out


def compare(a, b):
    A = np.load(a)
    B = np.load(b)
    worst = 0.0
    for label in [s[0] for s in SCENES if f"{s[0]}_dydt" in A and f"{s[0]}_dydt" in B]:
        da, db = A[f"{label}_dydt"], B[f"{label}_dydt"]
        z, nm = int(A[f"{label}_nballs"]), int(A[f"{label}_nmodes"])
        print(f"{label} (state size {da.size}):")
        for name, idx in blocks(z, nm):
            scale = np.max(np.abs(da[idx]))
            d = np.max(np.abs(db[idx] - da[idx]))
            rel = d / scale if scale > 0 else d
            worst = max(worst, rel)
            print(f"  {name:10s} max|old| {scale:10.3e}  max|new-old| {d:9.2e}  rel {rel:8.1e}")
        wa, wb = A[f"{label}_work"], B[f"{label}_work"]
        sc = np.maximum(np.max(np.abs(wa), axis=0), 1e-300)
        rw = np.max(np.abs(wb - wa), axis=0) / sc
        print(f"  work array: max over columns of max|new-old|/max|old| {np.max(rw):.1e}")
    print(f"worst dy/dt block: {worst:.1e}")
    return worst


def table(a, b):
    """Minimum over the interleaved runs of each part, old → new."""
    ra = [json.loads(line) for line in Path(a).read_text().splitlines() if line.strip()]
    rb = [json.loads(line) for line in Path(b).read_text().splitlines() if line.strip()]
    labels = [s[0] for s in SCENES if all(s[0] in r for r in ra + rb)]
    print(f"runs: {len(ra)} old, {len(rb)} new; minimum over runs, and (max) (µs per call)")
    print("| part | " + " | ".join(f"{lb} old | {lb} new" for lb in labels) + " |")
    print("|---|" + "---:|" * (2 * len(labels)))
    for k in PARTS + ("contacts_no_traction_us",):
        vals = []
        for label in labels:
            for rows in (ra, rb):
                v = [r[label][k] for r in rows]
                vals.append(f"{min(v):.2f} ({max(v):.2f})")
        print(f"| {k[:-3]} | " + " | ".join(vals) + " |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("states", "measure", "compare", "table"))
    ap.add_argument("paths", nargs="+")
    ap.add_argument("--repeats", type=int, default=15)
    a = ap.parse_args(argv)
    if a.what == "states":
        make_states(a.paths[0])
    elif a.what == "measure":
        measure(a.paths[0], a.paths[1], a.repeats)
    elif a.what == "compare":
        compare(a.paths[0], a.paths[1])
    else:
        table(a.paths[0], a.paths[1])


if __name__ == "__main__":
    main()
