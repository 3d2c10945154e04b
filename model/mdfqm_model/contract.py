"""The fixed-point and timing contract shared by the golden model and the gateware.

Everything the hardware computes is specified here in integers, so that the model can predict
every bit of every clock. The gateware imports only the *constants and shapes* of this module
(widths, bounds, loop latency, the sorting network's comparator list); the values it must
produce come from :mod:`mdfqm_model.update` and :mod:`mdfqm_model.clock`.

Notation follows ``shared/design/ALGORITHM.md``: ``N`` legs, gate state ``h`` in {0,1}^N,
phase voltage ``v(h) = h - mean(h)`` in units of the DC link (Vdc = 1).

Reference format
----------------
Each phase reference is a two's-complement integer ``c_i`` of ``width`` (W) bits. One Vdc is
``FULL = 2**(W-2)`` codes, so a code spans [-2, 2) Vdc: twice the largest phase voltage any
state can produce, which leaves room for overmodulation tests up to twice the linear range and
for common-mode offsets without input clipping.

Internal integer domain (everything scaled by N)
------------------------------------------------
- Common-mode removal, exact: ``R_i = N c_i - sum_j c_j``  (so ``sum(R) == 0``).
- Feedback of a state with ``k = popcount(h)`` legs on: ``U_i = FULL (N h_i - k)``
  (this is ``N FULL v(h)``, an exact integer).
- Optimum signal: ``T = X + R``.  Integrator: ``X' = T - U``.  ``sum(X) == 0`` always.
- One Vdc is ``N FULL`` in this domain; the linear range is ``max(T) - min(T) <= N FULL``.

Integrator bound (anti-windup)
------------------------------
(With ``largest_duty`` this holds up to LARGEST_DUTY_MAX_PHASES = 12 phases, which is why that
rule is refused beyond; ``exact_nearest`` keeps ``|X_i| <= 1 Vdc`` for every N tested, 3..32.)

``X_i`` must fit in a signed ``x_width = W + ceil(log2 N)`` bit word, i.e.
``-2**(x_width-1) <= X_i < 2**(x_width-1)``; ``2**(x_width-1) >= 2 N FULL`` (>= 2 Vdc).
If any component of ``X' = T - U`` falls outside, the update is *saturated*: the integrator
holds its old value (conditional integration), which keeps ``sum(X) == 0`` exactly and makes
wrap-around impossible. The chosen state is still output. In the linear range the bound is never
reached (the model's tests check this).

Sort1 (N-input sort) tie-break
------------------------------
``T`` is sorted descending by the key ``(-T_i, i)``: equal values keep leg order (lower leg
index first). ``rho`` are the sorted values, ``perm[p]`` the leg at sorted position ``p``.

Candidates and the two selection rules
--------------------------------------
Candidate ``j`` (j = 0..N-1) is the staircase state with the top-``j`` legs on; ``j = 0`` is the
*zero class* (all-off or all-on; both give v = 0, and the all-on column ``j = N`` always ties with
``j = 0``).
- ``largest_duty`` (patent / paper, gamma = 1): ``d_0 = N FULL - (rho_1 - rho_N)``,
  ``d_j = rho_j - rho_{j+1}`` for j = 1..N-1 (1-based rho).
- ``exact_nearest`` (design notes section 4): ``S_j = 2 (rho_1 + .. + rho_j) - FULL j (N - j)``,
  ``S_0 = 0``; this is ``N FULL`` times the exact score, so the largest ``S_j`` is the state
  nearest to ``T``.
The selected ``j*`` is the *smallest* ``j`` with the largest value (sort2's tie-break).
For N = 3 the two rules give the same ``j*`` for every input (``d = 1.5 S + const``).

Zero-state policy
-----------------
If ``j* == 0``: ``ALL_OFF`` (0) gives h = 0...0 (the paper); ``FEWEST_TRANSITIONS`` (1) gives
all-on when ``2 popcount(h_prev) > N`` and all-off otherwise (ties go to all-off), where
``h_prev`` is the previously output state (0 after reset). Otherwise ``h`` has the legs
``perm[0..j*-1]`` on.

Clock-level timing of the core (see :mod:`mdfqm_model.clock`)
--------------------------------------------------------------
All registers reset synchronously to zero. ``L = loop_latency(N, rule)`` clocks.
- Update sequencer: a counter ``phase``; a cycle with ``phase == 0`` is an *update start*
  (output ``start``). At an update start the runtime inputs *of that cycle* are latched:
  ``P = max(period, L)`` (``period_clamped`` = ``period < L``, registered), ``osr = max(osr, 1)``
  (used for the ``sub`` step of that same cycle), ``zero_policy`` (used by that update).
  Next ``phase`` is 0 if ``phase + 1 >= P`` (P being the value latched at the start of this
  update) else ``phase + 1``.
- Sync: ``sync_in`` high in a cycle with ``phase + 1 >= L`` (the update in flight is committed
  by the next cycle) makes the next cycle an update start; earlier in an update it is ignored,
  so an update is never cut short. Wire one instance's ``start`` to the others' ``sync_in``: a
  follower out of step restarts one clock after the leader's start; one already in step (same
  period, common reset) stays in the same clock (sync_in is ignored at its own start).
- Sampling switch: a counter ``sub`` of updates; an update start with ``sub == 0`` is a
  *sampling tick* (``sample`` output high that cycle). At each update start
  ``sub <- 0 if sub + 1 >= osr else sub + 1``.
- Reference stage: the stream ``ref`` (valid/ready) has ``ready = not (s1 or s2 or full)``.
  A beat accepted in cycle a is registered (s1 set), common mode is removed over the next two
  cycles (s2, then ``pending`` with ``full`` set, visible from cycle a + 3). At a sampling tick
  with ``full``, the update uses ``pending`` (and it becomes ``held``, ``full`` clears);
  otherwise the update uses ``held`` (zero-order hold). ``held`` is 0 after reset.
- An update starting in cycle s computes ``T = X + R`` in cycle s; ``h``, the integrator, the
  ``saturated`` flag and a one-cycle ``update`` strobe all change together, visible in cycle
  ``s + L``. So ``P >= L`` guarantees every update sees the previous update's feedback.

b-bit pulse-width resolution: the gating-signal generator
---------------------------------------------------------
The paper's general generator (its Sec. 3.1): MDFQM (b = 0), SVPWM, DPWM and any b between, in
one component (RTL ``GatingSignalGenerator``, clock model :class:`mdfqm_model.clock.
GeneratorModel`, per-update arithmetic :func:`mdfqm_model.bbit.bbit_update`). It contains the
core's blocks (reference stage, integrators, sort1, MDFQM selection) and adds a quantiser and a
slot layout; the MDFQM-only core does not contain them.

- Elaboration parameter ``max_bits`` B in ``[1, min(MAX_BITS_LIMIT, width - 2)]`` (so that
  ``S = 2**b <= FULL``): the largest resolution offered.
- Runtime inputs, latched at each update start with ``period``, ``osr``, ``zero_policy``:
  ``mode`` (MODE_WIDTH bits, the index into ``MODES``: 0 mdfqm, 1 svpwm, 2 dpwm0, 3 dpwm1,
  4 dpwm = sector-dependent clamp) and ``bits`` (BITS_WIDTH bits, b). :func:`latch_mode`:
  codes >= len(MODES) act as mdfqm; mdfqm uses b = 0 whatever ``bits`` says; a gamma mode with
  ``bits`` outside ``[1, B]`` uses the nearest end. ``mode_clamped`` (registered at the start,
  like ``period_clamped``) flags an illegal ``mode`` code or a clamped ``bits``.
- Arithmetic of a gamma-mode update: :mod:`mdfqm_model.bbit` (duties with zero split gamma,
  cumulative instants rounded half up to ``S`` slots and clamped, centred layout, mean feedback).
  The gateware uses two identities of it (checked by the model's tests): the instant of the leg
  at sorted position ``p`` telescopes to ``2 C_i = g2 NF + (2 - g2) max(T) + g2 min(T) - 2 T_i``
  (``g2 = 2 gamma``), so the un-permuted per-leg instants need only sort1's extremes; and
  ``q_i = floor(Q_i / 2**(B - b))`` with ``Q_i = floor(clamp(2 C_i + NF / S, 0, 2 NF) 2**B /
  (2 NF))``, a (B+1)-bit quotient by the constant ``2 NF`` (one restoring step per clock, all
  legs in parallel; for b < B its last B - b bits are forced to 0, which is the floor).
  The integrators then take ``U`` in units of ``FULL / 2**B``: ``U_i = (FULL / 2**B)
  (sum_k m_k - N m_i)``, ``m_i = q_i 2**(B - b)``; an MDFQM state's ``N h_i - k`` is scaled by
  ``2**B``. ``sum(U) == 0``, so ``sum(X) == 0`` stays exact; saturation (hold on leaving the
  ``x_width`` word) is unchanged; in the linear range ``|X_i| <= (N - 1) FULL / S``.
- ``L_b = resolution_latency(N, B) = 7 + depth(sort1) + ceil(log2 N) + B`` (20 for N = 3,
  B = 8; 21 for N = 5, B = 6): every stage of the quantiser is at most one carry chain, and
  the division takes one clock per quotient bit. The quantiser runs only for long updates.
- Short and long updates: an update is *short* if its mode is mdfqm and the previous update's
  mode was mdfqm (after reset the previous mode counts as mdfqm), else *long*. A short update is
  exactly the core's (latency ``L``, minimum period ``L``, sync threshold ``phase + 1 >= L``),
  so the generator with ``mode`` held at 0 is cycle-for-cycle the MDFQM core. A long update has
  latency ``L_b = resolution_latency(N, B)``; its minimum period is ``max(L_b, 2**b)``
  (b = 0 for an mdfqm update: ``L_b``), values below are used as that and flagged by
  ``period_clamped``; its sync threshold is ``phase + 1 >= L_b``.
- Presentation: the result of an update starting in cycle s (``h`` or the first slot of its
  layout, the integrators, ``saturated``, the ``update`` strobe) is visible in cycle
  ``s + L`` (short) or ``s + L_b`` (long). A layout of a gamma-mode update presented in cycle V
  with latched period P and ``S = 2**b`` has slots of ``l = floor(P / S)`` clocks (``P >= S`` by
  the clamp); slot ``j < S - 1`` covers cycles ``[V + j l, V + (j + 1) l)``, the last slot runs
  from ``V + (S - 1) l`` until the next presentation (it absorbs the ``P - S l`` remainder
  clocks; the feedback counts slots, so choose P a multiple of S for exactly equal slots). An
  MDFQM state is held until the next presentation.
- Switching modes (only ever at update boundaries, by the latch): a long update is presented
  ``L_b`` after its start, i.e. exactly when the previous layout has run its whole period, so no
  layout is cut short; going from mdfqm to a gamma mode the last MDFQM state is held
  ``L_b - L`` clocks longer; going back, the first mdfqm update (long) is presented at ``s + L_b``
  and the next (short) one at its ``s + L``, so that MDFQM state lasts ``P - (L_b - L) >= L``
  clocks. Outputs change only at presentations and slot boundaries. (A ``sync_in`` restart
  shortens the running layout like any period, as for the core.)
- Zero policy: ``h_prev`` is the last state of the previously presented update (its ``h`` for
  MDFQM, its last slot for a layout: the legs with ``q_i = 0``); 0 after reset. For the core this
  is the ``h`` register, as before.
"""

