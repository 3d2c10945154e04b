"""The drop-in top's stimulus as the specification's rules: one small sequence per row of
docs/robustness.md, per register field and clamp of spec/rdl/mdfqm_top.rdl and per timing rule
of docs/top.md, each acting as firmware, the FOC loop or the power stage would (see
mdfqm_testkit.sequences for the frame). :class:`mdfqm_testkit.top_stimulus.TopRun` schedules
them among random background traffic and hits their coverpoints from what the golden model
shows; the docstring of each sequence says which promise it tries.
"""

from __future__ import annotations

from typing import ClassVar

from mdfqm_spec import regmap as regs
from mdfqm_spec.contract import MODES, min_period
from mdfqm_testkit.bbit_stimulus import ROUNDING_PLACES
from mdfqm_testkit.core_stimulus import TIE_BINS
from mdfqm_testkit.coverage import band, band_low, bands
from mdfqm_testkit.harness import pack
from mdfqm_testkit.sequences import Sequence, doc, rdl, robustness

TOP_MD = "docs/top.md"
CONTRACT_MD = "docs/contract.md"

#: the resources of the top a sequence can hold (the scheduler starts a sequence only when
#: none of its claims is held); ALL for a sequence that resets the top
PERIOD, ADC, DEAD, OSR, CTRL, MODULATION = "period", "adc", "dead", "osr", "ctrl", "modulation"
STREAM, FAULT, WATCHDOG, SYNC, IRQ, COUNTERS, REF = (
    "stream", "fault", "watchdog", "sync", "irq", "counters", "ref")
ALL = frozenset({PERIOD, ADC, DEAD, OSR, CTRL, MODULATION, STREAM, FAULT, WATCHDOG, SYNC, IRQ,
                 COUNTERS, REF})

#: the events a register access can meet in its clock (docs/robustness.md, "two events in
#: one clock"; docs/top.md, "Update timing")
EVENTS = ("update start", "beat accepted", "fault pin edge", "fault latch set", "sync pulse",
          "gate turn-on")
#: the accesses that meet them
ACCESS_KINDS = ("register write", "CMD write", "IRQ_STATUS write-1-to-clear")
#: IRQ_STATUS / IRQ_ENABLE bits, by source (docs/top.md, "Interrupt")
IRQ_SOURCES = {"FAULT": regs.IRQ_FAULT, "COUNTER_WRAP": regs.IRQ_COUNTER_WRAP,
               "SAMPLE": regs.IRQ_SAMPLE, "SHORT_EDGE": regs.IRQ_SHORT_EDGE,
               "WATCHDOG": regs.IRQ_WATCHDOG}
#: bands of the 16-bit PERIOD in force (the minimum of the update's mode below the first)
PERIOD_EDGES = (0, 32, 256, 4096, 8192, 16384, 32768)
#: run length from which PERIOD's bands from 4096 clocks are aimed at (their updates stall
#: every sequence that waits for an update start)
PERIOD_BAND_RUN = 100_000
#: run length from which the top octaves of the 16-bit times are aimed at: PERIOD from 16384,
#: DEAD and MIN_PULSE from 32768 (LongTimes: an update or a pulse of up to 65,535 clocks, a few
#: times)
LONG_TIMES_RUN = 500_000
#: bands of the 16-bit ADC_OFFSET at which a trigger pulsed
ADC_EDGES = (0, 1, 256, 4096, 8192, 32768)
#: run length from which an update of each ADC band's length fits (its band's first offset,
#: plus the update running when it is written, at most a few times in a run)
ADC_BAND_RUN = {0: 0, 1: 0, 256: 0, 4096: 30_000, 8192: 50_000, 32768: 150_000}


def period_edges(run) -> list[int]:
    """The bands of PERIOD aimed at in ``run``."""
    return [e for e in PERIOD_EDGES if e < 4096 or (e < 16384 and run.cycles >= PERIOD_BAND_RUN)
            or run.cycles >= LONG_TIMES_RUN]


def adc_edges(run) -> list[int]:
    """The bands of ADC_OFFSET aimed at in ``run``."""
    return [e for e in ADC_EDGES if ADC_BAND_RUN[e] <= run.cycles]


class TopSequence(Sequence, family=True):
    """A sequence of the drop-in top (mdfqm_testkit.top_stimulus.TopRun)."""

    family = "top"


def short_period(run) -> int:
    """A period of a few dozen to a few hundred clocks: the gates switch within a few
    thousand clocks in every mode (below the slot modes' minimum at large b it is clamped)."""
    return run.rng.choice([90, 130, 170, run.rng.randint(20, 27), run.rng.randint(28, 255)])


# ------------------------------------------------------------------------- firmware start-up


class Operate(TopSequence):
    """Firmware start-up: every runtime setting written (period, OSR, dead time, minimum pulse,
    ADC offset, interrupt enables, fault reactions, watchdog off), the latches cleared, the
    gates enabled; after a reset and at the start of a run."""

    rules = (doc(TOP_MD, "Register map"), rdl("CTRL.ENABLE"))
    claims = ALL
    weight = 0.0            # started by the run itself, never drawn

    def body(self):
        run, rng = self.run, self.rng
        dead_min = run.model.dead_min
        run.nominal.update({
            regs.IRQ_ENABLE: rng.choice([regs.IRQ_MASK, rng.getrandbits(5)]),
            regs.OSR: rng.choice([1, 1, 2]),
            regs.PERIOD: short_period(run),
            regs.DEAD: rng.choice([0, dead_min, dead_min + rng.randrange(1, 24)]),
            regs.MIN_PULSE: rng.randrange(8),
            regs.ADC_OFFSET: rng.randrange(100),
            regs.WATCHDOG: 0,
            regs.FAULT_REACTION: rng.randrange(16),
            regs.CTRL: regs.CTRL_ENABLE | rng.randint(0, 1) * regs.CTRL_ZERO_POLICY,
        })
        writes = [run.write(address, value) for address, value in run.nominal.items()
                  if address != regs.CTRL]
        writes.append(run.command(regs.CMD_FAULT_CLEAR | regs.CMD_WATCHDOG_CLEAR))
        writes.append(run.write(regs.CTRL, run.nominal[regs.CTRL]))
        yield from run.settle(*writes)


# ------------------------------------------------------------------------ runtime settings


class PeriodBands(TopSequence):
    """PERIOD in each band of its 16-bit field, in force at an update start and held for an
    update at least; the longest bands only where the run has room for them. An update of 256
    clocks or more is cut short by a sync pulse at a phase just past the band's power of two
    (from there to L - 2 past it: the update has committed, and sync_in starts the next one,
    docs/top.md "Several instances") while that bin is open, and half the time after."""

    rules = (rdl("PERIOD.PERIOD"), doc(TOP_MD, "Update timing and the ADC trigger"),
             doc(TOP_MD, "Several instances"))
    claims = frozenset({PERIOD, SYNC})
    POINT = "PERIOD in force at an update start"
    SYNC_POINT = "sync pulse starts the next update at a phase just past"

    @staticmethod
    def sync_edges(run) -> list[int]:
        """The powers of two of an update's phase that a sync is aimed just past."""
        return [e for e in period_edges(run) if e >= 256]

    @staticmethod
    def sync_phases(run, edge: int) -> range:
        """The phases just past ``edge`` a sync is aimed at: the update has committed there
        (from ``edge``, at least 256, on) and they stay below the next power of two."""
        return range(edge, edge + run.model.latency - 1)

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: (*bands(period_edges(run)), "below the minimum"),
                cls.SYNC_POINT: tuple(str(e) for e in cls.sync_edges(run))}

    def body(self):
        run, rng = self.run, self.rng
        syncs = [b for b in bands(period_edges(run))
                 if str(band_low(b)) in run.coverage.open_bins(self.SYNC_POINT)]
        wanted = run.coverage.open_bins(self.POINT) or syncs or ["short"]
        choice = rng.choice(wanted)
        if choice == "below the minimum":
            value = rng.randrange(run.model.latency)
        elif choice == "short":
            value = short_period(run)
        else:                       # above the loop latency, so that it is not clamped
            lo = max(band_low(choice), run.model.latency)
            value = lo + rng.randrange(min(600, lo))
        yield from run.settle(run.write(regs.PERIOD, value), run.read(regs.PERIOD))
        yield from run.updates(1, limit=3 * 65536)          # taken at that start
        edge = max((e for e in self.sync_edges(run) if e <= value), default=None)
        phase = None if edge is None else rng.choice(self.sync_phases(run, edge))
        if phase is not None and phase + 2 < value and (
                str(edge) in run.coverage.open_bins(self.SYNC_POINT) or rng.random() < 0.5):
            core = run.model.core
            if (yield from run.until(lambda: core.phase == phase, limit=phase + 1)):
                run.sync_in = 1
                yield
        if value >= 4096:           # long updates cost clocks: back to a short operating point
            value = short_period(run)
            yield from run.settle(run.write(regs.PERIOD, value))
        run.nominal[regs.PERIOD] = value


def slot_minimums(model) -> dict[int, list[int]]:
    """The slot modes' minimum periods above the loop latency, each with the b that have it
    (docs/contract.md: ``max(L_b, 2**b)``)."""
    found: dict[int, list[int]] = {}
    for b in range(1, model.max_bits + 1):
        low = min_period(True, b, model.latency, model.long_latency)
        if low > model.latency:
            found.setdefault(low, []).append(b)
    return found


