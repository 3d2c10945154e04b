# amaranth: UnusedElaboratable=no
"""The blocks of a campaign: each drop-in (core, generator, the top with each front) and the
gate driver, with what tests each: its vector stimulus (stage 1), its cocotb tests and formal
proof (stage 2).

The stimulus is the project's own (the test kit's core, b-bit, top and driver stimulus:
tb/mdfqm_testkit/), at the sizes the vector regressions of ``make test`` use; the cocotb tests
and the proof are those ``make test`` runs on the same configuration.
"""

from __future__ import annotations

import copy
import random
from collections.abc import Callable
from dataclasses import dataclass, field

from mdfqm_spec import regmap
from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.driver_stimulus import long_times_cycles
from mdfqm_testkit.top_stimulus import FULL_TOP_RUNS

__all__ = ["BLOCKS", "DRIVER", "DRIVER_SCENARIOS", "TOP_BLOCKS", "Block", "CocotbTest", "Run",
           "core_runs", "driver_runs", "generator_runs", "top_runs"]

#: one vector run: (name, inputs by port, expected outputs by port)
Run = tuple[str, dict, dict]


@dataclass(frozen=True)
class CocotbTest:
    """One cocotb test module run against the mutant (as ``make test`` runs it)."""

    module: str
    toplevel: str
    params: dict
    testcase: tuple[str, ...] | None = None


@dataclass(frozen=True)
class Block:
    """A block under mutation.

    ``build(formal)`` makes the component; ``toplevel`` is the module name its tests expect;
    ``stimulus(seed)`` gives the vector runs of stage 1; ``cocotb`` and ``formal_depth`` the
    tests of stage 2 (``formal_depth`` None: no proof of the block as a whole)."""

    name: str
    title: str
    toplevel: str
    build: Callable[[bool], object]
    stimulus: Callable[[int], list[Run]]
    cocotb: tuple[CocotbTest, ...] = ()
    formal_depth: int | None = None
    #: fault classes of the make-test sample: class -> source lines (``file:line``) to draw from
    classes: dict = field(default_factory=dict)
    #: hierarchy scopes (prefixes) left out of the draw: logic another block measures
    exclude: tuple[str, ...] = ()
    #: (instance, block): an instance of another block of the campaign, built with that block's
    #: parameters (tools/tests/test_mutate.py checks), whose survivors and undecided mutants
    #: also run through that block's stages (tools/mutate/campaign.py ``inner_checks``)
    inner: tuple[tuple[str, str], ...] = ()


def core_runs(seed: int, cycles: int = 200_000) -> list[Run]:
    from mdfqm_spec.contract import Contract
    from mdfqm_testkit.core_stimulus import SCENARIOS, generate

    contract = Contract(3, 16)
    runs = []
    for scenario in SCENARIOS:       # tb/test_core_vectors.py: 200 000 clocks a scenario
        stim, expected = generate(random.Random(f"{seed}-{scenario}"), scenario, contract,
                                  "largest_duty", cycles)
        runs.append((scenario, stim, expected))
    return runs


def generator_runs(seed: int, cycles: int = 20_000) -> list[Run]:
    from mdfqm_spec.contract import Contract
    from mdfqm_testkit.bbit_stimulus import LIMITS_CYCLES, SCENARIOS, generate

    contract = Contract(3, 16)
    runs = []
    for scenario in SCENARIOS:       # tb/test_bbit_vectors.py: 20 000 clocks a scenario
        stim, expected, _ = generate(random.Random(f"{seed}-{scenario}"), scenario, contract,
                                     "largest_duty", 8, cycles,
                                     bits_choices=tuple(range(1, 9)), segment=4000)
        runs.append((scenario, stim, expected))
    # tb/test_bbit_vectors.py's limits run, long enough for the largest period
    stim, expected, _ = generate(random.Random(f"{seed}-limits"), "limits", contract,
                                 "largest_duty", 8, max(cycles, LIMITS_CYCLES),
                                 bits_choices=tuple(range(1, 9)), segment=4000)
    runs.append(("limits-long", stim, expected))
    return runs


