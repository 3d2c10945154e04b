# amaranth: UnusedElaboratable=no
"""Every SymbiYosys run (``tb/mdfqm_testkit/formal.py``): the k-induction proofs and the covers of
each block alone (leg and gate driver, integrators, decoder, sort1, sort2, the b-bit generator) and
of the whole drop-in top (real and free core), and the tests of the tests: each safety proof must
fail on a design broken on purpose (a leg without dead time; the fault path and the integrator bound
cut in the netlist with Yosys ``connect -set`` on the named wire), and the check of the quantiser's
tables on a model that leaves them free ROMs.

The simulations of the same blocks, the properties included, are in their own files
(tb/test_driver.py, tb/test_top.py, ...).
"""

import pytest
from amaranth import C, Module, Mux, Signal, Value
from amaranth.hdl import Assert, Assume
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

import mdfqm_gateware.top as top_module
from mdfqm_gateware import driver, fronts, integrator
from mdfqm_gateware.core import MdfqmCore
from mdfqm_gateware.driver import GateDriver, LegDriver
from mdfqm_gateware.fronts import AxiLiteFront, WishboneFront
from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_gateware.integrator import Integrator
from mdfqm_gateware.resolution import Quantiser
from mdfqm_gateware.selector import ArgMax, StateDecoder
from mdfqm_gateware.sort import SortNetwork
from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec.bus import mapped_words
from mdfqm_spec.contract import BITS_WIDTH, Contract, sorting_network
from mdfqm_spec.regmap import ADDR_WIDTH, IRQ_MASK
from mdfqm_testkit.formal import AscWithoutDeadTimeLeg, NoDeadTimeLeg, assertion_site, run_sby

# ---------------------------------------------------------------------- leg and gate driver


@pytest.mark.parametrize(("name", "factory", "depth", "tasks"), [
    # the drop-in widths (a cover of a 64-clock dead time would need a deeper cover run)
    ("leg_dmin64_tw16", lambda: LegDriver(64, 16, formal=True), 24, ("prove",)),
    ("leg_dmin3_tw4", lambda: LegDriver(3, 4, formal=True), 24, ("prove", "cover")),
    ("gate_driver_n3_dmin5_tw16", lambda: GateDriver(3, 5, 16, True, False, formal=True), 20,
     ("prove", "cover")),
    # the other three pin polarity pairs (the properties at the pins read them back), all off
    # only: the fault reaction is the same logic before the polarity, proved in the run above
    # (and in the tops'), and it triples these runs' time
    ("gate_driver_n3_high_high",
     lambda: GateDriver(3, 2, 6, False, False, asc=False, formal=True), 12, ("prove",)),
    ("gate_driver_n3_high_low",
     lambda: GateDriver(3, 2, 6, False, True, asc=False, formal=True), 12, ("prove",)),
    ("gate_driver_n3_low_low",
     lambda: GateDriver(3, 2, 6, True, True, asc=False, formal=True), 12, ("prove",)),
])
def test_sby_proves_the_driver_properties(name, factory, depth, tasks):
    run_sby(factory(), name, depth, tasks)


def test_sby_proves_the_five_leg_gate_driver():
    """The driver's safety properties (both-on, dead time, fault, reset) for five legs, all
    off only (the fault reaction's logic is per leg and proved at three legs above and in the
    five-phase tops; with it this run takes twice as long)."""
    run_sby(GateDriver(5, 5, 16, True, False, asc=False, formal=True), "gate_driver_n5", 20,
            ("prove", "cover"))


# ---------------------------------------------------------------------- core blocks


@pytest.mark.parametrize(("phases", "width", "unit_shift"), [
    (3, 16, None), (5, 16, None), (9, 16, None),     # the core's (feedback in units of FULL)
    (3, 16, 6), (5, 16, 6),                         # the generator's (max_bits 8, kept copy)
])
def test_sby_proves_the_integrator_never_wraps(phases, width, unit_shift):
    """Property 5 per phase (T = X + R exactly after a start, X = T - U exactly or held after a
    commit) for any reference and feedback the ports carry, with the state register the core
    builds and the kept copy the generator's."""
    run_sby(Integrator(phases, width, unit_shift, formal=True, formal_sums=False,
                       kept_copy=unit_shift is not None),
            f"integrator_n{phases}_w{width}_s{unit_shift}", {"prove": 2, "cover": 8})


