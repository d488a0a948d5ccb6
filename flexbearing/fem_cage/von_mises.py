"""Exact maximum von Mises stress over the cage's mesh nodes (hot loop).

The nodal stress is linear in a coordinate vector: sigma_n = S_n q (S_n: 6 x m, Voigt
xx yy zz yz xz xy; flexbearing.fem_cage.stress_modes). Von Mises (von Mises 1913)

    vm^2 = 1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2) = |L sigma|^2

with L = rows ((e1-e2)/√2, (e2-e3)/√2, (e3-e1)/√2, √3 e4, √3 e5, √3 e6), so vm_n(q) = |A_n q|,
A_n = L S_n, a seminorm of q. Every search below is exact: it returns max_n |A_n q| computed by
the same kernel (`node_vm_sq`) as the brute-force loop over every node, so the value is bitwise
the brute-force value (the node can differ only on an exact tie). They differ in how they prove
that the nodes they do not evaluate cannot beat it.

1. Stateless searches for any vector (`MaxVonMises`, `MaxVonMisesSorted`; used by
   `flexbearing reduce`'s checks). Two bounds hold for every node (Cauchy–Schwarz / triangle):

       vm_n(q) <= ||A_n||_2 |q|                                (global bound, sorted once)
       vm_n(q) <= |A_c q| + sum_b ||(A_n - A_c)[:, b]||_2 |q_b|    (centre c of a leaf or group of
                                                                   similar nodes, mode blocks b)

   MaxVonMises groups nodes into leaves of ~8 with similar stress modes (principal-direction
   bisection of the rows A_n weighted by a typical modal amplitude) and leaves into groups,
   opens the group with the largest bound first and then only what can beat the running maximum.
   Mode blocks: the rigid modes, then elastic blocks of 2, 2, 2, 2, 4, 4, 8, 16, ... (mode_blocks).
   On a valid mesh these centre bounds are loose (the stress of a spinning, pocket-loaded cage is
   close to its maximum at many nodes): ~2 ms per call on the 4 mm paper cage.

2. The run's search along a trajectory (`TrackingMaxVonMises`, called after every accepted
   integrator step by flexbearing.multibody.stress_peak). It works in load space: the run's stress is

       sigma_n = S_n,kept q_kept + S_n,res diag(1/omega^2)(Phi_b,res^T F + Omega^2 Q_cf,res)
               = W_n y,   y = (Omega^2, q_kept, F)                                     (LS)

   (`load_space_stress`: the kept elastic modes are integrated, the discarded ones follow
   quasi-statically, Craig & Kurdila 2006 §14.3; F the load-point loads: 6 per pocket node and the
   guide land's 3), K = 1 + n_kept + 6 P columns. y splits into the tracked part z = (Omega^2,
   q_kept), which carries most of the stress and changes smoothly from step to step, and the
   load part x = F, small (measured on the paper cage: at most 1-4 % of the maximum) but jumping
   at every pocket collision. For node n, with a reference z_r (an earlier step's z) and blocks
   b of the tracked coordinates (Omega^2; mode pairs) and of the loads (force and moment of each
   load point),

       vm_n(y) <= |D_n z_r| + sum_b ||D_n,b||_2 |z_b - z_r,b| + sum_b ||E_n,b||_2 |x_b|    (T)

   (triangle inequality and Cauchy–Schwarz per block; D_n, E_n the tracked and load columns of
   A_n = L W_n). The first term is stored: T_n = |D_n z_r| is evaluated (6 x 21 multiply-adds
   instead of 6 x 147, in float32 from a float32 copy of D) when the node's leaf is refreshed;
   the bound then only costs the block distances. Nodes are grouped spatially (principal-direction
   bisection of the node coordinates) into leaves of at most 48 nodes (~36 on the 4 mm cage) and
   consecutive leaves into groups of 2; a leaf or group bound is (T) with the maxima over its
   nodes: U (max T_n) + P (max ||D_n,b||) . |z - z_r|_b + E (max ||E_n,b||) . |x|_b. Every leaf
   and group keeps its own reference slot r in a ring of the last R = 16 tracked vectors; when a
   slot is overwritten, every item referring to it adds P . |z_new - z_old|_b to its slack (the
   bound stays valid: triangle inequality). Per call:

     a. the threshold `best` starts at the caller's value (the monitor passes the peak of the
        current sample interval: a node that cannot beat it cannot change the recorded maximum)
        raised by the exact value of the seed node (the last new maximum's node: by time
        coherence close to the current maximum);
     b. each group whose bound (T) cannot beat `best` is skipped; an open group bounds its leaves;
        a leaf that can beat `best` with a stale reference is refreshed (T_n at the current z,
        reference = now) and bounded again; nodes of a leaf that still can are evaluated exactly;
     c. the group's bound is rebuilt from its leaves' bounds at the current z (reference = now).

   Why it is fast: between two accepted steps z moves little (the drift term is ~1 % of the
   maximum), so only the leaves whose stored value is within the drift plus the load bound of the
   threshold are refreshed, and only their nodes within the load bound are evaluated exactly.
   Measured on every step of the paper unsteady scene on the 4 mm mesh (18,247 nodes, 512 leaves,
   256 groups; benchmarks/results/von_mises.md): per call ~32 groups opened, ~19 leaves refreshed,
   ~13 exact node evaluations, 25 us (the previous centre-bound search: ~2 ms). It is exact for any
   sequence of vectors, but fast only along a trajectory: independent random vectors refresh
   nearly every leaf they open.

Rounding. The kernel computes s_r = fl(sum_c W_rc y_c) with |fl(s_r) - s_r| <= gamma_K sum_c
|W_rc||y_c| <= gamma_K H, H = sum_c alpha_c |y_c|, alpha_c = max_n,r |W_n,rc|, gamma_K = K u/(1 - K u)
(Higham, "Accuracy and Stability of Numerical Algorithms", 2002, §3.1), so a computed value is
at most (1 + 4u)(b + √6 gamma_K H) for any exact upper bound b. Every skip test therefore
compares (b SAFETY + 2.5 gamma_K H)^2 with best (SAFETY = 1 + 1e-9 covers the relative rounding of
the bound's own sums of non-negative terms and of the stored norms); the stored T_n carry the same
absolute term for the tracked part, plus (nz + 10) 2^-24 sum_c ||D_n,c|| |z_c| for the float32
refresh (D and z rounded to float32, nz products summed, six squares and a square root). A
skipped node cannot beat the computed maximum.

numpy + numba only (no dolfinx): the runtime imports this with the reduced-cage file. The numba
kernels are allocation-free; `tracking_max_sq` takes the tuple `TrackingMaxVonMises.arrays` so it
can be called from another @njit loop; `brute_force_max_sq` is the reference (every node, the same
node kernel). Exactness against brute force: tests/test_von_mises.py (random vectors of several
families, a synthetic trajectory) and tests/test_stress_peak.py (a real run: the recorded maximum
of each sample interval equals the brute-force maximum over every step of that interval).
"""
from __future__ import annotations

