"""OrangeCrab r0.2 with an LFE5U-25F (CSFBGA285).

Clock: 48 MHz oscillator -> EHXPLLL -> 80 MHz system clock. The board has no UART bridge: use a
3.3 V USB-UART adapter on the Feather pins 0 (FPGA RX) and 1 (FPGA TX). Pins: gates on Feather
pins 5, 6, 9 (upper) and 10, 11, 12 (lower), fault on 13, scope trigger on A0; RGB LED:
green = active, red = fault, blue = heartbeat; the user button toggles enable.
"""

from amaranth.build import Attrs
from amaranth_boards.orangecrab_r0_2 import OrangeCrabR0_2_25FPlatform
from amaranth_boards.resources import UARTResource

from boards.common import Board, Ecp5Pll

BOARD = Board(
    name="orangecrab",
    title="OrangeCrab r0.2 (LFE5U-25F-8MG285C)",
    platform=OrangeCrabR0_2_25FPlatform,
    clock="clk",
    clock_hz=48e6,
    pll=Ecp5Pll(clki_div=3, clkfb_div=5, clkop_div=7, clkop_cphase=3),   # ecppll -i 48 -o 80
    connector=("io", 0),                                                 # Feather header
    connector_label="Feather",
    pin_labels={"a0": "pin A0"},
    gate_pins=(("5", "6", "9"), ("10", "11", "12")),
    fault_pin="13",
    trigger_pin="a0",
    uart=("uart", 0),
    leds={"led_active": ("rgb_led", 0, "g"), "led_fault": ("rgb_led", 0, "r"),
          "heartbeat": ("rgb_led", 0, "b")},
    buttons=((("button", 0), "enable"),),
    io_attrs={"IO_TYPE": "LVCMOS33"},
    fault_attrs={"IO_TYPE": "LVCMOS33", "PULLMODE": "UP"},
    extra_resources=(UARTResource(0, rx="0", tx="1", conn=("io", 0),
                                  attrs=Attrs(IO_TYPE="LVCMOS33", PULLMODE="UP")),),
    demo={"max_bits": 8},
)
