"""The fixed-point and timing contract of every block, as code: widths, bounds, latencies, the
sorting network, the generator's runtime clamp, and the validators of the parameters.

Both the gateware (:mod:`mdfqm_gateware`) and the golden model (:mod:`mdfqm_model`) import this
module; the model predicts every bit of every clock from it, the gateware builds its shapes from
it. The contract in prose (the integer domain, the tie-breaks, the clock-level timing rules, the
b-bit generator) is ``docs/contract.md``.
Pure Python: no NumPy, no Amaranth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .validate import validate_int

__all__ = [
    "ALL_OFF", "ARGMAX_GROUP", "BITS_WIDTH", "CLARKE_FRAC", "CLARKE_K", "FEWEST_TRANSITIONS",
    "LARGEST_DUTY_MAX_PHASES", "MAX_BITS_LIMIT", "MAX_WIDTH", "MIN_PHASES", "MODES", "MODE_WIDTH",
    "OSR_WIDTH", "PERIOD_WIDTH", "RULES", "TIME_WIDTH", "ZERO_POLICIES", "Contract",
    "argmax_stages", "ceil_log2", "latch_mode", "loop_latency", "min_period", "min_width",
    "modes_built_in", "reference_latency", "resolution_latency", "signed_bits", "sorting_network",
    "validate_dead_min", "validate_max_bits", "validate_rule", "validate_time_width",
    "validate_top_max_bits", "validate_zero_policy",
]

RULES = ("largest_duty", "exact_nearest")
ALL_OFF = 0
FEWEST_TRANSITIONS = 1
ZERO_POLICIES = (ALL_OFF, FEWEST_TRANSITIONS)

MIN_PHASES = 3
MAX_WIDTH = 32

#: width of the core's ``period`` input (clocks per update) and of the top's PERIOD register
PERIOD_WIDTH = 16
#: width of the core's ``osr`` input (updates per reference sample) and of the top's OSR register
OSR_WIDTH = 8
#: width of the gate driver's dead-time / minimum-pulse inputs and of its leg counters (clocks)
TIME_WIDTH = 16

#: inverse Clarke transform (``docs/contract.md``, "Alpha-beta input"): ``CLARKE_K =
#: round(sqrt(3)/2 * 2**CLARKE_FRAC)``, the fixed-point sqrt(3)/2
CLARKE_FRAC = 17
CLARKE_K = round(math.sqrt(3) / 2 * (1 << CLARKE_FRAC))


def ceil_log2(value: int) -> int:
    """Smallest ``b`` with ``2**b >= value`` (``value >= 1``)."""
    return (value - 1).bit_length()


def signed_bits(lo: int, hi: int) -> int:
    """Bits of the smallest two's-complement word holding every integer in [lo, hi]."""
    bits = 1
    while not (-(1 << (bits - 1)) <= lo and hi <= (1 << (bits - 1)) - 1):
        bits += 1
    return bits


def min_width(phases: int) -> int:
    """Narrowest legal reference width for ``phases`` legs: ``FULL >= 16 N``.

    The state lattice has spacing ``1/N`` Vdc; the reference must resolve it at least 16 times.
    """
    return 2 + ceil_log2(16 * phases)


def sorting_network(n: int) -> list[list[tuple[int, int]]]:
    """Batcher's odd-even merge sort for ``n`` inputs, as layers of comparators.

    Built for the next power of two, comparators touching absent inputs removed (valid because
    every comparator puts its larger element at its lower index), then scheduled as soon as
    possible. Each pair ``(a, b)`` has ``a < b``: afterwards position ``a`` holds the element that
    sorts first. The number of layers is the depth of sort1 in clocks.
    """
    if n < 1:
        raise ValueError(f"sorting_network: n must be >= 1, not {n}")
    size = 1 << ceil_log2(n)
    comparators = []
    span = 1
    while span < size:
        step = span
        while step >= 1:
            for j in range(step % span, size - step, 2 * step):
                for i in range(min(step, size - j - step)):
                    if (i + j) // (2 * span) == (i + j + step) // (2 * span):
                        comparators.append((i + j, i + j + step))
            step //= 2
        span *= 2
    ready = [0] * n
    layers: list[list[tuple[int, int]]] = []
    for a, b in comparators:
        if b >= n:
            continue
        layer = max(ready[a], ready[b])
        while len(layers) <= layer:
            layers.append([])
        layers[layer].append((a, b))
        ready[a] = ready[b] = layer + 1
    return layers


#: candidates compared at once in one stage of the selector's max-tournament (all pairs)
ARGMAX_GROUP = 4


