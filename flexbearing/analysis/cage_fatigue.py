"""The cage's fatigue from a run's dynamic stress history: damage, life and safety factor per node.

Stress history. The run records, for every sample interval, the full-basis modal coordinates q_k
of the integrator step with the interval's largest stress (/outputs/cage_modal_coordinates_full at
/outputs/von_mises_max_time; flexbearing.coupling.flexible_cage). The stress tensor at mesh node n is

    sigma_n(t_k) = S_n q_k          (S_n (6, M) the reduced cage's stress modes, Pa per unit q)

so the history at any node is rebuilt from what a flexible-cage run recording "von_mises" already
writes; nothing more is recorded. The history is the sequence of those steps, one per sample
interval (1e-4 s in the paper scenes): cycles faster than about two sample intervals (above
5 kHz there) are not resolved, and each interval's sample is the step of the cage's largest
stress, not of the node's own extreme, so ranges at nodes away from the hot spot can be
under-read by the stress change within one interval.

Damage field. At every node: the signed von Mises history (flexbearing.analysis.stress_equivalent),
rainflow counted as one block of the repeated duty cycle, mean-stress corrected, Miner-summed on
the material's S–N curve (flexbearing.analysis.fatigue, flexbearing.analysis.sn_curves). The duty
cycle: the run's block (the samples at settle <= t <= until) repeated back to back (3600 s / block
length blocks an hour), or `blocks_per_hour` given by the user. Per node: damage rate (1/s), life
(s) and the safety factor on the stress history for the design life.

Start-up left out. A run starts from a quasi-static (or steady) state, not from the state its
dynamics settle to; repeating its start-up transient as the duty cycle counts a transient the
bearing meets once per start as if it ran it continuously. By default (settle None) the block
starts where the run's start-up transient ends: MSER-5 (White 1997) on the cage speed, slip, cage
forces and von Mises stress of the first speed phase, the latest truncation over them
(flexbearing.analysis.settling.run_startup). A run whose transient runs past half of that phase
has no settled part: refused in one line (give `settle` to count from a time anyway). The block
is then tested for drift (the same module's trend test); a block that still drifts is counted
and flagged (`CageFatigue.startup["settled"]` False, named in the report).

Candidate nodes, with the full tensor history and the critical-plane check: the hot spots of the
run's peak search (every node that held the cage's maximum von Mises in some sample interval,
/outputs/von_mises_max_vertex), the `n_worst` nodes of the damage field, and the user's nodes. At
each: the normal stress on the critical plane (stress_equivalent; the plane of largest damage),
whose life is reported beside the signed von Mises one (the smaller governs), and the dominant
cycles (largest damage share) with their times.

Files (SI; `write_fatigue_files`): fatigue.h5 (the fields, the candidates' tensor histories and
cycles), fatigue.xdmf (ParaView: damage_rate, life, safety_factor and the peak signed von Mises
at every node of the mesh, beside von_mises.xdmf), fatigue.json (the facts), and the picture of the
unrolled damage field (flexbearing.analysis.fatigue_picture).
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numba import njit
import h5py
from tqdm import tqdm

from flexbearing.analysis import stress_equivalent as eq
from flexbearing.analysis.fatigue import Cycles, block_damage, cycle_damage, rainflow_cycles, safety_factor
from flexbearing.analysis.mean_stress import DEFAULT_CORRECTION, check_correction, equivalent_amplitude
from flexbearing.analysis.sn_curves import DEFAULT_SN_CURVE, sn_curve
from flexbearing.common.validation import InputError, require_range
from flexbearing.analysis.field_export import open_reduced_cage, _dataset, cage_cells, write_xdmf
from flexbearing.simulation.results import check_run, sample_interval
from flexbearing.analysis.stress_picture import cage_skin

HOUR = 3600.0
# Design life of the safety factor: an assumed round number (neither the paper nor SPEC gives the
# engine's); every report states it and --fatigue-design-life-h sets it.
DEFAULT_DESIGN_LIFE = 10_000.0 * HOUR      # s
CHUNK_ELEMENTS = 4_000_000                 # nodes x samples per block of the field pass (~200 MB)
# Critical plane: coarse lattice, then a local grid of LOCAL_STEPS^2 normals spaced h/8 around the
# best coarse plane; the N_EXACT planes of largest normal-stress range of each are counted.
# Nodes whose damage bound (screen_bound) is below SCREEN times the largest counted damage are not
# counted: their life is more than 1/SCREEN times the worst node's (four decades: the damage
# picture's range).
SCREEN = 1e-4
COARSE_PLANES = 1000
LOCAL_STEPS = 25
N_EXACT = 8


@dataclass(frozen=True)
class FatigueSettings:
    """What the fatigue step is asked (SI). blocks_per_hour None: the run's block repeated back to
    back. nodes: extra candidate node numbers (rows of the reduced cage's /mesh/vertices)."""
    material: str = DEFAULT_SN_CURVE
    correction: str = DEFAULT_CORRECTION
    blocks_per_hour: float | None = None
    design_life: float = DEFAULT_DESIGN_LIFE
    nodes: tuple[int, ...] = ()
    n_worst: int = 10
    settle: float | None = None       # s; None: after the run's start-up transient (module doc)
    until: float | None = None        # s; None: to the run's end

    def validate(self, n_nodes: int | None = None) -> "FatigueSettings":
        sn_curve(self.material)
        check_correction(self.correction)
        if self.blocks_per_hour is not None:
            require_range("fatigue blocks_per_hour", self.blocks_per_hour, 0.0, None, lo_open=True, unit="1/h")
        require_range("fatigue design_life", self.design_life, 0.0, None, lo_open=True, unit="s")
        require_range("fatigue n_worst", self.n_worst, 0, 1000)
        if self.settle is not None:
            require_range("fatigue settle", self.settle, 0.0, None, unit="s")
        if self.until is not None:
            require_range("fatigue until", self.until, 0.0, None, lo_open=True, unit="s")
        for n in self.nodes:
            if n_nodes is not None and not 0 <= int(n) < n_nodes:
                raise InputError(f"fatigue node = {n} is outside the allowed range [0, {n_nodes - 1}] "
                                 f"(rows of the reduced cage's /mesh/vertices)")
        return self


@dataclass
class CageFatigue:
    """The result (module doc). Arrays over the mesh's nodes: damage_rate (1/s), life (s),
    safety_factor (1), peak_signed_von_mises (Pa, the signed value of largest magnitude), counted
    (screen_bound: where False, damage_rate is an upper bound and life, safety_factor lower bounds).
    candidates: one dict per candidate node (SI), worst first. timing: wall times (s) and the
    peak memory of the pass's arrays (bytes)."""
    settings: FatigueSettings
    curve_source: str
    block_duration: float           # s
    blocks_per_hour: float
    n_samples: int
    damage_rate: np.ndarray
    life: np.ndarray
    safety_factor: np.ndarray
    peak_signed_von_mises: np.ndarray
    counted: np.ndarray             # bool: counted exactly; else damage_rate and 1/safety_factor are bounds
    candidates: list = field(default_factory=list)
    histories: dict = field(default_factory=dict)      # node -> (T, 6) tensor history, Pa
    times: np.ndarray | None = None
    timing: dict = field(default_factory=dict)
    reduced_cage: object = None     # the ReducedCage the field lives on
    startup: dict = field(default_factory=dict)        # the start-up left out (start_of_block)


def start_of_block(run_h5, settings: FatigueSettings) -> dict:
    """The block's start (module doc, "Start-up left out"): {settle (s), rule ("MSER-5 start-up
    transient" | "given"), settled (the block's drift verdict: True, False or None), reason,
    method}. InputError (one line) where the rule finds no settled part."""
    from flexbearing.analysis.settling import run_startup, window_settling, settling_signals
    from flexbearing.simulation.results import opened
    if settings.settle is None:
        st = run_startup(run_h5, settings.until)
        past = [v["signal"].replace("_", " ") for v in st["signals"].values() if v["transient_past_half"]]
        if past:
            raise InputError(f"fatigue: {Path(str(run_h5)).name} has no settled part to repeat as a duty cycle: "
                             f"the start-up transient of its {', '.join(past)} runs past half of its first phase "
                             f"({st['t_first']:g}–{st['t_last']:g} s; MSER-5); run it longer, or give --settle S "
                             f"to count from t = S anyway")
        settle = st["transient_end"] if st["transient_end"] is not None else 0.0
        rule = "MSER-5 start-up transient" if st["transient_end"] is not None else \
            "none left out (no cage speed, slip, force or stress recorded to find the start-up by)"
        return {"settle": float(settle), "rule": rule, "settled": st["settled"], "reason": st["reason"],
                "method": st["method"]}
    with opened(run_h5) as r:
        t = np.asarray(r.t, dtype=float)
        mask = t >= settings.settle - 1e-12 * max(1.0, settings.settle)
        if settings.until is not None:
            mask &= t <= settings.until + 1e-12 * max(1.0, settings.until)
        st = window_settling(t, settling_signals(r.outputs), mask)
    return {"settle": float(settings.settle), "rule": "given", "settled": st["settled"], "reason": st["reason"],
            "method": st["method"]}


def read_history(run_h5, settle: float, reduced_cage=None, until: float | None = None):
    """(times (T,) s, q (T, M), peak-search hot-spot nodes (T,), ReducedCage, block duration s) of
    a flexible-cage run at settle <= t (<= until) (module doc)."""

    path = check_run(run_h5)
    with h5py.File(path, "r") as f:
        out = f["outputs"]
        if "cage_modal_coordinates_full" not in out:
            raise InputError(f"{path}: no /outputs/cage_modal_coordinates_full: the fatigue step needs a "
                             f"flexible-cage run recording \"von_mises\" (cage model of this run: "
                             f"{f.attrs.get('cage_model', '?')!r})")
        t = out["time"][...]
        dt = sample_interval(f, t)
        keep = t >= settle - 1e-12 * max(1.0, abs(settle))
        if until is not None:
            keep &= t <= until + 1e-12 * max(1.0, abs(until))
        q = out["cage_modal_coordinates_full"][...]
        keep &= np.all(np.isfinite(q), axis=1)
        tp = out["von_mises_max_time"][...] if "von_mises_max_time" in out else t
        tp = np.where(np.isfinite(tp), tp, t)
        hot = out["von_mises_max_vertex"][...] if "von_mises_max_vertex" in out else np.full(len(t), -1.0)
        hot = np.where(np.isfinite(hot), hot, -1).astype(np.int64)
        rc_path = reduced_cage or f.attrs.get("reduced_cage_file")
        rc_hash = str(f.attrs.get("reduced_cage_hash", ""))
    if keep.sum() < 2:
        raise InputError(f"fatigue: {path} has {int(keep.sum())} sample(s) at t >= settle = {settle:g} s "
                         f"(allowed: at least 2)")
    rc, _ = open_reduced_cage(path, rc_path, rc_hash, q.shape[1])
    tk = t[keep]
    return tp[keep], np.ascontiguousarray(q[keep]), hot[keep], rc, float(tk[-1] - tk[0] + dt)


def _signed_von_mises_of(S, q, a, b=None) -> np.ndarray:
    """Signed von Mises histories (nodes, T) of nodes a..b-1 (or of the index array a)."""
    Sn = S[a:b] if b is not None else S[np.asarray(a)]
    T = q.shape[0]
    sig = (Sn.reshape(-1, S.shape[2]) @ q.T).reshape(len(Sn), 6, T)
    out = np.empty((len(Sn), T))
    eq.signed_von_mises_block(sig, out)
    return out


@njit(cache=True)
def history_stats(x, hi, lo, n_rev):
    """Per row of x (nodes, T): largest and smallest value and the number of reversals (slope sign
    changes, plateaus skipped, plus the two ends: what the rainflow count sees); allocation-free."""
    for i in range(x.shape[0]):
        h = x[i, 0]
        l = x[i, 0]
        r = 2
        last = 0.0
        for t in range(1, x.shape[1]):
            v = x[i, t]
            h = max(h, v)
            l = min(l, v)
            d = v - x[i, t - 1]
            if d != 0.0:
                if d * last < 0.0:
                    r += 1
                last = d
        hi[i] = h
        lo[i] = l
        n_rev[i] = r


def screen_bound(hi, lo, n_rev, curve, correction: str) -> np.ndarray:
    """Upper bound of a node's damage per block from its largest and smallest value and reversal
    count r: the repeated block holds at most (r + 2)/2 cycles, each of amplitude <= R/2 (R = hi - lo)
    and mean <= hi, so sigma_ar <= the correction of (R/2, max(hi, 0)) (each correction grows with
    the amplitude and, for Goodman, Gerber and SWT, with a tensile mean; flexbearing.analysis.mean_stress):
    D_block <= (r + 2)/2 / N(that)."""
    a = 0.5 * (np.asarray(hi) - np.asarray(lo))
    s_ar = equivalent_amplitude(a, np.maximum(hi, 0.0) if correction != "swt" else np.maximum(hi, 0.0) - a,
                                correction, curve.ultimate_strength)
    return 0.5 * (np.asarray(n_rev) + 2.0) / curve.cycles_to_failure(s_ar)


def screen_safety_factor(hi, lo, n_rev, curve, correction: str, blocks: float) -> np.ndarray:
    """Lower bound of the safety factor from screen_bound (bisection on its homogeneous-or-growing
    bound in lambda, per node)."""
    out = np.empty(len(hi))
    for i in range(len(hi)):
        a = 0.5 * (hi[i] - lo[i])
        m = max(hi[i], 0.0) if correction != "swt" else max(hi[i], 0.0) - a
        one = Cycles(np.array([2.0 * a]), np.array([m]), np.array([0.5 * (n_rev[i] + 2.0)]),
                     np.zeros(1, np.int64), np.zeros(1, np.int64))
        out[i] = safety_factor(one, curve, correction, blocks)
    return out


def node_history(rc, q: np.ndarray, node: int) -> np.ndarray:
    """sigma_n(t_k) = S_n q_k (T, 6), Pa."""
    return q @ rc.stress_modes[node].T


def critical_plane(sigma: np.ndarray, curve, correction: str, blocks_per_hour: float):
    """(damage per block, unit normal (3,), cycles) of the plane of largest damage of the
    normal-stress history n . sigma(t) n (module doc: coarse lattice, then a local grid)."""
    def best_of(normals):
        sn = eq.normal_stress(sigma, normals)
        rank = np.argsort(-(sn.max(axis=1) - sn.min(axis=1)), kind="stable")[:N_EXACT]
        best = (-1.0, None, None)
        for i in rank:
            cyc = rainflow_cycles(sn[i], repeated=True)
            dmg = block_damage(cyc, curve, correction)
            if dmg > best[0]:
                best = (dmg, normals[i], cyc)
        return best
    d0, n0, c0 = best_of(eq.plane_normals(COARSE_PLANES))
    h = eq.lattice_spacing(COARSE_PLANES)
    u = np.cross(n0, [1.0, 0.0, 0.0] if abs(n0[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(n0, u)
    g = np.linspace(-1.5 * h, 1.5 * h, LOCAL_STEPS)
    A, B = np.meshgrid(g, g)
    local = n0 + A.reshape(-1, 1) * u + B.reshape(-1, 1) * v
    local /= np.linalg.norm(local, axis=1, keepdims=True)
    d1, n1, c1 = best_of(local)
    return (d1, n1, c1) if d1 >= d0 else (d0, n0, c0)


def dominant_cycles(cycles, curve, correction: str, times: np.ndarray, n: int = 3) -> list[dict]:
    """The n cycles of largest damage share: range, mean (Pa), count, share (1), t_start <= t_end
    (s, the times of its two reversals)."""
    dmg = cycle_damage(cycles, curve, correction)
    total = dmg.sum()
    out = []
    for i in np.argsort(-dmg, kind="stable")[:n]:
        if not dmg[i] > 0.0:
            break
        # a cycle of the repeated block may run across the block's seam: its two reversal times,
        # sorted, are where in the run it is
        ta, tb = sorted((float(times[cycles.start[i]]), float(times[cycles.end[i]])))
        out.append({"range": float(cycles.range[i]), "mean": float(cycles.mean[i]), "count": float(cycles.count[i]),
                    "damage_share": float(dmg[i] / total), "t_start": ta, "t_end": tb})
    return out


def cage_fatigue(run_h5, settings: FatigueSettings = FatigueSettings(), reduced_cage=None,
                 quiet: bool = True) -> CageFatigue:
    """The damage field and the candidate nodes of a flexible-cage run (module doc)."""
    t0 = time.perf_counter()
    startup = start_of_block(run_h5, settings)
    times, q, hot, rc, block = read_history(run_h5, startup["settle"], reduced_cage, settings.until)
    n_nodes = rc.stress_modes.shape[0]
    settings.validate(n_nodes)
    curve = sn_curve(settings.material)
    per_hour = settings.blocks_per_hour if settings.blocks_per_hour is not None else HOUR / block
    blocks = per_hour * settings.design_life / HOUR
    T = len(times)
    t_read = time.perf_counter() - t0

    # the field, in one pass over blocks of nodes: each node's signed von Mises history, its
    # largest and smallest value and number of reversals, whose damage bound (screen_bound) decides
    # whether it is counted: not when the bound is below SCREEN times the largest damage counted
    # so far, seeded by the hot spots of the run's peak search (where the worst node is expected;
    # a larger seed only skips more, never wrongly: the threshold only grows)
    S = rc.stress_modes
    chunk = max(1, CHUNK_ELEMENTS // T)
    hi, lo, n_rev = np.zeros(n_nodes), np.zeros(n_nodes), np.zeros(n_nodes, np.int64)
    dmg = np.full(n_nodes, np.nan)
    sf = np.full(n_nodes, np.nan)
    seed = np.unique(hot[hot >= 0])
    d_max = 0.0
    bar = tqdm(total=n_nodes + len(seed), desc="fatigue: stress history and rainflow at every cage node",
               unit="node", disable=quiet, mininterval=1.0)

    def count(rows, svm):
        nonlocal d_max
        for i, n in enumerate(rows):
            if np.isnan(dmg[n]):
                cyc = rainflow_cycles(svm[i], repeated=True)
                dmg[n] = block_damage(cyc, curve, settings.correction)
                sf[n] = safety_factor(cyc, curve, settings.correction, blocks)
                d_max = max(d_max, dmg[n])
    count(seed, _signed_von_mises_of(S, q, seed))
    bar.update(len(seed))
    for a in range(0, n_nodes, chunk):
        b = min(n_nodes, a + chunk)
        svm = _signed_von_mises_of(S, q, a, b)
        history_stats(svm, hi[a:b], lo[a:b], n_rev[a:b])
        bound = screen_bound(hi[a:b], lo[a:b], n_rev[a:b], curve, settings.correction)
        pick = np.flatnonzero(bound >= SCREEN * d_max)
        pick = pick[np.argsort(-bound[pick], kind="stable")]          # largest first: raises d_max early
        count(a + pick, svm[pick])
        bar.update(b - a)
    bar.close()
    peak = np.where(hi >= -lo, hi, lo)
    bound = screen_bound(hi, lo, n_rev, curve, settings.correction)
    counted = np.isfinite(dmg)
    # screened-out nodes: their bound (damage) and the safety factor it implies (lower bounds)
    dmg[~counted] = bound[~counted]
    sf[~counted] = screen_safety_factor(hi[~counted], lo[~counted], n_rev[~counted], curve, settings.correction,
                                        blocks)
    t_field = time.perf_counter() - t0 - t_read
    rate = dmg * per_hour / HOUR
    with np.errstate(divide="ignore"):
        life = np.where(rate > 0.0, 1.0 / rate, math.inf)

    # candidates: hot spots of the peak search, the worst of the field, the user's
    hot_nodes, hot_count = np.unique(hot[hot >= 0], return_counts=True)
    worst = np.argsort(-dmg, kind="stable")[:settings.n_worst]
    cand = list(dict.fromkeys([int(n) for n in worst] + [int(n) for n in hot_nodes]
                              + [int(n) for n in settings.nodes]))
    where = _locations(rc, cand)
    result = CageFatigue(settings, curve.source, block, per_hour, T, rate, life, sf, peak, counted, times=times,
                         reduced_cage=rc, startup=startup)
    for n in cand:
        sigma = node_history(rc, q, n)
        cyc = rainflow_cycles(eq.signed_von_mises(sigma), repeated=True)
        d_cp, normal, cyc_cp = critical_plane(sigma, curve, settings.correction, per_hour)
        rate_cp = d_cp * per_hour / HOUR
        sf_cp = safety_factor(cyc_cp, curve, settings.correction, blocks)
        result.histories[n] = sigma
        result.candidates.append({
            "node": n, **where[n], "peak_von_mises": float(eq.von_mises(sigma).max()),
            "peak_signed_von_mises": float(peak[n]),
            "hot_spot_samples": int(hot_count[hot_nodes == n].sum()) if n in hot_nodes else 0,
            "user_node": n in settings.nodes,
            "damage_rate": float(rate[n]), "life": float(life[n]), "safety_factor": float(sf[n]),
            "critical_plane_damage_rate": float(rate_cp),
            "critical_plane_life": float(1.0 / rate_cp) if rate_cp > 0 else math.inf,
            "critical_plane_safety_factor": float(sf_cp),
            "critical_plane_normal": [float(v) for v in normal],
            "governing_life": float(min(life[n], 1.0 / rate_cp if rate_cp > 0 else math.inf)),
            "governing_safety_factor": float(min(sf[n], sf_cp)),
            "dominant_cycles": dominant_cycles(cyc, curve, settings.correction, times),
            "dominant_cycles_critical_plane": dominant_cycles(cyc_cp, curve, settings.correction, times)})
    result.candidates.sort(key=lambda c: c["governing_life"])
    result.timing = {"read": t_read, "field": t_field, "candidates": time.perf_counter() - t0 - t_read - t_field,
                     "total": time.perf_counter() - t0, "nodes": n_nodes, "samples": T,
                     "chunk_bytes": int(chunk * T * 6 * 8 * 2)}
    return result


def _locations(rc, nodes) -> dict:
    """{node: position (m, body frame), azimuth_deg, radius (m), axial (m), surface, pocket}."""
    skin = cage_skin(rc)
    faces = skin["faces"]
    X = np.asarray(rc.vertices, dtype=np.float64)
    out = {}
    for n in nodes:
        on = np.any(faces == n, axis=1)
        parts = [name for name in ("outside", "bore") if (on & skin[name]).any()]
        pockets = sorted({int(p) for p in skin["pocket"][on & skin["wall"]]})
        parts += [f"wall of pocket {p}" for p in pockets]
        x = X[n]
        out[n] = {"position": [float(v) for v in x], "azimuth_deg": float(np.degrees(np.arctan2(x[2], x[1])) % 360.0),
                  "radius": float(np.hypot(x[1], x[2])), "axial": float(x[0]),
                  "surface": ", ".join(parts) or ("side face or edge" if on.any() else "interior")}
    return out


# ---------------------------------------------------------------- files

FATIGUE_H5 = "fatigue.h5"
FATIGUE_XDMF = "fatigue.xdmf"
FATIGUE_JSON = "fatigue.json"


def facts(result: CageFatigue) -> dict:
    """The JSON-able facts of a result (SI; inf written as null)."""
    s = result.settings
    worst = int(np.argmax(result.damage_rate))

    def num(v):
        return None if v is None or not math.isfinite(v) else float(v)
    return {"material": s.material, "sn_curve_source": result.curve_source, "mean_stress_correction": s.correction,
            "equivalent_stress": "signed von Mises (field); normal stress on the critical plane (candidates)",
            "block_duration": result.block_duration, "blocks_per_hour": result.blocks_per_hour,
            "duty_cycle": ("the run's block repeated back to back" if s.blocks_per_hour is None
                           else "user-given blocks per hour"),
            "design_life": s.design_life, "settle": result.startup.get("settle", s.settle),
            "startup_rule": result.startup.get("rule"), "block_settled": result.startup.get("settled"),
            "block_settled_reason": result.startup.get("reason"), "until": s.until, "samples": result.n_samples,
            "nodes": len(result.damage_rate), "nodes_counted": int(result.counted.sum()), "screen": SCREEN,
            "worst_node": worst, "worst_damage_rate": num(result.damage_rate[worst]),
            "worst_life": num(result.life[worst]), "min_safety_factor": num(np.nanmin(result.safety_factor)),
            "timing": result.timing,
            "candidates": [{k: ([num(x) for x in v] if k == "critical_plane_normal" else
                                num(v) if isinstance(v, float) else v) for k, v in c.items()}
                           for c in result.candidates],
            "units": {"damage_rate": "1/s", "life": "s", "safety_factor": "1", "stress": "Pa", "time": "s"}}


def write_fatigue_files(result: CageFatigue, rc, out_dir) -> dict:
    """fatigue.h5 (fields over the nodes, each candidate's tensor history and its signed von
    Mises cycles), fatigue.xdmf (the fields on the mesh for ParaView, one grid) and fatigue.json
    (facts) in out_dir; returns their paths. Refuses to write through a symlink."""

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {"h5": out_dir / FATIGUE_H5, "xdmf": out_dir / FATIGUE_XDMF, "json": out_dir / FATIGUE_JSON}
    for p in paths.values():
        if p.is_symlink():
            raise InputError(f"fatigue output {p} is a symbolic link (allowed: a regular file or none); "
                             f"not written through it")
    topo_type, cells = cage_cells(rc)
    life = np.where(np.isfinite(result.life), result.life, np.finfo(float).max)
    sf = np.where(np.isfinite(result.safety_factor), result.safety_factor, np.finfo(float).max)
    with h5py.File(paths["h5"], "w") as g:
        _dataset(g, "mesh/geometry", rc.vertices, "m")
        _dataset(g, "mesh/topology", cells, "1")
        _dataset(g, "fields/damage_rate", result.damage_rate, "1/s")
        _dataset(g, "fields/life", life, "s")
        _dataset(g, "fields/safety_factor", sf, "1")
        _dataset(g, "fields/peak_signed_von_mises", result.peak_signed_von_mises, "Pa")
        _dataset(g, "fields/counted", result.counted.astype(np.int64), "1")
        g["fields"].attrs["note"] = ("counted = 0: damage_rate is an upper bound and life, safety_factor lower "
                                     "bounds (screened out: life above 1/screen times the worst node's)")
        _dataset(g, "time", result.times, "s")
        for n, sigma in result.histories.items():
            _dataset(g, f"candidates/{n}/stress", sigma, "Pa").attrs["columns"] = "xx yy zz yz xz xy"
            cyc = rainflow_cycles(eq.signed_von_mises(sigma), repeated=True)
            for name in ("range", "mean"):
                _dataset(g, f"candidates/{n}/signed_von_mises_cycles/{name}", getattr(cyc, name), "Pa")
            _dataset(g, f"candidates/{n}/signed_von_mises_cycles/count", cyc.count, "1")
        g.attrs["facts"] = json.dumps(facts(result))
    write_xdmf(paths["xdmf"], paths["h5"].name, "cage_fatigue", topo_type, "/mesh/topology", cells.shape,
               len(rc.vertices), [{"time": 0.0, "geometry": "/mesh/geometry", "attributes": [
                   ("damage_rate", "Scalar", "/fields/damage_rate", "1/s"),
                   ("life", "Scalar", "/fields/life", "s"),
                   ("safety_factor", "Scalar", "/fields/safety_factor", "1"),
                   ("peak_signed_von_mises", "Scalar", "/fields/peak_signed_von_mises", "Pa"),
                   ("counted", "Scalar", "/fields/counted", "1", "Int")]}],
               {"frame": "cage body frame (x the cage axis, pocket 0 at +y), cage at rest", "units": "SI",
                "material": result.settings.material, "mean_stress_correction": result.settings.correction,
                "design_life_s": result.settings.design_life, "blocks_per_hour": result.blocks_per_hour,
                "note": "life and safety_factor: float max where infinite; counted = 0: screened-out node "
                        "(damage_rate an upper bound, life and safety_factor lower bounds)"})
    paths["json"].write_text(json.dumps(facts(result), indent=1) + "\n")
    return paths
