"""`flexbearing mesh`: mesh the cage, write FILE.msh and FILE.xdmf (+ .h5) beside it.

Also the cage geometry and mesh options that `modes` and `mesh-study` share (flexbearing.cli.modes).
The work: flexbearing.mesh.cage_mesh (gmsh, quality check and repair, flexbearing.mesh.quality), flexbearing.fem_cage.xdmf.
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

from flexbearing.common.validation import InputError
from flexbearing.common.safe_files import OutputPlan
from flexbearing.mesh.cage_geometry import CAGE_PRESETS
from flexbearing.mesh.cage_mesh import DEFAULT_MESH_SIZE, DEFAULT_ORDER, DEFAULT_POCKET_SIZE
from flexbearing.mesh.quality import mesh_file_quality, require_valid, MIN_JACOBIAN_RATIO
from flexbearing.fem_cage.xdmf import write_mesh_xdmf
from flexbearing.mesh.cage_mesh import build_cage_mesh, mesh_quality_of, quality_path
from flexbearing.mesh.cad_cage import build_cad_cage_mesh


def add_geometry_arguments(p):
    """Cage geometry options shared by mesh/modes/mesh-study (lengths in mm on the command line)."""
    g = p.add_argument_group("cage geometry (mm; default: the paper preset)")
    g.add_argument("--preset", choices=tuple(CAGE_PRESETS), default="paper",
                   help="paper = PAPER_CAGE (multibody's preset), nominal = the assumed defaults, "
                        "calibrated = fitted to Table 8 inside the Table 3 envelope (CALIBRATED_CAGE), "
                        "table8 = 7.0 mm-wall ring that reproduces Table 8, outside the envelope "
                        "(TABLE8_EQUIVALENT_CAGE)")
    g.add_argument("--pocket-diameter-mm", type=float)
    g.add_argument("--land-width-mm", type=float)
    g.add_argument("--relief-depth-mm", type=float)
    g.add_argument("--chamfer-mm", type=float)
    g.add_argument("--bore-chamfer-mm", type=float, help="bore-edge chamfer (default: --chamfer-mm)")
    g.add_argument("--n-pockets", type=int)
    g.add_argument("--scene", metavar="SCENE",
                   help="the cage of this scene: its [cage] (CAD or parametric), derived from its own bearing "
                        "(flexbearing.simulation.derived) with its material; the geometry options then do not apply")


_GEOMETRY_OPTIONS = (("pocket_diameter_mm", "pocket_diameter"), ("land_width_mm", "land_width"),
                     ("relief_depth_mm", "relief_depth"), ("chamfer_mm", "chamfer"),
                     ("bore_chamfer_mm", "bore_chamfer"))


def scene_of(args):
    """The scene of --scene (validated; its derived values printed unless --quiet), or None.
    The geometry options are refused beside it: the scene says the cage."""
    path = getattr(args, "scene", None)
    if not path:
        return None
    given = [o for o, _ in _GEOMETRY_OPTIONS + (("n_pockets", ""),) if getattr(args, o, None) is not None]
    if getattr(args, "preset", "paper") != "paper":
        given.insert(0, "preset")
    if given:
        raise InputError(f"--{given[0].replace('_', '-')}: --scene {path} gives the cage; give its geometry "
                         f"in the scene's [cage] table instead")
    from flexbearing.simulation.scene import load_scene
    from flexbearing.simulation.derived import guidance_words
    scene = load_scene(path)
    if not getattr(args, "quiet", False):
        from mpi4py import MPI
        if MPI.COMM_WORLD.rank == 0:
            for d in scene.derived:
                if d.key.startswith(("cage.", "bearing.")):
                    print(d.line())
            print(f"cage guidance: {guidance_words(scene.bearing)}")
    return scene


def geometry_from_args(args):
    """The preset's geometry with the options' changes (mm on the command line), validated; or the
    cage of --scene (its bearing's own, flexbearing.simulation.derived)."""
    scene = scene_of(args)
    if scene is not None:
        args._scene = scene
        return scene.bearing.cage.validate()
    g = CAGE_PRESETS[args.preset]
    ch = {}
    for opt, field in _GEOMETRY_OPTIONS:
        v = getattr(args, opt, None)
        if v is not None:
            ch[field] = v * 1e-3
    if getattr(args, "n_pockets", None) is not None:
        ch["n_pockets"] = args.n_pockets
    return g.with_(**ch).validate()


MAX_ELEMENT_SIZE = 0.05     # m: coarser than the cage's section; a larger number is a size in mm


def element_size(text: str) -> float:
    """argparse type of --size/--pocket-size: an element size in metres, in (0, MAX_ELEMENT_SIZE]."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number (an element size in m, e.g. 4e-3)") from None
    if not 0.0 < v <= MAX_ELEMENT_SIZE:
        raise argparse.ArgumentTypeError(f"{v:g} m is outside the allowed range (0, {MAX_ELEMENT_SIZE:g}] m; "
                                         f"sizes are in metres (4 mm = 4e-3)")
    return v


def add_mesh_arguments(p, size: float = DEFAULT_MESH_SIZE, pocket_size: float = DEFAULT_POCKET_SIZE):
    p.add_argument("--size", type=element_size, default=size,
                   help=f"global element size, m (default {size:g})")
    p.add_argument("--pocket-size", type=element_size, default=pocket_size,
                   help=f"element size on the pocket walls, m (default {pocket_size:g})")
    p.add_argument("--order", type=int, default=DEFAULT_ORDER, choices=(1, 2),
                   help="1 = linear tets, 2 = curved quadratic tets (default)")


def quality_line(summary: dict, repair: dict | None) -> str:
    """One line a user reads: element count, the worst Jacobian ratio against its bound, the worst
    scaled Jacobian, and what the repair changed."""
    s = (f"{summary['n_cells']:,} cells, {summary['n_inverted']} inverted, min Jacobian ratio "
         f"{summary['min_jacobian_ratio']:.3f} (bound {summary['bound']:g}), min scaled Jacobian "
         f"{summary['min_scaled_jacobian']:.3f}")
    if repair is not None:
        s += (f"; repaired {repair['n_cells_flattened']} curved cell(s) of "
              f"{repair['quality_before']['n_below_bound']} below the bound "
              f"({repair['quality_before']['n_inverted']} inverted), nodes moved up to "
              f"{repair['max_node_shift_m'] * 1e6:.0f} µm off the surface")
    return s


def cmd_check(path) -> int:
    """`flexbearing mesh --check FILE`: the quality of any mesh file; exit 1 if it would be refused."""
    q = mesh_file_quality(path)
    print(f"{path}: {quality_line(q.summary(), None)}")
    try:
        require_valid(q, MIN_JACOBIAN_RATIO, str(path))
    except InputError as exc:
        print(f"refused: {exc}")
        return 1
    print("valid: every element passes")
    return 0


def cmd_mesh(args) -> int:
    from mpi4py import MPI
    if args.check:
        return cmd_check(Path(args.check))
    if not args.output:
        raise InputError("flexbearing mesh: give -o/--output FILE.msh (or --check FILE to check a mesh)")
    plan = planned_outputs(args).check()          # before any work: the one output rule
    out = mesh_output(args)
    t0 = time.perf_counter()
    if args.cad:
        if getattr(args, "scene", None):
            raise InputError(f"--cad: --scene {args.scene} gives the cage (its [cage] cad key for a CAD cage)")
        return cmd_mesh_cad(args, out, t0, plan)
    g = geometry_from_args(args)
    scene = getattr(args, "_scene", None)
    if scene is not None and scene.cad:
        return cmd_mesh_cad(args, out, t0, plan, scene)
    with plan.writing():                          # written beside, renamed into place when whole
        staged = plan.staged(out)                 # every rank (the staging folder is shared)
        if MPI.COMM_WORLD.rank == 0:
            build_cage_mesh(g, args.size, args.order, staged, pocket_size=args.pocket_size)
        MPI.COMM_WORLD.barrier()
        write_mesh_xdmf(staged)
    x = out.with_suffix(".xdmf")
    if not args.quiet and MPI.COMM_WORLD.rank == 0:
        print(f"wrote {out} and {x} ({time.perf_counter() - t0:.1f} s; size {args.size:g} m, "
              f"pocket size {args.pocket_size:g} m, order {args.order})")
        rep = mesh_quality_of(out)
        print("quality: " + quality_line(rep["quality"], rep["repair"]))
    return 0


def mesh_output(args) -> Path:
    """The .msh that `mesh -o` names (a name without .msh gets it)."""
    out = Path(args.output)
    return out if out.suffix == ".msh" else out.with_suffix(".msh")


def planned_outputs(args) -> OutputPlan:
    """Every file `flexbearing mesh -o X.msh` writes: X.msh, its quality sidecar and the XDMF
    pair X.xdmf + X.h5 (flexbearing.fem_cage.xdmf.write_mesh_xdmf: the .msh's stem)."""
    from mpi4py import MPI
    out = mesh_output(args)
    plan = OutputPlan("flexbearing mesh", inputs=[args.cad], comm=MPI.COMM_WORLD)
    for path in (out, quality_path(out), out.with_suffix(".xdmf"), out.with_suffix(".h5")):
        plan.file(path, "-o")
    return plan


def cmd_mesh_cad(args, out: Path, t0: float, plan: OutputPlan, scene=None) -> int:
    """`flexbearing mesh --cad CAGE.step -o cage.msh`: find the pockets and the land, match them
    to the bearing (the paper's, with --n-balls/--pitch-diameter-mm/--ball-diameter-mm changes),
    mesh and check; print what was found."""
    from mpi4py import MPI
    from flexbearing.multibody.bearing import PAPER_BEARING
    n_balls = args.n_balls or PAPER_BEARING.n_balls
    dm = args.pitch_diameter_mm * 1e-3 if args.pitch_diameter_mm else PAPER_BEARING.pitch_diameter
    dw = args.ball_diameter_mm * 1e-3 if args.ball_diameter_mm else PAPER_BEARING.ball_diameter
    file, guidance, unit, material = args.cad, args.guidance, args.cad_unit, None
    if scene is not None:             # the scene's CAD cage, matched to the scene's own bearing
        b = scene.bearing
        n_balls, dm, dw = b.n_balls, b.pitch_diameter, b.ball_diameter
        file, guidance, unit, material = scene.cad["file"], b.cage.guidance, scene.cad.get("unit"), b.cage.material
    cad = None
    with plan.writing():                          # written beside, renamed into place when whole
        staged = plan.staged(out)                 # every rank (the staging folder is shared)
        if MPI.COMM_WORLD.rank == 0:
            cad = build_cad_cage_mesh(file, staged, n_balls, dm, dw, guidance, unit,
                                      args.size, args.pocket_size, args.order, material=material)
        MPI.COMM_WORLD.barrier()
        write_mesh_xdmf(staged)
    x = out.with_suffix(".xdmf")
    if not args.quiet and MPI.COMM_WORLD.rank == 0:
        print("\n".join(cad.report_lines(dm, dw)))
        print(f"wrote {out} and {x} ({time.perf_counter() - t0:.1f} s; size {args.size:g} m, "
              f"pocket size {args.pocket_size:g} m, order {args.order})")
        rep = mesh_quality_of(out)
        print("quality: " + quality_line(rep["quality"], rep["repair"]))
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("mesh", help="mesh the cage (gmsh): FILE.msh + FILE.xdmf",
                              description="Mesh the cage with gmsh (tagged pockets, guide, volume). "
                              "Every mesh is checked (Jacobian of each curved tetrahedron) and its "
                              "badly curved elements repaired (flexbearing.mesh.quality).")
    add_geometry_arguments(p)
    add_mesh_arguments(p)
    p.add_argument("-o", "--output", help="output .msh file (XDMF and FILE.quality.json written beside it)")
    p.add_argument("--check", metavar="FILE", help="only check an existing mesh file: every tetrahedron's "
                   "Jacobian (inverted, badly curved) and shape; exit 1 if flexbearing would refuse it")
    c = p.add_argument_group("a cage from CAD (STEP/BREP): pockets and land found from the geometry, "
                             "or from the file's named groups (a gmsh .geo naming the faces: docs/cage.md)")
    c.add_argument("--cad", metavar="FILE", help="mesh this STEP (.step/.stp) or BREP (.brep) cage, or a gmsh "
                   ".geo that merges one and names its faces, instead of the parametric one")
    c.add_argument("--cad-unit", choices=("m", "mm", "cm", "in"), default=None,
                   help="length unit of the CAD file (default: a STEP file's own; a BREP file needs it)")
    c.add_argument("--guidance", choices=("outer", "inner", "balls"), default="outer",
                   help="what guides the cage: the outer ring's land (outside), the inner ring's (bore), the balls")
    c.add_argument("--n-balls", type=int, default=None, help="balls of the bearing (default: the paper's 20)")
    c.add_argument("--pitch-diameter-mm", type=float, default=None, help="default: the paper's 167 mm")
    c.add_argument("--ball-diameter-mm", type=float, default=None, help="default: the paper's 22 mm")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_mesh)
