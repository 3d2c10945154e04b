"""Closed-loop stimulus for the whole core, shared by the per-cycle cocotb tests
(tb/test_core.py) and the vector-file regression and soak (tb/test_core_vectors.py, tb/soak.py).

The stream source reacts to the model's ``ready`` like a real producer (it holds valid and
payload until accepted and idles at random); because every cycle's ``ready`` is also compared
with the gateware's, the gateware sees exactly this stimulus.
"""

import copy
import math

from mdfqm_model.clock import CoreModel
from mdfqm_model.update import candidates, remove_common_mode, sort1
from mdfqm_testkit.harness import pack

#: every scenario generate() knows
SCENARIOS = ("sine", "overmod", "runtime", "ties", "extremes", "limits")
#: the largest value of each runtime setting port (their widths in the contract)
PERIOD_MAX, OSR_MAX = (1 << 16) - 1, (1 << 8) - 1
#: chance of a reset, of a sync pulse in a clock, per scenario; ``limits``: no reset (it would cut
#: its long updates short), syncs in its second half only (the longest update has run by then:
#: the syncs restart long updates at any phase), and there one aimed at each power of two of the
#: phase (:data:`SYNC_POINT`), none at random while an aimed one is due
RESETS = {"runtime": 0.002}
SYNCS = {"runtime": 0.05, "limits": 0.0005}

OUTPUTS = {"ref__ready": "ref_ready", "start": "start", "h": "h", "update": "update",
           "sample": "sample", "saturated": "saturated", "period_clamped": "period_clamped",
           "elapsed": "elapsed"}


def sine_codes(contract, amplitude, angle, offset=0):
    """Phase references of a balanced N-phase sine, ``amplitude`` in Vdc, plus a common mode."""
    n = contract.phases
    codes = []
    for i in range(n):
        value = amplitude * math.cos(angle - 2 * math.pi * i / n) + offset
        codes.append(max(contract.code_min,
                         min(contract.code_max, round(value * contract.full))))
    return codes


def extreme_codes(rng, contract, phases):
    """A beat of the codes at and around the ends and the middle of the range."""
    return [rng.choice([contract.code_min, contract.code_max, 0, -1, 1]) for _ in range(phases)]


