"""The register maps: the drop-in top's (``docs/top.md``) and the board demo's
(``docs/boards.md``), as one record type. Pure data, no Amaranth, no NumPy: the gateware builds
its register file from it, the model reads and writes through it, the host addresses the boards
with it, and tests check both documents against it.

The top's map has one source, ``spec/rdl/mdfqm_top.rdl`` (SystemRDL 2.0): ``tools/regmap_gen.py``
compiles it into :mod:`mdfqm_spec.regmap_top` (plain data, committed), from which this module takes
:data:`REGISTERS` and every word address and field mask (``CTRL``, ``REF_BASE``,
``CTRL_ENABLE``, ``STATUS_FAULT``, ...; ``<REG>_<FIELD>_SHIFT``, ``<REG>_MASK``). To change the
map, edit the RDL and regenerate (``spec/rdl/README.md``); nothing here imports the compiler.

Addresses are 32-bit-word addresses. Access: ``RW`` read/write, ``R`` read-only, ``W`` write-only
(write-1 strobes; reads return 0). The top's write clamps are in ``clamp``; the bus rules (one
request per ``cyc & stb & ~ack`` cycle, ``ack`` the next cycle) are in ``docs/top.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

from mdfqm_spec.contract import PERIOD_WIDTH, RULES, modes_built_in

from . import regmap_top as _top
from .regmap_top import *  # noqa: F403 -- the top's word addresses and field masks
from .regmap_top import ADDR_WIDTH, PARAMETERS
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
    "PARAMETERS",
    "REGISTERS",
    "TOP",
    "TOP_BASE",
    "Field",
    "Register",
    "Window",
    "default_max_bits",
    "demo_window",
    "info_word",
    "validate_top_phases",
]

#: the access kinds of :class:`Register`
ACCESS = ("RW", "R", "W")


@dataclass(frozen=True)
class Field:
    """One field of a :class:`Register`: bits ``[lsb + width - 1 : lsb]``."""

    name: str
    lsb: int
    width: int
    access: str               # SystemRDL sw: "r", "rw" or "w"
    reset: int | str = 0      # an int, or the configuration parameter it equals ("dead_min")
    clamp: str = ""           # the value a write stores (tools.regmap_gen.clamp_value)
    doc: str = ""
    onwrite: str = ""         # SystemRDL onwrite, e.g. "woclr" (write 1 to clear)
    singlepulse: bool = False  # a write-1 strobe: acts in the clock the write is taken, reads 0
    intr: bool = False        # an interrupt status bit
    in_force: bool = False    # a write is a request: a read returns the value in force

    @property
    def mask(self) -> int:
        return ((1 << self.width) - 1) << self.lsb


@dataclass(frozen=True)
class Register:
    """One register (or, with ``count`` > 1, an array of consecutive ones, ``NAME[i]``)."""

    name: str
    offset: int          # word offset inside its window
    access: str          # one of ACCESS
    width: int = 32      # bits stored and read back (the rest read 0)
    reset: str = "0"     # the reset value, as documented
    doc: str = ""        # the meaning
    count: int = 1       # registers in the array ("phases" of them for the per-leg ones)
    clamp: str = ""      # the value a write stores, when not the written bits (the top's)
    fields: tuple = ()   # its Fields, by bit position (the top's)


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
#: the top's registers, in address order, from spec/rdl/mdfqm_top.rdl (``docs/top.md`` has the
#: generated table; tools/tests/test_regmap_gen.py checks both against the RDL)
REGISTERS = tuple(
    Register(**{**reg, "fields": tuple(Field(**f) for f in reg["fields"])})
    for reg in _top.REGISTERS)

#: the top's window as the demo's bus sees it (word-address bits ``ADDR_WIDTH``: the fewest that
#: hold the map)
TOP_BASE = 0x000
TOP = Window("top", TOP_BASE, ADDR_WIDTH, REGISTERS)

#: legs the top's register map holds (REF[i], EVENTS[i])
MAX_PHASES = TOP["REF"].count
#: the ID register of the top, and of the board demo's window: "MDFQ"
ID_VALUE = TOP["ID"].fields[0].reset
#: bits of the switching counters: the widest (the RDL's default ``counter_width``)
COUNTER_WIDTH = PARAMETERS["counter_width"]
#: the drop-in configuration's dead-time floor in clocks: 0.64 us at 100 MHz, 1.33 us at 48 MHz
DEFAULT_DEAD_MIN = PARAMETERS["dead_min"]
#: the ADC trigger's count from each update start: it never wraps, since every update (PERIOD,
#: and every minimum period, below 2**16) ends before 2**16 clocks
ADC_COUNTER_WIDTH = PERIOD_WIDTH
#: where the demo's bus puts the demo's own window
DEMO_BASE = 0x100

# interrupt sources (the bits of IRQ_ENABLE and IRQ_STATUS): the fault latch set, a switching
# counter wrapped, a sampling tick (the update that takes the next reference has started: feed
# one now), a short edge (a leg's command changed before the leg had followed the last change:
# a pulse stretched or swallowed by the minimum pulse or the dead time), the watchdog tripped
IRQ_FAULT = _top.IRQ_STATUS_FAULT
IRQ_COUNTER_WRAP = _top.IRQ_STATUS_COUNTER_WRAP
IRQ_SAMPLE = _top.IRQ_STATUS_SAMPLE
IRQ_SHORT_EDGE = _top.IRQ_STATUS_SHORT_EDGE
IRQ_WATCHDOG = _top.IRQ_STATUS_WATCHDOG
IRQ_MASK = _top.IRQ_STATUS_MASK


def default_max_bits(width: int) -> int:
    """The top's (and the drop-in files') default ``max_bits``: the RDL's ``max_bits`` (8:
    2**8 slots per update, SVPWM with an 8-bit duty), or fewer when the width leaves less room
    (``width - 2``)."""
    return min(PARAMETERS["max_bits"], width - 2)


def validate_top_phases(phases) -> int:
    """``phases`` in [3, MAX_PHASES]: the legs the top's register map holds."""
    if isinstance(phases, bool) or not isinstance(phases, int) or not 3 <= phases <= MAX_PHASES:
        raise ValueError(f"phases must be an integer in [3, {MAX_PHASES}] (the register map "
                         f"holds {MAX_PHASES} legs), not {phases!r}")
    return phases


