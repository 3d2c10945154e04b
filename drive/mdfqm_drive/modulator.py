"""The drop-in top as a source of gate edges: the golden model's arithmetic, update by update,
and the gate driver's rules applied edge by edge instead of clock by clock.

A drive simulation at a real clock (48 MHz here) cannot afford the clock-level model
(:class:`mdfqm_model.top.TopModel`, one Python call per clock). :class:`IpModulator` computes the
same pins from the same contract (docs/top.md, "Update timing and the ADC trigger", "Modulation
mode and resolution", the gate driver's four rules), skipping the clocks in which nothing
changes:

- update ``k`` starts in cycle ``s_k = k P`` (P the period in force: ``PERIOD`` raised to the
  mode's smallest period); a sampling tick every ``OSR`` updates takes the last written
  reference (zero-order hold);
- its state(s) come from :func:`mdfqm_model.bbit.bbit_update` (MDFQM: one state; a slot mode:
  ``2**b`` slots of ``floor(P / 2**b)`` clocks, the last with the remainder), presented to the
  driver from ``c_k = s_k + L`` (``L_b`` in a slot mode);
- the driver, per leg: a switch that is on and no longer commanded turns off in the clock after
  the command changed, or once it has been on ``MIN_PULSE`` clocks; once both have been off
  ``dt = max(DEAD, dead_min)`` clocks, the commanded one turns on; the enable is taken at the
  first update boundary;
- the ADC trigger pulses in cycle ``s_k + 1 + ADC_OFFSET`` (none when ``ADC_OFFSET >= P``).

``tests/test_modulator.py`` checks the pins clock for clock against ``TopModel`` programmed
through its Wishbone registers, for every mode. A run keeps one mode (a mode change in a run is
outside this fast path: use ``TopModel``).
"""

from __future__ import annotations

from dataclasses import dataclass

from mdfqm_model.bbit import bbit_update
from mdfqm_model.update import remove_common_mode
from mdfqm_spec.contract import (
    ALL_OFF,
    MODES,
    Contract,
    latch_mode,
    loop_latency,
    min_period,
    resolution_latency,
    validate_dead_min,
    validate_zero_policy,
)
from mdfqm_spec.regmap import DEFAULT_DEAD_MIN, default_max_bits

__all__ = ["IpModulator", "IpSettings", "Update"]

_FAR_PAST = -(1 << 40)


