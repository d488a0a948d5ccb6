"""The exact von Mises searches as objects: each builds, from the stress modes, the arrays its
compiled kernel in flexbearing.fem_cage.von_mises searches, and calls it.

    MaxVonMisesSorted, MaxVonMises    stateless searches for any modal vector (method 1 of
                                      flexbearing.fem_cage.von_mises: global and leaf bounds)
    TrackingMaxVonMises               the run's search along a trajectory in load space (method 2:
                                      the tracked bound (T)), with load_space_stress (LS) and its
                                      blocks; saved to and read from a file beside the reduced cage

The equations, the bounds and the rounding argument that make every search exact (its value is
the brute-force maximum max_n |L S_n q|, von Mises 1913) are stated once, in
flexbearing.fem_cage.von_mises, beside the kernels that evaluate them. The compiled kernels stay
there (the integrator links them; its cache check hashes that file); this module is numpy only.
"""
from __future__ import annotations

import copy

import numpy as np

from flexbearing.fem_cage.von_mises import (L_VM, SAFETY, count_visits, brute_force_max_sq,
                                            max_von_mises_leaves_sq, max_von_mises_sq, tracking_max_sq)
from flexbearing.common.safe_files import atomic_output


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
        self.order = order            # row i of the search is row order[i] of W
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
        return count_visits(self.A, self.bound, self.block_bound, self.block_starts,
                             np.ascontiguousarray(q, dtype=np.float64), self.work)


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
        self.order = order            # row i of the search is row order[i] of W
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


def _rows(W: np.ndarray) -> np.ndarray:
    """(N, K, 6) rows (L W_n)^T of the load-space stress W (N, 6, K): the node kernel's layout."""
    return np.ascontiguousarray(np.einsum("rs,nsk->nkr", L_VM, W))


def _leaf_tables(Wt: np.ndarray, leaf_starts: np.ndarray, n_tracked: int) -> np.ndarray:
    """(NL, n_tracked, 6 Lmax) float32: each leaf's tracked rows, node index fastest (zero-padded
    to the largest leaf), for the leaf kernel's bounds."""
    ls = np.asarray(leaf_starts)
    NL, Lmax = len(ls) - 1, int(np.diff(ls).max())
    Dz = np.zeros((NL, n_tracked, 6, Lmax), dtype=np.float32)
    for leaf in range(NL):
        blk = Wt[ls[leaf]:ls[leaf + 1], :n_tracked, :]
        Dz[leaf, :, :, :blk.shape[0]] = blk.transpose(1, 2, 0)
    return np.ascontiguousarray(Dz.reshape(NL, n_tracked, 6 * Lmax))


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
        Wt = _rows(W)                                                   # rows (L W_n)^T: (N, K, 6)
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
        coln = np.linalg.norm(Wt[:, :n_tracked, :], axis=2)              # (N, nz) ||D_n[:, c]||
        Cl = np.array([coln[a:b].max(axis=0) for a, b in zip(ls[:-1], ls[1:])]) * SAFETY
        Dz = _leaf_tables(Wt, ls, n_tracked)
        G = len(gs) - 1
        nbz = len(zstart) - 1
        R = int(ring)
        self.arrays = (Wt, Dz, Cl, zstart,
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
        self.order = order            # row i of the search is row order[i] of W
        self.n_tracked = int(n_tracked)
        self.n_coordinates = K
        self.n_leaves, self.n_groups = NL, G
        self._seed = -np.ones(1, dtype=np.int64)

    # ---- the search as a file (flexbearing.coupling.flexible_cage caches it beside the reduced cage).
    # The file holds the tree (node order, leaf and group bounds, per-node block norms: ~2 MB on
    # the 4 mm paper cage), not the load-space stress W itself (129 MB, a second copy of the
    # stress modes): `load` takes W, rebuilt by the caller from the reduced cage, and re-derives
    # the two tables that are W in another layout (the rows L W_n in search order, and their
    # float32 leaf copies). On the 4 mm paper cage W takes ~0.9 s, the search built from it
    # ~0.9-1.3 s more, loaded from the file ~0.14 s more (benchmarks/results/
    # reduce_design_loop.md, round two).
    FILE_VERSION = 2          # bump when the construction above changes what the arrays hold
    _FROM_W = (0, 1)          # arrays[0] (rows of L W_n), arrays[1] (their leaf copies): from W

    def save(self, path, source: str = "") -> None:
        """Write the freshly built search (its arrays but those derived from W, node order and
        sizes) to an .npz file, atomically (flexbearing.common.safe_files.atomic_output: a unique
        temporary created exclusively beside it, renamed over it; removed on any failure). Call
        it before the first search: the arrays include the search's scratch and references.
        `source`: what it was built from (the reduced cage's digest), checked by `load`."""
        kept = {f"arr_{i}": a for i, a in enumerate(self.arrays) if i not in self._FROM_W}
        size = sum(a.nbytes for a in kept.values()) + 2 * self.node_ids.nbytes + (1 << 16)
        with atomic_output(path, suffix=".npz", reserve=size) as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, **kept, node_ids=self.node_ids, order=self.order,
                         source=np.array(str(source)),
                         meta=np.array([self.FILE_VERSION, self.n_tracked, self.n_coordinates,
                                        self.n_leaves, self.n_groups, len(self.arrays)], dtype=np.int64))

    @classmethod
    def load(cls, path, W: np.ndarray, source: str | None = None) -> "TrackingMaxVonMises | None":
        """The search `save` wrote, over the load-space stress W (N, 6, K) it was built from
        (load_space_stress of the same reduced cage and mode count), or None if the file is of
        another FILE_VERSION, was built from another `source`, or does not fit W's shape. A
        damaged file raises (zip's CRC-32 of every array is checked as it is read)."""
        W = np.asarray(W, dtype=np.float64)
        with np.load(str(path), allow_pickle=False) as f:
            meta = f["meta"]
            if int(meta[0]) != cls.FILE_VERSION:
                return None
            if source is not None and ("source" not in f.files or str(f["source"]) != str(source)):
                return None
            order = f["order"]
            if W.ndim != 3 or W.shape[1] != 6 or W.shape[2] != int(meta[2]) or len(order) != W.shape[0]:
                return None
            n_arrays = int(meta[5])
            stored = {i: np.ascontiguousarray(f[f"arr_{i}"]) for i in range(n_arrays)
                      if i not in cls._FROM_W}
            self = cls.__new__(cls)
            self.node_ids = f["node_ids"]
            self.order = order
        self.n_tracked, self.n_coordinates = int(meta[1]), int(meta[2])
        self.n_leaves, self.n_groups = int(meta[3]), int(meta[4])
        Wt = np.ascontiguousarray(_rows(W)[order])
        stored[0] = Wt
        stored[1] = _leaf_tables(Wt, stored[11], self.n_tracked)
        self.arrays = tuple(stored[i] for i in range(n_arrays))
        self._seed = -np.ones(1, dtype=np.int64)
        return self

    N_TABLES = 13             # arrays[:13] are the search's tables (read only); the rest its state

    def with_own_state(self) -> "TrackingMaxVonMises":
        """A search over the same tables (shared, read only) with its own scratch, references and
        seed: two threads may each search with one (the references of one search are mutated
        by every call, so a search is not for two threads at once)."""
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
