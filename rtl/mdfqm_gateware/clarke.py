"""Inverse Clarke transform in front of the core, so an FOC loop's alpha-beta output connects
directly: a two-stage stream pipeline with back-pressure."""

from amaranth import Cat, Module, Signal, signed
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import CLARKE_FRAC as FRAC
from mdfqm_spec.contract import CLARKE_K as K
from mdfqm_spec.validate import validate_positive

__all__ = ["InverseClarke"]


class InverseClarke(wiring.Component):
    """alpha-beta codes in, three phase codes out (:mod:`mdfqm_model.clarke` is the contract).

    Stage 1 registers ``K beta`` (one constant multiply, a DSP on iCE40 UP5K / ECP5), stage 2 the
    rounded and clamped codes. Each stage takes new data when it is empty or its content moves on
    in the same cycle, so the pipeline runs at one beat per clock and holds its output under
    back-pressure (:class:`mdfqm_model.clarke.InverseClarkeModel` predicts every cycle).

    Ports
    -----
    i : In(stream.Signature(ArrayLayout(signed(width), 2)))
        ``[alpha, beta]`` on the phase-code scale. ``i.ready`` depends on ``o.ready``.
    o : Out(stream.Signature(ArrayLayout(signed(width), 3)))
        ``[a, b, c]``; connect to ``MdfqmCore.ref`` (three phases).
    clamped : Out(1)
        With ``o.valid``: a code was clamped to the ``width``-bit range (|v| too large).

    Parameters
    ----------
    width : int in [8, 32]
    """

    def __init__(self, width: int = 16):
        self.width = validate_positive(width, "width", minimum=8, maximum=32)
        super().__init__({
            "i": In(stream.Signature(data.ArrayLayout(signed(width), 2))),
            "o": Out(stream.Signature(data.ArrayLayout(signed(width), 3))),
            "clamped": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        w = self.width
        lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
        alpha = Signal(signed(w))
        product = Signal(signed(w + K.bit_length() + 1))
        valid1 = Signal()
        ready2 = ~self.o.valid | self.o.ready
        ready1 = ~valid1 | ready2
        m.d.comb += self.i.ready.eq(ready1)
        with m.If(ready1):
            m.d.sync += valid1.eq(self.i.valid)
            with m.If(self.i.valid):
                m.d.sync += [alpha.eq(self.i.payload[0]), product.eq(self.i.payload[1] * K)]

        half = 1 << (FRAC - 1)
        common = -(alpha * half) + half
        raw = [alpha, (common + product) >> FRAC, (common - product) >> FRAC]
        codes, clamps = [], []
        for i, value in enumerate(raw):
            code = Signal(signed(w), name=f"code{i}")
            over, under = value > hi, value < lo
            with m.If(over):
                m.d.comb += code.eq(hi)
            with m.Elif(under):
                m.d.comb += code.eq(lo)
            with m.Else():
                m.d.comb += code.eq(value)
            codes.append(code)
            clamps.append(over | under)
        with m.If(ready2):
            m.d.sync += self.o.valid.eq(valid1)
            with m.If(valid1):
                m.d.sync += [self.o.payload.eq(Cat(*codes)), self.clamped.eq(Cat(*clamps).any())]
        return m