class PeriodBelowLatency(TopSequence):
    """PERIOD below the loop latency (0 .. L-1), and below a slot mode's minimum (at each
    minimum the slot modes have: between L and it, one below it half the time): used as the
    minimum, STATUS.PERIOD_CLAMPED set for that update, read back."""

    rules = (robustness("update period below the loop latency"),
             rdl("STATUS.PERIOD_CLAMPED"))
    claims = frozenset({PERIOD, MODULATION})
    POINT = "PERIOD below the minimum of the update"
    #: the bins of PERIOD below the loop latency, whatever the mode
    ZERO, BELOW_L = "0", "1..L-1"

    @staticmethod
    def slot_bin(minimum: int) -> str:
        return f"in a slot mode, between L and its minimum {minimum}"

    @classmethod
    def coverpoints(cls, run):
        bins = (cls.ZERO, cls.BELOW_L, "STATUS.PERIOD_CLAMPED read 1")
        if run.model.max_bits:
            bins += ("in a slot mode",
                     *(cls.slot_bin(v) for v in slot_minimums(run.model)))
        return {cls.POINT: bins}

    def body(self):
        run, rng = self.run, self.rng
        minimums = slot_minimums(run.model) if run.model.max_bits else {}
        open_ = [v for v in minimums if self.slot_bin(v) in run.coverage.open_bins(self.POINT)]
        # PERIOD 0 and 1..L-1 take their turns while the slot modes' minimums are still open
        plain = [b for b in (self.ZERO, self.BELOW_L)
                 if b in run.coverage.open_bins(self.POINT)]
        slot_turn = bool(open_) and not (plain and rng.random() < 0.5)
        if slot_turn or (not open_ and not plain and minimums and rng.random() < 0.3):
            low = rng.choice(open_ or list(minimums))
            value = rng.choice([low - 1, rng.randint(run.model.latency, low - 1)])
            word = run.modulation_word(legal=True, mode=rng.randint(1, len(MODES) - 1),
                                       bits=rng.choice(minimums[low]))
            yield from run.settle(run.write(regs.MODULATION, word), run.write(regs.PERIOD, value))
            yield from run.updates(2)
            yield from run.settle(run.read(regs.STATUS),
                                  run.restore(regs.PERIOD, regs.MODULATION))
            yield from run.updates(1)
            yield from run.settle(run.read(regs.STATUS))
            return
        pick = rng.choice(plain or [self.ZERO, self.BELOW_L])
        value = 0 if pick == self.ZERO else rng.randrange(1, run.model.latency)
        yield from run.settle(run.write(regs.PERIOD, value))
        yield from run.updates(2)
        yield from run.settle(run.read(regs.STATUS), run.restore(regs.PERIOD))
        yield from run.updates(1)
        yield from run.settle(run.read(regs.STATUS))


class OsrSettings(TopSequence):
    """OSR 0 (acts as 1), 1, 2 .. 254 and 255 in force: the sampling tick every OSR updates."""

    rules = (robustness("OSR 0"), rdl("OSR.OSR"))
    claims = frozenset({OSR})
    POINT = "OSR in force at an update start"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("0 (acts as 1)", "1", "2..254", "255")}

    def body(self):
        run, rng = self.run, self.rng
        pick = rng.choice(run.coverage.open_bins(self.POINT) or ["1", "2..254"])
        value = {"0 (acts as 1)": 0, "1": 1, "255": 255}.get(pick, rng.choice([2, 3, 4, 254]))
        yield from run.settle(run.write(regs.OSR, value), run.read(regs.OSR))
        yield from run.updates(rng.randint(2, 6))
        yield from run.settle(run.restore(regs.OSR))


class ZeroPolicy(TopSequence):
    """CTRL.ZERO_POLICY flipped (the gates kept enabled): each zero-state policy in force."""

    rules = (rdl("CTRL.ZERO_POLICY"), doc(CONTRACT_MD, "Zero-state policy"))
    claims = frozenset({CTRL})
    POINT = "zero policy in force at an update start"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("all-off", "fewest transitions")}

    def body(self):
        run = self.run
        run.nominal[regs.CTRL] ^= regs.CTRL_ZERO_POLICY
        yield from run.settle(run.restore(regs.CTRL), run.read(regs.CTRL))
        yield from run.updates(2)


class EnableMidUpdate(TopSequence):
    """CTRL.ENABLE cleared and set again in the middle of an update: taken at the next update
    boundary; STATUS.ACTIVE read on both sides of it."""

    rules = (robustness("enable toggled in the middle of an update"), doc(TOP_MD, "Enable"),
             rdl("STATUS.ACTIVE"))
    claims = frozenset({CTRL})
    POINT = "CTRL.ENABLE written in the middle of an update"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("cleared", "set", "STATUS.ACTIVE read 1", "STATUS.ACTIVE read 0")}

    def body(self):
        run = self.run
        middle = run.aim(run.moment_mid_update)
        off = run.nominal[regs.CTRL] & ~regs.CTRL_ENABLE
        yield from run.settle(run.read(regs.STATUS), run.write(regs.CTRL, off, aim=middle))
        yield from run.updates(1)
        yield from run.wait(run.model.long_latency + 2)
        middle = run.aim(run.moment_mid_update)
        yield from run.settle(run.read(regs.STATUS), run.restore(regs.CTRL, aim=middle))
        yield from run.updates(1)
        yield from run.wait(run.model.long_latency + 2)
        yield from run.settle(run.read(regs.STATUS))


class RuntimeChanges(TopSequence):
    """PERIOD, OSR, CTRL or MODULATION written in the very clock of an update start, or the
    clock before it: taken at the next update start only."""

    rules = (robustness("runtime changes of period / OSR / zero policy / mode"),
             doc(TOP_MD, "Modulation mode and resolution"))
    claims = frozenset({PERIOD, OSR, CTRL, MODULATION})
    POINT = "a setting written in the clock of an update start"
    BEFORE = "a setting written the clock before an update start"
    SETTINGS: ClassVar[dict] = {"PERIOD": regs.PERIOD, "OSR": regs.OSR, "CTRL": regs.CTRL,
                                "MODULATION": regs.MODULATION}

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: tuple(cls.SETTINGS), cls.BEFORE: tuple(cls.SETTINGS)}

    def body(self):
        run, rng = self.run, self.rng
        at_start = run.coverage.open_bins(self.POINT)
        before = run.coverage.open_bins(self.BEFORE)
        lead = 1 if before and (not at_start or rng.random() < 0.5) else 0
        name = rng.choice((before if lead else at_start) or list(self.SETTINGS))
        address = self.SETTINGS[name]
        value = {"PERIOD": short_period(run), "OSR": rng.choice([1, 2]),
                 "CTRL": run.nominal[regs.CTRL] ^ regs.CTRL_ZERO_POLICY,
                 "MODULATION": run.modulation_word(legal=True)}[name]
        run.nominal[address] = value
        yield from run.aimed(lambda: run.write(
            address, value, aim=run.aim(run.moment_update_start, lead=lead)),
            self.BEFORE if lead else self.POINT, name)
        yield from run.updates(1)
        yield from run.settle(run.read(address))


class ModulationModes(TopSequence):
    """MODULATION.MODE and .BITS: every mode built in, and each slot mode at every b, in force
    (taken at the next update start, read back in force): the offsets and slot counts of each
    (mode, b) are their own."""

    rules = (rdl("MODULATION.MODE"), rdl("MODULATION.BITS"),
             doc(TOP_MD, "Modulation mode and resolution"))
    claims = frozenset({MODULATION})
    MODES_POINT = "mode in force"
    BITS_POINT = "slot mode and b in force"

    @staticmethod
    def slot_bin(mode: int, bits: int) -> str:
        return f"{MODES[mode]}, b {bits}"

    @classmethod
    def coverpoints(cls, run):
        points = {cls.MODES_POINT: MODES[:len(MODES) if run.model.max_bits else 1]}
        if run.model.max_bits:
            points[cls.BITS_POINT] = tuple(cls.slot_bin(mode, b) for mode in range(1, len(MODES))
                                           for b in range(1, run.model.max_bits + 1))
        return points

    def body(self):
        run, rng = self.run, self.rng
        modes = run.coverage.open_bins(self.MODES_POINT)
        pairs = run.coverage.open_bins(self.BITS_POINT) if run.model.max_bits else []
        mode = bits = None
        if modes:
            mode = MODES.index(rng.choice(modes))
        elif pairs:
            name, b = rng.choice(pairs).split(", b ")
            mode, bits = MODES.index(name), int(b)
        word = run.modulation_word(legal=True, mode=mode, bits=bits)
        run.nominal[regs.MODULATION] = word
        yield from run.settle(run.write(regs.MODULATION, word), run.read(regs.MODULATION))
        yield from run.updates(2, limit=200_000)
        yield from run.settle(run.read(regs.MODULATION))


class Handover(TopSequence):
    """A slot mode and MDFQM alternating update by update, with the fewest-transitions zero
    policy: an MDFQM update that chooses the zero state right after a layout takes all-on or
    all-off from the layout's last slot (docs/contract.md, "Zero-state policy"). A bin per leg
    whose state in that last slot decides the choice (the legs on there one more than half of
    N: without that leg it would flip)."""

    rules = (doc(CONTRACT_MD, "Zero-state policy"), doc(TOP_MD, "Modulation mode and resolution"))
    claims = frozenset({MODULATION, CTRL, PERIOD, STREAM})
    POINT = "MDFQM zero state after a layout, decided by the last slot's"

    @classmethod
    def applies(cls, run):
        return run.model.max_bits > 0

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: tuple(f"leg {i}" for i in range(run.model.phases))}

    def body(self):
        run, rng = self.run, self.rng
        run.stream.kind = "linear"
        yield from run.settle(
            run.write(regs.CTRL, run.nominal[regs.CTRL] | regs.CTRL_ZERO_POLICY),
            run.write(regs.PERIOD, run.model.long_latency + rng.randint(0, 8)))
        for _ in range(60):
            if not run.coverage.open_bins(self.POINT) and rng.random() < 0.2:
                break
            layout = run.modulation_word(legal=True, mode=rng.randint(1, len(MODES) - 1),
                                         bits=rng.randint(1, min(3, run.model.max_bits)))
            yield from run.settle(run.write(regs.MODULATION, layout))
            yield from run.updates(1)
            yield from run.settle(run.write(regs.MODULATION, run.modulation_word(mode=0)))
            yield from run.updates(1)
        yield from run.settle(run.restore(regs.MODULATION, regs.CTRL, regs.PERIOD))
        run.stream.kind = "sine"


