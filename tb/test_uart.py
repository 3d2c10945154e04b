# amaranth: UnusedElaboratable=no
"""UART receiver and transmitter, every output on every clock, against
tb/mdfqm_testkit/demo_models.py."""

import cocotb
import pytest
from amaranth import Module
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out, connect

from demo.uart import UartRx, UartTx, uart_divider
from mdfqm_testkit.demo_models import UartRxModel, UartTxModel
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

#: edge cases, and the smallest and largest of the boards' dividers at 115200 baud (16.5 MHz:
#: 143, 36 MHz: 313, 48 MHz: 417, 50 MHz: 434); the counters differ only in width
DIVIDERS = [4, 5, 16, 143, 434]


class UartPair(wiring.Component):
    """Test wrapper: an independent transmitter and receiver in one toplevel."""

    def __init__(self, divider):
        self.divider = divider
        super().__init__({
            "tx_i": In(stream.Signature(8)), "tx": Out(1), "tx_busy": Out(1),
            "rx": In(1, init=1), "rx_o": Out(stream.Signature(8)),
            "overrun": Out(1), "frame_error": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        m.submodules.utx = utx = UartTx(self.divider)
        m.submodules.urx = urx = UartRx(self.divider)
        connect(m, wiring.flipped(self.tx_i), utx.i)
        connect(m, urx.o, wiring.flipped(self.rx_o))
        m.d.comb += [self.tx.eq(utx.tx), self.tx_busy.eq(utx.busy), urx.rx.eq(self.rx),
                     self.overrun.eq(urx.overrun), self.frame_error.eq(urx.frame_error)]
        return m


def skewed_frame(byte, divider, skew, stop=1):
    """One frame whose bits last ``divider * (1 + skew)`` clocks (rounded at bit edges)."""
    bits = [0] + [(byte >> i) & 1 for i in range(8)] + [stop]
    edges = [round(k * divider * (1 + skew)) for k in range(11)]
    return [bits[k] for k in range(10) for _ in range(edges[k + 1] - edges[k])]


def rx_line(rng, divider, frames, stress):
    """Line levels and the bytes of the good frames sent on it."""
    line, sent = [1] * rng.randint(0, 3 * divider), []
    for _ in range(frames):
        byte = rng.randrange(256)
        skew = rng.uniform(-0.03, 0.03) if stress else rng.uniform(-0.02, 0.02)
        kind = rng.random() if stress else 1.0
        if kind < 0.1:                      # low stop bit: frame error
            line += skewed_frame(byte, divider, skew, stop=0) + [0] * rng.randint(0, divider)
        elif kind < 0.2:                    # a glitch shorter than half a bit
            line += [0] * rng.randint(1, max(1, divider // 2 - 2))
        elif kind < 0.25:                   # a break: low for many bit times
            line += [0] * (20 * divider)
        else:
            line += skewed_frame(byte, divider, skew)
            sent.append(byte)
        line += [1] * rng.choice([0, 0, 1, rng.randint(1, 3 * divider)])
    return line + [1] * (3 * divider), sent


def decode_line(levels, divider):
    """Bytes of the 8N1 frames on a per-clock line (sampled mid-bit); for the end-to-end check."""
    out, c = [], 0
    while c < len(levels):
        if levels[c] == 0:
            mid = c + divider // 2
            picks = [mid + k * divider for k in range(10)]
            samples = [levels[i] for i in picks if i < len(levels)]
            if len(samples) < 10:
                break
            assert samples[0] == 0 and samples[9] == 1, f"bad frame on tx at cycle {c}"
            out.append(sum(b << i for i, b in enumerate(samples[1:9])))
            c = mid + 9 * divider
        else:
            c += 1
    return out


def generate(rng, divider, frames, stress):
    """Closed-loop stimulus with the models in the loop; returns (stimulus, expected outputs,
    bytes sent on rx, bytes the model received, bytes offered to tx)."""
    line, sent = rx_line(rng, divider, frames, stress)
    to_send = [rng.randrange(256) for _ in range(frames)]
    cycles = max(len(line), 10 * divider * (frames + 1) * (3 if stress else 2))
    line += [1] * (cycles - len(line))
    rx, tx = UartRxModel(divider), UartTxModel(divider)
    stim = {name: [] for name in ("tx_i__valid", "tx_i__payload", "rx", "rx_o__ready")}
    expected = {name: [] for name in ("tx_i__ready", "tx", "tx_busy", "rx_o__valid",
                                      "rx_o__payload", "overrun", "frame_error")}
    queue, offered, gap, ready, received = list(to_send), None, 0, 1, []
    for cycle in range(cycles):
        if offered is None and queue and gap == 0:
            offered = queue.pop(0)
        gap = max(0, gap - 1)
        if stress and cycle % 700 == 0:
            ready = int(rng.random() < 0.6)
        valid = int(offered is not None)
        t = tx.step(valid=valid, payload=offered if valid else 0)
        r = rx.step(rx=line[cycle], ready=ready)
        stim["tx_i__valid"].append(valid)
        stim["tx_i__payload"].append(offered if valid else rng.randrange(256))
        stim["rx"].append(line[cycle])
        stim["rx_o__ready"].append(ready)
        expected["tx_i__ready"].append(t["ready"])
        expected["tx"].append(t["tx"])
        expected["tx_busy"].append(t["busy"])
        expected["rx_o__valid"].append(r["valid"])
        expected["rx_o__payload"].append(r["payload"] if r["valid"] else None)
        expected["overrun"].append(r["overrun"])
        expected["frame_error"].append(r["frame_error"])
        if valid and t["ready"]:
            offered = None
            gap = rng.choice([0, 0, 0, rng.randint(1, 5 * divider)])
        if r["valid"] and ready:
            received.append(r["payload"])
    return stim, expected, sent, received, to_send


async def run(dut, name, frames, stress):
    divider = params()["divider"]
    rng = seeded_rng(dut, name)
    stim, expected, sent, received, to_send = generate(rng, divider, frames, stress)
    if not stress:   # the model itself must recover every byte of a clean line, and send all
        assert received == sent, "model: clean frames not all received"
        assert decode_line(expected["tx"], divider) == to_send, "model: tx line wrong"
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("%s: %d cycles, %d frames received, every output equal to the model",
                  name, checked, len(received))


@cocotb.test()
async def uart_clean(dut):
    """Back-to-back and gapped frames, +-2 % baud error, no back-pressure: every byte arrives."""
    await run(dut, "uart_clean", params()["frames"], stress=False)


@cocotb.test()
async def uart_stress(dut):
    """+-3 % baud error, glitches, frame errors, breaks, receiver back-pressure (overruns)."""
    await run(dut, "uart_stress", params()["frames"] * 5 // 3, stress=True)


@pytest.mark.parametrize("divider", DIVIDERS)
def test_uart(divider):
    frames = 24 if divider <= 16 else 3           # long bits: fewer frames, same paths
    run_block(lambda: UartPair(divider), "uart_pair", "test_uart",
              {"divider": divider, "frames": frames})


@pytest.mark.parametrize(("cls", "divider", "message"), [
    (UartTx, 3, "divider must be an integer in [4, 65536], not 3"),
    (UartRx, 65537, "divider must be an integer in [4, 65536], not 65537"),
    (UartRx, 10.0, "divider must be an integer in [4, 65536], not 10.0"),
])
def test_uart_rejects_bad_divider(cls, divider, message):
    with pytest.raises(ValueError) as info:
        cls(divider)
    assert str(info.value) == message


def test_uart_divider():
    assert uart_divider(12e6, 115200) == 104
    assert uart_divider(25_000_000, 115200) == 217
    assert uart_divider(48e6, 1_000_000) == 48


@pytest.mark.parametrize(("clk_hz", "baud", "message"), [
    (0, 115200, "clk_hz must be a positive number, not 0"),
    (12e6, -1, "baud must be a positive number, not -1"),
    (12e6, 4e6, "baud 4000000.0 needs 3.00 clocks per bit at 12000000.0 Hz; "
                "the divider must be in [4, 65536]"),
    (1e6, 230400, "baud 230400 is 8.5 % off at 1000000.0 Hz (divider 4); at most 2 % is allowed"),
])
def test_uart_divider_rejects(clk_hz, baud, message):
    with pytest.raises(ValueError) as info:
        uart_divider(clk_hz, baud)
    assert str(info.value) == message
