"""A cycle-level bench of the drop-in top for the cocotb tests (tb/test_top.py, and the tests
that reuse its model or port names): the bus masters of both fronts, an FOC-like stream
source, the fault and sync inputs, with the expected outputs from
:class:`mdfqm_model.top.TopModel` every clock and the traces of the independent checks."""

import math
from collections import deque

import numpy as np

from mdfqm_model.driver import check_gate_safety
from mdfqm_model.top import TopModel
from mdfqm_spec import regmap as regs
from mdfqm_spec.contract import MODES
from mdfqm_testkit.harness import pack
from mdfqm_testkit.top_stimulus import IDLE_WISHBONE

COMMON_INPUTS = ("rst", "ref__valid", "ref__payload", "fault_in", "sync_in")
COMMON_OUTPUTS = {"ref__ready": "ref_ready", "upper": "upper", "lower": "lower",
                  "adc_trigger": "adc_trigger", "sync_out": "sync_out", "fault": "fault",
                  "irq": "irq"}


def port_name(name: str) -> str:
    """The Verilog port of a bus input or output of the model (``wb_ack`` -> ``wb__ack``)."""
    for bus in ("wb_", "s_axi_"):
        if name.startswith(bus):
            return bus + "_" + name[len(bus):]
    return name


def make_model(p):
    return TopModel(p["phases"], p["width"], p["rule"], p["dead_min"], p["upper_active_low"],
                    p["lower_active_low"], bus=p.get("bus", "wishbone"),
                    counter_width=p.get("counter_width", 32), max_bits=p.get("max_bits"),
                    asc=p.get("asc", True))


class WishboneMaster:
    """One operation at a time: ``cyc`` raised, ``stb`` with it or up to two clocks later, both
    held until ``ack``; idle gaps between, with ``cyc`` or ``stb`` alone at random (never
    both) and random address, data and ``sel``."""

    def __init__(self, rng):
        self.rng, self.current, self.gap, self.lead = rng, None, 0, 0

    def busy(self):
        return self.current is not None

    def inputs(self, ops):
        rng = self.rng
        if self.current is None and self.gap == 0 and ops:
            self.current, self.lead = ops.popleft(), rng.choice([0, 0, 0, 1, 2])
        adr, we, dat = self.current or (rng.randrange(64), rng.randint(0, 1), rng.getrandbits(32))
        if self.current is None:
            cyc, stb = rng.choice(IDLE_WISHBONE)
        else:
            cyc, stb = 1, int(self.lead == 0)
            self.lead = max(0, self.lead - 1)
        return {"wb_cyc": cyc, "wb_stb": stb, "wb_we": we, "wb_adr": adr, "wb_dat_w": dat,
                "wb_sel": rng.choice([0xF, 0xF, 0x1, 0x0])}

    def observe(self, bus, out):
        """The read data of an operation that completed this cycle (None for a write)."""
        done = None
        if self.current is not None and out["wb_ack"]:
            done = [None if self.current[1] else out["wb_dat_r"]]
            self.current, self.gap = None, self.rng.choice([0, 0, 1, 2])
        elif self.current is None and self.gap:
            self.gap -= 1
        return done

    def abort(self):
        self.current, self.gap = None, 0


