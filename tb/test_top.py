# amaranth: UnusedElaboratable=no
"""The drop-in top (generator or core + gate driver + Wishbone or AXI4-Lite registers +
counters + ADC trigger), every output on every clock, against mdfqm_model.top.TopModel, with
random MODULATION writes (mode and b, legal or not) inside every scenario; independent checks
of the safety properties, the switching counters and the ADC trigger on the same traces; two
instances sharing update boundaries through sync_out -> sync_in. The top's SymbiYosys proofs
and covers are in tb/test_formal.py."""


import functools
import operator

import cocotb
import numpy as np
import pytest
from amaranth import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec import regmap as regs
from mdfqm_spec.contract import MODES, min_period
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start
from mdfqm_testkit.top_bench import Bench, make_model, port_name

# (phases, width, rule, dead_min, upper_active_low, lower_active_low, bus, counter_width,
#  max_bits): the generator at the drop-in's b, a smaller one, the MDFQM-only top
# (phases, width, rule, dead_min, upper_low, lower_low, bus, counter_width, max_bits, asc)
CASES = [(3, 16, "largest_duty", 3, False, False, "wishbone", 32, 8, True),
         (5, 16, "exact_nearest", 5, True, True, "wishbone", 32, 4, True),
         (3, 16, "largest_duty", 4, False, True, "axi4lite", 8, 0, False)]
SINGLE_TESTS = ["top_operate", "top_register_reference", "top_counters", "top_adc_trigger",
                "top_fault", "top_fault_reaction", "top_interrupt", "top_watchdog",
                "top_bad_input", "top_short_edge_timing"]

#: The model carried from one cocotb test to the next of the same simulation (the gate driver's
#: dead-time memory and the fault synchroniser are not reset, by design). A failing test can make
#: later tests of the same run fail too; the first failure is the real one.
CARRY = {}


def begin(p, rng, key="single", prefix=""):
    """A Bench on the carried model, stepped through the reset cycles of :func:`harness.start`."""
    if key not in CARRY:
        CARRY[key] = (make_model(p), None)
    model, last = CARRY[key]
    for _ in range(2):
        if last is None:
            model.step(rst=1)
        else:
            model.step(**last, rst=1)
    bench = Bench(rng, model, prefix)
    bench.dt_run0 = [leg.dt_run for leg in model.driver.legs]
    return bench


def finish(bench, key="single"):
    CARRY[key] = (bench.model, bench.last)
    return bench.check_safety(bench.dt_run0)


def configure(b, period, dead, min_pulse=0, osr=1, adc_offset=0, ctrl=regs.CTRL_ENABLE):
    b.write(regs.PERIOD, period)
    b.write(regs.OSR, osr)
    b.write(regs.DEAD, dead)
    b.write(regs.MIN_PULSE, min_pulse)
    b.write(regs.ADC_OFFSET, adc_offset)
    b.write(regs.CMD, regs.CMD_FAULT_CLEAR | regs.CMD_COUNT_CLEAR)
    b.write(regs.CTRL, ctrl)


async def run_bench(dut, name, build, min_turn_ons=20, modes_seen=None):
    """Generate with ``build(bench)``, then drive the DUT and compare every cycle. With a
    generator inside, the modes in ``modes_seen`` (default: every mode) must each have been in
    force in some cycle of the run."""
    p = params()
    rng = seeded_rng(dut, name)
    bench = begin(p, rng)
    build(bench, rng, p)
    turn_ons = finish(bench)
    assert turn_ons >= min_turn_ons, f"{name}: only {turn_ons} turn-ons, the test is vacuous"
    if bench.model.max_bits:
        want = set(range(len(MODES))) if modes_seen is None else modes_seen
        missing = want - set(bench.trace["mode"])
        assert not missing, f"{name}: modes {sorted(missing)} never in force"
    await start(dut)
    checked = await check_cycles(dut, bench.stim, bench.expected)
    dut._log.info("%s: %d cycles, %d turn-ons, every output equal to the model", name,
                  checked, turn_ons)
    return bench


# ---------------------------------------------------------------------- scenarios


def build_operate(b, rng, p):
    """Sine references through the direct stream port; settings moving while running."""
    configure(b, period=24, dead=4, osr=2, adc_offset=5)
    for round_ in range(40):
        if round_ % 5 == 0:
            b.write(regs.PERIOD, rng.choice([0, 12, 24, 40]))
            b.write(regs.DEAD, rng.choice([0, 2, 6, 11]))           # changed while running
            b.write(regs.MIN_PULSE, rng.choice([0, 3, 15]))
            b.write(regs.CTRL, rng.choice([1, 1, 3, 0, 2]))         # enable toggled mid-update
            b.amplitude = rng.uniform(0.1, 0.6)
        if round_ % 5 in (0, 3):
            b.modulation()
        for address in (regs.STATUS, regs.GATES, regs.EVENTS_TOTAL, regs.CTRL, regs.DEAD):
            b.read(address)
        b.run_until_idle()
        for _ in range(rng.randint(150, 350)):
            b.tick()


