# amaranth: UnusedElaboratable=no
"""tools/mutate without a campaign: mutation keys name source text and kind, survive edits
elsewhere in the file and come back to the same cell, a stale key says how to draw the sample
again; the registry agrees with the source and with docs/robustness.md; a flop's mutated bit
keeps its power-up value, the wrapper and the miter have the block's ports; a proof decides a
kill only with a counterexample from reset; the report reads a counterexample and tallies a
database; an invariant probe proves only a mutation that changes nothing, a reading's proof
only with lemmas that hold. The campaign itself is ``make mutate``; its sample in ``make
test`` is tb/test_mutation_sample.py."""

import json
from pathlib import Path

import pytest
from amaranth import Cat, Module, Mux, Signal
from amaranth.hdl import Assert
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_gateware.driver import GateDriver
from tools.mutate import campaign, keys, netlist, registry, report, sample, stages
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


def test_a_key_whose_source_text_is_gone_says_how_to_draw_the_sample_again(driver_netlist):
    key = driver_netlist.sample(1, 5)[0].key
    source, rest = key.split(" ", 1)
    file = source.split("@")[0]
    with pytest.raises(keys.StaleKeyError) as gone:
        driver_netlist.index.resolve(f"{file}@00000000 {rest}")
    assert "no longer in" in str(gone.value) and keys.REDRAW in str(gone.value)
    scope, typed, port, mode = rest.split(" ")
    with pytest.raises(keys.StaleKeyError) as missing:
        driver_netlist.index.resolve(f"{source} {scope} {typed.split('#')[0]}#999 {port} {mode}")
    assert "the logic changed" in str(missing.value) and keys.REDRAW in str(missing.value)


_SOURCE = """from amaranth import Mux


def build(m, a, b, c):
    m.d.comb += a.eq(Mux(b, c,   # the select
                         0))
    m.d.sync += [
        b.eq(c),
        c.eq(a + 1),
    ]
    with m.If(a ==
              3):
        m.d.sync += c.eq(0)
    ports = {"upper": 1,
             "lower": 2}
    return ports
"""


def test_a_source_unit_is_the_smallest_piece_around_its_line(tmp_path):
    path = tmp_path / "unit.py"
    path.write_text(_SOURCE)
    lines = _SOURCE.splitlines()

    def at(text):
        return keys.unit_at(path, next(i for i, line in enumerate(lines, 1) if text in line))

    assert at("# the select").text == at("0))").text == "m.d.comb += a.eq(Mux(b, c, 0))"
    assert at("c.eq(a + 1)").text == "c.eq(a + 1)"              # one entry of the list
    assert at("with m.If").text == at("3):").text == "with m.If(a == 3)"    # the header only
    assert at("m.d.sync += c.eq(0)").text == "m.d.sync += c.eq(0)"
    assert at('"lower": 2').text == "'lower': 2"                 # one entry of the dict


def test_keys_survive_edits_elsewhere_in_the_file_and_not_of_their_own_text(tmp_path):
    path = tmp_path / "unit.py"
    path.write_text(_SOURCE)
    line = next(i for i, text in enumerate(_SOURCE.splitlines(), 1) if "c.eq(a + 1)" in text)
    wanted = keys.unit_at(path, line).digest
    # lines added above it, comments and spacing changed: the same unit, found at its new line
    path.write_text("# a new first line\n\n" + _SOURCE.replace("c.eq(a + 1)", "c.eq(a+1)  # x"))
    found = keys.locate(path, wanted)
    assert [(u.first, u.text) for u in found] == [(line + 2, "c.eq(a + 1)")]
    # its own text edited: gone
    path.write_text(_SOURCE.replace("c.eq(a + 1)", "c.eq(a + 2)"))
    assert keys.locate(path, wanted) == []


def test_a_key_parses_back_to_itself():
    text = "rtl/mdfqm_gateware/driver.py@0123abcd~ leg0 $mux#2 Y[3] cnot1/7"
    key = keys.Key.parse(text)
    assert str(key) == text and key.files == ("rtl/mdfqm_gateware/driver.py",)
    assert (key.scope, key.type, key.rank, key.port, key.bit, key.mode, key.ctrlbit) == \
        ("leg0", "$mux", 2, "Y", 3, "cnot1", 7)
    assert str(keys.Key.parse("nosrc top $and#0 A[0] const1")) == "nosrc top $and#0 A[0] const1"
    with pytest.raises(keys.StaleKeyError, match="not a mutation key"):
        keys.Key.parse("rtl/mdfqm_gateware/driver.py:12 leg0 $mux#2 Y[3] inv")   # a line


