"""Helpers of the formal properties that live beside the RTL (emitted only with ``formal=True``)."""

from amaranth import Cat, Signal

__all__ = ["delayed", "is_permutation"]


def delayed(m, value, clocks: int, name: str):
    """``value`` of ``clocks`` clocks earlier (what a block's output must be compared with
    after its latency)."""
    for stage in range(clocks):
        registered = Signal.like(value, name=f"{name}_d{stage + 1}", reset_less=True)
        m.d.sync += registered.eq(value)
        value = registered
    return value


def is_permutation(indices, count: int):
    """Every position ``0 .. count-1`` appears among ``indices`` (``count`` of them)."""
    return Cat(*[Cat(*[index == position for index in indices]).any()
                 for position in range(count)]).all()
