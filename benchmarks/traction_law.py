"""The EHL film-shear traction law against the paper's 4106 fit (issue 25): curves, cost, attitude.

Run: nice -n 5 .venv/bin/python benchmarks/traction_law.py [--skip-attitude]
Writes benchmarks/results/traction_law.json, traction_law_curves.png (mu(s) at the slip-rate
test's contacts, cases 1 and 6 at the validation oil state, and at the paper's steady scene, the
fit beside each) and traction_law_sweep.png (the no-dead-zone sweep), and prints:
* the contacts' conditions (load, p0, rolling speed, film) and each curve's slope at s = 0, its
  maximum and the slip where it is reached;
* the cost of the traction of one contact (8 slices) inside a compiled loop, and of one call of
  the dynamics' right-hand side at case 1's quasi-static state, fit against EHL law;
* the attitude table of tests/test_attitude_independent.py (independent single-ball model,
  flexbearing.multibody.steady, dynamics) for cases 1 and 6 at mu = 0.03 and 0.1.
The markdown beside it (traction_law.md) is written by hand from this output.
"""
import argparse
import json
import math
import os
import sys
import time
from dataclasses import replace

import numpy as np
from numba import njit

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

from flexbearing.studies.validation import slip_rate as V  # noqa: E402
from flexbearing.multibody import dynamics as D  # noqa: E402
from flexbearing.multibody import outputs as O  # noqa: E402
from flexbearing.multibody import traction as T  # noqa: E402
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL  # noqa: E402
from flexbearing.multibody.film import film_thickness  # noqa: E402
from flexbearing.multibody.hertz import hertz_point_contact  # noqa: E402
from flexbearing.multibody.initial import initial_state  # noqa: E402
from flexbearing.multibody.model import build_model  # noqa: E402
from flexbearing.multibody import state_layout as SL  # noqa: E402

SLIPS = np.concatenate([[0.0], np.geomspace(1e-5, 1.0, 241)])


def contacts_of(model, case, oil):
    """Outer and loaded-inner contact of ball 0 at the quasi-static start of a case (no radial
    load): (label, Q, Rx, Ry, UR)."""
    omega = case["speed_rpm"] * math.pi / 30.0
    y = initial_state(model, omega, case["axial_load"], 0.0)
    out = O.evaluate_outputs(model, 0.0, y, np.array([[0.0, omega]]),
                             np.array([[0.0, case["axial_load"], 0.0, 0.0]]), np.zeros((0, 6)))
    rows = []
    work = D.new_work(model)
    dydt = np.zeros_like(y)
    D.rhs(0.0, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table,
          np.array([[0.0, omega]]), np.array([[0.0, case["axial_load"], 0.0, 0.0]]), np.zeros((0, 6)), work, model.cage)
    from flexbearing.multibody import model as M
    q = out["contact_load"][0]
    k_in = 1 if q[1] >= q[2] else 2
    for name, k in (("outer", 0), ("inner", k_in)):
        c = M.W_C0 + k * M.N_WC
        rows.append((name, float(q[k]), float(work[0, c + M.WC_RX]), float(work[0, c + M.WC_RY]),
                     abs(float(work[0, c + M.WC_UR]))))
    return rows


def curve_row(label, q, rx, ry, ur, oil, e_eff):
    tab = T.ehl_traction_table(oil.viscosity_temperature_coeff)
    mu = T.ehl_traction_curve(SLIPS, q, rx, ry, e_eff, ur, oil, tab)
    A, B, C, D_ = T.traction_coefficients(q, ur, rx, e_eff, PAPER_OIL.viscosity(PAPER_OIL.temperature_ref_c),
                                          oil.temperature_k, oil.thermal_conductivity)
    fit = np.array([T.traction_coefficient(s, A, B, C, D_) for s in SLIPS])
    a, b, p0, _ = hertz_point_contact(rx, ry, e_eff, q)
    h = film_thickness(rx, ry, e_eff, q, ur, oil.viscosity(), oil.pressure_viscosity_coeff)[1]
    k = int(np.argmax(mu))
    dead = SLIPS[np.argmax(fit > 0.0)] if np.any(fit > 0.0) else float("nan")
    return {"contact": label, "Q_N": q, "p0_GPa": p0 / 1e9, "UR_m_s": ur, "oil_C": oil.temperature_c,
            "film_um": h * 1e6, "ehl_slope_at_0": float(mu[1] / SLIPS[1]), "ehl_max": float(mu[k]),
            "ehl_s_at_max": float(SLIPS[k]), "ehl_mu_at_0.01": float(np.interp(0.01, SLIPS, mu)),
            "ehl_mu_at_0.1": float(np.interp(0.1, SLIPS, mu)), "fit_max": float(fit.max()),
            "fit_s_at_max": float(SLIPS[int(np.argmax(fit))]), "fit_zero_below_s": float(dead),
            "curve_ehl": mu.tolist(), "curve_fit": fit.tolist()}


