"""Every published test series of scenes/validation/ against the model (`flexbearing validate series`).

For each series file (flexbearing.studies.validation.series_file.load_series) and each of its points, the model's
steady state is computed with one parameter set for every series (`MODEL_PARAMETERS`; nothing is tuned
per case or per series) and set beside what the source measured; the declared unknowns of the series
give a band; the two race-control brackets are evaluated at the model's own operating contact angles;
the source's qualitative statements ([[checks]]) are checked where the model can compute the quantity.
`write_page` writes docs/validation.md from the rows (the page says how to reproduce it).

Model per point: the steady fixed point with weight, flexbearing.multibody.steady.steady_held_cage_state
(frozen azimuths, cage held in its guide film; the fast path of the uncertainty study, checked there
against the dynamics: rms 0.41 slip points over 20 pairs, benchmarks/results/slip_rate_uncertainty.md),
on the validation's model (flexbearing.studies.validation.slip_rate.build_validation_model: EHL film-shear traction,
gravity 9.81 m/s² along −z, free balls). Slip S = (n_m − n_c)/n_m with n_m at the mean loaded operating
contact angle (flexbearing.multibody.outputs, the slip-rate validation's definition). The dynamics
(`flexbearing validate slip-rate`, minutes per case) is the independent check; its recorded Table 5
slips (benchmarks/results/slip_rate_session14_ehl.json, the same bearing, oil and traction law) are shown
beside the steady ones.

The bearing of a series (`series_bearing`): the numbers the source gives; each declared unknown at its
nominal value (the paper preset's value where the series is the paper bearing, flexbearing.multibody.bearing;
otherwise the middle of the declared range) or at a sample of its range. What neither gives (groove radii,
cage proportions, pocket and land clearance of the NASA and 1979 bearings) is taken from the paper bearing
in proportion (the cross-section scaled with D_w about d_m): a declared approximation, printed in the page. Free contact angle,
shim angle and clearance are tied by flexbearing.multibody.clearance (a split ring given alpha0 and Pd gets
its shim angle from them; a combination that no shim angle gives is "infeasible" and left out of the band).
A series' bearing keeps the paper cage's outer-land guidance: the model has outer-land, inner-land and
ball guidance (flexbearing.mesh.cage_geometry.GUIDANCES), but the guidance a series states is not carried
into its bearing, so a series with an inner-land-guided cage is computed with an outer-land-guided one
(said in the page).

Band: `n_samples` scrambled Sobol' points (flexbearing.studies.uncertainty.unit_sample) of the series'
[[unknowns]] box, each point's steady state; the 5–95 % quantiles of the converged ones. Rows are
appended to OUT/rows.jsonl as they finish (resumable; a killed run loses at most the jobs in flight).
"""
from __future__ import annotations

import json
import math
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.studies.validation import kinematics as K, series_file as SF
from flexbearing.common.materials import ball_material_named
from flexbearing.multibody.clearance import resolve_inner_ring
from flexbearing.simulation.jobs import read_rows, run_jobs

# One parameter set for every series (module docstring): the slip-rate validation's model and oil state.
# Where a series publishes a value (oil inlet temperature, supply) that value is used instead.
MODEL_PARAMETERS = {
    "traction_law": "ehl", "traction_scale": 1.0, "gravity_m_s2": 9.81, "ball_attitude": "free",
    "oil_temperature_C": 150.0,          # slip_rate.VALIDATION_OIL_TEMPERATURE_C (unpublished)
    "cavity_oil_fraction_ref": 0.002,    # at 4000 rpm, falling as 1/n (flexbearing.multibody.oil_supply)
    "cavity_oil_reference_rpm": 4000.0,
}
# A thrust-free ball bearing has no defined steady state: a point whose thrust is only bounded below by
# 0 is sampled from this fraction of its upper bound.
MIN_THRUST_FRACTION = 0.05
DYNAMICS_RECORD = Path(__file__).resolve().parents[3] / "benchmarks" / "results" / "slip_rate_session14_ehl.json"


@dataclass(frozen=True)
class PointJob:
    """One steady solve: series file, point id, speed and loads, the unknowns' values, the sample
    index (−1: nominal) and the purpose ("point", or "check:<name>" for a check's extra state)."""
    series_path: str
    point_id: str
    speed_rpm: float
    axial_load: float
    radial_load: float
    values: dict
    sample: int
    purpose: str = "point"


# ------------------------------------------------------------------------------------- the bearing
def _given(vs: SF.ValidationSeries, key: str):
    q = vs.bearing.get(key)
    return None if q is None or q.value is None else q.value


def _is_paper_bearing(vs: SF.ValidationSeries) -> bool:
    from flexbearing.multibody.bearing import PAPER_BEARING as P
    return (_given(vs, "pitch_diameter") == P.pitch_diameter and _given(vs, "ball_diameter") == P.ball_diameter
            and _given(vs, "n_balls") == P.n_balls)