def build_register_reference(b, rng, p):
    """References written to REF[i] and committed through CMD; the stream port also offering
    beats at times (the committed register beat wins)."""
    configure(b, period=20, dead=3, osr=1)
    c = b.model.contract
    for k in range(60):
        values = b.sine_beat() if k % 3 else [rng.choice([c.code_min, c.code_max, 0, -1])
                                              for _ in range(b.n)]
        for i, v in enumerate(values):
            b.write(regs.REF_BASE + i, v)
        if k % 7 == 0:                              # out of range: saturates
            b.write(regs.REF_BASE + rng.randrange(b.n), rng.choice([1 << 31, (1 << 31) - 1]))
        b.write(regs.CMD, regs.CMD_REF_COMMIT)
        if k % 4 == 0:
            b.write(regs.CMD, regs.CMD_REF_COMMIT)        # a second commit while pending
        b.read(regs.STATUS)
        b.read(regs.REF_BASE + rng.randrange(b.n))
        if k % 6 == 0:
            b.modulation()
        both = k % 5 == 0
        b.run_until_idle(stream=both)
        for _ in range(rng.randint(20, 90)):
            b.tick(stream=both)


def build_counters(b, rng, p):
    """Switching counters against the gate trace: every read of EVENTS[i] / EVENTS_TOTAL equals
    the number of turn-ons seen on the gates since the last clear."""
    configure(b, period=16, dead=2, osr=1)
    for round_ in range(30):
        for i in range(b.n):
            b.read(regs.EVENTS_BASE + i)
        b.read(regs.EVENTS_TOTAL)
        if round_ % 6 == 5:
            b.write(regs.CMD, regs.CMD_COUNT_CLEAR)
        if round_ % 4 == 0:
            b.modulation()
        b.run_until_idle()
        for _ in range(rng.randint(30, 200)):
            b.tick()
    # independent count: turn-on edges on the recorded gates
    up, lo = np.array(b.trace["up"]), np.array(b.trace["lo"])
    checked = 0
    for cycle, address, value in b.reads:
        last_clear = max([t for t in range(cycle) if b.trace["count_clear"][t]], default=-1)
        legs = (range(b.n) if address == regs.EVENTS_TOTAL
                else [address - regs.EVENTS_BASE] if address >= regs.EVENTS_BASE else [])
        count = 0
        for leg in legs:
            on = ((up >> leg) | (lo >> leg)) & 1
            lo_t = max(last_clear + 1, 1)
            count += int(np.sum(on[lo_t:cycle] & ~on[lo_t - 1:cycle - 1] & 1))
        if legs:
            assert value == count, (cycle, address, value, count)
            checked += 1
    assert checked > 50


def build_adc_trigger(b, rng, p):
    """The ADC trigger at s + 1 + ADC_OFFSET of every update (s the update start, in every
    mode); none when ADC_OFFSET >= P, P the period in force (slot modes: at least L_b and
    2**b)."""
    slot = [(40, 3, 1, 2), (24, 23, 4, 1), (70, 69, 2, 2)] if b.model.max_bits else []
    for period, offset, mode, bits in [(20, 0, 0, 0), (20, 7, 0, 0), (20, 19, 0, 0),
                                       (20, 20, 0, 0), (33, 31, 0, 0), (0, 3, 0, 0), *slot]:
        b.write(regs.PERIOD, period)
        b.write(regs.ADC_OFFSET, offset)
        b.modulation(mode, bits)
        b.write(regs.CTRL, regs.CTRL_ENABLE)
        b.run_until_idle()
        p_eff = max(period, min_period(mode != 0, bits, b.model.latency, b.model.long_latency))
        for _ in range(2 * p_eff):             # the update that takes the new mode starts
            b.tick()
        first = b.cycle
        for _ in range(6 * p_eff + 3):
            b.tick()
        sync = np.array(b.expected["sync_out"][first:])
        adc = np.array(b.expected["adc_trigger"][first:])
        starts = np.flatnonzero(sync)
        assert (np.diff(starts[1:]) == p_eff).all()
        want = np.zeros_like(adc)
        if offset < p_eff:
            for s in starts:
                if s + 1 + offset < len(want):
                    want[s + 1 + offset] = 1
        lo = starts[1]
        assert (adc[lo:] == want[lo:]).all(), (period, offset)


def build_fault(b, rng, p):
    """Fault chatter on the pin, clears through CMD while active and after; status reads."""
    configure(b, period=18, dead=4)
    b.run_until_idle()
    chatter = 0
    for cycle in range(5000):
        if rng.random() < 0.004:
            chatter = rng.choice([1, 2, 7, 30])
        fault_in = 0
        if chatter:
            chatter -= 1
            fault_in = rng.randint(0, 1) if chatter > 1 else 1
        if b.idle() and rng.random() < 0.05:
            b.write(regs.CMD, regs.CMD_FAULT_CLEAR)
            b.read(regs.STATUS)
        if cycle % 600 == 0:
            b.modulation()
        b.tick(fault_in=fault_in)


