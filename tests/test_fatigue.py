"""Cage fatigue (flexbearing.analysis.fatigue, mean_stress, sn_curves, stress_equivalent, cage_fatigue)
against closed forms and the published example.

Expected values are computed here from the formulas written out in each test (Basquin
N = 1/2 (S_ar/S_f')^(1/b), the mean-stress corrections, the critical-plane amplitude of
tension-torsion), never by the functions under test.

Tolerances:
- ASTM E1049 example: exact (integer ranges, half-cycle counts).
- Damage of sampled sines: the peaks are sampled at sin(pi/2 + 2 pi j) = 1 - O(1e-16), so the
  amplitude is exact to a few ulp and the damage (amplitude^k, k ~ 10) to ~1e-14: rtol 1e-12.
- Safety factor: bisection on log(lambda) to 1e-12: rtol 1e-9.
- Critical plane: the search's final grid spacing delta bounds the angle to the best plane by
  delta/sqrt(2); the amplitude of n.sigma n near its maximum then drops by at most
  sin^2(angle) (f* + ||C|| + ||S||) (C, S the cos and sin tensors of the history; the first-order
  term vanishes at a maximum), plus 1 - cos(pi/P) for a sine sampled P times a period whose peak
  falls between samples: that relative tolerance, times the S–N slope k for the damage.
"""
from __future__ import annotations

import math
from collections import defaultdict

import h5py
import numpy as np
import pytest
from tolerances import assert_within, gamma, norm_bound

from flexbearing.analysis import stress_equivalent as eq
from flexbearing.analysis.cage_fatigue import (COARSE_PLANES, LOCAL_STEPS, FatigueSettings, cage_fatigue,
                                               critical_plane, screen_bound, screen_safety_factor,
                                               write_fatigue_files)
from flexbearing.analysis.fatigue import block_damage, rainflow_cycles, safety_factor
from flexbearing.analysis.mean_stress import equivalent_amplitude
from flexbearing.analysis.sn_curves import SNCurve, sn_curve
from flexbearing.common.validation import InputError

SF, B, SU = 1758e6, -0.0977, 1172e6          # the 40CrNiMoA preset's constants (Dowling Table 9.1)


def n_basquin(s_ar):
    """Basquin's life, written out: N = 1/2 (S_ar / S_f')^(1/b)."""
    return 0.5 * (s_ar / SF) ** (1.0 / B)


def sine(mean, amp, periods, per_period=40):
    k = np.arange(periods * per_period)
    return mean + amp * np.sin(2 * np.pi * k / per_period)


# ---------------------------------------------------------------- rainflow

