"""Top model: the Wishbone register file (timing, clamps, map), the reference arbitration, the
switching counters, the ADC trigger and sync_out; and the register table of docs/top.md."""

import re
from pathlib import Path

import numpy as np
import pytest

from mdfqm_model.driver import check_gate_safety
from mdfqm_model.top import TopModel
from mdfqm_spec import regmap as regs
from mdfqm_spec.regmap import REGISTERS

DOCS = Path(__file__).resolve().parents[2] / "docs" / "top.md"


class Master:
    """A Wishbone classic master on a TopModel: request until ack, then one idle cycle."""

    def __init__(self, model, **held):
        self.m, self.held, self.log = model, held, []
        self.up, self.lo = [], []          # active-high gates visible in each cycle

    def tick(self, **kw):
        self.up.append(self.m.driver.up)
        self.lo.append(self.m.driver.lo)
        out = self.m.step(**{**self.held, **kw})
        self.log.append(out)
        return out

    def access(self, address, we, value=0):
        bus = {"wb_cyc": 1, "wb_stb": 1, "wb_we": we, "wb_adr": address, "wb_dat_w": value}
        first = self.tick(**bus)
        assert first["wb_ack"] == 0
        out = self.tick(**bus)              # held through the ack cycle: not a second request
        assert out["wb_ack"] == 1
        after = self.tick()
        assert after["wb_ack"] == 0
        return out["wb_dat_r"]

    def write(self, address, value):
        self.access(address, 1, value & 0xFFFFFFFF)

    def read(self, address):
        return self.access(address, 0)

    def run(self, cycles, **kw):
        return [self.tick(**kw) for _ in range(cycles)]


def test_reset_values_and_read_only_registers():
    m = TopModel(3, 16, dead_min=7)
    bus = Master(m)
    assert bus.read(regs.ID) == 0x4D444651
    info = bus.read(regs.INFO)
    assert info & 0x1F == 3 and (info >> 5) & 0x3F == 16 and (info >> 16) & 0xFF == m.latency
    assert (info >> 11) & 7 == 0
    assert bus.read(regs.DEAD_MIN) == 7
    assert bus.read(regs.CTRL) == 0
    assert bus.read(regs.PERIOD) == m.latency
    assert bus.read(regs.OSR) == 1
    assert bus.read(regs.DEAD) == 7
    for address in (regs.MIN_PULSE, regs.ADC_OFFSET, regs.EVENTS_TOTAL, regs.GATES, regs.CMD,
                    regs.REF_BASE, regs.EVENTS_BASE + 2, regs.REF_BASE + 3, 0x3F,
                    regs.MODULATION):
        assert bus.read(address) == 0
    for address in (regs.ID, regs.INFO, regs.DEAD_MIN, regs.STATUS, regs.GATES,
                    regs.EVENTS_TOTAL, regs.EVENTS_BASE):
        bus.write(address, 0xFFFFFFFF)
    assert bus.read(regs.ID) == 0x4D444651 and bus.read(regs.DEAD_MIN) == 7
    assert bus.read(regs.EVENTS_BASE) == 0


def test_info_word_flags():
    m = TopModel(5, 18, "exact_nearest", 3, upper_active_low=True, lower_active_low=False)
    assert m.info == (5 | 18 << 5 | 1 << 11 | 1 << 12 | 1 << 14 | 1 << 15 | m.latency << 16
                      | 8 << 24 | 5 << 28)
    m = TopModel(3, 16, max_bits=0, asc=False, watchdog=False)
    assert m.info == 3 | 16 << 5 | m.latency << 16 | 1 << 28
    assert TopModel(3, 16, max_bits=0, asc=False).info == m.info | 1 << 15
    assert TopModel(3, 16, max_bits=3).info >> 24 == 3 | 5 << 4


@pytest.mark.parametrize("max_bits", [-1, 15, True, 1.0])
def test_max_bits_is_refused_by_name(max_bits):
    with pytest.raises(ValueError, match="max_bits"):
        TopModel(3, 16, max_bits=max_bits)


