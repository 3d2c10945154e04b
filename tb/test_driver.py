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

from formal import NoDeadTimeLeg
from harness import check_cycles, params, run_block, seeded_rng, start
from mdfqm_gateware.driver import GateDriver, LegDriver
from mdfqm_model.driver import DRIVER_INPUTS, DRIVER_OUTPUTS, GateDriverModel, check_gate_safety

# (phases, dead_min, time_width, upper_active_low, lower_active_low)
CASES = [(3, 1, 16, False, False), (5, 4, 16, True, False), (6, 2, 6, True, True),
         (3, 3, 16, False, True)]           # every pair of pin polarities

INPUTS = DRIVER_INPUTS


class Stimulus:
    """A core-like source of update strobes plus the runtime settings of one scenario."""

    def __init__(self, rng, p):
        self.rng, self.p = rng, p
        self.n, self.top = p["phases"], (1 << p["time_width"]) - 1
        self.period, self.phase, self.h = 10, 0, 0
        self.enable, self.dead, self.min_pulse = 1, p["dead_min"], 0

    def dead_choice(self):
        # the largest value only with narrow counters: a dead time in force is never shortened
        # (not even by a reset), so 65535 would silence the legs of the following tests
        big = self.top if self.top < 100 else 200
        return self.rng.choice([0, 1, 2, self.p["dead_min"], 3, 5, 9, min(17, self.top), big])

    def update_strobe(self):
        """An update every ``period`` clocks; h changes a few legs at a time."""
        rng = self.rng
        self.phase += 1
        if self.phase < self.period:
            return 0
        self.phase = 0
        flips = rng.choice([0, 1, 1, 2, self.n])
        for _ in range(flips):
            self.h ^= 1 << rng.randrange(self.n)
        return 1


#: The model carried from one cocotb test to the next of the same simulation: the leg's
#: ``dt_run`` and the fault synchroniser are not reset (by design), so the DUT enters each test
#: with the state the previous test left. A failing test can therefore make later tests of the
#: same run fail too; the first failure is the real one.
CARRY = {"model": None, "last": None}


def carried_model(p):
    """The model after the reset cycles of :func:`harness.start` (the DUT sees the previous
    test's last inputs, or zeros, during them)."""
    if CARRY["model"] is None:
        CARRY["model"] = GateDriverModel(p["phases"], p["dead_min"], p["time_width"],
                                         p["upper_active_low"], p["lower_active_low"])
        CARRY["last"] = {name: 0 for name in INPUTS}
    model = CARRY["model"]
    for _ in range(2):
        model.step(**{**CARRY["last"], "rst": 1})
    return model


