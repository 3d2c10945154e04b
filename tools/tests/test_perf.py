"""tools/perf.py without place and route: the design list follows the drop-in files, the table
puts met / MISSED right, the serial wrapper feeds every port bit of a design."""

import re

import pytest
from amaranth.back import rtlil

from mdfqm_gateware.core import MdfqmCore
from mdfqm_gateware.dropin import default_configs
from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_gateware.top import MdfqmTop
from tools import perf

PARAMS = ("phases", "width", "rule", "max_bits", "bus", "counter_width", "dead_min")


def _params(component):
    return type(component), {p: getattr(component, p, None) for p in PARAMS}


def test_configs_cover_the_drop_in_files():
    configs = {c.dropin: c for c in perf.CONFIGS}
    dropins = default_configs(3, 16)
    assert len(dropins) == 4
    for name, factory in dropins:
        assert name in configs, f"drop-in {name} not measured"
        assert _params(configs[name].build()) == _params(factory())
    # and the core at N = 5, as the drop-in file for five phases
    name, factory = default_configs(5, 16)[0]
    assert _params(configs[name].build()) == _params(factory())
    assert len({c.key for c in perf.CONFIGS}) == len(perf.CONFIGS) == 5
    assert [c.design for c in perf.CONFIGS] == [
        "core", "core", "generator (b<=8)", "top, Wishbone", "top, AXI4-Lite"]


def test_targets():
    targets = {c.key: c.targets for c in perf.CONFIGS}
    assert targets["core3"] == {"up5k": 48, "hx8k": 100, "ecp5": 150}
    assert targets["top_wb"] == targets["top_axil"] == {"up5k": 40, "hx8k": 90, "ecp5": 130}
    assert targets["core5"] == targets["generator"] == {}
    assert {d.key for d in perf.DEVICES} == set(perf.CORE_TARGETS) == set(perf.TOP_TARGETS)
    # nextpnr is asked for the core's target on every row, as before
    assert {d.key: d.target_mhz for d in perf.DEVICES} == perf.CORE_TARGETS


def _row(key, device_key, fmax, **extra):
    config = next(c for c in perf.CONFIGS if c.key == key)
    device = next(d for d in perf.DEVICES if d.key == device_key)
    row = {"key": key, "design": config.design, "phases": 5 if key == "core5" else 3,
           "width": 16, "device": device.name, "device_key": device_key,
           "target": config.targets.get(device_key), "fmax": fmax, "latency": 8,
           "long_latency": None, "luts": 1000, "ffs": 900, "carry": 300}
    return {**row, **extra}


def _cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def test_table_marks_met_and_missed():
    rows = [
        _row("core3", "up5k", 47.9),
        _row("core3", "hx8k", 100.0),
        _row("core5", "ecp5", 120.0, latency=11),
        _row("generator", "up5k", 44.0, long_latency=20, long_period=256, max_bits=8),
        _row("top_wb", "up5k", 40.2),
        _row("top_axil", "ecp5", 129.9),
    ]
    text = perf.table(rows, "Yosys X, nextpnr-Y")
    body = [_cells(line) for line in text.splitlines() if line.startswith("| ")]
    header, *cells = body
    assert header[:6] == ["design", "N / width", "device", "loop latency (clocks)",
                          "Fmax (MHz)", "target (MHz)"]
    column = {name: i for i, name in enumerate(header)}
    got = [(c[column["design"]], c[column["target (MHz)"]]) for c in cells]
    assert got == [("core", "48 (MISSED)"), ("core", "100 (met)"), ("core", "-"),
                   ("generator (b<=8)", "-"), ("top, Wishbone", "40 (met)"),
                   ("top, AXI4-Lite", "130 (MISSED)")]
    assert cells[0][column["max update rate (MHz)"]] == f"{47.9 / 8:.2f}"
    assert cells[2][column["max update rate (MHz)"]] == f"{120 / 11:.2f}"
    assert cells[2][column["N / width"]] == "5 / 16"
    generator = cells[3]
    assert generator[column["loop latency (clocks)"]] == "8 short, 20 long"
    assert generator[column["max update rate (MHz)"]].startswith(
        f"{44 / 8:.2f} short, {44 / 256:.3f} long at b = 8")
    assert "256 at b = 8" in text and "Yosys X, nextpnr-Y" in text