class AxiLiteMaster:
    """Accesses started in queue order, a write's AW and W (and a read's AR) raised after their
    own random delays and held, with their payload, until taken; the next write's AW/W (read's
    AR) may start while the previous one waits for its response, so responses meet
    back-pressure with the next access ready; ``bready`` and ``rready`` at random; random
    payloads on idle channels."""

    def __init__(self, rng):
        self.rng, self.writes, self.reads, self.gap = rng, deque(), deque(), 0

    def busy(self):
        return bool(self.writes or self.reads)

    @staticmethod
    def _addressing(ops, channels):
        """The op of ``ops`` still in its address/data phase, if any (the newest)."""
        return ops[-1] if ops and not set(channels) <= ops[-1]["done"] else None

    def inputs(self, ops):
        rng = self.rng
        while self.gap == 0 and ops:
            adr, we, dat = ops[0]
            queue, channels = (self.writes, ("aw", "w")) if we else (self.reads, ("ar",))
            if self._addressing(queue, channels) is not None or len(queue) >= 2:
                break
            ops.popleft()
            queue.append({"adr": adr * 4 + rng.randrange(4), "dat": dat, "done": set(),
                          "wait": {ch: rng.choice([0, 0, 0, 1, 3]) for ch in channels}})
        w = self._addressing(self.writes, ("aw", "w"))
        r = self._addressing(self.reads, ("ar",))

        def raised(op, channel):
            return int(op is not None and channel not in op["done"] and op["wait"][channel] == 0)

        self.current = {"aw": w, "w": w, "ar": r}
        self.raised = {ch: raised(op, ch) for ch, op in self.current.items()}
        return {
            "s_axi_awvalid": self.raised["aw"], "s_axi_wvalid": self.raised["w"],
            "s_axi_arvalid": self.raised["ar"],
            "s_axi_awaddr": w["adr"] if w else rng.randrange(256),
            "s_axi_wdata": w["dat"] if w else rng.getrandbits(32),
            "s_axi_araddr": r["adr"] if r else rng.randrange(256),
            "s_axi_wstrb": rng.choice([0xF, 0xF, 0x3, 0x0]), "s_axi_awprot": rng.randrange(8),
            "s_axi_arprot": rng.randrange(8),
            "s_axi_bready": int(rng.random() < 0.6), "s_axi_rready": int(rng.random() < 0.6),
        }

    def observe(self, bus, out):
        """The read data of the access that completed this cycle: ``[value]`` for a read,
        ``[None]`` for a write, None when nothing completed (B and R together: the read's)."""
        for ch, op in self.current.items():
            if op is None or ch in op["done"]:
                continue
            if self.raised[ch] and out[f"s_axi_{ch}ready"]:
                op["done"].add(ch)
            elif not self.raised[ch]:
                op["wait"][ch] -= 1
        done = None
        if out["s_axi_bvalid"] and bus["s_axi_bready"]:
            assert self.writes and {"aw", "w"} <= self.writes[0]["done"], "B without a write"
            self.writes.popleft()
            done = [None]
        if out["s_axi_rvalid"] and bus["s_axi_rready"]:
            assert self.reads and "ar" in self.reads[0]["done"], "R without a read"
            self.reads.popleft()
            done = [out["s_axi_rdata"]]
        if done is not None:
            self.gap = self.rng.choice([0, 0, 0, 1, 2])
        elif self.gap:
            self.gap -= 1
        return done

    def abort(self):
        self.writes.clear()
        self.reads.clear()
        self.gap = 0


MASTERS = {"wishbone": WishboneMaster, "axi4lite": AxiLiteMaster}


