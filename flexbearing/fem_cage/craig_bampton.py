"""Craig–Bampton reduction of the free–free cage and its "modified" (orthonormalised) basis.

Interface coordinates are linear functionals of the displacement, u_b = C u (6 per interface
node: RBE2 master DOFs selected after elimination, or RBE3 averages; flexbearing.fem_cage.interface).
The Craig–Bampton basis (Craig & Bampton, AIAA J. 6(7):1313, 1968) is u = Psi u_b + Phi eta
(+ U xi when augmented):

* constraint (static) modes Psi (n x nb): the least-energy displacement for each unit interface
  value, min 1/2 u^T K u subject to C u = e_j:

      [ K  C^T ] [ Psi    ]   [ 0 ]
      [ C   0  ] [ Lambda ] = [ I ]                                               (1)

  (the saddle point also handles a free–free K: C fixes the rigid motions);
* fixed-interface normal modes Phi (n x nf): K phi = omega^2 M phi on {C u = 0}, the largest
  eigenvalues 1/omega^2 of the operator A x = [I 0] S^-1 [M x; 0] with S the saddle matrix of
  (1): by shift-and-invert block Lanczos (flexbearing.fem_cage.block_lanczos) where the BLAS is
  an optimised one, else by SLEPc's Krylov–Schur, one solve per application, then cleaned by a
  Rayleigh–Ritz step on the converged vectors (fixed_interface_modes says why both);
* optional fixed-interface static body-load vectors U (n x nl) (augmentation): the static
  response to a distributed load f with the interface held, min 1/2 u^T K u - u^T f on {C u = 0},

      [ K  C^T ] [ U ]   [ f ]
      [ C   0  ] [ L ] = [ 0 ]                                                      (2)

  (the same saddle factorisation, one more right-hand side per load), then M-orthogonalised
  against Phi and M-orthonormalised. Why: the CB basis [Psi Phi] is statically complete only for
  loads at the interface. The free–free static response to a self-equilibrated body load f is
  u = Psi C u + w with C w = 0 and v^T K w = v^T f for every v with C v = 0 (the Psi part drops
  out: v^T K Psi = -v^T C^T Lambda = 0), i.e. w = U from (2): [Psi U] holds it exactly.
  Used for the centrifugal load of the spinning cage, f_cf = M x_perp (per unit Omega^2, x the
  bearing axis; flexbearing.fem_cage.reduction.centrifugal_load): a thin ring's
  axisymmetric stretching lies far above the 30 fixed-interface modes, and without U the hoop
  stress of the full CB basis is off by tens of percent (measured -33 %...+24 % on a 6-pocket
  test ring; tests/test_cb_centrifugal.py). This is the "modal truncation augmentation" /
  static-correction idea (Dickens, Nakagawa & Wittbrodt, Comput. Struct. 62 (1997) 985) applied
  inside the reduction, so the runtime's residual static correction of discarded modes becomes
  exact for the centrifugal load too.

Reduced matrices, with B = [Psi Phi U]:  K_cb = B^T K B with the constraint block
Psi^T K Psi = -Psi^T C^T Lambda = -(C Psi)^T Lambda = -Lambda, the interface reactions of (1)
(no product with K needed), the Psi–Phi block zero (the coupling
Phi^T K Psi = -Phi^T C^T Lambda vanishes because C Phi = 0) and Phi^T K Phi = Omega^2; the Psi–U
block vanishes for the same reason and the Phi–U block because U is M-orthogonal to the
fixed-interface eigenvectors (Phi^T K U = Omega^2 Phi^T M U = 0); both are computed, not assumed
(info "augmentation_coupling_max"). M_cb = B^T M B (full).

"Modified Craig–Bampton" (ADAMS/Flex, MSC.ADAMS "Theory of Flexible Bodies"; Exudyn's
FEMinterface does the same): solve K_cb N = M_cb N diag(omega^2) on the reduced space, so the
new basis B N is M-orthonormal and K-orthogonal: modal mass I, modal stiffness diag(omega^2),
sorted by frequency. Here the 6 rigid-body modes are built exactly (the CB basis reproduces a
rigid motion with u_b = G (t, omega), eta = 0): translations of the centre of mass along
x, y, z and rotations about the principal axes through it, each mass-normalised; the elastic
modes are the eigenvectors in the M_cb-orthogonal complement, so every elastic mode has zero
linear and angular momentum about the centre of mass (the linearised mean-axis conditions).

Linear algebra: scipy sparse for assembly-level products; PETSc + MUMPS LDL^T (factorised once;
the constraint modes and the body-load vectors as blocks of right-hand sides in one call each)
for the saddle system; block Lanczos or SLEPc for the eigenproblem. Products with M go through
`mass_times` when the caller has a faster one (the vector mass matrix is Ms ⊗ I3: one third of
the work with the scalar Ms; kron_mass_times). Serial only.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from flexbearing.common.blas import blas_info
from .block_lanczos import block_lanczos_modes, constraint_projection


# ------------------------------------------------------------------ PETSc helpers

def petsc_to_scipy(A) -> sp.csr_matrix:
    """Serial PETSc AIJ -> scipy CSR (copy)."""
    indptr, indices, data = A.getValuesCSR()
    return sp.csr_matrix((data.copy(), indices.copy(), indptr.copy()), shape=A.getSize())


def scipy_to_petsc(A):
    from flexbearing.common.fe_stack import PETSc
    A = sp.csr_matrix(A)
    A.sort_indices()
    ity = PETSc.IntType
    M = PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr.astype(ity), A.indices.astype(ity),
                                                   A.data.astype(np.float64)))
    M.assemble()
    return M


def _lu_solver():
    from flexbearing.common.fe_stack import PETSc
    for name in ("mumps", "superlu_dist", "superlu"):
        if PETSc.Sys.hasExternalPackage(name):
            return name
    return "petsc"


def lu_ksp(A, symmetric: bool = False):
    """A direct solver for the PETSc matrix A: KSP PREONLY + LU (MUMPS when available, with
    memory relaxation ICNTL(14) = 80: indefinite systems — saddle points, K − w²M near a
    resonance — need room to pivot). symmetric: A is symmetric (indefinite allowed) and MUMPS is
    there: its LDL^T factorisation (PCCHOLESKY, MUMPS SYM = 2, 2x2 pivots; Amestoy et al., MUMPS
    user guide §5.1) instead of LU — half the factor, so factorising and every solve cost less
    (the paper cage's saddle matrix: 4.1 s and 0.061 s per solve against 6.1 s and 0.098 s;
    benchmarks/results/reduce_design_loop.md). Returns (ksp set up, solver name)."""
    from flexbearing.common.fe_stack import PETSc
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setOperators(A)
    ksp.setType(PETSc.KSP.Type.PREONLY)
    pc = ksp.getPC()
    solver = _lu_solver()
    if symmetric and solver == "mumps":
        A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        pc.setType(PETSc.PC.Type.CHOLESKY)
    else:
        pc.setType(PETSc.PC.Type.LU)
    pc.setFactorSolverType(solver)
    if solver == "mumps":
        pc.setFactorSetUpSolverType()
        pc.getFactorMatrix().setMumpsIcntl(14, 80)
    ksp.setUp()
    return ksp, solver + (" LDL^T" if symmetric and solver == "mumps" else "")


def saddle_matrix(K: sp.spmatrix, C: sp.spmatrix) -> sp.csr_matrix:
    """S = [[K, C^T], [C, 0]] (CSR). K's arrays are reused as the first n rows padded to the full
    width, and the few constraint entries added by one sparse sum: sp.bmat went through COO for
    K's 19 million entries on the paper cage (1.7-3.4 s, against ~0.3 s)."""
    K = sp.csr_matrix(K)
    C = sp.csr_matrix(C)
    n, nc = K.shape[0], C.shape[0]
    N = n + nc
    indptr = np.concatenate([K.indptr, np.full(nc, K.indptr[-1], dtype=K.indptr.dtype)])
    Kp = sp.csr_matrix((K.data, K.indices, indptr), shape=(N, N))
    coupling = sp.bmat([[sp.csr_matrix((n, n)), C.T], [C, sp.csr_matrix((nc, nc))]], format="csr")
    return (Kp + coupling).tocsr()


