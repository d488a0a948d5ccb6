"""Screening of the race-control candidates over Table 5's 15 cases (issue 35, item 4).

For each candidate mechanism a physically bounded setting (docs/race_control.md gives the source
of every bound) is run through the steady solver (flexbearing.multibody.steady) on the 15 cases of
the seed paper's Table 5, and each case's slip is put beside the two race-control brackets at the
model's own contact angles (flexbearing.studies.validation.kinematics.brackets) and the measured slip.

    python benchmarks/race_control_screening.py [--state held|thrust] [--variants a,b] [--cases 1,6]
        [--out benchmarks/results/race_control_screening.json]
    python benchmarks/race_control_screening.py --markdown HELD.json [HELD2.json]   (the tables of docs/race_control.md)
    python benchmarks/race_control_screening.py --tnd7870                          (TN D-7870's 6 % as inner control)
    python benchmarks/race_control_screening.py --dynamics VARIANT 1,6,12 [OUT.json] (the dynamic validation with it)

--state held (default): `steady_held_cage_state` with weight and the radial load (the uncertainty
study's fast path, 2–60 s a case); thrust: `steady_thrust_state` under the axial load alone, no
weight (0.2–0.5 s a case; the radial load is left out, so only trends are read from it).

Per case it records: slip (the validation's definition, nm at the mean loaded angle), the mean
loaded contact angles, the ball's pitch beta (spin axis to bearing axis, in the cage frame), the
brackets, the loads and semi-major axes of both contacts, the load on the second (unloaded) inner
half, the mean pocket force, the spin at each contact (rad/s, relative to its race, along the
normal) and Jones's control ratio Q_i·a_i / (Q_o·a_o·cos(alpha_o − alpha_i)) (> 1: inner-race
control by Jones's criterion). The spin-resistance section (`spin_resistance`) evaluates the EHL
law's spin moment of each contact against spin on its own (flexbearing.multibody.traction).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from flexbearing.studies.validation import slip_rate as V
from flexbearing.studies.validation import kinematics as RC
from flexbearing.multibody import model as M
from flexbearing.multibody.steady import steady_held_cage_state, steady_thrust_state

# name -> (model options, oil-air fraction at 4000 rpm or None for the validation's, description)
VARIANTS = {
    "baseline": ({}, None, "the validation model (EHL law, free balls, X_ref 0.2 % falling as 1/n)"),
    "pocket_mu_0.1": ({"pocket_friction": 0.1}, None, "Coulomb pocket friction 0.1 (boundary-lubricated steel)"),
    "pocket_mu_0.3": ({"pocket_friction": 0.3}, None, "Coulomb pocket friction 0.3 (dry steel, upper bound)"),
    "cavity_oil_5pct": ({}, 0.05, "cavity oil 5 % at 4000 rpm (flooded under-race supply)"),
    "cavity_oil_20pct": ({}, 0.20, "cavity oil 20 % at 4000 rpm (upper bound)"),
    "ball_drag_moment": ({"ball_drag_moment": True}, None, "viscous drag moment on the spinning ball (new term)"),
    "ball_drag_moment_flooded": ({"ball_drag_moment": True}, 0.20, "drag moment with cavity oil 20 %"),
    # what it would take (a diagnostic factor, not physics): the inner contacts' spin moment x k
    "inner_spin_x3": ({"spin_moment_scale_inner": 3.0}, None, "inner spin moment x3 (diagnostic)"),
    "inner_spin_x10": ({"spin_moment_scale_inner": 10.0}, None, "inner spin moment x10 (diagnostic)"),
    "inner_spin_x30": ({"spin_moment_scale_inner": 30.0}, None, "inner spin moment x30 (diagnostic)"),
    "inner_spin_x100": ({"spin_moment_scale_inner": 100.0}, None, "inner spin moment x100 (diagnostic)"),
    # the third contact: more clearance unloads the second inner half (Pd = design + 60 um, the
    # uncertainty study's upper end), less loads it (Pd = design − 40 um)
    "clearance_plus_60um": ({}, None, "diametral clearance design + 60 um (third contact unloaded)"),
    "clearance_minus_40um": ({}, None, "diametral clearance design − 40 um (third contact loaded)"),
}
CLEARANCE_CHANGE = {"clearance_plus_60um": 60e-6, "clearance_minus_40um": -40e-6}


def pitch_angles(out: dict) -> np.ndarray:
    """Pitch beta of every ball's spin axis to the bearing axis, in the frame that orbits with it (rad)."""
    w = out["ball_angular_velocity"]
    rel_x = w[:, 0] - out["ball_orbit_speed"]
    return np.arctan2(np.abs(w[:, 1]), np.abs(rel_x))


