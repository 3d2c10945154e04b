"""The board folders without place and route: constraint files current, PLL settings equal to
what icepll / ecppll compute, clock and UART arithmetic, the build's log parsing and timing
gate, the report's table splicing."""

import dataclasses
import json
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
import boards  # noqa: E402
from boards import build as board_build  # noqa: E402
from boards import constraints  # noqa: E402
from boards.common import Ecp5Pll, Ice40Pll  # noqa: E402
from tools import board_report as report  # noqa: E402


def test_constraint_files_are_current():
    assert constraints.main(["--check"]) == 0, "run python -m boards.constraints"


@pytest.mark.parametrize("name", sorted(boards.BOARDS))
def test_board_clock_and_uart(name):
    board = boards.get(name)
    config = board.config()
    assert config.clk_hz == board.sys_clk_hz
    assert abs(config.clk_hz / config.divider - 115200) / 115200 < 0.01
    pins = [*board.gate_pins[0], *board.gate_pins[1], board.fault_pin, board.trigger_pin]
    assert len(set(pins)) == len(pins) == 8
    assert {action for _, action in board.buttons} <= set(config.buttons)


def tool_output(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT / "build")
    return result.stdout + result.stderr


@pytest.mark.parametrize("name", [n for n in sorted(boards.BOARDS)
                                  if isinstance(boards.get(n).pll, Ice40Pll)])
def test_ice40_pll_is_what_icepll_computes(name):
    board = boards.get(name)
    (ROOT / "build").mkdir(exist_ok=True)
    out = tool_output(["yowasp-icepll", "-i", f"{board.clock_hz / 1e6:g}",
                       "-o", f"{board.sys_clk_hz / 1e6:g}"])
    want = {key: int(value) for key, value in
            re.findall(r"^(DIVR|DIVF|DIVQ|FILTER_RANGE):\s+(\d+)", out, re.M)}
    pll = board.pll
    assert want == {"DIVR": pll.divr, "DIVF": pll.divf, "DIVQ": pll.divq,
                    "FILTER_RANGE": pll.filter_range}, out
    assert f"{board.sys_clk_hz / 1e6:.3f} MHz (achieved)" in out


@pytest.mark.parametrize("name", [n for n in sorted(boards.BOARDS)
                                  if isinstance(boards.get(n).pll, Ecp5Pll)])
def test_ecp5_pll_is_what_ecppll_computes(name):
    board = boards.get(name)
    out = tool_output(["yowasp-ecppll", "-i", f"{board.clock_hz / 1e6:g}",
                       "-o", f"{board.sys_clk_hz / 1e6:g}", "-f", "ecppll_check.v"])
    text = (ROOT / "build" / "ecppll_check.v").read_text()
    want = {key: int(value) for key, value in
            re.findall(r"\.(CLKI_DIV|CLKFB_DIV|CLKOP_DIV|CLKOP_CPHASE)\((\d+)\)", text)}
    pll = board.pll
    assert want == {"CLKI_DIV": pll.clki_div, "CLKFB_DIV": pll.clkfb_div,
                    "CLKOP_DIV": pll.clkop_div, "CLKOP_CPHASE": pll.clkop_cphase}, out


@pytest.mark.parametrize(("pll", "message"), [
    (Ice40Pll(divr=0, divf=20, divq=1, filter_range=1),
     "iCE40 PLL out of range: PFD 12.0 MHz, VCO 252.0 MHz"),
    (Ecp5Pll(clki_div=1, clkfb_div=2, clkop_div=2, clkop_cphase=0),
     "ECP5 PLL out of range: VCO 100.0 MHz"),
])
def test_pll_ranges_are_checked(pll, message):
    with pytest.raises(ValueError) as info:
        pll.check(12e6 if isinstance(pll, Ice40Pll) else 25e6)
    assert str(info.value) == message


NEXTPNR_LOG = """\
Info: Device utilisation:
Info: 	         ICESTORM_LC:    4059/   5280    76%
Info: 	        ICESTORM_RAM:       1/     30     3%
Info: Max frequency for clock 'clk': 17.00 MHz (PASS at 16.52 MHz)
Info: Max frequency for clock 'clk': 15.97 MHz (FAIL at 16.52 MHz)
ERROR: Max frequency for clock 'clk': 15.97 MHz (FAIL at 16.52 MHz)
"""


def test_nextpnr_log_parsing_keeps_the_post_route_figure():
    parsed = board_build.parse_nextpnr_log(NEXTPNR_LOG)
    assert parsed["utilisation"]["ICESTORM_LC"] == (4059, 5280)
    assert parsed["clocks"] == {"clk": (15.97, "FAIL", 16.52)}