def argmax_stages(candidates: int) -> int:
    """Pipeline stages of the max-tournament over ``candidates`` values, ARGMAX_GROUP a stage."""
    stages, remaining = 0, candidates
    while remaining > 1:
        remaining = -(-remaining // ARGMAX_GROUP)
        stages += 1
    return stages


#: Most phases the largest-duty rule is offered for. It is not the nearest state for N > 3, and
#: for N >= 16 its integrators grow past the bound inside the linear range (measured in the
#: model's tests); up to 12 phases they stay below 2.01 Vdc against a bound of >= 2.67 Vdc.
LARGEST_DUTY_MAX_PHASES = 12


def validate_rule(rule, phases: int | None = None) -> str:
    """``rule`` if it is one of :data:`RULES` (and, given ``phases``, offered for that many: the
    largest-duty rule is refused beyond :data:`LARGEST_DUTY_MAX_PHASES`)."""
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, not {rule!r}")
    if rule == "largest_duty" and phases is not None and phases > LARGEST_DUTY_MAX_PHASES:
        raise ValueError(
            f"rule 'largest_duty' is offered for at most {LARGEST_DUTY_MAX_PHASES} phases (its "
            f"integrators outgrow their bound beyond); use 'exact_nearest' for {phases} phases")
    return rule


def validate_zero_policy(zero_policy) -> int:
    """``zero_policy`` (0 = all-off, 1 = fewest transitions) as an ``int``."""
    if isinstance(zero_policy, bool) or zero_policy not in ZERO_POLICIES:
        raise ValueError(
            f"zero_policy must be one of {ZERO_POLICIES} (0 = all-off, 1 = fewest transitions), "
            f"not {zero_policy!r}"
        )
    return int(zero_policy)


def loop_latency(phases: int, rule: str = "largest_duty") -> int:
    """Clocks from an update start to its result: the minimum update period ``L``.

    1 (T = X + R) + depth(sort1) + 1 (duties or scores) + argmax stages + 1 (decode h)
    + 1 (feedback and integrator commit). Refuses what :func:`validate_rule` refuses.
    """
    validate_rule(rule, phases)
    return 1 + len(sorting_network(phases)) + 1 + argmax_stages(phases) + 1 + 1


def reference_latency(phases: int) -> int:
    """Clocks from a reference beat's acceptance (cycle ``a``) to its common-mode-free ``R``
    being pending (``full`` from cycle ``a + reference_latency``): one clock to register the
    beat, then ``N`` clocks summing it and ``N`` clocks forming ``R_i = N c_i - sum c``, one
    phase per clock. A sampling tick uses it when it is pending in the cycle before the tick."""
    if not isinstance(phases, int) or phases < MIN_PHASES:
        raise ValueError(f"phases must be an integer >= {MIN_PHASES}, not {phases!r}")
    return 1 + 2 * phases


#: generator modes, index = the ``mode`` input's code (docs/contract.md, "b-bit pulse-width
#: resolution")
MODES = ("mdfqm", "svpwm", "dpwm0", "dpwm1", "dpwm")
#: width of the generator's ``mode`` input
MODE_WIDTH = 3
#: width of the generator's ``bits`` input
BITS_WIDTH = 4
#: largest ``max_bits`` offered (4096 slots per update)
MAX_BITS_LIMIT = 12


def validate_max_bits(max_bits, width: int) -> int:
    """``max_bits`` if it is an integer in ``[1, min(MAX_BITS_LIMIT, width - 2)]``."""
    top = min(MAX_BITS_LIMIT, width - 2)
    if isinstance(max_bits, bool) or not isinstance(max_bits, int) or not 1 <= max_bits <= top:
        raise ValueError(
            f"max_bits must be an integer in [1, {top}] for a {width}-bit reference "
            f"(2**max_bits slots <= FULL, at most {MAX_BITS_LIMIT}), not {max_bits!r}")
    return max_bits


def validate_top_max_bits(max_bits, width: int) -> int:
    """The top's ``max_bits``: 0 (the MDFQM-only top, the core alone) or a generator's
    (:func:`validate_max_bits`)."""
    if isinstance(max_bits, int) and not isinstance(max_bits, bool) and max_bits == 0:
        return 0
    try:
        return validate_max_bits(max_bits, width)
    except ValueError as error:
        raise ValueError(f"{error} (or 0: MDFQM only)") from None


def modes_built_in(max_bits: int) -> int:
    """Modes a generator with this ``max_bits`` offers (codes ``0 .. modes - 1``): all of
    :data:`MODES`, or mdfqm alone for ``max_bits`` 0 (the MDFQM-only top)."""
    return len(MODES) if max_bits else 1


def resolution_latency(phases: int, max_bits: int) -> int:
    """``L_b``: clocks from the start of a long update to its presentation.

    1 (T = X + R) + depth(sort1) + 1 (max + min) + 1 (zero split and offsets) + 1 (per-leg
    instants) + 1 (clamp, divider load) + max_bits (restoring division, one quotient bit a clock)
    + ceil(log2 N) (once the sums over the legs: the quantiser now accumulates the feedback
    alongside the division and is done early, the latency is kept) + 1 (feedback) + 1
    (integrator commit / presentation).
    """
    if isinstance(phases, bool) or not isinstance(phases, int) or phases < MIN_PHASES:
        raise ValueError(f"phases must be an integer >= {MIN_PHASES}, not {phases!r}")
    if isinstance(max_bits, bool) or not isinstance(max_bits, int) or max_bits < 1:
        raise ValueError(f"max_bits must be an integer >= 1, not {max_bits!r}")
    return 7 + len(sorting_network(phases)) + ceil_log2(phases) + max_bits


def latch_mode(mode: int, bits: int, max_bits: int) -> tuple[int, int, bool]:
    """The runtime clamp of the generator: ``(mode code, b, clamped)`` used for an update.

    Codes of modes not built in (``>= modes_built_in(max_bits)``: 5..7, or 1..7 when
    ``max_bits`` is 0, the MDFQM-only top) act as mdfqm (flagged); mdfqm uses b = 0 (``bits``
    ignored, not flagged); a gamma mode uses ``min(max(bits, 1), max_bits)`` (flagged when that
    differs).
    """
    if not 0 <= mode < (1 << MODE_WIDTH) or not 0 <= bits < (1 << BITS_WIDTH):
        raise ValueError(f"mode must be a {MODE_WIDTH}-bit and bits a {BITS_WIDTH}-bit code, "
                         f"not {mode!r}, {bits!r}")
    if mode >= modes_built_in(max_bits):
        return 0, 0, True
    if mode == 0:
        return 0, 0, False
    b = min(max(bits, 1), max_bits)
    return mode, b, b != bits


def min_period(long: bool, b: int, latency: int, long_latency: int) -> int:
    """Smallest honoured period: ``latency`` for a short update, ``max(L_b, 2**b)`` for a long
    one (b = 0 for mdfqm)."""
    return max(long_latency, 1 << b) if long else latency


@dataclass(frozen=True)
class Contract:
    """Widths and bounds of one configuration; construction validates the parameters."""

    phases: int = 3
    width: int = 16

    def __post_init__(self):
        if not isinstance(self.phases, int) or self.phases < MIN_PHASES:
            raise ValueError(f"phases must be an integer >= {MIN_PHASES}, not {self.phases!r}")
        if not isinstance(self.width, int) or not (
            min_width(self.phases) <= self.width <= MAX_WIDTH
        ):
            raise ValueError(
                f"width must be an integer in [{min_width(self.phases)}, {MAX_WIDTH}] for "
                f"{self.phases} phases (FULL = 2**(width-2) >= 16 * phases), not {self.width!r}"
            )

    @property
    def full(self) -> int:
        """Codes of one Vdc at the reference input."""
        return 1 << (self.width - 2)

    @property
    def code_min(self) -> int:
        return -(1 << (self.width - 1))

    @property
    def code_max(self) -> int:
        return (1 << (self.width - 1)) - 1

    @property
    def unit(self) -> int:
        """One Vdc in the internal (N-scaled) domain: ``N FULL``."""
        return self.phases * self.full

    @property
    def r_bound(self) -> int:
        """Largest ``|R_i|`` after common-mode removal."""
        return (self.phases - 1) * ((1 << self.width) - 1)

    @property
    def r_width(self) -> int:
        return signed_bits(-self.r_bound, self.r_bound)

    @property
    def x_width(self) -> int:
        return self.width + ceil_log2(self.phases)

    @property
    def x_min(self) -> int:
        return -(1 << (self.x_width - 1))

    @property
    def x_max(self) -> int:
        return (1 << (self.x_width - 1)) - 1

    @property
    def t_width(self) -> int:
        """Width of ``T = X + R``."""
        return signed_bits(self.x_min - self.r_bound, self.x_max + self.r_bound)

    @property
    def u_bound(self) -> int:
        """Largest ``|U_i|``: ``FULL (N - 1)``."""
        return self.full * (self.phases - 1)


def validate_time_width(time_width) -> int:
    """``time_width`` in [2, 32] (bits of the dead-time and minimum-pulse counters)."""
    return validate_int(time_width, "time_width", 2, 32)


def validate_dead_min(dead_min, time_width: int = TIME_WIDTH) -> int:
    """``dead_min`` in [1, 2**time_width - 1]: the dead-time floor in clocks."""
    top = (1 << time_width) - 1
    if isinstance(dead_min, bool) or not isinstance(dead_min, int) or not 1 <= dead_min <= top:
        raise ValueError(f"dead_min must be an integer in [1, {top}] (clocks), not {dead_min!r}")
    return dead_min