def contact_spins(out: dict) -> tuple[np.ndarray, np.ndarray]:
    """Spin of the ball relative to the outer and to the more loaded inner race about the contact
    normal (rad/s), per ball: outer normal (sin a, cos a), inner (−sin a, −cos a) in (e_x, e_r)
    (flexbearing.multibody.dynamics), the inner race turning at omega_i about e_x."""
    w = out["ball_angular_velocity"]
    ang = out["contact_angle"]
    Q = out["contact_load"]
    ao = ang[:, 0]
    pick = np.where(Q[:, 1] >= Q[:, 2], 1, 2)
    ai = ang[np.arange(len(pick)), pick]
    s_o = w[:, 0] * np.sin(ao) + w[:, 1] * np.cos(ao)
    s_i = -(w[:, 0] - out["inner_ring_speed"]) * np.sin(ai) - w[:, 1] * np.cos(ai)
    return s_o, s_i


def case_row(case: dict, options: dict, oil_fraction_ref, state: str, clearance_change: float = 0.0) -> dict:
    from dataclasses import replace
    bearing = V.validation_bearing()
    if clearance_change:
        bearing = replace(bearing, radial_clearance=bearing.radial_clearance + clearance_change).validate()
    x_ref = V.VALIDATION_OIL_AIR_FRACTION if oil_fraction_ref is None else oil_fraction_ref
    oil = V.validation_oil(None, V.case_oil_air_fraction(x_ref, case["speed_rpm"], "inverse_speed"))
    opts = {**V.validation_model_options(), **options}
    omega = case["speed_rpm"] * 2.0 * math.pi / 60.0
    t0 = time.process_time()
    if state == "held":
        model = V.build_validation_model(bearing, oil, opts, "ehl", 1.0)
        _, info = steady_held_cage_state(model, omega, (case["axial_load"], 0.0, -case["radial_load"]), strict=False)
    else:
        model = V.build_validation_model(bearing, oil, {**opts, "gravity": 0.0}, "ehl", 1.0)
        _, info = steady_thrust_state(model, omega, case["axial_load"], strict=False)
    out = info["outputs"]
    Q = out["contact_load"]
    ang = np.abs(out["contact_angle"])
    ao = float(np.mean(np.abs(out["contact_angle_outer"])))
    ai = float(np.mean(np.abs(out["contact_angle_inner_loaded"])))
    ref = math.degrees(0.5 * (ao + ai))
    br = RC.brackets(case["speed_rpm"], bearing.ball_diameter, bearing.pitch_diameter, math.degrees(ai),
                     math.degrees(ao), ref)
    from flexbearing.multibody.dynamics import new_work  # noqa: F401  (the work array is not needed)
    q_o = float(np.mean(Q[:, 0]))
    q_i = float(np.mean(np.max(Q[:, 1:], axis=1)))
    q_third = float(np.max(np.min(Q[:, 1:], axis=1)))
    a_o, a_i = semi_major_axes(model, out)
    s_o, s_i = contact_spins(out)
    jones = q_i * a_i / (q_o * a_o * math.cos(ao - ai))
    return dict(case=case["case"], converged=bool(info["converged"]), slip_pct=100.0 * float(out["slip_rate"]),
                test_slip_pct=case["test_slip_pct"], inner_control_pct=br.inner_slip_percent,
                outer_control_pct=br.outer_slip_percent, alpha_o_deg=math.degrees(ao), alpha_i_deg=math.degrees(ai),
                beta_deg=math.degrees(float(np.mean(pitch_angles(out)))),
                beta_outer_control_deg=br.outer.pitch_angle_deg, beta_inner_control_deg=br.inner.pitch_angle_deg,
                q_outer=q_o, q_inner=q_i, q_third_contact_max=q_third, a_outer=a_o, a_inner=a_i,
                spin_outer=float(np.mean(s_o)), spin_inner=float(np.mean(s_i)), jones_ratio=jones,
                pocket_force_mean=float(np.mean(out["pocket_force"])), cpu_s=time.process_time() - t0,
                max_contact_angle_deg=float(np.degrees(ang.max())))


