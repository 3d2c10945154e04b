# amaranth: UnusedElaboratable=no
"""UART -> Wishbone bridge on its byte streams, every output on every clock, against
tb/mdfqm_testkit/demo_models.py: BridgeModel, with a Wishbone slave with random wait states and
an unmapped range, and a host that follows (and breaks) mdfqm_spec.bridge."""

import cocotb
import pytest
from amaranth import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out, connect

from demo.arbiter import WishboneArbiter
from demo.bridge import UartBridge
from demo.bus_master import BusSequencer
from demo.register_bank import RegisterBank
from demo.wishbone import WishboneDecoder, WishboneSignature
from mdfqm_spec import bridge as proto
from mdfqm_spec.regmap import DEMO
from mdfqm_testkit.demo_models import ArbiterModel, BridgeModel, SequencerModel
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

CASES = [(16, 5, 40), (16, 64, 300), (8, 3, 25)]
OUTPUTS = {"rx__ready": "rx_ready", "tx__valid": "tx_valid", "tx__payload": "tx_payload",
           "bus__cyc": "cyc", "bus__stb": "stb", "bus__we": "we", "bus__adr": "adr",
           "bus__dat_w": "dat_w", "bus__sel": "sel", "checksum_error": "checksum_error",
           "bus_timeout_error": "bus_timeout_error"}
MAPPED_BELOW = 0x60    # the test slave answers word addresses below this (after aliasing)


class Slave:
    """Wishbone-classic slave: ``ack`` after 0..3 wait states (fewer than the bridge's timeout)
    for mapped addresses, never for the others; ``dat_r`` is random except in the ``ack``
    clock. A cycle whose ``cyc`` drops is abandoned, except an answer decided in the clock
    before, which still comes (as a registered slave's ``ack`` does)."""

    def __init__(self, rng, bus_timeout):
        self.rng, self.mem, self.wait, self.taken = rng, {}, None, None
        self.waits = [0, 0, 1, min(3, bus_timeout - 1)]   # always inside the bridge's timeout

    def respond(self, out):
        """``(ack, dat_r)`` for this clock, given the master's outputs of this clock."""
        requested = out["cyc"] and out["stb"] and out["adr"] < MAPPED_BELOW
        if self.wait is None and requested:
            self.wait, self.taken = self.rng.choice(self.waits), dict(out)
        elif self.wait != 0 and not requested:
            self.wait = None
        if self.wait is None:
            return 0, self.rng.getrandbits(32)
        if self.wait:
            self.wait -= 1
            return 0, self.rng.getrandbits(32)
        self.wait, out = None, self.taken
        if out["we"]:
            self.mem[out["adr"]] = out["dat_w"]
            return 1, self.rng.getrandbits(32)
        return 1, self.mem.get(out["adr"], 0)


def requests(rng, count, addr_mask):
    """(bytes to send, what the reply must be, silence after) per request."""
    mem, plan = {}, []
    for _ in range(count):
        kind = rng.random()
        addr = rng.choice([rng.randrange(MAPPED_BELOW)] * 3 + [rng.randrange(1 << 16)])
        word = addr & addr_mask
        mapped = word < MAPPED_BELOW
        if kind < 0.35:
            data = rng.getrandbits(32)
            frame = proto.encode_write(addr, data)
            if mapped:
                mem[word] = data
            want = (proto.CMD_WRITE, addr, data) if mapped else (proto.STATUS_BUS_TIMEOUT, addr, 0)
        elif kind < 0.7:
            frame = proto.encode_read(addr)
            want = ((proto.CMD_READ, addr, mem.get(word, 0)) if mapped
                    else (proto.STATUS_BUS_TIMEOUT, addr, 0))
        elif kind < 0.8:                                   # corrupted checksum
            good = bytearray(rng.choice([proto.encode_write(addr, rng.getrandbits(32)),
                                         proto.encode_read(addr)]))
            good[-1] ^= 1 << rng.randrange(8)
            frame = bytes(good)
            data = int.from_bytes(frame[3:7], "big") if frame[0] == proto.CMD_WRITE else 0
            want = (proto.STATUS_BAD_CHECKSUM, addr, data)
        elif kind < 0.9:                                   # garbage, then a good read
            garbage = bytes(rng.choice([0, 0x41, 0xFF, 0x0D]) for _ in range(rng.randint(1, 4)))
            frame = garbage + proto.encode_read(addr)
            want = ((proto.CMD_READ, addr, mem.get(word, 0)) if mapped
                    else (proto.STATUS_BUS_TIMEOUT, addr, 0))
        else:                                              # truncated frame: no reply, silence
            full = proto.encode_write(addr, rng.getrandbits(32))
            frame = full[:rng.randint(1, len(full) - 1)]
            want = None
        plan.append((frame, want))
    return plan


