"""Craig–Bampton interface of the cage: one 6-DOF node per pocket, tied to the pocket wall.

Each pocket k gets an interface ("master") node m at the pocket centre x_m: on the pocket's
radial axis at the cage mean radius, in the mid-plane x = 0,

    x_m = (0, r_mean cos theta_k, r_mean sin theta_k),  theta_k = 2 pi k / Z  (from +y to +z),

with DOFs (u_x, u_y, u_z, theta_x, theta_y, theta_z) in the cage body frame. The ball–pocket
force and moment of the multibody model act there. The node is tied to the DOF nodes s of the
pocket wall (every P2 node on the facets tagged 101 + k, vertices and mid-side nodes alike) by

* RBE2 ("rigid", ABAQUS kinematic coupling): the wall moves as a rigid body with the node,
      u_s = u_m + theta_m x (x_s - x_m)                                              (1)
  The wall DOFs are eliminated: u = T z, z = (all other DOFs, master DOFs), K_z = T^T K T,
  M_z = T^T M T. The wall becomes rigid (the cage gets stiffer).
* RBE3 ("distributing", ABAQUS distributing coupling / NASTRAN RBE3): the node follows the
  weighted least-squares rigid motion of the wall, which keeps its own stiffness:
      x_c = sum w_s x_s,  r_s = x_s - x_c,  J = sum w_s (|r_s|^2 I - r_s r_s^T),
      theta_m = J^-1 sum w_s r_s x u_s,  u_m = sum w_s u_s + theta_m x (x_m - x_c)      (2)
  i.e. (u_m, theta_m) = C u with C a 6 x n matrix per pocket; a force/moment F on the node is
  distributed to the wall as f = C^T F. Weights w_s = ∫_wall N_s dA / A (consistent surface
  weights: a uniform pressure on the wall has the nodal loads w_s). (2) reproduces any rigid
  motion exactly (u_s = t + omega x x_s gives u_m = t + omega x x_m, theta_m = omega).

References: MSC Nastran Quick Reference Guide, RBE2/RBE3 entries; Abaqus Analysis User's Guide
§35.3.2 "Coupling constraints" (kinematic vs distributing).

The algebra here is numpy/scipy on node coordinates and DOF indices; only
`pocket_wall_nodes` and `pocket_wall_weights` touch dolfinx. DOF numbering: blocked vector
space, dof = 3 * node + component (dolfinx VectorFunctionSpace, serial).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

POCKET_TAG0 = 101      # flexbearing.mesh.cage_mesh: pocket k wall = facet tag 101 + k
DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


def skew(a) -> np.ndarray:
    """[a]x with [a]x b = a x b."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def pocket_centres(geometry) -> np.ndarray:
    """Interface node positions (Z, 3), m: on the pocket axis in the mid-plane, at the mean radius
    (cylindrical pockets) or at the sphere's centre (spherical: the pocket force passes through it)."""
    th = np.asarray(geometry.pocket_azimuths())
    r = 0.5 * geometry.pocket_centre_diameter if geometry.pocket_shape == "spherical" else geometry.mean_radius
    return np.column_stack([np.zeros_like(th), r * np.cos(th), r * np.sin(th)])


def rigid_interface_matrix(x_master: np.ndarray) -> np.ndarray:
    """G (6Z, 6): master DOFs of the rigid motion (t, omega) of the body about the origin:
    u_m = t + omega x x_m = t - [x_m]x omega, theta_m = omega."""
    x_master = np.atleast_2d(x_master)
    G = np.zeros((6 * len(x_master), 6))
    for k, x in enumerate(x_master):
        G[6 * k:6 * k + 3, 0:3] = np.eye(3)
        G[6 * k:6 * k + 3, 3:6] = -skew(x)
        G[6 * k + 3:6 * k + 6, 3:6] = np.eye(3)
    return G


def rigid_field(x_nodes: np.ndarray) -> np.ndarray:
    """R (3N, 6): nodal displacements of the 6 unit rigid motions (t_x, t_y, t_z, omega_x,
    omega_y, omega_z about the origin), u(x) = t + omega x x, blocked numbering."""
    n = len(x_nodes)
    R = np.zeros((3 * n, 6))
    for i in range(3):
        R[i::3, i] = 1.0
    x, y, z = x_nodes[:, 0], x_nodes[:, 1], x_nodes[:, 2]
    # omega_x e_x x (x,y,z) = (0, -z, y); omega_y: (z, 0, -x); omega_z: (-y, x, 0)
    R[1::3, 3], R[2::3, 3] = -z, y
    R[0::3, 4], R[2::3, 4] = z, -x
    R[0::3, 5], R[1::3, 5] = -y, x
    return R


