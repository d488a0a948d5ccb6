"""XDMF files for ParaView: the tagged cage mesh, its FE mode shapes, the reduced cage's kept modes.

`write_mesh_xdmf`: the .msh read with dolfinx, mesh + cell and facet tags (`flexbearing mesh`).

`write_modes_xdmf`: mode shapes, one XDMF/HDF5 pair, one "time step" per mode (`flexbearing modes
--xdmf`). Fields per step: "displacement" (the M-normalised mode shape phi, phi^T M phi = 1, so its
unit is m/sqrt(kg)) and "von_mises" (sigma_vM of that displacement field, Pa/sqrt(kg)).
The step value is the mode number (1-based), so ParaView's time slider walks the modes;
a JSON sidecar lists the frequency of each step.
Fields are interpolated to Lagrange of the geometry's degree (2 on a curved quadratic mesh)
and written on that space's own nodes as tetra10 cells with meshio: dolfinx 0.5.2's
XDMFFile.write_function re-evaluates fields by Newton pull-back, which fails on coarse
curved cells. Under MPI each rank's cells (with their ghost nodes duplicated) are gathered to
rank 0: fine for viewing.

`write_reduced_cage_xdmf`: the kept modes of a reduced cage file (vertex displacement and von
Mises per mode; `flexbearing reduce --xdmf`), from the file alone.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
from .stress_modes import von_mises

# basix P2 tetrahedron dof order (vertices, then edges (2,3),(1,3),(1,2),(0,3),(0,2),(0,1))
# to VTK/XDMF tetra10 (vertices, then edges (0,1),(1,2),(0,2),(0,3),(1,3),(2,3)).
_TET10_FROM_BASIX = [0, 1, 2, 3, 9, 6, 8, 7, 5, 4]


def write_mesh_xdmf(msh_path) -> Path:
    """Read the .msh with dolfinx and write mesh + cell/facet tags to the same stem .xdmf."""
    from flexbearing.common.fe_stack import MPI, XDMFFile, write_meshtags
    from .elasticity import load_cage_mesh
    domain, cell_tags, facet_tags, names = load_cage_mesh(msh_path, MPI.COMM_WORLD)
    out = Path(msh_path).with_suffix(".xdmf")
    domain.topology.create_connectivity(domain.topology.dim - 1, domain.topology.dim)
    with XDMFFile(domain.comm, str(out), "w") as xf:
        xf.write_mesh(domain)
        cell_tags.name = "cell_tags"
        facet_tags.name = "facet_tags"
        write_meshtags(xf, cell_tags, domain)
        write_meshtags(xf, facet_tags, domain)
    return out


def write_modes_xdmf(path, V, vecs, freqs_hz, material, labels=None) -> Path:
    import meshio
    from flexbearing.common.fe_stack import (fem, vector_space, scalar_space, geometry_degree, cell_dofs,
                                             expression, petsc_vector)
    from .elasticity import von_mises_expression

    path = Path(path).with_suffix(".xdmf")
    domain = V.mesh
    comm = domain.comm
    gdeg = geometry_degree(domain)
    W = vector_space(domain, "Lagrange", gdeg)
    Q = scalar_space(domain, "Lagrange", gdeg)
    u, uo, vm = fem.Function(V), fem.Function(W), fem.Function(Q)
    vm_expr = expression(von_mises_expression(u, material), Q)
    points = W.tabulate_dof_coordinates()
    assert np.allclose(points, Q.tabulate_dof_coordinates())      # same node layout
    cells = cell_dofs(Q)
    if gdeg == 2:
        cells, ctype = cells[:, _TET10_FROM_BASIX], "tetra10"
    else:
        ctype = "tetra"
    npts = len(points)

    def gathered(arr):
        parts = comm.gather(arr, root=0)
        return np.concatenate(parts) if comm.rank == 0 else None

    offsets = comm.gather(npts, root=0)
    if comm.rank == 0:
        starts = np.concatenate([[0], np.cumsum(offsets)[:-1]])
    all_cells = comm.gather(cells, root=0)
    all_points = gathered(points)
    if comm.rank == 0:
        all_cells = np.concatenate([c + s for c, s in zip(all_cells, starts)])
        path = path.resolve()
        path.parent.mkdir(parents=True, exist_ok=True)
        # meshio 5.0 opens the .h5 relative to the working directory: write from path's folder.
        cwd = os.getcwd()
        os.chdir(path.parent)
        writer = meshio.xdmf.TimeSeriesWriter(path.name)
        writer.__enter__()
        writer.write_points_cells(all_points, [(ctype, all_cells)])
    try:
        for i, vec in enumerate(vecs):
            vec.copy(petsc_vector(u))
            u.x.scatter_forward()
            uo.interpolate(u)
            vm.interpolate(vm_expr)
            disp = gathered(uo.x.array.reshape(-1, 3)[:npts])
            von = gathered(vm.x.array[:npts])
            if comm.rank == 0:
                writer.write_data(float(i + 1), point_data={"displacement": disp, "von_mises": von})
    finally:
        if comm.rank == 0:
            writer.__exit__(None, None, None)
            os.chdir(cwd)
    if comm.rank == 0:
        meta = {"modes": [{"step": i + 1, "frequency_hz": float(f),
                           **({"label": labels[i]} if labels else {})}
                          for i, f in enumerate(freqs_hz)],
                "fields": {"displacement": "M-normalised mode shape, m/sqrt(kg)",
                           "von_mises": "von Mises stress of the mode shape, Pa/sqrt(kg)"}}
        path.with_suffix(".json").write_text(json.dumps(meta, indent=1))
    comm.barrier()
    return path


def write_reduced_cage_xdmf(rc, path, n_keep: int | None = None) -> Path:
    """Mode shapes (vertex displacement, m per unit q) and von Mises of each kept mode on the
    vertex mesh, one XDMF (+ .h5) readable by ParaView. Reads only the reduced cage object."""
    import meshio
    m = rc.n_modes if n_keep is None else min(n_keep, rc.n_modes)
    pd = {}
    for k in range(m):
        tag = f"mode_{k + 1:03d}_{rc.frequency_hz[k]:.1f}Hz"
        pd[f"{tag}_displacement"] = rc.vertex_displacement[:, :, k]
        pd[f"{tag}_von_mises"] = von_mises(rc.stress_modes[:, :, k])
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    cells = rc.tets10 if rc.tets10 is not None else rc.tets
    kind = {4: "tetra", 10: "tetra10"}[cells.shape[1]]
    meshio.write(path, meshio.Mesh(rc.vertices, [(kind, cells)], point_data=pd))
    return path
