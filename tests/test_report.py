"""flexbearing.analysis.report (with flexbearing.analysis.windows, flexbearing.analysis.plots) on small synthetic run files whose statistics are known in closed form.

The synthetic run: Z = 4 balls, dt = 1 ms, 0.6 s in three phases (acceleration 0–0.2 s, uniform
0.2–0.4 s, deceleration 0.4–0.6 s), one 20 ms impact centred at 0.3 s. Signals:

    outer contact stress, ball b:  A_p + B_p sin(2π (t/T0 − b/4)),  T0 = 20 ms (20 samples)
        -> peak over phase p = A_p + B_p (the sample k/20 − b/4 ≡ 1/4 exists for every ball),
           mean over the phase and the balls = A_p (the four sines, a quarter period apart, sum
           to zero at every instant)
    inner contact stresses: left = 1.1 × outer (loaded), right = 0.5 × outer -> inner = 1.1 × outer
    pocket force: −(P_p + P_p sin(...)), negative sign on purpose (the report uses |F|)
    guiding force: G0 + C sin(π (t − 0.29)/0.02) inside the impact window, G0 outside
    film (outer, inner-left loaded; inner-right unloaded with film 0, which must be ignored):
        h0 + dh·t + b·1e-8 (outer), + 1e-7 (inner-left) -> per-ball min = outer
    slip: +0.02 everywhere except −0.03 at t = 0.45 s (peak = largest magnitude, signed)

Tolerances: 1e-9 relative on values built from sin(π/2 + 2πn) and sums of exact sines
(rounding of ~1e3 floating-point terms); the XDMF field is compared at 1e-12 relative (HDF5
stores the float64 values unchanged; only the summation order of S q differs).
"""
from __future__ import annotations

import json
import math

import h5py
import numpy as np
import pytest
from tolerances import assert_within, dot_bound, von_mises_bound

from flexbearing.analysis import field_export, plots, report, windows
from flexbearing.simulation.results import ResultsWriter
from flexbearing.simulation.scene import loads_scene
from flexbearing.common.validation import InputError

Z = 4
DT = 1e-3
T0 = 0.02
PHASES = ((0.0, 0.2), (0.2, 0.4), (0.4, 0.6))
A = (1.5e9, 1.8e9, 1.6e9)          # Pa, mean outer contact stress per phase
B = (0.1e9, 0.2e9, 0.15e9)         # Pa, amplitude per phase
P = (100.0, 200.0, 150.0)          # N, pocket force level per phase
G0, C = 50.0, 400.0                # N, guiding force level and impact bump
H0, DH = 3e-6, 1e-6                # m, m/s film
IMPACT = (0.29, 0.31)

SCENE = """
name = "synthetic_{cage}"
[cage]
model = "{cage}"
[operation]
duration = 0.6
[operation.speed]
phases = [
  {{ kind = "ramp", duration = 0.2, start_rpm = 10000, end_rpm = 14000 }},
  {{ kind = "uniform", duration = 0.2, rpm = 14000 }},
  {{ kind = "ramp", duration = 0.2, start_rpm = 14000, end_rpm = 10000 }},
]
[operation.load]
axial_load = 55e3
radial_load = 4e3
[[operation.load.impacts]]
t_center = 0.3
duration = 0.02
magnitude = 50e3
[output]
sample_interval = 1e-3
record = {record}
"""


def _phase(t):
    return 0 if t < 0.2 - 1e-12 else (1 if t < 0.4 - 1e-12 else 2)


def _bump(t):
    return C * math.sin(math.pi * (t - IMPACT[0]) / 0.02) if IMPACT[0] - 1e-12 <= t <= IMPACT[1] + 1e-12 else 0.0


def _sample(t, film=True):
    p = _phase(t)
    s = np.sin(2 * np.pi * (round(t / DT) / 20.0 - np.arange(Z) / 4.0))
    outer = A[p] + B[p] * s
    cs = np.stack([outer, 1.1 * outer, 0.5 * outer], axis=1)
    load = np.ones((Z, 3))
    load[:, 2] = 0.0                              # inner-right unloaded
    v = {"contact_stress": cs, "contact_load": load,
         "pocket_force": -(P[p] + P[p] * s),
         "cage_land_force_magnitude": G0 + _bump(t),
         "slip_rate": -0.03 if abs(t - 0.45) < 1e-9 else 0.02,
         "inner_ring_speed": 1000.0 + 100 * t, "cage_speed": 450.0 + 40 * t}
    if film:
        h = H0 + DH * t + 1e-8 * np.arange(Z)
        v["film_thickness_min"] = np.stack([h, h + 1e-7, np.zeros(Z)], axis=1)
    return v


