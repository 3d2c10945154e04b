"""Clock-level model of the drop-in top: core + gate driver + Wishbone register file + switching
counters + ADC trigger. The register map is :mod:`mdfqm_spec.regmap` (the gateware builds its
register file from it, ``docs/top.md`` documents it, a test checks the table there).

The core's algorithm is not repeated here: :class:`TopModel` composes
:class:`mdfqm_model.clock.CoreModel` and :class:`mdfqm_model.driver.GateDriverModel`.

Wishbone classic slave (32-bit data, word addresses, ``ADDR_WIDTH`` bits)
-------------------------------------------------------------------------
A *request* is a cycle with ``cyc & stb & ~ack``. Its write takes effect at the end of that
cycle (visible in the next), ``ack`` is high in the next cycle for one clock (registered), and
``dat_r`` in that cycle holds the register read in the request cycle (0 after a write or when
no request). No stalls, no ERR/RTY; ``sel`` is accepted and ignored (every write writes the
whole register: use 32-bit accesses). A master holding ``stb`` through the ``ack`` cycle is not
seen twice: the cycle with ``ack`` high is never a request.

Write clamps (every value of every field is legal; nothing wraps): unsigned fields saturate at
their maximum (``min(value, max)`` of the 32-bit word); ``DEAD`` is also raised to the
floor ``dead_min``; ``REF[i]`` takes the word as signed 32-bit and saturates it into the
``width``-bit code range; ``CTRL`` keeps its two defined bits. Writes to read-only or unmapped
addresses are acknowledged and ignored; unmapped addresses read 0.

Per-cycle behaviour (registers reset synchronously; see also the two sub-models)
-------------------------------------------------------------------------------
- Core inputs: ``period = PERIOD``, ``osr = OSR``, ``zero_policy = CTRL.ZERO_POLICY``,
  ``sync_in`` (port). ``sync_out`` is the core's ``start`` (combinational from its registers).
- Reference: ``CMD.REF_COMMIT`` copies ``REF[0..N-1]`` into a snapshot and sets ``ref_pending``.
  The core's stream sees ``valid = ref_pending | ref.valid`` and the snapshot while
  ``ref_pending``: **a committed register beat wins** over the direct stream port, whose
  ``ready`` is ``core_ready & ~ref_pending``. ``ref_pending`` clears when the core accepts it;
  a commit while one is pending replaces the snapshot (a commit wins over the clear).
- Driver inputs: the core's ``h`` and ``update``, ``enable = CTRL.ENABLE``, ``dead = DEAD``,
  ``min_pulse = MIN_PULSE``, ``fault_in`` (port), ``fault_clear = CMD.FAULT_CLEAR`` strobe.
- Switching counters: ``EVENTS[i] += event[i]``, ``EVENTS_TOTAL += popcount(event)`` each
  cycle, ``event`` being the driver's turn-on strobes (one per turn-on of either switch of a
  leg: in complementary switching, one per change of the leg's state). 32 bits, wrapping.
  ``CMD.COUNT_CLEAR`` zeroes them all (the strobes of that cycle are not counted).
- ADC trigger: ``elapsed = 0 if start else cnt``; ``cnt <= min(elapsed + 1, 2**17 - 1)``;
  ``adc_trigger <= elapsed == ADC_OFFSET``. So the pulse is in cycle ``s + 1 + ADC_OFFSET``,
  ``s`` the update start, and there is none when ``ADC_OFFSET >= P`` (the update period).
"""

from __future__ import annotations

import numpy as np

from mdfqm_spec.contract import TIME_WIDTH, validate_dead_min
from mdfqm_spec.regmap import (
    ADC_COUNTER_WIDTH,
    ADC_OFFSET,
    ADDR_WIDTH,
    CMD,
    CMD_COUNT_CLEAR,
    CMD_FAULT_CLEAR,
    CMD_REF_COMMIT,
    COUNTER_WIDTH,
    CTRL,
    CTRL_ENABLE,
    CTRL_MASK,
    CTRL_ZERO_POLICY,
    DEAD,
    DEAD_MIN,
    DEFAULT_DEAD_MIN,
    EVENTS_BASE,
    EVENTS_TOTAL,
    GATES,
    ID,
    ID_VALUE,
    INFO,
    MIN_PULSE,
    OSR,
    PERIOD,
    REF_BASE,
    STATUS,
    STATUS_ACTIVE,
    STATUS_FAULT,
    STATUS_FAULT_INPUT,
    STATUS_PERIOD_CLAMPED,
    STATUS_REF_PENDING,
    STATUS_SATURATED,
    info_word,
    validate_top_phases,
)

