"""The fixed sample of mutants ``make test`` runs (tb/test_mutation_sample.py): at least one per
block, per fault class and per row of docs/robustness.md, each of which the block's vector stage
must kill. It lives in the registry (tools/mutate/registry.py ``SAMPLE``), which this module
writes, and from which it writes the robustness table's last column.

Keys name source text and kind, not cells nor lines (tools/mutate/keys.py), so the sample
survives the design being rebuilt and edits elsewhere in a file; a key whose source text is
gone fails the test with the command that draws a new sample:

    python -m tools.mutate.sample --write [--seed 7]   # draw, and rewrite the registry's SAMPLE
    python -m tools.mutate.sample --docs               # rewrite docs/robustness.md's last column

Drawing: for each (block, fault class or row), every mutation ``mutate`` knows at the class's
source lines (below, found by their text), run through the sample's own short vector stimulus; a
seeded choice among the killed ones. A class where none is killed is printed as such (it goes
to the campaign's report, not into the sample).
"""

from __future__ import annotations

import argparse
import json
import random
import re
import textwrap
from pathlib import Path

from .blocks import BLOCKS
from .keys import Key
from .netlist import ROOT, BlockNetlist, mutsel_width, wrapper
from .registry import SAMPLE, Sampled
from .stages import MutantBench, run_vectors

__all__ = ["ANY", "CLASSES", "DOCS", "ROWS", "SEED", "TRIED", "build", "docs_mismatches",
           "draw", "main", "mutant_cell", "registry_origin", "registry_text", "stimulus",
           "write_docs", "write_registry"]

BUILD = ROOT / "build" / "mutate" / "sample"
#: The sample's stimulus per block: the block's own vector stimulus, shortened (clocks per
#: scenario / run), so that the whole sample runs in about a minute on two cores. A top's run
#: must close its functional coverage: 60,000 clocks do for both fronts (the test of the top's
#: vectors runs as long); 40,000 and 50,000 left bins open at the sample's seed
SIZES = {"core": 12_000, "generator": 4_000, "driver": None, "top_wb": 60_000,
         "top_axi": 60_000}

