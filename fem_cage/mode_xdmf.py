"""Mode shapes for ParaView: one XDMF/HDF5 pair, one "time step" per mode.

Fields per step: "displacement" (the M-normalised mode shape phi, phi^T M phi = 1, so its
unit is m/sqrt(kg)) and "von_mises" (sigma_vM of that displacement field, Pa/sqrt(kg)).
The step value is the mode number (1-based), so ParaView's time slider walks the modes;
a JSON sidecar lists the frequency of each step.
XDMF needs the field on the mesh's own nodes: fields are interpolated to Lagrange of the
geometry's degree (2 on a curved quadratic mesh, 1 on a linear one).
"""
from __future__ import annotations

import json
from pathlib import Path


def write_modes_xdmf(path, V, vecs, freqs_hz, material, labels=None) -> Path:
    from dolfinx import fem
    from dolfinx.io import XDMFFile
    from .elasticity import von_mises_field

    path = Path(path).with_suffix(".xdmf")
    path.parent.mkdir(parents=True, exist_ok=True)
    domain = V.mesh
    gdeg = domain.geometry.cmap.degree
    W = fem.VectorFunctionSpace(domain, ("Lagrange", gdeg))
    u = fem.Function(V)
    uo = fem.Function(W, name="displacement")
    with XDMFFile(domain.comm, str(path), "w") as xf:
        xf.write_mesh(domain)
        for i, vec in enumerate(vecs):
            vec.copy(u.vector)
            u.x.scatter_forward()
            uo.interpolate(u)
            vm = von_mises_field(u, material, degree=gdeg)
            xf.write_function(uo, float(i + 1))
            xf.write_function(vm, float(i + 1))
    if domain.comm.rank == 0:
        meta = {"modes": [{"step": i + 1, "frequency_hz": float(f),
                           **({"label": labels[i]} if labels else {})}
                          for i, f in enumerate(freqs_hz)],
                "fields": {"displacement": "M-normalised mode shape, m/sqrt(kg)",
                           "von_mises": "von Mises stress of the mode shape, Pa/sqrt(kg)"}}
        path.with_suffix(".json").write_text(json.dumps(meta, indent=1))
    return path
