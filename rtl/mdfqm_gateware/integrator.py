"""Weighting-filter integrators: T = X + R at the update start, X <- T - v(h) at the commit."""

from amaranth import Cat, Module, Signal, signed
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_model.contract import signed_bits

from .params import contract_for


class Integrator(wiring.Component):
    """Per-phase integrators ``z/(z-1)`` in the exact N-scaled integer domain, with anti-windup.

    Contract (:mod:`mdfqm_model.contract`): ``T = X + R`` is registered at the update start and
    held for the whole update (the pipeline behind it reads it until the commit). At the commit
    ``U_i = FULL (N h_i - k)`` and ``X' = T - U``; if any ``X'_i`` leaves the signed
    ``x_width``-bit range the integrators keep their value and ``o_saturated`` is set (conditional
    integration: ``sum(X) == 0`` holds exactly and nothing can wrap).

    Ports
    -----
    i_start : In(1)
        Update start: load ``T``.
    i_r : In(ArrayLayout(signed(r_width), phases))
        Reference used by the update starting this cycle.
    i_commit : In(1)
        Commit cycle: ``i_h``/``i_count`` hold this update's state.
    i_u : In(ArrayLayout(signed(u_width), phases))
        Feedback ``U = N FULL v(h)`` of this update's state (valid with ``i_commit``).
    o_t : Out(ArrayLayout(signed(t_width), phases))
        Optimum signal of the current update (registered, valid from the cycle after a start).
    o_x : Out(ArrayLayout(signed(x_width), phases))
        Integrator state (registered).
    o_saturated : Out(1)
        Registered at each commit: that update was held by the bound.
    """

    def __init__(self, phases: int, width: int):
        self.contract = contract_for(phases, width)
        self.phases = phases
        c = self.contract
        super().__init__({
            "i_start": In(1),
            "i_r": In(data.ArrayLayout(signed(c.r_width), phases)),
            "i_commit": In(1),
            "i_u": In(data.ArrayLayout(signed(signed_bits(-c.u_bound, c.u_bound)), phases)),
            "o_t": Out(data.ArrayLayout(signed(c.t_width), phases)),
            "o_x": Out(data.ArrayLayout(signed(c.x_width), phases)),
            "o_saturated": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        with m.If(self.i_start):
            m.d.sync += [self.o_t[i].eq(self.o_x[i] + self.i_r[i]) for i in range(n)]

        # X' fits the signed x_width-bit word iff its bits above the word's sign bit are all
        # copies of it: a few LUTs after the adder instead of two more carry chains.
        candidate = [Signal(signed(c.t_width + 1), name=f"x_next{i}") for i in range(n)]
        fits_each = []
        for i in range(n):
            m.d.comb += candidate[i].eq(self.o_t[i] - self.i_u[i])
            top = candidate[i][c.x_width - 1:]
            fits_each.append((top == 0) | (top == (1 << len(top)) - 1))
        fits = Cat(*fits_each).all()
        with m.If(self.i_commit):
            m.d.sync += self.o_saturated.eq(~fits)
            with m.If(fits):
                m.d.sync += [self.o_x[i].eq(candidate[i]) for i in range(n)]
        return m