@pytest.mark.parametrize(("phases", "width", "kept_copy"), [(3, 16, False), (4, 8, True)])
def test_sby_proves_the_integrators_sum_to_zero(phases, width, kept_copy):
    """Property 5 and sum(X) == 0 for any reference / feedback sequences that each sum to zero.
    The sum follows from the per-phase exactness by linearity; the solver's proof of it is an
    adder-tree rearrangement that did not finish in 7 minutes for five phases (yices, z3 and
    boolector alike), so it runs for three and four."""
    run_sby(Integrator(phases, width, formal=True, kept_copy=kept_copy),
            f"integrator_sums_n{phases}_w{width}",
            {"prove": 2, "cover": 8})


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_the_state_is_a_candidate_and_the_feedback_its_voltage(phases):
    """Property 6 for any permutation, winner, policy and previous state; the covers reach
    every one of the 2**N gate states."""
    run_sby(StateDecoder(phases, formal=True), f"decoder_n{phases}", {"prove": 2, "cover": 4})


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_sort1_is_a_stable_descending_sort(phases):
    """For any input sequence: every layer holds a permutation (so the decoder's ``i_perm``
    always is one) and the inputs permuted by it; the output is sorted, ties in input order.
    Width: the core's T at the drop-in size."""
    sort1 = SortNetwork(phases, Contract(phases, 16).t_width, formal=True)
    run_sby(sort1, f"sort1_n{phases}", sort1.latency + 2)


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_sort2_picks_the_first_maximum(phases):
    """For any input sequence: the index is always a candidate (the decoder's ``i_j < N``) and
    a valid one is the first maximum."""
    sort2 = ArgMax(phases, 20, formal=True)
    run_sby(sort2, f"sort2_n{phases}", sort2.latency + 2)


# ---------------------------------------------------------------------- b-bit generator


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_the_generator_at_the_drop_in_size(phases):
    """The b-bit generator (max_bits 8): the core's blocks' properties in place, and the mode
    and b in force legal whatever arrives on ``mode`` and ``bits``."""
    run_sby(GatingSignalGenerator(phases, 16, max_bits=8, formal=True), f"generator_n{phases}",
            len(sorting_network(phases)) + 2, ("prove",))


@pytest.mark.parametrize(("phases", "width", "depth"), [
    # 28: the saturated commit takes more than 24 steps (28 reach it) since a long update's
    # minimum period is decoded, not looked up in a table: prep made the table a ROM whose
    # contents the solver chose freely (minima below the contract's, which the design never
    # has: shorter witnesses); run_sby now maps every such table to logic.
    # At N = 5 (the narrowest width, 9) it is reached in step 34 (depth 35: steps 0-34), in
    # about 10 min beside another proof, so `make prove-long` gives the run 30 min
    (3, 8, 28),
    pytest.param(5, 9, 35, marks=pytest.mark.long_proof),
])
def test_sby_covers_every_mode_of_the_generator(phases, width, depth):
    """With max_bits 2 (a long update fits the bounded run): an update in every mode (mdfqm,
    svpwm, dpwm0, dpwm1, sector dpwm), the slot layout switching the gates inside an update in
    each gamma mode, both clamps, a saturated commit, every gate state as an update's result."""
    run_sby(GatingSignalGenerator(phases, width, max_bits=2, formal=True),
            f"generator_modes_n{phases}", depth, ("cover",), timeout=1800)


class QuantiserTables(wiring.Component):
    """The quantiser, its tables of b checked a clock after any b in ``[0, max_bits]`` arrives:
    ``o_slots = 2**b - 1`` and ``o_delta = 2**(max_bits - b)`` (its docstring)."""

    def __init__(self, max_bits: int):
        self.max_bits = max_bits
        super().__init__({"bits": In(BITS_WIDTH)})

    def elaborate(self, platform):
        m = Module()
        m.submodules.quantiser = quantiser = Quantiser(3, 8, self.max_bits)
        m.d.comb += quantiser.i_bits.eq(self.bits)
        bits_prev = Signal(BITS_WIDTH, reset_less=True)
        seen = Signal()     # a b arrived a clock ago (not the reset's)
        m.d.sync += [bits_prev.eq(self.bits), seen.eq(1)]
        slots, delta = C(0, self.max_bits), C(0, self.max_bits + 1)
        for b in range(self.max_bits + 1):
            slots = Mux(bits_prev == b, (1 << b) - 1, slots)
            delta = Mux(bits_prev == b, 1 << (self.max_bits - b), delta)
        m.d.comb += [
            Assume(self.bits <= self.max_bits),
            Assert(~seen | (quantiser.o_slots == slots), "o_slots is not 2**b - 1"),
            Assert(~seen | (quantiser.o_delta == delta), "o_delta is not 2**(max_bits - b)"),
        ]
        return m


