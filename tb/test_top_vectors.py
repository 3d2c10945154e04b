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
from mdfqm_model.update import mdfqm_update, remove_common_mode
from mdfqm_spec.contract import MODES, RULES, ZERO_POLICIES, Contract
from mdfqm_testkit import spec_trace
from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.top_sequences import LongTimes
from mdfqm_testkit.top_stimulus import FULL_TOP_RUNS, half_step_codes, top_stimulus
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


@pytest.mark.parametrize("phases", [3, 5])
def test_half_step_beats_change_the_state_at_every_update(phases):
    """The premise of the long dead-time trials (top_sequences.LongTimes): with every beat half
    of one leg's active vector, the MDFQM update changes the state at every update, from any
    legal integrators, after fewer updates than the trial waits for, with either rule and zero
    policy."""
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"half-step beats, {phases} phases: seed {seed} (replay with SEED={seed})")
    rng = random.Random(seed)
    contract = Contract(phases, 16)
    settle = LongTimes.SETTLE_LIMIT - LongTimes.CHANGING_UPDATES
    for rule in RULES:
        for zero_policy in ZERO_POLICIES:
            for _ in range(200):
                x = [rng.randint(contract.x_min, contract.x_max) for _ in range(phases - 1)]
                x.append(-sum(x))
                if not contract.x_min <= x[-1] <= contract.x_max:
                    continue
                r = remove_common_mode(half_step_codes(contract, rng.randrange(phases)), phases)
                start, states = tuple(x), [0]
                for _ in range(settle + 40):
                    result = mdfqm_update(x, r, states[-1], contract, rule, zero_policy)
                    x = result.x_next
                    states.append(result.h)
                held = [k for k in range(settle, len(states) - 1)
                        if states[k] == states[k + 1]]
                assert not held, (f"{rule}, zero policy {zero_policy}, from {start}: the "
                                  f"state held at updates {held}: {states}")
