"""Mode shapes for ParaView: one XDMF/HDF5 pair, one "time step" per mode.

Fields per step: "displacement" (the M-normalised mode shape phi, phi^T M phi = 1, so its
unit is m/sqrt(kg)) and "von_mises" (sigma_vM of that displacement field, Pa/sqrt(kg)).
The step value is the mode number (1-based), so ParaView's time slider walks the modes;
a JSON sidecar lists the frequency of each step.
Fields are interpolated to Lagrange of the geometry's degree (2 on a curved quadratic mesh)
and written on that space's own nodes as tetra10 cells with meshio: dolfinx 0.5.2's
XDMFFile.write_function re-evaluates fields by Newton pull-back, which fails on coarse
curved cells. Under MPI each rank's cells (with their ghost nodes duplicated) are gathered to
rank 0: fine for viewing.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

# basix P2 tetrahedron dof order (vertices, then edges (2,3),(1,3),(1,2),(0,3),(0,2),(0,1))
# to VTK/XDMF tetra10 (vertices, then edges (0,1),(1,2),(0,2),(0,3),(1,3),(2,3)).
_TET10_FROM_BASIX = [0, 1, 2, 3, 9, 6, 8, 7, 5, 4]


def write_modes_xdmf(path, V, vecs, freqs_hz, material, labels=None) -> Path:
    import meshio
    from dolfinx import fem
    from .elasticity import von_mises_expression

    path = Path(path).with_suffix(".xdmf")
    domain = V.mesh
    comm = domain.comm
    gdeg = domain.geometry.cmap.degree
    W = fem.VectorFunctionSpace(domain, ("Lagrange", gdeg))
    Q = fem.FunctionSpace(domain, ("Lagrange", gdeg))
    u, uo, vm = fem.Function(V), fem.Function(W), fem.Function(Q)
    vm_expr = fem.Expression(von_mises_expression(u, material), Q.element.interpolation_points())
    points = W.tabulate_dof_coordinates()
    assert np.allclose(points, Q.tabulate_dof_coordinates())      # same node layout
    n_cells = domain.topology.index_map(3).size_local
    cells = Q.dofmap.list.array.reshape(-1, Q.dofmap.dof_layout.num_dofs)[:n_cells]
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
            vec.copy(u.vector)
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
