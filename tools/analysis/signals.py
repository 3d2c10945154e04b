"""References, the runs of each method, and their waveforms.

Conventions
-----------
- Voltages in units of the DC link (Vdc = 1). The reference is a balanced N-phase cosine with
  phase-voltage peak ``amp`` (the *amplitude ratio* Vd/Vdc; the linear range of N = 3 ends at
  ``1/sqrt(3) = 0.577``), quantised to the contract's codes (``FULL`` codes per Vdc).
- The reference is sampled at ``fc`` (the sampling switch) and held. MDFQM updates at
  ``osr * fc``. The carrier-based methods (SVPWM, DPWM) take one reference sample per carrier
  period ``1 / fsw`` (``fsw = fc`` unless swept).
- SVPWM / DPWM come in two forms: ``ideal`` (the b -> infinity limit: exact centred pulses of the
  sampled reference, x = 0, continuous edge times) and ``bbit`` (the b-bit generator of
  :mod:`mdfqm_model.bbit`, edges on a grid of 2**b slots per period, quantisation error fed back).
- A *switching event* is one leg changing state (one complementary transistor pair commutating).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mdfqm_model.bbit import modulate_bbit
from mdfqm_model.update import modulate_batch
from mdfqm_spec.contract import ALL_OFF, FEWEST_TRANSITIONS, Contract

from .metrics import PWave

__all__ = [
    "ALL_OFF",
    "FEWEST_TRANSITIONS",
    "Method",
    "Run",
    "bbit_method",
    "ideal",
    "ideal_duties",
    "mdfqm",
    "reference_codes",
    "run_mdfqm_batch",
    "run_method",
]


@dataclass(frozen=True)
class Method:
    """One generator setting: ``kind`` is ``"mdfqm"``, ``"bbit"`` or ``"ideal"``; ``mode`` the
    b-bit / ideal mode (``"svpwm"``, ``"dpwm"``, ...); ``osr`` (MDFQM), ``b`` (b-bit)."""

    label: str
    kind: str
    mode: str = "mdfqm"
    osr: int = 1
    b: int = 0
    zero_policy: int = ALL_OFF
    rule: str = "largest_duty"


def mdfqm(osr: int, zero_policy: int, rule: str = "largest_duty") -> Method:
    pol = "all-off" if zero_policy == ALL_OFF else "fewest-transitions"
    return Method(f"MDFQM OSR{osr} {pol}", "mdfqm", "mdfqm", osr, 0, zero_policy, rule)


def ideal(mode: str = "svpwm") -> Method:
    return Method(mode.upper(), "ideal", mode)


def bbit_method(mode: str = "svpwm", b: int = 8) -> Method:
    return Method(f"{mode.upper()} b={b}", "bbit", mode, 1, b)


def reference_codes(
    contract: Contract, fs: float, f0: float, amp: float, seconds: float, theta0: float = 0.0
) -> np.ndarray:
    """K x N codes of the reference sampled at ``fs`` for ``seconds`` (K = round(fs seconds))."""
    n = contract.phases
    k = round(fs * seconds)
    t = np.arange(k) / fs
    shifts = 2 * np.pi * np.arange(n) / n
    v = amp * np.cos(2 * np.pi * f0 * t[:, None] + theta0 - shifts[None, :])
    codes = np.round(v * contract.full).astype(np.int64)
    return np.clip(codes, contract.code_min, contract.code_max)


def ideal_duties(v: np.ndarray, mode: str) -> np.ndarray:
    """Duties of the ideal (x = 0, infinite resolution) carrier methods for phase voltages ``v``.

    ``svpwm``: gamma = 1/2, ``a = 1/2 + v - (max + min)/2``; ``dpwm0``: top leg clamped on,
    ``a = 1 + v - max``; ``dpwm1``: bottom leg clamped off, ``a = v - min``; ``dpwm``: the leg with
    the larger |extreme| clamped (as :mod:`mdfqm_model.bbit`). Clipped to [0, 1].
    """
    v = np.asarray(v, dtype=float)
    v = v - v.mean(axis=1, keepdims=True)
    hi = v.max(axis=1, keepdims=True)
    lo = v.min(axis=1, keepdims=True)
    if mode == "svpwm":
        a = 0.5 + v - (hi + lo) / 2
    elif mode == "dpwm0":
        a = 1 + v - hi
    elif mode == "dpwm1":
        a = v - lo
    elif mode == "dpwm":
        a = np.where(hi >= -lo, 1 + v - hi, v - lo)
    else:
        raise ValueError(f"no ideal form of mode {mode!r}")
    return np.clip(a, 0.0, 1.0)


@dataclass
class Run:
    """One run: its method, gate waveform, and how many updates saturated."""

    method: Method
    wave: PWave
    saturated: int = 0

    def events_per_second(self) -> float:
        return self.wave.switching_events() / self.wave.period


def run_method(
    contract: Contract,
    m: Method,
    fc: float,
    f0: float,
    amp: float,
    seconds: float,
    fsw: float | None = None,
) -> Run:
    """Run ``m`` on one reference point (carrier methods sample at ``fsw``, default ``fc``)."""
    if m.kind == "mdfqm":
        return run_mdfqm_batch(contract, m.osr, m.zero_policy, fc, [(f0, amp)], seconds, m.rule)[0]
    f = fc if fsw is None else fsw
    refs = reference_codes(contract, f, f0, amp, seconds)
    if m.kind == "ideal":
        duties = ideal_duties(refs / contract.full, m.mode)
        return Run(m, PWave.from_centred_duties(duties, f))
    h, _, sat = modulate_bbit(refs, contract, m.mode, m.b, 1)
    return Run(m, PWave.from_samples(h, f * (1 << m.b), contract.phases), int(sat.sum()))


def run_mdfqm_batch(
    contract: Contract,
    osr: int,
    zero_policy: int,
    fc: float,
    points: list[tuple[float, float]],
    seconds: float,
    rule: str = "largest_duty",
) -> list[Run]:
    """MDFQM for many ``(f0, amp)`` points at once (one vectorised batch)."""
    refs = np.stack([reference_codes(contract, fc, f0, a, seconds) for f0, a in points])
    h, _, sat = modulate_batch(refs, contract, rule, zero_policy, osr)
    m = mdfqm(osr, zero_policy, rule)
    return [
        Run(m, PWave.from_samples(h[i], fc * osr, contract.phases), int(sat[i].sum()))
        for i in range(len(points))
    ]