#: fault class -> {block: (file, regular expression on the line's text, modes, ports)}; the
#: lines are found by their text (a process's multiplexers carry the source line of the
#: signal they drive, so the fault latch's priority is at its port's declaration)
CLASSES = {
    "pin polarity": {
        # the upper pins are active low: the inverter Yosys makes of the polarity xor has the
        # source of what it drives, the port's declaration
        "driver": ("rtl/mdfqm_gateware/driver.py", r'"(upper|lower)": Out\(phases\)', ("inv",),
                   None),
        "top_wb": ("rtl/mdfqm_gateware/driver.py", r'"(upper|lower)": Out\(1\)', ("inv",),
                   ("Q",)),
    },
    "bus handshake (cyc or stb alone)": {
        "top_wb": ("rtl/mdfqm_gateware/fronts.py", r"request\.eq\(bus\.cyc & bus\.stb",
                   ("const1",), None),
        "top_axi": ("rtl/mdfqm_gateware/fronts.py", r"do_write\.eq\(aw_full & w_full",
                    ("const1",), None),
    },
    "two events in one clock": {
        # the fault latch: set and clear in one clock, set wins
        "driver": ("rtl/mdfqm_gateware/driver.py", r'"fault": Out\(1\)',
                   ("const0", "const1"), ("S",)),
        # two legs turning on in one clock count two
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"turn_ons\.eq\(sum",
                   ("const0", "const1", "inv", "cnot0", "cnot1"), None),
        # an interrupt event and its write-1-to-clear in one clock: the event stays
        "top_axi": ("rtl/mdfqm_gateware/top.py", r"status_next = \(irq_status & ~cleared\)",
                    ("const0", "const1", "inv"), None),
    },
    "datapath": {
        "core": ("rtl/mdfqm_gateware/integrator.py", r"\.eq\(", ("inv", "const0", "const1"),
                 None),
        "generator": ("rtl/mdfqm_gateware/resolution.py", r"\.eq\(",
                      ("inv", "const0", "const1"), None),
    },
}
#: the rows of docs/robustness.md (words of their first column that find them) -> the logic
#: that implements the row's behaviour, as CLASSES (a port may name its bit, ``Y[1]``): a mutant
#: there must fail the tests (the table's last column names it, written from the registry)
ANY = ("inv", "const0", "const1", "cnot0", "cnot1")
ROWS = {
    "Wishbone: `stb` without `cyc`": {
        "top_wb": ("rtl/mdfqm_gateware/fronts.py", r"request\.eq\(bus\.cyc & bus\.stb",
                   ("const1",), None)},
    "any pair of pin polarities": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r'"(upper|lower)": Out\(phases\)', ("inv",),
                   None)},
    "two events in one clock: a register write": {
        # bit 1 of the sum of the legs' turn-on strobes: lost only when two legs turn on in
        # the same clock
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"turn_ons\.eq\(sum", ("const0",),
                   ("Y[1]",))},
    "reference beyond the linear range": {
        "core": ("rtl/mdfqm_gateware/integrator.py", r"fits\.eq\(Cat\(\*fits_each\)\.all\(\)\)",
                 ANY, None)},
    "common-mode offset": {
        "core": ("rtl/mdfqm_gateware/reference.py", r"total\.eq\(total \+ phase_code\)", ANY,
                 None)},
    "extreme codes": {
        "core": ("rtl/mdfqm_gateware/reference.py",
                 r"pending\[n - 1\]\.eq\(~\(scaled_n \+ total\)\)", ANY, None)},
    "equal references (ties)": {
        "core": ("rtl/mdfqm_gateware/sort.py", r"next_(values|index)\[a\]\.eq\(Mux\(a_first",
                 ANY, None)},
    "update period below the loop latency": {
        "core": ("rtl/mdfqm_gateware/sequencer.py",
                 r"clamped = ~at_least\(self\.period, self\.latency\)", ANY, None)},
    "OSR 0": {
        "core": ("rtl/mdfqm_gateware/sequencer.py", r"osr_now = Mux\(self\.osr == 0", ANY,
                 None)},
    "runtime changes of period / OSR / zero policy / mode": {
        # the zero policy taken at a start: its register and enable (the port's source line)
        "core": ("rtl/mdfqm_gateware/sequencer.py", r'"policy": Out\(1\)', ANY, None)},
    "illegal generator `mode`": {
        "generator": ("rtl/mdfqm_gateware/sequencer.py",
                      r"legal = self\.mode < len|bits_now = Mux\(self\.bits < 1", ANY, None)},
    "`MODULATION` written with a mode not built in": {
        "top_wb": ("rtl/mdfqm_gateware/sequencer.py",
                   r"legal = self\.mode < len|bits_now = Mux\(self\.bits < 1", ANY, None)},
    "`sync_in` at any time": {
        "core": ("rtl/mdfqm_gateware/sequencer.py",
                 r"ends = ~self\.start & late & \(self\.sync_in \| reached\)", ANY, None)},
    "reset in the middle of an update": {
        "core": ("rtl/mdfqm_gateware/sequencer.py", r"start_q, tick_q, sub_one = Signal\(init=1\)",
                 ANY, ("S",))},          # the reset multiplexer's select
    "a reference beat while one is pending": {
        "core": ("rtl/mdfqm_gateware/reference.py", r"ref\.ready\.eq\(", ANY, None)},
    "AXI4-Lite: an access to a word that holds no register": {
        "top_axi": ("rtl/mdfqm_gateware/fronts.py",
                    r"return Mux\(mask\.bit_select\(address, 1\), AXI_RESP_OKAY", ANY, None)},
    "`IRQ_STATUS` written with any value": {
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"status_next = \(irq_status & ~cleared\)", ANY,
                   None)},
    "any value to any register": {
        "top_wb": ("rtl/mdfqm_gateware/top.py", r'dead\.eq\(Mux\(clamp\["below_floor"\]', ANY,
                   None)},
    "dead time below the elaboration floor": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"dt_expr = Mux\(dead_seen < self\.dead_min",
                   ANY, None)},
    "a commanded pulse shorter than the minimum pulse": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"c < self\.min_pulse\)", ANY, None)},
    "a slot or an update shorter than the dead time plus the minimum pulse": {
        "driver": ("rtl/mdfqm_gateware/driver.py",
                   r"Mux\(drive & self\.active, \(cmd \^ cmd_lat\)", ANY, None)},
    "fault input chatter, fault during a dead time": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"fault_active\.eq\(self\.fault_input", ANY,
                   None)},
    "enable toggled in the middle of an update": {
        "driver": ("rtl/mdfqm_gateware/driver.py",
                   r"drive_if_clear\.eq\(Mux\(self\.update, self\.enable", ANY, None)},
    "a fault or a watchdog trip with an active short circuit chosen": {
        "driver": ("rtl/mdfqm_gateware/driver.py",
                   r"kill_common = |now_if_(fault|clear)\.eq\(Mux\(kill_if", ANY, None)},
    "the controller stops sending references": {
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"trip\.eq\(\(timeout != 0\)", ANY, None)},
}
#: candidates simulated per (class, block) when drawing
TRIED = 12


