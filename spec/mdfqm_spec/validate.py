"""Parameter validators shared by the gateware, the model and the tools: each refuses a bad value
with a ``ValueError`` whose message names the parameter and the legal range."""

from __future__ import annotations

__all__ = ["validate_bool", "validate_int", "validate_positive"]


def validate_int(value, name: str, lo: int, hi: int) -> int:
    """``value`` if it is an integer (not a bool) in ``[lo, hi]``.

    Integer-like values that are not ``int`` (a NumPy integer, say) are accepted and returned as
    ``int``; the check uses ``__index__`` so no NumPy import is needed here.
    """
    is_bool = isinstance(value, bool) or type(value).__name__ in ("bool", "bool_")
    if is_bool or not hasattr(type(value), "__index__") or not lo <= value.__index__() <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], not {value!r}")
    return value.__index__()


def validate_positive(value, name: str, minimum: int = 1, maximum: int | None = None) -> int:
    """``value`` if it is an integer ``>= minimum`` (and ``<= maximum`` when given)."""
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum or (
            maximum is not None and value > maximum):
        bound = f"in [{minimum}, {maximum}]" if maximum is not None else f">= {minimum}"
        raise ValueError(f"{name} must be an integer {bound}, not {value!r}")
    return value


def validate_bool(value, name: str) -> bool:
    """``value`` if it is a ``bool``, else ``ValueError`` naming ``name``."""
    if not isinstance(value, bool):
        raise ValueError(f"{name} must be a bool, not {value!r}")
    return value
