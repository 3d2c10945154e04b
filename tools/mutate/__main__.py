"""``python -m tools.mutate``: the mutation campaign (``make mutate``) and its report.

    python -m tools.mutate [--blocks core,generator,driver,top_wb,top_axi] [--count N]
                           [--seed S] [--jobs 2] [--resume] [--out reports]
    python -m tools.mutate --block top_wb --only '<key>'      # one mutant, every stage
    python -m tools.mutate --report-only                       # the report from the databases

See tools/mutate/__init__.py for the method.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path

from .blocks import BLOCKS
from .campaign import DEFAULT_COUNTS, STAGES, Settings, run

__all__ = ["main"]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.mutate", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--blocks", default=",".join(BLOCKS),
                        help="blocks to mutate (default: all: %(default)s)")
    parser.add_argument("--block", help="one block (with --only)")
    parser.add_argument("--count", type=int,
                        help="mutations per block (default: " + ", ".join(
                            f"{k} {v}" for k, v in DEFAULT_COUNTS.items()) + ")")
    parser.add_argument("--seed", type=int, default=1,
                        help="seed of the selection and of the stimulus (default 1)")
    parser.add_argument("--jobs", type=int, default=2, help="parallel mutants (default 2)")
    parser.add_argument("--resume", action="store_true",
                        help="keep the results of an earlier run of the same design and seed")
    parser.add_argument("--recheck", action="store_true",
                        help="with --resume: the equivalence stage again on the survivors and "
                             "undecided mutants")
    parser.add_argument("--retry", action="store_true",
                        help="with --resume: every mutant neither killed nor proven equivalent "
                             "through every stage again (after the tests changed)")
    parser.add_argument("--retry-survived", action="store_true",
                        help="with --resume: the survivors only through every stage again (after "
                             "a test that closes their hole); undecided mutants keep their "
                             "records")
    parser.add_argument("--only", action="append", default=[],
                        help="run this mutation key only (repeatable; needs --block)")
    parser.add_argument("--stages", default=",".join(STAGES),
                        help="stages to run (default: %(default)s)")
    parser.add_argument("--eq-timeout", type=float, default=90.0,
                        help="seconds of each equiv proof (default 90)")
    parser.add_argument("--out", default="reports", help="where MUTATION.md goes")
    parser.add_argument("--no-report", action="store_true", help="do not write the report")
    parser.add_argument("--report-only", action="store_true",
                        help="write the report from the databases, run nothing")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)

    from .report import write_report

    command = "python -m tools.mutate " + " ".join(sys.argv[1:] if argv is None else argv)
    if args.report_only:
        # the command of the run that made the databases, from the report it wrote
        previous = Path(args.out) / "MUTATION.md"
        ran = (re.search(r"^- Command: `([^`]+)`", previous.read_text(), re.M)
               if previous.exists() else None)
        print(write_report(args.out, command=ran.group(1) if ran else None))
        return 0
    blocks = tuple(args.blocks.split(","))
    if args.only:
        if not args.block:
            parser.error("--only needs --block")
        blocks = (args.block,)
    elif args.block:
        blocks = (args.block,)
    unknown = [b for b in blocks if b not in BLOCKS]
    if unknown:
        parser.error(f"unknown block(s) {unknown}; known: {', '.join(BLOCKS)}")
    stages = tuple(args.stages.split(","))
    if not set(stages) <= set(STAGES):
        parser.error(f"stages must be among {', '.join(STAGES)}")
    counts = dict(DEFAULT_COUNTS)
    if args.count:
        counts = {b: args.count for b in BLOCKS}
    settings = Settings(blocks=blocks, counts=counts, seed=args.seed, jobs=args.jobs,
                        resume=args.resume or args.recheck or args.retry or args.retry_survived,
                        recheck=args.recheck, retry=args.retry,
                        retry_survived=args.retry_survived,
                        only=tuple(args.only), stages=stages,
                        eq_timeout=args.eq_timeout, progress=not args.no_progress)
    print(f"mutate: seed {args.seed}, blocks {', '.join(blocks)}, {args.jobs} jobs "
          f"({time.strftime('%Y-%m-%d %H:%M')})", flush=True)
    run(settings)
    if args.only:
        from .campaign import BUILD

        for key in args.only:
            import json

            db = json.loads((BUILD / f"{args.block}-only" / "results.json").read_text())
            result = db["results"][key]
            print(f"{key}: {result['status']} ({result['stage']}): {result['detail']}")
            for line in result.get("log", []):
                print(f"  {line}")
    elif not args.no_report:
        print(f"report: {write_report(args.out, command=command)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
