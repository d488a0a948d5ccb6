"""Slip-rate validation under the test bearing's unknown inputs (issue 23, item 2).

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
Pd = design_clearance(alphaD) + clearance_excess (flexbearing.studies.validate: the smallest that lets the
split-ring bearing run in two-point contact; the TOML gives the reason).

Model per (point, case): the steady fixed point with weight, flexbearing.multibody.steady.steady_held_cage_state
(frozen azimuths, cage held in its guide film; 1.7 CPU-s per run on average, measured), on the validation's model
(flexbearing.studies.validate.build_validation_model: EHL film-shear law at the point's traction scale,
gravity 9.81 m/s² along −z, free balls), oil at the point's temperature and cavity fraction
X_ref·4000/n. Slip S = (nm − nc)/nm with nm at the mean loaded contact angle (flexbearing.multibody.outputs,
the validation's definition). The dynamic validation (flexbearing.studies.validate.run_slip_case, minutes per
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
  leave-one-out error is reported — and the indices are estimated on the surrogate with Saltelli's design and the
  estimators (`sobol_indices`)
      first order  S_i  = mean(f(B)·(f(A_B^i) − f(A)))/V              (Saltelli et al. 2010, eq. (b))
      total        ST_i = mean((f(A) − f(A_B^i))²)/(2V)              (Jansen 1999)
  with V the variance of f over A and B, A_B^i = A with column i from B. Confidence: bootstrap
  (the sample points resampled and the surrogate refitted, and the design's rows resampled), the
  2.5–97.5 % percentiles. The indices are those of the surrogate: its LOO error bounds how far
  they describe the model.
- the surrogate's best point of the box (mean error over the cases with a surrogate, minimised on
  2^14 Sobol' points per ball material), re-run with the model as named extra points (`candidate_points`; the
  command does it).
"""
from __future__ import annotations

import json
import math
import os
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from flexbearing.common.validation import InputError, require_range
from flexbearing.common.materials import BALL_MATERIALS as COMMON_BALL_MATERIALS, ball_material_named

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


def load_unknowns(path) -> UnknownsStudy:
    """Read and check an unknowns file: [study] (name, description, points >= 64, seed) and one
    [unknowns.NAME] table per unknown of UNKNOWN_LIMITS (kind, lo/hi or values, nominal, unit, reason).
    Every problem is an InputError naming the field, its value and what is allowed."""
    from flexbearing.simulation.scene import read_toml
    path = Path(path)
    data = read_toml(path, "unknowns file")
    _only(data, "unknowns file", ("study", "unknowns"))
    head = data.get("study")
    if not isinstance(head, dict):
        raise InputError(f"{path}: [study] is missing")
    _only(head, "study", ("name", "description", "points", "seed"))
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


def _only(d, where, allowed):
    if not isinstance(d, dict):
        raise InputError(f"{where} must be a table")
    extra = [k for k in d if k not in allowed]
    if extra:
        raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; allowed: {', '.join(allowed)}")


def _parse_unknown(name, spec) -> Unknown:
    where = f"unknowns.{name}"
    if name not in UNKNOWN_LIMITS:
        raise InputError(f"{where}: {name!r} is not an unknown of the model; allowed: {', '.join(UNKNOWN_LIMITS)}")
    _only(spec, where, ("kind", "lo", "hi", "values", "nominal", "unit", "reason"))
    kind = spec.get("kind")
    if kind not in UNKNOWN_KINDS:
        raise InputError(f"{where}.kind = {kind!r} is not known; allowed: {', '.join(UNKNOWN_KINDS)}")
    reason = spec.get("reason", "")
    if not isinstance(reason, str) or not reason.strip():
        raise InputError(f"{where}.reason is missing: say why the range (paper, SPEC or practice)")
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
def unit_sample(n: int, d: int, seed: int) -> np.ndarray:
    """(n, d) scrambled Sobol' points in [0, 1)^d (scipy.stats.qmc, Owen scrambling)."""
    from scipy.stats import qmc
    if n < 1:
        raise InputError(f"sample size n = {n} is not allowed; allowed: >= 1")
    sob = qmc.Sobol(d, scramble=True, seed=seed)
    m = int(math.log2(n))
    return sob.random_base2(m) if 2 ** m == n else sob.random(n)


