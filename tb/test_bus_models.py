# amaranth: UnusedElaboratable=no
"""Both tops driven by third-party bus masters, checked against the model and the register map.

The other top tests drive the bus with the project's own masters (tb/test_top.py) and check it
with the project's own model, so a misreading of the protocol shared by both would pass. Here
the bus is driven by the field's own models: ``cocotbext-axi``'s ``AxiLiteMaster`` (random
pauses on all five channels, so AW and W arrive apart, and ``bready`` / ``rready`` hold
responses back; reads and writes issued concurrently) and ``cocotbext-wishbone``'s
``WishboneMaster`` (several operations in one cycle, ``cyc`` held with ``stb`` low between them,
byte selects). Whatever those masters put on the pins, a shadow ``TopModel`` steps on the same
inputs every clock and every output of the top must equal it (pins, bus, irq; the first
difference fails the test at once). On top of that, checks that do not go through the model at
all, from the register map's documented contract:

- the value each master returns for each read is, in order, the model's read response (the
  master and the project agree on which clock carries the data);
- every mapped register reads its documented reset; unmapped words read 0 and (AXI) answer
  ``SLVERR``, mapped ones ``OKAY``; INFO and DEAD_MIN hold the instance's parameters;
- every read-write register reads back the clamp of the written word (``clamp`` in
  spec/rdl/mdfqm_top.rdl), masked to its fields, sign-extended for REF;
- the bus corner cases that make this test worth having did happen (counted, not assumed).
"""

import logging
import math
import random
import warnings
from typing import ClassVar

import cocotb
import pytest
from cocotb.triggers import ReadOnly, RisingEdge

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec import regmap as regs
from mdfqm_testkit.harness import pack, params, run_block, seeded_rng, start
from mdfqm_testkit.top_bench import COMMON_INPUTS, COMMON_OUTPUTS, make_model, port_name
from tools.regmap_gen import clamp_value

#: (phases, width, rule, dead_min, bus); the drop-in configuration and a five-phase one
CASES = [(3, 16, "largest_duty", 64, "wishbone"), (3, 16, "largest_duty", 64, "axi4lite"),
         (5, 12, "exact_nearest", 5, "wishbone"), (5, 12, "exact_nearest", 5, "axi4lite")]
#: the clocks of random operation once the top runs
RUN_CLOCKS = 6000
OKAY, SLVERR = 0b00, 0b10


# ------------------------------------------------------------------ the map's own contract


def registers_by_address(p):
    """{word address: (name, record)} of every word the instance maps (arrays to N words)."""
    mapped = {}
    for reg in regs.REGISTERS:
        for i in range(p["phases"] if reg.count > 1 else 1):
            mapped[reg.offset + i] = (reg.name, reg)
    return mapped


def map_parameters(p):
    """The RDL parameters of this instance (the clamp and reset expressions' names)."""
    model = make_model(p)
    return {**regs.PARAMETERS, "phases": p["phases"], "width": p["width"],
            "rule": int(p["rule"] == "exact_nearest"), "dead_min": p["dead_min"],
            "upper_active_low": False, "lower_active_low": False, "counter_width": 32,
            "latency": model.latency}


def software_owned(reg):
    """Registers only software or the elaboration sets: their reset is readable as documented
    (the status, counter and interrupt-status words move on their own from the first clock)."""
    return reg.name in ("ID", "INFO", "DEAD_MIN", "CMD") or (
        reg.access == "RW" and not any(f.onwrite for f in reg.fields))


def field_mask(reg):
    mask = 0
    for f in reg.fields:
        mask |= ((1 << f.width) - 1) << f.lsb
    return mask


def documented_reset(reg, parameters):
    """A register's reset word from its fields' reset (an int or a parameter's name)."""
    word = 0
    for f in reg.fields:
        value = f.reset if isinstance(f.reset, int) else int(parameters[f.reset])
        word |= (value & ((1 << f.width) - 1)) << f.lsb
    return word


def read_back(reg, word, parameters):
    """What a read returns after ``word`` was written to read-write register ``reg``: each
    field's clamp of the word (the written bits where a field has none)."""
    value = 0
    for f in reg.fields:
        stored = clamp_value(f.clamp, word, parameters, f.lsb) if f.clamp else word >> f.lsb
        value |= (stored & ((1 << f.width) - 1)) << f.lsb
    if reg.name == "REF" and value >> (parameters["width"] - 1):
        value |= 0xFFFFFFFF ^ ((1 << parameters["width"]) - 1)   # reads sign-extended
    return value


