# generated from spec/rdl/mdfqm_top.rdl by tools/regmap_gen.py; do not edit
"""The drop-in top's register map as plain data, compiled from its SystemRDL source:
:mod:`mdfqm_spec.regmap` builds its records and constants from this module.

Addresses are 32-bit-word addresses (the RDL's byte addresses / 4). Constants: the word
address of each register (``<NAME>_BASE`` the first of an array); for each field that is
not its register's only namesake, its mask ``<REG>_<FIELD>`` and position
``<REG>_<FIELD>_SHIFT``, and ``<REG>_MASK`` the bits the register defines. A reset is an
int, or the name of the configuration parameter it equals (``PARAMETERS``: the RDL
addrmap's parameters and their drop-in defaults); a register's ``reset`` is as documented
(``"config"``: several parameters). ``clamp``: the value a write stores, an expression of
``v`` (the written word), ``s`` (the word as signed 32-bit) and the parameters.
"""

# the constants (mdfqm_spec.regmap imports them all); the records are REGISTERS
__all__ = [
    "ADC_OFFSET",
    "ADDR_WIDTH",
    "CMD",
    "CMD_ALL_OFF",
    "CMD_ALL_OFF_SHIFT",
    "CMD_COUNT_CLEAR",
    "CMD_COUNT_CLEAR_SHIFT",
    "CMD_FAULT_CLEAR",
    "CMD_FAULT_CLEAR_SHIFT",
    "CMD_MASK",
    "CMD_REF_COMMIT",
    "CMD_REF_COMMIT_SHIFT",
    "CMD_WATCHDOG_CLEAR",
    "CMD_WATCHDOG_CLEAR_SHIFT",
    "CTRL",
    "CTRL_ENABLE",
    "CTRL_ENABLE_SHIFT",
    "CTRL_MASK",
    "CTRL_ZERO_POLICY",
    "CTRL_ZERO_POLICY_SHIFT",
    "DEAD",
    "DEAD_MIN",
    "EVENTS_BASE",
    "EVENTS_TOTAL",
    "FAULT_REACTION",
    "FAULT_REACTION_FAULT",
    "FAULT_REACTION_FAULT_SHIFT",
    "FAULT_REACTION_MASK",
    "FAULT_REACTION_WATCHDOG",
    "FAULT_REACTION_WATCHDOG_SHIFT",
    "GATES",
    "GATES_LOWER",
    "GATES_LOWER_SHIFT",
    "GATES_MASK",
    "GATES_UPPER",
    "GATES_UPPER_SHIFT",
    "ID",
    "INFO",
    "INFO_ASC",
    "INFO_ASC_SHIFT",
    "INFO_LATENCY",
    "INFO_LATENCY_SHIFT",
    "INFO_LOWER_ACTIVE_LOW",
    "INFO_LOWER_ACTIVE_LOW_SHIFT",
    "INFO_MASK",
    "INFO_MAX_BITS",
    "INFO_MAX_BITS_SHIFT",
    "INFO_MODES",
    "INFO_MODES_SHIFT",
    "INFO_PHASES",
    "INFO_PHASES_SHIFT",
    "INFO_RULE",
    "INFO_RULE_SHIFT",
    "INFO_UPPER_ACTIVE_LOW",
    "INFO_UPPER_ACTIVE_LOW_SHIFT",
    "INFO_WATCHDOG",
    "INFO_WATCHDOG_SHIFT",
    "INFO_WIDTH",
    "INFO_WIDTH_SHIFT",
    "IRQ_ENABLE",
    "IRQ_ENABLE_COUNTER_WRAP",
    "IRQ_ENABLE_COUNTER_WRAP_SHIFT",
    "IRQ_ENABLE_FAULT",
    "IRQ_ENABLE_FAULT_SHIFT",
    "IRQ_ENABLE_MASK",
    "IRQ_ENABLE_SAMPLE",
    "IRQ_ENABLE_SAMPLE_SHIFT",
    "IRQ_ENABLE_SHORT_EDGE",
    "IRQ_ENABLE_SHORT_EDGE_SHIFT",
    "IRQ_ENABLE_WATCHDOG",
    "IRQ_ENABLE_WATCHDOG_SHIFT",
    "IRQ_STATUS",
    "IRQ_STATUS_COUNTER_WRAP",
    "IRQ_STATUS_COUNTER_WRAP_SHIFT",
    "IRQ_STATUS_FAULT",
    "IRQ_STATUS_FAULT_SHIFT",
    "IRQ_STATUS_MASK",
    "IRQ_STATUS_SAMPLE",
    "IRQ_STATUS_SAMPLE_SHIFT",
    "IRQ_STATUS_SHORT_EDGE",
    "IRQ_STATUS_SHORT_EDGE_SHIFT",
    "IRQ_STATUS_WATCHDOG",
    "IRQ_STATUS_WATCHDOG_SHIFT",
    "MIN_PULSE",
    "MODULATION",
    "MODULATION_BITS",
    "MODULATION_BITS_SHIFT",
    "MODULATION_MASK",
    "MODULATION_MODE",
    "MODULATION_MODE_SHIFT",
    "OSR",
    "PARAMETERS",
    "PERIOD",
    "REF_BASE",
    "STATUS",
    "STATUS_ACTIVE",
    "STATUS_ACTIVE_SHIFT",
    "STATUS_FAULT",
    "STATUS_FAULT_INPUT",
    "STATUS_FAULT_INPUT_SHIFT",
    "STATUS_FAULT_SHIFT",
    "STATUS_MASK",
    "STATUS_MODE_CLAMPED",
    "STATUS_MODE_CLAMPED_SHIFT",
    "STATUS_PERIOD_CLAMPED",
    "STATUS_PERIOD_CLAMPED_SHIFT",
    "STATUS_REACTION",
    "STATUS_REACTION_SHIFT",
    "STATUS_REF_PENDING",
    "STATUS_REF_PENDING_SHIFT",
    "STATUS_SATURATED",
    "STATUS_SATURATED_SHIFT",
    "STATUS_WATCHDOG",
    "STATUS_WATCHDOG_SHIFT",
    "WATCHDOG",
    "WATCHDOG_MASK",
    "WATCHDOG_TIMEOUT",
    "WATCHDOG_TIMEOUT_SHIFT",
    "WATCHDOG_TRIPS",
    "WATCHDOG_TRIPS_MASK",
    "WATCHDOG_TRIPS_TRIPS",
    "WATCHDOG_TRIPS_TRIPS_SHIFT",
]

