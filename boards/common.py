"""What the board tops share: PLL primitives, the power-on reset, and the glue that puts
:class:`demo.design.DemoDesign` between a board's resources.

A board folder (``boards/<board>/top.py``) declares only its pins, its clocking and its
button/LED choices as a :class:`Board`; :class:`DemoTop` does the rest.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from amaranth import ClockDomain, ClockSignal, Elaboratable, Instance, Module, Signal
from amaranth.build import Attrs, Pins, PinsN, Resource, Subsignal
from amaranth.lib import io
from amaranth.lib.cdc import ResetSynchronizer

from demo.design import DemoConfig, DemoDesign

__all__ = ["Board", "DemoTop", "Ecp5Pll", "Ice40Pll", "demo_resources"]


@dataclass(frozen=True)
class Ice40Pll:
    """SB_PLL40_{PAD,CORE} in SIMPLE feedback: ``f_out = f_in (divf + 1) / ((divr + 1) 2**divq)``
    (the values ``icepll -i <f_in> -o <f_out>`` prints)."""

    divr: int
    divf: int
    divq: int
    filter_range: int
    pad: bool = True          # SB_PLL40_PAD (clock pin is the PLL's pad) or SB_PLL40_CORE

    def out_hz(self, in_hz: float) -> float:
        return in_hz * (self.divf + 1) / ((self.divr + 1) * (1 << self.divq))

    def check(self, in_hz: float) -> None:
        pfd = in_hz / (self.divr + 1)
        vco = pfd * (self.divf + 1)
        if not (10e6 <= pfd <= 133e6 and 533e6 <= vco <= 1066e6):
            raise ValueError(f"iCE40 PLL out of range: PFD {pfd / 1e6} MHz, VCO {vco / 1e6} MHz")

    def instance(self, clk_in, clk_out, locked) -> Instance:
        kind = "SB_PLL40_PAD" if self.pad else "SB_PLL40_CORE"
        return Instance(
            kind,
            p_FEEDBACK_PATH="SIMPLE",
            p_DIVR=self.divr, p_DIVF=self.divf, p_DIVQ=self.divq,
            p_FILTER_RANGE=self.filter_range,
            **({"i_PACKAGEPIN": clk_in} if self.pad else {"i_REFERENCECLK": clk_in}),
            i_RESETB=1, i_BYPASS=0,
            o_PLLOUTGLOBAL=clk_out, o_LOCK=locked,
        )


@dataclass(frozen=True)
class Ecp5Pll:
    """EHXPLLL with CLKOP feedback: ``f_out = f_in clkfb_div / clki_div``,
    ``f_vco = f_out clkop_div`` (the values ``ecppll -i <f_in> -o <f_out>`` prints)."""

    clki_div: int
    clkfb_div: int
    clkop_div: int
    clkop_cphase: int

    def out_hz(self, in_hz: float) -> float:
        return in_hz * self.clkfb_div / self.clki_div

    def check(self, in_hz: float) -> None:
        vco = self.out_hz(in_hz) * self.clkop_div
        if not 400e6 <= vco <= 800e6:
            raise ValueError(f"ECP5 PLL out of range: VCO {vco / 1e6} MHz")

    def instance(self, clk_in, clk_out, locked) -> Instance:
        return Instance(
            "EHXPLLL",
            a_ICP_CURRENT="12", a_LPF_RESISTOR="8", a_MFG_ENABLE_FILTEROPAMP="1",
            a_MFG_GMCREF_SEL="2",
            p_PLLRST_ENA="DISABLED", p_INTFB_WAKE="DISABLED", p_STDBY_ENABLE="DISABLED",
            p_DPHASE_SOURCE="DISABLED", p_OUTDIVIDER_MUXA="DIVA", p_CLKOP_ENABLE="ENABLED",
            p_CLKI_DIV=self.clki_div, p_CLKOP_DIV=self.clkop_div,
            p_CLKOP_CPHASE=self.clkop_cphase, p_CLKOP_FPHASE=0,
            p_FEEDBK_PATH="CLKOP", p_CLKFB_DIV=self.clkfb_div,
            i_RST=0, i_STDBY=0, i_CLKI=clk_in, i_CLKFB=clk_out, i_PHASESEL0=0, i_PHASESEL1=0,
            i_PHASEDIR=1, i_PHASESTEP=1, i_PHASELOADREG=1, i_PLLWAKESYNC=0, i_ENCLKOP=0,
            o_CLKOP=clk_out, o_LOCK=locked,
        )


@dataclass(frozen=True)
class Board:
    """One board: its amaranth-boards platform, clocking and the demo's pins.

    ``clock`` is the platform's clock resource; ``pll`` (or None) makes the system clock;
    ``gates``/``fault``/``trigger`` are added as resources (:func:`demo_resources`) on
    ``connector`` pins; ``uart`` is ``(resource, number)``; ``leds`` maps the demo's
    ``led_active``/``led_fault``/``heartbeat`` to ``(resource, number[, subsignal])``;
    ``buttons`` is a
    list of ``((resource, number), action)``.
    """

    name: str
    title: str
    platform: type
    clock: str
    clock_hz: float
    pll: object
    connector: tuple
    gate_pins: tuple            # (upper pins, lower pins) on the connector, leg order
    fault_pin: str
    trigger_pin: str
    uart: tuple
    leds: dict
    buttons: tuple = ()
    io_attrs: dict = field(default_factory=dict)
    fault_attrs: dict = field(default_factory=dict)
    extra_resources: tuple = ()
    connector_label: str = ""   # the connector's name on the board's silkscreen
    pin_labels: dict = field(default_factory=dict)   # connector pin -> silkscreen name
    por_us: float = 20.0        # reset held after PLL lock (iCE40 BRAM needs > 3 us)
    nextpnr_opts: str = ""
    synth_opts: str = ""        # options of Yosys's synth_<family> (the UP5K's "-dsp")
    demo: dict = field(default_factory=dict)      # DemoConfig overrides
    notes: str = ""

    @property
    def sys_clk_hz(self) -> int:
        if self.pll is None:
            return round(self.clock_hz)
        self.pll.check(self.clock_hz)
        return round(self.pll.out_hz(self.clock_hz))

    def config(self, **overrides) -> DemoConfig:
        """The demo's configuration on this board (``overrides`` for simulation)."""
        args = {"clk_hz": self.sys_clk_hz, "buttons": tuple(a for _, a in self.buttons),
                **self.demo, **overrides}
        return DemoConfig(**args)

    def pin_label(self, pin: str) -> str:
        """How the board's silkscreen names connector pin ``pin``."""
        label = self.connector_label or f"{self.connector[0]}{self.connector[1]}"
        return f"{label} {self.pin_labels.get(pin, 'pin ' + pin)}"

    def make_platform(self):
        platform = self.platform()
        platform.add_resources(demo_resources(self))
        platform.add_resources(list(self.extra_resources))
        return platform