@pytest.mark.parametrize(("address", "value", "stored"), [
    (regs.DEAD, 0, 7), (regs.DEAD, 6, 7), (regs.DEAD, 8, 8), (regs.DEAD, 0x10000, 0xFFFF),
    (regs.DEAD, 0xFFFFFFFF, 0xFFFF),
    (regs.PERIOD, 0, 0), (regs.PERIOD, 0x12345, 0xFFFF), (regs.PERIOD, 77, 77),
    (regs.OSR, 0, 0), (regs.OSR, 256, 255), (regs.OSR, 9, 9),
    (regs.MIN_PULSE, 0x80000000, 0xFFFF), (regs.ADC_OFFSET, 0x10001, 0xFFFF),
    (regs.ADC_OFFSET, 12, 12), (regs.CTRL, 0xFFFFFFFF, 3), (regs.CTRL, 0xFFFFFFFC, 0),
    (regs.REF_BASE, 0x7FFFFFFF, 0x7FFF), (regs.REF_BASE + 1, 0x80000000, 0xFFFF8000),
    (regs.REF_BASE + 2, 0xFFFFFFFF, 0xFFFFFFFF), (regs.REF_BASE, 0x1234, 0x1234),
    (regs.REF_BASE + 2, -20000 & 0xFFFFFFFF, -20000 & 0xFFFFFFFF),
    (regs.REF_BASE + 3, 5, 0),            # beyond the phases: unmapped
    (regs.FAULT_REACTION, 0b1001, 0b1001), (regs.FAULT_REACTION, 0b0110, 0b0110),
    (regs.FAULT_REACTION, 0b1111, 0), (regs.FAULT_REACTION, 0xFFFFFFF7, 0b0100),
])
def test_write_clamps(address, value, stored):
    bus = Master(TopModel(3, 16, dead_min=7))
    bus.write(address, value)
    assert bus.read(address) == stored


def test_bus_timing_and_back_to_back_requests():
    m = TopModel(3, 16, dead_min=2)
    bus = Master(m)
    cyc = {"wb_cyc": 1, "wb_stb": 1, "wb_we": 1, "wb_adr": regs.DEAD, "wb_dat_w": 9}
    o0 = bus.tick(**cyc)                 # request
    assert o0["wb_ack"] == 0 and m.dead == 2   # issued; the register file takes it next
    o1 = bus.tick(**{**cyc, "wb_we": 0})  # ack cycle: the new request is not seen yet
    assert o1["wb_ack"] == 1 and o1["wb_dat_r"] == 0
    assert m.dead == 9                   # taken at the end of the ack cycle
    o2 = bus.tick(**{**cyc, "wb_we": 0})  # the read is taken now
    o3 = bus.tick(**{**cyc, "wb_we": 0})
    assert o2["wb_ack"] == 0 and o3["wb_ack"] == 1 and o3["wb_dat_r"] == 9
    # stb without cyc, and cyc without stb, are not requests
    assert bus.tick(wb_cyc=0, wb_stb=1)["wb_ack"] == 0
    assert bus.tick(wb_cyc=1, wb_stb=0)["wb_ack"] == 0
    assert bus.tick()["wb_ack"] == 0


