"""The b-bit pulse-width-resolution gating-signal generator (the paper's Sec. 3, eqs. 6-8).

Each update period is split into ``S = 2**b`` equal slots; the duties of the staircase states are
quantised to whole slots and the quantisation error is fed back through the same integrator as
MDFQM. SVPWM (gamma = 1/2, centred) and DPWM (gamma = 0 / 1, or a sector-dependent clamp) are
settings of this one generator; MDFQM is its ``b = 0`` end (one state per update, handled by
:func:`mdfqm_model.update.mdfqm_update`).

Fixed-point contract (extends :mod:`mdfqm_spec.contract`; all quantities exact integers)
------------------------------------------------------------------------------------------
- Same input format and N-scaled domain as the core: ``R_i = N c_i - sum(c)``, ``T = X + R``,
  one Vdc = ``NF = N FULL``; sort1 by the key ``(-T_i, i)`` gives ``rho``, ``perm``.
- Duties (N-scaled), zero split ``gamma`` in {0, 1/2, 1}:
  ``d_0 = gamma (NF - rho_1 + rho_N)``, ``d_j = rho_j - rho_{j+1}`` (j = 1..N-1),
  ``d_N = (1 - gamma) (NF - rho_1 + rho_N)``. Staircase column ``j`` (top ``j`` legs on) dwells
  ``d_j``. Modes: ``svpwm`` gamma = 1/2; ``dpwm0`` gamma = 0 (top leg clamped on); ``dpwm1``
  gamma = 1 (bottom leg clamped off); ``dpwm`` sector-dependent: gamma = 0 if
  ``rho_1 >= -rho_N`` else 1 (clamp the leg with the larger |extreme|).
- Quantisation: the cumulative switching instants ``C_j = d_0 + .. + d_{j-1}`` (j = 1..N) are
  rounded to multiples of ``NF / S``, half up, and clamped to ``[0, S]``:
  ``q_j = clamp(floor((2 C_j S + NF) / (2 NF)), 0, S)`` (``2 C_j`` is an integer), ``q_0 = 0``,
  ``q_{N+1} = S``; column ``j`` gets ``n_j = q_{j+1} - q_j`` slots (sum ``S``). Equivalently the leg
  at sorted position ``p`` (0-based) is on for ``S - q_{p+1}`` slots.
- Mean feedback over the period: ``U_i = (FULL / S) (N n_i - sum_k n_k)`` with ``n_i`` the
  on-slots of leg ``i`` (exact: ``S <= FULL``, both powers of two, so ``b <= width - 2``).
- Integrator ``X' = T - U`` with the contract's hold-on-saturation rule (``x_width`` bits).
- Layout: each leg's on-slots are centred in the period, slots ``[(S - n) // 2, (S - n) // 2 + n)``
  (left of centre by half a slot when ``S - n`` is odd). Longer intervals contain shorter ones, so
  every slot holds a staircase state and each leg switches at most twice per period. With
  gamma = 1/2 this is the centred 0-V1-V2-7-7-V2-V1-0 sequence.
- In the linear range (``rho_1 - rho_N <= NF``) every ``q_j`` rounds an exact instant, so each
  leg's on-time is within half a slot of the exact duty and ``|X_i| <= (N - 1) FULL / S`` (less
  than one quantum ``1/S`` Vdc).

The gateware (``GatingSignalGenerator``) computes exactly this, per leg and without the
permutation, through the identities stated in :mod:`mdfqm_spec.contract` (section "b-bit
pulse-width resolution") and checked in ``model/tests/test_bbit_hardware.py``; its clock-level
model is :class:`mdfqm_model.clock.GeneratorModel`, which calls :func:`bbit_update`.

SVPWM definition used by the analysis: this generator with ``mode="svpwm"``, large ``b``
(default 8: 256 slots per carrier period) and OSR 1; the carrier period is the update period.
Its quantisation error (< 1/256 Vdc, first-order noise-shaped by the loop) is negligible next to
the carrier ripple. :func:`ideal_svpwm_edges` gives the ideal continuous SVPWM (x = 0) as exact
switching instants for cross-checks.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mdfqm_spec.contract import ALL_OFF, MODES, Contract, validate_rule, validate_zero_policy

from .update import (
    _check_codes,
    _check_osr,
    _int_vector,
    integrate,
    mdfqm_update,
    modulate,
    remove_common_mode,
    sort1,
)

__all__ = [
    "MODES",
    "BbitResult",
    "bbit_update",
    "centred_slots",
    "centred_slots_array",
    "gamma2_for",
    "ideal_svpwm_edges",
    "modulate_bbit",
    "quantised_instants",
    "rounding_numerators",
    "validate_mode",
]



def validate_mode(mode: str, b: int, contract: Contract) -> None:
    """Check ``mode`` and ``b``: ``mdfqm`` needs ``b == 0``; the others ``1 <= b <= width - 2``."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, not {mode!r}")
    if isinstance(b, bool) or not isinstance(b, (int, np.integer)):
        raise ValueError(f"b must be an integer, not {b!r}")
    if mode == "mdfqm":
        if b != 0:
            raise ValueError(f"mode 'mdfqm' is the b = 0 generator, not b = {b}")
        return
    if not 1 <= b <= contract.width - 2:
        raise ValueError(
            f"b must be in [1, {contract.width - 2}] for mode {mode!r} (S = 2**b <= FULL), not {b}"
        )