def _step(kind, delay, cell, port, to_cell=None, to_port=None):
    """One step of a path in nextpnr's ``--report`` JSON."""
    return {"type": kind, "delay": delay, "from": {"cell": cell, "port": port},
            "to": {"cell": to_cell or cell, "port": to_port or port}}


#: a nextpnr ``--report`` of a demo: the system clock's path (two logic steps, the first flop
#: an arbiter's, the last an NCO register's LUT input) and an I/O path from an async pin
CRITICAL_PATHS = {"fmax": {"clk": {"achieved": 76.9, "constraint": 24.0}}, "critical_paths": [
    {"from": "posedge clk", "to": "posedge clk", "path": [
        _step("clk-to-q", 1.39, "demo.arbiter.owner_SB_DFFESR_Q_DFFLC", "O"),
        _step("routing", 3.60, "demo.arbiter.owner_SB_DFFESR_Q_DFFLC", "O",
              "demo.regs.bus__ack_SB_LUT4_I1_LC", "I0"),
        _step("logic", 1.28, "demo.regs.bus__ack_SB_LUT4_I1_LC", "I0", None, "O"),
        _step("routing", 1.76, "demo.regs.bus__ack_SB_LUT4_I1_LC", "O",
              "demo.top.driver.leg0.count_next_SB_DFFSR_Q_14_D_SB_LUT4_O_LC", "I3"),
        _step("logic", 0.87, "demo.top.driver.leg0.count_next_SB_DFFSR_Q_14_D_SB_LUT4_O_LC",
              "I3", None, "O"),
        _step("routing", 2.95, "demo.top.driver.leg0.count_next_SB_DFFSR_Q_14_D_SB_LUT4_O_LC",
              "O", "demo.NCO_FREQ_SB_DFFESR_Q_23_D_SB_LUT4_O_LC", "I2"),
        _step("setup", 1.15, "demo.NCO_FREQ_SB_DFFESR_Q_23_D_SB_LUT4_O_LC", "I2")]},
    {"from": "<async>", "to": "posedge clk", "path": [
        _step("source", 0.0, "pin_fault_n_0.buf0", "D_IN_0"),
        _step("setup", 4.86, "pin_fault_n_0.i$1_SB_LUT4_I3_LC", "I3")]}]}


def test_limiting_path_names_the_signals_it_runs_between(tmp_path):
    """The system clock's critical path of a build's nextpnr report, in the demo's hierarchy:
    the first flop's signal to the last one's, the tools' cell suffixes dropped (an I/O path
    is not it); none without a report."""
    (tmp_path / board_build.REPORT).write_text(json.dumps(CRITICAL_PATHS))
    assert board_build.limiting_path(tmp_path) == {
        "from": "arbiter.owner", "to": "NCO_FREQ", "steps": 2, "ns": 13.0}
    assert board_build.limiting_path(tmp_path / "no build") is None
    assert board_build.signal_of("demo.top.driver.leg0.count_next_TRELLIS_FF_Q_1") == \
        "top.driver.leg0.count_next"


def test_yosys_stat_parsing():
    text = "x\n2.50. Printing statistics.\n     1222   SB_CARRY\n     2874   SB_LUT4\n" \
           "      762   SB_DFFSR\n=== design hierarchy ===\n     9   SB_LUT4\n"
    assert report.parse_yosys_stat(text) == {"SB_CARRY": 1222, "SB_LUT4": 2874,
                                             "SB_DFFSR": 762}


def test_report_row_gives_the_median_and_the_minimum_over_the_seeds():
    board = boards.get("icebreaker")
    resources = {"luts": 3500, "ffs": 2400, "logic": (4224, 5280), "brams": (1, 30),
                 "plls": (1, 1), "fmax": 28.3, "verdict": "PASS", "target": 27.0}
    fmaxes = {1: 28.3, 2: 29.6, 3: 26.9, 4: 27.5, 5: 29.3}
    text = report.table([(board, resources, 113.0, fmaxes)], ["tools"], None, (1, 2, 3, 4, 5))
    row = next(line for line in text.splitlines() if line.startswith("| icebreaker"))
    assert "| 4224 / 5280 (80 %) |" in row
    assert "| 28.3 (PASS, +5 %) | 28.3 / 26.9 (FAIL on some seeds) | 113 |" in row
    assert "the median and the minimum Fmax over nextpnr seeds 1,2,3,4,5" in text
    # a board's nextpnr options other than its seed are stated (every seed's build takes them)
    assert "builds also with" not in text
    routed = dataclasses.replace(board, nextpnr_opts="--seed 1 --router router2")
    assert "; icebreaker's builds also with `--router router2`;" in report.table(
        [(routed, resources, 113.0, fmaxes)], ["tools"], None, (1, 2, 3, 4, 5))
    # each placement's limiting path under the table, seeds with the same one together
    bus = {"from": "arbiter.owner", "to": "NCO_FREQ", "steps": 8, "ns": 33.0}
    fault = {"from": "top.driver.fault_sync.stage1", "to": "top.driver.leg0.count_next",
             "steps": 9, "ns": 30.0}
    text = report.table([(board, {**resources, "path": bus}, 113.0, fmaxes)], ["tools"], None,
                        (1, 2, 3), {"icebreaker": {1: bus, 2: fault, 3: bus}})
    assert ("Limiting paths (from -> to): icebreaker: the bitstream's arbiter.owner -> NCO_FREQ "
            "(8 logic steps); seeds 1, 3: arbiter.owner -> NCO_FREQ (8 logic steps); seed 2: "
            "top.driver.fault_sync.stage1 -> top.driver.leg0.count_next (9 logic steps).") in text