def nominal_values(vs: SF.ValidationSeries) -> dict:
    """The unknowns at their nominal values (module docstring): the paper preset's where the series is
    the paper bearing and the preset has the quantity, else the middle of the range."""
    from flexbearing.multibody.bearing import PAPER_BEARING as P
    preset = {}
    if _is_paper_bearing(vs):
        preset = {"free_contact_angle_deg": math.degrees(P.free_contact_angle),
                  "diametral_clearance": P.radial_clearance, "cage_pocket_clearance": P.pocket_clearance,
                  "cage_land_clearance": P.guide_land_diameter - P.cage.outside_diameter,
                  "oil_inlet_temperature_C": MODEL_PARAMETERS["oil_temperature_C"]}
    out = {}
    for u in vs.unknowns:
        v = preset.get(u.name)
        out[u.name] = v if v is not None and u.low <= v <= u.high else 0.5 * (u.low + u.high)
    return out


def sample_values(vs: SF.ValidationSeries, n: int, seed: int = 35) -> list[dict]:
    """n scrambled Sobol' points of the series' unknowns box (uniform in each range)."""
    from flexbearing.studies.sensitivity import unit_sample
    if not vs.unknowns or n < 1:
        return []
    u = unit_sample(n, len(vs.unknowns), seed)
    return [{k.name: k.low + float(row[j]) * (k.high - k.low) for j, k in enumerate(vs.unknowns)} for row in u]


def series_bearing(vs: SF.ValidationSeries, values: dict):
    """The model's Bearing of a series at the unknowns' `values` (module docstring); InputError if the
    combination is not a bearing (e.g. a free contact angle no shim angle gives with that clearance)."""
    from flexbearing.multibody.bearing import PAPER_BEARING as P

    def get(key, default=None):
        v = _given(vs, key)
        return values.get(key, default) if v is None else v

    dm, dw = get("pitch_diameter"), get("ball_diameter")
    if dm is None or dw is None:
        raise InputError(f"{vs.series.id}: pitch_diameter and ball_diameter must be given or declared unknown")
    # the cross-section in proportion to the ball (widths and radial offsets from d_m scale with D_w)
    s = dw / P.ball_diameter
    bore = get("bore", dm - (P.pitch_diameter - P.bore_diameter) * s)
    od = get("outside_diameter", 2.0 * dm - bore)
    width = get("width", P.width * s)
    fe = get("outer_groove_curvature", P.fe)
    fi = get("inner_groove_curvature", P.fi)
    cq = vs.bearing.cage.quantities if vs.bearing.cage is not None else {}

    def cage_get(key, default):
        q = cq.get(key)
        if q is not None and q.value is not None:
            return q.value
        return values.get(f"cage_{key}", default)

    c_od = cage_get("outside_diameter", dm + (P.cage.outside_diameter - P.pitch_diameter) * s)
    c_bore = cage_get("bore", dm + (P.cage.bore_diameter - P.pitch_diameter) * s)
    c_width = cage_get("width", P.cage.width * s)
    cp = cage_get("pocket_clearance", P.pocket_clearance * dw / P.ball_diameter)
    land = cage_get("land_clearance", (P.guide_land_diameter - P.cage.outside_diameter) * s)
    pocket = dw + 2.0 * cp
    # as many balls as given, else the paper's fill (Z·Dw/(pi·dm)), never more than the cage's bore
    # chord lets pockets of this size stand side by side
    z_max = int(math.floor(math.pi / math.asin(min(1.0, 0.5 * pocket / (0.5 * c_bore))))) - 1
    z = get("n_balls", P.n_balls * P.ball_diameter / P.pitch_diameter * dm / dw)
    z = int(max(3, min(round(z), z_max)))
    ring = vs.bearing.inner_ring or "one_piece"
    a0 = get("free_contact_angle_deg")
    pd = get("diametral_clearance")
    if ring == "one_piece" and a0 is not None:
        pd = None                       # the given angle wins; the clearance is derived from it
    layout = resolve_inner_ring(ring, fe, fi, dw, None if a0 is None else math.radians(a0), None,
                                pd if pd is not None or a0 is None else None)
    cage = replace(P.cage, outside_diameter=c_od, bore_diameter=c_bore, width=c_width, land_width=0.5 * c_width,
                   n_pockets=z, pocket_diameter=pocket, ball_diameter=dw)
    named = ball_material_named(vs.bearing.ball_material or "steel")
    b = replace(P, outside_diameter=od, bore_diameter=bore, width=width, pitch_diameter=dm, ball_diameter=dw,
                n_balls=z, fe=fe, fi=fi, inner_ring=ring, shim_angle=layout.shim_angle if ring == "split" else 0.0,
                radial_clearance=layout.diametral_clearance, guide_land_diameter=c_od + land, cage=cage,
                ball_material=named.material, ball_thermal=named.thermal)
    return b.validate()


