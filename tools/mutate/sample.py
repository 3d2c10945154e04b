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

__all__ = ["CLASSES", "SEED", "build", "draw", "main", "stimulus"]

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
    from vectors import ports_of

    spec = BLOCKS[block]
    netlist = BlockNetlist(spec.build(True), directory)
    mutations = netlist.resolve(keys)
    module = f"{block}_mutants"
    netlist.write_mutants(mutations, module)
    component = spec.build(False)
    component._MustUse__used = True
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
    """A new sample: {block: [(key, class), ...]} (see the module docstring)."""
    rng = random.Random(seed)
    sample: dict[str, list] = {name: [] for name in BLOCKS}
    for fault_class, per_block in CLASSES.items():
        for block, (path, pattern, modes, ports) in per_block.items():
            netlist = BlockNetlist(BLOCKS[block].build(True), BUILD / "draw" / block)
            candidates = []
            for location in lines_matching(path, pattern):
                candidates += [m for m in netlist.candidates_at(location) if m.mode in modes
                               and (ports is None or m.port in ports)]
            keys = sorted({m.key for m in candidates})
            if not keys:
                print(f"# {block} / {fault_class}: no mutation at {path} /{pattern}/")
                continue
            binary, prepared, _ = build(block, keys, BUILD / "draw" / f"{block}-cand")
            killed = [key for k, key in enumerate(keys, 1)
                      if run_vectors(binary, prepared, k)["killed"]]
            print(f"# {block} / {fault_class}: {len(killed)} of {len(keys)} killed")
            if killed:
                sample[block] += [(key, fault_class) for key in
                                  rng.sample(killed, min(2, len(killed)))]
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