def write_run(path, cage="rigid", film=True, n=601, status="complete"):
    record = ["contact_stress", "pocket_force", "guiding_force", "slip"] + (["film_thickness"] if film else [])
    if cage == "flexible":
        record.append("von_mises")
    scene = loads_scene(SCENE.format(cage=cage, record=json.dumps(record)), "synthetic.toml")
    w = ResultsWriter.create(path, scene)
    for k in range(n):
        t = k * DT
        w.add_sample(t, _sample(t, film))
    w.write_block()
    w.set_status(status)
    w.close()
    return path


# ---------------------------------------------------------------- tables

def test_phases_and_impacts_from_scene():
    scene = loads_scene(SCENE.format(cage="rigid", record='["contact_stress"]'))
    ph = windows.speed_phases(scene)
    assert [p["kind"] for p in ph] == ["acceleration", "uniform speed", "deceleration"]
    assert [(p["t_start"], p["t_end"]) for p in ph] == [(0.0, 0.2), (0.2, 0.4), (0.4, 0.6)]
    assert ph[0]["speed_start_rpm"] == pytest.approx(10000) and ph[2]["speed_end_rpm"] == pytest.approx(10000)
    imp = windows.impact_windows(scene)
    assert len(imp) == 1
    assert imp[0]["t_start"] == pytest.approx(0.29) and imp[0]["t_peak"] == pytest.approx(0.3)
    assert imp[0]["magnitude"] == pytest.approx(50e3)


def test_table_rpm_segments_of_one_kind_are_merged():
    text = SCENE.format(cage="rigid", record='["contact_stress"]').replace(
        """phases = [
  { kind = "ramp", duration = 0.2, start_rpm = 10000, end_rpm = 14000 },
  { kind = "uniform", duration = 0.2, rpm = 14000 },
  { kind = "ramp", duration = 0.2, start_rpm = 14000, end_rpm = 10000 },
]""", "table_rpm = [[0.0, 10000], [0.1, 12000], [0.2, 14000], [0.3, 14000]]")
    ph = windows.speed_phases(loads_scene(text))
    # two acceleration segments -> one phase; constant after the last knot up to the duration
    assert [(p["kind"], p["t_start"], p["t_end"]) for p in ph] == [
        ("acceleration", 0.0, 0.2), ("uniform speed", 0.2, 0.6)]


def test_phase_table_equals_hand_computed(tmp_path):
    rows = windows.phase_table(write_run(tmp_path / "run.h5"))
    assert [r["kind"] for r in rows] == ["run", "acceleration", "uniform speed", "deceleration", "impact"]
    assert [r["n_samples"] for r in rows] == [601, 200, 200, 201, 21]
    rel = 1e-9
    t_all = np.arange(601) * DT
    for p, r in enumerate(rows[1:4]):
        assert r["outer_contact_stress_peak"] == pytest.approx(A[p] + B[p], rel=rel)
        assert r["outer_contact_stress_mean"] == pytest.approx(A[p], rel=rel)
        assert r["inner_contact_stress_peak"] == pytest.approx(1.1 * (A[p] + B[p]), rel=rel)
        assert r["inner_contact_stress_mean"] == pytest.approx(1.1 * A[p], rel=rel)
        assert r["pocket_force_peak"] == pytest.approx(2 * P[p], rel=rel)
        assert r["pocket_force_mean"] == pytest.approx(P[p], rel=rel)
        # film: the unloaded inner-right contact (film 0) is ignored; minimum at the phase start, ball 0
        t0, t1 = PHASES[p]
        tw = t_all[(t_all >= t0 - 1e-12) & ((t_all < t1 - 1e-12) if p < 2 else (t_all <= t1 + 1e-12))]
        assert r["film_thickness_min_min"] == pytest.approx(H0 + DH * t0, rel=rel)
        assert r["film_thickness_min_t_min"] == pytest.approx(t0, abs=1e-12)
        assert r["film_thickness_min_mean"] == pytest.approx(H0 + DH * tw.mean() + 1e-8 * 1.5, rel=rel)
    # whole run: the largest phase peak, the sample-weighted mean of the phase means
    assert rows[0]["outer_contact_stress_peak"] == pytest.approx(A[1] + B[1], rel=rel)
    assert rows[0]["outer_contact_stress_mean"] == pytest.approx((200 * A[0] + 200 * A[1] + 201 * A[2]) / 601, rel=rel)
    # guiding force: half-sine bump of C on G0 in the impact window [0.29, 0.31] (21 samples)
    bump = C * np.sin(np.pi * np.arange(21) / 20)
    imp = rows[4]
    assert imp["guiding_force_peak"] == pytest.approx(G0 + C, rel=rel)
    assert imp["guiding_force_t_peak"] == pytest.approx(0.3, abs=1e-12)
    assert imp["guiding_force_mean"] == pytest.approx(G0 + bump.sum() / 21, rel=rel)
    assert rows[2]["guiding_force_mean"] == pytest.approx(G0 + bump.sum() / 200, rel=rel)
    assert rows[1]["guiding_force_mean"] == pytest.approx(G0, rel=rel)
    # slip changes sign: the peak is the signed value of largest magnitude (-3 % at 0.45 s)
    assert rows[3]["slip_rate_peak"] == pytest.approx(-0.03, rel=rel)
    assert rows[3]["slip_rate_t_peak"] == pytest.approx(0.45, abs=1e-12)
    assert rows[1]["slip_rate_peak"] == pytest.approx(0.02, rel=rel)
    assert "von_mises_max_peak" not in rows[0]              # rigid run: not recorded, not reported



