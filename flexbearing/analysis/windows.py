"""A run's time windows and their statistics: the numbers of the report (flexbearing.analysis.report).

Everything is read from the run's results file (flexbearing.simulation.results): the SI datasets under
/outputs and the scene's TOML text under /scene, which gives the phases of the speed profile and
the impacts. Windows: the whole run, each phase of the speed profile, each impact
(`report_windows`); per window the statistics of the quantities below (`phase_table`), of the
cage's motion (`cage_motion_table`), of the power loss (`power_loss_table`) and of the cage's
stress against its yield strength (`cage_strength_rows`). All SI (speeds in rpm where the keys say).

Quantities (each only when the run recorded what it needs)

    outer_contact_stress   p0 at the outer-race contact of each ball          contact_stress[:, :, 0]
    inner_contact_stress   p0 at the loaded inner-race contact of each ball   max(contact_stress[:, :, 1:])
    pocket_force           ball–pocket normal force of each ball, |F|         pocket_force
    guiding_force          cage–guide-land film force |(F_y, F_z)|            cage_land_force_magnitude
    cage_rim_force         cage–rim contact force (only if ever non-zero)     cage_rim_force
    von_mises_max          maximum von Mises stress over the cage and over    von_mises_max
                           every integrator step of the sample interval
                           (flexbearing.multibody.stress_peak; the mean is over samples)
    film_thickness_min     minimum film thickness of each ball over its       film_thickness_min where
                           loaded contacts (unloaded contacts carry no film)  contact_load > 0
    slip_rate              cage slip S = (n_m - n_c)/n_m                      slip_rate

Statistics over a time window W (a phase of the speed profile, an impact, or the whole run):

    peak  = max over t in W and over the balls of the per-ball value (min for the film thickness;
            for the slip rate, which changes sign, the signed value of largest magnitude)
    p99   = 99th percentile over the samples t in W of the worst ball's value e(t) = max over
            the balls (for the film thickness `p1`, the 1st percentile of the thinnest film; for
            the slip rate the signed 99th or 1st percentile, whichever is larger in magnitude);
            order statistics interpolated linearly (Hyndman & Fan 1996, definition 7, numpy's
            default): with n samples sorted e_(1) <= ... <= e_(n), h = 0.99 (n - 1) + 1 and
            p99 = e_(floor h) + (h - floor h)(e_(floor h + 1) - e_(floor h))
    mean  = mean over t in W and over the balls of the per-ball value

Why p99 beside the peak: the cage's pocket and guiding forces and its stress are dominated by
single ball–cage collisions of a fraction of a sample interval (the von Mises value of a sample is
already the maximum over every integrator step in it). The peak of a window is then one event:
the whole-run peaks of the pocket and guiding forces differ by 12 and 20 % between five equally
valid integrations of the paper's unsteady case (tolerances 0.6–1e-6, scenes/
study_tolerance_scatter.toml), their p99 by 8 and 5 %, their means by 1 and 0.4 %
(benchmarks/results/study/README.md). p99, the level the worst ball exceeds in 1 % of the
window's time, is set by the many collisions of the window (200
samples in a 20 ms impact window at 0.1 ms, i.e. between the 2nd and 3rd largest; 5,500 in the
paper's 0.6 s run). It is a sample statistic: it estimates the share of time, so a run's sample
interval must resolve the signal for it to mean the same thing across runs.

For a per-ball quantity the mean over the balls and time equals the time average of one ball's
signal over whole cage revolutions (every ball passes every azimuth), i.e. the "average value" of
the paper's single-ball curves (Yang et al. 2025, §4.2, Figs. 19–21); the peak is the bearing's
worst ball. Bearing-level quantities (guiding force, von Mises, slip) have one column. Phase
windows are [t_start, t_end) (the last one closed); impact windows are [t_start, t_start + T] of
the load pulse.

Settled or not: the report gives each uniform-speed phase's row (and the whole run's, when it is
one phase) a "settling" verdict (flexbearing.analysis.settling: MSER-5 start-up truncation and a
batch-means trend test of the cage speed, slip, cage forces and stress); the mean and p99 of a
window that has not settled are marked in the report's tables, since they are those of a
transient. The statistics themselves are computed the same way either way.

Cage motion (runs that record "cage_orbit" and "cage_speed"; flexbearing.analysis.cage_motion): per window
the eccentricity ratio e/Cg (mean, max), the share of samples on the guide rim, the whirl ratio
(the cage centre's net whirl angle over the cage's rotation angle) and the velocity dispersion
std/mean of the centre's speed (Ghaisas, Wassgren & Sadeghi 2004); cage_orbit.png draws the orbit
in units of the clearance per speed phase, impact samples in red.

Friction torque and power loss (runs that record "power_loss"; flexbearing.multibody.power_loss): per window
the mean drive torque of the inner ring (the bearing's friction torque), the mean power each
dissipative source takes (traction and rolling resistance at the outer and inner races, contact
damping, pockets, churning, guide land, cage structural damping), the drive and external-load
power, the rate of change of the mechanical energy and the residual of the energy balance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
import warnings

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.simulation.results import Run, opened
from flexbearing.multibody.output_registry import OUTPUT
from flexbearing.analysis.cage_motion import motion_arrays, window_motion


RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class Quantity:
    key: str             # name in tables and file names
    label: str           # axis / table label
    source: str          # the recorded dataset it is made of (flexbearing.multibody.output_registry)
    display_unit: str    # printed unit
    scale: float         # SI -> display
    extreme: str         # "max" (peak = largest value) | "min" (film: smallest) | "absmax"
                         # (slip: the signed value of largest magnitude)
    per_ball: bool       # one column per ball (envelope + ball 1 in plots)

    @property
    def unit(self) -> str:
        """SI unit of the arrays: the source dataset's (flexbearing.multibody.output_registry)."""
        return OUTPUT[self.source].unit

    @property
    def extreme_stat(self) -> str:
        """Name of the window's extreme statistic: "min" for the film, "peak" otherwise."""
        return "min" if self.extreme == "min" else "peak"

    @property
    def percentile_stat(self) -> str:
        """Name of the window's percentile statistic (module doc): "p1" for the film, "p99" otherwise."""
        return "p1" if self.extreme == "min" else "p99"

    @property
    def stats(self) -> tuple[str, str, str]:
        """The window statistics reported for the quantity, in table order."""
        return (self.extreme_stat, self.percentile_stat, "mean")