def gamma2_for(mode: str, rho: Sequence[int]) -> int:
    """Twice the zero split gamma (0, 1 or 2) of ``mode`` for the sorted ``rho``."""
    if mode == "svpwm":
        return 1
    if mode == "dpwm0":
        return 0
    if mode == "dpwm1":
        return 2
    if mode == "dpwm":
        return 0 if rho[0] >= -rho[-1] else 2
    raise ValueError(f"gamma is defined for {MODES[1:]}, not {mode!r}")


def rounding_numerators(rho: Sequence[int], gamma2: int, slots: int,
                        contract: Contract) -> list[int]:
    """``[2 C_j S + NF for j = 1..N]``: the instant ``C_j`` rounds to the slot
    ``floor(numerator / (2 NF))`` (half up: a numerator that is a multiple of ``2 NF`` is
    exactly half-way between two slot boundaries)."""
    n = contract.phases
    nf = contract.unit
    two_c = gamma2 * (nf - rho[0] + rho[-1])       # 2 C_1
    out = [two_c * slots + nf]
    for j in range(1, n):
        two_c += 2 * (rho[j - 1] - rho[j])
        out.append(two_c * slots + nf)
    return out


def quantised_instants(rho: Sequence[int], gamma2: int, slots: int, contract: Contract) -> list:
    """``[q_0, .., q_{N+1}]``: the switching instants rounded to whole slots (see module doc)."""
    two_nf = 2 * contract.unit
    return [0, *(min(max(v // two_nf, 0), slots)
                 for v in rounding_numerators(rho, gamma2, slots, contract)), slots]


def centred_slots(on_slots: Sequence[int], slots: int) -> list[int]:
    """Per-slot gate bitmasks with each leg's ``on_slots[i]`` on-slots centred in the period."""
    out = [0] * slots
    for i, n_on in enumerate(on_slots):
        start = (slots - n_on) // 2
        for s in range(start, start + n_on):
            out[s] |= 1 << i
    return out


@dataclass(frozen=True)
class BbitResult:
    """One update of the b-bit generator.

    ``slots``: gate bitmask of each of the ``S`` slots; ``on_slots``: per leg; ``x_next``,
    ``saturated``, ``t``, ``rho``, ``perm`` as in :class:`mdfqm_model.update.UpdateResult`;
    ``q``: the quantised instants ``q_0..q_{N+1}``; ``gamma2``: twice the zero split used.
    """

    slots: tuple[int, ...]
    on_slots: tuple[int, ...]
    x_next: tuple[int, ...]
    saturated: bool
    t: tuple[int, ...]
    rho: tuple[int, ...]
    perm: tuple[int, ...]
    q: tuple[int, ...]
    gamma2: int


def bbit_update(
    x: Sequence[int],
    r: Sequence[int],
    contract: Contract,
    mode: str = "svpwm",
    b: int = 8,
    h_prev: int = 0,
    rule: str = "largest_duty",
    zero_policy: int = ALL_OFF,
) -> BbitResult:
    """One update of the b-bit generator (``mode="mdfqm"``, ``b=0``: one MDFQM update).

    ``x``: integrator state; ``r``: the common-mode-free reference ``R``; ``h_prev``, ``rule`` and
    ``zero_policy`` are used by MDFQM only.
    """
    validate_mode(mode, b, contract)
    n = contract.phases
    if mode == "mdfqm":
        res = mdfqm_update(x, r, h_prev, contract, rule, zero_policy)
        on = tuple((res.h >> i) & 1 for i in range(n))
        return BbitResult((res.h,), on, res.x_next, res.saturated, res.t, res.rho, res.perm, (), 2)
    on, x_next, saturated, t, rho, perm, q, g2 = _gamma_update(x, r, contract, mode, b)
    return BbitResult(
        tuple(centred_slots(on, 1 << b)),
        tuple(on),
        x_next,
        saturated,
        tuple(t),
        tuple(rho),
        tuple(perm),
        tuple(q),
        g2,
    )


def _gamma_update(x, r, contract: Contract, mode: str, b: int):
    """The arithmetic of one gamma-mode update (no slot layout)."""
    n = contract.phases
    xv = _int_vector(x, n, "x")
    rv = _int_vector(r, n, "r")
    if sum(xv) != 0 or sum(rv) != 0:
        raise ValueError("x and r must each sum to 0 (r is the output of remove_common_mode)")
    slots = 1 << b
    t = [a + c for a, c in zip(xv, rv, strict=True)]
    rho, perm = sort1(t)
    g2 = gamma2_for(mode, rho)
    q = quantised_instants(rho, g2, slots, contract)
    on = [0] * n
    for p in range(n):
        on[perm[p]] = slots - q[p + 1]
    scale = contract.full // slots
    total = sum(on)
    u = [scale * (n * on[i] - total) for i in range(n)]
    x_next, saturated = integrate(xv, t, u, contract)
    return on, x_next, saturated, t, rho, perm, q, g2


def centred_slots_array(on_slots: np.ndarray, slots: int) -> np.ndarray:
    """Vectorised :func:`centred_slots`: K x N on-slot counts -> (K*S,) gate bitmasks."""
    on = np.asarray(on_slots, dtype=np.int64)
    k, n = on.shape
    pos = np.arange(slots, dtype=np.int64)[None, :]
    out = np.zeros((k, slots), dtype=np.int64)
    for i in range(n):
        start = (slots - on[:, i : i + 1]) // 2
        bit = (pos >= start) & (pos < start + on[:, i : i + 1])
        out |= bit.astype(np.int64) << i
    return out.reshape(-1)


def modulate_bbit(
    refs_codes,
    contract: Contract,
    mode: str = "svpwm",
    b: int = 8,
    osr: int = 1,
    rule: str = "largest_duty",
    zero_policy: int = ALL_OFF,
):
    """Run the generator over K reference samples, each held for ``osr`` updates.

    Returns ``(h_slots, x, saturated)``: ``h_slots`` (K*osr*S,) int64 gate bitmasks, one per slot
    (``S = 2**b``; for MDFQM one per update); ``x`` (K*osr, N) the integrator after each update;
    ``saturated`` (K*osr,) bool. Starts from the reset state.
    """
    a = _check_codes(refs_codes, contract)
    osr = _check_osr(osr)
    validate_mode(mode, b, contract)
    validate_rule(rule)
    validate_zero_policy(zero_policy)
    n = contract.phases
    if mode == "mdfqm":
        return modulate(a, contract, rule, zero_policy, osr)
    k_total = a.shape[0] * osr
    ons = np.zeros((k_total, n), dtype=np.int64)
    xs = np.zeros((k_total, n), dtype=np.int64)
    sat = np.zeros(k_total, dtype=bool)
    x = (0,) * n
    k = 0
    for row in a.tolist():
        r = remove_common_mode(row, n)
        for _ in range(osr):
            on, x, saturated, *_ = _gamma_update(x, r, contract, mode, b)
            ons[k] = on
            xs[k] = x
            sat[k] = saturated
            k += 1
    return centred_slots_array(ons, 1 << b), xs, sat


def ideal_svpwm_edges(refs: np.ndarray) -> np.ndarray:
    """Ideal continuous centred SVPWM (x = 0, infinite resolution), one carrier period per sample.

    ``refs``: K x N phase voltages in Vdc (any common mode; removed here). Returns the K x N duties
    ``a_i = 1/2 + v_i - (max v + min v) / 2`` (min-max injection, i.e. gamma = 1/2), clipped to
    [0, 1] outside the linear range; leg ``i`` is on during ``[(1 - a_i)/2, (1 + a_i)/2)`` of the
    period. This is the ``b -> infinity`` limit of ``mode="svpwm"``.
    """
    v = np.asarray(refs, dtype=float)
    v = v - v.mean(axis=1, keepdims=True)
    duty = 0.5 + v - 0.5 * (v.max(axis=1, keepdims=True) + v.min(axis=1, keepdims=True))
    return np.clip(duty, 0.0, 1.0)
