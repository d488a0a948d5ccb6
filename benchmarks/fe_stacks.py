"""The same answers on both FE stacks: Debian 12 (dolfinx 0.5.2, the reference) and PyPI (dolfinx 0.11).

On ONE mesh of the paper cage (made once, by the Debian stack's gmsh, and copied into the PyPI
stack's cache: the mesh's cache key does not depend on the gmsh version), each stack:

1. assembles K and M (P3) and solves the free-free modes (SLEPc Krylov-Schur, shift-invert,
   relative residual tolerance 1e-9; flexbearing.fem_cage.modes.free_free_modes);
2. builds its reduced cage (Craig-Bampton, flexbearing.coupling.flexible_cage.reduced_cage_path),
   timed;
3. runs the paper's steady flexible scene for 20 ms with its own reduced cage (the integrator's
   tolerance 1e-4, the scene's).

Tolerances, from the methods. Both stacks discretise identically (same mesh, element, quadrature),
so K and M differ by rounding only (the cells are summed in another order: ~1e-16 relative per
entry). A symmetric-definite eigenvalue whose eigenpair has relative residual <= tol is within
tol of the exact one (Bauer-Fike for a symmetric pencil; in practice the Rayleigh quotient is
accurate to ~tol^2), so each stack's frequency f = sqrt(lambda)/(2 pi) is within tol/2 of the
exact f of its matrices and the two stacks' modes 7-26 agree to tol = 1e-9 relative. The two runs
differ by the reduced cages (~1e-9) and by their adaptive step sequences: each step's local error
is held to the integrator tolerance (1e-4 relative), and over 20 ms from the initial state (ball
and cage impacts, a transient) those local errors grow to the run's global error, which is
measured here as the difference from the same stack's run at tolerance 1e-5: the stacks agree to
the integrator's tolerance when their difference is no larger than that, output by output
(`--integrator-reference`, benchmarks/results/fe_stacks_runs.md).

    python benchmarks/fe_stacks.py --debian .venv/bin/python --pypi .venv-pypi/bin/python \
        --work W --reduce-pairs 2                        -> benchmarks/results/fe_stacks.json and .md
    python benchmarks/fe_stacks.py --work W --integrator-reference  -> fe_stacks_runs.json and .md
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results"

MESH = """
import sys
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.mesh.cage_mesh import cached_cage_mesh
print(cached_cage_mesh(PAPER_CAGE))
"""

MODES = """
import json, sys, time
import numpy as np
import flexbearing
from flexbearing.common.fe_stack import MPI, versions
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass, global_ndofs
from flexbearing.fem_cage.modes import free_free_modes
t0 = time.perf_counter()
domain, _, _, _ = load_cage_mesh(sys.argv[1], MPI.COMM_SELF)
V, K, M = assemble_stiffness_mass(domain, PAPER_CAGE.material, 3)
f, vecs, info = free_free_modes(K, M, 27, return_info=True)
print(json.dumps({"frequencies_hz": [float(x) for x in f], "ndofs": global_ndofs(V),
                  "wall_s": time.perf_counter() - t0, "versions": versions(),
                  "solver": info["solver"]}))
