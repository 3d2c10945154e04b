"""Closed-loop stimulus for the drop-in top (either front, any size), with the expected
outputs from :class:`mdfqm_model.top.TopModel`: used by the top's vector regression
(tb/test_top_vectors.py), the drop-in files' and the netlists' vector runs
(tb/test_dropin_files.py, tb/test_postsynth.py) and the mutation campaign (tools/mutate).

The stimulus is the specification's rules as small named sequences
(:mod:`mdfqm_testkit.top_sequences`: one per row of docs/robustness.md, per register field and
clamp of spec/rdl/mdfqm_top.rdl, per timing rule of docs/top.md), which :class:`TopRun`
schedules among random background traffic (reads of any word, writes to words that hold no
writable register, a reference stream from an FOC loop that honours ``ready``), preferring those
whose coverpoints are still open, so that a run closes its coverage by aiming, not by length.
The golden model is stepped clock by clock while generating: a sequence waits for the moment it
aims at (an update start, a beat's acceptance, the fault latch setting, a gate turn-on, ...),
read from the model's state or from a copy stepped ahead, and the coverpoints are hit from
what the model shows in each clock, never from what a sequence meant.
"""

from __future__ import annotations

import copy
import math
from collections import deque
from itertools import count

from mdfqm_model.top import TopModel
from mdfqm_model.update import candidates, remove_common_mode, sort1
from mdfqm_spec import regmap as regs
from mdfqm_spec.bus import WRITE_LATENCY, mapped_words
from mdfqm_spec.contract import FEWEST_TRANSITIONS, MODES, latch_mode, min_period
from mdfqm_testkit import top_sequences as seq
from mdfqm_testkit.bbit_stimulus import (
    boundary_codes,
    rounding_legs,
    rounding_places,
    tie_codes,
)
from mdfqm_testkit.bus_masters import MASTERS, Access
from mdfqm_testkit.core_stimulus import (
    aimed_tie,
    extreme_codes,
    linear_amplitude,
    sine_codes,
    tie_bins,
    x_at_use,
)
from mdfqm_testkit.coverage import Coverage, band
from mdfqm_testkit.harness import pack
from mdfqm_testkit.sequences import Waits
from mdfqm_testkit.vectors import ports_of

#: sequences running at once, at most (besides background traffic)
CONCURRENT = 4
#: chance per clock that the scheduler starts a sequence while fewer run
START_RATE = 0.05
#: how much more often a sequence with open coverpoints is drawn
OPEN_BOOST = 8.0
#: chance per idle bus clock of a background access
BACKGROUND_RATE = 0.01
#: the runs (clocks) of the full Wishbone top's regression (tb/test_top_vectors.py) and of its
#: mutation campaign: the first long enough for every band of the 16-bit times
FULL_TOP_RUNS = (seq.LONG_TIMES_RUN, 60_000)


class Aim:
    """The moment an access is held for: ``moment(k)`` tells whether the event happens ``k``
    clocks from now; ``lead`` clocks before it is the access's clock: the clock a read is
    issued in, or the one the register file takes a write in (``delay``, WRITE_LATENCY
    clocks after its issue: docs/top.md, "Register bus"). ``patience`` clocks later the
    access goes anyway (the moment may never come: the gates disabled, ...)."""

    def __init__(self, run, moment, lead: int, patience: int, unless=None):
        self.run, self.moment, self.lead = run, moment, lead
        self.deadline = run.cycle + patience
        self.unless = unless
        self.delay = 0

    def _given_up(self) -> bool:
        return self.run.cycle >= self.deadline or bool(self.unless and self.unless())

    def now(self) -> bool:
        """The access issued in this clock meets the moment (Wishbone: the request clock)."""
        return self._given_up() or self.moment(self.lead + self.delay)

    def next(self) -> bool:
        """The access issued in the next clock meets it (AXI4-Lite: AW and W raised in this
        one)."""
        return self._given_up() or self.moment(self.lead + self.delay + 1)


#: beats on the half-slot grid tried for one whose instant sits at a rounding place
ROUNDING_TRIES = 64