import numpy as np
from numba import njit

SQ2, SQ3 = np.sqrt(0.5), np.sqrt(3.0)
L_VM = np.array([[SQ2, -SQ2, 0, 0, 0, 0],
                 [0, SQ2, -SQ2, 0, 0, 0],
                 [-SQ2, 0, SQ2, 0, 0, 0],
                 [0, 0, 0, SQ3, 0, 0],
                 [0, 0, 0, 0, SQ3, 0],
                 [0, 0, 0, 0, 0, SQ3]])
SAFETY = 1.0 + 1e-9


@njit(cache=True)
def node_vm_sq(A, k, q):
    """|A_k q|^2 for row k; A stored transposed, (N, m, 6) C-contiguous, so the six stress
    rows accumulate independently (vectorises without reassociating any sum: the same rounding
    wherever the kernel is inlined)."""
    a0 = a1 = a2 = a3 = a4 = a5 = 0.0
    for j in range(q.shape[0]):
        qj = q[j]
        a0 += A[k, j, 0] * qj
        a1 += A[k, j, 1] * qj
        a2 += A[k, j, 2] * qj
        a3 += A[k, j, 3] * qj
        a4 += A[k, j, 4] * qj
        a5 += A[k, j, 5] * qj
    return a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3 + a4 * a4 + a5 * a5


@njit(cache=True)
def _block_norms(q, block_starts, work):
    """work[b] = ||q over mode block b||; returns SAFETY·||q|| (the factor of the node bounds)."""
    qn = 0.0
    for b in range(block_starts.shape[0] - 1):
        s = 0.0
        for j in range(block_starts[b], block_starts[b + 1]):
            s += q[j] * q[j]
        work[b] = np.sqrt(s)
        qn += s
    return np.sqrt(qn) * SAFETY


@njit(cache=True)
def max_von_mises_sq(A, bound, block_bound, block_starts, q, work):
    """(max_n vm_n(q)^2, n*) over sorted nodes; work: float array of len(block_starts)-1."""
    nb = block_starts.shape[0] - 1
    qn = _block_norms(q, block_starts, work)
    best = -1.0
    arg = -1
    for k in range(A.shape[0]):
        ub = bound[k] * qn
        if ub * ub <= best:
            break
        ubb = 0.0
        for b in range(nb):
            ubb += block_bound[k, b] * work[b]
        ubb *= SAFETY
        if ubb * ubb <= best:
            continue
        v = node_vm_sq(A, k, q)
        if v > best:
            best = v
            arg = k
    return best, arg


@njit(cache=True)
def brute_force_max_sq(A, q):
    """Reference: the same kernel over every node."""
    best = -1.0
    arg = -1
    for k in range(A.shape[0]):
        v = node_vm_sq(A, k, q)
        if v > best:
            best = v
            arg = k
    return best, arg


@njit(cache=True)
def _count_visits(A, bound, block_bound, block_starts, q, work):
    """Diagnostics: (nodes passed the global test, exact evaluations) for one call."""
    nb = block_starts.shape[0] - 1
    qn = _block_norms(q, block_starts, work)
    best = -1.0
    visited = 0
    exact = 0
    for k in range(A.shape[0]):
        ub = bound[k] * qn
        if ub * ub <= best:
            break
        visited += 1
        ubb = 0.0
        for b in range(nb):
            ubb += block_bound[k, b] * work[b]
        if ubb * SAFETY * ubb * SAFETY <= best:
            continue
        exact += 1
        v = node_vm_sq(A, k, q)
        if v > best:
            best = v
    return visited, exact