def lines_matching(path: str, pattern: str) -> list[str]:
    """``file:line`` of every line of ``path`` whose text matches ``pattern``."""
    text = (ROOT / path).read_text().splitlines()
    return [f"{path}:{i}" for i, line in enumerate(text, 1) if re.search(pattern, line)]


def stimulus(block: str, seed: int):
    """The block's vector runs at the sample's size."""
    size = SIZES[block]
    runs = BLOCKS[block].stimulus(seed) if size is None else sized(block, seed, size)
    return runs


def sized(block: str, seed: int, size: int):
    from . import blocks

    if block == "core":
        return blocks.core_runs(seed, size)
    if block == "generator":
        return blocks.generator_runs(seed, size)
    return blocks.top_runs(block, (size,))(seed)


def build(block: str, keys, directory: Path):
    """The netlist of ``keys`` (mutant k = keys[k - 1]) of ``block``, its bench and its
    prepared vector files: ``(bench binary, prepared runs, mutations)``."""
    from mdfqm_testkit.vectors import ports_of

    spec = BLOCKS[block]
    netlist = BlockNetlist(spec.build(True), directory)
    mutations = netlist.resolve(keys)
    module = f"{block}_mutants"
    netlist.write_mutants(mutations, module)
    component = spec.build(False)
    source = directory / f"mutants-{spec.toplevel}.v"
    text = ((directory / "mutants.net.v").read_text()
            + wrapper(spec.toplevel, module, ports_of(component), mutsel_width(len(keys))))
    if not source.exists() or source.read_text() != text:
        source.write_text(text)
    bench = MutantBench(component, spec.toplevel, f"{directory.parent.name}-"
                        f"{directory.name}", source=source)
    return str(bench.binary), bench.prepare(stimulus(block, SEED)), mutations


#: the seed of the sample's stimulus
SEED = 2024