class SaddleSolver:
    """Factorise S = [[K, C^T], [C, 0]] once (symmetric indefinite: MUMPS LDL^T when available,
    else LU; lu_ksp); solve many RHS."""

    def __init__(self, K: sp.spmatrix, C: sp.spmatrix):
        self.n, self.nc = K.shape[0], C.shape[0]
        self.C = sp.csr_matrix(C)
        S = saddle_matrix(K, C)
        self.S = scipy_to_petsc(S)
        self.ksp, self.solver = lu_ksp(self.S, symmetric=True)
        self._b, self._x = self.S.createVecRight(), self.S.createVecRight()

    def destroy(self):
        """Free the factorisation now (MUMPS holds GBs on the paper cage; don't wait for gc)."""
        self.ksp.destroy()
        self.S.destroy()

    def solve(self, rhs_u: np.ndarray | None, rhs_c: np.ndarray | None):
        """Return (u, lambda) for S [u; lambda] = [rhs_u; rhs_c] (vectors or column blocks).

        A block of right-hand sides goes to the factorisation in one call (MatMatSolve on a dense
        block: MUMPS solves the columns together with level-3 BLAS: 0.037 s per column for 120
        columns against 0.10 s for one at a time on the paper cage, 160,572 dofs;
        benchmarks/results/reduce_design_loop.md)."""
        cols = next(r for r in (rhs_u, rhs_c) if r is not None)
        single = np.ndim(cols) == 1
        k = 1 if single else np.shape(cols)[1]
        if single:
            buf = np.zeros(self.n + self.nc)
            if rhs_u is not None:
                buf[:self.n] = rhs_u
            if rhs_c is not None:
                buf[self.n:] = rhs_c
            self._b.setArray(buf)
            self.ksp.solve(self._b, self._x)
            x = self._x.getArray(readonly=True)
            return x[:self.n].copy(), x[self.n:].copy()
        X = np.empty((self.n + self.nc, k))
        for j0 in range(0, k, self.BLOCK):
            j1 = min(k, j0 + self.BLOCK)
            X[:, j0:j1] = self._block_solve(None if rhs_u is None else rhs_u[:, j0:j1],
                                            None if rhs_c is None else rhs_c[:, j0:j1], j1 - j0)
        return X[:self.n], X[self.n:]

    # columns per MatMatSolve: the dense block (n x BLOCK float64) is 64 MB on the paper cage
    BLOCK = 50

    def _block_solve(self, rhs_u, rhs_c, k):
        from flexbearing.common.fe_stack import PETSc
        N = self.n + self.nc
        Bm = PETSc.Mat().createDense([N, k], comm=PETSc.COMM_SELF)
        Bm.setUp()
        B = Bm.getDenseArray()                   # PETSc's own column-major storage, zeroed
        B[:] = 0.0
        if rhs_u is not None:
            B[:self.n] = rhs_u
        if rhs_c is not None:
            B[self.n:] = rhs_c
        Xm = PETSc.Mat().createDense([N, k], comm=PETSc.COMM_SELF)
        Xm.setUp()
        Bm.assemble()
        Xm.assemble()
        self.ksp.getPC().getFactorMatrix().matSolve(Bm, Xm)
        X = Xm.getDenseArray().copy()
        Bm.destroy()
        Xm.destroy()
        return X


