"""Clock-level model of the gate driver: dead time, minimum pulse, enable, fault, polarity.

This is the specification of :mod:`mdfqm_gateware.driver`; the gateware must produce every bit
on every clock that :class:`GateDriverModel` predicts. ``step`` returns the outputs visible
*during* a cycle (a function of the registers only, like :class:`mdfqm_model.clock.CoreModel`,
except ``short_edge_now`` and the two ``*_acted`` codes, which also depend on that cycle's
inputs), then advances the
registers with that cycle's inputs. ``rst`` is synchronous.

One leg (:class:`LegModel`)
---------------------------
Registers, all in the *active-high* domain (1 = switch on), reset to zero unless noted:

- ``up``, ``lo``: the upper and lower gate of the leg (the outputs, registered).
- ``cnt``: clocks since ``on = up | lo`` last changed, saturating at ``2**time_width - 1``.
  While both are off it is the elapsed dead time (0 in the first off cycle), while one is on it
  is that switch's on-time so far (0 in its first on cycle).
- ``dt_run`` (**not reset**): the dead time in force when the current off interval began: the
  clamped dead-time input of the last cycle in which a switch was on. It is kept through a
  reset, so a reset cannot shorten a dead time that is already running.
- ``event``: one-clock strobe, high in the cycle in which a switch's turn-on becomes visible.

Inputs: ``cmd`` (1: upper on, 0: lower on), ``drive`` (0: both off now), ``asc`` (the fault
reaction: 0 none, 1 active short circuit low, 2 active short circuit high; the driver never
gives a nonzero ``asc`` together with ``drive``), ``dead`` and ``min_pulse`` (unsigned
``time_width``-bit clocks). With ``dt = max(dead, dead_min)`` (the floor ``dead_min`` is fixed
at elaboration) and ``dt_req = max(dt_run, dt)``, the next state is:

0. ``asc`` 1 (2): the *ASC switch* is the lower (upper) one. It stays on if it is on; the other
   switch, if on, turns off now (the minimum pulse is ignored, as on a fault); from both off the
   ASC switch turns on if ``cnt + 1 >= dt_req`` (the dead time, as rule 4), else both stay off.
1. ``drive == 0``: both off (fault and disable override the minimum pulse).
2. a switch is on and it is the commanded one: keep it.
3. a switch is on, the other one is commanded: turn it off if ``cnt + 1 >= min_pulse``
   (it has been on for ``min_pulse`` clocks by the end of this cycle), else keep it: **pulses
   are stretched to min_pulse, never dropped**. ``min_pulse`` 0 and 1 mean "no minimum".
4. both off: turn the commanded switch on if ``cnt + 1 >= dt_req`` (both have been off for
   ``dt_req`` clocks by the end of this cycle), else stay off.

``cnt <= 0`` if ``on`` changes, else ``min(cnt + 1, max)``; ``dt_run <= dt`` while ``on``;
``event <= not on and next on``.

Consequences (checked by :func:`check_gate_safety` and the tests): ``up & lo`` is never 1; every
turn-on follows at least ``dt_req`` off clocks (at least the dead time in force when the off
interval began, and at least the one in force when the turn-on is decided, so raising ``dead``
lengthens a running dead time at once and lowering it only affects later ones); a commanded
pulse of ``w`` clocks gives an on-time of ``max(w - dt, min_pulse)`` clocks when ``w > dt``; a
command that reverts within the dead time turns nothing on (the dead time swallows it, as in any
dead-time inserter), and the previously-on switch comes back after the dead time.

The N-leg driver (:class:`GateDriverModel`)
-------------------------------------------
- ``dead`` and ``min_pulse`` reach the legs through a register (``dead_seen``,
  ``min_pulse_seen``; **not reset**, power-up 0): the legs above act in cycle ``t`` on the
  values given in cycle ``t - 1``, so a new dead time or minimum pulse acts one clock after it
  arrives. This lets the gateware decide from flags computed a clock ahead (its Fmax path).
- Fault synchroniser: two flops (**not reset**, like every synchroniser)
  ``s1 <= fault_in``, ``fault_input <= s1``.
- Fault latch ``fault`` (reset 0): ``<= 1`` if ``fault_input``, else ``<= 0`` if ``fault_clear``,
  else hold. A clear while the synchronised input is still active does nothing.
  ``fault_active = fault_input | fault``.
- The command follows ``h`` in every cycle (``cmd = h``: the core's ``h`` changes only at
  update boundaries, the generator's also at the slot boundaries of a slot mode, and the driver
  applies its rules to every edge alike); the enable is taken at update boundaries only:
  ``en = enable if update else active``; ``cmd_lat <= cmd``; ``active <= en and not
  fault_active and not stop``. So a fault also clears ``active``: after a clear, outputs resume
  only at the next update boundary with ``enable`` high.
- ``stop`` (the top's watchdog latch, a synchronous input) acts like ``fault_active`` in the
  cycle it is high: ``drive`` low, every output off in the next cycle, ``active`` cleared.
- Short edges (``short_edge_now``, combinational per leg: high in a cycle in which leg ``i``'s
  command changes (``cmd[i] != cmd_lat[i]``) while the leg is driven in this cycle and the
  last (``drive and active``) and has not yet followed the last change: the switch
  ``cmd_lat[i]`` names is not on, or it is on but still inside its minimum pulse
  (``cnt + 1 < min_pulse_seen``). Such an edge ends a commanded pulse shorter than the dead time
  plus the minimum pulse, which the rules above swallow (the dead time) or stretch (the minimum
  pulse): safe, but not what was commanded, so it is reported, never silent: the top sets
  ``IRQ_STATUS.SHORT_EDGE`` from it, the clock after the edge. ``short_edge`` (reset 0) is the
  same, registered: high in the cycle after the edge.
- Each leg: ``drive = en and not fault_active and not stop``. A synchronised fault (or
  ``stop``) visible in cycle ``t`` turns every output off in cycle ``t + 1`` (every output but
  the ASC switches under an active short circuit, below).
- The fault reaction (``asc`` parameter True: the active short circuit built in; False: all
  off only). The *sources* are the fault (``fault_active``) and ``stop`` (the watchdog latch);
  a source *rises* in a cycle in which it is high and was low in the cycle before (registers
  ``fault_prev``, ``stop_prev``, reset 0: a source high in the first cycle after a reset rises).
  The inputs ``reaction_fault`` and ``reaction_watchdog`` (2 bits each) name each source's
  reaction: 1 ASC low, 2 ASC high; 0, 3, and any value when ``asc`` is False, all off (the
  outputs ``reaction_fault_acted`` and ``reaction_watchdog_acted``: each input as acted on, 0
  for all off, in the same cycle; the top's ``FAULT_REACTION`` reads them back). The
  reaction *now* of a cycle:

  - 0 (all off) if neither source is high, or ``all_off`` (the CMD.ALL_OFF strobe) is high, or
    a source rises whose reaction is all off;
  - otherwise, if neither source was high in the cycle before (the gates leave normal
    operation): the rising source's reaction (both rising: the fault's, when the watchdog's
    is not all off, by the previous rule);
  - otherwise the reaction in force ``reaction`` (held: a later write of the inputs does not
    change it, and ASC low never becomes ASC high or the reverse).

  ``reaction <= now`` (reset 0); ``reaction`` is the output ``reaction`` (the top's
  ``STATUS.REACTION``): the reaction that decided the gates of this cycle. Each leg gets
  ``asc = now`` (rule 0 above) and ``drive and reaction == 0``: in the cycle after the reaction
  in force goes from an ASC to all off (``ALL_OFF``, or both sources clear), every switch is off,
  even when the enable is taken in that cycle (it is: ``active`` follows ``drive``); the dead
  time then guards the next turn-on.
- Pins: ``upper = up ^ upper_active_low``, ``lower = lo ^ lower_active_low`` (the inversion is
  applied last, to registers).

Inputs must be in range (``h`` an N-bit mask, bits 0/1, ``dead``/``min_pulse`` unsigned
``time_width`` bits), otherwise ``ValueError``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from mdfqm_spec.contract import TIME_WIDTH, validate_dead_min, validate_time_width
from mdfqm_spec.validate import validate_bool

from .inputs import check_bit, check_uint, stimulus_columns

__all__ = [
    "DRIVER_INPUTS",
    "DRIVER_OUTPUTS",
    "GateDriverModel",
    "LegModel",
    "SafetyError",
    "check_gate_safety",
]

#: inputs of :meth:`GateDriverModel.step` (and the gateware's ports, ``rst`` its reset)
DRIVER_INPUTS = ("rst", "h", "update", "enable", "dead", "min_pulse", "fault_in", "fault_clear",
                 "stop", "reaction_fault", "reaction_watchdog", "all_off")
#: per-cycle outputs of :meth:`GateDriverModel.step`
DRIVER_OUTPUTS = ("upper", "lower", "event", "fault", "fault_input", "active", "short_edge",
                  "short_edge_now", "reaction", "reaction_fault_acted", "reaction_watchdog_acted")


class LegModel:
    """One leg: complementary gates with dead time and minimum pulse (see the module docstring)."""

    def __init__(self, dead_min: int, time_width: int = TIME_WIDTH):
        self.time_width = validate_time_width(time_width)
        self.dead_min = validate_dead_min(dead_min, time_width)
        self.top = (1 << time_width) - 1
        self.dt_run = 0  # not reset: its power-up value
        self.reset()

    def reset(self) -> None:
        """The reset state of every resettable register (``dt_run`` keeps its value)."""
        self.up = 0
        self.lo = 0
        self.cnt = 0
        self.event = 0

    def dead_clamped(self, dead: int) -> int:
        return max(dead, self.dead_min)

    def next_state(self, cmd: int, drive: int, dead: int, min_pulse: int,
                   asc: int = 0) -> tuple[int, int]:
        """``(up, lo)`` of the next cycle, from this cycle's registers and inputs."""
        on = self.up or self.lo
        if asc:
            want_up, want_lo = int(asc == 2), int(asc == 1)
            if on:
                return self.up & want_up, self.lo & want_lo
            if self.cnt + 1 >= max(self.dt_run, self.dead_clamped(dead)):
                return want_up, want_lo
            return 0, 0
        if not drive:
            return 0, 0
        want_up, want_lo = int(cmd == 1), int(cmd == 0)
        if on:
            if (self.up and want_up) or (self.lo and want_lo):
                return self.up, self.lo
            if self.cnt + 1 >= min_pulse:
                return 0, 0
            return self.up, self.lo
        dt_req = max(self.dt_run, self.dead_clamped(dead))
        if self.cnt + 1 >= dt_req:
            return want_up, want_lo
        return 0, 0

    def step(self, rst: int, cmd: int, drive: int, dead: int, min_pulse: int,
             asc: int = 0) -> dict:
        """Outputs of this cycle (``up``, ``lo``, ``event``, active-high), then advance."""
        out = {"up": self.up, "lo": self.lo, "event": self.event}
        on = int(self.up or self.lo)
        n_dt_run = self.dead_clamped(dead) if on else self.dt_run
        if rst:
            self.reset()
        else:
            n_up, n_lo = self.next_state(cmd, drive, dead, min_pulse, asc)
            n_on = int(n_up or n_lo)
            self.cnt = 0 if n_on != on else min(self.cnt + 1, self.top)
            self.event = int(not on and n_on)
            self.up, self.lo = n_up, n_lo
        self.dt_run = n_dt_run
        return out


