"""Linear elasticity of the cage: read the tagged mesh, assemble stiffness K and mass M.

Weak form (small strain, isotropic, no body load), for u, v in [P_k]^3 on the cage volume Omega:

    k(u, v) = ∫_Omega sigma(u) : eps(v) dx,   eps(u) = (grad u + grad u^T)/2,
    sigma(u) = 2 mu eps(u) + lambda tr(eps(u)) I,
    lambda = E nu / ((1 + nu)(1 - 2 nu)),  mu = E / (2 (1 + nu));
    m(u, v) = ∫_Omega rho u · v dx.

No Dirichlet condition: the cage is free–free, K is singular with the 6 rigid-body motions in
its null space (flexbearing.fem_cage.modes handles that with a shifted factorisation).
Reference: any FE text, e.g. Hughes, "The Finite Element Method" (2000), §2.7 and §7.
dolfinx calls that differ between the Debian (0.5.2) and PyPI (0.11) stacks go through
flexbearing.common.fe_stack.
"""
from __future__ import annotations

from pathlib import Path

from mpi4py import MPI




def load_cage_mesh(path, comm=MPI.COMM_WORLD, min_quality: float | None = None, check: bool = True):
    """Read a gmsh .msh (linear or curved quadratic tets) into dolfinx, distributed over comm.

    Returns (domain, cell_tags, facet_tags, names) with names: physical name -> tag.
    Refuses (flexbearing.common.validation.InputError) a mesh with inverted or badly curved tetrahedra
    (flexbearing.mesh.quality.check_mesh_file: Jacobian ratio below min_quality, default
    flexbearing.mesh.quality.MIN_JACOBIAN_RATIO), naming the elements and where they are; check=False skips
    that (only for studies of what invalid elements do).
    The file is read by gmsh on rank 0 only and the mesh is then partitioned (dolfinx
    model_to_mesh); dolfinx 0.5.2's read_from_msh is broken, hence this wrapper.
    """
    import gmsh

    from flexbearing.common import fe_stack
    from flexbearing.common.validation import InputError

    path = Path(path)
    names = None
    if comm.rank == 0:
        if not path.exists():
            raise FileNotFoundError(path)
        if path.suffix != ".msh":
            raise InputError(f"mesh file {path}: flexbearing reads gmsh .msh files (the FE model needs "
                             f"gmsh's physical groups); got {path.suffix or 'no suffix'}: convert it to "
                             f".msh or let `flexbearing mesh` make the mesh")
        # every mesh, built here or given by the user (--mesh), is checked before any FE work:
        # inverted or badly curved elements give wrong stresses (flexbearing.mesh.quality)
        from flexbearing.mesh.quality import check_mesh_file, MIN_JACOBIAN_RATIO
        if check:
            check_mesh_file(path, bound=MIN_JACOBIAN_RATIO if min_quality is None else min_quality)
        fe_stack.gmsh_initialize(gmsh)
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cage")
        gmsh.merge(str(path))
        names = {gmsh.model.getPhysicalName(d, t): t for d, t in gmsh.model.getPhysicalGroups()}
        has_volume = any(d == 3 for d, _ in gmsh.model.getPhysicalGroups())
    names, has_volume = comm.bcast((names, has_volume if comm.rank == 0 else None), root=0)
    if not has_volume:
        # an untagged mesh (no physical volume) gives dolfinx no cells to read
        if comm.rank == 0:
            gmsh.finalize()
        from flexbearing.common.validation import InputError
        raise InputError(f"mesh {str(path)!r} has no physical volume group (groups: {sorted(names) or 'none'}): "
                         "make it with `flexbearing mesh` or `flexbearing mesh --cad CAGE.step`")
    try:
        domain, cell_tags, facet_tags = fe_stack.read_gmsh_model(gmsh.model, comm, 0, gdim=3)
    finally:
        if comm.rank == 0:
            gmsh.finalize()
    return domain, cell_tags, facet_tags, names


def lame_parameters(material) -> tuple[float, float]:
    """(lambda, mu) from E and nu: lambda = E nu/((1+nu)(1-2nu)), mu = E/(2(1+nu))."""
    E, nu = material.youngs_modulus, material.poisson_ratio
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def strain(u):
    import ufl
    return ufl.sym(ufl.grad(u))


def stress(u, material):
    """Cauchy stress sigma = 2 mu eps + lambda tr(eps) I (Hooke, isotropic)."""
    import ufl
    lam, mu = lame_parameters(material)
    eps = strain(u)
    return 2.0 * mu * eps + lam * ufl.tr(eps) * ufl.Identity(len(u))


def assemble_stiffness_mass(domain, material, degree: int = 2, quadrature_degree: int | None = None):
    """Return (V, K, M): the vector P-degree Lagrange space and assembled PETSc matrices.

    K_ij = k(phi_j, phi_i), M_ij = m(phi_j, phi_i) (forms in the module docstring); no BCs.
    """
    import ufl
    from flexbearing.common.fe_stack import fem, assemble_matrix, vector_space

    material.validate("cage.material")
    V = vector_space(domain, "Lagrange", int(degree))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    # Quadrature: exact for the P-degree polynomial integrands on affine cells; on curved
    # quadratic cells the Jacobian varies and the default estimate would be needlessly high.
    md = {"quadrature_degree": int(quadrature_degree or 2 * int(degree))}
    k_form = fem.form(ufl.inner(stress(u, material), strain(v)) * ufl.dx(metadata=md))
    m_form = fem.form(material.density * ufl.inner(u, v) * ufl.dx(metadata=md))
    K = assemble_matrix(k_form)
    K.assemble()
    M = assemble_matrix(m_form)
    M.assemble()
    return V, K, M


def von_mises_expression(u, material):
    """sigma_vM = sqrt(3/2 s:s), s = sigma - tr(sigma)/3 I (deviatoric stress)."""
    import ufl
    s = stress(u, material)
    dev = s - ufl.tr(s) / 3.0 * ufl.Identity(len(u))
    return ufl.sqrt(1.5 * ufl.inner(dev, dev))


def total_mass(domain, material) -> float:
    """∫ rho dx over the mesh (all ranks), kg."""
    import ufl
    from flexbearing.common.fe_stack import fem
    local = fem.assemble_scalar(fem.form(material.density * ufl.dx(domain=domain)))
    return domain.comm.allreduce(local, op=MPI.SUM)


def global_ndofs(V) -> int:
    im = V.dofmap.index_map
    return im.size_global * V.dofmap.index_map_bs
