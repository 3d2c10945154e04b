"""Inverse Clarke transform (alpha-beta to three phase codes), bit-exact, and the clock-level
model of its two-stage stream pipeline (:class:`mdfqm_gateware.clarke.InverseClarke`).

Fixed-point contract
--------------------
``alpha`` and ``beta`` are ``width``-bit two's-complement codes on the phase-code scale
(amplitude-invariant Clarke, the paper's eq. 4): ``v_a = alpha``,
``v_b = -alpha/2 + (sqrt(3)/2) beta``, ``v_c = -alpha/2 - (sqrt(3)/2) beta``. With
``K = round(sqrt(3)/2 * 2**FRAC)`` (``FRAC = 17``):

- ``a = alpha``
- ``b = floor((-alpha * 2**(FRAC-1) + K beta + 2**(FRAC-1)) / 2**FRAC)``  (round half up)
- ``c = floor((-alpha * 2**(FRAC-1) - K beta + 2**(FRAC-1)) / 2**FRAC)``

each clamped to the ``width``-bit code range (``clamped`` says so). The codes need not sum to
zero: the core removes the common mode exactly. The error against the real transform is at most
half a code plus ``|beta| 2**-FRAC``.
"""

from __future__ import annotations

from dataclasses import dataclass

from mdfqm_spec.contract import CLARKE_FRAC as FRAC
from mdfqm_spec.contract import CLARKE_K as K

__all__ = ["InverseClarkeModel", "inverse_clarke"]


def inverse_clarke(alpha: int, beta: int, width: int) -> tuple[tuple[int, int, int], bool]:
    """Phase codes ``(a, b, c)`` and whether any was clamped, per the module's contract."""
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    for name, value in (("alpha", alpha), ("beta", beta)):
        if not lo <= value <= hi:
            raise ValueError(f"{name} must be a {width}-bit code in [{lo}, {hi}], not {value!r}")
    half = 1 << (FRAC - 1)
    common = -alpha * half + half
    raw = (alpha, (common + K * beta) >> FRAC, (common - K * beta) >> FRAC)
    codes = tuple(min(hi, max(lo, v)) for v in raw)
    return codes, codes != raw


@dataclass
class _Stage:
    valid: int = 0
    data: tuple = ()


class InverseClarkeModel:
    """Clock-level model of the two-stage stream pipeline.

    Stage 1 registers the products, stage 2 the clamped codes. A stage takes new data when it is
    empty or its content moves on in the same cycle: ``ready_2 = not valid_2 or out_ready``,
    ``ready_1 = not valid_1 or ready_2``; ``in_ready = ready_1`` and ``out_valid = valid_2`` are
    functions of the registers and ``out_ready``. :meth:`step` returns the outputs of the cycle,
    then advances.
    """

    def __init__(self, width: int = 16):
        self.width = width
        self.reset()

    def reset(self) -> None:
        self.s1 = _Stage(0, (0, 0))
        self.s2 = _Stage(0, ((0, 0, 0), False))

    def step(self, rst=0, in_valid=0, alpha=0, beta=0, out_ready=0) -> dict:
        ready2 = (not self.s2.valid) or bool(out_ready)
        ready1 = (not self.s1.valid) or ready2
        codes, clamped = self.s2.data
        out = {"in_ready": int(ready1), "out_valid": self.s2.valid, "codes": codes,
               "clamped": int(clamped)}
        if rst:
            self.reset()
            return out
        if ready2:
            self.s2 = _Stage(self.s1.valid,
                             inverse_clarke(*self.s1.data, self.width) if self.s1.valid
                             else self.s2.data)
        if ready1:
            self.s1 = _Stage(int(bool(in_valid)), (alpha, beta) if in_valid else self.s1.data)
        return out