def generate(rng, scenario, p, cycles):
    n, dead_min = p["phases"], p["dead_min"]
    model = carried_model(p)
    dt_run0 = [leg.dt_run for leg in model.legs]
    s = Stimulus(rng, p)
    stim = {name: [] for name in INPUTS}
    expected = {name: [] for name in DRIVER_OUTPUTS}
    up, lo, in_force = [], [], []
    chatter = stopped = 0
    for cycle in range(cycles):
        rst = fault_in = clear = 0
        if scenario == "random":
            if rng.random() < 0.002:
                s.period = rng.choice([1, 2, 3, 8, 13, 30, 60])
            if rng.random() < 0.004:
                s.enable ^= 1
            if rng.random() < 0.01:
                s.dead = s.dead_choice()
            if rng.random() < 0.005:
                s.min_pulse = rng.choice([0, 1, 3, 10, 30, min(s.top, 200)])
            if rng.random() < 0.002:
                chatter = rng.randint(1, 12)
            if rng.random() < 0.002:        # a watchdog trip: stop held a while, then cleared
                stopped = rng.choice([1, 2, 7, 40])
            clear = int(rng.random() < 0.03)
            rst = int(rng.random() < 0.0007)
        elif scenario == "fault_chatter":
            # chattering input: glitches of one clock, bursts, a long assertion; clears
            # attempted while active and while inactive
            if cycle % 300 == 0:
                s.period = rng.choice([5, 9, 20])
            if rng.random() < 0.01:
                chatter = rng.choice([1, 2, 5, 40])
            clear = int(rng.random() < 0.05)
        elif scenario == "fault_in_dead_time":
            s.period = 25
            s.dead = 9 if cycle < cycles // 2 else dead_min
            if s.phase in (rng.randint(0, 12), 1) and rng.random() < 0.3:
                fault_in = 1
            clear = int(s.phase == 20)
        elif scenario == "enable_mid_update":
            if cycle % 400 == 0:
                s.period = rng.choice([6, 11, 23])
            if rng.random() < 0.05:
                s.enable ^= 1
        elif scenario == "dead_change":
            s.period = rng.choice([s.period, s.period, 19, 31]) if s.phase == 0 else s.period
            # change the dead time a few clocks after an update: inside running dead times
            if s.phase in (1, 2, 3, 5, 8) and rng.random() < 0.3:
                s.dead = s.dead_choice()
        elif scenario == "min_pulse" and cycle % 200 == 0:
            s.period = rng.choice([1, 2, 3, 4, 6, 9])
            s.dead = rng.choice([dead_min, 2, 3, 5])
            s.min_pulse = rng.choice([0, 1, 2, 4, 7, 12])
        if chatter:
            chatter -= 1
            fault_in = rng.randint(0, 1) if chatter > 1 else 1
        stop = int(stopped > 0)
        stopped = max(stopped - 1, 0)
        update = s.update_strobe()
        h = s.h if update or rng.random() < 0.5 else rng.randrange(1 << n)  # noise between
        inputs = {"rst": rst, "h": h, "update": update, "enable": s.enable, "dead": s.dead,
                  "min_pulse": s.min_pulse, "fault_in": fault_in, "fault_clear": clear,
                  "stop": stop}
        in_force.append(model.dead_in_force)     # the legs act on last clock's dead
        out = model.step(**inputs)
        for name in INPUTS:
            stim[name].append(inputs[name])
        for name in DRIVER_OUTPUTS:
            expected[name].append(out[name])
        mask = (1 << n) - 1
        up.append(out["upper"] ^ (mask if p["upper_active_low"] else 0))
        lo.append(out["lower"] ^ (mask if p["lower_active_low"] else 0))
    CARRY["last"] = {name: stim[name][-1] for name in INPUTS}
    kill = [f | k for f, k in zip(expected["fault_input"], stim["stop"], strict=True)]
    turn_ons = check_gate_safety(up, lo, n, dead=in_force, kill=kill,
                                 rst=stim["rst"], dt_run0=dt_run0)
    return stim, expected, turn_ons


async def run_scenario(dut, scenario, cycles):
    p = params()
    rng = seeded_rng(dut, f"driver_{scenario}")
    stim, expected, turn_ons = generate(rng, scenario, p, cycles)
    assert turn_ons >= 20, f"driver_{scenario}: only {turn_ons} turn-ons, the test is vacuous"
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
async def driver_min_pulse(dut):
    """Update periods shorter than dead time + minimum pulse: pulses stretched or swallowed."""
    await run_scenario(dut, "min_pulse", 4000)


@pytest.mark.parametrize(("phases", "dead_min", "time_width", "upper_low", "lower_low"), CASES)
def test_driver(phases, dead_min, time_width, upper_low, lower_low):
    run_block(lambda: GateDriver(phases, dead_min, time_width, upper_low, lower_low),
              "gate_driver", "test_driver",
              {"phases": phases, "dead_min": dead_min, "time_width": time_width,
               "upper_active_low": upper_low, "lower_active_low": lower_low})


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
                  "stop": int(rng.random() < 0.01)}
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
])
def test_driver_rejects_bad_parameters(args, kwargs, message):
    with pytest.raises(ValueError) as info:
        GateDriver(*args, **kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"dead_min": 0}, "dead_min must be an integer in [1, 65535] (clocks), not 0"),
    ({"dead_min": 2.0}, "dead_min must be an integer in [1, 65535] (clocks), not 2.0"),
    ({"dead_min": 1, "formal": "no"}, "formal must be a bool, not 'no'"),
])
def test_leg_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        LegDriver(**kwargs)
    assert str(info.value) == message

