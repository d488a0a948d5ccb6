"""`flexbearing report`: time-history plots, per-phase tables and the cage's von Mises field of a run.

    flexbearing report RUN.h5 [--compare OTHER.h5] [-o DIR] [--frames auto|t1,t2,...]
                              [--series T0:T1[:N]] [--displacement-scale S] [--quiet]

Everything is read from the run's results file (coupling.results): the SI datasets under
/outputs, their `unit` attributes, and the scene's TOML text under /scene, which gives the phases
of the speed profile and the impacts. Files stay SI; only the printed tables and the plot axes use
the engineer's units (MPa, N, µm, rpm, %) and say so.

Quantities (each only when the run recorded what it needs)

    outer_contact_stress   p0 at the outer-race contact of each ball          contact_stress[:, :, 0]
    inner_contact_stress   p0 at the loaded inner-race contact of each ball   max(contact_stress[:, :, 1:])
    pocket_force           ball–pocket normal force of each ball, |F|         pocket_force
    guiding_force          cage–guide-land film force |(F_y, F_z)|            cage_land_force_magnitude
    cage_rim_force         cage–rim contact force (only if ever non-zero)     cage_rim_force
    von_mises_max          maximum von Mises stress over the cage and over    von_mises_max
                           every integrator step of the sample interval
                           (multibody.stress_peak; the mean is over samples)
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

Cage motion (runs that record "cage_orbit" and "cage_speed"; coupling.cage_motion): per window
the eccentricity ratio e/Cg (mean, max), the share of samples on the guide rim, the whirl ratio
(the cage centre's net whirl angle over the cage's rotation angle) and the velocity dispersion
std/mean of the centre's speed (Ghaisas, Wassgren & Sadeghi 2004); cage_orbit.png draws the orbit
in units of the clearance per speed phase, impact samples in red.

Friction torque and power loss (runs that record "power_loss"; multibody.power_loss): per window
the mean drive torque of the inner ring (the bearing's friction torque), the mean power each
dissipative source takes (traction and rolling resistance at the outer and inner races, contact
damping, pockets, churning, guide land, cage structural damping), the drive and external-load
power, the rate of change of the mechanical energy and the residual of the energy balance.

The cage's stress field (flexible cage): rebuilt from the recorded modal coordinates at every mesh
node, for ParaView at the peaks and, with --series, over a window with the balls
(coupling.field_export), and as a picture at the run's maximum (coupling.stress_picture).
"""
from __future__ import annotations

import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common.validation import InputError

RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class Quantity:
    key: str             # name in tables and file names
    label: str           # axis / table label
    unit: str            # SI unit of the arrays
    display_unit: str    # printed unit
    scale: float         # SI -> display
    extreme: str         # "max" (peak = largest value) | "min" (film: smallest) | "absmax"
                         # (slip: the signed value of largest magnitude)
    per_ball: bool       # one column per ball (envelope + ball 1 in plots)

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
    Quantity("outer_contact_stress", "Outer-race contact stress", "Pa", "MPa", 1e-6, "max", True),
    Quantity("inner_contact_stress", "Inner-race contact stress", "Pa", "MPa", 1e-6, "max", True),
    Quantity("pocket_force", "Pocket force", "N", "N", 1.0, "max", True),
    Quantity("guiding_force", "Guiding force", "N", "N", 1.0, "max", False),
    Quantity("cage_rim_force", "Cage rim contact force", "N", "N", 1.0, "max", False),
    Quantity("von_mises_max", "Max. von Mises stress of the cage", "Pa", "MPa", 1e-6, "max", False),
    Quantity("film_thickness_min", "Minimum film thickness", "m", "µm", 1e6, "min", True),
    Quantity("slip_rate", "Cage slip rate", "1", "%", 100.0, "absmax", False),
)
QUANTITY = {q.key: q for q in QUANTITIES}


# ---------------------------------------------------------------- reading a run

def _check_run(path) -> Path:
    import h5py
    path = Path(path)
    if not path.is_file():
        raise InputError(f"run file {str(path)!r} does not exist (a results file written by "
                         f"`flexbearing run`, .h5)")
    try:
        with h5py.File(path, "r") as f:
            fmt = f.attrs.get("format")
            ok = "outputs/time" in f
    except OSError as exc:
        raise InputError(f"run file {str(path)!r} is not an HDF5 file ({exc})") from None
    if fmt != "flexbearing-results" or not ok:
        raise InputError(f"{path} is not a flexbearing results file (format attribute {fmt!r}, "
                         f"expected 'flexbearing-results' with /outputs/time)")
    return path


def run_scene(f):
    """The Scene a run was made from (its stored TOML text), or None if it cannot be parsed."""
    from coupling.scene import loads_scene, parse_scene
    if "scene" not in f:
        return None
    raw = f["scene"][()]
    text = raw.decode() if isinstance(raw, bytes) else str(raw)
    try:
        return loads_scene(text, str(f.attrs.get("scene_path", "")))
    except Exception:
        pass
    try:   # results.py stores the parsed scene as JSON when it has no TOML text (case sets)
        return parse_scene(json.loads(text), path=str(f.attrs.get("scene_path", "")))
    except Exception:
        return None


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
    import warnings
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
    return _phase_rows(*_read_run(_check_run(run_h5)), include_impacts, settle)


