"""Free–free natural modes of the cage: K phi = omega^2 M phi (SLEPc, shift-invert).

Generalised symmetric-definite eigenproblem (GHEP). K is singular (6 rigid-body modes at
omega = 0), so the spectral transformation uses a small *negative* shift sigma:
(K - sigma M)^-1 M phi = theta phi, theta = 1/(omega^2 - sigma). K - sigma M is then symmetric
positive definite, factorised once (Cholesky, MUMPS when PETSc has it); the Krylov–Schur
iteration finds the largest theta, i.e. the omega^2 nearest sigma from above — the rigid modes
and the lowest elastic ones. Reference: SLEPc users manual (Roman et al.), ch. 3 "ST".
Frequencies f = sign(omega^2) sqrt(|omega^2|) / (2 pi) in Hz (rigid modes come out as ±tiny).
Eigenvectors are M-normalised: phi^T M phi = 1.
"""
from __future__ import annotations

import contextlib
import time

import numpy as np
from flexbearing.common.progress import Stages
from flexbearing.common.validation import require_range
from flexbearing.common.interrupt import sigint_noted

# Paper Table 8 (Yang, Liu, Deng, Lubricants 2025, 13, 249): free cage, modes 7..27, Hz.
# Modes 1-6 are the rigid-body modes.
PAPER_TABLE8_HZ = dict(zip(range(7, 28), (
    484.77, 484.77, 813.59, 813.59, 1370.3, 1370.3, 2455.6, 2455.6, 2622.8, 2622.8, 4226.1,
    4226.1, 4469.8, 4469.8, 6160.6, 6160.6, 6552.9, 6552.9, 6692.1, 6692.0, 7113.5)))


def _factor_solver() -> str:
    from flexbearing.common.fe_stack import PETSc
    for name in ("mumps", "superlu_dist"):
        if PETSc.Sys.hasExternalPackage(name):
            return name
    return "petsc"


class _Stopped(Exception):
    """Raised inside SLEPc's solve (through the preconditioner's apply) after a Ctrl-C."""


class _InterruptibleFactor:
    """petsc4py PC of type python: the Cholesky (MUMPS) or LU factorisation of the shift-invert
    operator, K - sigma M, applied as PREONLY's preconditioner exactly as the PC it wraps, but
    asking before each application whether Ctrl-C was pressed (`pressed`, a list filled by
    flexbearing.common.interrupt.sigint_noted): SLEPc's solve runs in C and does not see Python's KeyboardInterrupt until it
    returns (130-140 s for 300 modes of the paper cage), while it applies the operator every few
    milliseconds to tenths of a second. The factorisation itself (PCSetUp) is one C call and
    still runs to its end."""

    def __init__(self, solver: str):
        self.solver = solver
        self.inner = None
        self.pressed: list = []

    def setUp(self, pc):
        from petsc4py import PETSc
        A, P = pc.getOperators()
        if self.inner is None:
            self.inner = PETSc.PC().create(pc.getComm())
            self.inner.setType(PETSc.PC.Type.CHOLESKY if self.solver == "mumps" else PETSc.PC.Type.LU)
            self.inner.setFactorSolverType(self.solver)
        self.inner.setOperators(A, P)
        self.inner.setUp()

    def apply(self, pc, x, y):
        if self.pressed:
            raise _Stopped("interrupted (Ctrl-C)")
        self.inner.apply(x, y)

    def destroy(self, pc):
        if self.inner is not None:
            self.inner.destroy()
            self.inner = None


