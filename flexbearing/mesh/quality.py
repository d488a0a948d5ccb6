"""Validity and shape quality of the cage's tetrahedra, straight (4-node) or curved (10-node).

A curved quadratic tetrahedron is the isoparametric map of the reference tetrahedron

    x(xi) = sum_i x_i N_i(xi),   J(xi) = dx/dxi = sum_i x_i (grad_xi N_i)^T,

with the quadratic Lagrange shape functions in barycentric coordinates L0 = 1 - xi1 - xi2 - xi3,
L1..3 = xi1..3: vertex i, N_i = L_i (2 L_i - 1); edge (i, j), N = 4 L_i L_j (Zienkiewicz, Taylor &
Zhu, "The Finite Element Method: Its Basis and Fundamentals", 7th ed. (2013), §6.5). Node order
is VTK's (meshio's): vertices 0-3, edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3).

Validity. The map is one-to-one only where det J > 0 everywhere in the element. det J of a
quadratic tetrahedron is a cubic polynomial in the barycentric coordinates; written in the cubic
Bernstein basis, det J = sum_a c_a B_a(L), B_a = 3!/(a0! a1! a2! a3!) prod L_i^a_i, the
coefficients c_a bound it from below and above: min_a c_a <= det J <= max_a c_a, since the B_a are
non-negative and sum to 1 (Johnen, Remacle & Geuzaine, "Geometrical validity of curvilinear
finite elements", J. Comput. Phys. 233 (2013) 359). The c_a come from the values at the 20 points
of the cubic lattice (an exact interpolation of the cubic). So `min_bernstein > 0` certifies the
element; the sampled minimum (nodes, the cubic lattice, the quadrature points of the FE degree in
use) is an upper bound of the true minimum, the Bernstein one a lower bound.

Quality measures (each dimensionless, 1 for the ideal element):
- jacobian_ratio = min det J / |det J(centroid)|: how much the curving distorts the element
  (1 for a straight-sided one; <= 0 inverted). What decides whether the stresses recovered at an
  element's nodes can be trusted (benchmarks/results/cage_stress_convergence.md measures where).
- scaled_jacobian of the straight-sided corner tetrahedron: min over the four corners of
  det[e1 e2 e3] / (|e1| |e2| |e3|) scaled by sqrt(2) so that the regular tetrahedron gives 1
  (Knupp, "Achieving finite element mesh quality via optimization of the Jacobian matrix norm and
  associated quantities", Int. J. Numer. Meth. Eng. 48 (2000) 1165): the shape of the element
  (slivers and needles near 0).

numpy only (meshio to read files): the mesh layer's check, imported by flexbearing.mesh.cage_mesh and by the
reduction before any FE work.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
import contextlib
import io

import numpy as np

from flexbearing.common.validation import InputError

# Edges of the VTK/meshio tetra10 (node 4 + k sits on EDGES[k]).
EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))
# Below this Jacobian ratio an element is refused or repaired (measured: the stress at the nodes
# of elements below it is wrong by more than the 5 % the converged stress is held to; above it
# the recovered nodal stress agrees with the converged field — see MIN_JACOBIAN_RATIO_EVIDENCE).
MIN_JACOBIAN_RATIO = 0.3
MIN_JACOBIAN_RATIO_EVIDENCE = "benchmarks/results/cage_stress_convergence.md, section 'quality bound'"


def _barycentric(xi: np.ndarray) -> np.ndarray:
    """(P, 4) barycentric coordinates of reference points xi (P, 3)."""
    xi = np.atleast_2d(np.asarray(xi, dtype=float))
    return np.column_stack([1.0 - xi.sum(axis=1), xi])


def shape_gradients(xi: np.ndarray, n_nodes: int) -> np.ndarray:
    """(P, n_nodes, 3): d N_i / d xi at reference points xi (P, 3), VTK order, 4 or 10 nodes."""
    L = _barycentric(xi)
    P = len(L)
    dL = np.zeros((4, 3))                       # d L_i / d xi_a
    dL[0] = -1.0
    dL[1:] = np.eye(3)
    if n_nodes == 4:
        return np.broadcast_to(dL, (P, 4, 3)).copy()
    if n_nodes != 10:
        raise ValueError(f"tetrahedra with {n_nodes} nodes are not supported (4 or 10)")
    G = np.zeros((P, 10, 3))
    for i in range(4):
        G[:, i] = (4.0 * L[:, i] - 1.0)[:, None] * dL[i]
    for k, (i, j) in enumerate(EDGES):
        G[:, 4 + k] = 4.0 * (L[:, j][:, None] * dL[i] + L[:, i][:, None] * dL[j])
    return G


def reference_nodes(n_nodes: int) -> np.ndarray:
    """(n_nodes, 3) reference coordinates of the nodes (VTK order)."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    if n_nodes == 4:
        return V
    return np.vstack([V, [(V[i] + V[j]) / 2 for i, j in EDGES]])