def series_oil(vs: SF.ValidationSeries, values: dict, point: SF.Point | None = None):
    """The model's Oil of a series: the paper oil's properties where the series does not publish its
    own, the published inlet temperature (point, then oil section), else the unknown's value, else the
    parameter set's; the published supply (jet / under_race) with the parameter set's cavity fraction."""
    from flexbearing.multibody.bearing import PAPER_OIL
    changes = {}
    oq = vs.oil.quantities if vs.oil is not None else {}
    for key, field in (("density", "density"), ("pressure_viscosity_coefficient", "pressure_viscosity_coeff"),
                       ("thermal_conductivity", "thermal_conductivity"),
                       ("viscosity_temperature_coefficient_per_C", "viscosity_temperature_coeff")):
        q = oq.get(key)
        if q is not None and q.value is not None:
            changes[field] = q.value
    t = None
    if point is not None and "oil_inlet_temperature_C" in point.conditions:
        t = point.conditions["oil_inlet_temperature_C"].value
    if t is None and oq.get("inlet_temperature_C") is not None:
        t = oq["inlet_temperature_C"].value
    if t is None:
        t = values.get("oil_inlet_temperature_C", MODEL_PARAMETERS["oil_temperature_C"])
    supply = vs.oil.supply if vs.oil is not None and vs.oil.supply in ("jet", "under_race") else "unspecified"
    return replace(PAPER_OIL, temperature_c=float(t), supply=supply,
                   oil_air_fraction=MODEL_PARAMETERS["cavity_oil_fraction_ref"],
                   oil_air_reference_rpm=MODEL_PARAMETERS["cavity_oil_reference_rpm"], **changes).validate()


# ------------------------------------------------------------------------------------- one job
def solve_point(job: PointJob) -> dict:
    """One job (top-level for Dask workers): the steady state of the series' bearing at the point's
    conditions; returns the row (slip %, cage and epicyclic speeds, operating contact angles, the two
    brackets at those angles, power loss, pocket and land forces, convergence, CPU seconds)."""
    from flexbearing.studies.validation import slip_rate as V
    from flexbearing.multibody.steady import steady_held_cage_state
    t0 = time.process_time()
    vs = SF.load_series(job.series_path)
    point = next((p for p in vs.points if str(p.id) == job.point_id), None)
    row = dict(series=vs.series.id, point=job.point_id, sample=job.sample, purpose=job.purpose,
               speed_rpm=job.speed_rpm, axial_load=job.axial_load, radial_load=job.radial_load,
               values=job.values, feasible=True, converged=False, reason="")
    try:
        bearing = series_bearing(vs, job.values)
        oil = series_oil(vs, job.values, point)
    except InputError as exc:
        row.update(feasible=False, reason=str(exc), cpu_s=time.process_time() - t0)
        return row
    options = V.validation_model_options(MODEL_PARAMETERS["ball_attitude"], "on", MODEL_PARAMETERS["gravity_m_s2"])
    model = V.build_validation_model(bearing, oil, options, MODEL_PARAMETERS["traction_law"],
                                     MODEL_PARAMETERS["traction_scale"])
    omega = job.speed_rpm * math.pi / 30.0
    try:
        _, info = steady_held_cage_state(model, omega, (job.axial_load, 0.0, -job.radial_load), strict=False)
    except Exception as exc:           # a failed solve is a row, not the end of the study
        row.update(reason=f"{type(exc).__name__}: {exc}", cpu_s=time.process_time() - t0)
        return row
    out = info["outputs"]
    ai = math.degrees(float(np.mean(np.abs(out["contact_angle_inner_loaded"]))))
    ao = math.degrees(float(np.mean(out["contact_angle_outer"])))
    nm = float(out["nominal_cage_speed"]) * 30.0 / math.pi
    row.update(converged=bool(info["converged"]), reason=info.get("reason", ""),
               slip_pct=100.0 * float(out["slip_rate"]), cage_speed_rpm=info["cage_speed"] * 30.0 / math.pi,
               epicyclic_rpm=nm, inner_contact_angle_deg=ai, outer_contact_angle_deg=ao,
               free_contact_angle_deg=math.degrees(bearing.free_contact_angle),
               power_loss_W=float(out["power_loss"]), pocket_force_max_N=float(np.max(out["pocket_force"])),
               cage_land_force_N=float(out["cage_land_force_magnitude"]),
               pitch_diameter=bearing.pitch_diameter, ball_diameter=bearing.ball_diameter, n_balls=bearing.n_balls)
    try:
        br = K.brackets(job.speed_rpm, bearing.ball_diameter, bearing.pitch_diameter, ai, ao,
                         reference_angle_deg=0.5 * (ai + ao))
        row.update(inner_control_slip_pct=br.inner_slip_percent, outer_control_slip_pct=br.outer_slip_percent)
    except InputError as exc:
        row.update(bracket_error=str(exc))
    row["cpu_s"] = time.process_time() - t0
    return row


# ------------------------------------------------------------------------------------- the jobs
def _condition(point: SF.Point, key: str, default: float = 0.0) -> tuple[float, float]:
    q = point.conditions.get(key)
    return (default, default) if q is None else q.span()


