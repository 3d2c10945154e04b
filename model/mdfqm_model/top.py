"""Clock-level model of the drop-in top: the gating-signal generator (or, with ``max_bits`` 0,
the MDFQM core alone) + gate driver + register file behind a bus front (Wishbone classic or
AXI4-Lite) + switching counters + ADC trigger. The register map is
:mod:`mdfqm_spec.regmap` (the gateware builds its register file from it, ``docs/top.md``
documents it, a test checks the table there).

The algorithm is not repeated here: :class:`TopModel` composes
:class:`mdfqm_model.clock.GeneratorModel` (:class:`~mdfqm_model.clock.CoreModel` for the
MDFQM-only top) and :class:`mdfqm_model.driver.GateDriverModel`.

The register bus (:mod:`mdfqm_spec.bus`)
----------------------------------------
Either front issues *accesses* to the register file: a write issued in a cycle is taken by the
register file ``WRITE_LATENCY`` (1) cycles later and takes effect at the end of that cycle
(visible in the next), so a write issued in cycle ``c`` is visible from ``c + 2``; a read
issued in a cycle returns the registers of that cycle. A reset drops a write not yet taken.

- Wishbone classic (:class:`WishboneFrontModel`; 32-bit data, word addresses, ``ADDR_WIDTH``
  bits): a *request* is a cycle with ``cyc & stb & ~ack``; it is the access. ``ack`` is high in
  the next cycle for one clock (registered), and ``dat_r`` in that cycle holds the register read
  in the request cycle (0 after a write or when no request). No stalls, no ERR/RTY; ``sel`` is
  accepted and ignored (every write writes the whole register: use 32-bit accesses). A master
  holding ``stb`` through the ``ack`` cycle is not seen twice: the ``ack`` cycle is never a
  request.
- AXI4-Lite (:class:`AxiLiteFrontModel`; byte addresses, ``AXI_ADDR_WIDTH`` bits, the low two
  ignored): holding registers ``aw_full``/``w_full``/``ar_full``; ``awready = ~aw_full``,
  ``wready = ~w_full``, ``arready = ~ar_full``. A write is issued in a cycle with
  ``aw_full & w_full & (~bvalid | bready)``: both holding registers empty and ``bvalid`` (with
  ``bresp``) is high from the next cycle until a cycle with ``bready``. A read is issued in a
  cycle with ``ar_full & (~rvalid | rready)``: ``rvalid``, ``rdata`` (the register read) and
  ``rresp`` from the next cycle until ``rready``. Otherwise a holding register fills in the
  cycle after its channel's handshake. Responses: OKAY, or SLVERR for a word that holds no
  register. ``wstrb`` and ``*prot`` are ignored.

Write clamps (every value of every field is legal; nothing wraps): unsigned fields saturate at
their maximum (``min(value, max)`` of the 32-bit word); ``DEAD`` is also raised to the
floor ``dead_min``; ``REF[i]`` takes the word as signed 32-bit and saturates it into the
``width``-bit code range; ``CTRL`` keeps its two defined bits. Writes to read-only or unmapped
addresses are acknowledged and ignored (AXI4-Lite: SLVERR for unmapped ones); unmapped addresses
read 0.

Per-cycle behaviour (registers reset synchronously; see also the two sub-models)
-------------------------------------------------------------------------------
- Generator inputs: ``period = PERIOD``, ``osr = OSR``, ``zero_policy = CTRL.ZERO_POLICY``,
  ``sync_in`` (port), ``mode`` / ``bits`` = the last ``MODULATION`` write's fields (the
  request; the generator latches and clamps them at each update start). ``sync_out`` is the
  generator's ``start`` (combinational from its registers). ``MODULATION`` reads the generator's
  ``mode_in_force`` / ``bits_in_force``; ``STATUS.MODE_CLAMPED`` is its ``mode_clamped``. The
  MDFQM-only top (the core, ``max_bits`` 0) reads mode 0 and b 0, and its ``MODE_CLAMPED`` is
  set at each update start to ``mode request != 0`` (``latch_mode`` with ``max_bits`` 0).
- Reference: ``CMD.REF_COMMIT`` copies ``REF[0..N-1]`` into a snapshot and sets ``ref_pending``.
  The core's stream sees ``valid = ref_pending | ref.valid`` and the snapshot while
  ``ref_pending``: **a committed register beat wins** over the direct stream port, whose
  ``ready`` is ``core_ready & ~ref_pending``. ``ref_pending`` clears when the core accepts it;
  a commit while one is pending replaces the snapshot (a commit wins over the clear).
- Driver inputs: the generator's ``h`` (followed every clock) and ``update``,
  ``enable = CTRL.ENABLE``, ``dead = DEAD``, ``min_pulse = MIN_PULSE``, ``fault_in`` (port),
  ``fault_clear = CMD.FAULT_CLEAR`` strobe, ``stop`` = the watchdog latch,
  ``reaction_fault = FAULT_REACTION.FAULT``, ``reaction_watchdog = FAULT_REACTION.WATCHDOG``,
  ``all_off = CMD.ALL_OFF`` strobe. ``STATUS.REACTION`` reads the driver's ``reaction`` (the
  reaction in force). ``FAULT_REACTION`` stores each field as ``v % 3`` of its two bits (3
  stores 0), and 0 when the active short circuit is not built in (``asc`` False; ``INFO.ASC``).
- Switching counters: ``EVENTS[i] += event[i]``, ``EVENTS_TOTAL += popcount(event)`` each
  cycle, ``event`` being the driver's turn-on strobes (one per turn-on of either switch of a
  leg: in complementary switching, one per change of the leg's state). 32 bits, wrapping.
  ``CMD.COUNT_CLEAR`` zeroes them all (the strobes of that cycle are not counted), and
  ``WATCHDOG_TRIPS``.
- Interrupt: ``IRQ_STATUS`` bit ``k`` is set in the clock after its event and stays until a
  write of 1 to it (an event in the same clock as the clear wins): ``FAULT`` when the fault
  latch is about to set (``fault_input & ~fault``), ``COUNTER_WRAP`` when ``EVENTS_TOTAL``
  passes ``2**counter_width - 1`` (every per-leg counter wraps no earlier, being at most the
  total since the last clear; not in a ``COUNT_CLEAR`` clock), ``SAMPLE`` in a sampling tick
  (the core's ``sample``: the update that takes the next reference starts, so firmware can
  write the following one), ``SHORT_EDGE`` in a cycle with a short edge (the driver's
  ``short_edge_now`` not zero: a leg's command changes before the leg has followed the last
  change), ``WATCHDOG`` in the cycle of a watchdog trip (the update start ``s``: the bit is set from
  ``s + 1``, with the latch).
  ``irq <= |(IRQ_STATUS & IRQ_ENABLE)`` (registered from both
  registers: it follows them one clock later; reset 0).
- Reference watchdog: a reference *arrives* in a cycle with a beat taken on the port
  (``ref_valid & ref_ready``) or a ``CMD.REF_COMMIT`` write; the watchdog *sees* it in the next
  cycle (``arrival``, a register). ``quiet`` counts update starts since the last arrival seen
  (16 bits, saturating): ``quiet <= 0`` if an arrival is seen, ``WATCHDOG == 0``
  (off), the latch, or a trip in this cycle, else ``quiet + 1`` in a cycle with ``start``. A
  *trip* is a cycle with ``start``, no arrival seen, ``WATCHDOG != 0``, the latch clear and
  ``quiet >= WATCHDOG``: the latch (``STATUS.WATCHDOG``) sets, ``WATCHDOG_TRIPS`` counts it
  (saturating at 65535; ``CMD.COUNT_CLEAR`` zeroes it, a trip in the same cycle counts 1), and
  ``IRQ_STATUS.WATCHDOG`` is set. The latch is the driver's ``stop``: every gate off in the cycle
  after the latch is set (two after the tripping start ``s``: ``s + 2``), and the taken enable
  cleared; ``CMD.WATCHDOG_CLEAR`` clears it (gates resume at the next update boundary with
  ``CTRL.ENABLE``), after which the count starts again from 0. Without the watchdog built in
  (``watchdog`` False; ``INFO.WATCHDOG``) ``WATCHDOG`` and ``FAULT_REACTION.WATCHDOG`` store 0,
  so it never trips.
- ADC trigger: ``elapsed = 0 if start else cnt``; ``cnt <= (elapsed + 1) mod 2**16``;
  ``adc_trigger <= elapsed == ADC_OFFSET``. So the pulse is in cycle ``s + 1 + ADC_OFFSET``,
  ``s`` the update start, and there is none when ``ADC_OFFSET >= P`` (the update period).
  The count never wraps: an update lasts ``P <= 65535`` clocks (PERIOD is 16 bits and every
  minimum period is below it), so ``elapsed <= 65534``.
"""

