"""Checks of the clock-level models' per-cycle inputs, shared so each says the same thing."""

import numpy as np

__all__ = ["check_bit", "check_uint", "stimulus_columns"]


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


def stimulus_columns(stim, names, vectors=None) -> tuple[dict, int]:
    """Split a ``simulate`` stimulus into per-input columns and the cycle count.

    ``stim`` maps names from ``names`` to a scalar (held every cycle) or a length-C array;
    ``vectors`` maps the names whose value per cycle is a vector to that vector's length (then
    a 1-D value is held, a C x length array is per cycle). C is the arrays' common length, or
    ``stim["cycles"]`` when every input is held. Returns ``({name: ("scalar"|"array", value)},
    C)``; unknown names, ragged lengths or a disagreeing ``cycles`` raise ``ValueError``.
    """
    vectors = dict(vectors or {})
    unknown = set(stim) - set(names) - {"cycles"}
    if unknown:
        raise ValueError(f"unknown stimulus names {sorted(unknown)}; known: {tuple(names)}")
    cols, lengths = {}, set()
    for name in names:
        if name not in stim:
            continue
        a = np.asarray(stim[name])
        if name in vectors:
            size = vectors[name]
            if a.ndim == 1:
                if a.shape[0] != size:
                    raise ValueError(f"{name} must be C x {size} or {size} values")
                cols[name] = ("scalar", tuple(int(v) for v in a))
                continue
            if a.ndim != 2 or a.shape[1] != size:
                raise ValueError(f"{name} must be C x {size}, got shape {a.shape}")
            cols[name] = ("array", a.tolist())
            lengths.add(a.shape[0])
        elif a.ndim == 0:
            cols[name] = ("scalar", a.item())
        elif a.ndim == 1:
            cols[name] = ("array", a.tolist())
            lengths.add(a.shape[0])
        else:
            raise ValueError(f"{name} must be a scalar or a 1-D array, got shape {a.shape}")
    if len(lengths) > 1:
        raise ValueError(f"stimulus arrays differ in length: {sorted(lengths)}")
    if lengths:
        cycles = lengths.pop()
        if "cycles" in stim and stim["cycles"] != cycles:
            raise ValueError("stim['cycles'] disagrees with the array lengths")
    elif "cycles" in stim:
        cycles = int(stim["cycles"])
    else:
        raise ValueError("give at least one stimulus array or stim['cycles']")
    return cols, cycles
