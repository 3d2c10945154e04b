"""Comparisons written as the sign of a difference.

Yosys maps a subtraction onto one carry chain; some ``>``/``>=`` between wide signed values come
out of synth_ice40 as long LUT chains instead. Both operands must be signed (or both unsigned);
Amaranth widens the difference by one bit, so its top bit is the true sign.
"""


__all__ = ["greater", "greater_equal"]


def greater(a, b):
    """``a > b`` as the sign of ``b - a``."""
    return (b - a)[-1]


def greater_equal(a, b):
    """``a >= b`` as the inverted sign of ``a - b``."""
    return ~(a - b)[-1]