def point_jobs(vs: SF.ValidationSeries, n_samples: int, seed: int = 35) -> list[PointJob]:
    """The nominal job and the band's jobs of every point of a series. A speed given only as a range
    is taken at its upper end (the source's maxima are over the range); a load given only as a range,
    or declared unknown, is an unknown of the point (nominal: the middle; lower bound at least
    MIN_THRUST_FRACTION of the upper)."""
    jobs = []
    nominal = nominal_values(vs)
    samples = sample_values(vs, n_samples, seed)
    for p in vs.points:
        speed = _condition(p, "speed_rpm")[1]
        fa_lo, fa_hi = _condition(p, "axial_load")
        if "axial_load" not in p.conditions and vs.unknown("axial_load") is not None:
            fa_lo, fa_hi = vs.unknown("axial_load").low, vs.unknown("axial_load").high
        fa_lo = max(fa_lo, MIN_THRUST_FRACTION * fa_hi)
        fr = _condition(p, "radial_load")[0]
        for k, vals in [(-1, nominal)] + list(enumerate(samples)):
            fa = 0.5 * (fa_lo + fa_hi)
            if k >= 0 and "axial_load" in vals:
                fa = min(max(vals["axial_load"], fa_lo), fa_hi)
            jobs.append(PointJob(str(vs.path), str(p.id), speed, fa, fr, dict(vals), k))
    jobs += check_jobs(vs, nominal)
    return jobs


def check_jobs(vs: SF.ValidationSeries, nominal: dict) -> list[PointJob]:
    """Extra nominal states some checks need (`CHECKS`): a speed sweep and a load step."""
    jobs = []
    for spec in CHECKS.get(vs.series.id, ()):
        for speed, fa, fr in spec.get("states", ()):
            jobs.append(PointJob(str(vs.path), spec["point"], speed, fa, fr, dict(nominal), -1, f"check:{spec['name']}"))
    return jobs


# The qualitative statements the model can be checked against (series id -> specs). "states": extra
# nominal (speed rpm, Fa N, Fr N) the check needs; the evaluation is in `evaluate_checks`.
CHECKS = {
    "nasa_tnd7870": (
        {"name": "skid_at_most_6_percent", "kind": "magnitude", "point": "max_skid_25000rpm"},
        {"name": "skid_grows_with_speed", "kind": "trend", "point": "max_skid_25000rpm",
         "states": [(n, 11120.0, 0.0) for n in (10000.0, 15000.0, 20000.0)]},
        {"name": "power_speed_over_load", "kind": "trend", "point": "max_skid_25000rpm",
         "states": [(10000.0, 5560.0, 0.0), (10000.0, 16680.0, 0.0), (25000.0, 5560.0, 0.0)]},
    ),
    "yang2025_table5": (
        {"name": "slip_positive_everywhere", "kind": "sign", "point": "1"},
        {"name": "slip_grows_with_speed_falls_with_load", "kind": "trend", "point": "1"},
    ),
    "jlt1979_separator_forces": (
        {"name": "cage_forces_tens_of_newtons", "kind": "magnitude", "point": "to_12000rpm"},
    ),
    "nasa_tp1732": (
        {"name": "runs_at_2p5_million_DN", "kind": "magnitude", "point": "72000rpm"},
    ),
}


# ------------------------------------------------------------------------------------- running
def job_key(series: str, point: str, sample: int, purpose: str, speed_rpm: float, axial_load: float) -> str:
    """The identity of a job in the rows file."""
    return f"{series}|{point}|{sample}|{purpose}|{float(speed_rpm):.6g}|{float(axial_load):.6g}"


def _job_key(j: PointJob) -> str:
    return job_key(Path(j.series_path).stem, j.point_id, j.sample, j.purpose, j.speed_rpm, j.axial_load)


def _row_key(r: dict) -> str:
    return job_key(r["series"], r["point"], r["sample"], r["purpose"], r["speed_rpm"], r["axial_load"])


