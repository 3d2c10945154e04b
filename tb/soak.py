"""`make soak`: >= 10**7 checked cycles of the whole core through the vector-file path.

    python tb/soak.py [--cycles 10000000] [--seed N]

Splits the cycles over N = 3 / 16-bit (largest duty) and N = 5 / 16-bit (exact nearest), every
scenario of tb/mdfqm_testkit/core_stimulus.py, in chunks of at most 10**6 cycles (each chunk a fresh
reset), and reports mismatches and cycles/s: of the simulation alone and of the whole run, model
included. Exits non-zero on any mismatch.
"""

import argparse
import random
import sys
import time

from mdfqm_gateware.core import MdfqmCore
from mdfqm_spec.contract import Contract
from mdfqm_testkit.core_stimulus import SCENARIOS, generate
from mdfqm_testkit.vectors import VectorBench

CONFIGS = ((3, 16, "largest_duty"), (5, 16, "exact_nearest"))
CHUNK = 1_000_000


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=10_000_000)
    parser.add_argument("--seed", type=int, default=random.randrange(1 << 32))
    args = parser.parse_args(argv)
    print(f"soak: seed {args.seed} (replay with --seed {args.seed})", flush=True)
    started = time.monotonic()
    total = mismatches = 0
    sim_seconds = 0.0
    per_config = args.cycles // len(CONFIGS)
    for phases, width, rule in CONFIGS:
        bench = VectorBench(MdfqmCore(phases, width, rule), "mdfqm_core",
                            f"n{phases}-w{width}-{rule}")
        contract = Contract(phases, width)
        done, chunk_no = 0, 0
        while done < per_config:
            scenario = SCENARIOS[chunk_no % len(SCENARIOS)]
            cycles = min(CHUNK, per_config - done)
            rng = random.Random(f"{args.seed}-{phases}-{chunk_no}")
            stim, expected = generate(rng, scenario, contract, rule, cycles)
            result = bench.run(stim, expected, name=f"soak{chunk_no}")
            total += result["cycles"]
            mismatches += result["mismatches"]
            sim_seconds += result["seconds"]
            for line in result["first"]:
                print(f"N={phases} {scenario} chunk {chunk_no}: {line}")
            print(f"N={phases} {rule} chunk {chunk_no} ({scenario}): {result['cycles']} cycles, "
                  f"{result['mismatches']} mismatches, "
                  f"{result['cycles'] / result['seconds']:,.0f} cycles/s simulated", flush=True)
            done += cycles
            chunk_no += 1
    wall = time.monotonic() - started
    print(f"soak: {total} cycles checked, {mismatches} mismatches; simulation "
          f"{total / sim_seconds:,.0f} cycles/s, whole run (model included) "
          f"{total / wall:,.0f} cycles/s, {wall:.0f} s")
    return 1 if mismatches or total < args.cycles else 0


if __name__ == "__main__":
    sys.exit(main())