#: the RDL addrmap's parameters and their defaults (the drop-in configuration)
PARAMETERS = {
    "phases": 3,
    "width": 16,
    "rule": 0,
    "dead_min": 64,
    "upper_active_low": False,
    "lower_active_low": False,
    "counter_width": 32,
    "max_bits": 8,
    "latency": 8,
    "modes": 5,
    "asc": True,
    "watchdog": True,
}
#: word-address bits of the bus: the fewest that hold every register
ADDR_WIDTH = 6

# word addresses
ID = 0x00
INFO = 0x01
DEAD_MIN = 0x02
CTRL = 0x03
CMD = 0x04
STATUS = 0x05
PERIOD = 0x06
OSR = 0x07
DEAD = 0x08
MIN_PULSE = 0x09
ADC_OFFSET = 0x0A
EVENTS_TOTAL = 0x0B
GATES = 0x0C
IRQ_ENABLE = 0x0D
IRQ_STATUS = 0x0E
MODULATION = 0x0F
REF_BASE = 0x10
EVENTS_BASE = 0x20
WATCHDOG = 0x30
WATCHDOG_TRIPS = 0x31
FAULT_REACTION = 0x32

# INFO fields
INFO_PHASES = 0x0000001F
INFO_PHASES_SHIFT = 0
INFO_WIDTH = 0x000007E0
INFO_WIDTH_SHIFT = 5
INFO_RULE = 0x00000800
INFO_RULE_SHIFT = 11
INFO_UPPER_ACTIVE_LOW = 0x00001000
INFO_UPPER_ACTIVE_LOW_SHIFT = 12
INFO_LOWER_ACTIVE_LOW = 0x00002000
INFO_LOWER_ACTIVE_LOW_SHIFT = 13
INFO_ASC = 0x00004000
INFO_ASC_SHIFT = 14
INFO_WATCHDOG = 0x00008000
INFO_WATCHDOG_SHIFT = 15
INFO_LATENCY = 0x00FF0000
INFO_LATENCY_SHIFT = 16
INFO_MAX_BITS = 0x0F000000
INFO_MAX_BITS_SHIFT = 24
INFO_MODES = 0xF0000000
INFO_MODES_SHIFT = 28
INFO_MASK = 0xFFFFFFFF