@pytest.mark.parametrize("exact_tables", [True, False])
def test_sby_models_the_quantisers_tables_exactly(exact_tables):
    """The proofs see the design's tables of constants as they are: prep makes each table (a
    lookup by b) a ROM, whose contents the solver would choose freely, so run_sby maps it to
    logic. Without that step this proof fails: the tables are what the solver likes."""
    tables = QuantiserTables(4)
    if exact_tables:
        run_sby(tables, "quantiser_tables", 3, ("prove",))
    else:
        with pytest.raises(AssertionError, match="failed assertion"):
            run_sby(tables, "quantiser_tables_free", 3, ("prove",), keep_failed=False,
                    exact_tables=False)


# ---------------------------------------------------------------------- bus fronts


@pytest.mark.parametrize("bus", ["wishbone", "axi4lite"])
def test_sby_proves_the_bus_front_rules(bus):
    """The handshake rules of each front for any master behaviour (no assumption on the bus):
    Wishbone classic as ZipCPU's fwbc_slave checks them, AXI4-Lite as faxil_slave does (see
    rtl/mdfqm_gateware/fronts.py); the covers reach reads with data, acks back to back, held
    write responses with the next write waiting, SLVERR."""
    front = (WishboneFront(ADDR_WIDTH, formal=True) if bus == "wishbone" else
             AxiLiteFront(ADDR_WIDTH, mapped_words(3), formal=True))
    run_sby(front, f"front_{bus}", {"prove": 4, "cover": 10})




class FreeOutputs(wiring.Component):
    """A component whose every output is chosen freely by the solver in every clock
    (``AnySeq``): proving the top's properties over it proves them for any behaviour of the
    block it stands in for."""

    def elaborate(self, platform):
        from amaranth.hdl._ast import AnySeq  # not re-exported by amaranth.hdl in 0.5

        m = Module()
        for _path, member, value in self.signature.flatten(self):
            if member.flow == Out:
                m.d.comb += value.eq(AnySeq(len(Value.cast(value))))
        return m


class FreeCore(FreeOutputs):
    """Any core: any gate state and strobes in any clock."""

    def __init__(self, phases, width, rule, formal=False):
        reference = MdfqmCore(phases, width, rule)
        self.latency = reference.latency
        super().__init__(reference.signature)


class FreeGenerator(FreeOutputs):
    """Any generator: any gate state (so any edge inside an update), strobes, mode and b in
    force, in any clock."""

    def __init__(self, phases, width, rule, max_bits, formal=False):
        reference = GatingSignalGenerator(phases, width, rule, max_bits)
        self.latency, self.long_latency = reference.latency, reference.long_latency
        super().__init__(reference.signature)


# The whole top's bounded cover run (24 clocks) cannot drive an integrator into saturation,
# which takes many overmodulated updates; that cover is reached in the integrator's own run
# and in the generator's (above).
SATURATION_COVER_OUT_OF_DEPTH = ("cd dut.core.integrator", "delete r:FLAVOR=cover", "cd")
#: the proofs of the top with its real generator at the drop-in's b (and at N = 5): beyond
#: make test's budget, run by `make prove-top` (CI's step after make test) and `make prove-long`
TOP_PROOF = [pytest.mark.long_proof, pytest.mark.top_proof]


@pytest.mark.parametrize(("core", "phases", "dead_min", "tasks", "bus", "max_bits", "watchdog"), [
    ("free", 3, 64, ("prove",), "wishbone", 8, True),
    ("free", 5, 64, ("prove",), "wishbone", 8, True),
    ("free", 3, 2, ("prove", "cover"), "wishbone", 8, True),
    ("free", 3, 2, ("prove", "cover"), "axi4lite", 8, True),
    ("free", 3, 2, ("prove",), "wishbone", 0, False),    # the smallest build, no watchdog
    ("real", 3, 64, ("prove",), "wishbone", 2, True),
    ("real", 3, 64, ("prove",), "axi4lite", 2, True),
    ("real", 3, 64, ("prove",), "wishbone", 0, True),
    ("real", 5, 64, ("prove",), "wishbone", 0, True),
    ("real", 3, 2, ("cover",), "wishbone", 0, True),
    pytest.param("real", 3, 64, ("prove",), "wishbone", 8, True, marks=TOP_PROOF),
    pytest.param("real", 5, 64, ("prove",), "wishbone", 4, True, marks=TOP_PROOF),
    pytest.param("real", 3, 2, ("cover",), "wishbone", 1, True, marks=pytest.mark.long_proof),
    pytest.param("real", 5, 2, ("cover",), "wishbone", 0, True, marks=pytest.mark.long_proof)])