class ModulationClamp(TopSequence):
    """MODULATION written with a mode not built in, b 0, b above max_bits, bits outside its
    fields: the request clamped at the next update start (STATUS.MODE_CLAMPED), read back in
    force."""

    rules = (robustness("MODULATION written with a mode not built in"),
             rdl("STATUS.MODE_CLAMPED"))
    claims = frozenset({MODULATION})
    POINT = "MODULATION request clamped at an update start"

    @classmethod
    def coverpoints(cls, run):
        if not run.model.max_bits:
            return {cls.POINT: ("mode not built in", "STATUS.MODE_CLAMPED read 1")}
        bins = ["mode not built in", "b 0", "bits outside MODE and BITS",
                "STATUS.MODE_CLAMPED read 1"]
        if run.model.max_bits < 15:
            bins.append("b above max_bits")
        return {cls.POINT: tuple(bins)}

    def body(self):
        run, rng = self.run, self.rng
        built = len(MODES) if run.model.max_bits else 1
        pick = rng.choice(run.coverage.open_bins(self.POINT) or ["mode not built in", "b 0"])
        mode, bits, extra = rng.randint(1, len(MODES) - 1), rng.randint(1, 3), 0
        if pick == "mode not built in":
            mode = rng.randint(built, 7)
        elif pick == "b 0":
            bits = 0
        elif pick == "b above max_bits":
            bits = rng.randint(run.model.max_bits + 1, 15)
        elif pick == "bits outside MODE and BITS":
            extra = rng.choice([0xF0F8, 0xFFFF_F0F8, 1 << 31])
        word = (mode << regs.MODULATION_MODE_SHIFT | bits << regs.MODULATION_BITS_SHIFT
                | extra)
        yield from run.settle(run.write(regs.MODULATION, word))
        yield from run.updates(2, limit=200_000)
        yield from run.settle(run.read(regs.MODULATION), run.read(regs.STATUS),
                              run.restore(regs.MODULATION))


class AdcOffsetBands(TopSequence):
    """ADC_OFFSET in each band of its 16-bit field, the update long enough for the trigger to
    pulse at s + 1 + ADC_OFFSET, and an offset not below the period (no pulse)."""

    rules = (rdl("ADC_OFFSET.ADC_OFFSET"), doc(TOP_MD, "Update timing and the ADC trigger"))
    claims = frozenset({PERIOD, ADC, SYNC})
    POINT = "ADC trigger pulsed at an offset in"
    NONE = "none: ADC_OFFSET not below the period"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: (*bands(adc_edges(run)), cls.NONE)}

    def body(self):
        run, rng = self.run, self.rng
        pick = rng.choice(run.coverage.open_bins(self.POINT) or ["0", "1..255", "256..4095"])
        period = run.nominal[regs.PERIOD]
        if pick == self.NONE:
            offset = max(period, run.model.long_latency) + rng.randrange(4)
        else:
            low = band_low(pick)
            offset = low + rng.randrange(min(400, max(1, low)) if low else 1)
            if offset >= period - 2:
                period = offset + rng.randint(2, 200)
        writes = [run.write(regs.PERIOD, period), run.write(regs.ADC_OFFSET, offset)]
        yield from run.settle(*writes, run.read(regs.ADC_OFFSET))
        if pick == self.NONE:
            yield from run.updates(2, limit=3 * 65536)
        else:                       # the update in flight, then the one the offset fits in
            triggers = run.triggers
            yield from run.until(lambda: run.triggers > triggers
                                 and run.model.adc_offset == offset,
                                 limit=run.model.core.p_lat + 2 * period + 100)
        yield from run.settle(run.restore(regs.PERIOD, regs.ADC_OFFSET))


# ---------------------------------------------------------------------- the gate driver


class DeadTime(TopSequence):
    """DEAD written below the floor, and raised or lowered while a leg's dead time runs: never
    below dead_min, a running dead time lengthened but never shortened, acting two clocks
    after the write (aimed at the clock before a turn-on)."""

    rules = (robustness("dead time below the elaboration floor, or changed while running"),
             rdl("DEAD.DEAD"), doc(TOP_MD, "Gate driver (per leg)"))
    claims = frozenset({DEAD})
    POINT = "DEAD written"
    RUNNING = "DEAD lowered while a dead time runs, that dead time in"

    @classmethod
    def running_edges(cls, run) -> tuple[int, ...]:
        """Octaves of the running dead time that a lowering must not shorten (each sets its
        bit of the dead time in force), from the floor's: to 2**10 where the run has room, else
        to 2**7."""
        top = 10 if run.cycles >= PERIOD_BAND_RUN else 7
        floor = run.model.dead_min.bit_length() - 1
        return tuple(1 << k for k in range(min(floor, top), top + 1))

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("below the floor", "raised while a dead time runs",
                            "lowered while a dead time runs", "the clock before a turn-on"),
                cls.RUNNING: tuple(bands(cls.running_edges(run)))}

    def body(self):
        run, rng = self.run, self.rng
        running_open = run.coverage.open_bins(self.RUNNING)
        pick = rng.choice(run.coverage.open_bins(self.POINT) or
                          (["lowered while a dead time runs"] if running_open else [self.POINT]))
        dead_min = run.model.dead_min
        now = max(run.model.dead, dead_min)
        if pick == "below the floor":
            value, moment, lead = rng.randrange(dead_min), None, 0
        elif pick == "the clock before a turn-on":
            value, moment, lead = now + rng.randint(1, 8), run.moment_turn_on, 1
        else:
            if pick.startswith("lowered"):      # from a dead time in one of the octaves
                octave = rng.choice(running_open or bands(self.running_edges(run)))
                low = band_low(octave)
                now = max(dead_min + 2, low + rng.randrange(low))
                yield from run.settle(run.write(regs.DEAD, now))
                yield from run.wait(2)
                value = rng.randint(dead_min, now - 1)
            else:
                value = now + rng.randint(1, 12)
            moment, lead = run.moment_in_dead_time, 0
        yield from run.aimed(lambda: run.write(
            regs.DEAD, value, aim=moment and run.aim(moment, lead=lead)), self.POINT, pick)
        yield from run.settle(run.read(regs.DEAD))
        yield from run.updates(rng.randint(1, 3))
        yield from run.settle(run.restore(regs.DEAD))


class MinPulse(TopSequence):
    """MIN_PULSE longer than the commanded pulses (a slot or an update): each such pulse
    stretched to MIN_PULSE, never dropped."""

    rules = (robustness("a commanded pulse shorter than the minimum pulse"),
             rdl("MIN_PULSE.MIN_PULSE"), doc(TOP_MD, "Gate driver (per leg)"))
    claims = frozenset({DEAD})
    POINT = "commanded pulse shorter than MIN_PULSE"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("stretched",)}

    def body(self):
        run, rng = self.run, self.rng
        slot = run.slot_length()
        value = rng.randint(slot + 1, 3 * slot + 2)
        yield from run.settle(run.write(regs.MIN_PULSE, value), run.read(regs.MIN_PULSE))
        yield from run.until(lambda: run.coverage.covered(self.POINT, "stretched")
                             and rng.random() < 0.05, limit=8 * slot * 16 + 500)
        yield from run.settle(run.restore(regs.MIN_PULSE))


class LongTimes(TopSequence):
    """DEAD and MIN_PULSE in the high octaves of their 16-bit fields, where they decide the
    gates: a turn-on after a dead time of DEAD clocks (the updates longer than it, in MDFQM, so
    that a leg's command holds through its dead time), and a pulse held on to a MIN_PULSE of
    more than 32,768 clocks; in runs long enough for a few such times. Half the dead-time
    trials (each octave at least once) lower DEAD to dead_min while that long dead time runs:
    the turn-on still waits it out (docs/top.md, "Dead time in force"). The gates stay enabled,
    with no fault or watchdog trip, and every beat is half of one leg's active vector, a new
    beat each update (OSR 1), meanwhile: from any integrators the MDFQM update then changes the
    state at every update after a few (tb/test_top_vectors.py checks it on the model), and a
    trial begins once it has seen the state change at each of a few short updates. A reference
    that reverses each beat does not do that: from centred integrators it can leave the zero
    state in force at every update, and a trial of long updates without a turn-on."""

    rules = (rdl("DEAD.DEAD"), rdl("MIN_PULSE.MIN_PULSE"), doc(TOP_MD, "Gate driver (per leg)"))
    claims = frozenset({PERIOD, DEAD, MODULATION, SYNC, STREAM, OSR, CTRL, FAULT, WATCHDOG})
    #: a trial holds most of the top for updates of up to 65,535 clocks: seldom drawn once
    #: its bins are all hit
    closed_weight = 0.1
    DEAD_POINT = "DEAD in force at a turn-on"
    LOWERED = "DEAD lowered while a long dead time runs, that dead time in"
    PULSE_POINT = "a pulse stretched to a MIN_PULSE in"
    #: the octaves aimed at: the dead time's compare and count in their high bits
    DEAD_EDGES = (2048, 32768)
    PULSE_EDGES = (32768,)
    #: short updates in a row that must each change the state before a long trial begins,
    #: and the short updates waited for them at most
    CHANGING_UPDATES, SETTLE_LIMIT = 4, 40

    @classmethod
    def applies(cls, run):
        return run.cycles >= LONG_TIMES_RUN

    @classmethod
    def coverpoints(cls, run):
        return {cls.DEAD_POINT: tuple(bands(cls.DEAD_EDGES)),
                cls.LOWERED: tuple(bands(cls.DEAD_EDGES)),
                cls.PULSE_POINT: tuple(bands(cls.PULSE_EDGES))}

    def body(self):
        run, rng = self.run, self.rng
        # the state changes at every update: a dead time at each boundary
        run.stream.kind, run.stream.half_step_leg = "half step", rng.randrange(run.model.phases)
        open_dead = (run.coverage.open_bins(self.DEAD_POINT)
                     or run.coverage.open_bins(self.LOWERED))
        dead_trial = bool(open_dead) or (not run.coverage.open_bins(self.PULSE_POINT)
                                         and rng.random() < 0.5)
        if dead_trial:
            yield from self._long_dead_time(rng.choice(open_dead or bands(self.DEAD_EDGES)))
        if not dead_trial or run.coverage.open_bins(self.PULSE_POINT):
            # short updates again (a pulse shorter than MIN_PULSE is one the update ends)
            yield from run.settle(run.restore(regs.PERIOD, regs.DEAD))
            value = (1 << 15) + rng.randrange(4000)
            yield from run.settle(run.write(regs.MIN_PULSE, value), run.write(regs.OSR, 1))
            hit = yield from self._this_trial_hit(self.PULSE_POINT,
                                                  band(value, self.PULSE_EDGES), 3 * value)
            if hit:                 # the stretched pulse held to its end
                yield from run.wait(value + 100)
        yield from run.settle(run.restore(regs.PERIOD, regs.DEAD, regs.MIN_PULSE,
                                          regs.MODULATION, regs.OSR))
        run.stream.kind = "sine"

    def _long_dead_time(self, octave: str):
        """A turn-on after a dead time of DEAD in ``octave`` (lowered to dead_min while it
        runs in half the trials and while that octave's bin is open)."""
        run, rng = self.run, self.rng
        low = band_low(octave)
        dead = low + rng.randrange(min(low, 8000))
        # MDFQM: one state an update, each update longer than the dead time, the state
        # changing at each (seen in short updates first)
        yield from run.settle(run.write(regs.MODULATION, run.modulation_word(mode=0)),
                              run.write(regs.OSR, 1))
        if not (yield from self._state_changing()):
            return
        yield from run.settle(run.write(regs.PERIOD, min(0xFFFF, dead + rng.randint(500, 3000))),
                              run.write(regs.DEAD, dead))
        if octave in run.coverage.open_bins(self.LOWERED) or rng.random() < 0.5:
            # a dead time of DEAD clocks lowered while it runs: it must not end early
            legs = run.model.driver.legs
            running = yield from run.until(
                lambda: run.model.driver.active and any(
                    not (leg.up or leg.lo) and leg.dt_run == dead and leg.cnt > 16
                    for leg in legs), limit=2 * (dead + 3000))
            if running:
                yield from run.settle(run.write(regs.DEAD, run.model.dead_min))
        yield from self._this_trial_hit(self.DEAD_POINT, band(dead, self.DEAD_EDGES),
                                        limit=4 * (dead + 3000) + 1000)

    def _state_changing(self):
        """Wait until the state has changed at each of :data:`CHANGING_UPDATES` updates in
        a row (read at each update start), at most :data:`SETTLE_LIMIT` updates; whether it
        did."""
        run, in_a_row, last = self.run, 0, None
        for _ in range(self.SETTLE_LIMIT):
            yield from run.updates(1)
            state = run.model.core.h
            in_a_row = in_a_row + 1 if last is not None and state != last else 0
            last = state
            if in_a_row >= self.CHANGING_UPDATES:
                return True
        return False

    def _this_trial_hit(self, point, bin_, limit):
        """Wait until this trial hits ``bin_`` (a hit of an earlier trial does not count), at
        most ``limit`` clocks; whether it did."""
        coverage = self.run.coverage
        before = coverage.count(point, bin_)
        return (yield from self.run.until(lambda: coverage.count(point, bin_) > before, limit))


