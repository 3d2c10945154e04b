"""The gating-signal generator: MDFQM, SVPWM, DPWM and any b-bit resolution between them."""

from amaranth import Cat, Const, Module, Mux, Signal, signed
from amaranth.hdl import Assert, Cover
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import (
    BITS_WIDTH,
    MODE_WIDTH,
    MODES,
    Contract,
    loop_latency,
    resolution_latency,
    validate_max_bits,
    validate_rule,
)
from mdfqm_spec.validate import validate_bool

from .core import build_loop, loop_ports
from .resolution import Quantiser, SlotLayout
from .sequencer import UpdateSequencer

__all__ = ["GatingSignalGenerator"]


class GatingSignalGenerator(wiring.Component):
    """The paper's general gating-signal generator (its Sec. 3.1): each update period is split
    into ``S = 2**b`` slots, the staircase duties are quantised to whole slots and the error is
    fed back through the integrators; ``mode`` selects MDFQM (b = 0, the core), SVPWM
    (gamma = 1/2, centred 0-V1-V2-7-7-V2-V1-0), DPWM0 / DPWM1 (gamma = 0 / 1) or DPWM with the
    sector-dependent clamp, ``bits`` the resolution b; both are switched at runtime, at update
    boundaries.

    It contains the MDFQM core's blocks (reference stage, integrators, sort1, candidates, sort2,
    decoder; one sort network and one integrator bank serve every mode) plus a
    :class:`~.resolution.Quantiser` and a :class:`~.resolution.SlotLayout`. With ``mode`` held at
    0 it is, cycle for cycle and bit for bit, :class:`~.core.MdfqmCore`. Every bit and clock
    follows ``docs/contract.md`` (section "b-bit pulse-width resolution") and is
    predicted by :class:`mdfqm_model.clock.GeneratorModel`.

    Ports
    -----
    ref : In(stream.Signature(ArrayLayout(signed(width), phases)))
        Phase references (``2**(width-2)`` codes per Vdc, any common mode). One beat is taken at
        a time and used from the next sampling tick on (zero-order hold between ticks).
    period : In(16)
        Clocks per update, sampled at each update start; values below the update's minimum
        (``latency`` for a short update, ``max(long_latency, 2**b)`` for a long one) are used
        as that minimum and flagged by ``period_clamped``. In a gamma mode the ``2**b`` slots
        last ``floor(P / 2**b)`` clocks each, the last one also the remainder.
    osr : In(8)
        Updates per reference sample, sampled at each update start; 0 acts as 1.
    zero_policy : In(1)
        0: the MDFQM zero state is all-off. 1: all-off or all-on, whichever needs fewer
        transitions from the last state output. Sampled at each update start.
    sync_in : In(1)
        Share update boundaries between instances: high in a cycle in which the update in
        flight has committed by the next cycle (``phase + 1 >= latency``, or ``long_latency``
        for a long update) makes the next cycle an update start; ignored earlier.
    mode : In(MODE_WIDTH)
        0 mdfqm, 1 svpwm, 2 dpwm0, 3 dpwm1, 4 dpwm (sector clamp); 5..7 act as 0 and are flagged
        by ``mode_clamped``. Sampled at each update start.
    bits : In(BITS_WIDTH)
        b for the modes 1..4, used clamped to ``[1, max_bits]`` (flagged); ignored by mdfqm.
        Sampled at each update start.
    h : Out(phases)
        Gate state, bit i = upper switch of leg i on. Changes at ``update`` and, in a gamma mode,
        at the slot boundaries of the layout that ``update`` began.
    update : Out(1)
        One-clock strobe: the update's result (``h`` = its state or its first slot,
        ``saturated``) is visible this cycle; ``latency`` (short updates) or ``long_latency``
        (long ones) after its start.
    start : Out(1)
        High in the first clock of each update (use as sync out).
    sample : Out(1)
        High at an update start that samples the reference.
    saturated : Out(1)
        The last update hit the integrator bound and held the integrators (overmodulation).
    period_clamped : Out(1)
        The period requested at the last start was below that update's minimum.
    mode_clamped : Out(1)
        The last start's ``mode`` was illegal or its ``bits`` was clamped.
    mode_in_force : Out(MODE_WIDTH)
        The mode of the last update start, after the clamp (0 after reset).
    bits_in_force : Out(BITS_WIDTH)
        b of the last update start, after the clamp (0 for mdfqm and after reset).

    Parameters
    ----------
    phases, width, rule
        As :class:`~.core.MdfqmCore`'s.
    max_bits : int in [1, min(12, width - 2)]
        Largest resolution b offered (2**max_bits slots per update).
    formal : bool
        Emit the properties for the formal tests (none of them an assumption): the core's
        blocks' (as :class:`~.core.MdfqmCore` ``formal``), the mode and b in force always legal,
        and covers of an update in every mode, of the slot layout switching the gates inside an
        update in every gamma mode, and of both clamps.

    Attributes
    ----------
    latency : int
        Latency (and minimum period) of a short update: the core's (8 for three phases).
    long_latency : int
        Latency of a long update (20 for three phases and max_bits = 8).
    """

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty",
                 max_bits: int = 8, formal: bool = False):
        self.contract = Contract(phases, width)
        self.rule = validate_rule(rule, phases)
        self.formal = validate_bool(formal, "formal")
        self.max_bits = validate_max_bits(max_bits, width)
        self.phases, self.width = phases, width
        self.latency = loop_latency(phases, rule)
        self.long_latency = resolution_latency(phases, max_bits)
        super().__init__(loop_ports(
            phases, width,
            extra_inputs={"mode": In(MODE_WIDTH), "bits": In(BITS_WIDTH)},
            extra_outputs={"mode_clamped": Out(1), "mode_in_force": Out(MODE_WIDTH),
                           "bits_in_force": Out(BITS_WIDTH)}))

    def elaborate(self, platform):
        m = Module()
        n, bmax = self.phases, self.max_bits
        m.submodules.sequencer = sequencer = UpdateSequencer(
            self.latency, long_latency=self.long_latency, max_bits=bmax)
        h_last = Signal(n)          # last state of the last presented update (zero policy)
        loop = build_loop(m, self, sequencer, self.width - 2 - bmax, h_prev=h_last)
        integrator, sort1, candidates = loop.integrator, loop.sort1, loop.candidates
        sort2, decoder = loop.sort2, loop.decoder
        m.submodules.quantiser = quantiser = Quantiser(n, self.width, bmax)
        m.submodules.layout = layout = SlotLayout(n, bmax, len(self.period))
        assert 2 + sort1.latency + quantiser.latency == self.long_latency
        assert 2 + sort1.latency + candidates.latency + sort2.latency + decoder.latency \
            == self.latency

        # P, then P >> b once shifted: a slot mode has b >= 1, so a slot is at most half the
        # longest period and its count slot_m2 fits period_width signed bits (an MDFQM update
        # loads the layout's count too, unused: no slot follows its state)
        slot_len = Signal(len(self.period))
        slot_m2 = Signal(signed(len(self.period)))
        bbit = sequencer.mode_lat != 0
        commit = Mux(sequencer.long, quantiser.o_valid, decoder.o_valid)

        m.d.comb += [
            sequencer.mode.eq(self.mode),
            sequencer.bits.eq(self.bits),
            quantiser.i_t.eq(integrator.o_t),
            quantiser.i_max.eq(sort1.o_values[0]),     # neither given inverted
            quantiser.i_min.eq(sort1.o_values[n - 1]),
            # only long updates run the quantiser: a short one may end before it would finish
            quantiser.i_valid.eq(sort1.o_valid & sequencer.long),
            quantiser.i_mode.eq(sequencer.mode_lat),
            quantiser.i_bits.eq(sequencer.bits_lat),
            integrator.i_commit.eq(commit),
            # both given inverted; ~(u 2**B) is ~u above B bits set
            [integrator.i_units_n[i].eq(Mux(bbit, quantiser.o_units_n[i],
                                            Cat(Const((1 << bmax) - 1, bmax),
                                                decoder.o_units_n[i]).as_signed()))
             for i in range(n)],
            layout.i_load.eq(commit),
            layout.i_bbit.eq(bbit),
            layout.i_h.eq(decoder.o_h),
            layout.i_first.eq(quantiser.o_first),
            layout.i_lo.eq(quantiser.o_lo),
            layout.i_hi.eq(quantiser.o_hi),
            layout.i_slots.eq(quantiser.o_slots),
            layout.i_delta.eq(quantiser.o_delta),
            layout.i_slot_m2.eq(slot_m2),
            self.h.eq(layout.o_h),
            self.mode_clamped.eq(sequencer.mode_clamped),
            self.mode_in_force.eq(sequencer.mode_lat),
            self.bits_in_force.eq(sequencer.bits_lat),
        ]
        # slot length of the update in flight, P >> b, shifted one bit a clock from the
        # update's second clock on (P and b are still from there): b <= max_bits shifts end
        # long before the update commits
        first = Signal()
        shifts = Signal(BITS_WIDTH)
        m.d.sync += first.eq(sequencer.start)
        with m.If(first):
            m.d.sync += [slot_len.eq(sequencer.p_lat), shifts.eq(sequencer.bits_lat)]
        with m.Elif(shifts != 0):
            m.d.sync += [slot_len.eq(slot_len >> 1), shifts.eq(shifts - 1)]
        m.d.sync += [
            self.update.eq(commit),
            slot_m2.eq(slot_len - 2),
        ]
        with m.If(commit):
            m.d.sync += h_last.eq(Mux(bbit, quantiser.o_last, decoder.o_h))
        if self.formal:
            self._properties(m, sequencer, commit)
        return m

    def _properties(self, m, sequencer, commit):
        """The mode and b in force are legal whatever arrives; every mode is reachable, and in
        every gamma mode the layout switches the gates inside an update."""
        mode, bits = sequencer.mode_lat, sequencer.bits_lat
        m.d.comb += [
            Assert(mode < len(MODES), "the mode in force is not a legal mode"),
            Assert(Mux(mode == 0, bits == 0, (bits >= 1) & (bits <= self.max_bits)),
                   "the resolution in force is outside [1, max_bits]"),
        ]
        h_prev = Signal.like(self.h, name="formal_h_prev", reset_less=True)
        m.d.sync += h_prev.eq(self.h)
        for code in range(len(MODES)):
            m.d.comb += Cover(commit & (mode == code))
            if code:
                m.d.comb += Cover(~self.update & (self.h != h_prev) & (mode == code))
        m.d.comb += [Cover(self.mode_clamped), Cover(self.period_clamped)]
