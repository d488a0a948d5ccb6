"""MUMPS's fill-reducing ordering for the cage's saddle-point factorisation, on each FE stack.

The Craig–Bampton reduction factorises S = [[K, C^T], [C, 0]] once (LDL^T, MUMPS;
flexbearing.fem_cage.craig_bampton.lu_ksp) and solves blocks of right-hand sides with it. The
ordering (MUMPS ICNTL(7)) sets the factor's fill and so both times. Debian 12's MUMPS has the
built-in orderings only (AMD 0, AMF 2, PORD 4, QAMD 6); the PyPI wheel's also METIS (5) and
SCOTCH (3, with PT-SCOTCH). For each ordering the stack has: the CPU time (process time: the
machine is shared, wall time is not the solver's) of the factorisation and of one 50-column block
solve, the factor's size (INFOG(20), estimated entries), in interleaved rounds (every ordering
once per round), median over rounds. ICNTL(7) = 7 is MUMPS's automatic choice; INFOG(7) says
which ordering it took.

    python benchmarks/mumps_ordering.py MESH.msh [--rounds 3]      (run it with each stack's python)
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

ORDERINGS = {0: "AMD", 2: "AMF", 3: "SCOTCH", 4: "PORD", 5: "METIS", 6: "QAMD", 7: "auto"}


def saddle(msh: str, degree: int = 3):
    from flexbearing.common.fe_stack import MPI
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.fem_cage.elasticity import load_cage_mesh, assemble_stiffness_mass
    from flexbearing.fem_cage.craig_bampton import petsc_to_scipy, saddle_matrix, scipy_to_petsc
    from flexbearing.fem_cage import interface as itf
    domain, _, ft, _ = load_cage_mesh(msh, MPI.COMM_SELF)
    V, K, M = assemble_stiffness_mass(domain, PAPER_CAGE.material, degree)
    X = V.tabulate_dof_coordinates()[:, :3].copy()
    walls = itf.pocket_wall_nodes(V, ft, PAPER_CAGE.n_pockets)
    C = itf.rbe3_constraint(K.getSize()[0], walls, itf.pocket_wall_weights(V, ft, walls), X,
                            itf.pocket_centres(PAPER_CAGE))
    return scipy_to_petsc(saddle_matrix(petsc_to_scipy(K), C)), K.getSize()[0]


def factor(S, ordering: int, ncols: int = 50) -> dict:
    from flexbearing.common.fe_stack import PETSc
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setOperators(S)
    ksp.setType(PETSc.KSP.Type.PREONLY)
    pc = ksp.getPC()
    S.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    pc.setType(PETSc.PC.Type.CHOLESKY)
    pc.setFactorSolverType("mumps")
    pc.setFactorSetUpSolverType()
    F = pc.getFactorMatrix()
    F.setMumpsIcntl(14, 80)
    F.setMumpsIcntl(7, ordering)
    t0 = time.process_time()
    ksp.setUp()
    t_factor = time.process_time() - t0
    N = S.getSize()[0]
    B = PETSc.Mat().createDense([N, ncols], comm=PETSc.COMM_SELF)
    B.setUp()
    B.getDenseArray()[:] = np.random.default_rng(0).standard_normal((N, ncols))
    B.assemble()
    X = PETSc.Mat().createDense([N, ncols], comm=PETSc.COMM_SELF)
    X.setUp()
    X.assemble()
    t0 = time.process_time()
    F.matSolve(B, X)
    t_solve = time.process_time() - t0
    out = {"factor_cpu_s": t_factor, "solve50_cpu_s": t_solve, "used": ORDERINGS.get(F.getMumpsInfog(7), F.getMumpsInfog(7)),
           "factor_entries": float(-F.getMumpsInfog(20) * 1e6 if F.getMumpsInfog(20) < 0 else F.getMumpsInfog(20))}
    for o in (B, X, ksp):
        o.destroy()
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    from flexbearing.common.fe_stack import PETSc, versions
    have = [o for o in ORDERINGS
            if ORDERINGS[o] not in ("METIS", "SCOTCH")
            or PETSc.Sys.hasExternalPackage({"METIS": "metis", "SCOTCH": "ptscotch"}[ORDERINGS[o]])]
    S, n = saddle(args.mesh)
    rows = {ORDERINGS[o]: [] for o in have}
    for r in range(args.rounds):
        for o in have:
            try:
                rows[ORDERINGS[o]].append(factor(S, o))
            except Exception as exc:                      # an ordering MUMPS was built without
                rows[ORDERINGS[o]].append({"error": str(exc)[:200]})
            print(r, ORDERINGS[o], rows[ORDERINGS[o]][-1], file=sys.stderr, flush=True)
    summary = {}
    for name, rs in rows.items():
        ok = [x for x in rs if "error" not in x]
        if ok:
            summary[name] = {"factor_cpu_s": float(np.median([x["factor_cpu_s"] for x in ok])),
                             "solve50_cpu_s": float(np.median([x["solve50_cpu_s"] for x in ok])),
                             "factor_entries": ok[0]["factor_entries"], "used": ok[0]["used"], "rounds": len(ok)}
        else:
            summary[name] = {"error": rs[0]["error"]}
    print(json.dumps({"versions": versions(), "n_dofs": n, "saddle_size": S.getSize()[0],
                      "orderings": summary}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