# ------------------------------------------------------------------ Craig–Bampton

def constraint_modes(solver: SaddleSolver):
    """Psi (n x nb) and the interface reactions Lambda (nb x nb) from (1)."""
    return solver.solve(None, np.eye(solver.nc))


def kron_mass_times(Ms: sp.spmatrix):
    """X -> M X for the blocked vector mass matrix M = Ms ⊗ I3 (dof = 3 node + component; the
    mass of rho u·v on a blocked Lagrange space: entry (3i+a, 3j+b) = delta_ab ∫ rho N_i N_j) from
    the scalar Ms alone: (M X)[3i+a, k] = sum_j Ms[i, j] X[3j+a, k], i.e. Ms times X viewed as
    (N, 3k). The same sums as M X without M's structural zeros (a != b): a third of the work."""
    Ms = sp.csr_matrix(Ms)
    N = Ms.shape[0]

    def mass_times(X):
        X = np.ascontiguousarray(X)
        shape = X.shape
        return (Ms @ X.reshape(N, -1)).reshape(shape)
    return mass_times


class _ConstrainedInverse:
    """PETSc shell operator x -> u with [K C^T; C 0][u; l] = [M x; 0] (eigenvalues 1/omega^2)."""

    def __init__(self, solver: SaddleSolver, mass_times):
        self.solver, self.mass_times = solver, mass_times
        self.count = 0

    def mult(self, mat, x, y):
        u, _ = self.solver.solve(self.mass_times(x.getArray(readonly=True)), None)
        y.setArray(u)
        self.count += 1