def test_the_registry_names_source_text_that_exists():
    """Every key of the registry (the sample, the readings) names source text the files hold
    now: a key whose text was edited away is found here, without a netlist."""
    stale = [entry for entry in [*(e.key for e in registry.SAMPLE),
                                 *(r.key for r in registry.READINGS)]
             if any(unit is None for _, unit in keys.Key.parse(entry).where(netlist.ROOT))]
    assert not stale, (f"keys whose source text is gone: {stale}; draw the sample again with "
                       f"`{keys.REDRAW}` (a reading: its key from the campaign's report)")
    assert len({(e.block, e.key) for e in registry.SAMPLE}) == len(registry.SAMPLE)
    assert len({r.key for r in registry.READINGS}) == len(registry.READINGS)


def test_the_registrys_sample_is_as_its_writer_writes_it(tmp_path):
    """The SAMPLE section is the writer's (``--write``): written again from itself, with its
    origin, the registry is unchanged (a hand edit, or a comment that no longer shows the
    text its key names, fails here)."""
    copy = tmp_path / "registry.py"
    copy.write_text(sample.REGISTRY.read_text())
    sample.write_registry(list(registry.SAMPLE), sample.registry_origin(copy), copy)
    assert copy.read_text() == sample.REGISTRY.read_text()


def test_each_sample_mutant_is_of_its_class_or_rows_logic():
    """A sample mutant sits at the source its class or row of tools/mutate/sample.py names, with
    one of its modes and ports (what the draw would pick there)."""
    specs = {**sample.CLASSES, **{f"row: {row}": spec for row, spec in sample.ROWS.items()}}
    for entry in registry.SAMPLE:
        path, pattern, modes, ports = specs[entry.why][entry.block]
        key = keys.Key.parse(entry.key)
        units = {f"{path}@{keys.unit_at(netlist.ROOT / path, int(line.rpartition(':')[2])).digest}"
                 for line in sample.lines_matching(path, pattern)}
        assert {s.rstrip("~") for s in key.sources} & units, (entry, pattern)
        assert key.mode in modes, entry
        assert ports is None or key.port in ports or f"{key.port}[{key.bit}]" in ports, entry


def test_the_robustness_table_names_the_registrys_sample():
    """docs/robustness.md's last column is the registry's: written by `python -m
    tools.mutate.sample --docs`, every row (but the one without gateware) names its mutant."""
    assert sample.docs_mismatches() == [], (
        "docs/robustness.md and tools/mutate/registry.py disagree: `python -m "
        "tools.mutate.sample --docs` writes the column from the registry")


def test_the_mutation_tool_uses_public_interfaces_only():
    """tools/mutate reaches into nothing private: no sys.path edits, no private attributes of
    Amaranth or of another library's objects, no test module imported or written to (the test
    kit, mdfqm_testkit, is the interface)."""
    import re

    for path in sorted((netlist.ROOT / "tools" / "mutate").glob("*.py")):
        text = path.read_text()
        assert "sys.path" not in text, path
        assert not re.search(r"(from|import) tb\b|tb\.test_\w+\.", text), path
        # an attribute with a leading underscore of any object but the tool's own (self, or a
        # class of the tool named in a docstring)
        private = [m.group(0) for m in re.finditer(r"\b(?!self\b|cls\b)[a-z]\w*\._[a-z]\w*",
                                                   text)]
        assert not private, (path, private)
        assert '"_processes"' not in text and "__dict__" not in text, path


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
    results["c"]["by"] = "reading"
    results["d"]["undecided"] = ["formal"]
    tally = campaign.counts(results)
    assert tally == {"tried": 4, "killed": 2, "vector": 1, "cocotb": 0, "formal": 1,
                     "inner": 0, "equivalent": 1, "undecided": 0, "survived": 1, "went_on": 1,
                     "proven_invariant": 0, "proven_reading": 1, "proven_equiv": 0,
                     "proven_inner": 0}
    line = campaign.summary_line({"driver": tally}, 120)
    assert ("4 mutants: 2 killed (vector 1, cocotb 0, formal 1, inner block 0), 1 equivalent"
            in line)
    assert "66.7 % of the non-equivalent killed; 2.0 min" in line