def interesting_words(rng, reg, parameters):
    """Both ends of the field, either side of every clamp bound, and random words."""
    top = field_mask(reg)
    words = {0, 1, top, top + 1 & 0xFFFFFFFF, 0xFFFFFFFF, 0x80000000, 0x7FFFFFFF}
    if reg.name == "REF":
        half = 1 << (parameters["width"] - 1)
        words |= {half - 1, half, -half & 0xFFFFFFFF, -half - 1 & 0xFFFFFFFF}
    if reg.name == "DEAD":
        d = parameters["dead_min"]
        words |= {d - 1, d, d + 1}
    if reg.name == "FAULT_REACTION":
        words |= set(range(16))         # every code of both fields
    words |= {rng.getrandbits(32) for _ in range(3)}
    return sorted(words)


# ------------------------------------------------------------------ the masters


class WishboneBus:
    """cocotbext-wishbone's WishboneMaster on the top's ``wb__*`` port."""

    SIGNALS: ClassVar[dict] = {"cyc": "cyc", "stb": "stb", "we": "we", "adr": "adr",
                               "datwr": "dat_w", "datrd": "dat_r", "ack": "ack", "sel": "sel"}

    def __init__(self, dut, rng):
        from cocotbext.wishbone.driver import WBOp, WishboneMaster

        self.op, self.rng = WBOp, rng
        self.master = WishboneMaster(dut, "wb_", dut.clk, width=32, timeout=1000,
                                     signals_dict=self.SIGNALS)

    def _ops(self, ops):
        return [self.op(adr=adr, dat=dat, idle=self.rng.choice([0, 0, 1, 3]),
                        sel=self.rng.choice([0xF, 0xF, 0x1, 0x0]))
                for adr, dat in ops]

    async def transact(self, ops):
        """``ops``: [(word address, value or None for a read)] in one Wishbone cycle (cyc held,
        stb dropped for a random idle between them). Returns the read data, in order."""
        results = await self.master.send_cycle(self._ops(ops))
        return [(int(r.datrd), OKAY) for r, (_, dat) in zip(results, ops, strict=True)
                if dat is None]

    async def write(self, adr, value):
        await self.transact([(adr, value)])
        return OKAY

    async def read(self, adr):
        (value,) = await self.transact([(adr, None)])
        return value


class AxiLiteBus:
    """cocotbext-axi's AxiLiteMaster on the top's ``s_axi__*`` port, random pauses on every
    channel (a paused B or R sink holds ``bready`` / ``rready`` low)."""

    def __init__(self, dut, rng):
        from cocotbext.axi import AxiLiteBus as Bus
        from cocotbext.axi import AxiLiteMaster

        self.rng = rng
        self.master = AxiLiteMaster(Bus.from_prefix(dut, "s_axi_"), dut.clk, dut.rst)
        self.master.write_if.log.setLevel(logging.WARNING)   # a line per transfer otherwise
        self.master.read_if.log.setLevel(logging.WARNING)
        for channel in (self.master.write_if.aw_channel, self.master.write_if.w_channel,
                        self.master.write_if.b_channel, self.master.read_if.ar_channel,
                        self.master.read_if.r_channel):
            channel.set_pause_generator(self._pauses(random.Random(rng.getrandbits(32))))

    @staticmethod
    def _pauses(rng):
        while True:
            yield rng.random() < 0.4

    async def write(self, adr, value):
        response = await self.master.write(4 * adr, value.to_bytes(4, "little"))
        return int(response.resp)

    async def read(self, adr):
        response = await self.master.read(4 * adr, 4)
        return int.from_bytes(response.data, "little"), int(response.resp)


# ------------------------------------------------------------------ the shadow model