def semi_major_axes(model, out) -> tuple[float, float]:
    """Mean Hertz semi-major axes (m) of the outer and the more loaded inner contact (exact Hertz,
    flexbearing.multibody.hertz, at each ball's load and angle)."""
    from flexbearing.multibody.hertz import hertz_point_contact, race_curvature_radii
    p = model.p
    Q = out["contact_load"]
    ang = np.abs(out["contact_angle"])
    a_o, a_i = [], []
    for j in range(Q.shape[0]):
        k = 1 if Q[j, 1] >= Q[j, 2] else 2
        for c, inner, f, acc in ((0, False, p[M.P_FE], a_o), (k, True, p[M.P_FI], a_i)):
            rx, ry = race_curvature_radii(p[M.P_DW], p[M.P_DM], f, ang[j, c], inner)
            acc.append(hertz_point_contact(rx, ry, p[M.P_EBR], Q[j, c])[0] if Q[j, c] > 0 else 0.0)
    return float(np.mean(a_o)), float(np.mean(a_i))


def summary(rows: list[dict]) -> dict:
    ok = [r for r in rows if r["converged"]]
    err = [100.0 * abs(r["slip_pct"] - r["test_slip_pct"]) / r["test_slip_pct"] for r in ok]
    return dict(n=len(rows), converged=len(ok), mean_error_pct=float(np.mean(err)) if err else math.nan,
                max_error_pct=float(np.max(err)) if err else math.nan,
                right_sign=sum(1 for r in ok if r["slip_pct"] > 0.0),
                slip_range_pct=(min(r["slip_pct"] for r in ok), max(r["slip_pct"] for r in ok)) if ok else None)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--state", default="held", choices=["held", "thrust"])
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--cases", default=None)
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    cases = V.slip_rate_cases()
    if a.cases:
        keep = {int(c) for c in a.cases.split(",")}
        cases = [c for c in cases if c["case"] in keep]
    result = {"state": a.state, "command": "python benchmarks/race_control_screening.py " + " ".join(argv or sys.argv[1:]),
              "variants": {}}
    for name in a.variants.split(","):
        options, x_ref, text = VARIANTS[name]
        rows = []
        for c in cases:
            try:
                rows.append(case_row(c, options, x_ref, a.state, CLEARANCE_CHANGE.get(name, 0.0)))
            except Exception as exc:       # a failed solve is a row, not the end of the screening
                rows.append(dict(case=c["case"], converged=False, error=str(exc), test_slip_pct=c["test_slip_pct"]))
            r = rows[-1]
            if r.get("error"):
                print(f"{name:26s} case {r['case']:2d}  failed: {r['error']}", flush=True)
            else:
                print(f"{name:26s} case {r['case']:2d} {'ok ' if r['converged'] else 'NC '} slip {r['slip_pct']:+7.2f} "
                      f"(test {r['test_slip_pct']:+6.2f}; inner {r['inner_control_pct']:+6.2f} outer {r['outer_control_pct']:+6.2f}) "
                      f"a_o {r['alpha_o_deg']:5.1f} a_i {r['alpha_i_deg']:5.1f} beta {r['beta_deg']:5.1f} "
                      f"(outer {r['beta_outer_control_deg']:5.1f}) Jones {r['jones_ratio']:.2f} "
                      f"Q3 {r['q_third_contact_max']:.1f} N pocket {r['pocket_force_mean']:.2f} N {r['cpu_s']:.1f}s",
                      flush=True)
        s = summary([r for r in rows if not r.get("error")])
        print(f"{name}: {s}", flush=True)
        result["variants"][name] = {"description": text, "options": options, "oil_air_fraction_ref": x_ref,
                                    "rows": rows, "summary": s}
        if a.out:
            tmp = Path(a.out + ".part")
            tmp.write_text(json.dumps(result, indent=1, default=float) + "\n")
            tmp.replace(a.out)


if __name__ == "__main__" and not {"--markdown", "--tnd7870", "--dynamics"} & set(sys.argv):
    main()