def test_an_inner_blocks_key_is_the_outer_key_without_the_instance():
    source = "rtl/mdfqm_gateware/resolution.py@d841a694"
    assert (campaign.inner_key(f"{source} core.quantiser $add#0 B[1] inv", "core")
            == f"{source} quantiser $add#0 B[1] inv")
    assert (campaign.inner_key(f"{source} core $mux#0 B[3] const1", "core")
            == f"{source} top $mux#0 B[3] const1")
    for outside in ("top", "driver.leg0", "core_x.y"):
        assert campaign.inner_key(f"{source} {outside} $mux#0 B[3] const1", "core") is None


def test_an_inner_blocks_verdict_kills_or_proves_only_what_it_may():
    """Killed in the inner block: killed (by its stage); proven equivalent there: an
    undecided mutant is equivalent, a survivor (a difference the outer block showed) stays;
    anything else, or no cell there: the record as it was, the inner block's finding logged."""
    undecided = {"status": "undecided", "stage": "equivalence", "detail": "no difference",
                 "log": ["vector: 10 clocks equal"]}
    survived = {**undecided, "status": "survived", "detail": "an output differs"}
    killed = {"status": "killed", "stage": "vector", "detail": "run0: 3 mismatches"}
    proven = {"status": "equivalent", "stage": "equivalence", "by": "equiv", "detail": "proven"}
    still = {"status": "undecided", "stage": "equivalence", "detail": "no difference there"}
    got = campaign.merged(survived, killed, "generator")
    assert (got["status"], got["stage"]) == ("killed", "inner")
    assert got["detail"] == "by generator's vector stage: run0: 3 mismatches"
    got = campaign.merged(undecided, proven, "generator")
    assert (got["status"], got["by"]) == ("equivalent", "inner")
    assert campaign.merged(survived, proven, "generator")["status"] == "survived"
    for inner in (still, None):
        got = campaign.merged(undecided, inner, "generator")
        assert {k: v for k, v in got.items() if k not in ("log", "inner")} == {
            k: v for k, v in undecided.items() if k != "log"}
        assert got["inner"] == "generator" and got["log"][:-1] == undecided["log"]
        assert got["log"][-1].startswith("generator's stages: ")
    assert campaign.counts({"a": campaign.merged(survived, killed, "generator")})["inner"] == 1


def test_an_inner_block_is_built_as_its_own_campaign_builds_it():
    """An outer block's instance of an inner block has the inner block's class and
    parameters: the same netlist, so that the same mutation key names the same fault."""
    import inspect

    from amaranth.hdl import Fragment

    from tools.mutate.blocks import BLOCKS

    pairs = [(outer, scope, inner) for outer in BLOCKS.values() for scope, inner in outer.inner]
    assert pairs, "no block has an inner block"
    for outer, scope, inner in pairs:
        fragment = Fragment.get(outer.build(False), None)
        (instance,) = [f.origins[0] for f, name, _ in fragment.subfragments if name == scope]
        alone = BLOCKS[inner].build(False)
        assert type(instance) is type(alone), (outer.name, scope)
        for name in inspect.signature(type(alone).__init__).parameters:
            if name != "self":
                assert getattr(instance, name) == getattr(alone, name), (outer.name, name)


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
    assert any("kill_common = self.all_off" in text for text in lines)
    assert any("kill_if_clear = kill_common | ~self.stop" in text for text in lines)
    assert any("drive_if_clear.eq(Mux(self.update" in text for text in lines)
    assert any(text.startswith("m.d.comb += asc.eq(asc_lo | asc_hi)") for text in lines)
    assert any(text.startswith("nxt_up.eq(Mux(asc, ") for text in lines)
    assert any("asc_lo.eq(Mux(fault_active, now_if_fault == 1" in text for text in lines)
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