def free_free_modes(K, M, n_modes: int = 27, shift: float | None = None, tol: float = 1e-9,
                    max_it: int = 200, ncv: int | None = None, return_info: bool = False):
    """The n_modes lowest modes of K phi = omega^2 M phi.

    shift: sigma in (rad/s)^2; default -(2 pi * 1 Hz)^2 * (scale), a small negative number
    relative to the elastic spectrum so K - sigma M is positive definite but well conditioned.
    Returns (frequencies_hz ascending, eigenvectors: list of M-normalised PETSc Vecs).
    """
    from flexbearing.common.fe_stack import PETSc
    from flexbearing.common.fe_stack import SLEPc

    if n_modes < 1:
        from flexbearing.common.validation import InputError
        raise InputError(f"modes.n_modes = {n_modes} is outside the allowed range [1, inf)")
    if shift is None:
        shift = -(2 * np.pi * 10.0) ** 2      # -3948 (rad/s)^2: 10 Hz below zero
    eps = SLEPc.EPS().create(K.getComm())
    eps.setOperators(K, M)
    eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
    eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
    # ncv = 2 n + 10: measured on the cage (153k dofs, 27 modes) to converge in one Krylov-Schur
    # pass; ncv = 2 n needed a restart (+60 % time), larger ncv only adds orthogonalisation.
    eps.setDimensions(n_modes, ncv if ncv else 2 * n_modes + 10)
    eps.setTarget(shift)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_REAL)
    eps.setTolerances(tol, max_it)
    st = eps.getST()
    st.setType(SLEPc.ST.Type.SINVERT)
    st.setShift(shift)
    ksp = st.getKSP()
    ksp.setType(PETSc.KSP.Type.PREONLY)
    pc = ksp.getPC()
    solver = _factor_solver()
    # Cholesky of the SPD shifted matrix (PETSc's own Cholesky needs SBAIJ, so LU there), applied
    # through _InterruptibleFactor: a Ctrl-C stops the solve at its next operator application
    pc.setType(PETSc.PC.Type.PYTHON)
    factor = _InterruptibleFactor(solver)
    pc.setPythonContext(factor)
    eps.setFromOptions()
    with sigint_noted() as pressed:
        factor.pressed = pressed
        try:
            eps.solve()
        except (PETSc.Error, _Stopped):       # petsc4py passes the apply's exception on
            if pressed:
                # the solve was left midway (a dense work matrix still borrowed): SLEPc may
                # refuse to free it; the process is about to end, or the caller to go on
                with contextlib.suppress(PETSc.Error):
                    eps.destroy()
                raise KeyboardInterrupt from None
            raise
    if pressed:
        eps.destroy()
        raise KeyboardInterrupt
    nconv = eps.getConverged()
    if nconv < n_modes:
        raise RuntimeError(f"SLEPc converged {nconv} of {n_modes} modes; raise max_it or ncv")
    lam = np.empty(nconv)
    vecs = []
    for i in range(nconv):
        vr = K.createVecRight()
        lam[i] = eps.getEigenpair(i, vr).real
        vecs.append(vr)
    order = np.argsort(lam)[:n_modes]
    freqs = np.sign(lam[order]) * np.sqrt(np.abs(lam[order])) / (2 * np.pi)
    out = []
    Mv = M.createVecLeft()
    for i in order:
        v = vecs[i]
        M.mult(v, Mv)
        v.scale(1.0 / np.sqrt(v.dot(Mv)))
        out.append(v)
    info = {"solver": solver, "shift": shift, "iterations": eps.getIterationNumber(), "nconv": nconv}
    for i in set(range(nconv)) - set(order.tolist()):
        vecs[i].destroy()
    Mv.destroy()
    # Free the factorisation now: petsc4py objects in reference cycles otherwise live until
    # the cyclic GC runs, and repeated solves (calibration, mesh study) pile up gigabytes.
    eps.destroy()
    if return_info:
        return freqs, out, info
    return freqs, out


def cage_modes(mesh_path, material, degree: int = 2, n_modes: int = 27, comm=None, **kw):
    """Load the mesh, assemble K and M, solve: (frequencies_hz, vecs, V, domain, names, info)."""
    from mpi4py import MPI
    from .elasticity import load_cage_mesh, assemble_stiffness_mass
    comm = comm or MPI.COMM_WORLD
    domain, _, facet_tags, names = load_cage_mesh(mesh_path, comm)
    V, K, M = assemble_stiffness_mass(domain, material, degree)
    freqs, vecs, info = free_free_modes(K, M, n_modes, return_info=True, **kw)
    info["facet_tags"] = facet_tags
    return freqs, vecs, V, domain, names, info


# The parts of run_modes with their wall times on the paper cage (s; P3, 4 mm mesh, 160,572 dofs;
# `flexbearing modes` on 2 cores shared with other jobs, 2 min 26 s in all): the progress bar's
# estimate (flexbearing.common.progress)
MODES_STAGES = {"read mesh": 11.0, "K and M": 34.0, "eigensolve (SLEPc)": 95.0, "classify": 3.0}

