"""The whole-core regression of >= 10**6 checked cycles through the vector-file path
(tb/mdfqm_testkit/vectors.py: no Python per cycle), every output every cycle against CoreModel."""

import os
import random

import pytest

from mdfqm_gateware.core import MdfqmCore
from mdfqm_spec.contract import Contract
from mdfqm_testkit.core_stimulus import SCENARIOS, generate
from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.vectors import Tally, VectorBench


def run_core_vectors(phases, width, rule, cycles_per_scenario, seed):
    """Build the bench, run every scenario, return (checked cycles, mismatches, details, the
    stimulus' coverage)."""
    contract = Contract(phases, width)
    bench = VectorBench(MdfqmCore(phases, width, rule), "mdfqm_core",
                        f"n{phases}-w{width}-{rule}")
    tally = Tally()
    coverage = Coverage()
    for scenario in SCENARIOS:
        rng = random.Random(f"{seed}-{scenario}")
        stim, expected = generate(rng, scenario, contract, rule, cycles_per_scenario,
                                  coverage=coverage)
        tally.add(scenario, bench.run(stim, expected, name=scenario), cycles_per_scenario)
    return tally.total, tally.mismatches, tally.details, coverage


@pytest.mark.parametrize(("phases", "width", "rule", "cycles_per_scenario"), [
    (3, 16, "largest_duty", 200_000),
    (5, 16, "exact_nearest", 40_000),
])
def test_core_vectors(phases, width, rule, cycles_per_scenario):
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"core vectors: seed {seed} (replay with SEED={seed})")
    total, mismatches, details, coverage = run_core_vectors(phases, width, rule,
                                                            cycles_per_scenario, seed)
    assert mismatches == 0, f"seed {seed}: {mismatches} mismatches\n" + "\n".join(details)
    assert total == cycles_per_scenario * len(SCENARIOS)
    print(coverage.report())
    assert not coverage.missing(), f"seed {seed}: coverage missed {coverage.missing()}"