def test_sby_proves_the_top_properties(core, phases, dead_min, tasks, bus, max_bits, watchdog,
                                       monkeypatch):
    """k-induction over the whole top at the drop-in size (N = 3 and N = 5), with the real
    generator (or core, ``max_bits`` 0) and with a free one (any ``h``, ``update``, ``start``,
    stream ``ready``, mode in force in any clock: the driver's properties hold for any
    behaviour, edges inside an update included; once without the watchdog, the smallest
    build's). With the real generator or core the run also
    proves its properties in place, none of them assumed: the integrators never wrap, sort1 is
    a stable descending sort, sort2 picks the first maximum, the state is a candidate and the
    feedback its voltage, the mode and b in force are legal. Depth: sort1's latency + 2, so a
    sorted output has passed the whole network inside the induction window. The free cover run
    reaches gates switching after an enable through the bus, a fault cleared through the bus,
    both switches of every leg turning on, a turn-on in every mode and one after an edge inside
    a slot-mode update; the real core's every gate state as an update's result (both zero
    states through the zero policy; at N = 5 all-on needs a second update: reached in step
    43, depth 44), the real generator's a turn-on in every mode written through the bus and
    after a slot edge (48 clocks): those run in `make prove-long`, the proofs with the
    generator at the drop-in's b (and at N = 5) in `make prove-top` (CI) and `make
    prove-long`."""
    if core == "free":
        monkeypatch.setattr(top_module, "MdfqmCore", FreeCore)
        monkeypatch.setattr(top_module, "GatingSignalGenerator", FreeGenerator)
    cover_depth = {"free": 14, "real": 24 if phases == 3 else 44}[core]
    if core == "real" and max_bits:
        cover_depth = 48
    depth = {"prove": len(sorting_network(phases)) + 2, "cover": cover_depth}
    run_sby(MdfqmTop(phases, 16, dead_min=dead_min, bus=bus, max_bits=max_bits,
                     watchdog=watchdog, formal=True),
            f"top_{core}_n{phases}_dmin{dead_min}_{bus}_b{max_bits}{'' if watchdog else '_nowd'}",
            depth, tasks,
            mutation=SATURATION_COVER_OUT_OF_DEPTH if core == "real" else (),
            # the deep covers of `make prove-long` (the N = 5 one: about 7 min beside another
            # proof) get 30 min; make test's runs keep run_sby's 10
            timeout=1800 if "cover" in tasks and cover_depth > 24 else 600)


# ---------------------------------------------------------------------- tests of the tests
# Each must produce a counterexample: the proofs above are not vacuous.


def test_sby_finds_the_missing_dead_time():
    """The proof is not vacuous: the broken leg fails it."""
    with pytest.raises(AssertionError, match="BMC failed"):
        run_sby(NoDeadTimeLeg(3, 4, formal=True), "leg_broken", 12, tasks=("bmc",),
                keep_failed=False)


def test_sby_finds_an_ungated_fault():
    """With the fault no longer gating the legs, "all off after a fault" has a counterexample."""
    site = assertion_site(driver.__file__, "gates on one clock after the synchronised fault")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(GateDriver(3, 2, 6, formal=True), "driver_ungated_fault", 12, tasks=("bmc",),
                keep_failed=False, mutation=("cd dut", "connect -set fault_active 1'0", "cd"))


def test_sby_finds_an_asc_without_dead_time(monkeypatch):
    """A driver whose legs turn the ASC switch on at once, not after the dead time: the
    turn-on property has a counterexample (a fault with an ASC reaction while the other switch
    is on)."""
    monkeypatch.setattr(driver, "LegDriver", AscWithoutDeadTimeLeg)
    site = assertion_site(driver.__file__, "turn-on before the dead time in force elapsed")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut\.leg\d: "
                                             rf"\S*{site} "):
        run_sby(GateDriver(3, 2, 6, formal=True), "driver_asc_no_dead_time", 10, tasks=("bmc",),
                keep_failed=False)