def test_percentile_is_the_interpolated_order_statistic(tmp_path):
    """p99 / p1 (flexbearing.analysis.windows module doc, Hyndman & Fan definition 7): position h = q (n - 1)
    in the sorted worst-ball values, linear between the two order statistics around it."""
    rows = windows.phase_table(write_run(tmp_path / "run.h5"))
    rel = 1e-9
    n = [200, 200, 201]
    for p, r in enumerate(rows[1:4]):
        # worst ball of A + B sin(2pi(k/20 - b/4)): A + B max(|sin|, |cos|)(pi k/10) reaches A + B in
        # 4 of every 20 samples, so the two order statistics around h = 0.99 (n - 1) are both A + B
        assert r["outer_contact_stress_p99"] == pytest.approx(A[p] + B[p], rel=rel)
        assert r["pocket_force_p99"] == pytest.approx(2 * P[p], rel=rel)
        # thinnest film H0 + DH t rises linearly through the phase: p1 at t0 + 0.01 (n - 1) DT
        assert r["film_thickness_min_p1"] == pytest.approx(H0 + DH * (PHASES[p][0] + 0.01 * (n[p] - 1) * DT), rel=rel)
    # impact window, 21 samples of G0 + C sin(pi k/20): sorted, e_20 = G0 + C and e_19 = e_18 =
    # G0 + C sin(9 pi/20); h = 0.99 * 20 = 19.8
    s9 = math.sin(9 * math.pi / 20)
    assert rows[4]["guiding_force_p99"] == pytest.approx(G0 + C * (s9 + 0.8 * (1 - s9)), rel=rel)
    assert rows[4]["guiding_force_peak"] == pytest.approx(G0 + C, rel=rel)
    # one sample of -3 % among 200 of +2 % (deceleration): the peak is the single spike, the signed
    # p99 is not moved by it (h = 0.01 * 200 = 2 for p1 falls on +2 % already)
    assert rows[3]["slip_rate_peak"] == pytest.approx(-0.03, rel=rel)
    assert rows[3]["slip_rate_p99"] == pytest.approx(0.02, rel=rel)
    # tables carry the three statistics in order (peak, percentile, mean) for every quantity
    labels = [lab for lab, _, _ in report._stat_rows(["pocket_force", "film_thickness_min"])]
    assert labels == ["Pocket force, peak (N)", "Pocket force, p99 (N)", "Pocket force, mean (N)",
                      "Minimum film thickness, min (µm)", "Minimum film thickness, p1 (µm)",
                      "Minimum film thickness, mean (µm)"]

def test_interrupted_run_reports_the_phases_it_reached(tmp_path):
    rows = windows.phase_table(write_run(tmp_path / "cut.h5", n=251, status="interrupted"))
    assert [r["kind"] for r in rows] == ["run", "acceleration", "uniform speed"]
    assert rows[2]["n_samples"] == 51


