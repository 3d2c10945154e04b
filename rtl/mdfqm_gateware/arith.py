"""Comparisons written as the sign of a difference.

Yosys maps a subtraction onto one carry chain; some ``>``/``>=`` between wide signed values come
out of synth_ice40 as long LUT chains instead. Both operands must be signed (or both unsigned);
Amaranth widens the difference by one bit, so its top bit is the true sign.
"""


from amaranth import C, Cat, Const

__all__ = ["as_held", "at_least", "at_least_given", "difference", "greater", "greater_equal"]


def greater(a, b):
    """``a > b`` as the sign of ``b - a``."""
    return (b - a)[-1]


def greater_equal(a, b):
    """``a >= b`` as the inverted sign of ``a - b``."""
    return ~(a - b)[-1]


def at_least(value, constant: int):
    """``value >= constant`` for an unsigned ``value`` and a constant, as logic on the bits
    (no carry chain): from the lowest bit up, each bit of the constant ANDs (1) or ORs (0) that
    bit of ``value`` into the result so far; bits below the constant's lowest set bit drop
    out (the constant 0: always true)."""
    if constant < 0:
        raise ValueError(f"at_least: the constant must be >= 0, not {constant}")
    if constant >= 1 << len(value):
        return C(0, 1)
    result = None                          # None: every bit so far is below the constant's
    for k in range(len(value)):
        if (constant >> k) & 1:
            result = value[k] if result is None else value[k] & result
        elif result is not None:
            result = value[k] | result
    return C(1, 1) if result is None else result


def as_held(value, inverted: bool, wanted: bool):
    """``value``, held inverted or not, as a register held the ``wanted`` way takes it."""
    return ~value if inverted != wanted else value


def at_least_given(x, x_inverted: bool, y, y_inverted: bool):
    """``x >= y`` of two values each given inverted or not: the sign of their
    :func:`difference`."""
    return ~difference(x, x_inverted, y, y_inverted)[-1]


def difference(x, x_inverted: bool, y, y_inverted: bool):
    """``x - y`` of two values each given inverted or not: an addition of the two as given
    when exactly one is inverted (``x + ~y + 1``, its carry in as a low bit set in both
    operands; or ``~(~x + y)``)."""
    if y_inverted and not x_inverted:
        return (Cat(Const(1, 1), x).as_signed() + Cat(Const(1, 1), y).as_signed())[1:].as_signed()
    if x_inverted and not y_inverted:
        return ~(x + y)
    return as_held(x, x_inverted, False) - as_held(y, y_inverted, False)
