"""iCEBreaker (iCE40UP5K-SG48): the default board.

Clock: 12 MHz oscillator on pin 35 -> SB_PLL40_PAD -> 27 MHz system clock (the demo reaches
26.5-28.9 MHz on the UP5K over nextpnr seeds 1-4, measured 2026-11-27 with YoWASP nextpnr-ice40:
seed 1 28.93, seed 2 27.85, seed 3 28.08, seed 4 26.47 MHz, so the build places with seed 1;
its critical path is the bridge's register read through the top's read multiplexer). The
MDFQM-only top: the full generator does not fit beside the demo.
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
    pll=Ice40Pll(divr=0, divf=71, divq=5, filter_range=1, pad=True),   # icepll -i 12 -o 27
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
    # the demo fills 80 % of the UP5K and meets 27 MHz only with some placements (above)
    nextpnr_opts="--seed 1",
)
