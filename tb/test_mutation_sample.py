# amaranth: UnusedElaboratable=no
"""A fixed sample of mutants that the tests must keep killing (issue 15): at least one per block
(core, generator, gate driver, the top with each bus front), per fault class (pin polarity;
a bus handshake taken on cyc or stb alone, or on AW or W alone; two events in one clock: the
fault latch's set and clear, two legs turning on together in the switching counters) and per
row of docs/robustness.md (a mutant of the logic that implements the row's behaviour; the
table names it). Each must be killed by its block's vector stimulus (tools/mutate/sample.py:
the block's own stimulus, shortened); a later change that weakens the tests fails here.

The mutants are Yosys ``mutate`` mutations of the block's netlist, all built into one netlist
per block (``mutsel`` picks one) exactly as ``make mutate`` builds them (tools/mutate). The
sample lives in the registry, tools/mutate/registry.py ``SAMPLE``, drawn by ``python -m
tools.mutate.sample --write`` (a seeded choice among the mutants the sample's stimulus kills at
each class's lines and at each row's logic, tools/mutate/sample.py CLASSES and ROWS; the
Wishbone top's two-events row is bit 1 of the sum of the legs' turn-on strobes, lost only when
two legs turn on in the same clock). Its keys name the source text of the statement, not its
line (tools/mutate/keys.py), so the sample survives the design being rebuilt and edits
elsewhere in the file; a key whose text is gone fails with the command that draws a new sample.
"""

import pytest

from tools.mutate import sample
from tools.mutate.keys import REDRAW, StaleKeyError
from tools.mutate.registry import SAMPLE
from tools.mutate.stages import run_vectors

CLASSES = ("pin polarity", "bus handshake (cyc or stb alone)", "two events in one clock")
BLOCKS = sorted({entry.block for entry in SAMPLE})


def test_the_sample_covers_every_block_fault_class_and_robustness_row():
    assert set(BLOCKS) == set(sample.BLOCKS)
    classes = {entry.why for entry in SAMPLE}
    assert set(CLASSES) <= classes
    assert {f"row: {row}" for row in sample.ROWS} <= classes


@pytest.mark.parametrize("block", BLOCKS)
def test_sample_mutants_are_killed(block):
    entries = [entry for entry in SAMPLE if entry.block == block]
    try:
        binary, prepared, _ = sample.build(block, [e.key for e in entries],
                                           sample.BUILD / block)
    except StaleKeyError as error:
        pytest.fail(str(error))
    original = run_vectors(binary, prepared, 0)
    assert not original["killed"], f"{block}: the original fails: {original['detail']}"
    survivors = []
    for k, entry in enumerate(entries, 1):
        result = run_vectors(binary, prepared, k)
        print(f"{block} mutant {k} ({entry.why}) {entry.key}: {result['detail']}")
        if not result["killed"]:
            survivors.append(f"{entry.key} ({entry.why}): {result['detail']}")
    assert not survivors, (f"{block}: mutants the tests no longer kill (one again: python -m "
                           f"tools.mutate --block {block} --only '<key>'; a new sample: "
                           f"{REDRAW}):\n" + "\n".join(survivors))