class MaxVonMisesSorted:
    """Exact max von Mises, variant 1: nodes sorted by the global bound, per-node block bound
    (module docstring). Kept as a second, independent exact kernel; MaxVonMises is faster.
    S (N, 6, m) nodal stress modes (Pa per unit q).

    node_ids: the caller's index of each row of S (default 0..N-1); returned with the maximum.
    n_blocks: mode groups of the block bound (contiguous, as equal as possible).
    """

    def __init__(self, S: np.ndarray, node_ids: np.ndarray | None = None, n_blocks: int | None = None,
                 n_rigid: int = 6):
        S = np.asarray(S, dtype=np.float64)
        if S.ndim != 3 or S.shape[1] != 6:
            raise ValueError(f"stress modes must be (N, 6, m), got {S.shape}")
        n, _, m = S.shape
        A = np.einsum("rs,nsm->nrm", L_VM, S)
        bound = np.linalg.norm(A, ord=2, axis=(1, 2)) if m else np.zeros(n)
        if n_blocks is None:
            starts = mode_blocks(m, n_rigid) if m else np.array([0, 0], dtype=np.int64)
        else:
            starts = np.linspace(0, m, max(1, min(int(n_blocks), m)) + 1).round().astype(np.int64)
        nb = len(starts) - 1
        bb = np.zeros((n, nb))
        for b in range(nb):
            blk = A[:, :, starts[b]:starts[b + 1]]
            if blk.shape[2]:
                bb[:, b] = np.linalg.norm(blk, ord=2, axis=(1, 2))
        order = np.argsort(-bound, kind="stable")
        self.A = np.ascontiguousarray(A[order].transpose(0, 2, 1))
        self.bound = np.ascontiguousarray(bound[order])
        self.block_bound = np.ascontiguousarray(bb[order])
        self.block_starts = starts
        ids = np.arange(n) if node_ids is None else np.asarray(node_ids)
        self.node_ids = ids[order]
        self.work = np.zeros(nb)
        self.n_modes = m

    def __call__(self, q: np.ndarray) -> tuple[float, int]:
        """(max von Mises, Pa; node id where it occurs)."""
        q = np.ascontiguousarray(q, dtype=np.float64)
        v, k = max_von_mises_sq(self.A, self.bound, self.block_bound, self.block_starts, q,
                                self.work)
        return float(np.sqrt(v)), int(self.node_ids[k])

    def brute_force(self, q: np.ndarray) -> tuple[float, int]:
        v, k = brute_force_max_sq(self.A, np.ascontiguousarray(q, dtype=np.float64))
        return float(np.sqrt(v)), int(self.node_ids[k])

    def visits(self, q: np.ndarray) -> tuple[int, int]:
        return _count_visits(self.A, self.bound, self.block_bound, self.block_starts,
                             np.ascontiguousarray(q, dtype=np.float64), self.work)


# ------------------------------------------------------------------ leaf (cluster) bound

@njit(cache=True)
def _dot_row(a, row, b):
    """sum_i a[row, i] b[i] of non-negative terms (any summation order: SAFETY covers it)."""
    s = 0.0
    for i in range(b.shape[0]):
        s += a[row, i] * b[i]
    return s


@njit(cache=True)
def _open_group(A, centres, leaf_start, leaf_radius, node_radius, q, qb, g0, g1, best, arg,
                count):
    """Scan leaves g0..g1-1 (leaf bound, node bound, exact nodes); returns (best, arg)."""
    for c in range(g0, g1):
        v = np.sqrt(node_vm_sq(centres, c, q)) * SAFETY
        count[0] += 1
        b = v + _dot_row(leaf_radius, c, qb)
        if b * b <= best:
            continue
        for k in range(leaf_start[c], leaf_start[c + 1]):
            bn = v + _dot_row(node_radius, k, qb)
            if bn * bn <= best:
                continue
            count[1] += 1
            x = node_vm_sq(A, k, q)
            if x > best:
                best = x
                arg = k
    return best, arg


@njit(cache=True)
def max_von_mises_leaves_sq(A, gcentres, group_start, group_radius, centres, leaf_start,
                            leaf_radius, node_radius, block_starts, q, work, qb, count):
    """(max_n vm_n(q)^2, row n*): groups of leaves of nodes; a group, leaf or node is skipped when
    its bound |A_centre q| + sum_b radius_b |q_b| cannot beat the running maximum.
    work: n_groups floats, qb: n_blocks floats, count: 2 ints (centre evaluations, exact node
    evaluations; diagnostics). Allocation-free."""
    count[0] = 0
    count[1] = 0
    for b in range(block_starts.shape[0] - 1):
        s = 0.0
        for j in range(block_starts[b], block_starts[b + 1]):
            s += q[j] * q[j]
        qb[b] = np.sqrt(s) * SAFETY
    n_groups = gcentres.shape[0]
    top = 0
    topb = -1.0
    for g in range(n_groups):
        b = np.sqrt(node_vm_sq(gcentres, g, q)) * SAFETY + _dot_row(group_radius, g, qb)
        work[g] = b
        if b > topb:
            topb = b
            top = g
    count[0] += n_groups
    best, arg = _open_group(A, centres, leaf_start, leaf_radius, node_radius, q, qb,
                            group_start[top], group_start[top + 1], -1.0, -1, count)
    for g in range(n_groups):
        if g == top or work[g] * work[g] <= best:
            continue
        best, arg = _open_group(A, centres, leaf_start, leaf_radius, node_radius, q, qb,
                                group_start[g], group_start[g + 1], best, arg, count)
    return best, arg


