"""Closed-loop stimulus for the gating-signal generator, shared by the per-cycle cocotb tests
(tb/test_bbit.py), the vector-file runs (tb/test_bbit_vectors.py), the drop-in files' and
the netlists' runs and the mutation campaign.

As in core_stimulus, the stream source reacts to the model's ``ready`` like a real producer,
and every clock's expected outputs come from :class:`mdfqm_model.clock.GeneratorModel`. The
stimulus is the specification's rules as small named sequences (:class:`GeneratorSequence`,
see mdfqm_testkit.sequences): the b-bit generator's timing and clamps of docs/contract.md
("b-bit pulse-width resolution") and the rows of docs/robustness.md that its ports can break.
A scenario is a composition of those sequences run together by :class:`GeneratorRun`, which
hits their coverpoints from what the model shows in each clock:

- one per mode (``mdfqm``, ``svpwm``, ``dpwm0``, ``dpwm1``, ``dpwm``): that mode held
  (:class:`HeldMode`), b moving among ``bits_choices``, periods at the minimum, at multiples of
  ``2**b`` and with remainder clocks, and at b = 1 or 2 now and then slots of 2k to 4k clocks,
  OSR and zero policy moving;
- ``switch``: mode and b (illegal codes too), period (below the minimum too), OSR, sync pulses
  and resets all changing at random clocks (:class:`RandomSwitches`, :class:`SyncPulses`,
  :class:`Resets`);
- ``handover``: mdfqm and the slot modes alternating every update or two, mostly small b, the
  fewest-transitions zero policy, small amplitudes (:class:`Handover`);
- ``overmod`` / ``extremes``: up to twice the linear range with common mode, and extreme codes,
  in random modes (:class:`BeyondLinearRange`, :class:`ExtremeCodes`); in runs of 15,000 clocks
  or more, beats aimed so that an instant sits on or a step below its rounding point while a
  ``T`` lies beyond the integrators' range, below and above, for each zero split's offset;
- ``limits``: every setting at its ends and at the values its clamp changes
  (:class:`SettingsAtTheirLimits`: period 0, 1, the minimum and, where the run has room, one up
  to 2**16 - 1, held in a slot mode at b = 1 or 2; OSR 0, 1, 254, 255; mode 0-7, b 0, 1,
  max_bits, max_bits + 1, 15; extreme codes, codes on the b-bit grid), and sync pulses aimed at
  a power of two of an update's phase (:class:`SyncAtPowersOfTwo`, while no longest update is
  held);
- ``boundaries``: short trials from reset into empty integrators (:class:`FirstUpdateFromReset`):
  each mode at its shortest periods with every beat on the half-slot grid, ties for MDFQM, and
  ``dpwm0`` beats whose layout turns a chosen leg on at the first slot boundary;
- :func:`generate_core`: core_stimulus's scenarios (the core's model) with ``mode`` held at
  mdfqm and ``bits`` random: the generator must be the core, cycle for cycle.
"""

import math

from mdfqm_model.bbit import gamma2_for, rounding_numerators
from mdfqm_model.clock import GeneratorModel
from mdfqm_model.update import remove_common_mode, sort1
from mdfqm_spec.contract import MODES, latch_mode, min_period
from mdfqm_testkit import core_stimulus
from mdfqm_testkit.core_stimulus import (
    OSR_MAX,
    PERIOD_MAX,
    extreme_codes,
    limit_osr,
    limit_period,
    linear_amplitude,
    sine_codes,
    sync_delay,
    x_at_use,
)
from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.harness import pack
from mdfqm_testkit.sequences import Sequence, Waits, doc, robustness

#: port name -> model output name
OUTPUTS = {**core_stimulus.OUTPUTS, "mode_clamped": "mode_clamped",
           "mode_in_force": "mode_in_force", "bits_in_force": "bits_in_force"}
SCENARIOS = (*MODES, "switch", "handover", "overmod", "extremes", "limits", "boundaries")
#: clocks of a ``limits`` run with room for an update at the largest period (2**16 - 1)
LIMITS_CYCLES = 150_000
#: the mode of the ``boundaries`` scenario's first-slot trials
DPWM0 = MODES.index("dpwm0")
#: the shortest period of the mode scenarios' long slot-mode updates (at b = 1 or 2)
LONG_SLOTS_PERIOD = 4096
#: the run length from which the mode scenarios aim at long slots (two updates of up to 8191)
LONG_SLOTS_RUN = 20_000
INPUTS = ("rst", "ref__valid", "ref__payload", "period", "osr", "zero_policy", "sync_in",
          "mode", "bits")
CONTRACT_MD = "docs/contract.md"
RESOLUTION = doc(CONTRACT_MD, "b-bit pulse-width resolution: the gating-signal generator")
CORE_TIMING = doc(CONTRACT_MD, "Clock-level timing of the core (see `mdfqm_model.clock`)")


