"""Before -> after table of two runs' reports (a change of model, e.g. the traction law).

Run: .venv/bin/python benchmarks/report_before_after.py BEFORE/report.json AFTER/report.json
(the report.json files of `flexbearing report`). Prints, per phase and impact window of the
BEFORE report, the peak / p99 / mean of the contact stresses (MPa), the pocket and guiding forces
(N) and the cage slip rate (%) of both runs and the change, as a markdown table.
"""
import json
import sys

QUANTITIES = (("outer_contact_stress", "outer-race contact stress, MPa", 1e-6),
              ("inner_contact_stress", "inner-race contact stress, MPa", 1e-6),
              ("pocket_force", "pocket force, N", 1.0),
              ("guiding_force", "guiding force, N", 1.0),
              ("slip_rate", "cage slip rate, %", 100.0))
STATS = ("peak", "p99", "mean")


def _fmt(x: float) -> str:
    return f"{x:,.0f}" if abs(x) >= 100.0 else f"{x:.3g}"


def table(before: dict, after: dict) -> str:
    after_phases = {p["label"]: p for p in after["phases"]}
    lines = ["| window | quantity | " + " | ".join(f"{s} before → after" for s in STATS) + " |",
             "|---|---|" + "---:|" * len(STATS)]
    for p in before["phases"]:
        q = after_phases.get(p["label"])
        if q is None:
            continue
        for key, name, f in QUANTITIES:
            cells = []
            for s in STATS:
                a, b = p.get(f"{key}_{s}"), q.get(f"{key}_{s}")
                if a is None or b is None:
                    cells.append("–")
                else:
                    cells.append(f"{_fmt(a * f)} → {_fmt(b * f)}")
            lines.append(f"| {p['label']} | {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    with open(sys.argv[1]) as f:
        before = json.load(f)
    with open(sys.argv[2]) as f:
        after = json.load(f)
    print(table(before, after))


if __name__ == "__main__":
    main()