def test_report_leaves_a_failed_seed_out_of_the_median_and_names_it():
    board = boards.get("icebreaker")
    resources = {"luts": 3500, "ffs": 2400, "logic": (4224, 5280), "brams": (1, 30),
                 "plls": (1, 1), "fmax": 28.3, "verdict": "PASS", "target": 27.0,
                 "path": None}
    fmaxes = {1: 28.3, 2: 29.6, 3: "stopped after 20 min", 4: 27.5, 5: 29.3}
    text = report.table([(board, resources, 113.0, fmaxes)], ["tools"], None, (1, 2, 3, 4, 5))
    row = next(line for line in text.splitlines() if line.startswith("| icebreaker"))
    # median of 27.5, 28.3, 29.3, 29.6
    assert "| 28.8 / 27.5 (PASS, 4 of 5 seeds) |" in row
    assert ("Seeds whose build failed or was stopped (not counted in the median and the "
            "minimum): icebreaker seed 3 (stopped after 20 min).") in text
    nothing = {s: "not routed to the end" for s in (1, 2, 3)}
    text = report.table([(board, resources, 113.0, nothing)], ["tools"], None, (1, 2, 3))
    assert "| 28.3 (PASS, +5 %) | - (no seed routed) | 113 |" in text


def test_a_build_past_its_time_is_stopped_with_every_process_it_started(tmp_path):
    # a build's tools run as grandchildren (Python -> Amaranth's script -> Yosys, nextpnr)
    marker = tmp_path / "written by the grandchild"
    grandchild = f"import time, pathlib; time.sleep(2); pathlib.Path({str(marker)!r}).touch()"
    child = f"import subprocess, sys; subprocess.run([sys.executable, '-c', {grandchild!r}])"
    with pytest.raises(board_build.BuildTimeoutError, match=r"stopped after 0\.01 min"):
        board_build.run_bounded([sys.executable, "-c", child], 0.01)
    time.sleep(3)
    assert not marker.exists()
    # within its time, the exit status is the command's
    assert board_build.run_bounded([sys.executable, "-c", "raise SystemExit(3)"], 1) == 3


def test_a_bitstream_build_past_its_timeout_fails_and_says_why(capsys):
    out = ROOT / "build" / "timeout-test"
    assert board_build.main(["--board", "icebreaker", "--out", str(out),
                             "--timeout", "0.002"]) == 1
    message = capsys.readouterr().err
    assert "icebreaker: build stopped after 0.002 min (--timeout)" in message
    assert "try another seed" in message
    with pytest.raises(SystemExit):
        board_build.main(["--board", "icebreaker", "--timeout", "0"])


def test_report_table_is_spliced_between_markers():
    block = f"{report.BEGIN}\nnew\n{report.END}"
    assert report.splice(f"a\n{report.BEGIN}\nold\n{report.END}\nb\n", block) == \
        f"a\n{block}\nb\n"
    assert report.splice("# title\n", block) == f"# title\n\n## Board builds\n\n{block}\n"


def test_build_directory_must_not_be_under_tmp():
    with pytest.raises(SystemExit) as info:
        board_build.build_dir("icebreaker", Path("/tmp/boards"))
    assert "under /tmp" in str(info.value)


def test_unknown_board():
    with pytest.raises(ValueError) as info:
        boards.get("arty")
    assert str(info.value) == \
        "board must be one of ['hx8k', 'icebreaker', 'orangecrab', 'ulx3s'], not 'arty'"


def test_docs_list_every_demo_register():
    from mdfqm_spec.regmap import DEMO

    text = (ROOT / "docs" / "boards.md").read_text()
    for reg in DEMO.regs:
        assert f"`{reg.name}`" in text, reg.name