def test_settle_leaves_the_start_out(tmp_path):
    rows = windows.phase_table(write_run(tmp_path / "run.h5"), settle=0.25)
    assert [r["kind"] for r in rows] == ["run", "uniform speed", "deceleration", "impact"]
    assert rows[1]["n_samples"] == 150 and rows[0]["n_samples"] == 351
    with pytest.raises(InputError, match=r"settle = 0.7 s .*allowed range \[0, 0.6\) s"):
        windows.phase_table(tmp_path / "run.h5", settle=0.7)


def test_bad_run_file_is_refused(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        windows.phase_table(tmp_path / "missing.h5")
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = 1.0
    with pytest.raises(InputError, match="not a flexbearing results file"):
        windows.phase_table(other)


# ---------------------------------------------------------------- plots and report

def _is_nonblank_png(path):
    import matplotlib.image as mpimg
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = mpimg.imread(path)
    return path.stat().st_size > 5000 and float(img[..., :3].std()) > 0.01


def test_plots_only_recorded_quantities(tmp_path):
    # the run has no film thickness and no von Mises (rigid): no PNG for them, even though the
    # compared run has a film
    run = write_run(tmp_path / "nofilm.h5", film=False)
    other = write_run(tmp_path / "withfilm.h5")
    paths = plots.write_plots(run, tmp_path / "plots", compare=other)
    assert sorted(p.name for p in paths) == sorted([
        "speed.png", "outer_contact_stress.png", "inner_contact_stress.png", "pocket_force.png",
        "guiding_force.png", "slip_rate.png", "overview.png"])
    assert all(_is_nonblank_png(p) for p in paths)


# ---------------------------------------------------------------- flexible cage: XDMF

NV, M = 6, 3
VERTS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1], [1, 1, 0]], float) * 1e-2
TETS = np.array([[0, 1, 2, 3], [1, 2, 3, 4], [1, 2, 4, 5]])


def _fake_flexible_run(tmp_path):
    """A flexible run: modal coordinates q(t) in a tiny reduced cage's full basis (3 modes)."""
    from flexbearing.fem_cage.reduced_cage import read, write
    rng = np.random.default_rng(7)
    S = rng.normal(size=(NV, 6, M)) * 1e7     # Pa per unit q
    Phi = rng.normal(size=(NV, 3, M)) * 1e-5  # m per unit q
    rc = write(tmp_path / "cage.h5", {
        "mesh/vertices": VERTS, "mesh/tets": TETS, "stress/modes": S, "modes/vertex_displacement": Phi,
        "modes/frequency_hz": np.ones(M), "modes/omega": np.ones(M), "modes/modal_stiffness": np.ones(M),
        "modes/interface": np.zeros((2, 6, M)), "interface/positions": np.zeros((2, 3)),
        "invariants/mass": 1.0}, {"content_hash": "abcd1234abcd1234"})
    stored = read(rc)             # the tables as the file holds them (16-bit, reduced_cage schema 6)
    S, Phi = stored.stress_modes, stored.vertex_displacement
    run = write_run(tmp_path / "flex.h5", cage="flexible")
    n = 601
    q = rng.normal(size=(n, M))
    vm = np.array([_vm_by_deviator(S @ qi).max() for qi in q])
    with h5py.File(run, "r+") as f:
        f["outputs/cage_modal_coordinates_full"] = q
        f["outputs/von_mises_max"] = vm
        f["outputs/von_mises_max"].attrs["unit"] = "Pa"
        f.attrs["reduced_cage_file"] = str(rc)
        f.attrs["reduced_cage_hash"] = "abcd1234abcd1234"
    return run, S, Phi, q, vm


def _vm_by_deviator(voigt):
    """sqrt(3/2 s:s), s the deviator of the full 3x3 tensor (independent of report.von_mises)."""
    out = []
    for xx, yy, zz, yz, xz, xy in voigt:
        sig = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        s = sig - np.trace(sig) / 3 * np.eye(3)
        out.append(math.sqrt(1.5 * float((s * s).sum())))
    return np.array(out)


