"""iCEBreaker (iCE40UP5K-SG48): the default board.

Clock: 12 MHz oscillator on pin 35 -> SB_PLL40_PAD -> 33 MHz system clock. The full generator
(max_bits 8, every mode), synthesised with the UP5K's DSP blocks; the demo fills most of the
part, and its Fmax over nextpnr seeds 1-5 and the logic cells used are in docs/boards.md's
table (``make report``). The build places with seed 1.
Pins: gates, fault and scope trigger on PMOD1A; UART through the FTDI (second channel);
LEDs: green = active, red = fault, break-off LED2 = heartbeat; buttons: the user button
(enable toggle) and the break-off PMOD's three buttons.
"""

from amaranth_boards.icebreaker import ICEBreakerPlatform

from boards.common import Board, Ice40Pll

BOARD = Board(
    name="icebreaker",
    title="iCEBreaker v1.0 (iCE40UP5K-SG48)",
    platform=ICEBreakerPlatform,
    clock="clk12",
    clock_hz=12e6,
    pll=Ice40Pll(divr=0, divf=87, divq=5, filter_range=1, pad=True),   # icepll -i 12 -o 33
    connector=("pmod", 0),                                               # PMOD1A
    connector_label="PMOD1A",
    gate_pins=(("1", "2", "3"), ("7", "8", "9")),
    fault_pin="4",
    trigger_pin="10",
    uart=("uart", 0),
    leds={"led_active": ("led_g", 0), "led_fault": ("led_r", 0), "heartbeat": ("led", 2)},
    buttons=((("button", 0), "enable"), (("button", 1), "freq_down"),
             (("button", 2), "fault_clear"), (("button", 3), "freq_up")),
    io_attrs={"IO_STANDARD": "SB_LVCMOS"},
    fault_attrs={"IO_STANDARD": "SB_LVCMOS", "PULLUP": 1},
    extra_resources=tuple(ICEBreakerPlatform.break_off_pmod),
    notes="The break-off PMOD (PMOD2) must be attached for the heartbeat LED and buttons 1-3.",
    nextpnr_opts="--seed 1",
    # the UP5K's configuration, as make perf counts the UP5K (SB_MAC16 blocks for any multiplier)
    synth_opts="-dsp",
    demo={"max_bits": 8},
)
