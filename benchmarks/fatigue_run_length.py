"""The cage's fatigue safety factor against run length, the start-up transient in and out
(issue 41, "settled before statistics"): one flexible-cage run, its first 30 / 60 / 120 / 240 ms
taken as the duty-cycle block (a shorter run from the same start is the same trajectory: the
integrator stops at the same sample indices), counted from t = 0 and from the end of the
start-up transient the fatigue step finds by default (MSER-5, flexbearing.analysis.settling).

    python benchmarks/fatigue_run_length.py RUN.h5 [--lengths 0.03,0.06,0.12,0.24]

RUN.h5: a flexible-cage run recording "von_mises" (and cage_speed, slip, pocket_force,
guiding_force for the start-up rule), e.g. the 14-pocket CAD test cage's scene in
benchmarks/results/fatigue_run_length.md.
"""
from __future__ import annotations

import argparse
import math

from flexbearing.analysis.cage_fatigue import HOUR, FatigueSettings, cage_fatigue
from flexbearing.common.validation import InputError


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("--lengths", default="0.03,0.06,0.12,0.24")
    a = ap.parse_args()
    print("| run length (ms) | start-up | block (s) | left out to (s) | block settled | worst life (h) | safety factor |")
    print("|---:|---|---|---:|---|---:|---:|")
    for until in (float(x) for x in a.lengths.split(",")):
        for settle, label in ((0.0, "in"), (None, "out (default)")):
            try:
                r = cage_fatigue(a.run, FatigueSettings(settle=settle, until=until))
            except InputError as exc:
                print(f"| {until * 1e3:g} | {label} | refused: {exc} | | | | |")
                continue
            w = r.candidates[0]
            life = w["governing_life"]
            print(f"| {until * 1e3:g} | {label} | {r.times[0]:.4f}–{r.times[-1]:.4f} | {r.startup['settle']:.4f} | "
                  f"{r.startup['settled']} | {'inf' if not math.isfinite(life) else f'{life / HOUR:,.3g}'} | "
                  f"{w['governing_safety_factor']:.3g} |", flush=True)


if __name__ == "__main__":
    main()