def test_register_reference_is_committed_and_wins_over_the_port():
    m = TopModel(3, 16, dead_min=2)
    f = m.contract.full
    bus = Master(m, ref_valid=1, ref=[1, 2, 3])
    bus.tick()                                   # the port's beat is accepted at once
    assert m.core.busy and m.core.beat == (1, 2, 3)
    beat = (f // 2, -f // 4, -f // 4)
    for i, v in enumerate(beat):
        bus.write(regs.REF_BASE + i, v & 0xFFFFFFFF)
    bus.write(regs.CMD, regs.CMD_REF_COMMIT)
    assert m.ref_pending == 1 and m.ref_ready == 0     # the port waits
    assert bus.read(regs.STATUS) & regs.STATUS_REF_PENDING
    taken = []
    for _ in range(4 * m.latency):
        pending_ready = m.ref_pending and m.core.ref_ready
        port_ready = m.ref_ready
        bus.tick()
        if pending_ready:
            taken.append(("register", m.core.beat))
        elif port_ready:
            taken.append(("port", m.core.beat))
    assert taken[0] == ("register", beat) and m.ref_pending == 0
    assert taken[1:] and set(taken[1:]) == {("port", (1, 2, 3))}   # port resumes


def test_runtime_settings_reach_the_core():
    m = TopModel(5, 16, dead_min=2)
    bus = Master(m)
    bus.write(regs.PERIOD, 13)
    bus.write(regs.OSR, 3)
    bus.write(regs.CTRL, regs.CTRL_ZERO_POLICY)
    outs = bus.run(100)
    starts = [t for t, o in enumerate(outs) if o["sync_out"]]
    assert set(np.diff(starts[1:])) == {13}
    assert m.core.osr_lat == 3 and m.core.policy_lat == 1
    bus.write(regs.PERIOD, 1)
    bus.run(40)
    assert bus.read(regs.STATUS) & regs.STATUS_PERIOD_CLAMPED


def enable_and_run(m, cycles, period=16, dead=3, **kw):
    bus = Master(m)
    bus.write(regs.PERIOD, period)
    bus.write(regs.DEAD, dead)
    bus.write(regs.CTRL, regs.CTRL_ENABLE)
    f = m.contract.full
    out = []
    for k in range(cycles):
        angle = k * 0.01
        beat = [int(0.4 * f * np.cos(angle - 2 * np.pi * i / m.phases)) for i in range(m.phases)]
        out.append(bus.tick(ref_valid=1, ref=beat, **kw))
    return bus, out


def test_counters_count_turn_ons_and_clear():
    m = TopModel(3, 16, dead_min=2)
    bus, _ = enable_and_run(m, 3000)
    up, lo = np.array(bus.up), np.array(bus.lo)
    # counter state now = turn-ons visible in every recorded cycle (all off before cycle 0)
    for leg in range(3):
        on = np.concatenate([[0], ((up >> leg) | (lo >> leg)) & 1])
        assert m.events[leg] == int(np.sum(on[1:] & (1 - on[:-1])))
    assert sum(m.events) == m.total > 100
    check_gate_safety(up, lo, 3, dead=np.full(len(up), 3))
    total = m.total
    assert bus.read(regs.EVENTS_TOTAL) in range(total, total + 4)
    bus.write(regs.CMD, regs.CMD_COUNT_CLEAR)
    assert m.total <= 3 and bus.read(regs.EVENTS_BASE) <= 3


def test_counters_wrap_at_32_bits():
    m = TopModel(3, 16, dead_min=2)
    m.events = [(1 << 32) - 1] * 3
    m.total = (1 << 32) - 2
    m.driver.legs[0].event = 1
    m.driver.legs[2].event = 1
    m.step()
    assert m.events == [0, (1 << 32) - 1, 0] and m.total == 0


# (65535, 65534): the longest update's last count pulses, in the clock of the next start (the
# count never needs a 17th bit or a saturation)
@pytest.mark.parametrize(("period", "offset"), [(20, 0), (20, 5), (20, 19), (20, 20),
                                                (20, 65535), (0, 3), (65535, 65534)])
def test_adc_trigger_at_start_plus_one_plus_offset(period, offset):
    m = TopModel(3, 16, dead_min=2)
    bus = Master(m)
    bus.write(regs.PERIOD, period)
    bus.write(regs.ADC_OFFSET, offset)
    cycles = max(200, 2 * period + 100)
    outs = bus.run(cycles)
    starts = [t for t, o in enumerate(outs) if o["sync_out"]]
    p = max(period, m.latency)
    assert set(np.diff(starts[1:])) == {p}
    adc = [t for t, o in enumerate(outs) if o["adc_trigger"]]
    want = [s + 1 + offset for s in starts if offset < p and s + 1 + offset < cycles]
    assert [t for t in adc if t > starts[1]] == [t for t in want if t > starts[1]]


def test_fault_clear_through_cmd_and_status():
    m = TopModel(3, 16, dead_min=2)
    bus, _ = enable_and_run(m, 200)
    assert m.driver.up | m.driver.lo
    bus.tick(fault_in=1)
    bus.run(3)
    assert m.driver.up == 0 and m.driver.lo == 0
    status = bus.read(regs.STATUS)
    assert status & regs.STATUS_FAULT and not status & regs.STATUS_ACTIVE
    bus.write(regs.CMD, regs.CMD_FAULT_CLEAR)
    assert not bus.read(regs.STATUS) & regs.STATUS_FAULT
    bus.run(40)
    assert bus.read(regs.STATUS) & regs.STATUS_ACTIVE
    assert bus.read(regs.GATES) != 0


def test_fault_clear_while_the_input_is_active_is_ignored():
    m = TopModel(3, 16, dead_min=2)
    bus = Master(m, fault_in=1)
    bus.run(4)
    bus.write(regs.CMD, regs.CMD_FAULT_CLEAR)
    assert bus.read(regs.STATUS) & (regs.STATUS_FAULT | regs.STATUS_FAULT_INPUT) == 3


def test_fault_reaction_asc_low_then_all_off_then_clear_through_the_bus():
    m = TopModel(3, 16, dead_min=2)
    bus, _ = enable_and_run(m, 200)
    bus.write(regs.FAULT_REACTION, 1 << regs.FAULT_REACTION_FAULT_SHIFT)
    bus.tick(fault_in=1)
    bus.run(6)
    assert m.driver.up == 0 and m.driver.lo == 0b111
    status = bus.read(regs.STATUS)
    assert status >> regs.STATUS_REACTION_SHIFT == 1 and status & regs.STATUS_FAULT
    bus.write(regs.FAULT_REACTION, 2 << regs.FAULT_REACTION_FAULT_SHIFT)   # not in force
    assert bus.read(regs.STATUS) >> regs.STATUS_REACTION_SHIFT == 1 and m.driver.lo == 0b111
    bus.write(regs.CMD, regs.CMD_ALL_OFF)
    assert m.driver.up == 0 and m.driver.lo == 0
    status = bus.read(regs.STATUS)
    assert status & regs.STATUS_FAULT and not status & regs.STATUS_REACTION
    bus.write(regs.CMD, regs.CMD_FAULT_CLEAR)
    bus.run(40)
    assert bus.read(regs.STATUS) & regs.STATUS_ACTIVE and bus.read(regs.GATES) != 0


def test_fault_reaction_is_all_off_without_the_asc_built_in():
    m = TopModel(3, 16, dead_min=2, asc=False)
    bus, _ = enable_and_run(m, 200)
    bus.write(regs.FAULT_REACTION, 0b0101)
    assert bus.read(regs.FAULT_REACTION) == 0 and not bus.read(regs.INFO) & regs.INFO_ASC
    bus.tick(fault_in=1)
    bus.run(6)
    assert m.driver.up == 0 and m.driver.lo == 0


def test_fault_reaction_on_the_watchdog():
    m = TopModel(3, 16, dead_min=2)
    bus, _ = enable_and_run(m, 200)
    bus.write(regs.FAULT_REACTION, 2 << regs.FAULT_REACTION_WATCHDOG_SHIFT)
    bus.write(regs.WATCHDOG, 1)
    bus.run(4 * m.latency + 8)
    assert bus.read(regs.STATUS) & regs.STATUS_WATCHDOG
    assert m.driver.up == 0b111 and m.driver.lo == 0
    assert bus.read(regs.STATUS) >> regs.STATUS_REACTION_SHIFT == 2
    bus.write(regs.CMD, regs.CMD_WATCHDOG_CLEAR)
    assert m.driver.up == 0 and m.driver.lo == 0
    assert not bus.read(regs.STATUS) & regs.STATUS_REACTION


def test_polarity_at_reset():
    m = TopModel(3, 16, dead_min=2, upper_active_low=True)
    o = m.step()
    assert o["upper"] == 0b111 and o["lower"] == 0


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer in [3, 16] (the register map holds 16 legs), "
                    "not 2"),
    ({"phases": 17}, "phases must be an integer in [3, 16] (the register map holds 16 legs), "
                     "not 17"),
    ({"dead_min": 0}, "dead_min must be an integer in [1, 65535] (clocks), not 0"),
    ({"upper_active_low": "no"}, "upper_active_low must be a bool, not 'no'"),
])
def test_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        TopModel(**kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"wb_adr": 64}, "wb_adr must be an unsigned 6-bit integer, not 64"),
    ({"wb_dat_w": -1}, "wb_dat_w must be an unsigned 32-bit integer, not -1"),
    ({"wb_cyc": 2}, "wb_cyc must be an unsigned 1-bit integer, not 2"),
    ({"s_axi_awvalid": 1}, "unknown inputs ['s_axi_awvalid'] for the WishboneFrontModel"),
    ({"fault_in": 3}, "fault_in must be 0 or 1, not 3"),
])
def test_rejects_bad_inputs(kwargs, message):
    with pytest.raises(ValueError) as info:
        TopModel().step(**kwargs)
    assert str(info.value) == message