from __future__ import annotations

from typing import ClassVar

from mdfqm_spec.bus import (
    AXI_ADDR_WIDTH,
    AXI_RESP_OKAY,
    AXI_RESP_SLVERR,
    WRITE_LATENCY,
    mapped_words,
    validate_bus,
)
from mdfqm_spec.contract import (
    BITS_WIDTH,
    MODE_WIDTH,
    TIME_WIDTH,
    latch_mode,
    validate_dead_min,
    validate_top_max_bits,
)
from mdfqm_spec.regmap import (
    ADC_COUNTER_WIDTH,
    ADC_OFFSET,
    ADDR_WIDTH,
    CMD,
    CMD_ALL_OFF,
    CMD_COUNT_CLEAR,
    CMD_FAULT_CLEAR,
    CMD_REF_COMMIT,
    CMD_WATCHDOG_CLEAR,
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
    FAULT_REACTION,
    FAULT_REACTION_FAULT,
    FAULT_REACTION_FAULT_SHIFT,
    FAULT_REACTION_WATCHDOG,
    FAULT_REACTION_WATCHDOG_SHIFT,
    GATES,
    ID,
    ID_VALUE,
    INFO,
    IRQ_COUNTER_WRAP,
    IRQ_ENABLE,
    IRQ_FAULT,
    IRQ_MASK,
    IRQ_SAMPLE,
    IRQ_SHORT_EDGE,
    IRQ_STATUS,
    IRQ_WATCHDOG,
    MIN_PULSE,
    MODULATION,
    MODULATION_BITS_SHIFT,
    MODULATION_MODE_SHIFT,
    OSR,
    PERIOD,
    REF_BASE,
    STATUS,
    STATUS_ACTIVE,
    STATUS_FAULT,
    STATUS_FAULT_INPUT,
    STATUS_MODE_CLAMPED,
    STATUS_PERIOD_CLAMPED,
    STATUS_REACTION_SHIFT,
    STATUS_REF_PENDING,
    STATUS_SATURATED,
    STATUS_WATCHDOG,
    WATCHDOG,
    WATCHDOG_TRIPS,
    default_max_bits,
    info_word,
    validate_top_phases,
)
from mdfqm_spec.validate import validate_bool, validate_int