def run_series(out_dir, directory=SF.VALIDATION_DIR, n_samples: int = 16, series: list[str] | None = None,
               workers: int | None = None, scheduler: str | None = None, seed: int = 35,
               progress: bool = True) -> dict:
    """Every job of every series (or of the named ones) not yet in OUT_DIR/rows.jsonl, on Dask
    (flexbearing.simulation.jobs.run_jobs), each row appended and flushed as it finishes (resumable).
    Returns {"rows_file", "rows", "failures", "new_rows", "series"}."""
    if isinstance(n_samples, bool) or not isinstance(n_samples, int) or not 0 <= n_samples <= 4096:
        raise InputError(f"samples = {n_samples!r} is not allowed; allowed: an integer in [0, 4096]")
    all_series = SF.load_all(directory)
    known = [vs.series.id for vs in all_series]
    for name in series or ():
        if name not in known:
            raise InputError(f"series = {name!r} is not in {directory}; allowed: {', '.join(known)}")
    chosen = [vs for vs in all_series if series is None or vs.series.id in series]
    d = Path(out_dir)
    d.mkdir(parents=True, exist_ok=True)
    rows_file = d / "rows.jsonl"
    done = {_row_key(r) for r in read_rows(rows_file)}
    jobs = [j for vs in chosen for j in point_jobs(vs, n_samples, seed) if _job_key(j) not in done]
    # the slowest (fastest speeds) first, so that the workers finish together
    jobs.sort(key=lambda j: -j.speed_rpm)

    def on_result(k, row):
        with open(rows_file, "a") as f:
            f.write(json.dumps(row, default=float) + "\n")
            f.flush()
            os.fsync(f.fileno())

    names = [f"{Path(j.series_path).stem} {j.point_id} #{j.sample} {j.purpose}" for j in jobs]
    failures = run_jobs(solve_point, [(j,) for j in jobs], on_result, workers=workers, scheduler=scheduler,
                        names=names, description="validation series (point, sample)",
                        progress=progress) if jobs else []
    return dict(rows_file=str(rows_file), rows=read_rows(rows_file), failures=failures,
                new_rows=len(jobs) - len(failures), series=chosen)


# ------------------------------------------------------------------------------------- analysis
def _q(values, q):
    return float(np.quantile(values, q)) if len(values) else float("nan")


def _dynamics_slips() -> dict:
    """Table 5 slips of the dynamics as recorded (DYNAMICS_RECORD), by case, or {}."""
    try:
        rows = json.loads(DYNAMICS_RECORD.read_text())["rows"]
    except (OSError, ValueError, KeyError):
        return {}
    return {str(r["case"]): float(r["slip_pct"]) for r in rows}


def analyse(chosen: list[SF.ValidationSeries], rows: list[dict]) -> list[dict]:
    """Per series: per point the measured values, the nominal row, the band of the samples, the errors;
    the checks evaluated; counts (samples, converged, infeasible)."""
    dyn = _dynamics_slips()
    out = []
    for vs in chosen:
        mine = [r for r in rows if r["series"] == vs.series.id]
        pts = []
        for p in vs.points:
            pid = str(p.id)
            nominal = next((r for r in mine if r["point"] == pid and r["sample"] == -1 and r["purpose"] == "point"), None)
            samples = [r for r in mine if r["point"] == pid and r["sample"] >= 0 and r["purpose"] == "point"]
            ok = [r for r in samples if r.get("converged")]
            band = {k: (_q([r[k] for r in ok], 0.05), _q([r[k] for r in ok], 0.5), _q([r[k] for r in ok], 0.95))
                    for k in ("slip_pct", "inner_contact_angle_deg", "outer_contact_angle_deg", "power_loss_W",
                              "pocket_force_max_N", "cage_land_force_N", "inner_control_slip_pct",
                              "outer_control_slip_pct") if ok and all(k in r for r in ok)}
            measured = {k: q for k, q in p.measured.items()}
            entry = dict(point=pid, status=p.status, conditions={k: q.span() for k, q in p.conditions.items()},
                         measured={k: (q.value, q.span(), q.source) for k, q in measured.items()},
                         reported_model={k: q.value for k, q in p.reported_model.items()},
                         nominal=nominal, band=band, n_samples=len(samples), n_converged=len(ok),
                         n_infeasible=sum(not r.get("feasible", True) for r in samples),
                         positive_slips=sorted(r["slip_pct"] for r in ok if r["slip_pct"] > 0.0),
                         dynamics_slip_pct=dyn.get(pid) if vs.series.id == "yang2025_table5" else None)
            m = p.measured.get("measured_cage_slip_percent")
            if m is not None and m.value is not None and nominal and nominal.get("converged"):
                entry["slip_error_pct"] = 100.0 * abs(nominal["slip_pct"] - m.value) / abs(m.value)
                entry["slip_error_points"] = nominal["slip_pct"] - m.value
                lo, _, hi = band.get("slip_pct", (math.nan, math.nan, math.nan))
                entry["measured_in_band"] = bool(lo <= m.value <= hi) if not math.isnan(lo) else None
            pts.append(entry)
        out.append(dict(series=vs, points=pts, checks=evaluate_checks(vs, mine, pts)))
    return out


def _nominal_rows(rows, purpose):
    return [r for r in rows if r["purpose"] == purpose and r["sample"] == -1]


