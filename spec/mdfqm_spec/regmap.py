"""The register maps: the drop-in top's (``docs/top.md``) and the board demo's
(``docs/boards.md``), as one record type. Pure data, no Amaranth, no NumPy: the gateware builds
its register file from it, the model reads and writes through it, the host addresses the boards
with it, and tests check both documents against it.

Addresses are 32-bit-word addresses. Access: ``RW`` read/write, ``R`` read-only, ``W`` write-only
(write-1 strobes; reads return 0). The top's write clamps are in ``doc``; the bus rules (one
request per ``cyc & stb & ~ack`` cycle, ``ack`` the next cycle) are in ``docs/top.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

from mdfqm_spec.contract import RULES, TIME_WIDTH

from .validate import validate_int

__all__ = [
    "ACCESS",
    "ADC_COUNTER_WIDTH",
    "ADDR_WIDTH",
    "COUNTER_WIDTH",
    "DEFAULT_DEAD_MIN",
    "DEMO",
    "DEMO_BASE",
    "ID_VALUE",
    "INFO_TOP",
    "MAX_PHASES",
    "REGISTERS",
    "TOP",
    "TOP_BASE",
    "Register",
    "Window",
    "demo_window",
    "info_word",
    "validate_top_phases",
]

#: the access kinds of :class:`Register`
ACCESS = ("RW", "R", "W")


@dataclass(frozen=True)
class Register:
    """One register (or, with ``count`` > 1, an array of consecutive ones, ``NAME[i]``)."""

    name: str
    offset: int          # word offset inside its window
    access: str          # one of ACCESS
    width: int = 32      # bits stored and read back (the rest read 0)
    reset: str = "0"     # the reset value, as documented
    doc: str = ""        # the meaning, and the clamp a write goes through
    count: int = 1       # registers in the array ("phases" of them for the per-leg ones)


@dataclass(frozen=True)
class Window:
    """Registers at ``base`` .. ``base + 2**addr_width - 1``; offsets are checked to be unique."""

    name: str
    base: int
    addr_width: int
    regs: tuple

    def __post_init__(self):
        seen = set()
        for reg in self.regs:
            if reg.access not in ACCESS:
                raise ValueError(f"{self.name}.{reg.name}: access {reg.access!r}")
            offsets = set(range(reg.offset, reg.offset + reg.count))
            if not 0 <= reg.offset <= reg.offset + reg.count <= 1 << self.addr_width or \
                    offsets & seen:
                raise ValueError(f"{self.name}.{reg.name}: offset {reg.offset:#x}")
            if not 1 <= reg.width <= 32:
                raise ValueError(f"{self.name}.{reg.name}: width {reg.width}")
            seen |= offsets

    def __getitem__(self, name: str) -> Register:
        for reg in self.regs:
            if reg.name == name:
                return reg
        raise KeyError(f"no register {name!r} in the {self.name} window")

    def addr(self, name: str, index: int = 0) -> int:
        """Bus word address of register ``name`` (element ``index`` of an array)."""
        reg = self[name]
        if not 0 <= index < reg.count:
            raise IndexError(f"{self.name}.{name} has {reg.count} elements, not {index + 1}")
        return self.base + reg.offset + index

    def at(self, offset: int) -> Register | None:
        """The register holding word ``offset`` of the window, if any."""
        return next((r for r in self.regs if r.offset <= offset < r.offset + r.count), None)


# ---------------------------------------------------------------------------- the drop-in top
#: word-address bits of the top's bus
ADDR_WIDTH = 6
#: legs the top's register map holds (REF[i], EVENTS[i])
MAX_PHASES = 16
#: the ID register of the top, and of the board demo's window: "MDFQ"
ID_VALUE = 0x4D444651
COUNTER_WIDTH = 32
ADC_COUNTER_WIDTH = 17          # > 16 bits: it saturates above every ADC_OFFSET
DEFAULT_DEAD_MIN = 64           # clocks: 0.64 us at 100 MHz, 1.33 us at 48 MHz
#: where the demo's bus puts the top, and the demo's own window
TOP_BASE = 0x000
DEMO_BASE = 0x100

# word addresses
ID, INFO, DEAD_MIN, CTRL, CMD, STATUS = 0x00, 0x01, 0x02, 0x03, 0x04, 0x05
PERIOD, OSR, DEAD, MIN_PULSE, ADC_OFFSET = 0x06, 0x07, 0x08, 0x09, 0x0A
EVENTS_TOTAL, GATES, IRQ_ENABLE, IRQ_STATUS = 0x0B, 0x0C, 0x0D, 0x0E
REF_BASE, EVENTS_BASE = 0x10, 0x20

# CTRL bits
CTRL_ENABLE, CTRL_ZERO_POLICY = 1 << 0, 1 << 1
CTRL_MASK = CTRL_ENABLE | CTRL_ZERO_POLICY
# CMD bits (write-1 strobes)
CMD_REF_COMMIT, CMD_FAULT_CLEAR, CMD_COUNT_CLEAR = 1 << 0, 1 << 1, 1 << 2
# STATUS bits
(STATUS_FAULT, STATUS_FAULT_INPUT, STATUS_ACTIVE, STATUS_REF_PENDING, STATUS_SATURATED,
 STATUS_PERIOD_CLAMPED) = (1 << b for b in range(6))
# interrupt sources (IRQ_ENABLE, IRQ_STATUS): the fault latch set, a switching counter wrapped,
# a sampling tick (the update that takes the next reference has started: feed one now)
IRQ_FAULT, IRQ_COUNTER_WRAP, IRQ_SAMPLE = 1 << 0, 1 << 1, 1 << 2
IRQ_MASK = IRQ_FAULT | IRQ_COUNTER_WRAP | IRQ_SAMPLE

_TIME_MAX = (1 << TIME_WIDTH) - 1

#: the top's registers, in address order (``docs/top.md`` has the same table; a test checks it)
REGISTERS = (
    Register("ID", ID, "R", reset=f"{ID_VALUE:#010X}".replace("0X", "0x")),
    Register("INFO", INFO, "R", reset="config"),
    Register("DEAD_MIN", DEAD_MIN, "R", TIME_WIDTH, reset="dead_min"),
    Register("CTRL", CTRL, "RW", 2, doc="bits other than ENABLE, ZERO_POLICY dropped"),
    Register("CMD", CMD, "W", 3, doc="write-1 strobes; reads 0"),
    Register("STATUS", STATUS, "R", 6),
    Register("PERIOD", PERIOD, "RW", 16, reset="latency",
             doc="min(v, 65535); core uses max(PERIOD, latency)"),
    Register("OSR", OSR, "RW", 8, reset="1", doc="min(v, 255); core uses max(OSR, 1)"),
    Register("DEAD", DEAD, "RW", TIME_WIDTH, reset="dead_min",
             doc=f"min(max(v, dead_min), {_TIME_MAX})"),
    Register("MIN_PULSE", MIN_PULSE, "RW", TIME_WIDTH, doc=f"min(v, {_TIME_MAX})"),
    Register("ADC_OFFSET", ADC_OFFSET, "RW", 16, doc="min(v, 65535)"),
    Register("EVENTS_TOTAL", EVENTS_TOTAL, "R", COUNTER_WIDTH, doc="wraps at 2**32"),
    Register("GATES", GATES, "R"),
    Register("IRQ_ENABLE", IRQ_ENABLE, "RW", 3, doc="bits other than the three sources dropped"),
    Register("IRQ_STATUS", IRQ_STATUS, "RW", 3,
             doc="write 1 to clear; an event in the same clock wins"),
    Register("REF", REF_BASE, "RW", doc="signed, saturated to the width-bit code range",
             count=MAX_PHASES),
    Register("EVENTS", EVENTS_BASE, "R", COUNTER_WIDTH, doc="wraps at 2**32", count=MAX_PHASES),
)

#: the top's window as the demo's bus sees it
TOP = Window("top", TOP_BASE, ADDR_WIDTH, REGISTERS)


def validate_top_phases(phases) -> int:
    """``phases`` in [3, MAX_PHASES]: the legs the top's register map holds."""
    if isinstance(phases, bool) or not isinstance(phases, int) or not 3 <= phases <= MAX_PHASES:
        raise ValueError(f"phases must be an integer in [3, {MAX_PHASES}] (the register map "
                         f"holds {MAX_PHASES} legs), not {phases!r}")
    return phases


