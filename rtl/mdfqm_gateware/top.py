"""The drop-in top: the gating-signal generator (MDFQM, SVPWM, DPWM, b-bit; or the MDFQM core
alone, ``max_bits=0``) + gate driver + register file behind a Wishbone-classic or an AXI4-Lite
front + switching counters + ADC trigger + reference watchdog. Every bit on every clock follows
:class:`mdfqm_model.top.TopModel`; the register map (addresses, bits, reset values, clamps) is
imported from :mod:`mdfqm_spec.regmap` and documented in ``docs/top.md``.
"""

import functools
import operator

from amaranth import C, Cat, Module, Mux, ResetSignal, Signal, signed
from amaranth.hdl import Assert, Cover
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec import regmap
from mdfqm_spec.bus import AXI_ADDR_WIDTH, WRITE_LATENCY, mapped_words, validate_bus
from mdfqm_spec.contract import (
    BITS_WIDTH,
    MODE_WIDTH,
    MODES,
    TIME_WIDTH,
    Contract,
    loop_latency,
    resolution_latency,
    validate_dead_min,
    validate_rule,
    validate_top_max_bits,
)
from mdfqm_spec.regmap import info_word, validate_top_phases
from mdfqm_spec.validate import validate_bool, validate_int

from .arith import at_least
from .bus import AxiLiteSignature, WishboneSignature
from .core import MdfqmCore
from .driver import GateDriver
from .fronts import AxiLiteFront, WishboneFront
from .generator import GatingSignalGenerator

__all__ = ["MdfqmTop"]


def _saturate(value, top: int, over):
    """``min(value, top)`` for an unsigned ``value`` and ``top = 2**k - 1``, given ``over``:
    the bits of ``value`` above ``k`` not all 0 (see :func:`_clamp_tests`)."""
    k = top.bit_length()
    assert top == (1 << k) - 1
    return Mux(over, top, value[:k])


def _delayed(m, value, clocks: int, name: str, reset_less: bool = False):
    """``value`` through ``clocks`` registers in a row (the last one; ``value`` for 0)."""
    for k in range(clocks):
        reg = Signal.like(value, name=f"{name}_{k + 1}", reset_less=reset_less)
        m.d.sync += reg.eq(value)
        value = reg
    return value


def _only_asc(driver):
    """Every switch off but those of the active short circuit in force (none when the
    reaction in force is all off)."""
    ones = (1 << len(driver.up)) - 1
    r = driver.reaction
    return ((driver.up & Mux(r == 2, 0, ones)) == 0) & ((driver.lo & Mux(r == 1, 0, ones)) == 0)


def _saturate_code(value, contract, fits):
    """A bus word (two's complement) clamped to the contract's reference codes, the full
    ``width``-bit signed range, given ``fits``: the word is in that range (see
    :func:`_clamp_tests`)."""
    width = contract.width
    assert (contract.code_min, contract.code_max) == (-(1 << (width - 1)), (1 << (width - 1)) - 1)
    return Mux(fits, value[:width], Mux(value[-1], contract.code_min, contract.code_max))


def _clamp_tests(word, contract, dead_min: int) -> dict:
    """The tests of a bus word that the registers' clamps select by: above 16 bits, above 8
    bits, below the dead-time floor, and in the reference codes' range (the bits from
    ``width - 1`` up all equal). Each is logic on the bits, no compare's carry chain."""
    high = word[contract.width - 1:]
    return {"over16": word[16:].any(), "over8": word[8:].any(),
            "below_floor": ~at_least(word, dead_min), "code_fits": (high == 0) | high.all()}


