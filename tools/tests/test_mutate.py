# amaranth: UnusedElaboratable=no
"""tools/mutate without a campaign: mutation keys name source and kind and come back to the same
cell, a flop's mutated bit keeps its power-up value, the wrapper and the miter have the block's
ports, the report reads a counterexample and tallies a database, an invariant probe proves
only a mutation that changes nothing. The campaign itself is
``make mutate``; its sample in ``make test`` is tb/test_mutation_sample.py."""

import json
from pathlib import Path

import pytest
from amaranth import Cat, Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_gateware.driver import GateDriver
from tools.mutate import campaign, netlist, report, stages
from tools.mutate.netlist import BlockNetlist, CellIndex, split_cell, switch_sources

BUILD = netlist.ROOT / "build" / "mutate" / "unit"


@pytest.fixture(scope="module")
def driver_netlist():
    return BlockNetlist(GateDriver(2, 3, 6, True, False, formal=True), BUILD / "driver")


def test_cell_names_split_into_scope_and_local_name():
    assert split_cell("$flatten\\core.\\sort1.$45") == ("core.sort1", "$45")
    assert split_cell("$flatten\\leg0.$procmux$85") == ("leg0", "$procmux$85")
    assert split_cell("$12") == ("", "$12")


def test_short_src_is_relative_to_the_repository():
    assert netlist.short_src(f"{netlist.ROOT}/rtl/mdfqm_gateware/top.py:12") == \
        "rtl/mdfqm_gateware/top.py:12"
    assert netlist.short_src("/x/lib/python3.11/site-packages/amaranth/lib/cdc.py:102.3-4") \
        == "amaranth/lib/cdc.py:102"


def test_switches_take_their_process_source():
    text = ('  attribute \\src "a.py:3"\n  process $1\n    switch \\x\n      case 1\'1\n'
            "    end\n  end\n")
    out = switch_sources(text).splitlines()
    assert out[2] == '    attribute \\src "a.py:3"' and out[3] == "    switch \\x"


def test_keys_name_source_and_kind_and_resolve_to_the_same_cell(driver_netlist):
    mutations = driver_netlist.sample(30, 3)
    assert len({m.key for m in mutations}) == len(mutations) == 30
    for m in mutations:
        assert m.key.startswith(("rtl/", "amaranth/")), m.key
        assert "$" not in m.key.split(" ")[0]
        again = driver_netlist.index.resolve(m.key)
        assert (again.cell, again.port, again.bit, again.mode, again.ctrlbit) == \
            (m.cell, m.port, m.bit, m.mode, m.ctrlbit)
    with pytest.raises(KeyError):
        driver_netlist.index.resolve("rtl/x.py:1 top $and#0 Y[0] inv")


def test_a_mutated_flop_bit_keeps_its_power_up_value(driver_netlist):
    index = CellIndex(driver_netlist.directory / "sim.json")
    flops = [(cell, bit) for (cell, bit), value in index.ff_init.items() if value == "1"]
    assert flops, "the leg's count register powers up at 1"
    cell, bit = flops[0]
    assert index.init(cell, "Q", bit) == "1" and index.init(cell, "D", bit) is None
    m = netlist.Mutation("k", cell, "inv", "Q", bit, None, "", (), "1")
    assert m.commands()[1].startswith("setattr -set init 1'1 dut/c:")


def test_the_mutants_netlist_and_its_wrapper(driver_netlist):
    mutations = driver_netlist.sample(5, 1)
    path = driver_netlist.write_mutants(mutations, "drv_mutants")
    text = path.read_text()
    assert "module drv_mutants" in text and "mutsel" in text
    ports = ([("rst", 1), ("h", 2)], [("event", 2), ("upper", 2)])
    wrap = netlist.wrapper("gate_driver", "drv_mutants", ports, netlist.mutsel_width(5))
    assert "output [1:0] \\event ," in wrap and ".mutsel(mutsel)" in wrap
    assert "input [2:0]" not in wrap and "reg [2:0] mutsel;" in wrap
    miter = stages.miter_verilog("drv_mutants", ports, 3, 4)
    assert ".mutsel(3'd0)" in miter and ".mutsel(3'd4)" in miter
    assert "assert (gold_event == gate_event);" in miter and "assume (rst);" in miter