class GateDriverModel:
    """N legs, the fault synchroniser and latch, the enable and command latches and polarity.

    ``phases`` N >= 1 legs, ``dead_min`` the dead-time floor in clocks (>= 1), ``time_width``
    the width of ``dead`` / ``min_pulse``, ``upper_active_low`` / ``lower_active_low`` the pin
    polarity of each side (elaboration-time, never runtime: see ``docs/top.md``), ``asc``
    whether the active short circuit is built in (False: every reaction is all off).
    """

    def __init__(
        self,
        phases: int,
        dead_min: int,
        time_width: int = TIME_WIDTH,
        upper_active_low: bool = False,
        lower_active_low: bool = False,
        asc: bool = True,
    ):
        if isinstance(phases, bool) or not isinstance(phases, int) or phases < 1:
            raise ValueError(f"phases must be an integer >= 1, not {phases!r}")
        self.phases = phases
        self.time_width = validate_time_width(time_width)
        self.dead_min = validate_dead_min(dead_min, time_width)
        self.upper_active_low = validate_bool(upper_active_low, "upper_active_low")
        self.lower_active_low = validate_bool(lower_active_low, "lower_active_low")
        self.asc = validate_bool(asc, "asc")
        self.mask = (1 << phases) - 1
        self.legs = [LegModel(dead_min, time_width) for _ in range(phases)]
        self.sync1 = 0  # the synchroniser is not reset
        self.fault_input = 0
        self.dead_seen = 0       # the input registers of dead and min_pulse are not reset
        self.min_pulse_seen = 0
        self.reset()

    def reset(self) -> None:
        """Reset state of every resettable register."""
        self.fault = 0
        self.active = 0
        self.cmd_lat = 0
        self.short_edge = 0
        self.reaction = 0
        self.fault_prev = 0
        self.stop_prev = 0
        for leg in self.legs:
            leg.reset()

    # ------------------------------------------------------------------ views
    @property
    def up(self) -> int:
        """Upper gates, active-high bitmask."""
        return sum(leg.up << i for i, leg in enumerate(self.legs))

    @property
    def dead_in_force(self) -> int:
        """The clamped dead time the legs act on in this cycle (``max(dead_seen, dead_min)``):
        the ``dead`` trace :func:`check_gate_safety` takes."""
        return max(self.dead_seen, self.dead_min)

    @property
    def lo(self) -> int:
        """Lower gates, active-high bitmask."""
        return sum(leg.lo << i for i, leg in enumerate(self.legs))

    def outputs(self) -> dict:
        return {
            "upper": self.up ^ (self.mask if self.upper_active_low else 0),
            "lower": self.lo ^ (self.mask if self.lower_active_low else 0),
            "event": sum(leg.event << i for i, leg in enumerate(self.legs)),
            "fault": self.fault,
            "fault_input": self.fault_input,
            "active": self.active,
            "short_edge": self.short_edge,
            "reaction": self.reaction,
        }

    def reaction_code(self, value: int) -> int:
        """A source's reaction input as the driver acts on it: 1 ASC low, 2 ASC high, else 0
        (3, and every value without the active short circuit built in)."""
        return value if self.asc and value in (1, 2) else 0

    def reaction_now(self, fault_active: int, stop: int, reaction_fault: int,
                     reaction_watchdog: int, all_off: int) -> int:
        """The reaction of this cycle (module docstring, "The fault reaction")."""
        if not (fault_active or stop):
            return 0
        f, w = self.reaction_code(reaction_fault), self.reaction_code(reaction_watchdog)
        rise_f = fault_active and not self.fault_prev
        rise_w = stop and not self.stop_prev
        if all_off or (rise_f and f == 0) or (rise_w and w == 0):
            return 0
        if not (self.fault_prev or self.stop_prev):
            return f if rise_f else w
        return self.reaction

    def short_edges(self, cmd: int, drive: int) -> int:
        """The legs whose command ``cmd`` of this cycle is a short edge (module docstring)."""
        if not (drive and self.active):
            return 0
        short = 0
        for i, leg in enumerate(self.legs):
            last = (self.cmd_lat >> i) & 1
            if (cmd >> i) & 1 == last:
                continue
            followed = (leg.up if last else leg.lo) and leg.cnt + 1 >= self.min_pulse_seen
            short |= int(not followed) << i
        return short

    # ------------------------------------------------------------------ one clock
    def step(
        self, rst=0, h=0, update=0, enable=0, dead=0, min_pulse=0, fault_in=0, fault_clear=0,
        stop=0, reaction_fault=0, reaction_watchdog=0, all_off=0,
    ) -> dict:
        rst = check_bit(rst, "rst")
        h = check_uint(h, self.phases, "h")
        update = check_bit(update, "update")
        enable = check_bit(enable, "enable")
        dead = check_uint(dead, self.time_width, "dead")
        min_pulse = check_uint(min_pulse, self.time_width, "min_pulse")
        fault_in = check_bit(fault_in, "fault_in")
        fault_clear = check_bit(fault_clear, "fault_clear")
        stop = check_bit(stop, "stop")
        reaction_fault = check_uint(reaction_fault, 2, "reaction_fault")
        reaction_watchdog = check_uint(reaction_watchdog, 2, "reaction_watchdog")
        all_off = check_bit(all_off, "all_off")
        out = self.outputs()

        fault_active = self.fault_input or self.fault
        cmd = h
        en = enable if update else self.active
        drive = int(en and not fault_active and not stop)
        short = self.short_edges(cmd, drive)
        out["short_edge_now"] = short
        out["reaction_fault_acted"] = self.reaction_code(reaction_fault)
        out["reaction_watchdog_acted"] = self.reaction_code(reaction_watchdog)
        now = self.reaction_now(int(bool(fault_active)), stop, reaction_fault,
                                reaction_watchdog, all_off)
        leg_drive = int(drive and self.reaction == 0)
        for i, leg in enumerate(self.legs):
            leg.step(rst, (cmd >> i) & 1, leg_drive, self.dead_seen, self.min_pulse_seen, now)
        self.dead_seen, self.min_pulse_seen = dead, min_pulse
        if rst:
            self.reset()
        else:
            if self.fault_input:
                self.fault = 1
            elif fault_clear:
                self.fault = 0
            self.cmd_lat = cmd
            self.active = drive
            self.short_edge = short
            self.reaction = now
            self.fault_prev = int(bool(fault_active))
            self.stop_prev = stop
        self.fault_input, self.sync1 = self.sync1, fault_in
        return out

    def simulate(self, stim: Mapping[str, object]) -> dict:
        """Run ``C`` cycles; ``stim`` maps :meth:`step`'s input names to arrays or scalars."""
        return _simulate(self.step, DRIVER_INPUTS, DRIVER_OUTPUTS, stim)