QUANTITIES = (
    Quantity("outer_contact_stress", "Outer-race contact stress", "contact_stress", "MPa", 1e-6, "max", True),
    Quantity("inner_contact_stress", "Inner-race contact stress", "contact_stress", "MPa", 1e-6, "max", True),
    Quantity("pocket_force", "Pocket force", "pocket_force", "N", 1.0, "max", True),
    Quantity("guiding_force", "Guiding force", "cage_land_force_magnitude", "N", 1.0, "max", False),
    Quantity("cage_rim_force", "Cage rim contact force", "cage_rim_force", "N", 1.0, "max", False),
    Quantity("von_mises_max", "Max. von Mises stress of the cage", "von_mises_max", "MPa", 1e-6, "max", False),
    Quantity("film_thickness_min", "Minimum film thickness", "film_thickness_min", "µm", 1e6, "min", True),
    Quantity("slip_rate", "Cage slip rate", "slip_rate", "%", 100.0, "absmax", False),
)


QUANTITY = {q.key: q for q in QUANTITIES}


def _kind(w0: float, w1: float) -> str:
    if abs(w1 - w0) <= 1e-9 * max(abs(w0), abs(w1), 1.0):
        return "uniform speed"
    return "acceleration" if w1 > w0 else "deceleration"


def speed_phases(scene, duration: float | None = None) -> list[dict]:
    """Phases of the speed profile: [{label, kind, t_start, t_end, speed_start_rpm, speed_end_rpm}].

    From the scene's `phases` list when it has one (one phase each); from a `table_rpm` the
    segments between knots, consecutive segments of the same kind (acceleration, uniform speed,
    deceleration) merged, plus the constant speed after the last knot up to the duration."""
    duration = scene.duration if duration is None else duration
    tab = np.asarray(scene.speed_table)
    segs = []
    for i in range(len(tab) - 1):
        segs.append([tab[i, 0], tab[i + 1, 0], tab[i, 1], tab[i + 1, 1]])
    if tab[-1, 0] < duration - 1e-12:
        segs.append([tab[-1, 0], duration, tab[-1, 1], tab[-1, 1]])
    from_phases = "phases" in scene.data.get("operation", {}).get("speed", {})
    merged = []
    for s in segs:
        k = _kind(s[2], s[3])
        if merged and not from_phases and merged[-1][4] == k:
            merged[-1][1], merged[-1][3] = s[1], s[3]
        else:
            merged.append(s + [k])
    out = []
    for t0, t1, w0, w1, k in merged:
        r0, r1 = w0 * RPM_PER_RAD_S, w1 * RPM_PER_RAD_S
        speed = f"{r0:,.0f} rpm" if k == "uniform speed" else f"{r0:,.0f}→{r1:,.0f} rpm"
        out.append({"label": f"{k} {speed}", "kind": k, "t_start": float(t0), "t_end": float(t1),
                    "speed_start_rpm": float(r0), "speed_end_rpm": float(r1)})
    return out


