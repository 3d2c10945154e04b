# amaranth: UnusedElaboratable=no
"""A fixed sample of mutants that the tests must keep killing (issue 15): at least one per block
(core, generator, gate driver, the top with each bus front), per fault class (pin polarity;
a bus handshake taken on cyc or stb alone, or on AW or W alone; two events in one clock: the
fault latch's set and clear, two legs turning on together in the switching counters) and per
row of docs/robustness.md (a mutant of the logic that implements the row's behaviour; the
table names it). Each must be killed by its block's vector stimulus (tools/mutate/sample.py:
the block's own stimulus, shortened); a later change that weakens the tests fails here.

The mutants are Yosys ``mutate`` mutations of the block's netlist, all built into one netlist
per block (``mutsel`` picks one) exactly as ``make mutate`` builds them (tools/mutate). They are
named by source line and kind of mutation, not by netlist cell, so the sample survives the
design being rebuilt; a key that no longer names a cell (its line moved) fails with the
command that draws a new sample (``python -m tools.mutate.sample``)."""

import pytest

from tools.mutate import sample
from tools.mutate.stages import run_vectors

#: block -> [(mutation key, fault class or robustness row)]: drawn by ``python -m
#: tools.mutate.sample --seed 7`` (a seeded choice among the mutants the sample's stimulus kills
#: at each class's lines and at each row's logic, tools/mutate/sample.py CLASSES and ROWS), with
#: the Wishbone top's two-events mutant chosen by hand among those: bit 1 of the sum of the legs'
#: turn-on strobes (lost only when two legs turn on in the same clock)
SAMPLE = {
    "core": [
        ("rtl/mdfqm_gateware/integrator.py:125 integrator $add#0 B[7] const1",
         "datapath"),
        ("rtl/mdfqm_gateware/integrator.py:84 integrator $mux#0 B[4] const1",
         "datapath"),
        ("rtl/mdfqm_gateware/integrator.py:84 integrator $mux#0 A[22] const0",
         "row: reference beyond the linear range"),
        ("rtl/mdfqm_gateware/reference.py:59 reference $add#2 Y[11] inv",
         "row: common-mode offset"),
        ("rtl/mdfqm_gateware/reference.py:60 reference $mul#0 A[6] inv",
         "row: extreme codes"),
        ("rtl/mdfqm_gateware/sort.py:95 sort1 $mux#1 B[4] const0",
         "row: equal references (ties)"),
        ("rtl/mdfqm_gateware/sequencer.py:128 sequencer $lt#0 A[7] inv",
         "row: update period below the loop latency"),
        ("rtl/mdfqm_gateware/sequencer.py:146 sequencer $logic_not#0 A[6] const0",
         "row: OSR 0"),
        ("rtl/mdfqm_gateware/sequencer.py:129 sequencer $ge#0 A[7] inv",
         "row: sync_in at any time"),
        ("rtl/mdfqm_gateware/reference.py:53 reference $not#0 Y[0] inv",
         "row: a reference beat while one is pending"),
        ("rtl/mdfqm_gateware/integrator.py:84 integrator $mux#0 Y[24] const1",
         "datapath"),
        ("rtl/mdfqm_gateware/sequencer.py:93 sequencer $mux#0 S[0] const0",
         "row: runtime changes of period / OSR / zero policy / mode"),
        ("rtl/mdfqm_gateware/sequencer.py:124 sequencer $mux#0 S[0] const0",
         "row: reset in the middle of an update"),
    ],
    "generator": [
        ("rtl/mdfqm_gateware/resolution.py:229 quantiser $sub#3 B[10] const1",
         "datapath"),
        ("rtl/mdfqm_gateware/resolution.py:382 layout $sub#0 A[4] const1",
         "datapath"),
        ("rtl/mdfqm_gateware/sequencer.py:169 sequencer $mux#1 Y[3] cnot1/2",
         "row: illegal generator mode or bits"),
        ("rtl/mdfqm_gateware/resolution.py:190 quantiser $add#0 Y[9] inv",
         "datapath"),
    ],
    "driver": [
        ("rtl/mdfqm_gateware/driver.py:368~ top $not#0 Y[2] inv",
         "pin polarity"),
        ("rtl/mdfqm_gateware/driver.py:368~ top $not#0 Y[0] inv",
         "pin polarity"),
        ("rtl/mdfqm_gateware/driver.py:373 top $mux#0 S[0] const0",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/driver.py:373 top $mux#2 S[0] const1",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/driver.py:122 leg2 $mux#0 Y[8] cnot0/3",
         "row: dead time below the elaboration floor"),
        ("rtl/mdfqm_gateware/driver.py:151 leg1 $gt#0 A[11] inv",
         "row: a commanded pulse shorter than the minimum pulse"),
        ("rtl/mdfqm_gateware/driver.py:392 top $or#0 Y[0] inv",
         "row: fault input chatter, fault during a dead time"),
        ("rtl/mdfqm_gateware/driver.py:368~ top $not#0 Y[1] inv",
         "pin polarity"),
        ("rtl/mdfqm_gateware/driver.py:373 top $mux#2 S[0] const0",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/driver.py:427 top $mux#0 Y[1] cnot1/0",
         "row: a slot shorter than the dead time plus the minimum pulse"),
        ("rtl/mdfqm_gateware/driver.py:401 top $mux#0 S[0] const1",
         "row: enable toggled in the middle of an update"),
        # chosen among the 11 of 12 candidates at the reaction's lines that the driver's
        # stimulus kills (seed 7): a second source whose reaction is all off no longer ends an
        # active short circuit
        ("rtl/mdfqm_gateware/driver.py:458 top $or#2 B[0] const0",
         "row: a fault or a watchdog trip with an active short circuit chosen"),
    ],
    "top_wb": [
        ("rtl/mdfqm_gateware/driver.py:99 driver.leg1 $dff#0 Q[0] inv",
         "pin polarity"),
        ("rtl/mdfqm_gateware/driver.py:100 driver.leg2 $dff#0 Q[0] inv",
         "pin polarity"),
        ("rtl/mdfqm_gateware/fronts.py:60 front $and#1 B[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/fronts.py:60 front $and#1 A[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/top.py:371 top $add#3 B[2] const1",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/top.py:371 top $add#3 Y[0] inv",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/top.py:386 top $and#0 A[1] cnot0/4",
         "row: IRQ_STATUS written in the clock of a new event"),
        ("rtl/mdfqm_gateware/top.py:254 top $lt#0 A[11] inv",
         "row: any value to any register"),
        ("rtl/mdfqm_gateware/top.py:435 top $ge#0 B[13] inv",
         "row: the controller stops sending references (watchdog)"),
        ("rtl/mdfqm_gateware/driver.py:99 driver.leg0 $dff#0 Q[0] inv",
         "pin polarity"),
        ("rtl/mdfqm_gateware/top.py:371 top $add#2 Y[1] const0",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/sequencer.py:169 core.sequencer $mux#1 Y[0] const0",
         "row: MODULATION written with a mode not built in"),
    ],
    "top_axi": [
        ("rtl/mdfqm_gateware/fronts.py:143 front $and#0 Y[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/fronts.py:143 front $and#1 A[0] const1",
         "bus handshake (cyc or stb alone)"),
        ("rtl/mdfqm_gateware/top.py:386 top $and#0 B[3] const1",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/top.py:386 top $and#0 Y[4] const1",
         "two events in one clock"),
        ("rtl/mdfqm_gateware/fronts.py:133 front $shift#1 A[6] inv",
         "row: AXI4-Lite: an access to a word that holds no register"),
    ],
}
CLASSES = ("pin polarity", "bus handshake (cyc or stb alone)", "two events in one clock")


def test_the_sample_covers_every_block_fault_class_and_robustness_row():
    assert set(SAMPLE) == set(sample.BLOCKS)
    assert all(SAMPLE.values())
    classes = {fault_class for entries in SAMPLE.values() for _, fault_class in entries}
    assert set(CLASSES) <= classes
    assert {f"row: {row}" for row in sample.ROWS} <= classes


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
