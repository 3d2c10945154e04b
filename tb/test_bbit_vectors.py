"""The gating-signal generator through the vector-file path (tb/mdfqm_testkit/vectors.py: no
Python per cycle), every output every cycle against GeneratorModel: every scenario of
bbit_stimulus (each mode, random switches, mode handovers, overmodulation, extreme codes, the
settings at their limits, trials from reset) with b anywhere in [1, max_bits]; and the
``limits`` scenario long enough for an update at the largest period. Each scenario's functional
coverage must close (every bin of its sequences), and the bins hit go to
build/traceability.md (tb/mdfqm_testkit/spec_trace.py)."""

import os
import random

import pytest

from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_model.update import candidates, remove_common_mode, sort1
from mdfqm_spec.contract import Contract
from mdfqm_testkit import spec_trace
from mdfqm_testkit.bbit_stimulus import (
    LIMITS_CYCLES,
    SCENARIOS,
    generate,
    half_way_codes,
    tie_codes,
)
from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.vectors import Tally, VectorBench


def closed(coverage, seed, scenario):
    """The scenario's coverage closed (every goal hit), else the bins missing."""
    missing = coverage.missing()
    assert not missing, (f"seed {seed}, {scenario}: coverage not closed:\n"
                         + "\n".join(f"  {point}: {b}" for point, b in missing))


def run_bbit_vectors(phases, width, rule, max_bits, cycles_per_scenario, seed):
    """Build the bench, run every scenario, return (checked cycles, mismatches, details)."""
    contract = Contract(phases, width)
    bench = VectorBench(GatingSignalGenerator(phases, width, rule, max_bits),
                        "gating_signal_generator", f"n{phases}-w{width}-{rule}-b{max_bits}")
    tally = Tally()
    for scenario in SCENARIOS:
        rng = random.Random(f"{seed}-{scenario}")
        coverage = Coverage()
        stim, expected, _ = generate(rng, scenario, contract, rule, max_bits,
                                     cycles_per_scenario,
                                     bits_choices=tuple(range(1, max_bits + 1)), segment=4000,
                                     coverage=coverage)
        spec_trace.record(f"bbit_vectors[n{phases}-w{width}-{rule}-b{max_bits}]", "generator",
                          coverage)
        closed(coverage, seed, scenario)
        tally.add(scenario, bench.run(stim, expected, name=scenario), cycles_per_scenario)
    return tally.total, tally.mismatches, tally.details


@pytest.mark.parametrize(("phases", "width", "rule", "max_bits", "cycles_per_scenario"), [
    (3, 16, "largest_duty", 8, 20_000),
    (5, 14, "exact_nearest", 5, 8_000),
    (4, 10, "largest_duty", 8, 4_000),      # max_bits = width - 2: S up to FULL
])
def test_bbit_vectors(phases, width, rule, max_bits, cycles_per_scenario):
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"bbit vectors: seed {seed} (replay with SEED={seed})")
    total, mismatches, details = run_bbit_vectors(phases, width, rule, max_bits,
                                                  cycles_per_scenario, seed)
    assert mismatches == 0, f"seed {seed}: {mismatches} mismatches\n" + "\n".join(details)
    assert total == cycles_per_scenario * len(SCENARIOS)


def test_bbit_limits_vectors():
    """Every setting at its ends, the period up to 2**16 - 1 (the count-downs' top bits)."""
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"bbit limits vectors: seed {seed} (replay with SEED={seed})")
    contract = Contract(3, 16)
    bench = VectorBench(GatingSignalGenerator(3, 16, "largest_duty", 8),
                        "gating_signal_generator", "n3-w16-largest_duty-b8-limits")
    coverage = Coverage()
    stim, expected, _ = generate(random.Random(f"{seed}-limits"), "limits", contract,
                                 "largest_duty", 8, LIMITS_CYCLES, bits_choices=tuple(range(1, 9)),
                                 segment=4000, coverage=coverage)
    spec_trace.record("bbit_limits_vectors", "generator", coverage)
    closed(coverage, seed, "limits")
    assert max(stim["period"]) == (1 << 16) - 1 and max(stim["osr"]) == 255
    result = bench.run(stim, expected, name="limits")
    assert result["cycles"] == LIMITS_CYCLES
    assert result["mismatches"] == 0, f"seed {seed}:\n" + "\n".join(result["first"])


@pytest.mark.parametrize("phases", [3, 4, 5, 7])
def test_tie_codes_tie_the_largest_candidates(phases):
    """The ``boundaries`` scenario's MDFQM beats: from an empty integrator, two largest_duty
    candidates of the model tie for the largest, and every code is in range."""
    contract = Contract(phases, 16)
    rng = random.Random(phases)
    for _ in range(500):
        codes = tie_codes(rng, contract, phases)
        assert all(contract.code_min <= c <= contract.code_max for c in codes), codes
        rho, _ = sort1(remove_common_mode(codes, phases))
        values = candidates(rho, contract, "largest_duty")
        assert values.count(max(values)) >= 2, (codes, values)


@pytest.mark.parametrize("phases", [3, 5])
@pytest.mark.parametrize("bits", [1, 3, 6, 8])
def test_half_way_codes_put_every_svpwm_instant_half_way(phases, bits):
    """The ``boundaries`` scenario's half-way svpwm beats: from an empty integrator every
    cumulative instant of docs/contract.md, ``2 C_j S / (2 NF)`` slots (``2 C_1 = NF - rho_0 +
    rho_{N-1}`` at gamma 1/2, then ``+ 2 (rho_{j-1} - rho_j)``), is a whole number of slots
    and a half, and every code is in range."""
    contract = Contract(phases, 16)
    nf, slots = contract.unit, 1 << bits
    rng = random.Random(phases * 100 + bits)
    for _ in range(300):
        codes = half_way_codes(rng, contract, phases, bits)
        assert all(contract.code_min <= c <= contract.code_max for c in codes), codes
        rho, _ = sort1(remove_common_mode(codes, phases))
        two_c = [nf - rho[0] + rho[-1]]
        for j in range(1, phases):
            two_c.append(two_c[-1] + 2 * (rho[j - 1] - rho[j]))
        assert all((c * slots) % (2 * nf) == nf for c in two_c), (codes, two_c)
