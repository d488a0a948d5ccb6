"""Why the held cage's guide-land force grows with the axial load (paper §4.4.1 disagreement).

The axial-load study (benchmarks/results/study/README.md) finds the cage held at one azimuth in its
guide film at 55–65 kN, with the film force balancing the resultant of the pocket forces, and that
resultant (so the guiding force) growing with Fa, where the paper reports a falling guiding force.
This benchmark takes the mechanism apart on the paper bearing at 14,000 rpm, Fr 4 kN, rigid cage,
without impacts, at Fa 45–65 kN:

1. the frozen-azimuth held-cage state (`flexbearing.multibody.steady.steady_held_cage_state`): every ball's
   pocket force as a function of its azimuth psi, fitted by F_t(psi) = F0 + F1·cos(psi − phi1)
   (+ a second harmonic). All balls drive the cage against its drag (F0 < 0 on the balls); the
   first harmonic gives the pocket-force resultant on the cage, |R| = (Z/2)·F1 (sum over Z equally
   spaced balls of F1·cos(psi − phi1)·e_t(psi)), which the film must carry;
2. its cause: the balls in the loaded zone (psi = 270°, the radial load along −Z) have lower
   contact angles and touch the second inner half-groove (three-point contact), so they drive the
   cage less than the balls opposite; the size of that difference is the stiffness k with which
   the races' traction gears a ball to its kinematics (`orbital_traction_stiffness`) times the
   azimuthal variation of the orbital speed the races want (F1/k), and k grows with Fa (heavier
   contacts, less skid);
3. the dynamics integrated from that state (rigid cage, tolerance 1e-6) for `--duration` s and
   averaged over its last 40 %: the same harmonic fit on the balls' actual azimuths, the lag of
   the dynamic pattern behind the frozen one (phi1 dynamic − frozen), and the cage's held
   position and film force.

Run:  .venv/bin/python benchmarks/held_cage_mechanism.py [--duration 0.12] [--study-dir out/study/axial_load]
Writes benchmarks/results/held_cage_mechanism.{json,md}. About 1 min on 2 cores. With
--study-dir, the flexible-cage study runs' held window (0.36–0.40 s, uniform phase after the
second impact) is added for comparison (pocket resultant and film force only: those runs do not
record the balls' azimuths).
"""
from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

AXIAL_LOADS = (45e3, 50e3, 55e3, 60e3, 65e3)
RADIAL_LOAD = 4e3
RPM = 14000.0
RESULTS = Path(__file__).resolve().parent / "results"


def harmonic_fit(psi, force):
    """(F0, F1, phi1_deg, residual_rms): least-squares F = F0 + a1·cos psi + b1·sin psi
    + a2·cos 2psi + b2·sin 2psi, F1 = hypot(a1, b1), phi1 = atan2(b1, a1) (psi from +Y to +Z)."""
    psi = np.ravel(psi)
    force = np.ravel(force)
    basis = np.c_[np.ones_like(psi), np.cos(psi), np.sin(psi), np.cos(2 * psi), np.sin(2 * psi)]
    c = np.linalg.lstsq(basis, force, rcond=None)[0]
    rms = float(np.sqrt(np.mean((force - basis @ c) ** 2)))
    return float(c[0]), float(math.hypot(c[1], c[2])), float(math.degrees(math.atan2(c[2], c[1]))), rms


def orbital_traction_stiffness(model, y, omega, load, rel_step: float = 1e-4) -> np.ndarray:
    """k_j = −dF_t,j/dv_j (N per m/s): how much more tangential force the races exert against ball j
    when it orbits faster by dv with its spin held, F_t = m_b·r·psi'' and v = r·psi', so
    k = −m_b·d(psi''_j)/d(psi'_j). Central difference of step rel_step·omega_c on every ball's orbit
    speed and the cage speed together (the pocket's relative velocity, and so its hydrodynamic
    resistance, unchanged): the traction and churning response only. This is the stiffness with
    which the races gear a ball to its own kinematics; an azimuthal variation dv(psi) of the speed
    the races want the ball to orbit at becomes a pocket-force variation k·dv."""
    from flexbearing.multibody import dynamics as D
    from flexbearing.multibody import model as M
    from flexbearing.multibody import state_layout as SL

    z = model.n_balls
    c0 = M.state_layout(model)["cage"]
    speed_table = np.array([[0.0, omega]])
    load_table = np.array([[0.0, *load]])
    work, dydt = D.new_work(model), np.zeros_like(y)
    step = rel_step * abs(y[c0 + SL.CAGE_OMEGA])
    acc = []
    for sign in (1.0, -1.0):
        yy = y.copy()
        yy[SL.BALL_PSI_DOT:SL.ring_offset(z):SL.BALL_STATE] += sign * step
        yy[c0 + SL.CAGE_OMEGA] += sign * step
        D.rhs(0.0, yy, dydt, model.p, model.flags, model.hertz_table, model.traction_table, speed_table,
              load_table, np.zeros((0, 6)), work, model.cage)
        acc.append(dydt[SL.BALL_PSI_DOT:SL.ring_offset(z):SL.BALL_STATE].copy())
    return -model.p[M.P_MB] * (acc[0] - acc[1]) / (2.0 * step)


