"""ULX3S with an LFE5U-85F (CABGA381).

Clock: 25 MHz oscillator -> EHXPLLL -> 75 MHz system clock.
Pins: gates, fault and scope trigger on GPIO header J1 (GP0-GP3 / GN0-GN3); UART through
the FTDI (US1 port); LEDs D0 = active, D1 = fault, D7 = heartbeat; buttons: UP/DOWN frequency,
RIGHT/LEFT amplitude, FIRE1 enable toggle, FIRE2 fault clear.
"""

from amaranth_boards.ulx3s import ULX3S_85F_Platform

from boards.common import Board, Ecp5Pll

LVCMOS33 = {"IO_TYPE": "LVCMOS33", "DRIVE": "4"}

BOARD = Board(
    name="ulx3s",
    title="ULX3S (LFE5U-85F-6BG381C)",
    platform=ULX3S_85F_Platform,
    clock="clk25",
    clock_hz=25e6,
    pll=Ecp5Pll(clki_div=1, clkfb_div=3, clkop_div=8, clkop_cphase=4),   # ecppll -i 25 -o 75
    connector=("gpio", 0),
    connector_label="header",
    pin_labels={f"{i}{s}": f"{'GP' if s == '+' else 'GN'}{i}" for i in range(4)
                for s in "+-"},
    gate_pins=(("0+", "1+", "2+"), ("0-", "1-", "2-")),
    fault_pin="3+",
    trigger_pin="3-",
    uart=("uart", 0),
    leds={"led_active": ("led", 0), "led_fault": ("led", 1), "heartbeat": ("led", 7)},
    buttons=((("button_up", 0), "freq_up"), (("button_down", 0), "freq_down"),
             (("button_right", 0), "amp_up"), (("button_left", 0), "amp_down"),
             (("button_fire", 0), "enable"), (("button_fire", 1), "fault_clear")),
    io_attrs=LVCMOS33,
    fault_attrs={"IO_TYPE": "LVCMOS33", "PULLMODE": "UP"},
    demo={"max_bits": 8},
)
