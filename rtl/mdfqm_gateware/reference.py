"""Reference stage: the sampling switch (zero-order hold) and exact common-mode removal."""

from amaranth import Module, Mux, Signal, signed
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import Contract

__all__ = ["ReferenceStage"]


class ReferenceStage(wiring.Component):
    """Accept phase references, remove their common mode, hold them between sampling ticks.

    Contract (``docs/contract.md``, "Reference stage"): a beat accepted in cycle ``a``
    becomes ``pending`` (``R_i = N c_i - sum_j c_j``, exact) visible from cycle ``a + 3``; one beat
    is in flight at a time, so ``ready`` is low from acceptance until a sampling tick consumes
    ``pending``. A tick without a new beat keeps the held reference (zero-order hold).

    Ports
    -----
    ref : In(stream.Signature(ArrayLayout(signed(width), phases)))
        Phase reference codes, ``FULL = 2**(width-2)`` codes per Vdc. ``ref.ready`` is
        combinational from registers only.
    tick : In(1)
        Sampling tick (an update start that samples); may be high in any cycle.
    r : Out(ArrayLayout(signed(r_width), phases))
        Combinational: the reference an update starting this cycle uses —
        ``pending`` if ``tick`` and a beat is pending, else the held one.
    """

    def __init__(self, phases: int, width: int):
        self.contract = Contract(phases, width)
        self.phases, self.width = phases, width
        r_shape = signed(self.contract.r_width)
        super().__init__({
            "ref": In(stream.Signature(data.ArrayLayout(signed(width), phases))),
            "tick": In(1),
            "r": Out(data.ArrayLayout(r_shape, phases)),
        })

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        r_shape = signed(c.r_width)
        raw = Signal(data.ArrayLayout(signed(self.width), n))
        scaled = Signal(data.ArrayLayout(r_shape, n))
        total = Signal(r_shape)
        pending = Signal(data.ArrayLayout(r_shape, n))
        held = Signal(data.ArrayLayout(r_shape, n))
        in_raw, in_scaled, full = Signal(), Signal(), Signal()

        m.d.comb += self.ref.ready.eq(~(in_raw | in_scaled | full))
        m.d.sync += in_raw.eq(self.ref.valid & self.ref.ready)
        with m.If(self.ref.valid & self.ref.ready):
            m.d.sync += raw.eq(self.ref.payload)
        m.d.sync += in_scaled.eq(in_raw)
        with m.If(in_raw):
            m.d.sync += total.eq(sum(raw[i] for i in range(n)))
            m.d.sync += [scaled[i].eq(raw[i] * n) for i in range(n)]
        with m.If(in_scaled):
            m.d.sync += [pending[i].eq(scaled[i] - total) for i in range(n)]
            m.d.sync += full.eq(1)

        take = self.tick & full
        with m.If(take):
            m.d.sync += [held.eq(pending), full.eq(0)]
        m.d.comb += self.r.eq(Mux(take, pending, held))
        return m
