"""The host side without hardware: the bridge protocol, the client's retries, the device API
and the CLI against the simulated device, and the simulated device's framing against the
gateware bridge's cycle model (so the device the host is tested on behaves like the chip)."""

import io
import random
from types import SimpleNamespace

import pytest

from mdfqm_host.cli import cmd_info, find_ports, main
from mdfqm_host.client import BusError, Client, NoReplyError
from mdfqm_host.device import TOP_MAP, Counters, DemoDevice, linear_limit
from mdfqm_host.simdevice import SimulatedDevice
from mdfqm_spec import bridge as proto
from mdfqm_spec.regmap import ID_VALUE, demo_window
from mdfqm_testkit.demo_models import BridgeModel

DEMO = demo_window(3, 16, 32)


class FakeClock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now

    def sleep(self, seconds):
        self.now += seconds


def device(**kwargs):
    clock = FakeClock()
    dev = SimulatedDevice(clock=clock, **kwargs)
    return dev, clock, Client(dev, sleep=clock.sleep)


# ------------------------------------------------------------------------------ protocol

def test_frames_sum_to_zero_and_round_trip():
    rng = random.Random(1)
    for _ in range(200):
        addr, data = rng.randrange(1 << 16), rng.getrandbits(32)
        for frame in (proto.encode_write(addr, data), proto.encode_read(addr),
                      proto.encode_reply(proto.CMD_READ, addr, data)):
            assert sum(frame) % 256 == 0
        assert len(proto.encode_write(addr, data)) == proto.request_length(proto.CMD_WRITE) == 8
        assert len(proto.encode_read(addr)) == proto.request_length(proto.CMD_READ) == 4
        reply = proto.decode_reply(proto.encode_reply(proto.CMD_READ, addr, data))
        assert (reply.status, reply.addr, reply.data, reply.ok) == (proto.CMD_READ, addr, data,
                                                                    True)
    assert proto.encode_read(0x0103) == bytes([0x52, 0x01, 0x03, (-0x56) & 0xFF])


@pytest.mark.parametrize(("frame", "message"), [
    (b"R\x00\x01", "reply of 3 bytes, expected 8: 52 00 01"),
    (b"R\x00\x01\x00\x00\x00\x00\x00", "reply checksum wrong: 52 00 01 00 00 00 00 00"),
    (b"X\x00\x00\x00\x00\x00\x00\xa8", "reply status 0x58 unknown: 58 00 00 00 00 00 00 a8"),
])
def test_decode_reply_rejects(frame, message):
    with pytest.raises(proto.ProtocolError) as info:
        proto.decode_reply(frame)
    assert str(info.value) == message


