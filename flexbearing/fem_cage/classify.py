"""Name each cage mode by its ring family and circumferential wave number n.

Method (beam-section projection): nodes are sorted into azimuthal sectors; in each sector the
nodal displacement is fitted by least squares with the rigid motion of the cross-section in
cylindrical components (x axial, r radial, t tangential; section centroid (x0, R0)):

    u_x = a_x - phi_t (r - R0)                       (axial translation, twist phi_t)
    u_r = a_r + phi_t (x - x0)
    u_t = a_t + phi_r (x - x0) - phi_x (r - R0)      (tangential, out-of-plane slope phi_r,
                                                       in-plane slope phi_x)
The displacement field is split into in-plane (a_r, a_t, phi_x), out-of-plane (a_x, phi_r),
twist (phi_t) and the residual (section distortion: pocket-local deformation). Shares are
sums of squares over nodes. n is the dominant azimuthal Fourier order of the leading
component (a_r for in-plane, a_x for out-of-plane, phi_t for twist) over the sectors.
Families (the paper's words, §4.1): "in-plane bending" (n >= 2), "in-plane breathing" (n = 0),
"out-of-plane bending-torsion" (n >= 2), "torsion" (twist-dominated), "local" (residual
share > 0.5), "rigid" (|f| below rigid_tol_hz).
Ring theory background: Rao, "Vibration of Continuous Systems" (2007) §11.4–11.5.
"""
from __future__ import annotations

import numpy as np


def nodal_displacements(V, vec, comm=None):
    """(X, U): coordinates (N, 3) and displacements (N, 3) of all owned nodes, gathered on
    every rank (small enough for classification and plots)."""
    comm = comm or V.mesh.comm
    n_owned = V.dofmap.index_map.size_local
    X = V.tabulate_dof_coordinates()[:n_owned]
    arr = vec.getArray(readonly=True)
    U = np.asarray(arr[:3 * n_owned]).reshape(-1, 3)
    if comm.size > 1:
        X = np.vstack(comm.allgather(X))
        U = np.vstack(comm.allgather(U))
    return X, U


def section_fit(X, U, n_sectors: int = 80):
    """Per-node split of U into in-plane, out-of-plane, twist parts and residual (N, 3 each)."""
    x, y, z = X[:, 0], X[:, 1], X[:, 2]
    r = np.hypot(y, z)
    th = np.arctan2(z, y) % (2 * np.pi)
    er = np.stack([np.zeros_like(r), y / r, z / r], axis=1)
    et = np.stack([np.zeros_like(r), -z / r, y / r], axis=1)
    ux, ur, ut = U[:, 0], np.einsum("ij,ij->i", U, er), np.einsum("ij,ij->i", U, et)
    sector = np.minimum((th / (2 * np.pi) * n_sectors).astype(int), n_sectors - 1)
    parts = {k: np.zeros((len(x), 3)) for k in ("inplane", "outofplane", "twist")}
    coef = np.zeros((n_sectors, 6))    # a_x, a_r, a_t, phi_t, phi_r, phi_x
    for s in range(n_sectors):
        idx = np.nonzero(sector == s)[0]
        if len(idx) < 4:
            continue
        dx, dr = x[idx] - x[idx].mean(), r[idx] - r[idx].mean()
        m = len(idx)
        one, zero = np.ones(m), np.zeros(m)
        # rows: u_x block, u_r block, u_t block; columns: a_x a_r a_t phi_t phi_r phi_x
        A = np.block([[one[:, None], zero[:, None], zero[:, None], -dr[:, None], zero[:, None], zero[:, None]],
                      [zero[:, None], one[:, None], zero[:, None], dx[:, None], zero[:, None], zero[:, None]],
                      [zero[:, None], zero[:, None], one[:, None], zero[:, None], dx[:, None], -dr[:, None]]])
        b = np.concatenate([ux[idx], ur[idx], ut[idx]])
        c, *_ = np.linalg.lstsq(A, b, rcond=None)
        coef[s] = c
        ax, ar, at, pt, pr, px = c
        # cylindrical components (x, r, t) of each part
        inp = np.stack([zero, ar + 0 * dx, at - px * dr], axis=1)
        oop = np.stack([ax + 0 * dx, zero, pr * dx], axis=1)
        tw = np.stack([-pt * dr, pt * dx, zero], axis=1)
        for key, cyl in (("inplane", inp), ("outofplane", oop), ("twist", tw)):
            parts[key][idx] = (cyl[:, :1] * np.array([1.0, 0, 0]) + cyl[:, 1:2] * er[idx]
                               + cyl[:, 2:3] * et[idx])
    fitted = parts["inplane"] + parts["outofplane"] + parts["twist"]
    parts["residual"] = U - fitted
    return parts, coef


def _wave_number(signal: np.ndarray) -> tuple[int, float]:
    """Dominant Fourier order of a periodic sector signal and its share of the power."""
    p = np.abs(np.fft.rfft(signal)) ** 2
    total = p.sum()
    if total <= 0:
        return 0, 0.0
    n = int(np.argmax(p))
    return n, float(p[n] / total)


def classify_mode(X, U, frequency_hz: float = np.inf, rigid_tol_hz: float = 1.0,
                  n_sectors: int = 80) -> dict:
    """Family, wave number n and the shares behind them for one mode shape."""
    parts, coef = section_fit(X, U, n_sectors)
    total = float(np.sum(U ** 2)) or 1.0
    share = {k: float(np.sum(v ** 2)) / total for k, v in parts.items()}
    if abs(frequency_hz) < rigid_tol_hz:
        return {"family": "rigid", "n": None, "shares": share}
    lead = max(("inplane", "outofplane", "twist"), key=lambda k: share[k])
    # n: the strongest order among the components of the leading family
    cands = {"inplane": [1, 2, 5], "outofplane": [0, 4], "twist": [3]}[lead]
    n, conc = max((_wave_number(coef[:, c]) for c in cands), key=lambda t: t[1])
    if share["residual"] > 0.5:
        family = "local"
    elif lead == "inplane":
        family = "in-plane breathing" if n == 0 else "in-plane bending"
    elif lead == "outofplane":
        family = "out-of-plane bending-torsion" if share["twist"] > 0.1 * share["outofplane"] \
            else "out-of-plane bending"
    else:
        family = "torsion"
    return {"family": family, "n": n, "concentration": conc, "shares": share, "lead": lead}


def classify_modes(V, vecs, freqs_hz, rigid_tol_hz: float = 1.0, n_sectors: int = 80) -> list[dict]:
    out = []
    for f, v in zip(freqs_hz, vecs):
        X, U = nodal_displacements(V, v)
        out.append(classify_mode(X, U, f, rigid_tol_hz, n_sectors))
    return out


def short_label(c: dict) -> str:
    if c["family"] == "rigid":
        return "rigid"
    return f"{c['family']} n={c['n']}"