def _sample_interval(f, t) -> float:
    """The run's sample interval, s: its attribute, else the mean spacing of the samples t."""
    return float(f.attrs.get("sample_interval", np.diff(t).mean() if len(t) > 1 else 1.0))


def _timebase(f):
    """(sample times, scene or None, sample interval) of an open run file."""
    t = f["outputs/time"][...]
    return t, run_scene(f), _sample_interval(f, t)


def _read_run(path):
    """(t, quantity arrays, scene or None, sample interval) of a checked run file, read once."""
    import h5py
    with h5py.File(path, "r") as f:
        t, scene, dt = _timebase(f)
        arrays = quantity_arrays(f["outputs"])
    return t, arrays, scene, dt


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


def _phase_rows(t, arrays, scene, dt, include_impacts: bool, settle: float) -> list[dict]:
    """`phase_table` of data already read (`_read_run`)."""
    return [{**head, **window_stats(t, arrays, mask)}
            for head, mask in report_windows(t, scene, dt, include_impacts, settle)]


def _read_motion(path):
    """(cage-motion arrays of coupling.cage_motion.motion_arrays or None, scene or None, sample interval)."""
    import h5py
    from coupling.cage_motion import motion_arrays
    with h5py.File(path, "r") as f:
        motion = motion_arrays(f["outputs"])
        _, scene, dt = _timebase(f)
    return motion, scene, dt


def cage_motion_table(run_h5, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """Cage-motion statistics per report window (whole run, phases, impacts; `report_windows`):
    eps_mean, eps_max, rim_fraction, whirl_ratio, whirl_rate_mean [rad/s], centre_speed_mean [m/s],
    velocity_dispersion, held_fraction, cage_revolutions (coupling.cage_motion.window_motion). [] when the run did
    not record the cage orbit (scene output "cage_orbit") and the cage speed."""
    return _cage_motion_rows(*_read_motion(_check_run(run_h5)), include_impacts, settle)


def _cage_motion_rows(motion, scene, dt, include_impacts: bool, settle: float) -> list[dict]:
    from coupling.cage_motion import window_motion
    if motion is None:
        return []
    m = motion
    rows = []
    for head, mask in report_windows(m["t"], scene, dt, include_impacts, settle):
        rows.append({**head, **window_motion(m["t"][mask], m["centre_yz"][mask], m["cage_speed"][mask],
                                             eccentricity_ratio=m["eccentricity_ratio"][mask])})
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


def _motion_markdown(rows: list[dict]) -> str:
    head = ["quantity"] + [_col_name(r) for r in rows]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * len(rows)]
    for label, key, scale, fmt in MOTION_ROWS:
        cells = [label] + ["–" if r.get(key) is None else fmt.format(r[key] * scale) for r in rows]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _read_power(path):
    """(t, the recorded power datasets, scene or None, sample interval); data None when the run did
    not record the scene output "power_loss"."""
    import h5py
    from multibody.power_loss import RECORDED
    names = list(RECORDED.values()) + ["ring_drive_torque", "inner_ring_speed"]
    optional = ("external_load_power", "mechanical_energy")
    with h5py.File(path, "r") as f:
        g = f["outputs"]
        t, scene, dt = _timebase(f)
        data = None
        if all(n in g for n in names):
            data = {n: g[n][...] for n in names + [n for n in optional if n in g]}
    return t, data, scene, dt


def power_loss_table(run_h5, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """Friction torque and power loss by source per report window (whole run, phases, impacts;
    `report_windows`), W and N·m (multibody.power_loss.window_power). [] when the run did not record
    the scene output "power_loss"."""
    return _power_rows(*_read_power(_check_run(run_h5)), include_impacts, settle)


def _power_rows(t, data, scene, dt, include_impacts: bool, settle: float) -> list[dict]:
    from multibody.power_loss import window_power
    if data is None:
        return []
    return [{**head, **window_power(t[mask], {k: v[mask] for k, v in data.items()})}
            for head, mask in report_windows(t, scene, dt, include_impacts, settle)]


def _power_markdown(rows: list[dict]) -> str:
    from multibody.power_loss import BREAKDOWN
    head = ["quantity"] + [_col_name(r) for r in rows]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * len(rows)]

    def line(label, cells):
        lines.append("| " + " | ".join([label] + cells) + " |")

    def watts(v):
        return "–" if v is None else f"{(v if abs(v) >= 0.5 else 0.0):,.0f}"

    line("Friction torque (drive torque of the inner ring), N·m", [f"{r['drive_torque']:.3g}" for r in rows])
    line("**Power loss, W**", [f"**{watts(r['loss'])}**" for r in rows])
    for label, key in BREAKDOWN:
        line(f"&nbsp;&nbsp;{label}, W (%)",
             [f"{watts(r[key])} ({100.0 * r[key] / r['loss']:.1f})" if r["loss"] else watts(r[key]) for r in rows])
    line("Drive power T·omega_i, W", [watts(r["drive_power"]) for r in rows])
    line("External load power F·v_ring, W", [watts(r["load_power"]) for r in rows])
    line("Rate of change of the mechanical energy, W", [watts(r["energy_rate"]) for r in rows])
    line("Balance residual (drive + load − loss − energy rate), W", [watts(r["residual"]) for r in rows])
    return "\n".join(lines)