#: the driver's configuration: three legs, both pin polarities (the upper side active low),
#: the dead-time floor and width of the driver's own proof (tb/test_formal.py)
DRIVER = {"phases": 3, "dead_min": 5, "time_width": 16, "upper_active_low": True,
          "lower_active_low": False, "asc": True}
#: tb/test_driver.py's cocotb tests, in their order, with their lengths
DRIVER_SCENARIOS = (("random", 12000), ("fault_chatter", 4000), ("fault_in_dead_time", 3000),
                    ("enable_mid_update", 3000), ("dead_change", 4000), ("fault_reaction", 8000),
                    ("min_pulse", 4000), ("long_times", long_times_cycles(DRIVER["time_width"])))


def driver_runs(seed: int) -> list[Run]:
    """The cocotb driver test's scenarios (tb/test_driver.py) as one vector run, each led by
    the two reset clocks ``harness.start`` gives it (the driver keeps its dead time in force
    and the fault synchroniser through a reset, so the scenarios follow one another in one
    simulation, as in the cocotb test: :class:`DriverRun` carries the model)."""
    from mdfqm_model.driver import DRIVER_INPUTS, DRIVER_OUTPUTS
    from mdfqm_testkit.driver_stimulus import DriverRun

    p = DRIVER
    mask = (1 << p["phases"]) - 1
    run = DriverRun(p)
    stim = {name: [] for name in DRIVER_INPUTS}
    expected = {name: [] for name in (*DRIVER_OUTPUTS, "up", "lo")}

    def add(inputs, out):
        for name in DRIVER_INPUTS:
            stim[name].append(inputs[name])
        for name in DRIVER_OUTPUTS:
            expected[name].append(out[name])
        expected["up"].append(out["upper"] ^ (mask if p["upper_active_low"] else 0))
        expected["lo"].append(out["lower"] ^ (mask if p["lower_active_low"] else 0))

    for k, (scenario, cycles) in enumerate(DRIVER_SCENARIOS):
        for inputs, out in copy.deepcopy(run).reset_clocks():
            add(inputs, out)
        s, e, _ = run.generate(random.Random(f"{seed}-driver-{k}"), scenario, cycles)
        for c in range(cycles):
            add({name: s[name][c] for name in DRIVER_INPUTS},
                {name: e[name][c] for name in DRIVER_OUTPUTS})
    return [("scenarios", stim, expected)]


#: the top blocks: name -> (front, counter_width). The Wishbone block is the drop-in as
#: shipped (32-bit counters); the AXI4-Lite block's counters are 8 bits, the narrowest the top
#: builds, so that every bit of EVENTS and EVENTS_TOTAL and their wrap (COUNTER_WRAP) are in a
#: run's reach: at 32 bits, the bits from about 2**20 turn-ons and the wrap are out of any
#: simulation's (the last campaign at 32 bits: 5 of the block's 7 undecided mutants)
TOP_BLOCKS = {"top_wb": ("wishbone", regmap.COUNTER_WIDTH), "top_axi": ("axi4lite", 8)}


def top_runs(block: str, runs: tuple[int, ...]):
    """The vector runs of a top block, each of ``runs`` clocks; each run's functional coverage
    must close, as in tb/test_top_vectors.py."""
    bus, counter_width = TOP_BLOCKS[block]

    def make(seed: int) -> list[Run]:
        from mdfqm_gateware.top import MdfqmTop
        from mdfqm_testkit.top_stimulus import top_stimulus

        top = MdfqmTop(3, 16, bus=bus, counter_width=counter_width)
        out = []
        for k, cycles in enumerate(runs):
            coverage = Coverage()
            stim, expected, _ = top_stimulus(random.Random(f"{seed}-{bus}-{k}"), top, 3, 16,
                                             cycles, coverage)
            if coverage.missing():
                raise RuntimeError(f"{block}, seed {seed}, run {k}: coverage not closed: "
                                   f"{coverage.missing()}")
            out.append((f"run{k}", stim, expected))
        return out
    return make