def demo_resources(board: Board) -> list:
    """The gate, fault and trigger pins of the demo on ``board.connector``."""
    upper, lower = board.gate_pins
    conn = board.connector
    return [
        Resource("gates", 0,
                 Subsignal("upper", Pins(" ".join(upper), dir="o", conn=conn)),
                 Subsignal("lower", Pins(" ".join(lower), dir="o", conn=conn)),
                 Attrs(**board.io_attrs)),
        # active-low fault input (open-drain driver FAULT# with the FPGA's pull-up)
        Resource("fault_n", 0, PinsN(board.fault_pin, dir="i", conn=conn),
                 Attrs(**board.fault_attrs)),
        Resource("trigger", 0, Pins(board.trigger_pin, dir="o", conn=conn),
                 Attrs(**board.io_attrs)),
    ]


class DemoTop(Elaboratable):
    """Clock, reset and pins around :class:`DemoDesign` for one :class:`Board`.

    Reset: the system domain is held in reset until the PLL locks and then for ``por_us``
    (a synchronous reset, released through a :class:`ResetSynchronizer`).
    """

    def __init__(self, board: Board, **overrides):
        self.board = board
        self.config = board.config(**overrides)
        self.design = DemoDesign(self.config)

    def elaborate(self, platform):
        b = self.board
        m = Module()
        m.submodules.demo = demo = self.design

        # ---- clock and reset
        m.domains.sync = ClockDomain("sync")
        m.domains.por = ClockDomain("por", reset_less=True, local=True)
        locked = Signal()
        if b.pll is None:
            m.submodules.clk_buf = clk = io.Buffer("i", platform.request(b.clock, dir="-"))
            m.d.comb += [ClockSignal("sync").eq(clk.i), locked.eq(1)]
        else:
            clk = platform.request(b.clock, dir="-")
            pll_out = Signal()
            m.submodules.pll = b.pll.instance(clk.io, pll_out, locked)
            # nextpnr derives the PLL output's constraint from the input clock's
            m.d.comb += ClockSignal("sync").eq(pll_out)
        m.d.comb += ClockSignal("por").eq(ClockSignal("sync"))
        delay = max(1, round(b.por_us * 1e-6 * b.sys_clk_hz))
        timer = Signal(range(delay + 1))
        with m.If(~locked):
            m.d.por += timer.eq(0)
        with m.Elif(timer != delay):
            m.d.por += timer.eq(timer + 1)
        m.submodules.reset_sync = ResetSynchronizer(timer != delay, domain="sync")

        # ---- pins (every resource through an explicit I/O buffer)
        requested = {}

        def buffer(direction, name, number, *path):
            if (name, number) not in requested:
                requested[name, number] = platform.request(name, number, dir="-")
            port = requested[name, number]
            for attr in path:
                port = getattr(port, attr)
            buf = io.Buffer(direction, port)
            m.submodules["_".join(["pin", name, str(number), *path])] = buf
            return buf

        uart_name, uart_number = b.uart
        m.d.comb += [
            demo.uart_rx.eq(buffer("i", uart_name, uart_number, "rx").i),
            buffer("o", uart_name, uart_number, "tx").o.eq(demo.uart_tx),
            buffer("o", "gates", 0, "upper").o.eq(demo.upper),
            buffer("o", "gates", 0, "lower").o.eq(demo.lower),
            demo.fault_in.eq(buffer("i", "fault_n", 0).i),       # PinsN: active high here
            buffer("o", "trigger", 0).o.eq(demo.trigger),
        ]
        for port, (name, number, *sub) in b.leds.items():
            m.d.comb += buffer("o", name, number, *sub).o.eq(getattr(demo, port))
        for i, ((name, number), _) in enumerate(b.buttons):
            m.d.comb += demo.buttons[i].eq(buffer("i", name, number).i)
        return m
