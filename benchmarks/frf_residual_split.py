"""Why the run's 26-mode truncation misses the damped FRF near 2.8 kHz (reduced model only, 1 s).

Reads benchmarks/results/frf_paper_damped.json (its grid) and the paper reduced cage from the cache
and compares, at the loaded interface node (pocket 1, unit circumferential/radial/axial forces),
the full Craig–Bampton basis with D = beta·K in every mode (what matches the full FE within
0.49 %) against the run's 20 elastic modes plus the residual of the others taken
  (b)  static and undamped, q_k = f_k / omega_k²                (what the runtime does), and
  (bd) static but with its stiffness-proportional damping, q_k = f_k / (omega_k² (1 + i·Omega·beta)).
The gap (b) − (bd) is the damping of the discarded modes; what remains in (bd) is their inertia.

    .venv/bin/python benchmarks/frf_residual_split.py
"""
import json
from pathlib import Path

import numpy as np


def main():
    import flexbearing.mesh.cage_mesh as cm
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.fem_cage import reduced_cage as rcf
    from flexbearing.verification.frequency_response import pocket_directions
    r = json.loads((Path(__file__).parent / "results" / "frf_paper_damped.json").read_text())
    key = rcf.cache_key(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                        rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, cm.DEFAULT_DEGREE, True)
    rc = rcf.read(rcf.find_cached(key))
    w = 2 * np.pi * np.array(r["grid_hz"])
    beta, om, M, n_keep = r["beta_s"], rc.omega, len(rc.omega), r["n_keep"]
    phi = rc.interface_modes[r["load_node"]]
    g = phi.T @ pocket_directions(rc.interface_positions[r["load_node"]])

    def response(mode):
        out = []
        for W in w:
            k = np.arange(6, M)
            dyn = 1.0 / (om[k] ** 2 - W * W + 1j * W * beta * om[k] ** 2)
            h = np.zeros(M, complex)
            if mode == "c":
                h[k] = dyn
            else:
                h[6:n_keep] = dyn[:n_keep - 6]
                res = om[n_keep:] ** 2 * (1 + 1j * W * beta) if mode == "bd" else om[n_keep:] ** 2
                h[n_keep:] = 1.0 / res
            out.append(phi[:3] @ (h[:, None] * g))
        return np.array(out)

    c = response("c")
    for mode in ("b", "bd"):
        e = np.linalg.norm(response(mode) - c, axis=1) / np.linalg.norm(c, axis=1)
        print(f"{mode}: max relative difference to the full basis {e.max():.4f}")


if __name__ == "__main__":
    main()
