"""The per-update MDFQM algorithm, in exact integers (the bit-true golden model of one update).

Fixed-point contract (``docs/contract.md``, :mod:`mdfqm_spec.contract`; implemented to the letter)
----------------------------------------------------------------------------------------------------
- Inputs are integers: reference codes ``c_i`` are ``width``-bit two's complement,
  ``FULL = 2**(width-2)`` codes per Vdc.  Everything below works in the *N-scaled* domain, where one
  Vdc is ``N FULL`` and every quantity is an exact integer (Python ``int``; no rounding anywhere).
- ``R_i = N c_i - sum(c)`` (:func:`remove_common_mode`), so ``sum(R) == 0``.
- ``T = X + R``; sort1 orders ``T`` descending by the key ``(-T_i, i)`` (:func:`sort1`).
- Candidates (:func:`candidates`), index ``j`` = number of top legs on, ``j = 0`` the zero class:
  ``largest_duty``: ``d_0 = N FULL - (rho_1 - rho_N)``, ``d_j = rho_j - rho_{j+1}``;
  ``exact_nearest``: ``S_0 = 0``, ``S_j = 2 (rho_1 + .. + rho_j) - FULL j (N - j)``.
- ``j* =`` the smallest index of the largest candidate (:func:`select`).
- Gate state (:func:`decode`): legs ``perm[0..j*-1]`` on; for ``j* == 0`` the zero policy decides
  all-off (``ALL_OFF``) or, with ``FEWEST_TRANSITIONS``, all-on iff ``2 popcount(h_prev) > N``.
  ``h`` is an ``int`` bitmask, bit ``i`` = leg ``i`` (1 = upper switch on).
- Feedback (:func:`feedback`): ``U_i = FULL (N h_i - popcount(h))``.
- Integrator: ``X' = T - U``; if any ``X'_i`` is outside ``[x_min, x_max]`` (a signed
  ``x_width``-bit word) the update is *saturated* and ``X`` holds (conditional integration).
  The chosen state is still output.

Only NumPy (for :func:`modulate_batch`) and the standard library are used.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mdfqm_spec.contract import (
    ALL_OFF,
    FEWEST_TRANSITIONS,
    Contract,
    validate_rule,
    validate_zero_policy,
)

__all__ = [
    "UpdateResult",
    "candidates",
    "decode",
    "feedback",
    "mdfqm_update",
    "modulate",
    "modulate_batch",
    "popcount",
    "remove_common_mode",
    "select",
    "sort1",
]


def _int_vector(values: Sequence[int], n: int, name: str) -> list[int]:
    """Convert to a list of Python ints of length ``n`` (rejects non-integers)."""
    out = []
    for v in values:
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
            raise ValueError(f"{name} must hold integers, got {v!r}")
        out.append(int(v))
    if len(out) != n:
        raise ValueError(f"{name} must have {n} entries (one per phase), got {len(out)}")
    return out


# --------------------------------------------------------------------------------------------
# bit-mask helper
# --------------------------------------------------------------------------------------------


def popcount(h: int) -> int:
    """Number of legs on in the bitmask ``h``."""
    return bin(h).count("1")


# --------------------------------------------------------------------------------------------
# the stages of one update
# --------------------------------------------------------------------------------------------


def remove_common_mode(codes: Sequence[int], phases: int) -> list[int]:
    """Common-mode removal, exact: ``R_i = N c_i - sum_j c_j`` (so ``sum(R) == 0``).

    ``codes`` are the ``phases`` reference codes (integers). The result is in the N-scaled domain
    (one Vdc = ``N FULL``).
    """
    c = _int_vector(codes, phases, "codes")
    s = sum(c)
    return [phases * ci - s for ci in c]


def sort1(t: Sequence[int]) -> tuple[list[int], list[int]]:
    """Sort ``t`` descending by the key ``(-t_i, i)`` (equal values keep leg order).

    Returns ``(rho, perm)``: ``rho[p] = t[perm[p]]`` with ``rho[0] >= rho[1] >= ...``;
    ``perm[p]`` is the leg at sorted position ``p``.
    """
    tt = [int(v) for v in t]
    perm = sorted(range(len(tt)), key=lambda i: (-tt[i], i))
    return [tt[i] for i in perm], perm


def candidates(rho: Sequence[int], contract: Contract, rule: str) -> list[int]:
    """The ``N`` candidate values, index ``j`` = number of top legs on (``j = 0``: zero class).

    ``largest_duty``: ``[N FULL - (rho_1 - rho_N), rho_1 - rho_2, .., rho_{N-1} - rho_N]``.
    ``exact_nearest``: ``S_j = 2 (rho_1 + .. + rho_j) - FULL j (N - j)``, ``S_0 = 0``
    (``N FULL`` times the exact score ``||T||^2 - ||T - N FULL v||^2`` scaled; larger = nearer).
    """
    validate_rule(rule)
    n = contract.phases
    full = contract.full
    r = [int(v) for v in rho]
    if len(r) != n:
        raise ValueError(f"rho must have {n} entries, got {len(r)}")
    if rule == "largest_duty":
        return [n * full - (r[0] - r[n - 1])] + [r[j - 1] - r[j] for j in range(1, n)]
    out = [0]
    prefix = 0
    for j in range(1, n):
        prefix += r[j - 1]
        out.append(2 * prefix - full * j * (n - j))
    return out


def select(values: Sequence[int]) -> int:
    """The smallest index of the largest value (sort2's tie-break)."""
    best = 0
    for j in range(1, len(values)):
        if values[j] > values[best]:
            best = j
    return best


def decode(perm: Sequence[int], j: int, zero_policy: int, h_prev: int, phases: int) -> int:
    """Gate state bitmask for candidate ``j``.

    ``j >= 1``: legs ``perm[0..j-1]`` on. ``j == 0`` (zero class): ``ALL_OFF`` gives 0;
    ``FEWEST_TRANSITIONS`` gives all-on when ``2 popcount(h_prev) > N``, else all-off.
    """
    validate_zero_policy(zero_policy)
    if not 0 <= j < phases:
        raise ValueError(f"j must be in [0, {phases - 1}], not {j}")
    if j == 0:
        if zero_policy == FEWEST_TRANSITIONS and 2 * popcount(h_prev) > phases:
            return (1 << phases) - 1
        return 0
    h = 0
    for p in range(j):
        h |= 1 << perm[p]
    return h


def feedback(h: int, contract: Contract) -> list[int]:
    """``U_i = FULL (N h_i - popcount(h))`` (``N FULL`` times the phase voltage ``v(h)``)."""
    n = contract.phases
    if not 0 <= h < (1 << n):
        raise ValueError(f"h must be a {n}-bit mask, not {h!r}")
    k = popcount(h)
    return [contract.full * (n * ((h >> i) & 1) - k) for i in range(n)]


# --------------------------------------------------------------------------------------------
# one update
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class UpdateResult:
    """Everything one update computes (all exact integers).

    ``h``: gate state bitmask; ``x_next``: integrator after the update (``== x`` if saturated);
    ``saturated``: the anti-windup hold fired; ``t``: ``T = X + R``; ``rho``, ``perm``: sort1;
    ``j``: the selected candidate (0 = zero class).
    """

    h: int
    x_next: tuple[int, ...]
    saturated: bool
    t: tuple[int, ...]
    rho: tuple[int, ...]
    perm: tuple[int, ...]
    j: int


def integrate(x: Sequence[int], t: Sequence[int], u: Sequence[int], contract: Contract):
    """``X' = T - U`` with the hold-on-saturation rule; returns ``(x_next, saturated)``."""
    cand = [ti - ui for ti, ui in zip(t, u, strict=True)]
    if any(v < contract.x_min or v > contract.x_max for v in cand):
        return tuple(int(v) for v in x), True
    return tuple(cand), False


def mdfqm_update(
    x: Sequence[int],
    r: Sequence[int],
    h_prev: int,
    contract: Contract,
    rule: str = "largest_duty",
    zero_policy: int = ALL_OFF,
) -> UpdateResult:
    """One MDFQM update (b = 0: one state per update) per the contract.

    ``x``: integrator state ``X`` (sum 0, each in ``[x_min, x_max]``); ``r``: the common-mode-free
    reference ``R`` (the output of :func:`remove_common_mode`, sum 0); ``h_prev``: the previously
    output state (for the fewest-transitions zero policy).
    """
    n = contract.phases
    validate_rule(rule)
    validate_zero_policy(zero_policy)
    xv = _int_vector(x, n, "x")
    rv = _int_vector(r, n, "r")
    if sum(xv) != 0:
        raise ValueError(f"x must sum to 0 (integrator state), got sum {sum(xv)}")
    if any(v < contract.x_min or v > contract.x_max for v in xv):
        raise ValueError(f"x entries must be in [{contract.x_min}, {contract.x_max}]")
    if sum(rv) != 0:
        raise ValueError(
            f"r must be the common-mode-free reference R (sum 0), got sum {sum(rv)}; "
            "use remove_common_mode(codes, phases)"
        )
    if any(abs(v) > contract.r_bound for v in rv):
        raise ValueError(f"r entries must be within +-{contract.r_bound}")
    if not 0 <= h_prev < (1 << n):
        raise ValueError(f"h_prev must be a {n}-bit mask, not {h_prev!r}")
    t = [a + b for a, b in zip(xv, rv, strict=True)]
    rho, perm = sort1(t)
    j = select(candidates(rho, contract, rule))
    h = decode(perm, j, zero_policy, h_prev, n)
    x_next, saturated = integrate(xv, t, feedback(h, contract), contract)
    return UpdateResult(h, x_next, saturated, tuple(t), tuple(rho), tuple(perm), j)


# --------------------------------------------------------------------------------------------
# whole runs
# --------------------------------------------------------------------------------------------


def _check_osr(osr: int) -> int:
    if isinstance(osr, bool) or not isinstance(osr, (int, np.integer)) or osr < 1:
        raise ValueError(f"osr must be an integer >= 1, not {osr!r}")
    return int(osr)


def _check_codes(refs_codes, contract: Contract) -> np.ndarray:
    a = np.asarray(refs_codes)
    if a.ndim != 2 or a.shape[1] != contract.phases:
        raise ValueError(
            f"refs_codes must be a K x {contract.phases} array of codes, got shape {a.shape}"
        )
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"refs_codes must be integers, got dtype {a.dtype}")
    a = a.astype(np.int64)
    if a.size and (a.min() < contract.code_min or a.max() > contract.code_max):
        raise ValueError(
            f"refs_codes must be {contract.width}-bit codes in "
            f"[{contract.code_min}, {contract.code_max}]"
        )
    return a


