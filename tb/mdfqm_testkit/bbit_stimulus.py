"""Closed-loop stimulus for the gating-signal generator, shared by the per-cycle cocotb tests
(tb/test_bbit.py) and the vector-file run (tb/test_bbit_vectors.py).

As in core_stimulus: the stream source reacts to the model's ``ready`` like a real producer,
and every cycle's expected outputs come from :class:`mdfqm_model.clock.GeneratorModel`.
Scenarios:

- one per mode (``mdfqm``, ``svpwm``, ``dpwm0``, ``dpwm1``, ``dpwm``): that mode held, ``bits``
  moving among ``bits_choices`` at random cycles (taken at the next update start), periods at
  the minimum, at multiples of ``2**b`` and with remainder clocks, and at b = 1 or 2 now and
  then a long one (4096 to 8191 clocks: the slot length's high bits), OSR and zero policy
  moving;
- ``switch``: mode and bits (illegal codes included), period (below the minimum included), OSR,
  sync_in and resets all changing at random cycles;
- ``handover``: mdfqm and the gamma modes alternating every update or two, mostly small b (up
  to max_bits at times), mostly the fewest-transitions zero policy, small amplitudes: an MDFQM
  update right after a layout, whose zero state depends on the layout's last slot;
- ``overmod`` / ``extremes``: up to twice the linear range with common mode, and extreme codes,
  in random modes;
- ``limits``: every setting at its ends and at the values its clamp changes: period 0, 1, the
  minimum and now and then a long one up to 2**16 - 1 (2**16 - 1 itself in a slot mode at b = 1
  or 2); OSR 0, 1, 254, 255; mode 0-7 (5-7 illegal); bits 0, 1, max_bits, max_bits + 1, 15;
  extreme codes, codes on the b-bit grid (the quantiser's decision boundaries,
  :func:`grid_codes`) and overmodulation; in the second half sync pulses, now and then one
  aimed at a power of two of an update's phase (the largest inside it half the time), and no
  random one while it is due;
- ``boundaries``: short trials from reset, each a random mode and b at its shortest periods,
  every beat on the half-slot grid (:func:`boundary_codes`): from reset the integrators are
  empty, so the first update's instants sit exactly on the quantiser's decision boundaries
  and the duty sort's ties (a closed loop only wanders onto them now and then); svpwm (whose
  offset is the sector sum ``max + min``) twice as often as each other slot mode; 3 in 4
  slot-mode trials end with MDFQM updates (the fewest-transitions zero state after a layout);
  every other trial is a ``dpwm0`` one from :func:`first_slot_codes`, its b and leg in turn
  (a leg that turns on at the first slot boundary, which the layout decides at its load);
- :func:`generate_core`: core_stimulus's scenarios (the core's model, ``CoreModel``) with
  ``mode`` held at mdfqm and ``bits`` random: the generator must be the core, cycle for cycle.
"""

import math

from mdfqm_model.clock import GeneratorModel
from mdfqm_spec.contract import MODES, min_period
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
)
from mdfqm_testkit.harness import pack

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
#: chance of a reset, of a sync pulse in a clock, per scenario (``limits`` as in core_stimulus)
RESETS = {"switch": 0.0005}
SYNCS = {"switch": 0.02, "limits": 0.0005}
INPUTS = ("rst", "ref__valid", "ref__payload", "period", "osr", "zero_policy", "sync_in",
          "mode", "bits")