def limit_period(rng, latency, room, longest_yet=0):
    """A period of the ``limits`` scenario: 0, 1 and around the latency (the clamp's edge), and
    now and then a long one, up to ``PERIOD_MAX``, when the run has ``room`` clocks left for it
    to end in (every bit of the update's count-down set at some time). ``PERIOD_MAX`` itself
    once the run is a quarter through, if ``longest_yet`` is below it and there is room."""
    if longest_yet < PERIOD_MAX and PERIOD_MAX + 4 * latency < room < 3 * PERIOD_MAX:
        return PERIOD_MAX
    if room > 4 * latency and rng.random() < 0.2:
        longest = min(PERIOD_MAX, room)
        return rng.choice([longest, rng.randint(longest // 2, longest),
                           (1 << rng.randint(2, longest.bit_length() - 1)) + rng.randint(0, 2)])
    return rng.choice([0, 1, latency - 1, latency, latency + 1, 2 * latency + 3])


def sync_delay(rng, start, period=None):
    """The clock of the sync pulse the ``limits`` scenario aims into the update that starts at
    ``start`` (-1: none): at a power of two of its phase, give or take a few clocks (a stuck or
    inverted bit of the phase counter changes whether the sync restarts the update). Given the
    update's ``period``, the power of two is one inside the update, the largest one half the
    time (the phase counter's high bits are reached only in the few long updates)."""
    if rng.random() < 0.5:
        return -1
    if period is None:
        power = rng.randint(2, 15)
    else:
        top = max(2, min(15, (period - 1).bit_length() - 1))
        power = top if rng.random() < 0.5 else rng.randint(2, top)
    return start + (1 << power) + rng.randint(-2, 9)


def limit_osr(rng):
    """An OSR of the ``limits`` scenario: 0 (taken as 1), 1, 2, the largest ones, a power of
    two (one bit set: a stuck or inverted bit of the OSR's tests shows)."""
    return rng.choice([0, 1, 2, OSR_MAX - 1, OSR_MAX, rng.randint(0, OSR_MAX),
                       1 << rng.randint(0, 7)])


#: the ``ties`` scenario's coverpoint: an update whose sort1 meets two legs with equal T (its
#: order of equal values decides: docs/contract.md, "Sort1 (N-input sort) tie-break") or T one
#: step apart, and one whose two largest candidates are equal (the smallest j wins: "Candidates
#: and the two selection rules") or close. A step is N: every T_i - T_j is a multiple of N in
#: the N-scaled domain (R_i - R_j = N (c_i - c_j), and the feedback's U_i - U_j = N FULL (h_i -
#: h_j)); so are largest_duty's candidates, and exact_nearest's are even: "close" is at most
#: 2 N apart
TIE_POINT = "core ties: aimed coincidences of the two sorts"
TIE_BINS = ("legs equal", "legs one step apart", "candidates equal", "candidates close")
#: one beat in this many of the ``ties`` scenario is aimed (each aim simulates the model ahead)
TIE_AIM_EVERY = 16

#: the ``limits`` scenario's coverpoint: a sync pulse just past a power of two 2**k of the
#: phase (``elapsed``), 1 to 6 clocks after the phase count carried into bit k, for each k the
#: run has room for: a sync restarts an update once ``phase + 1 >= latency`` (docs/contract.md,
#: "Sync"), so every bit of the phase decides that test somewhere along a long update
SYNC_POINT = "core sync: a sync pulse at a power of two of the update's phase"
#: the bits of the phase counter (a 16-bit period) from the first one above the latency's
SYNC_POWERS = range(3, 16)


def sync_bins(cycles):
    """The powers of two of the phase a ``limits`` run of ``cycles`` clocks aims its sync pulses
    at: those whose update fits a quarter of the run (its second half holds the syncs)."""
    return [k for k in SYNC_POWERS if (1 << k) + 16 <= cycles // 4]


def sync_bin(k):
    """The :data:`SYNC_POINT` bin of the power ``2**k``."""
    return f"phase 2**{k} + 1 to 2**{k} + 6"


def tie_bins(t, contract, rule):
    """The :data:`TIE_BINS` an update with ``T = t`` hits."""
    rho, _ = sort1(t)
    n = contract.phases
    legs = min(rho[p] - rho[p + 1] for p in range(n - 1))
    ranked = sorted(candidates(rho, contract, rule), reverse=True)
    top = ranked[0] - ranked[1]
    return ([TIE_BINS[legs // n]] if legs in (0, n) else []) + \
        ([TIE_BINS[2 + (top > 0)]] if top <= 2 * n else [])


def x_at_use(model, codes, settings, limit=4096):
    """The integrators ``X`` of the update that takes a beat of ``codes`` offered now (the model
    ready): a copy of the model run ahead with ``settings`` held (the keyword inputs of its
    ``step`` besides the stream: ``period``, ``osr``, ``zero_policy`` for the core's model, and
    ``mode`` and ``bits`` too for the generator's); None if that update does not start within
    ``limit`` clocks."""
    probe = copy.deepcopy(model)
    probe.step(ref_valid=1, ref=codes, **settings)
    for _ in range(limit):
        probe.step(**settings)
        if probe.fresh_reference:           # the tick that takes it
            return probe.x
    return None


def aimed_tie(rng, model, contract, rule, settings, codes):
    """A beat (offered now, the model ready) whose update meets a tie of sort1 (two legs' T
    equal or one step, N, apart) or of sort2 (the two largest candidates equal or close), each
    half the time; ``codes`` where the update cannot be foreseen. sort1's: ``T_a - T_b = X_a -
    X_b + N (c_a - c_b)``, so ``c_a`` is set from ``c_b``; sort2's: a pattern search over the
    codes for the distance aimed at between the two largest candidates (0, or the smallest
    above 0 it finds)."""
    x = x_at_use(model, codes, settings)
    if x is None:
        return codes
    n, lo, hi = contract.phases, contract.code_min, contract.code_max

    def t_of(c):
        return [xi + ri for xi, ri in zip(x, remove_common_mode(c, n), strict=True)]

    codes = list(codes)
    apart = rng.choice((0, n))
    if rng.random() < 0.5:
        a, b = rng.sample(range(n), 2)
        codes[a] = max(lo, min(hi, codes[b] + (apart - (x[a] - x[b])) // n))
        return codes

    def distance(c):
        ranked = sorted(candidates(sort1(t_of(c))[0], contract, rule), reverse=True)
        gap = ranked[0] - ranked[1]
        return gap if apart == 0 else abs(gap - 1) if gap else 2 * contract.full

    best, step = distance(codes), contract.full // 2
    while step >= 1 and best > 0:
        moved = False
        for i in range(n):
            for delta in (step, -step):
                trial = list(codes)
                trial[i] = max(lo, min(hi, trial[i] + delta))
                d = distance(trial)
                if d < best:
                    codes, best, moved = trial, d, True
        if not moved:
            step //= 2
    return codes


def linear_amplitude(phases):
    """Largest sine amplitude (Vdc) inside the linear range max(v) - min(v) <= 1."""
    spread = max(math.cos(2 * math.pi * i / phases) for i in range(phases)) - min(
        math.cos(2 * math.pi * i / phases) for i in range(phases))
    return 1 / spread


def generate(rng, scenario, contract, rule, cycles, coverage=None):
    """Closed-loop stimulus: a stream source that reacts to the model's ``ready`` like a real
    producer (holds valid and payload until accepted, idles at random) and the runtime settings
    of ``scenario``. Returns (inputs per cycle, expected outputs per cycle). With a
    :class:`~mdfqm_testkit.coverage.Coverage`, the ``ties`` scenario declares :data:`TIE_BINS`
    and counts the updates that hit them (from the model's ``T``), and the ``limits`` scenario
    the bins of :data:`SYNC_POINT` its run has room for (hit by the model's ``elapsed`` in the
    clock of a sync pulse)."""
    model = CoreModel(contract.phases, contract.width, rule)
    if coverage is not None and scenario == "ties":
        coverage.want(TIE_POINT, TIE_BINS, "core ties")
    # the powers of two of the phase not yet met by a sync pulse (kept here, not in the
    # coverage: the stimulus is the same with or without one)
    sync_open = set(sync_bins(cycles)) if scenario == "limits" else set()
    if coverage is not None and scenario == "limits":
        coverage.want(SYNC_POINT, [sync_bin(k) for k in sync_open], "core limits")
    beats = 0
    latency = model.latency
    n = contract.phases
    lin = linear_amplitude(n)
    period, osr, policy = latency, 4, 0
    angle, step = rng.uniform(0, 2 * math.pi), rng.uniform(0.002, 0.05)
    amplitude, offset = 0.9 * lin, 0.0
    offered, longest, holding, sync_at = None, 0, False, -1
    stim = {"rst": [], "ref__valid": [], "ref__payload": [], "period": [], "osr": [],
            "zero_policy": [], "sync_in": []}
    expected = {name: [] for name in OUTPUTS}
    for cycle in range(cycles):
        rst = 0
        if cycle % 997 == 0:                              # runtime settings move
            if scenario in ("sine", "runtime"):
                period = rng.choice([latency, latency, latency + 1, 2 * latency + 3])
                osr = rng.choice([1, 2, 4, 4])
                policy = rng.randint(0, 1)
                amplitude = rng.uniform(0.05, 1.0) * lin
            if scenario == "runtime":
                period = rng.choice([0, 1, latency - 1, latency, latency + 5, 65535 % 50])
                osr = rng.choice([0, 1, 3, 255 % 7])
            if scenario == "overmod":
                amplitude = rng.uniform(1.0, 2.0) * lin
                offset = rng.uniform(-0.5, 0.5)
                policy = rng.randint(0, 1)
            if scenario == "limits":
                if not holding:          # the largest period is held until an update takes it
                    room = cycles - cycle - 2 * latency
                    period = limit_period(rng, latency, room, longest)
                    longest, holding = max(longest, period), period == PERIOD_MAX
                    fits = [k for k in sync_open if (1 << k) + 16 <= room // 2]
                    if cycle > cycles // 2 and fits:
                        # an update long enough for the largest power not met yet
                        period = (1 << max(fits)) + 16 + rng.randint(0, 64)
                osr, policy = limit_osr(rng), rng.randint(0, 1)
                amplitude, offset = rng.uniform(0.0, 2.0) * lin, rng.uniform(-0.5, 0.5)
        if scenario in RESETS and rng.random() < RESETS[scenario]:
            rst = 1                                       # reset mid-run
        # an aimed beat of the ``ties`` scenario waits until the model is ready, so that the
        # update which takes it is foreseen from the clock it is offered in
        aiming = scenario == "ties" and beats % TIE_AIM_EVERY == TIE_AIM_EVERY - 1
        if offered is None and (model.ref_ready or not aiming) and rng.random() < 0.7:
            angle += step
            if scenario == "extremes" or (scenario == "limits" and rng.random() < 0.5):
                offered = extreme_codes(rng, contract, n)
            elif scenario == "ties":
                level = rng.randint(contract.code_min, contract.code_max)
                offered = [rng.choice([level, -level // 2, 0]) for _ in range(n)]
            else:
                offered = sine_codes(contract, amplitude, angle, offset)
            if scenario in ("ties", "extremes"):
                policy = rng.randint(0, 1)
            if aiming:
                offered = aimed_tie(rng, model, contract, rule,
                                    {"period": period, "osr": osr, "zero_policy": policy},
                                    offered)
            beats += 1
        # no random sync while an aimed one is due (it would cut the long update short)
        sync_in = int((scenario in SYNCS and (scenario != "limits" or cycle > cycles // 2)
                       and sync_at < cycle and rng.random() < SYNCS[scenario])
                      or cycle == sync_at)
        valid = int(offered is not None)
        payload = offered or [0] * n
        out = model.step(rst=rst, ref_valid=valid, ref=payload, period=period, osr=osr,
                         zero_policy=policy, sync_in=sync_in)
        if valid and out["ref_ready"] and not rst:
            offered = None
        if coverage is not None and scenario == "ties" and out["start"] and not rst:
            _, x, r = model.inflight[:3]
            for bin_ in tie_bins([xi + ri for xi, ri in zip(x, r, strict=True)], contract, rule):
                coverage.hit(TIE_POINT, bin_)
        if sync_in and not rst:
            bits = [k for k in SYNC_POWERS
                    if out["elapsed"] >> 3 == 1 << (k - 3) and 1 <= out["elapsed"] % 8 <= 6]
            for k in bits:
                sync_open.discard(k)
                if coverage is not None and scenario == "limits":
                    coverage.hit(SYNC_POINT, sync_bin(k))
        holding = holding and not out["start"]
        if out["start"]:
            sync_at = -1            # an aim belongs to the update it was aimed into
        if scenario == "limits" and cycle > cycles // 2 and sync_at < cycle:
            # the largest power not met yet that the update running now still reaches
            begun = cycle - out["elapsed"]
            ahead = [k for k in sync_open
                     if cycle < begun + (1 << k) and (1 << k) + 8 < model.p_lat]
            if ahead:
                sync_at = begun + (1 << max(ahead)) + rng.randint(1, 6)
            elif sync_open and model.p_lat - out["elapsed"] > 997:
                # an update that reaches no power still open is cut short, so that a period
                # set for one starts sooner
                sync_at = cycle + 1
            elif out["start"]:
                sync_at = sync_delay(rng, cycle)
        stim["rst"].append(rst)
        stim["ref__valid"].append(valid)
        stim["ref__payload"].append(pack(payload, contract.width))
        stim["period"].append(period)
        stim["osr"].append(osr)
        stim["zero_policy"].append(policy)
        stim["sync_in"].append(sync_in)
        for port, key in OUTPUTS.items():
            expected[port].append(out[key])
    return stim, expected
