"""Exact maximum von Mises stress over the cage for a vector of modal coordinates (hot loop).

The nodal stress is linear in the modal coordinates q: sigma_n = S_n q (S_n: 6 x m, Voigt
xx yy zz yz xz xy; fem_cage.stress_modes). Von Mises (von Mises 1913)

    vm^2 = 1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2) = |L sigma|^2

with L = rows ((e1-e2)/√2, (e2-e3)/√2, (e3-e1)/√2, √3 e4, √3 e5, √3 e6), so vm_n(q) = |A_n q|,
A_n = L S_n, a seminorm of q. Two bounds hold for every node (Cauchy–Schwarz / triangle):

    vm_n(q) <= ||A_n||_2 |q|                                   (global bound, sorted once)
    vm_n(q) <= sum_b ||A_n[:, b]||_2 |q_b|                      (block bound, b = mode groups)

A third bound makes it cheap: nodes are grouped into leaves of ~8 nodes with similar stress
modes (principal-direction bisection of the rows A_n, weighted by a typical modal amplitude such
as 1/omega_k), and consecutive leaves into groups of 16. With a leaf (or group) centre A_c, the
mean of its A_n, the triangle inequality gives for each of its nodes

    vm_n(q) <= |A_c q| + sum_b ||(A_n - A_c)[:, b]||_2 |q_b|        (leaf bound, per mode block b)

and the same with the largest radius over the leaf (group) for the whole leaf (group). Mode
blocks: the 6 rigid modes, then elastic blocks of 2, 2, 2, 2, 4, 4, 8, 16, ... (mode_blocks):
a dynamic response lives in the low modes, so the bound follows where q actually is.

Algorithm (MaxVonMises; exact, no sampling): evaluate every group bound, open the group with the
largest one (its leaf bounds, then exact node values) to get a running maximum, then open only
the groups, leaves and nodes whose bound can beat the running maximum. The returned value is
bitwise the value the brute-force loop (the same kernel over all nodes) finds; every bound
carries a relative safety factor 1 + 1e-9 that covers its rounding. Exactness is checked by
tests/test_von_mises.py and by `flexbearing reduce --json` against brute force on 1000 random
modal vectors; benchmarks/bench_von_mises.py measures the cost per call on the paper cage.
MaxVonMisesSorted is a simpler exact variant (nodes sorted once by the global bound, early exit,
per-node block bound).

numpy + numba only (no dolfinx): the runtime imports this with the reduced-cage file.
The numba kernel `max_von_mises_sq` is allocation-free and can be called from another @njit loop
with the arrays of a MaxVonMises (A, bound, block_bound, block_starts, work).
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
def _residual_bound(radius, k, qb):
    r = 0.0
    for b in range(qb.shape[0]):
        r += radius[k, b] * qb[b]
    return r


@njit(cache=True)
def _open_group(A, centres, leaf_start, leaf_radius, node_radius, q, qb, g0, g1, best, arg,
                count):
    """Scan leaves g0..g1-1 (leaf bound, node bound, exact nodes); returns (best, arg)."""
    for c in range(g0, g1):
        v = np.sqrt(node_vm_sq(centres, c, q)) * SAFETY
        count[0] += 1
        b = v + _residual_bound(leaf_radius, c, qb)
        if b * b <= best:
            continue
        for k in range(leaf_start[c], leaf_start[c + 1]):
            bn = v + _residual_bound(node_radius, k, qb)
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
        b = np.sqrt(node_vm_sq(gcentres, g, q)) * SAFETY + _residual_bound(group_radius, g, qb)
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