def fixed_interface_modes(solver: SaddleSolver, K: sp.spmatrix, M: sp.spmatrix, n_fixed: int,
                          tol: float = 1e-10, method: str = "auto", mass_times=None):
    """The n_fixed lowest modes of K phi = omega^2 M phi with C phi = 0.

    method: "block-lanczos" (flexbearing.fem_cage.block_lanczos: blocks of right-hand sides through
    the factorisation, level-3 BLAS), "slepc" (Krylov–Schur, one solve per application, then a
    Rayleigh–Ritz step), or "auto": block Lanczos when the loaded BLAS is an optimised one
    (flexbearing.common.blas), SLEPc with the reference BLAS, on which block Lanczos is the slower
    (paper cage, 30 modes, factorisation apart: OpenBLAS 8.0 s against SLEPc's 14.0 s; reference
    BLAS 21.0 s against 14.3 s; benchmarks/bench_eigensolver.py, results/eigensolver.json). Both converge the same modes (to the tolerances:
    tests/test_block_lanczos.py). tol: SLEPc's relative residual; block Lanczos uses its own
    default (block_lanczos.DEFAULT_TOL, the M-norm residual). mass_times: X -> M X (default M @ X).

    Returns (omega (n_fixed,), Phi (n x n_fixed) M-orthonormal, info dict; info["M_Phi"] = M Phi
    when the method has it).
    """
    if method == "auto":
        method = "block-lanczos" if blas_info().optimised else "slepc"
    if method not in ("block-lanczos", "slepc"):
        raise ValueError(f"reduce.eigensolver = {method!r} is outside the allowed set "
                         "{auto, block-lanczos, slepc}")
    mass_times = mass_times or (lambda X: M @ X)
    if method == "block-lanczos":
        modes = block_lanczos_modes(lambda F: solver.solve(F, None)[0], mass_times, K.shape[0],
                                    n_fixed, project=constraint_projection(solver.C))
        info = {"eigensolver": "block Lanczos", "operator_applications": modes.operator_columns,
                "lanczos_steps": modes.steps, "lanczos_basis": modes.basis_size,
                "nconv": n_fixed, "max_relative_residual": float(modes.residual.max()),
                "M_Phi": modes.M_Phi}
        return modes.omega, modes.Phi, info
    from flexbearing.common.fe_stack import PETSc
    from flexbearing.common.fe_stack import SLEPc
    n = K.shape[0]
    ctx = _ConstrainedInverse(solver, mass_times)
    A = PETSc.Mat().createPython([n, n], ctx, comm=PETSc.COMM_SELF)
    A.setUp()
    eps = SLEPc.EPS().create(PETSc.COMM_SELF)
    eps.setOperators(A)
    eps.setProblemType(SLEPc.EPS.ProblemType.NHEP)
    eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.LARGEST_MAGNITUDE)
    eps.setDimensions(n_fixed, min(n, max(2 * n_fixed, n_fixed + 20)))
    eps.setTolerances(tol, 500)
    eps.getST().setType(SLEPc.ST.Type.SHIFT)
    eps.solve()
    nconv = eps.getConverged()
    if nconv < n_fixed:
        raise RuntimeError(f"SLEPc converged {nconv} of {n_fixed} fixed-interface modes")
    vr, vi = A.createVecRight(), A.createVecRight()
    Vs = np.empty((n, n_fixed))              # SLEPc orders by |1/omega^2|: the lowest omega first
    for i in range(n_fixed):
        eps.getEigenpair(i, vr, vi)
        Vs[:, i] = vr.getArray(readonly=True)
    # Rayleigh–Ritz on the converged subspace: exact M-orthonormality, clean double roots.
    Kr = Vs.T @ (K @ Vs)
    Mr = Vs.T @ mass_times(Vs)
    lam, Y = sla.eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T))
    Phi = Vs @ Y[:, :n_fixed]
    info = {"eigensolver": "SLEPc Krylov-Schur", "slepc_iterations": eps.getIterationNumber(),
            "operator_applications": ctx.count, "nconv": nconv}
    eps.destroy()
    A.destroy()
    return np.sqrt(np.maximum(lam[:n_fixed], 0.0)), Phi, info