class LowerPinActiveHighDriver(GateDriver):
    """A broken driver whose lower pins ignore ``lower_active_low`` (the last assignment to
    the pins wins): with an active-low lower driver, every lower switch is on from reset."""

    def elaborate(self, platform):
        m = super().elaborate(platform)
        m.d.comb += self.lower.eq(self.lo)
        return m


@pytest.mark.parametrize(("upper_low", "lower_low"), [(False, True), (True, True)])
def test_sby_finds_a_wrong_pin_polarity(upper_low, lower_low):
    """The lower pins driven active-high although the parameter says active-low (a mixed pair
    and a both-low one): the properties at the pins have a counterexample."""
    site = assertion_site(driver.__file__, "pins not off after reset")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(LowerPinActiveHighDriver(3, 2, 6, upper_low, lower_low, formal=True),
                f"driver_wrong_polarity_{int(upper_low)}{int(lower_low)}", 6, tasks=("bmc",),
                keep_failed=False)


class UnwiredWatchdogTop(MdfqmTop):
    """A broken top whose watchdog latch does not reach the driver (the last assignment to
    the driver's ``stop`` wins)."""

    def elaborate(self, platform):
        m = super().elaborate(platform)
        m.d.comb += m.submodules.driver.stop.eq(0)
        return m


def test_sby_finds_a_watchdog_that_does_not_stop_the_gates(monkeypatch):
    """The top with its watchdog latch no longer reaching the driver: "gates off a clock after
    the latch" has a counterexample (a free core, so the trip is a few clocks away)."""
    monkeypatch.setattr(top_module, "GatingSignalGenerator", FreeGenerator)
    site = assertion_site(top_module.__file__,
                          "gates on a clock after the watchdog latch (but the ASC switches)")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(UnwiredWatchdogTop(3, 16, dead_min=2, formal=True), "top_watchdog_unwired", 14,
                tasks=("bmc",), keep_failed=False)


@pytest.mark.parametrize(("broken", "message"), [
    # the total counter never counts (the turn-ons it adds tied to 0: 0..3 at N = 3)
    ("turn_ons 2'd0", "EVENTS_TOTAL is not the count of every leg's turn-ons"),
    # IRQ_STATUS never set (its register tied to 0)
    (f"irq_status {IRQ_MASK.bit_length()}'d0",
     "IRQ_STATUS is not set by its events and cleared by writing 1s"),
    # WATCHDOG_TRIPS never counts (its register tied to 0)
    ("wd_trips 16'd0", "WATCHDOG_TRIPS is not the saturating count of watchdog trips"),
], ids=["total_uncounted", "irq_status_unset", "watchdog_trips_uncounted"])
def test_sby_finds_a_top_register_that_misses_events(broken, message, monkeypatch):
    """A top whose total counter, IRQ_STATUS or WATCHDOG_TRIPS ignores its events: the
    property has a counterexample at the first one."""
    monkeypatch.setattr(top_module, "GatingSignalGenerator", FreeGenerator)
    site = assertion_site(top_module.__file__, message)
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(MdfqmTop(3, 16, dead_min=2, formal=True), f"top_{broken.split()[0]}_broken", 14,
                tasks=("bmc",), keep_failed=False,
                mutation=("cd dut", f"connect -set {broken}", "cd"))


def test_sby_finds_an_unbounded_integrator():
    """Integrating although the result does not fit: the wrap is caught."""
    site = assertion_site(integrator.__file__,
                          "integrator differs from T - U after a commit (it wrapped)")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(Integrator(3, 8, formal=True), "integrator_unbounded", 12, tasks=("bmc",),
                keep_failed=False, mutation=("cd dut", "connect -set fits 1'1", "cd"))


@pytest.mark.parametrize(("bus", "broken", "message"), [
    ("wishbone", "bus__ack 1'1", "wishbone: ack right after reset"),
    ("axi4lite", "port__w_en 1'1",
     "axi4lite: write responses do not match the AW requests one for one"),
])
def test_sby_finds_a_broken_bus_front(bus, broken, message):
    """A Wishbone front whose ack is stuck high, an AXI4-Lite front that issues a write in
    every clock, held or not: each breaks its bus's rules, and the check says which."""
    site = assertion_site(fronts.__file__, message)
    front = (WishboneFront(ADDR_WIDTH, formal=True) if bus == "wishbone" else
             AxiLiteFront(ADDR_WIDTH, mapped_words(3), formal=True))
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(front, f"front_{bus}_broken", 6, tasks=("bmc",), keep_failed=False,
                mutation=("cd dut", f"connect -set {broken}", "cd"))
