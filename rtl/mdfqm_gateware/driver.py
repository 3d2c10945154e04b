"""Gate driver: complementary outputs with dead time, minimum pulse, enable, fault and polarity.

Every bit on every clock follows :mod:`mdfqm_model.driver` (its docstring is the specification;
:class:`mdfqm_model.driver.GateDriverModel` predicts it). Safety is by construction, in the
*active-high* domain (1 = switch on), and each property is stated beside its logic as an
``Assert`` emitted only when the component is built with ``formal=True`` (so the drop-in Verilog
is unchanged):

- the two switches of a leg are never both on;
- every turn-on follows at least the dead time in force of off clocks (``dt_req``: the larger of
  the clamped dead time of the last on cycle and of the deciding cycle; never below the floor
  ``dead_min`` fixed at elaboration);
- a synchronised fault turns every output off on the next clock, and stays latched until a
  clear while the input is inactive; so does ``stop`` (the top's watchdog latch) while high;
  under an active short circuit (the fault reaction ASC low / ASC high) every output but the
  ASC switches (the lower / the upper ones) turns off on the next clock, and only those turn
  on, each after the dead time; the reaction in force changes only to all off while a latch
  is set, and an ASC ends through all off (every switch off on the next clock);
- reset gives all off and the reaction all off; the gates stay off until an enable is taken at
  an update boundary, or a latch with an ASC reaction is set.

Polarity inversion is applied last, to registered signals.
"""

from amaranth import C, Cat, Module, Mux, ResetSignal, Signal
from amaranth.hdl import Assert, Assume, Cover
from amaranth.lib import wiring
from amaranth.lib.cdc import FFSynchronizer
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import TIME_WIDTH, validate_dead_min, validate_time_width
from mdfqm_spec.validate import validate_bool

__all__ = ["GateDriver", "LegDriver"]