def run_dynamics(model, y, omega, load, duration, average_from):
    """Integrate from y (rigid cage, tolerance 1e-6), sample every 0.1 ms; return the balls'
    azimuths and tangential pocket forces, the cage centre, film force and pocket resultant over
    t >= average_from."""
    from flexbearing.multibody import outputs as O
    from flexbearing.multibody import model as M
    from flexbearing.multibody import state_layout as SL
    from flexbearing.multibody.integrator import Workspace, advance

    z = model.n_balls
    c0 = M.state_layout(model)["cage"]
    speed_table = np.array([[0.0, omega]])
    load_table = np.array([[0.0, *load]])
    impacts = np.zeros((0, 6))
    ws, t, h = Workspace(model), 0.0, 1e-7
    psi, ft, centre, land, resultant = [], [], [], [], []
    for k in range(1, int(round(duration / 1e-4)) + 1):
        y, t, h, _, _ = advance(model, y, t, k * 1e-4, speed_table, load_table, impacts, tol=1e-6, h=h, ws=ws)
        if t >= average_from - 1e-12:
            o = O.evaluate_outputs(model, t, y, speed_table, load_table, impacts)
            psi.append(y[SL.BALL_PSI:SL.ring_offset(z):SL.BALL_STATE].copy())
            ft.append(o["pocket_force_tangential"])
            centre.append(y[c0 + SL.CAGE_Y:c0 + SL.CAGE_Z + 1].copy())
            land.append(o["cage_land_force"])
            resultant.append(o["pocket_force_on_cage"].sum(axis=0))
    return (np.array(psi), np.array(ft), np.mean(centre, axis=0), np.mean(land, axis=0),
            np.mean(resultant, axis=0))


def study_held_window(study_dir: Path, index: int, window=(0.36, 0.40)):
    """Pocket resultant and film force (y, z) of the flexible study run `index` over `window`."""
    import h5py

    path = study_dir / f"axial_load_{index}.h5"
    if not path.exists():
        return None
    with h5py.File(path, "r") as f:
        o = f["outputs"]
        t = o["time"][:]
        w = (t >= window[0]) & (t <= window[1])
        return dict(pocket_resultant=o["pocket_force_on_cage"][w].sum(axis=1).mean(axis=0).tolist(),
                    land_force=o["cage_land_force"][w].mean(axis=0).tolist(),
                    centre=o["cage_centre"][w][:, 1:].mean(axis=0).tolist())


def main(argv=None) -> int:
    from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
    from flexbearing.multibody.model import P_CG, build_model
    from flexbearing.multibody.steady import steady_held_cage_state
    from flexbearing.multibody import state_layout as SL

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.12, help="dynamic run length, s (averaged over its last 40 %%)")
    ap.add_argument("--study-dir", type=Path, default=None, help="folder of the axial-load study runs (flexible cage)")
    ap.add_argument("--out", type=Path, default=RESULTS / "held_cage_mechanism")
    args = ap.parse_args(argv)
    model = build_model(PAPER_BEARING, PAPER_OIL, {})
    z = model.n_balls
    omega = RPM * math.pi / 30
    rows = []
    for i, fa in enumerate(AXIAL_LOADS):
        load = (fa, 0.0, -RADIAL_LOAD)
        t0 = time.perf_counter()
        y, info = steady_held_cage_state(model, omega, load, strict=False)
        t_frozen = time.perf_counter() - t0
        out = info["outputs"]
        psi0 = y[SL.BALL_PSI:SL.ring_offset(z):SL.BALL_STATE]
        f0, f1, phi1, rms = harmonic_fit(psi0, out["pocket_force_tangential"])
        t0 = time.perf_counter()
        psi_d, ft_d, centre_d, land_d, res_d = run_dynamics(model, y.copy(), omega, load, args.duration,
                                                            0.6 * args.duration)
        t_dyn = time.perf_counter() - t0
        g0, g1, gphi1, grms = harmonic_fit(psi_d, ft_d)
        row = dict(
            axial_load=fa,
            frozen=dict(converged=info["converged"], residual=info["residual"], wall_s=t_frozen,
                        cage_speed=info["cage_speed"], cage_centre_yz=info["cage_centre"][1:].tolist(),
                        eccentricity_ratio=info["cage_eccentricity_ratio"], land_force=info["cage_land_force"].tolist(),
                        pocket_resultant=info["pocket_resultant"].tolist(), pocket_mean=f0, pocket_harmonic=f1,
                        pocket_phase_deg=phi1, fit_rms=rms,
                        third_contact_load_mean=float(np.mean(out["contact_load"][:, 2])),
                        orbital_stiffness=float(np.mean(orbital_traction_stiffness(model, y, omega, load))),
                        slide_inner_mean=float(np.mean(np.abs(out["slide_ratio"][:, 1])))),
            dynamic=dict(wall_s=t_dyn, cage_centre_yz=centre_d.tolist(),
                         eccentricity_ratio=float(np.hypot(*centre_d) / model.p[P_CG]),
                         land_force=land_d.tolist(), pocket_resultant=res_d.tolist(), pocket_mean=g0,
                         pocket_harmonic=g1, pocket_phase_deg=gphi1, fit_rms=grms,
                         lag_deg=float((gphi1 - phi1 + 180.0) % 360.0 - 180.0)))
        if args.study_dir is not None:
            row["flexible_study"] = study_held_window(args.study_dir, i)
        rows.append(row)
        fr, dy = row["frozen"], row["dynamic"]
        print(f"Fa {fa / 1e3:.0f} kN: frozen F0 {fr['pocket_mean']:.2f} N F1 {fr['pocket_harmonic']:.2f} N at "
              f"{fr['pocket_phase_deg']:.0f} deg, |R| {np.hypot(*fr['pocket_resultant'][1:]):.1f} N, k "
              f"{fr['orbital_stiffness']:.1f} N/(m/s); dynamic F0 {dy['pocket_mean']:.2f} F1 {dy['pocket_harmonic']:.2f} "
              f"lag {dy['lag_deg']:.0f} deg |R| {np.hypot(*dy['pocket_resultant'][1:]):.1f} N ({t_frozen:.1f} + {t_dyn:.1f} s)")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    meta = dict(bearing="paper", rpm=RPM, radial_load=RADIAL_LOAD, cage="rigid", duration=args.duration,
                average_from=0.6 * args.duration, units="SI (N, m, deg for phases)")
    args.out.with_suffix(".json").write_text(json.dumps(dict(meta=meta, rows=rows), indent=1))
    args.out.with_suffix(".md").write_text(markdown(rows, meta))
    print(f"wrote {args.out.with_suffix('.json')} and .md")
    return 0