def test_von_mises_xdmf_reads_back_with_meshio(tmp_path):
    import meshio
    run, S, Phi, q, vm_rec = _fake_flexible_run(tmp_path)
    xdmf = field_export.write_von_mises_xdmf(run, tmp_path / "rep", "auto")
    t = np.arange(601) * DT
    # auto frames: the max of the recorded von Mises in the impact window [0.29, 0.31] s and in
    # each phase outside it (the uniform phase 0.2-0.4 s without samples 290..310)
    windows = [np.arange(0, 200), np.r_[200:290, 311:400], np.arange(400, 601), np.arange(290, 311)]
    expected = sorted({int(w[np.argmax(vm_rec[w])]) for w in windows})
    assert len(expected) == 4
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as r:
        points, cells = r.read_points_cells()
        assert np.array_equal(points, VERTS)
        assert np.array_equal(cells[0].data, TETS) and cells[0].type == "tetra"
        assert r.num_steps == len(expected)
        for step, k in enumerate(expected):
            tk, pdata, _ = r.read_data(step)
            assert tk == pytest.approx(t[k], abs=1e-12)
            hand = _vm_by_deviator(S @ q[k])
            v = 4
            # two closed forms of von Mises, two summation orders of S q; Phi q in another order
            # (tests/tolerances.py: von_mises_bound, dot_bound)
            vm = pdata["von_mises"]
            assert_within(abs(vm[v] - hand[v]), von_mises_bound(S[v], q[k], hand[v]),
                          "von Mises at a node", effect=hand[v])
            assert_within(abs(vm.max() - vm_rec[k]), von_mises_bound(S, q[k], vm_rec[k]).max(),
                          "frame von Mises maximum", effect=vm_rec[k])
            u = Phi @ q[k]
            assert_within(np.abs(pdata["displacement"] - u), dot_bound(len(q[k]), np.abs(Phi) @ np.abs(q[k])),
                          "displacement = Phi q", effect=np.abs(u).max())
    meta = json.loads(xdmf.with_suffix(".json").read_text())
    assert [fr["sample"] for fr in meta["frames"]] == expected
    assert meta["reduced_cage_hash"] == "matches (content verified against its digest)"   # issue 36


def test_von_mises_xdmf_explicit_frames_and_bad_frames(tmp_path):
    import meshio
    run, S, Phi, q, _ = _fake_flexible_run(tmp_path)
    xdmf = field_export.write_von_mises_xdmf(run, tmp_path / "rep", "0.1, 0.3004")   # nearest samples 100, 300
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as r:
        r.read_points_cells()
        times = [r.read_data(i)[0] for i in range(r.num_steps)]
    assert times == pytest.approx([0.1, 0.3], abs=1e-12)
    with pytest.raises(InputError, match=r"outside the run \(allowed range \[0, 0.6\] s\)"):
        field_export.write_von_mises_xdmf(run, tmp_path / "rep", "0.7")
    with pytest.raises(InputError, match="--frames"):
        field_export.write_von_mises_xdmf(run, tmp_path / "rep", "first")


def test_report_command_end_to_end(tmp_path):
    from flexbearing.cli.main import main
    run, *_ = _fake_flexible_run(tmp_path)
    steady = write_run(tmp_path / "steady.h5")
    out = tmp_path / "report"
    assert main(["report", str(run), "--compare", str(steady), "-o", str(out), "--quiet"]) == 0
    md = (out / "report.md").read_text()
    assert "Max. von Mises stress of the cage, peak (MPa)" in md
    assert "change vs synthetic_rigid" in md
    assert (out / "von_mises_max.png").exists() and (out / "von_mises.xdmf").exists()
    js = json.loads((out / "report.json").read_text())
    assert js["phases"][1]["outer_contact_stress_peak"] == pytest.approx(A[0] + B[0], rel=1e-9)
    # printed in MPa: the steady (synthetic_rigid) whole-run mean (200·1.5 + 200·1.8 + 201·1.6)/601 GPa
    assert "| Outer-race contact stress, mean (MPa) | 1,633 |" in md
    assert main(["report", str(tmp_path / "nope.h5"), "--quiet"]) == 2


# ---------------------------------------------------------------- cage motion

WHIRL = (300.0, 150.0, -50.0)      # rad/s, whirl rate of the cage centre per phase (synthetic)
EPS_ORBIT = 0.4                    # eccentricity ratio of the synthetic circular orbit
CG = 375e-6                        # m, guide clearance of the synthetic cage