def _simulate(step, names, outputs, stim) -> dict:
    cols, c = stimulus_columns(stim, names)
    out = {k: np.zeros(c, dtype=np.int64) for k in outputs}
    for i in range(c):
        kw = {n: (v[i] if kind == "array" else v) for n, (kind, v) in cols.items()}
        o = step(**kw)
        for k in outputs:
            out[k][i] = o[k]
    return out


# ------------------------------------------------------------------------------ safety checker


class SafetyError(AssertionError):
    """An unsafe gate pattern: both switches of a leg on, a short dead time, a missed fault."""


def check_gate_safety(
    up: Sequence[int],
    lo: Sequence[int],
    phases: int,
    dead: Sequence[int] | None = None,
    kill: Sequence[int] | None = None,
    rst: Sequence[int] | None = None,
    dt_run0: Sequence[int] | None = None,
    reaction: Sequence[int] | None = None,
) -> int:
    """Check the absolute safety properties on an active-high gate trace, independently of
    :class:`LegModel`'s state machine. Raises :class:`SafetyError`, returns the number of
    turn-ons seen.

    ``up`` / ``lo``: per-cycle N-bit masks (1 = on), cycle 0 being the first cycle after a reset.
    ``dead``: per-cycle clamped dead time ``max(DEAD, dead_min)``. Properties:

    1. never ``up & lo``;
    2. a turn-on in cycle ``t`` follows at least ``g`` clocks with both switches of the leg off,
       ``g >= dead[t0 - 1]`` (the dead time in force in the last on cycle before the off
       interval, or ``dt_run0`` for an interval that began before cycle 0) and
       ``g >= dead[t - 1]`` (the one in force when the turn-on was decided); the interval
       open at cycle 0 counts from cycle 0;
    3. ``kill[t]`` (e.g. the synchronised fault) high: every gate off in cycle ``t + 1``, but
       the ASC switches of ``reaction[t + 1]`` when given (the reaction in force in that cycle:
       1 the lower switches may be on, 2 the upper ones);
    4. ``rst[t]`` high: every gate off in cycle ``t + 1``.
    """
    up = np.asarray(up, dtype=np.int64)
    lo = np.asarray(lo, dtype=np.int64)
    c = len(up)
    mask = (1 << phases) - 1
    both = np.flatnonzero(up & lo)
    if len(both):
        t = int(both[0])
        raise SafetyError(f"cycle {t}: both switches on, up={up[t]:#x} lo={lo[t]:#x}")
    asc = np.zeros(c, dtype=np.int64) if reaction is None else np.asarray(reaction, np.int64)
    for name, arr in (("kill", kill), ("rst", rst)):
        if arr is None:
            continue
        arr = np.asarray(arr, dtype=np.int64)
        others_up, others_lo = up, lo
        if name == "kill":
            others_up = np.where(asc == 2, 0, up)
            others_lo = np.where(asc == 1, 0, lo)
        hits = np.flatnonzero(arr[:-1] & (((others_up[1:] | others_lo[1:]) & mask) != 0))
        if len(hits):
            t = int(hits[0])
            raise SafetyError(f"cycle {t + 1}: gates on one clock after {name} (cycle {t})")
    turn_ons = 0
    for leg in range(phases):
        on = ((up >> leg) | (lo >> leg)) & 1
        gap = 0  # off cycles so far in the current interval
        need = 0 if dt_run0 is None else int(dt_run0[leg])
        for t in range(c):
            if on[t]:
                if t > 0 and not on[t - 1]:
                    turn_ons += 1
                    if dead is not None:
                        need_now = max(need, int(dead[t - 1]))
                        if gap < need_now:
                            raise SafetyError(
                                f"cycle {t}: leg {leg} turned on after {gap} off clocks, "
                                f"dead time in force {need_now}"
                            )
                gap = 0
                if dead is not None:
                    need = int(dead[t])
            else:
                gap += 1
    return turn_ons