def build_fault_reaction(b, rng, p):
    """The fault reaction as firmware uses it: FAULT_REACTION written (every code, 3 and the
    undefined bits too), a fault on the pin or a watchdog trip (the stream stalled) or both,
    STATUS read during it, FAULT_REACTION rewritten while a reaction is in force, CMD.ALL_OFF,
    the clears; the gates enabled or not. Functional coverage from the model's trace: each
    source with each reaction, an ASC ended by ALL_OFF and by a clear, a write while an ASC is
    in force, STATUS.REACTION read as each ASC (without the ASC built in: never an ASC)."""
    configure(b, period=rng.choice([12, 20]), dead=3)
    b.run_until_idle()
    m = b.model
    plans = [(source, code) for source in ("fault", "watchdog") for code in (0, 1, 2)]
    rng.shuffle(plans)
    plans += [(rng.choice(["fault", "watchdog", "both"]), rng.randrange(4)) for _ in range(6)]
    writes_in_force, asc_plans = 0, 0
    for source, code in plans:
        # ALL_OFF ends every other ASC (and half the others), the clears the rest
        asc_plans += code in (1, 2)
        all_off = asc_plans % 2 == 1 if code in (1, 2) else rng.random() < 0.5
        enabled = rng.random() < 0.8
        b.write(regs.CTRL, regs.CTRL_ENABLE if enabled else 0)
        other = rng.randrange(4)
        fault_code, wd_code = (other, code) if source == "watchdog" else (code, other)
        word = (fault_code << regs.FAULT_REACTION_FAULT_SHIFT
                | wd_code << regs.FAULT_REACTION_WATCHDOG_SHIFT)
        b.write(regs.FAULT_REACTION, word | rng.choice([0, 0, 0xFFFFFFF0]))
        b.read(regs.FAULT_REACTION)
        if source != "fault":
            b.write(regs.WATCHDOG, 1)
        b.run_until_idle()
        for _ in range(rng.randint(30, 200)):
            b.tick()
        fault_len = rng.randint(3, 40)
        for k in range(rng.randint(250, 450)):
            stalled = source != "fault" and k < 120
            fault_in = int(source != "watchdog" and k < fault_len)
            if b.idle():
                if k == 150:
                    b.read(regs.STATUS)
                    if code in (1, 2) or rng.random() < 0.5:   # not the one in force
                        writes_in_force += m.driver.reaction != 0
                        b.write(regs.FAULT_REACTION, rng.getrandbits(4))
                        b.read(regs.STATUS)
                elif k == 200 and all_off:
                    b.write(regs.CMD, regs.CMD_ALL_OFF)
                    b.read(regs.STATUS)
                elif k == 240:
                    b.write(regs.WATCHDOG, 0)
                    b.write(regs.CMD, regs.CMD_FAULT_CLEAR | regs.CMD_WATCHDOG_CLEAR)
                    b.read(regs.STATUS)
            b.tick(fault_in=fault_in, stream=not stalled)
        b.run_until_idle()
    b.write(regs.CTRL, regs.CTRL_ENABLE)
    b.run_until_idle()
    for _ in range(200):
        b.tick()
    # functional coverage, from the model's trace and the STATUS reads
    r = np.array(b.trace["reaction"])
    fault, wd = np.array(b.trace["kill"]), np.array(b.trace["watchdog"])
    ended = np.flatnonzero((r[:-1] != 0) & (r[1:] == 0))
    by_all_off = sum(int(np.array(b.trace["all_off"])[t - 1:t + 1].any()) for t in ended)
    read = {v >> regs.STATUS_REACTION_SHIFT & 3 for _, a, v in b.reads if a == regs.STATUS}
    if m.asc:
        assert {1, 2} <= set(r.tolist()), "an ASC never in force"
        assert {1, 2} <= read, "STATUS.REACTION never read as each ASC"
        assert by_all_off >= 1 and len(ended) - by_all_off >= 1, \
            "an ASC not ended by ALL_OFF and by a clear"
        assert writes_in_force >= 1, "FAULT_REACTION never written while an ASC was in force"
    else:
        assert not r.any() and read == {0}, "an ASC without the ASC built in"
    assert fault.any() and wd.any(), "a source never set"