def _whirl_angle(t):
    """Piecewise-linear, continuous whirl angle with the rates WHIRL in the three phases."""
    a = 0.0
    for (t0, t1), w in zip(PHASES, WHIRL):
        a += w * (min(max(t, t0), t1) - t0)
    return a


def write_orbit_run(path, n=601):
    w = ResultsWriter.create(path, loads_scene(SCENE.format(cage="rigid", record='["cage_orbit", "cage_speed"]'),
                                               "synthetic.toml"))
    for k in range(n):
        t = k * DT
        phi = _whirl_angle(t)
        w.add_sample(t, {"cage_centre": [0.0, EPS_ORBIT * CG * math.cos(phi), EPS_ORBIT * CG * math.sin(phi)],
                         "cage_eccentricity_ratio": EPS_ORBIT, "cage_speed": 450.0 + 40 * t})
    w.write_block()
    w.set_status("complete")
    w.close()
    return path


def test_cage_motion_table_per_phase(tmp_path):
    """Whirl ratio of each window = (whirl angle swept)/(cage angle ∫(450 + 40 t) dt), exact for the
    piecewise-linear angle and the linear speed (1e-9: rounding); circular orbit: dispersion 0."""
    rows = windows.cage_motion_table(write_orbit_run(tmp_path / "orbit.h5"))
    assert [r["kind"] for r in rows] == ["run", "acceleration", "uniform speed", "deceleration", "impact"]
    t_all = np.arange(601) * DT
    for r in rows:
        sel = windows.window_mask(t_all, r["t_start"], r["t_end"], r["kind"] in ("run", "deceleration", "impact"), DT)
        ta, tb = t_all[sel][0], t_all[sel][-1]
        cage_angle = 450.0 * (tb - ta) + 20.0 * (tb * tb - ta * ta)
        assert r["whirl_ratio"] == pytest.approx((_whirl_angle(tb) - _whirl_angle(ta)) / cage_angle, rel=1e-9)
        assert r["eps_mean"] == pytest.approx(EPS_ORBIT, rel=1e-12) and r["rim_fraction"] == 0.0
    assert rows[3]["whirl_ratio"] < 0.0                                   # backward whirl in phase 3
    assert rows[1]["velocity_dispersion"] == pytest.approx(0.0, abs=1e-9)  # one rate inside a phase
    assert rows[0]["velocity_dispersion"] > 0.1                            # three rates over the run


def test_report_has_the_cage_motion_section_only_when_recorded(tmp_path):
    out = report.write_report(write_orbit_run(tmp_path / "orbit.h5"), tmp_path / "rep")
    md = out["report"].read_text()
    assert "## Cage motion in the guide clearance" in md
    assert "| Eccentricity ratio e/Cg, mean | 0.400 |" in md
    assert _is_nonblank_png(tmp_path / "rep" / "cage_orbit.png")
    js = json.loads(out["json"].read_text())
    assert js["cage_motion"][2]["whirl_ratio"] > 0.0 and len(js["cage_motion"]) == 5
    plain = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep2")
    assert "Cage motion" not in plain["report"].read_text()
    assert not (tmp_path / "rep2" / "cage_orbit.png").exists()


# ---------------------------------------------------------------- friction torque and power loss
TORQUE = (2.0, 3.0, 2.5)            # N·m per phase; drive power = torque · (1000 + 100 t)


def write_power_run(path, n=601):
    """Every source constant within a phase except the churning, which carries the energy
    change: loss = drive power − dE/dt exactly, E = 5 + 20 t (J)."""
    w = ResultsWriter.create(path, loads_scene(SCENE.format(cage="rigid", record='["power_loss"]'),
                                               "synthetic.toml"))
    for k in range(n):
        t = k * DT
        p = _phase(t)
        drive = TORQUE[p] * (1000.0 + 100.0 * t)
        trac = np.zeros((Z, 3))
        trac[:, 0] = 10.0 * (p + 1)            # outer race, per ball
        trac[:, 1] = 5.0                       # inner halves
        fixed = trac.sum() + 30.0              # + 30 W guide land
        churning = drive - 20.0 - fixed        # the rest, spread over the balls
        w.add_sample(t, {"ring_drive_torque": TORQUE[p], "inner_ring_speed": 1000.0 + 100.0 * t,
                         "drive_power": drive, "power_loss": drive - 20.0,
                         "power_loss_traction": trac, "power_loss_rolling": np.zeros((Z, 3)),
                         "power_loss_contact_damping": np.zeros((Z, 3)),
                         "power_loss_pocket": np.zeros(Z), "power_loss_churning": np.full(Z, churning / Z),
                         "power_loss_guide_land": 30.0, "power_loss_cage_damping": 0.0,
                         "mechanical_energy": 5.0 + 20.0 * t, "external_load_power": 0.0})
    w.write_block()
    w.set_status("complete")
    w.close()
    return path