from .clock import CoreModel
from .driver import GateDriverModel
from .inputs import check_bit

__all__ = ["TOP_OUTPUTS", "TopModel"]

#: per-cycle outputs of :meth:`TopModel.step`
TOP_OUTPUTS = ("wb_ack", "wb_dat_r", "ref_ready", "upper", "lower", "adc_trigger", "sync_out",
               "fault")


def _u32(value, name):
    if (isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer))
            or not 0 <= value < (1 << 32)):
        raise ValueError(f"{name} must be an unsigned 32-bit integer, not {value!r}")
    return int(value)


class TopModel:
    """Cycle-accurate model of :class:`mdfqm_gateware.top.MdfqmTop` (see the module docstring)."""

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty",
                 dead_min: int = DEFAULT_DEAD_MIN, upper_active_low: bool = False,
                 lower_active_low: bool = False):
        validate_top_phases(phases)
        validate_dead_min(dead_min, TIME_WIDTH)
        self.core = CoreModel(phases, width, rule)
        self.driver = GateDriverModel(phases, dead_min, TIME_WIDTH, upper_active_low,
                                      lower_active_low)
        self.phases, self.width, self.rule = phases, width, rule
        self.dead_min = dead_min
        self.latency = self.core.latency
        self.contract = self.core.contract
        self.info = info_word(phases, width, rule, upper_active_low, lower_active_low,
                              self.latency)
        self.reset()

    def reset(self) -> None:
        """Reset state of the top's own registers (the sub-models reset on ``rst`` themselves)."""
        n = self.phases
        self.ctrl = 0
        self.period = self.latency
        self.osr = 1
        self.dead = self.dead_min
        self.min_pulse = 0
        self.adc_offset = 0
        self.ref = [0] * n
        self.snapshot = [0] * n
        self.ref_pending = 0
        self.ack = 0
        self.dat_r = 0
        self.events = [0] * n
        self.total = 0
        self.adc_cnt = 0
        self.adc = 0

    # ------------------------------------------------------------------ the register file
    def read(self, address: int, core_out: dict, drv_out: dict, up: int, lo: int) -> int:
        """The word a read of ``address`` returns in a cycle with these sub-model outputs and
        active-high gates ``up`` / ``lo`` (the registers of this cycle, before :meth:`step`
        advances them)."""
        n = self.phases
        if address == ID:
            return ID_VALUE
        if address == INFO:
            return self.info
        if address == DEAD_MIN:
            return self.dead_min
        if address == CTRL:
            return self.ctrl
        if address == STATUS:
            return (drv_out["fault"] * STATUS_FAULT | drv_out["fault_input"] * STATUS_FAULT_INPUT
                    | drv_out["active"] * STATUS_ACTIVE | self.ref_pending * STATUS_REF_PENDING
                    | core_out["saturated"] * STATUS_SATURATED
                    | core_out["period_clamped"] * STATUS_PERIOD_CLAMPED)
        if address == PERIOD:
            return self.period
        if address == OSR:
            return self.osr
        if address == DEAD:
            return self.dead
        if address == MIN_PULSE:
            return self.min_pulse
        if address == ADC_OFFSET:
            return self.adc_offset
        if address == EVENTS_TOTAL:
            return self.total
        if address == GATES:
            return up | lo << 16
        if REF_BASE <= address < REF_BASE + n:
            return self.ref[address - REF_BASE] & 0xFFFFFFFF
        if EVENTS_BASE <= address < EVENTS_BASE + n:
            return self.events[address - EVENTS_BASE]
        return 0

    def write(self, address: int, value: int) -> None:
        """A write's effect on the stored registers (CMD strobes are handled in :meth:`step`)."""
        c = self.contract
        if address == CTRL:
            self.ctrl = value & CTRL_MASK
        elif address == PERIOD:
            self.period = min(value, 0xFFFF)
        elif address == OSR:
            self.osr = min(value, 0xFF)
        elif address == DEAD:
            self.dead = min(max(value, self.dead_min), 0xFFFF)
        elif address == MIN_PULSE:
            self.min_pulse = min(value, 0xFFFF)
        elif address == ADC_OFFSET:
            self.adc_offset = min(value, 0xFFFF)
        elif REF_BASE <= address < REF_BASE + self.phases:
            signed = value - (1 << 32) if value >> 31 else value
            self.ref[address - REF_BASE] = min(max(signed, c.code_min), c.code_max)

    # ------------------------------------------------------------------ one clock
    @property
    def ref_ready(self) -> int:
        return int(self.core.ref_ready and not self.ref_pending)

    def step(self, rst=0, wb_cyc=0, wb_stb=0, wb_we=0, wb_adr=0, wb_dat_w=0, wb_sel=0xF,
             ref_valid=0, ref=None, fault_in=0, sync_in=0) -> dict:
        """Outputs visible during this cycle, then advance to the next one."""
        rst = check_bit(rst, "rst")
        wb_cyc, wb_stb = check_bit(wb_cyc, "wb_cyc"), check_bit(wb_stb, "wb_stb")
        wb_we = check_bit(wb_we, "wb_we")
        if (isinstance(wb_adr, (bool, np.bool_)) or not isinstance(wb_adr, (int, np.integer))
                or not 0 <= wb_adr < (1 << ADDR_WIDTH)):
            raise ValueError(f"wb_adr must be an unsigned {ADDR_WIDTH}-bit integer, not {wb_adr!r}")
        wb_adr = int(wb_adr)
        wb_dat_w = _u32(wb_dat_w, "wb_dat_w")
        if isinstance(wb_sel, bool) or wb_sel not in range(16):
            raise ValueError(f"wb_sel must be an unsigned 4-bit integer, not {wb_sel!r}")
        ref_valid = check_bit(ref_valid, "ref_valid")
        fault_in, sync_in = check_bit(fault_in, "fault_in"), check_bit(sync_in, "sync_in")

        req = wb_cyc and wb_stb and not self.ack
        wr = req and wb_we
        cmd = wb_dat_w if wr and wb_adr == CMD else 0
        port_ready = self.ref_ready
        core_ready = self.core.ref_ready

        core_out = self.core.step(
            rst=rst, ref_valid=int(self.ref_pending or ref_valid),
            ref=self.snapshot if self.ref_pending else ref, period=self.period, osr=self.osr,
            zero_policy=int(bool(self.ctrl & CTRL_ZERO_POLICY)), sync_in=sync_in)
        assert core_out["ref_ready"] == core_ready
        up, lo = self.driver.up, self.driver.lo
        drv_out = self.driver.step(
            rst=rst, h=core_out["h"], update=core_out["update"],
            enable=int(bool(self.ctrl & CTRL_ENABLE)), dead=self.dead, min_pulse=self.min_pulse,
            fault_in=fault_in, fault_clear=int(bool(cmd & CMD_FAULT_CLEAR)))
        out = {
            "wb_ack": self.ack,
            "wb_dat_r": self.dat_r,
            "ref_ready": port_ready,
            "upper": drv_out["upper"],
            "lower": drv_out["lower"],
            "adc_trigger": self.adc,
            "sync_out": core_out["start"],
            "fault": drv_out["fault"],
        }
        if rst:
            self.reset()
            return out
        rd = self.read(wb_adr, core_out, drv_out, up, lo) if req and not wb_we else 0

        # reference arbitration (a commit wins over the clear of an accepted beat)
        if cmd & CMD_REF_COMMIT:
            self.snapshot, self.ref_pending = list(self.ref), 1
        elif self.ref_pending and core_ready:
            self.ref_pending = 0
        # switching counters
        event = drv_out["event"]
        if cmd & CMD_COUNT_CLEAR:
            self.events, self.total = [0] * self.phases, 0
        else:
            mask = (1 << COUNTER_WIDTH) - 1
            self.events = [(e + ((event >> i) & 1)) & mask for i, e in enumerate(self.events)]
            self.total = (self.total + bin(event).count("1")) & mask
        # ADC trigger
        elapsed = 0 if core_out["start"] else self.adc_cnt
        self.adc_cnt = min(elapsed + 1, (1 << ADC_COUNTER_WIDTH) - 1)
        self.adc = int(elapsed == self.adc_offset)
        # the bus
        if wr:
            self.write(wb_adr, wb_dat_w)
        self.ack = int(req)
        self.dat_r = rd
        return out