def body_load_vectors(solver: SaddleSolver, M: sp.spmatrix, Phi: np.ndarray,
                      body_loads: np.ndarray, mass_times=None) -> np.ndarray:
    """Fixed-interface static responses (2) to the columns of body_loads (n x nl), M-orthogonalised
    against the fixed-interface modes Phi and among themselves, unit modal mass (n x nl).

    Classical Gram–Schmidt in the M inner product, done twice ("twice is enough", Giraud et al.,
    Numer. Math. 101 (2005) 87): U and Phi are nearly parallel in the low modes' directions, and
    one pass leaves M-inner products ~1e-8 there. A load whose response lies in span(Phi) to
    1e-10 of its norm adds nothing and is refused (the reduction would be singular).
    mass_times: X -> M X (default M @ X)."""
    mass_times = mass_times or (lambda X: M @ X)
    U, _ = solver.solve(np.asarray(body_loads, dtype=float).reshape(M.shape[0], -1), None)
    U = U.reshape(M.shape[0], -1)
    out = np.zeros_like(U)
    for j in range(U.shape[1]):
        u = U[:, j].copy()
        norm0 = np.sqrt(u @ mass_times(u))
        for _ in range(2):
            Q = np.hstack([Phi, out[:, :j]])
            u -= Q @ (Q.T @ mass_times(u))
        norm = np.sqrt(u @ mass_times(u))
        if not norm > 1e-10 * norm0:
            raise ValueError(f"craig_bampton.body_loads column {j}: its fixed-interface static "
                             "response lies in the span of the fixed-interface modes")
        out[:, j] = u / norm
    return out


