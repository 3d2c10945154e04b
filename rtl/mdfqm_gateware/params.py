"""Parameter validation shared by the components: exact messages naming the parameter."""

from mdfqm_model.contract import Contract
from mdfqm_model.update import validate_rule

__all__ = ["contract_for", "validate_bool", "validate_positive", "validate_rule"]


def contract_for(phases, width) -> Contract:
    """Validate ``phases`` and ``width`` (``ValueError`` naming the bad one) and return widths."""
    return Contract(phases=phases, width=width)


def validate_positive(value, name: str, minimum: int = 1, maximum: int | None = None) -> int:
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