def build_interrupt(b, rng, p):
    """Firmware serving the interrupt: every source enabled at times, IRQ_STATUS read and cleared
    when irq is high (also in the clock of a new event), faults, sampling ticks, counters run
    past their width (8 bits in one configuration: it wraps every 256 turn-ons), short edges
    (a minimum pulse longer than the update period for a while)."""
    configure(b, period=10, dead=2, osr=2)
    b.write(regs.IRQ_ENABLE, regs.IRQ_MASK)
    b.run_until_idle()
    b.amplitude, b.step_angle = 0.55, 0.08          # busy legs: hundreds of turn-ons
    served, clear_due, watchdog_done = 0, False, False
    # 8000 clocks, and on until the counters have wrapped (the slot modes' long updates at a
    # large max_bits switch less often)
    wrap_at = (1 << p["counter_width"]) + 2 * b.n if p["counter_width"] < 32 else 0
    turn_ons, cycle = 0, 0
    while cycle < 8000 or (turn_ons < wrap_at and cycle < 40_000):
        fault_in = int(cycle % 1500 in range(700, 706))
        clear_due |= cycle % 1500 == 720
        if cycle % 1000 == 0:           # MDFQM while the minimum pulse is long: its commands
            b.modulation(mode=0 if cycle == 3000 else None)  # change often enough to be cut
        if cycle in (3000, 3600):
            b.write(regs.MIN_PULSE, 30 if cycle == 3000 else 0)
        if cycle == 5000:               # a trip: a 2-update timeout, the stream pauses until
            b.write(regs.WATCHDOG, 2)   # the latch sets (however late the write lands)
        if b.model.wd_tripped and not watchdog_done:
            b.write(regs.WATCHDOG, 0)
            b.write(regs.CMD, regs.CMD_WATCHDOG_CLEAR)
            watchdog_done = True
        stalled = b.model.wd_timeout == 2 and not watchdog_done
        if b.idle():
            if clear_due:
                b.write(regs.CMD, regs.CMD_FAULT_CLEAR)
                clear_due = False
            elif b.expected[b.prefix + "irq"] and b.expected[b.prefix + "irq"][-1]:
                b.read(regs.IRQ_STATUS)
                # (COUNTER_WRAP and WATCHDOG, each set once or rarely, are left set: the
                # final read must see them; an AXI write may overtake the read before it.) A
                # source is acknowledged only once a read has shown it: a rare event (a short
                # edge) set after the read and cleared by this write would go unseen
                shown = functools.reduce(operator.or_, (
                    value for _, address, value in b.reads if address == regs.IRQ_STATUS), 0)
                b.write(regs.IRQ_STATUS, rng.choice([regs.IRQ_FAULT | regs.IRQ_SAMPLE,
                                                     regs.IRQ_SAMPLE, 0xFFFFFFED])
                        & ~(regs.IRQ_MASK & ~shown))
                served += 1
            elif rng.random() < 0.01:
                b.write(regs.IRQ_ENABLE, rng.choice([0, regs.IRQ_SAMPLE, regs.IRQ_FAULT | 2,
                                                     regs.IRQ_MASK, 0xFFFFFFFF]))
                b.read(regs.IRQ_ENABLE)
        b.tick(fault_in=fault_in, stream=not stalled)
        on = [up | lo for up, lo in zip(b.trace["up"][-2:], b.trace["lo"][-2:], strict=True)]
        turn_ons += bin(on[-1] & ~on[0]).count("1") if len(on) == 2 else 0
        cycle += 1
    assert served > 20, "the interrupt was never served"
    assert watchdog_done, "the watchdog never tripped"
    raised = [bool(v) for v in b.expected[b.prefix + "irq"]]
    assert any(raised) and not all(raised)
    b.read(regs.IRQ_STATUS)
    b.run_until_idle()
    seen = 0
    for _, address, value in b.reads:
        seen |= value if address == regs.IRQ_STATUS else 0
    wraps = turn_ons >= (1 << p["counter_width"]) + 2 * b.n     # some before the first clear
    assert any(b.trace["short_edge"]), "no short edge: SHORT_EDGE untested"
    assert seen & regs.IRQ_MASK == (regs.IRQ_MASK if wraps else regs.IRQ_MASK
                                    & ~regs.IRQ_COUNTER_WRAP)
    assert wraps or p["counter_width"] == 32, f"only {turn_ons} turn-ons: no counter wrapped"


def build_watchdog(b, rng, p):
    """A controller that stalls: the stream pauses (or register commits stop) for random
    stretches against random timeouts (0 = off, 1, small, the clamp of a huge write); trips read
    through STATUS / WATCHDOG_TRIPS / IRQ_STATUS, cleared through CMD (also while the stream is
    still away, and with COUNT_CLEAR in the same write), a clear in the clock of a trip; then
    five aimed stalls past a 3-update timeout, so that every run trips the latch."""
    configure(b, period=rng.choice([9, 16, 25]), dead=3, osr=rng.choice([1, 2]))
    b.write(regs.IRQ_ENABLE, regs.IRQ_WATCHDOG)
    b.write(regs.WATCHDOG, 3)
    b.run_until_idle()
    stall = 0
    commits = False
    for cycle in range(12000):
        if stall == 0 and rng.random() < 0.004:
            stall = rng.choice([20, 60, 150, 400])
            commits = rng.random() < 0.3
        stall = max(stall - 1, 0)
        if b.idle():
            if rng.random() < 0.003:
                b.write(regs.WATCHDOG, rng.choice([0, 1, 2, 3, 5, 0xFFFFFFFF, 0x10003]))
                b.read(regs.WATCHDOG)
            elif b.model.wd_tripped and rng.random() < 0.02:
                b.read(regs.STATUS)
                b.read(regs.WATCHDOG_TRIPS)
                b.write(regs.IRQ_STATUS, regs.IRQ_WATCHDOG)
                b.write(regs.CMD, rng.choice([regs.CMD_WATCHDOG_CLEAR,
                                              regs.CMD_WATCHDOG_CLEAR | regs.CMD_COUNT_CLEAR,
                                              0xF]))
            elif commits and stall and rng.random() < 0.01:   # a register-fed controller
                for i in range(b.n):
                    b.write(regs.REF_BASE + i, rng.randrange(-2000, 2000))
                b.write(regs.CMD, regs.CMD_REF_COMMIT)
            elif rng.random() < 0.002:
                b.write(regs.CMD, regs.CMD_WATCHDOG_CLEAR)    # also when nothing tripped
        if cycle % 2500 == 0:
            b.modulation()
        b.tick(stream=stall == 0)
    # the rule's own sequence, whatever the random stretches gave: in MDFQM (short updates),
    # five stalls longer than a 3-update timeout, each trip cleared after the stream is back
    b.modulation(mode=0, bits=0)
    b.write(regs.WATCHDOG, 3)
    for _ in range(5):
        b.write(regs.CMD, regs.CMD_WATCHDOG_CLEAR)
        b.run_until_idle()
        for _ in range(100):
            b.tick(stream=True)
        for _ in range(200):
            b.tick(stream=False)
    b.read(regs.WATCHDOG_TRIPS)
    b.run_until_idle()
    latch = np.array(b.trace["watchdog"])
    trips = int(np.sum(latch[1:] & ~latch[:-1]))
    on = np.array(b.trace["up"]) | np.array(b.trace["lo"])
    caught_on = int(np.sum(latch[1:] & ~latch[:-1] & (on[1:] != 0)))
    assert trips >= 5, f"only {trips} watchdog trips: the watchdog is barely tested"
    assert caught_on >= 3, "too few trips caught the gates on"


