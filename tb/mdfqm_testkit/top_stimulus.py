"""Closed-loop stimulus for the drop-in top (either front, any size), with the expected
outputs from :class:`mdfqm_model.top.TopModel`: used by the drop-in files' vector runs
(tb/test_dropin_files.py) and the top's long vector regression (tb/test_top_vectors.py)."""

import math
from collections import deque

from mdfqm_model.top import TopModel
from mdfqm_spec import regmap as regs
from mdfqm_spec.contract import MODES, Contract
from mdfqm_testkit.bbit_stimulus import boundary_codes, tie_codes
from mdfqm_testkit.core_stimulus import extreme_codes, sine_codes
from mdfqm_testkit.harness import pack
from mdfqm_testkit.vectors import ports_of

#: (cyc, stb) of an idle Wishbone master clock: neither, cyc alone, stb alone (never a request)
IDLE_WISHBONE = ((0, 0), (0, 0), (1, 0), (0, 1))


#: the events a register write or command can meet in one clock (``census`` of top_stimulus)
COINCIDENT = ("beat", "fault", "sync", "turn_on")


def top_stimulus(rng, component, phases, width, cycles, census=None):
    """The drop-in top under a bus master (one access at a time, random gaps and ready stalls;
    Wishbone or AXI4-Lite as the component's), a reference stream that reacts to ``ready``
    (sines from near zero into overmodulation, extreme codes, ties), a fault pulse and its
    clear, a stall of the stream (the watchdog on at times, TIMEOUT 1, 2 or 8 at its start,
    WATCHDOG_TRIPS polled back to back and the latch cleared now and then meanwhile),
    sync pulses and a reset in the middle and four more (after each reset, a beat whose largest
    candidates tie), and eight reset trials on the b-bit grid (a slot mode written, then one
    beat on the half-slot grid into empty integrators: the quantiser's decision boundaries);
    periods of 20-27 clocks (around the slot modes' minimum), 90-170, 300-1100 with the ADC
    trigger anywhere in them, and now and then 4400-6000 with it past 4096 or 8400-9000 with
    it past 8192; on Wishbone,
    ``cyc`` or ``stb`` alone while idle and ``cyc`` raised before ``stb`` at times; the settings
    make the gates switch within a few thousand clocks; MODULATION written now and then (any
    mode code, any b code, mostly small); a burst of back-to-back
    commands and clears (``CMD`` with random bits, ``IRQ_STATUS`` write-1-to-clear, settings)
    under frequent fault and sync pulses, so that writes land in the same clock as the other
    events; every register written at and beyond its clamps and read back, the gates disabled
    meanwhile; in a run of 200 000 clocks or more, after the burst, one update longer than
    32768 clocks with the ADC trigger in its upper half, in a shorter one with 8600 clocks or
    more left then, one of 9000 with it past 8192. Returns (inputs, expected outputs) by
    port, and the set of modes that were in force in some clock. ``census``, a dict if given,
    counts the clocks where a register write (``write``) or a ``CMD`` write (``command``) is
    issued together with each of :data:`COINCIDENT`: a reference beat taken, the fault input
    high, a sync pulse, a gate turning on; keys like ``("command", "beat")``."""
    axi = component.bus == "axi4lite"
    model = TopModel(phases, width, component.rule, component.dead_min,
                     component.upper_active_low, component.lower_active_low, bus=component.bus,
                     counter_width=component.counter_width, max_bits=component.max_bits,
                     asc=component.asc)
    contract = Contract(phases, width)
    inputs, outputs = ports_of(component)
    stim = {port: [] for port, _ in inputs}
    expected = {port: [] for port, _ in outputs}
    amplitude = 0.5                     # of Vdc

    hold = 0        # no restore of the settings, no random sync before this cycle: a long update
                    # runs out (the aimed syncs below come regardless)
    longer_drawn = False

    def settings(now):
        nonlocal hold, longer_drawn
        # now and then updates longer than 4096 clocks with the ADC trigger past 4096 (the
        # trigger counter's upper bits), left alone (no restore, no sync) for two of them
        long = rng.random() < 0.1 and not missing_modes()     # (a long one holds a mode)
        # the first of them and a third of the others past 8192 with the trigger there too
        # (the counter's bit 13)
        longer = long and (not longer_drawn or rng.random() < 1 / 3)
        longer_drawn |= longer
        # medium ones with the trigger anywhere in them (the counter's bits 8-10), or short
        # ones: 20 to 27 clocks is below the slot modes' 2**b at b = 5 and above it at b <= 4
        # (the minimum there is the long latency, 20)
        medium = not long and rng.random() < 0.15
        period = (rng.randint(8400, 9000) if longer else rng.randint(4400, 6000) if long
                  else rng.randint(300, 1100) if medium
                  else rng.choice([90, 130, 170, rng.randint(20, 27)]))
        if long:
            hold = now + 2 * period
        return deque([(regs.IRQ_ENABLE, 1, regs.IRQ_MASK), (regs.OSR, 1, rng.choice([1, 2])),
                      (regs.PERIOD, 1, period),
                      # a dead time at the floor (0 acts as dead_min) or above it
                      (regs.DEAD, 1, rng.choice([0, component.dead_min,
                                                 component.dead_min + rng.randrange(1, 24)])),
                      (regs.MIN_PULSE, 1, rng.randrange(8)),
                      (regs.ADC_OFFSET, 1, rng.randint(8192 if longer else 4096, period - 1)
                       if long
                       else rng.randrange(period) if medium else rng.randrange(100)),
                      (regs.WATCHDOG, 1, rng.choice([0, 2, 4, 8])),
                      # each source's reaction, any code (3 stores all off)
                      (regs.FAULT_REACTION, 1, rng.randrange(16)),
                      (regs.CTRL, 1, regs.CTRL_ENABLE | rng.randint(0, 1) * regs.CTRL_ZERO_POLICY)])

    def random_write():
        """Any word to any address, but a dead time or minimum pulse of at most 63 clocks: a
        dead time in force is never shortened (docs/top.md), so one of 65535 clocks would stop
        the gates for the rest of a run."""
        address = rng.randrange(64)
        data = rng.choice([0, 1, 3, 90, 0xFFFF]) if rng.random() < 0.3 else rng.getrandbits(32)
        if address in (regs.DEAD, regs.MIN_PULSE):
            data &= 0x3F
        return address, 1, data

    def limit_writes(now):
        """Every register at and beyond the values its clamp changes (docs/top.md, "Every
        clamp"), each read back, with the gates disabled (a dead time or minimum pulse of
        65535 clocks never in force), then the settings again."""
        big = (0xFFFF, 0x10000, 0xFFFFFFFF)
        # walking ones (over the whole word) and zeros: a stuck or swapped bit of a register or
        # of its clamp's compare shows
        walk16 = (*(1 << k for k in range(32)), *(0xFFFF ^ (1 << k) for k in range(16)))
        walk8 = (*(w for k in range(8) for w in (1 << k, 0xFF ^ (1 << k))),
                 *(1 << k for k in range(8, 32)))
        codes = (contract.code_max, contract.code_max + 1, contract.code_min,
                 contract.code_min - 1, (1 << 31) - 1, -(1 << 31),
                 # a single one in a positive word, a single zero in a negative one: each bit
                 # of the clamp's in-range test decides alone
                 *(1 << k for k in range(contract.width - 1, 31)),
                 *(~(1 << k) for k in range(contract.width - 1, 31)))
        values = {regs.PERIOD: (0, 1, *big, *walk16),
                  regs.OSR: (0, 1, 255, 256, 0xFFFFFFFF, *walk8),
                  regs.DEAD: (0, 1, *big, *walk16), regs.MIN_PULSE: (0, *big, *walk16),
                  regs.ADC_OFFSET: (0, *big, *walk16), regs.WATCHDOG: (1, *big, *walk16, 0),
                  regs.MODULATION: (0xFFFFFFFF, 0), regs.IRQ_ENABLE: (0xFFFFFFFF,),
                  regs.FAULT_REACTION: (0xFFFFFFFF, 0b0101, 0b1010, 0b0111, 0b1101, 0),
                  regs.CTRL: (0xFFFFFFFF & ~regs.CTRL_ENABLE,),
                  **{regs.REF_BASE + i: tuple(pack([c], 32) for c in codes)
                     for i in range(phases)}}
        writes = deque([(regs.CTRL, 1, 0)])
        for address, words in values.items():
            for word in words:
                writes += [(address, 1, word), (address, 0, 0)]
        return writes + settings(now)

    mode_codes = []
    modes = set()

    def missing_modes():
        built = len(MODES) if component.max_bits else 1
        return sorted(set(range(built)) - modes)

    def next_mode():
        """A mode not yet in force first, then every mode code (0-7) once in each round, in a
        random order: every mode is in force in a short run too (a mode is taken only at an
        update start, and the next MODULATION write may come first)."""
        if missing_modes():
            return rng.choice(missing_modes())
        if not mode_codes:
            mode_codes.extend(rng.sample(range(8), 8))
        return mode_codes.pop()

    bits_codes = []

    def next_bits():
        """Mostly small b (short updates), else every b of the slot modes in turn (their
        per-b tables: b = 5 and 6 alone set some bits) and now and then any code."""
        if rng.random() < 0.6:
            return rng.choice([1, 2, 3, 15, rng.randrange(16)])
        if not bits_codes:
            bits_codes.extend(rng.sample(range(1, max(component.max_bits, 1) + 1),
                                         max(component.max_bits, 1)))
        return bits_codes.pop()

    ops = settings(0)
    current, gap, angle, offered, lead = None, 0, rng.uniform(0, 2 * math.pi), None, 0
    was_on = 0
    burst_start = cycles * 7 // 10
    burst_end = burst_start + max(4000, cycles // 8)
    aw_done = w_done = ar_done = False
    fault_until = -1
    # resets: at the start, in the middle, and four more short trials of a tie
    resets = {0, cycles // 2, *(cycles * k // 16 for k in (3, 5, 11, 13))}
    # and eight trials on the b-bit grid, each reset before (not inside) the fault pulse, the
    # limit writes, the stall and the burst
    grid_resets = {cycles * k // 64 for k in (3, 7, 9, 15, 19, 22, 35, 37)} - resets
    grid_bits = None       # b of a grid trial whose beat is not yet offered
    # after the burst, in a long run: one update of more than 32768 clocks with the ADC trigger
    # in its upper half (the trigger counter's bit 15); in a run with 8600 clocks or more left
    # after the burst, one of 9000 with the trigger past 8192 (bit 13; the long settings'
    # updates rarely run out between the resets of a short run); started by two sync pulses
    # once the period is written, the firmware quiet meanwhile
    adc_window = burst_end + 1 if cycles - burst_end >= 8600 else None
    aimed_syncs = {burst_end + 200, burst_end + 260} if adc_window else set()
    for cycle in range(cycles):
        rst = int(cycle in resets or cycle in grid_resets)
        if cycle in grid_resets and component.max_bits:
            # a slot mode written first, no beat until every write is done: the updates run
            # with R = 0, the integrators stay empty, and the beat on the half-slot grid goes
            # into the first update of the slot mode (its instants on the quantiser's decision
            # boundaries, as the generator's ``boundaries`` trials)
            ops, current, offered = settings(cycle), None, None
            grid_bits = rng.randint(1, component.max_bits)
            ops.appendleft((regs.MODULATION, 1,
                            rng.randint(1, len(MODES) - 1) << regs.MODULATION_MODE_SHIFT
                            | grid_bits << regs.MODULATION_BITS_SHIFT))
        elif rst:
            ops, current = settings(cycle), None
            # from reset the integrators are empty and MDFQM runs: the first update's
            # largest candidates tie exactly (docs/robustness.md, "equal references")
            offered = (tie_codes(rng, contract, phases) if component.rule == "largest_duty"
                       else boundary_codes(rng, contract, phases, 1))
        if grid_bits is not None and not ops and current is None:
            offered, grid_bits = boundary_codes(rng, contract, phases, grid_bits), None
        firmware_quiet = (adc_window is not None and cycle >= adc_window) or grid_bits is not None
        stalled = cycles * 3 // 5 <= cycle < cycles * 3 // 5 + 3000   # the watchdog's turn
        if stalled and not ops:
            # the firmware polls WATCHDOG_TRIPS back to back while the stream stalls (a read in
            # the tripping start's own clock sees the count before it), and clears the latch
            # now and then once it has tripped (a clear restarts the quiet count), so that it
            # trips again
            ops.append((regs.CMD, 1, regs.CMD_WATCHDOG_CLEAR)
                       if model.wd_tripped and rng.random() < 0.2 else (regs.WATCHDOG_TRIPS, 0, 0))
        if not ops and not firmware_quiet and rng.random() < 0.02:   # firmware: reads, settings
            ops.extend(rng.choice([
                [(rng.randrange(64), 0, 0)],
                [(regs.REF_BASE + i, 1, pack([rng.randrange(-40000, 40000)], 32))
                 for i in range(phases)] + [(regs.CMD, 1, regs.CMD_REF_COMMIT)],
                [(regs.CMD, 1, regs.CMD_FAULT_CLEAR), (regs.STATUS, 0, 0)],
                [(regs.CMD, 1, regs.CMD_COUNT_CLEAR), (regs.EVENTS_TOTAL, 0, 0)],
                [(regs.IRQ_STATUS, 0, 0), (regs.IRQ_STATUS, 1, regs.IRQ_MASK)],
                [random_write()],
                [(regs.MODULATION, 1, next_mode() << regs.MODULATION_MODE_SHIFT
                  | next_bits() << regs.MODULATION_BITS_SHIFT),
                 (regs.MODULATION, 0, 0)],
                [(regs.CMD, 1, regs.CMD_WATCHDOG_CLEAR), (regs.WATCHDOG_TRIPS, 0, 0)],
                # the firmware's step from an active short circuit to all off
                [(regs.CMD, 1, regs.CMD_ALL_OFF), (regs.STATUS, 0, 0)],
                # every switching counter read (not only right after a clear)
                [(regs.EVENTS_BASE + i, 0, 0) for i in range(phases)]
                + [(regs.EVENTS_TOTAL, 0, 0)],
            ]))
        burst = burst_start <= cycle < burst_end
        # firmware restoring its settings now and then (random writes may leave a dead time
        # of 65535 clocks or the enable off: the gates would stop switching for good)
        if cycle == burst_end or (not ops and cycle >= hold and rng.random() < 0.0005):
            ops.extend(settings(cycle))
            ops.append((regs.CMD, 1, regs.CMD_FAULT_CLEAR | regs.CMD_WATCHDOG_CLEAR))
        if burst and not ops:
            ops.append(rng.choice([
                (regs.CMD, 1, rng.randrange(32)),
                (regs.CMD, 1, rng.randrange(32) & ~regs.CMD_REF_COMMIT),  # the port served
                (regs.IRQ_STATUS, 1, rng.getrandbits(32)), (regs.IRQ_STATUS, 0, 0),
                random_write(), random_write(),
            ]))
            gap = 0
        if cycle == adc_window:
            period, offset = ((rng.randint(33_500, 34_500), rng.randint(32_768, 33_300))
                              if cycles >= 200_000
                              else (9000, rng.randint(8192, cycles - burst_end - 300)))
            ops.extend([(regs.PERIOD, 1, period), (regs.ADC_OFFSET, 1, offset)])
            hold = cycle + 2 * period
        if cycle == cycles * 2 // 5:           # every register at its clamps
            ops.extend(limit_writes(cycle))
        if cycle == cycles * 3 // 5:           # the stall starts: a short timeout first
            ops.appendleft((regs.WATCHDOG, 1, rng.choice([1, 2, 8])))
            if rng.random() < 0.75:            # and mostly short updates: many trips
                ops.appendleft((regs.PERIOD, 1, rng.choice([90, rng.randint(20, 27)])))
                aimed_syncs.add(cycle + 40)      # in force at once (a sync once it is written)
        if current is None and ops and gap == 0:
            current, aw_done, w_done, ar_done = ops.popleft(), False, False, False
            lead = rng.choice([0, 0, 0, 1, 2])     # Wishbone: cyc raised before stb
        gap = max(0, gap - 1)
        adr, we, data = current or (rng.randrange(64), rng.randint(0, 1), rng.getrandbits(32))
        busy = current is not None
        if axi:
            byte = adr << 2 | rng.randrange(4)
            bus = {"s_axi_awaddr": byte, "s_axi_awprot": rng.randrange(8),
                   "s_axi_awvalid": int(busy and we and not aw_done), "s_axi_wdata": data,
                   "s_axi_wstrb": rng.randrange(16),
                   "s_axi_wvalid": int(busy and we and not w_done),
                   "s_axi_bready": int(rng.random() < 0.6), "s_axi_araddr": byte,
                   "s_axi_arprot": rng.randrange(8),
                   "s_axi_arvalid": int(busy and not we and not ar_done),
                   "s_axi_rready": int(rng.random() < 0.6)}
        else:
            # idle: cyc or stb alone (a master holding the bus, a shared strobe), never both;
            # an access: cyc, then stb after ``lead`` clocks, both held until ack
            cyc, stb = (1, int(lead == 0)) if busy else rng.choice(IDLE_WISHBONE)
            lead = max(0, lead - 1)
            bus = {"wb_cyc": cyc, "wb_stb": stb, "wb_we": we, "wb_adr": adr,
                   "wb_dat_w": data, "wb_sel": rng.choice([0xF, 0xF, 0x1, 0x0])}
        if offered is None and not stalled and grid_bits is None and rng.random() < 0.3:
            angle += 0.05
            pick = rng.random()
            if pick < 0.1:                      # the ends and the middle of the code range
                offered = extreme_codes(rng, contract, phases)
            elif pick < 0.2:                    # ties
                level = rng.randint(contract.code_min, contract.code_max)
                offered = [rng.choice([level, -level // 2, 0]) for _ in range(phases)]
            else:
                offered = sine_codes(contract, amplitude, angle)
        if cycle % 5000 == 0:                   # from near zero into overmodulation
            amplitude = rng.uniform(0.05, 1.0)
        if cycle == cycles // 4:
            fault_until = cycle + rng.randrange(3, 20)
        if burst and rng.random() < 0.01:
            fault_until = cycle + rng.randrange(3)
        fault_in = int(cycle <= fault_until)
        sync_in = int(cycle in aimed_syncs
                      or (cycle >= hold and rng.random() < (0.05 if burst else 0.003)))
        payload, valid = offered or [0] * phases, int(offered is not None)
        modes.add(getattr(model.core, "mode_lat", 0))
        if census is not None and not rst:
            write, _ = model.front.access({name: bus.get(name, 0) for name in model.front.INPUTS})
            on = model.driver.up | model.driver.lo
            happening = {"beat": valid and model.ref_ready, "fault": fault_in, "sync": sync_in,
                         "turn_on": on & ~was_on}
            for kind in ("write", "command"):
                if write is not None and (kind == "write" or write[0] == regs.CMD):
                    for event in COINCIDENT:
                        if happening[event]:
                            census[kind, event] = census.get((kind, event), 0) + 1
            was_on = on
        out = model.step(rst=rst, ref_valid=valid, ref=payload,
                         fault_in=fault_in, sync_in=sync_in, **bus)
        if offered is not None and out["ref_ready"] and not rst:
            offered = None
        if busy and not rst:                      # the master sees this cycle's outputs
            if axi:
                aw_done |= bool(bus["s_axi_awvalid"] and out["s_axi_awready"])
                w_done |= bool(bus["s_axi_wvalid"] and out["s_axi_wready"])
                ar_done |= bool(bus["s_axi_arvalid"] and out["s_axi_arready"])
                done = ((out["s_axi_bvalid"] and bus["s_axi_bready"]) if we
                        else (out["s_axi_rvalid"] and bus["s_axi_rready"]))
            else:
                done = out["wb_ack"]
            if done:
                current, gap = None, rng.choice([0, 0, 1, 3])
        values = {"rst": rst, "ref_valid": valid, "ref_payload": pack(payload, width),
                  "fault_in": fault_in, "sync_in": sync_in, **bus}
        for port, _ in inputs:                    # model names: wb__ack -> wb_ack
            stim[port].append(values[port.replace("__", "_")])
        for port, _ in outputs:
            expected[port].append(out[port.replace("__", "_")])
    return stim, expected, modes
