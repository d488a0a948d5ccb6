"""The finite-element stack this process runs on, and the one place where the two stacks differ.

flexbearing's FE half (the mesh with gmsh, K and M with dolfinx, the modes with SLEPc, the
Craig–Bampton reduction with PETSc/MUMPS) runs on either of two stacks, with the same code:

* **Debian 12** (the reference, `make setup`): dolfinx 0.5.2 (python3-dolfinx-real), UFL 2022.2,
  PETSc/SLEPc and petsc4py/slepc4py 3.18, mpi4py 3.1 on Debian's OpenMPI, gmsh 4.8.
* **PyPI** (`pip install "flexbearing[fem]"`, Python >= 3.12; docs/install.md): dolfinx 0.11
  (the `dolfinx-solver-real` wheel, which carries PETSc 3.25, SLEPc 3.25, MUMPS and petsc4py /
  slepc4py inside), UFL 2026.1, mpi4py 4.1 on the MPICH 5 wheel, gmsh 4.15.

Every FE-library call whose spelling differs between them goes through this module; everything
else (UFL forms, `fem.form`, `fem.assemble_scalar`, `fem.locate_dofs_topological`, PETSc's
Mat/Vec/KSP, SLEPc's EPS) is spelled the same on both and is called directly, with the modules
taken from here so that they load in the right order (below). The spelling is chosen by what the
installed library has (a feature test), never by a version number; nothing else in the package
tests a version.

Load order. The PyPI wheels link dolfinx, PETSc and SLEPc against `libmpi.so.12`, which the MPICH
wheel installs in the environment's own `lib/`, a folder the dynamic linker does not search.
mpi4py's loader finds it there and opens it; a library that needs it afterwards then resolves to
that copy. So `mpi4py.MPI` is imported before any of them. Then h5py and netCDF4: dolfinx 0.11's
`dolfinx.fem.petsc` opens PETSc's library with cffi into the process's global symbol scope, and
with it the wheel's HDF5 1.14; h5py and netCDF4 carry their own HDF5 (2.0), and a module loaded
after that binds its HDF5 calls to the global 1.14 ("h5py is running against HDF5 1.14.6 when it
was built against 2.0.0", then "ValueError: Not a datatype" or "NetCDF: HDF error"). Loaded
first, they have bound their own. (On Debian the order changes nothing: one OpenMPI on the
linker's path, one HDF5 per build.) So import MPI, PETSc, SLEPc, dolfinx's `fem` and the
assemblers from this module (`from flexbearing.common.fe_stack import PETSc, fem`), never
directly. No LD_LIBRARY_PATH, nothing in the user's shell. Each name is imported on first use
(PEP 562 module `__getattr__`), so importing this module costs nothing: a run whose reduced cage
is cached, or whose cage is rigid, never loads the FE stack.

What each stack lacks (said here once):

* Debian 12: its MUMPS has no METIS, SCOTCH or ParMETIS; MUMPS's automatic choice (ICNTL(7) = 7,
  left as it is on both stacks) takes PORD there and METIS on the PyPI wheel, and on the paper
  cage's saddle matrix the orderings differ by ~10 % at most (benchmarks/mumps_ordering.py,
  benchmarks/results/mumps_ordering.md); dolfinx 0.5.2's `read_from_msh` is broken
  (`read_gmsh_model` goes through gmsh on rank 0 and `model_to_mesh` on both). It is the stack of
  `make setup`/`make test`/`make demo` and the reference results.
* PyPI: Python >= 3.12 on Linux with glibc >= 2.34 only (the wheel is manylinux_2_34); no
  CalculiX (the slow independent FE checks need `ccx` from the system) and no ParaView/Chromium
  (the report's .pvsm, movie and PDF are left out without them, as on Debian without
  `make viewers`); gmsh's wheel needs the system's X11/OpenGL libraries (libGLU, libXcursor,
  libXft, libXinerama).
* Both: neither gmsh keeps a STEP file's face names (checked with gmsh 4.8/OCC 7.6 and gmsh
  4.15/OCC 7.8: of a STEP whose ADVANCED_FACEs are named, only the solid's product name comes
  through), so named CAD faces come in a gmsh .geo (flexbearing.mesh.cad_cage) on both.

Both compute the same model: the same elements, quadrature and solvers. Their results agree to
the solvers' tolerances, not bit for bit: dolfinx 0.11 numbers the mesh's cells and dofs in
another order, so sums are taken in another order (docs/install.md quotes the measured
differences).
"""
from __future__ import annotations

import importlib
import signal
import sys
import threading

import numpy as np

