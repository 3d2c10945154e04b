# amaranth: UnusedElaboratable=no
"""The gating-signal generator, every output on every clock, against
mdfqm_model.clock.GeneratorModel: each mode with b in {1, 3, 6}, random runtime switches,
overmodulation, extreme codes, and with mode = mdfqm the core's own scenarios against the core's
model (CoreModel)."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_gateware.integrator import Integrator
from mdfqm_gateware.resolution import Quantiser, SlotLayout
from mdfqm_gateware.sequencer import UpdateSequencer
from mdfqm_spec.contract import Contract, loop_latency, resolution_latency
from mdfqm_testkit.bbit_stimulus import generate, generate_core
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

CASES = [(3, 16, "largest_duty", 8), (5, 16, "exact_nearest", 6)]


def check_boundaries(trace, expected):
    """The latched mode changes only at update starts, and between two ``update`` strobes the
    output of an MDFQM update is constant (a gamma-mode layout changes at slot boundaries)."""
    starts = trace["start"]
    for cycle in range(1, len(starts)):
        if trace["mode"][cycle] != trace["mode"][cycle - 1] and not trace["rst"][cycle - 1]:
            assert starts[cycle - 1], f"mode latched outside an update start (cycle {cycle})"
    return sum(starts)


async def run_scenario(dut, scenario, cycles):
    p = params()
    contract = Contract(p["phases"], p["width"])
    rng = seeded_rng(dut, f"bbit_{scenario}")
    stim, expected, trace = generate(rng, scenario, contract, p["rule"], p["max_bits"], cycles)
    starts = check_boundaries(trace, expected)
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("bbit_%s: %d cycles, %d updates, every output equal to the model", scenario,
                  checked, starts)


def cycles(scale=1):
    return params().get("cycles", 30000) // scale


@cocotb.test()
async def bbit_mdfqm(dut):
    """mode = mdfqm (b = 0) through the generator's own model."""
    await run_scenario(dut, "mdfqm", cycles())


@cocotb.test()
async def bbit_svpwm(dut):
    """SVPWM, centred 0-V1-V2-7-7-V2-V1-0, b in {1, 3, 6}."""
    await run_scenario(dut, "svpwm", cycles())


@cocotb.test()
async def bbit_dpwm0(dut):
    """DPWM0 (gamma = 0: the top leg clamped on), b in {1, 3, 6}."""
    await run_scenario(dut, "dpwm0", cycles())


@cocotb.test()
async def bbit_dpwm1(dut):
    """DPWM1 (gamma = 1: the bottom leg clamped off), b in {1, 3, 6}."""
    await run_scenario(dut, "dpwm1", cycles())


@cocotb.test()
async def bbit_dpwm_sector(dut):
    """DPWM with the sector-dependent clamp, b in {1, 3, 6}."""
    await run_scenario(dut, "dpwm", cycles())


@cocotb.test()
async def bbit_switch(dut):
    """Mode, bits (illegal values too), period, OSR, sync_in and reset at random cycles."""
    await run_scenario(dut, "switch", cycles())


@cocotb.test()
async def bbit_handover(dut):
    """mdfqm and gamma modes alternating every update or two, fewest-transitions zero policy."""
    await run_scenario(dut, "handover", cycles())


@cocotb.test()
async def bbit_overmodulation(dut):
    """Up to twice the linear range with common mode, random modes: the bound holds."""
    await run_scenario(dut, "overmod", cycles(2))


@cocotb.test()
async def bbit_extreme_codes(dut):
    """Most negative / most positive codes, random modes."""
    await run_scenario(dut, "extremes", cycles(2))


@cocotb.test()
async def bbit_is_the_core_when_mdfqm(dut):
    """mode held at mdfqm (bits random): the core's scenarios against the core's model."""
    p = params()
    contract = Contract(p["phases"], p["width"])
    for scenario in ("sine", "runtime", "ties"):
        rng = seeded_rng(dut, f"bbit_core_{scenario}")
        stim, expected = generate_core(rng, scenario, contract, p["rule"], cycles(3))
        await start(dut)
        checked = await check_cycles(dut, stim, expected)
        dut._log.info("core %s through the generator: %d cycles equal to CoreModel", scenario,
                      checked)