def info_word(phases: int, width: int, rule: str, upper_active_low: bool,
              lower_active_low: bool, latency: int) -> int:
    """``INFO``: phases [4:0], width [10:5], rule [11] (1 exact_nearest), upper_active_low [12],
    lower_active_low [13], loop latency [23:16]."""
    return (phases | width << 5 | RULES.index(rule) << 11 | int(upper_active_low) << 12
            | int(lower_active_low) << 13 | latency << 16)


# ---------------------------------------------------------------------------- the board demo
#: INFO[24] of the demo window: the window at TOP_BASE holds the drop-in top
INFO_TOP = 1 << 24


def demo_window(phases: int, width: int, acc_bits: int) -> Window:
    """The demo's own block: identification, the NCO, telemetry counters, buttons."""
    validate_int(phases, "phases", 1, 8)
    return Window("demo", DEMO_BASE, 5, (
        Register("ID", 0x00, "R", reset=f"{ID_VALUE:#010x}", doc=f"{ID_VALUE:#010x} ('MDFQ')"),
        Register("INFO", 0x01, "R", doc="[7:0] phases, [15:8] reference width, [23:16] NCO "
                                        "accumulator bits, [24] modulator is the drop-in top"),
        Register("CLK_HZ", 0x02, "R", doc="system clock in Hz"),
        Register("NCO_FREQ", 0x03, "RW", acc_bits,
                 doc="phase increment per clock: f = NCO_FREQ * CLK_HZ / 2**acc_bits"),
        Register("NCO_AMP", 0x04, "RW", width - 1,
                 doc="peak reference code, 2**(width-2) codes per Vdc"),
        Register("NCO_PHASE", 0x05, "R", acc_bits, doc="phase accumulator"),
        Register("SNAPSHOT", 0x06, "W", 1, doc="copy CYCLES and SWITCHES_i, all in one clock"),
        Register("CYCLES", 0x07, "R", doc="clock counter at the last SNAPSHOT"),
        *(Register(f"SWITCHES_{i}", 0x08 + i, "R",
                   doc=f"turn-ons of either switch of leg {i} at the last SNAPSHOT")
          for i in range(phases)),
        Register("BUTTONS", 0x10, "R", 8, doc="debounced buttons, bit i = button i pressed"),
    ))


#: the default configuration's demo window (three phases, 16-bit references, 32-bit NCO)
DEMO = demo_window(3, 16, 32)