# CTRL fields
CTRL_ENABLE = 0x00000001
CTRL_ENABLE_SHIFT = 0
CTRL_ZERO_POLICY = 0x00000002
CTRL_ZERO_POLICY_SHIFT = 1
CTRL_MASK = 0x00000003

# CMD fields
CMD_REF_COMMIT = 0x00000001
CMD_REF_COMMIT_SHIFT = 0
CMD_FAULT_CLEAR = 0x00000002
CMD_FAULT_CLEAR_SHIFT = 1
CMD_COUNT_CLEAR = 0x00000004
CMD_COUNT_CLEAR_SHIFT = 2
CMD_WATCHDOG_CLEAR = 0x00000008
CMD_WATCHDOG_CLEAR_SHIFT = 3
CMD_ALL_OFF = 0x00000010
CMD_ALL_OFF_SHIFT = 4
CMD_MASK = 0x0000001F

# STATUS fields
STATUS_FAULT = 0x00000001
STATUS_FAULT_SHIFT = 0
STATUS_FAULT_INPUT = 0x00000002
STATUS_FAULT_INPUT_SHIFT = 1
STATUS_ACTIVE = 0x00000004
STATUS_ACTIVE_SHIFT = 2
STATUS_REF_PENDING = 0x00000008
STATUS_REF_PENDING_SHIFT = 3
STATUS_SATURATED = 0x00000010
STATUS_SATURATED_SHIFT = 4
STATUS_PERIOD_CLAMPED = 0x00000020
STATUS_PERIOD_CLAMPED_SHIFT = 5
STATUS_MODE_CLAMPED = 0x00000040
STATUS_MODE_CLAMPED_SHIFT = 6
STATUS_WATCHDOG = 0x00000080
STATUS_WATCHDOG_SHIFT = 7
STATUS_REACTION = 0x00000300
STATUS_REACTION_SHIFT = 8
STATUS_MASK = 0x000003FF

# GATES fields
GATES_UPPER = 0x0000FFFF
GATES_UPPER_SHIFT = 0
GATES_LOWER = 0xFFFF0000
GATES_LOWER_SHIFT = 16
GATES_MASK = 0xFFFFFFFF

# IRQ_ENABLE fields
IRQ_ENABLE_FAULT = 0x00000001
IRQ_ENABLE_FAULT_SHIFT = 0
IRQ_ENABLE_COUNTER_WRAP = 0x00000002
IRQ_ENABLE_COUNTER_WRAP_SHIFT = 1
IRQ_ENABLE_SAMPLE = 0x00000004
IRQ_ENABLE_SAMPLE_SHIFT = 2
IRQ_ENABLE_SHORT_EDGE = 0x00000008
IRQ_ENABLE_SHORT_EDGE_SHIFT = 3
IRQ_ENABLE_WATCHDOG = 0x00000010
IRQ_ENABLE_WATCHDOG_SHIFT = 4
IRQ_ENABLE_MASK = 0x0000001F

# IRQ_STATUS fields
IRQ_STATUS_FAULT = 0x00000001
IRQ_STATUS_FAULT_SHIFT = 0
IRQ_STATUS_COUNTER_WRAP = 0x00000002
IRQ_STATUS_COUNTER_WRAP_SHIFT = 1
IRQ_STATUS_SAMPLE = 0x00000004
IRQ_STATUS_SAMPLE_SHIFT = 2
IRQ_STATUS_SHORT_EDGE = 0x00000008
IRQ_STATUS_SHORT_EDGE_SHIFT = 3
IRQ_STATUS_WATCHDOG = 0x00000010
IRQ_STATUS_WATCHDOG_SHIFT = 4
IRQ_STATUS_MASK = 0x0000001F

# MODULATION fields
MODULATION_MODE = 0x00000007
MODULATION_MODE_SHIFT = 0
MODULATION_BITS = 0x00000F00
MODULATION_BITS_SHIFT = 8
MODULATION_MASK = 0x00000F07

# WATCHDOG fields
WATCHDOG_TIMEOUT = 0x0000FFFF
WATCHDOG_TIMEOUT_SHIFT = 0
WATCHDOG_MASK = 0x0000FFFF

# WATCHDOG_TRIPS fields
WATCHDOG_TRIPS_TRIPS = 0x0000FFFF
WATCHDOG_TRIPS_TRIPS_SHIFT = 0
WATCHDOG_TRIPS_MASK = 0x0000FFFF