def impact_windows(scene) -> list[dict]:
    """Impacts of the load spectrum: [{label, kind, t_start, t_end, t_peak, magnitude}] (s, N);
    t_peak is the centre of the pulse (the maximum of a half-sine)."""
    out = []
    for i, (t0, T, fx, fy, fz, _shape) in enumerate(np.asarray(scene.impacts).reshape(-1, 6)):
        mag = float(math.sqrt(fx * fx + fy * fy + fz * fz))
        out.append({"label": f"impact {i + 1} ({mag / 1e3:g} kN at {t0 + 0.5 * T:g} s)", "kind": "impact",
                    "t_start": float(t0), "t_end": float(t0 + T), "t_peak": float(t0 + 0.5 * T),
                    "magnitude": mag})
    return out


def _nanreduce(func, a, axis):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return func(a, axis=axis)


def quantity_arrays(outputs) -> dict[str, np.ndarray]:
    """The report's quantities (module doc) as (n, k) float arrays in SI, k = balls or 1, from a
    mapping of recorded outputs (an h5py group or a dict of arrays); absent ones are left out.
    NaN marks a value that does not exist at that instant (e.g. a ball with no loaded contact)."""
    def get(name):
        return np.asarray(outputs[name][...], dtype=np.float64) if name in outputs else None

    q = {}
    cs = get("contact_stress")
    if cs is not None and cs.ndim == 3:
        q["outer_contact_stress"] = cs[:, :, 0]
        if cs.shape[2] > 1:
            q["inner_contact_stress"] = cs[:, :, 1:].max(axis=2)
    pf = get("pocket_force")
    if pf is not None:
        q["pocket_force"] = np.abs(pf.reshape(pf.shape[0], -1))
    land = get("cage_land_force_magnitude")
    if land is None and "cage_land_force" in outputs:
        lf = get("cage_land_force")
        land = np.hypot(lf[:, 0], lf[:, 1])
    if land is not None:
        q["guiding_force"] = land.reshape(-1, 1)
    rim = get("cage_rim_force")
    if rim is not None and np.any(rim != 0.0):
        q["cage_rim_force"] = np.abs(rim.reshape(-1, 1))
    vm = get("von_mises_max")
    if vm is not None:
        q["von_mises_max"] = vm.reshape(-1, 1)
    film = get("film_thickness_min")
    if film is not None and film.ndim == 3:
        load = get("contact_load")
        loaded = (load > 0.0) if load is not None and load.shape == film.shape else (film > 0.0)
        h = np.where(loaded & np.isfinite(film), film, np.nan)
        q["film_thickness_min"] = _nanreduce(np.nanmin, h, 2)
    slip = get("slip_rate")
    if slip is not None:
        q["slip_rate"] = slip.reshape(-1, 1)
    return q


def envelope(key: str, a: np.ndarray) -> np.ndarray:
    """Per-sample worst ball: max over the balls (min for the film thickness)."""
    f = np.nanmin if QUANTITY[key].extreme == "min" else np.nanmax
    return _nanreduce(f, a, 1)


def window_mask(t: np.ndarray, t0: float, t1: float, closed: bool, dt: float) -> np.ndarray:
    """Samples with t0 <= t < t1 (t <= t1 when closed); tolerance dt·1e-6 on sample times."""
    eps = 1e-6 * dt
    return (t >= t0 - eps) & ((t <= t1 + eps) if closed else (t < t1 - eps))


def window_stats(t: np.ndarray, arrays: dict, mask: np.ndarray) -> dict:
    """peak / mean (module doc) and the time of the peak of every quantity over the masked samples."""
    row = {"n_samples": int(mask.sum())}
    idx = np.flatnonzero(mask)
    for key, a in arrays.items():
        qd = QUANTITY[key]
        sub = a[idx]
        ext = qd.extreme_stat
        ok = np.isfinite(sub)
        if not ok.any():
            row[f"{key}_{ext}"] = row[f"{key}_mean"] = row[f"{key}_t_{ext}"] = None
            continue
        env = envelope(key, sub)
        j = int(np.nanargmin(env) if qd.extreme == "min" else
                np.nanargmax(np.abs(env)) if qd.extreme == "absmax" else np.nanargmax(env))
        row[f"{key}_{ext}"] = float(env[j])
        row[f"{key}_t_{ext}"] = float(t[idx[j]])
        row[f"{key}_{qd.percentile_stat}"] = envelope_percentile(qd, env)
        row[f"{key}_mean"] = float(sub[ok].mean())
    return row