def build_bad_input(b, rng, p):
    """Any value to any register, in any order, with resets, faults and sync pulses at random:
    the gates stay safe. For most of the run the timing registers get small values (below the
    floor, 0, 1, ...) so that the legs keep switching and the dead-time checks have work; in the
    last part every register also gets the extremes (0xFFFFFFFF, 0x80000000, 0x10000, ...)."""
    extremes = [0, 1, 2, 0x7FFF, 0x8000, 0xFFFF, 0x10000, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF]
    timing = (regs.DEAD, regs.MIN_PULSE, regs.PERIOD, regs.ADC_OFFSET, regs.OSR)
    cycles = 9000
    for cycle in range(cycles):
        late = cycle > cycles * 0.8
        if b.idle() and rng.random() < 0.3:
            address = rng.randrange(1 << regs.ADDR_WIDTH)
            if rng.random() < 0.6:
                address = rng.choice([regs.CTRL, regs.CMD, *timing, regs.REF_BASE])
            value = rng.choice([*extremes, rng.getrandbits(32), rng.randrange(40)])
            if address in timing and not late:
                value = rng.choice([0, 1, 2, rng.randrange(16), rng.randrange(40)])
            if address == regs.CTRL and rng.random() < 0.7:
                value |= regs.CTRL_ENABLE
            if address == regs.CMD and rng.random() < 0.7:
                value &= ~regs.CMD_COUNT_CLEAR
            if rng.random() < 0.5:
                b.write(address, value)
            else:
                b.read(address)
        b.tick(rst=int(rng.random() < 0.0005), fault_in=int(rng.random() < 0.0008),
               sync_in=int(rng.random() < 0.03))


@cocotb.test()
async def top_operate(dut):
    """Direct-port sine, settings (period, dead time, min pulse, enable) changed while running."""
    await run_bench(dut, "top_operate", build_operate)


@cocotb.test()
async def top_register_reference(dut):
    """REF[i] + CMD.REF_COMMIT, saturating writes, double commits, the port competing."""
    await run_bench(dut, "top_register_reference", build_register_reference)


@cocotb.test()
async def top_counters(dut):
    """EVENTS[i] / EVENTS_TOTAL against the turn-ons on the gates, with clears."""
    await run_bench(dut, "top_counters", build_counters)


@cocotb.test()
async def top_adc_trigger(dut):
    """ADC trigger position against the update starts, offsets inside and outside the period."""
    await run_bench(dut, "top_adc_trigger", build_adc_trigger, min_turn_ons=5,
                    modes_seen={0, 1, 2, 4})


@cocotb.test()
async def top_fault(dut):
    """Fault chatter through the pin, clears and status reads through the bus."""
    await run_bench(dut, "top_fault", build_fault)


@cocotb.test()
async def top_fault_reaction(dut):
    """FAULT_REACTION per source, STATUS.REACTION, CMD.ALL_OFF, the clears, rewrites."""
    await run_bench(dut, "top_fault_reaction", build_fault_reaction, modes_seen=set())


@cocotb.test()
async def top_interrupt(dut):
    """IRQ_ENABLE / IRQ_STATUS served like firmware does; faults, ticks and counter wraps."""
    await run_bench(dut, "top_interrupt", build_interrupt)


@cocotb.test()
async def top_watchdog(dut):
    """The reference watchdog: stalls, trips, clears, timeouts changed while counting."""
    await run_bench(dut, "top_watchdog", build_watchdog, modes_seen=set())


# ---------------------------------------------------------------------- the docs' own clocks
#: the client's example of issue 30 (docs/top.md, "Short edges"): updates shorter than the dead
#: time, no minimum pulse, only SHORT_EDGE enabled
AIMED = {"period": 40, "dead": 64}