# modes a free-free analysis computes at most: Table 8 needs 27, the reduced cage's basis 160; the
# shift-invert Lanczos time grows with the count, and SLEPc's solve does not answer Ctrl-C until it
# returns (100,000 modes took minutes before it could be stopped)
MAX_N_MODES = 300


def run_modes(g, mesh_path, degree: int, n_modes: int, classify: bool = True, quiet: bool = True):
    """The free-free modal analysis of cage geometry `g` on a mesh file: assemble, solve, classify
    the mode families (flexbearing.fem_cage.classify). Returns a result dict (frequencies_hz, ndofs, mass_kg,
    timing_s, eigensolver, and with classify "modes": family, n, label of each) and the solution
    objects (V, vecs) for writing. quiet: no progress bar (rank 0 shows it)."""
    from mpi4py import MPI
    from .elasticity import load_cage_mesh, assemble_stiffness_mass, global_ndofs, total_mass
    require_range("modes.n_modes", n_modes, 7, MAX_N_MODES)       # 6 rigid + at least one elastic
    comm = MPI.COMM_WORLD
    stage = Stages("free-free modes", {k: w for k, w in MODES_STAGES.items() if k != "classify" or classify},
                   quiet or comm.rank != 0)
    t0 = time.perf_counter()
    stage("read mesh")
    domain, _, _, names = load_cage_mesh(mesh_path, comm)
    t1 = time.perf_counter()
    stage("K and M")
    V, K, M = assemble_stiffness_mass(domain, g.material, degree)
    t2 = time.perf_counter()
    stage("eigensolve (SLEPc)")
    freqs, vecs, info = free_free_modes(K, M, n_modes, return_info=True)
    K.destroy()
    M.destroy()
    t3 = time.perf_counter()
    res = {"frequencies_hz": [float(f) for f in freqs], "ndofs": global_ndofs(V),
           "mass_kg": total_mass(domain, g.material),
           "timing_s": {"read_mesh": t1 - t0, "assemble": t2 - t1, "eigensolve": t3 - t2},
           "eigensolver": {k: v for k, v in info.items() if k != "facet_tags"},
           "mpi_ranks": comm.size}
    if classify:
        stage("classify")
        from .classify import classify_modes, short_label
        rigid_tol = 1e-3 * max(abs(freqs[min(6, len(freqs) - 1)]), 1.0)
        cl = classify_modes(V, vecs, freqs, rigid_tol_hz=rigid_tol)
        res["modes"] = [{"mode": i + 1, "frequency_hz": float(f), "family": c["family"], "n": c["n"],
                         "shares": {k: round(x, 4) for k, x in c["shares"].items()},
                         "label": short_label(c)} for i, (f, c) in enumerate(zip(freqs, cl))]
        res["timing_s"]["classify"] = time.perf_counter() - t3
    stage(None)
    return res, V, vecs


def mode_table(freqs, labels=None, paper: bool = True) -> str:
    """The frequencies beside the paper's Table 8 (relative error of modes 7-27, RMS and max);
    paper=False (a cage that is not the paper's): the frequencies and families alone."""
    if not paper:
        lines = [f"{'mode':>4} {'f (Hz)':>10}  family"]
        lines += [f"{i + 1:>4} {f:>10.2f}  {labels[i] if labels else ''}" for i, f in enumerate(freqs)]
        return "\n".join(lines)
    lines = [f"{'mode':>4} {'f (Hz)':>10} {'Table 8 (Hz)':>12} {'rel.err':>8}  family"]
    errs = []
    for i, f in enumerate(freqs):
        m = i + 1
        ref = PAPER_TABLE8_HZ.get(m)
        e = (f - ref) / ref if ref else None
        if e is not None:
            errs.append(e)
        lab = labels[i] if labels else ""
        lines.append(f"{m:>4} {f:>10.2f} {ref if ref else '':>12} "
                     f"{'' if e is None else f'{100 * e:+7.2f}%':>8}  {lab}")
    if errs:
        errs = np.array(errs)
        lines.append(f"modes 7-27: RMS relative error {100 * np.sqrt(np.mean(errs ** 2)):.2f} %, "
                     f"max |error| {100 * np.max(np.abs(errs)):.2f} %")
    return "\n".join(lines)
