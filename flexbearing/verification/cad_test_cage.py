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
from pathlib import Path

from flexbearing.common import fe_stack

Z, OD, BORE, WIDTH, PITCH, DP, TURN = 14, 176.0, 158.0, 26.0, 167.0, 22.4, 7.0   # mm, degrees
# mm: the elliptical pockets' diameter in the direction of rotation; the model takes at most
# 2A²/(Dw/2) = 22.807 mm with A = DP/2 and the 22 mm ball (the ball fits the ellipse's end curvature)
DC = 22.8


DIMPLE = 2.0        # mm: radius of the spherical dimple on the outside (`make_cad_cage(dimple=True)`)


def make_cad_cage(path, z: int = Z, pitch: float = PITCH, dp: float = DP, sphere_offset_mm: float = 0.0,
                  scale: float = 1.0, shape: str = "spherical", dimple: bool = False,
                  cone_angle_deg: float = 5.0, dc: float = DC, ellipse_turn_deg: float = 0.0,
                  skew_mm: float = 0.0):
    """Write the test cage to `path` (.step in mm, or .brep in mm·scale); pocket 3 moved radially
    by sphere_offset_mm (a pocket off the pitch circle, for the refusal); shape "cylindrical":
    radial cylinders through the ring instead of the spheres; dimple: a spherical dimple of
    DIMPLE mm centred on the outside between pockets 0 and 1 (a sphere the geometric search
    takes for a fifteenth pocket; named groups leave it out).

    shape "conical": radial cones of half-angle cone_angle_deg (> 0 wider at the outside), the
    model's cone of pocket diameter dp (CageGeometry.cone_radius: radius dp/(2 cos β) + s tan β
    at s from the pitch circle, outwards); shape "elliptical": radial cylinders of elliptical
    section, dp along the bearing axis and dc in the direction of rotation, the section turned
    by ellipse_turn_deg about the pocket axis (0: the model's). skew_mm moves pocket 3's tool of
    these two shapes in the direction of rotation, its axis then missing the bearing axis.
    Returns the path."""
    import gmsh
    fe_stack.gmsh_initialize(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        outer = occ.addCylinder(-WIDTH / 2, 0, 0, WIDTH, 0, 0, OD / 2)
        inner = occ.addCylinder(-WIDTH / 2, 0, 0, WIDTH, 0, 0, BORE / 2)
        ring, _ = occ.cut([(3, outer)], [(3, inner)])
        tools = []
        for k in range(z):
            th = 2 * math.pi * k / z + math.radians(TURN)
            if shape in ("conical", "elliptical"):
                tools.append(_radial_tool(occ, shape, th, dp, dc, cone_angle_deg, ellipse_turn_deg,
                                          skew_mm if k == 3 else 0.0))
                continue
            if shape == "cylindrical":
                r0, length = BORE / 2 - 5.0, (OD - BORE) / 2 + 10.0
                tools.append((3, occ.addCylinder(0, r0 * math.cos(th), r0 * math.sin(th),
                                                 0, length * math.cos(th), length * math.sin(th), dp / 2)))
                continue
            r = pitch / 2 + (sphere_offset_mm if k == 3 else 0.0)
            tools.append((3, occ.addSphere(0, r * math.cos(th), r * math.sin(th), dp / 2)))
        if dimple:
            th = math.pi / z + math.radians(TURN)
            tools.append((3, occ.addSphere(0, OD / 2 * math.cos(th), OD / 2 * math.sin(th), DIMPLE)))
        ring, _ = occ.cut(ring, tools)
        if scale != 1.0:
            occ.dilate(ring, 0, 0, 0, scale, scale, scale)
        occ.synchronize()
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def _radial_tool(occ, shape: str, th: float, dp: float, dc: float, cone_angle_deg: float,
                 ellipse_turn_deg: float, skew: float):
    """The tool cutting one conical or elliptical pocket at azimuth th (`make_cad_cage`): from 5 mm
    inside the bore to 5 mm outside the outside, along e_r = (0, cos th, sin th)."""
    r0, length = BORE / 2 - 5.0, (OD - BORE) / 2 + 10.0
    er = (0.0, math.cos(th), math.sin(th))
    t = (0.0, -math.sin(th), math.cos(th))              # the direction of rotation
    if shape == "conical":
        b = math.radians(cone_angle_deg)
        rad = [dp / (2 * math.cos(b)) + (s - PITCH / 2) * math.tan(b) for s in (r0, r0 + length)]
        x0 = [r0 * e + skew * u for e, u in zip(er, t)]
        return (3, occ.addCone(*x0, *(length * e for e in er), rad[0], rad[1]))
    # elliptical: drawn in the local xy plane (x -> t, y -> the bearing axis), extruded along z -> e_r
    big, small = max(dp, dc) / 2, min(dp, dc) / 2
    curve = occ.addEllipse(0, 0, 0, big, small)
    surf = occ.addPlaneSurface([occ.addCurveLoop([curve])])
    spin = (0.0 if dc >= dp else math.pi / 2) + math.radians(ellipse_turn_deg)
    occ.rotate([(2, surf)], 0, 0, 0, 0, 0, 1, spin)
    occ.translate([(2, surf)], skew, 0, r0)
    vol = [dt for dt in occ.extrude([(2, surf)], 0, 0, length) if dt[0] == 3]
    occ.rotate(vol, 0, 0, 0, 0, 0, 1, -math.pi / 2)     # local x -> -y, y -> x
    occ.rotate(vol, 0, 0, 0, 1, 0, 0, th - math.pi / 2)  # -y -> t, z -> e_r
    return vol[0]


def make_named_cad_cage(path, guidance: str = "inner", wrong: str = "", **cage):
    """Write the test cage as STEP (`make_cad_cage(**cage)`, beside `path`) and the gmsh .geo
    `path` that merges it and names its faces by the convention of flexbearing.mesh.cad_cage:
    `pocket_1` … `pocket_Z` (pocket k+1 the faces within a pocket radius of its sphere's centre),
    `guide` (the bore for "inner", the outside for "outer"). The faces are found here from the
    numbers the cage is drawn with (their bounding boxes), independently of the reader.
    `wrong` makes the names disagree with the geometry: "count" (the last pocket group left
    out), "side_as_pocket" (pocket_4 names a side face), "outside_as_guide" (the guide named on
    the outside of an inner-guided cage), "pocket_as_guide" (a pocket face in the guide group).
    Returns the path of the .geo."""
    import gmsh
    path = Path(path)
    step = make_cad_cage(path.with_suffix(".step"), **cage)
    pockets, bore, outside, sides = [[] for _ in range(Z)], [], [], []
    fe_stack.gmsh_initialize(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(str(step))
        gmsh.model.occ.synchronize()
        for _, s in gmsh.model.getEntities(2):
            x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(2, s)
            c = [(x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2]
            if abs(x1 - x0) < 1e-3:
                sides.append(s)
                continue
            for k in range(Z):
                th = 2 * math.pi * k / Z + math.radians(TURN)
                centre = (0.0, PITCH / 2 * math.cos(th), PITCH / 2 * math.sin(th))
                if math.dist(c, centre) < DP / 2 and abs(x1 - x0) < DP + 1e-3 and abs(x1 - x0) < WIDTH - 1e-3:
                    pockets[k].append(s)
                    break
            else:
                if y1 - y0 > BORE - 1e-3:       # a whole ring cylinder: its radius is half its span
                    (outside if (y1 - y0) / 2 > PITCH / 2 else bore).append(s)
    finally:
        gmsh.finalize()
    assert all(len(f) == 1 for f in pockets) and len(bore) == 1 and len(outside) == 1, (pockets, bore, outside)
    guide = bore if guidance == "inner" else outside
    names = [(f"pocket_{k + 1}", f) for k, f in enumerate(pockets)]
    if wrong == "count":
        names = names[:-1]
    elif wrong == "side_as_pocket":
        names[3] = ("pocket_4", [sides[0]])
    elif wrong == "outside_as_guide":
        guide = outside
    elif wrong == "pocket_as_guide":
        guide = guide + pockets[0][:1]
    lines = ['SetFactory("OpenCASCADE");', f'Merge "{step.name}";']
    lines += [f'Physical Surface("{n}") = {{{", ".join(map(str, f))}}};' for n, f in names]
    lines.append(f'Physical Surface("guide") = {{{", ".join(map(str, guide))}}};')
    path.write_text("\n".join(lines) + "\n")
    return path


def mesh_groups(msh_path) -> dict:
    """The physical groups of a cage mesh file, read back with gmsh: {name: (dim, tag, nodes (n, 3)
    in m)} — what the CAD and pocket-shape tests check a mesh's tagging and its pocket nodes with."""
    import gmsh
    import numpy as np
    fe_stack.gmsh_initialize(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(msh_path))
        out = {}
        for d, t in gmsh.model.getPhysicalGroups():
            _, X = gmsh.model.mesh.getNodesForPhysicalGroup(d, t)
            out[gmsh.model.getPhysicalName(d, t)] = (d, t, np.asarray(X).reshape(-1, 3))
        return out
    finally:
        gmsh.finalize()


def calculix_modes_check(step_path, out_msh, n_modes: int = 20) -> dict:
    """The CAD test cage's free–free modes, the project's P2 against CalculiX C3D10 on the same
    5 mm curved mesh (flexbearing.verification.calculix_check.frequency_case; steel of the paper
    cage, inner-land guided, 14 pockets on the 167 mm pitch circle, 22 mm balls)."""
    from flexbearing.mesh.cad_cage import build_cad_cage_mesh
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from .calculix_check import frequency_case, project_model
    build_cad_cage_mesh(step_path, out_msh, Z, PITCH * 1e-3, 22e-3, "inner", size=5e-3, pocket_size=4e-3)
    return frequency_case(project_model(out_msh, PAPER_CAGE.material), PAPER_CAGE.material, n_modes,
                          msh_path=out_msh)