def cage_strength_rows(t, arrays, scene, dt, include_impacts: bool = True, settle: float = 0.0) -> list[dict]:
    """The cage's maximum von Mises stress against its material's yield strength, per report window.

        utilization = sigma_vM / R_e        (R_e: the scene's cage.yield_strength; 40CrNiMoA 835 MPa)

    of the window's peak and p99 (window_stats), and the share of its sample intervals whose maximum
    (over every integrator step, multibody.stress_peak) exceeds R_e, with their number. The cage
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


def _strength_markdown(rows: list[dict]) -> str:
    head = ["quantity"] + [_col_name(r) for r in rows]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * len(rows)]

    def line(label, key, fmt, scale=1.0):
        cells = ["–" if r[key] is None else fmt.format(r[key] if scale == 1.0 else r[key] * scale) for r in rows]
        lines.append("| " + " | ".join([label] + cells) + " |")
    line("Max. von Mises stress, peak (MPa)", "von_mises_max_peak", "{:,.0f}", 1e-6)
    line("Utilization peak / R_e", "utilization_peak", "{:.2f}")
    line("Utilization p99 / R_e", "utilization_p99", "{:.2f}")
    line("Sample intervals above R_e", "intervals_above_yield", "{:d}")
    line("Share of the window above R_e (%)", "share_above_yield", "{:.2f}", 100.0)
    return "\n".join(lines)


def write_orbit_plot(run_h5, out_dir, settle: float = 0.0) -> Path | None:
    """cage_orbit.png: the cage centre in units of the guide clearance (the rim is the unit circle),
    one panel per phase of the speed profile, samples inside impact windows in red; below, the
    eccentricity ratio against time. None when the run did not record the cage orbit."""
    from coupling.cage_motion import normalised_orbit
    path = _check_run(run_h5)
    motion, scene, dt = _read_motion(path)
    if motion is None or motion["t"].size == 0:
        return None
    t = motion["t"]
    xy = normalised_orbit(motion["centre_yz"], motion["eccentricity_ratio"])
    windows = report_windows(t, scene, dt, True, settle)
    panels = [w for w in windows if w[0]["kind"] not in ("run", "impact")] or windows[:1]
    in_impact = np.zeros(t.size, dtype=bool)
    for head, mask in windows:
        if head["kind"] == "impact":
            in_impact |= mask
    plt = _style()
    n = len(panels)
    fig = plt.figure(figsize=(max(3.3 * n, 6.0), 5.6), layout="constrained")
    grid = fig.add_gridspec(2, n, height_ratios=(3.0, 1.3))
    circle = np.linspace(0.0, 2.0 * np.pi, 361)
    lim = max(1.05, float(np.nanmax(np.abs(xy))) * 1.05 if xy.size else 1.05)
    for i, (head, mask) in enumerate(panels):
        ax = fig.add_subplot(grid[0, i])
        ax.plot(np.cos(circle), np.sin(circle), color="0.3", lw=0.8, ls="--", label="guide rim (e = Cg)")
        ax.plot(xy[mask, 0], xy[mask, 1], color="tab:blue", lw=0.5, label="cage centre")
        hit = mask & in_impact
        if hit.any():
            ax.plot(xy[hit, 0], xy[hit, 1], ".", color="tab:red", ms=1.5, label="during an impact")
        ax.set_aspect("equal")
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_xlabel("y / Cg")
        if i == 0:
            ax.set_ylabel("z / Cg")
        ax.set_title(_col_name(head), fontsize=8)
    ax = fig.add_subplot(grid[1, :])
    ax.plot(t, motion["eccentricity_ratio"], color="tab:blue", lw=0.7)
    ax.axhline(1.0, color="0.3", lw=0.8, ls="--")
    ax.set_xlabel("Time (s)")
    ax.set_ylabel("e / Cg")
    ax.set_xlim(float(t[0]), float(t[-1]))
    fig.axes[0].legend(loc="lower left", fontsize=6, framealpha=0.8)
    out = Path(out_dir) / "cage_orbit.png"
    fig.savefig(out)
    plt.close(fig)
    return out


# ---------------------------------------------------------------- plots

def _run_data(path):
    import h5py
    with h5py.File(path, "r") as f:
        t = f["outputs/time"][...]
        arrays = quantity_arrays(f["outputs"])
        speed = {k: f["outputs"][k][...] for k in ("inner_ring_speed", "cage_speed", "nominal_cage_speed")
                 if k in f["outputs"]}
        scene = run_scene(f)
        name = str(f.attrs.get("scene_name", Path(path).stem))
        status = str(f.attrs.get("status", ""))
        cage = str(f.attrs.get("cage_model", ""))
    phases = speed_phases(scene) if scene is not None else []
    impacts = impact_windows(scene) if scene is not None else []
    return {"t": t, "arrays": arrays, "speed": speed, "phases": phases, "impacts": impacts,
            "name": name, "status": status, "cage_model": cage, "path": Path(path)}


def _style():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 9, "axes.titlesize": 10, "axes.labelsize": 9,
                         "legend.fontsize": 7.5, "xtick.direction": "in", "ytick.direction": "in",
                         "xtick.top": True, "ytick.right": True, "axes.grid": True,
                         "grid.alpha": 0.25, "grid.linewidth": 0.5, "savefig.dpi": 150,
                         "lines.linewidth": 0.9})
    return plt


def _decorate(ax, data, small=False):
    """Shade and label the phases of the speed profile, mark the impact instants."""
    import matplotlib.transforms as mtransforms
    trans = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    fs = 6 if small else 7
    for i, ph in enumerate(data["phases"]):
        if len(data["phases"]) > 1 and i % 2 == 0:
            ax.axvspan(ph["t_start"], ph["t_end"], color="0.5", alpha=0.08, lw=0, zorder=0)
        if len(data["phases"]) > 1 or not small:
            kind = ph["kind"].replace("uniform speed", "uniform")
            rpm = (f"{ph['speed_start_rpm']:,.0f} rpm" if ph["kind"] == "uniform speed" else
                   f"{ph['speed_start_rpm']:,.0f}→{ph['speed_end_rpm']:,.0f} rpm")
            ax.text(0.5 * (ph["t_start"] + ph["t_end"]), 0.985, f"{kind}\n{rpm}", transform=trans,
                    ha="center", va="top", fontsize=fs, color="0.25", zorder=5,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.7))
        if i > 0:
            ax.axvline(ph["t_start"], color="0.55", lw=0.6, ls="-", zorder=1)
    for j, imp in enumerate(data["impacts"]):
        ax.axvline(imp["t_peak"], color="tab:red", lw=0.8, ls=(0, (3, 2)), zorder=1,
                   label="impact (load peak)" if j == 0 else None)
        ax.text(imp["t_peak"], 0.02, f" I{j + 1}", transform=trans, color="tab:red", fontsize=fs,
                ha="left", va="bottom")
    if data["t"].size:
        ax.set_xlim(float(data["t"][0]), float(data["t"][-1]))


def _plot_quantity(ax, key, data, compare, small=False):
    qd = QUANTITY[key]
    a = data["arrays"][key]
    t = data["t"]
    if compare is not None and key in compare["arrays"]:
        ax.plot(compare["t"], envelope(key, compare["arrays"][key]) * qd.scale, color="0.6", lw=0.7,
                label=f"{compare['name']}: worst ball" if qd.per_ball else compare["name"], zorder=2)
    if qd.per_ball:
        # ball 1 on top: the paper's curves follow one ball (its contact stress oscillates as it
        # orbits through the load zone), the envelope is the worst ball at each instant
        ax.plot(t, a[:, 0] * qd.scale, color="tab:orange", lw=0.5, alpha=0.85, label=f"{data['name']}: ball 1",
                zorder=5)
        ax.plot(t, envelope(key, a) * qd.scale, color="tab:blue", lw=0.9, zorder=4,
                label=f"{data['name']}: worst ball")
    else:
        ax.plot(t, a[:, 0] * qd.scale, color="tab:blue", lw=0.9, label=data["name"], zorder=4)
    _decorate(ax, data, small)
    ax.set_ylabel(f"{qd.label} ({qd.display_unit})" if not small else f"{qd.label}\n({qd.display_unit})")
    # headroom for the phase labels
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.22 * (hi - lo))


def _plot_speed(ax, data, compare, small=False):
    sp = data["speed"]
    if compare is not None and "inner_ring_speed" in compare["speed"]:
        ax.plot(compare["t"], compare["speed"]["inner_ring_speed"] * RPM_PER_RAD_S, color="0.6", lw=0.7,
                label=f"{compare['name']}: inner ring")
    if "inner_ring_speed" in sp:
        ax.plot(data["t"], sp["inner_ring_speed"] * RPM_PER_RAD_S, color="k", lw=1.0, label="inner ring")
    if "cage_speed" in sp:
        ax.plot(data["t"], sp["cage_speed"] * RPM_PER_RAD_S, color="tab:blue", lw=0.8, label="cage")
    if "nominal_cage_speed" in sp:
        ax.plot(data["t"], sp["nominal_cage_speed"] * RPM_PER_RAD_S, color="tab:blue", lw=0.8,
                ls="--", label="cage, no slip (n_m)")
    _decorate(ax, data, small)
    ax.set_ylabel("Speed (rpm)")
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.22 * (hi - lo))


def write_plots(run_h5, out_dir, compare=None) -> list[Path]:
    """One PNG per recorded quantity (time history, phases shaded and labelled, impacts marked;
    the `compare` run overlaid in grey), speed.png, and overview.png with all of them."""
    path = _check_run(run_h5)
    data = _run_data(path)
    cmp_data = _run_data(_check_run(compare)) if compare is not None else None
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    plt = _style()
    keys = [q.key for q in QUANTITIES if q.key in data["arrays"]]
    written = []
    title = f"{data['name']} ({data['cage_model']} cage)" + (f" vs {cmp_data['name']}" if cmp_data else "")
    if data["status"] and data["status"] != "complete":
        title += f" — run status: {data['status']}"
    if data["speed"]:
        fig, ax = plt.subplots(figsize=(7.0, 3.6), layout="constrained")
        _plot_speed(ax, data, cmp_data)
        ax.set_xlabel("Time (s)")
        ax.set_title(title)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
        written.append(out_dir / "speed.png")
        fig.savefig(written[-1])
        plt.close(fig)
    for key in keys:
        fig, ax = plt.subplots(figsize=(7.0, 3.6), layout="constrained")
        _plot_quantity(ax, key, data, cmp_data)
        ax.set_xlabel("Time (s)")
        ax.set_title(title)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
        written.append(out_dir / f"{key}.png")
        fig.savefig(written[-1])
        plt.close(fig)
    panels = (["speed"] if data["speed"] else []) + keys
    if panels:
        ncol = 2 if len(panels) > 3 else 1
        nrow = math.ceil(len(panels) / ncol)
        height = 2.3 * nrow + 1.1
        fig, axes = plt.subplots(nrow, ncol, figsize=(11.0, height), sharex=True, squeeze=False)
        for ax, key in zip(axes.flat, panels):
            if key == "speed":
                _plot_speed(ax, data, cmp_data, small=True)
            else:
                _plot_quantity(ax, key, data, cmp_data, small=True)
        for ax in axes.flat[len(panels):]:
            ax.set_visible(False)
        for ax in axes[-1]:
            ax.set_xlabel("Time (s)")
        if len(panels) % ncol:
            axes[-2, -1].xaxis.set_tick_params(labelbottom=True)
            axes[-2, -1].set_xlabel("Time (s)")
        handles, labels = [], []
        for ax in axes.flat[:len(panels)]:
            for h, lab in zip(*ax.get_legend_handles_labels()):
                if lab not in labels:
                    handles.append(h)
                    labels.append(lab)
        fig.suptitle(title)
        # matplotlib 3.6: constrained layout ignores figure legends, so reserve the strip by hand
        fig.tight_layout(rect=(0.0, 0.65 / height, 1.0, 1.0 - 0.1 / height))
        fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 4), fontsize=7.5,
                   frameon=False)
        written.append(out_dir / "overview.png")
        fig.savefig(written[-1])
        plt.close(fig)
    return written


# ---------------------------------------------------------------- report.md

def _fmt(v, scale: float) -> str:
    if v is None or not np.isfinite(v):
        return "–"
    x = v * scale
    ax = abs(x)
    if ax >= 100:
        return f"{x:,.0f}"
    if ax >= 10:
        return f"{x:.1f}"
    return f"{x:.2f}" if ax >= 0.1 or x == 0 else f"{x:.3g}"


def _stat_rows(keys) -> list[tuple[str, str, Quantity]]:
    rows = []
    for k in keys:
        qd = QUANTITY[k]
        for stat in qd.stats:
            rows.append((f"{qd.label}, {stat} ({qd.display_unit})", f"{k}_{stat}", qd))
    return rows


def _markdown_table(columns: list[tuple[str, dict]], keys, increase_from: int | None = None) -> str:
    head = ["quantity"] + [c for c, _ in columns]
    if increase_from is not None:
        head.append(f"change vs {columns[increase_from][0]}")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * (len(head) - 1)]
    for label, field, qd in _stat_rows(keys):
        cells = [label] + [_fmt(row.get(field), qd.scale) for _, row in columns]
        if increase_from is not None:
            a, b = columns[increase_from][1].get(field), columns[-1][1].get(field)
            if a is None or b is None:
                cells.append("–")
            elif qd.display_unit == "%":      # a signed ratio (slip): the difference, in points
                cells.append(f"{(b - a) * qd.scale:+.2f} points")
            else:
                cells.append(f"{100 * (b - a) / abs(a):+.1f} %" if a != 0 else "–")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _col_name(row: dict) -> str:
    if row["kind"] == "run":
        return f"whole run {row['t_start']:g}–{row['t_end']:g} s"
    if row["kind"] == "impact":
        return f"{row['label'].split(' (')[0]}, {row['t_start']:g}–{row['t_end']:g} s"
    return f"{row['label']}, {row['t_start']:g}–{row['t_end']:g} s"


def write_report(run_h5, out_dir, compare=None, frames="auto", reduced_cage=None,
                 quiet: bool = True, settle: float = 0.0, series: str | None = None,
                 displacement_scale: float | None = None) -> dict:
    """Plots, the per-phase table (report.md, report.json), the same as one self-contained page
    with the plots embedded (report.html, coupling.html_page) and, for a flexible-cage run, the
    picture of the cage's stress field at the run's maximum and the von Mises XDMF frames; with
    `series` ("T0:T1[:N]") the ParaView time series of that window (coupling.field_export.
    write_series, written first: a bad window stops the report). Returns {"report", "html",
    "json", "plots", "xdmf", "stress_picture", "series"} (None where not written)."""
    import h5py

    from coupling import field_export
    path = _check_run(run_h5)
    cmp_path = _check_run(compare) if compare is not None else None
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    series_out = None
    if series is not None:
        say(f"report: ParaView series {series} of {path.name}")
        series_out = field_export.write_series(path, out_dir, series, reduced_cage=reduced_cage,
                                               displacement_scale=displacement_scale)
    run = _read_run(path)
    rows = _phase_rows(*run, True, settle)
    cmp_rows = phase_table(cmp_path, settle=settle) if cmp_path else None
    amplification = _impact_amplification(*run)
    motion_rows = _cage_motion_rows(*_read_motion(path), True, settle)
    power_rows = _power_rows(*_read_power(path), True, settle)
    strength_rows = cage_strength_rows(*run, True, settle)
    say(f"report: plots of {path.name} -> {out_dir}")
    plots = write_plots(path, out_dir, compare=cmp_path)
    orbit_png = write_orbit_plot(path, out_dir, settle=settle) if motion_rows else None
    with h5py.File(path, "r") as f:
        name = str(f.attrs.get("scene_name", path.stem))
        status = str(f.attrs.get("status", ""))
        cage = str(f.attrs.get("cage_model", ""))
        flexible = "cage_modal_coordinates_full" in f["outputs"]
    cmp_name = None
    if cmp_path:
        with h5py.File(cmp_path, "r") as f:
            cmp_name = str(f.attrs.get("scene_name", cmp_path.stem))
    xdmf, xdmf_note = None, "not written: the run has no flexible-cage modal coordinates (rigid cage)."
    picture, picture_md = None, []
    if flexible:
        try:
            say("report: von Mises XDMF frames and the stress picture")
            xdmf = field_export.write_von_mises_xdmf(path, out_dir, frames, reduced_cage=reduced_cage)
            xdmf_note = f"`{xdmf.name}` (+ `{xdmf.with_suffix('.h5').name}`; frames in `{xdmf.with_suffix('.json').name}`)"
        except InputError as exc:
            xdmf_note = f"not written: {exc}"
            say(f"report: {xdmf_note}")
        from coupling.stress_picture import picture_markdown, write_stress_picture
        try:
            picture, facts = write_stress_picture(path, out_dir, reduced_cage=reduced_cage, settle=settle,
                                                  yield_strength=strength_rows[0]["yield_strength"]
                                                  if strength_rows else None)
            picture_md = picture_markdown(picture, facts)
        except InputError as exc:
            picture_md = ["## Cage von Mises stress at the run's maximum", "", f"Not drawn: {exc}", ""]
            say(f"report: stress picture not drawn: {exc}")
    keys = [q.key for q in QUANTITIES if rows and f"{q.key}_mean" in rows[0]]
    md = [f"# Run report: {name}", "",
          f"- results file: `{path}` (status: {status}, cage: {cage}, "
          f"{rows[0]['n_samples'] if rows else 0} samples, {rows[0]['t_start'] if rows else 0:g}–"
          f"{rows[0]['t_end'] if rows else 0:g} s)"]
    if cmp_path:
        md.append(f"- compared with: `{cmp_path}` ({cmp_name})")
    md += ["- source: the SI datasets of the results file (Pa, N, m, rad/s, 1); shown here in MPa, N, "
           "µm, rpm and %. Machine-readable SI values: `report.json`.",
           "- peak = maximum over the window and over the balls (the worst ball); min for the film "
           "thickness; for the slip rate the signed value of largest magnitude. p99 = the 99th percentile over the window's "
           "samples of the worst ball's value, the level it exceeds in 1 % of the time (p1 of the thinnest film; "
           "robust where the peak is one ball–cage collision). mean = mean over the window and over the balls (= one ball's time average over "
           "whole cage revolutions, the paper's \"average value\"). Inner-race contact stress: the "
           "loaded one of the two inner halves; film: the smallest over a ball's loaded contacts; "
           "guiding force: cage–land film force magnitude.",
           "- phase windows [t_start, t_end), the last one closed; impact windows = the load pulse"
           + (f"; samples before t = {settle:g} s (start-up transient) left out of every window." if settle
              else "; the start-up transient from the quasi-static initial state is included "
                   "(`--settle S` leaves it out)."), ""]
    if cmp_rows:
        md += [f"## {cmp_name} vs {name} (whole runs)", "",
               _markdown_table([(cmp_name, cmp_rows[0]), (name, rows[0])], keys, increase_from=0), ""]
    if rows:
        md += [f"## {name}: per phase of the speed profile and per impact", "",
               _markdown_table([(_col_name(r), r) for r in rows], keys), ""]
        peaks = [(r["label"], r.get(f"{k}_t_peak")) for r in rows[1:] for k in ("von_mises_max",)
                 if r.get(f"{k}_t_peak") is not None]
        if peaks:
            md += ["Instants of maximum von Mises stress: " + "; ".join(f"{lab}: {tp:g} s" for lab, tp in peaks), ""]
    if strength_rows:
        ys = strength_rows[0]["yield_strength"]
        above = strength_rows[0]["intervals_above_yield"]
        md += ["## Cage stress against the yield strength", "",
               _strength_markdown(strength_rows), "",
               f"R_e = {ys / 1e6:,.0f} MPa (the scene's cage.yield_strength; default the minimum yield strength "
               "of quenched and tempered 40CrNiMoA, GB/T 3077). The von Mises stress of a sample interval is "
               "the maximum over the cage's mesh nodes and every integrator step in it (multibody.stress_peak). "
               "The cage model is linear elastic: where the utilization exceeds 1 its stress is the elastic "
               "one, an upper bound of the real stress with a local plastic zone, and the model is outside "
               "its validity there. "
               + ("No sample interval of the run exceeds R_e." if above == 0 else
                  f"{above} sample interval(s) of the run exceed R_e. Peaks that are single ball–cage collisions "
                  "scatter by a few percent between equally valid integrations (benchmarks/results/study/README.md), "
                  "so read the p99 utilization beside the peak."), ""]
    if amplification:
        md += ["## Contact stress at the impacts against the quasi-static equilibrium", "",
               _amplification_table(amplification), "",
               "Quasi-static: multibody.quasi_static at the pulse's peak instant (speed and load of that instant, a "
               "ball on the load line, Jones's race control); run: the worst ball's peak from the start of the pulse to "
               "5 T_n after its end (a short pulse's largest response comes after it). Amplification = run / "
               "quasi-static (coupling.amplification). One-DOF estimate: the inner ring's mass on the bearing's secant "
               "radial stiffness from the load before the pulse to its peak, natural period T_n, and the undamped "
               "shock spectrum of the displacement under a half-sine pulse of duration t_d (the contact stress "
               "amplifies less: p0 grows as Q^(1/3)); near 1 when t_d >> T_n: the pulse is then quasi-static for the "
               "contacts, and the stress it adds is the static response to the larger load.", ""]
    if motion_rows:
        md += ["## Cage motion in the guide clearance", "",
               _motion_markdown(motion_rows), "",
               "From the recorded cage centre (its offset from the guide-land centre) and cage speed "
               "(coupling.cage_motion): e/Cg the eccentricity ratio (1 = on the guide rim); whirl ratio = the "
               "centre's net whirl angle over the cage's rotation angle in the window (> 0 forward; 1 synchronous "
               "whirl, 0.5 half-frequency whirl on the land film, near 0 a centre held at one azimuth by a "
               "static load); velocity dispersion = std/mean of the centre's speed, the stability index of "
               "Ghaisas, Wassgren & Sadeghi (2004): 0 for a steady circular whirl, of order 1 for the "
               "irregular, collision-driven motion of an unstable cage, but also for a whirl that decays to rest "
               "inside the window (a cage that settles at one azimuth after an impact): read it with the orbit, "
               "`cage_orbit.png`, and the time held: the share of samples whose centre moves slower than a "
               "half-frequency whirl at a tenth of the clearance would (a cage at rest at one azimuth).", ""]
    if power_rows:
        md += ["## Friction torque and power loss", "",
               _power_markdown(power_rows), "",
               "Window means of the power each dissipative force pair of the model dissipates "
               "(multibody.power_loss): the sliced EHL traction (sliding and spin) and the EHL rolling "
               "forces of the race contacts, the contact damping, the lubricated pockets, the churning "
               "drag of the balls, the guide-land film and rim and, for a flexible cage, its modal "
               "damping. The drive torque is what holds the inner ring at its prescribed speed, the "
               "bearing's friction torque; in a steady window the drive power equals the loss (the "
               "work–energy theorem of the model, exact to rounding at single states, "
               "tests/test_power_loss.py); the residual is the sampling error of the window means "
               "(and the small non-conservative part of the angle-dependent Hertz constant). The "
               "oil's viscosity is isothermal (no inlet shear heating), which overestimates the EHL "
               "rolling resistance at high speed.", ""]
    if cmp_rows and len(cmp_rows) > 2:
        md += [f"## {cmp_name}: per phase", "", _markdown_table([(_col_name(r), r) for r in cmp_rows], keys), ""]
    if orbit_png is not None:
        plots = plots + [orbit_png]
    md += ["## Plots", ""] + [f"![{p.stem}]({p.name})" for p in plots] + [""]
    md += picture_md
    md += ["## Cage von Mises field (ParaView)", "", f"Frames at the peaks: {xdmf_note}", "",
           field_export.series_markdown(series_out, series), ""]
    report = out_dir / "report.md"
    report.write_text("\n".join(md))
    from coupling.html_page import write_html
    page = write_html(report)
    js = out_dir / "report.json"
    js.write_text(json.dumps({"run": str(path), "scene": name, "status": status, "units": {
        q.key: q.unit for q in QUANTITIES}, "phases": rows, "compare": str(cmp_path) if cmp_path else None,
        "compare_phases": cmp_rows, "impact_amplification": amplification, "cage_motion": motion_rows,
        "power_loss": power_rows, "cage_strength": strength_rows}, indent=1, allow_nan=False,
        default=float) + "\n")
    return {"report": report, "html": page, "json": js, "plots": plots, "xdmf": xdmf,
            "stress_picture": picture, "series": series_out}


def _impact_amplification(t, arrays, scene, dt) -> list[dict]:
    """coupling.amplification.impact_amplification for the run's impacts (data of `_read_run`; [] without
    impacts, contact stresses or a readable scene, or where the quasi-static solve refuses the instant)."""
    if scene is None or len(scene.impacts) == 0 or "outer_contact_stress" not in arrays:
        return []
    from coupling.amplification import impact_amplification
    try:
        return impact_amplification(scene, t, arrays)
    except InputError:
        return []


def _amplification_table(items) -> str:
    lines = ["| impact | Fr at peak (kN) | outer p0 quasi-static (MPa) | outer p0 run (MPa) | amplification | "
             "inner p0 quasi-static (MPa) | inner p0 run (MPa) | amplification | t_d/T_n | one-DOF estimate |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for a in items:
        cells = [a["label"], f"{math.hypot(a['load'][1], a['load'][2]) / 1e3:.1f}"]
        for key in ("outer_contact_stress", "inner_contact_stress"):
            cells += [f"{a[f'quasi_static_{key}'] / 1e6:,.0f}",
                      f"{a[f'dynamic_{key}'] / 1e6:,.0f}" if f"dynamic_{key}" in a else "–",
                      f"{a[f'{key}_amplification']:.4f}" if f"{key}_amplification" in a else "–"]
        cells += [f"{a['duration_over_period']:.3g}" if "duration_over_period" in a else "–",
                  f"{a['one_dof_amplification']:.4f}" if "one_dof_amplification" in a else "–"]
        if not a["converged"]:
            cells[0] += " (quasi-static not converged)"
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def print_table(rows: list[dict], file=None) -> None:
    file = sys.stdout if file is None else file    # the stream at call time, not at import
    keys = [q.key for q in QUANTITIES if rows and f"{q.key}_mean" in rows[0]]
    w = max(len(lab) for lab, _, _ in _stat_rows(keys)) if keys else 10
    for r in rows:
        print(f"{_col_name(r)}  ({r['n_samples']} samples)", file=file)
        for lab, field, qd in _stat_rows(keys):
            print(f"  {lab:<{w}}  {_fmt(r.get(field), qd.scale):>10}", file=file)


# ---------------------------------------------------------------- CLI

def register(subparsers) -> None:
    p = subparsers.add_parser("report", help="plots, per-phase tables and the cage's von Mises field of a run",
                              description="Report of a run: one PNG per quantity and an overview, "
                                          "report.md/report.json with peak, p99 and mean per phase of the "
                                          "speed profile and per impact, and (flexible cage) a picture of the "
                                          "cage's von Mises field at the run's maximum and ParaView XDMF "
                                          "files of it (10-node tetrahedra, every node drawn): the peaks "
                                          "(--frames) and a time series with the balls (--series). "
                                          "Headless check and screenshot: xvfb-run -a pvpython "
                                          "docs/paraview_open.py DIR (README).")
    p.add_argument("run", help="results file of `flexbearing run` (.h5)")
    p.add_argument("--compare", metavar="OTHER.h5", help="overlay and tabulate another run beside it "
                                                         "(e.g. the steady scene)")
    p.add_argument("-o", "--output", metavar="DIR", help="output folder (default: <run>_report beside the run)")
    p.add_argument("--frames", default="auto", help="von Mises frames: auto (max in each phase and each "
                                                   "impact) or times in s, e.g. 0.1,0.3")
    p.add_argument("--series", metavar="T0:T1[:N]",
                   help="ParaView time series of the window T0..T1 s at every N-th sample (default every "
                        "one): the cage placed and deformed, coloured by von Mises (series_cage.xdmf), "
                        "and the balls and the cage centre (series_points.xdmf); needs a flexible-cage "
                        "run for the cage and the scene output \"kinematics\" for the balls")
    p.add_argument("--displacement-scale", type=float, metavar="S",
                   help="magnification of the series' displacement_scaled field (Warp By Vector at scale "
                        "1 then draws the cage S times deformed; default: the largest displacement drawn "
                        "as about 1%% of the cage's outside diameter)")
    p.add_argument("--settle", type=float, default=0.0, metavar="S",
                   help="leave samples before t = S seconds (start-up transient) out of the tables")
    p.add_argument("--reduced-cage", metavar="FILE", help="reduced cage file (default: the one the run names)")
    p.add_argument("--quiet", action="store_true", help="print only the written paths, not the table")
    p.set_defaults(func=cmd_report)


def cmd_report(args) -> int:
    run = Path(args.run)
    out_dir = Path(args.output) if args.output else run.with_name(run.stem + "_report")
    res = write_report(run, out_dir, compare=args.compare, frames=args.frames,
                       reduced_cage=args.reduced_cage, quiet=args.quiet, settle=args.settle,
                       series=args.series, displacement_scale=args.displacement_scale)
    if not args.quiet:
        print_table(json.loads(res["json"].read_text())["phases"])
    print(f"report: {res['report']} (and {res['html'].name}, plots embedded)")
    print(f"plots:  {len(res['plots'])} PNG in {out_dir}")
    if res["stress_picture"]:
        print(f"stress: {res['stress_picture']}")
    if res["xdmf"]:
        print(f"xdmf:   {res['xdmf']}")
    if res["series"]:
        for key in ("cage", "points"):
            if res["series"][key]:
                print(f"series: {res['series'][key]} ({res['series']['n_frames']} frames)")
        for note in res["series"]["notes"]:
            print(f"series: {note}")
    return 0
