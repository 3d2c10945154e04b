"""The C firmware driver (sw/mdfqm_driver.c) against the drop-in top, as firmware runs it.

The driver is compiled alone with ``gcc -std=c99 -Wall -Wextra -Werror -pedantic`` against the
header generated from the SystemRDL map (the only register facts it has), then linked into a
Verilator harness (sw/sim/harness.cpp) around the drop-in file ``mdfqm_top_n3_w16.v`` with a
Wishbone shim. The harness plays firmware: init, timing, zero policy, interrupts (sampling tick:
the next reference; fault: clear it once the input is gone), a fault pulse with an active short
circuit low as the fault reaction, CMD.ALL_OFF before the clear, the counters read and
cleared. It logs every clock's inputs and outputs; here a fresh golden model steps through
the same inputs and every output of every clock must match, and the driver's own results (INFO
decoded, causes handled, fault cleared, counters) are checked against the model's view.
"""

import shutil
import subprocess

import pytest

from mdfqm_gateware.dropin import default_configs, dropin_verilog
from mdfqm_spec import regmap as regs
from mdfqm_testkit.clock_log import NAME, replay_clock_log, top_params
from mdfqm_testkit.harness import ROOT, verilator_build_env
from mdfqm_testkit.top_bench import make_model

SW = ROOT / "sw"
CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]


@pytest.fixture(scope="module")
def run_log(tmp_path_factory):
    gcc, verilator = shutil.which("gcc"), shutil.which("verilator")
    if gcc is None or verilator is None:
        pytest.skip("needs gcc and verilator on PATH (make setup puts verilator in .venv/bin)")
    from tools import regmap_gen

    work = tmp_path_factory.mktemp("c_driver")
    compiled = regmap_gen.compile_rdl()
    regmap_gen.write_peakrdl(compiled, regmap_gen.describe(compiled), work)
    obj = work / "mdfqm_driver.o"
    subprocess.run([gcc, *CFLAGS, "-O2", "-I", str(work), "-c", str(SW / "mdfqm_driver.c"),
                    "-o", str(obj)], check=True, capture_output=True, text=True)
    source = work / f"{NAME}.v"
    source.write_text(dropin_verilog(dict(default_configs(3, 16))[NAME](), NAME))
    verilator_build_env()
    build = subprocess.run(
        [verilator, "--cc", "--exe", "--build", "-O2", "-j", "2", "--top-module", NAME,
         "-Mdir", str(work / "obj"), "-CFLAGS", f"-I{work} -I{SW}", "-LDFLAGS", str(obj),
         str(source), str(SW / "sim" / "harness.cpp")],
        capture_output=True, text=True)
    assert build.returncode == 0, build.stdout[-3000:] + build.stderr[-3000:]
    log = work / "run.log"
    subprocess.run([str(work / "obj" / f"V{NAME}"), str(log)], check=True, timeout=300)
    return log.read_text().splitlines()


def test_driver_compiles_as_c99_with_every_warning_an_error(run_log):
    assert run_log        # the fixture compiled it with CFLAGS (a warning fails it there)


def test_every_clock_equals_the_model(run_log):
    _, p = top_params()
    model, checked = replay_clock_log(run_log, p)
    assert checked >= 40000
    # what the harness asked the driver to set is what the registers hold (a driver writing the
    # wrong offset or field would pass the clock-by-clock comparison, not this)
    settings = (model.period, model.osr, model.dead, model.min_pulse, model.adc_offset,
                model.ctrl, model.irq_enable, model.wd_timeout, model.fault_reaction)
    assert settings == (60, 2, 70, 3, 5, regs.CTRL_ENABLE | regs.CTRL_ZERO_POLICY,
                        regs.IRQ_ENABLE_FAULT | regs.IRQ_ENABLE_SAMPLE | regs.IRQ_ENABLE_WATCHDOG,
                        6, 1 << regs.FAULT_REACTION_FAULT_SHIFT)


def upper_of(clocks):
    """The ``upper`` column of the harness's clock lines ("C", the cycle, then the 11 inputs
    and ``wb_dat_r``, ``wb_ack``, ``ref_ready`` before it)."""
    return [int(c[16], 16) for c in clocks]


def test_the_driver_did_its_job(run_log):
    """What firmware would see: the instance identified, interrupts served, the fault set and
    cleared, gates switching, counters read and cleared, a stalled loop tripping the watchdog
    once, cleared."""
    _, p = top_params()
    tagged = {}
    for line in run_log:
        tag, *rest = line.split()
        tagged.setdefault(tag, []).append(rest)
    ok, phases, width, latency, dead_min, max_bits, modes, asc, watchdog = map(
        int, tagged["INIT"][0])
    assert (ok, phases, width, dead_min, asc, watchdog) == (0, p["phases"], p["width"],
                                                            p["dead_min"], 1, 1)
    model = make_model(p)
    assert (latency, max_bits, modes) == (model.latency, model.max_bits, 5) and max_bits >= 3
    assert tagged["MODULATION"][0] == ["1", "3"], "SVPWM at b = 3 not in force"
    causes = [tuple(map(int, c)) for c in tagged["IRQ"]]
    samples, faults, skipped, watchdogs, trips_after_clear = map(int, tagged["DONE"][0])
    assert sum(c[2] for c in causes) == samples + skipped and samples > 50, \
        "sampling interrupts not served"
    assert skipped > 5 and sum(c[3] for c in causes) == watchdogs == 1, \
        "the stalled loop did not trip the watchdog once"
    assert "WATCHDOG_CLEAR" in tagged and trips_after_clear == 0
    assert sum(c[0] for c in causes) == faults == 1, "the fault interrupt not seen once"
    assert tagged["CLEAR"][-1] == ["1"], "the fault was never cleared"
    # the fault's reaction: ASC low in force, then all off by CMD.ALL_OFF (the latch still set)
    assert tagged["ASC"] == [["1", "0"]], "ASC low not in force, or not ended by ALL_OFF"
    clocks = [line.split() for line in run_log if line.startswith("C ")]
    fault = [int(c[20], 16) for c in clocks]
    assert 1 in fault and fault[-1] == 0
    lower = [int(c[17], 16) for c in clocks]
    asc = [t for t, (f, u, lo) in enumerate(zip(fault, upper_of(clocks), lower, strict=True))
           if f and lo == 7 and u == 0]
    assert len(asc) > 100, "the lower switches not all on during the fault (ASC low)"
    assert not lower[asc[-1] + 1] and fault[asc[-1] + 1], "ASC low not ended before the clear"
    upper = upper_of(clocks)
    turn_ons = sum(bin(a & ~b).count("1") for a, b in zip(upper[1:], upper, strict=False))
    *legs, total = (int(v, 16) for v in tagged["COUNTS"][0])
    assert len(legs) == phases and total == sum(legs) and turn_ons > 100 and total > 100
    cleared_total, status = (int(v, 16) for v in tagged["CLEARED"][0])
    assert cleared_total < 8 and status & (regs.STATUS_FAULT | regs.STATUS_WATCHDOG) == 0