class Shadow:
    """Steps a TopModel on whatever the DUT's inputs are, every clock, and compares every
    output; records the model's read responses (and AXI write responses) in order, and counts
    the bus corner cases seen."""

    def __init__(self, dut, p):
        self.dut, self.model = dut, make_model(p)
        front = self.model.front
        self.bus_inputs = {k: getattr(dut, port_name(k)) for k in front.INPUTS}
        self.common = {k: getattr(dut, k) for k in COMMON_INPUTS}
        self.outputs = {key: getattr(dut, port) for port, key in
                        {**{port_name(k): k for k in front.OUTPUTS}, **COMMON_OUTPUTS}.items()}
        self.wishbone = "wb_cyc" in front.INPUTS
        self.reads, self.writes, self.cycles = [], [], 0
        self.seen = dict.fromkeys(
            ("cyc_without_stb", "sel_partial", "acked_reads", "acked_writes") if self.wishbone
            else ("aw_before_w", "w_before_aw", "b_held", "r_held", "read_and_write_together",
                  "acked_reads", "acked_writes"), 0)
        for _ in range(2):          # the reset clocks of harness.start
            self.model.step(rst=1)

    def _count(self, bus, out):
        s = self.seen
        if self.wishbone:
            s["cyc_without_stb"] += bus["wb_cyc"] and not bus["wb_stb"]
            s["sel_partial"] += bus["wb_cyc"] and bus["wb_stb"] and bus["wb_sel"] != 0xF
            s["acked_reads"] += out["wb_ack"] and not bus["wb_we"]
            s["acked_writes"] += out["wb_ack"] and bus["wb_we"]
            return
        s["aw_before_w"] += bus["s_axi_awvalid"] and not bus["s_axi_wvalid"]
        s["w_before_aw"] += bus["s_axi_wvalid"] and not bus["s_axi_awvalid"]
        s["b_held"] += out["s_axi_bvalid"] and not bus["s_axi_bready"]
        s["r_held"] += out["s_axi_rvalid"] and not bus["s_axi_rready"]
        s["read_and_write_together"] += bus["s_axi_arvalid"] and bus["s_axi_awvalid"]
        s["acked_reads"] += out["s_axi_rvalid"] and bus["s_axi_rready"]
        s["acked_writes"] += out["s_axi_bvalid"] and bus["s_axi_bready"]

    async def run(self):
        width = self.model.width
        while True:
            await ReadOnly()
            bus = {k: int(h.value) for k, h in self.bus_inputs.items()}
            common = {k: int(h.value) for k, h in self.common.items()}
            ref = [(common["ref__payload"] >> (i * width)) & ((1 << width) - 1)
                   for i in range(self.model.phases)]
            ref = [r - (1 << width) if r >> (width - 1) else r for r in ref]
            out = self.model.step(rst=common["rst"], ref_valid=common["ref__valid"], ref=ref,
                                  fault_in=common["fault_in"], sync_in=common["sync_in"], **bus)
            got = {k: int(h.value) for k, h in self.outputs.items()}
            if got != {k: out[k] for k in got}:   # fails the test at once (a started task)
                diff = {k: (got[k], out[k]) for k in got if got[k] != out[k]}
                raise AssertionError(f"clock {self.cycles}: RTL differs from the model, "
                                     f"(rtl, model) {diff}; inputs {bus} {common}")
            if not common["rst"]:
                self._count(bus, out)
                if self.wishbone and out["wb_ack"]:
                    (self.writes if bus["wb_we"] else self.reads).append((out["wb_dat_r"], OKAY))
                if not self.wishbone and out["s_axi_rvalid"] and bus["s_axi_rready"]:
                    self.reads.append((out["s_axi_rdata"], out["s_axi_rresp"]))
                if not self.wishbone and out["s_axi_bvalid"] and bus["s_axi_bready"]:
                    self.writes.append(out["s_axi_bresp"])
            self.cycles += 1
            await RisingEdge(self.dut.clk)


async def stream_source(dut, p, rng):
    """An FOC-like reference stream on ``ref__*``: a beat held until taken, random idles."""
    n, width = p["phases"], p["width"]
    full = 1 << (width - 2)
    dut.ref__valid.value = 0
    angle = rng.uniform(0, 6.3)
    while True:
        await RisingEdge(dut.clk)
        if int(dut.ref__valid.value) and not int(dut.ref__ready.value):
            continue            # ready is sampled before the edge's updates: held
        if rng.random() < 0.5:
            dut.ref__valid.value = 0
            continue
        angle += 0.03
        beat = [round(0.5 * full * math.cos(angle - 2 * math.pi * i / n))
                for i in range(n)]
        dut.ref__payload.value = pack(beat, width)
        dut.ref__valid.value = 1


# ------------------------------------------------------------------ the test