from .clock import CoreModel, GeneratorModel
from .driver import GateDriverModel
from .inputs import check_bit, check_uint

__all__ = ["TOP_OUTPUTS", "AxiLiteFrontModel", "TopModel", "WishboneFrontModel"]

#: per-cycle outputs of :meth:`TopModel.step` besides the bus front's (``front.OUTPUTS``)
TOP_OUTPUTS = ("ref_ready", "upper", "lower", "adc_trigger", "sync_out", "fault", "irq")


class WishboneFrontModel:
    """The Wishbone-classic front (see the module docstring): inputs ``wb_*``, outputs
    ``wb_ack`` and ``wb_dat_r``."""

    #: input name -> bits
    INPUTS: ClassVar[dict] = {"wb_cyc": 1, "wb_stb": 1, "wb_we": 1, "wb_adr": ADDR_WIDTH,
                              "wb_dat_w": 32, "wb_sel": 4}
    OUTPUTS = ("wb_ack", "wb_dat_r")

    def __init__(self, phases: int):
        self.reset()

    def reset(self) -> None:
        self.ack = 0
        self.dat_r = 0

    def outputs(self) -> dict:
        return {"wb_ack": self.ack, "wb_dat_r": self.dat_r}

    def access(self, bus: dict) -> tuple:
        """``(write, read)`` issued this cycle: ``(address, data)`` or None, an address or None."""
        request = bus["wb_cyc"] and bus["wb_stb"] and not self.ack
        write = (bus["wb_adr"], bus["wb_dat_w"]) if request and bus["wb_we"] else None
        read = bus["wb_adr"] if request and not bus["wb_we"] else None
        return write, read

    def advance(self, bus: dict, write, read, value: int) -> None:
        self.ack = int(write is not None or read is not None)
        self.dat_r = value if read is not None else 0