class ShortEdges(TopSequence):
    """A slot mode whose slots are shorter than the dead time plus the minimum pulse: each
    short pulse swallowed or stretched, never silent (IRQ_STATUS.SHORT_EDGE)."""

    rules = (robustness("a slot or an update shorter than the dead time plus the minimum "
                        "pulse"), rdl("IRQ_STATUS.SHORT_EDGE"))
    claims = frozenset({MODULATION, PERIOD})
    POINT = "short edge"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("swallowed by the dead time", "stretched to MIN_PULSE")}

    def body(self):
        run, rng = self.run, self.rng
        if run.model.max_bits:
            word = run.modulation_word(legal=True, mode=rng.randint(1, len(MODES) - 1),
                                       bits=rng.randint(1, min(4, run.model.max_bits)))
            yield from run.settle(run.write(regs.MODULATION, word))
        yield from run.settle(run.write(regs.PERIOD, rng.randint(run.model.latency, 48)))
        yield from run.until(lambda: not run.coverage.open_bins(self.POINT)
                             and rng.random() < 0.02, limit=3000)
        yield from run.settle(run.restore(regs.MODULATION, regs.PERIOD))


# ------------------------------------------------------------------ reference and arbitration


class ReferenceBeats(TopSequence):
    """A run of stream beats of one kind from the FOC loop: the kind's own rule."""

    claims = frozenset({STREAM})
    KIND = ""
    POINT = ""
    BINS: tuple = ()

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: cls.BINS}

    def body(self):
        run = self.run
        run.stream.kind = self.KIND
        yield from run.until(lambda: not run.coverage.open_bins(self.POINT)
                             and self.rng.random() < 0.01, limit=4000)
        yield from run.settle(run.read(regs.STATUS))
        run.stream.kind = "sine"


class Overmodulation(ReferenceBeats):
    """References beyond the linear range, up to twice it, with common mode: the integrators
    hold instead of wrapping, STATUS.SATURATED set for that update and read back."""

    rules = (robustness("reference beyond the linear range"), rdl("STATUS.SATURATED"))
    KIND = "overmodulation"
    POINT = "reference beyond the linear range"
    BINS = ("an update saturated", "STATUS.SATURATED read 1")


class HeldIntegrators(TopSequence):
    """Once an update has saturated, the integrators held (conditional integration) and ran on
    from the held values: with the references back inside the linear range, a beat aimed so
    that leg i's instant sits exactly on its rounding point in a slot mode at the finest b, for
    each leg. The integrators at the update that takes the beat come from the model run ahead,
    and the codes cancel them (``R(c* + D) = R(c*) - X`` for ``D_i = (X_0 - X_i) / N``), so the
    update's ``T`` is that of a beat on the half-slot grid into empty integrators."""

    rules = (doc(CONTRACT_MD, "Integrator bound (anti-windup)"),)
    claims = frozenset({STREAM, MODULATION})
    POINT = "after a saturated update: a leg's instant on its rounding point"

    @classmethod
    def applies(cls, run) -> bool:
        """Slot modes built in, and a long run (the overmodulation, the return into the linear
        range and three aims take room the short runs leave to the other rules)."""
        return bool(run.model.max_bits) and run.cycles >= LONG_TIMES_RUN

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: tuple(f"leg {i}" for i in range(run.model.phases))}

    def body(self):
        run, rng, m = self.run, self.rng, self.run.model
        mode = rng.randint(1, len(MODES) - 1)
        word = run.modulation_word(legal=True, mode=mode, bits=m.max_bits)
        run.nominal[regs.MODULATION] = word
        yield from run.settle(run.write(regs.MODULATION, word))
        if not m.core.saturated:
            run.stream.kind = "overmodulation"
            yield from run.until(lambda: m.core.saturated, limit=20_000)
        run.stream.kind = "linear"
        yield from run.updates(4)

        def codes():
            legs = [int(b.split()[1]) for b in run.coverage.open_bins(self.POINT)]
            return run.stream.held_integrators_codes(rng.choice(legs or range(m.phases)), mode)

        yield from run.aimed_beat(codes, "held")
        run.stream.kind = "sine"


class SortTies(TopSequence):
    """MDFQM updates at the sorts' ties: beats aimed so that the update that takes each has two
    legs' T equal or one step (N) apart, where sort1's tie-break decides their order, or its
    two largest candidates equal or close, where the smallest j wins; foreseen from the
    integrators of the model run ahead (as the core's ``ties`` scenario:
    mdfqm_testkit.core_stimulus.aimed_tie)."""

    rules = (doc(CONTRACT_MD, "Sort1 (N-input sort) tie-break"),
             doc(CONTRACT_MD, "Candidates and the two selection rules"))
    claims = frozenset({STREAM, MODULATION})
    POINT = "MDFQM update at a tie of the sorts"
    #: aims a trial makes at most (it ends earlier, half the time, once the bins are hit)
    AIMS = 8

    @classmethod
    def applies(cls, run) -> bool:
        """Long runs (each aim runs a copy of the model ahead to the update)."""
        return run.cycles >= LONG_TIMES_RUN

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: TIE_BINS}

    def body(self):
        run = self.run
        if run.model.max_bits:  # MDFQM: the legs' order and the largest candidate decide
            word = run.modulation_word(mode=0)
            run.nominal[regs.MODULATION] = word
            yield from run.settle(run.write(regs.MODULATION, word))
        run.stream.kind = "linear"
        for _ in range(self.AIMS):
            if not run.coverage.open_bins(self.POINT) and self.rng.random() < 0.5:
                break
            yield from run.aimed_beat(run.stream.sort_tie_codes, "sort tie")
        run.stream.kind = "sine"


class CommonMode(ReferenceBeats):
    """References with a common-mode offset of up to half the DC bus: removed exactly."""

    rules = (robustness("common-mode offset on the reference"),)
    KIND = "common mode"
    POINT = "beat with a common-mode offset"
    BINS = ("accepted",)


class ExtremeCodes(ReferenceBeats):
    """Beats of the most negative and most positive codes (and the middle of the range)."""

    rules = (robustness("extreme codes"),)
    KIND = "extreme"
    POINT = "beat of extreme codes"
    BINS = ("accepted",)


class Ties(ReferenceBeats):
    """Beats with equal references on two or more legs."""

    rules = (robustness("equal references (ties)"),)
    KIND = "ties"
    POINT = "beat with equal references"
    BINS = ("accepted",)


class RefArbitration(TopSequence):
    """References written to REF[i] and committed (CMD.REF_COMMIT): a committed register beat
    wins over the port's (ready low, the port's beat held), a commit while one is pending
    replaces it, a commit in the clock a port beat is accepted; STATUS.REF_PENDING read."""

    rules = (robustness("a reference beat while one is pending"),
             doc(TOP_MD, "Reference input: which wins"), rdl("REF.REF"), rdl("CMD.REF_COMMIT"),
             rdl("STATUS.REF_PENDING"))
    claims = frozenset({REF, STREAM})
    POINT = "register reference"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("committed", "commit while one is pending",
                            "port beat held while one is pending",
                            "commit in the clock a port beat is accepted",
                            "STATUS.REF_PENDING read 1")}

    def body(self):
        run, rng = self.run, self.rng
        codes = run.stream.sine_codes()
        writes = [run.write(regs.REF_BASE + i, pack([c], 32)) for i, c in enumerate(codes)]
        against = "commit in the clock a port beat is accepted"
        if against in run.coverage.open_bins(self.POINT):
            run.stream.eager = True
            yield from run.aimed(lambda: run.command(regs.CMD_REF_COMMIT,
                                                     aim=run.aim(run.moment_beat)),
                                 self.POINT, against)
        writes.append(run.command(regs.CMD_REF_COMMIT))
        if rng.random() < 0.5:
            writes.append(run.command(regs.CMD_REF_COMMIT))
        run.stream.eager = rng.random() < 0.5
        writes.append(run.read(regs.STATUS))
        yield from run.settle(*writes)
        run.stream.eager = False
        yield from run.wait(rng.randint(5, 60))
        yield from run.settle(run.read(regs.REF_BASE + rng.randrange(run.model.phases)))


# ---------------------------------------------------------------------- sync and reset


