"""The uncertainty study's report: the terminal summary, the markdown report with its plain
statement, the analysis as JSON and the bands figure (the paper's Fig. 15(a) with bands), from the
numbers of flexbearing.studies.uncertainty.analyse.

    <directory>/slip_rate_uncertainty.md, .json, .png         (write_report)
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from flexbearing.studies.uncertainty import candidate_points, mean_error_pct
from flexbearing.studies.validation.slip_rate import slip_rate_cases


def _fmt_point(p: dict) -> str:
    return (f"shim {p['shim_angle']:.1f}°, Pd + {1e6 * p['clearance_excess']:.0f} um, oil {p['oil_temperature']:.0f} °C, "
            f"traction ×{p['traction_scale']:.2f}, X_ref {100 * p['oil_air_fraction']:.2f} %, {p['ball_material']}")


def extra_point_errors(analysis: dict, complete_only: bool = True) -> dict:
    """{point name: (mean error %, slips % by case, number of cases in the mean)} of the extra
    points: with all 15 cases converged, or (complete_only False) over the converged cases."""
    test = np.array(analysis["test_slip_pct"])
    out = {}
    for name, by_case in analysis["extra_points"].items():
        ks = sorted((int(k) for k, r in by_case.items() if r["converged"]))
        if not ks or (complete_only and len(ks) < len(test)):
            continue
        s = np.array([(by_case.get(k) or by_case[str(k)])["slip_pct"] for k in ks])
        out[name] = (float(mean_error_pct(s, test[np.array(ks) - 1])), s.tolist(), len(ks))
    return out


def summary_text(analysis: dict) -> str:
    """Plain-text summary of `analyse` for the terminal."""
    a = analysis
    lines = [f"{a['n_converged']}/{a['n_runs']} (point, case) converged; {a['n_complete']}/{a['n_points']} points complete",
             f"test slips inside their 5-95 % band: {a['test_inside']}/15; paper's simulation: {a['paper_inside']}/15"]
    for b in a["bands"]:
        lines.append(f"  case {b['case']:2d}: band {b['q05']:7.2f} .. {b['q95']:6.2f} %  (median {b['q50']:6.2f}; "
                     f"test {b['test_slip_pct']:5.2f}, paper {b['paper_slip_pct']:5.2f}){'  inside' if b['test_inside'] else ''}")
    if a.get("best_sample_point"):
        lines.append(f"best sample point: mean error {a['best_sample_point']['mean_error_pct']:.1f} % "
                     f"({_fmt_point(a['best_sample_point'])}); paper's simulation {a['paper_mean_error_pct']:.1f} %")
    for name, (e, _, n) in extra_point_errors(a, complete_only=False).items():
        lines.append(f"point {name}: mean error {e:.1f} % over its {n} converged cases")
    if a.get("sensitivity"):
        me = a["sensitivity"]["mean error"]
        lines.append("total Sobol' index of the mean error: " +
                     ", ".join(f"{n} {v['ST']:.2f}" for n, v in sorted(me.items(), key=lambda kv: -kv[1]["ST"])))
    return "\n".join(lines)


REPORT_STEM = "slip_rate_uncertainty"


DECISIVE_ST = 0.1          # an unknown "matters" when its total index on the mean error is at least this


def report_markdown(analysis: dict, command: str = "", fast_path_check: str = "") -> str:
    """The report (benchmarks/results/slip_rate_uncertainty.md): unknowns, bands, indices, best
    points and the plain statement. fast_path_check: a markdown section on the steady fixed point
    against the dynamic validation (`fast_path_table`)."""
    a = analysis
    L = ["# Slip rate under the test bearing's unknown inputs", ""]
    if command:
        L += ["Reproduce (resumable; rows in out/uncertainty/<name>/rows.jsonl):", "", f"    {command}", ""]
    L += [f"{a['n_points']} scrambled Sobol' points of the unknowns below × Table 4's 15 cases, each the steady "
          f"fixed point with weight (flexbearing.multibody.steady.steady_held_cage_state, EHL law; flexbearing.studies.uncertainty "
          f"docstring). Converged: {a['n_converged']}/{a.get('n_ran', a['n_runs'])} (point, case) runs; points with all 15 cases: "
          f"{a['n_complete']}/{a['n_points']}. Slips in %, S = (nm − nc)/nm.", "",
          *([f"**Partial study**: {a['n_ran']} of {a['n_runs']} (point, case) runs had finished when this "
             "report was written (`--report-only`); the bands and indices are over those.", ""]
            if a.get("n_ran", a["n_runs"]) < a["n_runs"] else []),
          "## The unknowns (scenes/slip_rate_unknowns.toml has the reasons in full)", "",
          "| unknown | range | nominal (validation default) | why (first sentence) |", "|---|---|---|---|"]
    for u in a["unknowns"]:
        nom = u["nominal"] if isinstance(u["nominal"], str) else f"{u['nominal'] * (1e6 if u['unit'] == 'm' else 1):g}"
        L.append(f"| {u['name']} | {u['range']} | {nom} | {u.get('reason', '').split('. ')[0].replace(chr(10), ' ')}. |")
    if fast_path_check:
        L += ["", fast_path_check]
    L += ["", "## Bands per case (the paper's Fig. 15(a) with bands: slip_rate_uncertainty.png)", "",
          "| case | Fa/Fr N | rpm | test % | paper % | nominal point % | 5 % | median | 95 % | min | max | test inside |",
          "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    cases = {c["case"]: c for c in slip_rate_cases()}
    nominal = a["extra_points"].get("nominal", {})
    for b in a["bands"]:
        c = cases[b["case"]]
        nom = nominal.get(b["case"]) or nominal.get(str(b["case"]))
        nom_s = "—" if not nom else (f"{nom['slip_pct']:.2f}" + ("" if nom["converged"] else " (not conv.)"))
        L.append(f"| {b['case']} | {c['axial_load']:.0f}/{c['radial_load']:.0f} | {c['speed_rpm']} | {b['test_slip_pct']:.2f} | "
                 f"{b['paper_slip_pct']:.2f} | {nom_s} | {b['q05']:.2f} | {b['q50']:.2f} | {b['q95']:.2f} | {b['min']:.2f} | "
                 f"{b['max']:.2f} | {'yes' if b['test_inside'] else 'no'} |")
    L += ["", f"**Test points inside their 5–95 % band: {a['test_inside']} of 15** (the paper's simulated slips: "
              f"{a['paper_inside']} of 15). Bands over the converged points of each case "
              f"({min(b['n_converged'] for b in a['bands'])}–{max(b['n_converged'] for b in a['bands'])} of {a['n_points']})."]
    conv = a.get("convergence")
    if conv:
        L += ["", "## Where the fast path does not converge", "",
              "Converged fraction per case: " + ", ".join(f"{c}: {100 * v:.0f} %" for c, v in
                                                          conv["converged_fraction_by_case"].items()) + ".",
              "Failure rate of the (point, case) runs in the lower / upper half of each unknown's range: " +
              "; ".join(f"{n} {100 * v['fail_lower_half']:.0f} / {100 * v['fail_upper_half']:.0f} %"
                        for n, v in conv["fail_rate_by_unknown"].items()) + ".",
              "A run that does not converge is left out of its case's band and surrogate; where that happens "
              "in one part of the box, the bands there rest on fewer points (no fixed point with a held cage: "
              "the dynamics there whirl or drift, flexbearing.multibody.steady docstring)."]
    L += ["", "## Mean error against the test", ""]
    if a["best_sample_point"]:
        bp = a["best_sample_point"]
        errs = sorted(q["mean_error_pct"] for q in a["per_point"] if q["complete"])
        L.append(f"Over the {len(errs)} complete sample points the mean relative error runs from {errs[0]:.1f} % to "
                 f"{errs[-1]:.1f} % (median {float(np.median(errs)):.1f} %); the paper's simulation has "
                 f"{a['paper_mean_error_pct']:.1f} %. Best sample point (point {bp['point']}): **{bp['mean_error_pct']:.1f} %** "
                 f"at {_fmt_point(bp)}; its slips: "
                 + ", ".join(f"{s:.2f}" for s in bp["slips_pct"]) + ".")
    extra = extra_point_errors(a, complete_only=False)
    if a["surrogate_best"]:
        L += ["", "The surrogate's minimum of the mean error over the box (2^14 Sobol' points per ball material), "
                  "then re-run with the model:", "",
              "| ball | point | surrogate mean error % | model mean error % (converged cases) |", "|---|---|---:|---:|"]
        for c, named in zip(a["surrogate_best"], candidate_points(a)):
            got = extra.get(named["point"])
            L.append(f"| {c['ball_material']} | {_fmt_point(c)} | {c['surrogate_mean_error_pct']:.1f} | "
                     f"{'not run' if got is None else f'{got[0]:.1f} ({got[2]} of 15)'} |")
    if a["sensitivity"]:
        f = a["surrogate_fit"]
        L += ["", "## Variance-based sensitivity (Sobol' indices on a quadratic surrogate)", "",
              f"Surrogate: a quadratic in the unit coordinates per case, least squares on the points where that "
              f"case converged ({min(f['n_points'])}–{max(f['n_points'])} of {a['n_points']}): the full quadratic "
              f"({f['n_terms']['all']} terms) where there are at least twice as many points, else squares and the "
              f"ball material's interactions only ({f['n_terms']['choice']} terms; cases "
              f"{', '.join(str(c) for c, m in zip(f['cases'], f['forms']) if m == 'choice') or 'none'}), else "
              f"linear and squares only ({f['n_terms']['none']} terms, additive: S = ST; cases "
              f"{', '.join(str(c) for c, m in zip(f['cases'], f['forms']) if m == 'none') or 'none'}); cases left out "
              f"(fewer than {2 * f['n_terms']['none']} converged points): {', '.join(map(str, f['left_out'])) or 'none'}. "
              f"The mean error here is over the {len(f['cases'])} cases with a surrogate. Leave-one-out error of the slip: "
              f"{min(f['loo_rms_pct_points']):.2f}–{max(f['loo_rms_pct_points']):.2f} points rms against a sample "
              f"spread (std) of {min(f['sample_std_pct_points']):.2f}–{max(f['sample_std_pct_points']):.2f} points "
              f"(LOO R² {min(f['r2_loo']):.3f}–{max(f['r2_loo']):.3f}); of the mean error: "
              f"{f['mean_error_loo_rms_pct'] if f['mean_error_loo_rms_pct'] is not None else float('nan'):.1f} % rms "
              f"(on the complete points). Indices: Saltelli first order S and Jansen total ST on "
              f"2^13 × (d + 2) surrogate evaluations; brackets: bootstrap 95 % intervals (sample points "
              f"resampled and the surrogate refitted, design rows resampled; 200 replicates).", ""]
        names = [u["name"] for u in a["unknowns"]]
        L += ["| output | " + " | ".join(f"{n}: S / ST" for n in names) + " |",
              "|---|" + "---|" * len(names)]
        for out, by in a["sensitivity"].items():
            cells = [f"{by[n]['S']:.2f} [{by[n]['S_lo']:.2f}, {by[n]['S_hi']:.2f}] / {by[n]['ST']:.2f} "
                     f"[{by[n]['ST_lo']:.2f}, {by[n]['ST_hi']:.2f}]" for n in names]
            L.append(f"| {out} | " + " | ".join(cells) + " |")
    L += ["", "## What the data allow", ""] + statement(a)
    return "\n".join(L) + "\n"


def statement(a: dict) -> list[str]:
    """The plain statement of the report, from the numbers of `analyse`."""
    out = []
    if a["sensitivity"]:
        me = a["sensitivity"]["mean error"]
        ranked = sorted(me.items(), key=lambda kv: -kv[1]["ST"])
        matter = [n for n, v in ranked if v["ST_lo"] >= DECISIVE_ST]
        out.append(f"- **Which unknowns matter** (total index of the mean error over the {len(a['surrogate_fit']['cases'])} "
                   f"cases with a surrogate, lower 95 % limit ≥ {DECISIVE_ST}): " + (", ".join(f"{n} (ST {me[n]['ST']:.2f})" for n in matter) or "none")
                   + "; the rest: " + ", ".join(f"{n} {v['ST']:.2f}" for n, v in ranked if n not in matter) + ".")
    best = a["best_sample_point"]
    extra = extra_point_errors(a, complete_only=False)
    found = [(best["mean_error_pct"], f"sample point {best['point']}")] if best else []
    found += [(e, f"{name}, over its {n} converged cases") for name, (e, _, n) in extra.items() if name != "nominal"]
    if found:
        e, where = min(found)
        reach = "reaches" if e <= 7.0 else "does not reach"
        out.append(f"- **The paper's 7 % mean error**: the best point found ({where}) has {e:.1f} %, so the "
                   f"sampled box {reach} it with this model" + ("" if e <= 7.0 else
                   " (the surrogate's minimum, re-run above, is the search over the whole box)") + ".")
    inside = a["test_inside"]
    out.append(f"- **Bands**: {inside} of 15 test slips lie inside the 5–95 % band of their case.")
    if a["sensitivity"]:
        top = max(a["sensitivity"]["mean error"].items(), key=lambda kv: kv[1]["ST"])[0]
        out.append(f"- **The measurement that would decide it**: the unknown with the largest total index, {top} "
                   f"({MEASUREMENT.get(top, 'measure it')}).")
    return out


MEASUREMENT = {
    "ball_material": "the ball material of the test bearing: a magnet or the bearing's part number settles it",
    "shim_angle": "the shim angle of the split inner ring: measured contact angle under a light thrust, or the "
                  "inner-ring drawing",
    "clearance_excess": "the mounted radial clearance (or the axial play) of the test bearing",
    "oil_temperature": "the oil temperature at the bearing's outer ring / oil outlet during each case",
    "traction_scale": "a traction curve of 4106 oil on a ball-on-disc rig at 0.5–0.7 GPa, 4–25 m/s",
    "oil_air_fraction": "the oil flow rate and jet geometry of the rig (the cavity's oil content)",
}


def write_report(analysis: dict, directory, command: str = "") -> list[Path]:
    """<directory>/slip_rate_uncertainty.md, .json (the analysis) and .png (the bands figure); the
    fast-path check of <directory>/slip_rate_uncertainty_check.json is tabulated if present."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    check = d / f"{REPORT_STEM}_check.json"
    fast_path_check = fast_path_table(json.loads(check.read_text())) if check.exists() else ""
    md = d / f"{REPORT_STEM}.md"
    js = d / f"{REPORT_STEM}.json"
    png = d / f"{REPORT_STEM}.png"
    md.write_text(report_markdown(analysis, command, fast_path_check))
    js.write_text(json.dumps(analysis, indent=1, default=_json_default) + "\n")
    plot_bands(analysis, png)
    return [md, js, png]


