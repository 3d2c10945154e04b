"""iCE40-HX8K Breakout Board (iCE40HX8K-CT256).

Clock: 12 MHz oscillator on J3 -> SB_PLL40_CORE -> 72 MHz system clock (the demo with the
full generator, max_bits 8, reaches about 74 MHz on the HX8K).
Pins: gates, fault and scope trigger on header J2; UART through the FTDI's second channel;
LEDs D2 = active, D3 = fault, D9 = heartbeat. The board has no user buttons.
"""

from amaranth_boards.ice40_hx8k_b_evn import ICE40HX8KBEVNPlatform

from boards.common import Board, Ice40Pll

BOARD = Board(
    name="hx8k",
    title="iCE40-HX8K Breakout Board (iCE40HX8K-CT256)",
    platform=ICE40HX8KBEVNPlatform,
    clock="clk12",
    clock_hz=12e6,
    pll=Ice40Pll(divr=0, divf=47, divq=3, filter_range=1, pad=False),    # icepll -i 12 -o 72
    connector=("j", 2),                                                  # header J2
    connector_label="J2",
    gate_pins=(("9", "11", "13"), ("10", "12", "14")),
    fault_pin="17",
    trigger_pin="18",
    uart=("uart", 0),
    leds={"led_active": ("led", 0), "led_fault": ("led", 1), "heartbeat": ("led", 7)},
    io_attrs={"IO_STANDARD": "SB_LVCMOS"},
    fault_attrs={"IO_STANDARD": "SB_LVCMOS", "PULLUP": 1},
    demo={"max_bits": 8},
)