def generate(rng, count, addr_width, bus_timeout, frame_timeout):
    model = BridgeModel(addr_width, bus_timeout, frame_timeout)
    slave = Slave(rng, bus_timeout)
    plan = requests(rng, count, (1 << addr_width) - 1)
    stim = {"rx__valid": [], "rx__payload": [], "tx__ready": [], "bus__ack": [],
            "bus__dat_r": []}
    expected = {port: [] for port in OUTPUTS}
    replies, got = [], bytearray()
    pending, waiting, silence, gap = b"", None, 0, 0
    item = 0
    while item < len(plan) or pending or waiting is not None or silence:
        if not pending and waiting is None and not silence and item < len(plan):
            pending, want = plan[item]
            item += 1
            waiting = want if want is not None else None
            silence = frame_timeout + 2 if want is None else 0
        out = model.outputs()
        valid = int(bool(pending) and gap == 0)
        payload = pending[0] if valid else rng.randrange(256)
        tx_ready = int(rng.random() < 0.7)
        ack, dat_r = slave.respond(out)
        model.step(rx_valid=valid, rx_payload=payload, tx_ready=tx_ready, ack=ack, dat_r=dat_r)
        for name, value in (("rx__valid", valid), ("rx__payload", payload),
                            ("tx__ready", tx_ready), ("bus__ack", ack), ("bus__dat_r", dat_r)):
            stim[name].append(value)
        for port, key in OUTPUTS.items():
            expected[port].append(out[key])
        if valid and out["rx_ready"]:
            pending = pending[1:]
            gap = rng.choice([0, 0, 0, 1, 4])
        else:
            gap = max(0, gap - 1)
        if not pending and waiting is None and silence:
            silence -= 1
        if out["tx_valid"] and tx_ready:
            got.append(out["tx_payload"])
            if len(got) == proto.REPLY_LENGTH:
                reply = proto.decode_reply(bytes(got))
                assert (reply.status, reply.addr, reply.data) == waiting, \
                    f"model reply {reply} for request {plan[item - 1][0].hex(' ')}, " \
                    f"protocol says {waiting}"
                replies.append(reply)
                got.clear()
                waiting = None
    return stim, expected, replies


async def run(dut, name, count):
    p = params()
    rng = seeded_rng(dut, name)
    stim, expected, replies = generate(rng, count, p["addr_width"], p["bus_timeout"],
                                       p["frame_timeout"])
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    kinds = {chr(s): sum(r.status == s for r in replies) for s in proto.STATUSES}
    dut._log.info("%s: %d cycles, replies %s, every output equal to the model", name, checked,
                  kinds)


@cocotb.test()
async def bridge_requests(dut):
    """Reads, writes, bad checksums, garbage, truncated frames, unmapped addresses."""
    await run(dut, "bridge_requests", 160)