@dataclass(frozen=True)
class IpSettings:
    """The registers a firmware sets (docs/top.md's register map) and the IP's clock.

    ``period`` PERIOD (clocks per update), ``osr`` OSR (updates per reference sample), ``dead``
    DEAD and ``min_pulse`` MIN_PULSE (clocks), ``adc_offset`` ADC_OFFSET, ``mode`` the name of
    MODULATION.MODE (``mdfqm``, ``svpwm``, ``dpwm0``, ``dpwm1``, ``dpwm``), ``bits``
    MODULATION.BITS, ``zero_policy`` CTRL.ZERO_POLICY; ``f_clk`` the clock (Hz).
    """

    period: int
    osr: int = 1
    dead: int = 0
    min_pulse: int = 0
    adc_offset: int = 0
    mode: str = "mdfqm"
    bits: int = 0
    zero_policy: int = ALL_OFF
    f_clk: float = 48e6

    def __post_init__(self):
        for name, top in (("period", 65535), ("osr", 255), ("dead", 65535),
                          ("min_pulse", 65535), ("adc_offset", 65535), ("bits", 15)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= top:
                raise ValueError(f"IpSettings.{name} must be an integer in [0, {top}], "
                                 f"not {value!r}")
        if self.mode not in MODES:
            raise ValueError(f"IpSettings.mode must be one of {MODES}, not {self.mode!r}")
        validate_zero_policy(self.zero_policy)
        if not self.f_clk > 0:
            raise ValueError(f"IpSettings.f_clk must be > 0, not {self.f_clk!r}")


@dataclass
class Update:
    """What one update puts on the pins.

    ``start`` its first cycle ``s``; ``tick`` whether it is a sampling tick; ``adc`` the ADC
    trigger's cycle or None; ``edges`` the pin changes it decides, ``(cycle, upper, lower)``
    (the masks hold from that cycle on), in cycles ``(c, c + P]``; ``states`` the generator's
    slot states; ``saturated`` the integrator's hold flag.
    """

    start: int
    tick: bool
    adc: int | None
    edges: list
    states: tuple
    saturated: bool


class _Leg:
    """One leg's driver state: which switch is on (1 upper, 0 lower, None: both off) and the
    first cycle of that state."""

    __slots__ = ("on", "since")

    def __init__(self):
        self.on = None
        self.since = _FAR_PAST

    def follow(self, commands, end: int, dt: int, mp: int):
        """Apply the commands ``[(cycle, value), ...]`` (value from that cycle on, the first at the
        window's start) up to the output of cycle ``end``; yield ``(cycle, on)`` changes."""
        t = commands[0][0]
        n = len(commands)

        def value_at(cycle):
            v = commands[0][1]
            for c, val in commands:
                if c > cycle:
                    break
                v = val
            return v

        while t < end:
            if self.on is not None:
                # first cycle >= max(t, since + mp - 1) whose command names the other switch
                tau = max(t, self.since + mp - 1)
                found = None
                for idx in range(n):
                    c0 = commands[idx][0]
                    c1 = commands[idx + 1][0] if idx + 1 < n else end
                    if c1 <= tau or commands[idx][1] == self.on:
                        continue
                    found = max(c0, tau)
                    break
                if found is None or found >= end:
                    return
                self.on, self.since = None, found + 1
            else:
                tau = max(t, self.since + dt - 1)
                if tau >= end:
                    return
                self.on, self.since = value_at(tau), tau + 1
            t = self.since
            yield self.since, self.on


class IpModulator:
    """The top's pins, update by update (see the module docstring).

    Elaboration parameters as :class:`mdfqm_gateware.top.MdfqmTop`'s: ``phases`` (3: the plant
    is three-phase), ``width``, ``rule``, ``max_bits``, ``dead_min``.
    """

    def __init__(self, settings: IpSettings, phases: int = 3, width: int = 16,
                 rule: str = "largest_duty", max_bits: int | None = None,
                 dead_min: int = DEFAULT_DEAD_MIN):
        self.settings = settings
        self.contract = Contract(phases, width)
        self.phases = phases
        self.rule = rule
        self.max_bits = default_max_bits(width) if max_bits is None else max_bits
        mode, b, self.mode_clamped = latch_mode(MODES.index(settings.mode), settings.bits,
                                                self.max_bits)
        self.mode = MODES[mode]
        self.b = b
        short = loop_latency(phases, rule)
        long_latency = resolution_latency(phases, self.max_bits) if self.max_bits else short
        slot_mode = mode != 0
        self.latency = long_latency if slot_mode else short
        self.period = max(settings.period, min_period(slot_mode, b, short, long_latency))
        self.slots = 1 << b
        self.slot_len = self.period // self.slots
        self.dt = max(settings.dead, validate_dead_min(dead_min))
        self.mp = settings.min_pulse
        self.osr = max(settings.osr, 1)
        self.f_clk = settings.f_clk
        self.reset()

    def reset(self) -> None:
        n = self.phases
        self.k = 0
        self.x = (0,) * n
        self.r = (0,) * n
        self.pending = None
        self.h = 0
        self.legs = [_Leg() for _ in range(n)]
        self.pins = (0, 0)

    @property
    def update_rate(self) -> float:
        return self.f_clk / self.period

    @property
    def control_period(self) -> float:
        """Seconds between sampling ticks: ``OSR * P / f_clk``."""
        return self.osr * self.period / self.f_clk

    def full_scale(self) -> int:
        """Codes per Vdc (``FULL``)."""
        return self.contract.full

    def write_reference(self, codes) -> None:
        """A reference written and committed (REF[i] + CMD.REF_COMMIT): taken at the next
        sampling tick. ``codes``: one signed ``width``-bit code per phase, FULL per Vdc."""
        c = self.contract
        clamped = tuple(min(max(int(v), c.code_min), c.code_max) for v in codes)
        if len(clamped) != self.phases:
            raise ValueError(f"a reference has {self.phases} codes, not {len(clamped)}")
        self.pending = clamped

    def next_update(self) -> Update:
        """Advance by one update: its start, tick, ADC trigger and the pin changes it decides."""
        s = self.k * self.period
        tick = self.k % self.osr == 0
        if tick and self.pending is not None:
            self.r = tuple(remove_common_mode(self.pending, self.phases))
            self.pending = None
        res = bbit_update(self.x, self.r, self.contract, self.mode, self.b, self.h, self.rule,
                          self.settings.zero_policy)
        self.x = res.x_next
        states = res.slots
        self.h = states[-1]
        c = s + self.latency
        end = c + self.period
        edges = self._drive(c, end, states)
        a = self.settings.adc_offset
        adc = s + 1 + a if a < self.period else None
        self.k += 1
        return Update(s, tick, adc, edges, states, res.saturated)

    def _drive(self, c: int, end: int, states) -> list:
        """The pin changes in cycles ``(c, end]`` from the slot states presented from ``c``."""
        starts = [c + j * self.slot_len for j in range(len(states))]
        changes = {}
        for i, leg in enumerate(self.legs):
            commands = [(starts[0], (states[0] >> i) & 1)]
            for st, h in zip(starts[1:], states[1:], strict=True):
                v = (h >> i) & 1
                if v != commands[-1][1]:
                    commands.append((st, v))
            for cycle, on in leg.follow(commands, end, self.dt, self.mp):
                changes.setdefault(cycle, []).append((i, on))
        edges = []
        upper, lower = self.pins
        for cycle in sorted(changes):
            for i, on in changes[cycle]:
                bit = 1 << i
                upper = (upper | bit) if on == 1 else (upper & ~bit)
                lower = (lower | bit) if on == 0 else (lower & ~bit)
            edges.append((cycle, upper, lower))
        self.pins = (upper, lower)
        return edges