"""

REDUCE = """
import json, sys, time
from flexbearing.simulation.scene import load_scene
from flexbearing.coupling.flexible_cage import reduced_cage_path
scene = load_scene(sys.argv[1])
t0 = time.perf_counter()
p = reduced_cage_path(scene, quiet=True)
print(json.dumps({"path": str(p), "wall_s": time.perf_counter() - t0}))
"""


def child_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def call(python: str, code: str, *args, env=None) -> str:
    out = subprocess.run([python, "-c", code, *map(str, args)], capture_output=True, text=True,
                         env=env, cwd=ROOT)
    if out.returncode != 0:
        raise SystemExit(f"{python}: {out.stderr[-3000:]}")
    return out.stdout.strip().splitlines()[-1]


def reduce_pairs(stacks: dict, env: dict, scene: Path, pairs: int) -> dict:
    """New geometry -> reduced cage (the mesh cached, the reduced cage not), the stacks alternating
    (interleaved pairs, so a change of the machine's load hits both alike): the child's CPU time
    (user + sys) and wall time of each, and the median ratio PyPI / Debian of the pairs."""
    out = {s: {"cpu_s": [], "wall_s": []} for s in stacks}
    for _ in range(pairs):
        for s, py in stacks.items():
            shutil.rmtree(Path(env[s]["FLEXBEARING_CACHE"]) / "reduced_cage", ignore_errors=True)
            c0, t0 = child_cpu(), time.perf_counter()
            call(py, REDUCE, scene, env=env[s])
            out[s]["wall_s"].append(time.perf_counter() - t0)
            out[s]["cpu_s"].append(child_cpu() - c0)
            print(s, "reduce", out[s]["wall_s"][-1], out[s]["cpu_s"][-1], flush=True)
    import numpy as np
    for k in ("cpu_s", "wall_s"):
        out[f"median_ratio_pypi_over_debian_{k}"] = float(np.median(
            np.array(out["pypi"][k]) / np.array(out["debian"][k])))
    return out


def scene_20ms(folder: Path) -> Path:
    text = (ROOT / "scenes" / "paper_steady.toml").read_text()
    text = text.replace("duration = 0.6 ", "duration = 0.02 ").replace("duration = 0.6,", "duration = 0.02,")
    text = text.replace("checkpoint_every = 200", "checkpoint_every = 1000")
    p = folder / "steady_20ms.toml"
    p.write_text(text)
    return p


def compare_runs(a: Path, b: Path) -> dict:
    """max |a - b| / max |a| of every recorded output (same sample times)."""
    import h5py
    import numpy as np
    out = {}
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        names = []
        fa["outputs"].visit(lambda n: names.append(n) if isinstance(fa["outputs"][n], h5py.Dataset) else None)
        for n in sorted(names):
            x, y = fa["outputs"][n][()], fb["outputs"][n][()]
            if x.dtype.kind != "f" or x.shape != y.shape:
                continue
            scale = np.nanmax(np.abs(x)) if x.size else 0.0
            if not scale:
                continue
            out[n] = float(np.nanmax(np.abs(x - y)) / scale)
    return out


def integrator_reference(stacks: dict, env: dict, work: Path) -> int:
    """The 20 ms runs against the integrator's own error: the Debian stack's run at the scene's
    tolerance (1e-4) against (a) the PyPI stack's run, (b) the Debian stack at tolerance 1e-5 (the
    integrator's error of the 1e-4 run, to leading order), (c) the Debian stack with the PyPI
    stack's reduced cage. The stacks agree to the integrator's tolerance when (a) is no larger
    than (b), output by output. Uses the reduced cages in the work folder's caches (from a run of
    this script without this flag)."""
    import numpy as np
    scene = scene_20ms(work)
    fine = work / "steady_20ms_tol1e-5.toml"
    fine.write_text(scene.read_text().replace("tolerance = 1e-4", "tolerance = 1e-5"))
    mixed = work / "cache_mixed"
    (mixed / "reduced_cage").mkdir(parents=True, exist_ok=True)
    for f in (work / "cache_pypi" / "reduced_cage").glob("*.h5"):
        shutil.copy2(f, mixed / "reduced_cage" / f.name)
    runs = {"debian": (stacks["debian"], scene, env["debian"]), "pypi": (stacks["pypi"], scene, env["pypi"]),
            "debian_tol1e-5": (stacks["debian"], fine, env["debian"]),
            "debian_pypi_cage": (stacks["debian"], scene, dict(env["debian"], FLEXBEARING_CACHE=str(mixed)))}
    for name, (py, sc, e) in runs.items():
        out = subprocess.run([str(Path(py).parent / "flexbearing"), "run", str(sc), "-o", str(work / f"ref_{name}.h5"),
                              "--quiet", "--force"], capture_output=True, text=True, env=e, cwd=work)
        if out.returncode != 0:
            raise SystemExit(f"{name} run: {out.stderr[-3000:]}")
    cmp = {k: compare_runs(work / "ref_debian.h5", work / f"ref_{k}.h5")
           for k in ("pypi", "debian_tol1e-5", "debian_pypi_cage")}
    ratio = {k: cmp["pypi"][k] / v for k, v in cmp["debian_tol1e-5"].items() if v > 0 and k in cmp["pypi"]}
    res = {"compare": cmp, "ratio_stacks_over_integrator": ratio,
           "median_ratio": float(np.median(list(ratio.values()))), "max_ratio": float(max(ratio.values()))}
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "fe_stacks_runs.json").write_text(json.dumps(res, indent=1))
    lines = ["# 20 ms flexible runs on the two FE stacks against the integrator's own error", "",
             "`python benchmarks/fe_stacks.py --integrator-reference` (after a run without the flag): the paper's "
             "steady flexible scene, 20 ms from its initial state, each output's max |a - b| / max |a| against the "
             "Debian stack's run at the scene's tolerance 1e-4.", "",
             "| output | PyPI stack | Debian at tolerance 1e-5 | Debian with the PyPI reduced cage | PyPI / tol-1e-5 |",
             "|---|---:|---:|---:|---:|"]
    for k in sorted(cmp["pypi"]):
        c = [cmp[x].get(k, float("nan")) for x in ("pypi", "debian_tol1e-5", "debian_pypi_cage")]
        lines.append(f"| {k} | {c[0]:.2e} | {c[1]:.2e} | {c[2]:.2e} | {ratio.get(k, float('nan')):.2f} |")
    lines += ["", f"Ratio (PyPI stack's difference) / (the integrator's error estimate): median "
              f"{res['median_ratio']:.2f}, max {res['max_ratio']:.2f} over the outputs."]
    (OUT / "fe_stacks_runs.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--debian", default=str(ROOT / ".venv" / "bin" / "python"))
    ap.add_argument("--pypi", default=str(ROOT / ".venv-pypi" / "bin" / "python"))
    ap.add_argument("--work", help="work folder (default: a temporary one)")
    ap.add_argument("--skip-run", action="store_true", help="modes and reduction only")
    ap.add_argument("--reduce-pairs", type=int, default=0,
                    help="also time the reduction in this many interleaved Debian/PyPI pairs")
    ap.add_argument("--integrator-reference", action="store_true",
                    help="only the 20 ms runs against the integrator's own error (integrator_reference)")
    args = ap.parse_args(argv)
    work = Path(args.work or tempfile.mkdtemp(prefix="fe_stacks_"))
    stacks = {"debian": args.debian, "pypi": args.pypi}
    env = {s: dict(os.environ, FLEXBEARING_CACHE=str(work / f"cache_{s}")) for s in stacks}
    if args.integrator_reference:
        return integrator_reference(stacks, env, work)
    msh = Path(call(stacks["debian"], MESH, env=env["debian"]))
    (work / "cache_pypi" / "meshes").mkdir(parents=True, exist_ok=True)
    shutil.copy2(msh, work / "cache_pypi" / "meshes" / msh.name)
    res = {"mesh": msh.name, "stacks": {}}
    for s, py in stacks.items():
        c0 = child_cpu()
        res["stacks"][s] = json.loads(call(py, MODES, msh, env=env[s]))
        res["stacks"][s]["cpu_s"] = child_cpu() - c0
        print(s, "modes", res["stacks"][s]["wall_s"], flush=True)
    fd = res["stacks"]["debian"]["frequencies_hz"]
    fp = res["stacks"]["pypi"]["frequencies_hz"]
    rel = [abs(a - b) / a for a, b in zip(fd[6:26], fp[6:26])]
    res["modes_7_26_max_relative_difference"] = max(rel)
    res["modes_tolerance"] = 1e-9
    scene = scene_20ms(work)
    for s, py in stacks.items():
        c0 = child_cpu()
        r = json.loads(call(py, REDUCE, scene, env=env[s]))
        res["stacks"][s]["reduce_wall_s"] = r["wall_s"]
        res["stacks"][s]["reduce_cpu_s"] = child_cpu() - c0
        print(s, "reduce", r["wall_s"], flush=True)
    if args.reduce_pairs:
        res["reduce_pairs"] = reduce_pairs(stacks, env, scene, args.reduce_pairs)
    if not args.skip_run:
        for s, py in stacks.items():
            exe = str(Path(py).parent / "flexbearing")
            t0, c0 = time.perf_counter(), child_cpu()
            out = subprocess.run([exe, "run", str(scene), "-o", str(work / f"run_{s}.h5"), "--quiet", "--force"],
                                 capture_output=True, text=True, env=env[s], cwd=work)
            if out.returncode != 0:
                raise SystemExit(f"{s} run: {out.stderr[-3000:]}")
            res["stacks"][s]["run_20ms_wall_s"] = time.perf_counter() - t0
            res["stacks"][s]["run_20ms_cpu_s"] = child_cpu() - c0
            print(s, "run", res["stacks"][s]["run_20ms_wall_s"], flush=True)
        diff = compare_runs(work / "run_debian.h5", work / "run_pypi.h5")
        res["run_20ms_relative_difference"] = diff
        res["run_20ms_max_relative_difference"] = max(diff.values())
        res["run_tolerance"] = 1e-4
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "fe_stacks.json").write_text(json.dumps(res, indent=1))
    lines = ["# The two FE stacks on one mesh of the paper cage", "",
             f"`python benchmarks/fe_stacks.py --reduce-pairs 2`; mesh {msh.name}, "
             f"{res['stacks']['debian']['ndofs']} dofs, P3.", "",
             "Times: CPU seconds of the child process (user + sys; the machine is shared, so wall times "
             "say little), wall in parentheses.", "",
             "| stack | dolfinx | PETSc | SLEPc | gmsh | modes 1-27 (s) | reduce (s) | 20 ms run (s) |",
             "|---|---|---|---|---|---|---|---|"]
    nan = float("nan")
    for s, r in res["stacks"].items():
        v = r["versions"]
        lines.append(f"| {s} | {v['dolfinx']} | {v['petsc']} | {v['slepc']} | {v['gmsh']} | "
                     f"{r['cpu_s']:.1f} ({r['wall_s']:.1f}) | {r['reduce_cpu_s']:.1f} ({r['reduce_wall_s']:.1f}) | "
                     f"{r.get('run_20ms_cpu_s', nan):.1f} ({r.get('run_20ms_wall_s', nan):.1f}) |")
    lines += ["", "| mode | Debian (Hz) | PyPI (Hz) | relative difference |", "|---|---|---|---|"]
    for i in range(6, 26):
        lines.append(f"| {i + 1} | {fd[i]:.6f} | {fp[i]:.6f} | {abs(fd[i] - fp[i]) / fd[i]:.2e} |")
    lines += ["", f"Modes 7-26: max relative difference {res['modes_7_26_max_relative_difference']:.2e} "
              f"(tolerance {res['modes_tolerance']:.0e}, the eigensolver's)."]
    if "run_20ms_max_relative_difference" in res:
        lines += [f"20 ms flexible run (integrator tolerance {res['run_tolerance']:.0e}): max over outputs of "
                  f"max|a - b| / max|a| = {res['run_20ms_max_relative_difference']:.2e}. Transient outputs "
                  "(pocket forces, damping powers) differ pointwise between any two runs of this start, the "
                  "same stack at another tolerance included: fe_stacks_runs.md compares each output with the "
                  "integrator's own error (`--integrator-reference`). Per output:", ""]
        lines += [f"- {k}: {v:.2e}" for k, v in sorted(res["run_20ms_relative_difference"].items())]
    if "reduce_pairs" in res:
        rp = res["reduce_pairs"]
        lines += ["", f"New geometry -> reduced cage (mesh cached), {len(rp['debian']['cpu_s'])} interleaved pairs: "
                  f"CPU s Debian {rp['debian']['cpu_s']}, PyPI {rp['pypi']['cpu_s']}; median ratio PyPI/Debian "
                  f"{rp['median_ratio_pypi_over_debian_cpu_s']:.2f} (CPU), "
                  f"{rp['median_ratio_pypi_over_debian_wall_s']:.2f} (wall)."]
    (OUT / "fe_stacks.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    ok = res["modes_7_26_max_relative_difference"] <= res["modes_tolerance"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