def aimed_short_edge(sync_out, up0, lo0, latency):
    """The first clock with a short edge of leg 0, found on the pins by docs/top.md's rules
    alone, or None: an update starting in ``s`` presents its state in ``s + L``, and a switch
    no longer commanded turns off the clock after; so ``lower[0]`` falling in ``s + L + 1``
    means the state of ``s + L`` commanded the upper switch. When the lower switch then comes
    back without the upper ever turning on, the command went back to the lower switch at the
    one state presented in between (MDFQM changes its state only at update boundaries): in that
    clock the switch named before (the upper) was off, the edge is short."""
    starts = [c for c, v in enumerate(sync_out) if v]
    for s in starts:
        up_at = s + latency
        if up_at + 1 >= len(lo0) or not (lo0[up_at] and not lo0[up_at + 1]):
            continue
        back = next((c for c in range(up_at + 1, len(lo0)) if up0[c] or lo0[c]), None)
        if back is None or up0[back]:
            continue
        presented = [s2 + latency for s2 in starts if up_at < s2 + latency < back]
        if len(presented) == 1:
            return presented[0]
    return None


def aimed_inputs(p, clock, reads, writes):
    """The bus inputs of ``clock`` (model names) for accesses *issued* in given clocks
    (``reads``: clock -> address, ``writes``: clock -> (address, value)): Wishbone requests in
    the issue clock, held through the ``ack`` clock; AXI4-Lite AR (AW and W) a clock ahead,
    ``rready`` and ``bready`` always high."""
    if p.get("bus", "wishbone") == "wishbone":
        for c in (clock, clock - 1):
            if c in reads or c in writes:
                adr, value = (reads[c], 0) if c in reads else writes[c]
                return {"wb_cyc": 1, "wb_stb": 1, "wb_we": int(c in writes), "wb_adr": adr,
                        "wb_dat_w": value, "wb_sel": 0xF}
        return {}
    bus = {"s_axi_rready": 1, "s_axi_bready": 1, "s_axi_wstrb": 0xF}
    if clock + 1 in reads:
        bus.update(s_axi_araddr=reads[clock + 1] * 4, s_axi_arvalid=1)
    if clock + 1 in writes:
        adr, value = writes[clock + 1]
        bus.update(s_axi_awaddr=adr * 4, s_axi_awvalid=1, s_axi_wdata=value, s_axi_wvalid=1)
    return bus