def test_astm_e1049_example_cycle_table():
    """ASTM E1049-85 (2017), §5.4.4, Fig. 6: the history -2 1 -3 5 -1 3 -4 4 -2 counts as
    range 3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5 cycles."""
    cyc = rainflow_cycles([-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0])
    table = defaultdict(float)
    for r, c in zip(cyc.range, cyc.count):
        table[r] += c
    assert dict(table) == {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def test_cycle_indices_point_at_the_reversals_of_the_original_history():
    x = np.array([0.0, -2.0, -2.0, 1.0, 0.5, -3.0, 5.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0])
    cyc = rainflow_cycles(x)
    assert np.allclose(np.abs(x[cyc.start] - x[cyc.end]), cyc.range, rtol=0, atol=0)
    rep = rainflow_cycles(x, repeated=True)
    assert np.allclose(np.abs(x[rep.start] - x[rep.end]), rep.range, rtol=0, atol=0)


def test_repeated_block_closes_its_residue():
    """A repeated block of n sine periods: exactly n cycles of range 2 S_a (the half cycles of
    the residue pair up), whatever the phase the block starts at."""
    for shift in (0, 7, 13):
        x = np.roll(sine(50e6, 300e6, 6), shift)
        cyc = rainflow_cycles(x, repeated=True)
        big = np.isclose(cyc.range, 600e6, rtol=1e-12)
        assert cyc.count[big].sum() == pytest.approx(6.0, abs=0)
        assert cyc.count[~big].sum() == 0.0 or np.all(cyc.range[~big] < 1e-6 * 600e6)


# ---------------------------------------------------------------- mean stress, S–N, Miner

def test_mean_stress_corrections_against_hand_values():
    a, m, u = 200e6, 100e6, 1000e6
    assert equivalent_amplitude(a, m, "goodman", u) == pytest.approx(200e6 / 0.9, rel=1e-15)       # 222.2 MPa
    assert equivalent_amplitude(a, m, "gerber", u) == pytest.approx(200e6 / 0.99, rel=1e-15)       # 202.0 MPa
    assert equivalent_amplitude(a, m, "swt", u) == pytest.approx(math.sqrt(300e6 * 200e6), rel=1e-15)  # 244.9 MPa
    assert equivalent_amplitude(a, m, "none", u) == a
    # compressive mean: no credit (Goodman, Gerber); SWT: no damage once S_max <= 0
    assert equivalent_amplitude(a, -100e6, "goodman", u) == a
    assert equivalent_amplitude(a, -100e6, "gerber", u) == a
    assert equivalent_amplitude(a, -300e6, "swt", u) == 0.0
    assert equivalent_amplitude(a, u, "goodman", u) == math.inf
    with pytest.raises(InputError, match="goodman"):
        equivalent_amplitude(a, m, "soderberg", u)


def test_basquin_curve_and_preset_source():
    c = sn_curve("40CrNiMoA")
    assert c.fatigue_strength_coefficient == SF and c.fatigue_strength_exponent == B and c.ultimate_strength == SU
    assert "Dowling" in c.source and "Table 9.1" in c.source
    assert c.cycles_to_failure(500e6) == pytest.approx(n_basquin(500e6), rel=1e-14)
    assert c.amplitude_at(n_basquin(500e6)) == pytest.approx(500e6, rel=1e-14)
    with pytest.raises(InputError, match="brass, bronze and PEEK"):
        sn_curve("brass")


@pytest.mark.parametrize("correction", ["goodman", "gerber", "swt", "none"])
def test_constant_amplitude_sine_on_a_one_element_stress_state(correction):
    """Uniaxial sigma_xx = S_m + S_a sin: the signed von Mises is sigma_xx, the repeated block has
    n cycles, D = n / N(S_ar) exactly."""
    n, sm, sa = 12, 150e6, 350e6
    sigma = np.zeros((n * 40, 6))
    sigma[:, 0] = sine(sm, sa, n)
    x = eq.signed_von_mises(sigma)
    np.testing.assert_allclose(x, sigma[:, 0], rtol=1e-15, atol=1e-6)
    s_ar = {"goodman": sa / (1 - sm / SU), "gerber": sa / (1 - (sm / SU) ** 2),
            "swt": math.sqrt((sm + sa) * sa), "none": sa}[correction]
    d = block_damage(rainflow_cycles(x, repeated=True), sn_curve("40CrNiMoA"), correction)
    assert d == pytest.approx(n / n_basquin(s_ar), rel=1e-12)


def test_two_level_block_loading_miner_sum():
    """n1 cycles at S_a1 then n2 at S_a2 (zero mean), repeated: D = n1/N1 + n2/N2."""
    n1, n2, a1, a2 = 5, 40, 400e6, 150e6
    x = np.r_[sine(0.0, a1, n1), sine(0.0, a2, n2)]
    cyc = rainflow_cycles(x, repeated=True)
    d = block_damage(cyc, sn_curve("40CrNiMoA"), "none")
    assert d == pytest.approx(n1 / n_basquin(a1) + n2 / n_basquin(a2), rel=1e-12)
    assert cyc.count[np.isclose(cyc.range, 2 * a1, rtol=1e-12)].sum() == n1
    assert cyc.count[np.isclose(cyc.range, 2 * a2, rtol=1e-12)].sum() == n2


def test_safety_factor_closed_forms():
    """One level, n cycles a block, B blocks. Without a mean correction lambda = (S_f'/S_a)
    (2 n B)^b; with Goodman lambda S_a / (1 - lambda S_m / S_u) = A, A = S_f' (2 n B)^b, so
    lambda = A / (S_a + S_m A / S_u)."""
    n, sm, sa, blocks = 10, 120e6, 250e6, 3.6e7
    cyc = rainflow_cycles(sine(sm, sa, n), repeated=True)
    c = sn_curve("40CrNiMoA")
    A = SF * (2 * n * blocks) ** B
    assert safety_factor(cyc, c, "none", blocks) == pytest.approx(A / sa, rel=1e-9)
    assert safety_factor(cyc, c, "goodman", blocks) == pytest.approx(A / (sa + sm * A / SU), rel=1e-9)
    lam = safety_factor(cyc, c, "gerber", blocks)
    assert blocks * block_damage(cyc, c, "gerber", lam) == pytest.approx(1.0, rel=1e-9)
    assert safety_factor(rainflow_cycles(np.zeros(10), repeated=True), c, "goodman", blocks) == math.inf


# ---------------------------------------------------------------- multiaxial equivalents

def test_signed_von_mises_closed_form_against_eigenvalues():
    rng = np.random.default_rng(3)
    s = rng.standard_normal((20000, 6)) * 1e8
    ref = eq.von_mises(s)
    lp = eq.largest_principal(s)
    x = eq.signed_von_mises(s)
    # two closed forms of the same norm: the textbook differences (von_mises) against 3 sqrt(J2/3)
    # from the deviator (q = tr/3 subtracted): each of the 6 entries is a combination of the
    # components with absolute coefficients summing to <= 2, formed in <= 4 roundings (+2 for the
    # /6 and 3x of the second form): norm_bound (tests/tolerances.py) with w = 2 sum|s| per entry
    w = np.repeat(2.0 * np.abs(s).sum(axis=1, keepdims=True), 6, axis=1)
    assert_within(np.abs(np.abs(x) - ref), norm_bound(6, w, ref), "signed von Mises magnitude",
                  effect=ref.min())
    w = np.linalg.eigvalsh(np.stack([s[:, [0, 5, 4]], s[:, [5, 1, 3]], s[:, [4, 3, 2]]], axis=1))
    clear = np.abs(w[:, 0] + w[:, 2]) > 1e-9 * np.abs(w).max(axis=1)      # no near-tie of the extremes
    assert np.all(np.sign(x[clear]) == np.sign(lp[clear]))
    # hydrostatic tension and compression: von Mises 0
    assert eq.signed_von_mises(np.array([1e8, 1e8, 1e8, 0, 0, 0])) == 0.0


def _tension_torsion(sa, ta, phase, periods=8, per_period=360):
    w = 2 * np.pi * np.arange(periods * per_period) / per_period
    sigma = np.zeros((len(w), 6))
    sigma[:, 0] = sa * np.sin(w)
    sigma[:, 5] = ta * np.sin(w + phase)
    return sigma


@pytest.mark.parametrize("phase", [0.0, np.pi / 2])
def test_critical_plane_of_tension_torsion(phase):
    """sigma_x = S_a sin(wt), tau_xy = T_a sin(wt + phase), T_a = S_a: the largest normal-stress
    amplitude over the planes is S_a/2 + sqrt(S_a^2/4 + T_a^2) in phase and
    max_c sqrt(S_a^2 c^2 + 4 T_a^2 c (1 - c)) = 2 S_a / sqrt(3) at 90 degrees (stress_equivalent doc)."""
    sa = ta = 200e6
    periods = 8
    sigma = _tension_torsion(sa, ta, phase, periods)
    f_star = sa / 2 + math.sqrt(sa ** 2 / 4 + ta ** 2) if phase == 0 else 2 * sa / math.sqrt(3)
    c = sn_curve("40CrNiMoA")
    d, normal, cyc = critical_plane(sigma, c, "none", 1.0)
    delta = 3 * eq.lattice_spacing(COARSE_PLANES) / (LOCAL_STEPS - 1)
    C = np.array([[sa, ta * math.sin(phase), 0], [ta * math.sin(phase), 0, 0], [0, 0, 0]])
    S = np.array([[0, ta * math.cos(phase), 0], [ta * math.cos(phase), 0, 0], [0, 0, 0]])
    rel = math.sin(delta / math.sqrt(2)) ** 2 * (f_star + np.linalg.norm(C, 2) + np.linalg.norm(S, 2)) / f_star
    rel += 1 - math.cos(math.pi / 360)       # a sampled sine's largest sample: within half a step of its peak
    amp = 0.5 * cyc.range.max()
    assert f_star * (1 - rel) <= amp <= f_star * (1 + 1e-12)
    assert d == pytest.approx(periods / n_basquin(f_star), rel=-rel / B + 1e-12)
    assert abs(normal[2]) < 1e-9 + math.sin(delta)         # the plane's normal lies in the x-y plane


# ---------------------------------------------------------------- the run's damage field

def _synthetic_run(tmp_path, periods=5, per_period=40):
    """test_field_export's synthetic flexible run (27-node cage, 3 random stress modes) with modal
    coordinates q_0 = 1 + 1/2 sin(wt), q_1 = q_2 = 0: every node's stress is S_n0 q_0(t)."""
    from test_field_export import fake_run
    n = periods * per_period
    run, X, S, _, _, _ = fake_run(tmp_path, n=n)
    q = np.zeros((n, S.shape[2]))
    q[:, 0] = 1.0 + 0.5 * np.sin(2 * np.pi * np.arange(n) / per_period)
    with h5py.File(run, "r+") as f:
        f["outputs/cage_modal_coordinates_full"][...] = q
    return run, S, n


def test_damage_field_of_a_proportional_history(tmp_path):
    """At every node the signed von Mises is s_n q_0(t), s_n = signed von Mises of S_n0: n cycles of
    amplitude |s_n|/2 at mean s_n a block; the block (n samples of 1 ms) repeated back to back."""
    run, S, n = _synthetic_run(tmp_path)
    res = cage_fatigue(run, FatigueSettings(correction="goodman", design_life=3600.0, settle=0.0))
    s_n = np.array([eq.signed_von_mises(S[i, :, 0]) for i in range(len(S))])
    s_ar = 0.5 * np.abs(s_n) / (1 - np.maximum(s_n, 0) / SU)
    block = n * 1e-3
    rate = 5 / n_basquin(s_ar) / block                          # 1/s
    assert res.block_duration == pytest.approx(block, rel=1e-12)
    c = res.counted
    assert c.sum() >= 1 and c[np.argmax(rate)]
    # rounding of the rate, relative: the history s_n q_0(t) (one product) and its signed von
    # Mises (<= 15 roundings), the amplitude (max - min)/2 of 1.5 s_n and 0.5 s_n (condition 2)
    # and the mean, Goodman (condition g = (S_m/S_u)/(1 - S_m/S_u) on S_m), Basquin (condition
    # |1/b| = 10.2 on S_ar, the power or exp/log: 34 roundings), the block (an accumulated sum:
    # gamma_200); twice, for the test's own evaluation (Higham §1.6, §3.1)
    g = np.maximum(s_n, 0) / SU / (1 - np.maximum(s_n, 0) / SU)
    rtol = 2 * (abs(1 / B) * ((2 + g) * gamma(15) + gamma(3)) + gamma(34) + gamma(200))
    assert_within(np.abs(res.damage_rate[c] - rate[c]), rtol[c] * rate[c], "damage rate",
                  effect=rate[c].min())
    assert np.all(res.damage_rate[~c] >= rate[~c])             # screened out: an upper bound
    assert_within(np.abs(res.life[c] - 1 / rate[c]), (rtol[c] + 2 * gamma(1)) / rate[c], "life",
                  effect=(1 / rate[c]).min())
    # safety factor over one hour: Goodman closed form per node (test_safety_factor_closed_forms)
    blocks = 3600.0 / block
    A = SF * (2 * 5 * blocks) ** B
    lam = A / (0.5 * np.abs(s_n) + np.maximum(s_n, 0) * A / SU)
    np.testing.assert_allclose(res.safety_factor[c], lam[c], rtol=1e-9)
    assert np.all(res.safety_factor[~c] <= lam[~c] * (1 + 1e-9))
    worst = res.candidates[0]
    assert worst["node"] == int(np.argmax(rate))
    assert worst["dominant_cycles"][0]["range"] == pytest.approx(abs(s_n[worst["node"]]), rel=1e-12)


def test_screening_bounds_hold_on_random_histories():
    rng = np.random.default_rng(7)
    c = sn_curve("40CrNiMoA")
    from flexbearing.analysis.cage_fatigue import history_stats
    x = np.cumsum(rng.standard_normal((40, 300)), axis=1) * 2e7 + rng.normal(size=(40, 1)) * 2e8
    hi, lo, r = np.zeros(40), np.zeros(40), np.zeros(40, np.int64)
    history_stats(x, hi, lo, r)
    for corr in ("goodman", "gerber", "swt", "none"):
        bound = screen_bound(hi, lo, r, c, corr)
        sf_lb = screen_safety_factor(hi, lo, r, c, corr, 1e6)
        for i in range(40):
            cyc = rainflow_cycles(x[i], repeated=True)
            assert block_damage(cyc, c, corr) <= bound[i] * (1 + 1e-12)
            assert safety_factor(cyc, c, corr, 1e6) >= sf_lb[i] * (1 - 1e-9)


def test_fatigue_files_and_bad_settings(tmp_path):
    import meshio
    run, S, n = _synthetic_run(tmp_path)
    res = cage_fatigue(run, FatigueSettings(nodes=(3,), settle=0.0))
    assert any(cand["node"] == 3 and cand["user_node"] for cand in res.candidates)
    paths = write_fatigue_files(res, res.reduced_cage, tmp_path / "out")
    with meshio.xdmf.TimeSeriesReader(paths["xdmf"]) as r:
        points, cells = r.read_points_cells()
        _, point_data, _ = r.read_data(0)
    np.testing.assert_array_equal(point_data["damage_rate"], res.damage_rate)
    assert set(point_data) >= {"damage_rate", "life", "safety_factor", "peak_signed_von_mises", "counted"}
    with h5py.File(paths["h5"], "r") as f:
        assert f["fields/damage_rate"].attrs["unit"] == "1/s" and f["fields/life"].attrs["unit"] == "s"
        np.testing.assert_allclose(f["candidates/3/stress"][:, 0],
                                   S[3, 0, 0] * (1 + 0.5 * np.sin(2 * np.pi * np.arange(n) / 40)), rtol=1e-12)
    with pytest.raises(InputError, match=r"fatigue node = 99 is outside the allowed range \[0, 26\]"):
        cage_fatigue(run, FatigueSettings(nodes=(99,), settle=0.0))
    with pytest.raises(InputError, match="blocks_per_hour"):
        FatigueSettings(blocks_per_hour=0.0).validate()
    with pytest.raises(InputError, match="allowed: 40CrNiMoA"):
        FatigueSettings(material="PEEK").validate()
    link = tmp_path / "lnk"
    link.mkdir()
    (link / "fatigue.h5").symlink_to(tmp_path / "elsewhere.h5")
    with pytest.raises(InputError, match="symbolic link"):
        write_fatigue_files(res, res.reduced_cage, link)


def test_custom_curve_validates():
    with pytest.raises(InputError, match="fatigue_strength_exponent"):
        SNCurve("x", 1e9, 0.1, 1e9, "none").validate()


def test_report_fatigue_section_and_cli_errors(tmp_path, capsys):
    """`flexbearing report --fatigue` on the synthetic run: the section, its picture and ParaView file;
    bad fatigue options stop with one line naming the field and exit code 2."""
    from flexbearing.cli.main import main
    run, S, n = _synthetic_run(tmp_path)
    out = tmp_path / "rep"
    assert main(["report", str(run), "-o", str(out), "--quiet", "--fatigue", "--fatigue-nodes", "4",
                 "--fatigue-blocks-per-hour", "20", "--settle", "0"]) == 0
    md = (out / "report.md").read_text()
    assert "## Cage fatigue at this duty cycle" in md and "fatigue_damage.png" in md and "fatigue.xdmf" in md
    assert "4 (yours)" in md and "20 blocks per hour" in md
    assert (out / "fatigue_damage.png").stat().st_size > 10_000 and (out / "fatigue.xdmf").is_file()
    import json
    facts = json.loads((out / "report.json").read_text())["cage_fatigue"]
    assert facts["blocks_per_hour"] == 20 and facts["mean_stress_correction"] == "goodman"
    capsys.readouterr()
    for bad, field in ((["--fatigue-correction", "soderberg"], "mean-stress correction"),
                       (["--fatigue-blocks-per-hour", "-1"], "fatigue blocks_per_hour = -1"),
                       (["--fatigue-nodes", "1,x"], "--fatigue-nodes"),
                       (["--fatigue-material", "brass"], "fatigue material = 'brass'")):
        assert main(["report", str(run), "-o", str(tmp_path / "bad"), "--quiet", "--fatigue"] + bad) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and field in err[0]


def test_signed_von_mises_overreads_out_of_phase_tension_torsion():
    """tau_a = sigma_a, 90 degrees out of phase: the signed von Mises jumps from +sqrt(3) sigma_a to
    -sqrt(3) sigma_a where sigma_x changes sign (range 2 sqrt(3) sigma_a; a sample at most one step
    of 2 pi/P from the flip reads at least sqrt(3 - 2 sin^2(2 pi/P)) sigma_a), while the critical
    plane's amplitude is 2/sqrt(3) sigma_a (test_critical_plane_of_tension_torsion)."""
    sa = 200e6
    P = 360
    x = eq.signed_von_mises(_tension_torsion(sa, sa, np.pi / 2, per_period=P))
    cyc = rainflow_cycles(x, repeated=True)
    r = cyc.range.max()
    assert 2 * sa * math.sqrt(3 - 2 * math.sin(2 * math.pi / P) ** 2) <= r <= 2 * math.sqrt(3) * sa * (1 + 1e-12)
    assert cyc.range.max() / 2 > 1.49 * (2 * sa / math.sqrt(3))


def test_duty_cycle_without_a_settled_part_is_refused_or_flagged(tmp_path):
    """The synthetic run's cage speed ramps over the whole run (test_report's scene): by default the
    duty cycle leaves out the start-up transient, and here the transient never ends (MSER-5's
    minimum past half of the phase): cage_fatigue refuses in one line, the report's section says
    so and is written; with --settle given the block is counted and flagged as not settled."""
    from flexbearing.analysis.fatigue_report import fatigue_section
    run, S, n = _synthetic_run(tmp_path)
    with pytest.raises(InputError, match=r"has no settled part to repeat as a duty cycle: the start-up transient "
                                         r"of its cage speed runs past half") as exc:
        cage_fatigue(run, FatigueSettings())
    assert "\n" not in str(exc.value)
    md, facts, files = fatigue_section(run, tmp_path / "out", FatigueSettings())
    assert md[2].startswith("Not computed: fatigue: run.h5 has no settled part") and files == {}
    res = cage_fatigue(run, FatigueSettings(settle=0.0))
    assert res.startup["rule"] == "given" and res.startup["settled"] is False


def test_duty_cycle_leaves_out_the_detected_start_up(tmp_path):
    """The synthetic run with a cage speed that approaches its level as 450·(1 + 0.05·exp(−t/10 ms))
    on noise of 0.1 rad/s: MSER-5 puts the transient's end near tau·ln(A·sqrt5/sigma) = 62 ms
    (tests/test_settling.py), within tau·ln 2 plus a batch; the block (its times: the peak-search steps,
    within a sample interval before each sample) starts there (or later, where
    another signal's start-up ends later), and the section names the window left out."""
    from flexbearing.analysis.fatigue_report import fatigue_markdown
    run, S, n = _synthetic_run(tmp_path)
    rng = np.random.default_rng(4)
    with h5py.File(run, "r+") as f:
        t = f["outputs/time"][...]
        f["outputs/cage_speed"][...] = 450.0 * (1 + 0.05 * np.exp(-t / 0.01)) + 0.1 * rng.standard_normal(len(t))
    res = cage_fatigue(run, FatigueSettings())
    expected = 0.01 * math.log(22.5 * math.sqrt(5) / 0.1)
    settle = res.startup["settle"]
    assert res.startup["rule"].startswith("MSER-5")
    assert settle >= expected - (0.01 * math.log(2) + 5e-3)
    assert res.times[0] >= settle - 1e-3 and res.block_duration == pytest.approx(t[-1] - settle + 1e-3, rel=1e-9)
    md = "\n".join(fatigue_markdown(res, {"xdmf": tmp_path / "fatigue.xdmf", "h5": tmp_path / "fatigue.h5",
                                          "json": tmp_path / "fatigue.json"}))
    assert f"Start-up: 0–{settle:.4g} s left out of the duty cycle" in md
