"""`flexbearing modes | mesh-study | calibrate-cage`: the cage's free–free modal analysis.

The work: flexbearing.fem_cage.modes (run_modes, mode_table), flexbearing.fem_cage.mesh_study, flexbearing.fem_cage.calibrate.
"""
from __future__ import annotations

import dataclasses
import json
import time

import numpy as np
from pathlib import Path

from flexbearing.cli.mesh import MAX_ELEMENT_SIZE, add_geometry_arguments, add_mesh_arguments, geometry_from_args
from flexbearing.mesh.cage_geometry import CAGE_PRESETS
from flexbearing.mesh.cage_mesh import DEFAULT_DEGREE
from flexbearing.mesh.cage_mesh import cached_cage_mesh, cache_path
from flexbearing.common.validation import require_range, InputError
from flexbearing.common.safe_files import OutputPlan, write_text_atomic
from flexbearing.fem_cage.modes import MAX_N_MODES, mode_table, run_modes
from flexbearing.fem_cage.mesh_study import run_mesh_study, DEFAULT_STUDY
from flexbearing.fem_cage.calibrate import run_calibration


def _comm():
    from mpi4py import MPI
    return MPI.COMM_WORLD


def mesh_for(args, g) -> Path:
    """The .msh to use: --mesh FILE, else the cached mesh for (geometry, size, order) (a --scene's
    CAD cage: its cached CAD mesh, matched to the scene's bearing)."""
    comm = _comm()
    if getattr(args, "mesh", None):
        return Path(args.mesh)
    size, ps = args.size, args.pocket_size
    scene = getattr(args, "_scene", None)
    if scene is not None and scene.cad:
        from flexbearing.mesh.cad_cage import cached_cad_cage_mesh
        b = scene.bearing
        path = None
        if comm.rank == 0:
            path, _ = cached_cad_cage_mesh(scene.cad["file"], b.n_balls, b.pitch_diameter, b.ball_diameter,
                                           b.cage.guidance, scene.cad.get("unit"), b.cage.material, size, ps,
                                           args.order)
        return Path(comm.bcast(str(path) if path else None, root=0))
    if comm.rank == 0:
        cached_cage_mesh(g, size, args.order, ps)
    comm.barrier()
    return cache_path(g, size, args.order, ps)


def modes_xdmf_files(xdmf) -> list[Path]:
    """The files of `modes --xdmf X`: X.xdmf, its heavy data X.h5 and the frequencies X.json
    (flexbearing.fem_cage.xdmf.write_modes_xdmf)."""
    x = Path(xdmf).with_suffix(".xdmf")
    return [x, x.with_suffix(".h5"), x.with_suffix(".json")]


def planned_outputs(args) -> OutputPlan:
    """Every file `flexbearing modes` writes: --json, and --xdmf's three (modes_xdmf_files)."""
    plan = OutputPlan("flexbearing modes", inputs=[getattr(args, "mesh", None)], comm=_comm())
    if args.json:
        plan.file(args.json, "--json")
    for path in modes_xdmf_files(args.xdmf) if args.xdmf else ():
        plan.file(path, "--xdmf")
    return plan