def _top_tests(block: str) -> tuple[CocotbTest, ...]:
    bus, counter_width = TOP_BLOCKS[block]
    top = {"phases": 3, "width": 16, "rule": "largest_duty",
           "dead_min": regmap.DEFAULT_DEAD_MIN, "upper_active_low": False,
           "lower_active_low": False, "bus": bus, "counter_width": counter_width}
    singles = ("top_operate", "top_register_reference", "top_counters", "top_adc_trigger",
               "top_fault", "top_fault_reaction", "top_interrupt", "top_watchdog",
               "top_bad_input")
    return (CocotbTest("test_top", "mdfqm_top",
                       {**top, "max_bits": regmap.default_max_bits(16)}, singles),
            CocotbTest("test_bus_models", "mdfqm_top_bus_models", top))


def _blocks() -> dict[str, Block]:
    from mdfqm_gateware.core import MdfqmCore
    from mdfqm_gateware.driver import GateDriver
    from mdfqm_gateware.generator import GatingSignalGenerator
    from mdfqm_gateware.top import MdfqmTop
    from mdfqm_spec.contract import sorting_network

    depth = len(sorting_network(3)) + 2        # as tb/test_formal.py
    d = DRIVER
    core_params = {"phases": 3, "width": 16, "rule": "largest_duty"}
    blocks = [
        Block("core", "core (MdfqmCore, N=3, 16 bits)", "mdfqm_core",
              lambda formal: MdfqmCore(3, 16, formal=formal), core_runs,
              (CocotbTest("test_core", "mdfqm_core", core_params),), depth),
        Block("generator", "generator (GatingSignalGenerator, N=3, 16 bits, b<=8)",
              "gating_signal_generator",
              lambda formal: GatingSignalGenerator(3, 16, max_bits=8, formal=formal),
              generator_runs,
              (CocotbTest("test_bbit", "gating_signal_generator", {**core_params,
                                                                   "max_bits": 8}),), depth),
        Block("driver", "gate driver (GateDriver, 3 legs, dead_min 5, upper active low)",
              "gate_driver",
              lambda formal: GateDriver(d["phases"], d["dead_min"], d["time_width"],
                                        d["upper_active_low"], d["lower_active_low"],
                                        asc=d["asc"], formal=formal),
              driver_runs, (CocotbTest("test_driver", "gate_driver", dict(d)),), 20),
        Block("top_wb", "top, Wishbone (MdfqmTop, the drop-in mdfqm_top_n3_w16)", "mdfqm_top",
              lambda formal: MdfqmTop(3, 16, formal=formal),
              top_runs("top_wb", FULL_TOP_RUNS), _top_tests("top_wb"), depth,
              inner=(("core", "generator"),)),
        # the AXI4-Lite top's own logic: its front, the register file, counters, watchdog; the
        # core and the driver inside are the Wishbone top's netlist, measured there. Its vector
        # stage runs the Wishbone block's run lengths (the top-level logic's long run, whose top
        # octaves of the settings, the watchdog and the counters' wrap a 50 000-clock run
        # cannot reach: make test runs them on the Wishbone top; tb/test_top_vectors.py's
        # AXI4-Lite case is the front's short run), its counters 8 bits (TOP_BLOCKS)
        Block("top_axi", "top, AXI4-Lite (MdfqmTop bus=axi4lite counter_width=8, "
              "mdfqm_top_axil_n3_w16 with 8-bit counters; its front and top-level logic)",
              "mdfqm_top", lambda formal: MdfqmTop(3, 16, bus="axi4lite",
                                                   counter_width=TOP_BLOCKS["top_axi"][1],
                                                   formal=formal),
              top_runs("top_axi", FULL_TOP_RUNS), _top_tests("top_axi"), depth,
              exclude=("core", "driver")),
    ]
    return {b.name: b for b in blocks}


BLOCKS = _blocks()