# name -> (module, attribute or None): the FE modules handed out by __getattr__, each after mpi4py
_LAZY = {
    "MPI": ("mpi4py.MPI", None),
    "PETSc": ("petsc4py.PETSc", None),
    "SLEPc": ("slepc4py.SLEPc", None),
    "dolfinx": ("dolfinx", None),
    "fem": ("dolfinx.fem", None),
    "cpp": ("dolfinx.cpp", None),
    "XDMFFile": ("dolfinx.io", "XDMFFile"),
    "assemble_matrix": ("dolfinx.fem.petsc", "assemble_matrix"),
    "assemble_vector": ("dolfinx.fem.petsc", "assemble_vector"),
}


# imported before any FE library, in this order (the module docstring says why)
LOAD_FIRST = ("mpi4py.MPI", "h5py", "netCDF4")


def _load_first() -> None:
    for module in LOAD_FIRST:
        if module not in sys.modules:
            try:
                importlib.import_module(module)
            except ImportError:
                if module == "mpi4py.MPI":
                    raise


def __getattr__(name: str):
    """`from flexbearing.common.fe_stack import PETSc` etc.: the module, loaded after LOAD_FIRST."""
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    _load_first()
    module, attr = _LAZY[name]
    obj = importlib.import_module(module)
    obj = getattr(obj, attr) if attr else obj
    globals()[name] = obj                          # the next lookup is a plain attribute
    return obj


def versions() -> dict:
    """The FE stack's versions (for `flexbearing --version`-style reports and the install docs)."""
    import gmsh
    dolfinx, PETSc, SLEPc = __getattr__("dolfinx"), __getattr__("PETSc"), __getattr__("SLEPc")
    import ufl
    return {"dolfinx": dolfinx.__version__, "ufl": ufl.__version__,
            "petsc": ".".join(map(str, PETSc.Sys.getVersion())),
            "slepc": ".".join(map(str, SLEPc.Sys.getVersion())),
            "mpi": " ".join(__getattr__("MPI").Get_library_version().splitlines()[0].split(",")[0]
                            .replace("\0", "").split()),
            "gmsh": gmsh.__version__}


# ------------------------------------------------------------------ gmsh (4.8 / 4.15)

def gmsh_initialize(gmsh) -> None:
    """gmsh.initialize(). gmsh 4.8 sets the SIGINT handler when it is imported; gmsh >= 4.9 sets
    it in initialize() unless interruptible=False, and Python allows signal.signal in the main
    thread only: off the main thread (a Dask worker building a reduced cage) it is left alone. On
    the main thread, finalize() puts Python's handler back (KeyboardInterrupt: a run stops cleanly)
    on both (gmsh 4.8's finalize() puts back the handler it saw when it was imported, `oldsig`:
    that is replaced by the one in force just before initialize(), so a process that was started
    with SIGINT ignored, in the background, and has set Python's handler since, keeps it); off the
    main thread gmsh 4.8's finalize() would call signal.signal too: that is dropped."""
    if threading.current_thread() is threading.main_thread():
        previous = signal.getsignal(signal.SIGINT)
        gmsh.initialize()
        if hasattr(gmsh, "prev_interrupt_handler"):
            # gmsh >= 4.9 means finalize() to put the handler back, but keeps it in a local
            # variable (no `global`): Ctrl-C would kill the process for good after the first mesh
            gmsh.prev_interrupt_handler = previous
        if getattr(gmsh, "oldsig", None) is not None:
            gmsh.oldsig = previous
        return
    if getattr(gmsh, "oldsig", None) is not None:
        gmsh.oldsig = None
    if getattr(gmsh, "prev_interrupt_handler", None) is not None:
        gmsh.prev_interrupt_handler = None     # its finalize() would call signal.signal here
    try:
        gmsh.initialize(interruptible=False)
    except TypeError:                              # gmsh 4.8: no such argument, nothing to skip
        gmsh.initialize()


# ------------------------------------------------------------------ dolfinx (0.5 / 0.11)

def read_gmsh_model(model, comm, rank: int = 0, gdim: int = 3):
    """The gmsh model (on `rank`) as a dolfinx mesh distributed over comm:
    (domain, cell_tags, facet_tags). dolfinx 0.5: dolfinx.io.gmshio.model_to_mesh, a tuple;
    dolfinx >= 0.10: dolfinx.io.gmsh.model_to_mesh, a MeshData named tuple."""
    __getattr__("MPI")
    try:
        from dolfinx.io import gmshio as reader
    except ImportError:
        from dolfinx.io import gmsh as reader
    out = reader.model_to_mesh(model, comm, rank, gdim=gdim)
    if hasattr(out, "facet_tags"):
        return out.mesh, out.cell_tags, out.facet_tags
    return out[0], out[1], out[2]