@lru_cache(maxsize=None)
def _cubic_lattice() -> tuple[np.ndarray, np.ndarray]:
    """(20, 3) reference points of the cubic lattice and the (20, 20) matrix taking the values of
    a cubic there to its Bernstein coefficients."""
    alphas = [a for a in itertools.product(range(4), repeat=4) if sum(a) == 3]
    L = np.array(alphas, dtype=float) / 3.0           # lattice point of multi-index a
    V = np.empty((20, 20))
    for p, lp in enumerate(L):
        for q, a in enumerate(alphas):
            c = math.factorial(3) / np.prod([math.factorial(k) for k in a])
            V[p, q] = c * np.prod([lp[i] ** a[i] for i in range(4)])
    return L[:, 1:].copy(), np.linalg.inv(V)


def quadrature_points(degree: int) -> np.ndarray:
    """Reference points of the quadrature rule of the given degree on the tetrahedron: basix's
    default rule (the one dolfinx assembles with) when basix is installed, else a collapsed
    Gauss–Legendre rule of the same degree."""
    try:
        import basix
        pts, _ = basix.make_quadrature(basix.CellType.tetrahedron, int(degree))
        return np.asarray(pts, dtype=float)
    except ImportError:                                   # pragma: no cover (Debian has basix)
        n = int(degree) // 2 + 1
        g, _ = np.polynomial.legendre.leggauss(n)
        g = 0.5 * (g + 1.0)
        pts = [(a * (1 - b) * (1 - c), b * (1 - c), c) for a in g for b in g for c in g]
        return np.array(pts)


def jacobian_determinants(points: np.ndarray, cells: np.ndarray, xi: np.ndarray,
                          chunk: int = 20000) -> np.ndarray:
    """(Nc, P) det J of every cell at the reference points xi (P, 3); cells (Nc, 4|10), VTK order."""
    points = np.asarray(points, dtype=float)
    cells = np.asarray(cells)
    G = shape_gradients(xi, cells.shape[1])             # (P, n, 3)
    out = np.empty((len(cells), len(G)))
    for s in range(0, len(cells), chunk):
        X = points[cells[s:s + chunk]]                   # (E, n, 3)
        J = np.einsum("eni,pna->epia", X, G, optimize=True)
        out[s:s + chunk] = np.linalg.det(J)
    return out


