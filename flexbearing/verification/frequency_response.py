"""Frequency response of the free–free cage to a harmonic pocket force: full FE vs reduced cage.

Full FE (direct frequency response; Craig & Kurdila, "Fundamentals of Structural Dynamics",
2nd ed. 2006, §10.2, and ch. 14 for the modal side):

    (K - w^2 M + i w D) u = f,   D = beta K,   f = C_l^T F                              (1)

f is the pocket force F (N, N m; 6 components at interface node l) applied through the same
RBE3/RBE2 interface functional C as the static checks (flexbearing.fem_cage.interface: the load a ball puts
on the pocket wall). One LU factorisation per frequency (PETSc + MUMPS); beta > 0 is solved in
the real 2n form [[A, -B], [B, A]] [Re u; Im u] = [f; 0], A = K - w^2 M, B = w beta K.

Reduced cage (modal superposition on the orthonormal basis of flexbearing.fem_cage.reduced_cage, modal mass
I, modal stiffness diag(omega_k^2), modal damping beta omega_k^2):

    q_k = Phi_l,k^T F / (omega_k^2 - w^2 + i w beta omega_k^2),      k < n_keep          (2)
    q_k = Phi_l,k^T F / omega_k^2                                     k >= n_keep          (3)

(2) the kept modes (rigid ones included: omega = 0 gives -Phi^T F / w^2), (3) the residual
static correction of the discarded modes (mode-acceleration method, reduced_cage.
static_correction; what the runtime adds), optional. Response at the loaded interface node:
u_l = Phi_l q.

Free–free: at w = 0 (1) is singular (rigid modes). Both models contain the same exact rigid modes
R (mass-normalised), whose response -R R^T f / w^2 is identical in both and swamps the elastic
deformation at low w; the comparison is therefore made on the ELASTIC response

    u_el = (I - R R^T M) u                                                                (4)

(the deformation in the mean-axis frame; at w = 0 it is the inertia-relief static response
K u = f - M R a, R^T M u = 0, solved by the saddle LU), and the total response is also given for
w > 0. Frequencies within +-exclude of any natural frequency are left out of the grid
(frequency_grid): there the response is set by how well the reduced model places the resonance,
not by the truncation.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from flexbearing.common.validation import require_range
from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP


class _LU:
    """A x = b for a sparse real matrix, factorised once (PETSc LU, MUMPS when available)."""

    def __init__(self, A: sp.spmatrix):
        from flexbearing.fem_cage.craig_bampton import lu_ksp, scipy_to_petsc
        self.A = scipy_to_petsc(A)
        self.ksp, _ = lu_ksp(self.A)
        self._b, self._x = self.A.createVecRight(), self.A.createVecRight()

    def solve(self, b: np.ndarray) -> np.ndarray:
        self._b.setArray(np.asarray(b, dtype=float))
        self.ksp.solve(self._b, self._x)
        return self._x.getArray(readonly=True).copy()

    def destroy(self):
        self.ksp.destroy()
        self.A.destroy()


def pocket_load(C: sp.spmatrix, node: int, F: np.ndarray) -> np.ndarray:
    """f = C_l^T F: the 6-vector F (force N, moment N m) at interface node `node` as nodal loads."""
    C = sp.csr_matrix(C)
    return np.asarray(C[6 * node:6 * node + 6].T @ np.asarray(F, dtype=float)).ravel()


def full_frf(K: sp.spmatrix, M: sp.spmatrix, loads: np.ndarray, omegas, observe: np.ndarray,
             beta: float = 0.0, rigid: np.ndarray | None = None, progress=None) -> np.ndarray:
    """Direct frequency response (1) of the full FE model.

    loads (n, nl) load vectors; omegas (nw,) rad/s (>= 0; 0 only with `rigid`); observe (no, n)
    dense observation rows (e.g. the interface functional C_l); beta (s) stiffness-proportional
    damping; rigid (n, 6) mass-normalised rigid modes: if given, the elastic response (4) is
    observed. Returns (nw, no, nl) complex."""
    require_range("frequency_response.beta", beta, 0.0, 1.0, unit="s")
    K, M = sp.csr_matrix(K), sp.csr_matrix(M)
    loads = np.asarray(loads, dtype=float).reshape(K.shape[0], -1)
    observe = np.atleast_2d(observe)
    if rigid is not None:                              # observe (I - R R^T M) u
        observe = observe - (observe @ rigid) @ (M @ rigid).T
    omegas = np.asarray(omegas, dtype=float)
    out = np.zeros((len(omegas), observe.shape[0], loads.shape[1]), dtype=complex)
    for i, w in enumerate(omegas):
        if w == 0.0:
            if rigid is None:
                raise ValueError("frequency_response.omega = 0 needs the rigid modes (free–free K)")
            from flexbearing.fem_cage.craig_bampton import SaddleSolver
            s = SaddleSolver(K, sp.csr_matrix((M @ rigid).T))   # inertia relief, R^T M u = 0
            for j in range(loads.shape[1]):
                out[i, :, j] = observe @ s.solve(loads[:, j], None)[0]
            s.destroy()
        elif beta == 0.0:
            lu = _LU(K - w * w * M)
            for j in range(loads.shape[1]):
                out[i, :, j] = observe @ lu.solve(loads[:, j])
            lu.destroy()
        else:
            A, B = K - w * w * M, (w * beta) * K
            lu = _LU(sp.bmat([[A, -B], [B, A]], format="csr"))
            n = K.shape[0]
            for j in range(loads.shape[1]):
                x = lu.solve(np.r_[loads[:, j], np.zeros(n)])
                out[i, :, j] = observe @ (x[:n] + 1j * x[n:])
            lu.destroy()
        if progress is not None:
            progress.update(1)
    return out


def modal_frf(load_modes: np.ndarray, observe_modes: np.ndarray, omega: np.ndarray, omegas,
              loads: np.ndarray, n_keep: int | None = None, residual: bool = True,
              beta: float = 0.0, elastic: bool = True, n_rigid: int = 6) -> np.ndarray:
    """Reduced-cage frequency response (2)–(3).

    load_modes (6, M): the modes at the loaded interface node (Phi_l); observe_modes (no, M);
    omega (M,) ascending, the first n_rigid zero; loads (6, nl) pocket force/moment columns;
    n_keep: modes kept dynamic (rigid included; None = all); residual: add (3) for the others;
    elastic: leave the rigid modes out (response (4)). Returns (nw, no, nl) complex."""
    omega = np.asarray(omega, dtype=float)
    m = len(omega)
    n_keep = m if n_keep is None else int(n_keep)
    require_range("frequency_response.n_keep", n_keep, n_rigid, m)
    g = np.asarray(load_modes).T @ np.asarray(loads, dtype=float).reshape(6, -1)    # (M, nl)
    w2k = omega ** 2
    omegas = np.asarray(omegas, dtype=float)
    out = np.zeros((len(omegas), np.shape(observe_modes)[0], g.shape[1]), dtype=complex)
    first = n_rigid if elastic else 0
    for i, w in enumerate(omegas):
        h = np.zeros(m, dtype=complex)
        k = np.arange(first, n_keep)
        den = w2k[k] - w * w + 1j * w * beta * w2k[k]
        if w == 0.0 and not elastic:
            raise ValueError("frequency_response.omega = 0 with the rigid modes: infinite response")
        h[k] = 1.0 / den
        if residual and n_keep < m:
            h[n_keep:] = 1.0 / w2k[n_keep:]
        out[i] = observe_modes @ (h[:, None] * g)
    return out


def frequency_grid(f_max_hz: float, natural_hz, n: int = 60, exclude: float = 0.02,
                   include_zero: bool = True) -> np.ndarray:
    """n equally spaced frequencies (Hz) in [0, f_max] (0 itself if include_zero), without those
    within +-exclude (relative) of any of natural_hz (elastic natural frequencies of both
    models: full FE and reduced)."""
    require_range("frequency_response.exclude", exclude, 0.0, 0.5)
    f = np.linspace(0.0, f_max_hz, n + 1)[0 if include_zero else 1:]
    nat = np.asarray([x for x in np.ravel(natural_hz) if x > 0])
    if nat.size:
        keep = np.all(np.abs(f[:, None] / nat[None, :] - 1.0) > exclude, axis=1)
        f = f[keep]
    return f


def relative_error(reduced: np.ndarray, full: np.ndarray, rows=slice(0, 3),
                   floor: np.ndarray | None = None) -> np.ndarray:
    """|u_red - u_full| / max(|u_full|, floor) per frequency and load case over the observation
    rows `rows` (default the three translations of the interface node), complex vector 2-norms:
    (nw, nl). floor (nl,): e.g. the static response amplitude |u_full(0)| — near an
    antiresonance of the driving-point response |u_full| -> 0 and the plain relative error says
    nothing about the model; floor=None gives the plain relative error."""
    d = np.linalg.norm(reduced[:, rows] - full[:, rows], axis=1)
    den = np.linalg.norm(full[:, rows], axis=1)
    if floor is not None:
        den = np.maximum(den, np.asarray(floor)[None, :])
    return d / np.maximum(den, 1e-300)


def pocket_directions(x_node: np.ndarray) -> np.ndarray:
    """(6, 3) unit pocket forces at an interface node at x_node: columns circumferential, radial,
    axial (the ball's drive, a radial push and the axial friction component)."""
    th = np.arctan2(x_node[2], x_node[1])
    F = np.zeros((6, 3))
    F[:3, 0] = [0.0, -np.sin(th), np.cos(th)]
    F[:3, 1] = [0.0, np.cos(th), np.sin(th)]
    F[:3, 2] = [1.0, 0.0, 0.0]
    return F


def compare(red: dict, load_node: int = 1, n_keep: int = DEFAULT_N_KEEP, n_elastic: int = 10,
            n_freq: int = 60, exclude: float = 0.02, beta: float = 0.0, full_hz=None,
            progress=None, at_resonances: bool = False) -> dict:
    """Full FE (1) vs reduced cage (2)–(3) at interface node load_node of an in-memory reduction
    (flexbearing.fem_cage.reduction.reduce_model), unit circumferential, radial and axial pocket forces.

    Grid: frequency_grid up to the n_elastic-th elastic natural frequency of the full model
    (full_hz: its elastic frequencies, Hz, at least n_elastic; computed when None), +-exclude
    around every elastic natural frequency of both models below it removed. Errors (relative_error
    of the interface node's translations, elastic response (4)): (a) n_keep modes without the
    residual correction, (b) with it, (c) the whole basis dynamic (the CB basis' own floor);
    each also with the static amplitude as the floor of the denominator (antiresonances);
    plus (b) for the total response (rigid modes included, w > 0).

    at_resonances: add the full model's elastic natural frequencies (<= f_max) to the grid — with
    damping (beta > 0, exclude = 0) the response peaks there and the frequency error of the
    reduced model costs most: relative error ~ (delta omega_k / omega_k) / zeta_k at the peak,
    zeta_k = beta·omega_k / 2."""
    from flexbearing.fem_cage.craig_bampton import scipy_to_petsc
    omega = red["omega"]
    if full_hz is None:
        from flexbearing.fem_cage.modes import free_free_modes
        f_all, _ = free_free_modes(scipy_to_petsc(red["Kz"]), scipy_to_petsc(red["Mz"]),
                                   6 + n_elastic + 2)
        full_hz = np.asarray(f_all[6:])
    full_hz = np.asarray(full_hz)[:n_elastic + 2]
    red_hz = red["frequency_hz"][6:6 + n_elastic + 2]
    f_max = full_hz[n_elastic - 1]
    freqs = frequency_grid(f_max, np.r_[full_hz, red_hz], n_freq, exclude)
    if at_resonances:
        freqs = np.unique(np.r_[freqs, full_hz[full_hz <= f_max * (1 + 1e-12)]])
    w = 2 * np.pi * freqs
    Fd = pocket_directions(red["interface_positions"][load_node])
    C = sp.csr_matrix(red["C"])
    K, M = (red["Kz"], red["Mz"])                       # rbe2: the coupled model's DOFs z
    loads = np.column_stack([pocket_load(C, load_node, Fd[:, j]) for j in range(Fd.shape[1])])
    obs = C[6 * load_node:6 * load_node + 6].toarray()
    R = red["Bz"][:, :6]
    full_el = full_frf(K, M, loads, w, obs, beta, rigid=R, progress=progress)
    phi_l = red["phi_b"][6 * load_node:6 * load_node + 6]
    out = {"load_node": int(load_node), "n_keep": int(n_keep), "beta_s": beta,
           "exclude_rel": exclude, "n_elastic": n_elastic, "f_max_hz": float(f_max),
           "full_elastic_hz": full_hz[:n_elastic].tolist(),
           "reduced_elastic_hz": red_hz[:n_elastic].tolist(), "grid_hz": freqs.tolist(),
           "load_directions": ["circumferential", "radial", "axial"], "n_modes": int(len(omega)),
           "response": "elastic (mean-axis) translations of the loaded interface node"}
    cases = {"a_truncated": dict(n_keep=n_keep, residual=False),
             "b_truncated_residual": dict(n_keep=n_keep, residual=True),
             "c_full_basis": dict(n_keep=None, residual=False)}
    static = np.linalg.norm(full_el[0, :3], axis=0) if freqs[0] == 0.0 else None
    for label, kw in cases.items():
        r = modal_frf(phi_l, phi_l, omega, w, Fd, beta=beta, elastic=True, **kw)
        e = relative_error(r, full_el)
        out[f"max_rel_error_{label}"] = float(e.max())
        out[f"rel_error_{label}"] = e.tolist()
        i, j = np.unravel_index(np.argmax(e), e.shape)
        out[f"worst_{label}"] = {"f_hz": float(freqs[i]), "direction": out["load_directions"][j],
                                 "full_amplitude_over_static": float(
                                     np.linalg.norm(full_el[i, :3, j]) / static[j])
                                 if static is not None else None}
        if static is not None:
            ef = relative_error(r, full_el, floor=static)
            out[f"max_rel_error_static_floor_{label}"] = float(ef.max())
            out[f"rel_error_static_floor_{label}"] = ef.tolist()
    # total response (rigid modes in both), w > 0 only
    pos = w > 0
    full_tot = full_el[pos].copy()
    rig = (obs @ R) @ (R.T @ loads)                   # R R^T f observed: (6, nl)
    full_tot -= rig[None] / (w[pos] ** 2)[:, None, None]
    r = modal_frf(phi_l, phi_l, omega, w[pos], Fd, beta=beta, elastic=False,
                  n_keep=n_keep, residual=True)
    out["max_rel_error_b_total_response"] = float(relative_error(r, full_tot).max())
    out["full_elastic_amplitude_m_per_N"] = np.linalg.norm(full_el[:, :3], axis=1).tolist()
    return out
