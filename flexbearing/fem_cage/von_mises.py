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

The searches as objects, which build the arrays these kernels take from the stress modes:
flexbearing.fem_cage.von_mises_search (MaxVonMisesSorted, MaxVonMises, TrackingMaxVonMises,
load_space_stress). This module holds the kernels only: the integrator links them, and its numba
cache check hashes this file.

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
def count_visits(A, bound, block_bound, block_starts, q, work):
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


# ------------------------------------------------------------------ the run's tracking search

U_ROUND = np.finfo(np.float64).eps / 2.0        # unit roundoff u
_F32 = 2.0 ** -24 * SAFETY                      # relative rounding of a float32 copy


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