def test_power_loss_table_per_phase(tmp_path):
    """Window means: traction split outer/inner, drive torque, and the sampled energy balance
    (drive − loss − dE/dt) closes to rounding because the synthetic E grows at exactly the
    drive − loss of every sample (1e-9: sums of ~200 floating-point terms)."""
    rows = windows.power_loss_table(write_power_run(tmp_path / "power.h5"))
    assert [r["kind"] for r in rows] == ["run", "acceleration", "uniform speed", "deceleration", "impact"]
    for r, p in zip(rows[1:4], range(3)):
        assert r["drive_torque"] == pytest.approx(TORQUE[p], rel=1e-12)
        assert r["traction_outer"] == pytest.approx(Z * 10.0 * (p + 1), rel=1e-12)
        assert r["traction_inner"] == pytest.approx(Z * 5.0, rel=1e-12)
        assert r["guide_land"] == pytest.approx(30.0, rel=1e-12)
    for r in rows:
        assert r["energy_rate"] == pytest.approx(20.0, rel=1e-9)
        assert r["residual"] == pytest.approx(0.0, abs=1e-9 * r["loss"])


def test_report_has_the_power_section_only_when_recorded(tmp_path):
    out = report.write_report(write_power_run(tmp_path / "power.h5"), tmp_path / "rep")
    md = out["report"].read_text()
    assert "## Friction torque and power loss" in md
    assert "| Friction torque (drive torque of the inner ring), N·m | 2.5 | 2 | 3 | 2.5 | 3 |" in md
    js = json.loads(out["json"].read_text())
    assert js["power_loss"][2]["drive_torque"] == pytest.approx(3.0)
    plain = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep2")
    assert "Friction torque" not in plain["report"].read_text()
    assert json.loads(plain["json"].read_text())["power_loss"] == []


# ---------------------------------------------------------------- report.html (flexbearing.analysis.html_page)

def test_html_page_holds_the_markdown_tables_and_the_plots(tmp_path):
    """report.html: every Markdown table of report.md becomes an HTML table with the same cells, in
    order (the page is parsed back with the standard library's HTMLParser, which also checks that
    the elements it opens are closed), and every plot is embedded: its data URI decodes to the PNG
    file's bytes exactly."""
    import base64
    from html.parser import HTMLParser

    out = report.write_report(write_orbit_run(tmp_path / "orbit.h5"), tmp_path / "rep")
    md = out["report"].read_text()
    md_rows = [[c.strip().replace("**", "").replace("`", "") for c in line.strip().strip("|").split("|")]
               for line in md.splitlines() if line.startswith("|") and not set(line) <= set("|-: ")]

    class Page(HTMLParser):
        def __init__(self):
            super().__init__()
            self.rows, self.images, self.stack, self.cell = [], [], [], None

        def handle_starttag(self, tag, attrs):
            if tag not in ("meta", "img", "br"):
                self.stack.append(tag)
            if tag == "tr":
                self.rows.append([])
            elif tag in ("td", "th"):
                self.cell = ""
            elif tag == "img":
                self.images.append(dict(attrs))

        def handle_endtag(self, tag):
            assert self.stack and self.stack.pop() == tag, f"</{tag}> closes {self.stack}"
            if tag in ("td", "th"):
                self.rows[-1].append(self.cell)
                self.cell = None

        def handle_data(self, data):
            if self.cell is not None:
                self.cell += data

    page = Page()
    page.feed(out["html"].read_text())
    assert page.stack == []
    assert page.rows == md_rows and len(md_rows) > 5
    assert "e/Cg" in out["html"].read_text()
    plots = [line[line.rindex("](") + 2:-1] for line in md.splitlines() if line.startswith("![")]
    assert len(page.images) == len(plots) > 0
    for img, name in zip(page.images, plots):
        head, data = img["src"].split(",", 1)
        assert head == "data:image/png;base64"
        assert base64.b64decode(data) == (tmp_path / "rep" / name).read_bytes()


