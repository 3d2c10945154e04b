"""Weighting-filter integrators: T = X + R at the update start, X <- T - v(h) at the commit."""

from amaranth import Cat, Module, Mux, Signal, signed
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

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
    i_h : In(phases)
    i_count : In(range(phases + 1))
        ``popcount(i_h)``.
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
            "i_h": In(phases),
            "i_count": In(range(phases + 1)),
            "o_t": Out(data.ArrayLayout(signed(c.t_width), phases)),
            "o_x": Out(data.ArrayLayout(signed(c.x_width), phases)),
            "o_saturated": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        with m.If(self.i_start):
            m.d.sync += [self.o_t[i].eq(self.o_x[i] + self.i_r[i]) for i in range(n)]

        # U_i is FULL (N - k) for a leg that is on and -FULL k for one that is off.
        u_on = Signal(signed(c.t_width))
        u_off = Signal(signed(c.t_width))
        m.d.comb += [u_on.eq(c.full * (n - self.i_count)), u_off.eq(-(c.full * self.i_count))]
        candidate = [Signal(signed(c.t_width + 1), name=f"x_next{i}") for i in range(n)]
        for i in range(n):
            m.d.comb += candidate[i].eq(self.o_t[i] - Mux(self.i_h[i], u_on, u_off))
        fits = Cat(*[(value >= c.x_min) & (value <= c.x_max) for value in candidate]).all()
        with m.If(self.i_commit):
            m.d.sync += self.o_saturated.eq(~fits)
            with m.If(fits):
                m.d.sync += [self.o_x[i].eq(candidate[i]) for i in range(n)]
        return m