def cmd_modes(args) -> int:
    require_range("modes.n_modes", args.n_modes, 7, MAX_N_MODES)       # before any mesh or FE work
    plan = planned_outputs(args).check()
    comm = _comm()
    t0 = time.perf_counter()
    g = geometry_from_args(args)
    path = mesh_for(args, g)
    tm = time.perf_counter() - t0
    res, V, vecs = run_modes(g, path, args.degree, args.n_modes, classify=not args.no_classify,
                             quiet=args.quiet)
    res["timing_s"]["mesh"] = tm
    res["wall_s"] = time.perf_counter() - t0
    scene = getattr(args, "_scene", None)
    if getattr(args, "mesh", None) or (scene is not None and scene.cad):
        # the mesh's own geometry, measured from its nodes (not the preset's numbers)
        geometry = measured_mesh_geometry(path)
        res["mesh"] = {"file": str(path), "order": args.order, "degree": args.degree, "geometry": geometry}
    else:
        res["mesh"] = {"file": str(path), "size_m": args.size, "pocket_size_m": args.pocket_size,
                       "order": args.order, "degree": args.degree, "geometry": g.to_dict()}
    res["material"] = {**dataclasses.asdict(g.material), "source": material_source(args, g)}
    labels = [m["label"] for m in res["modes"]] if "modes" in res else None
    if args.xdmf:
        from flexbearing.fem_cage.xdmf import write_modes_xdmf
        x = modes_xdmf_files(args.xdmf)[0]
        with plan.writing():
            write_modes_xdmf(plan.staged(x), V, vecs, res["frequencies_hz"], g.material, labels)
        res["xdmf"] = str(x)
    if comm.rank == 0:
        if not args.quiet:
            # Table 8 is the paper's cage: compared only for a preset's geometry meshed here
            paper = not getattr(args, "mesh", None) and g in CAGE_PRESETS.values()
            if not paper:
                print(f"cage from {args.mesh or 'the options'}: not the paper's cage, no Table 8 comparison")
            print(mode_table(res["frequencies_hz"], labels, paper=paper))
            geo = res["mesh"]["geometry"]
            print(f"cage: outside Ø {geo['outside_diameter'] * 1e3:.2f} mm, bore Ø {geo['bore_diameter'] * 1e3:.2f} mm, "
                  f"width {geo['width'] * 1e3:.2f} mm"
                  + (f", {geo['n_pockets']} pockets" if geo.get("n_pockets") else "")
                  + (" (measured from the mesh's nodes)" if "source" in geo else " (the geometry meshed)"))
            m = res["material"]
            print(f"material: {m['density']:g} kg/m³, E = {m['youngs_modulus'] / 1e9:g} GPa, ν = "
                  f"{m['poisson_ratio']:g} ({m['source']})")
            print(f"{res['ndofs']} dofs, P{args.degree} on order-{args.order} mesh, {comm.size} MPI rank(s), "
                  f"wall {res['wall_s']:.1f} s (mesh {tm:.1f}, assemble {res['timing_s']['assemble']:.1f}, "
                  f"eigensolve {res['timing_s']['eigensolve']:.1f})")
            if args.xdmf:
                print(f"mode shapes: {res['xdmf']}")
        if args.json:
            write_text_atomic(args.json, json.dumps(res, indent=1, default=float))
    return 0


def planned_mesh_study_outputs(args) -> OutputPlan:
    """Every file `flexbearing mesh-study -o DIR` writes (flexbearing.fem_cage.mesh_study:
    mesh_study.csv, .json, .png), checked before any work (written in place, not staged)."""
    plan = OutputPlan("flexbearing mesh-study")
    plan.folder(args.output, "-o", names=("mesh_study.csv", "mesh_study.json", "mesh_study.png"))
    return plan


def planned_calibrate_outputs(args) -> OutputPlan:
    """Every file `flexbearing calibrate-cage -o DIR` writes (flexbearing.fem_cage.calibrate: the
    evaluations log, calibration.json, calibration.md), checked before any work (written in place)."""
    plan = OutputPlan("flexbearing calibrate-cage")
    plan.folder(args.output, "-o", names=("evaluations.jsonl", "calibration.json", "calibration.md"))
    return plan


def measured_mesh_geometry(path) -> dict:
    """The cage's outside and bore diameters and width measured from a mesh file's nodes (m; the
    largest and smallest distance from the bearing axis x, the axial extent; the nodes lie on the
    surfaces), and its pockets counted from the physical groups named pocket*."""
    import gmsh
    from flexbearing.common.fe_stack import gmsh_initialize
    gmsh_initialize(gmsh)  # gmsh 4.8 has no isInitialized(): own the session for this call
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        _, xyz, _ = gmsh.model.mesh.getNodes()
        names = [gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups(2)]
    finally:
        gmsh.finalize()
    P = np.asarray(xyz, dtype=float).reshape(-1, 3)
    r = np.hypot(P[:, 1], P[:, 2])
    pockets = sum(1 for n in names if n.lower().startswith("pocket") and n.lower() != "pockets")
    return {"outside_diameter": float(2.0 * r.max()), "bore_diameter": float(2.0 * r.min()),
            "width": float(np.ptp(P[:, 0])), "n_pockets": pockets, "n_nodes": int(P.shape[0]),
            "source": "measured from the mesh's nodes (m): 2·max and 2·min distance from the x axis, x extent"}


