"""Force and torque budgets of the steady slip-rate cases (paper Table 5; flexbearing.studies.validation.slip_rate).

For one case: run the dynamic model (rigid cage) for `--t-run` s from the quasi-static start, then
average the recorded quantities over `--window` s (1 ms samples) and print what drives and what
brakes the balls and the cage:

* per contact (outer, loaded inner half): load Q, contact angle, p0, entrainment speed UR, slide
  ratio s = du/UR, rolling-direction traction T (on the ball, N) and T/Q, and the traction fit's
  plateau D and curve maximum at that load and speed (flexbearing.multibody.traction);
* per ball: churning drag, tangential pocket force, ball spin components in the orbiting frame;
* cage: land (Petroff) torque, pocket torque sum_j r·F_t, cage speed, nm, slip.

    nice -n 5 .venv/bin/python -m benchmarks.bench_slip_rate --case 1 --t-run 0.6 [--traction-law bounded]
    .venv/bin/python -m benchmarks.bench_slip_rate --tables [--oil-temperature 120]   (quasi-static, seconds)
"""
from __future__ import annotations

import argparse
import json
import math

import numpy as np

from flexbearing.studies.validation import kinematics as K, slip_rate as V
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import outputs as O
from flexbearing.multibody import integrator as I
from flexbearing.multibody import model as M
from flexbearing.multibody.initial import initial_state
from flexbearing.multibody.traction import traction_coefficients_table, traction_curve_maximum


def case_budget(case_no: int, t_run: float = 0.6, window: float = 0.05, oil_temperature_c=None,
                oil_air_fraction=None, traction_law=None, tol: float = 1e-5, traction_scale: float = 1.0) -> dict:
    case = [c for c in V.slip_rate_cases() if c["case"] == case_no][0]
    bearing = V.VALIDATION_BEARING
    oil = V.validation_oil(oil_temperature_c, oil_air_fraction)
    model = V.build_validation_model(bearing, oil, traction_law=traction_law, traction_scale=traction_scale)
    omega, y, sp, ld, imp = V.steady_case_start(model, case)
    ws = I.Workspace(model)
    t, h = 0.0, 1e-6
    y, t, h, _, _ = I.advance(model, y, t, t_run - window, sp, ld, imp, tol, h, ws)
    acc: dict = {}
    n = 0
    while t < t_run - 1e-12:
        y, t, h, _, _ = I.advance(model, y, t, min(t + 1e-3, t_run), sp, ld, imp, tol, h, ws)
        out = O.evaluate_outputs(model, t, y, sp, ld, imp)
        Q = out["contact_load"]
        pick = np.where(Q[:, 1] >= Q[:, 2], 1, 2)
        zi = np.arange(Q.shape[0])
        rows = {
            "Q_o": Q[:, 0], "Q_i": Q[zi, pick], "Q_i_other": Q[zi, 3 - pick],
            "alpha_o_deg": np.degrees(out["contact_angle"][:, 0]),
            "alpha_i_deg": np.degrees(np.abs(out["contact_angle"][zi, pick])),
            "p0_o": out["contact_stress"][:, 0], "p0_i": out["contact_stress"][zi, pick],
            "UR_o": np.abs(out["entrainment_speed"][:, 0]), "UR_i": np.abs(out["entrainment_speed"][zi, pick]),
            "s_o": out["slide_ratio"][:, 0], "s_i": out["slide_ratio"][zi, pick],
            "T_o": out["traction_force"][:, 0], "T_i": out["traction_force"][zi, pick],
            "drag": out["churning_drag"], "pocket_t": out["pocket_force_tangential"],
            "w_x": out["ball_angular_velocity"][:, 0], "w_r": out["ball_angular_velocity"][:, 1],
            "w_t": out["ball_angular_velocity"][:, 2],
        }
        for k, v in rows.items():
            acc[k] = acc.get(k, 0.0) + float(np.mean(v))
        for k in ("cage_land_torque", "cage_speed", "nominal_cage_speed", "slip_rate", "cage_eccentricity_ratio"):
            acc[k] = acc.get(k, 0.0) + float(out[k])
        n += 1
    res = {k: v / n for k, v in acc.items()}
    # traction fit at the mean inner and outer conditions
    p = model.p
    for c, kind in (("o", 0), ("i", 1)):
        q, ur = res[f"Q_{c}"], res[f"UR_{c}"]
        alpha = math.radians(res[f"alpha_{c}_deg"])
        rx = D._hertz_lookup(model.hertz_table, kind, math.cos(alpha))[4]
        A, B, C, Dd = traction_coefficients_table(q, max(ur, p[M.P_UMIN]), rx, p[M.P_EBR], p[M.P_ETA_TRACTION],
                                                  p[M.P_T0K], p[M.P_K0], model.traction_table)
        res[f"fit_D_{c}"] = Dd
        res[f"fit_mu_max_{c}"] = traction_curve_maximum(A, B, C, Dd)
        res[f"mu_eff_{c}"] = res[f"T_{c}"] / q if q > 0 else 0.0
    res["pocket_torque"] = -res["pocket_t"] * 0.5 * bearing.pitch_diameter * bearing.n_balls
    res.update(case=case_no, t_run=t_run, oil_temperature_c=oil.temperature_c,
               oil_air_fraction=oil.oil_air_fraction, traction_law=traction_law or V.VALIDATION_TRACTION_LAW,
               traction_scale=traction_scale)
    return res


