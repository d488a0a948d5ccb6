"""flexbearing.common.fe_stack: the one module where the Debian (dolfinx 0.5.2, gmsh 4.8) and PyPI
(dolfinx 0.11, gmsh 4.15) FE stacks differ. The same tests run on both (`make test` and
`make test-pypi`): each function of the module against an analytic value on a unit cube, the load
order that keeps the PyPI wheels' MPI and HDF5 libraries apart, and gmsh off the main thread."""
import subprocess
import sys
import threading

import numpy as np
import pytest


def test_importing_the_module_loads_no_fe_library():
    """The names are loaded on first use: importing fe_stack (as flexbearing.mesh does) costs nothing."""
    code = ("import sys, flexbearing.common.fe_stack; "
            "print(sorted(m for m in ('dolfinx', 'petsc4py', 'slepc4py', 'mpi4py', 'gmsh') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_hdf5_readers_work_after_the_fe_stack(tmp_path):
    """dolfinx 0.11's PETSc module opens PETSc (and the wheel's HDF5 1.14) into the global symbol
    scope; h5py and netCDF4 (with their own HDF5) imported after that fail ("Not a datatype",
    "NetCDF: HDF error"). Through fe_stack they are loaded first: both write and read a file."""
    code = f"""
import numpy as np
from flexbearing.common.fe_stack import assemble_matrix, fem, PETSc, SLEPc
import h5py, netCDF4
with h5py.File({str(tmp_path / 'a.h5')!r}, 'w') as f:
    f['x'] = np.arange(3.0)
with h5py.File({str(tmp_path / 'a.h5')!r}) as f:
    assert list(f['x'][:]) == [0.0, 1.0, 2.0]
d = netCDF4.Dataset({str(tmp_path / 'a.nc')!r}, 'w'); d.createDimension('x', 3)
d.createVariable('v', 'f8', ('x',))[:] = np.arange(3.0); d.close()
assert list(netCDF4.Dataset({str(tmp_path / 'a.nc')!r})['v'][:]) == [0.0, 1.0, 2.0]
print('ok')
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]


@pytest.fixture(scope="module")
def cube():
    from flexbearing.common.fe_stack import MPI
    from dolfinx import mesh
    return mesh.create_unit_cube(MPI.COMM_SELF, 2, 2, 2)


def test_spaces_and_dofmaps(cube):
    """The blocked vector space has 3 dofs per node (dof = 3 node + component); P2 on the 2x2x2 cube
    (48 tetrahedra) has 5^3 = 125 nodes and 10 per cell; the tensor space 9 values per dof."""
    from flexbearing.common import fe_stack as fs
    V = fs.vector_space(cube, "Lagrange", 2)
    assert fs.element_degree(V) == 2
    assert V.dofmap.index_map.size_global == 125 and V.dofmap.index_map_bs == 3
    assert fs.cell_dofs(V).shape == (48, 10)
    assert fs.geometry_dofmap(cube).shape == (48, 4) and fs.geometry_degree(cube) == 1
    Q = fs.scalar_space(cube, "Lagrange", 1)
    assert Q.dofmap.index_map.size_global == 27 and Q.dofmap.index_map_bs == 1
    W = fs.tensor_space(cube, "DG", 1)
    assert W.dofmap.index_map_bs == 9 and fs.cell_dofs(W).shape == (48, 4)
    assert sorted(fs.vtk_permutation(10)) == list(range(10))


def test_expression_gives_hookes_stress_of_a_uniform_strain(cube):
    """u = (a x, 0, 0): eps_xx = a, sigma_xx = (lambda + 2 mu) a, sigma_yy = sigma_zz = lambda a
    (Hooke), at every point; interpolated (fs.expression) and evaluated (fs.evaluate_expression)."""
    from flexbearing.common import fe_stack as fs
    from flexbearing.common.materials import Material
    from flexbearing.fem_cage.elasticity import stress, lame_parameters
    mat = Material(density=7850.0, youngs_modulus=2.1e11, poisson_ratio=0.3)
    lam, mu = lame_parameters(mat)
    a = 1e-3
    V = fs.vector_space(cube, "Lagrange", 1)
    u = fs.fem.Function(V)
    u.interpolate(lambda x: np.vstack([a * x[0], 0 * x[0], 0 * x[0]]))
    W = fs.tensor_space(cube, "DG", 0)
    sig = fs.fem.Function(W)
    sig.interpolate(fs.expression(stress(u, mat), W))
    expect = np.diag([(lam + 2 * mu) * a, lam * a, lam * a]).ravel()
    rtol = 1e-12                                   # a few roundings of a linear field's gradient
    assert np.allclose(sig.x.array.reshape(-1, 9), expect, rtol=rtol, atol=rtol * abs(expect).max())
    e = fs.fem.Expression(stress(u, mat), np.array([[0.25, 0.25, 0.25]]))
    vals = fs.evaluate_expression(e, cube, np.arange(48))
    assert vals.shape == (48, 9)
    assert np.allclose(vals, expect, rtol=rtol, atol=rtol * abs(expect).max())
    # the PETSc Vec is u's own storage (fs.petsc_vector)
    v = fs.petsc_vector(u)
    v.set(2.0)
    assert np.all(u.x.array == 2.0)


def test_xdmf_mesh_and_tags(cube, tmp_path):
    """write_meshtags: the tags written beside the mesh, as a grid of 48 cells with one value each
    (read from the XDMF's XML and its HDF5 file, not by dolfinx)."""
    import xml.etree.ElementTree as ET
    import h5py
    from flexbearing.common import fe_stack as fs
    from dolfinx import mesh
    tdim = cube.topology.dim
    cells = np.arange(48, dtype=np.int32)
    tags = mesh.meshtags(cube, tdim, cells, np.full(48, 7, dtype=np.int32))
    tags.name = "cell_tags"
    path = tmp_path / "cube.xdmf"
    with fs.XDMFFile(cube.comm, str(path), "w") as xf:
        xf.write_mesh(cube)
        fs.write_meshtags(xf, tags, cube)
    grid = next(g for g in ET.parse(path).iter("Grid") if g.get("Name") == "cell_tags")
    item = grid.find("Attribute").find("DataItem")
    h5file, dataset = item.text.strip().split(":")
    with h5py.File(tmp_path / h5file, "r") as f:
        assert list(np.ravel(f[dataset][()])) == [7] * 48


def test_ctrl_c_is_python_s_again_after_gmsh():
    """gmsh sets SIGINT to the default action while it works (Ctrl-C kills a long mesh); after
    finalize() Python's handler is back, so Ctrl-C in a run that meshed first raises
    KeyboardInterrupt and the run stops cleanly (gmsh 4.15 alone would leave SIG_DFL for good)."""
    import signal
    import gmsh
    from flexbearing.common.fe_stack import gmsh_initialize
    signal.signal(signal.SIGINT, signal.default_int_handler)     # Python's (a test may have left gmsh's)
    gmsh_initialize(gmsh)
    gmsh.finalize()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_gmsh_initialises_off_the_main_thread(tmp_path):
    """A Dask worker builds a reduced cage on a task thread: gmsh must start there (gmsh >= 4.9
    installs its SIGINT handler in initialize(), which Python allows on the main thread only)."""
    import gmsh
    from flexbearing.common.fe_stack import gmsh_initialize
    errors = []

    def work():
        try:
            gmsh_initialize(gmsh)
            try:
                gmsh.option.setNumber("General.Terminal", 0)
                gmsh.model.add("box")
                gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
                gmsh.model.occ.synchronize()
                errors.append(len(gmsh.model.getEntities(2)))
            finally:
                gmsh.finalize()
        except Exception as exc:                    # noqa: BLE001 (reported by the assert)
            errors.append(exc)

    t = threading.Thread(target=work)
    t.start()
    t.join()
    assert errors == [6]                             # a box has 6 faces


def test_reduced_cage_digest_is_the_same_on_both_stacks(tmp_path):
    """A reduced cage written on one stack is read on the other (the cache is shared): its content
    digest takes the root attributes as Python values, since numpy 2 writes np.int64(26) as
    "np.int64(26)" and numpy 1 as "26". Known answer, hashed here by hand from the format
    (flexbearing.fem_cage.reduced_cage.data_digest): name|dtype|shape| and bytes, then k=v;."""
    import hashlib
    import h5py
    from flexbearing.fem_cage.reduced_cage import data_digest
    path = tmp_path / "r.h5"
    with h5py.File(path, "w") as f:
        f["a"] = np.arange(3, dtype="<f8")
        f.attrs["schema_version"] = 5
        f.attrs["content_hash"] = "abc"
        f.attrs["parameters"] = "{}"
        f.attrs["n_modes"] = 26
    h = hashlib.sha256()
    h.update(b"a|<f8|(3,)|" + np.arange(3, dtype="<f8").tobytes())
    h.update(b"schema_version=5;content_hash='abc';parameters='{}';n_modes=26;")
    with h5py.File(path, "r") as f:
        assert data_digest(f) == h.hexdigest()
