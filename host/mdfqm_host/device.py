"""The demo device in physical units: frequency, amplitude, modulation mode and resolution,
zero policy, dead time, watchdog, counters.

The modulator is the drop-in top ``MdfqmTop`` (register map in ``docs/top.md``, constants from
:mod:`mdfqm_spec.regmap`) at ``TOP_BASE``; the demo's own block is
:func:`mdfqm_spec.regmap.demo_window`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mdfqm_spec import regmap as top
from mdfqm_spec.contract import MODES as MODULATIONS
from mdfqm_spec.regmap import ID_VALUE, INFO_TOP, TOP_BASE, demo_window

from .client import Client

__all__ = ["MODULATIONS", "TOP_MAP", "ZERO_POLICIES", "Counters", "DemoDevice", "DeviceInfo",
           "Status"]

#: CLI zero-policy name -> CTRL.ZERO_POLICY (MDFQM's choice between the two zero states)
ZERO_POLICIES = {"all-off": 0, "fewest-transitions": 1}


@dataclass(frozen=True)
class ModulatorMap:
    """Addresses and bits of the modulator window that the host uses."""

    name: str
    ctrl: int
    period: int
    osr: int
    dead: int
    min_pulse: int
    status: int
    dead_min: int
    fault_clear: tuple          # (address, value) of the write that clears the fault latch
    status_bits: dict           # name -> bit mask
    time_max: int               # largest DEAD / MIN_PULSE value
    ctrl_enable: int
    ctrl_zero_policy: int
    info: int
    modulation: int
    watchdog: int
    watchdog_trips: int
    watchdog_clear: tuple       # (address, value) of the write that clears the watchdog latch
    events: int                 # EVENTS_0; leg i's switching counter at events + i


TOP_MAP = ModulatorMap(
    "MdfqmTop", ctrl=TOP_BASE + top.CTRL, period=TOP_BASE + top.PERIOD,
    osr=TOP_BASE + top.OSR, dead=TOP_BASE + top.DEAD, min_pulse=TOP_BASE + top.MIN_PULSE,
    status=TOP_BASE + top.STATUS, dead_min=TOP_BASE + top.DEAD_MIN,
    fault_clear=(TOP_BASE + top.CMD, top.CMD_FAULT_CLEAR),
    status_bits={"fault": top.STATUS_FAULT, "fault_input": top.STATUS_FAULT_INPUT,
                 "active": top.STATUS_ACTIVE, "ref_pending": top.STATUS_REF_PENDING,
                 "saturated": top.STATUS_SATURATED, "period_clamped": top.STATUS_PERIOD_CLAMPED,
                 "mode_clamped": top.STATUS_MODE_CLAMPED, "watchdog": top.STATUS_WATCHDOG},
    time_max=0xFFFF, ctrl_enable=top.CTRL_ENABLE, ctrl_zero_policy=top.CTRL_ZERO_POLICY,
    info=TOP_BASE + top.INFO, modulation=TOP_BASE + top.MODULATION,
    watchdog=TOP_BASE + top.WATCHDOG, watchdog_trips=TOP_BASE + top.WATCHDOG_TRIPS,
    watchdog_clear=(TOP_BASE + top.CMD, top.CMD_WATCHDOG_CLEAR),
    events=TOP_BASE + top.EVENTS_BASE)


@dataclass(frozen=True)
class DeviceInfo:
    clk_hz: int
    phases: int
    width: int
    acc_bits: int
    top: bool
    max_bits: int               # largest resolution b of the slot modes (0: MDFQM-only top)
    modes: int                  # modulation modes built in: MODULATIONS[:modes]
    asc: bool = False           # the active short circuit built in (INFO.ASC)
    watchdog: bool = False      # the reference watchdog built in (INFO.WATCHDOG)

    @property
    def full(self) -> int:
        """Reference codes per Vdc."""
        return 1 << (self.width - 2)


@dataclass(frozen=True)
class Status:
    enabled: bool
    flags: dict
    freq_hz: float
    amplitude: float
    zero_policy: str
    modulation: str             # the mode in force (MODULATION read back)
    bits: int                   # b in force (0 in MDFQM)
    update_hz: float
    osr: int
    dead_ns: float
    min_pulse_ns: float
    watchdog: int               # timeout in update starts (0: off)
    watchdog_trips: int


@dataclass(frozen=True)
class Counters:
    cycles: int
    switches: tuple

    def rates(self, earlier: Counters, clk_hz: int) -> tuple[float, tuple[float, ...]]:
        """Seconds between two snapshots and each leg's switching frequency in Hz (two
        turn-ons per switching period: upper and lower), from 32-bit wrapping counters."""
        cycles = (self.cycles - earlier.cycles) % (1 << 32)
        seconds = cycles / clk_hz
        if cycles == 0:
            return 0.0, tuple(0.0 for _ in self.switches)
        return seconds, tuple(((now - then) % (1 << 32)) / 2 / seconds
                              for now, then in zip(self.switches, earlier.switches, strict=True))


class NotDemoError(IOError):
    """The device does not answer with the demo's ID."""


