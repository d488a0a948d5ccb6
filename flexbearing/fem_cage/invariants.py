"""Mass properties and the modal inertia invariants of the floating frame of reference.

The cage is a continuum of density rho meshed with solid (translational-DOF) elements. A point
with body-frame reference position x moves to x + u, u(x, t) = sum_k Phi_k(x) q_k(t) in the body
frame. The floating-frame equations (Shabana, "Dynamics of Multibody Systems", 4th ed. 2020,
ch. 5, "inertia shape integrals"; MSC ADAMS/Flex "Theory of flexible bodies": the nine inertia
invariants; Exudyn ObjectFFRFreducedOrder builds the same terms from the mass matrix) need

    I1 = ∫ rho dV = m                                          (scalar)
    I2 = ∫ rho x dV = m c                                      (3)
    I3 = ∫ rho Phi_k dV                                        (3, M)
    I4 = ∫ rho x × Phi_k dV                                    (3, M)
    I5 = ∫ rho Phi_j × Phi_k dV                                (3, M, M)  I5[:, j, k]
    I6 = ∫ rho Phi_j · Phi_k dV  (generalised mass)           (M, M)
    I7 = ∫ rho [x]x^T [x]x dV = ∫ rho (|x|^2 I - x x^T) dV    (3, 3)  inertia about the origin
    I8 = ∫ rho [x]x [Phi_k]x dV                                (3, 3, M)  I8[:, :, k]
    I9 = ∫ rho [Phi_j]x^T [Phi_k]x dV                          (3, 3, M, M)  I9[:, :, j, k]

([a]x b = a × b). Solid elements carry no nodal rotary inertia, so ADAMS's I_p Phi*_p terms
are zero here. All of them follow from three kinds of consistent-mass moments, exact for the FE
fields (the P2 interpolant of x is the curved P2 geometry itself, constants are exact):

    Ixx[a, b]       = ∫ rho x_a x_b dV        = X_a^T Ms X_b
    Sx[a, b, k]     = ∫ rho x_a Phi_k,b dV    = X_a^T Ms Phi_b[:, k]
    SS[a, b, j, k]  = ∫ rho Phi_j,a Phi_k,b dV = Phi_a[:, j]^T Ms Phi_b[:, k]   (Shabana's S_ab)

with Ms the scalar consistent mass matrix (one block of the vector mass matrix), X_a the nodal
coordinate a, Phi_a the component-a rows of the modes. Which ones a runtime uses: with the
mean-axis elastic set (flexbearing.fem_cage.craig_bampton: every elastic mode M-orthogonal to the rigid
modes) I3 = 0 and I4 = 0 for the elastic modes (checked), I6 = identity; the remaining coupling
terms are I1, I2, I5, I7, I8, I9 (mass matrix blocks M_rr, M_rf and the quadratic-velocity
vector of the floating-frame equations).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

EPS3 = np.zeros((3, 3, 3))
EPS3[0, 1, 2] = EPS3[1, 2, 0] = EPS3[2, 0, 1] = 1.0
EPS3[0, 2, 1] = EPS3[2, 1, 0] = EPS3[1, 0, 2] = -1.0


def scalar_mass_matrix(M_vector: sp.spmatrix) -> sp.csr_matrix:
    """Ms from the blocked vector mass matrix (dof = 3 node + c, M = Ms ⊗ I3)."""
    return sp.csr_matrix(M_vector)[0::3, 0::3]


def mass_moments(Ms: sp.spmatrix, X: np.ndarray, Phi: np.ndarray | None = None) -> dict:
    """Raw consistent-mass moments: mass, first (3), second (3x3), Sx (3,3,M), SS (3,3,M,M),
    S1 = ∫ rho Phi (3, M). Phi: (3N, M) blocked modes, or None (rigid properties only)."""
    Ms = sp.csr_matrix(Ms)
    one = np.ones(Ms.shape[0])
    MX = Ms @ X                                         # (N, 3)
    out = {"mass": float(one @ (Ms @ one)), "first": one @ MX, "second": X.T @ MX}
    if Phi is not None:
        P = [np.ascontiguousarray(Phi[a::3]) for a in range(3)]
        MP = [Ms @ p for p in P]
        m = Phi.shape[1]
        out["S1"] = np.array([one @ MP[b] for b in range(3)])            # (3, M)
        out["Sx"] = np.array([[X[:, a] @ MP[b] for b in range(3)] for a in range(3)])
        SS = np.empty((3, 3, m, m))
        for a in range(3):
            for b in range(a, 3):           # Ms symmetric: SS[b, a] = SS[a, b]^T (6 products, not 9)
                SS[a, b] = P[a].T @ MP[b]
                SS[b, a] = SS[a, b].T
        out["SS"] = SS
    return out


def rigid_properties(mom: dict) -> dict:
    """Mass, centre of mass, inertia about the origin and about the CoM (Steiner)."""
    m, S, Ixx = mom["mass"], mom["first"], mom["second"]
    c = S / m
    J_o = np.trace(Ixx) * np.eye(3) - Ixx
    J_c = J_o - m * (c @ c * np.eye(3) - np.outer(c, c))
    return {"mass": m, "center_of_mass": c, "inertia_origin": J_o, "inertia_com": J_c}


def ffrf_invariants(mom: dict) -> dict:
    """I1..I9 (module docstring) from the raw moments."""
    Sx, SS = mom["Sx"], mom["SS"]
    Ixx = mom["second"]
    I = {"I1": mom["mass"], "I2": mom["first"], "I3": mom["S1"]}
    I["I4"] = np.einsum("iab,abk->ik", EPS3, Sx)
    I["I5"] = np.einsum("iab,abjk->ijk", EPS3, SS)
    I["I6"] = np.einsum("aajk->jk", SS)
    I["I7"] = np.trace(Ixx) * np.eye(3) - Ixx
    # [x]x[phi]x = phi x^T - (x.phi) I  ->  I8[i, j, k] = Sx[j, i, k] - delta_ij sum_a Sx[a, a, k]
    I["I8"] = np.transpose(Sx, (1, 0, 2)) - np.eye(3)[:, :, None] * np.einsum("aak->k", Sx)
    # [pj]x^T [pk]x = -[pj]x[pk]x = (pj.pk) I - pk pj^T -> I9[i,l,j,k] = d_il tr - SS[l, i, j, k]
    I["I9"] = (np.eye(3)[:, :, None, None] * np.einsum("aajk->jk", SS)
               - np.transpose(SS, (1, 0, 2, 3)))
    return I


def ring_analytic(outer_radius: float, inner_radius: float, width: float, density: float) -> dict:
    """Plain ring (hollow cylinder about x): m = rho pi (Ro^2 - Ri^2) w,
    J_xx = m (Ro^2 + Ri^2)/2, J_yy = J_zz = m (3 (Ro^2 + Ri^2) + w^2)/12, CoM at the origin."""
    Ro, Ri, w = outer_radius, inner_radius, width
    m = density * np.pi * (Ro ** 2 - Ri ** 2) * w
    Jx = 0.5 * m * (Ro ** 2 + Ri ** 2)
    Jy = m * (3 * (Ro ** 2 + Ri ** 2) + w ** 2) / 12.0
    return {"mass": m, "center_of_mass": np.zeros(3), "inertia_com": np.diag([Jx, Jy, Jy]),
            "volume": m / density}


def direct_mass_properties(domain, density: float, quadrature_degree: int) -> dict:
    """∫ rho dV, ∫ rho x dV, ∫ rho x_a x_b dV assembled directly as dolfinx scalar forms (the
    independent check of mass_moments); serial."""
    import ufl
    from flexbearing.common.fe_stack import fem
    dx = ufl.dx(domain=domain, metadata={"quadrature_degree": int(quadrature_degree)})
    x = ufl.SpatialCoordinate(domain)

    def integral(expr):
        return fem.assemble_scalar(fem.form(expr * dx))

    m = integral(density + 0.0 * x[0])
    first = np.array([integral(density * x[a]) for a in range(3)])
    second = np.array([[integral(density * x[a] * x[b]) for b in range(3)] for a in range(3)])
    return {"mass": m, "first": first, "second": second}