# ------------------------------------------------------------------ what the test's slips ask of the balls
def contact_capacity(model, oil, out, ball: int = 0) -> dict:
    """EHL-law numbers of the outer and the more loaded inner contact of one ball at a steady state:
    load, semi-axes, peak pressure, rolling speed, the traction curve's maximum mu_max (uniform
    slip, flexbearing.multibody.traction.ehl_traction_curve), the spin moment at the operating spin
    (sliced_traction_ehl with du = spin·y) and the limiting-shear spin moment (3/8)·mu_max·Q·a·E(k)
    of Jones's Coulomb contact (E(k) the complete elliptic integral of the second kind, k² = 1 − b²/a²),
    which the slices carry without the E(k) factor (they take the spin's sliding along the rolling
    direction only)."""
    from scipy.special import ellipe
    from flexbearing.multibody import traction as TR
    from flexbearing.multibody.film import film_thickness
    from flexbearing.multibody.hertz import hertz_point_contact, race_curvature_radii
    p = model.p
    Q = out["contact_load"][ball]
    ang = np.abs(out["contact_angle"][ball])
    ur_all = np.abs(out["entrainment_speed"][ball])
    s_o, s_i = contact_spins(out)
    k_in = 1 if Q[1] >= Q[2] else 2
    res = {}
    for name, c, inner, f, spin in (("outer", 0, False, p[M.P_FE], s_o[ball]), ("inner", k_in, True, p[M.P_FI], s_i[ball])):
        rx, ry = race_curvature_radii(p[M.P_DW], p[M.P_DM], f, ang[c], inner)
        a, b, p0, _ = hertz_point_contact(rx, ry, p[M.P_EBR], Q[c])
        ur = max(ur_all[c], p[M.P_UMIN])
        slips = np.geomspace(1e-4, 0.5, 200)
        mu = TR.ehl_traction_curve(slips, Q[c], rx, ry, p[M.P_EBR], ur, oil, model.traction_table)
        h = film_thickness(rx, ry, p[M.P_EBR], Q[c], ur, oil.viscosity(), oil.pressure_viscosity_coeff)[1]
        law = TR.ehl_parameters(model.traction_table, oil.viscosity())
        _, _, m_spin = TR.sliced_traction_ehl(Q[c], a, b, p0, h, ur, 0.0, abs(spin), 0.0, 0.0, int(model.flags[M.F_NSLICES]),
                                              False, p[M.P_SLIN], law.eta_inlet, oil.pressure_viscosity_coeff,
                                              oil.thermal_conductivity, law.tau0, law.gamma_l, law.shear_modulus,
                                              law.k_solid, law.kappa_solid, law.beta_t)
        ek = float(ellipe(1.0 - (b / a) ** 2))
        res[name] = dict(Q=float(Q[c]), a=a, b=b, p0=p0, UR=ur, h=h, spin=float(spin), spin_roll=abs(spin) * a / ur,
                         mu_max=float(mu.max()), spin_moment=abs(m_spin),
                         spin_moment_limit=3.0 / 8.0 * float(mu.max()) * Q[c] * a * ek, ellipe=ek)
    return res


def demand_rows(held: dict) -> list[dict]:
    """Per case, from the held-state baseline rows: the pitch pure rolling needs for the test's slip
    at the model's contact angles, its gyroscopic couple and the friction coefficient that carries it
    (flexbearing.studies.gyroscopic_demand), beside the pitch, couple and friction of the model's
    own state and the EHL law's traction maximum at the two contacts."""
    from flexbearing.studies.gyroscopic_demand import gyroscopic_demand
    bearing = V.validation_bearing()
    rows = []
    for r, c in zip(held["rows"], V.slip_rate_cases()):
        if not r.get("converged"):
            continue
        args = (c["speed_rpm"], bearing.ball_diameter, bearing.pitch_diameter, bearing.ball_mass,
                math.radians(r["alpha_i_deg"]), math.radians(r["alpha_o_deg"]), r["q_outer"], r["q_inner"])
        test = gyroscopic_demand(c["test_slip_pct"], *args)
        inner = gyroscopic_demand(r["inner_control_pct"], *args)
        rows.append(dict(case=c["case"], test_pitch_deg=test.pitch_deg, test_couple=test.gyroscopic_couple,
                         test_mu=test.friction_needed, inner_pitch_deg=inner.pitch_deg,
                         inner_couple=inner.gyroscopic_couple, inner_mu=inner.friction_needed,
                         model_pitch_deg=r["beta_deg"]))
    return rows