class AxiLiteFrontModel:
    """The AXI4-Lite front (see the module docstring): inputs and outputs ``s_axi_*``."""

    INPUTS: ClassVar[dict] = {
        "s_axi_awaddr": AXI_ADDR_WIDTH, "s_axi_awprot": 3, "s_axi_awvalid": 1,
        "s_axi_wdata": 32, "s_axi_wstrb": 4, "s_axi_wvalid": 1, "s_axi_bready": 1,
        "s_axi_araddr": AXI_ADDR_WIDTH, "s_axi_arprot": 3, "s_axi_arvalid": 1, "s_axi_rready": 1}
    OUTPUTS = ("s_axi_awready", "s_axi_wready", "s_axi_bvalid", "s_axi_bresp", "s_axi_arready",
               "s_axi_rvalid", "s_axi_rdata", "s_axi_rresp")

    def __init__(self, phases: int):
        self.mapped = mapped_words(phases)
        self.reset()

    def reset(self) -> None:
        self.aw_full = self.w_full = self.ar_full = 0
        self.aw_adr = self.ar_adr = self.w_data = 0
        self.bvalid = self.bresp = 0
        self.rvalid = self.rdata = self.rresp = 0

    def outputs(self) -> dict:
        return {"s_axi_awready": 1 - self.aw_full, "s_axi_wready": 1 - self.w_full,
                "s_axi_bvalid": self.bvalid, "s_axi_bresp": self.bresp,
                "s_axi_arready": 1 - self.ar_full, "s_axi_rvalid": self.rvalid,
                "s_axi_rdata": self.rdata, "s_axi_rresp": self.rresp}

    def access(self, bus: dict) -> tuple:
        write = read = None
        if self.aw_full and self.w_full and (not self.bvalid or bus["s_axi_bready"]):
            write = (self.aw_adr, self.w_data)
        if self.ar_full and (not self.rvalid or bus["s_axi_rready"]):
            read = self.ar_adr
        return write, read

    def _resp(self, address: int) -> int:
        return AXI_RESP_OKAY if address in self.mapped else AXI_RESP_SLVERR

    def advance(self, bus: dict, write, read, value: int) -> None:
        if write is not None:
            self.aw_full = self.w_full = 0
            self.bvalid, self.bresp = 1, self._resp(self.aw_adr)
        else:
            if bus["s_axi_awvalid"] and not self.aw_full:
                self.aw_full, self.aw_adr = 1, bus["s_axi_awaddr"] >> 2
            if bus["s_axi_wvalid"] and not self.w_full:
                self.w_full, self.w_data = 1, bus["s_axi_wdata"]
            if bus["s_axi_bready"]:
                self.bvalid = 0
        if read is not None:
            self.ar_full = 0
            self.rvalid, self.rdata, self.rresp = 1, value, self._resp(self.ar_adr)
        else:
            if bus["s_axi_arvalid"] and not self.ar_full:
                self.ar_full, self.ar_adr = 1, bus["s_axi_araddr"] >> 2
            if bus["s_axi_rready"]:
                self.rvalid = 0


FRONTS = {"wishbone": WishboneFrontModel, "axi4lite": AxiLiteFrontModel}