from __future__ import annotations

from dataclasses import dataclass

RULES = ("largest_duty", "exact_nearest")
ALL_OFF = 0
FEWEST_TRANSITIONS = 1
ZERO_POLICIES = (ALL_OFF, FEWEST_TRANSITIONS)

MIN_PHASES = 3
MAX_WIDTH = 32


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


def check_rule(phases: int, rule: str) -> str:
    """Refuse an unknown rule, or the largest-duty rule beyond LARGEST_DUTY_MAX_PHASES."""
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, not {rule!r}")
    if rule == "largest_duty" and phases > LARGEST_DUTY_MAX_PHASES:
        raise ValueError(
            f"rule 'largest_duty' is offered for at most {LARGEST_DUTY_MAX_PHASES} phases (its "
            f"integrators outgrow their bound beyond); use 'exact_nearest' for {phases} phases")
    return rule


def loop_latency(phases: int, rule: str = "largest_duty") -> int:
    """Clocks from an update start to its result: the minimum update period ``L``.

    1 (T = X + R) + depth(sort1) + 1 (duties or scores) + argmax stages + 1 (decode h)
    + 1 (feedback and integrator commit). Refuses what :func:`check_rule` refuses.
    """
    check_rule(phases, rule)
    return 1 + len(sorting_network(phases)) + 1 + argmax_stages(phases) + 1 + 1


