"""`flexbearing reduce`: build (or find in the cache) the reduced cage file and verify it.

The reduction is flexbearing.fem_cage.reduction, its checks flexbearing.fem_cage.reduction_check. The command imports
dolfinx only when it must build; `--xdmf` and `--json` on a cached file without `--check` read
the HDF5 file only.
"""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np

from flexbearing.cli.mesh import element_size
from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP
from flexbearing.fem_cage import reduced_cage as rcf
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.common.validation import require_range, InputError
from flexbearing.common.safe_files import OutputPlan
from flexbearing.fem_cage.reduction import build
import flexbearing.mesh.cage_mesh as cm


def run_scene(args) -> int:
    """`flexbearing reduce --scene SCENE`: the reduced cage the scene's run uses (its cage, CAD or
    parametric, mesh size and FE degree), built once and cached under the run's own key."""
    from flexbearing.simulation.scene import load_scene
    from flexbearing.coupling.flexible_cage import reduced_cage_path
    from flexbearing.simulation.derived import guidance_words
    scene = load_scene(args.scene)
    if not args.quiet:                 # the cage's derived values (its bearing's own, not the paper's)
        for d in scene.derived:
            if d.key.startswith("cage."):
                print(d.line())
        print(f"cage guidance: {guidance_words(scene.bearing)}")
    if scene.cad and not args.quiet:
        print("\n".join(scene.cad["report"]))
    path = reduced_cage_path(scene, quiet=args.quiet)
    rc = rcf.read(path)
    if not args.quiet:
        print(f"reduced cage: {path} ({path.stat().st_size / 1e6:.1f} MB)")
        print(f"  {rc.n_modes} modes stored; elastic {np.round(rc.frequency_hz[6:16], 1).tolist()} Hz ...")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("reduce", help="build the reduced (Craig–Bampton) cage file, or find it in the cache",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=element_size, default=None, help="global element size, m (default: mesh default)")
    p.add_argument("--pocket-size", type=element_size, default=None, help="element size on the pocket walls, m")
    p.add_argument("--order", type=int, default=None, help="geometric mesh order 1|2 (default 2, curved)")
    p.add_argument("--degree", type=int, default=None, help="Lagrange degree of the FE space (default: flexbearing.mesh.cage_mesh.DEFAULT_DEGREE)")
    p.add_argument("--coupling", choices=("rbe2", "rbe3"), default=None,
                   help="pocket coupling: rbe3 distributing (default, adds no stiffness) or rbe2 rigid")
    p.add_argument("--n-fixed", type=int, default=None, help="fixed-interface normal modes (default 30)")
    p.add_argument("--no-centrifugal-vector", dest="centrifugal", action="store_false",
                   help="do not augment the basis with the fixed-interface centrifugal response "
                        "(then the full basis is statically exact for pocket loads only)")
    p.add_argument("--no-guide-vectors", dest="guide_loads", action="store_false",
                   help="do not augment the basis with the fixed-interface responses to the unit "
                        "land (guide-surface) loads")
    p.add_argument("--no-inertia-relief-vectors", dest="inertia_relief", action="store_false",
                   help="do not augment the basis with the fixed-interface responses to the six "
                        "rigid-body inertia loads (then loads with a net force are not statically "
                        "exact in the free cage)")
    p.add_argument("--n-keep", type=int, default=DEFAULT_N_KEEP,
                   help=f"modes the runtime keeps, rigid included (default {DEFAULT_N_KEEP})")
    p.add_argument("--force", action="store_true", help="rebuild even if cached")
    p.add_argument("--check", action="store_true", help="run the verification (needs dolfinx)")
    p.add_argument("--json", type=Path, default=None, help="write the summary (checks, frequencies, costs) here")
    p.add_argument("--xdmf", type=Path, default=None, help="write kept modes' shapes and von Mises for ParaView")
    p.add_argument("-o", "--output", type=Path, default=None, help="also copy the reduced cage file here")
    p.add_argument("--scene", type=Path, default=None,
                   help="reduce the cage of this scene (its [cage] table: cad, geometry, mesh_size, "
                        "element_order) as its run will; the other options then do not apply")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=run)


def reduced_xdmf_files(xdmf) -> list[Path]:
    """The files of `reduce --xdmf X.xdmf`: X.xdmf and its heavy data X.h5 (meshio's XDMF writer,
    flexbearing.fem_cage.xdmf.write_reduced_cage_xdmf)."""
    x = Path(xdmf)
    return [x, x.with_suffix(".h5")]


