"""The fixed sample of mutants ``make test`` runs (tb/test_mutation_sample.py): at least one per
block and per fault class, each of which the block's vector stage must kill.

Keys name source and kind, not cells, so the sample survives the design being rebuilt; a key
that no longer resolves (its source line moved) fails the test with the command that draws a
new sample:

    python -m tools.mutate.sample [--seed 7]      # prints a SAMPLE for the test file

Drawing: for each (block, fault class), every mutation ``mutate`` knows at the class's source
lines (below, found by their text), run through the sample's own short vector stimulus; a
seeded choice among the killed ones. A class where none is killed is printed as such (it goes
to the campaign's report, not into the sample).
"""

from __future__ import annotations

import argparse
import random
import re
from pathlib import Path

from .blocks import BLOCKS
from .netlist import ROOT, BlockNetlist, mutsel_width, wrapper
from .stages import MutantBench, run_vectors

__all__ = ["ANY", "CLASSES", "ROWS", "SEED", "TRIED", "build", "draw", "main", "stimulus"]

BUILD = ROOT / "build" / "mutate" / "sample"
#: The sample's stimulus per block: the block's own vector stimulus, shortened (clocks per
#: scenario / run), so that the whole sample runs in about a minute on two cores
SIZES = {"core": 12_000, "generator": 4_000, "driver": None, "top_wb": 60_000,
         "top_axi": 40_000}

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
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"total_next\.eq\(total \+ sum",
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
#: the rows of docs/robustness.md (their first words) -> the logic that implements the row's
#: behaviour, as CLASSES: a mutant there must fail the tests (the table says which)
ANY = ("inv", "const0", "const1", "cnot0", "cnot1")
ROWS = {
    "reference beyond the linear range": {
        "core": ("rtl/mdfqm_gateware/integrator.py", r"o_x\.eq\(Mux\(self\.o_saturated", ANY,
                 None)},
    "common-mode offset": {
        "core": ("rtl/mdfqm_gateware/reference.py", r"total\.eq\(sum\(", ANY, None)},
    "extreme codes": {
        "core": ("rtl/mdfqm_gateware/reference.py", r"scaled\[i\]\.eq\(raw\[i\] \* n\)", ANY,
                 None)},
    "equal references (ties)": {
        "core": ("rtl/mdfqm_gateware/sort.py", r"next_(values|index)\[a\]\.eq\(Mux\(a_first",
                 ANY, None)},
    "update period below the loop latency": {
        "core": ("rtl/mdfqm_gateware/sequencer.py", r"clamped = self\.period < self\.latency",
                 ANY, None)},
    "OSR 0": {
        "core": ("rtl/mdfqm_gateware/sequencer.py", r"osr_now = Mux\(self\.osr == 0", ANY,
                 None)},
    "runtime changes of period / OSR / zero policy / mode": {
        # the zero policy taken at a start: its register and enable (the port's source line)
        "core": ("rtl/mdfqm_gateware/sequencer.py", r'"policy": Out\(1\)', ANY, None)},
    "illegal generator mode or bits": {
        "generator": ("rtl/mdfqm_gateware/sequencer.py",
                      r"legal = self\.mode < len|bits_now = Mux\(self\.bits < 1", ANY, None)},
    "MODULATION written with a mode not built in": {
        "top_wb": ("rtl/mdfqm_gateware/sequencer.py",
                   r"legal = self\.mode < len|bits_now = Mux\(self\.bits < 1", ANY, None)},
    "sync_in at any time": {
        "core": ("rtl/mdfqm_gateware/sequencer.py",
                 r"restart = self\.sync_in & \(phase >= self\.latency - 1\)", ANY, None)},
    "reset in the middle of an update": {
        "core": ("rtl/mdfqm_gateware/sequencer.py", r"start_q, tick_q = Signal\(init=1\)", ANY,
                 ("S",))},          # the reset multiplexer's select
    "a reference beat while one is pending": {
        "core": ("rtl/mdfqm_gateware/reference.py", r"ref\.ready\.eq\(", ANY, None)},
    "AXI4-Lite: an access to a word that holds no register": {
        "top_axi": ("rtl/mdfqm_gateware/fronts.py",
                    r"return Mux\(mask\.bit_select\(address, 1\), AXI_RESP_OKAY", ANY, None)},
    "IRQ_STATUS written in the clock of a new event": {
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"status_next = \(irq_status & ~cleared\)", ANY,
                   None)},
    "any value to any register": {
        "top_wb": ("rtl/mdfqm_gateware/top.py", r"dead\.eq\(Mux\(word < self\.dead_min", ANY,
                   None)},
    "dead time below the elaboration floor": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"dt_expr = Mux\(dead_seen < self\.dead_min",
                   ANY, None)},
    "a commanded pulse shorter than the minimum pulse": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"c < self\.min_pulse\)", ANY, None)},
    "a slot shorter than the dead time plus the minimum pulse": {
        "driver": ("rtl/mdfqm_gateware/driver.py",
                   r"Mux\(drive & self\.active, \(cmd \^ cmd_lat\)", ANY, None)},
    "fault input chatter, fault during a dead time": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"fault_active\.eq\(self\.fault_input", ANY,
                   None)},
    "enable toggled in the middle of an update": {
        "driver": ("rtl/mdfqm_gateware/driver.py", r"drive\.eq\(Mux\(self\.update, self\.enable",
                   ANY, None)},
    "a fault or a watchdog trip with an active short circuit chosen": {
        "driver": ("rtl/mdfqm_gateware/driver.py",
                   r"m\.d\.comb \+= now\.eq\(Mux\(kill|kill = \(~\(fault_active", ANY, None)},
    "the controller stops sending references (watchdog)": {
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
        return blocks._core_runs(seed, size)
    if block == "generator":
        return blocks._generator_runs(seed, size)
    bus = "wishbone" if block == "top_wb" else "axi4lite"
    return blocks._top_runs(bus, (size,))(seed)


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


def draw(seed: int) -> dict:
    """A new sample: {block: [(key, class), ...]} (see the module docstring): per block one
    netlist and bench with every class's candidates (at most :data:`TRIED` each, seeded),
    then a seeded choice among the killed ones (two per fault class, one per row)."""
    rng = random.Random(seed)
    sample: dict[str, list] = {name: [] for name in BLOCKS}
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
                          and (ports is None or m.port in ports)}
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
        for fault_class, keys, count in classes:
            hits = sorted(k for k in keys if k in killed)
            print(f"# {block} / {fault_class}: {len(hits)} of {len(keys)} killed")
            sample[block] += [(key, fault_class) for key in
                              rng.sample(hits, min(count, len(hits)))]
    return sample


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.mutate.sample",
                                     description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args(argv)
    sample = draw(args.seed)
    print(f"SAMPLE = {{  # python -m tools.mutate.sample --seed {args.seed}")
    for block, entries in sample.items():
        print(f"    {block!r}: [")
        for key, fault_class in entries:
            print(f"        ({key!r},\n         {fault_class!r}),")
        print("    ],")
    print("}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