def material_source(args, g) -> str:
    """Where the cage material came from, in words."""
    scene = getattr(args, "_scene", None)
    if scene is not None:
        given = "material" in scene.data.get("cage", {})
        return "the scene's [cage.material]" if given else "the paper's 40CrNiMoA, the scene's default"
    return f"the preset '{args.preset}': 40CrNiMoA, the paper's cage steel (--scene for another material)"


def cmd_mesh_study(args) -> int:
    require_range("mesh-study.n_modes", args.n_modes, 7, MAX_N_MODES)
    planned_mesh_study_outputs(args).check()
    g = geometry_from_args(args)
    levels = DEFAULT_STUDY if not args.levels else [_level(s) for s in args.levels]
    run_mesh_study(g, levels, Path(args.output), n_modes=args.n_modes, quiet=args.quiet)
    return 0


def _level(text: str) -> tuple:
    """--levels SIZE,POCKET,ORDER,DEGREE (sizes in m, as every --size) -> flexbearing.fem_cage.mesh_study's level
    (sizes in mm)."""
    try:
        size, pocket, order, degree = (float(x) for x in text.split(","))
    except ValueError:
        raise InputError(f"--levels {text!r}: give SIZE,POCKET,ORDER,DEGREE, sizes in m (e.g. 4e-3,2e-3,2,3)") from None
    for v in (size, pocket):
        if not 0.0 < v <= MAX_ELEMENT_SIZE:
            raise InputError(f"--levels {text!r}: size {v:g} m is outside the allowed range "
                             f"(0, {MAX_ELEMENT_SIZE:g}] m; sizes are in metres (4 mm = 4e-3)")
    return (size * 1e3, pocket * 1e3, int(order), int(degree))


def cmd_calibrate(args) -> int:
    planned_calibrate_outputs(args).check()
    run_calibration(Path(args.output), size=args.size, pocket_size=args.pocket_size,
                    order=args.order, degree=args.degree, params=args.params, quiet=args.quiet,
                    max_evals=args.max_evals)
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("modes", help="free-free modes of the cage vs the paper's Table 8",
                              description="Free-free modal analysis of the cage (dolfinx + SLEPc).")
    add_geometry_arguments(p)
    add_mesh_arguments(p)
    p.add_argument("--mesh", help="use this .msh instead of the cached mesh")
    p.add_argument("--degree", type=int, default=DEFAULT_DEGREE, choices=(1, 2, 3),
                   help=f"Lagrange degree (default {DEFAULT_DEGREE}: the converged default, see mesh-study)")
    p.add_argument("--n-modes", type=int, default=27)
    p.add_argument("--json", help="write frequencies, ndofs, wall time, mesh info to this JSON file")
    p.add_argument("--xdmf", help="write mode shapes (displacement, von Mises) to this XDMF file")
    p.add_argument("--no-classify", action="store_true", help="skip the mode-family classification")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_modes)

    p = subparsers.add_parser("mesh-study", help="mesh convergence: frequency vs dofs, CSV + PNG",
                              description="Mesh convergence study of the cage modes.")
    add_geometry_arguments(p)
    p.add_argument("--levels", nargs="+", metavar="SIZE,POCKET,ORDER,DEGREE",
                   help="mesh levels, sizes in m (default: the built-in sequence)")
    p.add_argument("--n-modes", type=int, default=27)
    p.add_argument("-o", "--output", default="out/mesh-study", help="output folder")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_mesh_study)

    p = subparsers.add_parser("calibrate-cage",
                              help="fit unknown cage geometry to the paper's Table 8 (least squares)",
                              description="Model updating of the cage geometry against Table 8.")
    add_mesh_arguments(p, size=8e-3, pocket_size=8e-3)        # the calibration's coarse mesh
    p.add_argument("--degree", type=int, default=3, choices=(1, 2, 3))
    p.add_argument("--params", nargs="+", default=None,
                   help="parameters to fit (default: pocket_diameter chamfer land_width relief_depth)")
    p.add_argument("--max-evals", type=int, default=40)
    p.add_argument("-o", "--output", default="out/calibrate-cage", help="output folder")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_calibrate)
