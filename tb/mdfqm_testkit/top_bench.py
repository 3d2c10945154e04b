"""A cycle-level bench of the drop-in top for the cocotb tests (tb/test_top.py, and the tests
that reuse its model or port names): the bus masters of both fronts (the project's one master
of each kind, :mod:`mdfqm_testkit.bus_masters`, importable from here too), an FOC-like stream
source, the fault and sync inputs, with the expected outputs from
:class:`mdfqm_model.top.TopModel` every clock and the traces of the independent checks."""

import math
from collections import deque

import numpy as np

from mdfqm_model.driver import check_gate_safety
from mdfqm_model.top import TopModel
from mdfqm_spec import regmap as regs
from mdfqm_spec.contract import MODES
from mdfqm_testkit.bus_masters import (
    IDLE_WISHBONE,
    MASTERS,
    Access,
    AxiLiteMaster,
    AxiLitePolicy,
    WishboneMaster,
    WishbonePolicy,
)
from mdfqm_testkit.harness import pack

#: the bus masters are the project's (mdfqm_testkit.bus_masters); imported from here too
__all__ = ["COMMON_INPUTS", "COMMON_OUTPUTS", "IDLE_WISHBONE", "MASTERS", "Access",
           "AxiLiteMaster", "AxiLitePolicy", "Bench", "WishboneMaster", "WishbonePolicy",
           "make_model", "port_name"]

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
                    asc=p.get("asc", True), watchdog=p.get("watchdog", True))




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
        _, read = m.front.access(bus)
        write = m.write_taken           # the write the register file takes in this clock
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