@pytest.mark.parametrize(("phases", "width", "rule", "max_bits"), CASES)
def test_bbit(phases, width, rule, max_bits):
    run_block(lambda: GatingSignalGenerator(phases, width, rule, max_bits),
              "gating_signal_generator", "test_bbit",
              {"phases": phases, "width": width, "rule": rule, "max_bits": max_bits})


def test_bbit_latencies_are_the_contract():
    g = GatingSignalGenerator(3, 16)
    assert (g.latency, g.long_latency) == (loop_latency(3), resolution_latency(3, 8)) == (8, 20)
    g = GatingSignalGenerator(5, 16, "exact_nearest", 6)
    assert (g.latency, g.long_latency) == (11, 21)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer >= 3, not 2"),
    ({"width": 7},
     "width must be an integer in [8, 32] for 3 phases (FULL = 2**(width-2) >= 16 * phases), "
     "not 7"),
    ({"rule": "nearest"},
     "rule must be one of ('largest_duty', 'exact_nearest'), not 'nearest'"),
    ({"max_bits": 0},
     "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not 0"),
    ({"max_bits": 13},
     "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not 13"),
    ({"width": 10, "max_bits": 9},
     "max_bits must be an integer in [1, 8] for a 10-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not 9"),
    ({"max_bits": True},
     "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not True"),
])
def test_bbit_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        GatingSignalGenerator(**kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(("factory", "message"), [
    (lambda: Quantiser(3, 16, 0),
     "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not 0"),
    (lambda: Quantiser(2, 16, 4), "phases must be an integer >= 3, not 2"),
    (lambda: SlotLayout(2, 4), "phases must be an integer >= 3, not 2"),
    (lambda: SlotLayout(3, 13), "max_bits must be an integer in [1, 12], not 13"),
    (lambda: SlotLayout(3, 4, 1), "period_width must be an integer in [2, 32], not 1"),
    (lambda: UpdateSequencer(8, long_latency=4), "long_latency must be an integer >= 8, not 4"),
    (lambda: UpdateSequencer(8, long_latency=20, max_bits=16),
     "max_bits must be an integer in [1, 15], not 16"),
    (lambda: UpdateSequencer(8, period_width=8, long_latency=20, max_bits=8),
     "period_width must hold the longest minimum period 256, not 8"),
    (lambda: Integrator(3, 16, unit_shift=15), "unit_shift must be an integer in [0, 14], not 15"),
    (lambda: Integrator(3, 16, unit_shift=-1), "unit_shift must be an integer in [0, 14], not -1"),
    (lambda: Integrator(3, 16, formal_sums=0), "formal_sums must be a bool, not 0"),
    (lambda: GatingSignalGenerator(formal="yes"), "formal must be a bool, not 'yes'"),
])
def test_blocks_reject_bad_parameters(factory, message):
    with pytest.raises(ValueError) as info:
        factory()
    assert str(info.value) == message


def test_core_blocks_unchanged_by_default():
    """The generator's options are off by default: the core's sequencer has no mode ports and
    its integrator takes the feedback in units of FULL."""
    assert "mode" not in UpdateSequencer(8).signature.members
    assert Integrator(3, 16).unit_shift == 14 and Integrator(3, 16).units_width == 3
    assert Integrator(3, 16, unit_shift=6).units_width == 11


@pytest.mark.parametrize("args", [(3, 16, "largest_duty", 8), (5, 16, "exact_nearest", 6),
                                  (4, 10, "largest_duty", 8), (9, 16, "exact_nearest", 12)])
def test_bbit_verilog_is_lint_clean(args, tmp_path):
    """verilator --lint-only -Wall with the project's waivers (mdfqm_gateware.dropin.lint)."""
    from amaranth.back import verilog

    from mdfqm_gateware.dropin import lint

    path = tmp_path / "gating_signal_generator.v"
    path.write_text(verilog.convert(GatingSignalGenerator(*args), name=path.stem,
                                    emit_src=False))
    lint(path)