def half_step_codes(contract, leg: int) -> list[int]:
    """A beat of half of ``leg``'s active vector: ``FULL / 2`` on that leg, 0 on the others."""
    return [contract.full // 2 if i == leg else 0 for i in range(contract.phases)]


class StreamSource:
    """The FOC loop's reference stream: a beat held with its payload until accepted, idle clocks
    between; balanced sines whose amplitude drifts from near zero into overmodulation, with
    beats of extreme codes and ties mixed in, or the kind a sequence asks for (``kind``: one
    of them alone; ``linear``, sines inside the linear range only; ``half step``, every beat
    half of one leg's active vector, ``FULL / 2`` on leg ``half_step_leg``: the same reference
    as a duty of one half between that leg's state and a zero state, which a feedback
    quantiser meets by changing the state at every update, once the integrators have taken a
    few such beats);
    ``eager`` offers a beat in every clock, ``stalled`` none (a controller that stopped)."""

    def __init__(self, run):
        self.run, self.rng = run, run.rng
        self.contract = run.model.contract
        self.phases = run.model.phases
        self.kind, self.eager, self.stalled = "sine", False, False
        self.half_step_leg = 0
        self.offered: list | None = None
        self.label = ""
        self.angle = self.rng.uniform(0, 2 * math.pi)
        self.amplitude = 0.5

    def sine_codes(self, amplitude=None, offset=0.0):
        self.angle += 0.05
        return sine_codes(self.contract, self.amplitude if amplitude is None else amplitude,
                          self.angle, offset)

    def first_after_reset(self, bits: int, mode: int = 0, places=()) -> None:
        """The first beat after a reset, into empty integrators: on the half-slot grid of b
        (a slot mode), or one whose largest candidates tie (MDFQM, largest_duty). With
        ``places`` (of ``ROUNDING_PLACES``): the first of up to :data:`ROUNDING_TRIES` such
        beats that puts an instant of ``mode``'s update at one of them (``T = R`` from empty
        integrators)."""
        c, n = self.contract, self.phases
        if not (bits or self.run.model.rule != "largest_duty"):
            self.offered, self.label = tie_codes(self.rng, c, n), "tie"
            return
        for _ in range(ROUNDING_TRIES if places else 1):
            codes = boundary_codes(self.rng, c, n, max(bits, 1))
            if rounding_places(remove_common_mode(codes, n), mode, bits, c) & set(places):
                break
        self.offered, self.label = codes, "grid"

    def held_integrators_codes(self, leg: int, mode: int) -> list | None:
        """A beat, offered now (the model ready), whose update (``mode`` at the finest b) puts
        ``leg``'s instant exactly on its rounding point from the integrators the model holds
        then: a beat on the half-slot grid for empty integrators, each code moved by
        ``(X_0 - X_i) / N`` to cancel them; None if none of :data:`ROUNDING_TRIES` fits the
        code range or the update is not foreseen."""
        m, c, n = self.run.model, self.contract, self.phases
        bits = m.max_bits
        x = x_at_use(m.core, [0] * n, self._held_settings())
        if x is None:
            return None
        for _ in range(ROUNDING_TRIES):
            grid = boundary_codes(self.rng, c, n, bits)
            if ("on it", leg) not in rounding_legs(remove_common_mode(grid, n), mode, bits, c):
                continue
            codes = [g + (x[0] - xi) // n for g, xi in zip(grid, x, strict=True)]
            if all(c.code_min <= code <= c.code_max for code in codes):
                return codes
        return None

    def sort_tie_codes(self) -> list:
        """A beat inside the linear range, offered now (the model ready), moved so that its
        update meets a tie of sort1 or sort2 (core_stimulus.aimed_tie, from the integrators of
        the model run ahead)."""
        m = self.run.model
        base = self.sine_codes(self.rng.uniform(0.2, 0.9) * linear_amplitude(self.phases))
        return aimed_tie(self.rng, m.core, self.contract, m.rule, self._held_settings(), base)

    def _held_settings(self) -> dict:
        """The core's (the generator's) inputs besides the stream, as the registers hold them
        now: what a copy of its model run ahead steps with."""
        m = self.run.model
        settings = {"period": m.period, "osr": m.osr,
                    "zero_policy": int(bool(m.ctrl & regs.CTRL_ZERO_POLICY))}
        if m.max_bits:
            settings.update(mode=m.mode_request, bits=m.bits_request)
        return settings

    def _beat(self):
        rng, c, n = self.rng, self.contract, self.phases
        lin = linear_amplitude(n)
        kind = self.kind
        if kind == "sine":
            pick = rng.random()
            kind = "extreme" if pick < 0.1 else "ties" if pick < 0.2 else "sine"
        if kind == "overmodulation":
            return self.sine_codes(rng.uniform(1.0, 2.0) * lin, rng.uniform(-0.5, 0.5))
        if kind == "linear":
            return self.sine_codes(rng.uniform(0.2, 0.9) * lin)
        if kind == "half step":
            return half_step_codes(c, self.half_step_leg)
        if kind == "common mode":
            return self.sine_codes(rng.uniform(0.05, 0.6),
                                   rng.choice([-1, 1]) * rng.uniform(0.25, 0.5))
        if kind == "extreme":
            return extreme_codes(rng, c, n)
        if kind == "ties":
            level = rng.randint(c.code_min, c.code_max)
            codes = [rng.choice([level, -level // 2, 0]) for _ in range(n)]
            codes[rng.randrange(n)] = codes[rng.randrange(n)]
            return codes
        return self.sine_codes()

    def decide(self) -> None:
        if self.run.cycle % 5000 == 0:       # from near zero into overmodulation
            self.amplitude = self.rng.uniform(0.05, 1.0)
        if self.offered is None and not self.stalled and (self.eager or self.rng.random() < 0.3):
            self.offered, self.label = self._beat(), self.kind

    def offering(self) -> bool:
        return self.offered is not None or (self.eager and not self.stalled)


class TopRun(Waits):
    """One run of the drop-in top: the model, the bus master of its front, the stream, the
    fault and sync pins, the sequences running and the coverage (see the module docstring)."""

    def __init__(self, rng, component, phases: int, width: int, cycles: int,
                 coverage: Coverage | None = None):
        self.rng, self.cycles = rng, cycles
        self.model = TopModel(phases, width, component.rule, component.dead_min,
                              component.upper_active_low, component.lower_active_low,
                              bus=component.bus, counter_width=component.counter_width,
                              max_bits=component.max_bits, asc=component.asc,
                              watchdog=component.watchdog)
        self.axi = component.bus == "axi4lite"
        self.inputs, self.outputs = ports_of(component)
        self.stim = {port: [] for port, _ in self.inputs}
        self.expected = {port: [] for port, _ in self.outputs}
        self.master = MASTERS[component.bus](rng)
        self.queue: deque = deque()
        self.stream = StreamSource(self)
        self.coverage = Coverage() if coverage is None else coverage
        self.cycle = self.starts = 0
        self.active: list = []            # (sequence, its body)
        self.pending = None               # a sequence waiting for its claims to be free
        self.nominal: dict[int, int] = {}
        self.fault_in = self.sync_in = self.rst = 0
        self.results: dict[int, int | None] = {}
        self.tags = count(1)
        self.modes_in_force: set[int] = set()
        #: two legs turned on in one clock since EVENTS_TOTAL was last read
        self.two_on_since_read = False
        #: ADC trigger pulses so far (each counted in the clock that decides it)
        self.triggers = 0
        self._ahead: list = []
        self._monitor = Monitor(self)
        #: the pins (``with_pin``) of the writes issued and not yet taken, oldest first
        self.pins_issued = deque([None] * WRITE_LATENCY)
        mapped = mapped_words(phases)
        rw = {r.offset + i for r in regs.REGISTERS if r.access == "RW"
              for i in range(phases if r.count > 1 else 1)}
        self.mapped_writable = rw | {regs.CMD}
        self.read_only = {a for a in mapped if a not in self.mapped_writable}
        self.sequences = [s for s in seq.TopSequence.registry if s.applies(self)]
        #: each sequence's coverpoints in this run
        self.points = {s: s.coverpoints(self) for s in self.sequences}
        for sequence, points in self.points.items():
            for point, bins in points.items():
                self.coverage.want(point, bins, sequence.key())
        self._ports = ([(port, port.replace("__", "_")) for port, _ in self.inputs],
                       [(port, port.replace("__", "_")) for port, _ in self.outputs])

    # --------------------------------------------------------------- what sequences use
    def write(self, address: int, value: int, aim: Aim | None = None,
              with_pin: str | None = None) -> Access:
        """Queue a write; ``with_pin`` ("sync_in", "fault_in") raises that pin in the clock
        the register file takes the write."""
        if aim is not None:
            aim.delay = WRITE_LATENCY
        access = Access(address, 1, value & 0xFFFF_FFFF, aim, (next(self.tags), with_pin))
        self.queue.append(access)
        return access

    def read(self, address: int) -> Access:
        access = Access(address, 0, self.rng.getrandbits(32), None, (next(self.tags), None))
        self.queue.append(access)
        return access

    def command(self, bits: int, aim: Aim | None = None) -> Access:
        return self.write(regs.CMD, bits, aim)

    def restore(self, *addresses, aim: Aim | None = None) -> list[Access]:
        """The firmware's settings written again."""
        return [self.write(a, self.nominal[a], aim) for a in addresses if a in self.nominal]

    def done(self, access: Access) -> bool:
        return access.tag[0] in self.results

    def value(self, access: Access):
        return self.results.get(access.tag[0])

    def aim(self, moment, lead: int = 0, patience: int | None = None, unless=None) -> Aim:
        """An aim at ``moment`` (one of the ``moment_*`` methods), given up after ``patience``
        clocks (by default four updates of the length in force: every moment aimed at recurs
        within an update or two while the gates switch), or once ``unless()`` holds (the
        moment cannot come any more)."""
        if patience is None:
            patience = 4 * self.model.core.p_lat + 50
        return Aim(self, moment, lead, patience, unless)

    def aimed(self, write, point: str, bin_: str, attempts: int = 4):
        """Issue ``write()`` (it queues an aimed access and returns it) until the coverpoint's
        bin is hit, as measured from the model, at most ``attempts`` times: the bus may be busy
        in the clock of the moment, or the moment not come within the aim's patience.
        True once hit."""
        for _ in range(attempts):
            yield from self.settle(write())
            if self.coverage.covered(point, bin_):
                return True
        return False

    def settle(self, *accesses):
        """Wait until every access (lists of them too) has completed."""
        flat = [a for item in accesses for a in (item if isinstance(item, list) else [item])]
        while not all(self.done(a) for a in flat):
            yield

    def updates(self, n: int, limit: int = 70_000):
        """Wait until ``n`` more update starts have passed."""
        target = self.starts + n
        yield from self.until(lambda: self.starts >= target, limit)

    def modulation_word(self, legal: bool = True, mode: int | None = None,
                        bits: int | None = None) -> int:
        rng, top = self.rng, self.model.max_bits
        if mode is None:
            mode = rng.randrange(len(MODES) if top else 1)
        if bits is None:
            bits = rng.choice([1, 1, 2, 2, 3, 4, rng.randint(1, max(top, 1))])
        if legal:
            bits = min(max(bits, 1), max(top, 1))
        return mode << regs.MODULATION_MODE_SHIFT | bits << regs.MODULATION_BITS_SHIFT

    def slot_length(self) -> int:
        core = self.model.core
        return max(1, core.slot_len if getattr(core, "mode_lat", 0) else core.p_lat)

    def aimed_beat(self, codes, label: str):
        """One beat aimed from the model's state: the stream stalls until the model is ready
        with nothing offered, ``codes()`` (called then; None: no beat) is offered in that
        clock, and the stream runs again for two updates."""
        self.stream.stalled = True
        ready = yield from self.until(lambda: self.model.ref_ready and self.stream.offered is None,
                                      limit=20_000)
        if ready:
            beat = codes()
            if beat is not None:
                self.stream.offered, self.stream.label = beat, label
                yield
        self.stream.stalled = False
        yield from self.updates(2)

    def update_clocks(self, period: int) -> int:
        """Clocks an update lasts with PERIOD = ``period`` in the mode and b requested now (a
        slot mode's updates last at least ``max(L_b, 2**b)``: docs/contract.md)."""
        m = self.model
        mode, bits, _ = latch_mode(m.mode_request, m.bits_request, m.max_bits)
        return max(period, min_period(bool(mode), bits, m.latency, m.long_latency))

    def wrap_reachable(self) -> bool:
        """Whether EVENTS_TOTAL is brought past 2**counter_width in this run: a wrap takes
        about 2**counter_width * 20 clocks of short slot-mode updates that hold most of the top
        (mdfqm_testkit.top_sequences.Counters), spared in runs at least 50 times as long (at
        8 bits, the 500,000-clock run, not the 60,000-clock one: measured, its other bins
        starved)."""
        return (1 << self.model.counter_width) * 1000 <= self.cycles

    def room_before_start(self) -> bool:
        core = self.model.core
        return core.phase != 0 and core.p_lat - core.phase > 48

    # the moments an access can be aimed at: whether the event happens k clocks from now
    def ahead(self, k: int) -> TopModel:
        """The model k clocks from now (0: itself), stepped with this clock's pins and
        stream, no bus access but the one the front issues by itself."""
        if not self._ahead or self._ahead[0] is not self.model:
            self._ahead = [self.model]
        while len(self._ahead) <= k:
            future = copy.deepcopy(self._ahead[-1])
            offered = self.stream.offered
            bus = {"s_axi_bready": 1, "s_axi_rready": 1} if self.axi else {}
            future.step(rst=0, ref_valid=int(self.stream.offering()),
                        ref=offered or [0] * future.phases, fault_in=self.fault_in,
                        sync_in=self.sync_in if len(self._ahead) == 1 else 0, **bus)
            self._ahead.append(future)
        return self._ahead[k]

    def moment_update_start(self, k: int) -> bool:
        core = self.model.core
        if k == 1:          # the sequencer's next phase (docs/contract.md), no copy stepped
            threshold = (self.model.long_latency if getattr(core, "long_lat", 0)
                         else self.model.latency)
            return core.phase != 0 and (core.phase + 1 >= core.p_lat
                                        or bool(self.sync_in and core.phase + 1 >= threshold))
        return self.ahead(k).core.phase == 0

    def moment_sample(self, k: int) -> bool:
        if k == 1:
            return self.moment_update_start(1) and self.model.core.sub == 0
        core = self.ahead(k).core
        return core.phase == 0 and core.sub == 0

    def moment_beat(self, k: int) -> bool:
        return self.stream.offering() and bool(self.ahead(k).ref_ready)

    def moment_fault_latch(self, k: int) -> bool:
        if k == 1:          # the synchroniser's second flop and the latch (docs/top.md, Fault)
            driver = self.model.driver
            return bool(driver.sync1 and not (driver.fault or driver.fault_input))
        driver = self.ahead(k).driver
        return bool(driver.fault_input and not driver.fault)

    def _legs_next(self):
        """Each leg's (up, lo) in the next clock, from the driver's own rules on this clock's
        registers (docs/top.md, "Gate driver"); None while a fault, the watchdog or a fault
        reaction is in play (then a copy of the model is stepped)."""
        m = self.model
        driver, core = m.driver, m.core
        if driver.fault_input or driver.fault or m.wd_tripped or driver.reaction:
            return None
        enable = m.ctrl & regs.CTRL_ENABLE if core.update else driver.active
        drive = int(bool(enable))
        return drive, [leg.next_state((core.h >> i) & 1, drive, driver.dead_seen,
                                      driver.min_pulse_seen)
                       for i, leg in enumerate(driver.legs)]

    def moment_turn_on(self, k: int) -> bool:
        if k == 1 and (legs := self._legs_next()) is not None:
            return any(not (leg.up or leg.lo) and (up or lo)
                       for leg, (up, lo) in zip(self.model.driver.legs, legs[1], strict=True))
        return any(leg.event for leg in self.ahead(k).driver.legs)

    def moment_short_edge(self, k: int) -> bool:
        if k == 0:          # the driver's own test on this clock's command (docs/top.md)
            m = self.model
            driver, core = m.driver, m.core
            enable = m.ctrl & regs.CTRL_ENABLE if core.update else driver.active
            drive = int(bool(enable) and not (driver.fault_input or driver.fault
                                              or m.wd_tripped))
            return bool(driver.short_edges(core.h, drive))
        return bool(self.ahead(k + 1).driver.short_edge)

    def moment_in_dead_time(self, k: int) -> bool:
        if k == 1 and (legs := self._legs_next()) is not None:
            return bool(legs[0]) and any(not (up or lo) for up, lo in legs[1])
        driver = self.ahead(k).driver
        return bool(driver.active) and any(not (leg.up or leg.lo) for leg in driver.legs)

    def moment_mid_update(self, k: int) -> bool:
        if k == 1:
            core = self.model.core
            return core.phase != 0 and 0 < core.phase + 1 < core.p_lat - 1
        core = self.ahead(k).core
        return 0 < core.phase < core.p_lat - 1 and not core.update

    def moment_in_layout(self, k: int) -> bool:
        core = self.ahead(k).core
        return (bool(getattr(core, "mode_lat", 0)) and core.phase != 0
                and core.slot_idx < len(core.slots) - 1)

    def moment_watchdog_trip(self, k: int) -> bool:
        if k == 1:          # the next start finds the quiet count as it is now (docs/top.md)
            m = self.model
            arrival = m.ref_ready and self.stream.offered is not None
            return bool(m.wd_timeout and not m.wd_tripped and not arrival
                        and self.moment_update_start(1) and m.wd_quiet >= m.wd_timeout)
        m = self.ahead(k)
        return bool(m.wd_timeout and not m.wd_tripped and m.core.phase == 0
                    and not m.wd_arrival and m.wd_quiet >= m.wd_timeout)

    def source_moment(self, source: str):
        """The moment of an interrupt source's event (None: none to aim at)."""
        return {"FAULT": self.moment_fault_latch, "SAMPLE": self.moment_sample,
                "SHORT_EDGE": self.moment_short_edge,
                "WATCHDOG": self.moment_watchdog_trip}.get(source)

    # --------------------------------------------------------------------- the scheduler
    def _start(self, sequence) -> None:
        self.active.append((sequence, sequence.body()))

    def _held(self) -> set:
        return set().union(*(s.claims for s, _ in self.active)) if self.active else set()

    def _schedule(self) -> None:
        """Start the sequence that waits for its claims once they are free; else, now and
        then, draw one (those with open coverpoints first): started if its claims are free,
        else it waits, and nothing that needs its claims starts meanwhile. One that resets
        the top (claims ALL) waits until no other one runs."""
        waiting = self.pending
        if waiting is not None:
            free = not self.active if waiting.claims == seq.ALL else not (
                waiting.claims & self._held())
            if free:
                self._start(waiting)
                self.pending = waiting = None
            elif waiting.claims == seq.ALL:
                return
        if (len(self.active) >= CONCURRENT or self.rng.random() >= START_RATE
                or any(s.claims == seq.ALL for s, _ in self.active)):
            return
        weights = []
        for sequence in self.sequences:
            if any(self.coverage.is_open(p) for p in self.points[sequence]):
                weights.append(sequence.weight * OPEN_BOOST)
            else:
                weights.append(sequence.weight if sequence.closed_weight is None
                               else sequence.closed_weight)
        if not any(weights):
            return
        chosen = self.rng.choices(self.sequences, weights)[0](self)
        if waiting is not None and chosen.claims & waiting.claims:
            return
        if chosen.claims == seq.ALL or chosen.claims & self._held():
            if waiting is None:
                self.pending = chosen
            return
        self._start(chosen)

    def _resume(self) -> None:
        for entry in list(self.active):
            try:
                next(entry[1])
            except StopIteration:
                self.active.remove(entry)

    def _background(self) -> None:
        """Firmware's idle traffic: a read of any word, or a write to a word that holds no
        writable register (ignored)."""
        if self.queue or self.master.busy() or self.rng.random() >= BACKGROUND_RATE:
            return
        if self.rng.random() < 0.8:
            self.read(self.rng.randrange(64))
        else:
            words = sorted(set(range(64)) - self.mapped_writable)
            self.write(self.rng.choice(words), self.rng.getrandbits(32))

    # --------------------------------------------------------------------- one clock
    def clock(self) -> None:
        self.sync_in = self.rst = 0
        self._ahead = []
        if self.cycle == 0:
            self._start(seq.Operate(self))
        self._schedule()
        self._resume()
        if self.rst:
            self._reset()
        self._background()
        self.stream.decide()
        self._ahead = []
        bus = self.master.inputs(self.queue)
        issued, read = self.model.front.access(bus)
        write = self.model.write_taken
        issued_write = self.master.issued_write() if issued is not None else None
        self.pins_issued.append(issued_write.tag[1] if issued_write is not None else None)
        pin = self.pins_issued.popleft()        # the pin of the write taken in this clock
        if pin == "sync_in":
            self.sync_in = 1
        elif pin == "fault_in":
            self.fault_in = 1
        payload = self.stream.offered or [0] * self.model.phases
        valid = int(self.stream.offered is not None)
        self.modes_in_force.add(getattr(self.model.core, "mode_lat", 0))
        before = self._monitor.before(bus, write, read, valid, payload)
        out = self.model.step(rst=self.rst, ref_valid=valid, ref=payload, fault_in=self.fault_in,
                              sync_in=self.sync_in, **bus)
        if valid and out["ref_ready"] and not self.rst:
            self.stream.offered = None
        if not self.rst:
            self.master.observe(bus, out)
            for done in self.master.completed:
                self.results[done.access.tag[0]] = done.value
                self._monitor.completed(done.access, done.value)
        self._monitor.after(before)
        if before["start"] and not self.rst:
            self.starts += 1
        values = {"rst": self.rst, "ref_valid": valid,
                  "ref_payload": pack(payload, self.model.width),
                  "fault_in": self.fault_in, "sync_in": self.sync_in, **bus}
        inputs, outputs = self._ports             # port -> model name: wb__ack -> wb_ack
        for port, name in inputs:
            self.stim[port].append(values[name])
        for port, name in outputs:
            self.expected[port].append(out[name])
        self.cycle += 1

    def _reset(self) -> None:
        """A reset drops every access in flight and the beat offered (a producer's valid is
        low in a reset)."""
        self.master.abort()
        self.queue.clear()
        self.stream.offered = None
        self.pins_issued = deque([None] * WRITE_LATENCY)

    def generate(self):
        for _ in range(self.cycles):
            self.clock()
        return self.stim, self.expected, self.modes_in_force


class Monitor:
    """The coverpoints of the top's sequences, hit from what the model shows in each clock:
    ``before`` reads the registers of the clock and its inputs, ``after`` what the clock
    changed, ``completed`` a read's returned word."""

    def __init__(self, run: TopRun):
        self.run = run
        m = run.model
        self.clamp_bins: dict[int, dict[int, list[str]]] = {}
        for sequence in seq.TopSequence.registry:
            if issubclass(sequence, seq.ClampWalk) and sequence.POINT:
                addresses = ([regs.REF_BASE + i for i in range(m.phases)]
                             if sequence is seq.RefClamp else [sequence.REGISTER])
                by_word: dict[int, list[str]] = {}
                for name, word in sequence.values(run).items():
                    by_word.setdefault(word & 0xFFFF_FFFF, []).append(name)
                for address in addresses:
                    self.clamp_bins[address] = (sequence.POINT, by_word)
        self.adc_edges = seq.adc_edges(run)
        self.period_edges = seq.period_edges(run)
        self.fault_edges: deque = deque(maxlen=4)
        self.last_fault_in = 0
        self.last_bus: dict = {}
        self.triggered = False
        self.update_offset = None       # (P, ADC_OFFSET) at the last update start
        self.after_reset = False
        self.pins_point = seq.PinPolarity.point(run)
        self.setting_written = None
        self.dead_written = False
        #: an update has saturated since the last reset (the integrators held once)
        self.saturated_since_reset = False
        #: without the watchdog built in: the last WATCHDOG written (as its clamp would store
        #: it with one) and the update starts since a reference last arrived
        self.timeout_written, self.starts_without_reference = 0, 0

    def hit(self, point, bin_):
        self.run.coverage.hit(point, bin_)

    @staticmethod
    def arrival(beat, write) -> bool:
        """A reference arrives in this clock: a beat taken on the port or a commit written."""
        return bool(beat or (write is not None and write[0] == regs.CMD
                             and write[1] & regs.CMD_REF_COMMIT))

    def _starts_without_reference(self, start, beat, write) -> None:
        """Without the watchdog built in: the update starts since a reference last arrived,
        against the last WATCHDOG written."""
        if self.arrival(beat, write):
            self.starts_without_reference = 0
        elif start:
            self.starts_without_reference += 1
            if 0 < self.timeout_written < self.starts_without_reference:
                self.hit(seq.WatchdogNotBuiltIn.POINT,
                         "more update starts without a reference than WATCHDOG written")

    # --------------------------------------------------------------------- before the step
    def before(self, bus, write, read, valid, payload) -> dict:
        run, m = self.run, self.run.model
        core, driver = m.core, m.driver
        rst = run.rst
        start = core.phase == 0
        beat = bool(valid and m.ref_ready)
        turn_on = sum(leg.event << i for i, leg in enumerate(driver.legs))
        fault_pin_edge = run.fault_in and not self.last_fault_in
        latch_set = bool(driver.fault_input and not driver.fault)
        facts = {"start": start, "turn_on": turn_on, "irq_status": m.irq_status,
                 # the dead time each leg's turn-on (seen a clock later) waited: the one in
                 # force when its switches went off, or a longer one since
                 "waited": [max(leg.dt_run, driver.dead_in_force) for leg in driver.legs],
                 # the update committing in this clock: its zero policy, and the last slot's
                 # state of the layout before it (generator only)
                 "commit_policy": (core.inflight[3] if core.inflight is not None
                                   and core.inflight[0] == 1 else None),
                 "h_last": getattr(core, "h_last", 0),
                 "after_layout": len(getattr(core, "slots", ())) > 1,
                 "irq": m.irq, "reaction": driver.reaction, "write": write,
                 "period": m.period, "mode_request": m.mode_request,
                 "bits_request": m.bits_request, "rst": rst,
                 "named_on": [leg.up if (driver.cmd_lat >> i) & 1 else leg.lo
                              for i, leg in enumerate(driver.legs)] if driver.active else (),
                 "fault_rise": bool((driver.fault_input or driver.fault)
                                    and not driver.fault_prev),
                 "stop_rise": bool(m.wd_tripped and not driver.stop_prev),
                 "left_normal": not (driver.fault_prev or driver.stop_prev)}
        if not m.watchdog:
            self._starts_without_reference(start, beat, write)
        if run.fault_in != self.last_fault_in:
            self.fault_edges.append(run.cycle)
            if len(self.fault_edges) >= 3 and self.fault_edges[-1] - self.fault_edges[-3] <= 8:
                self.hit(seq.FaultLatch.POINT, "chatter")
        if fault_pin_edge and run.moment_in_dead_time(0):
            self.hit(seq.FaultLatch.POINT, "raised in a dead time")
        self.last_fault_in = run.fault_in
        if rst:
            self._reset(start)
            return facts
        self._bus(bus)
        if write is not None:
            self._write(write, start, beat, turn_on, latch_set, fault_pin_edge)
        if read == regs.EVENTS_TOTAL and run.two_on_since_read:
            self.hit(seq.Counters.POINT, "EVENTS_TOTAL read after two legs turned on in one "
                     "clock")
            run.two_on_since_read = False
        if beat:
            self._beat(payload)
        elif valid and m.ref_pending:
            self.hit(seq.RefArbitration.POINT, "port beat held while one is pending")
        if run.sync_in:
            threshold = m.long_latency if getattr(core, "long_lat", 0) else m.latency
            if not start and core.phase + 1 >= threshold:
                self.hit(seq.SyncPulses.POINT, "starts the next update")
                for edge in seq.PeriodBands.sync_edges(run):
                    if core.phase in seq.PeriodBands.sync_phases(run, edge):
                        self.hit(seq.PeriodBands.SYNC_POINT, str(edge))
                if getattr(core, "mode_lat", 0):
                    self.hit(seq.SyncPulses.POINT, "starts the next update in a slot mode")
            else:
                self.hit(seq.SyncPulses.POINT, "ignored: update in flight")
        if bin(turn_on).count("1") >= 2:
            run.two_on_since_read = True
        for leg in driver.legs:
            if leg.event:
                self.hit(self.pins_point, "upper" if leg.up else "lower")
        if start:
            self._start()
        elapsed = 0 if start else m.adc_cnt
        if elapsed == m.adc_offset:
            self.triggered = True
            run.triggers += 1
            self.hit(seq.AdcOffsetBands.POINT, band(m.adc_offset, self.adc_edges))
        trip = run.moment_watchdog_trip(0)
        if trip:
            timeout = m.wd_timeout
            self.hit(seq.Watchdog.POINT, "tripped at TIMEOUT 1" if timeout == 1 else
                     "tripped at TIMEOUT 2..7" if timeout < 8 else "tripped at TIMEOUT 8..")
            edges = seq.Watchdog.octave_edges(run)
            if edges and m.wd_quiet == timeout:     # not lowered below it: the count ran to it
                self.hit(seq.Watchdog.OCTAVES, band(timeout, edges))
            if self.arrival(beat, write):
                self.hit(seq.Watchdog.POINT, "a reference in the tripping start's clock")
        total = m.total + bin(turn_on).count("1")
        clearing = write is not None and write[0] == regs.CMD and write[1] & regs.CMD_COUNT_CLEAR
        if total >> m.counter_width and not clearing:
            self.hit(seq.Counters.POINT, "EVENTS_TOTAL wrapped")
        return facts

    def _reset(self, start) -> None:
        run = self.run
        if start:
            where = "in an update start's clock"
        elif run.moment_in_layout(0):
            where = "inside a slot layout"
        else:
            where = "in the middle of an update"
        self.hit(seq.ResetMidUpdate.POINT, where)
        self.after_reset = True
        self.saturated_since_reset = False

    def _bus(self, bus) -> None:
        run, front = self.run, self.run.model.front
        point = seq.BusHandshakes.POINT
        if not run.axi:
            cyc, stb = bus["wb_cyc"], bus["wb_stb"]
            if run.master.busy():
                if cyc and not stb:
                    self.hit(point, "cyc raised before stb")
                if cyc and stb and front.ack:
                    self.hit(point, "stb held in the ack clock")
            elif cyc != stb:
                self.hit(point, "cyc alone while idle" if cyc else "stb alone while idle")
            return
        aw = bus["s_axi_awvalid"] and not front.aw_full
        w = bus["s_axi_wvalid"] and not front.w_full
        if front.aw_full and not front.w_full:
            self.hit(point, "AW before W")
        if front.w_full and not front.aw_full:
            self.hit(point, "W before AW")
        if aw and w:
            self.hit(point, "AW and W together")
        if front.bvalid and not bus["s_axi_bready"]:
            self.hit(point, "B held by bready low")
        if front.rvalid and not bus["s_axi_rready"]:
            self.hit(point, "R held by rready low")
        if aw and front.bvalid:
            self.hit(point, "next AW while B waits")
        if front.bvalid and bus["s_axi_bready"] and front.bresp:
            self.hit(point, "SLVERR write")
        if front.rvalid and bus["s_axi_rready"] and front.rresp:
            self.hit(point, "SLVERR read")
        if bus["s_axi_wvalid"] and bus["s_axi_wstrb"] != 0xF:
            self.hit(point, "wstrb other than 0xF")

    def _write(self, write, start, beat, turn_on, latch_set, fault_pin_edge) -> None:
        run, m = self.run, self.run.model
        driver = m.driver
        address, value = write
        kind = ("CMD write" if address == regs.CMD else
                "IRQ_STATUS write-1-to-clear" if address == regs.IRQ_STATUS else
                "register write")
        events = {"update start": start, "beat accepted": beat,
                  "fault pin edge": fault_pin_edge, "fault latch set": latch_set,
                  "sync pulse": bool(run.sync_in), "gate turn-on": bool(turn_on)}
        point = f"{seq.TwoEventsInOneClock.POINT} an event"
        for event, happening in events.items():
            if happening:
                self.hit(point, f"{kind} / {event}")
        names = {v: k for k, v in seq.RuntimeChanges.SETTINGS.items()}
        if address in names and start:
            self.hit(seq.RuntimeChanges.POINT, names[address])
        self.setting_written = names.get(address)
        if address in self.clamp_bins:
            clamp_point, by_word = self.clamp_bins[address]
            for name in by_word.get(value, ()):
                self.hit(clamp_point, name)
        random_point = seq.RandomWrites.POINT
        if address == regs.CMD:
            self.hit(random_point, "CMD")
            self._command(value, beat, turn_on)
        elif address in run.mapped_writable:
            self.hit(random_point, "a read-write register")
        elif address in run.read_only:
            self.hit(random_point, "a read-only register")
        else:
            self.hit(random_point, "an unmapped word")
        if address in (regs.ID, regs.INFO, regs.DEAD_MIN):
            self.hit(seq.Identification.POINT, "written, ignored")
        if address in (regs.IRQ_ENABLE, regs.IRQ_STATUS) and value & ~regs.IRQ_MASK:
            self.hit(seq.IrqService.UNDEFINED,
                     "IRQ_ENABLE" if address == regs.IRQ_ENABLE else "IRQ_STATUS")
        if address == regs.DEAD:
            point = seq.DeadTime.POINT
            if value < m.dead_min:
                self.hit(point, "below the floor")
            if run.moment_in_dead_time(0):
                now = max(m.dead, m.dead_min)
                new = min(max(value, m.dead_min), 0xFFFF)
                if new > now:
                    self.hit(point, "raised while a dead time runs")
                elif new < now:
                    self.hit(point, "lowered while a dead time runs")
                    running = max((leg.dt_run for leg in m.driver.legs
                                   if not (leg.up or leg.lo)), default=0)
                    edges = seq.DeadTime.running_edges(run)
                    if running >= edges[0]:
                        self.hit(seq.DeadTime.RUNNING, band(running, edges))
                    if running >= seq.LongTimes.DEAD_EDGES[0]:
                        self.hit(seq.LongTimes.LOWERED,
                                 band(running, seq.LongTimes.DEAD_EDGES))
            self.dead_written = True
        if address == regs.CTRL and not m.core.update:
            was, now = m.ctrl & regs.CTRL_ENABLE, value & regs.CTRL_ENABLE
            if was and not now:
                self.hit(seq.EnableMidUpdate.POINT, "cleared")
            elif now and not was:
                self.hit(seq.EnableMidUpdate.POINT, "set")
        if address == regs.MODULATION and value & ~(regs.MODULATION_MODE
                                                    | regs.MODULATION_BITS):
            self.hit(seq.ModulationClamp.POINT, "bits outside MODE and BITS")
        if address == regs.WATCHDOG:
            stored = min(value, 0xFFFF)
            if not m.watchdog:
                self.timeout_written = stored
                if stored:
                    self.hit(seq.WatchdogNotBuiltIn.POINT, "WATCHDOG written non-zero")
            elif (stored and not m.wd_tripped and m.wd_timeout > m.wd_quiet
                    and stored <= m.wd_quiet):
                self.hit(seq.Watchdog.POINT, "TIMEOUT lowered below the quiet count")
        if address == regs.FAULT_REACTION and driver.reaction:
            self.hit(seq.FaultReaction.POINT, "rewritten while an ASC is in force")

    def _command(self, value, beat, turn_on) -> None:
        m = self.run.model
        driver = m.driver
        if value & regs.CMD_REF_COMMIT:
            point = seq.RefArbitration.POINT
            self.hit(point, "committed")
            if m.ref_pending:
                self.hit(point, "commit while one is pending")
            if beat:
                self.hit(point, "commit in the clock a port beat is accepted")
        if value & regs.CMD_COUNT_CLEAR and turn_on:
            self.hit(seq.Counters.POINT, "COUNT_CLEAR in the clock of a turn-on")
        if value & regs.CMD_FAULT_CLEAR:
            if driver.fault_input:
                self.hit(seq.FaultLatch.POINT, "clear while the input is high")
            elif driver.fault:
                self.hit(seq.FaultLatch.POINT, "clear once the input is low")
        if value & regs.CMD_WATCHDOG_CLEAR and m.wd_tripped:
            self.hit(seq.Watchdog.POINT, "cleared")
        if value & regs.CMD_WATCHDOG_CLEAR and not m.watchdog:
            self.hit(seq.WatchdogNotBuiltIn.POINT, "CMD.WATCHDOG_CLEAR written")

    def _beat(self, payload) -> None:
        run, m = self.run, self.run.model
        c, n = m.contract, m.phases
        if abs(sum(payload)) >= n * c.full // 4:
            self.hit(seq.CommonMode.POINT, "accepted")
        if set(payload) <= {c.code_min, c.code_max, 0, -1, 1} and (
                c.code_min in payload or c.code_max in payload):
            self.hit(seq.ExtremeCodes.POINT, "accepted")
        if len(set(payload)) < n:
            self.hit(seq.Ties.POINT, "accepted")
        if self.after_reset:
            self.after_reset = False
            empty = not any(m.core.x)
            if empty and run.stream.label == "tie" and m.rule == "largest_duty":
                rho, _ = sort1(remove_common_mode(payload, n))
                values = candidates(rho, c, "largest_duty")
                if values.count(max(values)) >= 2:
                    self.hit(seq.ResetMidUpdate.FIRST, "largest candidates tie")
            if (empty and run.stream.label == "grid"
                    and latch_mode(m.mode_request, m.bits_request, m.max_bits)[0]):
                self.hit(seq.ResetMidUpdate.FIRST, "on the half-slot grid into a slot mode")

    def _start(self) -> None:
        """The update start of this clock: the settings it takes."""
        m = self.run.model
        osr = m.osr
        self.hit(seq.OsrSettings.POINT, "0 (acts as 1)" if osr == 0 else "1" if osr == 1
                 else "255" if osr == 255 else "2..254")
        self.hit(seq.ZeroPolicy.POINT, "fewest transitions" if m.ctrl & regs.CTRL_ZERO_POLICY
                 else "all-off")
        last = self.update_offset
        if last is not None and not self.triggered and last[1] >= last[0]:
            self.hit(seq.AdcOffsetBands.POINT, seq.AdcOffsetBands.NONE)
        self.triggered = False

    # ---------------------------------------------------------------------- after the step
    def after(self, facts) -> None:
        m = self.run.model
        core, driver = m.core, m.driver
        if facts["rst"]:
            return
        if core.update and core.saturated:
            self.saturated_since_reset = True
        if facts["start"]:
            self.update_offset = (core.p_lat, m.adc_offset)
            if core.period_clamped:
                self.hit(seq.PeriodBands.POINT, "below the minimum")
                below = seq.PeriodBelowLatency
                point = below.POINT
                if facts["period"] == 0:
                    self.hit(point, below.ZERO)
                elif facts["period"] < m.latency:
                    self.hit(point, below.BELOW_L)
                if getattr(core, "mode_lat", 0):
                    self.hit(point, "in a slot mode")
                    low = min_period(True, core.bits_lat, m.latency, m.long_latency)
                    if m.latency <= facts["period"] < low:
                        self.hit(point, below.slot_bin(low))
            else:
                self.hit(seq.PeriodBands.POINT, band(facts["period"], self.period_edges))
            mode = getattr(core, "mode_lat", 0)
            self.hit(seq.ModulationModes.MODES_POINT, MODES[mode])
            if mode:
                self.hit(seq.ModulationModes.BITS_POINT,
                         seq.ModulationModes.slot_bin(mode, core.bits_lat))
            if mode and core.bits_lat == m.max_bits:
                _, x, r = core.inflight[:3]
                t = [xi + ri for xi, ri in zip(x, r, strict=True)]
                found = rounding_legs(t, mode, core.bits_lat, m.contract)
                for place in {place for place, _ in found}:
                    self.hit(seq.ResetMidUpdate.ROUNDING,
                             seq.ResetMidUpdate.rounding_bin(mode, place))
                if self.saturated_since_reset:
                    for place, leg in found:
                        if place == "on it":
                            self.hit(seq.HeldIntegrators.POINT, f"leg {leg}")
            if not mode:
                _, x, r = core.inflight[:3]
                t = [xi + ri for xi, ri in zip(x, r, strict=True)]
                for bin_ in tie_bins(t, m.contract, m.rule):
                    self.hit(seq.SortTies.POINT, bin_)
            request = (facts["mode_request"], facts["bits_request"])
            built = len(MODES) if m.max_bits else 1
            point = seq.ModulationClamp.POINT
            if request[0] >= built:
                self.hit(point, "mode not built in")
            elif request[0] and m.max_bits:
                if request[1] == 0:
                    self.hit(point, "b 0")
                elif request[1] > m.max_bits:
                    self.hit(point, "b above max_bits")
        if core.update and core.saturated:
            self.hit(seq.Overmodulation.POINT, "an update saturated")
        if (core.update and m.max_bits and len(core.slots) == 1 and facts["after_layout"]
                and facts["commit_policy"] == FEWEST_TRANSITIONS
                and core.h == (1 << m.phases) - 1
                and facts["h_last"].bit_count() == m.phases // 2 + 1):
            for i in range(m.phases):
                if (facts["h_last"] >> i) & 1:
                    self.hit(seq.Handover.POINT, f"leg {i}")
        if core.phase == 0 and getattr(self, "setting_written", None):
            self.hit(seq.RuntimeChanges.BEFORE, self.setting_written)
        self.setting_written = None
        if getattr(self, "dead_written", False) and any(leg.event for leg in driver.legs):
            self.hit(seq.DeadTime.POINT, "the clock before a turn-on")
        self.dead_written = False
        # short edges of this clock: swallowed (the switch named was not on) or stretched
        for i in range(m.phases):
            if (driver.short_edge >> i) & 1:
                named_on = facts["named_on"][i]
                self.hit(seq.ShortEdges.POINT, "stretched to MIN_PULSE" if named_on
                         else "swallowed by the dead time")
                if named_on:
                    self.hit(seq.MinPulse.POINT, "stretched")
                    if driver.min_pulse_seen >= seq.LongTimes.PULSE_EDGES[0]:
                        self.hit(seq.LongTimes.PULSE_POINT,
                                 band(driver.min_pulse_seen, seq.LongTimes.PULSE_EDGES))
        waited = max((facts["waited"][i] for i in range(m.phases)
                      if (facts["turn_on"] >> i) & 1), default=0)
        if waited >= seq.LongTimes.DEAD_EDGES[0]:
            self.hit(seq.LongTimes.DEAD_POINT, band(waited, seq.LongTimes.DEAD_EDGES))
        # interrupts
        new = m.irq_status & ~facts["irq_status"]
        for name, bit in seq.IRQ_SOURCES.items():
            if new & bit:
                self.hit(seq.IrqService.SET, name)
        if m.irq and not facts["irq"]:
            for name, bit in seq.IRQ_SOURCES.items():
                if facts["irq_status"] & m.irq_enable & bit:
                    self.hit(seq.IrqService.RAISED, name)
        write = facts["write"]
        if write is not None and write[0] == regs.IRQ_STATUS:
            for name, bit in seq.IRQ_SOURCES.items():
                if write[1] & bit and m.irq_status & bit:
                    self.hit(seq.IrqService.SAME_CLOCK, name)
        # the fault reaction: entered (from none), left (from an ASC)
        before, now = facts["reaction"], driver.reaction
        point = seq.FaultReaction.POINT
        if facts["left_normal"] and (facts["fault_rise"] or facts["stop_rise"]):
            source = "fault" if facts["fault_rise"] else "watchdog"
            names = {1: "ASC low", 2: "ASC high"}
            self.hit(point, f"{names.get(now, 'all off')} ({source})")
        if before and not now:
            left = seq.FaultReaction.LEFT
            if write is not None and write[0] == regs.CMD and write[1] & regs.CMD_ALL_OFF:
                self.hit(left, "by CMD.ALL_OFF")
            elif not (driver.fault or driver.fault_input or m.wd_tripped):
                self.hit(left, "by the clear")
            else:
                self.hit(left, "by a second source whose reaction is all off")

    def completed(self, access, value) -> None:
        """A read returned ``value``: what it shows."""
        if value is None:
            return
        address = access.address
        if address == regs.STATUS:
            flags = {regs.STATUS_PERIOD_CLAMPED: (seq.PeriodBelowLatency.POINT,
                                                  "STATUS.PERIOD_CLAMPED read 1"),
                     regs.STATUS_MODE_CLAMPED: (seq.ModulationClamp.POINT,
                                                "STATUS.MODE_CLAMPED read 1"),
                     regs.STATUS_SATURATED: (seq.Overmodulation.POINT,
                                             "STATUS.SATURATED read 1"),
                     regs.STATUS_REF_PENDING: (seq.RefArbitration.POINT,
                                               "STATUS.REF_PENDING read 1"),
                     regs.STATUS_FAULT: (seq.FaultLatch.POINT, "STATUS.FAULT read 1"),
                     regs.STATUS_FAULT_INPUT: (seq.FaultLatch.POINT,
                                               "STATUS.FAULT_INPUT read 1"),
                     regs.STATUS_WATCHDOG: (seq.Watchdog.POINT, "STATUS.WATCHDOG read 1")}
            for mask, (point, name) in flags.items():
                if value & mask:
                    self.hit(point, name)
            self.hit(seq.EnableMidUpdate.POINT, "STATUS.ACTIVE read 1"
                     if value & regs.STATUS_ACTIVE else "STATUS.ACTIVE read 0")
        elif address in (regs.ID, regs.INFO, regs.DEAD_MIN):
            self.hit(seq.Identification.POINT, {regs.ID: "ID read", regs.INFO: "INFO read",
                                                regs.DEAD_MIN: "DEAD_MIN read"}[address])
        elif regs.EVENTS_BASE <= address < regs.EVENTS_BASE + self.run.model.phases:
            self.hit(seq.Counters.POINT, f"EVENTS[{address - regs.EVENTS_BASE}] read")
        elif address == regs.GATES:
            if value & regs.GATES_UPPER:
                self.hit(seq.Counters.POINT, "GATES read with an upper gate on")
            if value & regs.GATES_LOWER:
                self.hit(seq.Counters.POINT, "GATES read with a lower gate on")


def top_stimulus(rng, component, phases, width, cycles, coverage=None):
    """The drop-in top under the specification's sequences (see the module docstring):
    ``cycles`` clocks of inputs and expected outputs by port, and the set of modes in force in
    some clock. ``coverage``, a :class:`~mdfqm_testkit.coverage.Coverage` if given, receives
    the run's goals and hits (the caller asserts what it needs)."""
    run = TopRun(rng, component, phases, width, cycles, coverage)
    return run.generate()


__all__ = ["Aim", "Monitor", "StreamSource", "TopRun", "top_stimulus"]