def sample_points(study: UnknownsStudy, n: int | None = None) -> list[dict]:
    """The study's points: [{name: value}] from `unit_sample` mapped by each `Unknown.from_unit`."""
    u = unit_sample(study.points if n is None else n, len(study.unknowns), study.seed)
    return [{k.name: _plain(k.from_unit(float(row[j]))) for j, k in enumerate(study.unknowns)} for row in u]


def _plain(v):
    return v if isinstance(v, str) else float(v)




def point_bearing_oil(point: dict, speed_rpm: float):
    """(bearing, oil, traction_scale) of a sample point for a case at speed_rpm (module docstring):
    shim angle and Pd = design clearance + excess, ball material, oil temperature, cavity oil
    fraction X_ref·4000/n (flexbearing.studies.validate.case_oil_air_fraction)."""
    from flexbearing.studies import validate as V
    b = V.validation_bearing(point["shim_angle"])
    b = replace(b, radial_clearance=b.radial_clearance + point["clearance_excess"],
                ball_material=ball_material_named(point["ball_material"], "unknowns.ball_material").material,
                ball_thermal=ball_material_named(point["ball_material"], "unknowns.ball_material").thermal).validate()
    x = V.case_oil_air_fraction(point["oil_air_fraction"], speed_rpm, "inverse_speed")
    oil = V.validation_oil(point["oil_temperature"], x)
    return b, oil, float(point["traction_scale"])


def steady_case_slip(point: dict, case: dict) -> dict:
    """One job: the steady fixed point with weight (flexbearing.multibody.steady.steady_held_cage_state) of
    `case` (flexbearing.studies.validate.slip_rate_cases row) at sample `point`; returns the row (slip in %,
    convergence, residual, contact angles, cage eccentricity, CPU seconds)."""
    from flexbearing.studies import validate as V
    from flexbearing.multibody.steady import steady_held_cage_state
    t0 = time.process_time()
    bearing, oil, scale = point_bearing_oil(point, case["speed_rpm"])
    model = V.build_validation_model(bearing, oil, V.validation_model_options(), "ehl", scale)
    omega = case["speed_rpm"] * 2.0 * math.pi / 60.0
    _, info = steady_held_cage_state(model, omega, (case["axial_load"], 0.0, -case["radial_load"]))
    out = info["outputs"]
    return dict(case=case["case"], slip_pct=100.0 * float(out["slip_rate"]), converged=info["converged"],
                residual=info["residual"], iterations=info["iterations"],
                cage_speed=info["cage_speed"], nominal_cage_speed=float(out["nominal_cage_speed"]),
                contact_angle_outer_deg=math.degrees(float(np.mean(out["contact_angle_outer"]))),
                contact_angle_inner_deg=math.degrees(float(np.mean(np.abs(out["contact_angle_inner_loaded"])))),
                cage_eccentricity_ratio=info["cage_eccentricity_ratio"], reason=info.get("reason", ""),
                continuation_steps=len(info.get("continuation", [])), cpu_s=time.process_time() - t0)


# ------------------------------------------------------------------------------------ the study
def read_rows(path) -> list[dict]:
    """The rows of a JSON-lines results file (a torn last line, from a kill mid-write, is skipped)."""
    path = Path(path)
    rows = []
    if path.exists():
        for line in path.read_text().splitlines():
            try:
                rows.append(json.loads(line))
            except json.JSONDecodeError:
                continue
    return rows


def study_points(study: UnknownsStudy, extra_points: list[dict] | None = None) -> list[dict]:
    """The sample points with their ids ("point": 0..n−1), then the named extra points."""
    return [dict(p, point=k) for k, p in enumerate(sample_points(study))] + [dict(e) for e in extra_points or []]


def run_study(study: UnknownsStudy, out_dir, cases: list[int] | None = None, workers: int | None = None,
              scheduler: str | None = None, extra_points: list[dict] | None = None, progress: bool = True) -> dict:
    """Run every (point, case) not yet in OUT_DIR/<name>/rows.jsonl (resumable) via run_jobs and
    append each row as it finishes. extra_points: further named points (e.g. "nominal") run with
    the sample. Returns {"rows_file", "points", "failures", "new_rows", "cpu_s"}."""
    from flexbearing.simulation.jobs import run_jobs
    from flexbearing.studies.validate import slip_rate_cases
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

    failures = run_jobs(steady_case_slip, jobs, on_result, workers=workers, scheduler=scheduler, names=names,
                        description="uncertainty (point, case)", progress=progress) if jobs else []
    return dict(rows_file=str(rows_file), points=points, failures=failures, new_rows=len(jobs) - len(failures),
                cpu_s=cpu[0])


