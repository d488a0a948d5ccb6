"""Modal stress shapes: the nodal stress tensor of each mode at the cage mesh's geometry nodes.

Stress of a displacement field u (Lagrange P_k, k = 2 or 3): sigma = 2 mu eps(u) +
lambda tr(eps(u)) I (Hooke, flexbearing.fem_cage.elasticity.stress), a polynomial of degree k-1 inside each
tetrahedron, discontinuous between cells. Nodal values, the ABAQUS/ADAMS "averaged nodal stress"
convention:

    sigma_n = (1 / |cells(n)|) sum_{c ∋ n} sigma|_c (x_n)                              (1)

at the geometry nodes n of the mesh — the 4 vertices of each tetrahedron, plus its 6 edge nodes
on a curved quadratic mesh — i.e. each cell's stress is interpolated into a discontinuous
Lagrange tensor space of the geometry's degree (exact point values of the cell field at those
nodes) and averaged, unweighted, over the cells sharing node n. Why these points: stress extremes
sit on the surface, at corners and along edges (pocket rims), which these nodes sample; they are
the nodes ParaView draws; and the same operator (1) is used for the full FE recovery in every
check, so "modal recovery vs full FE" compares like with like. What it is not: for P2 on affine
cells (linear cell stress) the cell maximum of von Mises (convex) is at a vertex, so (1) before
averaging carries the field's maximum; for P3 (quadratic cell stress) an extremum inside a cell
or face is not sampled. Averaging smooths the jump
between cells; at a re-entrant edge or at the edge of a rigid (RBE2) pocket wall it under-reads
a singular peak, as ABAQUS's averaged output does.

Voigt order everywhere in flexbearing: (xx, yy, zz, yz, xz, xy), Pa. Linear in u, so the
stress of u = Phi q is S q with S[n, :, k] the stress mode k at vertex n.
"""
from __future__ import annotations

import numpy as np

VOIGT = (0, 4, 8, 5, 2, 1)           # row-major 3x3 -> (xx, yy, zz, yz, xz, xy)
VOIGT_NAMES = ("xx", "yy", "zz", "yz", "xz", "xy")


def mesh_nodes(domain):
    """(nodes, coords (Nn, 3), cells (Nc, k), vtk_cells (Nc, k)): the geometry nodes of the mesh
    (vertices, plus edge nodes on a curved quadratic mesh), their coordinates, the cells as
    compact node indices in dolfinx order and in VTK order (tetra / tetra10, for XDMF)."""
    from flexbearing.common.fe_stack import geometry_dofmap, vtk_permutation
    gdm = geometry_dofmap(domain)
    nodes, cells = np.unique(gdm, return_inverse=True)
    cells = cells.reshape(gdm.shape).astype(np.int64)
    perm = vtk_permutation(gdm.shape[1])
    vtk = np.empty_like(cells)
    vtk[:, perm] = cells          # perm maps VTK -> dolfinx local order
    return nodes, domain.geometry.x[nodes].copy(), cells, vtk


class NodalStress:
    """The operator (1) at the mesh's geometry nodes (vertices, and edge nodes of a curved
    quadratic mesh): displacement dof array of V -> nodal stress (Nn, 6); also the displacement
    interpolated to the same nodes (`displacement`)."""

    def __init__(self, V, material):
        from flexbearing.common.fe_stack import fem, vector_space, tensor_space, cell_dofs, expression
        from .elasticity import stress
        domain = V.mesh
        self.u = fem.Function(V)
        self.nodes, self.coords, self.cells, self.vtk_cells = mesh_nodes(domain)
        k = self.cells.shape[1]
        gdeg = {4: 1, 10: 2}[k]
        # DG space of the geometry's degree: its local dofs sit at the cell's geometry nodes, in
        # the same local order as the geometry dofmap (same Lagrange element layout).
        W = tensor_space(domain, "DG", gdeg)
        self.sig = fem.Function(W)
        self.expr = expression(stress(self.u, material), W)
        self.dg_dofs = cell_dofs(W)
        self.count = np.bincount(self.cells.ravel(), minlength=len(self.nodes)).astype(float)
        # (1) as one sparse matrix, DG dof -> node, 1/|cells(n)| each: one product per mode
        # (np.add.at, unbuffered, took half the stress-mode time on the paper cage)
        import scipy.sparse as sp
        self.average = sp.csr_matrix(
            (1.0 / self.count[self.cells.ravel()], (self.cells.ravel(), self.dg_dofs.ravel())),
            shape=(len(self.nodes), len(self.sig.x.array) // 9))
        Vg = vector_space(domain, "Lagrange", gdeg)
        self.ug = fem.Function(Vg)
        self.ug_dofs = cell_dofs(vector_space(domain, "DG", gdeg))
        self.ug_cells = cell_dofs(Vg)
        self._ug_node = np.empty(len(self.nodes), dtype=np.int64)
        self._ug_node[self.cells.ravel()] = self.ug_cells.ravel()

    def __call__(self, u_array: np.ndarray) -> np.ndarray:
        self.u.x.array[:] = u_array
        self.sig.interpolate(self.expr)
        vals = self.sig.x.array.reshape(-1, 9)[:, VOIGT]              # (n_dg, 6)
        return self.average @ vals

    def displacement(self, u_array: np.ndarray) -> np.ndarray:
        """u at the geometry nodes (Nn, 3), by interpolation into the geometry's Lagrange space."""
        self.u.x.array[:] = u_array
        self.ug.interpolate(self.u)
        return self.ug.x.array.reshape(-1, 3)[self._ug_node]


def stress_modes(V, material, Phi: np.ndarray, zero_columns=(), progress=None):
    """(S (Nn, 6, M), D (Nn, 3, M), op): nodal stress (1) and nodal displacement of each column
    of Phi (dof arrays of V); the stress of columns in zero_columns (the exact rigid modes) is
    set to 0 without computing."""
    op = NodalStress(V, material)
    m = Phi.shape[1]
    S = np.zeros((len(op.nodes), 6, m))
    D = np.zeros((len(op.nodes), 3, m))
    zero = set(int(k) for k in zero_columns)
    for k in range(m):
        if k not in zero:
            S[:, :, k] = op(Phi[:, k])
        D[:, :, k] = op.displacement(Phi[:, k])
        if progress is not None:
            progress.update(1)
    return S, D, op


def von_mises(sigma: np.ndarray) -> np.ndarray:
    """sigma_vM = sqrt(1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2))
    for Voigt rows (..., 6) (textbook form, von Mises 1913)."""
    s = np.asarray(sigma)
    a, b, c, d, e, f = (s[..., i] for i in range(6))
    return np.sqrt(0.5 * ((a - b) ** 2 + (b - c) ** 2 + (c - a) ** 2) + 3.0 * (d * d + e * e + f * f))