def evaluate_checks(vs: SF.ValidationSeries, rows: list[dict], pts: list[dict]) -> list[dict]:
    """[{name, kind, statement, verdict: pass/fail/not computed, computed: text}] for the series'
    CHECKS (the other [[checks]] are listed as not computable by this model)."""
    res = []
    by_point = {e["point"]: e for e in pts}
    for spec in CHECKS.get(vs.series.id, ()):
        name, verdict, text = spec["name"], "not computed", "no converged state"
        e = by_point.get(spec["point"])
        nom = e["nominal"] if e else None
        if name == "skid_at_most_6_percent" and nom and nom.get("converged"):
            s = nom["slip_pct"]
            verdict = "pass" if 0.0 <= s <= 6.0 else "fail"
            text = (f"nominal slip {s:+.2f} % (band {_band(e, 'slip_pct')} % over the unknowns); measured skid "
                    f"≤ 6 %, cage lagging")
        elif name == "skid_grows_with_speed":
            sweep = sorted((r["speed_rpm"], r["slip_pct"]) for r in _nominal_rows(rows, f"check:{name}")
                           if r.get("converged"))
            if len(sweep) >= 2:
                grows = all(b[1] > a[1] for a, b in zip(sweep, sweep[1:]))
                verdict = "pass" if grows and sweep[-1][1] > 0 else "fail"
                text = ", ".join(f"{n:.0f} rpm: {sl:+.2f} %" for n, sl in sweep) + " (nominal bearing, Fa 11.1 kN)"
        elif name == "power_speed_over_load":
            st = {(r["speed_rpm"], r["axial_load"]): r["power_loss_W"] for r in _nominal_rows(rows, f"check:{name}")
                  if r.get("converged")}
            try:
                p0, pl, ps = st[(10000.0, 5560.0)], st[(10000.0, 16680.0)], st[(25000.0, 5560.0)]
                verdict = "pass" if ps - p0 > pl - p0 > 0 else "fail"
                text = (f"power loss {p0:.0f} W at 10,000 rpm / 5.56 kN; tripled load {pl:.0f} W "
                        f"({pl - p0:+.0f} W); 2.5× speed {ps:.0f} W ({ps - p0:+.0f} W)")
            except KeyError:
                pass
        elif name == "slip_positive_everywhere":
            s = [x["nominal"]["slip_pct"] for x in pts if x["nominal"] and x["nominal"].get("converged")]
            if s:
                verdict = "pass" if min(s) > 0 else "fail"
                text = f"computed slips {min(s):+.2f} … {max(s):+.2f} % ({sum(v > 0 for v in s)}/{len(s)} positive)"
        elif name == "slip_grows_with_speed_falls_with_load":
            groups = {}
            for x in pts:
                if x["nominal"] and x["nominal"].get("converged"):
                    groups.setdefault(x["conditions"]["axial_load"][0], []).append(
                        (x["conditions"]["speed_rpm"][0], x["nominal"]["slip_pct"]))
            if groups:
                speed_ok = all(all(b[1] > a[1] for a, b in zip(sorted(g), sorted(g)[1:])) for g in groups.values())
                at = {fa: dict(g) for fa, g in groups.items()}
                loads = sorted(at)
                load_ok = all(at[a].get(n, -math.inf) > at[b].get(n, math.inf) for a, b in zip(loads, loads[1:])
                              for n in (4000, 5000, 6000, 8000) if n in at[a] and n in at[b])
                verdict = "pass" if speed_ok and load_ok else "fail"
                text = (f"grows with speed in every group: {speed_ok}; falls with load at equal speed: {load_ok}; "
                        + "; ".join(f"Fa {fa:.0f} N: " + ", ".join(f"{n:.0f}: {sl:+.2f}" for n, sl in sorted(g))
                                    for fa, g in sorted(groups.items())))
        elif name == "cage_forces_tens_of_newtons" and nom and nom.get("converged"):
            f_p, f_l = nom["pocket_force_max_N"], nom["cage_land_force_N"]
            # the abstract gives maxima over speeds to 12,000 rpm at an unstated load: only the order of
            # magnitude can be compared, both ways (a factor 10 either side)
            ok = all(0.1 * m <= f <= 10.0 * m for f, m in ((f_p, 25.0), (f_l, 20.0)))
            verdict = "pass" if ok else "fail"
            text = (f"nominal max pocket force {f_p:.1f} N (band {_band(e, 'pocket_force_max_N', '{:.1f}')}), "
                    f"land force {f_l:.1f} N (band {_band(e, 'cage_land_force_N', '{:.1f}')}); measured maxima 25 N "
                    f"and 20 N (pass: both within a factor 10 either way, the order of magnitude; steady states, "
                    f"not the dynamics' peaks)")
        elif name == "runs_at_2p5_million_DN" and e is not None:
            n_ok = e["n_converged"] + (1 if nom and nom.get("converged") else 0)
            verdict = "pass" if nom and nom.get("converged") else "fail"
            text = (f"steady state at 72,000 rpm converged: {bool(nom and nom.get('converged'))} (nominal); "
                    f"{n_ok} of {e['n_samples'] + 1} states with the samples"
                    + (f"; nominal slip {nom['slip_pct']:+.2f} %" if nom and nom.get("converged") else ""))
        res.append(dict(name=name, kind=spec["kind"], verdict=verdict, computed=text))
    return res


# ------------------------------------------------------------------------------------- the page
def _f(v, fmt="{:+.2f}"):
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else fmt.format(v)


def _band(e, key, fmt="{:+.2f}"):
    b = e["band"].get(key)
    return "—" if b is None else f"{fmt.format(b[0])} … {fmt.format(b[2])}"


