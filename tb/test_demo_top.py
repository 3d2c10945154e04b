# amaranth: UnusedElaboratable=no
"""The whole board demo (DemoDesign) driven through its UART, on each board's configuration:
bytes in -> bridge -> registers -> NCO -> drop-in top -> gate pins, every pin on every clock against
tb/mdfqm_testkit/demo_models.py: DemoModel; the replies are checked against the protocol and the
register maps, the switching counters against the top's own counters.

Each board's configuration is used as built (clock, NCO, buttons, dead-time floor, the
settings written after reset) except two timings that would make the simulation long: the UART
runs at 8 clocks per bit (the boards' dividers are tested in tb/test_uart.py) and buttons are
sampled every 40 clocks instead of every 10 ms.
"""

import sys
from collections import deque
from pathlib import Path

import cocotb
import pytest

from demo.design import DemoConfig, DemoDesign
from mdfqm_spec import bridge as proto
from mdfqm_spec import regmap as top_map
from mdfqm_spec.regmap import ID_VALUE, TOP_BASE, demo_window
from mdfqm_testkit.demo_models import DemoModel, line_bits
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
import boards  # noqa: E402

PINS = ("uart_tx", "upper", "lower", "led_active", "led_fault", "heartbeat", "trigger")
SIM_DIVIDER = 8
SIM_DEBOUNCE = 40


def sim_config(board_name: str) -> DemoConfig:
    board = boards.get(board_name)
    return board.config(baud=board.sys_clk_hz / SIM_DIVIDER, debounce=SIM_DEBOUNCE)