#: generator modes, index = the ``mode`` input's code (see "b-bit pulse-width resolution")
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


def resolution_latency(phases: int, max_bits: int) -> int:
    """``L_b``: clocks from the start of a long update to its presentation.

    1 (T = X + R) + depth(sort1) + 1 (max + min) + 1 (zero split and offsets) + 1 (per-leg
    instants) + 1 (clamp, divider load) + max_bits (restoring division, one quotient bit a clock)
    + ceil(log2 N) (sums over the legs) + 1 (feedback) + 1 (integrator commit / presentation).
    """
    if isinstance(phases, bool) or not isinstance(phases, int) or phases < MIN_PHASES:
        raise ValueError(f"phases must be an integer >= {MIN_PHASES}, not {phases!r}")
    if isinstance(max_bits, bool) or not isinstance(max_bits, int) or max_bits < 1:
        raise ValueError(f"max_bits must be an integer >= 1, not {max_bits!r}")
    return 7 + len(sorting_network(phases)) + ceil_log2(phases) + max_bits


def latch_mode(mode: int, bits: int, max_bits: int) -> tuple[int, int, bool]:
    """The runtime clamp of the generator: ``(mode code, b, clamped)`` used for an update.

    Codes ``>= len(MODES)`` act as mdfqm (flagged); mdfqm uses b = 0 (``bits`` ignored, not
    flagged); a gamma mode uses ``min(max(bits, 1), max_bits)`` (flagged when that differs).
    """
    if not 0 <= mode < (1 << MODE_WIDTH) or not 0 <= bits < (1 << BITS_WIDTH):
        raise ValueError(f"mode must be a {MODE_WIDTH}-bit and bits a {BITS_WIDTH}-bit code, "
                         f"not {mode!r}, {bits!r}")
    if mode >= len(MODES):
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