def draw(seed: int) -> list[Sampled]:
    """A new sample (see the module docstring): per block one netlist and bench with every
    class's candidates (at most :data:`TRIED` each, seeded), then a seeded choice among the
    killed ones (two per fault class, one per row)."""
    rng = random.Random(seed)
    sample: list[Sampled] = []
    wanted = [(f"row: {row}", spec, 1) for row, spec in ROWS.items()]
    wanted = [(name, spec, 2) for name, spec in CLASSES.items()] + wanted
    for block in BLOCKS:
        netlist = BlockNetlist(BLOCKS[block].build(True), BUILD / "draw" / block)
        classes = []
        for fault_class, per_block, count in wanted:
            if block not in per_block:
                continue
            path, pattern, modes, ports = per_block[block]
            candidates = {m.key for location in lines_matching(path, pattern)
                          for m in netlist.candidates_at(location) if m.mode in modes
                          and _port_matches(m.port, m.bit, ports)}
            keys = sorted(candidates)
            keys = rng.sample(keys, min(TRIED, len(keys)))
            if not keys:
                print(f"# {block} / {fault_class}: no mutation at {path} /{pattern}/")
            classes.append((fault_class, keys, count))
        every = sorted({key for _, keys, _ in classes for key in keys})
        if not every:
            continue
        binary, prepared, _ = build(block, every, BUILD / "draw" / f"{block}-cand")
        killed = {key for k, key in enumerate(every, 1)
                  if run_vectors(binary, prepared, k)["killed"]}
        chosen: set[str] = set()         # a mutant stands for one class or row only
        for fault_class, keys, count in classes:
            hits = sorted(k for k in keys if k in killed)
            print(f"# {block} / {fault_class}: {len(hits)} of {len(keys)} killed")
            picks = rng.sample([k for k in hits if k not in chosen],
                               min(count, len(set(hits) - chosen)))
            chosen.update(picks)
            sample += [Sampled(block, key, fault_class) for key in picks]
    return sample


def _port_matches(port: str, bit: int, ports) -> bool:
    """Whether a mutation's port and bit are among ``ports`` (``None``: any; ``"Y"`` or
    ``"Y[1]"``)."""
    return ports is None or port in ports or f"{port}[{bit}]" in ports


# ------------------------------------------------------------------------------ the registry
REGISTRY = ROOT / "tools" / "mutate" / "registry.py"
_BEGIN = ("# -- sample: written by tools/mutate/sample.py (--write), not by hand; the comments "
          "are the")
_END = "# -- end of the sample"
_ORIGIN = "# -- origin: "


def _unit_text(key: str) -> str:
    """The source text a key names (its first source), for a comment or the table."""
    for _file, unit in Key.parse(key).where(ROOT):
        return unit.text if unit is not None else "(gone)"
    return "(no source)"


def registry_text(sample: list[Sampled], origin: str) -> str:
    """The registry's SAMPLE section for ``sample`` (between its markers, markers included);
    ``origin``: how the sample was drawn."""
    out = [_BEGIN, "# -- source text each key names", *textwrap.wrap(
        origin, 96, initial_indent=_ORIGIN, subsequent_indent="# --   "),
        "SAMPLE: tuple[Sampled, ...] = ("]
    for entry in sample:
        text = _unit_text(entry.key)
        text = text if len(text) <= 88 else text[:85] + "..."
        # json's quoting is Python's, with the double quotes of the rest of the code
        out += [f"    # {text}", f"    Sampled({json.dumps(entry.block)},",
                f"            {json.dumps(entry.key)},", f"            {json.dumps(entry.why)}),"]
    out += [")", _END]
    return "\n".join(out)


def registry_origin(path: Path = REGISTRY) -> str:
    """How the registry's sample was drawn (its ``origin`` comment)."""
    lines = path.read_text().split("\n")
    first = next(i for i, line in enumerate(lines) if line.startswith(_ORIGIN))
    words = [lines[first].removeprefix(_ORIGIN)]
    for line in lines[first + 1:]:
        if not line.startswith("# --   "):
            break
        words.append(line.removeprefix("# --   "))
    return " ".join(words)


def write_registry(sample: list[Sampled], origin: str, path: Path = REGISTRY) -> None:
    """Replace the SAMPLE section of the registry (``path``) with ``sample``."""
    text = path.read_text()
    first = text.index(_BEGIN)
    last = text.index(_END) + len(_END)
    path.write_text(text[:first] + registry_text(sample, origin) + text[last:])


# ------------------------------------------------------------------- docs/robustness.md
DOCS = ROOT / "docs" / "robustness.md"
#: how the table says which vector runs kill a mutant of each block
_RUNS = {"core": "the core's", "generator": "the generator's", "driver": "the gate driver's",
         "top_wb": "the Wishbone top's", "top_axi": "the AXI4-Lite top's"}