@njit(cache=True)
def loop_fit(n):
    s = 0.0
    for i in range(n):
        A, B, C, D_ = T.traction_coefficients(200.0 + i % 5, 18.6, 0.0097, 2.3e11, 0.055, 423.0, 0.0966)
        tx, ty, mz = T.sliced_traction(200.0, 1.2e-3, 18.6, 0.05 + 1e-3 * (i % 3), -400.0, 0.0, 0.3,
                                       A, B, C, D_, 8, True, 2e-3)
        s += tx
    return s


@njit(cache=True)
def loop_ehl(n, eta_in, tau0, gamma_l, g_mod, k_solid, kappa_solid, beta_t):
    s = 0.0
    for i in range(n):
        h = film_thickness(0.0097, 0.2, 2.3e11, 200.0 + i % 5, 18.6, 9e-4, 1.85e-8)[1]
        tx, ty, mz = T.sliced_traction_ehl(200.0, 1.2e-3, 2.0e-4, 0.6e9, h, 18.6, 0.05 + 1e-3 * (i % 3), -400.0,
                                           0.0, 0.3, 8, True, 2e-3, eta_in, 1.85e-8, 0.0966, tau0, gamma_l, g_mod,
                                           k_solid, kappa_solid, beta_t)
        s += tx
    return s


def cost():
    law = T.ehl_parameters(T.ehl_traction_table(PAPER_OIL.viscosity_temperature_coeff), 9e-4)
    args = (law.eta_inlet, law.tau0, law.gamma_l, law.shear_modulus, law.k_solid, law.kappa_solid, law.beta_t)
    loop_fit(10)
    loop_ehl(10, *args)
    n = 200_000
    res = {}
    for name, f in (("fit", lambda: loop_fit(n)), ("ehl", lambda: loop_ehl(n, *args))):
        best = min(_timed(f) for _ in range(5))
        res[f"contact_{name}_ns"] = best / n * 1e9
    case = V.slip_rate_cases()[0]
    omega = case["speed_rpm"] * math.pi / 30.0
    for law in ("fit", "ehl"):
        model = V.build_validation_model(V.VALIDATION_BEARING, V.validation_oil(None, None), None, law)
        y = initial_state(model, omega, case["axial_load"], case["radial_load"])
        args = (model.p, model.flags, model.hertz_table, model.traction_table, np.array([[0.0, omega]]),
                np.array([[0.0, case["axial_load"], 0.0, -case["radial_load"]]]), np.zeros((0, 6)),
                D.new_work(model), model.cage)
        dydt = np.zeros_like(y)
        D.rhs(0.0, y, dydt, *args)
        m = 5000
        best = min(_timed(lambda: [D.rhs(0.0, y, dydt, *args) for _ in range(m)]) for _ in range(5))
        res[f"rhs_{law}_us"] = best / m * 1e6
    return res