def test_html_escapes_text_and_keeps_a_missing_plot_as_text(tmp_path):
    from flexbearing.analysis.html_page import markdown_to_html
    page = markdown_to_html("# a < b & c\n\n| x | y |\n|---|---:|\n| `p<1` | **2** |\n| &nbsp;z | 3 |\n\n"
                            "![lost](none.png)\n", tmp_path)
    assert "<h1>a &lt; b &amp; c</h1>" in page
    assert "<td>&nbsp;z</td>" in page
    assert '<td><code>p&lt;1</code></td><td class="num"><strong>2</strong></td>' in page
    assert "[lost: plot none.png not found]" in page


# ---------------------------------------------------------------- cage stress against the yield strength

def test_cage_strength_against_the_yield_strength(tmp_path):
    """utilization = sigma_vM / R_e of the window's peak and p99, and the count and share of sample
    intervals above R_e, on a stress signal built for it: 400 MPa everywhere, a half-sine of
    600 MPa on it in the impact window (0.29-0.31 s, 21 samples: 1000 MPa at 0.30 s). With
    R_e = 835 MPa (the default of a flexible scene, 40CrNiMoA) the samples above it are those with
    600 sin(pi k/20) > 435, i.e. sin > 0.725: k = 6..14 (sin(6 pi/20) = 0.809, sin(5 pi/20) = 0.707),
    9 samples."""
    run = write_run(tmp_path / "flex.h5", cage="flexible")
    t = np.arange(601) * DT
    bump = np.where((t >= 0.29 - 1e-12) & (t <= 0.31 + 1e-12), np.sin(np.pi * (t - 0.29) / 0.02), 0.0)
    vm = 400e6 + 600e6 * np.clip(bump, 0.0, None)
    with h5py.File(run, "r+") as f:
        f["outputs/von_mises_max"] = vm
    t_, arrays, scene, dt = windows.read_run(run)
    assert scene.flexible["yield_strength"] == 835e6
    rows = windows.cage_strength_rows(t_, arrays, scene, dt)
    whole, impact = rows[0], rows[-1]
    assert impact["kind"] == "impact"
    assert impact["utilization_peak"] == pytest.approx(1000e6 / 835e6, rel=1e-12)
    assert impact["intervals_above_yield"] == 9 and whole["intervals_above_yield"] == 9
    assert impact["share_above_yield"] == pytest.approx(9 / 21, rel=1e-12)
    assert whole["share_above_yield"] == pytest.approx(9 / 601, rel=1e-12)
    s9 = math.sin(9 * math.pi / 20)       # p99 of the impact window, as test_percentile_...
    assert impact["utilization_p99"] == pytest.approx((400e6 + 600e6 * (s9 + 0.8 * (1 - s9))) / 835e6, rel=1e-12)
    assert rows[1]["utilization_peak"] == pytest.approx(400e6 / 835e6, rel=1e-12)  # acceleration: flat
    assert rows[1]["intervals_above_yield"] == 0
    md = report.write_report(run, tmp_path / "rep")["report"].read_text()
    assert "## Cage stress against the yield strength" in md and "R_e = 835 MPa" in md
    assert "| Utilization peak / R_e | 1.20 |" in md
    # a rigid cage has no stress: no section; a scene with its own material and no R_e: none either
    assert windows.cage_strength_rows(*windows.read_run(write_run(tmp_path / "rigid.h5"))) == []


def test_yield_strength_in_the_scene():
    from flexbearing.simulation.scene import loads_scene
    base = SCENE.format(cage="flexible", record='["von_mises"]')
    assert loads_scene(base).flexible["yield_strength"] == 835e6
    own = base.replace('model = "flexible"', 'model = "flexible"\nyield_strength = 1.1e9')
    assert loads_scene(own).flexible["yield_strength"] == 1.1e9
    other = base.replace('model = "flexible"', 'model = "flexible"\n[cage.material]\ndensity = 8500.0')
    assert "yield_strength" not in loads_scene(other).flexible      # another material: not assumed
    with pytest.raises(InputError, match=r"cage.yield_strength"):
        loads_scene(base.replace('model = "flexible"', 'model = "flexible"\nyield_strength = -5'))