def planned_outputs(args, cached: Path | None = None) -> OutputPlan:
    """Every file `flexbearing reduce` writes besides the cache: -o (a copy of the reduced cage
    file), --json, --xdmf's two. cached: the cache entry the run reads (an input: -o onto it, or a
    hard link to it, is refused). With --scene none of them is written."""
    plan = OutputPlan("flexbearing reduce", inputs=[cached, getattr(args, "scene", None)])
    if getattr(args, "scene", None):
        return plan
    if args.output:
        plan.file(args.output, "-o", h5_kind="reduced cage file")
    if args.json:
        plan.file(args.json, "--json")
    for path in reduced_xdmf_files(args.xdmf) if args.xdmf else ():
        plan.file(path, "--xdmf")
    return plan


def run(args) -> int:
    if getattr(args, "scene", None):
        planned_outputs(args).check()
        return run_scene(args)
    size = cm.DEFAULT_MESH_SIZE if args.size is None else args.size
    pocket = cm.DEFAULT_POCKET_SIZE if args.pocket_size is None else args.pocket_size
    order = cm.DEFAULT_ORDER if args.order is None else args.order
    degree = cm.DEFAULT_DEGREE if args.degree is None else args.degree
    coupling = args.coupling or rcf.DEFAULT_COUPLING
    n_fixed = rcf.DEFAULT_N_FIXED if args.n_fixed is None else args.n_fixed
    require_range("reduce.n_fixed", n_fixed, 0, 2000)
    geometry = PAPER_CAGE.validate()
    centrifugal = getattr(args, "centrifugal", True)
    guide_loads = getattr(args, "guide_loads", True)
    inertia_relief = getattr(args, "inertia_relief", True)
    key = rcf.cache_key(geometry, size, order, pocket, coupling, n_fixed, degree, centrifugal,
                        guide_loads, inertia_relief)
    plan = planned_outputs(args, rcf.cache_path(key)).check()       # before any work
    # used only when built from this key and the cache's mesh for it (provenance)
    path = None if args.force else rcf.find_cached(key, cm.cache_path(geometry, size, order, pocket))
    summary = None
    if path is None or args.check:
        path, red, summary = build(geometry, size, order, pocket, coupling, n_fixed,
                                   quiet=args.quiet, checks=args.check or args.json is not None,
                                   n_keep=args.n_keep, degree=degree, centrifugal=centrifugal,
                                   guide_loads=guide_loads, inertia_relief=inertia_relief)
    rc = rcf.read(path)
    if rc.n_modes < args.n_keep:
        raise InputError(f"reduce.n_keep = {args.n_keep} is outside the allowed range [1, {rc.n_modes}]")
    if not args.quiet:
        print(f"reduced cage: {path}")
        print(f"  {rc.n_modes} modes stored ({coupling}, {n_fixed} fixed-interface"
              f"{', centrifugal vector' if centrifugal else ''}"
              f"{', land-load vectors' if guide_loads else ''}"
              f"{', inertia-relief vectors' if inertia_relief else ''}); "
              f"kept {args.n_keep}: elastic {np.round(rc.frequency_hz[6:args.n_keep], 1).tolist()} Hz")
    with plan.writing():            # each written beside its name, renamed into place when whole
        if args.output:
            shutil.copyfile(path, plan.staged(args.output))
        if args.json:
            _write_json(args, rc, path, summary, plan.staged(args.json))
        if args.xdmf:
            from flexbearing.fem_cage.xdmf import write_reduced_cage_xdmf
            write_reduced_cage_xdmf(rc, plan.staged(args.xdmf), args.n_keep)
    return 0


def _write_json(args, rc, path, summary, target) -> None:
    """The --json summary (checks, frequencies, costs) of the reduced cage `path`, to `target`."""
    out = summary if summary is not None else dict(rc.checks)
    out = dict(out)
    out["file"] = str(path)
    out["content_hash"] = str(rc.attrs.get("content_hash"))
    out["n_keep"] = args.n_keep
    out["kept_frequencies_hz"] = rc.frequency_hz[:args.n_keep].tolist()
    Path(target).write_text(json.dumps(out, indent=1, default=rcf._jsonable))
