# amaranth: UnusedElaboratable=no
"""The drop-in top's regression through the vector-file path (tb/mdfqm_testkit/vectors.py: no
Python per simulated clock): every output every clock against TopModel under the
specification's sequences (tb/mdfqm_testkit/top_sequences.py, scheduled by
tb/mdfqm_testkit/top_stimulus.py): every row of docs/robustness.md, every register field and
clamp of spec/rdl/mdfqm_top.rdl and every timing rule of docs/top.md that the top's
configuration has, with the coincidences aimed. Each run's functional coverage must close (every
bin of every sequence that applies), and the bins hit go to build/traceability.md
(tb/mdfqm_testkit/spec_trace.py). Both fronts, the MDFQM-only top (without the watchdog) and
both mixed pin polarity pairs. ``SEED=<n>`` replays."""

import os
import random

import pytest

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec.contract import MODES
from mdfqm_testkit import spec_trace
from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.top_stimulus import FULL_TOP_RUNS, top_stimulus
from mdfqm_testkit.vectors import VectorBench

#: (name, top, runs x clocks): 500 000 + 60 000 + 50 000 + 40 000 + 2 x 40 000 = 730 000
#: checked clocks; the first run long enough for the top octaves of PERIOD, DEAD, MIN_PULSE and
#: ADC_OFFSET
CASES = [
    ("wishbone_b8", lambda: MdfqmTop(3, 16, max_bits=8), FULL_TOP_RUNS),
    ("axi4lite_b3", lambda: MdfqmTop(3, 16, bus="axi4lite", max_bits=3), (50_000,)),
    # the smallest build: MDFQM only, without the watchdog (its absence as documented)
    ("mdfqm_only_no_watchdog", lambda: MdfqmTop(3, 16, max_bits=0, watchdog=False), (40_000,)),
    # a mixed pin polarity pair, both ways round (active-low upper drivers are common)
    ("upper_low_b2", lambda: MdfqmTop(3, 16, upper_active_low=True, max_bits=2), (40_000,)),
    ("lower_low_b2", lambda: MdfqmTop(3, 16, lower_active_low=True, max_bits=2), (40_000,)),
]


@pytest.mark.parametrize(("name", "build", "runs"), CASES, ids=[c[0] for c in CASES])
def test_top_vectors(name, build, runs):
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"top {name}: seed {seed} (replay with SEED={seed})")
    top = build()
    bench = VectorBench(top, "mdfqm_top", name)
    total, merged = 0, Coverage()
    for k, cycles in enumerate(runs):
        rng = random.Random(f"{seed}-{name}-{k}")
        coverage = Coverage()
        stim, expected, modes = top_stimulus(rng, top, 3, 16, cycles, coverage)
        merged.merge(coverage)
        spec_trace.record(f"top_vectors[{name}]", "top", coverage)
        missing = coverage.missing()
        assert not missing, (f"seed {seed}, run {k}: coverage not closed:\n"
                             + "\n".join(f"  {point}: {b}" for point, b in missing))
        if top.max_bits:
            assert modes == set(range(len(MODES))), f"modes in force: {sorted(modes)}"
        result = bench.run(stim, expected, name=f"run{k}")
        assert result["cycles"] == cycles, result
        assert result["mismatches"] == 0, (f"seed {seed}, run {k}: {result['mismatches']} "
                                           "mismatches\n" + "\n".join(result["first"]))
        total += cycles
        print(f"top {name} run {k}: {cycles} clocks, 0 mismatches, {len(coverage.hits)} bins "
              "hit, every goal among them", flush=True)
    print(f"top {name}: {total} clocks checked, 0 mismatches")