class TopModel:
    """Cycle-accurate model of :class:`mdfqm_gateware.top.MdfqmTop` (see the module docstring)."""

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty",
                 dead_min: int = DEFAULT_DEAD_MIN, upper_active_low: bool = False,
                 lower_active_low: bool = False, bus: str = "wishbone",
                 counter_width: int = COUNTER_WIDTH, max_bits: int | None = None,
                 asc: bool = True, watchdog: bool = True):
        validate_top_phases(phases)
        self.asc = validate_bool(asc, "asc")
        self.watchdog = validate_bool(watchdog, "watchdog")
        self.counter_width = validate_int(counter_width, "counter_width", 8, COUNTER_WIDTH)
        self.front = FRONTS[validate_bus(bus)](phases)
        validate_dead_min(dead_min, TIME_WIDTH)
        if max_bits is None:            # MdfqmTop's default
            max_bits = default_max_bits(width)
        self.max_bits = validate_top_max_bits(max_bits, width)
        self.core = (GeneratorModel(phases, width, rule, max_bits) if max_bits else
                     CoreModel(phases, width, rule))
        self.driver = GateDriverModel(phases, dead_min, TIME_WIDTH, upper_active_low,
                                      lower_active_low, asc)
        self.phases, self.width, self.rule = phases, width, rule
        self.dead_min = dead_min
        self.latency = self.core.latency
        self.contract = self.core.contract
        self.long_latency = self.core.long_latency if max_bits else self.latency
        self.info = info_word(phases, width, rule, upper_active_low, lower_active_low,
                              self.latency, max_bits, asc=asc, watchdog=watchdog)
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
        self.front.reset()
        self.events = [0] * n
        self.total = 0
        self.adc_cnt = 0
        self.adc = 0
        self.irq_enable = 0
        self.irq_status = 0
        self.irq = 0
        self.mode_request = 0
        self.bits_request = 0
        self.core_mode_clamped = 0      # the MDFQM-only top's flag (the generator has its own)
        self.wd_timeout = 0
        self.wd_quiet = 0               # update starts since the last reference arrival
        self.wd_tripped = 0
        self.wd_trips = 0
        self.wd_arrival = 0             # a reference arrived in the clock before
        self.fault_reaction = 0
        #: the writes issued and not yet taken by the register file, oldest first
        self.writes_issued = [None] * WRITE_LATENCY

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
                    | core_out["period_clamped"] * STATUS_PERIOD_CLAMPED
                    | self._mode_clamped(core_out) * STATUS_MODE_CLAMPED
                    | self.wd_tripped * STATUS_WATCHDOG
                    | drv_out["reaction"] << STATUS_REACTION_SHIFT)
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
        if address == IRQ_ENABLE:
            return self.irq_enable
        if address == IRQ_STATUS:
            return self.irq_status
        if address == MODULATION:
            mode, bits = ((core_out["mode_in_force"], core_out["bits_in_force"])
                          if self.max_bits else (0, 0))
            return mode << MODULATION_MODE_SHIFT | bits << MODULATION_BITS_SHIFT
        if address == WATCHDOG:
            return self.wd_timeout
        if address == WATCHDOG_TRIPS:
            return self.wd_trips
        if address == FAULT_REACTION:
            return self.fault_reaction
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
        elif address == IRQ_ENABLE:
            self.irq_enable = value & IRQ_MASK
        elif address == IRQ_STATUS:
            self.irq_status &= ~value
        elif address == WATCHDOG:
            self.wd_timeout = min(value, 0xFFFF) * self.watchdog
        elif address == FAULT_REACTION:
            # each field: 3 stores 0, and so does an ASC code when none is built in, and any
            # watchdog reaction without the watchdog
            fault = (value >> FAULT_REACTION_FAULT_SHIFT) % 4 % 3 * self.asc
            watchdog = (value >> FAULT_REACTION_WATCHDOG_SHIFT) % 4 % 3 * self.asc * self.watchdog
            self.fault_reaction = (fault << FAULT_REACTION_FAULT_SHIFT
                                   | watchdog << FAULT_REACTION_WATCHDOG_SHIFT)
        elif address == MODULATION:
            self.mode_request = (value >> MODULATION_MODE_SHIFT) & ((1 << MODE_WIDTH) - 1)
            self.bits_request = (value >> MODULATION_BITS_SHIFT) & ((1 << BITS_WIDTH) - 1)
        elif REF_BASE <= address < REF_BASE + self.phases:
            signed = value - (1 << 32) if value >> 31 else value
            self.ref[address - REF_BASE] = min(max(signed, c.code_min), c.code_max)

    @property
    def write_taken(self):
        """The write ``(address, data)`` the register file takes in this cycle (None: none):
        the one the front issued ``WRITE_LATENCY`` cycles ago."""
        return self.writes_issued[0]

    def _mode_clamped(self, core_out: dict) -> int:
        return core_out["mode_clamped"] if self.max_bits else self.core_mode_clamped

    # ------------------------------------------------------------------ one clock
    @property
    def ref_ready(self) -> int:
        return int(self.core.ref_ready and not self.ref_pending)

    def step(self, rst=0, ref_valid=0, ref=None, fault_in=0, sync_in=0, **bus) -> dict:
        """Outputs visible during this cycle, then advance to the next one. ``bus`` holds the
        front's inputs (``front.INPUTS``; each 0 when not given)."""
        rst = check_bit(rst, "rst")
        unknown = sorted(set(bus) - set(self.front.INPUTS))
        if unknown:
            raise ValueError(f"unknown inputs {unknown} for the {type(self.front).__name__}")
        bus = {name: check_uint(bus.get(name, 0), bits, name)
               for name, bits in self.front.INPUTS.items()}
        ref_valid = check_bit(ref_valid, "ref_valid")
        fault_in, sync_in = check_bit(fault_in, "fault_in"), check_bit(sync_in, "sync_in")

        issued, read = self.front.access(bus)
        write = self.write_taken
        cmd = write[1] if write is not None and write[0] == CMD else 0
        port_ready = self.ref_ready
        core_ready = self.core.ref_ready

        modulation = ({"mode": self.mode_request, "bits": self.bits_request}
                      if self.max_bits else {})
        core_out = self.core.step(
            rst=rst, ref_valid=int(self.ref_pending or ref_valid),
            ref=self.snapshot if self.ref_pending else ref, period=self.period, osr=self.osr,
            zero_policy=int(bool(self.ctrl & CTRL_ZERO_POLICY)), sync_in=sync_in, **modulation)
        assert core_out["ref_ready"] == core_ready
        up, lo = self.driver.up, self.driver.lo
        drv_out = self.driver.step(
            rst=rst, h=core_out["h"], update=core_out["update"],
            enable=int(bool(self.ctrl & CTRL_ENABLE)), dead=self.dead, min_pulse=self.min_pulse,
            fault_in=fault_in, fault_clear=int(bool(cmd & CMD_FAULT_CLEAR)), stop=self.wd_tripped,
            reaction_fault=(self.fault_reaction & FAULT_REACTION_FAULT)
            >> FAULT_REACTION_FAULT_SHIFT,
            reaction_watchdog=(self.fault_reaction & FAULT_REACTION_WATCHDOG)
            >> FAULT_REACTION_WATCHDOG_SHIFT,
            all_off=int(bool(cmd & CMD_ALL_OFF)))
        out = {
            **self.front.outputs(),
            "ref_ready": port_ready,
            "upper": drv_out["upper"],
            "lower": drv_out["lower"],
            "adc_trigger": self.adc,
            "sync_out": core_out["start"],
            "fault": drv_out["fault"],
            "irq": self.irq,
        }
        if rst:
            self.reset()
            return out
        value = self.read(read, core_out, drv_out, up, lo) if read is not None else 0

        # the watchdog (a reference arrives as a beat taken on the port or as a commit)
        arrival = self.wd_arrival                   # seen the clock after it arrives
        trip = (self.wd_timeout != 0 and not self.wd_tripped and core_out["start"]
                and not arrival and self.wd_quiet >= self.wd_timeout)
        self.wd_arrival = int(bool(ref_valid and port_ready) or bool(cmd & CMD_REF_COMMIT))
        if arrival or self.wd_timeout == 0 or self.wd_tripped or trip:
            self.wd_quiet = 0
        elif core_out["start"]:
            self.wd_quiet = min(self.wd_quiet + 1, 0xFFFF)
        if trip:
            self.wd_tripped = 1
        elif cmd & CMD_WATCHDOG_CLEAR:
            self.wd_tripped = 0
        kept = 0 if cmd & CMD_COUNT_CLEAR else self.wd_trips
        self.wd_trips = min(kept + trip, 0xFFFF)
        # reference arbitration (a commit wins over the clear of an accepted beat)
        if cmd & CMD_REF_COMMIT:
            self.snapshot, self.ref_pending = list(self.ref), 1
        elif self.ref_pending and core_ready:
            self.ref_pending = 0
        # switching counters
        event = drv_out["event"]
        wrapped = 0
        if cmd & CMD_COUNT_CLEAR:
            self.events, self.total = [0] * self.phases, 0
        else:
            mask = (1 << self.counter_width) - 1
            self.events = [(e + ((event >> i) & 1)) & mask for i, e in enumerate(self.events)]
            wrapped = (self.total + bin(event).count("1")) >> self.counter_width
            self.total = (self.total + bin(event).count("1")) & mask
        irq_events = ((IRQ_FAULT if drv_out["fault_input"] and not drv_out["fault"] else 0)
                      | (IRQ_COUNTER_WRAP if wrapped else 0)
                      | (IRQ_SAMPLE if core_out["sample"] else 0)
                      | (IRQ_SHORT_EDGE if drv_out["short_edge_now"] else 0)
                      | (IRQ_WATCHDOG if trip else 0))
        if core_out["start"]:
            self.core_mode_clamped = int(latch_mode(self.mode_request, self.bits_request, 0)[2])
        # ADC trigger
        elapsed = 0 if core_out["start"] else self.adc_cnt
        self.adc_cnt = (elapsed + 1) % (1 << ADC_COUNTER_WIDTH)
        self.adc = int(elapsed == self.adc_offset)
        # the bus (a write-1-to-clear of IRQ_STATUS loses against an event of the same clock)
        self.irq = int(bool(self.irq_status & self.irq_enable))   # this clock's registers
        if write is not None:
            self.write(*write)
        self.irq_status |= irq_events
        self.writes_issued = [*self.writes_issued[1:], issued]
        self.front.advance(bus, issued, read, value)
        return out
