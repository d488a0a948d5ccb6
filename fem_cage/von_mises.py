"""Exact maximum von Mises stress over the cage for a vector of modal coordinates (hot loop).

The nodal stress is linear in the modal coordinates q: sigma_n = S_n q (S_n: 6 x m, Voigt
xx yy zz yz xz xy; fem_cage.stress_modes). Von Mises (von Mises 1913)

    vm^2 = 1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2) = |L sigma|^2

with L = rows ((e1-e2)/√2, (e2-e3)/√2, (e3-e1)/√2, √3 e4, √3 e5, √3 e6), so vm_n(q) = |A_n q|,
A_n = L S_n, a seminorm of q. Two bounds hold for every node (Cauchy–Schwarz / triangle):

    vm_n(q) <= ||A_n||_2 |q|                                   (global bound, sorted once)
    vm_n(q) <= sum_b ||A_n[:, b]||_2 |q_b|                      (block bound, b = mode groups)

Algorithm (exact, no sampling): visit nodes in descending ||A_n||_2; stop as soon as the global
bound of the current node cannot beat the running maximum (every later node has a smaller one);
skip a node whose block bound cannot beat it; otherwise evaluate |A_n q| exactly. The returned
value is bitwise the value the brute-force loop (same kernel over all nodes) finds; bounds carry a
relative safety factor 1 + 1e-9 that covers their rounding (exactness is checked by
tests/test_von_mises.py against brute force on random modal vectors). The cost per call is
O(m) for the block norms plus, per visited node, O(B) for the block bound and 6m multiply-adds
for each exact evaluation; benchmarks/bench_von_mises.py measures it on the paper cage.

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


@njit(cache=True, fastmath=False)
def node_vm_sq(A, k, q):
    """|A_k q|^2 for node k (A: (N, 6, m) C-contiguous)."""
    total = 0.0
    m = q.shape[0]
    for r in range(6):
        acc = 0.0
        for j in range(m):
            acc += A[k, r, j] * q[j]
        total += acc * acc
    return total


@njit(cache=True)
def max_von_mises_sq(A, bound, block_bound, block_starts, q, work):
    """(max_n vm_n(q)^2, n*) over sorted nodes; work: float array of len(block_starts)-1."""
    nb = block_starts.shape[0] - 1
    qn = 0.0
    for b in range(nb):
        s = 0.0
        for j in range(block_starts[b], block_starts[b + 1]):
            s += q[j] * q[j]
        work[b] = np.sqrt(s)
        qn += s
    qn = np.sqrt(qn) * SAFETY
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
    qn = 0.0
    for b in range(nb):
        s = 0.0
        for j in range(block_starts[b], block_starts[b + 1]):
            s += q[j] * q[j]
        work[b] = np.sqrt(s)
        qn += s
    qn = np.sqrt(qn) * SAFETY
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


class MaxVonMises:
    """Precomputed hot-spot ordering for S (N, 6, m) nodal stress modes (Pa per unit q).

    node_ids: the caller's index of each row of S (default 0..N-1); returned with the maximum.
    n_blocks: mode groups of the block bound (contiguous, as equal as possible).
    """

    def __init__(self, S: np.ndarray, node_ids: np.ndarray | None = None, n_blocks: int = 6):
        S = np.asarray(S, dtype=np.float64)
        if S.ndim != 3 or S.shape[1] != 6:
            raise ValueError(f"stress modes must be (N, 6, m), got {S.shape}")
        n, _, m = S.shape
        A = np.einsum("rs,nsm->nrm", L_VM, S)
        bound = np.linalg.norm(A, ord=2, axis=(1, 2)) if m else np.zeros(n)
        nb = max(1, min(int(n_blocks), m))
        starts = np.linspace(0, m, nb + 1).round().astype(np.int64)
        bb = np.zeros((n, nb))
        for b in range(nb):
            blk = A[:, :, starts[b]:starts[b + 1]]
            if blk.shape[2]:
                bb[:, b] = np.linalg.norm(blk, ord=2, axis=(1, 2))
        order = np.argsort(-bound, kind="stable")
        self.A = np.ascontiguousarray(A[order])
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
