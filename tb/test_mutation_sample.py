# amaranth: UnusedElaboratable=no
"""A fixed sample of mutants that the tests must keep killing (issue 15): at least one per block
(core, generator, gate driver, the top with each bus front) and per fault class (pin polarity;
a bus handshake taken on cyc or stb alone, or on AW or W alone; two events in one clock: the
fault latch's set and clear, two legs turning on together in the switching counters). Each
must be killed by its block's vector stimulus (tools/mutate/sample.py: the block's own
stimulus, shortened); a later change that weakens the tests fails here.

The mutants are Yosys ``mutate`` mutations of the block's netlist, all built into one netlist
per block (``mutsel`` picks one) exactly as ``make mutate`` builds them (tools/mutate). They are
named by source line and kind of mutation, not by netlist cell, so the sample survives the
design being rebuilt; a key that no longer names a cell (its line moved) fails with the
command that draws a new sample (``python -m tools.mutate.sample``)."""

import pytest

from tools.mutate import sample
from tools.mutate.stages import run_vectors

#: block -> [(mutation key, fault class)]: drawn by ``python -m tools.mutate.sample --seed 7``
#: (a seeded choice among the mutants the sample's stimulus kills at each class's lines), the
#: two-events mutants of the tops chosen by hand among those: bit 1 of the sum of the legs'
#: turn-on strobes (lost only when two legs turn on in the same clock)
SAMPLE = {
    "core": [
        ("rtl/mdfqm_gateware/integrator.py:84 integrator $mux#0 Y[24] const1", "datapath"),
    ],
    "generator": [
        ("rtl/mdfqm_gateware/resolution.py:181 quantiser $add#0 Y[9] inv", "datapath"),
    ],
    "driver": [
        ("rtl/mdfqm_gateware/driver.py:290~ top $not#0 Y[1] inv", "pin polarity"),
        ("rtl/mdfqm_gateware/driver.py:294 top $mux#2 S[0] const0",
         "two events in one clock"),
    ],
    "top_wb": [
        ("rtl/mdfqm_gateware/driver.py:81 driver.leg0 $dff#0 Q[0] inv", "pin polarity"),
        ("rtl/mdfqm_gateware/fronts.py:60 front $and#0 A[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/fronts.py:60 front $and#0 B[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/top.py:346 top $add#2 Y[1] const0", "two events in one clock"),
    ],
    "top_axi": [
        ("rtl/mdfqm_gateware/fronts.py:143 front $and#1 A[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/fronts.py:143 front $and#0 Y[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/top.py:346 top $add#1 Y[1] const0", "two events in one clock"),
    ],
}
CLASSES = ("pin polarity", "bus handshake (cyc or stb alone)", "two events in one clock")


def test_the_sample_covers_every_block_and_fault_class():
    assert set(SAMPLE) == set(sample.BLOCKS)
    assert all(SAMPLE.values())
    classes = {fault_class for entries in SAMPLE.values() for _, fault_class in entries}
    assert set(CLASSES) <= classes


@pytest.mark.parametrize("block", sorted(SAMPLE))
def test_sample_mutants_are_killed(block):
    keys = [key for key, _ in SAMPLE[block]]
    try:
        binary, prepared, _ = sample.build(block, keys, sample.BUILD / block)
    except KeyError as error:
        pytest.fail(f"{error}: the sample no longer matches the source; draw a new one with "
                    "`python -m tools.mutate.sample` and update SAMPLE")
    original = run_vectors(binary, prepared, 0)
    assert not original["killed"], f"{block}: the original fails: {original['detail']}"
    survivors = []
    for k, (key, fault_class) in enumerate(SAMPLE[block], 1):
        result = run_vectors(binary, prepared, k)
        print(f"{block} mutant {k} ({fault_class}) {key}: {result['detail']}")
        if not result["killed"]:
            survivors.append(f"{key} ({fault_class}): {result['detail']}")
    assert not survivors, (f"{block}: mutants the tests no longer kill (one again: python -m "
                           f"tools.mutate --block {block} --only '<key>'):\n"
                           + "\n".join(survivors))