def test_the_first_difference_of_a_counterexample(tmp_path):
    vcd = tmp_path / "trace.vcd"
    vcd.write_text("$scope module miter $end\n$var wire 2 ! gold_upper $end\n"
                   "$var wire 2 \" gate_upper $end\n$upscope $end\n$enddefinitions $end\n"
                   "#0\nb00 !\nb00 \"\n#5\n#10\nb01 !\nb11 \"\n#15\n")
    assert report.first_difference(Path(vcd)) == "upper: original 1, mutant 3, clock 1"


def test_tallies_and_the_summary_line():
    results = {"a": {"status": "killed", "stage": "vector"},
               "b": {"status": "killed", "stage": "formal"},
               "c": {"status": "equivalent", "stage": "equivalence"},
               "d": {"status": "survived", "stage": "equivalence"}}
    tally = campaign.counts(results)
    assert tally == {"tried": 4, "killed": 2, "vector": 1, "cocotb": 0, "formal": 1,
                     "equivalent": 1, "undecided": 0, "survived": 1}
    line = campaign.summary_line({"driver": tally}, 120)
    assert "4 mutants: 2 killed (vector 1, cocotb 0, formal 1), 1 equivalent" in line
    assert "66.7 % of the non-equivalent killed; 2.0 min" in line


def test_a_resumed_run_keeps_the_records_its_retry_option_does_not_run_again():
    results = {status: {"status": status} for status in
               ("killed", "equivalent", "undecided", "survived")}
    kept = {name: set(campaign.kept_records(results, campaign.Settings(**options)))
            for name, options in (("resume", {}), ("retry", {"retry": True}),
                                  ("retry_survived", {"retry_survived": True}))}
    assert kept == {"resume": set(results), "retry": {"killed", "equivalent"},
                    "retry_survived": {"killed", "equivalent", "undecided"}}


def test_a_flop_moved_to_the_other_clock_edge_skips_the_formal_stage(tmp_path):
    """A mutation of a flop's clock port is outside the one-edge formal model (SymbiYosys's
    prep refuses the netlist, which left an error row before): the formal stage is recorded
    as not run, and not counted as a kill."""
    mutation = {**campaign.ORIGINAL, "key": "k", "cell": "$1", "mode": "inv", "port": "CLK"}
    record = campaign.evaluate({"block": "driver", "directory": str(tmp_path),
                                "stages": ["formal"]}, 1, mutation)
    assert record["status"] == "survived"
    assert record["log"] == [f"formal: not run: {campaign.OTHER_EDGE}"]


def test_the_regions_with_a_full_target_are_found_in_the_source():
    zones = report.regions()
    assert any("fronts.py" in line for line in zones["register write decode"])
    assert any("top.py" in line for line in zones["register write decode"])
    assert any("driver.py" in line for line in zones["fault path"])
    # the fault reaction's logic: the reaction in force and the legs' active short circuit
    lines = {report.line_text(line) for line in zones["fault path"]}
    assert any("kill = (~(fault_active | self.stop)" in text for text in lines)
    assert any(text.startswith("asc_keep = ") for text in lines)
    assert any("asc_lo.eq(now == 1)" in text for text in lines)
    assert report.in_region({"src": ["amaranth/lib/cdc.py:102"]}, zones["fault path"])
    assert not report.in_region({"src": ["amaranth/lib/cdc.py:102"]},
                                zones["register write decode"])


def test_the_bits_where_a_mutation_shows(driver_netlist):
    """An output-port mutation shows on its own bit; an input-port one on what the cell
    drives, followed through internal wires to the first named ones."""
    import json

    sim = driver_netlist.directory / "sim.json"
    cells = json.loads(sim.read_text())["modules"]["dut"]["cells"]
    flop = next(name for name, c in cells.items() if c["type"].endswith("dff")
                and len(c["connections"]["Q"]) > 1)
    named = stages.mutated_bits(sim, flop, "Q", 1)
    assert len(named) <= 1 and all(b.endswith("[1]") for b in named)
    assert stages.mutated_bits(sim, flop, "D", 1) == named


