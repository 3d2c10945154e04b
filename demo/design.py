"""The board-independent demo: UART -> bridge -> registers, an N-phase sine NCO feeding the
drop-in top (:class:`~mdfqm_gateware.top.MdfqmTop`), gates, fault, LEDs, buttons and a clock
counter for telemetry (the switching counters are the top's ``EVENTS_i``).

Board tops (``boards/<board>/top.py``) only add the clock, the reset and the pins; everything
here is simulated as one toplevel by ``tb/test_demo_top.py`` and predicted clock by clock by
``tb/mdfqm_testkit/demo_models.py: DemoModel``.

Bus: the UART bridge and the :class:`~.sequencer.BusSequencer` (settings after reset, the
enable and fault-clear buttons) share one Wishbone-classic bus (:class:`~.arbiter.
WishboneArbiter`); the decoder puts the top's registers at ``TOP_BASE`` (64 words) and the
demo's block at ``0x100`` (32 words).
"""

from __future__ import annotations

import math

from amaranth import Cat, Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out, connect

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec import regmap as top_map
from mdfqm_spec.contract import Contract, validate_top_max_bits
from mdfqm_spec.regmap import ID_VALUE, INFO_TOP, TOP_BASE, demo_window
from mdfqm_spec.validate import validate_positive

from .arbiter import WishboneArbiter
from .bridge import UartBridge
from .bus_master import BusSequencer
from .buttons import Buttons
from .nco import SineNco
from .register_bank import RegisterBank
from .uart import UartRx, UartTx, uart_divider
from .wishbone import WishboneDecoder

__all__ = ["ACTIONS", "DemoConfig", "DemoDesign"]

#: what a button can do
ACTIONS = ("enable", "fault_clear", "freq_up", "freq_down", "amp_up", "amp_down")


def _clocks(ns, clk_hz) -> int:
    """Whole clocks covering ``ns`` nanoseconds (rounded up, float noise ignored)."""
    return math.ceil(round(ns * clk_hz / 1e9, 6))