def modulate(
    refs_codes,
    contract: Contract,
    rule: str = "largest_duty",
    zero_policy: int = ALL_OFF,
    osr: int = 1,
):
    """Run MDFQM over a reference sequence with a zero-order hold of ``osr`` updates per sample.

    ``refs_codes``: K x N integer codes (one row per reference sample, common mode allowed).
    Starts from the reset state (``X = 0``, ``h_prev = 0``). Returns ``(h, x, saturated)``:
    ``h`` (K*osr,) int64 bitmasks, ``x`` (K*osr, N) int64 integrator state *after* each update,
    ``saturated`` (K*osr,) bool. Exact: uses :func:`mdfqm_update` (Python ints) for every update.
    """
    a = _check_codes(refs_codes, contract)
    osr = _check_osr(osr)
    validate_rule(rule)
    validate_zero_policy(zero_policy)
    n = contract.phases
    k_total = a.shape[0] * osr
    hs = np.zeros(k_total, dtype=np.int64)
    xs = np.zeros((k_total, n), dtype=np.int64)
    sat = np.zeros(k_total, dtype=bool)
    x = (0,) * n
    h = 0
    k = 0
    for row in a.tolist():
        r = remove_common_mode(row, n)
        for _ in range(osr):
            res = mdfqm_update(x, r, h, contract, rule, zero_policy)
            x, h = res.x_next, res.h
            hs[k] = h
            xs[k] = x
            sat[k] = res.saturated
            k += 1
    return hs, xs, sat