def _cond(e, key, fmt="{:.0f}"):
    lo, hi = e["conditions"].get(key, (None, None))
    if lo is None:
        return "—"
    return fmt.format(lo) if lo == hi else f"{fmt.format(lo)}–{fmt.format(hi)}"


def page_markdown(analysis: list[dict], command: str, n_samples: int) -> str:
    """docs/validation.md (module docstring)."""
    L = ["# Validation against published tests (generated)", "",
         f"Generated by `{command}` (flexbearing.studies.validation.series); do not edit by hand. Sources, "
         "transcription and what could be read of each: [validation_sources.md](validation_sources.md).", "",
         "**Model and its one parameter set** (the same for every series and point, nothing tuned per case): "
         "steady fixed point with weight (flexbearing.multibody.steady.steady_held_cage_state), "
         + ", ".join(f"{k} = {v}" for k, v in MODEL_PARAMETERS.items())
         + "; oil properties, inlet temperature and supply as published where a series gives them. "
         "Slip S = (n_m − n_c)/n_m with n_m at the mean operating contact angle (positive: the cage lags). "
         f"Band: 5–95 % of the converged steady states at {n_samples} Sobol' samples of the series' declared "
         "unknowns (infeasible combinations, e.g. an angle that no shim angle gives with that clearance, are "
         "left out and counted). Brackets: pure inner- / outer-race control (kinematics.brackets) at the model's "
         "own operating contact angles of the nominal state, with the same n_m. **Read the band with its last "
         "column**: a measured value 'inside' a band whose upper end is a gross skid (tens of %) is not agreement; "
         "the samples with S > 0 are listed with their range, and their unknowns are in the rows file.", "",
         "**Approximations.** Geometry a source does not give (groove radii, cage, pocket and land clearances of "
         "the NASA and 1979 bearings) is the paper bearing's in proportion to the ball; the model's cage is "
         "outer-land guided in every series (the 1979 bearing's is inner-land guided); no thermal model (oil at "
         "its inlet temperature; temperature statements are not computable).", ""]
    L += ["## Summary", "",
          "| series | source read in full | points with a number | mean / max error of the slip | measured inside the band | checks passed |",
          "|---|---|---|---|---|---|"]
    for a in analysis:
        vs = a["series"]
        errs = [e["slip_error_pct"] for e in a["points"] if "slip_error_pct" in e]
        inb = [e["measured_in_band"] for e in a["points"] if e.get("measured_in_band") is not None]
        chk = [c for c in a["checks"] if c["verdict"] != "not computed"]
        L.append(f"| `{vs.series.id}` | {'yes' if vs.series.full_text_read else 'no (abstract/summary)'} | "
                 f"{sum(1 for e in a['points'] if e['measured'])} | "
                 + (f"{np.mean(errs):.1f} % / {np.max(errs):.1f} %" if errs else "—") + " | "
                 + (f"{sum(inb)}/{len(inb)}" if inb else "—") + " | "
                 + (f"{sum(c['verdict'] == 'pass' for c in chk)}/{len(chk)}" if chk else "—") + " |")
    L += _example_block(analysis)
    for a in analysis:
        vs = a["series"]
        L += ["", f"## `{vs.series.id}`: {vs.series.title}", "", f"Source: {vs.series.source}. "
              f"Full text read: {'yes' if vs.series.full_text_read else 'no'}.", ""]
        if vs.unknowns:
            L += ["Declared unknowns (the band spans them; the nominal bearing takes "
                  + ("the paper preset's values" if _is_paper_bearing(vs) else "the middle of each range") + "):", "",
                  "| unknown | range | nominal |", "|---|---|---|"]
            nom = nominal_values(vs)
            for u in vs.unknowns:
                L.append(f"| {u.name} | {u.low:g} – {u.high:g} {u.unit} | {nom[u.name]:.4g} |")
            L.append("")
            if not _is_paper_bearing(vs):
                L += ["The bearing is mostly unknown here: the computed values are for the nominal bearing, the band "
                      "spans the declared ranges; read them as what a bearing of this class does, not as this "
                      "test bearing.", ""]
        L += ["| point | speed, rpm | Fa / Fr, N | measured | computed (nominal) | error | band (5–95 %) | "
              "inner control | outer control | dynamics | α_i / α_o operating, deg | power loss, W | "
              "pocket / land force, N | samples conv. / infeasible | samples with S > 0 |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for e in a["points"]:
            n = e["nominal"] or {}
            conv = n.get("converged")
            meas = "; ".join(f"{k.replace('measured_', '')} = {v[0]:g}" for k, v in e["measured"].items()
                             if v[0] is not None) or ("conditions only" if e["status"] == "conditions_only" else "—")
            slip = _f(n.get("slip_pct")) + " %" if conv else f"not converged ({n.get('reason', 'no row')})"[:80]
            L.append(
                f"| {e['point']} | {_cond(e, 'speed_rpm')} | {_f(n.get('axial_load'), '{:.0f}')} / "
                f"{_cond(e, 'radial_load')} | {meas} | slip {slip} | "
                + (f"{e['slip_error_pct']:.0f} % ({e['slip_error_points']:+.2f} pt)" if "slip_error_pct" in e else "—")
                + f" | {_band(e, 'slip_pct')} %"
                + (" (measured inside)" if e.get("measured_in_band") else "")
                + f" | {_f(n.get('inner_control_slip_pct') if conv else None)} | "
                f"{_f(n.get('outer_control_slip_pct') if conv else None)} | {_f(e.get('dynamics_slip_pct'))} | "
                f"{_f(n.get('inner_contact_angle_deg') if conv else None, '{:.1f}')} / "
                f"{_f(n.get('outer_contact_angle_deg') if conv else None, '{:.1f}')} | "
                f"{_f(n.get('power_loss_W') if conv else None, '{:.0f}')} | "
                f"{_f(n.get('pocket_force_max_N') if conv else None, '{:.1f}')} / "
                f"{_f(n.get('cage_land_force_N') if conv else None, '{:.1f}')} | "
                f"{e['n_converged']}/{e['n_samples']} / {e['n_infeasible']} | "
                + (f"{len(e['positive_slips'])}: {e['positive_slips'][0]:+.1f} … {e['positive_slips'][-1]:+.1f} %"
                   if e["positive_slips"] else "0") + " |")
        errs = [e["slip_error_pct"] for e in a["points"] if "slip_error_pct" in e]
        if errs:
            right = sum(1 for e in a["points"] if "slip_error_pct" in e and e["nominal"]["slip_pct"] > 0)
            L += ["", f"Slip: mean error {np.mean(errs):.1f} %, max {np.max(errs):.1f} %, right sign in "
                      f"{right}/{len(errs)} points."]
            rep = [(e["reported_model"].get("reported_model_cage_slip_percent"), e["measured"].get(
                "measured_cage_slip_percent", (None,))[0]) for e in a["points"]]
            rep = [abs(r - m) / abs(m) * 100 for r, m in rep if r is not None and m]
            if rep:
                L.append(f"The source's own simulation: mean error {np.mean(rep):.1f} %, max {np.max(rep):.1f} %.")
        L += ["", "Checks computed from the model (pass/fail with the computed value):", ""]
        for c in a["checks"]:
            L.append(f"- **{c['verdict']}** ({c['kind']}, `{c['name']}`): {c['computed']}")
        L += ["", "The source's statements as transcribed (temperatures, cage designs and oil flows are beyond "
                  "this model: no thermal model, one cage guidance):", ""]
        for ch in vs.checks:
            L.append(f"- ({ch.kind}) {ch.statement} — {ch.source}")
    return "\n".join(L) + "\n"


def _example_block(analysis: list[dict]) -> list[str]:
    """A ```python block (tests/test_examples.py runs it): the paper series' bearing is the preset, and the
    brackets of the first Table 5 point recomputed from the tabulated operating angles."""
    a = next((x for x in analysis if x["series"].series.id == "yang2025_table5"), None)
    row = a["points"][0]["nominal"] if a and a["points"] else None
    if not row or not row.get("converged") or "inner_control_slip_pct" not in row:
        return []
    return ["", "Reading the tables: the brackets of a row follow from its operating angles alone "
                "(Jones 1960; `kinematics.brackets`), and the paper series' bearing is the preset:", "",
            "```python",
            "from flexbearing.multibody.bearing import PAPER_BEARING",
            "from flexbearing.studies.validation import kinematics as K, series as VS, series_file as SF",
            "",
            'vs = SF.load_series("scenes/validation/yang2025_table5.toml")',
            "b = VS.series_bearing(vs, VS.nominal_values(vs))",
            "assert (b.pitch_diameter, b.ball_diameter, b.n_balls, b.inner_ring) == (0.167, 0.022, 20, 'split')",
            "assert abs(b.radial_clearance - PAPER_BEARING.radial_clearance) < 1e-12      # 88.4 um",
            f"alpha_i, alpha_o = {row['inner_contact_angle_deg']:.4f}, {row['outer_contact_angle_deg']:.4f}"
            f"   # point {a['points'][0]['point']}, computed (deg)",
            f"br = K.brackets({row['speed_rpm']:.0f}, 0.022, 0.167, alpha_i, alpha_o)",
            f"assert abs(br.inner_slip_percent - ({row['inner_control_slip_pct']:+.2f})) < 0.01",
            f"assert abs(br.outer_slip_percent - ({row['outer_control_slip_pct']:+.2f})) < 0.01",
            "```", ""]


def write_page(analysis: list[dict], path, command: str, n_samples: int) -> Path:
    """Write the page atomically (a reader never sees half of it); never through a symlink."""
    path = Path(path)
    if path.is_symlink():
        raise InputError(f"page = {path}: a symlink; write the page to a plain file")
    tmp = path.with_name(path.name + ".part")
    tmp.write_text(page_markdown(analysis, command, n_samples))
    os.replace(tmp, path)
    return path