def craig_bampton(K: sp.spmatrix, M: sp.spmatrix, C: sp.spmatrix, n_fixed: int, tol=1e-10,
                  body_loads: np.ndarray | None = None, eigensolver: str = "auto",
                  mass_times=None):
    """Constraint + fixed-interface modes (+ fixed-interface body-load vectors) and the CB
    reduced matrices.

    body_loads: None or (n x nl) distributed loads (e.g. the centrifugal load M x_perp) whose
    fixed-interface static responses (2) augment the basis.
    eigensolver: fixed_interface_modes's method (auto | block-lanczos | slepc). mass_times: X -> M X
    (default M @ X; kron_mass_times for the blocked vector mass).
    Returns dict: Psi (n x nb), Phi (n x nf), U (n x nl), omega_fixed, K_cb, M_cb
    ((nb+nf+nl)^2), info.
    """
    K, M, C = sp.csr_matrix(K), sp.csr_matrix(M), sp.csr_matrix(C)
    mass_times = mass_times or (lambda X: M @ X)
    solver = SaddleSolver(K, C)
    Psi, Lam = constraint_modes(solver)
    if n_fixed > 0:
        omega_f, Phi, info = fixed_interface_modes(solver, K, M, n_fixed, tol, eigensolver,
                                                   mass_times)
    else:
        omega_f, Phi, info = np.zeros(0), np.zeros((K.shape[0], 0)), {}
    M_Phi = info.pop("M_Phi", None)
    if body_loads is not None and np.size(body_loads):
        U = body_load_vectors(solver, M, Phi, body_loads, mass_times)
    else:
        U = np.zeros((K.shape[0], 0))
    nb, nf, nl = C.shape[0], Phi.shape[1], U.shape[1]
    Kbb = -Lam                                      # Psi^T K Psi = -(C Psi)^T Lambda, (1)
    K_cb = np.zeros((nb + nf + nl, nb + nf + nl))
    K_cb[:nb, :nb] = 0.5 * (Kbb + Kbb.T)
    K_cb[nb:nb + nf, nb:nb + nf] = np.diag(omega_f ** 2)
    B = np.hstack([Psi, Phi, U])
    if nl:
        KU = B.T @ (K @ U)                          # (nb+nf+nl, nl): the U rows and columns
        K_cb[:, nb + nf:] = KU
        K_cb[nb + nf:, :] = KU.T
        uu = KU[nb + nf:]
        K_cb[nb + nf:, nb + nf:] = 0.5 * (uu + uu.T)
        scale = max(np.abs(np.diag(uu)).max(), 1e-300)
        info["augmentation_coupling_max"] = float(np.abs(KU[:nb + nf]).max() / scale)
    MB = np.hstack([mass_times(Psi), M_Phi if M_Phi is not None else mass_times(Phi),
                    mass_times(U)])
    M_cb = B.T @ MB
    M_cb = 0.5 * (M_cb + M_cb.T)
    info["lu_solver"] = solver.solver
    solver.destroy()
    # Phi^T K Psi = -(C Phi)^T Lambda by (1): zero when C Phi = 0, which this checks
    info["coupling_block_max"] = float(np.abs((C @ Phi).T @ Lam).max()) if nf else 0.0
    info["n_body_load_vectors"] = int(nl)
    return {"Psi": Psi, "Phi": Phi, "U": U, "omega_fixed": omega_f, "K_cb": K_cb, "M_cb": M_cb,
            "info": info}


# ------------------------------------------------------------------ modified CB

def rigid_mass_properties(M_rigid: np.ndarray):
    """(mass, centre of mass, inertia tensor about the centre of mass) from the 6x6 rigid-body
    mass matrix about the origin, M_R = R^T M R with R the fields t + omega x x:
    M_R = [[m I, -m [c]x], [m [c]x, J_o]], J_c = J_o - m (|c|^2 I - c c^T) (Steiner)."""
    m = M_rigid[0, 0]
    c = -np.array([M_rigid[2, 4], M_rigid[0, 5], M_rigid[1, 3]]) / m   # entries of -m[c]x
    Jo = M_rigid[3:, 3:]
    Jc = Jo - m * (c @ c * np.eye(3) - np.outer(c, c))
    return m, c, 0.5 * (Jc + Jc.T)


def rigid_modes_cb(R: np.ndarray, M_cb: np.ndarray):
    """Mass-normalised rigid modes in CB coordinates (n_cb x 6) from R (n_cb x 6), the CB
    coordinates of the unit rigid motions (t, omega) about the origin: CoM translations x, y, z,
    then rotations about the principal axes through the CoM (ascending principal moment).
    Returns (modes, tw) with tw (6 x 6) the (t, omega) about the origin of each mode."""
    MR = R.T @ M_cb @ R
    m, c, Jc = rigid_mass_properties(MR)
    J, axes = np.linalg.eigh(Jc)
    tw = np.zeros((6, 6))                      # columns: (t, omega) about the origin
    for i in range(3):
        tw[i, i] = 1.0 / np.sqrt(m)
        a = axes[:, i]
        tw[0:3, 3 + i] = -np.cross(a, c) / np.sqrt(J[i])
        tw[3:6, 3 + i] = a / np.sqrt(J[i])
    Nr = R @ tw
    # Loewdin re-orthonormalisation: B R is rigid only to solver precision, so M_R is the exact
    # rigid mass matrix only to ~1e-10; N_r (N_r^T M N_r)^-1/2 keeps the modes' meaning and makes
    # them M-orthonormal to rounding.
    g, U = np.linalg.eigh(Nr.T @ M_cb @ Nr)
    W = U @ np.diag(g ** -0.5) @ U.T
    return Nr @ W, tw @ W


