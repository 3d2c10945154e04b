# amaranth: UnusedElaboratable=no
"""GateDriver (N legs, dead time, minimum pulse, enable, fault, polarity), every output on every
clock, against mdfqm_model.driver.GateDriverModel; the safety properties checked on the same
trace; and the formal properties (``formal=True``) exercised in Amaranth's simulator (their
SymbiYosys proofs are in tb/test_formal.py)."""

import cocotb
import numpy as np
import pytest
from amaranth import ClockDomain, Module
from amaranth.sim import Simulator

from mdfqm_gateware.driver import GateDriver, LegDriver
from mdfqm_model.driver import GateDriverModel
from mdfqm_testkit.driver_stimulus import (
    REACTION_BINS,
    REACTION_BINS_ALL_OFF,
    DriverRun,
    long_times_cycles,
)
from mdfqm_testkit.formal import AscWithoutDeadTimeLeg, NoDeadTimeLeg
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

# (phases, dead_min, time_width, upper_active_low, lower_active_low, asc)
# every pair of pin polarities; all off only; counters of 16 bits (the top's), 12, 10 and 6 (the
# long scenario's length grows with 2**time_width: one case at 16 bits)
CASES = [(3, 1, 16, False, False, True), (5, 4, 12, True, False, True),
         (6, 2, 6, True, True, True),
         (3, 3, 10, False, True, False)]

#: the scenarios of this simulation, one after the other (cocotb side)
_RUN = None


async def run_scenario(dut, scenario, cycles):
    global _RUN
    p = params()
    rng = seeded_rng(dut, f"driver_{scenario}")
    hit = set()
    _RUN = _RUN or DriverRun(p)
    stim, expected, turn_ons = _RUN.generate(rng, scenario, cycles, hit)
    # the long scenario turns each leg on a few times, after dead times of thousands of clocks
    least = p["phases"] if scenario == "long_times" else 20
    assert turn_ons >= least, f"driver_{scenario}: only {turn_ons} turn-ons, the test is vacuous"
    if scenario == "fault_reaction":        # functional coverage of the fault reaction
        want = REACTION_BINS if p["asc"] else REACTION_BINS_ALL_OFF
        missing = sorted(want - hit, key=str)
        assert not missing, f"driver_{scenario}: bins never reached {missing}"
        if not p["asc"]:
            assert not any(b[0] == "first" and b[2] for b in hit if isinstance(b, tuple)), \
                "an ASC without the ASC built in"
    if scenario == "long_times":    # a remembered dead time deciding, in every octave above
        # the floor (below it, DEAD lowered to 0 acts as dead_min and the two are equal)
        want = {("remembered_dead_time", k) for k in range(p["time_width"])
                if 1 << k > p["dead_min"]}
        missing = sorted(want - hit)
        assert not missing, f"driver_{scenario}: bins never reached {missing}"
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("driver_%s: %d cycles, %d turn-ons, every output equal to the model",
                  scenario, checked, turn_ons)


@cocotb.test()
async def driver_random(dut):
    """Core-like updates, every runtime setting moving, fault bursts, clears, resets."""
    await run_scenario(dut, "random", 12000)


@cocotb.test()
async def driver_fault_chatter(dut):
    """A chattering fault input: one-clock glitches and bursts, clears while active/inactive."""
    await run_scenario(dut, "fault_chatter", 4000)


@cocotb.test()
async def driver_fault_in_dead_time(dut):
    """Faults arriving inside running dead times (and at the update that starts them)."""
    await run_scenario(dut, "fault_in_dead_time", 3000)


@cocotb.test()
async def driver_enable_mid_update(dut):
    """Enable toggled anywhere inside updates: taken only at update boundaries."""
    await run_scenario(dut, "enable_mid_update", 3000)


@cocotb.test()
async def driver_dead_change(dut):
    """The dead time raised and lowered inside running dead times."""
    await run_scenario(dut, "dead_change", 4000)


@cocotb.test()
async def driver_fault_reaction(dut):
    """The fault reaction: each source and reaction, entries with legs on, inside their
    minimum pulse or a dead time; ALL_OFF, clears, a second source, new inputs, resets."""
    await run_scenario(dut, "fault_reaction", 8000)


@cocotb.test()
async def driver_min_pulse(dut):
    """Update periods shorter than dead time + minimum pulse: pulses stretched or swallowed."""
    await run_scenario(dut, "min_pulse", 4000)


@cocotb.test()
async def driver_long_times(dut):
    """DEAD and MIN_PULSE in every octave up to 2**time_width - 1 (pulses stretched to the
    minimum pulse, turn-ons after the dead time, and in each round DEAD lowered while a leg
    waits out the round's: it waits for the remembered one), then the largest dead time with
    the legs disabled for longer than the counters saturate, and enabled: the commanded
    switches turn on at once. Last: the long dead time stays in force after it (it is never
    shortened)."""
    await run_scenario(dut, "long_times", long_times_cycles(params()["time_width"]))


@pytest.mark.parametrize(("phases", "dead_min", "time_width", "upper_low", "lower_low", "asc"),
                         CASES)