def envelope_percentile(qd: Quantity, env: np.ndarray) -> float:
    """p99 (p1 for the film; signed for the slip) of a window's worst-ball values e(t) (module doc)."""
    e = env[np.isfinite(env)]
    if qd.extreme == "max":
        return float(np.percentile(e, 99.0))
    if qd.extreme == "min":
        return float(np.percentile(e, 1.0))
    lo, hi = np.percentile(e, [1.0, 99.0])
    return float(hi if abs(hi) >= abs(lo) else lo)


def phase_table(run_h5, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """Per-window statistics of the report's quantities (SI; speeds in rpm as the keys say).

    Rows: the whole run, each phase of the speed profile, then each impact window. A row has
    label, kind ("run" | "acceleration" | "uniform speed" | "deceleration" | "impact"), t_start,
    t_end [s], n_samples and for every recorded quantity <key>_peak (<key>_min for the film),
    <key>_p99 (<key>_p1 for the film), <key>_mean and the time of the peak <key>_t_peak (module
    doc for the definitions).
    settle [s]: samples with t < settle (the start-up transient from the quasi-static initial
    state) are left out of every window."""
    return phase_rows(*read_run(run_h5), include_impacts, settle)


def read_run(run: Run | str):
    """(t, quantity arrays, scene or None, sample interval) of a run (an open Run or a path)."""
    with opened(run) as r:
        return r.t, quantity_arrays(r.outputs), r.scene, r.dt


def report_windows(t, scene, dt, include_impacts: bool = True, settle: float = 0.0) -> list[tuple[dict, np.ndarray]]:
    """The report's time windows of a run: (header, sample mask) for the whole run, each phase of
    the speed profile, then each impact (module doc); samples before `settle` left out of all."""
    if len(t) == 0:
        return []
    t_end = float(t[-1])
    if not 0.0 <= settle < t_end:
        raise InputError(f"settle = {settle:g} s must leave samples to report (allowed range "
                         f"[0, {t_end:g}) s)")
    kept = t >= settle - 1e-6 * dt
    out = [({"label": "whole run", "kind": "run", "t_start": max(float(t[0]), settle), "t_end": t_end}, kept)]
    if scene is not None:
        phases = speed_phases(scene)
        for i, ph in enumerate(phases):
            if ph["t_start"] > t_end + 1e-6 * dt:
                break            # an interrupted run: phases it never reached are left out
            mask = window_mask(t, ph["t_start"], ph["t_end"], i == len(phases) - 1, dt) & kept
            if mask.any():
                out.append(({**ph, "t_start": max(ph["t_start"], settle)}, mask))
        if include_impacts:
            for imp in impact_windows(scene):
                if imp["t_start"] > t_end + 1e-6 * dt:
                    continue
                mask = window_mask(t, imp["t_start"], imp["t_end"], True, dt) & kept
                if mask.any():
                    out.append((dict(imp), mask))
    return out


def phase_rows(t, arrays, scene, dt, include_impacts: bool, settle: float) -> list[dict]:
    """`phase_table` of data already read (`read_run`)."""
    return [{**head, **window_stats(t, arrays, mask)}
            for head, mask in report_windows(t, scene, dt, include_impacts, settle)]


def read_motion(run: Run | str):
    """(cage-motion arrays of flexbearing.analysis.cage_motion.motion_arrays or None, scene or None,
    sample interval) of a run (an open Run or a path)."""
    with opened(run) as r:
        guidance = r.scene.bearing.cage.guidance if r.scene is not None else "outer"
        return motion_arrays(r.outputs, guidance), r.scene, r.dt


def cage_motion_table(run_h5, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """Cage-motion statistics per report window (whole run, phases, impacts; `report_windows`):
    eps_mean, eps_max, rim_fraction, whirl_ratio, whirl_rate_mean [rad/s], centre_speed_mean [m/s],
    velocity_dispersion, held_fraction, cage_revolutions (flexbearing.analysis.cage_motion.window_motion). [] when the run did
    not record the cage orbit (scene output "cage_orbit") and the cage speed."""
    return cage_motion_rows(*read_motion(run_h5), include_impacts, settle)


def cage_motion_rows(motion, scene, dt, include_impacts: bool, settle: float) -> list[dict]:
    if motion is None:
        return []
    m = motion
    rows = []
    for head, mask in report_windows(m["t"], scene, dt, include_impacts, settle):
        rows.append({**head, **window_motion(m["t"][mask], m["centre_yz"][mask], m["cage_speed"][mask],
                                             eccentricity_ratio=m["eccentricity_ratio"][mask]),
                     "centre_reference": m.get("reference", "")})
    return rows


MOTION_ROWS = (   # (label, key, scale, format) of the cage-motion table
    ("Eccentricity ratio e/Cg, mean", "eps_mean", 1.0, "{:.3f}"),
    ("Eccentricity ratio e/Cg, max", "eps_max", 1.0, "{:.3f}"),
    ("Time on the guide rim (%)", "rim_fraction", 100.0, "{:.1f}"),
    ("Whirl ratio (whirl revolutions per cage revolution)", "whirl_ratio", 1.0, "{:+.3f}"),
    ("Cage-centre speed, mean (mm/s)", "centre_speed_mean", 1e3, "{:.3g}"),
    ("Velocity dispersion std/mean of the centre speed", "velocity_dispersion", 1.0, "{:.3f}"),
    ("Time held at one azimuth (%)", "held_fraction", 100.0, "{:.1f}"),
)


def read_power(run: Run | str):
    """(t, the recorded power datasets, scene or None, sample interval) of a run (an open Run or a
    path); data None when the run did not record the scene output "power_loss"."""
    from flexbearing.multibody.power_loss import RECORDED
    names = list(RECORDED.values()) + ["ring_drive_torque", "inner_ring_speed"]
    optional = ("external_load_power", "mechanical_energy")
    with opened(run) as r:
        g = r.outputs
        data = None
        if all(n in g for n in names):
            data = {n: g[n][...] for n in names + [n for n in optional if n in g]}
        return r.t, data, r.scene, r.dt


def power_loss_table(run_h5, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """Friction torque and power loss by source per report window (whole run, phases, impacts;
    `report_windows`), W and N·m (flexbearing.multibody.power_loss.window_power). [] when the run did not record
    the scene output "power_loss"."""
    return power_loss_rows(*read_power(run_h5), include_impacts, settle)


def power_loss_rows(t, data, scene, dt, include_impacts: bool, settle: float) -> list[dict]:
    from flexbearing.multibody.power_loss import window_power
    if data is None:
        return []
    return [{**head, **window_power(t[mask], {k: v[mask] for k, v in data.items()})}
            for head, mask in report_windows(t, scene, dt, include_impacts, settle)]


def cage_strength_rows(t, arrays, scene, dt, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """The cage's maximum von Mises stress against its material's yield strength, per report window.

        utilization = sigma_vM / R_e        (R_e: the scene's cage.yield_strength; 40CrNiMoA 835 MPa)

    of the window's peak and p99 (window_stats), and the share of its sample intervals whose maximum
    (over every integrator step, flexbearing.multibody.stress_peak) exceeds R_e, with their number. The cage
    model is linear elastic: above R_e its stress is the elastic one, an upper bound of the real
    stress with a local plastic zone. [] for a rigid cage or a scene without a yield strength."""
    ys = None if scene is None else scene.flexible.get("yield_strength")
    if ys is None or "von_mises_max" not in arrays:
        return []
    vm = arrays["von_mises_max"][:, 0]
    rows = []
    for head, mask in report_windows(t, scene, dt, include_impacts, settle):
        st = window_stats(t, {"von_mises_max": arrays["von_mises_max"]}, mask)
        v = vm[mask]
        v = v[np.isfinite(v)]
        above = int(np.count_nonzero(v > ys))
        rows.append({**head, "yield_strength": float(ys), "von_mises_max_peak": st["von_mises_max_peak"],
                     "von_mises_max_t_peak": st["von_mises_max_t_peak"],
                     "utilization_peak": None if st["von_mises_max_peak"] is None else st["von_mises_max_peak"] / ys,
                     "utilization_p99": None if st["von_mises_max_p99"] is None else st["von_mises_max_p99"] / ys,
                     "intervals_above_yield": above,
                     "share_above_yield": above / v.size if v.size else None})
    return rows


def window_title(row: dict) -> str:
    """The column title of a window row (tables, plot panels)."""
    if row["kind"] == "run":
        return f"whole run {row['t_start']:g}–{row['t_end']:g} s"
    if row["kind"] == "impact":
        return f"{row['label'].split(' (')[0]}, {row['t_start']:g}–{row['t_end']:g} s"
    return f"{row['label']}, {row['t_start']:g}–{row['t_end']:g} s"