def mode_blocks(m: int, n_rigid: int = 6) -> np.ndarray:
    """Block boundaries over the modes (sorted by frequency): the rigid ones, then elastic blocks
    of 2, 2, 2, 2, 4, 4, 8, 16, 32, ... (low modes carry most of a dynamic response, so they get
    their own blocks and the bound follows where q actually is)."""
    starts = [0]
    if m > n_rigid > 0:
        starts.append(n_rigid)
    sizes = [2, 2, 2, 2, 4, 4]
    k = 0
    while starts[-1] < m:
        size = sizes[k] if k < len(sizes) else 2 ** (k - 3)
        starts.append(min(m, starts[-1] + size))
        k += 1
    return np.array(starts, dtype=np.int64)


def _bisect_leaves(X: np.ndarray, leaf_size: int) -> list[np.ndarray]:
    """Principal-direction bisection of the rows of X (N, d) into leaves of <= leaf_size rows
    (median split along the dominant direction, found by a few power iterations)."""
    out = []
    stack = [np.arange(len(X))]
    rng = np.random.default_rng(0)
    while stack:
        idx = stack.pop()
        if len(idx) <= leaf_size:
            out.append(idx)
            continue
        Y = X[idx] - X[idx].mean(axis=0)
        v = rng.standard_normal(X.shape[1])
        for _ in range(6):
            v = Y.T @ (Y @ v)
            nv = np.linalg.norm(v)
            if nv == 0.0:
                break
            v /= nv
        order = np.argsort(Y @ v, kind="stable")
        half = len(idx) // 2
        stack.append(idx[order[:half]])
        stack.append(idx[order[half:]])
    return out


class MaxVonMises:
    """Exact max von Mises over the nodes of S (N, 6, m) (Pa per unit q) with the two-level leaf
    bound (module docstring): __call__(q) -> (max Pa, node id), brute_force(q), visits(q).
    The arrays (A, gcentres, ...) can be passed to `max_von_mises_leaves_sq` from another
    @njit loop (see __call__ for the argument order).

    mode_scale: typical |q_k| (e.g. 1/omega_k), used only to group nodes whose stress modes agree
    where q usually is; the result is exact for any q whatever the scale.
    """

    def __init__(self, S: np.ndarray, node_ids: np.ndarray | None = None, leaf_size: int = 8,
                 group_leaves: int = 16, mode_scale: np.ndarray | None = None, n_rigid: int = 6):
        S = np.asarray(S, dtype=np.float64)
        if S.ndim != 3 or S.shape[1] != 6:
            raise ValueError(f"stress modes must be (N, 6, m), got {S.shape}")
        n, _, m = S.shape
        A = np.einsum("rs,nsm->nrm", L_VM, S)
        w = np.ones(m) if mode_scale is None else np.asarray(mode_scale, dtype=float)
        # DFS order of the bisection: consecutive leaves form subtrees, so groups of
        # consecutive leaves are compact too.
        leaves = _bisect_leaves((A * w).reshape(n, -1), int(leaf_size))
        order = np.concatenate(leaves)
        starts = np.zeros(len(leaves) + 1, dtype=np.int64)
        starts[1:] = np.cumsum([len(l) for l in leaves])
        A = np.ascontiguousarray(A[order])
        blocks = mode_blocks(m, n_rigid)
        nb = len(blocks) - 1

        def centre_and_radii(rows):
            blk = A[rows]
            c = blk.mean(axis=0)
            D = blk - c
            r = np.zeros((len(blk), nb))
            for b in range(nb):
                Db = D[:, :, blocks[b]:blocks[b + 1]]
                if Db.shape[2]:
                    r[:, b] = np.linalg.norm(Db, ord=2, axis=(1, 2))
            return c, r

        n_leaves = len(leaves)
        centres = np.empty((n_leaves, 6, m))
        node_r = np.zeros((n, nb))
        leaf_r = np.zeros((n_leaves, nb))
        for c in range(n_leaves):
            centres[c], r = centre_and_radii(slice(starts[c], starts[c + 1]))
            node_r[starts[c]:starts[c + 1]] = r
            leaf_r[c] = r.max(axis=0)
        gstart = np.unique(np.r_[np.arange(0, n_leaves, int(group_leaves)), n_leaves]).astype(np.int64)
        ng = len(gstart) - 1
        gcentres = np.empty((ng, 6, m))
        group_r = np.zeros((ng, nb))
        for g in range(ng):
            gcentres[g], r = centre_and_radii(slice(starts[gstart[g]], starts[gstart[g + 1]]))
            group_r[g] = r.max(axis=0)
        self.A = np.ascontiguousarray(A.transpose(0, 2, 1))
        self.centres = np.ascontiguousarray(centres.transpose(0, 2, 1))
        self.gcentres = np.ascontiguousarray(gcentres.transpose(0, 2, 1))
        self.leaf_start, self.group_start, self.block_starts = starts, gstart, blocks
        self.leaf_radius, self.node_radius, self.group_radius = leaf_r, node_r, group_r
        ids = np.arange(n) if node_ids is None else np.asarray(node_ids)
        self.node_ids = ids[order]
        self.work = np.zeros(ng)
        self.qb = np.zeros(nb)
        self.count = np.zeros(2, dtype=np.int64)
        self.n_modes = m

    def _call(self, q):
        return max_von_mises_leaves_sq(self.A, self.gcentres, self.group_start, self.group_radius,
                                       self.centres, self.leaf_start, self.leaf_radius,
                                       self.node_radius, self.block_starts,
                                       np.ascontiguousarray(q, dtype=np.float64), self.work,
                                       self.qb, self.count)

    def __call__(self, q: np.ndarray) -> tuple[float, int]:
        v, k = self._call(q)
        return float(np.sqrt(v)), int(self.node_ids[k])

    def brute_force(self, q: np.ndarray) -> tuple[float, int]:
        v, k = brute_force_max_sq(self.A, np.ascontiguousarray(q, dtype=np.float64))
        return float(np.sqrt(v)), int(self.node_ids[k])

    def visits(self, q: np.ndarray) -> tuple[int, int]:
        """(centre evaluations, exact node evaluations) of one call."""
        self._call(q)
        return int(self.count[0]), int(self.count[1])


