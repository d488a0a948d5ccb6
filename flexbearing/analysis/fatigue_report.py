"""The report's section on the cage's fatigue (`flexbearing report --fatigue`): the worst nodes with
their location, life, safety factor and dominant cycles, the unrolled damage picture and the
ParaView fields (flexbearing.analysis.cage_fatigue, fatigue_picture). One function,
`fatigue_section`, which the report calls once."""
from __future__ import annotations

import math
import h5py
from flexbearing.analysis.fatigue_picture import write_damage_picture


HOUR = 3600.0
N_ROWS = 10


def _h(v) -> str:
    return "∞" if v is None or not math.isfinite(v) else f"{v / HOUR:.3g}"


def _cycle(c: dict | None) -> str:
    if not c:
        return "–"
    return (f"{c['range'] / 1e6:,.0f} / {c['mean'] / 1e6:,.0f} MPa × {c['count']:g} at "
            f"{c['t_start']:.4f}–{c['t_end']:.4f} s ({100 * c['damage_share']:.0f} %)")


def fatigue_markdown(result, files: dict) -> list[str]:
    """Markdown lines of the section (result: CageFatigue, files: the written paths)."""
    from flexbearing.analysis.cage_fatigue import SCREEN
    s = result.settings
    rows = ["| node | where (surface; θ, x, r) | peak von Mises (MPa) | life, signed von Mises (h) | "
            "life, critical plane (h) | safety factor | dominant cycle (range / mean × count at t, share) | "
            "peak-search samples |", "|---:|---|---:|---:|---:|---:|---|---:|"]
    for c in result.candidates[:N_ROWS]:
        rows.append(f"| {c['node']}{' (yours)' if c['user_node'] else ''} | {c['surface']}; "
                    f"{c['azimuth_deg']:.1f}°, {c['axial'] * 1e3:.2f} mm, {c['radius'] * 1e3:.2f} mm | "
                    f"{c['peak_von_mises'] / 1e6:,.1f} | {_h(c['life'])} | {_h(c['critical_plane_life'])} | "
                    f"{c['governing_safety_factor']:.3g} | {_cycle((c['dominant_cycles'] or [None])[0])} | "
                    f"{c['hot_spot_samples']} |")
    w = result.candidates[0] if result.candidates else None
    t = result.timing
    md = ["## Cage fatigue at this duty cycle", ""]
    if w:
        md += [f"Worst node **{w['node']}** ({w['surface']}; θ = {w['azimuth_deg']:.1f}°, x = {w['axial'] * 1e3:.2f} mm, "
               f"r = {w['radius'] * 1e3:.2f} mm): life **{_h(w['governing_life'])} h**, safety factor "
               f"**{w['governing_safety_factor']:.3g}** on the stress history for a design life of "
               f"{s.design_life / HOUR:,.0f} h.", ""]
    md += startup_lines(result)
    md += rows + ["",
                  f"Duty cycle: {'the run' if s.blocks_per_hour is None else 'a block of the run'} "
                  f"({result.block_duration:.4g} s, {result.n_samples} samples"
                  + (f", from t = {result.startup.get('settle', s.settle or 0.0):g} s"
                     if result.startup.get("settle", s.settle) else "")
                  + (f" to t = {s.until:g} s" if s.until is not None else "") + ") "
                  + ("repeated back to back" if s.blocks_per_hour is None else "given by the user")
                  + f": {result.blocks_per_hour:,.4g} blocks per hour. Material {s.material}: "
                  f"{result.curve_source}; Basquin's line continued without an endurance limit "
                  f"(conservative), polished-specimen curve (no surface or size factor). Mean stress: {s.correction}. "
                  "Cycles: rainflow (ASTM E1049-85 §5.4.4) of one block of the repeated history, Palmgren–Miner sum. "
                  "Equivalent stress: the signed von Mises at every node (sign of the largest principal stress); "
                  "at the candidates also the normal stress on the critical plane (the plane of largest damage); "
                  "the smaller life governs. Safety factor: the factor on the whole stress history at which the "
                  "damage over the design life reaches 1. Candidates: the nodes that held the cage's maximum in the "
                  "run's peak search (count in the last column), the worst of the field and the user's "
                  "(`--fatigue-nodes`).",
                  "",
                  f"The stress history is the run's recorded samples (the integrator step of each sample "
                  f"interval's largest cage stress): cycles faster than about two sample intervals are not seen. "
                  f"Elastic stress (linear FE cage); no crack-growth or notch-sensitivity model. "
                  f"{result.counted.sum():,} of {len(result.damage_rate):,} nodes counted; the others' damage bound "
                  f"is below {SCREEN:g} of the worst (their fields hold the bound). Cost: {t['total']:.1f} s "
                  f"(field {t['field']:.1f} s, candidates with critical planes {t['candidates']:.1f} s).", ""]
    if files.get("picture"):
        md += [f"![fatigue damage]({files['picture'].name})", ""]
    md += [f"ParaView: `{files['xdmf'].name}` (+ `{files['h5'].name}`): damage_rate (1/s), life (s), safety_factor, "
           f"peak_signed_von_mises (Pa) and counted at every mesh node, beside the von Mises frames; "
           f"facts and every candidate's dominant cycles in `{files['json'].name}`.", ""]
    return md


