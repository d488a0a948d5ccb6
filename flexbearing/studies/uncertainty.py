"""Slip-rate validation under the test bearing's unknown inputs.

The paper (Yang, Liu, Deng, Lubricants 2025, 13, 249, Tables 4/5) gives loads, speeds and slips of
15 steady cases but not the shim angle, the clearance, the oil temperature, the traction of its oil
at the test's light contacts, the cavity's oil content, nor (beyond Table 1) whether the balls were
steel. `scenes/slip_rate_unknowns.toml` declares a range and a reason for each (`load_unknowns`
checks it); this module samples that box, runs the 15 cases at every point and says what the
spread allows.

Sample. A scrambled Sobol' sequence (scipy.stats.qmc.Sobol, Owen scrambling, `seed` of the file)
of n points in the unit cube [0, 1)^d, mapped per unknown (`Unknown.from_unit`):
    uniform:      x = lo + u·(hi − lo)
    log_uniform:  x = lo·(hi/lo)^u
    choice:       x = values[floor(u·m)]   (m values, equally likely)
The shim angle and the clearance are sampled independently; the diametral clearance of a point is
Pd = design_clearance(alphaD) + clearance_excess (flexbearing.studies.validation.slip_rate: the smallest that lets the
split-ring bearing run in two-point contact; the TOML gives the reason).

Model per (point, case): the steady fixed point with weight, flexbearing.multibody.steady.steady_held_cage_state
(frozen azimuths, cage held in its guide film; 1.7 CPU-s per run on average, measured), on the validation's model
(flexbearing.studies.validation.slip_rate.build_validation_model: EHL film-shear law at the point's traction scale,
gravity 9.81 m/s² along −z, free balls), oil at the point's temperature and cavity fraction
X_ref·4000/n. Slip S = (nm − nc)/nm with nm at the mean loaded contact angle (flexbearing.multibody.outputs,
the validation's definition). The dynamic validation (flexbearing.studies.validation.slip_rate.run_slip_case, minutes per
case) is the independent check of this fast path (`benchmarks/results/slip_rate_uncertainty.md`
states the agreement: 20 pairs, rms 0.41 points); a (point, case) whose Newton iteration does not
converge (30 % of the runs, most at high speed and light load) is recorded with converged = False
and left out of the bands — the dynamics there settled at ordinary slips in two checks and in a
gross-skid state (+58 %) in one, so the bands can miss a gross-skid tail at high speed.

Jobs: one per (point, case), run by flexbearing.simulation.jobs.run_jobs (Dask); each finished row is appended
to a JSON-lines file at once, so an interrupted study continues where it stopped (`run_study`).

Analysis (`analyse`):
- bands: per case the 5 / 50 / 95 % quantiles of the converged slips over the points, and whether
  the test's slip falls inside [q5, q95];
- mean relative error against the test per point (points where all 15 cases converged) and the best;
- variance-based global sensitivity (Sobol' indices) of each case's slip and of the mean error to
  each unknown. The direct Saltelli design needs n·(d + 2) model runs per index set; instead a
  surrogate is fitted to the sample per case on its converged points — a quadratic polynomial in
  the unit coordinates (the choice as an indicator; least squares, `QuadraticSurrogate`; the full
  quadratic, or fewer interaction terms where fewer points converged, SURROGATE_FORMS) whose
  leave-one-out error is reported — and the indices are estimated on the surrogate with Saltelli's
  design and the Saltelli (2010) first-order and Jansen (1999) total estimators
  (flexbearing.studies.sensitivity, which states them). Confidence: bootstrap (the sample points
  resampled and the surrogate refitted, and the design's rows resampled), the 2.5–97.5 %
  percentiles. The indices are those of the surrogate: its LOO error bounds how far they describe
  the model.
- the surrogate's best point of the box (mean error over the cases with a surrogate, minimised on
  2^14 Sobol' points per ball material), re-run with the model as named extra points (`candidate_points`; the
  command does it).

The report of an analysis (the summary, the markdown, the figure): flexbearing.studies.uncertainty_report.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import NamedTuple

import numpy as np

from flexbearing.common.materials import BALL_MATERIALS as COMMON_BALL_MATERIALS, ball_material_named
from flexbearing.common.validation import InputError, require_range, require_table
from flexbearing.multibody.steady import steady_held_cage_state
from flexbearing.simulation.jobs import read_rows, run_jobs
from flexbearing.simulation.scene import read_toml
from flexbearing.simulation.stopped import Interrupted
from flexbearing.studies.validation import slip_rate as V
from flexbearing.studies.sensitivity import (SURROGATE_FORMS, QuadraticSurrogate, saltelli_matrices,
                                             sobol_of_columns, unit_sample)
from flexbearing.studies.validation.slip_rate import slip_rate_cases

UNKNOWN_KINDS = ("uniform", "log_uniform", "choice")
BALL_MATERIALS = tuple(COMMON_BALL_MATERIALS)  # names of the choice "ball_material" (flexbearing.common.materials)
MIN_POINTS = 64
# the unknowns the model knows, with the hard limits a declared range must stay inside (unit as the TOML)
UNKNOWN_LIMITS = {
    "shim_angle": (0.0, 45.0, "deg"),                # Bearing.validate: [0, 45)
    "clearance_excess": (0.0, 100e-6, "m"),          # Pd <= 0.01·Dw = 220 um with the design clearance
    "oil_temperature": (-60.0, 250.0, "°C"),         # Oil.validate
    "traction_scale": (0.5, 2.0, "-"),               # flexbearing.multibody.traction.EHL_RANGES
    "oil_air_fraction": (0.0, 1.0, "-"),             # Oil.validate
    "ball_material": (None, None, "-"),
}
QUANTILES = (0.05, 0.5, 0.95)


@dataclass(frozen=True)
class Unknown:
    """One unknown input: its distribution on the declared range (module docstring)."""
    name: str
    kind: str
    lo: float = 0.0
    hi: float = 0.0
    values: tuple = ()
    nominal: object = None
    unit: str = ""
    reason: str = ""

    def from_unit(self, u: float):
        """The value at unit coordinate u in [0, 1) (module docstring, "Sample")."""
        if self.kind == "uniform":
            return self.lo + u * (self.hi - self.lo)
        if self.kind == "log_uniform":
            return self.lo * (self.hi / self.lo) ** u
        return self.values[min(int(u * len(self.values)), len(self.values) - 1)]

    def to_unit(self, x) -> float:
        """Inverse of `from_unit` (the middle of the value's cell for a choice)."""
        if self.hi == self.lo and self.kind != "choice":
            return 0.5                              # a fixed unknown (lo = hi)
        if self.kind == "uniform":
            return (x - self.lo) / (self.hi - self.lo)
        if self.kind == "log_uniform":
            return math.log(x / self.lo) / math.log(self.hi / self.lo)
        return (self.values.index(x) + 0.5) / len(self.values)

    def describe_range(self) -> str:
        if self.kind == "choice":
            return " / ".join(str(v) for v in self.values)
        scale = 1e6 if self.unit == "m" else 1.0
        unit = "um" if self.unit == "m" else self.unit
        return f"{self.lo * scale:g}–{self.hi * scale:g} {unit}" + (" (log)" if self.kind == "log_uniform" else "")


@dataclass(frozen=True)
class UnknownsStudy:
    """A parsed unknowns file (scenes/slip_rate_unknowns.toml)."""
    name: str
    description: str
    points: int
    seed: int
    unknowns: tuple
    path: str = ""

    @property
    def names(self) -> list[str]:
        return [u.name for u in self.unknowns]

    def nominal(self) -> dict:
        return {u.name: u.nominal for u in self.unknowns}


# the keys of an unknowns file's tables (checked below; listed in docs/scene.md by flexbearing.studies.input_docs)
UNKNOWNS_FILE_KEYS = ("study", "unknowns")
UNKNOWNS_HEAD_KEYS = ("name", "description", "points", "seed")
UNKNOWN_KEYS = ("kind", "lo", "hi", "values", "nominal", "unit", "reason")


def load_unknowns(path) -> UnknownsStudy:
    """Read and check an unknowns file: [study] (name, description, points >= 64, seed) and one
    [unknowns.NAME] table per unknown of UNKNOWN_LIMITS (kind, lo/hi or values, nominal, unit, reason).
    Every problem is an InputError naming the field, its value and what is allowed."""
    path = Path(path)
    data = read_toml(path, "unknowns file")
    require_table("unknowns file", data, UNKNOWNS_FILE_KEYS)
    head = data.get("study")
    if not isinstance(head, dict):
        raise InputError(f"{path}: [study] is missing")
    require_table("study", head, UNKNOWNS_HEAD_KEYS)
    points = head.get("points", MIN_POINTS)
    if isinstance(points, bool) or not isinstance(points, int) or points < MIN_POINTS:
        raise InputError(f"study.points = {points!r} is not allowed; allowed: an integer >= {MIN_POINTS}")
    seed = head.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise InputError(f"study.seed = {seed!r} is not allowed; allowed: an integer >= 0")
    table = data.get("unknowns")
    if not isinstance(table, dict) or not table:
        raise InputError(f"{path}: [unknowns.NAME] tables are missing")
    unknowns = []
    for name, spec in table.items():
        unknowns.append(_parse_unknown(name, spec))
    missing = [n for n in UNKNOWN_LIMITS if n not in table]
    if missing:
        raise InputError(f"{path}: unknowns {', '.join(missing)} are missing (every one of "
                         f"{', '.join(UNKNOWN_LIMITS)} needs a range; give lo = hi to fix one)")
    return UnknownsStudy(str(head.get("name", path.stem)), str(head.get("description", "")), points, seed,
                         tuple(unknowns), str(path))


def _parse_unknown(name, spec) -> Unknown:
    where = f"unknowns.{name}"
    if name not in UNKNOWN_LIMITS:
        raise InputError(f"{where}: {name!r} is not an unknown of the model; allowed: {', '.join(UNKNOWN_LIMITS)}")
    require_table(where, spec, UNKNOWN_KEYS)
    kind = spec.get("kind")
    if kind not in UNKNOWN_KINDS:
        raise InputError(f"{where}.kind = {kind!r} is not known; allowed: {', '.join(UNKNOWN_KINDS)}")
    reason = spec.get("reason", "")
    if not isinstance(reason, str) or not reason.strip():
        raise InputError(f"{where}.reason is missing: say why the range (paper, assumption or practice)")
    lo_lim, hi_lim, unit = UNKNOWN_LIMITS[name]
    if spec.get("unit", unit) != unit:
        raise InputError(f"{where}.unit = {spec.get('unit')!r}; allowed: {unit!r} (the model's unit)")
    if name == "ball_material":
        if kind != "choice":
            raise InputError(f"{where}.kind = {kind!r}; allowed: 'choice' (a discrete input)")
        values = spec.get("values")
        if not isinstance(values, list) or not values or any(v not in BALL_MATERIALS for v in values) \
                or len(set(values)) != len(values):
            raise InputError(f"{where}.values = {values!r}; allowed: distinct names from {', '.join(BALL_MATERIALS)}")
        nominal = spec.get("nominal", values[0])
        if nominal not in values:
            raise InputError(f"{where}.nominal = {nominal!r} is not one of values {values}")
        return Unknown(name, kind, values=tuple(values), nominal=nominal, unit=unit, reason=reason.strip())
    if kind == "choice":
        raise InputError(f"{where}.kind = 'choice'; allowed: 'uniform', 'log_uniform' (a continuous input)")
    for key in ("lo", "hi"):
        if key not in spec:
            raise InputError(f"{where}.{key} is missing")
    lo = require_range(f"{where}.lo", spec["lo"], lo_lim, hi_lim, unit=unit)
    hi = require_range(f"{where}.hi", spec["hi"], lo, hi_lim, unit=unit)
    if kind == "log_uniform" and lo <= 0.0:
        raise InputError(f"{where}.lo = {lo:g} {unit}: a log_uniform range needs lo > 0")
    nominal = require_range(f"{where}.nominal", spec.get("nominal", 0.5 * (lo + hi)), lo, hi, unit=unit)
    return Unknown(name, kind, lo, hi, (), nominal, unit, reason.strip())


# ------------------------------------------------------------------------------------- sampling


def sample_points(study: UnknownsStudy, n: int | None = None) -> list[dict]:
    """The study's points: [{name: value}] from `unit_sample` mapped by each `Unknown.from_unit`."""
    u = unit_sample(study.points if n is None else n, len(study.unknowns), study.seed)
    return [{k.name: _plain(k.from_unit(float(row[j]))) for j, k in enumerate(study.unknowns)} for row in u]


def _plain(v):
    return v if isinstance(v, str) else float(v)




def point_bearing_oil(point: dict, speed_rpm: float):
    """(bearing, oil, traction_scale) of a sample point for a case at speed_rpm (module docstring):
    shim angle and Pd = design clearance + excess, ball material, oil temperature, cavity oil
    fraction X_ref·4000/n (flexbearing.studies.validation.slip_rate.case_oil_air_fraction)."""
    b = V.validation_bearing(point["shim_angle"])
    b = replace(b, radial_clearance=b.radial_clearance + point["clearance_excess"],
                ball_material=ball_material_named(point["ball_material"], "unknowns.ball_material").material,
                ball_thermal=ball_material_named(point["ball_material"], "unknowns.ball_material").thermal).validate()
    x = V.case_oil_air_fraction(point["oil_air_fraction"], speed_rpm, "inverse_speed")
    oil = V.validation_oil(point["oil_temperature"], x)
    return b, oil, float(point["traction_scale"])


class SteadyCase(NamedTuple):
    """The steady problem of one (point, case) run: what steady_held_cage_state is given."""
    model: object             # flexbearing.multibody.model.Model at the point's bearing and oil
    speed_rad_s: float        # inner-ring speed, rad/s
    load: tuple               # (Fa, 0, -Fr) on the inner ring, N


def case_problem(point: dict, case: dict) -> SteadyCase:
    """The model, speed and load of `case` (a slip_rate_cases row) at sample `point`: the bearing and oil
    the point's unknowns give (point_bearing_oil), the validation model with the EHL traction law,
    the radial load along -Z (the weight's direction, as in the slip-rate tests)."""
    bearing, oil, scale = point_bearing_oil(point, case["speed_rpm"])
    model = V.build_validation_model(bearing, oil, V.validation_model_options(), "ehl", scale)
    return SteadyCase(model, case["speed_rpm"] * 2.0 * math.pi / 60.0,
                      (case["axial_load"], 0.0, -case["radial_load"]))


def steady_case_slip(point: dict, case: dict) -> dict:
    """One job: the steady fixed point with weight (flexbearing.multibody.steady.steady_held_cage_state) of
    `case` (flexbearing.studies.validation.slip_rate.slip_rate_cases row) at sample `point`; returns the row (slip in %,
    convergence, residual, contact angles, cage eccentricity, CPU seconds; fold: the run has no held-cage
    state because its branch ends in a fold, steady._held_cage_continuation; strict=False: a run without a
    root is a row, not the end of the study)."""
    t0 = time.process_time()
    problem = case_problem(point, case)
    _, info = steady_held_cage_state(*problem, strict=False)
    out = info["outputs"]
    return dict(case=case["case"], slip_pct=100.0 * float(out["slip_rate"]), converged=info["converged"],
                residual=info["residual"], iterations=info["iterations"],
                cage_speed=info["cage_speed"], nominal_cage_speed=float(out["nominal_cage_speed"]),
                contact_angle_outer_deg=math.degrees(float(np.mean(out["contact_angle_outer"]))),
                contact_angle_inner_deg=math.degrees(float(np.mean(np.abs(out["contact_angle_inner_loaded"])))),
                cage_eccentricity_ratio=info["cage_eccentricity_ratio"], reason=info.get("reason", ""),
                fold=bool(info.get("fold", False)),   # no held-cage state: the branch ends in a fold (steady.py)
                # converged / no steady state (proved) / fold (a certified turning point) / not converged:
                # flexbearing.multibody.steady_existence; the reason starts with it
                verdict=info.get("verdict", "converged" if info["converged"] else "not converged"),
                verdict_cpu_s=float(info.get("verdict_cpu_s", 0.0)),
                # a root of the continuation: does the cage stay held in the dynamics from it (None: not checked,
                # the direct solve's root; flexbearing.multibody.steady_hold)
                held=info.get("held"),
                continuation_steps=len(info.get("continuation", [])), cpu_s=time.process_time() - t0)


# ------------------------------------------------------------------------------------ the study
def study_points(study: UnknownsStudy, extra_points: list[dict] | None = None) -> list[dict]:
    """The sample points with their ids ("point": 0..n−1), then the named extra points."""
    return [dict(p, point=k) for k, p in enumerate(sample_points(study))] + [dict(e) for e in extra_points or []]


class UncertaintyInterrupted(Interrupted):
    """The uncertainty study (`run_study`) stopped early; every finished (point, case) is in its rows
    file (`rows_file`), and running it again runs only the others (the family:
    flexbearing.simulation.stopped)."""

    def __init__(self, message: str, rows_file: str, cause: BaseException):
        super().__init__(message, cause=cause)
        self.rows_file = rows_file


def run_study(study: UnknownsStudy, out_dir, cases: list[int] | None = None, workers: int | None = None,
              scheduler: str | None = None, extra_points: list[dict] | None = None, progress: bool = True) -> dict:
    """Run every (point, case) not yet in OUT_DIR/<name>/rows.jsonl (resumable) via run_jobs and
    append each row as it finishes. extra_points: further named points (e.g. "nominal") run with
    the sample. Returns {"rows_file", "points", "failures", "new_rows", "cpu_s"}."""
    d = Path(out_dir) / study.name
    d.mkdir(parents=True, exist_ok=True)
    rows_file = d / "rows.jsonl"
    points = study_points(study, extra_points)
    (d / "points.json").write_text(json.dumps({"study": study.name, "seed": study.seed, "points": points},
                                              indent=1) + "\n")
    sel = [c for c in slip_rate_cases() if cases is None or c["case"] in cases]
    done = {(r["point"], r["case"]) for r in read_rows(rows_file)}
    jobs, names, keys = [], [], []
    for p in points:
        for c in sel:
            if (p["point"], c["case"]) not in done:
                jobs.append(({k: p[k] for k in study.names}, c))
                names.append(f"point {p['point']} case {c['case']}")
                keys.append((p["point"], c["case"]))
    cpu = [0.0]

    def on_result(k, row):
        row = dict(row, point=keys[k][0])
        cpu[0] += row["cpu_s"]
        with open(rows_file, "a") as f:
            f.write(json.dumps(row) + "\n")
            f.flush()
            os.fsync(f.fileno())

    try:
        failures = run_jobs(steady_case_slip, jobs, on_result, workers=workers, scheduler=scheduler,
                            names=names, description="uncertainty (point, case)",
                            progress=progress) if jobs else []
    except KeyboardInterrupt as exc:
        raise UncertaintyInterrupted(f"uncertainty study {study.name} interrupted: {rows_file} holds every "
                                     f"finished (point, case); run the same command again to continue",
                                     str(rows_file), exc) from exc
    return dict(rows_file=str(rows_file), points=points, failures=failures, new_rows=len(jobs) - len(failures),
                cpu_s=cpu[0])


# ------------------------------------------------------------------------------------ the analysis
def mean_error_pct(slips: np.ndarray, test: np.ndarray) -> np.ndarray:
    """Mean relative error (%) of slips (..., 15) against the test's (15,), as flexbearing.studies.validation.slip_rate.summarise."""
    return np.mean(100.0 * np.abs(slips - test) / np.abs(test), axis=-1)


def analyse(study: UnknownsStudy, rows: list[dict], points: list[dict], n_design: int = 2 ** 13,
            n_boot: int = 200, n_search: int = 2 ** 14) -> dict:
    """Bands, points inside, mean error per point, surrogate Sobol' indices with bootstrap intervals
    and the surrogate's best point (module docstring). rows: steady_case_slip rows with "point";
    points: the study's points (sample ones have integer "point" ids)."""
    cases = slip_rate_cases()
    ids = [c["case"] for c in cases]
    test = np.array([c["test_slip_pct"] for c in cases])
    paper = np.array([c["paper_slip_pct"] for c in cases])
    sample = [p for p in points if isinstance(p["point"], int)]
    slip = np.full((len(sample), len(ids)), np.nan)
    conv = np.zeros((len(sample), len(ids)), bool)
    ran = np.zeros((len(sample), len(ids)), bool)
    pos = {p["point"]: k for k, p in enumerate(sample)}
    extra = {}
    for r in rows:
        if r["point"] in pos:
            k = pos[r["point"]]
            slip[k, ids.index(r["case"])] = r["slip_pct"] if r["converged"] else np.nan
            conv[k, ids.index(r["case"])] = r["converged"]
            ran[k, ids.index(r["case"])] = True
        else:
            extra.setdefault(r["point"], {})[r["case"]] = r
    bands = []
    for j, c in enumerate(cases):
        v = slip[:, j][np.isfinite(slip[:, j])]
        q = np.quantile(v, QUANTILES) if len(v) else [np.nan] * 3
        bands.append(dict(case=c["case"], test_slip_pct=c["test_slip_pct"], paper_slip_pct=c["paper_slip_pct"],
                          n_converged=int(len(v)), q05=float(q[0]), q50=float(q[1]), q95=float(q[2]),
                          min=float(v.min()) if len(v) else np.nan, max=float(v.max()) if len(v) else np.nan,
                          test_inside=bool(q[0] <= c["test_slip_pct"] <= q[2]) if len(v) else False,
                          paper_inside=bool(q[0] <= c["paper_slip_pct"] <= q[2]) if len(v) else False))
    complete = np.all(conv, axis=1)
    err = mean_error_pct(slip, test)
    per_point = []
    for k, p in enumerate(sample):
        per_point.append(dict(point=p["point"], **{n: p[n] for n in study.names}, complete=bool(complete[k]),
                              mean_error_pct=float(err[k]) if complete[k] else None,
                              slips_pct=[None if not np.isfinite(s) else float(s) for s in slip[k]]))
    best = min((q for q in per_point if q["complete"]), key=lambda q: q["mean_error_pct"], default=None)
    base = dict(study=study.name, unknowns=[dict(name=k.name, kind=k.kind, range=k.describe_range(),
                                                 nominal=k.nominal, unit=k.unit, reason=k.reason)
                                            for k in study.unknowns],
                n_points=len(sample), n_complete=int(complete.sum()),
                n_converged=int(conv.sum()), n_runs=int(conv.size),
                bands=bands, test_inside=int(sum(b_["test_inside"] for b_ in bands)),
                paper_inside=int(sum(b_["paper_inside"] for b_ in bands)),
                per_point=per_point, best_sample_point=best, extra_points={str(k): v for k, v in extra.items()},
                paper_mean_error_pct=float(mean_error_pct(paper, test)),
                test_slip_pct=test.tolist(), paper_slip_pct=paper.tolist(),
                surrogate_fit=None, sensitivity=None, surrogate_best=[])
    # surrogate per case on the points where that case converged, its form by the number of those
    # points (at least twice its terms); cases with fewer are left out of the indices
    u = np.array([[k.to_unit(p[k.name]) for k in study.unknowns] for p in sample])
    base["convergence"] = convergence_pattern(study, u, conv, ran, ids)
    base["n_ran"] = int(ran.sum())
    forms = []
    for j in range(len(ids)):
        n_j = int(conv[:, j].sum())
        forms.append(next((f for f in SURROGATE_FORMS if n_j >= 2 * QuadraticSurrogate(study.unknowns, f).n_terms()),
                          None))
    keep = [j for j, f in enumerate(forms) if f is not None]
    if not keep:
        return base
    test_k = test[keep]

    def fit_all(pick):
        return [QuadraticSurrogate(study.unknowns, forms[j]).fit(u[pick], slip[pick, j]) for j in keep]

    def predict(surs, x):                 # the features once per surrogate form
        feats = {f: QuadraticSurrogate(study.unknowns, f).features(x) for f in {s_.interactions for s_ in surs}}
        return np.column_stack([feats[s_.interactions] @ s_.coef for s_ in surs])

    surs = fit_all(np.arange(len(u)))
    loo = np.full((len(u), len(keep)), np.nan)
    for c_, (j, s_) in enumerate(zip(keep, surs)):
        loo[:, c_] = s_.loo_residuals(u, slip[:, j])
    sk = slip[:, keep]
    fit = dict(cases=[ids[j] for j in keep], forms=[forms[j] for j in keep],
               left_out=[ids[j] for j, f in enumerate(forms) if f is None],
               n_points=[int(conv[:, j].sum()) for j in keep],
               n_terms={f: QuadraticSurrogate(study.unknowns, f).n_terms() for f in SURROGATE_FORMS},
               loo_rms_pct_points=[float(x) for x in np.sqrt(np.nanmean(loo ** 2, axis=0))],
               sample_std_pct_points=[float(x) for x in np.nanstd(sk, axis=0)],
               r2_loo=[float(x) for x in 1.0 - np.nanmean(loo ** 2, axis=0) / np.nanvar(sk, axis=0)])
    ok = np.all(np.isfinite(sk), axis=1)
    loo_err = mean_error_pct(sk[ok] - loo[ok], test_k) - mean_error_pct(sk[ok], test_k)
    fit["mean_error_loo_rms_pct"] = float(np.sqrt(np.mean(loo_err ** 2))) if ok.any() else None
    d = len(study.unknowns)
    rng = np.random.default_rng(study.seed)
    a, b = saltelli_matrices(n_design, d, study.seed + 1)
    abs_ = [np.where(np.arange(d)[None, :] == i, b, a) for i in range(d)]

    def evaluate(surs_):
        ys = [predict(surs_, a), predict(surs_, b)] + [predict(surs_, x) for x in abs_]
        ys = [np.column_stack([y, mean_error_pct(y, test_k)]) for y in ys]
        return ys[0], ys[1], np.stack(ys[2:])

    fa, fb, fab = evaluate(surs)
    s, st = sobol_of_columns(fa, fb, fab)
    boot_s, boot_st = [], []
    for _ in range(n_boot):
        ga, gb, gab = evaluate(fit_all(rng.integers(0, len(u), len(u))))
        rows_ = rng.integers(0, n_design, n_design)
        x, y = sobol_of_columns(ga, gb, gab, rows_)
        boot_s.append(x)
        boot_st.append(y)
    s_ci = np.percentile(np.array(boot_s), [2.5, 97.5], axis=0)
    st_ci = np.percentile(np.array(boot_st), [2.5, 97.5], axis=0)
    outputs = [f"case {ids[j]}" for j in keep] + ["mean error"]
    sens = {o: {n: dict(S=float(s[j, i]), S_lo=float(s_ci[0, j, i]), S_hi=float(s_ci[1, j, i]),
                        ST=float(st[j, i]), ST_lo=float(st_ci[0, j, i]), ST_hi=float(st_ci[1, j, i]))
                for i, n in enumerate(study.names)} for j, o in enumerate(outputs)}
    # the surrogate's best point of the box, per ball material (mean error over the kept cases)
    search = unit_sample(n_search, d, study.seed + 2)
    mat = [k for k in study.unknowns if k.kind == "choice"]
    candidates = []
    groups = [None] if not mat else list(mat[0].values)
    for g in groups:
        us = search.copy()
        if g is not None:
            us[:, study.names.index(mat[0].name)] = mat[0].to_unit(g)
        pred = predict(surs, us)
        e = mean_error_pct(pred, test_k)
        k = int(np.argmin(e))
        candidates.append(dict({n: _plain(kk.from_unit(float(us[k, j]))) for j, (n, kk) in
                                enumerate(zip(study.names, study.unknowns))},
                               surrogate_mean_error_pct=float(e[k]),
                               surrogate_slips_pct=[float(x) for x in pred[k]]))
    base.update(surrogate_fit=fit, sensitivity=sens, surrogate_best=candidates)
    return base


def candidate_points(analysis: dict) -> list[dict]:
    """The surrogate's best points (`analyse`, "surrogate_best") as named extra points for
    `run_study`: "best_<material>_<hash of the values>", so that a re-run with other rows (other
    candidates) does not mix them up."""
    out = []
    names = [u["name"] for u in analysis["unknowns"]]
    for c in analysis["surrogate_best"]:
        values = {n: c[n] for n in names}
        tag = hashlib.sha1(json.dumps(values, sort_keys=True).encode()).hexdigest()[:8]
        out.append(dict(values, point=f"best_{values.get('ball_material', 'x')}_{tag}"))
    return out


def convergence_pattern(study: UnknownsStudy, u: np.ndarray, conv: np.ndarray, ran: np.ndarray, ids: list) -> dict:
    """Where the fast path fails: per case the converged fraction of the runs made, and per unknown
    the failure rate of the (point, case) runs in the lower and the upper half of its unit range."""
    def fail(mask):
        n = ran[mask].sum()
        return float(1.0 - conv[mask].sum() / n) if n else float("nan")
    by_unknown = {}
    for j, k in enumerate(study.unknowns):
        by_unknown[k.name] = dict(fail_lower_half=fail(u[:, j] < 0.5), fail_upper_half=fail(u[:, j] >= 0.5))
    by_case = {str(c): float(conv[:, i].sum() / ran[:, i].sum()) if ran[:, i].any() else float("nan")
               for i, c in enumerate(ids)}
    return dict(converged_fraction_by_case=by_case, fail_rate_by_unknown=by_unknown)
