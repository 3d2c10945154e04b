# amaranth: UnusedElaboratable=no
"""The whole MDFQM core, every output on every clock, against mdfqm_model.clock.CoreModel."""

# (line 1: components built only to be refused or measured are never elaborated, on purpose)

import time

import cocotb
import pytest

from mdfqm_gateware.core import MdfqmCore
from mdfqm_spec.contract import Contract, loop_latency
from mdfqm_testkit.core_stimulus import generate
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

CASES = [(3, 16, "largest_duty"), (3, 16, "exact_nearest"), (3, 12, "largest_duty"),
         (3, 18, "largest_duty"), (4, 16, "largest_duty"), (5, 16, "largest_duty"),
         (5, 16, "exact_nearest"), (6, 16, "largest_duty"), (9, 16, "exact_nearest"),
         (9, 12, "largest_duty")]

async def run_scenario(dut, scenario, cycles):
    p = params()
    contract = Contract(p["phases"], p["width"])
    rng = seeded_rng(dut, f"core_{scenario}")
    stim, expected = generate(rng, scenario, contract, p["rule"], cycles)
    await start(dut)
    began = time.monotonic()
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("core_%s: %d cycles, every output equal to the model (%.0f checked cycles/s)",
                  scenario, checked, checked / (time.monotonic() - began))


@cocotb.test()
async def core_sine(dut):
    """Sine references inside the linear range, runtime period/OSR/policy changes."""
    await run_scenario(dut, "sine", params().get("cycles", 20000))


@cocotb.test()
async def core_overmodulation(dut):
    """Up to twice the linear range with common-mode offsets: the integrator bound holds."""
    await run_scenario(dut, "overmod", params().get("cycles", 20000) // 2)


@cocotb.test()
async def core_runtime_and_reset(dut):
    """Periods below the loop latency (clamped), OSR 0, resets in the middle of updates, sync."""
    await run_scenario(dut, "runtime", params().get("cycles", 20000) // 2)


@cocotb.test()
async def core_ties(dut):
    """Equal references: sort1 and sort2 tie-breaks and the zero policies."""
    await run_scenario(dut, "ties", params().get("cycles", 20000) // 4)


@cocotb.test()
async def core_extreme_codes(dut):
    """Most negative / most positive codes on every phase."""
    await run_scenario(dut, "extremes", params().get("cycles", 20000) // 4)


@pytest.mark.parametrize(("phases", "width", "rule"), CASES)
def test_core(phases, width, rule):
    run_block(lambda: MdfqmCore(phases, width, rule), "mdfqm_core", "test_core",
              {"phases": phases, "width": width, "rule": rule})


def test_core_latency_is_the_contract():
    assert MdfqmCore(3, 16).latency == loop_latency(3) == 8
    assert MdfqmCore(5, 16).latency == loop_latency(5)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer >= 3, not 2"),
    ({"phases": 3, "width": 7},
     "width must be an integer in [8, 32] for 3 phases (FULL = 2**(width-2) >= 16 * phases), "
     "not 7"),
    ({"phases": 9, "width": 9},
     "width must be an integer in [10, 32] for 9 phases (FULL = 2**(width-2) >= 16 * phases), "
     "not 9"),
    ({"phases": 16, "width": 16},
     "rule 'largest_duty' is offered for at most 12 phases (its integrators outgrow their bound "
     "beyond); use 'exact_nearest' for 16 phases"),
    ({"rule": "nearest"},
     "rule must be one of ('largest_duty', 'exact_nearest'), not 'nearest'"),
])
def test_core_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        MdfqmCore(**kwargs)
    assert str(info.value) == message