def test_docs_register_table_matches_the_map():
    """Every row of the register table in docs/top.md (generated from the RDL by
    tools/regmap_gen.py): address, name, access, reset, clamp."""
    text = DOCS.read_text()
    table = text.split("<!-- regmap:begin -->")[1].split("<!-- regmap:end -->")[0]
    rows = {}
    for line in table.splitlines():
        cells = [c.strip().replace("\\|", "|")
                 for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
        if len(cells) >= 5 and re.fullmatch(r"0x[0-9A-F]{2}(\+i)?", cells[0]):
            rows[int(cells[0][:4], 16)] = cells
    assert sorted(rows) == sorted(r.offset for r in REGISTERS)
    for r in REGISTERS:
        cells = rows[r.offset]
        assert cells[1].strip("`") == (f"{r.name}[i]" if r.count > 1 else r.name), cells
        assert cells[2] == r.access, cells
        assert cells[3].strip("`") == r.reset, cells
        assert cells[4].strip("`") == r.clamp, cells



# ------------------------------------------------------------------ the AXI4-Lite front


def axi(**kw):
    return {f"s_axi_{k}": v for k, v in kw.items()}


def test_axil_write_then_read_timing():
    """AW and W in the same clock a: held from a + 1, the write issued in a + 1 (bready high),
    bvalid in a + 2, the register file takes it in a + 2 (visible in a + 3); a read's AR in b:
    issued in b + 1, rdata in b + 2."""
    m = TopModel(3, 16, bus="axi4lite")
    out = m.step(**axi(awaddr=regs.PERIOD * 4, awvalid=1, wdata=40, wvalid=1, bready=1))
    assert out["s_axi_awready"] == out["s_axi_wready"] == 1 and out["s_axi_bvalid"] == 0
    out = m.step(**axi(bready=1))                              # a + 1: issued
    assert out["s_axi_awready"] == 0 and out["s_axi_bvalid"] == 0 and m.period != 40
    out = m.step(**axi(bready=1))                              # a + 2: response, taken
    assert out["s_axi_bvalid"] == 1 and out["s_axi_bresp"] == 0 and out["s_axi_awready"] == 1
    assert m.period == 40
    assert m.step(**axi(rready=1))["s_axi_bvalid"] == 0
    m.step(**axi(araddr=regs.PERIOD * 4 + 3, arvalid=1))       # low address bits ignored
    out = m.step(**axi(rready=0))
    assert out["s_axi_arready"] == 0 and out["s_axi_rvalid"] == 0
    for _ in range(3):                                         # held until rready
        out = m.step(**axi(rready=0))
        assert out["s_axi_rvalid"] == 1 and out["s_axi_rdata"] == 40
    out = m.step(**axi(rready=1))
    assert out["s_axi_rvalid"] == 1
    assert m.step()["s_axi_rvalid"] == 0


def test_axil_aw_and_w_apart_and_b_backpressure():
    """W first, AW three clocks later: the write waits for both; a stalled B holds the next
    write back (it is issued in the clock bready is high) and its payload stays put."""
    m = TopModel(3, 16, bus="axi4lite")
    m.step(**axi(wdata=regs.CTRL_ENABLE, wvalid=1))
    for _ in range(3):
        out = m.step(**axi(wvalid=1, wdata=7))                 # not taken again: wready low
        assert out["s_axi_wready"] == 0 and m.ctrl == 0
    m.step(**axi(awaddr=regs.CTRL * 4, awvalid=1))
    m.step()                                                   # issued
    m.step()                                                   # taken
    assert m.ctrl == regs.CTRL_ENABLE
    m.step(**axi(awaddr=regs.OSR * 4, awvalid=1, wdata=5, wvalid=1))   # B pending, no bready
    for _ in range(4):
        out = m.step()
        assert out["s_axi_bvalid"] == 1 and m.osr == 1         # second write held back
    m.step(**axi(bready=1))                                    # old B taken, new write issued
    assert m.osr == 1
    out = m.step()                                             # taken
    assert out["s_axi_bvalid"] == 1 and m.osr == 5


def test_axil_unmapped_words_answer_slverr_and_read_zero():
    m = TopModel(3, 16, bus="axi4lite")
    for word, resp in ((regs.REF_BASE + 3, 2), (regs.EVENTS_BASE + 2, 0), (0x3F, 2),
                       (regs.ID, 0)):
        m.step(**axi(araddr=word * 4, arvalid=1, awaddr=word * 4, awvalid=1, wvalid=1,
                     wdata=0xFFFFFFFF))
        m.step(**axi(rready=1, bready=1))
        out = m.step(**axi(rready=1, bready=1))
        assert out["s_axi_rresp"] == resp and out["s_axi_bresp"] == resp, word
        assert out["s_axi_rdata"] == (regs.ID_VALUE if word == regs.ID else 0), word
    assert m.period == m.latency and m.ctrl == 0               # nothing written anywhere


# ------------------------------------------------------------------ the interrupt


def test_irq_sources_enable_and_write_one_to_clear():
    """Written from docs/top.md, "Interrupt": each source sets its IRQ_STATUS bit the clock after
    its event, irq is the OR of IRQ_STATUS & IRQ_ENABLE of the clock before, writing 1 clears,
    an event wins."""
    m = TopModel(3, 16, dead_min=2, counter_width=8)
    bus = Master(m)
    assert bus.read(regs.IRQ_STATUS) == 0                   # the first tick's bit: next clock
    assert bus.read(regs.IRQ_STATUS) & regs.IRQ_SAMPLE
    bus.write(regs.IRQ_STATUS, 0xFFFFFFFF)
    bus.write(regs.OSR, 200)                                # ticks 200 updates apart: rare
    bus.run(m.latency * 2)
    bus.write(regs.IRQ_STATUS, regs.IRQ_MASK)
    status = bus.read(regs.IRQ_STATUS)
    assert status & regs.IRQ_FAULT == 0 and bus.log[-1]["irq"] == 0
    bus.write(regs.IRQ_ENABLE, 0xFFFFFFFF)
    assert bus.read(regs.IRQ_ENABLE) == regs.IRQ_MASK
    # a fault: the bit rises with the latch, irq a clock later
    outs = bus.run(3, fault_in=1)
    outs += bus.run(2)
    first = next(i for i, o in enumerate(outs) if o["fault"])
    assert outs[first + 1]["irq"] == 1 and outs[first]["irq"] == 0
    assert bus.read(regs.IRQ_STATUS) & regs.IRQ_FAULT
    bus.write(regs.CMD, regs.CMD_FAULT_CLEAR)
    bus.write(regs.IRQ_STATUS, regs.IRQ_FAULT)
    assert bus.read(regs.IRQ_STATUS) & regs.IRQ_FAULT == 0
    # counters of 8 bits wrap after 256 turn-ons: COUNTER_WRAP
    bus.write(regs.IRQ_ENABLE, regs.IRQ_COUNTER_WRAP)
    bus.write(regs.PERIOD, 8)
    bus.write(regs.CTRL, regs.CTRL_ENABLE)
    bus.write(regs.REF_BASE, 3000)
    bus.write(regs.REF_BASE + 1, -3000)
    bus.write(regs.CMD, regs.CMD_REF_COMMIT)
    outs = bus.run(4000)
    assert any(o["irq"] for o in outs) and bus.read(regs.IRQ_STATUS) & regs.IRQ_COUNTER_WRAP
    assert bus.read(regs.EVENTS_TOTAL) < 256


def test_irq_event_in_the_clock_of_its_clear_wins():
    m = TopModel(3, 16, dead_min=2)
    bus = Master(m)
    bus.write(regs.IRQ_ENABLE, regs.IRQ_SAMPLE)
    while m.core.phase != 0:                   # run to the clock before an update start
        bus.tick()
    # clear SAMPLE in the start (tick) clock itself: the new event wins
    out = bus.tick(wb_cyc=1, wb_stb=1, wb_we=1, wb_adr=regs.IRQ_STATUS, wb_dat_w=regs.IRQ_SAMPLE)
    assert out["wb_ack"] == 0
    assert m.irq_status & regs.IRQ_SAMPLE and [bus.tick()["irq"] for _ in range(2)][1] == 1


def test_short_edge_sets_irq_status_the_clock_after_the_edge():
    """Written from docs/top.md, "Short edges" and "Interrupt" (issue 30's example): PERIOD 40,
    DEAD 64, MIN_PULSE 0, IRQ_ENABLE = SHORT_EDGE. An update presents its state at s + L and
    a switch no longer commanded turns off a clock later: ``lower[0]`` falling in u + 1
    (u = s + L) is leg 0 commanded up in u. The lower switch back without the upper ever on
    is leg 0 commanded down at the one state presented in between, t = u + 40, with the upper
    off: a short edge in t. IRQ_STATUS (cleared in t - 2) read in t is clear, read in t + 1,
    t + 2, t + 3 set; irq rises in t + 2. One run per read clock, each from a fresh model."""
    def run(reads, clear_at, cycles):
        m = TopModel(3, 16, dead_min=2, max_bits=0)
        writes = {0: (regs.PERIOD, 40), 2: (regs.DEAD, 64), 4: (regs.MIN_PULSE, 0),
                  6: (regs.IRQ_ENABLE, regs.IRQ_SHORT_EDGE), 8: (regs.CTRL, regs.CTRL_ENABLE)}
        if clear_at is not None:
            writes[clear_at] = (regs.IRQ_STATUS, 0xFFFFFFFF)
        trace, data = [], {}
        for c in range(cycles):
            bus = {}
            if c in writes or c in reads:       # a request, in the clock of the access
                adr, value = writes.get(c, (reads.get(c), 0))
                bus = {"wb_cyc": 1, "wb_stb": 1, "wb_we": int(c in writes), "wb_adr": adr,
                       "wb_dat_w": value}
            out = m.step(ref_valid=1, ref=[1000, -500, -500], **bus)
            trace.append((out["sync_out"], out["upper"] & 1, out["lower"] & 1, out["irq"]))
            if c - 1 in reads:
                data[c - 1] = out["wb_dat_r"]
        return trace, data, m.latency

    def short_edge(trace, latency):
        sync, up0, lo0, _ = zip(*trace, strict=True)
        starts = [c for c, v in enumerate(sync) if v]
        for s in starts:
            u = s + latency
            if not (lo0[u] and not lo0[u + 1]):
                continue
            back = next(c for c in range(u + 1, len(lo0)) if up0[c] or lo0[c])
            between = [s2 + latency for s2 in starts if u < s2 + latency < back]
            if lo0[back] and len(between) == 1:
                return between[0]
        return None

    trace, _, latency = run({}, None, 800)
    t = short_edge(trace, latency)
    assert t is not None, "no short edge aimed: the test is vacuous"
    status = []
    for k in range(4):
        trace, data, _ = run({t + k: regs.IRQ_STATUS}, t - 2, t + 80)
        assert short_edge(trace, latency) == t
        status.append(int(bool(data[t + k] & regs.IRQ_SHORT_EDGE)))
        assert [irq for *_, irq in trace[t - 1:t + 8]] == [0, 0, 0] + [1] * 6, k
    assert status == [0, 1, 1, 1], status


# ------------------------------------------------------------------ modulation mode and b
def modulation(mode, bits):
    return mode << regs.MODULATION_MODE_SHIFT | bits << regs.MODULATION_BITS_SHIFT


@pytest.mark.parametrize(("max_bits", "written", "in_force", "clamped"), [
    (8, (1, 3), (1, 3), 0),        # svpwm at b = 3: taken as written
    (8, (4, 9), (4, 8), 1),        # b above max_bits: max_bits, flagged
    (8, (2, 0), (2, 1), 1),        # b = 0 in a slot mode: 1, flagged
    (8, (0, 5), (0, 0), 0),        # mdfqm ignores b, no flag
    (8, (6, 2), (0, 0), 1),        # no mode 6: mdfqm, flagged
    (3, (3, 7), (3, 3), 1),        # a smaller max_bits
    (0, (1, 3), (0, 0), 1),        # the MDFQM-only top: every other mode is mdfqm, flagged
    (0, (0, 9), (0, 0), 0),
])
def test_modulation_reads_the_mode_in_force_from_the_next_update_start(max_bits, written,
                                                                       in_force, clamped):
    """A MODULATION write is a request: reads keep the mode and b in force until an update
    start takes it (clamped, STATUS.MODE_CLAMPED for that update); mdfqm before."""
    m = TopModel(3, 16, max_bits=max_bits)
    bus = Master(m)
    bus.write(regs.PERIOD, 40)
    bus.run(2 * m.long_latency)
    while not bus.tick()["sync_out"]:                                # just after a start
        pass
    bus.write(regs.MODULATION, modulation(*written) | 0xFFFF_F0F8)   # other bits dropped
    assert bus.read(regs.MODULATION) == 0                            # not started yet
    assert not bus.read(regs.STATUS) & regs.STATUS_MODE_CLAMPED
    bus.run(40)                                                      # an update start
    assert bus.read(regs.MODULATION) == modulation(*in_force)
    assert bool(bus.read(regs.STATUS) & regs.STATUS_MODE_CLAMPED) == bool(clamped)
    bus.write(regs.MODULATION, 0)                                    # back to mdfqm
    bus.run(2 * max(40, m.long_latency, 1 << in_force[1]))      # b = 8: 256-clock updates
    assert bus.read(regs.MODULATION) == 0
    assert not bus.read(regs.STATUS) & regs.STATUS_MODE_CLAMPED


def test_slot_mode_switches_inside_an_update_and_the_driver_follows():
    """SVPWM at b = 2: the gates change inside an update (between update strobes), with the
    dead time at every edge."""
    m = TopModel(3, 16, dead_min=2)
    bus = Master(m, ref_valid=1, ref=[6000, -2000, -4000])
    bus.write(regs.PERIOD, 64)
    bus.write(regs.MODULATION, modulation(1, 2))
    bus.write(regs.CTRL, regs.CTRL_ENABLE)
    ups = []
    for _ in range(6 * 64):
        ups.append(m.core.update)
        bus.tick()
    up, lo = np.array(bus.up[-len(ups):]), np.array(bus.lo[-len(ups):])
    update = np.array(ups)
    changes = np.flatnonzero(np.diff(up | lo << 3) != 0) + 1
    inside = [t for t in changes if not update[max(0, t - 4):t + 1].any()]
    assert len(inside) >= 4, "no gate edge inside an update"
    check_gate_safety(up, lo, 3, dead=np.full(len(up), 2))


def test_watchdog_trips_at_the_timeout_plus_first_quiet_start_and_stops_the_gates():
    """Hand-derived from docs/top.md, "Reference watchdog": WATCHDOG = 2 written, no reference
    afterwards: the update starts s1, s2 pass, s3 trips; STATUS.WATCHDOG from s3 + 1, every
    gate off from s3 + 2 until CMD.WATCHDOG_CLEAR; a reference arriving meanwhile does not clear
    it; after the clear the gates come back; a trip counts once."""
    m = TopModel(3, 16, dead_min=2, max_bits=0)
    bus = Master(m)
    bus.write(regs.PERIOD, 20)
    bus.write(regs.CTRL, regs.CTRL_ENABLE)
    bus.write(regs.IRQ_ENABLE, regs.IRQ_WATCHDOG)
    bus.run(100, ref_valid=1, ref=[3000, -1000, -2000])      # the core switches
    assert m.driver.up | m.driver.lo
    bus.write(regs.WATCHDOG, 2)
    written = len(bus.log)                  # the write's effect is visible from here
    assert bus.read(regs.WATCHDOG) == 2
    bus.run(90)
    starts = [t for t, out in enumerate(bus.log) if out["sync_out"] and t >= written]
    s3 = starts[2]
    on = [u | lo for u, lo in zip(bus.up, bus.lo, strict=True)]
    assert any(on[starts[0]:s3 + 2]), "no gate on before the trip: the test is vacuous"
    assert not any(on[s3 + 2:])
    assert bus.read(regs.STATUS) & regs.STATUS_WATCHDOG
    assert bus.read(regs.WATCHDOG_TRIPS) == 1
    assert bus.read(regs.IRQ_STATUS) & regs.IRQ_WATCHDOG
    assert bus.log[-1]["irq"] == 1
    bus.run(30, ref_valid=1, ref=[3000, -1000, -2000])        # a reference: still tripped
    assert bus.read(regs.STATUS) & regs.STATUS_WATCHDOG and not any(on[s3 + 2:])
    bus.write(regs.CMD, regs.CMD_WATCHDOG_CLEAR)
    cleared = len(bus.log)
    bus.run(40, ref_valid=1, ref=[3000, -1000, -2000])
    assert not bus.read(regs.STATUS) & regs.STATUS_WATCHDOG
    on = [u | lo for u, lo in zip(bus.up, bus.lo, strict=True)]
    assert any(on[cleared:]) and not any(on[s3 + 2:cleared])
    assert bus.read(regs.WATCHDOG_TRIPS) == 1
    bus.write(regs.CMD, regs.CMD_COUNT_CLEAR)
    assert bus.read(regs.WATCHDOG_TRIPS) == 0


def test_watchdog_not_built_in_never_trips():
    """Hand-derived from docs/top.md, "Reference watchdog", without the watchdog built in:
    INFO.WATCHDOG 0, a WATCHDOG write stores 0 and so does FAULT_REACTION.WATCHDOG; the
    references stop and the gates go on switching, with STATUS.WATCHDOG, WATCHDOG_TRIPS and
    IRQ_STATUS.WATCHDOG 0."""
    m = TopModel(3, 16, dead_min=2, max_bits=0, watchdog=False)
    bus = Master(m)
    assert not bus.read(regs.INFO) & regs.INFO_WATCHDOG
    assert TopModel(3, 16).info & regs.INFO_WATCHDOG
    bus.write(regs.PERIOD, 20)
    bus.write(regs.CTRL, regs.CTRL_ENABLE)
    bus.write(regs.IRQ_ENABLE, regs.IRQ_WATCHDOG)
    bus.write(regs.FAULT_REACTION, 1 << regs.FAULT_REACTION_WATCHDOG_SHIFT | 1)
    assert bus.read(regs.FAULT_REACTION) == 1           # the fault's reaction is kept
    bus.run(100, ref_valid=1, ref=[3000, -1000, -2000])
    bus.write(regs.WATCHDOG, 1)
    assert bus.read(regs.WATCHDOG) == 0
    written = len(bus.log)
    bus.run(200)                                        # ten updates without a reference
    assert len(set(bus.up[written:])) > 1, "the gates stopped switching"
    assert not bus.read(regs.STATUS) & regs.STATUS_WATCHDOG
    assert bus.read(regs.WATCHDOG_TRIPS) == 0 and not bus.read(regs.IRQ_STATUS) & regs.IRQ_WATCHDOG
    bus.write(regs.CMD, regs.CMD_WATCHDOG_CLEAR)        # nothing to clear: nothing changes
    assert not bus.read(regs.STATUS) & regs.STATUS_WATCHDOG


def test_watchdog_off_and_fed_never_trips():
    """WATCHDOG 0 (the reset value) never trips, however long without a reference; a reference
    in every update keeps WATCHDOG = 1 from tripping; a write above 65535 stores 65535."""
    m = TopModel(3, 16, dead_min=2, max_bits=0)
    bus = Master(m)
    bus.write(regs.PERIOD, 12)
    bus.write(regs.CTRL, regs.CTRL_ENABLE)
    bus.run(3000)
    assert not bus.read(regs.STATUS) & regs.STATUS_WATCHDOG
    bus.write(regs.WATCHDOG, 1)
    bus.run(3000, ref_valid=1, ref=[2000, -1000, -1000])     # a beat offered in every clock
    assert not bus.read(regs.STATUS) & regs.STATUS_WATCHDOG
    assert bus.read(regs.WATCHDOG_TRIPS) == 0
    bus.write(regs.WATCHDOG, 0x12345678)
    assert bus.read(regs.WATCHDOG) == 0xFFFF