# ------------------------------------------------------------------------- variance-based indices
def saltelli_matrices(n: int, d: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(A, B): two independent (n, d) unit samples, the halves of one 2d-dimensional scrambled
    Sobol' sample (Saltelli et al. 2010)."""
    ab = unit_sample(n, 2 * d, seed)
    return ab[:, :d], ab[:, d:]


def sobol_from_values(fa: np.ndarray, fb: np.ndarray, fab: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(S, ST) from f(A) (n,), f(B) (n,), f(A_B^i) (d, n): Saltelli 2010 first order and Jansen
    1999 total (module docstring). V is the variance of f over A and B together."""
    v = np.var(np.concatenate([fa, fb]))
    if v <= 0.0:
        return np.zeros(fab.shape[0]), np.zeros(fab.shape[0])
    s = np.mean(fb[None, :] * (fab - fa[None, :]), axis=1) / v
    st = 0.5 * np.mean((fa[None, :] - fab) ** 2, axis=1) / v
    return s, st


def sobol_indices(f, d: int, n: int = 2 ** 13, seed: int = 0, n_boot: int = 200,
                  rng_seed: int = 1) -> dict:
    """Sobol' indices of f: (m, d) unit points -> (m,) or (m, k) values, on Saltelli's design
    (n·(d + 2) evaluations). Returns {"S", "ST"} of shape (d,) or (k, d) and their bootstrap
    2.5/97.5 % limits "S_ci", "ST_ci" (rows of the design resampled, n_boot times)."""
    a, b = saltelli_matrices(n, d, seed)
    fa, fb = np.asarray(f(a)), np.asarray(f(b))
    fab = []
    for i in range(d):
        abi = a.copy()
        abi[:, i] = b[:, i]
        fab.append(np.asarray(f(abi)))
    fab = np.stack(fab)                           # (d, n) or (d, n, k)
    return _indices_with_ci(fa, fb, fab, n_boot, np.random.default_rng(rng_seed))


def _indices_multi(fa, fb, fab, rows=None):
    if rows is not None:
        fa, fb, fab = fa[rows], fb[rows], fab[:, rows]
    if fa.ndim == 1:
        return sobol_from_values(fa, fb, fab)
    out = [sobol_from_values(fa[:, j], fb[:, j], fab[:, :, j]) for j in range(fa.shape[1])]
    return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def _indices_with_ci(fa, fb, fab, n_boot, rng):
    s, st = _indices_multi(fa, fb, fab)
    n = fa.shape[0]
    bs, bst = [], []
    for _ in range(n_boot):
        rows = rng.integers(0, n, n)
        x, y = _indices_multi(fa, fb, fab, rows)
        bs.append(x)
        bst.append(y)
    bs, bst = np.array(bs), np.array(bst)
    return {"S": s, "ST": st, "S_ci": np.percentile(bs, [2.5, 97.5], axis=0),
            "ST_ci": np.percentile(bst, [2.5, 97.5], axis=0)}


@dataclass
class QuadraticSurrogate:
    """Quadratic polynomial in the unit coordinates, least squares (module docstring). Choice
    unknowns enter as indicators of their non-first values (no square: an indicator's square is
    itself). interactions: "all" = the full quadratic (every product of two inputs; 27 terms for
    the six unknowns), "choice" = linear and square terms plus the products of the choice with each
    other input (17 terms), "none" = linear and square terms (12 terms: additive, S = ST); the
    smaller forms serve a case with fewer converged points. coef: (p, k) for k outputs."""
    unknowns: tuple
    interactions: str = "all"
    coef: np.ndarray = field(default=None)

    def features(self, u: np.ndarray) -> np.ndarray:
        cols = [np.ones(len(u))]
        lin, is_choice = [], []
        for j, k in enumerate(self.unknowns):
            if k.kind == "choice":
                m = len(k.values)
                idx = np.minimum((u[:, j] * m).astype(int), m - 1)
                lin += [(idx == i).astype(float) for i in range(1, m)]
                is_choice += [True] * (m - 1)
            else:
                lin.append(u[:, j] - 0.5)
                is_choice.append(False)
        cols += lin
        for i in range(len(lin)):
            for j in range(i, len(lin)):
                if i == j and is_choice[i]:
                    continue
                if i != j and (self.interactions == "none" or
                               (self.interactions == "choice" and not (is_choice[i] or is_choice[j]))):
                    continue
                cols.append(lin[i] * lin[j])
        return np.column_stack(cols)

    def n_terms(self) -> int:
        """Number of terms (columns of `features`)."""
        return self.features(unit_sample(8, len(self.unknowns), 0)).shape[1]

    def fit(self, u: np.ndarray, y: np.ndarray) -> "QuadraticSurrogate":
        """Least squares per output column on that column's finite values (NaN = a (point, case)
        that did not converge: each case's fit uses the points where it converged)."""
        x = self.features(u)
        y2 = y.reshape(len(y), -1)
        coef = np.empty((x.shape[1], y2.shape[1]))
        for j in range(y2.shape[1]):
            ok = np.isfinite(y2[:, j])
            coef[:, j] = np.linalg.lstsq(x[ok], y2[ok, j], rcond=None)[0]
        self.coef = coef if y.ndim == 2 else coef[:, 0]
        return self

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return self.features(u) @ self.coef

    def loo_residuals(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Leave-one-out residuals e_i/(1 − h_ii) (the hat matrix of each column's least-squares
        fit on its finite values; NaN where y is NaN)."""
        x = self.features(u)
        y2 = y.reshape(len(y), -1)
        out = np.full(y2.shape, np.nan)
        for j in range(y2.shape[1]):
            ok = np.isfinite(y2[:, j])
            h = x[ok] @ np.linalg.pinv(x[ok])
            out[ok, j] = (y2[ok, j] - h @ y2[ok, j]) / (1.0 - np.diag(h))
        return out if y.ndim == 2 else out[:, 0]

def mean_error_pct(slips: np.ndarray, test: np.ndarray) -> np.ndarray:
    """Mean relative error (%) of slips (..., 15) against the test's (15,), as flexbearing.studies.validate.summarise."""
    return np.mean(100.0 * np.abs(slips - test) / np.abs(test), axis=-1)


def analyse(study: UnknownsStudy, rows: list[dict], points: list[dict], n_design: int = 2 ** 13,
            n_boot: int = 200, n_search: int = 2 ** 14) -> dict:
    """Bands, points inside, mean error per point, surrogate Sobol' indices with bootstrap intervals
    and the surrogate's best point (module docstring). rows: steady_case_slip rows with "point";
    points: the study's points (sample ones have integer "point" ids)."""
    from flexbearing.studies.validate import slip_rate_cases
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
    s, st = _indices_multi(fa, fb, fab)
    boot_s, boot_st = [], []
    for _ in range(n_boot):
        ga, gb, gab = evaluate(fit_all(rng.integers(0, len(u), len(u))))
        rows_ = rng.integers(0, n_design, n_design)
        x, y = _indices_multi(ga, gb, gab, rows_)
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


SURROGATE_FORMS = ("all", "choice", "none")     # QuadraticSurrogate.interactions, preferred first


def candidate_points(analysis: dict) -> list[dict]:
    """The surrogate's best points (`analyse`, "surrogate_best") as named extra points for
    `run_study`: "best_<material>_<hash of the values>", so that a re-run with other rows (other
    candidates) does not mix them up."""
    import hashlib
    out = []
    names = [u["name"] for u in analysis["unknowns"]]
    for c in analysis["surrogate_best"]:
        values = {n: c[n] for n in names}
        tag = hashlib.sha1(json.dumps(values, sort_keys=True).encode()).hexdigest()[:8]
        out.append(dict(values, point=f"best_{values.get('ball_material', 'x')}_{tag}"))
    return out


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
    L = ["# Slip rate under the test bearing's unknown inputs (issue 23, item 2)", ""]
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
    from flexbearing.studies.validate import slip_rate_cases
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
         "same inputs (flexbearing.studies.validate.run_slip_case); `benchmarks/uncertainty_fast_path_check.py`, "
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