def scaled_jacobian(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """(Nc,) scaled Jacobian of the straight corner tetrahedron (module docstring), in [-1, 1]."""
    X = np.asarray(points, dtype=float)[np.asarray(cells)[:, :4]]
    worst = np.full(len(X), np.inf)
    for c in range(4):
        # right-handed order at each corner: the corner-0 triple (1, 2, 3) is positive for a
        # positively oriented tetrahedron; at other corners the even permutations keep the sign.
        o = {0: (1, 2, 3), 1: (0, 3, 2), 2: (0, 1, 3), 3: (0, 2, 1)}[c]
        e = [X[:, k] - X[:, c] for k in o]
        det = np.einsum("ei,ei->e", e[0], np.cross(e[1], e[2]))
        norms = np.linalg.norm(e[0], axis=1) * np.linalg.norm(e[1], axis=1) * np.linalg.norm(e[2], axis=1)
        worst = np.minimum(worst, math.sqrt(2.0) * det / np.maximum(norms, 1e-300))
    return worst


@dataclass
class MeshQuality:
    """Per-cell measures of a tetrahedral mesh and where its worst cells are."""
    n_cells: int
    n_nodes_per_cell: int
    min_det_sampled: np.ndarray          # (Nc,) over nodes, cubic lattice and quadrature points
    min_det_bernstein: np.ndarray        # (Nc,) certified lower bound (== sampled for 4 nodes)
    det_centroid: np.ndarray             # (Nc,)
    jacobian_ratio: np.ndarray           # (Nc,) min_det_sampled / det_centroid
    scaled_jacobian: np.ndarray          # (Nc,) of the straight corner tetrahedron
    centroids: np.ndarray                # (Nc, 3) m
    quadrature_degree: int
    extra: dict = field(default_factory=dict)

    @property
    def n_inverted(self) -> int:
        """Cells with det J <= 0 at some sampled point (nodes, lattice, quadrature points)."""
        return int(np.count_nonzero(self.min_det_sampled <= 0.0))

    @property
    def n_uncertified(self) -> int:
        """Cells whose Bernstein lower bound is not positive (inverted or not proven valid)."""
        return int(np.count_nonzero(self.min_det_bernstein <= 0.0))

    def below(self, bound: float) -> np.ndarray:
        """Indices of the cells whose Jacobian ratio is below bound, worst first."""
        idx = np.flatnonzero(self.jacobian_ratio < bound)
        return idx[np.argsort(self.jacobian_ratio[idx])]

    def describe(self, cells_idx, n: int = 5) -> str:
        """Where cells are, in the cage's words: index, axial x, radius r, azimuth (mm, deg)."""
        parts = []
        for e in list(cells_idx)[:n]:
            x, y, z = self.centroids[e]
            parts.append(f"cell {int(e)} (ratio {self.jacobian_ratio[e]:.3g}, at x = {x * 1e3:.2f} mm, "
                         f"r = {math.hypot(y, z) * 1e3:.2f} mm, azimuth "
                         f"{math.degrees(math.atan2(z, y)) % 360:.1f} deg)")
        more = len(cells_idx) - n
        return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")

    def summary(self, bound: float = MIN_JACOBIAN_RATIO) -> dict:
        r = self.jacobian_ratio
        return {"n_cells": self.n_cells, "nodes_per_cell": self.n_nodes_per_cell,
                "n_inverted": self.n_inverted, "n_uncertified": self.n_uncertified,
                "min_jacobian_ratio": float(r.min()), "worst_cell": int(r.argmin()),
                "n_below_bound": int(np.count_nonzero(r < bound)), "bound": bound,
                "jacobian_ratio_percentiles": {p: float(np.percentile(r, p)) for p in (0.1, 1, 5, 50)},
                "min_scaled_jacobian": float(self.scaled_jacobian.min()),
                "scaled_jacobian_percentiles": {p: float(np.percentile(self.scaled_jacobian, p))
                                                for p in (0.1, 1, 5, 50)},
                "quadrature_degree": self.quadrature_degree}


def mesh_quality(points: np.ndarray, cells: np.ndarray, fe_degree: int = 3) -> MeshQuality:
    """Quality of every cell (module docstring); fe_degree: the Lagrange degree the FE model uses,
    whose stiffness quadrature (degree 2·fe_degree, flexbearing.fem_cage.elasticity) is sampled too."""
    cells = np.asarray(cells)
    nn = cells.shape[1]
    qdeg = 2 * int(fe_degree)
    lattice, to_bernstein = _cubic_lattice()
    centroid = np.full((1, 3), 0.25)
    xi = np.vstack([reference_nodes(nn), lattice, quadrature_points(qdeg), centroid])
    d = jacobian_determinants(points, cells, xi)
    n_ref, n_lat = nn, len(lattice)
    d_centroid = d[:, -1]
    min_sampled = d[:, :-1].min(axis=1)
    if nn == 10:
        c = d[:, n_ref:n_ref + n_lat] @ to_bernstein.T
        min_bern = c.min(axis=1)
    else:
        min_bern = min_sampled.copy()
    X = np.asarray(points, dtype=float)[cells[:, :4]]
    # |det J(centroid)|: an inverted cell whose centroid is inverted too keeps a negative ratio
    ref = np.abs(d_centroid)
    ref = np.where(ref > 0, ref, np.abs(d[:, :-1]).max(axis=1) + 1e-300)
    return MeshQuality(len(cells), nn, min_sampled, min_bern, d_centroid, min_sampled / ref,
                       scaled_jacobian(points, cells), X.mean(axis=1), qdeg)


def read_tetrahedra(path) -> tuple[np.ndarray, np.ndarray]:
    """(points (N, 3) m, cells (Nc, 4|10) VTK order) of the tetrahedra in a mesh file (meshio)."""
    import meshio
    path = Path(path)
    if not path.is_file():
        raise InputError(f"mesh file {path} does not exist or is not a file")
    def unreadable(why: str) -> InputError:
        return InputError(f"mesh file {path} cannot be read as a mesh ({why}): give a gmsh .msh file, "
                          f"e.g. one written by `flexbearing mesh`")
    if path.suffix == ".msh":
        with open(path, "rb") as fh:
            if not fh.read(64).lstrip().startswith(b"$MeshFormat"):
                raise unreadable("it does not start with gmsh's $MeshFormat header")
    try:
        # meshio prints its own error and calls sys.exit on a file none of its readers takes
        with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
            m = meshio.read(str(path))
    except (Exception, SystemExit) as exc:   # ReadError, ParseError, KeyError, ... of its readers
        text = str(exc).splitlines()[0][:120] if str(exc) else ""
        raise unreadable(f"{type(exc).__name__}{': ' + text if text else ''}") from None
    blocks = [c.data for c in m.cells if c.type in ("tetra", "tetra10")]
    if not blocks:
        raise InputError(f"mesh file {path}: no tetrahedra (tetra or tetra10 cells) in it")
    kinds = {b.shape[1] for b in blocks}
    if len(kinds) > 1:
        raise InputError(f"mesh file {path}: mixes 4- and 10-node tetrahedra")
    return np.asarray(m.points, dtype=float), np.vstack(blocks)


def check_mesh_file(path, fe_degree: int = 3, bound: float = MIN_JACOBIAN_RATIO) -> MeshQuality:
    """Refuse a mesh file with inverted or badly curved elements (InputError naming them and
    where they are); return its quality when every element passes."""
    points, cells = read_tetrahedra(path)
    q = mesh_quality(points, cells, fe_degree)
    require_valid(q, bound, str(path))
    return q


def require_valid(q: MeshQuality, bound: float = MIN_JACOBIAN_RATIO, what: str = "mesh") -> None:
    """InputError unless every cell has a positive Jacobian and a Jacobian ratio >= bound."""
    bad = q.below(bound)
    if q.n_inverted or q.n_uncertified or len(bad):
        inv = np.flatnonzero((q.min_det_sampled <= 0) | (q.min_det_bernstein <= 0))
        worst = np.unique(np.r_[inv, bad])
        worst = worst[np.argsort(q.jacobian_ratio[worst])]
        raise InputError(
            f"{what}: {q.n_inverted} inverted element(s) (det J <= 0) and {len(bad)} below the "
            f"Jacobian-ratio bound {bound:g} (min det J / det J at the centroid; stresses at their "
            f"nodes would be wrong): {q.describe(worst)}. Use a finer mesh (mesh.size / "
            f"mesh.pocket_size) or let flexbearing build the mesh (it repairs such elements).")


def mesh_file_quality(path, fe_degree: int = 3) -> MeshQuality:
    """The quality of a mesh file without refusing it (reports, studies)."""
    points, cells = read_tetrahedra(Path(path))
    return mesh_quality(points, cells, fe_degree)


# ------------------------------------------------------------------ repair

@dataclass
class RepairLog:
    """What repair_curved_elements changed: the cells it flattened (fraction of their curving
    kept, 0 = straight-sided), the mid-edge nodes it moved and by how much (m): that is the
    distance by which those nodes now lie off the CAD surface they were placed on."""
    bound: float
    passes: int
    n_cells_flattened: int
    n_nodes_moved: int
    max_node_shift: float
    cells_before: list
    quality_before: dict
    quality_after: dict

    def as_dict(self) -> dict:
        return {"bound": self.bound, "passes": self.passes,
                "n_cells_flattened": self.n_cells_flattened, "n_nodes_moved": self.n_nodes_moved,
                "max_node_shift_m": self.max_node_shift, "cells_below_bound_before":
                self.cells_before[:50], "quality_before": self.quality_before,
                "quality_after": self.quality_after}


def repair_curved_elements(points: np.ndarray, cells: np.ndarray, bound: float = MIN_JACOBIAN_RATIO,
                           fe_degree: int = 3, max_halvings: int = 4) -> tuple[np.ndarray, RepairLog]:
    """Flatten the curved elements whose Jacobian ratio is below `bound` (module docstring).

    Each mid-edge node of a quadratic tetrahedron sits at x_m = x_s + d, x_s the midpoint of its
    straight edge and d the curving that puts it on the CAD surface. A pass takes every cell below
    the bound and halves d on its six edges (the cell then bends half as much, and so do the
    neighbours sharing those edges); after `max_halvings` passes the cells still below the bound
    are made straight-sided (d = 0 on their edges). A straight-sided cell has det J constant and
    equal to that of its corner tetrahedron, which the linear mesher made positive: its ratio is 1,
    so it never falls below the bound again and the loop ends (each pass straightens at least one
    more cell). The price is geometric: the moved nodes leave the surface by at most |d| (reported
    as max_node_shift), a local faceting of the pocket wall at those few cells; measured effect on
    the stress in benchmarks/results/cage_stress_convergence.md.

    Returns (new points, RepairLog). Linear (4-node) meshes are returned unchanged.
    """
    import scipy.sparse as sp
    pts = np.array(points, dtype=float)
    cells = np.asarray(cells)
    q0 = mesh_quality(pts, cells, fe_degree)
    before = q0.summary(bound)
    bad0 = q0.below(bound)
    if cells.shape[1] != 10 or len(bad0) == 0:
        return pts, RepairLog(bound, 0, 0, 0, 0.0, bad0.tolist(), before, before)
    lattice, _ = _cubic_lattice()
    xi = np.vstack([reference_nodes(10), lattice, quadrature_points(2 * int(fe_degree)),
                    np.full((1, 3), 0.25)])
    mids = cells[:, 4:]
    ends = np.array(EDGES)
    straight = 0.5 * (pts[cells[:, ends[:, 0]]] + pts[cells[:, ends[:, 1]]])     # (Nc, 6, 3)
    node_mid = np.full(len(pts), -1)                     # mid node -> one (cell, edge) owning it
    node_mid[mids.ravel()] = np.arange(mids.size)
    owner = np.flatnonzero(node_mid >= 0)
    base = straight.reshape(-1, 3)[node_mid[owner]]      # straight position of each mid node
    curve = pts[owner] - base                            # d of each mid node
    frac = np.ones(len(owner))                           # share of d kept
    pos_of = np.full(len(pts), -1)
    pos_of[owner] = np.arange(len(owner))
    # cells touching each mid node (to re-evaluate the neighbours of what moved)
    inc = sp.csr_matrix((np.ones(mids.size), (mids.ravel(), np.repeat(np.arange(len(cells)), 6))),
                        shape=(len(pts), len(cells)))

    def ratios(idx):
        d = jacobian_determinants(pts, cells[idx], xi)
        ref = np.abs(d[:, -1])
        ref = np.where(ref > 0, ref, np.abs(d[:, :-1]).max(axis=1) + 1e-300)
        return d[:, :-1].min(axis=1) / ref

    ratio = q0.jacobian_ratio.copy()
    flattened = set()
    passes = 0
    bad = bad0
    while len(bad):
        passes += 1
        nodes = np.unique(mids[bad].ravel())
        k = pos_of[nodes]
        frac[k] = 0.0 if passes > max_halvings else 0.5 * frac[k]
        pts[nodes] = base[k] + frac[k, None] * curve[k]
        flattened.update(bad.tolist())
        touched = np.unique(inc[nodes].indices)
        ratio[touched] = ratios(touched)
        bad = touched[ratio[touched] < bound]
        if passes > max_halvings + len(cells):          # cannot happen (docstring); never loop forever
            raise RuntimeError("repair_curved_elements did not converge")
    moved = frac < 1.0
    shift = float(((1.0 - frac[moved])[:, None] * np.linalg.norm(curve[moved], axis=1)[:, None]).max()) \
        if moved.any() else 0.0
    after = mesh_quality(pts, cells, fe_degree).summary(bound)
    return pts, RepairLog(bound, passes, len(flattened), int(moved.sum()), shift, bad0.tolist(),
                          before, after)