def markdown(rows, meta) -> str:
    z = 20
    lines = [f"# Held cage: pocket-force pattern against axial load (paper bearing, {meta['rpm']:.0f} rpm, "
             f"Fr {meta['radial_load'] / 1e3:.0f} kN, rigid cage)", "",
             "`.venv/bin/python benchmarks/held_cage_mechanism.py` (module docstring for the method). "
             "F_t(psi) = F0 + F1·cos(psi − phi1) + 2nd harmonic, on the balls (negative: the ball drives the cage); "
             f"the pocket resultant on the cage is (Z/2)·F1 = {z // 2}·F1 and the guide-land film carries it. "
             f"Dynamic: integrated from the frozen state for {meta['duration']:g} s, averaged from "
             f"{meta['average_from']:g} s.", "",
             "| Fa (kN) | k (N per m/s) | F1/k (m/s) | inner slide | 3rd-contact Q (N) | F0 frozen / dyn (N) | F1 frozen / dyn (N) "
             "| phi1 frozen / dyn (deg) | lag (deg) | film force frozen / dyn (N) | e/Cg frozen / dyn |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        fr, dy = r["frozen"], r["dynamic"]
        lines.append(
            f"| {r['axial_load'] / 1e3:.0f} | {fr['orbital_stiffness']:.1f} | {fr['pocket_harmonic'] / fr['orbital_stiffness']:.3f} "
            f"| {fr['slide_inner_mean']:.4f} | {fr['third_contact_load_mean']:.1f} "
            f"| {fr['pocket_mean']:.2f} / {dy['pocket_mean']:.2f} | {fr['pocket_harmonic']:.2f} / {dy['pocket_harmonic']:.2f} "
            f"| {fr['pocket_phase_deg']:.0f} / {dy['pocket_phase_deg']:.0f} | {dy['lag_deg']:.0f} "
            f"| {np.hypot(*fr['land_force']):.1f} / {np.hypot(*dy['land_force']):.1f} "
            f"| {fr['eccentricity_ratio']:.3f} / {dy['eccentricity_ratio']:.3f} |")
    if rows and rows[0].get("flexible_study"):
        lines += ["", "Flexible-cage axial-load study, held window 0.36–0.40 s (unsteady scene, after the second impact):", "",
                  "| Fa (kN) | pocket resultant (y, z) (N) | film force (y, z) (N) | rigid dynamic pocket resultant (y, z) (N) |",
                  "|---:|---:|---:|---:|"]
        for r in rows:
            s = r["flexible_study"]
            if s:
                pr, lf, rd = s["pocket_resultant"], s["land_force"], r["dynamic"]["pocket_resultant"]
                lines.append(f"| {r['axial_load'] / 1e3:.0f} | ({pr[1]:.1f}, {pr[2]:.1f}) | ({lf[0]:.1f}, {lf[1]:.1f}) "
                             f"| ({rd[1]:.1f}, {rd[2]:.1f}) |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    raise SystemExit(main())
