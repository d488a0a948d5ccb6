"""A cage the project has not seen, drawn with gmsh's OpenCASCADE API and written as STEP or BREP:
the test and benchmark input of the CAD pipeline (flexbearing.mesh.cad_cage; tests/test_cad_cage.py,
benchmarks/results/cad_cage_pipeline.md).

A plain ring, outside 176 mm, bore 158 mm, width 26 mm (numbers in millimetres, as a STEP file
declares them), with 14 spherical pockets of 22.4 mm centred on the 167 mm pitch circle of the
paper's bearing, turned 7° so that no pocket sits at +y. Guided by the inner ring's land
(the scene says so: guidance is a property of the bearing's arrangement, not of the file).
"""
from __future__ import annotations

import math

Z, OD, BORE, WIDTH, PITCH, DP, TURN = 14, 176.0, 158.0, 26.0, 167.0, 22.4, 7.0   # mm, degrees


def make_cad_cage(path, z: int = Z, pitch: float = PITCH, dp: float = DP, sphere_offset_mm: float = 0.0,
                  scale: float = 1.0, shape: str = "spherical"):
    """Write the test cage to `path` (.step in mm, or .brep in mm·scale); pocket 3 moved radially
    by sphere_offset_mm (a pocket off the pitch circle, for the refusal); shape "cylindrical":
    radial cylinders through the ring instead of the spheres. Returns the path."""
    import gmsh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        outer = occ.addCylinder(-WIDTH / 2, 0, 0, WIDTH, 0, 0, OD / 2)
        inner = occ.addCylinder(-WIDTH / 2, 0, 0, WIDTH, 0, 0, BORE / 2)
        ring, _ = occ.cut([(3, outer)], [(3, inner)])
        tools = []
        for k in range(z):
            th = 2 * math.pi * k / z + math.radians(TURN)
            if shape == "cylindrical":
                r0, length = BORE / 2 - 5.0, (OD - BORE) / 2 + 10.0
                tools.append((3, occ.addCylinder(0, r0 * math.cos(th), r0 * math.sin(th),
                                                 0, length * math.cos(th), length * math.sin(th), dp / 2)))
                continue
            r = pitch / 2 + (sphere_offset_mm if k == 3 else 0.0)
            tools.append((3, occ.addSphere(0, r * math.cos(th), r * math.sin(th), dp / 2)))
        ring, _ = occ.cut(ring, tools)
        if scale != 1.0:
            occ.dilate(ring, 0, 0, 0, scale, scale, scale)
        occ.synchronize()
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path