def test_driver(phases, dead_min, time_width, upper_low, lower_low, asc):
    run_block(lambda: GateDriver(phases, dead_min, time_width, upper_low, lower_low, asc=asc),
              "gate_driver", "test_driver",
              {"phases": phases, "dead_min": dead_min, "time_width": time_width,
               "upper_active_low": upper_low, "lower_active_low": lower_low, "asc": asc})


# ---------------------------------------------------------------------- formal properties


def simulate_properties(dut, phases, dead_min, time_width, seed, cycles, compare=True):
    """Random stimulus on ``dut`` (built with ``formal=True``) in Amaranth's simulator, every
    output compared with the model; a violated ``Assert`` raises ``AssertionError``."""
    rng = np.random.default_rng(seed)
    model = GateDriverModel(phases, dead_min, time_width)
    m = Module()
    m.domains.sync = cd = ClockDomain()
    m.submodules.dut = dut
    sim = Simulator(m)
    sim.add_clock(1e-6)
    top = (1 << time_width) - 1

    async def bench(ctx):
        for _ in range(cycles):
            kw = {"rst": int(rng.random() < 0.01), "h": int(rng.integers(1 << phases)),
                  "update": int(rng.random() < 0.2), "enable": int(rng.random() < 0.85),
                  "dead": int(rng.choice([0, 1, dead_min, 3, 6, top])),
                  "min_pulse": int(rng.choice([0, 1, 4, 12])),
                  "fault_in": int(rng.random() < 0.02), "fault_clear": int(rng.random() < 0.1),
                  "stop": int(rng.random() < 0.01),
                  "reaction_fault": int(rng.integers(4)), "reaction_watchdog": int(rng.integers(4)),
                  "all_off": int(rng.random() < 0.02)}
            for name, value in kw.items():
                ctx.set(cd.rst if name == "rst" else getattr(dut, name), value)
            want = model.step(**kw)
            got = {name: ctx.get(getattr(dut, name)) for name in want}
            assert not compare or got == want, "differs from the model"
            await ctx.tick()

    sim.add_testbench(bench)
    sim.run()


@pytest.mark.parametrize("phases", [3, 5])
def test_formal_properties_hold_in_simulation(phases):
    simulate_properties(GateDriver(phases, 2, 6, formal=True), phases, 2, 6, phases, 2500)


def test_formal_properties_catch_a_missing_dead_time(monkeypatch):
    import mdfqm_gateware.driver as driver

    monkeypatch.setattr(driver, "LegDriver", NoDeadTimeLeg)
    with pytest.raises(AssertionError, match=r"turn-on before the dead"):
        simulate_properties(GateDriver(3, 2, 6, formal=True), 3, 2, 6, 1, 2500, compare=False)


def test_formal_properties_catch_an_asc_without_dead_time(monkeypatch):
    import mdfqm_gateware.driver as driver

    monkeypatch.setattr(driver, "LegDriver", AscWithoutDeadTimeLeg)
    with pytest.raises(AssertionError, match=r"turn-on before the dead"):
        simulate_properties(GateDriver(3, 2, 6, formal=True), 3, 2, 6, 1, 2500, compare=False)


def test_formal_properties_do_not_change_the_drop_in_verilog():
    from amaranth.back import verilog

    plain = verilog.convert(GateDriver(3, 4), name="d", emit_src=False)
    assert "assert" not in plain
    assert "assert" in verilog.convert(GateDriver(3, 4, formal=True), name="d", emit_src=False)


@pytest.mark.parametrize(("args", "kwargs", "message"), [
    ((0, 1), {}, "phases must be an integer >= 1, not 0"),
    ((3, 0), {}, "dead_min must be an integer in [1, 65535] (clocks), not 0"),
    ((3, 70000), {}, "dead_min must be an integer in [1, 65535] (clocks), not 70000"),
    ((3, 4), {"time_width": 2}, "dead_min must be an integer in [1, 3] (clocks), not 4"),
    ((3, 1), {"time_width": 40}, "time_width must be an integer in [2, 32], not 40"),
    ((3, 1), {"upper_active_low": 0}, "upper_active_low must be a bool, not 0"),
    ((3, 1), {"lower_active_low": None}, "lower_active_low must be a bool, not None"),
    ((3, 1), {"formal": 1}, "formal must be a bool, not 1"),
    ((3, 1), {"asc": "yes"}, "asc must be a bool, not 'yes'"),
])
def test_driver_rejects_bad_parameters(args, kwargs, message):
    with pytest.raises(ValueError) as info:
        GateDriver(*args, **kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"dead_min": 0}, "dead_min must be an integer in [1, 65535] (clocks), not 0"),
    ({"dead_min": 2.0}, "dead_min must be an integer in [1, 65535] (clocks), not 2.0"),
    ({"dead_min": 1, "formal": "no"}, "formal must be a bool, not 'no'"),
    ({"dead_min": 1, "asc": 0}, "asc must be a bool, not 0"),
])
def test_leg_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        LegDriver(**kwargs)
    assert str(info.value) == message