class _Decade12(wiring.Component):
    """The decade counter with one property: ``count`` is never ``bad``. 12 is unreachable but
    the step from 11 reaches it (an induction of one step fails, of four closes: 10 has no
    predecessor); 5 is reached from reset."""

    o: Out(1)

    def __init__(self, bad: int):
        self.bad = bad
        super().__init__()

    def elaborate(self, platform):
        m = Module()
        count = Signal(4)
        m.d.sync += count.eq(Mux(count == 9, 0, count + 1))
        m.d.comb += [self.o.eq(count[0]), Assert(count != self.bad, "never bad")]
        return m


def test_only_a_counterexample_from_reset_is_a_formal_kill():
    """The proof's verdicts from real SymbiYosys runs: a counterexample from reset kills; an
    induction that no longer closes (no counterexample from reset) is undecided, never a kill;
    a proof passes."""
    verdicts = {(bad, depth): stages.run_formal(_Decade12(bad), f"verdict_{bad}_{depth}", depth,
                                                None)
                for bad, depth in ((5, 8), (12, 1), (12, 4))}
    assert verdicts[(5, 8)]["verdict"] == stages.KILLED and verdicts[(5, 8)]["killed"]
    assert "counterexample at step" in verdicts[(5, 8)]["detail"]
    assert "never bad" in verdicts[(5, 8)]["detail"]
    assert verdicts[(12, 1)]["verdict"] == stages.UNDECIDED
    assert not verdicts[(12, 1)]["killed"] and "not a kill" in verdicts[(12, 1)]["detail"]
    assert verdicts[(12, 4)]["verdict"] == stages.PASSED


def test_a_run_without_a_verdict_raises_and_a_time_limit_is_undecided():
    assert stages.formal_verdict("... DONE (TIMEOUT, rc=8)", "x")["verdict"] == stages.UNDECIDED
    with pytest.raises(RuntimeError, match="did not run"):
        stages.formal_verdict("... DONE (ERROR, rc=16)", "x")
    with pytest.raises(RuntimeError, match="without a verdict"):
        stages.formal_verdict("something else", "x")


def test_an_input_probe_compares_the_cells_outputs():
    """``count[3] & count[2]`` with its input ``count[2]`` stuck at 0: the input bit differs
    (count 4 to 7) but the AND's output never does (count[3] is 0 then): proven equivalent, the
    copy of the cell compared with the original. Inverted, the output differs at 8: not
    proven."""
    decade = BlockNetlist(_Decade(), BUILD / "decade")
    gate = next(name for name, cell in decade.index.cells.items() if cell["type"] == "$and")
    port = next(p for p in ("A", "B") if _reads_bit(decade, gate, p, 2))
    verdicts = {}
    for mode in ("const0", "inv"):
        mutation = decade.index.resolve(decade.index.key(gate, port, 0, mode, None))
        assert netlist.worth_a_probe(decade.directory, mutation)
        probe = netlist.write_invariant_probe(decade.directory, mutation, f"probe-in-{mode}")
        assert "the mutated cell's outputs differ from the original's" in probe.read_text()
        verdicts[mode] = stages.run_invariant(_Decade(), f"decade_in_{mode}", 5, probe)["verdict"]
    assert verdicts == {"const0": "equivalent", "inv": "undecided"}


def _reads_bit(block: BlockNetlist, cell: str, port: str, bit: int) -> bool:
    """Whether ``cell``'s ``port`` reads bit ``bit`` of the counter (its only multi-bit wire)."""
    module = json.loads((block.directory / "sim.json").read_text())["modules"]["dut"]
    count = next(net["bits"] for name, net in module["netnames"].items()
                 if not name.startswith("$") and len(net["bits"]) == 4)
    return module["cells"][cell]["connections"][port] == [count[bit]]


class _Twins(wiring.Component):
    """Two decade counters from the same reset, so always equal, and an AND of the first's bit
    3 and the second's bit 2: never 1. An induction over the AND alone fails (states where the
    counters differ, 3 and 15, lead to 8 and 4); with the lemma that they are equal it closes."""

    o: Out(2)

    def elaborate(self, platform):
        m = Module()
        a, b = Signal(4, name="a"), Signal(4, name="b")
        m.d.sync += [a.eq(Mux(a == 9, 0, a + 1)), b.eq(Mux(b == 9, 0, b + 1))]
        m.d.comb += self.o.eq(Cat(a[3] & b[2], a[0]))
        return m