class Bench:
    """Closed-loop stimulus for one TopModel: a bus master of its front (operations queued and
    issued in order, handshakes as the bus allows, idle gaps between), an FOC-like stream source
    (holds a beat until accepted, idles at random), and the fault / sync inputs. Records the
    inputs and the expected outputs of every cycle, and the independent-check traces."""

    def __init__(self, rng, model, prefix=""):
        self.rng, self.model, self.prefix = rng, model, prefix
        self.n = model.phases
        self.ops = deque()
        self.master = MASTERS["wishbone" if "wb_cyc" in model.front.INPUTS else "axi4lite"](rng)
        self.offered = None
        inputs = (*COMMON_INPUTS, *(port_name(k) for k in model.front.INPUTS))
        outputs = {**{port_name(k): k for k in model.front.OUTPUTS}, **COMMON_OUTPUTS}
        self.outputs = outputs
        self.stim = {prefix + name: [] for name in inputs}
        self.expected = {prefix + name: [] for name in outputs}
        self.trace = {k: [] for k in ("up", "lo", "dead", "kill", "rst", "adc_offset",
                                      "count_clear", "short_edge", "mode", "watchdog",
                                      "reaction", "all_off")}
        self.mode_cycle = []         # MODULATION modes still to be written (random order)
        self.issued_reads = deque()  # (issue cycle, address) of reads not yet answered
        self.reads = []          # (issue cycle, address, value)
        self.last = {}           # the last cycle's inputs, held through the reset of the next run
        self.cycle = 0
        self.angle, self.step_angle, self.amplitude = rng.uniform(0, 6.3), 0.02, 0.5

    # ------------------------------------------------------------------ bus operations
    def write(self, address, value):
        self.ops.append((address, 1, value & 0xFFFFFFFF))

    def read(self, address):
        self.ops.append((address, 0, self.rng.getrandbits(32)))

    def idle(self):
        return not self.master.busy() and not self.ops

    def modulation(self, mode=None, bits=None):
        """Write MODULATION: the given mode and b, or random ones (mostly legal, small b so
        that updates stay short; now and then a mode not built in, b 0, above max_bits, 15)."""
        rng = self.rng
        if mode is None:
            if not self.mode_cycle:             # every mode within each six writes
                self.mode_cycle = [*range(len(MODES)), rng.randrange(8)]
                rng.shuffle(self.mode_cycle)
            mode = self.mode_cycle.pop()
        if bits is None:
            bits = rng.choice([1, 1, 2, 2, 3, 4, 0, 15, rng.randrange(16)])
        self.write(regs.MODULATION, mode << regs.MODULATION_MODE_SHIFT
                   | bits << regs.MODULATION_BITS_SHIFT | rng.choice([0, 0, 0xF0F8]))
        self.read(regs.MODULATION)

    def sine_beat(self):
        c = self.model.contract
        self.angle += self.step_angle
        return [max(c.code_min, min(c.code_max, round(
            self.amplitude * c.full * math.cos(self.angle - 2 * math.pi * i / self.n))))
            for i in range(self.n)]

    # ------------------------------------------------------------------ one clock
    def tick(self, rst=0, fault_in=0, sync_in=0, stream=True, source_rate=0.6):
        rng, m = self.rng, self.model
        bus = self.master.inputs(self.ops)
        if self.offered is None and stream and rng.random() < source_rate:
            self.offered = self.sine_beat()
        write, read = m.front.access(bus)
        t = self.trace
        t["dead"].append(m.driver.dead_in_force)     # the legs act on last clock's DEAD
        t["kill"].append(m.driver.fault_input | m.wd_tripped)    # the watchdog: driver stop
        t["rst"].append(rst)
        t["adc_offset"].append(m.adc_offset)
        t["count_clear"].append(int(not rst and write is not None and write[0] == regs.CMD
                                    and bool(write[1] & regs.CMD_COUNT_CLEAR)))
        t["up"].append(m.driver.up)
        t["lo"].append(m.driver.lo)
        t["short_edge"].append(m.driver.short_edge)
        t["watchdog"].append(m.wd_tripped)
        t["reaction"].append(m.driver.reaction)
        t["all_off"].append(int(not rst and write is not None and write[0] == regs.CMD
                                and bool(write[1] & regs.CMD_ALL_OFF)))
        t["mode"].append(getattr(m.core, "mode_lat", 0))
        if read is not None and not rst:
            self.issued_reads.append((self.cycle, read))
        payload, ref_valid = self.offered or [0] * self.n, int(self.offered is not None)
        out = m.step(rst=rst, ref_valid=ref_valid, ref=payload, fault_in=fault_in,
                     sync_in=sync_in, **bus)
        if ref_valid and out["ref_ready"] and not rst:
            self.offered = None
        done = self.master.observe(bus, out)
        if done is not None and done[0] is not None:
            self.reads.append((*self.issued_reads.popleft(), done[0]))
        if rst:
            self.master.abort()
            self.issued_reads.clear()
        self.last = {**bus, "fault_in": fault_in, "sync_in": sync_in}
        inputs = {"rst": rst, "ref__valid": ref_valid, "ref__payload": pack(payload, m.width),
                  "fault_in": fault_in, "sync_in": sync_in,
                  **{port_name(k): v for k, v in bus.items()}}
        for name, value in inputs.items():
            self.stim[self.prefix + name].append(value)
        for port, key in self.outputs.items():
            self.expected[self.prefix + port].append(out[key])
        self.cycle += 1
        return out

    def run_until_idle(self, limit=10000, **kw):
        for _ in range(limit):
            if self.idle():
                return
            self.tick(**kw)
        raise AssertionError("bus operations did not complete")

    # ------------------------------------------------------------------ independent checks
    def check_safety(self, dt_run0):
        up, lo = np.array(self.trace["up"]), np.array(self.trace["lo"])
        dead = np.maximum(np.array(self.trace["dead"]), self.model.dead_min)
        return check_gate_safety(up, lo, self.n, dead=dead, kill=self.trace["kill"],
                                 rst=self.trace["rst"], dt_run0=dt_run0,
                                 reaction=self.trace["reaction"])
