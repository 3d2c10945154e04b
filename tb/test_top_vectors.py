# amaranth: UnusedElaboratable=no
"""The drop-in top's long regression through the vector-file path (tb/mdfqm_testkit/vectors.py: no
Python per simulated cycle): >= 10**6 checked clocks in `make test`, every output every clock
against TopModel, the generator's every mode in force (random MODULATION writes, legal and not)
under a firmware-like bus master, with resets, a fault and sync pulses
(tb/mdfqm_testkit/top_stimulus.py). The MDFQM-only top and the AXI4-Lite front get a shorter run
each. ``SEED=<n>`` replays."""

import os
import random

import pytest

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec.contract import MODES
from mdfqm_testkit.top_stimulus import COINCIDENT, top_stimulus
from mdfqm_testkit.vectors import VectorBench

#: (name, top, runs x cycles): 4 x 225 000 + 2 x 50 000 + 2 x 30 000 = 1 060 000 checked
#: clocks
CASES = [
    ("wishbone_b8", lambda: MdfqmTop(3, 16, max_bits=8), (225_000,) * 4),
    ("axi4lite_b3", lambda: MdfqmTop(3, 16, bus="axi4lite", max_bits=3), (50_000,)),
    ("mdfqm_only", lambda: MdfqmTop(3, 16, max_bits=0), (50_000,)),
    # a mixed pin polarity pair, both ways round (active-low upper drivers are common)
    ("upper_low_b2", lambda: MdfqmTop(3, 16, upper_active_low=True, max_bits=2), (30_000,)),
    ("lower_low_b2", lambda: MdfqmTop(3, 16, lower_active_low=True, max_bits=2), (30_000,)),
]


@pytest.mark.parametrize(("name", "build", "runs"), CASES, ids=[c[0] for c in CASES])
def test_top_vectors(name, build, runs):
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"top {name}: seed {seed} (replay with SEED={seed})")
    top = build()
    bench = VectorBench(top, "mdfqm_top", name)
    total, census = 0, {}
    for k, cycles in enumerate(runs):
        rng = random.Random(f"{seed}-{name}-{k}")
        stim, expected, modes = top_stimulus(rng, top, 3, 16, cycles, census)
        if top.max_bits:
            assert modes == set(range(len(MODES))), f"modes in force: {sorted(modes)}"
        result = bench.run(stim, expected, name=f"run{k}")
        assert result["cycles"] == cycles, result
        assert result["mismatches"] == 0, (f"seed {seed}, run {k}: {result['mismatches']} "
                                           "mismatches\n" + "\n".join(result["first"]))
        total += cycles
        print(f"top {name} run {k}: {cycles} cycles, modes in force {sorted(modes)}, "
              "0 mismatches", flush=True)
    print(f"top {name}: {total} cycles checked, 0 mismatches; a write / a command in the "
          "clock of " + ", ".join(f"{event} {census.get(('write', event), 0)} / "
                                   f"{census.get(('command', event), 0)}"
                                   for event in COINCIDENT))
    # two events in one clock: every pair met (a command with a turn-on, a fault, a sync, a
    # beat) in the long case; the short runs meet a few of each on average, not every seed
    if total < 500_000:
        return
    missing = [pair for pair in ((kind, event) for kind in ("write", "command")
                                 for event in COINCIDENT) if not census.get(pair)]
    assert not missing, f"seed {seed}: never in one clock: {missing}"