class LegDriver(wiring.Component):
    """One inverter leg: complementary upper/lower gates with dead time and minimum pulse.

    The rules (:class:`mdfqm_model.driver.LegModel`): ``asc_lo`` (``asc_hi``) high: the lower
    (upper) switch is the ASC switch: it stays on if on, the other one turns off on the next
    clock, and from both off the ASC switch turns on once both have been off ``dt_req`` clocks;
    otherwise ``drive`` low turns both off on the next clock; the on switch stays on while it
    is commanded; a switch that is no longer commanded turns off once it has been on
    ``min_pulse`` clocks (shorter pulses are stretched); the commanded switch turns on once
    both have been off ``dt_req`` clocks,
    ``dt_req = max(dt_run, max(dead, dead_min))``, ``dt_run`` the clamped dead time of the last
    cycle a switch was on (kept through reset: a dead time already running is never shortened,
    by a smaller ``dead`` or by a reset).

    Ports
    -----
    cmd : In(1)
        Commanded switch: 1 upper, 0 lower. Read in every cycle.
    drive : In(1)
        0: both switches off on the next clock (disable, fault). Read in every cycle.
    asc_lo, asc_hi : In(1)
        The active short circuit, low (the lower switch) or high (the upper one); never both.
        Either overrides ``cmd`` and ``drive``. Read in every cycle.
    dead : In(time_width)
        Dead time in clocks; values below ``dead_min`` act as ``dead_min``. Read in every cycle;
        the leg acts on it one clock later (an input register).
    min_pulse : In(time_width)
        Minimum on-time in clocks (0 and 1: none). Read in every cycle, acted on one clock later.
    upper, lower : Out(1)
        Gates, active-high, registered (reset 0).
    event : Out(1)
        Registered strobe, high in the cycle a turn-on of either switch becomes visible.
    in_min_pulse : Out(1)
        From registers (one of two, selected by a third; no logic of the inputs): the present
        state has lasted fewer than ``min_pulse`` clocks (an on switch
        no longer commanded would be held on; the model's ``cnt + 1 < min_pulse_seen``).

    Parameters
    ----------
    dead_min : int in [1, 2**time_width - 1]
        Dead-time floor in clocks, fixed at elaboration.
    time_width : int in [2, 32]
        Width of ``dead``, ``min_pulse`` and the leg counter.
    asc : bool
        Build the active short circuit in; False: ``asc_lo`` and ``asc_hi`` are ignored (the
        leg of a driver without it: the logic and the proofs as without the ports).
    formal : bool
        Emit the ``Assert``/``Cover`` statements of the safety properties.
    """

    def __init__(self, dead_min: int, time_width: int = TIME_WIDTH, asc: bool = True,
                 formal: bool = False):
        self.time_width = validate_time_width(time_width)
        self.dead_min = validate_dead_min(dead_min, time_width)
        self.asc = validate_bool(asc, "asc")
        self.formal = validate_bool(formal, "formal")
        super().__init__({
            "cmd": In(1),
            "drive": In(1),
            "asc_lo": In(1),
            "asc_hi": In(1),
            "dead": In(time_width),
            "min_pulse": In(time_width),
            "upper": Out(1),
            "lower": Out(1),
            "event": Out(1),
            "in_min_pulse": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        tw, top = self.time_width, (1 << self.time_width) - 1
        rst = ResetSignal()
        # the inputs as the leg acts on them: one clock late (the model's dead_seen), so that
        # the decisions of a clock are flags computed in the clock before (the Fmax path)
        dead_seen = Signal(tw, reset_less=True)
        min_pulse_seen = Signal(tw, reset_less=True)
        # ``count_next``: what the count of clocks in the present on/off state plus one (the
        # model's cnt + 1) becomes next clock if the state holds: the decisions need only this
        # one; the count itself is the proofs' (built with formal=True only). It saturates at
        # 2**tw - 1, not at the model's 2**tw: every decision compares it with a tw-bit value,
        # for which the two answer alike, and the increment's carry out is the saturation test.
        # A restart (a new state: count_next 2) is not muxed into the registers behind it: it
        # is itself registered (``restarted``), and the count, the decisions and their compares
        # run on as if held, the restart's values kept beside them and selected by it. So the
        # late restart, decided by the fault and reaction logic, ends in one flop a leg, not in
        # the count's 16 and the decisions' (the UP5K's Fmax path).
        # The held count is kept inverted: ``count >= x`` is then ``x + ~count`` not carrying
        # out, an addition of two registers as they are, where a compare with the count itself
        # puts an inverter in front of every bit of the carry chain (a LUT a bit on the
        # iCE40); its saturating increment is a decrement, whose carry out is the saturation
        # test.
        restarted = Signal(init=1, reset_less=True)
        count_held_n = Signal(tw, reset_less=True)      # ~count_next unless restarted
        count_held = ~count_held_n      # an expression: the invariants read it mid-settle
        count_next_now = Mux(restarted, 2, count_held)
        count_next = Signal(tw)
        m.d.comb += count_next.eq(count_next_now)
        count_dec = Signal(tw + 1)
        m.d.comb += count_dec.eq(count_held_n + top)     # carries out unless saturated
        dt_run = Signal(tw, reset_less=True)
        # the decisions, registered both ways (after a restart, and with the state held):
        # count >= max(dt_run, dead_seen, dead_min) (read while off only), count < min_pulse_seen
        elapsed_after_restart, elapsed_held = Signal(reset_less=True), Signal(reset_less=True)
        short_after_restart, short_held = Signal(reset_less=True), Signal(reset_less=True)
        dead_elapsed_now = Mux(restarted, elapsed_after_restart, elapsed_held)
        pulse_short_now = Mux(restarted, short_after_restart, short_held)
        dead_elapsed, pulse_short = Signal(), Signal()
        m.d.comb += [dead_elapsed.eq(dead_elapsed_now), pulse_short.eq(pulse_short_now)]
        dt = Signal(tw)
        dt_expr = Mux(dead_seen < self.dead_min, self.dead_min, dead_seen)
        nxt_up, nxt_lo = Signal(), Signal()
        m.d.comb += self.in_min_pulse.eq(pulse_short)

        # the terms used in several places are signals, each one net (an expression would be
        # elaborated once per use)
        on = Signal()
        m.d.comb += [on.eq(self.upper | self.lower), dt.eq(dt_expr)]
        # the next state while driven, written flat (the Fmax path runs from ``drive`` through
        # the next state into the gates and ``restarted``): an on switch is kept while
        # commanded or inside its minimum pulse, else turned off; from off, the commanded switch
        # turns on once the dead time has elapsed
        keep = Signal()
        m.d.comb += keep.eq((self.upper & self.cmd) | (self.lower & ~self.cmd) | pulse_short)
        # an active short circuit: only its switch is kept, or turned on after the dead time
        asc_lo, asc_hi = (self.asc_lo, self.asc_hi) if self.asc else (C(0, 1), C(0, 1))
        asc = Signal()
        m.d.comb += asc.eq(asc_lo | asc_hi)
        m.d.comb += [
            nxt_up.eq(Mux(asc, asc_hi & Mux(on, self.upper, dead_elapsed),
                          self.drive & Mux(on, self.upper & keep, dead_elapsed & self.cmd))),
            nxt_lo.eq(Mux(asc, asc_lo & Mux(on, self.lower, dead_elapsed),
                          self.drive & Mux(on, self.lower & keep, dead_elapsed & ~self.cmd))),
        ]
        # the next clock starts a new state (count 1): the on/off state changes (a switch
        # on in both clocks is the same switch: the two are never on together, and from
        # one on to the other there is a clock of both off)
        restart = Signal()
        m.d.comb += restart.eq(rst | (on ^ (nxt_up | nxt_lo)))

        def decisions(c, run_ok):
            """(dead_elapsed, pulse_short) of the next clock if its count is the constant
            ``c`` and ``run_ok`` is its ``c >= dt_run``; every compare side by side."""
            return ((c >= self.dead) & (c >= self.dead_min) & run_ok, c < self.min_pulse)

        def held_reaches(x):
            """``count_held >= x`` for a ``tw``-bit ``x``: ``x + ~count_held`` fits ``tw``
            bits."""
            return ~(x + count_held_n)[tw]

        # a restart from on: dt_run of the next clock is dt (this one's)
        elapsed_restart, short_restart = decisions(1, Mux(on, dead_seen <= 1, dt_run <= 1))
        # a state held: dead_elapsed of an on state is never read (the next state of an on leg
        # does not depend on it), so only an off state's matters, whose dt_run stays; the
        # compares run on the held count, and on count 2 in the clock after a restart
        elapsed_on_held = (held_reaches(self.dead) & (count_held_n <= top - self.dead_min)
                           & held_reaches(dt_run))
        short_on_held = ~held_reaches(self.min_pulse)
        elapsed_on_2, short_on_2 = decisions(2, dt_run <= 2)
        elapsed_hold = Mux(restarted, elapsed_on_2, elapsed_on_held)
        short_hold = Mux(restarted, short_on_2, short_on_held)
        m.d.sync += [
            self.upper.eq(nxt_up),
            self.lower.eq(nxt_lo),
            self.event.eq(~on & (nxt_up | nxt_lo)),
            restarted.eq(restart),
            # after a restart the count held on is 3 (count_next 2 plus one)
            count_held_n.eq(Mux(restarted, top - 3, Mux(count_dec[tw], count_dec[:tw], 0))),
            elapsed_after_restart.eq(elapsed_restart),
            elapsed_held.eq(elapsed_hold),
            short_after_restart.eq(short_restart),
            short_held.eq(short_hold),
            dead_seen.eq(self.dead),
            min_pulse_seen.eq(self.min_pulse),
        ]
        with m.If(on):
            m.d.sync += dt_run.eq(dt)

        if self.formal:
            # the model's cnt + 1, saturating at 2**tw, counted apart from the design's register
            count = Signal(tw + 1, init=1)
            m.d.sync += count.eq(Mux(restart, 1, Mux(count == top + 1, top + 1, count + 1)))
            self._properties(m, self.upper | self.lower, dt, (count - 1)[:tw], dt_run,
                             (asc_lo, asc_hi))
            # expressions of registers, not comb signals: the simulator evaluates an assert as
            # soon as any of its inputs changes, before a comb signal has followed
            self._invariants(m, dt_expr, count, count_next_now, dt_run, dead_elapsed_now,
                             pulse_short_now, min_pulse_seen)
        return m

    def _invariants(self, m, dt, count, count_next, dt_run, dead_elapsed, pulse_short,
                    min_pulse_seen):
        """The registered decisions equal what they stand for (inductive invariants; the
        properties below do not depend on them being right)."""
        top = (1 << self.time_width) - 1
        m.d.comb += [
            Assert((count >= 1) & (count <= top + 1), "invariant: count in range"),
            Assert(count_next == Mux(count >= top, top, count + 1),
                   "invariant: count_next is the next count (saturating at 2**tw - 1)"),
            Assert(self.upper | self.lower
                   | (dead_elapsed == ((count >= dt) & (count >= dt_run))),
                   "invariant: dead_elapsed is the dead-time compare while off"),
            Assert(pulse_short == (count < min_pulse_seen),
                   "invariant: pulse_short is the minimum-pulse compare"),
        ]

    def _properties(self, m, on, dt, cnt, dt_run, asc):
        """Safety properties, on ghost registers independent of the leg's own counter; the
        last two asserts are inductive invariants (they make k-induction converge at any
        ``time_width``)."""
        tw = self.time_width
        gap = Signal(tw + 1, reset_less=True)       # off clocks before this one (saturating)
        need = Signal(tw, reset_less=True)          # clamped dead time of the last on cycle
        dt_prev = Signal(tw, reset_less=True)       # clamped dead time of the previous cycle
        on_prev = Signal(reset_less=True)
        drive_prev = Signal(init=1, reset_less=True)
        cmd_prev = Signal(reset_less=True)
        rst_prev = Signal(reset_less=True)
        asc_lo_prev = Signal(reset_less=True)
        asc_hi_prev = Signal(reset_less=True)
        up_prev = Signal(reset_less=True)
        lo_prev = Signal(reset_less=True)
        # the leg's own off count and dead time in force a clock ago: when the ASC switch is
        # due (the dead-time rule's own numbers; the turn-on asserts above bound it by the ghost)
        due_prev = Signal(reset_less=True)
        gap_top = (1 << (tw + 1)) - 1
        m.d.sync += [
            gap.eq(Mux(on, 0, Mux(gap == gap_top, gap_top, gap + 1))),
            dt_prev.eq(dt),
            on_prev.eq(on),
            drive_prev.eq(self.drive),
            cmd_prev.eq(self.cmd),
            rst_prev.eq(ResetSignal()),
            asc_lo_prev.eq(asc[0]),
            asc_hi_prev.eq(asc[1]),
            up_prev.eq(self.upper),
            lo_prev.eq(self.lower),
            due_prev.eq(~on & (cnt + 1 >= dt) & (cnt + 1 >= dt_run)),
        ]
        if self.asc:        # the driver never gives both
            m.d.comb += Assume(~(self.asc_lo & self.asc_hi))
        asc_prev = asc_lo_prev | asc_hi_prev
        with m.If(on):
            m.d.sync += need.eq(dt)
        turn_on = on & ~on_prev
        m.d.comb += [
            Assert(~(self.upper & self.lower), "both switches of a leg on"),
            Assert(~turn_on | ((gap >= need) & (gap >= dt_prev)),
                   "turn-on before the dead time in force elapsed"),
            Assert(~turn_on | (gap >= self.dead_min), "turn-on before the dead-time floor"),
            Assert(drive_prev | asc_lo_prev | asc_hi_prev | ~on,
                   "a switch on one clock after drive went low outside an ASC"),
            Assert(~rst_prev | ~on, "a switch on one clock after reset"),
            Assert(~(self.upper & ~on_prev) | Mux(asc_prev, asc_hi_prev, cmd_prev),
                   "upper turned on while not commanded"),
            Assert(~(self.lower & ~on_prev) | Mux(asc_prev, asc_lo_prev, ~cmd_prev),
                   "lower turned on while not commanded"),
            Assert(~asc_lo_prev | rst_prev | ~self.upper, "an upper switch on in an ASC low"),
            Assert(~asc_hi_prev | rst_prev | ~self.lower, "a lower switch on in an ASC high"),
            Assert(~(asc_lo_prev & lo_prev) | rst_prev | self.lower,
                   "the ASC low switch turned off while the ASC holds"),
            Assert(~(asc_hi_prev & up_prev) | rst_prev | self.upper,
                   "the ASC high switch turned off while the ASC holds"),
            Assert(~(asc_lo_prev & due_prev) | rst_prev | self.lower,
                   "the ASC low switch not on once the dead time elapsed"),
            Assert(~(asc_hi_prev & due_prev) | rst_prev | self.upper,
                   "the ASC high switch not on once the dead time elapsed"),
            Assert(self.event == turn_on, "event strobe is not the turn-on"),
            Assert(on | (cnt <= gap), "invariant: the leg's off count never exceeds the gap"),
            Assert(need == dt_run, "invariant: the remembered dead time is the ghost's"),
            Cover(turn_on & (gap > self.dead_min)),
            Cover(self.upper & ~on_prev),
            Cover(self.lower & ~on_prev),
        ]
        if self.asc:
            m.d.comb += [Cover(self.lower & ~on_prev & asc_lo_prev),
                         Cover(self.upper & ~on_prev & asc_hi_prev)]


class GateDriver(wiring.Component):
    """N legs, the fault synchroniser and latch, the command followed in every cycle and the
    enable taken at update boundaries.

    Specification: :class:`mdfqm_model.driver.GateDriverModel`. The command ``h`` is followed
    in every cycle (every edge of it, at an update boundary or at a slot boundary inside an
    update, under the same rules); ``enable`` is taken in cycles with ``update`` high; a
    synchronised fault turns every output off on the next clock, latches, clears the taken
    enable, and is cleared by ``fault_clear`` only while the synchronised input is inactive;
    outputs then resume at the next update boundary with ``enable`` high. ``stop`` acts like
    the fault latch without latching anything itself. The fault reaction (the model's "The
    fault reaction"): when the gates leave normal operation (the first of the fault and
    ``stop`` rises) the reaction in force becomes that source's (``reaction_fault`` /
    ``reaction_watchdog``: 1 ASC low, 2 ASC high, else all off); while a source is high it can
    only become all off (a rising source whose reaction is all off, or ``all_off``); with both
    low it is all off. A leg leaving an ASC is off for a clock before anything turns on again.

    Ports
    -----
    h : In(phases)
        Gate state from the core or the generator, bit i = upper switch of leg i on. Read in
        every cycle.
    update : In(1)
        Update boundary strobe (the core's ``update``): when ``enable`` is taken.
    enable : In(1)
        Requested enable; taken at update boundaries.
    dead, min_pulse : In(time_width)
        Dead time (clamped to ``dead_min``) and minimum on-time in clocks; read every cycle,
        acted on one clock later.
    fault_in : In(1)
        Asynchronous, active-high fault (desaturation / over-current / driver fault); passes a
        two-flop synchroniser (not reset). A pulse must span a rising clock edge to be seen.
    fault_clear : In(1)
        Clears the fault latch in a cycle where the synchronised input is low.
    stop : In(1)
        Synchronous stop (the top's watchdog latch, registered there): while high, every output
        turns off on the next clock and the taken enable is cleared, as on a fault (the fault
        reaction, below). Read in every cycle.
    reaction_fault, reaction_watchdog : In(2)
        The reaction to the fault and to ``stop``: 1 ASC low, 2 ASC high, 0 and 3 all off (and
        every value when ``asc`` is False). Read in the cycle a source rises.
    all_off : In(1)
        Strobe: the reaction in force becomes all off (every switch off on the next clock).
    upper, lower : Out(phases)
        Gate pins, registered, after the polarity of each side (``*_active_low``). Reset: every
        switch off (pin level 1 for an active-low side).
    event : Out(phases)
        Registered strobe per leg: a turn-on (either switch) becomes visible this cycle.
    short_edge_now : Out(phases)
        Combinational, per leg: in this cycle the leg's command changes while the leg is driven
        (this cycle and the one before) but has not followed the last change (the switch then
        commanded is off, or on inside its minimum pulse): a commanded pulse shorter than the
        dead time plus the minimum pulse, swallowed or stretched. The top's
        ``IRQ_STATUS.SHORT_EDGE`` takes it, so that the bit is set the clock after the edge.
    short_edge : Out(phases)
        ``short_edge_now`` registered: a strobe in the cycle after the short edge.
    fault : Out(1)
        The fault latch (registered).
    fault_input : Out(1)
        The synchronised fault input (registered).
    active : Out(1)
        The enable taken at the last update boundary and not cleared by a fault (registered).
    up, lo : Out(phases)
        The gates in the active-high domain (registered; before polarity).
    reaction : Out(2)
        The reaction in force (registered, reset 0): the one that decided this cycle's gates;
        0 all off or none, 1 ASC low, 2 ASC high.
    reaction_fault_acted, reaction_watchdog_acted : Out(2)
        Combinational: ``reaction_fault`` and ``reaction_watchdog`` as the driver acts on them
        (1 and 2 as they are; 0 and 3, and every value when ``asc`` is False, 0). The top's
        ``FAULT_REACTION`` reads them back.

    Parameters
    ----------
    phases : int >= 1
    dead_min, time_width, formal
        As :class:`LegDriver`.
    upper_active_low, lower_active_low : bool
        Pin polarity of each side, fixed at elaboration so that the reset level is safe.
    asc : bool
        Build the active short circuit in; False: every reaction is all off (``reaction`` 0).
    """

    def __init__(self, phases: int, dead_min: int, time_width: int = TIME_WIDTH,
                 upper_active_low: bool = False, lower_active_low: bool = False,
                 asc: bool = True, formal: bool = False):
        if isinstance(phases, bool) or not isinstance(phases, int) or phases < 1:
            raise ValueError(f"phases must be an integer >= 1, not {phases!r}")
        self.phases = phases
        self.time_width = validate_time_width(time_width)
        self.dead_min = validate_dead_min(dead_min, time_width)
        self.upper_active_low = validate_bool(upper_active_low, "upper_active_low")
        self.lower_active_low = validate_bool(lower_active_low, "lower_active_low")
        self.asc = validate_bool(asc, "asc")
        self.formal = validate_bool(formal, "formal")
        super().__init__({
            "h": In(phases),
            "update": In(1),
            "enable": In(1),
            "dead": In(time_width),
            "min_pulse": In(time_width),
            "fault_in": In(1),
            "fault_clear": In(1),
            "stop": In(1),
            "reaction_fault": In(2),
            "reaction_watchdog": In(2),
            "all_off": In(1),
            "upper": Out(phases),
            "lower": Out(phases),
            "event": Out(phases),
            "short_edge_now": Out(phases),
            "short_edge": Out(phases),
            "fault": Out(1),
            "fault_input": Out(1),
            "active": Out(1),
            "up": Out(phases),
            "lo": Out(phases),
            "reaction": Out(2),
            "reaction_fault_acted": Out(2),
            "reaction_watchdog_acted": Out(2),
        })

    def elaborate(self, platform):
        m = Module()
        n = self.phases
        m.submodules.fault_sync = FFSynchronizer(self.fault_in, self.fault_input, stages=2)

        # Fault latch: set dominates clear; a clear counts only while the input is inactive.
        with m.If(self.fault_input):
            m.d.sync += self.fault.eq(1)
        with m.Elif(self.fault_clear):
            m.d.sync += self.fault.eq(0)
        fault_active = Signal()      # named: the formal tests' "ungated fault" mutant cuts it
        m.d.comb += fault_active.eq(self.fault_input | self.fault)

        # The command followed in every cycle, the enable taken at update boundaries; a fault
        # clears the taken enable.
        # Every term the legs take is formed twice from registers, once as if a fault is active
        # and once as if none is, and ``fault_active`` picks one last: the synchronised fault
        # input passes one multiplexer on its way to the legs, not the reaction's logic (the
        # Fmax path of the tops on the UP5K and the HX8K).
        cmd_lat = Signal(n)
        cmd = Signal(n)
        drive = Signal()
        drive_if_clear = Signal()
        m.d.comb += [
            cmd.eq(self.h),
            drive_if_clear.eq(Mux(self.update, self.enable, self.active) & ~self.stop),  # no fault
            drive.eq(drive_if_clear & ~fault_active),
        ]
        m.d.sync += [cmd_lat.eq(cmd), self.active.eq(drive)]
        now_if_fault, now_if_clear = self._reaction(m, fault_active)
        asc_lo, asc_hi = Signal(), Signal()     # the reaction of this clock, one-hot
        leg_drive = Signal()
        m.d.comb += [
            asc_lo.eq(Mux(fault_active, now_if_fault == 1, now_if_clear == 1)),
            asc_hi.eq(Mux(fault_active, now_if_fault == 2, now_if_clear == 2)),
            # a leg leaving an ASC (the reaction of the last clock) is off for a clock
            leg_drive.eq(~fault_active & drive_if_clear & (self.reaction == 0)),
        ]

        legs = []
        for i in range(n):
            leg = LegDriver(self.dead_min, self.time_width, asc=self.asc, formal=self.formal)
            m.submodules[f"leg{i}"] = leg
            legs.append(leg)
            m.d.comb += [
                leg.cmd.eq(cmd[i]),
                leg.drive.eq(leg_drive),
                leg.asc_lo.eq(asc_lo),
                leg.asc_hi.eq(asc_hi),
                leg.dead.eq(self.dead),
                leg.min_pulse.eq(self.min_pulse),
            ]
        up = Cat(leg.upper for leg in legs)
        lo = Cat(leg.lower for leg in legs)
        followed = Cat(Mux(cmd_lat[i], leg.upper, leg.lower) & ~leg.in_min_pulse
                       for i, leg in enumerate(legs))
        m.d.comb += self.short_edge_now.eq(
            Mux(drive & self.active, (cmd ^ cmd_lat) & ~followed, 0))
        m.d.sync += self.short_edge.eq(self.short_edge_now)
        ones = (1 << n) - 1
        m.d.comb += [
            self.up.eq(up),
            self.lo.eq(lo),
            self.event.eq(Cat(leg.event for leg in legs)),
            # polarity last, on registers: an inverter after a flop cannot glitch
            self.upper.eq(up ^ (ones if self.upper_active_low else 0)),
            self.lower.eq(lo ^ (ones if self.lower_active_low else 0)),
        ]

        if self.formal:
            self._properties(m, up, lo)
            self._reaction_properties(m, up, lo, fault_active)
        return m

    def _code(self, reaction):
        """A source's reaction input as acted on: 1 and 2 as they are, 0 and 3 all off."""
        return Mux((reaction == 1) | (reaction == 2), reaction, 0)

    def _reaction(self, m, fault_active):
        """The reaction of this clock, registered into ``reaction``: ``(now_if_fault,
        now_if_clear)``, what it is with ``fault_active`` high and low, each from registers."""
        now_if_fault, now_if_clear = Signal(2), Signal(2)
        if not self.asc:
            return now_if_fault, now_if_clear      # all off only: nothing to latch
        fault_prev = Signal()
        stop_prev = Signal()
        f, w = self.reaction_fault_acted, self.reaction_watchdog_acted
        m.d.comb += [f.eq(self._code(self.reaction_fault)),
                     w.eq(self._code(self.reaction_watchdog))]
        rise_w = self.stop & ~stop_prev
        held = fault_prev | stop_prev               # the gates had left normal operation
        # the reaction becomes all off: on ALL_OFF, with no source high, or when a source
        # rises whose reaction is all off (with the fault high, it rises unless it was high)
        kill_common = self.all_off | (rise_w & (w == 0))     # either reaction, all off
        kill_if_fault = kill_common | (~fault_prev & (f == 0))
        kill_if_clear = kill_common | ~self.stop        # no fault: the watchdog's reaction
        m.d.comb += [
            now_if_fault.eq(Mux(kill_if_fault, 0, Mux(held, self.reaction, f))),
            now_if_clear.eq(Mux(kill_if_clear, 0, Mux(held, self.reaction, w))),
        ]
        m.d.sync += [self.reaction.eq(Mux(fault_active, now_if_fault, now_if_clear)),
                     fault_prev.eq(fault_active), stop_prev.eq(self.stop)]
        return now_if_fault, now_if_clear

    def _reaction_properties(self, m, up, lo, fault_active):
        """The fault reaction: only the ASC switches on while a latch is set (every switch
        off on the next clock after a latch rises but those); the reaction in force set only
        when the gates leave normal operation, to the rising source's reaction, and changed
        after that only to all off; an ASC left through all off; all off after reset, after
        CMD.ALL_OFF and with no latch set. On ghost registers, not the reaction's own."""
        ones = (1 << self.phases) - 1
        ghost = {name: Signal(width, reset_less=True, name=f"formal_{name}") for name, width in (
            ("stopped", 1), ("stopped2", 1), ("fault", 1), ("code_f", 2), ("code_w", 2),
            ("all_off", 1), ("reaction", 2), ("clear", 1), ("clear2", 1), ("rst", 1))}
        rst = ResetSignal()
        stopped = fault_active | self.stop
        m.d.sync += [
            ghost["stopped"].eq(stopped & ~rst), ghost["stopped2"].eq(ghost["stopped"]),
            ghost["fault"].eq(fault_active), ghost["code_f"].eq(self._code(self.reaction_fault)),
            ghost["code_w"].eq(self._code(self.reaction_watchdog)),
            ghost["all_off"].eq(self.all_off), ghost["reaction"].eq(self.reaction),
            ghost["clear"].eq(self.fault_clear), ghost["clear2"].eq(ghost["clear"]),
            ghost["rst"].eq(rst),
        ]
        r, r_prev, rst_prev = self.reaction, ghost["reaction"], ghost["rst"]
        gates_off = (up == 0) & (lo == 0)
        # the switches that may be on while a latch was set in the clock before
        only_asc = (((up & Mux(r == 2, 0, ones)) == 0) & ((lo & Mux(r == 1, 0, ones)) == 0))
        entered = (r != 0) & (r_prev == 0)
        m.d.comb += [
            Assert(r != 3, "a reaction in force that is no reaction"),
            Assert(~ghost["stopped"] | only_asc,
                   "a switch other than the ASC ones on a clock after a latch was set"),
            Assert(ghost["stopped"] | (r == 0) | rst_prev,
                   "a reaction in force a clock after no latch was set"),
            Assert(~rst_prev | (r == 0), "the reaction in force not all off after reset"),
            Assert(~entered | (~ghost["stopped2"] & (r == Mux(ghost["fault"], ghost["code_f"],
                                                                ghost["code_w"]))),
                   "an ASC entered other than when the gates left normal operation, or not "
                   "the rising source's"),
            Assert((r_prev == 0) | (r == 0) | (r == r_prev) | rst_prev,
                   "an ASC changed to the other one"),
            Assert(~((r_prev != 0) & (r == 0)) | gates_off,
                   "an ASC left other than through all off"),
            Assert(~(ghost["all_off"] & ghost["stopped"]) | rst_prev | ((r == 0) & gates_off),
                   "a switch on a clock after ALL_OFF while a latch was set"),
        ]
        if not self.asc:
            m.d.comb += Assert(r == 0, "an ASC without the ASC built in")
            return
        m.d.comb += [
            Cover((r == 1) & (lo == ones)),
            Cover((r == 2) & (up == ones)),
            Cover((r_prev != 0) & (r == 0) & ghost["all_off"]),
            Cover((r_prev != 0) & (r == 0) & ghost["clear2"] & ~ghost["all_off"] & ~self.stop),
        ]

    def _properties(self, m, up, lo):
        input_prev = Signal(reset_less=True)
        stop_prev = Signal(reset_less=True)
        fault_prev = Signal(reset_less=True)
        clear_prev = Signal(reset_less=True)
        rst_prev = Signal(reset_less=True)
        m.d.sync += [
            input_prev.eq(self.fault_input),
            stop_prev.eq(self.stop),
            fault_prev.eq(self.fault),
            clear_prev.eq(self.fault_clear),
            rst_prev.eq(ResetSignal()),
        ]
        all_off = (up == 0) & (lo == 0)
        # the pins read back through the polarity the parameters document: a wrong inversion
        # at the pins is shoot-through at the board (from reset, for a mixed pair); checked a
        # clock late, on ghost registers (the simulator evaluates a comb assert mid-settle)
        ones = (1 << self.phases) - 1
        pin_up = Signal(self.phases, reset_less=True)
        pin_lo = Signal(self.phases, reset_less=True)
        rst_before = Signal(reset_less=True)
        m.d.sync += [
            pin_up.eq(self.upper ^ (ones if self.upper_active_low else 0)),
            pin_lo.eq(self.lower ^ (ones if self.lower_active_low else 0)),
            rst_before.eq(rst_prev),
        ]
        m.d.comb += [
            Assert((pin_up & pin_lo) == 0, "both switches of a leg on at the pins"),
            Assert(~rst_before | ((pin_up == 0) & (pin_lo == 0)), "pins not off after reset"),
        ]
        # under an ASC its switches may be on (the reaction's own properties bound them)
        r = self.reaction
        off_but_asc = (((up & Mux(r == 2, 0, ones)) == 0) & ((lo & Mux(r == 1, 0, ones)) == 0))
        m.d.comb += [
            Assert(~input_prev | off_but_asc, "gates on one clock after the synchronised fault"),
            Assert(~stop_prev | off_but_asc, "gates on one clock after stop"),
            Assert(~(self.fault & fault_prev) | off_but_asc,
                   "gates on while the fault is latched"),
            Assert(~input_prev | rst_prev | self.fault, "synchronised fault not latched"),
            Assert(~fault_prev | rst_prev | self.fault | (clear_prev & ~input_prev),
                   "fault latch cleared without a clear while the input was inactive"),
            Assert(~rst_prev | (~self.active & all_off), "not all off after reset"),
            Assert((up & lo) == 0, "both switches of a leg on"),
            Cover(fault_prev & ~self.fault),
            Cover(self.fault_input & (up != 0)),
            Cover(self.stop & (up != 0)),
        ]
