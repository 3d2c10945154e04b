"""Write the drop-in Verilog files (core, generator, top) and report what was built.

    mdfqm-dropin --out build/generated [--phases 3 --width 16] [--lint]
    python -m mdfqm_gateware.dropin ...                 # the same; `make` runs it

``--lint`` also runs ``verilator --lint-only -Wall`` on every generated file and fails on any
warning.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

from amaranth.back import verilog

from .core import MdfqmCore
from .generator import GatingSignalGenerator
from .top import MdfqmTop

__all__ = [
    "AMARANTH_STYLE_WAIVERS",
    "DROP_IN_MAX_BITS",
    "default_configs",
    "lint",
    "main",
    "port_table",
]


#: the generator's finest resolution in the drop-in file: 2**8 slots per update (SVPWM with an
#: 8-bit duty), or fewer when the width leaves less room
DROP_IN_MAX_BITS = 8


#: (module name, constructor) of every drop-in file `make` writes
def default_configs(phases: int, width: int):
    bits = min(DROP_IN_MAX_BITS, width - 2)
    return [
        (f"mdfqm_core_n{phases}_w{width}", lambda: MdfqmCore(phases, width)),
        (f"mdfqm_generator_n{phases}_w{width}_b{bits}",
         lambda: GatingSignalGenerator(phases, width, max_bits=bits)),
        (f"mdfqm_top_n{phases}_w{width}", lambda: MdfqmTop(phases, width)),
        (f"mdfqm_top_axil_n{phases}_w{width}",
         lambda: MdfqmTop(phases, width, bus="axi4lite")),
    ]


def port_table(component) -> list[str]:
    rows = []
    for path, member, _ in component.signature.flatten(component):
        name = "__".join(str(p) for p in path)
        rows.append(f"  {member.flow.value:>3} {name:<22} {member.shape}")
    return rows


#: Verilator -Wall rules that fire on the *style* of Amaranth's Verilog backend, not on the design:
#: every other rule is an error. Widths follow Amaranth's own (checked) arithmetic rules, which
#: the backend writes with implicit extension; registers carry their reset value as an
#: initialiser; View members and submodule ports keep named wires that nothing reads; one file
#: holds the whole hierarchy.
AMARANTH_STYLE_WAIVERS = ("DECLFILENAME", "MULTITOP", "PROCASSINIT", "WIDTHEXPAND", "WIDTHTRUNC",
                          "UNUSEDSIGNAL")


def lint(path: Path) -> None:
    verilator = shutil.which("verilator")
    if verilator is None:
        sys.exit("lint: verilator not found on PATH (run through make)")
    waivers = path.with_suffix(".vlt")
    waivers.write_text("`verilator_config\n" + "".join(
        f"lint_off -rule {rule}\n" for rule in AMARANTH_STYLE_WAIVERS))
    result = subprocess.run([verilator, "--lint-only", "-Wall", str(waivers), str(path)],
                            capture_output=True, text=True)
    if result.returncode != 0 or "%Warning" in result.stderr:
        sys.stderr.write(result.stderr)
        sys.exit(f"lint: verilator -Wall reported warnings on {path}")
    print(f"lint: verilator --lint-only -Wall clean: {path}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("build/generated"))
    parser.add_argument("--phases", type=int, default=3)
    parser.add_argument("--width", type=int, default=16)
    parser.add_argument("--lint", action="store_true")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name, factory in default_configs(args.phases, args.width):
        component = factory()
        path = args.out / f"{name}.v"
        path.write_text(verilog.convert(component, name=name, emit_src=False))
        long_update = (f", long-update latency {component.long_latency} clocks (max_bits "
                       f"{component.max_bits})" if hasattr(component, "long_latency") else "")
        print(f"wrote {path}: {component.phases} phases, {component.width}-bit reference, "
              f"rule {component.rule}, loop latency {component.latency} clocks{long_update}")
        print("\n".join(port_table(component)))
        if args.lint:
            lint(path)


if __name__ == "__main__":
    main()
