"""`flexbearing study`: one scene run over a range of a parameter (the paper's §4.4 studies).

    flexbearing study STUDY.toml [-o DIR] [--workers N] [--scheduler ADDRESS] [--quiet]

The work: flexbearing.studies.study (its docstring describes the study file and what is written).
"""
from __future__ import annotations

import sys
from pathlib import Path

def register(subparsers) -> None:
    p = subparsers.add_parser("study", help="a scene over a range of one parameter (the paper's §4.4 studies)",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("study", help="study file (TOML), e.g. scenes/study_axial_load.toml")
    p.add_argument("-o", "--output", default="out/study", help="output folder (default out/study)")
    p.add_argument("--workers", type=int, default=None,
                   help="runs at once on a local Dask cluster (default: the number of CPUs; 1 = one after "
                        "the other in this process)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on the existing Dask cluster whose scheduler is at ADDRESS, e.g. "
                        "tcp://10.0.0.5:8786 (`dask scheduler` prints it); its workers must see the "
                        "output folder and FLEXBEARING_CACHE at the same paths")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=cmd_study)


def cmd_study(args) -> int:
    from flexbearing.simulation.run import RunInterrupted
    from flexbearing.studies.study import StudyIncomplete, load_study, run_study, study_markdown
    study = load_study(args.study)
    print(f"== study {study.name}: {len(study.scenes)} runs of {study.scene_path} "
          f"({', '.join(study.keys)}) -> {Path(args.output) / study.name}", flush=True)
    try:
        result = run_study(study, args.output, workers=args.workers, quiet=args.quiet,
                           scheduler=args.scheduler)
    except StudyIncomplete as exc:
        print(f"flexbearing study: {exc}", file=sys.stderr)
        return 1
    except RunInterrupted as exc:
        print(f"flexbearing study: {exc} (run the same command again to continue)", file=sys.stderr)
        return 130 if isinstance(exc.__cause__, KeyboardInterrupt) else 1
    except KeyboardInterrupt:
        print("flexbearing study: interrupted; run the same command again to continue", file=sys.stderr)
        return 130
    print(study_markdown(study, result))
    print(f"wall {result['wall_time_s']:.1f} s; results in {Path(args.output) / study.name}")
    return 0
