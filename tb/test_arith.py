"""The comparisons of rtl/mdfqm_gateware/arith.py, exhaustively on small widths in the Amaranth
simulator: ``at_least`` (a compare with a constant as logic on the bits) for every constant
from 0 to past the largest value, ``greater`` and ``greater_equal`` (the sign of a difference)
for every pair of signed values."""

import pytest
from amaranth import Module, Signal, signed
from amaranth.sim import Simulator

from mdfqm_gateware.arith import at_least, greater, greater_equal


@pytest.mark.parametrize("width", [1, 3, 5])
def test_at_least_every_value_and_constant(width):
    value = Signal(width)
    constants = range((1 << width) + 2)
    outs = [Signal(name=f"at_least_{k}") for k in constants]
    m = Module()
    m.d.comb += [o.eq(at_least(value, k)) for o, k in zip(outs, constants, strict=True)]
    wrong = []

    async def bench(ctx):
        for v in range(1 << width):
            ctx.set(value, v)
            wrong.extend((v, k) for o, k in zip(outs, constants, strict=True)
                         if ctx.get(o) != int(v >= k))

    sim = Simulator(m)
    sim.add_testbench(bench)
    sim.run()
    assert not wrong, f"value, constant where at_least is wrong: {wrong[:8]}"


def test_at_least_refuses_a_negative_constant():
    with pytest.raises(ValueError, match="the constant must be >= 0, not -1"):
        at_least(Signal(4), -1)


def test_greater_and_greater_equal_on_every_signed_pair():
    a, b = Signal(signed(4)), Signal(signed(4))
    gt, ge = Signal(), Signal()
    m = Module()
    m.d.comb += [gt.eq(greater(a, b)), ge.eq(greater_equal(a, b))]
    wrong = []

    async def bench(ctx):
        for x in range(-8, 8):
            for y in range(-8, 8):
                ctx.set(a, x)
                ctx.set(b, y)
                if (ctx.get(gt), ctx.get(ge)) != (int(x > y), int(x >= y)):
                    wrong.append((x, y))

    sim = Simulator(m)
    sim.add_testbench(bench)
    sim.run()
    assert not wrong, f"pairs compared wrongly: {wrong[:8]}"
