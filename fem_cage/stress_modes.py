"""Modal stress shapes: the nodal stress tensor of each mode on the cage mesh vertices.

Stress of a displacement field u (P2): sigma = 2 mu eps(u) + lambda tr(eps(u)) I (Hooke,
fem_cage.elasticity.stress). Inside each tetrahedron sigma is a polynomial (exactly linear on an
affine P2 cell), discontinuous between cells. Nodal values, the ABAQUS/ADAMS "averaged nodal
stress" convention:

    sigma_n = (1 / |cells(n)|) sum_{c ∋ n} sigma|_c (x_n)                              (1)

i.e. the cell's stress is interpolated into a discontinuous P1 tensor space (values at the
cell's 4 vertices, exact for the linear cell field) and averaged, unweighted, over the cells
sharing vertex n. Why vertices (and not P2 nodes or quadrature points): they carry the field's
extremes on each cell (sigma linear, von Mises convex => its cell maximum is at a vertex),
there are ~8x fewer of them than P2 nodes, and the same operator (1) is used for the full FE
recovery in every check, so "modal recovery vs full FE" compares like with like. Averaging
smooths the jump between cells; at a re-entrant edge or at the edge of a rigid (RBE2) pocket
wall it under-reads the singular peak exactly as ABAQUS's averaged output does.

Voigt order everywhere in flexbearing: (xx, yy, zz, yz, xz, xy), Pa. Linear in u, so the
stress of u = Phi q is S q with S[n, :, k] the stress mode k at vertex n.
"""
from __future__ import annotations

import numpy as np

VOIGT = (0, 4, 8, 5, 2, 1)           # row-major 3x3 -> (xx, yy, zz, yz, xz, xy)
VOIGT_NAMES = ("xx", "yy", "zz", "yz", "xz", "xy")


def mesh_vertices(domain):
    """(vertex_nodes, coords (Nv, 3), tets (Nc, 4)): geometry node index of each mesh vertex,
    its coordinates and the cells as 4 compact vertex indices (for XDMF output)."""
    gdm = domain.geometry.dofmap.array.reshape(domain.topology.index_map(3).size_local, -1)
    corner = gdm[:, :4]
    vertex_nodes, tets = np.unique(corner, return_inverse=True)
    return vertex_nodes, domain.geometry.x[vertex_nodes].copy(), tets.reshape(-1, 4).astype(np.int64)


class VertexStress:
    """The operator (1): displacement dof array of V -> vertex stress (Nv, 6)."""

    def __init__(self, V, material):
        import ufl
        from dolfinx import fem
        from .elasticity import stress
        domain = V.mesh
        self.u = fem.Function(V)
        W = fem.TensorFunctionSpace(domain, ("DG", 1))
        self.sig = fem.Function(W)
        self.expr = fem.Expression(stress(self.u, material), W.element.interpolation_points())
        ncell = domain.topology.index_map(3).size_local
        self.vertex_nodes, self.coords, self.tets = mesh_vertices(domain)
        # DG1 local dof j of cell c sits at the cell's reference vertex j = geometry node j.
        self.dg_dofs = W.dofmap.list.array.reshape(ncell, 4)
        self.count = np.bincount(self.tets.ravel(), minlength=len(self.vertex_nodes)).astype(float)

    def __call__(self, u_array: np.ndarray) -> np.ndarray:
        self.u.x.array[:] = u_array
        self.sig.interpolate(self.expr)
        vals = self.sig.x.array.reshape(-1, 9)[:, VOIGT]              # (n_dg, 6)
        out = np.zeros((len(self.vertex_nodes), 6))
        np.add.at(out, self.tets.ravel(), vals[self.dg_dofs.ravel()])
        return out / self.count[:, None]


def stress_modes(V, material, Phi: np.ndarray, zero_columns=(), progress=None) -> np.ndarray:
    """S (Nv, 6, M): vertex stress (1) of each column of Phi (dof arrays of V); columns listed in
    zero_columns (the exact rigid modes, whose stress is zero) are set to 0 without computing."""
    op = VertexStress(V, material)
    m = Phi.shape[1]
    S = np.zeros((len(op.vertex_nodes), 6, m))
    zero = set(int(k) for k in zero_columns)
    for k in range(m):
        if k not in zero:
            S[:, :, k] = op(Phi[:, k])
        if progress is not None:
            progress.update(1)
    return S, op


def von_mises(sigma: np.ndarray) -> np.ndarray:
    """sigma_vM = sqrt(1/2[(sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2] + 3(syz^2 + sxz^2 + sxy^2))
    for Voigt rows (..., 6) (textbook form, von Mises 1913)."""
    s = np.asarray(sigma)
    a, b, c, d, e, f = (s[..., i] for i in range(6))
    return np.sqrt(0.5 * ((a - b) ** 2 + (b - c) ** 2 + (c - a) ** 2) + 3.0 * (d * d + e * e + f * f))