class MdfqmTop(wiring.Component):
    """An N-phase MDFQM / SVPWM / DPWM modulator with a safe gate driver, for a soft CPU or an
    FOC block. The modulation mode and the resolution b are runtime registers (``MODULATION``,
    taken at update starts); the gate driver applies dead time, minimum pulse, fault and the
    counters to every edge, at update and at slot boundaries alike. A reference watchdog
    (``WATCHDOG``, off after reset) turns the gates off when the references stop.

    Between the FOC loop (a reference per phase) and the gate-driver chip (an upper and a lower
    gate per leg). Runtime settings live in a register file behind a Wishbone-classic or an
    AXI4-Lite slave (``docs/top.md``: register map, clamps, bus timing, timing of one update).

    Ports
    -----
    wb : In(WishboneSignature(6))
        With ``bus="wishbone"``: ``wb__cyc wb__stb wb__we wb__adr[5:0] wb__dat_w[31:0]
        wb__sel[3:0]`` in, ``wb__dat_r[31:0] wb__ack`` out. ``ack`` is registered, one clock
        after the request; ``dat_r`` is valid with it. ``sel`` is ignored.
    s_axi : In(AxiLiteSignature(8))
        With ``bus="axi4lite"`` (instead of ``wb``): the five AXI4-Lite channels,
        ``s_axi__awaddr[7:0]`` (byte addresses) ... ``s_axi__rready``; see
        :class:`~.fronts.AxiLiteFront`.
    ref : In(stream.Signature(ArrayLayout(signed(width), phases)))
        Direct reference input for an FOC block in the same fabric (``ref__valid``,
        ``ref__ready``, ``ref__payload``; ``2**(width-2)`` codes per Vdc). ``ready`` is
        combinational from registers; it is low while a register-committed beat is pending (the
        register beat wins).
    fault_in : In(1)
        Asynchronous, active-high fault (desaturation / over-current / driver fault). Two-flop
        synchronised; every gate off one clock after the synchronised level is high; latched
        until ``CMD.FAULT_CLEAR`` while the synchronised input is low.
    sync_in : In(1)
        Synchronous to ``clk``: another instance's ``sync_out`` (the core's ``sync_in``).
    upper, lower : Out(phases)
        Gate pins of each leg, registered, in the polarity of the parameters; reset: all off.
        They follow every edge of the generator's gate state: at update boundaries and, in a
        slot mode, at the slot boundaries inside an update.
    adc_trigger : Out(1)
        Registered one-clock pulse in cycle ``s + 1 + ADC_OFFSET`` of each update (``s`` the
        update start); none when ``ADC_OFFSET`` is not below the update period.
    sync_out : Out(1)
        High in the first clock of each update (the core's ``start``, combinational from
        registers): wire it to the other instances' ``sync_in``.
    fault : Out(1)
        The fault latch (registered), for a LED or an interlock.
    irq : Out(1)
        Interrupt, level, active high (registered): ``IRQ_STATUS & IRQ_ENABLE`` not zero in the
        clock before.

    Parameters
    ----------
    phases : int in [3, 16]
    width : int in [min_width(phases), 32]
        Reference code width (see :class:`MdfqmCore`).
    rule : "largest_duty" | "exact_nearest"
    dead_min : int in [1, 65535]
        Dead-time floor in clocks, fixed at elaboration: smaller ``DEAD`` writes store it, and
        after a reset it is the dead time until software writes ``DEAD``. It must cover the
        power stage's turn-off time.
    upper_active_low, lower_active_low : bool
        Pin polarity per side (fixed at elaboration: the reset level must already be "off").
    bus : "wishbone" | "axi4lite"
        The register bus's front.
    counter_width : int in [8, 32]
        Bits of the switching counters (they wrap at ``2**counter_width``).
    asc : bool
        Build the active short circuit in (``FAULT_REACTION`` codes 1 and 2, ``INFO.ASC``);
        False: the only fault reaction is all off (those codes store 0).
    watchdog : bool
        Build the reference watchdog in (``WATCHDOG``, ``WATCHDOG_TRIPS``, ``INFO.WATCHDOG``);
        False: it never trips (``WATCHDOG`` and ``FAULT_REACTION.WATCHDOG`` store 0,
        ``WATCHDOG_TRIPS``, ``STATUS.WATCHDOG`` and ``IRQ_STATUS.WATCHDOG`` stay 0,
        ``CMD.WATCHDOG_CLEAR`` does nothing), for a design whose references cannot stop or
        that watches them itself.
    max_bits : int, 0 or in [1, min(12, width - 2)]; default min(8, width - 2)
        Largest resolution b of the slot modes (SVPWM, DPWM0, DPWM1, DPWM: ``2**b`` slots per
        update). 0 builds the MDFQM-only top (the core alone, the smallest): ``MODULATION``
        then holds mode 0, and any other mode written is clamped to it (flagged).
    formal : bool
        Emit the safety ``Assert`` statements and the bus front's handshake rules (not in the
        drop-in Verilog).

    Attributes
    ----------
    latency : int
        The loop latency (smallest update period) of an MDFQM update in clocks.
    long_latency : int
        The latency of a slot-mode update (``latency`` when ``max_bits`` is 0).
    """

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty",
                 dead_min: int = regmap.DEFAULT_DEAD_MIN, upper_active_low: bool = False,
                 lower_active_low: bool = False, bus: str = "wishbone",
                 counter_width: int = regmap.COUNTER_WIDTH,
                 max_bits: int | None = None, asc: bool = True, watchdog: bool = True,
                 formal: bool = False):
        validate_top_phases(phases)
        self.asc = validate_bool(asc, "asc")
        self.watchdog = validate_bool(watchdog, "watchdog")
        self.bus = validate_bus(bus)
        self.counter_width = validate_int(counter_width, "counter_width", 8,
                                          regmap.COUNTER_WIDTH)
        self.contract = Contract(phases, width)
        self.rule = validate_rule(rule, phases)
        self.dead_min = validate_dead_min(dead_min, TIME_WIDTH)
        self.upper_active_low = validate_bool(upper_active_low, "upper_active_low")
        self.lower_active_low = validate_bool(lower_active_low, "lower_active_low")
        self.formal = validate_bool(formal, "formal")
        self.phases, self.width = phases, width
        if max_bits is None:
            max_bits = regmap.default_max_bits(width)
        self.max_bits = validate_top_max_bits(max_bits, width)
        self.latency = loop_latency(phases, rule)
        self.long_latency = resolution_latency(phases, max_bits) if max_bits else self.latency
        super().__init__({
            **({"wb": In(WishboneSignature(regmap.ADDR_WIDTH))} if bus == "wishbone" else
               {"s_axi": In(AxiLiteSignature(AXI_ADDR_WIDTH))}),
            "ref": In(stream.Signature(data.ArrayLayout(signed(width), phases))),
            "fault_in": In(1),
            "sync_in": In(1),
            "upper": Out(phases),
            "lower": Out(phases),
            "adc_trigger": Out(1),
            "sync_out": Out(1),
            "fault": Out(1),
            "irq": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        if self.max_bits:
            core = GatingSignalGenerator(n, self.width, self.rule, self.max_bits,
                                         formal=self.formal)
            assert core.long_latency == self.long_latency
        else:
            core = MdfqmCore(n, self.width, self.rule, formal=self.formal)
        m.submodules.core = core
        assert core.latency == self.latency
        m.submodules.driver = driver = GateDriver(
            n, self.dead_min, TIME_WIDTH, self.upper_active_low, self.lower_active_low,
            asc=self.asc, formal=self.formal)
        if self.bus == "wishbone":
            m.submodules.front = front = WishboneFront(regmap.ADDR_WIDTH, formal=self.formal)
            wiring.connect(m, wiring.flipped(self.wb), front.bus)
        else:
            m.submodules.front = front = AxiLiteFront(regmap.ADDR_WIDTH, mapped_words(n),
                                                      formal=self.formal)
            wiring.connect(m, wiring.flipped(self.s_axi), front.bus)
        port = front.port
        # the write as the register file takes it, WRITE_LATENCY clocks after the front issues
        # it: registered, so that the bus inputs' paths end here and not in the register
        # decode and the gate driver behind it (the Fmax path of every device)
        w_en = _delayed(m, port.w_en, WRITE_LATENCY, "w_en")
        w_adr = _delayed(m, port.w_adr, WRITE_LATENCY, "w_adr", reset_less=True)
        w_data = _delayed(m, port.w_data, WRITE_LATENCY, "w_data", reset_less=True)
        # the clamps' tests of the word, made from the write as the front issues it and
        # delayed with it: a register's write then only selects (the clamps, from the
        # registered word, were the Fmax path of the tops on the UP5K)
        clamp = {name: _delayed(m, test, WRITE_LATENCY, f"w_{name}", reset_less=True)
                 for name, test in _clamp_tests(port.w_data, c, self.dead_min).items()}

        # ---------------------------------------------------------------- registers
        ctrl = Signal(2)
        period = Signal(16, init=self.latency)
        osr = Signal(8, init=1)
        dead = Signal(16, init=self.dead_min)
        min_pulse = Signal(16)
        adc_offset = Signal(16)
        ref_layout = data.ArrayLayout(signed(self.width), n)
        ref_regs = Signal(ref_layout)
        snapshot = Signal(ref_layout)
        ref_pending = Signal()
        events = Signal(data.ArrayLayout(self.counter_width, n))
        total = Signal(self.counter_width)
        irq_bits = regmap.IRQ_MASK.bit_length()
        irq_enable = Signal(irq_bits)
        irq_status = Signal(irq_bits)
        mode_request = Signal(MODE_WIDTH)
        bits_request = Signal(BITS_WIDTH)
        wd_timeout = Signal(16)
        wd_trips = Signal(16)
        reaction_fault = Signal(2)
        reaction_watchdog = Signal(2)

        # ---------------------------------------------------------------- register port
        # the command strobes are decoded from the write as the front issues it and delayed
        # with it: the decode sits before the registers, not between them and the gate driver
        cmd = Signal(5)
        m.d.comb += cmd.eq(_delayed(m, Mux(port.w_en & (port.w_adr == regmap.CMD),
                                           port.w_data[:5], 0), WRITE_LATENCY, "cmd"))
        ref_commit = cmd[0]
        fault_clear = cmd[1]
        count_clear = cmd[2]
        watchdog_clear = cmd[3]
        all_off = cmd[4]

        word = w_data

        def written(address):
            return w_en & (w_adr == address)

        with m.If(written(regmap.CTRL)):
            m.d.sync += ctrl.eq(word[:2])
        with m.If(written(regmap.PERIOD)):
            m.d.sync += period.eq(_saturate(word, 0xFFFF, clamp["over16"]))
        with m.If(written(regmap.OSR)):
            m.d.sync += osr.eq(_saturate(word, 0xFF, clamp["over8"]))
        with m.If(written(regmap.DEAD)):
            m.d.sync += dead.eq(Mux(clamp["below_floor"], self.dead_min,
                                 _saturate(word, 0xFFFF, clamp["over16"])))
        with m.If(written(regmap.MIN_PULSE)):
            m.d.sync += min_pulse.eq(_saturate(word, 0xFFFF, clamp["over16"]))
        with m.If(written(regmap.ADC_OFFSET)):
            m.d.sync += adc_offset.eq(_saturate(word, 0xFFFF, clamp["over16"]))
        with m.If(written(regmap.IRQ_ENABLE)):
            m.d.sync += irq_enable.eq(word[:irq_bits])
        if self.watchdog:   # else WATCHDOG and WATCHDOG_TRIPS read 0: it never trips
            with m.If(written(regmap.WATCHDOG)):
                m.d.sync += wd_timeout.eq(_saturate(word, 0xFFFF, clamp["over16"]))
        with m.If(written(regmap.MODULATION)):
            m.d.sync += [mode_request.eq(word[regmap.MODULATION_MODE_SHIFT:][:MODE_WIDTH]),
                         bits_request.eq(word[regmap.MODULATION_BITS_SHIFT:][:BITS_WIDTH])]
        if self.asc:        # else both read 0: every reaction is all off
            with m.If(written(regmap.FAULT_REACTION)):
                m.d.sync += reaction_fault.eq(word[0:2])
                if self.watchdog:
                    m.d.sync += reaction_watchdog.eq(word[2:4])
        for i in range(n):
            with m.If(written(regmap.REF_BASE + i)):
                m.d.sync += ref_regs[i].eq(_saturate_code(word, c, clamp["code_fits"]))

        mode_clamped, mode_in_force, bits_in_force = self._modulation(
            m, core, mode_request, bits_request)
        if self.watchdog:
            # a reference seen by the watchdog the clock after it arrives: off the bus-decode
            # path
            arrival = Signal()
            m.d.sync += arrival.eq((self.ref.valid & self.ref.ready) | ref_commit)
            wd_tripped, wd_trip, wd_quiet = self._watchdog(m, core.start, arrival, wd_timeout,
                                                           wd_trips, watchdog_clear, count_clear)
        else:
            wd_tripped, wd_trip = C(0, 1), C(0, 1)
        rd = Signal(32)
        status = Cat(driver.fault, driver.fault_input, driver.active, ref_pending,
                     core.saturated, core.period_clamped, mode_clamped, wd_tripped,
                     driver.reaction)
        info = info_word(n, self.width, self.rule, self.upper_active_low,
                         self.lower_active_low, self.latency, self.max_bits, asc=self.asc,
                         watchdog=self.watchdog)
        # the read: an OR of the registers, each ANDed with its address decoded (every word
        # not in the map reads 0)
        reads = {
            regmap.ID: C(regmap.ID_VALUE, 32), regmap.INFO: C(info, 32),
            regmap.DEAD_MIN: C(self.dead_min, 32), regmap.CTRL: ctrl, regmap.STATUS: status,
            regmap.PERIOD: period, regmap.OSR: osr, regmap.DEAD: dead,
            regmap.MIN_PULSE: min_pulse, regmap.ADC_OFFSET: adc_offset,
            regmap.EVENTS_TOTAL: total, regmap.GATES: driver.up | (driver.lo << 16),
            regmap.IRQ_ENABLE: irq_enable, regmap.IRQ_STATUS: irq_status,
            regmap.WATCHDOG: wd_timeout, regmap.WATCHDOG_TRIPS: wd_trips,
            # each field as the driver acts on it (3 reads 0): one decode for both
            regmap.FAULT_REACTION: Cat(driver.reaction_fault_acted,
                                       driver.reaction_watchdog_acted),
            regmap.MODULATION: (mode_in_force << regmap.MODULATION_MODE_SHIFT)
            | (bits_in_force << regmap.MODULATION_BITS_SHIFT),
            **{regmap.REF_BASE + i: ref_regs[i] for i in range(n)},     # signed: sign-extended
            **{regmap.EVENTS_BASE + i: events[i] for i in range(n)},
        }
        m.d.comb += rd.eq(functools.reduce(operator.or_, (
            Mux(port.r_adr == address, value, 0) for address, value in reads.items())))
        m.d.comb += port.r_data.eq(rd)

        # ---------------------------------------------------------------- reference input
        m.d.comb += [
            core.ref.valid.eq(ref_pending | self.ref.valid),
            core.ref.payload.eq(Mux(ref_pending, snapshot.as_value(),
                                    self.ref.payload.as_value())),
            self.ref.ready.eq(core.ref.ready & ~ref_pending),
        ]
        with m.If(ref_commit):
            m.d.sync += [snapshot.eq(ref_regs), ref_pending.eq(1)]
        with m.Elif(ref_pending & core.ref.ready):
            m.d.sync += ref_pending.eq(0)

        # ---------------------------------------------------------------- core and driver
        m.d.comb += [
            core.period.eq(period),
            core.osr.eq(osr),
            core.zero_policy.eq(ctrl[1]),
            core.sync_in.eq(self.sync_in),
            driver.h.eq(core.h),
            driver.update.eq(core.update),
            driver.enable.eq(ctrl[0]),
            driver.dead.eq(dead),
            driver.min_pulse.eq(min_pulse),
            driver.fault_in.eq(self.fault_in),
            driver.fault_clear.eq(fault_clear),
            driver.stop.eq(wd_tripped),
            driver.reaction_fault.eq(reaction_fault),
            driver.reaction_watchdog.eq(reaction_watchdog),
            driver.all_off.eq(all_off),
            self.upper.eq(driver.upper),
            self.lower.eq(driver.lower),
            self.fault.eq(driver.fault),
            self.sync_out.eq(core.start),
        ]

        # ---------------------------------------------------------------- switching counters
        turn_ons = Signal(range(n + 1))
        m.d.comb += turn_ons.eq(sum(driver.event[i] for i in range(n)))
        with m.If(count_clear):
            m.d.sync += [events.eq(0), total.eq(0)]
        with m.Else():
            m.d.sync += [events[i].eq(events[i] + driver.event[i]) for i in range(n)]
            m.d.sync += total.eq(total + turn_ons)
        # the total wraps when its sum carries out: at most N legs turn on in a clock, so only
        # when its high bits are all ones, and then the carry out of its low bits' sum. The
        # turn-ons pass through that small sum, not through the whole count's carry chain (on
        # the iCE40s it led from a leg's turn-on to IRQ_STATUS).
        low_bits = n.bit_length()
        low_sum = Signal(low_bits + 1)
        m.d.comb += low_sum.eq(total[:low_bits] + turn_ons)
        total_wraps = total[low_bits:].all() & low_sum[low_bits]

        # ---------------------------------------------------------------- interrupt
        sources = {regmap.IRQ_FAULT: driver.fault_input & ~driver.fault,
                   regmap.IRQ_COUNTER_WRAP: total_wraps & ~count_clear,
                   regmap.IRQ_SAMPLE: core.sample,
                   regmap.IRQ_SHORT_EDGE: driver.short_edge_now.any(),
                   regmap.IRQ_WATCHDOG: wd_trip}
        irq_events = Cat(*(sources[1 << bit] for bit in range(irq_bits)))
        cleared = Mux(written(regmap.IRQ_STATUS), word[:irq_bits], 0)
        status_next = (irq_status & ~cleared) | irq_events
        irq_formal = (port, irq_status, irq_events)         # for _irq_properties
        # irq from the registers, not their next values: off the bus decode's path (UP5K Fmax)
        m.d.sync += [irq_status.eq(status_next),
                     self.irq.eq((irq_status & irq_enable).any())]

        # ---------------------------------------------------------------- ADC trigger
        # the update's own clock count (the sequencer's): no counter of its own
        m.d.sync += self.adc_trigger.eq(core.elapsed == adc_offset)

        if self.formal:
            self._properties(m, ctrl, dead, driver, (events, total, count_clear), irq_formal)
            m.d.comb += Assert((driver.reaction_fault_acted != 3)
                               & (driver.reaction_watchdog_acted != 3),
                               "FAULT_REACTION reads a code that is no reaction")
            if self.watchdog:
                self._watchdog_properties(m, core.start, arrival, wd_timeout,
                                          (wd_tripped, wd_quiet, wd_trips),
                                          (watchdog_clear, count_clear), driver)
            if self.max_bits:
                self._mode_covers(m, core, driver)
            irq_was = Signal(reset_less=True)       # IRQ_STATUS & IRQ_ENABLE, a clock ago
            rst_prev = Signal(reset_less=True)
            m.d.sync += [irq_was.eq((irq_status & irq_enable).any()), rst_prev.eq(ResetSignal())]
            m.d.comb += [Assert(self.irq == (irq_was & ~rst_prev),
                                "irq is not IRQ_STATUS & IRQ_ENABLE of the clock before"),
                         Cover(self.irq & irq_status[0])]
        return m

    def _modulation(self, m, core, mode_request, bits_request):
        """The requested mode and b to the generator; ``(clamped flag, mode in force, b in
        force)``. The MDFQM-only top keeps mode 0 and flags a start that was asked for another
        (``mdfqm_spec.contract.latch_mode`` with ``max_bits`` 0)."""
        if self.max_bits:
            m.d.comb += [core.mode.eq(mode_request), core.bits.eq(bits_request)]
            return core.mode_clamped, core.mode_in_force, core.bits_in_force
        mode_clamped = Signal()
        with m.If(core.start):
            m.d.sync += mode_clamped.eq(mode_request != 0)
        return mode_clamped, 0, 0

    def _watchdog(self, m, start, arrival, timeout, trips, clear, count_clear):
        """The reference watchdog: ``(latch, trip strobe, quiet)``. ``quiet`` counts the update
        starts since the last reference arrival (held at 0 while off or tripped); the start that
        finds ``quiet >= TIMEOUT`` without an arrival seen (registered) in its clock trips it."""
        # the count is held inverted: ``quiet >= timeout`` is then ``timeout + ~quiet`` not
        # carrying out, an addition of two registers as they are (a compare would put an
        # inverter in front of every bit of its carry chain); the saturating increment is a
        # decrement, whose carry out is the saturation test. No reset (a reset to all ones
        # costs the iCE40 an inverter a bit): TIMEOUT resets to 0, which zeroes the count on
        # the clock after the reset, before any write can make TIMEOUT nonzero
        quiet_n = Signal(16, reset_less=True)
        quiet_dec = Signal(17)
        m.d.comb += quiet_dec.eq(quiet_n + 0xFFFF)          # carries out unless saturated
        tripped = Signal()
        trip = Signal()
        m.d.comb += trip.eq((timeout != 0) & ~tripped & start & ~arrival
                            & ~(timeout + quiet_n)[16])
        with m.If(arrival | (timeout == 0) | tripped | trip):
            m.d.sync += quiet_n.eq(0xFFFF)
        with m.Elif(start):
            m.d.sync += quiet_n.eq(Mux(quiet_dec[16], quiet_dec[:16], 0))
        with m.If(trip):
            m.d.sync += tripped.eq(1)
        with m.Elif(clear):
            m.d.sync += tripped.eq(0)
        # trips counted, saturating; CMD.COUNT_CLEAR with a trip in its clock leaves that one
        with m.If(count_clear):
            m.d.sync += trips.eq(trip)
        with m.Elif(trip & ~trips.all()):
            m.d.sync += trips.eq(trips + 1)
        return tripped, trip, ~quiet_n

    def _watchdog_properties(self, m, start, arrival, timeout, state, clears, driver):
        """Gates off the clock after the latch is seen (two after the tripping start), held
        until a clear; a trip only at an update start after ``TIMEOUT`` quiet ones (a ghost
        count, independent of the watchdog's own); WATCHDOG_TRIPS counts the latch's rises,
        saturating, zeroed by CMD.COUNT_CLEAR (a rise in the clearing clock counts 1).
        ``state``: the latch, the quiet count, the trip counter; ``clears``: CMD.WATCHDOG_CLEAR,
        CMD.COUNT_CLEAR."""
        tripped, quiet, trips = state
        clear, count_clear = clears
        ghost = Signal(17, reset_less=True, name="formal_wd_quiet")
        tripped_prev = Signal(reset_less=True, name="formal_wd_tripped_prev")
        clear_prev = Signal(reset_less=True, name="formal_wd_clear_prev")
        start_prev = Signal(reset_less=True, name="formal_wd_start_prev")
        armed_prev = Signal(reset_less=True, name="formal_wd_armed_prev")
        rst_prev = Signal(reset_less=True, name="formal_wd_rst_prev")
        m.d.sync += [
            ghost.eq(Mux(arrival | tripped | (timeout == 0) | ResetSignal(), 0,
                         Mux(start & (ghost != 0x1FFFF), ghost + 1, ghost))),
            tripped_prev.eq(tripped), clear_prev.eq(clear), start_prev.eq(start),
            armed_prev.eq((timeout != 0) & ~arrival & (ghost >= timeout)),
            rst_prev.eq(ResetSignal()),
        ]
        trips_prev = Signal.like(trips, reset_less=True, name="formal_wd_trips_prev")
        count_clear_prev = Signal(reset_less=True, name="formal_wd_count_clear_prev")
        m.d.sync += [trips_prev.eq(trips), count_clear_prev.eq(count_clear)]
        kept = Mux(count_clear_prev, 0, trips_prev)
        rose = tripped & ~tripped_prev
        all_off = _only_asc(driver)
        m.d.comb += [
            Assert(~rst_prev | (trips == 0), "WATCHDOG_TRIPS is not 0 after reset"),
            Assert(rst_prev | (trips == Mux(rose & (kept != 0xFFFF), kept + 1, kept)),
                   "WATCHDOG_TRIPS is not the saturating count of watchdog trips"),
            Cover(rose & count_clear_prev),
            Assert(~tripped_prev | all_off,
                   "gates on a clock after the watchdog latch (but the ASC switches)"),
            Assert(~tripped_prev | tripped | clear_prev | rst_prev,
                   "watchdog latch cleared without CMD.WATCHDOG_CLEAR"),
            Assert(tripped_prev | ~tripped | (start_prev & armed_prev),
                   "watchdog tripped other than at an update start after TIMEOUT quiet ones"),
            Assert(tripped | (timeout == 0) | (quiet == Mux(ghost > 0xFFFF, 0xFFFF, ghost)),
                   "invariant: the watchdog's count is the ghost's while it runs"),
            Cover(tripped & ~tripped_prev),
            Cover(tripped_prev & ~tripped),
        ]

    def _mode_covers(self, m, core, driver):
        """Covers: a turn-on at the pins in every mode, and one that follows an edge inside a
        slot-mode update (after the full dead time: the driver's proofs hold for every edge)."""
        h_prev = Signal.like(core.h, name="formal_h_prev", reset_less=True)
        slot_edge = Signal(name="formal_slot_edge")     # an edge since the last update strobe
        m.d.sync += h_prev.eq(core.h)
        with m.If(core.update):
            m.d.sync += slot_edge.eq(0)
        with m.Elif((core.h != h_prev) & (core.mode_in_force != 0)):
            m.d.sync += slot_edge.eq(1)
        turn_on = driver.event.any()
        for code in range(len(MODES)):
            m.d.comb += Cover(turn_on & (core.mode_in_force == code))
        m.d.comb += Cover(turn_on & slot_edge)

    def _properties(self, m, ctrl, dead, driver, counters, irq):
        """Reset gives all off until enabled; the dead-time register never below the floor;
        the switching counters count (``counters``: the legs', the total, the clear);
        IRQ_STATUS as documented (``irq``: the register port, the status, its events)."""
        self._counter_properties(m, *counters, driver,
                                 irq[2][regmap.IRQ_COUNTER_WRAP.bit_length() - 1])
        self._irq_properties(m, *irq)
        enabled_since_reset = Signal()          # reset by the domain's reset
        rst_prev = Signal(reset_less=True)
        m.d.sync += [enabled_since_reset.eq(enabled_since_reset | ctrl[0]),
                     rst_prev.eq(ResetSignal())]
        all_off = (driver.up == 0) & (driver.lo == 0)
        m.d.comb += [
            # before any enable only a fault reaction's ASC switches may be on
            Assert(enabled_since_reset | _only_asc(driver) | rst_prev,
                   "gates on before any enable (but the ASC switches)"),
            Assert(enabled_since_reset | ~driver.active | rst_prev,
                   "invariant: active before any enable"),
            Assert(dead >= self.dead_min, "DEAD below the floor"),
            Cover(enabled_since_reset & ~all_off),
        ]

    def _counter_properties(self, m, events, total, clear, driver, wrap):
        """Each leg's switching counter counts the driver's turn-on events of its leg, the
        total those of every leg (both modulo ``2**counter_width``), a CMD.COUNT_CLEAR zeroes
        them; the interrupt's COUNTER_WRAP event (``wrap``) is the total passing
        ``2**counter_width``; and (the invariant that closes the induction) the total is the
        legs' sum."""
        n, width = self.phases, self.counter_width
        events_prev = Signal.like(events, reset_less=True, name="formal_events_prev")
        total_prev = Signal(width, reset_less=True, name="formal_total_prev")
        event_prev = Signal(n, reset_less=True, name="formal_event_prev")
        clear_prev = Signal(reset_less=True, name="formal_count_clear_prev")
        rst_prev = Signal(reset_less=True, name="formal_count_rst_prev")
        wrap_prev = Signal(reset_less=True, name="formal_count_wrap_prev")
        m.d.sync += [events_prev.eq(events), total_prev.eq(total), event_prev.eq(driver.event),
                     clear_prev.eq(clear), rst_prev.eq(ResetSignal()), wrap_prev.eq(wrap)]
        for i in range(n):
            counted = (events_prev[i] + event_prev[i])[:width]
            m.d.comb += Assert(rst_prev | (events[i] == Mux(clear_prev, 0, counted)),
                               f"EVENTS_{i} is not the count of leg {i}'s turn-ons")
        counted = (total_prev + sum(event_prev[i] for i in range(n)))[:width]
        m.d.comb += [
            Assert(rst_prev | (total == Mux(clear_prev, 0, counted)),
                   "EVENTS_TOTAL is not the count of every leg's turn-ons"),
            Assert(total == sum(events[i] for i in range(n))[:width],
                   "invariant: EVENTS_TOTAL is the sum of the legs' counters"),
            # the legs add at most n a clock: the total wrapped exactly when it went down
            Assert(rst_prev | (wrap_prev == (~clear_prev & (total < total_prev))),
                   "the COUNTER_WRAP event is not EVENTS_TOTAL wrapping"),
            Cover(clear_prev & (total_prev != 0)),
        ]

    def _irq_properties(self, m, port, status, events):
        """IRQ_STATUS as docs/top.md has it: 0 after reset; each bit set the clock after its
        event, cleared by a write of IRQ_STATUS with a 1 in that bit taken by the register file
        (WRITE_LATENCY clocks after the front issues it; an event in the same clock wins), held
        otherwise. The write is followed here from the front's port through registers of the
        property's own, reset with the design's: a property built from the design's own
        delay and decode would follow their faults."""
        clocks = WRITE_LATENCY + 1
        w_en = _delayed(m, port.w_en, clocks, "formal_irq_w_en")
        w_adr = _delayed(m, port.w_adr, clocks, "formal_irq_w_adr", reset_less=True)
        w_data = _delayed(m, port.w_data[:len(status)], clocks, "formal_irq_w_data",
                          reset_less=True)
        status_prev = Signal.like(status, reset_less=True, name="formal_irq_status_prev")
        events_prev = Signal(len(status), reset_less=True, name="formal_irq_events_prev")
        rst_prev = Signal(reset_less=True, name="formal_irq_rst_prev")
        m.d.sync += [status_prev.eq(status), events_prev.eq(events),
                     rst_prev.eq(ResetSignal())]
        ones = Mux(w_en & (w_adr == regmap.IRQ_STATUS), w_data, 0)
        m.d.comb += [
            Assert(~rst_prev | (status == 0), "IRQ_STATUS is not 0 after reset"),
            Assert(rst_prev | (status == (events_prev | (status_prev & ~ones))),
                   "IRQ_STATUS is not set by its events and cleared by writing 1s"),
            Cover(~rst_prev & (status_prev & ones & ~events_prev).any()),
        ]