class SyncPulses(TopSequence):
    """sync_in pulses at any phase of an update: ignored while the update in flight has not
    committed, else the next clock starts an update (in a slot mode, with its threshold, cutting
    its layout short)."""

    rules = (robustness("sync_in at any time"), doc(TOP_MD, "Several instances"))
    claims = frozenset({SYNC})
    POINT = "sync pulse"

    @classmethod
    def coverpoints(cls, run):
        bins = ("ignored: update in flight", "starts the next update")
        if run.model.max_bits:
            bins += ("starts the next update in a slot mode",)
        return {cls.POINT: bins}

    def body(self):
        run, rng = self.run, self.rng
        for _ in range(rng.randint(1, 6)):
            yield from run.wait(rng.randrange(max(2, min(run.model.core.p_lat, 400))))
            run.sync_in = 1
            yield


class ResetMidUpdate(TopSequence):
    """A reset in an update start's clock, in the middle of an update or inside a slot layout:
    every register to its reset value, the update dropped; then the firmware's start-up again,
    and the first beat one whose largest candidates tie (MDFQM), or one on the half-slot grid
    into a slot mode's first update (its instants on the quantiser's decision boundaries): in
    each slot mode at the finest b, one with an instant exactly on its rounding point and one
    with an instant just below it, chosen from the empty integrators' ``T = R``."""

    rules = (robustness("reset in the middle of an update"),
             doc(CONTRACT_MD, "b-bit pulse-width resolution: the gating-signal generator"))
    claims = ALL
    weight = 2.0
    POINT = "reset"
    FIRST = "first beat after a reset"
    ROUNDING = "slot mode at the finest b: an instant at its rounding point"

    @staticmethod
    def rounding_bin(mode: int, place: str) -> str:
        return f"{MODES[mode]}: {place}"

    @classmethod
    def coverpoints(cls, run):
        points = {cls.POINT: ("in an update start's clock", "in the middle of an update")
                  + (("inside a slot layout",) if run.model.max_bits else ())}
        first = []
        if run.model.rule == "largest_duty":
            first.append("largest candidates tie")
        if run.model.max_bits:
            first.append("on the half-slot grid into a slot mode")
        if first:
            points[cls.FIRST] = tuple(first)
        if run.model.max_bits:
            points[cls.ROUNDING] = tuple(cls.rounding_bin(mode, place)
                                         for mode in range(1, len(MODES))
                                         for place in ROUNDING_PLACES)
        return points

    def body(self):
        run, rng = self.run, self.rng
        where = rng.choice(run.coverage.open_bins(self.POINT) or ["in the middle of an update"])
        moment = {"in an update start's clock": run.moment_update_start,
                  "inside a slot layout": run.moment_in_layout}.get(where, run.moment_mid_update)
        if where == "inside a slot layout":         # a layout of a few slots in force first
            word = run.modulation_word(mode=rng.randint(1, len(MODES) - 1),
                                       bits=rng.randint(1, 3))
            yield from run.settle(run.write(regs.MODULATION, word),
                                  run.write(regs.PERIOD, rng.randint(60, 200)))
            yield from run.updates(2)
        yield from run.until(lambda: moment(0), limit=4 * run.model.core.p_lat + 50)
        run.rst = 1
        yield
        first = run.coverage.open_bins(self.FIRST) or ["largest candidates tie"]
        rounding = run.coverage.open_bins(self.ROUNDING) if run.model.max_bits else []
        grid = bool(rounding) or (rng.choice(first) == "on the half-slot grid into a slot mode"
                                  and run.model.max_bits)
        run.stream.stalled = True
        bits = rng.randint(1, run.model.max_bits) if grid else 0
        mode = rng.randint(1, len(MODES) - 1)
        places = ()
        if rounding:        # aimed at an open bin: its mode at the finest b
            name, place = rng.choice(rounding).split(": ")
            mode, bits, places = MODES.index(name), run.model.max_bits, (place,)
        if grid:
            word = run.modulation_word(legal=True, mode=mode, bits=bits)
            run.nominal[regs.MODULATION] = word
            yield from run.settle(run.write(regs.MODULATION, word))
        else:
            run.nominal[regs.MODULATION] = 0
        yield from Operate(run).body()
        run.stream.first_after_reset(bits, mode, places)
        run.stream.stalled = False
        yield from run.updates(2)


# --------------------------------------------------------------------- fault and watchdog


class FaultLatch(TopSequence):
    """The fault pin: a pulse, chatter, a rise while a leg's dead time runs; a clear while
    the synchronised input is high (does nothing) and once it is low; STATUS.FAULT and
    STATUS.FAULT_INPUT read meanwhile."""

    rules = (robustness("fault input chatter, fault during a dead time"), doc(TOP_MD, "Fault"),
             rdl("CMD.FAULT_CLEAR"), rdl("STATUS.FAULT"), rdl("STATUS.FAULT_INPUT"))
    claims = frozenset({FAULT})
    POINT = "fault pin"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("chatter", "raised in a dead time", "clear while the input is high",
                            "clear once the input is low", "STATUS.FAULT read 1",
                            "STATUS.FAULT_INPUT read 1")}

    def body(self):
        run, rng = self.run, self.rng
        pick = rng.choice(run.coverage.open_bins(self.POINT) or ["pulse"])
        if pick == "raised in a dead time":
            yield from run.until(lambda: run.moment_in_dead_time(0), limit=3000)
        if pick == "chatter":
            for _ in range(rng.randint(4, 12)):
                run.fault_in ^= 1
                yield from run.wait(rng.randint(1, 3))
        run.fault_in = 1
        yield from run.wait(rng.randint(1, 4))
        yield from run.settle(run.read(regs.STATUS), run.command(regs.CMD_FAULT_CLEAR),
                              run.read(regs.STATUS))
        run.fault_in = 0
        yield from run.wait(rng.randint(3, 20))
        yield from run.settle(run.command(regs.CMD_FAULT_CLEAR), run.read(regs.STATUS))


class Watchdog(TopSequence):
    """The reference stream stalls with WATCHDOG set (1, 2 .. 7, 8 and above): the update start
    after WATCHDOG quiet ones trips (STATUS.WATCHDOG, WATCHDOG_TRIPS polled back to back), a
    reference in the tripping start's own clock is too late, WATCHDOG lowered below the quiet
    count trips at the next start, CMD.WATCHDOG_CLEAR ends it and the count starts again."""

    rules = (robustness("the controller stops sending references"),
             doc(TOP_MD, "Reference watchdog"), rdl("WATCHDOG.TIMEOUT"),
             rdl("WATCHDOG_TRIPS.TRIPS"), rdl("CMD.WATCHDOG_CLEAR"), rdl("STATUS.WATCHDOG"))
    claims = frozenset({WATCHDOG, STREAM, REF, PERIOD, MODULATION})
    POINT = "watchdog"
    OCTAVES = "tripped at a TIMEOUT in"

    @classmethod
    def applies(cls, run) -> bool:
        return run.model.watchdog

    @classmethod
    def octave_edges(cls, run) -> tuple[int, ...]:
        """Octaves of TIMEOUT that trip (each sets its bit of the quiet count the trip needs),
        to 2**8, in runs long enough for their quiet updates (none in shorter ones)."""
        return tuple(1 << k for k in range(9)) if run.cycles >= PERIOD_BAND_RUN else ()

    @classmethod
    def coverpoints(cls, run):
        points = {cls.POINT: ("tripped at TIMEOUT 1", "tripped at TIMEOUT 2..7",
                              "tripped at TIMEOUT 8..", "a reference in the tripping start's "
                              "clock", "TIMEOUT lowered below the quiet count",
                              "cleared", "STATUS.WATCHDOG read 1")}
        edges = cls.octave_edges(run)
        return {**points, cls.OCTAVES: tuple(bands(edges))} if edges else points

    def body(self):
        run, rng = self.run, self.rng
        model = run.model
        octaves = run.coverage.open_bins(self.OCTAVES)
        # the octaves first: a trip in each also covers the TIMEOUT bins of the point
        pick = rng.choice(octaves or run.coverage.open_bins(self.POINT)
                          or ["tripped at TIMEOUT 1"])
        if pick in octaves:             # a TIMEOUT inside that octave
            low = band_low(pick)
            timeout = low + rng.randrange(low)
        else:
            timeout = {"tripped at TIMEOUT 1": 1, "tripped at TIMEOUT 8..": rng.choice([8, 9, 13]),
                       "TIMEOUT lowered below the quiet count": 8}.get(pick, rng.randint(2, 7))
        # short updates for the long timeouts (a trip takes TIMEOUT of them): MDFQM's, not a
        # slot mode's at a large b (at least 2**b clocks)
        period = rng.randint(20, 40) if pick in octaves else rng.choice([90, rng.randint(20, 40)])
        settings = [run.write(regs.PERIOD, period), run.write(regs.WATCHDOG, timeout)]
        if pick in octaves and model.max_bits:
            settings.append(run.write(regs.MODULATION, run.modulation_word(mode=0)))
        yield from run.settle(*settings)
        run.stream.stalled = True
        if pick in octaves:             # the quiet updates first, then the polling below
            yield from run.until(lambda: model.wd_quiet + 2 >= timeout or model.wd_tripped,
                                 limit=(timeout + 2) * (run.update_clocks(period) + 8))
        if pick == "TIMEOUT lowered below the quiet count":
            yield from run.until(lambda: model.wd_quiet >= 3, limit=5000)
            yield from run.settle(run.write(regs.WATCHDOG, rng.randint(1, 2)))
        elif pick == "a reference in the tripping start's clock":
            moment = run.aim(run.moment_watchdog_trip, patience=65_536 * (timeout + 2),
                             unless=lambda: model.wd_tripped)
            yield from run.settle(run.command(regs.CMD_REF_COMMIT, aim=moment))
        for _ in range(400):              # firmware polls the trips back to back
            if model.wd_tripped:
                break
            yield from run.settle(run.read(regs.WATCHDOG_TRIPS))
        yield from run.settle(run.read(regs.STATUS), run.read(regs.WATCHDOG_TRIPS))
        run.stream.stalled = False
        yield from run.wait(rng.randint(10, 200))
        yield from run.settle(run.command(regs.CMD_WATCHDOG_CLEAR),
                              run.restore(regs.WATCHDOG, regs.PERIOD, regs.MODULATION),
                              run.read(regs.STATUS))