class DemoConfig:
    """Every parameter of the demo, validated, with the derived register values.

    Parameters
    ----------
    clk_hz : int >= 1_000_000
        System clock (after the board's PLL).
    baud : int
        UART rate (8N1); must be within 2 % of ``clk_hz / round(clk_hz / baud)``.
    phases, width : int
        The top's (``phases`` in [3, 8], the demo's tested range).
    buttons : tuple of str
        Action of each button input, from :data:`ACTIONS`, no repeats.
    debounce : int or None
        Clocks between button samples; default 10 ms.
    acc_bits, table_bits, sample_width, quarter :
        The NCO's (:class:`~.nco.SineNco`).
    freq_hz, amplitude :
        Reset frequency of the NCO and its amplitude in Vdc (peak of each phase).
    update_hz, dead_ns, min_pulse_ns :
        Written to the top's ``PERIOD`` (``round(clk_hz / update_hz)``), ``DEAD`` and
        ``MIN_PULSE`` after reset (rounded up to whole clocks).
    dead_min_ns :
        The top's dead-time floor (elaboration parameter, at least one clock).
    max_bits : int
        The top's ``max_bits``: 0 (the default) builds the MDFQM-only top, which every board
        fits (the iCEBreaker keeps it); 1 .. min(12, width - 2) the whole generator (SVPWM,
        DPWM, b-bit) behind the bus (the HX8K and ECP5 boards: 8).
    bus_timeout, frame_timeout : int or None
        The bridge's (default frame timeout: 30 byte times); ``bus_timeout`` in [2, 65536]: a
        register access takes two clocks (the arbiter registers the request).
    """

    def __init__(self, clk_hz, baud=115200, phases=3, width=16, buttons=(), debounce=None,
                 acc_bits=32, table_bits=8, sample_width=16, quarter=True, freq_hz=50.0,
                 amplitude=0.5, update_hz=100e3, dead_ns=500, min_pulse_ns=0, dead_min_ns=200,
                 bus_timeout=64, frame_timeout=None, max_bits=0):
        self.clk_hz = validate_positive(clk_hz, "clk_hz", minimum=1_000_000)
        self.baud = baud
        self.divider = uart_divider(clk_hz, baud)
        self.contract = Contract(phases, width)
        validate_positive(phases, "phases", minimum=3, maximum=8)
        self.phases, self.width = phases, width
        buttons = tuple(buttons)
        for action in buttons:
            if action not in ACTIONS:
                raise ValueError(f"buttons: {action!r} is not one of {ACTIONS}")
        if len(set(buttons)) != len(buttons):
            raise ValueError(f"buttons must not repeat an action: {buttons!r}")
        self.buttons = buttons
        self.debounce = validate_positive(
            clk_hz // 100 if debounce is None else debounce, "debounce", maximum=1 << 24)
        self.acc_bits, self.table_bits = acc_bits, table_bits
        self.sample_width, self.quarter = sample_width, quarter
        if not (isinstance(freq_hz, (int, float)) and 0 <= freq_hz < clk_hz / 2):
            raise ValueError(f"freq_hz must be a number in [0, clk_hz / 2), not {freq_hz!r}")
        if not (isinstance(amplitude, (int, float)) and 0 <= amplitude < 2):
            raise ValueError(f"amplitude must be a number of Vdc in [0, 2), not {amplitude!r}")
        # a register access takes two clocks through the arbiter's registered request
        self.bus_timeout = validate_positive(bus_timeout, "bus_timeout", minimum=2,
                                             maximum=1 << 16)
        self.frame_timeout = 300 * self.divider if frame_timeout is None else frame_timeout
        self.dead_min = validate_positive(max(1, _clocks(dead_min_ns, clk_hz)), "dead_min",
                                          maximum=0xFFFF)
        self.max_bits = validate_top_max_bits(max_bits, width)
        self.amp_step = self.contract.full // 32
        #: (address, value) written to the top by the bus sequencer after reset
        self.top_init = (
            (TOP_BASE + top_map.PERIOD, min(0xFFFF, round(clk_hz / update_hz))),
            (TOP_BASE + top_map.DEAD, min(0xFFFF, max(self.dead_min, _clocks(dead_ns, clk_hz)))),
            (TOP_BASE + top_map.MIN_PULSE, min(0xFFFF, _clocks(min_pulse_ns, clk_hz))),
        )
        self.demo_init = {
            "NCO_FREQ": round(freq_hz * (1 << acc_bits) / clk_hz),
            "NCO_AMP": min((1 << (width - 1)) - 1, round(amplitude * self.contract.full)),
        }
        self.heartbeat_bit = max(0, clk_hz.bit_length() - 2)   # toggles every ~0.5 to 1 s

    @property
    def info(self) -> int:
        return self.phases | self.width << 8 | self.acc_bits << 16 | INFO_TOP

    def as_dict(self) -> dict:
        """The main parameters (for test names and reports)."""
        return {"clk_hz": self.clk_hz, "baud": self.baud, "phases": self.phases,
                "width": self.width, "buttons": list(self.buttons), "debounce": self.debounce,
                "acc_bits": self.acc_bits, "table_bits": self.table_bits,
                "sample_width": self.sample_width, "quarter": self.quarter,
                "dead_min": self.dead_min, "bus_timeout": self.bus_timeout,
                "frame_timeout": self.frame_timeout, "max_bits": self.max_bits}


class DemoDesign(wiring.Component):
    """The whole demo between the pins of a board.

    Ports
    -----
    uart_rx : In(1)
        UART from the host (asynchronous; idle high).
    uart_tx : Out(1)
        UART to the host (registered; idle high).
    buttons : In(len(config.buttons))
        Active-high button levels (asynchronous); only present if the board has buttons.
    fault_in : In(1)
        Active-high fault from the power stage (asynchronous; the top synchronises it).
    upper, lower : Out(phases)
        Gate signals, active high, registered: upper and lower switch of each leg.
    led_active : Out(1)
        A gate is on: the top drives the power stage (registered).
    led_fault : Out(1)
        The top's fault latch (registered).
    heartbeat : Out(1)
        A bit of the clock counter (about 1 Hz): the clock runs.
    trigger : Out(1)
        The NCO phase MSB: a square wave in phase with phase 0 (scope trigger).

    Parameters
    ----------
    config : DemoConfig
    """

    def __init__(self, config: DemoConfig):
        if not isinstance(config, DemoConfig):
            raise ValueError(f"config must be a DemoConfig, not {config!r}")
        self.config = config
        n = config.phases
        members = {
            "uart_rx": In(1, init=1),
            "uart_tx": Out(1, init=1),
            "fault_in": In(1),
            "upper": Out(n),
            "lower": Out(n),
            "led_active": Out(1),
            "led_fault": Out(1),
            "heartbeat": Out(1),
            "trigger": Out(1),
        }
        if config.buttons:
            members["buttons"] = In(len(config.buttons))
        self.demo_window = demo_window(n, config.width, config.acc_bits)
        super().__init__(members)

    def elaborate(self, platform):
        m = Module()
        c = self.config
        n = c.phases
        m.submodules.uart_rx = urx = UartRx(c.divider)
        m.submodules.uart_tx = utx = UartTx(c.divider)
        m.submodules.bridge = bridge = UartBridge(16, c.bus_timeout, c.frame_timeout)
        m.submodules.sequencer = seq = BusSequencer(
            16, c.top_init, TOP_BASE + top_map.CTRL, top_map.CTRL_ENABLE,
            TOP_BASE + top_map.CMD, top_map.CMD_FAULT_CLEAR, top_map.TOP["CTRL"].width)
        m.submodules.arbiter = arbiter = WishboneArbiter(16)
        dw = self.demo_window
        m.submodules.decoder = decoder = WishboneDecoder(16, {
            "top": (TOP_BASE, top_map.ADDR_WIDTH), "demo": (dw.base, dw.addr_width)})
        m.submodules.regs = regs = RegisterBank(dw, init=c.demo_init,
                                                settable=("NCO_FREQ", "NCO_AMP"))
        m.submodules.nco = nco = SineNco(n, c.width, c.acc_bits, c.table_bits, c.sample_width,
                                         c.quarter)
        m.submodules.top = top = MdfqmTop(n, c.width, dead_min=c.dead_min, max_bits=c.max_bits)

        m.d.comb += [urx.rx.eq(self.uart_rx), self.uart_tx.eq(utx.tx)]
        connect(m, urx.o, bridge.rx)
        connect(m, bridge.tx, utx.i)
        connect(m, bridge.bus, arbiter.m0)
        connect(m, seq.bus, arbiter.m1)
        connect(m, arbiter.bus, decoder.bus)
        connect(m, decoder.demo, regs.bus)
        connect(m, decoder.top, top.wb)
        connect(m, nco.ref, top.ref)
        m.d.comb += [
            nco.freq.eq(regs.NCO_FREQ),
            nco.amplitude.eq(regs.NCO_AMP),
            top.fault_in.eq(self.fault_in),
            top.sync_in.eq(0),
            self.upper.eq(top.upper),
            self.lower.eq(top.lower),
            self.led_fault.eq(top.fault),
            self.trigger.eq(nco.phase[-1]),
        ]
        m.d.sync += self.led_active.eq((top.upper | top.lower) != 0)

        # telemetry: the clock counter, copied by SNAPSHOT; the turn-ons are counted by the
        # top (EVENTS_i), which the host reads after the snapshot
        cycles = Signal(32)
        m.d.sync += cycles.eq(cycles + 1)
        snap_cycles = Signal(32)
        with m.If(regs.SNAPSHOT):
            m.d.sync += snap_cycles.eq(cycles)
        m.d.comb += [
            regs.ID.eq(ID_VALUE),
            regs.INFO.eq(c.info),
            regs.CLK_HZ.eq(c.clk_hz),
            regs.NCO_PHASE.eq(nco.phase),
            regs.CYCLES.eq(snap_cycles),
            self.heartbeat.eq(cycles[c.heartbeat_bit]),
        ]

        # buttons
        pressed = {}
        if c.buttons:
            m.submodules.buttons = buttons = Buttons(len(c.buttons), c.debounce)
            m.d.comb += [buttons.raw.eq(self.buttons), regs.BUTTONS.eq(buttons.state)]
            pressed = {action: buttons.pressed[i] for i, action in enumerate(c.buttons)}
        none = Signal()      # constant 0 for the actions this board has no button for

        def press(action):
            return pressed.get(action, none)

        freq, amp = regs.NCO_FREQ, regs.NCO_AMP
        freq_top, amp_top = (1 << c.acc_bits) - 1, (1 << (c.width - 1)) - 1
        # each step one carry chain, its carry out the saturation test. The frequency's two
        # steps share one: f + f/8 + 1 (about +12.5 %) and f - f/8 - 1 = f + ~(f/8) are both
        # f + (f/8 xor ~up) + up, the carry in as (2f + up + 2 operand + up) / 2; up
        # overflows exactly when it carries out and down (f < f/8 + 1) exactly when it does
        # not, so a carry out equal to up saturates to all ones (up) or 0 (down). The
        # amplitude's likewise (a - step as a + 2**(width-1) - step, whose top bit says
        # a >= step).
        freq_up = press("freq_up")
        operand = Signal(c.acc_bits)
        stepped = Signal(c.acc_bits + 2)
        amp_up = Signal(c.width)
        amp_down = Signal(c.width)
        m.d.comb += [
            operand.eq((freq >> 3) ^ Mux(freq_up, 0, freq_top)),
            stepped.eq(Cat(freq_up, freq) + Cat(freq_up, operand)),
            amp_up.eq(amp + c.amp_step),
            amp_down.eq(amp + ((1 << (c.width - 1)) - c.amp_step)),
        ]
        m.d.comb += [
            regs.NCO_FREQ_set.eq(freq_up | press("freq_down")),
            regs.NCO_FREQ_value.eq(Mux(stepped[-1] == freq_up, Mux(freq_up, freq_top, 0),
                                       stepped[1:-1])),
            regs.NCO_AMP_set.eq(press("amp_up") | press("amp_down")),
            regs.NCO_AMP_value.eq(Mux(press("amp_up"),
                                      Mux(amp_up[-1], amp_top, amp_up[:-1]),
                                      Mux(amp_down[-1], amp_down[:-1], 0))),
            seq.enable_toggle.eq(press("enable")),
            seq.fault_clear.eq(press("fault_clear")),
        ]
        return m