def test_a_memorys_control_ports_are_not_drawn():
    """A ROM's read-port reset, enable or clock behind ``mutate -ctrl``'s multiplexer fails
    Yosys's Verilog writer (an internal assertion): only its address and data are mutated."""

    class Index:
        def __init__(self):
            self.cells = {"rom": {"type": "$mem_v2"}, "gate": {"type": "$and"}}

        def key(self, cell, port, bit, mode, ctrlbit):
            return f"{cell} {port}[{bit}] {mode}"

        def init(self, cell, port, bit):
            return None

    lines = [f"mutate -mode {mode} -module dut -cell {cell} -port {port} -portbit 0 -src /a.py:1"
             for mode, cell, port in (("const0", "rom", "RD_ARST"), ("inv", "rom", "RD_EN"),
                                      ("inv", "rom", "RD_DATA"), ("inv", "rom", "RD_ADDR"),
                                      ("const1", "gate", "A"))]
    assert [m.key for m in netlist.parse_list(lines, Index())] == \
        ["rom RD_DATA[0] inv", "rom RD_ADDR[0] inv", "gate A[0] const1"]


class _Decade(wiring.Component):
    """A counter from 0 to 9 (its bits 3 and 2 are never both set) and its parity."""

    o: Out(2)

    def elaborate(self, platform):
        m = Module()
        count = Signal(4)
        m.d.sync += count.eq(Mux(count == 9, 0, count + 1))
        m.d.comb += self.o.eq(Cat(count[3] & count[2], count[0]))
        return m


def test_an_invariant_probe_proves_only_a_mutation_that_changes_nothing():
    """The probe: the mutated bit always equals the original. ``count[3] & count[2]`` stuck
    at 0 changes nothing (the counter never reaches 12): proven equivalent by the block's
    k-induction. Stuck at 1 it differs from the first clock: not proven."""
    decade = BlockNetlist(_Decade(), BUILD / "decade")
    gate = next(name for name, cell in decade.index.cells.items() if cell["type"] == "$and")
    verdicts = {}
    for mode in ("const0", "const1"):
        mutation = decade.index.resolve(decade.index.key(gate, "Y", 0, mode, None))
        probe = netlist.write_invariant_probe(decade.directory, mutation, f"probe-{mode}")
        assert "the mutated bit differs from the original" in probe.read_text()
        verdicts[mode] = stages.run_invariant(_Decade(), f"decade_{mode}", 5, probe)["verdict"]
    assert verdicts == {"const0": "equivalent", "const1": "undecided"}


class _HeldAfterReset(wiring.Component):
    """A register loaded every clock and read only while a valid flag (reset with it) is set:
    its reset value is never read."""

    d: In(4)
    valid_in: In(1)
    o: Out(4)

    def elaborate(self, platform):
        m = Module()
        held = Signal(4, name="held")
        valid = Signal(name="valid")
        m.d.sync += [held.eq(self.d), valid.eq(self.valid_in)]
        plus = Signal(4, name="plus")           # a public follower of held
        m.d.comb += [plus.eq(held + 1), self.o.eq(Mux(valid, plus, 0))]
        return m


def test_the_equivalence_check_proves_an_unread_reset_value_and_finds_a_difference():
    """``held``'s reset value inverted (the reset multiplexer's ``B``) is never read: proven
    equivalent, once the rounds go on past a failing base case (``plus``, a follower of the
    unpaired bit, differs in the clock after reset; the check that stopped there said
    undecided). Its loaded value inverted (``A``) is read: not equivalent, a counterexample
    from reset."""
    from mdfqm_testkit.vectors import ports_of

    block = BlockNetlist(_HeldAfterReset(), BUILD / "held")
    cells = json.loads((block.directory / "sim.json").read_text())["modules"]["dut"]["cells"]
    # the reset multiplexer of held: B its reset value 0, A the loaded d
    mux = next(name for name, cell in cells.items() if cell["type"] == "$mux"
               and cell["connections"]["B"] == ["0"] * 4)
    verdicts = {}
    for port in ("B", "A"):
        mutation = block.index.resolve(block.index.key(mux, port, 1, "inv", None))
        block.write_mutants([mutation], "held_mutants", f"held_{port}")
        verdicts[port] = stages.run_equivalence(
            block.directory, block.directory / f"held_{port}.il", "held_mutants",
            ports_of(_HeldAfterReset()), netlist.mutsel_width(1), 1, 4, 60,
            tuple(stages.mutated_bits(block.directory / "sim.json", mux, port, 1)),
        )["verdict"]
    assert verdicts == {"B": "equivalent", "A": "not equivalent"}