def _timed(f):
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def attitude_table():
    sys.path.insert(0, os.path.join(HERE, "..", "tests"))
    import test_attitude_independent as A
    from flexbearing.multibody import integrator as I
    from flexbearing.multibody.steady import steady_thrust_state
    rows = []
    for case_no, mu0 in A.CASES:
        case = V.slip_rate_cases()[case_no - 1]
        ref = A.independent_state(case, mu0)[0]
        omega = case["speed_rpm"] * math.pi / 30.0
        row = {"case": case_no, "mu": mu0, "beta_independent": A.pitch_deg(ref[3], ref[4], ref[5]),
               "cage_independent": ref[3]}
        for ns in (8, A.N_SLICES):
            model = A._model(mu0, ns)
            y0 = initial_state(model, omega, case["axial_load"], 0.0)
            for j in range(model.n_balls):
                o = SL.ball_offset(j)
                y0[o + SL.BALL_X], y0[o + SL.BALL_R] = ref[0], ref[1]
                y0[o + SL.BALL_PSI_DOT:o + SL.BALL_W_T + 1] = ref[3:7]
            y0[SL.ring_offset(model.n_balls) + SL.RING_X] = ref[2]
            y0[SL.cage_offset(model.n_balls) + SL.CAGE_OMEGA] = ref[3]
            y_s, info = steady_thrust_state(model, omega, case["axial_load"], y_start=y0, strict=False)
            row[f"beta_steady_{ns}"] = A.pitch_deg(y_s[SL.BALL_PSI_DOT], y_s[SL.BALL_W_X], y_s[SL.BALL_W_R])
            row[f"cage_steady_{ns}"] = info["cage_speed"]
            if ns == A.N_SLICES:
                sp, ld = np.array([[0.0, omega]]), np.array([[0.0, case["axial_load"], 0.0, 0.0]])
                y_d, *_ = I.advance(model, y_s.copy(), 0.0, 0.02, sp, ld, np.zeros((0, 6)), 1e-6, 1e-7, I.Workspace(model))
                z = model.n_balls
                row["beta_dynamics"] = float(np.mean([A.pitch_deg(*y_d[SL.ball_offset(j) + SL.BALL_PSI_DOT:SL.ball_offset(j) + SL.BALL_W_R + 1])
                                                      for j in range(z)]))
                row["cage_dynamics"] = float(np.mean(y_d[[SL.ball_offset(j) + SL.BALL_PSI_DOT for j in range(z)]]))
        rows.append(row)
        print(row)
    return rows


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 3, figsize=(14, 8), sharex=True)
    for ax, r in zip(axes.ravel(), rows):
        ax.semilogx(SLIPS[1:], r["curve_ehl"][1:], label="EHL film-shear law")
        ax.semilogx(SLIPS[1:], r["curve_fit"][1:], "--", label="paper's 4106 fit (Wang, Yang & Wang 2004)")
        ax.set_title(f"{r['contact']}\nQ {r['Q_N']:.0f} N, p0 {r['p0_GPa']:.2f} GPa, UR {r['UR_m_s']:.1f} m/s, "
                     f"{r['oil_C']:.0f} °C", fontsize=9)
        ax.set_ylabel("traction coefficient mu")
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("slide/roll ratio s")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def sweep(path):
    """The no-dead-zone sweep of tests/test_traction_ehl.py (loads 30–8000 N, UR 1–60 m/s, oil
    20–200 °C, outer and inner race of the paper bearing): slope at s = 0, slip of the maximum and
    the maximum, and a figure of the curves."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from flexbearing.multibody.hertz import effective_modulus, race_curvature_radii
    e_eff = effective_modulus(210e9, 0.3, 210e9, 0.3)
    temps, loads, speeds = (20.0, 100.0, 200.0), (30.0, 200.0, 1500.0, 8000.0), (1.0, 10.0, 60.0)
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.5), sharey=True)
    rows = []
    for ax, tc in zip(axes, temps):
        oil = replace(PAPER_OIL, temperature_c=tc)
        tab = T.ehl_traction_table(oil.viscosity_temperature_coeff)
        for inner in (False, True):
            rx, ry = race_curvature_radii(0.022, 0.167, 0.52 if inner else 0.515, math.radians(35.0 if inner else 20.0), inner)
            for q in loads:
                for ur in speeds:
                    mu = T.ehl_traction_curve(SLIPS, q, rx, ry, e_eff, ur, oil, tab)
                    k = int(np.argmax(mu))
                    rows.append({"oil_C": tc, "inner": inner, "Q_N": q, "UR_m_s": ur, "slope_at_0": float(mu[1] / SLIPS[1]),
                                 "s_at_max": float(SLIPS[k]), "max": float(mu[k]),
                                 "monotone_to_max": bool(np.all(np.diff(mu[:k + 1]) > 0.0))})
                    if not inner:
                        ax.semilogx(SLIPS[1:], mu[1:], lw=1, color=f"C{loads.index(q)}",
                                    ls=("-", "--", ":")[speeds.index(ur)], label=f"{q:.0f} N, {ur:.0f} m/s")
        ax.set_title(f"EHL law, outer race (20°), oil {tc:.0f} °C", fontsize=9)
        ax.set_xlabel("slide/roll ratio s")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("traction coefficient mu")
    axes[-1].legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    summary = {"n": len(rows), "min_slope_at_0": min(r["slope_at_0"] for r in rows),
               "max_slope_at_0": max(r["slope_at_0"] for r in rows),
               "min_s_at_max": min(r["s_at_max"] for r in rows), "max_mu": max(r["max"] for r in rows),
               "all_monotone_to_max": all(r["monotone_to_max"] for r in rows)}
    print("sweep", summary)
    return {"summary": summary, "rows": rows}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skip-attitude", action="store_true")
    a = ap.parse_args()
    oil_v = V.validation_oil(None, None)
    model_v = V.build_validation_model(V.VALIDATION_BEARING, oil_v, {"gravity": 0.0})
    rows = []
    e_eff = model_v.p[19]
    for cn in (1, 6):
        case = V.slip_rate_cases()[cn - 1]
        for name, q, rx, ry, ur in contacts_of(model_v, case, oil_v):
            rows.append(curve_row(f"test case {cn}, {name} race", q, rx, ry, ur, oil_v, e_eff))
    model_p = build_model(PAPER_BEARING, PAPER_OIL, {})
    paper_case = {"axial_load": 55e3, "radial_load": 0.0, "speed_rpm": 14000}
    for name, q, rx, ry, ur in contacts_of(model_p, paper_case, PAPER_OIL):
        rows.append(curve_row(f"paper steady scene (thrust only), {name} race", q, rx, ry, ur, PAPER_OIL, e_eff))
    for r in rows:
        print({k: (round(v, 5) if isinstance(v, float) else v) for k, v in r.items() if not k.startswith("curve")})
    res = os.path.join(HERE, "results")
    out = {"slips": SLIPS.tolist(), "curves": rows, "sweep": sweep(os.path.join(res, "traction_law_sweep.png")),
           "cost": cost()}
    print(out["cost"])
    if not a.skip_attitude:
        out["attitude"] = attitude_table()
    plot(rows, os.path.join(res, "traction_law_curves.png"))
    with open(os.path.join(res, "traction_law.json"), "w") as f:
        json.dump(out, f, indent=1)
    print("wrote", os.path.join(res, "traction_law.json"), os.path.join(res, "traction_law_curves.png"))


if __name__ == "__main__":
    main()