@pytest.mark.parametrize(("addr_width", "bus_timeout", "frame_timeout"), CASES)
def test_bridge(addr_width, bus_timeout, frame_timeout):
    run_block(lambda: UartBridge(addr_width, bus_timeout, frame_timeout), "uart_bridge",
              "test_bridge", {"block": "bridge", "addr_width": addr_width,
                              "bus_timeout": bus_timeout, "frame_timeout": frame_timeout},
              testcase="bridge_requests")


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"addr_width": 17}, "addr_width must be an integer in [1, 16], not 17"),
    ({"bus_timeout": 0}, "bus_timeout must be an integer in [1, 65536], not 0"),
    ({"frame_timeout": 1}, "frame_timeout must be an integer in [2, 16777216], not 1"),
])
def test_bridge_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        UartBridge(**kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(("make", "message"), [
    (lambda: WishboneSignature(31), "addr_width must be an integer in [1, 30], not 31"),
    (lambda: WishboneArbiter(0), "addr_width must be an integer in [1, 30], not 0"),
    (lambda: WishboneDecoder(16, {}),
     "windows must be a non-empty dict of name -> (base, width), not {}"),
    (lambda: WishboneDecoder(16, {"bus": (0, 4)}),
     "windows: name 'bus' must be an identifier other than 'bus'"),
    (lambda: WishboneDecoder(16, {"a": (0x08, 4)}),
     "windows['a'] base must be a multiple of 0x10 inside the 16-bit address space, not 8"),
    (lambda: WishboneDecoder(8, {"a": (0, 9)}),
     "windows['a'] width must be an integer in [1, 8], not 9"),
    (lambda: WishboneDecoder(16, {"a": (0, 6), "b": (0x20, 4)}),
     "windows['b'] at 0x0020 (16 words) overlaps windows['a'] at 0x0000"),
    (lambda: RegisterBank(DEMO, init={"ID": 1}), "'ID' is not an RW register of the demo window"),
    (lambda: RegisterBank(DEMO, settable=("NOPE",)),
     "'NOPE' is not an RW register of the demo window"),
    (lambda: RegisterBank(DEMO, init={"NCO_AMP": 1 << 15}),
     "init['NCO_AMP'] must fit in 15 bits, not 32768"),
    (lambda: BusSequencer(16, [(0x10000, 0)], 3, 1, 4, 2),
     "init[0] addr must be an integer in [0, 65535], not 65536"),
    (lambda: BusSequencer(16, [(1, -1)], 3, 1, 4, 2),
     "init[0] data must be an integer in [0, 4294967295], not -1"),
    (lambda: BusSequencer(16, [1], 3, 1, 4, 2), "init[0] must be an (addr, data) tuple, not 1"),
    (lambda: BusSequencer(8, [], 256, 1, 4, 2),
     "ctrl_addr must be an integer in [0, 255], not 256"),
    (lambda: BusSequencer(8, [], 3, 1 << 32, 4, 2),
     "enable_mask must be an integer in [0, 4294967295], not 4294967296"),
    (lambda: BusSequencer(8, [], 3, 1, 4, 2, ctrl_width=33),
     "ctrl_width must be an integer in [1, 32], not 33"),
    (lambda: BusSequencer(8, [], 3, 0b100, 4, 2, ctrl_width=2),
     "enable_mask 0x4 must fit in ctrl_width = 2 bits"),
])
def test_bus_blocks_reject_bad_parameters(make, message):
    with pytest.raises(ValueError) as info:
        make()
    assert str(info.value) == message


# ------------------------------------------------------------------ arbiter + bus sequencer

SEQ_INIT = ((0x06, 240), (0x08, 9), (0x09, 0))
SEQ_ARGS = (0x03, 0b1, 0x04, 0b10, 2)     # CTRL, ENABLE, CMD, FAULT_CLEAR, the bits CTRL holds


class BusPair(wiring.Component):
    """Test wrapper: an external master (``m0``) and a BusSequencer share one bus."""

    def __init__(self):
        super().__init__({"m0": In(WishboneSignature(16)), "bus": Out(WishboneSignature(16)),
                          "enable_toggle": In(1), "fault_clear": In(1), "busy": Out(1),
                          "owner": Out(1)})

    def elaborate(self, platform):
        m = Module()
        m.submodules.seq = seq = BusSequencer(16, SEQ_INIT, *SEQ_ARGS)
        m.submodules.arbiter = arbiter = WishboneArbiter(16)
        connect(m, wiring.flipped(self.m0), arbiter.m0)
        connect(m, seq.bus, arbiter.m1)
        connect(m, arbiter.bus, wiring.flipped(self.bus))
        m.d.comb += [seq.enable_toggle.eq(self.enable_toggle), seq.fault_clear.eq(self.fault_clear),
                     self.busy.eq(seq.busy), self.owner.eq(arbiter.owner)]
        return m


def generate_bus_pair(rng, cycles):
    """A random external master, button pulses and a slave with wait states, all reacting to
    the models; the slave's registers must end up as the sequencer's writes say."""
    seq, arb = SequencerModel(SEQ_INIT, *SEQ_ARGS), ArbiterModel()
    slave = Slave(rng, 5)
    m0 = {"cyc": 0, "we": 0, "adr": 0, "dat_w": 0}
    names = ("m0__cyc", "m0__stb", "m0__we", "m0__adr", "m0__dat_w", "m0__sel", "bus__ack",
             "bus__dat_r", "enable_toggle", "fault_clear")
    outs = ("m0__ack", "m0__dat_r", "bus__cyc", "bus__stb", "bus__we", "bus__adr", "bus__dat_w",
            "bus__sel", "busy", "owner")
    stim, expected = {n: [] for n in names}, {n: [] for n in outs}
    toggles = clears = late_answers = 0
    for _ in range(cycles):
        so, owner, bus = seq.outputs(), arb.owner, arb.outputs()
        master0 = {**m0, "stb": m0["cyc"], "sel": 0xF}
        ack, dat_r = slave.respond({**bus, "adr": bus["adr"] % MAPPED_BELOW})
        toggle = int(rng.random() < 0.01)
        clear = int(rng.random() < 0.01)
        toggles, clears = toggles + toggle, clears + clear
        m0_ack = ack and not owner
        # an answer to a request its master gave up, while the other master waits for the bus
        late_answers += int(bool(ack and not m0["cyc"] and not owner and so["cyc"]))
        row = {"m0__cyc": m0["cyc"], "m0__stb": m0["cyc"], "m0__we": m0["we"],
               "m0__adr": m0["adr"], "m0__dat_w": m0["dat_w"], "m0__sel": 0xF,
               "bus__ack": ack, "bus__dat_r": dat_r, "enable_toggle": toggle,
               "fault_clear": clear}
        for name, value in row.items():
            stim[name].append(value)
        got = {"m0__ack": int(m0_ack), "m0__dat_r": dat_r, "bus__cyc": bus["cyc"],
               "bus__stb": bus["stb"], "bus__we": bus["we"], "bus__adr": bus["adr"],
               "bus__dat_w": bus["dat_w"], "bus__sel": bus["sel"], "busy": so["busy"],
               "owner": owner}
        for name in outs:
            expected[name].append(got[name])
        seq.step(ack=ack and owner, dat_r=dat_r, enable_toggle=toggle, fault_clear=clear)
        arb.step(master0, so, ack)
        # the external master: its cycle ends with the ack, or it gives up waiting
        if m0["cyc"] and (m0_ack or rng.random() < 0.2):
            m0 = {"cyc": 0, "we": 0, "adr": 0, "dat_w": 0}
        elif not m0["cyc"] and rng.random() < 0.3:
            m0 = {"cyc": 1, "we": rng.randint(0, 1), "adr": rng.choice([0x03, 0x04, 0x10]),
                  "dat_w": rng.getrandbits(32)}
    return stim, expected, slave, {"toggles": toggles, "clears": clears,
                                   "late answers": late_answers}


@cocotb.test()
async def arbiter_and_sequencer(dut):
    """Initial writes, enable toggles (read-modify-write) and fault clears from random button
    pulses, while another master keeps the bus busy and at times gives up waiting (an answer
    to its abandoned request must not reach the sequencer waiting for the bus)."""
    rng = seeded_rng(dut, "arbiter_and_sequencer")
    stim, expected, _, seen = generate_bus_pair(rng, 6000)
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("arbiter_and_sequencer: %d cycles, %s, every output equal to the models",
                  checked, seen)
    missed = [name for name, count in seen.items() if not count]
    assert not missed, f"never happened in this run: {missed}"


def test_arbiter_and_sequencer():
    run_block(BusPair, "bus_pair", "test_bridge", {"block": "bus_pair"},
              testcase="arbiter_and_sequencer")


def test_sequencer_model_writes_its_init_then_serves_the_buttons():
    import random
    stim, expected, _, seen = generate_bus_pair(random.Random(3), 6000)
    toggles, clears = seen["toggles"], seen["clears"]
    done = [(expected["bus__we"][c], expected["bus__adr"][c], expected["bus__dat_w"][c],
             stim["bus__dat_r"][c])
            for c in range(6000) if expected["owner"][c] and stim["bus__ack"][c]]
    assert [(a, d) for _, a, d, _ in done[:3]] == list(SEQ_INIT)
    rest = done[3:]
    reads = [i for i, (we, a, _, _) in enumerate(rest) if not we and a == SEQ_ARGS[0]]
    held = (1 << SEQ_ARGS[4]) - 1
    # every read of CTRL is followed by its write with ENABLE flipped (unless the run ends first)
    for i in (i for i in reads if i + 1 < len(rest)):
        assert rest[i + 1][:3] == (1, SEQ_ARGS[0], (rest[i][3] & held) ^ SEQ_ARGS[1])
    assert len(reads) >= 1 and sum(1 for we, a, d, _ in rest
                                   if we and (a, d) == SEQ_ARGS[2:4]) >= 1
    assert toggles >= len(reads) and clears >= 1