def grid_codes(rng, contract, phases, bits):
    """A beat on the ``b``-bit grid: the codes differ by whole steps of ``FULL >> b`` (give or
    take a code), around a random common mode. The differences set the slots, so the
    quantiser's remainders land at and next to its decision boundaries."""
    step = contract.full >> max(1, min(bits, contract.width - 2))
    base = rng.randint(-contract.full // 2, contract.full // 2)
    codes = [base + rng.randint(-(1 << bits), 1 << bits) * step + rng.choice([0, 0, 0, -1, 1])
             for _ in range(phases)]
    return [max(contract.code_min, min(contract.code_max, c)) for c in codes]


#: where an instant can sit against its rounding point (docs/contract.md, "b-bit pulse-width
#: resolution": an instant rounds half up to whole slots): a numerator ``2 C_j S + NF`` that
#: is a multiple of ``2 NF`` (exactly half-way, rounded up), or one at most ``2 N S`` below one
#: (a few of its smallest steps: rounded down); either inside the update (not clamped)
ROUNDING_PLACES = ("on it", "just below it")


def rounding_legs(t, mode: int, bits: int, contract) -> set[tuple[str, int]]:
    """``(place, leg)`` for each instant of a slot-mode update with ``T = t`` at one of the
    :data:`ROUNDING_PLACES` (the instant of sorted position p switches leg ``perm[p]``)."""
    rho, perm = sort1(t)
    slots, two_nf = 1 << bits, 2 * contract.unit
    found = set()
    numerators = rounding_numerators(rho, gamma2_for(MODES[mode], rho), slots, contract)
    for leg, numerator in zip(perm, numerators, strict=True):
        slot, rest = divmod(numerator, two_nf)
        if rest == 0 and 1 <= slot <= slots:
            found.add((ROUNDING_PLACES[0], leg))
        elif rest and 0 <= slot < slots and two_nf - rest <= 2 * contract.phases * slots:
            found.add((ROUNDING_PLACES[1], leg))
    return found


def rounding_places(t, mode: int, bits: int, contract) -> set[str]:
    """The :data:`ROUNDING_PLACES` the instants of a slot-mode update with ``T = t`` take."""
    return {place for place, _ in rounding_legs(t, mode, bits, contract)}


#: twice gamma -> the mode whose zero split it is: each measures the instants from its own
#: offset (docs/contract.md, "b-bit pulse-width resolution": ``2 C_i = g2 NF + (2 - g2)
#: max(T) + g2 min(T) - 2 T_i``, so ``2 max(T)`` for dpwm0, ``max(T) + min(T)`` for svpwm,
#: ``2 min(T)`` for dpwm1; dpwm takes the first or the last by its sector)
OFFSETS = {gamma2_for(mode, ()): mode for mode in ("dpwm0", "svpwm", "dpwm1")}
#: the sides of the integrators' range a leg's ``T = X + R`` can reach past (by up to R's
#: bound: docs/contract.md, "Integrator bound")
SIDES = ("below", "above")
#: (twice gamma, side, place) -> the bin of ``BeyondLinearRange.ROUNDING``
ROUNDING_BINS = {
    (g2, side, place): f"the {mode} offset, a T {side} the range, an instant {place}"
    for g2, mode in OFFSETS.items() for side in SIDES for place in ROUNDING_PLACES}


def sides_beyond(t, contract) -> set[str]:
    """The :data:`SIDES` of the integrators' ``x_width``-bit range some ``T_i`` lies beyond."""
    return {side for side, past in zip(SIDES, (min(t) < contract.x_min, max(t) > contract.x_max),
                                       strict=True) if past}


def rounding_beyond_codes(rng, contract, x, mode: int, bits: int, side: str, place: str,
                          tries: int):
    """A beat that, taken into the integrators ``x``, puts a leg's instant of a ``mode`` update
    at ``bits`` at ``place`` (of :data:`ROUNDING_PLACES`) against its rounding point while a
    leg's ``T`` lies beyond the integrators' range on ``side``; None if none of ``tries``
    random beats, each with one leg's code moved through a whole rounding period
    (``FULL >> b`` codes: its instant moves ``2 N`` per code against the others'), gets
    there."""
    n, lo, hi = contract.phases, contract.code_min, contract.code_max
    period = (contract.full >> bits) + 1
    for _ in range(tries):
        codes = [rng.choice((lo, hi, rng.randint(lo, hi))) for _ in range(n)]
        leg = rng.randrange(n)
        first = rng.randint(lo, hi - period)
        for code in range(first, first + period):
            codes[leg] = code
            t = [xi + ri for xi, ri in zip(x, remove_common_mode(codes, n), strict=True)]
            if side in sides_beyond(t, contract) and (
                    (place, leg) in rounding_legs(t, mode, bits, contract)):
                return codes
    return None


def boundary_codes(rng, contract, phases, bits):
    """A beat on the half-slot grid: one leg at a random code, every other leg a few half
    slots (``FULL >> (b + 1)``) above or below it, or anywhere on that grid now and then,
    give or take a code. From an empty integrator ``T_i - T_j = N (c_i - c_j)``, so the
    legs' rounded instants, measured from the clamped leg, land on the quantiser's decision
    boundaries (odd multiples), on the slot grid (even ones) and right next to both."""
    b = min(bits, contract.width - 2)
    step, spread = max(1, contract.full >> (b + 1)), 1 << (b + 1)
    base = rng.randint(contract.code_min // 2, contract.code_max // 2)
    side = rng.choice([-1, 1])                   # the first leg is the largest or the smallest
    codes = [base] + [base + side * (rng.randint(0, 2) if rng.random() < 0.8
                                     else rng.randint(-spread, spread)) * step
                      + rng.choice([-1, 0, 1]) for _ in range(phases - 1)]
    rng.shuffle(codes)
    return [max(contract.code_min, min(contract.code_max, c)) for c in codes]


def first_slot_codes(rng, contract, phases, bits, leg):
    """A beat whose ``dpwm0`` layout turns ``leg`` on at the first slot boundary: from an empty
    integrator leg i is off for ``round((c_max - c_i) S / FULL)`` slots at the start, so ``leg``
    sits 2 to 3 slots below the largest code (give or take a code) and the others anywhere
    below the largest, which is another leg's."""
    b = min(bits, contract.width - 2)
    half = max(1, contract.full >> (b + 1))
    top = rng.randint(contract.code_min + 8 * half, contract.code_max)
    largest = rng.choice([i for i in range(phases) if i != leg])
    codes = [top if i == largest
             else top - rng.choice([4, 5, 6]) * half + rng.choice([-1, 0, 1]) if i == leg
             else rng.randint(max(contract.code_min, top - contract.full), top)
             for i in range(phases)]
    return [max(contract.code_min, min(contract.code_max, c)) for c in codes]


def half_way_codes(rng, contract, phases, bits):
    """A beat whose ``svpwm`` instants, from an empty integrator, sit exactly half-way between
    two slot boundaries (the contract rounds them half up). From empty integrators
    ``rho_0 - rho_{N-1} = N (c_max - c_min)`` and ``2 C_1 = NF - N (c_max - c_min)``, so
    the instant ``2 C_1 S / (2 NF)`` is a whole number of slots and a half (``2 C_1 S`` an odd
    multiple of ``NF``) exactly when ``c_max - c_min`` is an odd multiple of ``FULL / S``; each
    later instant adds ``2 N`` times a gap, a whole number of slots when the gap is a multiple
    of ``FULL / S``. So: the smallest and the largest code an
    odd number of ``FULL / S`` apart, the others on that grid between them."""
    b = min(bits, contract.width - 2)
    unit = contract.full >> b
    span = unit * rng.randrange(1, max(2, min(1 << b, contract.full // unit)), 2)
    low = rng.randint(contract.code_min, contract.code_max - span)
    codes = [low, low + span] + [low + span - unit * rng.randint(0, span // unit)
                                 for _ in range(phases - 2)]
    rng.shuffle(codes)
    return codes


def tie_codes(rng, contract, phases):
    """A beat on which two ``largest_duty`` candidates tie for the largest (sort2's
    smallest-position rule decides). From an empty integrator, with ``g_j`` the gaps between
    the sorted codes: ``d_0 / N = FULL - sum g``, ``d_j / N = g_j``."""
    full = contract.full
    x = rng.randint(-(-full // phases), full // 2)          # the tied value, the largest
    first, second = sorted(rng.sample(range(phases), 2))     # the tied candidates
    gaps = [None] * (phases - 1)
    for j in (first, second):
        if j:
            gaps[j - 1] = x
    free = [k for k, g in enumerate(gaps) if g is None]
    # d_0 = x exactly when it ties, else at most x; every other gap at most x
    total = (full - 2 * x if first == 0
             else rng.randint(max(0, full - 3 * x), len(free) * x))
    for left, k in enumerate(free[::-1]):
        gaps[k] = total if left == len(free) - 1 else rng.randint(
            max(0, total - x * (len(free) - 1 - left)), min(x, total))
        total -= gaps[k]
    top = rng.randint(contract.code_min + sum(gaps), contract.code_max)
    codes = [top - sum(gaps[:k]) for k in range(phases)]
    rng.shuffle(codes)
    return codes


#: the period shapes of a slot mode's update (docs/contract.md: "choose P a multiple of S for
#: exactly equal slots"; the last slot absorbs the remainder)
SHAPES = ("at the minimum", "a multiple of 2**b", "with remainder clocks")


def _period_for(rng, model, mode, b, shape=None):
    """A period for (mode, b): the minimum, a multiple of 2**b, or one with remainder clocks
    (``shape``, one of :data:`SHAPES`, or any)."""
    if mode == 0:
        return rng.choice([model.latency, model.latency, model.latency + 1,
                           2 * model.latency + 3])
    s = 1 << b
    low = min_period(True, b, model.latency, model.long_latency)
    multiple = s * max(1, -(-low // s))
    remainder = low + rng.randint(1, max(1, s - 1))
    if remainder % s == 0:
        remainder += 1
    if shape is not None:
        return {"at the minimum": low, "a multiple of 2**b": multiple if multiple > low
                else multiple + s, "with remainder clocks": remainder}[shape]
    choices = [low, multiple, remainder]
    if s < low:
        choices.append(low + s * rng.randint(0, 2))
    return rng.choice(choices)


class GeneratorSequence(Sequence, family=True):
    """A sequence of the gating-signal generator (:class:`GeneratorRun`): it sets the runtime
    ports (``run.settings``), the stream (``run.stream``) and the ``rst`` / ``sync_in`` pins."""

    family = "generator"
    #: the scenarios it is part of
    SCENARIOS: tuple = ()


class Beats:
    """The reference stream: a beat held with its payload until accepted, idle clocks between
    (an FOC loop that honours ``ready``); ``kind`` the codes it offers."""

    def __init__(self, run):
        self.run, self.rng, self.contract = run, run.rng, run.contract
        self.kind = "sine"
        self.angle, self.step = self.rng.uniform(0, 2 * math.pi), self.rng.uniform(0.002, 0.05)
        self.amplitude, self.offset = 0.9 * run.linear, 0.0
        self.offered = None
        self.label = ""
        self.stalled = False        # no beat of its own (a sequence aims the next one)
        self.held = [0] * run.contract.phases   # the codes of kind "held"

    def offer(self, codes, label: str) -> None:
        self.offered, self.label = codes, label

    def decide(self) -> None:
        if self.stalled or self.offered is not None or self.rng.random() >= 0.7:  # idle gaps
            return
        rng, c, n = self.rng, self.contract, self.contract.phases
        self.angle += self.step
        kind = self.kind
        if kind == "limits":
            pick = rng.random()
            kind = "extreme" if pick < 0.3 else "grid" if pick < 0.7 else "sine"
        if kind == "extreme":
            codes = extreme_codes(rng, c, n)
        elif kind == "grid":
            codes = grid_codes(rng, c, n, max(self.run.settings["bits"], 1))
        elif kind == "boundary":
            codes = boundary_codes(rng, c, n, self.run.settings["bits"])
        elif kind == "held":
            codes = list(self.held)
        else:
            codes = sine_codes(c, self.amplitude, self.angle, self.offset)
        self.offer(codes, kind)


# ----------------------------------------------------------------------------- the sequences


class HeldMode(GeneratorSequence):
    """One mode held; every ``segment`` clocks or so b moves among the run's choices, the
    period to the mode's minimum, a multiple of 2**b or one with remainder clocks (at b = 1
    or 2 now and then slots of 2k to 4k clocks), OSR, zero policy, amplitude and common mode:
    each change taken at the next update start."""

    rules = (RESOLUTION, robustness("runtime changes of period / OSR / zero policy / mode"),
             doc(CONTRACT_MD, "Zero-state policy"))
    SCENARIOS = MODES
    POINT = "held mode: update taken"

    @classmethod
    def coverpoints(cls, run):
        if run.scenario == "mdfqm":
            shapes = ("at the minimum", "above the minimum")
        else:
            shapes = ("at the minimum", "a multiple of 2**b", "with remainder clocks")
            shapes += ("slots of 2k to 4k clocks",) if run.cycles >= LONG_SLOTS_RUN else ()
        bins = (*shapes, "zero policy 0", "zero policy 1")
        if run.scenario != "mdfqm":
            bins += tuple(f"b {b}" for b in run.bits_choices)
        return {cls.POINT: bins}

    def body(self):
        run, rng = self.run, self.rng
        mode = MODES.index(run.scenario)
        s = run.settings
        s["mode"] = mode
        while True:
            open_ = run.coverage.open_bins(self.POINT)
            bits = [int(b[2:]) for b in open_ if b.startswith("b ")]
            # slots of 2k to 4k clocks cost two updates of up to 8k clocks: once every b has
            # been in force
            long_slots = mode and run.cycles >= LONG_SLOTS_RUN and not bits and (
                "slots of 2k to 4k clocks" in open_ or rng.random() < 0.3)
            low_bits = [b for b in run.bits_choices if b <= 2]
            if long_slots and low_bits:
                s["bits"] = rng.choice(low_bits)
            else:
                s["bits"] = rng.choice(bits or list(run.bits_choices))
            s["policy"], s["osr"] = rng.randint(0, 1), rng.choice([1, 2, 4, 1])
            run.stream.amplitude = rng.uniform(0.05, 1.0) * run.linear
            run.stream.offset = rng.uniform(-0.3, 0.3)
            shapes = [x for x in SHAPES if x in open_]
            s["period"] = _period_for(rng, run.model, mode, s["bits"],
                                      rng.choice(shapes) if shapes else None)
            if long_slots and s["bits"] <= 2:       # slots of 2k to 4k clocks
                s["period"] = rng.randint(LONG_SLOTS_PERIOD, 2 * LONG_SLOTS_PERIOD - 1)
            if open_:           # a few updates of each setting while bins are open
                yield from run.updates(2 if long_slots else 3)
            else:
                yield from run.wait(rng.randint(run.segment // 3, run.segment))


class RandomSwitches(GeneratorSequence):
    """Mode and b (codes not built in and b out of range too), period (below the minimum and 0
    too), OSR (0 too) and amplitude changing at random clocks: each taken, clamped, at the
    next update start (mode_clamped, period_clamped for that update)."""

    rules = (robustness("illegal generator mode"),
             robustness("runtime changes of period / OSR / zero policy / mode"),
             robustness("update period below the loop latency"), robustness("OSR 0"))
    SCENARIOS = ("switch",)
    POINT = "switched settings taken at an update start"

    @classmethod
    def coverpoints(cls, run):
        bins = ["mode code not built in", "b 0 in a slot mode", "period below the minimum",
                "period 0", "OSR 0", *(f"mode {m}" for m in MODES)]
        if run.model.max_bits < 15:
            bins.append("b above max_bits in a slot mode")
        return {cls.POINT: tuple(bins)}

    def body(self):
        run, rng = self.run, self.rng
        s = run.settings
        while True:
            yield from run.until(lambda: rng.random() < 1 / 150, limit=run.cycles)
            s["mode"] = rng.choice([0, 0, 1, 2, 3, 4, rng.randint(0, 7)])
            s["bits"] = rng.choice([*run.bits_choices, rng.randint(0, 15)])
            open_ = run.coverage.open_bins(self.POINT)
            if open_ and rng.random() < 0.8:        # aim at a setting not taken yet
                pick = rng.choice(open_)
                if pick == "mode code not built in":
                    s["mode"] = rng.randint(len(MODES), 7)
                elif pick.startswith("mode "):
                    s["mode"] = MODES.index(pick[5:])
                elif pick.startswith("b "):
                    s["mode"] = rng.randint(1, len(MODES) - 1)
                    s["bits"] = 0 if pick.startswith("b 0") else rng.randint(
                        run.model.max_bits + 1, 15)
            legal_bits = min(max(s["bits"], 1), run.model.max_bits)
            s["period"] = rng.choice([_period_for(rng, run.model, min(s["mode"], 4), legal_bits),
                                      rng.randint(0, 2 * run.model.long_latency), 0])
            s["osr"] = rng.choice([0, 1, 2, 4])
            run.stream.amplitude = rng.uniform(0.05, 1.1) * run.linear


class SyncPulses(GeneratorSequence):
    """sync_in pulses at random clocks (one in ``rate``): ignored while the update in flight
    has not committed, else the next clock starts an update (a slot mode's threshold, its layout
    cut short)."""

    rules = (robustness("sync_in at any time"), CORE_TIMING)
    SCENARIOS = ("switch",)
    POINT = "sync pulse"
    RATE = 0.02

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("ignored: update in flight", "starts the next update",
                            "starts the next update in a slot mode")}

    def body(self):
        run, rng = self.run, self.rng
        while True:
            run.sync_in = int(rng.random() < self.RATE)
            yield


class Resets(GeneratorSequence):
    """A reset now and then, in the middle of an update or of a slot layout: every register
    to its reset value, the update in flight dropped."""

    rules = (robustness("reset in the middle of an update"),)
    SCENARIOS = ("switch",)
    POINT = "reset"
    RATE = 0.0005

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("in the middle of an update",)}

    def body(self):
        run, rng = self.run, self.rng
        while True:
            if run.coverage.is_open(self.POINT):     # the first one aimed inside an update
                yield from run.wait(rng.randint(200, 2000))
                yield from run.until(lambda: run.model.phase > 1, limit=PERIOD_MAX)
                run.rst = 1
            else:
                run.rst = int(rng.random() < self.RATE)
            yield


class Handover(GeneratorSequence):
    """MDFQM and the slot modes alternating every update or two, mostly small b, mostly the
    fewest-transitions zero policy, small amplitudes: an MDFQM update right after a layout
    (its zero state follows the layout's last slot, the update long), a layout right after
    MDFQM (the last MDFQM state held L_b - L clocks longer)."""

    rules = (RESOLUTION, doc(CONTRACT_MD, "Zero-state policy"))
    SCENARIOS = ("handover",)
    POINT = "mode handed over at an update start"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("MDFQM after a layout, fewest transitions",
                            "MDFQM after a layout, all-off", "a layout after MDFQM")}

    def body(self):
        run, rng = self.run, self.rng
        s, model = run.settings, run.model
        while True:
            yield from run.until(lambda: rng.random() < 1 / (1.5 * model.long_latency),
                                 limit=run.cycles)
            s["mode"] = rng.choice([0, 0, 0, 1, 2, 3, 4])
            s["bits"] = rng.choice([1, 1, 2, rng.randint(3, run.model.max_bits)])
            # mostly the fewest-transitions zero state, all-off while its bin is open
            open_ = run.coverage.open_bins(self.POINT)
            s["policy"] = int("MDFQM after a layout, all-off" not in open_
                              and rng.random() < 0.8)
            s["period"] = rng.choice([0, model.long_latency, model.long_latency + 3])
            run.stream.amplitude = rng.uniform(0.0, 0.4) * run.linear


class BeyondLinearRange(GeneratorSequence):
    """References up to twice the linear range with common mode, in random modes: the
    integrators hold instead of wrapping (saturated for that update). In a long run, once an
    update has saturated, beats aimed (from the model run ahead) so that a leg's instant sits
    exactly on its rounding point, or a step below it, while some leg's ``T`` lies beyond the
    integrators' range, below it and above it, for each zero split's offset: the quantiser
    rounds half up over ``T``'s whole width, where the extreme ``T`` is the dpwm0 or dpwm1
    offset's operand."""

    rules = (robustness("reference beyond the linear range"),
             robustness("common-mode offset on the reference"), RESOLUTION)
    SCENARIOS = ("overmod",)
    POINT = "update saturated"
    ROUNDING = "beyond the integrators' range: an instant at its rounding point"
    #: the run length from which the rounding point is aimed at (the cocotb run's)
    ROUNDING_RUN = 15_000
    #: beats an aim draws for a bin before it gives up (each tries a whole rounding period)
    TRIES = 100
    #: aims in a row between two changes of the random settings
    AIMS = 4
    #: updates a steer lets the integrators run back (each takes them up to ``(N - 1) FULL``
    #: nearer zero, from at most ``2**(x_width-1)``: docs/contract.md, "Integrator bound")
    RELEASE = 16
    #: updates a steer then lasts (each takes the integrators a quarter of ``N FULL`` or so
    #: further, to ``2**(x_width-1) >= 2 N FULL``)
    STEERING = 32

    @classmethod
    def coverpoints(cls, run):
        points = {cls.POINT: ("in MDFQM", "in a slot mode")}
        if run.cycles >= cls.ROUNDING_RUN:
            points[cls.ROUNDING] = tuple(ROUNDING_BINS.values())
        return points

    def body(self):
        run, rng = self.run, self.rng
        s = run.settings
        while True:
            for _ in range(self.AIMS):
                if run.model.saturated and run.coverage.is_open(self.ROUNDING):
                    yield from self.aim_at_rounding()
            open_ = run.coverage.open_bins(self.POINT)
            s["mode"] = (0 if open_ == ["in MDFQM"] else rng.randint(1, len(MODES) - 1)
                         if open_ == ["in a slot mode"] else rng.randint(0, len(MODES) - 1))
            s["bits"] = rng.choice(run.bits_choices)
            s["period"] = _period_for(rng, run.model, s["mode"], s["bits"])
            s["policy"], s["osr"] = rng.randint(0, 1), rng.choice([1, 2, 4, 1])
            deep = run.coverage.is_open(self.POINT)        # far out until both saturated
            run.stream.amplitude = rng.uniform(1.5 if deep else 1.0, 2.0) * run.linear
            run.stream.offset = rng.uniform(-0.5, 0.5)
            if run.coverage.is_open(self.ROUNDING):     # back to the aims soon
                yield from run.updates(2)
            else:
                yield from run.pace(self.POINT)

    def aim_at_rounding(self):
        """One beat aimed at an open bin of :attr:`ROUNDING`: the stream stalled until the
        model is ready with nothing offered, then, for each open bin in random order, the mode
        of its offset at the finest b and a beat searched for the integrators the model shows
        at the update that takes it; the first beat found is offered (a bin's side may be out
        of reach from those integrators) until the update that takes it starts. None found,
        the integrators are steered towards the side of an open bin."""
        run, rng, model = self.run, self.rng, self.run.model
        s, bits = run.settings, model.max_bits
        run.stream.stalled = True
        ready = yield from run.until(lambda: model.ref_ready and run.stream.offered is None,
                                     limit=PERIOD_MAX)
        aims = [key for key in ROUNDING_BINS
                if ready and ROUNDING_BINS[key] in run.coverage.open_bins(self.ROUNDING)]
        rng.shuffle(aims)
        for g2, side, place in aims:
            mode = MODES.index(OFFSETS[g2])
            s.update(mode=mode, bits=bits, osr=1,
                     period=_period_for(rng, model, mode, bits, "at the minimum"))
            x = x_at_use(model, [0] * run.contract.phases,
                         {"period": s["period"], "osr": s["osr"], "zero_policy": s["policy"],
                          "mode": mode, "bits": bits})
            codes = None if x is None else rounding_beyond_codes(
                rng, run.contract, x, mode, bits, side, place, self.TRIES)
            if codes is not None:
                run.stream.offer(codes, "beyond")
                break
        else:
            if aims:
                yield from self.steer(aims[0][1])
                return
        yield
        run.stream.stalled = False
        yield from run.updates(1)

    def steer(self, side: str):
        """MDFQM updates at the shortest period, first on equal codes (``R = 0``: the
        integrators, held at their bound, run back towards zero), then on a beat held just
        beyond the linear range (a quarter of FULL), two legs at one end of the code range and
        the others a step of ``5/4 FULL`` from them: the integrators creep to their bound
        along that direction, the two legs together. Two legs below and the others at the
        bound above (``side`` "below") is where a ``T`` below the range can sit next to
        another leg's instant still inside the update (their ``T`` within ``NF`` of each
        other), and the other way round for "above"."""
        run, rng, c = self.run, self.rng, self.run.contract
        n, step = c.phases, c.full + c.full // 4
        pair = rng.sample(range(n), 2)
        low = c.code_min if side == "below" else c.code_max - step
        codes = [low + (0 if (i in pair) == (side == "below") else step) for i in range(n)]
        run.settings.update(mode=0, osr=1, period=run.model.latency)
        run.stream.stalled = False
        for held, updates in (([low] * n, self.RELEASE), (codes, self.STEERING)):
            run.stream.held, run.stream.kind = held, "held"
            yield from run.updates(updates)
        run.stream.kind = "sine"


class ExtremeCodes(GeneratorSequence):
    """Beats of the most negative and most positive codes (and the middle of the range), in
    random modes."""

    rules = (robustness("extreme codes"), robustness("equal references (ties)"))
    SCENARIOS = ("extremes",)
    POINT = "extreme beat taken"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("in MDFQM", "in a slot mode")}

    def body(self):
        run, rng = self.run, self.rng
        s = run.settings
        run.stream.kind = "extreme"
        while True:
            open_ = run.coverage.open_bins(self.POINT)
            s["mode"] = (0 if open_ == ["in MDFQM"] else rng.randint(1, len(MODES) - 1)
                         if open_ == ["in a slot mode"] else rng.randint(0, len(MODES) - 1))
            s["bits"] = rng.choice(run.bits_choices)
            s["period"] = _period_for(rng, run.model, s["mode"], s["bits"])
            s["policy"], s["osr"] = rng.randint(0, 1), rng.choice([1, 2, 4, 1])
            yield from run.pace(self.POINT)


class SettingsAtTheirLimits(GeneratorSequence):
    """Every setting at its ends and at the values its clamp changes: period 0, 1, the minimum,
    a long one and, where the run has room, 2**16 - 1 held in a slot mode at b = 1 or 2 until
    an update takes it (the largest first); OSR 255 first, then 0, 1, 2, 254, a power of two;
    mode 0-7, b 0, 1, max_bits, max_bits + 1, 15; beats of extreme codes, on the b-bit grid
    (the quantiser's decision boundaries), in overmodulation."""

    rules = (robustness("update period below the loop latency"), robustness("OSR 0"),
             robustness("illegal generator mode"), RESOLUTION)
    SCENARIOS = ("limits",)
    POINT = "setting at its limit taken at an update start"

    @classmethod
    def coverpoints(cls, run):
        bins = ["period 0", "period 1", "OSR 0", "OSR 255", "mode code not built in", "b 0",
                "b max_bits", "b 15", "a beat on the b-bit grid"]
        if run.cycles - 2 * run.model.long_latency > PERIOD_MAX + 4 * run.model.long_latency:
            bins.append("period 65535 in a slot mode")
        return {cls.POINT: tuple(bins)}

    def body(self):
        run, rng = self.run, self.rng
        s, model = run.settings, run.model
        run.stream.kind = "limits"
        longest = longest_osr = 0
        while True:
            open_ = run.coverage.open_bins(self.POINT)
            s["policy"] = rng.randint(0, 1)
            s["mode"] = rng.choice([*range(len(MODES)), rng.randint(len(MODES), 7)])
            s["bits"] = rng.choice([0, 1, model.max_bits, model.max_bits + 1, 15,
                                    rng.choice(run.bits_choices)])
            if "mode code not built in" in open_:
                s["mode"] = rng.randint(len(MODES), 7)
            for value in (0, model.max_bits, 15):
                if f"b {'max_bits' if value == model.max_bits else value}" in open_:
                    s["bits"] = value
                    if s["mode"] == 0 or s["mode"] >= len(MODES):
                        s["mode"] = rng.randint(1, len(MODES) - 1)
                    break
            run.stream.kind = "grid" if "a beat on the b-bit grid" in open_ else "limits"
            # the long periods once the short settings are all taken (a long update would
            # use up a short run)
            short_first = any(b != "period 65535 in a slot mode" for b in open_)
            if not run.holding:      # the largest period is held until an update takes it
                room = run.cycles - run.cycle - 2 * model.long_latency
                short = 4 * model.long_latency
                if SyncAtPowersOfTwo.LONG_BIN in run.coverage.open_bins(
                        SyncAtPowersOfTwo.POINT):   # updates with a phase of 256 and more
                    short = max(short, 4 * SyncAtPowersOfTwo.LONG_PHASE)
                s["period"] = limit_period(rng, model.long_latency,
                                           min(room, short) if short_first else room, longest)
                if s["period"] != PERIOD_MAX and rng.random() < 0.5:
                    s["period"] = _period_for(rng, model, min(s["mode"], len(MODES) - 1),
                                              min(max(s["bits"], 1), model.max_bits))
                for value in (0, 1):     # an open bin's period is the one taken
                    if f"period {value}" in open_ and s["period"] != PERIOD_MAX:
                        s["period"] = value
                longest = max(longest, s["period"])
                run.holding = s["period"] == PERIOD_MAX
            if run.holding:      # the longest update in a slot mode at b = 1 or 2: slots of
                # 16k to 32k clocks
                s["mode"], s["bits"] = rng.randint(1, len(MODES) - 1), rng.choice([1, 2])
            s["osr"] = limit_osr(rng) if longest_osr == OSR_MAX else OSR_MAX   # the largest first
            if longest_osr == OSR_MAX and "OSR 0" in open_:
                s["osr"] = 0
            longest_osr = max(longest_osr, s["osr"])
            run.stream.amplitude = rng.uniform(0.0, 2.0) * run.linear
            run.stream.offset = rng.uniform(-0.5, 0.5)
            yield from run.pace(self.POINT)


class SyncAtPowersOfTwo(GeneratorSequence):
    """Sync pulses now and then, and one aimed at a power of two of an update's phase (the
    largest inside it half the time), give or take a few clocks; none while the longest
    update is held (it would be cut short) and no random one while an aimed one is due."""

    rules = (robustness("sync_in at any time"), CORE_TIMING)
    SCENARIOS = ("limits",)
    POINT = "sync pulse at an update's phase"
    #: the phase from which the update counter's high bits decide whether a sync restarts
    LONG_PHASE = 256
    LONG_BIN = f"a power of two of {LONG_PHASE} or more"

    @classmethod
    def coverpoints(cls, run):
        bins = ("ignored: update in flight", "starts the next update")
        if run.cycles >= LONG_SLOTS_RUN:        # room for updates of 256 clocks and more
            bins += (cls.LONG_BIN,)
        return {cls.POINT: bins}

    def body(self):
        run, rng = self.run, self.rng
        due = -1
        while True:
            quiet = run.holding or due >= run.cycle
            run.sync_in = int(run.cycle == due or (not quiet and rng.random() < 0.0005))
            if run.model.phase == 0 and not run.holding:
                due = sync_delay(rng, run.cycle, run.model.p_lat)
                if "ignored: update in flight" in run.coverage.open_bins(self.POINT):
                    due = run.cycle + rng.randint(1, run.model.latency - 2)   # not committed
                run.aimed_sync = due
            yield


#: the coverage bin of a first update whose svpwm instants sit half-way between slots
HALF_WAY = "svpwm instants half-way between slots"


class FirstUpdateFromReset(GeneratorSequence):
    """Short trials from reset: from empty integrators the first update's instants sit
    exactly on the quantiser's decision boundaries (every beat on the half-slot grid; every
    other svpwm beat with each instant exactly half-way between slots, where the rounding goes
    up) and the duty sort's ties; each mode at its shortest periods (svpwm twice as often), 3 in 4
    slot-mode trials ending with MDFQM updates (the fewest-transitions zero state after a
    layout); every other trial a dpwm0 one whose beat turns a chosen leg on at the first slot
    boundary (its b and leg in turn); MDFQM trials on a beat whose largest candidates tie."""

    rules = (RESOLUTION, robustness("equal references (ties)"),
             robustness("reset in the middle of an update"))
    SCENARIOS = ("boundaries",)
    POINT = "trial from reset"

    @classmethod
    def coverpoints(cls, run):
        bins = [f"first beat into {m}" for m in MODES]
        bins += [f"dpwm0 leg {leg} on at the first slot boundary"
                 for leg in range(min(run.contract.phases, run.cycles // 1500))]
        bins += ["MDFQM after the layout", HALF_WAY]
        return {cls.POINT: tuple(bins)}

    def body(self):
        run, rng = self.run, self.rng
        s, model, c = run.settings, run.model, run.contract
        trials = 0
        while True:
            trials += 1
            first_slot, turn = trials % 2 == 0, trials // 2
            tried = [m for m in MODES if f"first beat into {m}" in
                     run.coverage.open_bins(self.POINT)]
            mode = DPWM0 if first_slot else MODES.index(rng.choice(tried)) if tried else (
                rng.choice([0, 1, 1, 1, 1, 2, 2, 3, 3, 4, 4]))
            svpwm = MODES.index("svpwm")
            half_open = HALF_WAY in run.coverage.open_bins(self.POINT)
            if half_open and not first_slot and not tried:
                mode = svpwm        # the half-way trial aimed while its bin is open
            half_way = mode == svpwm and (half_open or rng.random() < 0.5)
            bits = (run.bits_choices[turn % len(run.bits_choices)] if first_slot
                    else rng.choice(run.bits_choices))
            s.update(mode=mode, bits=bits, period=_period_for(rng, model, mode, bits), osr=1,
                     policy=rng.randint(0, 1))
            run.stream.kind = "boundary"
            legs = [int(b.split()[2]) for b in run.coverage.open_bins(self.POINT)
                    if b.startswith("dpwm0 leg")]
            leg = legs[0] if legs else turn // len(run.bits_choices) % c.phases
            run.rst = 1
            run.trial = ("first slot", leg) if first_slot else ("mode", mode)
            run.trial = ("half way", mode) if half_way else run.trial
            run.stream.offer(first_slot_codes(rng, c, c.phases, bits, leg) if first_slot
                             else tie_codes(rng, c, c.phases)
                             if mode == 0 and model.rule == "largest_duty"
                             else half_way_codes(rng, c, c.phases, bits) if half_way
                             else boundary_codes(rng, c, c.phases, bits), "first")
            yield
            starts = rng.randint(2, 3)
            taken = yield from run.until(lambda: run.beats_taken > 0, limit=4 * PERIOD_MAX)
            if taken:
                yield from run.updates(starts - (1 if mode and not first_slot else 0))
            if mode and not first_slot and rng.random() < 0.75:
                s["mode"], s["policy"] = 0, 1     # the MDFQM update after the layout
                yield from run.updates(2)


class StreamHonoursReady(GeneratorSequence):
    """The reference stream of every scenario: a beat offered with idle gaps, held with its
    payload while ``ready`` is low (one beat pending), taken once ready."""

    rules = (robustness("a reference beat while one is pending"),)
    SCENARIOS = SCENARIOS
    POINT = "reference beat"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("held while ready is low", "taken")}

    def body(self):
        while True:
            self.run.stream.decide()
            yield


class GeneratorRun(Waits):
    """One scenario of the generator: the model, the runtime ports, the stream, the pins, the
    scenario's sequences and the coverage (see the module docstring)."""

    def __init__(self, rng, scenario, contract, rule, max_bits, cycles, bits_choices, segment,
                 coverage=None):
        if scenario not in SCENARIOS:
            raise ValueError(f"scenario must be one of {SCENARIOS}, not {scenario!r}")
        self.rng, self.scenario, self.contract = rng, scenario, contract
        self.cycles, self.bits_choices, self.segment = cycles, tuple(bits_choices), segment
        self.model = GeneratorModel(contract.phases, contract.width, rule, max_bits)
        self.linear = linear_amplitude(contract.phases)
        mode = MODES.index(scenario) if scenario in MODES else 1
        bits = rng.choice(self.bits_choices)
        self.settings = {"period": _period_for(rng, self.model, mode, bits), "mode": mode,
                         "bits": bits, "osr": rng.choice([1, 2, 4]),
                         "policy": rng.randint(0, 1)}
        self.stream = Beats(self)
        self.rst = self.sync_in = 0
        self.cycle = self.starts = self.beats_taken = 0
        self.holding = False           # the largest period held until an update takes it
        self.aimed_sync = -1
        self.trial = None
        self.first_layout = False      # a first-slot trial's layout not presented yet
        self.coverage = Coverage() if coverage is None else coverage
        self.sequences = [s(self) for s in GeneratorSequence.registry if scenario in s.SCENARIOS]
        for sequence in self.sequences:
            for point, bins in sequence.coverpoints(self).items():
                self.coverage.want(point, bins, sequence.key())
        self.bodies = [s.body() for s in self.sequences]

    # --------------------------------------------------------------- what sequences use
    def updates(self, n: int):
        """Wait until ``n`` more update starts have passed."""
        target = self.starts + n
        yield from self.until(lambda: self.starts >= target, limit=4 * PERIOD_MAX)

    def pace(self, point: str):
        """The wait before the next change of the settings: two updates while ``point`` has
        bins open (each change taken and played), else a third of a segment to a segment."""
        if self.coverage.is_open(point):
            yield from self.updates(2)
        else:
            yield from self.wait(self.rng.randint(self.segment // 3, self.segment))

    def hit(self, point, bin_):
        self.coverage.hit(point, bin_)

    # ---------------------------------------------------------------------- one clock
    def generate(self):
        stim = {name: [] for name in INPUTS}
        expected = {name: [] for name in OUTPUTS}
        trace = {"mode": [], "long": [], "start": [], "update": [], "rst": []}
        model, s = self.model, self.settings
        for _ in range(self.cycles):
            self.rst = self.sync_in = 0
            for body in self.bodies:
                next(body)
            offered = self.stream.offered
            valid = int(offered is not None)
            payload = offered or [0] * self.contract.phases
            start = model.phase == 0
            self._before(valid, start)
            trace["mode"].append(model.mode_lat)     # the registers visible in this clock
            trace["long"].append(model.long_lat)
            out = model.step(rst=self.rst, ref_valid=valid, ref=payload, period=s["period"],
                             osr=s["osr"], zero_policy=s["policy"], sync_in=self.sync_in,
                             mode=s["mode"], bits=s["bits"])
            if valid and out["ref_ready"] and not self.rst:
                self.stream.offered = None
                self.beats_taken += 1
            if self.rst:
                self.beats_taken, self.first_layout = 0, False
            self.holding = self.holding and not out["start"]
            if out["start"] and not self.rst:
                self.starts += 1
                self._update_started()
            self._after()
            for name, value in (("rst", self.rst), ("ref__valid", valid),
                                ("ref__payload", pack(payload, self.contract.width)),
                                ("period", s["period"]), ("osr", s["osr"]),
                                ("zero_policy", s["policy"]), ("sync_in", self.sync_in),
                                ("mode", s["mode"]), ("bits", s["bits"])):
                stim[name].append(value)
            for port, key in OUTPUTS.items():
                expected[port].append(out[key])
            trace["start"].append(out["start"])
            trace["rst"].append(self.rst)
            trace["update"].append(out["update"])
            self.cycle += 1
        return stim, expected, trace

    # ------------------------------------------------------------------------ coverage
    def _before(self, valid, start) -> None:
        """What the registers of this clock and its inputs show."""
        m = self.model
        if valid and not m.ref_ready:
            self.hit(StreamHonoursReady.POINT, "held while ready is low")
        elif valid and not self.rst:
            self.hit(StreamHonoursReady.POINT, "taken")
            self._beat()
        if self.rst:
            if not start:
                self.hit(Resets.POINT, "in the middle of an update")
            return
        if self.sync_in:
            threshold = m.long_latency if m.long_lat else m.latency
            restarts = not start and m.phase + 1 >= threshold
            self.hit(SyncPulses.POINT, "starts the next update" if restarts
                     else "ignored: update in flight")
            if restarts and m.mode_lat:
                self.hit(SyncPulses.POINT, "starts the next update in a slot mode")
            self.hit(SyncAtPowersOfTwo.POINT, "starts the next update" if restarts
                     else "ignored: update in flight")
            if self.cycle == self.aimed_sync and m.p_lat >= SyncAtPowersOfTwo.LONG_PHASE:
                self.hit(SyncAtPowersOfTwo.POINT, SyncAtPowersOfTwo.LONG_BIN)
        if start:
            self._start()

    def _start(self) -> None:
        """The update start of this clock: what it takes, clamped (docs/contract.md)."""
        m, s = self.model, self.settings
        mode, b, _ = latch_mode(s["mode"], s["bits"], m.max_bits)
        long = bool(mode or m.prev_bbit)
        low = min_period(long, b, m.latency, m.long_latency)
        period = max(s["period"], low)
        point = HeldMode.POINT
        if not mode:
            self.hit(point, "at the minimum" if period == low else "above the minimum")
        elif period == low:
            self.hit(point, "at the minimum")
        elif period % (1 << b) == 0:
            self.hit(point, "a multiple of 2**b")
        else:
            self.hit(point, "with remainder clocks")
        if mode and b <= 2 and period >= LONG_SLOTS_PERIOD:
            self.hit(point, "slots of 2k to 4k clocks")
        self.hit(point, f"zero policy {s['policy']}")
        if mode:
            self.hit(point, f"b {b}")
        switched = RandomSwitches.POINT
        if s["mode"] >= len(MODES):
            self.hit(switched, "mode code not built in")
            self.hit(SettingsAtTheirLimits.POINT, "mode code not built in")
        elif s["mode"]:
            if s["bits"] == 0:
                self.hit(switched, "b 0 in a slot mode")
            elif s["bits"] > m.max_bits:
                self.hit(switched, "b above max_bits in a slot mode")
        self.hit(switched, f"mode {MODES[mode]}")
        if s["period"] < low:
            self.hit(switched, "period below the minimum")
        if s["period"] == 0:
            self.hit(switched, "period 0")
        if s["osr"] == 0:
            self.hit(switched, "OSR 0")
        limits = SettingsAtTheirLimits.POINT
        for name, hit in (("period 0", s["period"] == 0), ("period 1", s["period"] == 1),
                          ("OSR 0", s["osr"] == 0), ("OSR 255", s["osr"] == OSR_MAX),
                          ("b 0", s["bits"] == 0), ("b max_bits", s["bits"] == m.max_bits),
                          ("b 15", s["bits"] == 15),
                          ("period 65535 in a slot mode", s["period"] == PERIOD_MAX and mode)):
            if hit:
                self.hit(limits, name)
        handover = Handover.POINT
        if mode == 0 and m.prev_bbit:
            self.hit(handover, "MDFQM after a layout, fewest transitions" if s["policy"]
                     else "MDFQM after a layout, all-off")
            if self.trial and self.trial[0] != "first slot":
                self.hit(FirstUpdateFromReset.POINT, "MDFQM after the layout")
        if mode and not m.prev_bbit and m.mode_lat == 0:
            self.hit(handover, "a layout after MDFQM")

    def _beat(self) -> None:
        """What a beat taken in this clock is."""
        m = self.model
        if self.stream.label == "grid":
            self.hit(SettingsAtTheirLimits.POINT, "a beat on the b-bit grid")
        if self.stream.label == "extreme":
            self.hit(ExtremeCodes.POINT, "in a slot mode" if m.mode_lat else "in MDFQM")
        if self.stream.label == "first" and self.trial is not None and not any(m.x):
            kind, which = self.trial
            self.hit(FirstUpdateFromReset.POINT,
                     f"first beat into {MODES[which] if kind != 'first slot' else 'dpwm0'}")
            if kind == "half way":
                self.hit(FirstUpdateFromReset.POINT, HALF_WAY)
            self.first_layout = kind == "first slot"

    def _update_started(self) -> None:
        """What the update started in this clock takes: an instant at its rounding point (on
        it or a step below) while a ``T`` lies beyond the integrators' range."""
        if BeyondLinearRange.ROUNDING not in self.coverage.goals:
            return
        _, x, r, _, (mode, bits, _) = self.model.inflight
        if not mode:
            return
        t = [xi + ri for xi, ri in zip(x, r, strict=True)]
        sides = sides_beyond(t, self.contract)
        places = rounding_places(t, mode, bits, self.contract) if sides else ()
        if places:
            g2 = gamma2_for(MODES[mode], sort1(t)[0])
            for side in sides:
                for place in places:
                    self.hit(BeyondLinearRange.ROUNDING, ROUNDING_BINS[g2, side, place])

    def _after(self) -> None:
        """What the clock presented: a saturated update, the first layout of a trial."""
        m = self.model
        if not m.update:
            return
        if m.saturated:
            self.hit(BeyondLinearRange.POINT, "in a slot mode" if m.mode_lat else "in MDFQM")
        if self.first_layout and m.mode_lat == DPWM0 and len(m.slots) > 1:
            leg = self.trial[1]
            if not (m.slots[0] >> leg) & 1 and (m.slots[1] >> leg) & 1:
                self.hit(FirstUpdateFromReset.POINT,
                         f"dpwm0 leg {leg} on at the first slot boundary")
                self.first_layout = False


def generate(rng, scenario, contract, rule, max_bits, cycles, bits_choices=(1, 3, 6),
             segment=1500, coverage=None):
    """Closed-loop stimulus for ``scenario``; returns (inputs per cycle, expected outputs per
    cycle, the model's trace of latched modes per cycle). ``coverage``, a
    :class:`~mdfqm_testkit.coverage.Coverage` if given, receives the scenario's goals and
    hits (the caller asserts what it needs)."""
    run = GeneratorRun(rng, scenario, contract, rule, max_bits, cycles, bits_choices, segment,
                       coverage)
    return run.generate()


def generate_core(rng, scenario, contract, rule, cycles):
    """core_stimulus's scenario (expected outputs from the core's model) with ``mode`` held at
    mdfqm and ``bits`` random: what the generator must reproduce exactly."""
    stim, expected = core_stimulus.generate(rng, scenario, contract, rule, cycles)
    stim["mode"] = [0] * cycles
    stim["bits"] = [rng.randint(0, 15) for _ in range(cycles)]
    for name in ("mode_clamped", "mode_in_force", "bits_in_force"):
        expected[name] = [0] * cycles
    return stim, expected