class DemoDevice:
    """Registers of the demo in physical units over a :class:`~.client.Client`."""

    def __init__(self, client: Client):
        self.client = client
        if (ident := client.read(demo_window(3, 16, 32).addr("ID"))) != ID_VALUE:
            raise NotDemoError(f"ID reads {ident:#010x}, not the demo's {ID_VALUE:#010x}")
        info = client.read(demo_window(3, 16, 32).addr("INFO"))
        phases, width, acc_bits = info & 0xFF, (info >> 8) & 0xFF, (info >> 16) & 0xFF
        self.demo = demo_window(phases, width, acc_bits)
        if not info & INFO_TOP:
            raise NotDemoError("INFO[24] is 0: not a bitstream with the drop-in top")
        self.map = TOP_MAP
        top_info = client.read(self.map.info)
        self.info = DeviceInfo(
            clk_hz=client.read(self.demo.addr("CLK_HZ")), phases=phases, width=width,
            acc_bits=acc_bits, top=True,
            max_bits=(top_info & top.INFO_MAX_BITS) >> top.INFO_MAX_BITS_SHIFT,
            modes=(top_info & top.INFO_MODES) >> top.INFO_MODES_SHIFT,
            asc=bool(top_info & top.INFO_ASC), watchdog=bool(top_info & top.INFO_WATCHDOG))

    # ---------------------------------------------------------------- conversions
    def _clocks(self, ns: float, name: str, maximum: int) -> int:
        clocks = round(ns * 1e-9 * self.info.clk_hz)
        if not 0 <= clocks <= maximum:
            raise ValueError(f"{name} must be in [0, {maximum * 1e9 / self.info.clk_hz:.0f}] ns "
                             f"at {self.info.clk_hz} Hz, not {ns}")
        return clocks

    def _ns(self, clocks: int) -> float:
        return clocks * 1e9 / self.info.clk_hz

    # ---------------------------------------------------------------- settings
    def set_frequency(self, hz: float) -> float:
        """Set the NCO frequency; returns the frequency actually set."""
        word = round(hz * (1 << self.info.acc_bits) / self.info.clk_hz)
        if not 0 <= word < 1 << (self.info.acc_bits - 1):
            raise ValueError(f"frequency must be in [0, {self.info.clk_hz / 2:.0f}) Hz, not {hz}")
        self.client.write(self.demo.addr("NCO_FREQ"), word)
        return word * self.info.clk_hz / (1 << self.info.acc_bits)

    def set_amplitude(self, vdc: float) -> float:
        """Set the peak phase reference in Vdc (the linear range of three phases ends at
        1/sqrt(3) = 0.577); returns the amplitude actually set."""
        code = round(vdc * self.info.full)
        if not 0 <= code < 1 << (self.info.width - 1):
            raise ValueError(f"amplitude must be in [0, 2) Vdc, not {vdc}")
        self.client.write(self.demo.addr("NCO_AMP"), code)
        return code / self.info.full

    def set_zero_policy(self, policy: str) -> None:
        """MDFQM's zero-state policy (``CTRL.ZERO_POLICY``): all-off or fewest-transitions."""
        if policy not in ZERO_POLICIES:
            raise ValueError(f"zero policy must be one of {sorted(ZERO_POLICIES)}, "
                             f"not {policy!r}")
        ctrl = self.client.read(self.map.ctrl)
        ctrl = (ctrl & ~self.map.ctrl_zero_policy) | (
            self.map.ctrl_zero_policy if ZERO_POLICIES[policy] else 0)
        self.client.write(self.map.ctrl, ctrl)

    def set_modulation(self, mode: str, bits: int | None = None) -> tuple[str, int]:
        """Request a modulation mode (``MODULATIONS``) and resolution b (default: the largest
        built in); refused here when this bitstream does not have it (the gateware would clamp
        it and flag STATUS.MODE_CLAMPED). Returns (mode, b) requested; the next update start
        takes them."""
        built_in = MODULATIONS[:self.info.modes]
        if mode not in built_in:
            raise ValueError(f"modulation must be one of {list(built_in)} on this bitstream "
                             f"(max_bits {self.info.max_bits}), not {mode!r}")
        if mode == "mdfqm":
            bits = 0
        elif bits is None:
            bits = self.info.max_bits
        elif not 1 <= bits <= self.info.max_bits:
            raise ValueError(f"bits must be in [1, {self.info.max_bits}], not {bits}")
        self.client.write(self.map.modulation,
                          MODULATIONS.index(mode) << top.MODULATION_MODE_SHIFT
                          | bits << top.MODULATION_BITS_SHIFT)
        return mode, bits

    def set_watchdog(self, updates: int) -> None:
        """Reference watchdog timeout in update starts (0: off); refused here when this
        bitstream does not have the watchdog (the gateware would store 0)."""
        if not 0 <= updates <= 0xFFFF:
            raise ValueError(f"watchdog must be in [0, 65535] update starts, not {updates}")
        if updates and not self.info.watchdog:
            raise ValueError("the reference watchdog is not built in this bitstream "
                             "(INFO.WATCHDOG 0)")
        self.client.write(self.map.watchdog, updates)

    def clear_watchdog(self) -> None:
        self.client.write(*self.map.watchdog_clear)

    def set_dead_time(self, ns: float) -> float:
        """Dead time in ns (the gateware raises it to its floor); returns what is in force."""
        self.client.write(self.map.dead, self._clocks(ns, "dead time", self.map.time_max))
        dead = max(self.client.read(self.map.dead), self.client.read(self.map.dead_min))
        return self._ns(dead)

    def set_min_pulse(self, ns: float) -> None:
        self.client.write(self.map.min_pulse,
                          self._clocks(ns, "minimum pulse", self.map.time_max))

    def set_update_rate(self, hz: float) -> float:
        """Core updates per second (``PERIOD = round(clk / hz)``); returns the rate set."""
        if not hz > 0:
            raise ValueError(f"update rate must be positive, not {hz}")
        period = round(self.info.clk_hz / hz)
        if not 1 <= period <= 0xFFFF:
            raise ValueError(f"update rate {hz} Hz needs PERIOD {period}, outside [1, 65535]")
        self.client.write(self.map.period, period)
        return self.info.clk_hz / period

    def set_osr(self, osr: int) -> None:
        if not 1 <= osr <= 255:
            raise ValueError(f"osr must be in [1, 255], not {osr}")
        self.client.write(self.map.osr, osr)

    def enable(self, on: bool = True) -> None:
        ctrl = self.client.read(self.map.ctrl)
        ctrl = ctrl | self.map.ctrl_enable if on else ctrl & ~self.map.ctrl_enable
        self.client.write(self.map.ctrl, ctrl)

    def clear_fault(self) -> None:
        self.client.write(*self.map.fault_clear)

    # ---------------------------------------------------------------- readings
    def status(self) -> Status:
        m, info = self.map, self.info
        ctrl = self.client.read(m.ctrl)
        status = self.client.read(m.status)
        period = self.client.read(m.period)
        modulation = self.client.read(m.modulation)
        code = (modulation & top.MODULATION_MODE) >> top.MODULATION_MODE_SHIFT
        return Status(
            enabled=bool(ctrl & m.ctrl_enable),
            flags={name: bool(status & bit) for name, bit in m.status_bits.items()},
            freq_hz=self.client.read(self.demo.addr("NCO_FREQ")) * info.clk_hz
            / (1 << info.acc_bits),
            amplitude=self.client.read(self.demo.addr("NCO_AMP")) / info.full,
            zero_policy="fewest-transitions" if ctrl & m.ctrl_zero_policy else "all-off",
            modulation=MODULATIONS[code] if code < len(MODULATIONS) else f"code {code}",
            bits=(modulation & top.MODULATION_BITS) >> top.MODULATION_BITS_SHIFT,
            update_hz=info.clk_hz / max(period, 1),
            osr=max(1, self.client.read(m.osr)),
            dead_ns=self._ns(max(self.client.read(m.dead), self.client.read(m.dead_min))),
            min_pulse_ns=self._ns(self.client.read(m.min_pulse)),
            watchdog=self.client.read(m.watchdog),
            watchdog_trips=self.client.read(m.watchdog_trips),
        )

    def counters(self) -> Counters:
        """Snapshot the clock counter, then read it and the top's switching counters
        (``EVENTS_i``, read one request after another: each a UART exchange, about a
        millisecond, after the snapshot)."""
        self.client.write(self.demo.addr("SNAPSHOT"), 1)
        return Counters(
            cycles=self.client.read(self.demo.addr("CYCLES")),
            switches=tuple(self.client.read(self.map.events + i)
                           for i in range(self.info.phases)))


def linear_limit(phases: int) -> float:
    """Largest sine amplitude (Vdc) in the linear range, where the spread max - min of the phase
    references stays within 1 Vdc at every angle (1/sqrt(3) = 0.577 for three phases)."""
    worst = max(
        max(math.cos(t - 2 * math.pi * i / phases) for i in range(phases))
        - min(math.cos(t - 2 * math.pi * i / phases) for i in range(phases))
        for t in (2 * math.pi * k / (360 * phases) for k in range(360)))
    return 1 / worst