def startup_lines(result) -> list[str]:
    """What the duty cycle leaves out at the start and whether the rest settled (cage_fatigue's
    module doc, "Start-up left out")."""
    st = result.startup or {}
    if not st:
        return []
    t0 = st["settle"]
    if st["rule"] == "given":
        text = (f"Start-up: the block starts at t = {t0:g} s (given: `--settle`)." if t0 > 0 else
                "Start-up: **included** (`--settle 0`): the block repeats the run's start from its initial state.")
    elif st["rule"].startswith("MSER-5"):
        text = (f"Start-up: 0–{t0:.4g} s left out of the duty cycle (the start-up transient from the run's initial "
                f"state, found by MSER-5 on the cage speed, slip, cage forces and stress; `--settle S` sets it).")
    else:
        text = f"Start-up: {st['rule']}."
    if st.get("settled") is False:
        text += f" **The block has not settled** ({st['reason']}): the life is that of a transient; run longer."
    elif st.get("settled") is None:
        text += f" Whether the block settled is undecided ({st['reason']})."
    return [text, ""]


def fatigue_section(run_h5, out_dir, settings, reduced_cage=None, quiet: bool = True):
    """(markdown lines, facts for report.json, files) of the fatigue section; for a run without a
    flexible cage the lines say why there is none (facts None). Bad settings raise InputError."""

    from flexbearing.analysis.cage_fatigue import cage_fatigue, facts, write_fatigue_files
    settings.validate()
    with h5py.File(run_h5, "r") as f:
        if "cage_modal_coordinates_full" not in f["outputs"]:
            return ["## Cage fatigue at this duty cycle", "", "Not computed: the run has no flexible-cage "
                    "stress history (a flexible-cage run recording \"von_mises\" has it).", ""], None, {}
    if settings.settle is None:
        from flexbearing.analysis.cage_fatigue import start_of_block
        from flexbearing.common.validation import InputError
        try:
            start_of_block(run_h5, settings)
        except InputError as exc:            # no settled part: flagged here, the rest of the report written
            return ["## Cage fatigue at this duty cycle", "", f"Not computed: {exc}.", ""], \
                {"refused": str(exc)}, {}
    result = cage_fatigue(run_h5, settings, reduced_cage=reduced_cage, quiet=quiet)
    files = write_fatigue_files(result, result.reduced_cage, out_dir)
    files["picture"] = write_damage_picture(result, result.reduced_cage, out_dir)
    return fatigue_markdown(result, files), facts(result), files
