"""Checks of the clock-level models' per-cycle inputs, shared so each says the same thing."""

import numpy as np


def check_bit(value, name: str) -> int:
    """``value`` as 0/1 (a bool or the integers 0 and 1), else ``ValueError`` naming ``name``."""
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, (int, np.integer)) and value in (0, 1):
        return int(value)
    raise ValueError(f"{name} must be 0 or 1, not {value!r}")


def check_uint(value, bits: int, name: str) -> int:
    """``value`` as an unsigned ``bits``-bit integer, else ``ValueError`` naming ``name``."""
    if (
        isinstance(value, (bool, np.bool_))
        or not isinstance(value, (int, np.integer))
        or not 0 <= value < (1 << bits)
    ):
        raise ValueError(f"{name} must be an unsigned {bits}-bit integer, not {value!r}")
    return int(value)