def rbe2_transformation(n_dofs: int, walls: list[np.ndarray], x_nodes: np.ndarray,
                        x_master: np.ndarray):
    """RBE2 elimination (1): returns (T, keep) with u = T z.

    walls[k]: node indices of pocket k's wall; x_nodes: (N, 3) node coordinates.
    z = (u[keep], master DOFs of node 0..Z-1 as ux uy uz rx ry rz); T is (n_dofs, len(keep)+6Z)
    sparse. Boundary (master) coordinates are the last 6Z entries of z.
    """
    slave = np.zeros(n_dofs, dtype=bool)
    for w in walls:
        for c in range(3):
            slave[3 * np.asarray(w) + c] = True
    keep = np.flatnonzero(~slave)
    n_keep = len(keep)
    rows = [keep]
    cols = [np.arange(n_keep)]
    vals = [np.ones(n_keep)]
    for k, w in enumerate(walls):
        w = np.asarray(w)
        r = x_nodes[w] - x_master[k]                 # (ns, 3)
        base = n_keep + 6 * k
        for c in range(3):
            d = 3 * w + c
            rows.append(d); cols.append(np.full(len(w), base + c)); vals.append(np.ones(len(w)))
            # -( [r]x )[c, j] theta_j
            for j in range(3):
                coef = -_skew_entry(r, c, j)
                nz = coef != 0.0
                rows.append(d[nz]); cols.append(np.full(nz.sum(), base + 3 + j)); vals.append(coef[nz])
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n_dofs, n_keep + 6 * len(walls)))
    return T, keep


def _skew_entry(r: np.ndarray, i: int, j: int) -> np.ndarray:
    """([r]x)[i, j] for each row of r (N, 3)."""
    if i == j:
        return np.zeros(len(r))
    table = {(0, 1): (2, -1.0), (0, 2): (1, 1.0), (1, 0): (2, 1.0),
             (1, 2): (0, -1.0), (2, 0): (1, -1.0), (2, 1): (0, 1.0)}
    comp, sign = table[(i, j)]
    return sign * r[:, comp]


def rbe3_constraint(n_dofs: int, walls: list[np.ndarray], weights: list[np.ndarray],
                    x_nodes: np.ndarray, x_master: np.ndarray) -> sp.csr_matrix:
    """RBE3 (2): C (6Z, n_dofs) sparse with (u_m, theta_m)_k = C[6k:6k+6] u."""
    rows, cols, vals = [], [], []
    for k, (w_nodes, w) in enumerate(zip(walls, weights)):
        w_nodes = np.asarray(w_nodes)
        w = np.asarray(w, dtype=float)
        w = w / w.sum()
        xs = x_nodes[w_nodes]
        xc = w @ xs
        r = xs - xc
        J = (w * (r * r).sum(1)).sum() * np.eye(3) - (r * w[:, None]).T @ r
        Jinv = np.linalg.inv(J)
        d = x_master[k] - xc
        for s in range(len(w_nodes)):
            # theta = Jinv [r_s]x (w_s u_s);  u_m = w_s u_s - [d]x theta
            Bth = Jinv @ skew(r[s]) * w[s]                  # (3, 3): d theta / d u_s
            Bu = w[s] * np.eye(3) - skew(d) @ Bth             # d u_m / d u_s
            B = np.vstack([Bu, Bth])                          # (6, 3)
            for c in range(3):
                rows.append(6 * k + np.arange(6))
                cols.append(np.full(6, 3 * w_nodes[s] + c))
                vals.append(B[:, c])
    C = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(6 * len(walls), n_dofs))
    C.eliminate_zeros()
    return C


def selection_matrix(n: int, idx: np.ndarray) -> sp.csr_matrix:
    """S (len(idx), n) with S z = z[idx]."""
    idx = np.asarray(idx)
    return sp.csr_matrix((np.ones(len(idx)), (np.arange(len(idx)), idx)), shape=(len(idx), n))


# ---------------------------------------------------------------- dolfinx side (serial only)

def pocket_wall_nodes(V, facet_tags, n_pockets: int) -> list[np.ndarray]:
    """Node (block) indices of V on each pocket wall (facet tag 101 + k)."""
    from flexbearing.common.fe_stack import fem
    domain = V.mesh
    fdim = domain.topology.dim - 1
    domain.topology.create_connectivity(fdim, domain.topology.dim)
    walls = []
    for k in range(n_pockets):
        facets = facet_tags.indices[facet_tags.values == POCKET_TAG0 + k]
        if len(facets) == 0:
            raise ValueError(f"mesh has no facets tagged pocket_{k:02d} ({POCKET_TAG0 + k})")
        walls.append(np.sort(fem.locate_dofs_topological(V, fdim, facets)))
    return walls


def pocket_wall_weights(V, facet_tags, walls: list[np.ndarray]) -> list[np.ndarray]:
    """Consistent surface weights w_s = ∫_wall N_s dA of each wall node (m^2)."""
    import ufl
    from flexbearing.common.fe_stack import fem, assemble_vector
    domain = V.mesh
    ds = ufl.Measure("ds", domain=domain, subdomain_data=facet_tags)
    v = ufl.TestFunction(V)
    ex = ufl.as_vector((1.0, 0.0, 0.0))
    # one form over all pocket walls (walls share no node: pockets are separate holes)
    tags = tuple(POCKET_TAG0 + k for k in range(len(walls)))
    b = assemble_vector(fem.form(ufl.inner(ex, v) * ds(tags)))
    arr = b.getArray()[0::3]
    return [np.array(arr[w]) for w in walls]
