"""Debounced push buttons.

Timing: each button passes a two-flip-flop synchroniser (reset 0); every ``debounce`` clocks (a
*tick*: the prescaler at ``debounce - 1``) ``state`` takes the synchronised level, and
``pressed`` is high for the clock after a tick at which ``state`` rose. Bounces shorter than the
tick interval cannot produce a second press.
"""

from amaranth import Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.validate import validate_positive

__all__ = ["Buttons"]


class Buttons(wiring.Component):
    """Synchronise, debounce and edge-detect ``count`` active-high buttons.

    Ports
    -----
    raw : In(count)
        Button levels, active high, asynchronous.
    state : Out(count)
        Debounced levels (registered).
    pressed : Out(count)
        One-clock pulses (registered) after a debounced rising edge.

    Parameters
    ----------
    count : int in [1, 8]
    debounce : int in [1, 2**24]
        Clocks between samples (about 10 ms on the boards).
    """

    def __init__(self, count: int, debounce: int):
        self.count = validate_positive(count, "count", maximum=8)
        self.debounce = validate_positive(debounce, "debounce", maximum=1 << 24)
        super().__init__({"raw": In(count), "state": Out(count), "pressed": Out(count)})

    def elaborate(self, platform):
        m = Module()
        s1, s2 = Signal(self.count), Signal(self.count)
        prescaler = Signal(range(self.debounce))
        m.d.sync += [s1.eq(self.raw), s2.eq(s1), self.pressed.eq(0)]
        with m.If(prescaler == self.debounce - 1):
            m.d.sync += [prescaler.eq(0), self.state.eq(s2), self.pressed.eq(s2 & ~self.state)]
        with m.Else():
            m.d.sync += prescaler.eq(prescaler + 1)
        return m