class WatchdogNotBuiltIn(TopSequence):
    """Without the watchdog built in: WATCHDOG written non-zero stores 0 (read back), the
    reference stream stalls for more update starts than the value written and nothing trips
    (STATUS, WATCHDOG_TRIPS read), CMD.WATCHDOG_CLEAR changes nothing."""

    rules = (doc(TOP_MD, "Reference watchdog"), rdl("WATCHDOG.TIMEOUT", clamp=True),
             rdl("INFO.WATCHDOG"), rdl("CMD.WATCHDOG_CLEAR"), rdl("STATUS.WATCHDOG"))
    claims = frozenset({WATCHDOG, STREAM, REF, PERIOD, MODULATION})
    POINT = "watchdog not built in"

    @classmethod
    def applies(cls, run) -> bool:
        return not run.model.watchdog

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("WATCHDOG written non-zero", "more update starts without a "
                            "reference than WATCHDOG written", "CMD.WATCHDOG_CLEAR written")}

    def body(self):
        run, rng = self.run, self.rng
        timeout = rng.randint(1, 3)
        period = rng.randint(20, 40)
        settings = [run.write(regs.PERIOD, period), run.write(regs.WATCHDOG, timeout)]
        if run.model.max_bits:      # MDFQM's short updates: the stall lasts a few of them
            settings.append(run.write(regs.MODULATION, run.modulation_word(mode=0)))
        yield from run.settle(*settings, run.read(regs.WATCHDOG))
        run.stream.stalled = True
        yield from run.wait((timeout + 3) * (run.update_clocks(period) + 8))
        yield from run.settle(run.read(regs.STATUS), run.read(regs.WATCHDOG_TRIPS),
                              run.command(regs.CMD_WATCHDOG_CLEAR), run.read(regs.STATUS))
        run.stream.stalled = False
        yield from run.settle(run.restore(regs.WATCHDOG, regs.PERIOD, regs.MODULATION))


class FaultReaction(TopSequence):
    """FAULT_REACTION per source (all off, ASC low, ASC high): the fault or a watchdog trip
    enters it through the dead time; FAULT_REACTION rewritten while in force changes nothing;
    left through all off only: CMD.ALL_OFF, the clear, or a second source whose reaction is
    all off; STATUS.REACTION read meanwhile."""

    rules = (robustness("a fault or a watchdog trip with an active short circuit chosen"),
             doc(TOP_MD, "Fault reaction"), rdl("FAULT_REACTION.FAULT"),
             rdl("FAULT_REACTION.WATCHDOG"), rdl("CMD.ALL_OFF"), rdl("STATUS.REACTION"))
    claims = frozenset({FAULT, WATCHDOG, STREAM, REF, PERIOD})
    POINT = "reaction in force"
    LEFT = "active short circuit left"

    @classmethod
    def coverpoints(cls, run):
        model = run.model
        # the watchdog is the second source, when it is built in
        sources = ("fault", "watchdog") if model.watchdog else ("fault",)
        if not model.asc:
            return {cls.POINT: tuple(f"all off ({source})" for source in sources)}
        return {cls.POINT: (*(f"ASC {side} ({source})" for source in sources
                              for side in ("low", "high")),
                            *(f"all off ({source})" for source in sources),
                            "rewritten while an ASC is in force"),
                cls.LEFT: ("by CMD.ALL_OFF", "by the clear",
                           *(("by a second source whose reaction is all off",)
                             if model.watchdog else ()))}

    def body(self):
        run, rng = self.run, self.rng
        model = run.model
        wanted = run.coverage.open_bins(self.POINT) + run.coverage.open_bins(self.LEFT)
        pick = rng.choice(wanted or ["ASC low (fault)"])
        source = "watchdog" if "watchdog" in pick or "second source" in pick else "fault"
        code = 1 if "low" in pick else 2 if "high" in pick else (
            0 if "all off" in pick else rng.randint(1, 2))
        other = 0 if "second source" in pick else rng.randrange(4)
        fault_code, watchdog_code = ((code, other) if source == "fault" else (other, code))
        if "second source" in pick:
            fault_code, watchdog_code = rng.randint(1, 2), 0
            source = "fault"
        reaction = (fault_code << regs.FAULT_REACTION_FAULT_SHIFT
                    | watchdog_code << regs.FAULT_REACTION_WATCHDOG_SHIFT)
        yield from run.settle(run.write(regs.FAULT_REACTION, reaction),
                              run.write(regs.PERIOD, rng.choice([90, rng.randint(20, 40)])))
        if source == "fault":
            run.fault_in = 1
        else:
            run.stream.stalled = True
            yield from run.settle(run.write(regs.WATCHDOG, 1))
        yield from run.until(lambda: model.driver.fault or model.wd_tripped, limit=5000)
        run.stream.stalled = False
        yield from run.wait(rng.randint(model.dead_min, 3 * model.dead_min))
        yield from run.settle(run.read(regs.STATUS))
        if "rewritten" in pick:
            yield from run.settle(run.write(regs.FAULT_REACTION, rng.getrandbits(4)),
                                  run.read(regs.STATUS))
        if "second source" in pick:
            run.stream.stalled = True
            yield from run.settle(run.write(regs.WATCHDOG, 1))
            yield from run.until(lambda: model.wd_tripped, limit=5000)
            run.stream.stalled = False
        elif "ALL_OFF" in pick or (rng.random() < 0.3 and "clear" not in pick):
            yield from run.settle(run.command(regs.CMD_ALL_OFF), run.read(regs.STATUS))
        yield from run.wait(rng.randint(2, 40))
        run.fault_in = 0
        yield from run.wait(4)
        yield from run.settle(run.write(regs.WATCHDOG, 0),
                              run.command(regs.CMD_FAULT_CLEAR | regs.CMD_WATCHDOG_CLEAR),
                              run.read(regs.STATUS),
                              run.restore(regs.FAULT_REACTION, regs.PERIOD))


# ------------------------------------------------------------------ interrupt and counters


class IrqService(TopSequence):
    """Interrupt service as firmware does it: IRQ_ENABLE written (undefined bits too), irq
    raised by each source, IRQ_STATUS read and written 1 to clear, also in the very clock of a
    new event of that source (the event wins); a source that has not raised irq yet is
    provoked the same way, with it alone enabled."""

    rules = (robustness("IRQ_ENABLE with undefined bits"), doc(TOP_MD, "Interrupt"),
             *(rdl(f"IRQ_ENABLE.{name}") for name in IRQ_SOURCES),
             *(rdl(f"IRQ_STATUS.{name}") for name in IRQ_SOURCES))
    claims = frozenset({IRQ})
    SET = "interrupt source set"
    RAISED = "irq raised by"
    SAME_CLOCK = "IRQ_STATUS cleared in the clock of a new event of"
    UNDEFINED = "undefined bits written"
    SAME_CLOCK_SOURCES = ("FAULT", "SAMPLE", "SHORT_EDGE", "WATCHDOG")

    @classmethod
    def sources(cls, run):
        wrap = run.wrap_reachable()
        return [name for name in IRQ_SOURCES if (name != "COUNTER_WRAP" or wrap)
                and (name != "WATCHDOG" or run.model.watchdog)]

    @classmethod
    def coverpoints(cls, run):
        sources = cls.sources(run)
        return {cls.SET: tuple(sources), cls.RAISED: tuple(sources),
                cls.SAME_CLOCK: tuple(name for name in cls.SAME_CLOCK_SOURCES
                                      if name in sources),
                cls.UNDEFINED: ("IRQ_ENABLE", "IRQ_STATUS")}

    def __init__(self, run):
        super().__init__(run)
        # a source whose bins are open is provoked: its event aimed at a clear of its bit
        pool = run.coverage.open_bins(self.SAME_CLOCK) or [
            name for name in run.coverage.open_bins(self.RAISED)
            if name in self.SAME_CLOCK_SOURCES]
        self.source = self.rng.choice(pool) if pool else None
        self.claims = frozenset({IRQ} | {"FAULT": {FAULT},
                                         "WATCHDOG": {WATCHDOG, STREAM, REF, PERIOD},
                                         "SHORT_EDGE": {MODULATION, PERIOD},
                                         }.get(self.source, set()))

    def body(self):
        run, rng = self.run, self.rng
        enable = rng.choice([regs.IRQ_MASK, rng.getrandbits(32), rng.getrandbits(5)])
        not_raised = run.coverage.open_bins(self.RAISED)
        if self.source in not_raised:
            # irq rises for the provoked source only while no other enabled source holds it
            # high: that source alone enabled (the undefined bits still drawn)
            enable = IRQ_SOURCES[self.source] | (enable & ~regs.IRQ_MASK)
        else:
            for name in not_raised:         # the sources not seen raise irq
                enable |= IRQ_SOURCES[name]
        run.nominal[regs.IRQ_ENABLE] = enable & regs.IRQ_MASK
        yield from run.settle(run.write(regs.IRQ_ENABLE, enable), run.read(regs.IRQ_ENABLE))
        if self.source is not None:
            yield from self.clear_in_the_clock_of_an_event(IRQ_SOURCES[self.source])
        for _ in range(rng.randint(1, 4)):      # service: read, clear what was read
            yield from run.until(lambda: run.model.irq, limit=rng.randint(20, 400))
            status = run.read(regs.IRQ_STATUS)
            yield from run.settle(status)
            yield from run.settle(run.write(regs.IRQ_STATUS, run.value(status)
                                            | rng.choice([0, rng.getrandbits(32)])))

    def clear_in_the_clock_of_an_event(self, bit):
        """The source's bit cleared first, then written 1 again in the very clock of its next
        event (the fault pin raised, the stream stalled under a short watchdog, or slots
        shorter than the dead time, when the source is one of those)."""
        run, rng = self.run, self.rng
        yield from run.settle(run.write(regs.IRQ_STATUS, regs.IRQ_MASK))
        if self.source == "FAULT":
            run.fault_in = 1
        elif self.source == "WATCHDOG":
            run.stream.stalled = True
            yield from run.settle(run.write(regs.PERIOD, rng.randint(20, 90)),
                                  run.write(regs.WATCHDOG, rng.randint(1, 3)))
        elif self.source == "SHORT_EDGE":
            if run.model.max_bits:
                yield from run.settle(run.write(regs.MODULATION, run.modulation_word(
                    mode=rng.randint(1, len(MODES) - 1), bits=min(2, run.model.max_bits))))
            yield from run.settle(run.write(regs.PERIOD, rng.randint(run.model.latency, 48)))
            yield from run.updates(2)
        model = run.model

        def gone() -> bool:
            """The event cannot come any more: the latch it sets is set already."""
            return bool(model.wd_tripped if self.source == "WATCHDOG"
                        else model.driver.fault if self.source == "FAULT" else False)

        patience = 65_536 * 5 if self.source == "WATCHDOG" else None
        attempts = 1 if self.source in ("FAULT", "WATCHDOG") else 4    # once per latch rise
        yield from run.aimed(lambda: run.write(
            regs.IRQ_STATUS, bit | rng.getrandbits(32),
            aim=run.aim(run.source_moment(self.source), patience=patience, unless=gone)),
            self.SAME_CLOCK, self.source, attempts)
        if self.source == "FAULT":
            yield from run.wait(rng.randint(1, 8))
            run.fault_in = 0
            yield from run.wait(4)
            yield from run.settle(run.command(regs.CMD_FAULT_CLEAR))
        elif self.source == "WATCHDOG":
            run.stream.stalled = False
            yield from run.settle(run.restore(regs.WATCHDOG, regs.PERIOD),
                                  run.command(regs.CMD_WATCHDOG_CLEAR))
        elif self.source == "SHORT_EDGE":
            yield from run.settle(run.restore(regs.MODULATION, regs.PERIOD))