@cocotb.test()
async def top_short_edge_timing(dut):
    """docs/top.md, "Short edges" and "Interrupt", clock by clock, with expectations computed
    from the docs' sentences, not from the model: a short edge aimed as in issue 30 (PERIOD 40,
    DEAD 64, MIN_PULSE 0, IRQ_ENABLE = SHORT_EDGE; leg 0 commanded up, then back down before its
    upper switch turned on), found on the pins; IRQ_STATUS cleared two clocks before the edge
    and read in the edge's clock and in each of the three after it (one run each, from a
    reset): SHORT_EDGE clear in the edge's clock, set from the next; ``irq`` low up to the
    clock after the edge, high from the one after that. The carried model steps along (every
    output equal to it as well)."""
    from cocotb.triggers import ReadOnly, RisingEdge

    p = params()
    bench = begin(p, seeded_rng(dut, "top_short_edge_timing"))
    model = bench.model
    n, mask = model.phases, (1 << model.phases) - 1
    beat = [1000, *([-1000 // (n - 1)] * (n - 1))]     # leg 0 just above the others
    setup = {2: (regs.PERIOD, AIMED["period"]), 4: (regs.DEAD, AIMED["dead"]),
             6: (regs.MIN_PULSE, 0), 8: (regs.IRQ_ENABLE, regs.IRQ_SHORT_EDGE),
             10: (regs.CTRL, regs.CTRL_ENABLE)}
    await start(dut)
    last = {}

    async def run(cycles, reads, writes):
        """From a reset (two clocks): ``cycles`` clocks; returns what the DUT showed in each,
        the gates in the active-high domain, and the data of each read by its issue clock."""
        nonlocal last
        shown = {k: [] for k in ("sync_out", "up0", "lo0", "irq")}
        data = {}
        for clock in range(-2, cycles):
            bus = {name: 0 for name in model.front.INPUTS} | aimed_inputs(p, clock, reads, writes)
            inputs = {"rst": int(clock < 0), "fault_in": 0, "sync_in": 0, **bus}
            for name, value in inputs.items():
                getattr(dut, port_name(name)).value = value
            dut.ref__valid.value = 1
            dut.ref__payload.value = pack(beat, model.width)
            want = model.step(**inputs, ref_valid=1, ref=beat)
            last = {**bus, "fault_in": 0, "sync_in": 0}
            await ReadOnly()
            got = {name: int(getattr(dut, port).value) for port, name in bench.outputs.items()}
            assert got == {name: want[name] for name in got}, (clock, got, want)
            if clock >= 0:
                up = got["upper"] ^ (mask if model.driver.upper_active_low else 0)
                lo = got["lower"] ^ (mask if model.driver.lower_active_low else 0)
                for key, value in (("sync_out", got["sync_out"]), ("up0", up & 1),
                                   ("lo0", lo & 1), ("irq", got["irq"])):
                    shown[key].append(value)
                answered = clock - 1        # the read issued in the clock before answers now
                if answered in reads:
                    data[answered] = got["wb_dat_r" if "wb_dat_r" in got else "s_axi_rdata"]
            await RisingEdge(dut.clk)
        return shown, data

    shown, data = await run(40 + 800, {20: regs.INFO}, setup)
    latency = (data[20] & regs.INFO_LATENCY) >> regs.INFO_LATENCY_SHIFT
    t = aimed_short_edge(shown["sync_out"], shown["up0"], shown["lo0"], latency)
    assert t is not None and t > 40, "no short edge aimed: the test is vacuous"
    status, irq = [], []
    for k in range(4):
        reads = {20: regs.INFO, t + k: regs.IRQ_STATUS}
        shown, data = await run(t + AIMED["dead"] + 8, reads,
                                {**setup, t - 2: (regs.IRQ_STATUS, 0xFFFFFFFF)})
        assert aimed_short_edge(shown["sync_out"], shown["up0"], shown["lo0"], latency) == t
        status.append(int(bool(data[t + k] & regs.IRQ_SHORT_EDGE)))
        irq.append(shown["irq"][t - 1:t + 8])
    assert status == [0, 1, 1, 1], \
        f"IRQ_STATUS.SHORT_EDGE read in clocks t .. t + 3 (t: the short edge): {status}"
    for seen in irq:
        assert seen == [0, 0, 0] + [1] * 6, f"irq in clocks t - 1 .. t + 7: {seen}"
    CARRY["single"] = (model, last)
    dut._log.info("top_short_edge_timing: short edge in clock %d; IRQ_STATUS.SHORT_EDGE set "
                  "from %d, irq from %d, as documented", t, t + 1, t + 2)


# last of the tests in one simulation: its extreme DEAD writes leave a dead time in force of up
# to 65535 clocks, kept through the reset by design, which would hold the short-edge test's
# gates off
@cocotb.test()
async def top_bad_input(dut):
    """Random addresses and values, resets, faults and sync pulses: the gates stay safe."""
    await run_bench(dut, "top_bad_input", build_bad_input, modes_seen=set())


@pytest.mark.parametrize(("phases", "width", "rule", "dead_min", "upper_low", "lower_low", "bus",
                          "counter_width", "max_bits", "asc"), CASES)
def test_top(phases, width, rule, dead_min, upper_low, lower_low, bus, counter_width, max_bits,
             asc):
    run_block(lambda: MdfqmTop(phases, width, rule, dead_min, upper_low, lower_low, bus=bus,
                               counter_width=counter_width, max_bits=max_bits, asc=asc),
              "mdfqm_top", "test_top",
              {"phases": phases, "width": width, "rule": rule, "dead_min": dead_min,
               "upper_active_low": upper_low, "lower_active_low": lower_low, "bus": bus,
               "counter_width": counter_width, "max_bits": max_bits, "asc": asc},
              testcase=SINGLE_TESTS)


# ---------------------------------------------------------------------- two instances


class TopPair(wiring.Component):
    """Two tops sharing update boundaries: ``a.sync_out`` drives ``b``'s core ``sync_in``
    (the ``b__sync_in`` port is left unconnected); every other port is brought out."""

    def __init__(self, **kwargs):
        self.top_a, self.top_b = MdfqmTop(**kwargs), MdfqmTop(**kwargs)
        signature = self.top_a.signature
        super().__init__({"a": Out(signature), "b": Out(signature)})

    def elaborate(self, platform):
        m = Module()
        m.submodules.a = a = self.top_a
        m.submodules.b = b = self.top_b
        for top, outer in ((a, self.a), (b, self.b)):
            inner_ports = top.signature.flatten(top)
            outer_ports = top.signature.flatten(outer)
            for (path, member, inner), (_, _, port) in zip(inner_ports, outer_ports, strict=True):
                if top is b and path == ("sync_in",):
                    m.d.comb += inner.eq(a.sync_out)
                elif member.flow == In:
                    m.d.comb += inner.eq(port)
                else:
                    m.d.comb += port.eq(inner)
        return m


@cocotb.test()
async def top_pair_sync(dut):
    """Instance b follows a's update boundaries one clock later, whatever its own period (as
    long as it is not shorter; with an equal period it may also run in step with a); the ADC
    triggers follow too."""
    p = params()
    rng = seeded_rng(dut, "top_pair_sync")
    a = begin(p, rng, "a", "a__")
    b = begin(p, rng, "b", "b__")
    latency = a.model.latency
    for phase in range(4):
        period_a = rng.choice([latency, 20, 31])
        # b's own period, never shorter; equal only without a's random syncs: a sync that a
        # takes while b, in step, ignores it (before phase + 1 >= L) leaves b a clock behind
        # for the rest of the window, or for good when the period is the latency
        period_b = period_a + rng.choice([1, 9, 40] if phase == 3 else [0, 1, 9, 40])
        offset = rng.randrange(period_a)
        configure(a, period=period_a, dead=3, adc_offset=offset)
        configure(b, period=period_b, dead=5, adc_offset=offset)
        settle = None
        for cycle in range(2500):
            if a.idle() and b.idle() and settle is None:
                # b ignores a start of a's that falls in its own first L - 1 clocks, and
                # drifts out of them by period_b - period_a clocks an update: pulled to a within
                # L + 1 updates of b's (or in step with a from the start, at equal periods)
                settle = a.cycle + (latency + 2) * period_b
            out_a = a.tick(sync_in=int(phase == 3 and rng.random() < 0.02))
            b.tick(sync_in=out_a["sync_out"])
            if cycle % 500 == 499:
                for bench in (a, b):
                    bench.read(regs.EVENTS_TOTAL)
        sa = np.array(a.expected["a__sync_out"][settle:])
        sb = np.array(b.expected["b__sync_out"][settle:])
        aa = np.array(a.expected["a__adc_trigger"][settle:])
        ab = np.array(b.expected["b__adc_trigger"][settle:])
        # b starts one clock after a; with equal periods it may already start with a (e.g.
        # from a common reset), and a sync_in at b's own start is ignored: lag 0
        lag = 0 if (sb == sa).all() else 1
        assert lag == 1 or period_b == period_a, "b with a longer period not pulled to a"
        assert (sb[lag:] == sa[:len(sa) - lag]).all() and sa.sum() > 10, "b does not follow a"
        assert (ab[lag:] == aa[:len(aa) - lag]).all() and aa.sum() > 10, "ADC triggers differ"
    turn_ons = finish(a, "a") + finish(b, "b")
    stim = {**a.stim, **b.stim}
    stim["rst"] = a.stim["a__rst"]
    del stim["a__rst"], stim["b__rst"]
    await start(dut)
    checked = await check_cycles(dut, stim, {**a.expected, **b.expected})
    dut._log.info("top_pair_sync: %d cycles, %d turn-ons, every output of both instances equal "
                  "to the models", checked, turn_ons)


def test_top_pair():
    phases, width, dead_min = 3, 12, 2
    run_block(lambda: TopPair(phases=phases, width=width, dead_min=dead_min), "mdfqm_top_pair",
              "test_top", {"phases": phases, "width": width, "rule": "largest_duty",
                           "dead_min": dead_min, "upper_active_low": False,
                           "lower_active_low": False},
              testcase="top_pair_sync")


# ---------------------------------------------------------------------- parameters


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer in [3, 16] (the register map holds 16 legs), "
                    "not 2"),
    ({"phases": 17}, "phases must be an integer in [3, 16] (the register map holds 16 legs), "
                     "not 17"),
    ({"width": 7}, "width must be an integer in [8, 32] for 3 phases "
                   "(FULL = 2**(width-2) >= 16 * phases), not 7"),
    ({"rule": "nearest"}, "rule must be one of ('largest_duty', 'exact_nearest'), not 'nearest'"),
    ({"dead_min": 0}, "dead_min must be an integer in [1, 65535] (clocks), not 0"),
    ({"dead_min": 65536}, "dead_min must be an integer in [1, 65535] (clocks), not 65536"),
    ({"upper_active_low": 1}, "upper_active_low must be a bool, not 1"),
    ({"lower_active_low": "low"}, "lower_active_low must be a bool, not 'low'"),
    ({"formal": None}, "formal must be a bool, not None"),
    ({"asc": 1}, "asc must be a bool, not 1"),
    ({"bus": "apb"}, "bus must be one of ('wishbone', 'axi4lite'), not 'apb'"),
    ({"counter_width": 7}, "counter_width must be an integer in [8, 32], not 7"),
    ({"max_bits": 15}, "max_bits must be an integer in [1, 12] for a 16-bit reference "
                       "(2**max_bits slots <= FULL, at most 12), not 15 (or 0: MDFQM only)"),
    ({"width": 9, "max_bits": 8}, "max_bits must be an integer in [1, 7] for a 9-bit reference "
                                  "(2**max_bits slots <= FULL, at most 12), not 8 "
                                  "(or 0: MDFQM only)"),
])
def test_top_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        MdfqmTop(**kwargs)
    assert str(info.value) == message


def test_top_formal_build_differs_only_by_properties():
    from amaranth.back import verilog

    plain = verilog.convert(MdfqmTop(3, 16), name="t", emit_src=False)
    assert "assert" not in plain
    assert "assert" in verilog.convert(MdfqmTop(3, 16, formal=True), name="t", emit_src=False)


def test_docs_port_table_matches_the_signature():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "top.md").read_text()
    documented = []
    for line in text.split("## Ports", 1)[1].split("## Register map", 1)[0].splitlines():
        cells = [c.strip().strip("`") for c in line.strip().strip("|").split("|")]
        if len(cells) == 4 and cells[1] in ("in", "out"):
            documented.append((cells[0], cells[1]))
    ports = {("clk", "in"), ("rst", "in")}
    for bus in ("wishbone", "axi4lite"):
        top = MdfqmTop(3, 16, bus=bus)
        ports |= {("__".join(map(str, path)), "in" if member.flow == In else "out")
                  for path, member, _ in top.signature.flatten(top)}
    assert sorted(documented) == sorted(ports)