def test_a_readings_proof_backs_it_only_with_lemmas_that_hold(tmp_path):
    """The AND stuck at 0 (the reading: the counters are equal and below 10): the probe alone
    does not close; with the lemma ``a == b`` the reading's proof does (equivalent); a wrong
    lemma fails from reset (the reading is wrong: undecided); a lemma naming no wire backs
    nothing (undecided, said so)."""
    twins = BlockNetlist(_Twins(), BUILD / "twins")
    gate = next(name for name, cell in twins.index.cells.items() if cell["type"] == "$and")
    mutation = twins.index.resolve(twins.index.key(gate, "Y", 0, "const0", None))
    alone = netlist.write_invariant_probe(twins.directory, mutation, "probe-alone")
    assert stages.run_invariant(_Twins(), "twins_alone", 5, alone)["verdict"] == "undecided"

    block = campaign.Block("twins", "twins", "twins", lambda formal: _Twins(), lambda seed: [],
                           formal_depth=5)
    results = {}
    for name, asserts in (("holds", ("{a} == {b}",)), ("wrong", ("{a} != {b}",)),
                          ("unknown", ("{nowhere} == 0",))):
        results[name] = campaign.check_reading(block, twins.directory, mutation,
                                               registry.Proof(asserts), 1)
    assert results["holds"]["verdict"] == "equivalent", results["holds"]
    assert "1 lemma(s)" in results["holds"]["detail"]
    assert results["wrong"]["verdict"] == "undecided"
    assert "fails from reset" in results["wrong"]["detail"]
    assert results["unknown"]["verdict"] == "undecided"
    assert "no wire nowhere" in results["unknown"]["detail"]


def test_the_report_counts_a_reading_only_through_its_proof(tmp_path, monkeypatch):
    """A database with a kill, an equivalent mutant proven by a reading's proof and an
    undecided one with a reading but no passing proof: the first is *equivalent* (its proof
    named), the second stays *undecided* and its reading is printed as an explanation, not
    checked; a mutant that went on past an undecided proof is counted so, not as a kill."""
    read_key = "rtl/mdfqm_gateware/top.py@00000000 top $dff#0 Q[4] inv"
    proven = registry.Reading(read_key, "a reading with a proof",
                              registry.Proof(("{adc_cnt} == {core.sequencer.phase}",)))
    monkeypatch.setattr(registry, "READINGS", (*registry.READINGS, proven))
    unread_key = next(r.key for r in registry.READINGS if r.proof is None)
    records = {
        "k": {"status": "killed", "stage": "vector", "detail": "run0: 3 mismatches",
              "log": ["vector: run0: 3 mismatches"]},
        read_key: {"status": "equivalent", "stage": "equivalence", "by": "reading",
                   "detail": "proven by the reading's proof", "log": ["reading: proven"],
                   "undecided": ["formal"]},
        unread_key: {"status": "undecided", "stage": "equivalence",
                     "detail": "no difference within 11 clocks of reset; not proven equivalent",
                     "log": ["vector: 10 clocks equal", "equivalence: no difference"]},
    }
    mutations = [{"key": key, "wire": "", "src": []} for key in records]
    (tmp_path / "db" / "top_wb").mkdir(parents=True)
    (tmp_path / "db" / "top_wb" / "results.json").write_text(json.dumps({
        "title": "top, Wishbone", "seed": 1, "jobs": 2, "seconds": 60, "date": "2026-01-02",
        "mutations": mutations, "results": records}))
    text = report.write_report(tmp_path, "python -m tools.mutate",
                               tmp_path / "db").read_text()
    assert ("| top, Wishbone | 3 | 1 (1 / 0 / 0 / 0) | 1 (0 / 1 / 0 / 0) | 1 (1) | 0 | 50.0 % |"
            in text)
    assert "1 mutants went on past a stage that could not decide" in text
    assert "results of 2026-01-02" in text
    equivalent, survivors = (text.split("## Equivalent by a reading's proof")[1],
                             text.split("## Survivors and undecided mutants")[1])
    assert read_key in equivalent and "reading, proven (its lemmas: `{adc_cnt}" in equivalent
    assert unread_key in survivors.split("## Equivalent")[0]
    assert "reading (an explanation, not checked: no proof backs it)" in survivors
    assert "## Traceability" in text