def _space(domain, family: str, degree: int, shape):
    fem = __getattr__("fem")
    if hasattr(fem, "functionspace"):                       # dolfinx >= 0.7
        return fem.functionspace(domain, (family, int(degree)) + ((shape,) if shape else ()))
    make = {0: fem.FunctionSpace, 1: fem.VectorFunctionSpace, 2: fem.TensorFunctionSpace}
    return make[len(shape or ())](domain, (family, int(degree)))     # dolfinx 0.5: gdim-sized


def scalar_space(domain, family: str, degree: int):
    """Scalar `family` P-degree space (0.5: FunctionSpace; >= 0.7: functionspace)."""
    return _space(domain, family, degree, None)


def vector_space(domain, family: str, degree: int):
    """Blocked 3-vector space, dof = 3 node + component (0.5: VectorFunctionSpace;
    >= 0.7: functionspace(mesh, (family, degree, (3,))))."""
    return _space(domain, family, degree, (domain.geometry.x.shape[1],))


def tensor_space(domain, family: str, degree: int):
    """3 x 3 tensor space, row-major (0.5: TensorFunctionSpace; >= 0.7: shape (3, 3))."""
    d = domain.geometry.x.shape[1]
    return _space(domain, family, degree, (d, d))


def element_degree(V) -> int:
    """The polynomial degree of V's element (0.5: ufl_element().degree(); the basix UFL
    element of >= 0.7: a property)."""
    degree = V.ufl_element().degree
    return int(degree() if callable(degree) else degree)


def geometry_degree(domain) -> int:
    """The degree of the mesh's coordinate element (2 on a curved quadratic mesh)
    (0.5: geometry.cmap; >= 0.8: geometry.cmaps[0], cmap deprecated)."""
    g = domain.geometry
    return int((g.cmaps[0] if hasattr(g, "cmaps") else g.cmap).degree)


def geometry_dofmap(domain) -> np.ndarray:
    """(cells, nodes per cell): the geometry nodes of each local cell (0.5: geometry.dofmap, an
    AdjacencyList; >= 0.8: geometry.dofmaps[0], a 2-D array)."""
    g = domain.geometry
    n = domain.topology.index_map(domain.topology.dim).size_local
    dm = g.dofmaps[0] if hasattr(g, "dofmaps") else g.dofmap
    return _cell_rows(dm, n)


def cell_dofs(V) -> np.ndarray:
    """(cells, dofs per cell) block dofs of each local cell (0.5: dofmap.list, an AdjacencyList;
    >= 0.7: a 2-D array)."""
    domain = V.mesh
    n = domain.topology.index_map(domain.topology.dim).size_local
    return _cell_rows(V.dofmap.list, n)


def _cell_rows(adjacency, n_cells: int) -> np.ndarray:
    if hasattr(adjacency, "array"):                # AdjacencyList of a fixed-width map
        arr = np.asarray(adjacency.array)
        return arr.reshape(-1, arr.size // adjacency.num_nodes)[:n_cells]
    return np.asarray(adjacency)[:n_cells]


def interpolation_points(V) -> np.ndarray:
    """Reference points at which V's element interpolates (0.5: a method; >= 0.7: a property)."""
    pts = V.element.interpolation_points
    return pts() if callable(pts) else pts


def expression(ufl_expr, V):
    """fem.Expression of ufl_expr at V's interpolation points (for Function.interpolate)."""
    return __getattr__("fem").Expression(ufl_expr, interpolation_points(V))


def evaluate_expression(expr, domain, cells: np.ndarray) -> np.ndarray:
    """expr (a fem.Expression) at its points on the given local cells, (cells, points * size)
    (0.5: expr.eval(cells); >= 0.7: expr.eval(mesh, cells))."""
    cells = np.asarray(cells, dtype=np.int32)
    try:
        out = expr.eval(domain, cells)
    except TypeError:
        out = expr.eval(cells)
    return np.asarray(out).reshape(len(cells), -1)


def petsc_vector(u):
    """The PETSc Vec holding Function u's dofs (0.5: u.vector; >= 0.7: u.x.petsc_vec)."""
    x = u.x
    return x.petsc_vec if hasattr(x, "petsc_vec") else u.vector


def write_meshtags(xdmf, tags, domain) -> None:
    """XDMFFile.write_meshtags (>= 0.7 also takes the mesh geometry the tags refer to)."""
    try:
        xdmf.write_meshtags(tags, domain.geometry)
    except TypeError:
        xdmf.write_meshtags(tags)


def vtk_permutation(nodes_per_cell: int) -> np.ndarray:
    """perm with vtk[:, perm] = dolfinx-ordered cell nodes, tetrahedra (dolfinx.cpp.io.perm_vtk,
    the same on both)."""
    cpp = __getattr__("cpp")
    return np.asarray(cpp.io.perm_vtk(cpp.mesh.CellType.tetrahedron, int(nodes_per_cell)))