def modulate_batch(
    refs_codes,
    contract: Contract,
    rule: str = "largest_duty",
    zero_policy: int = ALL_OFF,
    osr: int = 1,
):
    """Vectorised :func:`modulate` over a batch of independent runs (int64 NumPy, same results).

    ``refs_codes``: B x K x N codes. Returns ``(h, x, saturated)`` of shapes (B, K*osr),
    (B, K*osr, N), (B, K*osr). Exact as long as every intermediate fits in int64, which is
    checked (it holds for every width <= 32 and N <= 2**20).
    """
    a = np.asarray(refs_codes)
    if a.ndim != 3:
        raise ValueError(f"refs_codes must be B x K x N, got shape {a.shape}")
    bsz, kk, n = a.shape
    if n != contract.phases:
        raise ValueError(f"refs_codes must have {contract.phases} phases, got {n}")
    _check_codes(a.reshape(-1, n), contract)
    osr = _check_osr(osr)
    validate_rule(rule)
    validate_zero_policy(zero_policy)
    full = contract.full
    tmax = contract.x_max + contract.r_bound + 1
    if 2 * n * tmax + full * n * n >= 1 << 62:
        raise ValueError("modulate_batch: configuration too wide for int64 arithmetic")
    a = a.astype(np.int64)
    r_all = n * a - a.sum(axis=2, keepdims=True)
    idx = np.arange(n)
    weights = (1 << idx).astype(np.int64)
    j_all = np.arange(1, n, dtype=np.int64)
    offsets = full * j_all * (n - j_all)
    x = np.zeros((bsz, n), dtype=np.int64)
    h = np.zeros(bsz, dtype=np.int64)
    hs = np.zeros((bsz, kk * osr), dtype=np.int64)
    xs = np.zeros((bsz, kk * osr, n), dtype=np.int64)
    sat = np.zeros((bsz, kk * osr), dtype=bool)
    rows = np.arange(bsz)
    k = 0
    for s in range(kk):
        r = r_all[:, s, :]
        for _ in range(osr):
            t = x + r
            perm = np.argsort(-t, axis=1, kind="stable")
            rho = np.take_along_axis(t, perm, axis=1)
            if rule == "largest_duty":
                cand = np.empty((bsz, n), dtype=np.int64)
                cand[:, 0] = n * full - (rho[:, 0] - rho[:, -1])
                cand[:, 1:] = rho[:, :-1] - rho[:, 1:]
            else:
                cand = np.zeros((bsz, n), dtype=np.int64)
                cand[:, 1:] = 2 * np.cumsum(rho[:, :-1], axis=1) - offsets
            j = np.argmax(cand, axis=1)  # first index of the maximum
            on_sorted = idx[None, :] < j[:, None]
            hb = np.zeros((bsz, n), dtype=np.int64)
            hb[rows[:, None], perm] = on_sorted
            hn = hb @ weights
            if zero_policy == FEWEST_TRANSITIONS:
                pc = np.zeros(bsz, dtype=np.int64)
                for i in range(n):
                    pc += (h >> i) & 1
                allon = (j == 0) & (2 * pc > n)
                hn = np.where(allon, (1 << n) - 1, hn)
                hb = np.where(allon[:, None], 1, hb)
            kon = hb.sum(axis=1, keepdims=True)
            u = full * (n * hb - kon)
            xn = t - u
            bad = ((xn < contract.x_min) | (xn > contract.x_max)).any(axis=1)
            x = np.where(bad[:, None], x, xn)
            h = hn
            hs[:, k] = h
            xs[:, k] = x
            sat[:, k] = bad
            k += 1
    return hs, xs, sat