def capacity_rows(cases=(1, 6, 12)) -> list[dict]:
    """`contact_capacity` of ball 0 (the most loaded azimuth is not needed: the numbers are for
    orders of magnitude) at the held-state baseline of `cases`, with the ball's drag moment
    (Stokes–Lamb, flexbearing.multibody.drag) and its rotational Reynolds number beside them."""
    from flexbearing.multibody.drag import ball_drag_moment_coefficient, oil_air_mixture
    bearing = V.validation_bearing()
    rows = []
    for c in V.slip_rate_cases():
        if c["case"] not in cases:
            continue
        oil = V.validation_oil(None, V.case_oil_air_fraction(V.VALIDATION_OIL_AIR_FRACTION, c["speed_rpm"], "inverse_speed"))
        model = V.build_validation_model(bearing, oil, V.validation_model_options(), "ehl", 1.0)
        omega = c["speed_rpm"] * 2.0 * math.pi / 60.0
        _, info = steady_held_cage_state(model, omega, (c["axial_load"], 0.0, -c["radial_load"]), strict=False)
        out = info["outputs"]
        cap = contact_capacity(model, oil, out)
        rho_mix, eta_mix = oil_air_mixture(oil.oil_air_fraction, oil.density, oil.viscosity())
        w = float(np.linalg.norm(out["ball_angular_velocity"][0]))
        m_drag = ball_drag_moment_coefficient(bearing.ball_diameter, eta_mix) * w
        m_drag_oil = ball_drag_moment_coefficient(bearing.ball_diameter, oil.viscosity()) * w
        rows.append(dict(case=c["case"], outer=cap["outer"], inner=cap["inner"], ball_spin=w, drag_moment=m_drag,
                         drag_moment_pure_oil=m_drag_oil,
                         reynolds_spin=rho_mix * w * (0.5 * bearing.ball_diameter) ** 2 / eta_mix,
                         pocket_force=float(out["pocket_force"][0])))
    return rows