def grid_codes(rng, contract, phases, bits):
    """A beat on the ``b``-bit grid: the codes differ by whole steps of ``FULL >> b`` (give or
    take a code), around a random common mode. The differences set the slots, so the
    quantiser's remainders land at and next to its decision boundaries."""
    step = contract.full >> max(1, min(bits, contract.width - 2))
    base = rng.randint(-contract.full // 2, contract.full // 2)
    codes = [base + rng.randint(-(1 << bits), 1 << bits) * step + rng.choice([0, 0, 0, -1, 1])
             for _ in range(phases)]
    return [max(contract.code_min, min(contract.code_max, c)) for c in codes]


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


def _period_for(rng, model, mode, b):
    """A period for (mode, b): the minimum, a multiple of 2**b, or one with remainder clocks."""
    if mode == 0:
        return rng.choice([model.latency, model.latency, model.latency + 1,
                           2 * model.latency + 3])
    s = 1 << b
    low = min_period(True, b, model.latency, model.long_latency)
    choices = [low, s * max(1, -(-low // s)), low + rng.randint(1, max(1, s - 1))]
    if s < low:
        choices.append(low + s * rng.randint(0, 2))
    return rng.choice(choices)


def generate(rng, scenario, contract, rule, max_bits, cycles, bits_choices=(1, 3, 6),
             segment=1500):
    """Closed-loop stimulus for ``scenario``; returns (inputs per cycle, expected outputs per
    cycle, the model's trace of latched modes per cycle)."""
    if scenario not in SCENARIOS:
        raise ValueError(f"scenario must be one of {SCENARIOS}, not {scenario!r}")
    n = contract.phases
    model = GeneratorModel(n, contract.width, rule, max_bits)
    lin = linear_amplitude(n)
    mode = MODES.index(scenario) if scenario in MODES else 1
    bits = rng.choice(bits_choices)
    period = _period_for(rng, model, mode, bits)
    osr, policy = rng.choice([1, 2, 4]), rng.randint(0, 1)
    angle, step = rng.uniform(0, 2 * math.pi), rng.uniform(0.002, 0.05)
    amplitude, offset = 0.9 * lin, 0.0
    offered, longest, longest_osr, holding, sync_at = None, 0, 0, False, -1
    # boundaries: update starts left in a trial, counted once its first beat is taken
    starts_left, beat_taken, to_mdfqm, trials, first_slot = 0, False, False, 0, False
    next_change = rng.randint(1, segment)
    stim = {name: [] for name in INPUTS}
    expected = {name: [] for name in OUTPUTS}
    trace = {"mode": [], "long": [], "start": [], "update": [], "rst": []}
    for cycle in range(cycles):
        rst = 0
        if cycle == next_change:                    # runtime settings move, at random cycles
            next_change += rng.randint(segment // 3, segment)
            policy = rng.randint(0, 1)
            osr = rng.choice([1, 2, 4, 1])
            long_slots = False
            if scenario in MODES:
                bits = rng.choice(bits_choices)
                amplitude = rng.uniform(0.05, 1.0) * lin
                offset = rng.uniform(-0.3, 0.3)
                long_slots = mode != 0 and bits <= 2 and rng.random() < 0.3
            elif scenario in ("overmod", "extremes"):
                mode = rng.randint(0, len(MODES) - 1)
                bits = rng.choice(bits_choices)
                amplitude = rng.uniform(1.0, 2.0) * lin
                offset = rng.uniform(-0.5, 0.5)
            period = _period_for(rng, model, mode, bits)
            if long_slots:      # slots of 1k to 4k clocks: P's bit 12 set, its low bits seen
                period = rng.randint(LONG_SLOTS_PERIOD, 2 * LONG_SLOTS_PERIOD - 1)
            if scenario == "limits":
                mode = rng.choice([*range(len(MODES)), rng.randint(len(MODES), 7)])
                bits = rng.choice([0, 1, max_bits, max_bits + 1, 15, rng.choice(bits_choices)])
                if not holding:          # the largest period is held until an update takes it
                    period = limit_period(rng, model.long_latency,
                                          cycles - cycle - 2 * model.long_latency, longest)
                    if period != PERIOD_MAX and rng.random() < 0.5:
                        period = _period_for(rng, model, min(mode, len(MODES) - 1),
                                             min(max(bits, 1), max_bits))
                    longest, holding = max(longest, period), period == PERIOD_MAX
                if holding:      # the longest update in a slot mode at b = 1 or 2: its slots of
                    # 16k to 32k clocks set every bit of the slot length and its count-down
                    mode, bits = rng.randint(1, len(MODES) - 1), rng.choice([1, 2])
                osr = limit_osr(rng) if longest_osr == OSR_MAX else OSR_MAX   # the largest first
                longest_osr = max(longest_osr, osr)
                amplitude, offset = rng.uniform(0.0, 2.0) * lin, rng.uniform(-0.5, 0.5)
        if scenario == "switch" and rng.random() < 1 / 150:
            mode = rng.choice([0, 0, 1, 2, 3, 4, rng.randint(0, 7)])
            bits = rng.choice([*bits_choices, rng.randint(0, 15)])
            period = rng.choice([_period_for(rng, model, mode, min(max(bits, 1), max_bits)),
                                 rng.randint(0, 2 * model.long_latency), 0])
            osr = rng.choice([0, 1, 2, 4])
            amplitude = rng.uniform(0.05, 1.1) * lin
        if scenario == "handover" and rng.random() < 1 / (1.5 * model.long_latency):
            mode = rng.choice([0, 0, 0, 1, 2, 3, 4])
            bits = rng.choice([1, 1, 2, rng.randint(3, max_bits)])
            policy = int(rng.random() < 0.8)
            period = rng.choice([0, model.long_latency, model.long_latency + 3])
            amplitude = rng.uniform(0.0, 0.4) * lin
        if scenario in RESETS and rng.random() < RESETS[scenario]:
            rst = 1                                   # reset mid-run
        if to_mdfqm:      # an MDFQM update after the layout: its zero state follows the last slot's
            mode, policy, to_mdfqm = 0, 1, False
        if scenario == "boundaries" and starts_left == 0:
            rst, beat_taken, trials = 1, False, trials + 1       # a new trial from reset
            first_slot, turn = trials % 2 == 0, trials // 2
            starts_left = rng.randint(2, 3)
            mode = DPWM0 if first_slot else rng.choice([0, 1, 1, 1, 1, 2, 2, 3, 3, 4, 4])
            bits = (bits_choices[turn % len(bits_choices)] if first_slot
                    else rng.choice(bits_choices))
            period = _period_for(rng, model, mode, bits)
            osr, policy = 1, rng.randint(0, 1)
            leg = turn // len(bits_choices) % n
            offered = (first_slot_codes(rng, contract, n, bits, leg) if first_slot
                       else tie_codes(rng, contract, n) if mode == 0 and rule == "largest_duty"
                       else boundary_codes(rng, contract, n, bits))
        if offered is None and rng.random() < 0.7:    # idle gaps between beats
            angle += step
            pick = rng.random()
            if scenario == "boundaries":
                offered = boundary_codes(rng, contract, n, bits)
            elif scenario == "extremes" or (scenario == "limits" and pick < 0.3):
                offered = extreme_codes(rng, contract, n)
            elif scenario == "limits" and pick < 0.7:
                offered = grid_codes(rng, contract, n, max(bits, 1))
            else:
                offered = sine_codes(contract, amplitude, angle, offset)
        # limits: random syncs in the second half, none while an aimed one is due (it would
        # cut short the update it aims at)
        sync_in = int((scenario in SYNCS
                       and (scenario != "limits" or (cycles // 2 < cycle and sync_at < cycle))
                       and rng.random() < SYNCS[scenario]) or cycle == sync_at)
        valid = int(offered is not None)
        payload = offered or [0] * n
        trace["mode"].append(model.mode_lat)        # the registers visible in this cycle
        trace["long"].append(model.long_lat)
        out = model.step(rst=rst, ref_valid=valid, ref=payload, period=period, osr=osr,
                         zero_policy=policy, sync_in=sync_in, mode=mode, bits=bits)
        if valid and out["ref_ready"] and not rst:
            offered, beat_taken = None, True
        holding = holding and not out["start"]
        if out["start"] and not rst and beat_taken:
            starts_left = max(0, starts_left - 1)
            if (scenario == "boundaries" and starts_left == 1 and mode and not first_slot
                    and rng.random() < 0.75):
                to_mdfqm, starts_left = True, 2      # from the next clock: see above
        if scenario == "limits" and out["start"] and cycle > cycles // 2:
            sync_at = sync_delay(rng, cycle, model.p_lat)
        for name, value in (("rst", rst), ("ref__valid", valid),
                            ("ref__payload", pack(payload, contract.width)), ("period", period),
                            ("osr", osr), ("zero_policy", policy), ("sync_in", sync_in),
                            ("mode", mode), ("bits", bits)):
            stim[name].append(value)
        for port, key in OUTPUTS.items():
            expected[port].append(out[key])
        trace["start"].append(out["start"])
        trace["rst"].append(rst)
        trace["update"].append(out["update"])
    return stim, expected, trace


def generate_core(rng, scenario, contract, rule, cycles):
    """core_stimulus's scenario (expected outputs from the core's model) with ``mode`` held at
    mdfqm and ``bits`` random: what the generator must reproduce exactly."""
    stim, expected = core_stimulus.generate(rng, scenario, contract, rule, cycles)
    stim["mode"] = [0] * cycles
    stim["bits"] = [rng.randint(0, 15) for _ in range(cycles)]
    for name in ("mode_clamped", "mode_in_force", "bits_in_force"):
        expected[name] = [0] * cycles
    return stim, expected