# ------------------------------------------------------------------ the run's tracking search

U_ROUND = np.finfo(np.float64).eps / 2.0        # unit roundoff u
_F32 = 2.0 ** -24 * SAFETY                      # relative rounding of a float32 copy


def load_space_stress(S: np.ndarray, omega: np.ndarray, load_modes: np.ndarray,
                      q_cf: np.ndarray, n_keep: int, n_rigid: int = 6) -> np.ndarray:
    """W (N, 6, K) Pa per unit y of the load-space form (LS) of the module docstring,

        y = (Omega^2, q_n_rigid .. q_n_keep-1, F_0,0 .. F_P-1,5),   K = 1 + (n_keep - n_rigid) + 6 P

        W_n = [S_n,res c,  S_n,kept,  S_n,res diag(1/omega_res^2) Phi_b,res^T]
        c = diag(1/omega_res^2) Q_cf,res

    S (N, 6, M) stress modes of the full basis, omega (M,), load_modes (P, 6, M) the modal loads of
    the P load points per unit load component (flexbearing.coupling.flexible_cage.load_point_modes), q_cf (M,)
    the centrifugal modal load per unit Omega^2, n_keep (rigid included) the first residual mode.
    Same residual coordinates as flexbearing.fem_cage.reduced_cage.static_correction."""
    S = np.asarray(S, dtype=np.float64)
    omega = np.asarray(omega, dtype=np.float64)
    P, _, M = load_modes.shape
    w2 = omega[n_keep:] ** 2
    inv = np.where(w2 > 0, 1.0 / np.where(w2 > 0, w2, 1.0), 0.0)
    R = np.concatenate([np.asarray(q_cf, dtype=np.float64)[None, n_keep:],
                        np.asarray(load_modes, dtype=np.float64).reshape(P * 6, M)[:, n_keep:]]).T
    R = R * inv[:, None]                                   # (M - n_keep, 1 + 6P)
    res = S[:, :, n_keep:] @ R                             # (N, 6, 1 + 6P)
    return np.concatenate([res[:, :, :1], S[:, :, n_rigid:n_keep], res[:, :, 1:]], axis=2)


