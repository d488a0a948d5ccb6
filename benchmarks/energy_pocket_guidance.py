"""Energy conservation of a conservative free run for every pocket shape × guidance (issue 45).

For each of the 12 pairs (cylindrical, spherical, conical 8°, elliptical 23 mm × guided by the outer
land, the inner land, the balls): the paper bearing at 10,000 rpm, Fa 5 kN, Fr 1 kN, traction, drag and
damping off, Hertz constants at the free contact angle (tests/test_energy.py's conservative model), the
cage thrown at 0.1 m/s across the bearing and its guide clearance set to 0.1 mm (below the pocket
clearance, 0.25 mm) so that it strikes its rim as well as the pockets. Prints the largest
|E − E0| over 10 outputs of the run relative to the contact energy |V0| (the bound of the tests: 1e-4).

Run it on two checkouts to compare them (the numbers of issue 45's note):

    PYTHONPATH=. .venv/bin/python benchmarks/energy_pocket_guidance.py [--duration 0.005] [--tol 1e-6 ...]

With several tolerances (e.g. --tol 1e-6 1e-8 1e-10) one table per tolerance: a conservative
system's energy error is integration error only and must fall with the tolerance (about as tol for
Dormand–Prince 5(4)); one that stays put reveals a force that is not the gradient of its potential.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from flexbearing.mesh.cage_geometry import GUIDANCES, POCKET_SHAPES  # noqa: E402
from flexbearing.multibody import energy as E, integrator as I  # noqa: E402
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL  # noqa: E402
from flexbearing.multibody.initial import initial_state  # noqa: E402
from flexbearing.multibody.model import P_CG, P_Z, build_model  # noqa: E402
from flexbearing.multibody.state_layout import CAGE_VY, cage_offset  # noqa: E402

CONSERVATIVE = {"traction": False, "drag": False, "damping": False, "hertz_fixed_angle": True}
SHAPE_KEYS = {"conical": {"pocket_cone_angle": math.radians(8.0)},
              "elliptical": {"pocket_circumferential_diameter": 23.0e-3}}


def energy_error(shape, guidance, duration, tol, rpm=10000.0, fa=5000.0, fr=1000.0, n_out=10):
    """max |E − E0| / |V0| of the run described in the module docstring."""
    cage = PAPER_BEARING.cage.with_(guidance=guidance, pocket_shape=shape, **SHAPE_KEYS.get(shape, {}))
    m = build_model(PAPER_BEARING.with_(cage=cage), PAPER_OIL, CONSERVATIVE)
    w = rpm * math.pi / 30
    y = initial_state(m, w, fa, fr)
    m.p[P_CG] = 0.1e-3
    y[cage_offset(int(m.p[P_Z])) + CAGE_VY] += 0.1
    sp, ld, imp = np.array([[0.0, w]]), np.array([[0.0, fa, 0.0, -fr]]), np.zeros((0, 6))
    ws = I.Workspace(m)
    t, h = 0.0, 1e-6
    ek, ev0 = E.mechanical_energy(0.0, y, m.p, m.flags, m.hertz_table, ld, imp, m.cage)
    energies = [ek + ev0]
    for k in range(1, n_out + 1):
        y, t, h, _, _ = I.advance(m, y, t, duration * k / n_out, sp, ld, imp, tol, h, ws)
        ek, ev = E.mechanical_energy(t, y, m.p, m.flags, m.hertz_table, ld, imp, m.cage)
        energies.append(ek + ev)
    energies = np.array(energies)
    return float(np.max(np.abs(energies - energies[0])) / abs(ev0))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.005, help="simulated time, s")
    ap.add_argument("--tol", type=float, nargs="+", default=[I.DEFAULT_TOL], help="integrator tolerance(s)")
    a = ap.parse_args()
    for tol in a.tol:
        print(f"max |E - E0| / |V0|, {a.duration * 1e3:g} ms, tolerance {tol:g}")
        print("pocket shape  " + "".join(f"{g:>12s}" for g in GUIDANCES))
        for shape in POCKET_SHAPES:
            print(f"{shape:12s}  " + "".join(f"{energy_error(shape, g, a.duration, tol):12.2e}" for g in GUIDANCES),
                  flush=True)


if __name__ == "__main__":
    main()