def static_tables(oil_temperature_c: float = 120.0) -> str:
    """Quasi-static start of every case (flexbearing.multibody.initial): mean outer / loaded-inner contact load,
    angle, p0 and entrainment speed, the 4106 fit's plateau D and curve maximum at those contacts
    (the paper's fit, eta0 at 20 °C, T0 = oil temperature), and the slip of the pure-rolling cage
    speed for the same angles with a free ball (beta = 0), beta = alpha_o and beta = alpha_i
    (flexbearing.studies.validation.kinematics.pure_rolling_cage_speed_ratio), against nm at the mean angle."""
    oil = V.validation_oil(oil_temperature_c, 0.003)
    model = V.build_validation_model(V.VALIDATION_BEARING, oil, traction_law="fit")
    p = model.p
    dw, dm = p[M.P_DW], p[M.P_DM]
    lines = [f"quasi-static contacts, 4106 fit at T = {oil_temperature_c} C (eta0 of the fit 0.055 Pa s)",
             "| case | rpm | test % | Q_o N | Q_i N | a_o deg | a_i deg | p0_o GPa | p0_i GPa | fit D_o | fit max_o "
             "| fit D_i | fit max_i | S beta=0 % | S beta=a_o % | S beta=a_i % |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for c in V.slip_rate_cases():
        w = c["speed_rpm"] * math.pi / 30.0
        y = initial_state(model, w, c["axial_load"], c["radial_load"])
        out = O.evaluate_outputs(model, 0.0, y, np.array([[0.0, w]]),
                                 np.array([[0.0, c["axial_load"], 0.0, -c["radial_load"]]]), np.zeros((0, 6)))
        Q, ang = out["contact_load"], out["contact_angle"]
        zi = np.arange(Q.shape[0])
        pick = np.where(Q[:, 1] >= Q[:, 2], 1, 2)
        vals = []
        for kind, q, a, ur, p0 in ((0, Q[:, 0], ang[:, 0], out["entrainment_speed"][:, 0], out["contact_stress"][:, 0]),
                                   (1, Q[zi, pick], ang[zi, pick], out["entrainment_speed"][zi, pick],
                                    out["contact_stress"][zi, pick])):
            qm, am, um = float(np.mean(q)), float(np.mean(np.abs(a))), float(np.mean(np.abs(ur)))
            rx = D._hertz_lookup(model.hertz_table, kind, math.cos(am))[4]
            A, B, C, Dd = traction_coefficients_table(qm, um, rx, p[M.P_EBR], p[M.P_ETA_TRACTION], p[M.P_T0K],
                                                      p[M.P_K0], model.traction_table)
            vals.append((qm, am, float(np.mean(p0)), Dd, traction_curve_maximum(A, B, C, Dd)))
        ao, ai = vals[0][1], vals[1][1]
        nm = 0.5 * (1.0 - dw * math.cos(0.5 * (ao + ai)) / dm)
        s = [100.0 * (nm - K.pure_rolling_cage_speed_ratio(ao, ai, b, dw, dm)) / nm for b in (0.0, ao, ai)]
        lines.append(f"| {c['case']} | {c['speed_rpm']} | {c['test_slip_pct']:.2f} | {vals[0][0]:.0f} | {vals[1][0]:.0f} | "
                     f"{math.degrees(ao):.1f} | {math.degrees(ai):.1f} | {vals[0][2] / 1e9:.2f} | {vals[1][2] / 1e9:.2f} | "
                     f"{vals[0][3]:.4f} | {vals[0][4]:.4f} | {vals[1][3]:.4f} | {vals[1][4]:.4f} | "
                     f"{s[0]:.2f} | {s[1]:.2f} | {s[2]:.2f} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", type=int, nargs="+", default=[1])
    ap.add_argument("--t-run", type=float, default=0.6)
    ap.add_argument("--window", type=float, default=0.05)
    ap.add_argument("--oil-temperature", type=float, default=None)
    ap.add_argument("--oil-air-fraction", type=float, default=None)
    ap.add_argument("--traction-law", default=None, choices=[None, "fit", "bounded"])
    ap.add_argument("--traction-scale", type=float, default=1.0, help="diagnostic: multiply the traction curve")
    ap.add_argument("--json", default=None)
    ap.add_argument("--tables", action="store_true", help="print the quasi-static contact/fit/kinematics table and exit")
    a = ap.parse_args(argv)
    if a.tables:
        print(static_tables(120.0 if a.oil_temperature is None else a.oil_temperature))
        return
    allres = []
    for c in a.case:
        r = case_budget(c, a.t_run, a.window, a.oil_temperature, a.oil_air_fraction, a.traction_law,
                        traction_scale=a.traction_scale)
        allres.append(r)
        print(f"case {c} ({r['traction_law']}, T {r['oil_temperature_c']} C, X {r['oil_air_fraction']}, "
              f"{r['t_run']} s): slip {100 * r['slip_rate']:.2f} %  cage {r['cage_speed']:.1f} rad/s  nm {r['nominal_cage_speed']:.1f}")
        for c2 in ("o", "i"):
            print(f"  {c2}: Q {r[f'Q_{c2}']:.1f} N  alpha {r[f'alpha_{c2}_deg']:.1f} deg  p0 {r[f'p0_{c2}'] / 1e9:.3f} GPa  "
                  f"UR {r[f'UR_{c2}']:.2f} m/s  s {r[f's_{c2}']:+.4f}  T {r[f'T_{c2}']:+.3f} N  T/Q {r[f'mu_eff_{c2}']:+.4f}  "
                  f"fit D {r[f'fit_D_{c2}']:.4f}  fit mu_max {r[f'fit_mu_max_{c2}']:.4f}")
        print(f"  inner other half Q {r['Q_i_other']:.1f} N; drag {r['drag']:+.3f} N/ball; pocket F_t {r['pocket_t']:+.3f} N/ball; "
              f"w (x, r, t) {r['w_x']:.0f}, {r['w_r']:.1f}, {r['w_t']:.1f} rad/s")
        print(f"  cage: land torque {r['cage_land_torque']:+.4f} N m, pocket torque {r['pocket_torque']:+.4f} N m, "
              f"eps {r['cage_eccentricity_ratio']:.3f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(allres, f, indent=2, default=float)


if __name__ == "__main__":
    main()