@pytest.mark.parametrize(("call", "message"), [
    (lambda: proto.encode_read(1 << 16), "addr must be an integer in [0, 0xffff], not 65536"),
    (lambda: proto.encode_write(0, -1), "data must be an integer in [0, 0xffffffff], not -1"),
    (lambda: proto.encode_write(True, 0), "addr must be an integer in [0, 0xffff], not True"),
])
def test_encode_rejects(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert str(info.value) == message


# ------------------------------------------------------------------------------ client

def test_client_reads_and_writes():
    _, _, client = device()
    assert client.read(DEMO.addr("ID")) == ID_VALUE
    client.write(DEMO.addr("NCO_FREQ"), 0x12345678)
    assert client.read(DEMO.addr("NCO_FREQ")) == 0x12345678
    assert client.stats == {"requests": 3, "retries": 0}


@pytest.mark.parametrize("injection", ["drop_reply", "corrupt_reply", "truncate_reply",
                                       "corrupt_request"])
def test_client_retries_a_damaged_exchange(injection):
    dev, clock, client = device()
    client.write(DEMO.addr("NCO_AMP"), 1234)
    dev.inject(injection)
    assert client.read(DEMO.addr("NCO_AMP")) == 1234
    assert client.stats["retries"] == 1
    assert clock.now >= 0.02           # it waited for the device to drop partial frames
    if injection == "corrupt_request":
        assert dev.log[-2][3] == proto.STATUS_BAD_CHECKSUM


def test_client_gives_up_after_its_retries():
    dev, _, client = device()
    for _ in range(4):
        dev.inject("drop_reply")
    with pytest.raises(NoReplyError):
        client.read(DEMO.addr("ID"))
    assert client.stats["retries"] == 3


def test_client_reports_unmapped_addresses():
    _, _, client = device()
    with pytest.raises(BusError) as info:
        client.read(0x8000)
    assert str(info.value) == "no register at address 0x8000"


def test_garbage_and_partial_frames_are_dropped():
    dev, clock, client = device()
    dev.write(b"\x00\xffhello")                  # no 'W'/'R': ignored
    assert client.read(DEMO.addr("ID")) == ID_VALUE
    dev.write(proto.encode_write(DEMO.addr("NCO_AMP"), 7)[:5])   # a write cut short...
    clock.sleep(0.01)                            # ...then silence: dropped
    assert client.read(DEMO.addr("NCO_AMP")) != 7
    assert client.stats["retries"] == 0


# ------------------------------------------------------------------------------ the device

def test_device_settings_in_physical_units():
    _, clock, client = device(clk_hz=24_000_000)
    demo = DemoDevice(client)
    assert demo.info.clk_hz == 24_000_000 and demo.info.top
    assert demo.map is TOP_MAP
    f = demo.set_frequency(50.0)
    assert abs(f - 50.0) < 24e6 / 2**32 and client.read(DEMO.addr("NCO_FREQ")) == 8948
    assert demo.set_amplitude(0.5) == 0.5 and client.read(DEMO.addr("NCO_AMP")) == 8192
    demo.enable(True)
    demo.set_zero_policy("fewest-transitions")
    status = demo.status()
    assert status.enabled and status.zero_policy == "fewest-transitions"
    assert (status.modulation, status.bits) == ("mdfqm", 0)       # the reset mode
    assert (demo.info.max_bits, demo.info.modes) == (8, 5)
    assert demo.set_modulation("svpwm", 3) == ("svpwm", 3)
    assert client.read(demo.map.modulation) == 1 | 3 << 8
    assert demo.set_modulation("dpwm1") == ("dpwm1", 8)           # b defaults to the largest
    status = demo.status()
    assert (status.modulation, status.bits, status.zero_policy) == ("dpwm1", 8,
                                                                     "fewest-transitions")
    demo.set_watchdog(12)
    assert demo.status().watchdog == 12 and demo.status().watchdog_trips == 0
    assert status.flags["active"] and not status.flags["fault"]
    assert demo.set_update_rate(100e3) == 100e3 and client.read(demo.map.period) == 240
    assert demo.set_dead_time(0) == client.read(demo.map.dead_min) * 1e9 / 24e6   # the floor
    demo.set_min_pulse(1000)
    assert client.read(demo.map.min_pulse) == 24
    demo.enable(False)
    assert not demo.status().enabled and demo.status().zero_policy == "fewest-transitions"
    first = demo.counters()
    demo.enable(True)
    clock.sleep(0.5)
    seconds, rates = demo.counters().rates(first, 24_000_000)
    assert seconds == pytest.approx(0.5) and all(r > 0 for r in rates)


@pytest.mark.parametrize(("call", "message"), [
    (lambda d: d.set_frequency(-1), "frequency must be in [0, 12000000) Hz, not -1"),
    (lambda d: d.set_amplitude(2.5), "amplitude must be in [0, 2) Vdc, not 2.5"),
    (lambda d: d.set_zero_policy("svpwm"),
     "zero policy must be one of ['all-off', 'fewest-transitions'], not 'svpwm'"),
    (lambda d: d.set_modulation("all-off"),
     "modulation must be one of ['mdfqm', 'svpwm', 'dpwm0', 'dpwm1', 'dpwm'] on this bitstream "
     "(max_bits 8), not 'all-off'"),
    (lambda d: d.set_modulation("svpwm", 9), "bits must be in [1, 8], not 9"),
    (lambda d: d.set_watchdog(70000), "watchdog must be in [0, 65535] update starts, not 70000"),
    (lambda d: d.set_dead_time(1e7), "dead time must be in [0, 2730625] ns at 24000000 Hz, "
                                     "not 10000000.0"),
    (lambda d: d.set_update_rate(100), "update rate 100 Hz needs PERIOD 240000, outside "
                                       "[1, 65535]"),
    (lambda d: d.set_osr(0), "osr must be in [1, 255], not 0"),
])
def test_device_rejects_bad_settings(call, message):
    _, _, client = device(clk_hz=24_000_000)
    with pytest.raises(ValueError) as info:
        call(DemoDevice(client))
    assert str(info.value) == message


def test_a_bitstream_without_the_watchdog_says_so():
    """INFO.WATCHDOG 0: info reads it, a timeout is refused (the gateware would store 0), and
    0 (off) is still accepted."""
    _, _, client = device(watchdog=False)
    demo = DemoDevice(client)
    assert not demo.info.watchdog and DemoDevice(device()[2]).info.watchdog
    with pytest.raises(ValueError, match=r"not built in this bitstream \(INFO\.WATCHDOG 0\)"):
        demo.set_watchdog(12)
    demo.set_watchdog(0)
    assert demo.status().watchdog == 0
    out = io.StringIO()
    cmd_info(demo, SimpleNamespace(port="sim://"), out)
    assert "  watchdog   not built in\n" in out.getvalue()


def test_counter_rates_wrap_modulo_2_32():
    early = Counters(cycles=0xFFFF_FF00, switches=(0xFFFF_FFFE, 10, 0))
    late = Counters(cycles=0x0000_0100 + 24_000_000 - 0x200, switches=(2, 10 + 2000, 0))
    seconds, rates = late.rates(early, 24_000_000)
    assert seconds == pytest.approx(1.0)
    assert rates == pytest.approx((2.0, 1000.0, 0.0))


def test_linear_limit():
    assert linear_limit(3) == pytest.approx(3 ** -0.5, rel=1e-4)
    assert linear_limit(4) == pytest.approx(0.5, rel=1e-4)


# ------------------------------------------------------------------------------ the CLI

def run_cli(capsys, *argv):
    code = main(["--port", "sim://", *argv])
    return code, capsys.readouterr().out


def test_cli_commands(capsys):
    code, out = run_cli(capsys, "info")
    assert code == 0 and "3 phases, 16-bit references" in out and "MdfqmTop" in out
    assert "modulation mdfqm; built in: mdfqm, svpwm, dpwm0, dpwm1, dpwm (max b 8)" in out
    assert "fault reactions built in: all off, ASC low, ASC high" in out
    assert "zero policy all-off" in out and "watchdog   off, 0 trips" in out
    code, out = run_cli(capsys, "set", "--freq", "60", "--amp", "0.4", "--modulation", "svpwm",
                        "--bits", "4", "--zero-policy", "all-off",
                        "--dead-time", "500", "--min-pulse", "0", "--update-rate", "90000",
                        "--osr", "2", "--watchdog", "40", "--clear-fault", "--enable")
    assert code == 0
    assert out.splitlines() == ["frequency 60.0019 Hz", "amplitude 0.4000 Vdc",
                                "modulation svpwm b = 4", "zero policy all-off",
                                "dead time 3556 ns", "minimum pulse 0 ns",
                                "update rate 90.000 kHz", "OSR 2", "watchdog 40",
                                "fault cleared", "enabled"]
    with pytest.raises(SystemExit, match="--mode is gone: the zero-state policy is "
                                         "--zero-policy"):
        main(["--port", "sim://", "set", "--mode", "all-off"])
    code, out = run_cli(capsys, "counters")
    assert code == 0 and out.startswith("cycles ") and "leg 2:" in out
    code, out = run_cli(capsys, "monitor", "--count", "2", "--interval", "0")
    assert code == 0 and len(out.splitlines()) == 3 and "f_sw leg 0" in out
    code, out = run_cli(capsys, "read", "ID")
    assert out == f"0x0100: {ID_VALUE:#010x}\n"
    code, out = run_cli(capsys, "write", "0x104", "0x1000")
    assert out == "0x0104 <- 0x00001000\n"
    assert main(["--port", "sim://", "read", "dead_min"]) == 0
    assert capsys.readouterr().out == "0x0002: 0x00000040\n"
    with pytest.raises(SystemExit):
        main(["--port", "sim://", "read", "NOPE"])


def test_cli_finds_the_demo_among_ports():
    ports = [SimpleNamespace(device="/dev/ttyS0", vid=None, pid=None, description="n/a"),
             SimpleNamespace(device="/dev/ttyUSB0", vid=0x0403, pid=0x6010, description="x"),
             SimpleNamespace(device="/dev/ttyUSB1", vid=0x0403, pid=0x6010, description="x")]

    class Silent(SimulatedDevice):
        def write(self, data):
            return len(data)

    opened = []

    def opener(name):
        opened.append(name)
        return SimulatedDevice() if name == "/dev/ttyUSB1" else Silent()

    found = find_ports(115200, 0.1, comports=lambda: ports, opener=opener)
    assert found[0] == ("/dev/ttyUSB1", "FTDI FT2232H", True)
    assert [f[2] for f in found] == [True, False, False]
    assert sorted(opened) == ["/dev/ttyUSB0", "/dev/ttyUSB1"]     # ttyS0 is never written


# ------------------------------------------------------- the simulated device vs the gateware

def bridge_replies(stream, frame_timeout_clocks, regs):
    """Replies of the bridge's cycle model to ``stream`` (bytes, or ``None`` for a silence of
    ``frame_timeout`` clocks), with a slave that holds the demo window's NCO_FREQ register."""
    model = BridgeModel(16, 64, frame_timeout_clocks)
    regs, out, pending = dict(regs), bytearray(), []
    for item in stream:
        pending += [None] * frame_timeout_clocks if item is None else list(item)
    ack_next = 0
    while pending or model.state != "RECEIVE":
        o = model.outputs()
        byte = pending[0] if pending else None
        valid = int(byte is not None)
        ack, dat_r = 0, 0
        if o["cyc"] and DEMO.base <= o["adr"] < DEMO.base + 32 and not ack_next:
            ack_next = 1
        elif ack_next:
            ack, ack_next = 1, 0
            if o["we"]:
                regs[o["adr"]] = o["dat_w"]
            dat_r = regs.get(o["adr"], 0)
        model.step(rx_valid=valid, rx_payload=byte or 0, tx_ready=1, ack=ack, dat_r=dat_r)
        if o["rx_ready"] and pending:
            pending.pop(0)
        if o["tx_valid"]:
            out.append(o["tx_payload"])
    return bytes(out)


def test_simulated_device_frames_like_the_bridge():
    rng = random.Random(7)
    freq = DEMO.addr("NCO_FREQ")
    stream = []
    for _ in range(300):
        kind = rng.random()
        addr = rng.choice([freq, freq, 0x0400, 0x7FFF])
        if kind < 0.3:
            stream.append(proto.encode_write(addr, rng.getrandbits(32)))
        elif kind < 0.6:
            stream.append(proto.encode_read(addr))
        elif kind < 0.75:
            bad = bytearray(proto.encode_write(addr, rng.getrandbits(32)))
            bad[rng.randrange(1, 8)] ^= 0x40
            stream.append(bytes(bad))
        elif kind < 0.85:
            stream.append(bytes(rng.choice([0x00, 0x41, 0x0D]) for _ in range(3)))
        else:
            stream += [proto.encode_write(addr, 1)[:rng.randint(1, 7)], None]
    dev, clock, _ = device()
    initial = {freq: dev.demo_regs["NCO_FREQ"]}
    for item in stream:
        if item is None:
            clock.sleep(dev.frame_timeout * 1.01)   # the silence a timeout needs
        else:
            dev.write(item)
    assert dev.read(1 << 20) == bridge_replies(stream, 40, initial)