def load_space_blocks(n_elastic: int, n_load_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Block boundaries of y = (Omega^2, q_kept, F) for TrackingMaxVonMises: tracked blocks
    [Omega^2], then the kept elastic modes in pairs (a ring's modes come in pairs of equal
    frequency); load blocks: the force and the moment of each load point."""
    tracked = np.r_[0, 1 + np.arange(0, n_elastic, 2), 1 + n_elastic].astype(np.int64)
    loads = (1 + n_elastic + 3 * np.arange(2 * n_load_points + 1)).astype(np.int64)
    return np.unique(tracked), loads


def _block_spectral_norms(W: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """(N, n_blocks) ||W_n[:, b]||_2 of each column block (W: (N, K, 6), rows = columns of W_n);
    the largest eigenvalue of the block's Gram matrix (<= 3 x 3 here)."""
    out = np.zeros((W.shape[0], len(starts) - 1))
    for b in range(len(starts) - 1):
        blk = W[:, starts[b]:starts[b + 1], :]
        if blk.shape[1] == 0:
            continue
        gram = np.einsum("nir,njr->nij", blk, blk)
        out[:, b] = np.sqrt(np.maximum(np.linalg.eigvalsh(gram)[:, -1], 0.0))
    return out


@njit(cache=True)
def _dot_abs(a, row, y):
    s = 0.0
    for i in range(a.shape[1]):
        s += a[row, i] * abs(y[i])
    return s


@njit(cache=True)
def _axpy(acc, row, a):
    """acc += a row (its own function: LLVM vectorises it here, not inside the loop nest)."""
    for k in range(acc.shape[0]):
        acc[k] += row[k] * a


@njit(cache=True)
def _add_squares(acc, row):
    for k in range(acc.shape[0]):
        acc[k] += row[k] * row[k]


@njit(cache=True)
def _refresh_leaf(Dz, leaf, z32, T, n0, n1, acc, sq):
    """T[n0:n1] = |D_n z| of the leaf's nodes in float32 (Dz, z32 float32 copies; the caller adds
    the rounding slack); Dz[leaf] is (nz, 6 L) with row r of node i at r L + i, so the six stress
    rows of all L nodes accumulate in one contiguous (vectorised) loop. Returns max T."""
    L = Dz.shape[2] // 6
    acc[:] = 0.0
    for j in range(Dz.shape[1]):
        _axpy(acc, Dz[leaf, j], z32[j])
    sq[:] = 0.0
    for r in range(6):
        _add_squares(sq, acc[r * L:(r + 1) * L])
    u = 0.0
    for i in range(n1 - n0):
        t = np.sqrt(np.float64(sq[i]))
        T[n0 + i] = t
        if t > u:
            u = t
    return u


@njit(cache=True)
def _slot_distances(y, ring, n_used, zstart, dz):
    """dz[r, b] = SAFETY |z_b - ring[r]_b| for every used slot r and tracked block b."""
    for r in range(n_used):
        for b in range(zstart.shape[0] - 1):
            s = 0.0
            for j in range(zstart[b], zstart[b + 1]):
                d = y[j] - ring[r, j]
                s += d * d
            dz[r, b] = np.sqrt(s) * SAFETY


@njit(cache=True)
def tracking_max_sq(arrays, y, best_in, seed):
    """(best, row): the exact max_n vm_n(y)^2 and its row if it exceeds best_in, else
    (best_in, -1). Tracking search of the module docstring, allocation-free; `arrays` =
    TrackingMaxVonMises.arrays (its state arrays are updated: references, stored bounds,
    diagnostics count = [groups opened, leaves refreshed, leaves scanned, exact evaluations]).
    seed: rows evaluated exactly first (negative = none)."""
    (W, Dz, Cl, zstart, xstart, Pn, Pl, Pg, El, EgT, gstart, lstart, alpha, T, Ul, Sl, lref, Ug,
     Sg, gref, ring, ring_info, dz, xbn, eg, z32, acc, sq, count) = arrays
    K = y.shape[0]
    nz = zstart[zstart.shape[0] - 1]
    nbz = zstart.shape[0] - 1
    nbx = xstart.shape[0] - 1
    R = ring.shape[0]
    G = gstart.shape[0] - 1
    for i in range(4):
        count[i] = 0
    gam = K * U_ROUND / (1.0 - K * U_ROUND)
    h = 0.0
    for c in range(K):
        h += alpha[c] * abs(y[c])
    eta = 2.5 * gam * h                   # rounding of any value computed at this y
    hz = 0.0
    for c in range(nz):
        hz += alpha[c] * abs(y[c])
    eta_z = 2.5 * gam * hz                # ... of a stored T_n
    for j in range(nz):
        z32[j] = y[j]                     # the leaf refresh works in float32
    # distances to the reference slots; every group's load bound E_g . |x|_b (vectorised over
    # the groups)
    nused = ring_info[1]
    _slot_distances(y, ring, nused, zstart, dz)
    for b in range(nbx):
        s = 0.0
        for j in range(xstart[b], xstart[b + 1]):
            s += y[j] * y[j]
        xbn[b] = np.sqrt(s) * SAFETY
    eg[:] = 0.0
    for b in range(nbx):
        _axpy(eg, EgT[b], xbn[b])
    best = best_in
    arg = -1
    for i in range(seed.shape[0]):
        k = seed[i]
        if k >= 0:
            count[3] += 1
            v = node_vm_sq(W, k, y)
            if v > best:
                best = v
                arg = k
    cur = -1                              # ring slot of the current z (taken on first need)
    for g in range(G):
        rg = gref[g]
        if rg >= 0:
            d = 0.0
            for b in range(nbz):
                d += Pg[g, b] * dz[rg, b]
            ub = (Ug[g] + Sg[g] + d + eg[g]) * SAFETY + eta
            if ub * ub <= best:
                continue
        count[0] += 1
        if cur < 0:
            cur = ring_info[0]
            if cur < nused:
                # overwrite the oldest slot: whatever refers to it keeps a valid bound with the
                # slack P . |z_now - z_old|_b (dz[cur]: that distance)
                for h2 in range(G):
                    if gref[h2] == cur:
                        for b in range(nbz):
                            Sg[h2] += Pg[h2, b] * dz[cur, b]
                for l2 in range(Ul.shape[0]):
                    if lref[l2] == cur:
                        Sl[l2] += _dot_row(Pl, l2, dz[cur])
            else:
                nused = cur + 1
                ring_info[1] = nused
            for j in range(nz):
                ring[cur, j] = y[j]
            dz[cur, :] = 0.0
            ring_info[0] = (cur + 1) % R
        ug = 0.0
        for leaf in range(gstart[g], gstart[g + 1]):
            rl = lref[leaf]
            el = _dot_row(El, leaf, xbn)
            if rl >= 0:
                drift = _dot_row(Pl, leaf, dz[rl])
                ul = Ul[leaf] + Sl[leaf] + drift
                ub = (ul + el) * SAFETY + eta
            else:
                drift = np.inf
                ul = np.inf
                ub = np.inf
            if ub * ub > best and drift > 0.0:
                count[1] += 1
                Ul[leaf] = _refresh_leaf(Dz, leaf, z32, T, lstart[leaf], lstart[leaf + 1], acc,
                                         sq)
                # float32: D and z rounded (2^-24 each), nz products summed, six squares, a
                # square root: |T - |D z|| <= (nz + 10) 2^-24 sum_c ||D[:, c]|| |z_c|
                Sl[leaf] = eta_z + (nz + 10) * _F32 * _dot_abs(Cl, leaf, y)
                lref[leaf] = cur
                rl = cur
                drift = 0.0
                ul = Ul[leaf] + Sl[leaf]
                ub = (ul + el) * SAFETY + eta
            if ul > ug:
                ug = ul
            if ub * ub <= best:
                continue
            count[2] += 1
            for n in range(lstart[leaf], lstart[leaf + 1]):
                dn = 0.0
                if drift > 0.0:
                    dn = _dot_row(Pn, n, dz[rl])
                ub = (T[n] + Sl[leaf] + dn + el) * SAFETY + eta
                if ub * ub <= best:
                    continue
                count[3] += 1
                v = node_vm_sq(W, n, y)
                if v > best:
                    best = v
                    arg = n
        Ug[g] = ug
        Sg[g] = 0.0
        gref[g] = cur
    return best, arg


def empty_tracking_arrays() -> tuple:
    """A tuple with the types of TrackingMaxVonMises.arrays and no node (for a disabled caller:
    the compiled loop keeps one signature)."""
    f1, f2, i1 = np.zeros(1), np.zeros((1, 1)), np.zeros(2, dtype=np.int64)
    f32 = np.zeros(1, dtype=np.float32)
    return (np.zeros((1, 1, 6)), np.zeros((1, 1, 6), dtype=np.float32), f2, i1, i1, f2, f2, f2,
            f2, f2, i1, i1, f1, f1, f1, f1, -np.ones(1, dtype=np.int64), f1, f1,
            -np.ones(1, dtype=np.int64), f2, np.zeros(2, dtype=np.int64), f2, f1, f1, f32,
            f32, f32, np.zeros(4, dtype=np.int64))


class TrackingMaxVonMises:
    """Exact max von Mises along a trajectory of load-space vectors y (module docstring, 2).

    W (N, 6, K) nodal stress (Voigt) per unit y (load_space_stress); n_tracked: the first n_tracked coordinates are
    tracked (z), the rest are loads (x); tracked_blocks, load_blocks: block boundaries within
    [0, n_tracked] and [n_tracked, K]; coords (N, 3) node positions for the spatial leaves
    (None: principal-direction bisection of the tracked rows of W); node_ids: the caller's index
    of each row (default 0..N-1). __call__(y, best_in) -> (max Pa, node id) or (None, -1) when no
    node beats best_in (Pa); brute_force(y); `arrays` for the compiled kernel tracking_max_sq.
    """

    def __init__(self, W: np.ndarray, n_tracked: int, tracked_blocks: np.ndarray,
                 load_blocks: np.ndarray, coords: np.ndarray | None = None,
                 node_ids: np.ndarray | None = None, leaf_size: int = 48, group_leaves: int = 2,
                 ring: int = 16):
        W = np.asarray(W, dtype=np.float64)
        if W.ndim != 3 or W.shape[1] != 6:
            raise ValueError(f"load-space stress must be (N, 6, K), got {W.shape}")
        n, _, K = W.shape
        zstart = np.asarray(tracked_blocks, dtype=np.int64)
        xstart = np.asarray(load_blocks, dtype=np.int64)
        if zstart[0] != 0 or zstart[-1] != n_tracked or xstart[0] != n_tracked or xstart[-1] != K:
            raise ValueError(f"blocks must cover [0, {n_tracked}] and [{n_tracked}, {K}]: "
                             f"{zstart.tolist()}, {xstart.tolist()}")
        Wt = np.ascontiguousarray(np.einsum("rs,nsk->nkr", L_VM, W))   # rows (L W_n)^T: (N, K, 6)
        X = (np.asarray(coords, dtype=np.float64) if coords is not None
             else Wt[:, :n_tracked].reshape(n, -1))
        leaves = _bisect_leaves(X, int(leaf_size))
        order = np.concatenate(leaves)
        ls = np.zeros(len(leaves) + 1, dtype=np.int64)
        ls[1:] = np.cumsum([len(l) for l in leaves])
        NL = len(leaves)
        gs = np.unique(np.r_[np.arange(0, NL, int(group_leaves)), NL]).astype(np.int64)
        Wt = np.ascontiguousarray(Wt[order])
        Pn = _block_spectral_norms(Wt, zstart)
        En = _block_spectral_norms(Wt, xstart)
        Pl = np.array([Pn[a:b].max(axis=0) for a, b in zip(ls[:-1], ls[1:])])
        El = np.array([En[a:b].max(axis=0) for a, b in zip(ls[:-1], ls[1:])])
        Pg = np.array([Pl[a:b].max(axis=0) for a, b in zip(gs[:-1], gs[1:])])
        Eg = np.array([El[a:b].max(axis=0) for a, b in zip(gs[:-1], gs[1:])])
        Lmax = int(np.diff(ls).max())
        Dz = np.zeros((NL, n_tracked, 6, Lmax), dtype=np.float32)
        coln = np.linalg.norm(Wt[:, :n_tracked, :], axis=2)              # (N, nz) ||D_n[:, c]||
        Cl = np.array([coln[a:b].max(axis=0) for a, b in zip(ls[:-1], ls[1:])]) * SAFETY
        for leaf in range(NL):
            blk = Wt[ls[leaf]:ls[leaf + 1], :n_tracked, :]
            Dz[leaf, :, :, :blk.shape[0]] = blk.transpose(1, 2, 0)
        G = len(gs) - 1
        nbz = len(zstart) - 1
        R = int(ring)
        self.arrays = (Wt, np.ascontiguousarray(Dz.reshape(NL, n_tracked, 6 * Lmax)), Cl, zstart,
                       xstart, Pn, Pl, Pg, El, np.ascontiguousarray(Eg.T),
                       gs, ls, np.abs(Wt).max(axis=(0, 2)),
                       np.zeros(n), np.zeros(NL), np.zeros(NL), -np.ones(NL, dtype=np.int64),
                       np.zeros(G), np.zeros(G), -np.ones(G, dtype=np.int64),
                       np.zeros((R, n_tracked)), np.zeros(2, dtype=np.int64),
                       np.zeros((R, nbz)), np.zeros(len(xstart) - 1),
                       np.zeros(G), np.zeros(n_tracked, dtype=np.float32),
                       np.zeros(6 * Lmax, dtype=np.float32), np.zeros(Lmax, dtype=np.float32),
                       np.zeros(4, dtype=np.int64))
        ids = np.arange(n) if node_ids is None else np.asarray(node_ids)
        self.node_ids = ids[order]
        self.n_tracked = int(n_tracked)
        self.n_coordinates = K
        self.n_leaves, self.n_groups = NL, G
        self._seed = -np.ones(1, dtype=np.int64)

    # ---- the search as a file (flexbearing.coupling.flexible_cage caches it beside the reduced cage: building
    # it costs ~2.8 s on the 4 mm paper cage, reading it back ~0.3 s)
    FILE_VERSION = 1          # bump when the construction above changes what the arrays hold

    def save(self, path, source: str = "") -> None:
        """Write the freshly built search (its arrays, node order and sizes) to an .npz file,
        atomically (flexbearing.common.safe_files.atomic_output: a unique temporary created
        exclusively beside it, renamed over it; removed on any failure). Call it before the first
        search: the arrays include the search's scratch and references. `source`: what it was
        built from (the reduced cage's digest), checked by `load`."""
        from flexbearing.common.safe_files import atomic_output
        size = sum(a.nbytes for a in self.arrays) + self.node_ids.nbytes + (1 << 16)
        with atomic_output(path, suffix=".npz", reserve=size) as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, *self.arrays, node_ids=self.node_ids, source=np.array(str(source)),
                         meta=np.array([self.FILE_VERSION, self.n_tracked, self.n_coordinates,
                                        self.n_leaves, self.n_groups, len(self.arrays)], dtype=np.int64))

    @classmethod
    def load(cls, path, source: str | None = None) -> "TrackingMaxVonMises | None":
        """The search `save` wrote, or None if the file is of another FILE_VERSION or was built
        from another `source`. A damaged file raises (zip's CRC-32 of every array is checked as
        it is read)."""
        with np.load(str(path), allow_pickle=False) as f:
            meta = f["meta"]
            if int(meta[0]) != cls.FILE_VERSION:
                return None
            if source is not None and ("source" not in f.files or str(f["source"]) != str(source)):
                return None
            self = cls.__new__(cls)
            self.arrays = tuple(np.ascontiguousarray(f[f"arr_{i}"]) for i in range(int(meta[5])))
            self.node_ids = f["node_ids"]
        self.n_tracked, self.n_coordinates = int(meta[1]), int(meta[2])
        self.n_leaves, self.n_groups = int(meta[3]), int(meta[4])
        self._seed = -np.ones(1, dtype=np.int64)
        return self

    N_TABLES = 13             # arrays[:13] are the search's tables (read only); the rest its state

    def with_own_state(self) -> "TrackingMaxVonMises":
        """A search over the same tables (shared, read only) with its own scratch, references and
        seed: two threads may each search with one (the references of one search are mutated
        by every call, so a search is not for two threads at once)."""
        import copy
        other = copy.copy(self)
        other.arrays = self.arrays[:self.N_TABLES] + tuple(a.copy() for a in self.arrays[self.N_TABLES:])
        other._seed = -np.ones(1, dtype=np.int64)
        return other

    @property
    def A(self) -> np.ndarray:
        """(N, K, 6) rows (L W_n)^T in search order (the node kernel's layout)."""
        return self.arrays[0]

    @property
    def count(self) -> np.ndarray:
        """Diagnostics of the last call: groups opened, leaves refreshed, leaves scanned, exact
        node evaluations."""
        return self.arrays[-1]

    def reset(self) -> None:
        """Forget every reference (the next call refreshes everything it opens)."""
        a = self.arrays
        a[16][:] = -1          # leaf references
        a[19][:] = -1          # group references
        a[21][:] = 0           # ring: next slot, slots used

    def __call__(self, y: np.ndarray, best_in: float = -1.0, seed: int = -1):
        """(max von Mises Pa, node id) if some node beats best_in (Pa), else (None, -1)."""
        self._seed[0] = seed
        b2 = best_in * best_in if best_in >= 0 else -1.0
        v, k = tracking_max_sq(self.arrays, np.ascontiguousarray(y, dtype=np.float64), b2,
                               self._seed)
        if k < 0:
            return None, -1
        return float(np.sqrt(v)), int(self.node_ids[k])

    def row(self, y: np.ndarray, best_in_sq: float = -1.0, seed: int = -1) -> tuple[float, int]:
        """(max vm^2 Pa^2, row) as the kernel returns it; row -1 (and best_in_sq): no node's vm^2
        exceeds best_in_sq."""
        self._seed[0] = seed
        return tracking_max_sq(self.arrays, np.ascontiguousarray(y, dtype=np.float64),
                               float(best_in_sq), self._seed)

    def brute_force(self, y: np.ndarray) -> tuple[float, int]:
        v, k = brute_force_max_sq(self.A, np.ascontiguousarray(y, dtype=np.float64))
        return float(np.sqrt(v)), int(self.node_ids[k])