def _json_default(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.bool_):
        return bool(x)
    raise TypeError(type(x))


def plot_bands(analysis: dict, path) -> None:
    """The paper's Fig. 15(a) with bands: per case the 5–95 % band and median of the predicted slip,
    the test's and the paper's simulated slip, the nominal point; right: total Sobol' indices of the
    mean error with their 95 % intervals."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    a = analysis
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), gridspec_kw=dict(width_ratios=[2.2, 1]))
    ax = axes[0]
    x = np.array([b["case"] for b in a["bands"]])
    q05 = np.array([b["q05"] for b in a["bands"]])
    q50 = np.array([b["q50"] for b in a["bands"]])
    q95 = np.array([b["q95"] for b in a["bands"]])
    lo = np.array([b["min"] for b in a["bands"]])
    hi = np.array([b["max"] for b in a["bands"]])
    ax.vlines(x, lo, hi, color="0.75", lw=1, label="model: sample range")
    ax.bar(x, q95 - q05, bottom=q05, width=0.55, color="tab:blue", alpha=0.35, label="model: 5–95 % band")
    ax.plot(x, q50, "_", color="tab:blue", ms=14, mew=2, label="model: median")
    nom = a["extra_points"].get("nominal", {})
    if nom:
        xs = sorted(int(k) for k in nom)
        ax.plot(xs, [nom[k if k in nom else str(k)]["slip_pct"] for k in xs], "x", color="tab:blue",
                label="model: nominal point")
    ax.plot(x, a["test_slip_pct"], "o", color="k", label="test (Table 5)")
    ax.plot(x, a["paper_slip_pct"], "^", color="tab:red", mfc="none", label="paper's simulation (Table 5)")
    ax.axhline(0.0, color="0.5", lw=0.5)
    for g in (6.5, 11.5):                       # the load groups of Table 4
        ax.axvline(g, color="0.6", lw=0.5, ls=":")
    ax.set_xticks(x)
    ax.set_xlabel("case (Table 4: groups 1–6, 7–11, 12–15)")
    ax.set_ylabel("cage slip rate S, %")
    ax.set_title(f"Slip over the unknowns ({a['n_points']} points); test inside band: {a['test_inside']}/15")
    ax.legend(fontsize=7, loc="best")
    ax = axes[1]
    if a["sensitivity"]:
        me = a["sensitivity"]["mean error"]
        names = list(me)
        y = np.arange(len(names))
        st = np.array([me[n]["ST"] for n in names])
        s1 = np.array([me[n]["S"] for n in names])
        def err(v, key):                  # a bootstrap interval need not contain the estimate
            return np.clip([v - [me[n][f"{key}_lo"] for n in names], [me[n][f"{key}_hi"] for n in names] - v], 0, None)
        ax.barh(y + 0.2, st, 0.4, xerr=err(st, "ST"), color="tab:orange", label="total ST")
        ax.barh(y - 0.2, s1, 0.4, xerr=err(s1, "S"), color="tab:green", label="first order S")
        ax.set_yticks(y)
        ax.set_yticklabels(names, fontsize=8)
        ax.set_xlabel("Sobol' index of the mean error (95 % bootstrap)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def fast_path_table(check: dict) -> str:
    """Markdown section: the steady fixed point against the dynamic validation run, from the rows of
    benchmarks/uncertainty_fast_path_check.py ({"rows": [...]})."""
    rows = [r for r in check.get("rows", []) if r.get("steady_converged")]
    if not rows:
        return ""
    diff = np.array([r["steady_slip_pct"] - r["dynamic_slip_pct"] for r in rows])
    L = ["## The fast path against the dynamic validation (the independent check)", "",
         "Steady fixed point with weight (this study's model) against the dynamic run settled from the "
         "same inputs (flexbearing.studies.validation.slip_rate.run_slip_case); `benchmarks/uncertainty_fast_path_check.py`, "
         "rows in slip_rate_uncertainty_check.json.", "",
         "| point | case | dynamic % | settled | steady % | steady − dynamic, points |", "|---|---:|---:|---|---:|---:|"]
    for r in rows:
        L.append(f"| {r['point']} | {r['case']} | {r['dynamic_slip_pct']:.2f} | {r['dynamic_settled']} | "
                 f"{r['steady_slip_pct']:.2f} | {r['steady_slip_pct'] - r['dynamic_slip_pct']:+.2f} |")
    L += ["", f"Agreement over {len(rows)} pairs: mean difference {diff.mean():+.2f} points, largest "
              f"{np.abs(diff).max():.2f} points (rms {np.sqrt(np.mean(diff ** 2)):.2f})."]
    not_conv = [r for r in check.get("rows", []) if not r.get("steady_converged")]
    if not_conv:
        L.append("Not converged on the fast path (left out of the bands), with the dynamic run's slip: " +
                 ", ".join(f"point {r['point']} case {r['case']}: {r['dynamic_slip_pct']:.2f} % "
                           f"({'settled' if r['dynamic_settled'] else 'not settled'})" for r in not_conv) + ".")
    return "\n".join(L)