def info_word(phases: int, width: int, rule: str, upper_active_low: bool,
              lower_active_low: bool, latency: int, max_bits: int, **parameters) -> int:
    """``INFO``: each field holds the configuration parameter its reset names in the RDL
    (phases [4:0], width [10:5], rule [11] (1 exact_nearest), upper_active_low [12],
    lower_active_low [13], loop latency [23:16], max_bits [27:24], the modes built in [31:28]);
    a field added there for a new parameter takes it from ``parameters``."""
    values = {"phases": phases, "width": width, "rule": RULES.index(rule),
              "upper_active_low": upper_active_low, "lower_active_low": lower_active_low,
              "latency": latency, "max_bits": max_bits, "modes": modes_built_in(max_bits),
              **parameters}
    word = 0
    for f in TOP["INFO"].fields:
        if isinstance(f.reset, str) and f.reset not in values:
            raise ValueError(f"INFO.{f.name} holds parameter {f.reset!r}: pass it")
        value = int(values[f.reset]) if isinstance(f.reset, str) else f.reset
        if not 0 <= value < 1 << f.width:
            raise ValueError(f"INFO.{f.name}: {value} does not fit {f.width} bits")
        word |= value << f.lsb
    return word


# ---------------------------------------------------------------------------- the board demo
#: INFO[24] of the demo window: the window at TOP_BASE holds the drop-in top
INFO_TOP = 1 << 24


def demo_window(phases: int, width: int, acc_bits: int) -> Window:
    """The demo's own block: identification, the NCO, the clock counter, buttons. The
    switching counters are the top's own (``EVENTS_i``), not repeated here."""
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
        Register("SNAPSHOT", 0x06, "W", 1, doc="copy the clock counter into CYCLES"),
        Register("CYCLES", 0x07, "R", doc="clock counter at the last SNAPSHOT"),
        Register("BUTTONS", 0x10, "R", 8, doc="debounced buttons, bit i = button i pressed"),
    ))


#: the default configuration's demo window (three phases, 16-bit references, 32-bit NCO)
DEMO = demo_window(3, 16, 32)