def orthonormalise(K_cb: np.ndarray, M_cb: np.ndarray, G: np.ndarray):
    """Modified CB: N (n_cb x n_cb) with N^T M_cb N = I, N^T K_cb N = diag(omega^2), ascending;
    the first 6 columns are the exact rigid modes (omega = 0). G (nb x 6): interface values of
    the unit rigid motions (flexbearing.fem_cage.interface.rigid_interface_matrix). Returns (N, omega, tw).

    Solved in Jacobi-scaled coordinates (d = diag(M_cb)^-1/2): the CB coordinates mix metres,
    radians and mass-normalised modal amplitudes, and the scaling keeps N^T M_cb N = I to rounding.
    """
    n_cb = K_cb.shape[0]
    d = 1.0 / np.sqrt(np.diag(M_cb))
    Ms = d[:, None] * M_cb * d[None, :]
    Ks = d[:, None] * K_cb * d[None, :]
    R = np.zeros((n_cb, 6))
    R[:G.shape[0]] = G
    Nr, tw = rigid_modes_cb(R / d[:, None], Ms)
    Z = sla.null_space((Ms @ Nr).T)              # M-orthogonal complement of the rigid modes
    Kz = Z.T @ Ks @ Z
    Mz = Z.T @ Ms @ Z
    lam, Y = sla.eigh(0.5 * (Kz + Kz.T), 0.5 * (Mz + Mz.T))
    Ne = Z @ Y
    N = d[:, None] * np.hstack([Nr, Ne])
    omega = np.concatenate([np.zeros(6), np.sqrt(np.maximum(lam, 0.0))])
    return N, omega, tw


# ------------------------------------------------------------------ static checks

def reduced_static_interface(phi_b: np.ndarray, omega: np.ndarray, fixed_node: int,
                             load_node: int, load: np.ndarray) -> np.ndarray:
    """Interface displacements (6Z) of the reduced model under a 6-vector load at load_node with
    interface node fixed_node clamped (all 6 DOFs), modal coordinates q from

        [ diag(omega^2)  Phi_f^T ] [q]   [Phi_l^T F]
        [ Phi_f          0       ] [mu] = [   0    ],   u_b = Phi_b q.
    """
    m = phi_b.shape[1]
    Pf = phi_b[6 * fixed_node:6 * fixed_node + 6]
    Pl = phi_b[6 * load_node:6 * load_node + 6]
    A = np.zeros((m + 6, m + 6))
    A[:m, :m] = np.diag(omega ** 2)
    A[:m, m:] = Pf.T
    A[m:, :m] = Pf
    rhs = np.concatenate([Pl.T @ load, np.zeros(6)])
    q = np.linalg.solve(A, rhs)[:m]
    return phi_b @ q, q


def full_static(K: sp.spmatrix, C: sp.spmatrix, fixed_node: int, loads: list[tuple[int, np.ndarray]]):
    """Full-model static solutions: K u = C_l^T F with C_f u = 0 (interface node fixed_node
    clamped), by the saddle-point LU. Returns list of u (n,)."""
    C = sp.csr_matrix(C)
    Cf = C[6 * fixed_node:6 * fixed_node + 6]
    solver = SaddleSolver(sp.csr_matrix(K), Cf)
    out = []
    for node, F in loads:
        f = C[6 * node:6 * node + 6].T @ F
        u, _ = solver.solve(np.asarray(f).ravel(), None)
        out.append(u)
    solver.destroy()
    return out
