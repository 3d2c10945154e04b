"""Update sequencer: an update every P clocks, a sampling tick every OSR updates."""

import functools
import operator

from amaranth import Cat, Const, Module, Mux, Signal, signed
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import BITS_WIDTH, MODE_WIDTH, MODES, min_period, signed_bits
from mdfqm_spec.validate import validate_positive

from .arith import at_least

__all__ = ["UpdateSequencer"]


class UpdateSequencer(wiring.Component):
    """Runtime update period and oversampling ratio, latched at update boundaries.

    Contract (``docs/contract.md``, "Update sequencer", "Sampling switch"): a cycle with
    ``phase == 0`` is an update start; there ``P = max(period, latency)`` and
    ``osr = max(osr, 1)`` are latched, so a runtime change takes effect at the next boundary and a
    period below the loop latency can never start an update before the previous one committed.

    Ports
    -----
    period : In(period_width)
        Requested clocks per update; sampled at update starts.
    osr : In(osr_width)
        Requested updates per reference sample (0 is treated as 1); sampled at update starts.
    zero_policy : In(1)
        Zero-state policy request; sampled at update starts.
    sync_in : In(1)
        High in a cycle with ``phase + 1 >= latency`` (the update in flight has committed):
        the next cycle is an update start. Ignored earlier in an update.
    start : Out(1)
        High in the first cycle of each update (combinational from registers).
    tick : Out(1)
        High at an update start that is also a sampling tick (combinational from registers).
    tick_next : Out(1)
        The next cycle is a sampling tick (combinational: ``tick``'s next value; undefined in
        a reset cycle).
    policy : Out(1)
        ``zero_policy`` as latched at the last update start (registered).
    period_clamped : Out(1)
        ``period < latency`` at the last update start (registered).
    elapsed : Out(period_width)
        Clocks since the last update start: 0 in a start cycle, then 1, 2, ... (combinational
        from registers).

    With ``long_latency`` (the gating-signal generator, ``docs/contract.md`` section
    "b-bit pulse-width resolution") the sequencer also latches ``mode`` and ``bits`` with the
    runtime clamp of ``contract.latch_mode``, decides whether the update is *long* (its mode is
    not mdfqm, or the previous update's was not), and then honours the minimum period
    ``contract.min_period`` and the sync threshold of that kind of update. Without it the ports
    below marked "generator" do not exist and the logic is the core's.

    Ports (generator only)
    ----------------------
    mode : In(MODE_WIDTH)
        Requested mode code; sampled at update starts.
    bits : In(BITS_WIDTH)
        Requested resolution b; sampled at update starts.
    mode_lat : Out(MODE_WIDTH)
        Mode of the current update (registered at its start, after the clamp).
    bits_lat : Out(BITS_WIDTH)
        b of the current update (0 for mdfqm; registered).
    long : Out(1)
        The current update is long (registered).
    p_lat : Out(period_width)
        Period P of the current update, after the clamp (from registers latched at the start:
        valid from the second clock of the update on, ``phase >= 1``).
    mode_clamped : Out(1)
        The last start's ``mode`` was illegal or its ``bits`` was clamped (registered).

    Parameters
    ----------
    latency : int >= 2
        The loop latency: the smallest period that is honoured (of a short update).
    period_width, osr_width : int
        Widths of the runtime inputs.
    long_latency : int or None
        Latency of a long update (>= latency); None: the core's sequencer.
    max_bits : int
        Largest b (generator only).
    """

    def __init__(self, latency: int, period_width: int = 16, osr_width: int = 8,
                 long_latency: int | None = None, max_bits: int = 1):
        validate_positive(latency, "latency", minimum=2)
        validate_positive(period_width, "period_width", minimum=latency.bit_length(), maximum=32)
        validate_positive(osr_width, "osr_width", maximum=16)
        self.latency = latency
        self.period_width, self.osr_width = period_width, osr_width
        self.long_latency = long_latency
        ports = {
            "period": In(period_width),
            "osr": In(osr_width),
            "zero_policy": In(1),
            "sync_in": In(1),
            "start": Out(1),
            "tick": Out(1),
            "tick_next": Out(1),
            "policy": Out(1),
            "period_clamped": Out(1),
            "elapsed": Out(period_width),
        }
        if long_latency is not None:
            validate_positive(long_latency, "long_latency", minimum=latency)
            validate_positive(max_bits, "max_bits", minimum=1, maximum=(1 << BITS_WIDTH) - 1)
            if max(long_latency, 1 << max_bits).bit_length() > period_width:
                raise ValueError(f"period_width must hold the longest minimum period "
                                 f"{max(long_latency, 1 << max_bits)}, not {period_width}")
            self.max_bits = max_bits
            ports.update({
                "mode": In(MODE_WIDTH),
                "bits": In(BITS_WIDTH),
                "mode_lat": Out(MODE_WIDTH),
                "bits_lat": Out(BITS_WIDTH),
                "long": Out(1),
                "p_lat": Out(period_width),
                "mode_clamped": Out(1),
            })
        super().__init__(ports)

    def elaborate(self, platform):
        m = Module()
        # phase counts up from 0 in the start clock (the clock that ends an update clears it,
        # so that it is the elapsed count as it is; for sync_in: a compare with a constant).
        # start and tick are registers computed one clock ahead; so are the flags they are
        # made of (late: phase >= the latency minus one, where sync_in restarts; reached:
        # phase + 1 >= period; sub_one: the next start samples), so that tick_next, the
        # reference stage's hand-over enable, is a LUT or two from registers.
        phase = Signal(self.period_width)
        # updates since the last sampling start, plus one (the contract's sub + 1): kept
        # incremented so that the wrap test is one compare, with no adder in front of it
        sub_p1 = Signal(self.osr_width, init=1)
        start_q, tick_q, sub_one = Signal(init=1), Signal(init=1), Signal(init=1)
        late = Signal()
        reached = self._period_reached(m)
        m.d.comb += [self.start.eq(start_q), self.tick.eq(tick_q),
                     self.elapsed.eq(phase)]

        if self.long_latency is None:
            clamped = ~at_least(self.period, self.latency)
            # In a start cycle phase + 1 = 1 < latency <= P: never the end of the update. The
            # update ends at phase + 1 >= max(period, latency), or at sync_in once late.
            ends = ~self.start & late & (self.sync_in | reached)
            m.d.sync += [
                phase.eq(Mux(ends, 0, phase + 1)),
                late.eq(Mux(self.start, int(self.latency <= 2),
                            at_least(phase, self.latency - 2))),
                start_q.eq(ends),
                tick_q.eq(self.tick_next),
            ]
        else:
            clamped, ends = self._generator_sequence(m, phase, late, reached)
            m.d.sync += [
                phase.eq(Mux(ends, 0, phase + 1)),
                start_q.eq(ends),
                tick_q.eq(self.tick_next),
            ]
        m.d.comb += self.tick_next.eq(ends & sub_one)
        osr_now = Mux(self.osr == 0, 1, self.osr)
        with m.If(self.start):
            m.d.sync += [
                sub_p1.eq(Mux(sub_p1 >= osr_now, 1, sub_p1 + 1)),
                sub_one.eq(sub_p1 >= osr_now),
                self.period_clamped.eq(clamped),
                self.policy.eq(self.zero_policy),
            ]
        return m

    def _period_reached(self, m):
        """A register high from the clock with ``phase + 1 >= period`` until the next start
        (what it holds in a start clock is not read). An up-count loaded with ``~period`` at
        the start, so that its load is no adder (it merges into the count's own LUTs), and
        tested against a constant as logic on its bits."""
        # at phase j >= 1 the count is j - period - 2 (~period = -period - 1 at phase 1), and
        # phase + 1 >= period <=> count >= -3: next clock's flag is count >= -4, i.e. the bits
        # from 2 up all ones or the sign clear. It never wraps: an update ends within
        # max(period, minimum) clocks of its start, far below 2**period_width past -4.
        count = Signal(signed(self.period_width + 1))
        reached = Signal()
        m.d.sync += [
            count.eq(Mux(self.start, Cat(~self.period, Const(1, 1)).as_signed(), count + 1)),
            reached.eq(Mux(self.start, ~at_least(self.period, 3),
                           ~count[-1] | count[2:].all())),
        ]
        return reached

    def _generator_sequence(self, m, phase, late, reached):
        """Mode/bits clamp, short/long decision, minimum period and end of the update (the
        generator): returns (period clamped at this start, the update ends this cycle).

        ``P = max(period, minimum)`` is never formed in front of the end test: the update ends
        when both the requested period and the minimum have run, each a signed count-down loaded
        at the start (``period - 3``, and ``minimum - 3`` from a table of constants) whose sign
        bit says so: no lookup of the runtime mode and no comparator sits in front of the end.

        The start clock holds no carry chain and no lookup by the clamped b: a long update's
        minimum takes one of a few values (``max(L_b, 2**b)``), so ``period`` is compared with
        each of them as logic on its bits, and the request picks one through a decode of its
        own bits (the clamps folded into the decode's constants). ``p_lat`` is selected a
        clock later, from the period and the minimum latched at the start and the clamp flag.
        """
        long_lat, short, width = self.long_latency, self.latency, self.period_width
        legal = self.mode < len(MODES)
        mode_now = Mux(legal, self.mode, 0)
        bbit_now = mode_now != 0
        bits_now = Mux(self.bits < 1, 1, Mux(self.bits > self.max_bits, self.max_bits, self.bits))
        b_now = Mux(bbit_now, bits_now, 0)
        prev_bbit = Signal()
        long_now = bbit_now | prev_bbit
        # minimum period of a long update by its requested b code, after the clamp; a long
        # update in mdfqm (the first after a slot mode) has b = 0
        by_code = [min_period(True, min(max(code, 1), self.max_bits), short, long_lat)
                   for code in range(1 << BITS_WIDTH)]
        mdfqm_long = min_period(True, 0, short, long_lat)
        # picks[v]: the update's minimum is v (for a long update)
        picks = {}
        for v in sorted(set(by_code) | {mdfqm_long}):
            codes = Const(sum(1 << code for code, w in enumerate(by_code) if w == v),
                          1 << BITS_WIDTH)
            picks[v] = Mux(bbit_now, codes.bit_select(self.bits, 1), int(v == mdfqm_long))

        def chosen(value_of, shape):
            """``value_of(v)`` of the picked minimum v of a long update, else of ``short``."""
            return Mux(long_now, functools.reduce(operator.or_, (
                Mux(pick, Const(value_of(v), shape), 0) for v, pick in picks.items())),
                Const(value_of(short), shape))

        # period < minimum, each compare as logic on the bits of period
        clamped = Mux(long_now, functools.reduce(operator.or_, (
            pick & ~at_least(self.period, v) for v, pick in picks.items())),
            ~at_least(self.period, short))
        # from phase 1 on: phase + 1 >= period <=> reached, phase + 1 >= minimum <=> floor < 0;
        # floor, as wide as the largest minimum, holds once negative
        floor = Signal(signed(signed_bits(-1, max(picks) - 3)))
        period_lat = Signal(width)
        minimum_lat = Signal(width)
        # In a start cycle phase + 1 = 1 < latency <= P: never the end of the update.
        ends = ~self.start & ((self.sync_in & late) | (reached & floor[-1]))
        m.d.sync += [
            late.eq(Mux(self.start, Mux(long_now, int(long_lat <= 2), int(short <= 2)),
                        Mux(self.long, at_least(phase, long_lat - 2),
                            at_least(phase, short - 2)))),
            floor.eq(Mux(self.start, chosen(lambda v: v - 3, floor.shape()),
                         Mux(floor[-1], floor, floor - 1))),
        ]
        with m.If(self.start):
            m.d.sync += [
                period_lat.eq(self.period),
                minimum_lat.eq(chosen(lambda v: v, width)),
                prev_bbit.eq(bbit_now),
                self.long.eq(long_now),
                self.mode_lat.eq(mode_now),
                self.bits_lat.eq(b_now),
                self.mode_clamped.eq(~legal | (bbit_now & (bits_now != self.bits))),
            ]
        # P = max(period, minimum) of the update: the flag's compare selects
        m.d.comb += self.p_lat.eq(Mux(self.period_clamped, minimum_lat, period_lat))
        return clamped, ends