def test_paths_report_names_both_ends():
    row = _row("top_wb", "hx8k", 95.0, log="build/perf/top_wb_hx8k/nextpnr.log",
               critical={"from": "a_DFFLC", "to": "b_DFFLC", "from_net": "a", "to_net": "b_D",
                         "delay_ns": 10.5, "logic_levels": 7})
    text = perf.paths_report([row, _row("core3", "up5k", 45.0, critical=None)])
    assert "top, Wishbone, N = 3, iCE40 HX8K (ct256): a_DFFLC (a) -> b_DFFLC (b_D)" in text
    assert "10.50 ns, 7 logic steps" in text and "no clock-to-clock path" in text


def test_critical_path_picks_the_slowest():
    def step(kind, src, dst, delay, net="n"):
        return {"type": kind, "from": {"cell": src}, "to": {"cell": dst}, "delay": delay,
                "net": net}
    report = {"critical_paths": [
        {"from": "clk", "to": "clk", "path": [step("clk-to-q", "x", "y", 1.0, "xq"),
                                              step("logic", "y", "z", 2.0, "zd")]},
        {"from": "clk", "to": "clk", "path": [step("clk-to-q", "p", "q", 1.0, "pq"),
                                              step("logic", "q", "r", 1.0),
                                              step("logic", "r", "s", 2.0, "sd")]},
    ]}
    assert perf.critical_path(report) == {"from": "p", "to": "s", "from_net": "pq",
                                          "to_net": "sd", "delay_ns": 4.0, "logic_levels": 2}
    assert perf.critical_path({"critical_paths": []}) is None


def _module_ports(il: str, module: str):
    body = il.split(f"module \\{module}\n", 1)[1].split("\nend\n", 1)[0]
    ports = re.findall(r"^\s*wire width (\d+) (input|output) \d+ \\(\S+)$", body, re.M)
    return {name: (direction, int(width)) for width, direction, name in ports}


@pytest.mark.parametrize("build", [lambda: MdfqmTop(3, 16), lambda: MdfqmTop(3, 16, bus="axi4lite"),
                                   lambda: GatingSignalGenerator(3, 16, max_bits=8),
                                   lambda: MdfqmCore(3, 16)])
def test_wrapper_feeds_every_port_bit(build):
    wrapper = perf.SerialWrapper(build())
    il = rtlil.convert(wrapper, name="top")
    ports = _module_ports(il, "top.inner")
    clock_reset = {"core_clk", "core_rst"}
    assert clock_reset <= set(ports)
    inputs = sum(w for name, (d, w) in ports.items() if d == "input" and name not in clock_reset)
    outputs = sum(w for d, w in ports.values() if d == "output")
    # every bit of every port of the design, as Amaranth writes its module (a View counts by
    # its bits: the stream's payload is 48 bits, three elements)
    assert (wrapper.in_width, wrapper.out_width) == (inputs, outputs)
    assert ports["ref__payload"] == ("input", 48)
    # the wrapper's own ports are just the serial pins (and the clock and reset)
    assert set(_module_ports(il, "top")) == {"clk", "rst", "sdi", "sdo"}
    # no input of the design is tied to a constant in the wrapper
    cell = il.split("cell \\top.inner \\inner\n", 1)[1].split("\n  end\n", 1)[0]
    assert not re.search(r"connect \\\S+ \d+'[01]", cell)


@pytest.mark.parametrize("args", [["--designs", "nope"], ["--devices", "hx1k"],
                                  ["--quick", "--designs", "top_wb"], ["--designs", ","]])
def test_rejects_bad_selections(args):
    with pytest.raises(SystemExit) as info:
        perf.main(args)
    assert info.value.code not in (0, None)


def test_select_keeps_the_table_order():
    keys = [c.key for c in perf.CONFIGS]
    assert perf.select("top_axil,core3", keys, "design") == ["core3", "top_axil"]
    assert perf.select(None, keys, "design") == keys


def test_replace_block(tmp_path):
    readme = tmp_path / "README.md"
    readme.write_text("a\n<!-- perf:begin -->\nold\n<!-- perf:end -->\nb\n")
    perf.replace_block(readme, "perf", "new\n")
    assert readme.read_text() == "a\n<!-- perf:begin -->\nnew\n<!-- perf:end -->\nb\n"