#: the longest source text the table shows
_SHOWN = 72


def _change(key: Key) -> str:
    if key.mode == "inv":
        return "inverted"
    if key.mode in ("const0", "const1"):
        return f"stuck at {key.mode[-1]}"
    return f"inverted while bit {key.ctrlbit} is {key.mode[-1]}"


def mutant_cell(entry: Sampled) -> str:
    """The robustness table's last column for a sample mutant: its file and source text (not
    a line number: the column stays right while the key does), the cell, the change, the runs
    that kill it."""
    key = Key.parse(entry.key)
    text = _unit_text(entry.key)
    text = text if len(text) <= _SHOWN else text[:_SHOWN - 3] + "..."
    file = key.files[0] if key.files else "?"
    code = text.replace("|", "\\|").replace("`", "'")
    return (f"`{file}`, `{code}`: {key.scope or 'top'} `{key.type}` {key.port}[{key.bit}] "
            f"{_change(key)}; fails {_RUNS[entry.block]} vector runs")


def _cells(line: str) -> list[str]:
    """The cells of a table line (a ``\\|`` inside one is not a border)."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]


def _table(text: str) -> list[tuple[int, list[str]]]:
    """The robustness table's body rows: (line index, cells)."""
    return [(i, _cells(line)) for i, line in enumerate(text.split("\n"))
            if line.startswith("| ") and not line.startswith("| bad input |")]


def _expected_docs(text: str) -> tuple[list[str], list[str]]:
    """The table's lines with the last column written from the registry, and what does not
    match (a row no sample mutant names, words that find no row or several)."""
    lines = text.split("\n")
    problems = []
    named = [entry for entry in SAMPLE if entry.row is not None]
    for entry in named:
        hits = [i for i, cells in _table(text) if entry.row in cells[0]]
        if len(hits) != 1:
            problems.append(f"{entry.why!r} ({entry.block}) finds {len(hits)} rows of the table")
    for i, cells in _table(text):
        entries = [e for e in named if e.row in cells[0]]
        if not entries:
            if not cells[-1].startswith("none:"):
                problems.append(f"the row {cells[0][:60]!r}... names no sample mutant (a ROWS "
                                "entry in tools/mutate/sample.py, drawn into the registry)")
            continue
        cells[-1] = mutant_cell(entries[0])
        lines[i] = "| " + " | ".join(cells) + " |"
    return lines, problems


def docs_mismatches() -> list[str]:
    """How docs/robustness.md's last column differs from the registry (empty: it agrees)."""
    text = DOCS.read_text()
    lines, problems = _expected_docs(text)
    for was, now in zip(text.split("\n"), lines, strict=True):
        if was != now:
            problems.append(f"the table says {_cells(was)[-1]!r}, the registry "
                            f"{_cells(now)[-1]!r}")
    return problems


def write_docs() -> None:
    """Rewrite docs/robustness.md's last column from the registry."""
    lines, problems = _expected_docs(DOCS.read_text())
    if problems:
        raise SystemExit("\n".join(problems))
    DOCS.write_text("\n".join(lines))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.mutate.sample",
                                     description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--write", action="store_true",
                        help="draw a sample and write it into tools/mutate/registry.py")
    parser.add_argument("--docs", action="store_true",
                        help="write docs/robustness.md's last column from the registry")
    args = parser.parse_args(argv)
    if args.docs and not args.write:
        write_docs()
        print(f"wrote {DOCS.relative_to(ROOT)}")
        return 0
    sample = draw(args.seed)
    origin = f"drawn by `python -m tools.mutate.sample --write --seed {args.seed}`"
    if args.write:
        write_registry(sample, origin)
        print(f"wrote {REGISTRY.relative_to(ROOT)}; the table: python -m tools.mutate.sample "
              "--docs")
    else:
        print(registry_text(sample, origin))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
