"""Update sequencer: an update every P clocks, a sampling tick every OSR updates."""

from amaranth import Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from .params import validate_positive


class UpdateSequencer(wiring.Component):
    """Runtime update period and oversampling ratio, latched at update boundaries.

    Contract (:mod:`mdfqm_model.contract`, "Update sequencer", "Sampling switch"): a cycle with
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
    policy : Out(1)
        ``zero_policy`` as latched at the last update start (registered).
    period_clamped : Out(1)
        ``period < latency`` at the last update start (registered).

    Parameters
    ----------
    latency : int >= 2
        The loop latency: the smallest period that is honoured.
    period_width, osr_width : int
        Widths of the runtime inputs.
    """

    def __init__(self, latency: int, period_width: int = 16, osr_width: int = 8):
        validate_positive(latency, "latency", minimum=2)
        validate_positive(period_width, "period_width", minimum=latency.bit_length(), maximum=32)
        validate_positive(osr_width, "osr_width", maximum=16)
        self.latency = latency
        self.period_width, self.osr_width = period_width, osr_width
        super().__init__({
            "period": In(period_width),
            "osr": In(osr_width),
            "zero_policy": In(1),
            "sync_in": In(1),
            "start": Out(1),
            "tick": Out(1),
            "policy": Out(1),
            "period_clamped": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        # phase counts up from the start (for sync_in: a compare with a constant); left counts
        # the clocks to the end of the update down (the end is left == 0): neither needs an
        # adder in front of a comparator. start and tick are registers computed one clock ahead.
        phase = Signal(self.period_width)
        left = Signal(self.period_width)
        sub = Signal(self.osr_width)
        start_q, tick_q = Signal(init=1), Signal(init=1)
        m.d.comb += [self.start.eq(start_q), self.tick.eq(tick_q)]

        clamped = self.period < self.latency
        osr_now = Mux(self.osr == 0, 1, self.osr)
        restart = self.sync_in & (phase >= self.latency - 1)
        # In a start cycle phase + 1 = 1 < latency <= P: never the end of the update.
        ends = ~self.start & (restart | (left == 0))
        m.d.sync += [
            phase.eq(Mux(self.start, 1, phase + 1)),
            left.eq(Mux(self.start, Mux(clamped, self.latency - 2, self.period - 2), left - 1)),
            start_q.eq(ends),
            tick_q.eq(ends & (sub == 0)),     # sub only moves in start cycles
        ]
        with m.If(self.start):
            m.d.sync += [
                sub.eq(Mux(sub + 1 >= osr_now, 0, sub + 1)),
                self.period_clamped.eq(clamped),
                self.policy.eq(self.zero_policy),
            ]
        return m