@cocotb.test(timeout_time=2, timeout_unit="ms")   # a lost response hangs a master
async def bus_models(dut):
    # warnings are errors here too, but for cocotbext-axi 0.1.28's own uses of calls cocotb 2.1
    # deprecates (setimmediatevalue, Task.kill, Event.data): the library's, not this design's
    warnings.simplefilter("error")
    warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotbext\.axi")
    p = params()
    rng = seeded_rng(dut, "bus_models")
    parameters = map_parameters(p)
    mapped = registers_by_address(p)
    dut.fault_in.value = 0
    dut.sync_in.value = 0
    dut.ref__valid.value = 0
    dut.ref__payload.value = 0
    bus = (WishboneBus if p["bus"] == "wishbone" else AxiLiteBus)(dut, rng)
    await start(dut)
    shadow = Shadow(dut, p)
    cocotb.start_soon(shadow.run())
    returned_reads, returned_writes = [], []

    async def read(adr):
        value, resp = await bus.read(adr)
        returned_reads.append((value, resp))
        return value, resp

    async def write(adr, value):
        resp = await bus.write(adr, value)
        returned_writes.append(resp)
        return resp

    # every word after reset: documented reset or 0, OKAY or SLVERR
    for adr in range(1 << regs.ADDR_WIDTH):
        value, resp = await read(adr)
        if adr in mapped and not software_owned(mapped[adr][1]):
            continue
        if adr in mapped:
            name, reg = mapped[adr]
            want = (regs.ID_VALUE if name == "ID" else documented_reset(reg, parameters))
            assert (value, resp) == (want, OKAY), \
                f"{name} @ {adr:#x} reads {value:#x} resp {resp} after reset, want {want:#x}"
        else:
            assert (value, resp) == (0, OKAY if p["bus"] == "wishbone" else SLVERR), \
                f"unmapped word {adr:#x} reads {value:#x} resp {resp}"

    # every read-write register reads back the clamp of what was written
    for adr, (name, reg) in sorted(mapped.items()):
        if not (software_owned(reg) and reg.access == "RW") or name == "CTRL" or \
                any(f.in_force for f in reg.fields):
            continue        # (CTRL: the enable would start switching; MODULATION: test_top)
        for word in interesting_words(rng, reg, parameters):
            assert await write(adr, word) == OKAY
            value, _ = await read(adr)
            want = read_back(reg, word, parameters)
            assert value == want, f"{name} @ {adr:#x}: wrote {word:#x}, read {value:#x}, " \
                                  f"the map's clamp gives {want:#x}"

    # running: the stream on, interrupts on, random reads and writes, a fault and its clear
    latency = parameters["latency"]
    for adr, value in ((regs.PERIOD, latency + rng.randrange(3 * latency)), (regs.OSR, 1),
                       (regs.DEAD, parameters["dead_min"]), (regs.MIN_PULSE, 2),
                       (regs.IRQ_ENABLE, regs.IRQ_ENABLE_MASK),
                       (regs.CMD, regs.CMD_FAULT_CLEAR | regs.CMD_COUNT_CLEAR),
                       (regs.CTRL, regs.CTRL_ENABLE)):
        await write(adr, value)
    cocotb.start_soon(stream_source(dut, p, rng))
    readable = sorted(mapped)
    stop = shadow.cycles + RUN_CLOCKS

    async def reader():
        while shadow.cycles < stop:
            if isinstance(bus, WishboneBus) and rng.random() < 0.3:
                ops = [(rng.choice(readable), None) for _ in range(rng.randint(2, 4))]
                returned_reads.extend(await bus.transact(ops))
            else:
                await read(rng.choice(readable))

    async def writer():
        while shadow.cycles < stop:
            choice = rng.random()
            if choice < 0.3:
                value, _ = await read(regs.IRQ_STATUS)
                await write(regs.IRQ_STATUS, value)
            elif choice < 0.4:
                dut.fault_in.value = 1
                for _ in range(rng.randint(1, 4)):
                    await RisingEdge(dut.clk)
                dut.fault_in.value = 0
                await write(regs.CMD, regs.CMD_FAULT_CLEAR)
            elif choice < 0.5:
                await write(regs.CMD, regs.CMD_COUNT_CLEAR)
            else:
                base = regs.REF_BASE + rng.randrange(p["phases"])
                await write(base, rng.getrandbits(32))
                if rng.random() < 0.5:
                    await write(regs.CMD, regs.CMD_REF_COMMIT)

    if isinstance(bus, WishboneBus):
        # one master, one operation at a time: the two interleave at operation boundaries
        while shadow.cycles < stop:
            await (reader() if rng.random() < 0.5 else writer())
    else:
        done_reader = cocotb.start_soon(reader())
        await writer()
        await done_reader
    for _ in range(4):
        await RisingEdge(dut.clk)

    if returned_reads != shadow.reads:
        first = next((i for i, pair in enumerate(zip(returned_reads, shadow.reads, strict=False))
                      if pair[0] != pair[1]), min(len(returned_reads), len(shadow.reads)))
        raise AssertionError(
            f"{len(returned_reads)} reads returned by the master, {len(shadow.reads)} answered "
            f"in the model; first difference at read {first}")
    if not shadow.wishbone:
        assert returned_writes == shadow.writes, "write responses differ from the model's"
    dut._log.info("bus_models: %d clocks, %d reads, %d writes, corner cases %s",
                  shadow.cycles, len(returned_reads), len(returned_writes), shadow.seen)
    missing = [k for k, v in shadow.seen.items() if v == 0]
    assert not missing, f"bus corner cases never exercised: {missing}"


@pytest.mark.parametrize(("phases", "width", "rule", "dead_min", "bus"), CASES)
def test_bus_models(phases, width, rule, dead_min, bus):
    run_block(lambda: MdfqmTop(phases, width, rule, dead_min, bus=bus), "mdfqm_top_bus_models",
              "test_bus_models", {"phases": phases, "width": width, "rule": rule,
                                  "dead_min": dead_min, "bus": bus, "upper_active_low": False,
                                  "lower_active_low": False, "counter_width": 32})
