# amaranth: UnusedElaboratable=no
"""Write the drop-in Verilog files (core, generator, top) and report what was built.

    mdfqm-dropin --out build/generated [--phases 3 --width 16] [--lint]
    python -m mdfqm_gateware.dropin ...                 # the same; `make` runs it

Every file carries its own lint waivers (:data:`AMARANTH_STYLE_WAIVERS`, scoped to the file's
text), so that ``verilator --lint-only -Wall FILE`` is clean on it as shipped, with no waiver file.
``--lint`` runs exactly that on every generated file and fails on any warning.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

from amaranth.back import verilog

from mdfqm_spec.regmap import default_max_bits

from .core import MdfqmCore
from .generator import GatingSignalGenerator
from .top import MdfqmTop

__all__ = [
    "AMARANTH_STYLE_WAIVERS",
    "default_configs",
    "dropin_verilog",
    "lint",
    "main",
    "port_table",
    "with_waivers",
]


#: (module name, constructor) of every drop-in file `make` writes
def default_configs(phases: int, width: int):
    bits = default_max_bits(width)
    return [
        (f"mdfqm_core_n{phases}_w{width}", lambda: MdfqmCore(phases, width)),
        (f"mdfqm_generator_n{phases}_w{width}_b{bits}",
         lambda: GatingSignalGenerator(phases, width, max_bits=bits)),
        (f"mdfqm_top_n{phases}_w{width}", lambda: MdfqmTop(phases, width, max_bits=bits)),
        (f"mdfqm_top_axil_n{phases}_w{width}",
         lambda: MdfqmTop(phases, width, bus="axi4lite", max_bits=bits)),
        (f"mdfqm_top_mdfqm_only_n{phases}_w{width}", lambda: MdfqmTop(phases, width, max_bits=0)),
    ]


def port_table(component) -> list[str]:
    rows = []
    for path, member, _ in component.signature.flatten(component):
        name = "__".join(str(p) for p in path)
        rows.append(f"  {member.flow.value:>3} {name:<22} {member.shape}")
    return rows


#: The Verilator -Wall rules every drop-in file waives for its own text, each with the reason
#: (written into the file beside its waiver). They fire on the *style* of Amaranth's Verilog
#: backend or on the way a user's compilation lists the file, not on a defect in the design;
#: every other rule is an error. WIDTH and UNUSED are the rule groups every Verilator 4 and 5
#: knows (since 5.008 / 5.002 they hold WIDTHEXPAND and WIDTHTRUNC / UNUSEDSIGNAL, the rules that
#: fire): a lint_off comment naming a rule a Verilator does not know is an error there.
AMARANTH_STYLE_WAIVERS = {
    "DECLFILENAME": "one file holds the IP's whole hierarchy: its submodules (named "
                    "<top>.<path>) cannot each have a file of their own name.",
    "MULTITOP": "the file's top is meant to be instantiated by your design; a compilation that "
                "lists the file without instantiating it (or several drop-in files at once) "
                "has extra top levels of its own making.",
    "PROCASSINIT": "every register is declared with its Amaranth init value as initialiser "
                   "(the FPGA power-up value; Verilator's guidance for this rule allows that "
                   "FPGA idiom) and the registers with a reset also return to it on rst.",
    "TIMESCALEMOD": "the IP has no delays, so it sets no timescale (not to impose one on the "
                    "files after it); Verilator asks for one only when another file of the "
                    "compilation sets one.",
    "UNUSED": "UNUSEDSIGNAL: the backend keeps a named wire for every interface member and "
              "submodule port, and the carry bits of sums the design truncates. The inputs the "
              "IP ignores on purpose are documented (docs/top.md: Wishbone sel, AXI wstrb and "
              "*prot, AXI address bits [1:0]); the fault input's two-flop synchroniser has no "
              "reset by design, so its rst port is unused.",
    "WIDTH": "WIDTHEXPAND, WIDTHTRUNC: the backend writes Amaranth's width rules with Verilog's "
             "implicit extension and truncation (operands widened to the result, !x of a vector "
             "for x == 0, a bit looked up in a shifted constant); Amaranth checks the widths and "
             "the file is checked cycle for cycle against the golden model.",
}

#: Waived rules newer than older Verilators: (first Verilator that has the rule, its message).
#: These are waived by message in an in-file ``verilator_config`` section for the file's own
#: name, which every Verilator 4 and 5 accepts (a lint_off comment naming them would be an error
#: in the older ones).
BY_MESSAGE = {
    "PROCASSINIT": ("5.038", "Procedural assignment to declaration with initial value: *"),
}

#: The first line of the waivers: a file holding it carries them (see :func:`with_waivers`).
WAIVERS_START = "/* verilator lint_save */"
WAIVERS_END = "/* verilator lint_restore */"


def _comment(lines: list[str]) -> str:
    if any("*/" in line for line in lines):
        raise ValueError("a waiver's text would end the comment early")
    body = "\n".join(f" * {line}".rstrip() for line in lines)
    return f"/*\n{body}\n */\n"


def with_waivers(text: str, filename: str) -> str:
    """``text`` (Amaranth's Verilog of one design) as the drop-in file ``filename``: a comment on
    its waivers, the waivers (``lint_save`` + ``lint_off`` comments, the ``verilator_config``
    section of :data:`BY_MESSAGE`), the text, ``lint_restore``."""
    wrap = textwrap.TextWrapper(width=96)
    lines = [*wrap.wrap(f"{filename}: drop-in Verilog of the MDFQM gateware, written by "
                        "mdfqm_gateware.dropin (mdfqm-dropin) from the Amaranth design."), ""]
    lines += wrap.wrap(
        "Lint waivers, for this IP's own text only: `verilator --lint-only -Wall` is clean on "
        "this file as shipped, with no waiver file. The rules below fire on the style of "
        "Amaranth's Verilog backend, not on defects in the design. They are off between the "
        "lint_save below and the lint_restore at the end of the file, which puts back the "
        "settings in force before it, so your own code after this file (in the same file or "
        "compilation) is checked as before.")
    for rule, (since, _) in BY_MESSAGE.items():
        lines += ["", *wrap.wrap(
            f"{rule} (a rule of Verilator >= {since}) is waived by its message in the "
            "`verilator_config` section below, for this file's name only, because older "
            "Verilators stop with an error on a lint_off comment naming a rule they do not "
            "know: if you rename the file, change the name there too.")]
    lines.append("")
    for rule, reason in AMARANTH_STYLE_WAIVERS.items():
        lines += textwrap.wrap(f"{rule:<13} {reason}", width=96, subsequent_indent=" " * 14)
    pragmas = [WAIVERS_START]
    pragmas += [f"/* verilator lint_off {rule} */" for rule in AMARANTH_STYLE_WAIVERS
                if rule not in BY_MESSAGE]
    config = [f'lint_off -file "*{filename}" -match "{message}"'
              for rule, (_, message) in BY_MESSAGE.items() if rule in AMARANTH_STYLE_WAIVERS]
    if config:
        pragmas += ["`ifdef VERILATOR", "`verilator_config", *config, "`verilog", "`endif"]
    if not text.endswith("\n"):
        text += "\n"
    return _comment(lines) + "\n".join(pragmas) + "\n" + text + WAIVERS_END + "\n"


def dropin_verilog(component, name: str) -> str:
    """The drop-in file ``{name}.v`` of ``component``: module ``name``, with its waivers."""
    return with_waivers(verilog.convert(component, name=name, emit_src=False), f"{name}.v")


def lint(path: Path) -> None:
    """``verilator --lint-only -Wall path`` (no waiver file: the waivers are in the file); exit
    on any warning or error. A file without the waivers (plain Amaranth output) is linted as
    the drop-in file it would make: a copy with them, of the same name, in a temporary folder."""
    verilator = shutil.which("verilator")
    if verilator is None:
        sys.exit("lint: verilator not found on PATH (run through make)")
    text = path.read_text()
    with tempfile.TemporaryDirectory() as scratch:
        target = path
        if WAIVERS_START not in text:
            target = Path(scratch) / path.name
            target.write_text(with_waivers(text, path.name))
        result = subprocess.run([verilator, "--lint-only", "-Wall", str(target)],
                                capture_output=True, text=True)
    if result.returncode != 0 or "%Warning" in result.stderr or "%Error" in result.stderr:
        sys.stderr.write(result.stderr)
        sys.exit(f"lint: verilator -Wall reported warnings on {path}")
    waivers = "" if target == path else " (with the drop-in file's waivers added)"
    print(f"lint: verilator --lint-only -Wall clean: {path}{waivers}")


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
        path.write_text(dropin_verilog(component, name))
        long_update = (f", long-update latency {component.long_latency} clocks (max_bits "
                       f"{component.max_bits})" if hasattr(component, "long_latency") else "")
        print(f"wrote {path}: {component.phases} phases, {component.width}-bit reference, "
              f"rule {component.rule}, loop latency {component.latency} clocks{long_update}")
        print("\n".join(port_table(component)))
        if args.lint:
            lint(path)


if __name__ == "__main__":
    main()