def markdown(held_paths: list[str]) -> str:
    """The tables of docs/race_control.md from the held-state screening files."""
    variants = {}
    for path in held_paths:
        variants.update(json.loads(Path(path).read_text())["variants"])
    lines = ["| variant | converged | slip range, % | right sign | mean error, % | max error, % |", "|---|---:|---:|---:|---:|---:|"]
    for name, v in variants.items():
        s = v["summary"]
        lo, hi = s["slip_range_pct"]
        lines.append(f"| {name}: {v['description']} | {s['converged']}/{s['n']} | {lo:+.2f} … {hi:+.2f} | "
                     f"{s['right_sign']} | {s['mean_error_pct']:.1f} | {s['max_error_pct']:.1f} |")
    lines += ["", "| case | test % | inner control % | outer control % | steady % | alpha_o / alpha_i, deg | "
              "pitch beta model / outer ctl / inner ctl, deg | Jones ratio | third contact max, N |",
              "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in variants["baseline"]["rows"]:
        lines.append(f"| {r['case']} | {r['test_slip_pct']:+.2f} | {r['inner_control_pct']:+.2f} | {r['outer_control_pct']:+.2f} | "
                     f"{r['slip_pct']:+.2f} | {r['alpha_o_deg']:.1f} / {r['alpha_i_deg']:.1f} | "
                     f"{r['beta_deg']:.1f} / {r['beta_outer_control_deg']:.1f} / {r['beta_inner_control_deg']:.1f} | "
                     f"{r['jones_ratio']:.2f} | {r['q_third_contact_max']:.0f} |")
    lines += ["", "| case | pitch for the test slip, deg | its gyroscopic couple, N·m | friction needed | "
              "inner control: pitch, couple, friction |", "|---:|---:|---:|---:|---:|"]
    for d in demand_rows(variants["baseline"]):
        lines.append(f"| {d['case']} | {d['test_pitch_deg']:.1f} | {d['test_couple']:.3f} | {d['test_mu']:.3f} | "
                     f"{d['inner_pitch_deg']:.1f}°, {d['inner_couple']:.3f}, {d['inner_mu']:.3f} |")
    lines += ["", "| case | contact | Q, N | a, mm | p0, GPa | UR, m/s | spin, rad/s | spin·a/UR | mu_max (EHL law) | "
              "spin moment at the operating spin, N·m | (3/8)·mu_max·Q·a·E(k), N·m | h_c, um |", "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    caps = capacity_rows()
    for r in caps:
        for name in ("outer", "inner"):
            c = r[name]
            lines.append(f"| {r['case']} | {name} | {c['Q']:.0f} | {1e3 * c['a']:.2f} | {1e-9 * c['p0']:.2f} | {c['UR']:.1f} | "
                         f"{c['spin']:+.0f} | {c['spin_roll']:.3f} | {c['mu_max']:.3f} | {c['spin_moment']:.2e} | "
                         f"{c['spin_moment_limit']:.2e} | {1e6 * c['h']:.3f} |")
    lines += ["", "| case | ball spin, rad/s | Re_w | drag moment in the mixture, N·m | in pure oil, N·m | pocket force (ball 0), N |",
              "|---:|---:|---:|---:|---:|---:|"]
    for r in caps:
        lines.append(f"| {r['case']} | {r['ball_spin']:.0f} | {r['reynolds_spin']:.0f} | {r['drag_moment']:.1e} | "
                     f"{r['drag_moment_pure_oil']:.1e} | {r['pocket_force']:.2f} |")
    return "\n".join(lines)


if __name__ == "__main__" and "--markdown" in sys.argv:
    print(markdown([a for a in sys.argv[1:] if a != "--markdown"]))


def tnd7870_demand() -> list[tuple]:
    """NASA TN D-7870's 6 % skid at 25,000 rpm read as inner-race control (docs/race_control.md):
    over the corners of the declared geometry unknowns (scenes/validation/nasa_tnd7870.toml: pitch
    diameter 140–170 mm, ball 15–27 mm, free angle 16–24°, 15–30 balls; corners whose balls do not
    fit, Z·Dw > 0.9·pi·dm, left out), the symmetric split that inner control needs for 6 %
    (kinematics.split_for_slip), the pitch, the gyroscopic couple and the friction needed with
    steel balls at the series' largest thrust, 22,240 N: Q_i = F_a/(Z·sin a_i) and Q_o = Q_i plus the
    ball's centrifugal force at the epicyclic cage speed (a lower bound of the loads' sum, hence of
    the friction needed at that thrust: more at lighter thrust). Rows (dm, Dw, a0 deg, Z, split deg,
    pitch deg, couple N·m, friction, centrifugal N)."""
    import itertools
    from flexbearing.studies.gyroscopic_demand import gyroscopic_demand
    rows = []
    for dm, d, a0, z in itertools.product((0.140, 0.170), (0.015, 0.027), (16.0, 24.0), (15, 30)):
        if z * d > 0.9 * math.pi * dm:
            continue
        delta = RC.split_for_slip(25000.0, d, dm, a0, 6.0, "inner")
        ai, ao = a0 + delta, a0 - delta
        mb = 7800.0 * math.pi / 6.0 * d ** 3
        omega_c = 0.5 * 25000.0 * math.pi / 30.0 * (1.0 - d / dm * math.cos(math.radians(a0)))
        fc = mb * omega_c ** 2 * dm / 2.0
        qi = 22240.0 / (z * math.sin(math.radians(ai)))
        g = gyroscopic_demand(6.0, 25000.0, d, dm, mb, math.radians(ai), math.radians(ao), qi + fc, qi, math.radians(a0))
        rows.append((dm, d, a0, z, delta, g.pitch_deg, g.gyroscopic_couple, g.friction_needed, fc))
    return rows


if __name__ == "__main__" and "--tnd7870" in sys.argv:
    for row in tnd7870_demand():
        print(" ".join(f"{x:.4g}" for x in row))


def dynamics(variant: str, cases: list[int], out: str | None) -> list[dict]:
    """The dynamic slip-rate validation (flexbearing.studies.validation.slip_rate.run_slip_rate_validation, as
    `flexbearing validate slip-rate --cases ...`) with a screening variant's model options."""
    options, x_ref, _ = VARIANTS[variant]
    if x_ref is not None or variant in CLEARANCE_CHANGE:
        raise SystemExit(f"variant {variant}: only model-option variants run here")
    rows = V.run_slip_rate_validation(cases, options={**V.validation_model_options(), **options}, workers=1, quiet=True)
    for r in rows:
        print(f"{variant} case {r['case']:2d} slip {r['slip_pct']:+.2f} % (test {r['test_slip_pct']:+.2f}) "
              f"settled {r['settled']} t {r['t_end']:.2f} s", flush=True)
    if out:
        Path(out).write_text(json.dumps({"variant": variant, "options": options, "summary": V.summarise(rows),
                                         "rows": [{k: v for k, v in r.items() if k != "window_means"} for r in rows]},
                                        indent=1, default=float) + "\n")
    return rows


if __name__ == "__main__" and "--dynamics" in sys.argv:
    # python benchmarks/race_control_screening.py --dynamics VARIANT CASES [OUT.json]
    i = sys.argv.index("--dynamics")
    dynamics(sys.argv[i + 1], [int(c) for c in sys.argv[i + 2].split(",")], sys.argv[i + 3] if len(sys.argv) > i + 3 else None)