class Counters(TopSequence):
    """The switching counters: EVENTS[i], EVENTS_TOTAL and GATES read, EVENTS_TOTAL after two
    legs turned on in one clock, CMD.COUNT_CLEAR in the very clock of a turn-on (that clock's
    turn-ons not counted), EVENTS_TOTAL past 2**counter_width where a run can reach it: while
    that bin or COUNTER_WRAP's interrupt bins are open, a wrap is brought about (short updates
    in a slot mode, no clear meanwhile, IRQ_ENABLE.COUNTER_WRAP alone set and IRQ_STATUS
    cleared, so that the wrap raises irq) and served (EVENTS_TOTAL and IRQ_STATUS read, the
    bit cleared)."""

    rules = (doc(TOP_MD, "Switching counters"), rdl("EVENTS_TOTAL.EVENTS_TOTAL"),
             rdl("EVENTS.EVENTS"), rdl("CMD.COUNT_CLEAR"), rdl("GATES.UPPER"),
             rdl("GATES.LOWER"), rdl("IRQ_STATUS.COUNTER_WRAP"),
             robustness("IRQ_ENABLE with undefined bits"))
    claims = frozenset({COUNTERS})
    POINT = "switching counters"
    WRAPPED = "EVENTS_TOTAL wrapped"

    @classmethod
    def coverpoints(cls, run):
        bins = [f"EVENTS[{i}] read" for i in range(run.model.phases)]
        bins += ["EVENTS_TOTAL read after two legs turned on in one clock",
                 "COUNT_CLEAR in the clock of a turn-on", "GATES read with an upper gate on",
                 "GATES read with a lower gate on"]
        if run.wrap_reachable():
            bins.append(cls.WRAPPED)
        return {cls.POINT: tuple(bins)}

    def __init__(self, run):
        super().__init__(run)
        coverage = run.coverage
        self.wrap = run.wrap_reachable() and (
            self.WRAPPED in coverage.open_bins(self.POINT)
            or any("COUNTER_WRAP" in coverage.open_bins(point)
                   for point in (IrqService.SET, IrqService.RAISED)))
        if self.wrap:
            # the gates kept switching too: no disable, fault or watchdog trip meanwhile
            self.claims = frozenset({COUNTERS, IRQ, PERIOD, MODULATION, CTRL, FAULT, WATCHDOG})

    def body(self):
        if self.wrap:
            yield from self._wrap()
            return
        run, rng = self.run, self.rng
        open_ = run.coverage.open_bins(self.POINT)
        if "COUNT_CLEAR in the clock of a turn-on" in open_ or rng.random() < 0.2:
            yield from run.aimed(lambda: run.command(regs.CMD_COUNT_CLEAR,
                                                     aim=run.aim(run.moment_turn_on)),
                                 self.POINT, "COUNT_CLEAR in the clock of a turn-on")
        if "EVENTS_TOTAL read after two legs turned on in one clock" in open_:
            run.two_on_since_read = False
            yield from run.until(lambda: run.two_on_since_read, limit=3000)
        reads = [run.read(regs.EVENTS_BASE + i) for i in range(run.model.phases)]
        yield from run.settle(*reads, run.read(regs.EVENTS_TOTAL), run.read(regs.GATES))

    def _wrap(self):
        """EVENTS_TOTAL brought past 2**counter_width: every leg turns on once an update of a
        few dozen clocks (a slot mode at a b whose minimum period is below it; the MDFQM-only
        top switches as its references make it), no clear meanwhile; its interrupt alone
        enabled, then served."""
        run, rng = self.run, self.rng
        model = run.model
        period = rng.randint(30, 60)
        settings = [run.write(regs.PERIOD, period)]
        if model.max_bits:
            settings.append(run.write(regs.MODULATION, run.modulation_word(
                mode=rng.randint(1, len(MODES) - 1), bits=min(3, model.max_bits))))
        yield from run.settle(*settings, run.write(regs.IRQ_ENABLE, regs.IRQ_COUNTER_WRAP),
                              run.write(regs.IRQ_STATUS, regs.IRQ_MASK))
        before = run.coverage.count(self.POINT, self.WRAPPED)
        # at least one turn-on an update (slot modes), each within the period asked for
        yield from run.until(lambda: (run.coverage.count(self.POINT, self.WRAPPED) > before
                                      or not model.driver.active),
                             limit=((1 << model.counter_width) + 8) * (period + 8))
        status = run.read(regs.IRQ_STATUS)
        yield from run.settle(run.read(regs.EVENTS_TOTAL), status)
        yield from run.settle(run.write(regs.IRQ_STATUS, regs.IRQ_COUNTER_WRAP),
                              run.restore(regs.IRQ_ENABLE, regs.PERIOD, regs.MODULATION))


# ------------------------------------------------------------------- the bus, any register


class BusHandshakes(TopSequence):
    """Back-to-back accesses to any word (mapped, read-only, unmapped) through the master's
    handshake policies: Wishbone ``cyc`` before ``stb``, ``cyc`` or ``stb`` alone while idle;
    AXI4-Lite AW and W in any order, responses held by ``bready``/``rready`` low with the
    next access waiting, SLVERR for a word that holds no register, strobes ignored."""

    rules = (robustness("AXI4-Lite: an access to a word that holds no register"),
             robustness("Wishbone: stb without cyc"), doc(TOP_MD, "Register bus"))
    POINT = "bus handshake"
    WISHBONE = ("cyc alone while idle", "stb alone while idle", "cyc raised before stb",
                "stb held in the ack clock")
    AXI = ("AW before W", "W before AW", "AW and W together", "B held by bready low",
           "R held by rready low", "next AW while B waits", "SLVERR write", "SLVERR read",
           "wstrb other than 0xF")

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: cls.AXI if run.axi else cls.WISHBONE}

    def body(self):
        run, rng = self.run, self.rng
        accesses = []
        for _ in range(rng.randint(3, 12)):
            address = rng.choice([rng.randrange(64), regs.ID, regs.STATUS, 0x33 + rng.randrange(13),
                                  regs.REF_BASE + run.model.phases + rng.randrange(2)])
            if rng.random() < 0.5 or address in (regs.STATUS, regs.ID):
                accesses.append(run.read(address))
            elif address not in run.mapped_writable:
                accesses.append(run.write(address, rng.getrandbits(32)))
        yield from run.settle(*accesses)


class Identification(TopSequence):
    """ID, INFO and DEAD_MIN read, written (ignored) and read again."""

    rules = (rdl("ID.ID"), *(rdl(f"INFO.{f}") for f in (
        "PHASES", "WIDTH", "RULE", "UPPER_ACTIVE_LOW", "LOWER_ACTIVE_LOW", "ASC", "WATCHDOG",
        "LATENCY", "MAX_BITS", "MODES")), rdl("DEAD_MIN.DEAD_MIN"))
    POINT = "identification"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("ID read", "INFO read", "DEAD_MIN read", "written, ignored")}

    def body(self):
        run, rng = self.run, self.rng
        for address in rng.sample([regs.ID, regs.INFO, regs.DEAD_MIN], 3):
            yield from run.settle(run.read(address), run.write(address, rng.getrandbits(32)),
                                  run.read(address))


class ClampWalk(TopSequence):
    """A field written at and beyond the values its clamp changes, walking a one over the
    whole word and a zero over the field, each read back (docs/top.md, "Every clamp, in one
    place"); the setting then restored. Subclasses name the field."""

    REGISTER = 0
    FIELD = ""
    POINT = ""
    #: the gates are disabled first (a dead time or minimum pulse of 65535 clocks never in force)
    GATES_OFF = False
    #: each word written, read and replaced by MEDIUM between two update starts (a long PERIOD
    #: never taken), MEDIUM in force meanwhile
    BETWEEN_STARTS = False
    MEDIUM = 400

    @classmethod
    def values(cls, run) -> dict:
        """bin name -> the word written."""
        raise NotImplementedError

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: tuple(cls.values(run))}

    @staticmethod
    def walk(width: int, field: int) -> dict:
        ones = {f"one at bit {k}": 1 << k for k in range(width)}
        zeros = {f"zero at bit {k}": ((1 << field) - 1) ^ (1 << k) for k in range(field)}
        return {**ones, **zeros}

    def body(self):
        run = self.run
        values = self.values(run)
        todo = [name for name in run.coverage.open_bins(self.POINT) if name in values]
        todo = todo or self.rng.sample(sorted(values), min(6, len(values)))
        if self.GATES_OFF:
            yield from run.settle(run.write(regs.CTRL, run.nominal[regs.CTRL]
                                            & ~regs.CTRL_ENABLE))
            driver = run.model.driver
            yield from run.until(lambda: not (driver.up | driver.lo or driver.active
                                              or driver.reaction), limit=70_000)
        if self.BETWEEN_STARTS:        # a period with room for a write, a read and a restore
            yield from run.settle(run.write(self.REGISTER, self.MEDIUM))
            yield from run.updates(2)
        for name in todo:
            if self.BETWEEN_STARTS:
                room = yield from run.until(run.room_before_start, limit=2 * self.MEDIUM)
                if not room:
                    continue
            yield from run.settle(run.write(self.REGISTER, values[name]),
                                  run.read(self.REGISTER),
                                  *([run.write(self.REGISTER, self.MEDIUM)]
                                    if self.BETWEEN_STARTS else ()))
        yield from run.settle(run.restore(self.REGISTER))
        if self.GATES_OFF:
            yield from run.settle(run.restore(regs.CTRL))