class LineDecoder:
    """Bytes of the 8N1 frames on a per-clock line (mid-bit sampling)."""

    def __init__(self, divider):
        self.divider, self.prev, self.bits, self.count = divider, 1, None, 0

    def feed(self, level):
        byte = None
        if self.bits is None:
            if self.prev and not level:
                self.bits, self.count = [], 0
        else:
            self.count += 1
            if self.count >= self.divider // 2 and \
                    (self.count - self.divider // 2) % self.divider == 0:
                self.bits.append(level)
                if len(self.bits) == 10:
                    assert self.bits[0] == 0 and self.bits[9] == 1, "bad frame from the device"
                    byte = sum(b << i for i, b in enumerate(self.bits[1:9]))
                    self.bits = None
        self.prev = level
        return byte


def host_script(config, rng):
    """The host's side, as a generator: yields ``("request", frame)`` (receives the reply),
    ``("idle", clocks)``, ``("fault", level)``, ``("buttons", mask)``."""
    demo = demo_window(config.phases, config.width, config.acc_bits)
    n = config.phases

    def read(addr):
        reply = yield ("request", proto.encode_read(addr))
        assert (reply.status, reply.addr) == (proto.CMD_READ, addr), reply
        return reply.data

    def write(addr, data):
        reply = yield ("request", proto.encode_write(addr, data))
        assert (reply.status, reply.addr, reply.data) == (proto.CMD_WRITE, addr, data), reply

    top = {name: TOP_BASE + getattr(top_map, name) for name in
           ("ID", "CTRL", "CMD", "STATUS", "PERIOD", "DEAD", "MIN_PULSE", "EVENTS_BASE",
            "MODULATION")}

    # identification, and the settings the sequencer wrote after reset
    assert (yield from read(demo.addr("ID"))) == ID_VALUE
    assert (yield from read(demo.addr("INFO"))) == config.info
    assert (yield from read(demo.addr("CLK_HZ"))) == config.clk_hz
    assert (yield from read(top["ID"])) == top_map.ID_VALUE
    for addr, value in config.top_init:
        assert (yield from read(addr)) == value
    assert (yield from read(demo.addr("NCO_FREQ"))) == config.demo_init["NCO_FREQ"]

    # fast settings so that a few thousand clocks show many updates and a fraction of a period
    yield from write(top["PERIOD"], 24)
    yield from write(top["DEAD"], 0)                        # raised to the floor
    assert (yield from read(top["DEAD"])) == config.dead_min
    yield from write(demo.addr("NCO_FREQ"), (1 << config.acc_bits) // 30000)
    yield from write(demo.addr("NCO_AMP"), config.contract.full // 2)
    yield from write(top["CTRL"], top_map.CTRL_ENABLE | rng.choice([0, top_map.CTRL_ZERO_POLICY]))
    yield ("idle", 4000)
    status = yield from read(top["STATUS"])
    assert status & top_map.STATUS_ACTIVE and not status & top_map.STATUS_FAULT

    # telemetry as the host reads it: the clock counter's snapshot, then the top's switching
    # counters (every read's data is the model's: the bridge's reply is checked on the pin)
    yield from write(demo.addr("SNAPSHOT"), 1)
    cycles = yield from read(demo.addr("CYCLES"))
    events = []
    for i in range(n):
        events.append((yield from read(top["EVENTS_BASE"] + i)))
    assert cycles > 4000 and min(events) > 30, (cycles, events)

    # fault: the pin, the latch, the clear
    yield ("fault", 1)
    yield ("idle", 30)
    yield ("fault", 0)
    status = yield from read(top["STATUS"])
    assert status & top_map.STATUS_FAULT and not status & top_map.STATUS_ACTIVE
    yield from write(top["CMD"], top_map.CMD_FAULT_CLEAR)
    yield ("idle", 200)
    status = yield from read(top["STATUS"])
    assert status & top_map.STATUS_ACTIVE and not status & top_map.STATUS_FAULT

    # the modulation mode changed while running: SVPWM b = 3, DPWM b = 2, back to MDFQM (every
    # pin still checked against the model); a board with the MDFQM-only top clamps and flags it
    for mode, bits in ((1, 3), (4, 2), (0, 0)):
        word = mode << top_map.MODULATION_MODE_SHIFT | bits << top_map.MODULATION_BITS_SHIFT
        yield from write(top["MODULATION"], word)
        yield ("idle", 600)
        in_force = yield from read(top["MODULATION"])
        status = yield from read(top["STATUS"])
        assert in_force == (word if config.max_bits else 0), (mode, bits, in_force)
        assert bool(status & top_map.STATUS_MODE_CLAMPED) == (mode != 0 and not config.max_bits)
        assert status & top_map.STATUS_ACTIVE

    # line errors: a bad checksum and an unmapped address
    bad = bytearray(proto.encode_write(top["CTRL"], 0))
    bad[-1] ^= 0x5A
    reply = yield ("request", bytes(bad))
    assert reply.status == proto.STATUS_BAD_CHECKSUM
    reply = yield ("request", proto.encode_read(0x4000))
    assert reply.status == proto.STATUS_BUS_TIMEOUT
    assert (yield from read(top["CTRL"])) & top_map.CTRL_ENABLE      # nothing was written

    # buttons: press each one (held for several samples), then read what it changed
    def press(i):
        yield ("buttons", 1 << i)
        yield ("idle", 4 * SIM_DEBOUNCE)
        yield ("buttons", 0)
        yield ("idle", 3 * SIM_DEBOUNCE)

    freq, amp = (1 << config.acc_bits) // 30000, config.contract.full // 2
    ctrl = yield from read(top["CTRL"])
    for i, action in enumerate(config.buttons):
        if action == "fault_clear":
            yield ("fault", 1)
            yield ("idle", 10)
            yield ("fault", 0)
        yield from press(i)
        if action in ("freq_up", "freq_down"):
            freq = freq + (freq >> 3) + 1 if action == "freq_up" else freq - (freq >> 3) - 1
            assert (yield from read(demo.addr("NCO_FREQ"))) == freq, action
        elif action in ("amp_up", "amp_down"):
            amp += config.amp_step if action == "amp_up" else -config.amp_step
            assert (yield from read(demo.addr("NCO_AMP"))) == amp, action
        elif action == "enable":
            ctrl ^= top_map.CTRL_ENABLE
            assert (yield from read(top["CTRL"])) == ctrl, action
        else:
            assert not (yield from read(top["STATUS"])) & top_map.STATUS_FAULT, action

    # the frequency and amplitude steps stop at their limits: the top going up, 0 going down
    limits = {"freq_up": ("NCO_FREQ", (1 << config.acc_bits) - 1), "freq_down": ("NCO_FREQ", 0),
              "amp_up": ("NCO_AMP", (1 << (config.width - 1)) - 1), "amp_down": ("NCO_AMP", 0)}
    for i, action in enumerate(config.buttons):
        if action in limits:
            name, limit = limits[action]
            yield from write(demo.addr(name), limit)
            yield from press(i)
            assert (yield from read(demo.addr(name))) == limit, action
    yield ("idle", 300)


def generate(config, rng):
    """Run the host script with the model in the loop; returns (stimulus, expected pins,
    number of requests)."""
    model = DemoModel(config)
    inputs = ["uart_rx", "fault_in"] + (["buttons"] if config.buttons else [])
    stim = {name: [] for name in inputs}
    expected = {pin: [] for pin in PINS}
    script = host_script(config, rng)
    decoder = LineDecoder(config.divider)
    line, fault, buttons, idle, reply, waiting = deque(), 0, 0, 0, bytearray(), False
    send, requests = None, 0
    while True:
        if not waiting and idle == 0 and not line:
            try:
                command = script.send(send)
            except StopIteration:
                break
            send = None
            kind, arg = command
            if kind == "request":
                line.extend([1] * 3)
                for byte in arg:
                    line.extend(line_bits(byte, config.divider))
                waiting, requests = True, requests + 1
            elif kind == "idle":
                idle = arg
            elif kind == "fault":
                fault = arg
            elif kind == "buttons":
                buttons = arg
            continue
        rx = line.popleft() if line else 1
        pins = model.step(uart_rx=rx, buttons=buttons, fault_in=fault)
        stim["uart_rx"].append(rx)
        stim["fault_in"].append(fault)
        if config.buttons:
            stim["buttons"].append(buttons)
        for pin in PINS:
            expected[pin].append(pins[pin])
        idle = max(0, idle - 1)
        byte = decoder.feed(pins["uart_tx"])
        if byte is not None:
            assert waiting, "the device sent a byte nobody asked for"
            reply.append(byte)
            if len(reply) == proto.REPLY_LENGTH:
                send, waiting = proto.decode_reply(bytes(reply)), False
                reply.clear()
        if len(expected["uart_tx"]) > 400_000:
            raise AssertionError("the host script does not finish (a reply is missing)")
    return stim, expected, requests


@cocotb.test()
async def demo_through_uart(dut):
    """Identification, settings, enable, counters, fault and clear, line errors, buttons."""
    config = sim_config(params()["board"])
    rng = seeded_rng(dut, "demo_through_uart")
    stim, expected, requests = generate(config, rng)
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("demo_through_uart on %s: %d requests, %d cycles, every pin equal to the "
                  "model", params()["board"], requests, checked)


@pytest.mark.parametrize("board", sorted(boards.BOARDS))
def test_demo_top(board):
    run_block(lambda: DemoDesign(sim_config(board)), "demo_design", "test_demo_top",
              {"board": board})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"clk_hz": 999_999}, "clk_hz must be an integer >= 1000000, not 999999"),
    ({"buttons": ("reboot",)}, "buttons: 'reboot' is not one of ('enable', 'fault_clear', "
                               "'freq_up', 'freq_down', 'amp_up', 'amp_down')"),
    ({"buttons": ("enable", "enable")},
     "buttons must not repeat an action: ('enable', 'enable')"),
    ({"phases": 9}, "phases must be an integer in [3, 8], not 9"),
    ({"freq_hz": -1}, "freq_hz must be a number in [0, clk_hz / 2), not -1"),
    ({"amplitude": 2}, "amplitude must be a number of Vdc in [0, 2), not 2"),
    ({"debounce": 0}, "debounce must be an integer in [1, 16777216], not 0"),
    ({"bus_timeout": 1}, "bus_timeout must be an integer in [2, 65536], not 1"),
])
def test_demo_config_rejects_bad_parameters(kwargs, message):
    args = {"clk_hz": 18_000_000, **kwargs}
    with pytest.raises(ValueError) as info:
        DemoConfig(**args)
    assert str(info.value) == message


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"count": 0, "debounce": 10}, "count must be an integer in [1, 8], not 0"),
    ({"count": 9, "debounce": 10}, "count must be an integer in [1, 8], not 9"),
    ({"count": 2, "debounce": 0}, "debounce must be an integer in [1, 16777216], not 0"),
])
def test_buttons_reject_bad_parameters(kwargs, message):
    from demo.buttons import Buttons

    with pytest.raises(ValueError) as info:
        Buttons(**kwargs)
    assert str(info.value) == message


def test_demo_design_rejects_a_bad_config():
    with pytest.raises(ValueError) as info:
        DemoDesign({"clk_hz": 1})
    assert str(info.value) == "config must be a DemoConfig, not {'clk_hz': 1}"


def test_model_runs_the_script():
    """The model and the script alone, on the default board (a few seconds): a disagreement
    between them shows here before a simulator is built."""
    import random
    _, expected, requests = generate(sim_config(boards.DEFAULT), random.Random(1))
    assert requests > 20 and len(expected["upper"]) > 10_000