# FAULT_REACTION fields
FAULT_REACTION_FAULT = 0x00000003
FAULT_REACTION_FAULT_SHIFT = 0
FAULT_REACTION_WATCHDOG = 0x0000000C
FAULT_REACTION_WATCHDOG_SHIFT = 2
FAULT_REACTION_MASK = 0x0000000F

#: every register, in address order
REGISTERS = (
    {
        "name": "ID",
        "offset": 0x00,
        "access": "R",
        "width": 32,
        "reset": "0x4D444651",
        "clamp": "",
        "doc": "identification. \"MDFQ\" in ASCII.",
        "count": 1,
        "fields": (
            {"name": "ID", "lsb": 0, "width": 32, "access": "r", "reset": 0x4D444651},
        ),
    },
    {
        "name": "INFO",
        "offset": 0x01,
        "access": "R",
        "width": 32,
        "reset": "config",
        "clamp": "",
        "doc": "configuration. The elaboration parameters of this instance.",
        "count": 1,
        "fields": (
            {"name": "PHASES", "lsb": 0, "width": 5, "access": "r", "reset": "phases",
             "doc": "phases N"},
            {"name": "WIDTH", "lsb": 5, "width": 6, "access": "r", "reset": "width",
             "doc": "reference code width"},
            {"name": "RULE", "lsb": 11, "width": 1, "access": "r", "reset": "rule",
             "doc": "1 = exact_nearest"},
            {"name": "UPPER_ACTIVE_LOW", "lsb": 12, "width": 1, "access": "r",
             "reset": "upper_active_low"},
            {"name": "LOWER_ACTIVE_LOW", "lsb": 13, "width": 1, "access": "r",
             "reset": "lower_active_low"},
            {"name": "ASC", "lsb": 14, "width": 1, "access": "r", "reset": "asc",
             "doc": "1 = the active short circuit is built in (FAULT_REACTION codes 1 and 2)"},
            {"name": "WATCHDOG", "lsb": 15, "width": 1, "access": "r", "reset": "watchdog",
             "doc": "1 = the reference watchdog is built in (WATCHDOG)"},
            {"name": "LATENCY", "lsb": 16, "width": 8, "access": "r", "reset": "latency",
             "doc": "loop latency L (MDFQM updates)"},
            {"name": "MAX_BITS", "lsb": 24, "width": 4, "access": "r", "reset": "max_bits",
             "doc": "largest resolution b of the slot modes (0: MDFQM-only top)"},
            {"name": "MODES", "lsb": 28, "width": 4, "access": "r", "reset": "modes",
             "doc": "modulation modes built in: MODULATION.MODE codes 0..MODES-1"},
        ),
    },
    {
        "name": "DEAD_MIN",
        "offset": 0x02,
        "access": "R",
        "width": 16,
        "reset": "dead_min",
        "clamp": "",
        "doc": "the dead-time floor (clocks)",
        "count": 1,
        "fields": (
            {"name": "DEAD_MIN", "lsb": 0, "width": 16, "access": "r", "reset": "dead_min"},
        ),
    },
    {
        "name": "CTRL",
        "offset": 0x03,
        "access": "RW",
        "width": 2,
        "reset": "0",
        "clamp": "",
        "doc": "control. Other bits dropped.",
        "count": 1,
        "fields": (
            {"name": "ENABLE", "lsb": 0, "width": 1, "access": "rw", "reset": 0,
             "doc": "taken at the next update boundary"},
            {"name": "ZERO_POLICY", "lsb": 1, "width": 1, "access": "rw", "reset": 0,
             "doc": "zero-vector policy of the core"},
        ),
    },
    {
        "name": "CMD",
        "offset": 0x04,
        "access": "W",
        "width": 5,
        "reset": "0",
        "clamp": "",
        "doc": (
            "commands. Write-1 strobes, acting in the clock the register file takes the write; "
            "reads 0; other bits ignored."
        ),
        "count": 1,
        "fields": (
            {"name": "REF_COMMIT", "lsb": 0, "width": 1, "access": "w", "reset": 0,
             "doc": "copy REF[0..N-1] into a reference beat", "singlepulse": True},
            {"name": "FAULT_CLEAR", "lsb": 1, "width": 1, "access": "w", "reset": 0,
             "doc": "clear the fault latch if the input is inactive", "singlepulse": True},
            {"name": "COUNT_CLEAR", "lsb": 2, "width": 1, "access": "w", "reset": 0,
             "doc": "zero EVENTS[i], EVENTS_TOTAL and WATCHDOG_TRIPS", "singlepulse": True},
            {
                "name": "WATCHDOG_CLEAR",
                "lsb": 3,
                "width": 1,
                "access": "w",
                "reset": 0,
                "doc": (
                    "clear the watchdog latch (gates resume at the next update boundary with "
                    "ENABLE)"
                ),
                "singlepulse": True,
            },
            {"name": "ALL_OFF", "lsb": 4, "width": 1, "access": "w", "reset": 0,
             "doc": "move the fault reaction in force to all off (the latches stay set)",
             "singlepulse": True},
        ),
    },
    {
        "name": "STATUS",
        "offset": 0x05,
        "access": "R",
        "width": 10,
        "reset": "0",
        "clamp": "",
        "doc": "status. SATURATED and PERIOD_CLAMPED are the core's flags of its last update.",
        "count": 1,
        "fields": (
            {"name": "FAULT", "lsb": 0, "width": 1, "access": "r", "reset": 0, "doc": "latched"},
            {"name": "FAULT_INPUT", "lsb": 1, "width": 1, "access": "r", "reset": 0,
             "doc": "synchronised input"},
            {"name": "ACTIVE", "lsb": 2, "width": 1, "access": "r", "reset": 0,
             "doc": "enable taken at the last update boundary, not cancelled by a fault"},
            {"name": "REF_PENDING", "lsb": 3, "width": 1, "access": "r", "reset": 0,
             "doc": "a committed register beat not yet taken by the core"},
            {"name": "SATURATED", "lsb": 4, "width": 1, "access": "r", "reset": 0},
            {"name": "PERIOD_CLAMPED", "lsb": 5, "width": 1, "access": "r", "reset": 0},
            {
                "name": "MODE_CLAMPED",
                "lsb": 6,
                "width": 1,
                "access": "r",
                "reset": 0,
                "doc": (
                    "the last update start used a clamped MODULATION (mode not built in, or b out "
                    "of range)"
                ),
            },
            {"name": "WATCHDOG", "lsb": 7, "width": 1, "access": "r", "reset": 0,
             "doc": "the watchdog latch: tripped (fault reaction) until CMD.WATCHDOG_CLEAR"},
            {"name": "REACTION", "lsb": 8, "width": 2, "access": "r", "reset": 0,
             "doc": "the fault reaction in force: 0 none or all off, 1 ASC low, 2 ASC high"},
        ),
    },
    {
        "name": "PERIOD",
        "offset": 0x06,
        "access": "RW",
        "width": 16,
        "reset": "latency",
        "clamp": "min(v, 65535)",
        "doc": "clocks per update. The core uses max(PERIOD, L) and sets STATUS.PERIOD_CLAMPED.",
        "count": 1,
        "fields": (
            {"name": "PERIOD", "lsb": 0, "width": 16, "access": "rw", "reset": "latency",
             "clamp": "min(v, 65535)"},
        ),
    },
    {
        "name": "OSR",
        "offset": 0x07,
        "access": "RW",
        "width": 8,
        "reset": "1",
        "clamp": "min(v, 255)",
        "doc": "updates per reference sample. 0 acts as 1.",
        "count": 1,
        "fields": (
            {"name": "OSR", "lsb": 0, "width": 8, "access": "rw", "reset": 1,
             "clamp": "min(v, 255)"},
        ),
    },
    {
        "name": "DEAD",
        "offset": 0x08,
        "access": "RW",
        "width": 16,
        "reset": "dead_min",
        "clamp": "min(max(v, dead_min), 65535)",
        "doc": (
            "dead time in clocks. Never below dead_min: the driver clamps its input to dead_min "
            "again."
        ),
        "count": 1,
        "fields": (
            {"name": "DEAD", "lsb": 0, "width": 16, "access": "rw", "reset": "dead_min",
             "clamp": "min(max(v, dead_min), 65535)"},
        ),
    },
    {
        "name": "MIN_PULSE",
        "offset": 0x09,
        "access": "RW",
        "width": 16,
        "reset": "0",
        "clamp": "min(v, 65535)",
        "doc": "minimum on-time in clocks. 0 and 1 mean none.",
        "count": 1,
        "fields": (
            {"name": "MIN_PULSE", "lsb": 0, "width": 16, "access": "rw", "reset": 0,
             "clamp": "min(v, 65535)"},
        ),
    },
    {
        "name": "ADC_OFFSET",
        "offset": 0x0A,
        "access": "RW",
        "width": 16,
        "reset": "0",
        "clamp": "min(v, 65535)",
        "doc": "ADC trigger offset in clocks. No pulse when not below the update period.",
        "count": 1,
        "fields": (
            {"name": "ADC_OFFSET", "lsb": 0, "width": 16, "access": "rw", "reset": 0,
             "clamp": "min(v, 65535)"},
        ),
    },
    {
        "name": "EVENTS_TOTAL",
        "offset": 0x0B,
        "access": "R",
        "width": 32,
        "reset": "0",
        "clamp": "",
        "doc": "switching events of all legs. counter_width bits (32), wraps.",
        "count": 1,
        "fields": (
            {"name": "EVENTS_TOTAL", "lsb": 0, "width": 32, "access": "r", "reset": 0},
        ),
    },
    {
        "name": "GATES",
        "offset": 0x0C,
        "access": "R",
        "width": 32,
        "reset": "0",
        "clamp": "",
        "doc": "active-high gate state. Bit i = leg i.",
        "count": 1,
        "fields": (
            {"name": "UPPER", "lsb": 0, "width": 16, "access": "r", "reset": 0},
            {"name": "LOWER", "lsb": 16, "width": 16, "access": "r", "reset": 0},
        ),
    },
    {
        "name": "IRQ_ENABLE",
        "offset": 0x0D,
        "access": "RW",
        "width": 5,
        "reset": "0",
        "clamp": "",
        "doc": "interrupt enable. The sources that drive irq; other bits dropped.",
        "count": 1,
        "fields": (
            {"name": "FAULT", "lsb": 0, "width": 1, "access": "rw", "reset": 0,
             "doc": "fault latch about to set"},
            {"name": "COUNTER_WRAP", "lsb": 1, "width": 1, "access": "rw", "reset": 0,
             "doc": "EVENTS_TOTAL passes 2**counter_width - 1"},
            {"name": "SAMPLE", "lsb": 2, "width": 1, "access": "rw", "reset": 0,
             "doc": "sampling tick"},
            {"name": "SHORT_EDGE", "lsb": 3, "width": 1, "access": "rw", "reset": 0,
             "doc": "a leg's command changed before the leg had followed the last change"},
            {"name": "WATCHDOG", "lsb": 4, "width": 1, "access": "rw", "reset": 0,
             "doc": "the watchdog tripped"},
        ),
    },
    {
        "name": "IRQ_STATUS",
        "offset": 0x0E,
        "access": "RW",
        "width": 5,
        "reset": "0",
        "clamp": "",
        "doc": (
            "interrupt status. The IRQ_ENABLE sources; each bit is set the clock after its event; "
            "write 1 to clear, an event in the same clock wins; other bits ignored. irq is high "
            "from the clock after a bit is set here and in IRQ_ENABLE."
        ),
        "count": 1,
        "fields": (
            {"name": "FAULT", "lsb": 0, "width": 1, "access": "rw", "reset": 0, "onwrite": "woclr",
             "intr": True},
            {"name": "COUNTER_WRAP", "lsb": 1, "width": 1, "access": "rw", "reset": 0,
             "onwrite": "woclr", "intr": True},
            {"name": "SAMPLE", "lsb": 2, "width": 1, "access": "rw", "reset": 0,
             "onwrite": "woclr", "intr": True},
            {"name": "SHORT_EDGE", "lsb": 3, "width": 1, "access": "rw", "reset": 0,
             "onwrite": "woclr", "intr": True},
            {"name": "WATCHDOG", "lsb": 4, "width": 1, "access": "rw", "reset": 0,
             "onwrite": "woclr", "intr": True},
        ),
    },
    {
        "name": "MODULATION",
        "offset": 0x0F,
        "access": "RW",
        "width": 12,
        "reset": "0",
        "clamp": "",
        "doc": (
            "modulation mode and resolution. A write requests a mode and b; each update start "
            "takes the request, clamped (codes not built in act as 0, mdfqm; mdfqm uses b = 0; a "
            "slot mode uses b clamped to [1, max_bits]; STATUS.MODE_CLAMPED flags that update). A "
            "read returns the mode and b in force: those of the last update start, not the request."
        ),
        "count": 1,
        "fields": (
            {"name": "MODE", "lsb": 0, "width": 3, "access": "rw", "reset": 0,
             "doc": "0 mdfqm, 1 svpwm, 2 dpwm0, 3 dpwm1, 4 dpwm (sector clamp)", "in_force": True},
            {"name": "BITS", "lsb": 8, "width": 4, "access": "rw", "reset": 0,
             "doc": "resolution b of the slot modes (2**b slots per update)", "in_force": True},
        ),
    },
    {
        "name": "REF",
        "offset": 0x10,
        "access": "RW",
        "width": 32,
        "reset": "0",
        "clamp": "min(max(s, -2**(width - 1)), 2**(width - 1) - 1)",
        "doc": (
            "reference code of phase i. 2**(width-2) codes per Vdc; reads sign-extended; i >= N "
            "unmapped."
        ),
        "count": 16,
        "fields": (
            {"name": "REF", "lsb": 0, "width": 32, "access": "rw", "reset": 0,
             "clamp": "min(max(s, -2**(width - 1)), 2**(width - 1) - 1)"},
        ),
    },
    {
        "name": "EVENTS",
        "offset": 0x20,
        "access": "R",
        "width": 32,
        "reset": "0",
        "clamp": "",
        "doc": "switching events of leg i. counter_width bits (32), wraps; i >= N unmapped.",
        "count": 16,
        "fields": (
            {"name": "EVENTS", "lsb": 0, "width": 32, "access": "r", "reset": 0},
        ),
    },
    {
        "name": "WATCHDOG",
        "offset": 0x30,
        "access": "RW",
        "width": 16,
        "reset": "0",
        "clamp": "min(v, 65535) * watchdog",
        "doc": (
            "reference watchdog timeout (update starts). 0: off (the reset value). Otherwise the "
            "update starts allowed without a new reference (a beat accepted on the ref port, or a "
            "CMD.REF_COMMIT write): the next update start without one trips the watchdog "
            "(STATUS.WATCHDOG; the fault reaction from two clocks after that start, as on a fault, "
            "until CMD.WATCHDOG_CLEAR). Without the watchdog built in (INFO.WATCHDOG 0) a write "
            "stores 0: it never trips. docs/top.md, Reference watchdog."
        ),
        "count": 1,
        "fields": (
            {"name": "TIMEOUT", "lsb": 0, "width": 16, "access": "rw", "reset": 0,
             "clamp": "min(v, 65535) * watchdog"},
        ),
    },
    {
        "name": "WATCHDOG_TRIPS",
        "offset": 0x31,
        "access": "R",
        "width": 16,
        "reset": "0",
        "clamp": "",
        "doc": "watchdog trips. Trips since reset or CMD.COUNT_CLEAR; saturates at 65535.",
        "count": 1,
        "fields": (
            {"name": "TRIPS", "lsb": 0, "width": 16, "access": "r", "reset": 0},
        ),
    },
    {
        "name": "FAULT_REACTION",
        "offset": 0x32,
        "access": "RW",
        "width": 4,
        "reset": "0",
        "clamp": "FAULT: v % 4 % 3 * asc; WATCHDOG: v % 4 % 3 * asc * watchdog",
        "doc": (
            "fault reaction per source. What the gates do while a latch is set: 0 all off (the "
            "reset value), 1 active short circuit low (the lower switches on), 2 active short "
            "circuit high (the upper ones on); 3, or 1 and 2 without the active short circuit "
            "built in (INFO.ASC 0), store 0; so does any value in WATCHDOG without the watchdog "
            "built in (INFO.WATCHDOG 0). Taken when the gates leave normal operation: a later "
            "write does not change a reaction in force (STATUS.REACTION). docs/top.md, Fault "
            "reaction."
        ),
        "count": 1,
        "fields": (
            {"name": "FAULT", "lsb": 0, "width": 2, "access": "rw", "reset": 0,
             "clamp": "v % 4 % 3 * asc", "doc": "reaction to the fault latch"},
            {"name": "WATCHDOG", "lsb": 2, "width": 2, "access": "rw", "reset": 0,
             "clamp": "v % 4 % 3 * asc * watchdog", "doc": "reaction to the watchdog latch"},
        ),
    },
)
