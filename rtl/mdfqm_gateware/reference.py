"""Reference stage: exact common-mode removal, one phase per clock, and the sampling switch
(zero-order hold)."""

from amaranth import Module, Signal, signed
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import Contract

__all__ = ["ReferenceStage"]


class ReferenceStage(wiring.Component):
    """Accept phase references, remove their common mode, hold them between sampling ticks.

    Contract (``docs/contract.md``, "Reference stage"): a beat accepted in cycle ``a`` becomes
    ``pending`` (``R_i = N c_i - sum_j c_j``, exact) in cycle
    ``a + contract.reference_latency(N)`` (``a + 2N + 1``): one adder sums the beat over ``N``
    clocks, then one subtractor forms ``R_i`` over ``N`` more, a phase per clock (``N c_i`` a
    register ahead, so that each path holds one carry chain). In a cycle with
    ``tick_next`` and a pending beat, the beat becomes the held reference (``r``, from the next
    cycle on: the tick's) and the stage is free again. One beat is in flight at a time:
    ``ready`` is low from the cycle after an acceptance through the hand-over's cycle (high
    again in the tick's). A tick without a pending beat keeps the held reference (zero-order
    hold).

    Ports
    -----
    ref : In(stream.Signature(ArrayLayout(signed(width), phases)))
        Phase reference codes, ``FULL = 2**(width-2)`` codes per Vdc. ``ref.ready`` is
        combinational from registers only.
    tick_next : In(1)
        The next cycle is a sampling tick (an update start that samples); may be high in any
        cycle.
    r : Out(ArrayLayout(signed(r_width), phases))
        The held reference, registered: what an update starting in this cycle uses (0 after
        reset).
    """

    def __init__(self, phases: int, width: int):
        self.contract = Contract(phases, width)
        self.phases, self.width = phases, width
        r_shape = signed(self.contract.r_width)
        super().__init__({
            "ref": In(stream.Signature(data.ArrayLayout(signed(width), phases))),
            "tick_next": In(1),
            "r": Out(data.ArrayLayout(r_shape, phases)),
        })

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        r_shape = signed(c.r_width)
        raw = Signal(data.ArrayLayout(signed(self.width), n), reset_less=True)
        total = Signal(r_shape)
        pending = Signal(data.ArrayLayout(r_shape, n))
        # busy: a beat is being worked on; forming: its second half (R_i), else its sum;
        # which: the phase read in this clock, one-hot (a ring: no counter, no decoder).
        # ``raw`` turns with ``which``, so that the phase read is always ``raw[0]``: no
        # multiplexer in front of the two adders that read it (the Fmax path). The sum reads
        # the phases from 1 on and phase 0 last, so that the clock ending it also loads N c_0
        # into scaled; each clock of the second half then forms R_i from scaled and loads
        # N c_(i+1).
        busy, forming, full = Signal(), Signal(), Signal()
        which = Signal(n)
        phase_code = raw[0]
        # N c held inverted: R_i = ~(~(N c_i) + sum) is then an addition of two registers as
        # they are (a subtraction puts an inverter in front of every bit of its carry chain),
        # and the inversions are free in the sums' own logic. Loaded in every clock and read
        # only while busy: no reset (one to all ones would cost the iCE40 an inverter a bit)
        scaled_n = Signal(r_shape, reset_less=True)

        accept = self.ref.valid & self.ref.ready
        m.d.comb += self.ref.ready.eq(~(busy | full))
        # while not busy, raw follows the port (turned by one: phase 1 first); it is read only
        # while busy, and busy begins with an acceptance (so no reset either)
        with m.If(busy):
            m.d.sync += [raw[i].eq(raw[(i + 1) % n]) for i in range(n)]
        with m.Else():
            m.d.sync += [raw[i].eq(self.ref.payload[(i + 1) % n]) for i in range(n)]
        with m.If(accept):
            m.d.sync += [busy.eq(1), forming.eq(0), which.eq(0b10), total.eq(0)]
        # N c as shifted copies of c, one per set bit of N: no multiplier
        m.d.sync += scaled_n.eq(~sum(phase_code << k for k in range(n.bit_length())
                                     if (n >> k) & 1))
        with m.If(busy):
            m.d.sync += which.eq(which.rotate_left(1))
            with m.If(which[0]):
                m.d.sync += forming.eq(1)
            with m.If(~forming):
                m.d.sync += total.eq(total + phase_code)
            with m.Else():
                m.d.sync += [pending[i].eq(pending[i + 1]) for i in range(n - 1)]
                m.d.sync += pending[n - 1].eq(~(scaled_n + total))
                with m.If(which[0]):
                    m.d.sync += [busy.eq(0), full.eq(1)]

        with m.If(full & self.tick_next):
            m.d.sync += [self.r.eq(pending), full.eq(0)]
        return m