def _unsigned_clamp(field: int, top: int, extra: dict) -> dict:
    """The words that decide an unsigned saturating clamp: 0, 1, the largest value stored and
    the next, all ones, and a single one over the whole word and a single zero in the field."""
    values = {"0": 0, "1": 1, f"{top}": top, f"{top + 1}": top + 1, "all ones": 0xFFFF_FFFF}
    return {**values, **extra, **ClampWalk.walk(32, field)}


class PeriodClamp(ClampWalk):
    """PERIOD at and beyond its clamp (saturated at 65535), each value read back."""

    rules = (rdl("PERIOD.PERIOD", clamp=True), doc(TOP_MD, "Every clamp, in one place"),
             robustness("any value to any register"))
    claims = frozenset({PERIOD, SYNC})      # a sync pulse would start an update meanwhile
    REGISTER, POINT, BETWEEN_STARTS = regs.PERIOD, "PERIOD written at its clamp", True

    @classmethod
    def values(cls, run):
        return _unsigned_clamp(16, 0xFFFF, {})


class OsrClamp(ClampWalk):
    """OSR at and beyond its clamp (saturated at 255), each value read back."""

    rules = (rdl("OSR.OSR", clamp=True),)
    claims = frozenset({OSR})
    REGISTER, POINT = regs.OSR, "OSR written at its clamp"

    @classmethod
    def values(cls, run):
        return _unsigned_clamp(8, 0xFF, {})


class DeadClamp(ClampWalk):
    """DEAD at and beyond its clamp (raised to dead_min, saturated at 65535), read back, the
    gates disabled meanwhile."""

    rules = (rdl("DEAD.DEAD", clamp=True),)
    claims = frozenset({DEAD, CTRL, FAULT, WATCHDOG})
    REGISTER, POINT, GATES_OFF = regs.DEAD, "DEAD written at its clamp", True

    @classmethod
    def values(cls, run):
        floor = run.model.dead_min
        return _unsigned_clamp(16, 0xFFFF, {"below dead_min": floor - 1,
                                                "dead_min": floor})


class MinPulseClamp(ClampWalk):
    """MIN_PULSE at and beyond its clamp (saturated at 65535), read back, the gates disabled
    meanwhile."""

    rules = (rdl("MIN_PULSE.MIN_PULSE", clamp=True),)
    claims = frozenset({DEAD, CTRL, FAULT, WATCHDOG})
    REGISTER, POINT, GATES_OFF = regs.MIN_PULSE, "MIN_PULSE written at its clamp", True

    @classmethod
    def values(cls, run):
        return _unsigned_clamp(16, 0xFFFF, {})


class AdcOffsetClamp(ClampWalk):
    """ADC_OFFSET at and beyond its clamp (saturated at 65535), each value read back."""

    rules = (rdl("ADC_OFFSET.ADC_OFFSET", clamp=True),)
    claims = frozenset({ADC})
    REGISTER, POINT = regs.ADC_OFFSET, "ADC_OFFSET written at its clamp"

    @classmethod
    def values(cls, run):
        return _unsigned_clamp(16, 0xFFFF, {})


class WatchdogClamp(ClampWalk):
    """WATCHDOG at and beyond its clamp (saturated at 65535), each value read back; the
    watchdog off and cleared again after."""

    rules = (rdl("WATCHDOG.TIMEOUT", clamp=True),)
    claims = frozenset({WATCHDOG})
    REGISTER, POINT = regs.WATCHDOG, "WATCHDOG written at its clamp"

    @classmethod
    def values(cls, run):
        return _unsigned_clamp(16, 0xFFFF, {})

    def body(self):
        yield from super().body()
        yield from self.run.settle(self.run.command(regs.CMD_WATCHDOG_CLEAR))


class FaultReactionClamp(ClampWalk):
    """FAULT_REACTION with every code in each field (3 stores all off; 1 and 2 too without the
    active short circuit built in) and bits outside them, each value read back."""

    rules = (rdl("FAULT_REACTION.FAULT", clamp=True), rdl("FAULT_REACTION.WATCHDOG", clamp=True))
    claims = frozenset({FAULT})
    REGISTER, POINT = regs.FAULT_REACTION, "FAULT_REACTION written at its clamp"

    @classmethod
    def values(cls, run):
        codes = {f"FAULT {f}, WATCHDOG {w}": f | w << 2 for f in range(4) for w in range(4)}
        return {**codes, "bits outside its fields": 0xFFFF_FFF0 | 0b0110}


class RefClamp(ClampWalk):
    """REF[i] beyond the code range: signed saturation, a single one in a positive word and a
    single zero in a negative one above the code's width, each read back sign-extended."""

    rules = (rdl("REF.REF", clamp=True),)
    claims = frozenset({REF})
    POINT = "REF written at its clamp"

    @classmethod
    def values(cls, run):
        c = run.model.contract
        values = {"code_max": c.code_max, "code_max + 1": c.code_max + 1,
                  "code_min": c.code_min, "code_min - 1": c.code_min - 1,
                  "2**31 - 1": (1 << 31) - 1, "-2**31": -(1 << 31)}
        values |= {f"one at bit {k}": 1 << k for k in range(c.width - 1, 31)}
        values |= {f"zero at bit {k}": ~(1 << k) for k in range(c.width - 1, 31)}
        return {name: pack([v], 32) for name, v in values.items()}

    def body(self):
        self.REGISTER = regs.REF_BASE + self.rng.randrange(self.run.model.phases)
        yield from super().body()


class RandomWrites(TopSequence):
    """Any word to any address, in any order (a dead time or minimum pulse of at most 63
    clocks, a period of at most 1023: a dead time in force is never shortened), then the
    firmware's settings again."""

    rules = (robustness("any value to any register"),)
    claims = ALL - {SYNC, STREAM}
    POINT = "random word written to"

    @classmethod
    def coverpoints(cls, run):
        return {cls.POINT: ("a read-write register", "a read-only register", "CMD",
                            "an unmapped word")}

    def body(self):
        run, rng = self.run, self.rng
        writes = []
        for _ in range(rng.randint(2, 10)):
            address = rng.randrange(64)
            data = rng.choice([0, 1, 3, 90, 0xFFFF]) if rng.random() < 0.3 else rng.getrandbits(32)
            if address in (regs.DEAD, regs.MIN_PULSE):
                data &= 0x3F
            elif address in (regs.PERIOD, regs.ADC_OFFSET):
                data &= 0x3FF
            writes.append(run.write(address, data))
            if rng.random() < 0.5:
                writes.append(run.read(address))
        yield from run.settle(*writes)
        yield from run.wait(rng.randint(0, 300))
        yield from run.settle(*run.restore(*run.nominal),
                              run.command(regs.CMD_FAULT_CLEAR | regs.CMD_WATCHDOG_CLEAR))


# --------------------------------------------------------------------- two events at once


class TwoEventsInOneClock(TopSequence):
    """A register write, a CMD write or an IRQ_STATUS clear aimed at the very clock of an
    update start, a beat's acceptance, a fault pin edge, the fault latch setting, a sync pulse
    or a gate turn-on: each as documented for its register (a counter clear wins over that
    clock's turn-ons, an interrupt event wins over its clear, a commit in a beat's clock waits
    for ready)."""

    rules = (robustness("two events in one clock"),)
    POINT = "an access in the clock of"

    @classmethod
    def coverpoints(cls, run):
        return {f"{cls.POINT} an event": tuple(f"{kind} / {event}" for kind in ACCESS_KINDS
                                              for event in EVENTS)}

    def __init__(self, run):
        super().__init__(run)
        point = f"{self.POINT} an event"
        pairs = run.coverage.open_bins(point) or [f"{k} / {e}" for k in ACCESS_KINDS
                                                  for e in EVENTS]
        self.kind, self.event = self.rng.choice(pairs).split(" / ")
        needs = {"fault pin edge": {FAULT}, "fault latch set": {FAULT}, "sync pulse": {SYNC},
                 "beat accepted": {STREAM}}.get(self.event, set())
        kind = {"register write": {IRQ}, "CMD write": {COUNTERS, REF},
                "IRQ_STATUS write-1-to-clear": {IRQ}}[self.kind]
        self.claims = frozenset(needs | kind)

    def body(self):
        run, rng = self.run, self.rng
        if self.kind == "register write":
            address, value = regs.IRQ_ENABLE, run.nominal[regs.IRQ_ENABLE]
        elif self.kind == "CMD write":
            address = regs.CMD
            value = rng.choice([regs.CMD_COUNT_CLEAR, regs.CMD_REF_COMMIT,
                                regs.CMD_COUNT_CLEAR | regs.CMD_REF_COMMIT])
            if self.event.startswith("fault"):
                value |= regs.CMD_FAULT_CLEAR
        else:
            address, value = regs.IRQ_STATUS, rng.getrandbits(32)
        pair = f"{self.kind} / {self.event}"
        for _ in range(4):          # again while the bus missed the moment
            moment, pin = None, None
            if self.event == "fault pin edge":
                pin = "fault_in"
            elif self.event == "sync pulse":
                pin = "sync_in"
            elif self.event == "fault latch set":
                run.fault_in = 1
                moment = run.aim(run.moment_fault_latch, patience=10,
                                 unless=lambda: run.model.driver.fault)
            else:
                moment = run.aim({"update start": run.moment_update_start,
                                  "beat accepted": run.moment_beat,
                                  "gate turn-on": run.moment_turn_on}[self.event])
                run.stream.eager = self.event == "beat accepted"
            yield from run.settle(run.write(address, value, aim=moment, with_pin=pin))
            run.stream.eager = False
            if self.event.startswith("fault"):
                yield from run.wait(rng.randint(2, 10))
                run.fault_in = 0
                yield from run.wait(4)
                yield from run.settle(run.command(regs.CMD_FAULT_CLEAR))
            if run.coverage.covered(f"{self.POINT} an event", pair):
                break


class PinPolarity(TopSequence):
    """The gates switching at pins of either polarity (the configuration's pair): each side's
    pins leave their off level; GATES read in the active-high domain."""

    rules = (robustness("any pair of pin polarities"),)

    @staticmethod
    def point(run) -> str:
        """The coverpoint of the run's polarity pair."""
        driver = run.model.driver
        upper, lower = (("low" if low else "high")
                        for low in (driver.upper_active_low, driver.lower_active_low))
        return f"pins switched on (upper active {upper}, lower active {lower})"

    @classmethod
    def coverpoints(cls, run):
        return {cls.point(run): ("upper", "lower")}

    def body(self):
        yield from self.run.settle(self.run.read(regs.GATES))
