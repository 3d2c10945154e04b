"""Traceability from the specification to the stimulus and the coverage it reached.

The rules come from the documents themselves: the rows of docs/robustness.md's table
(:func:`robustness_rows`), every field and clamp of spec/rdl/mdfqm_top.rdl
(:func:`rdl_rules`, compiled with systemrdl-compiler) and the timing sections of docs/top.md
(:func:`timing_rules`). The sequences of each family (the drop-in top's,
mdfqm_testkit.top_sequences; the generator's, mdfqm_testkit.bbit_stimulus) name the rules they
check (mdfqm_testkit.sequences); :func:`unmapped` lists a rule no sequence names (tb/
test_spec_trace.py fails on it) and :func:`unknown` a sequence's rule the documents do not have.

The vector tests :func:`record` each run's coverage (a JSON file per test under
``build/trace``, so that pytest-xdist's workers write their own); at the end of a session
tb/conftest.py writes :func:`summary_markdown` (rule -> sequence -> bins hit) to
``build/traceability.md``, and the mutation report can embed the same text.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from mdfqm_testkit.coverage import Coverage
from mdfqm_testkit.harness import ROOT
from mdfqm_testkit.sequences import ROBUSTNESS, Sequence, anchor, doc, every_rule, rdl, robustness

TRACE_DIR = ROOT / "build" / "trace"
SUMMARY = ROOT / "build" / "traceability.md"
RDL_SOURCE = ROOT / "spec" / "rdl" / "mdfqm_top.rdl"
TOP_MD = "docs/top.md"
#: rows no stimulus sequence can check, each with where the row is shown instead
NOT_STIMULUS = {
    robustness("illegal elaboration parameters"):
        "refused at elaboration, before there is gateware to stimulate: the "
        "test_*_rejects_bad_parameters tests of every block",
}
#: sections of docs/top.md that state timing rules besides those under "Behaviour"
TIMING_SECTIONS = ("Register bus", "Interrupt", "Every clamp, in one place")


def _plain(text: str) -> str:
    return text.replace("`", "").strip()


def robustness_rows(path: Path | None = None) -> list[str]:
    """The first cell of every row of docs/robustness.md's table (backticks dropped)."""
    lines = (path or ROOT / ROBUSTNESS).read_text().splitlines()
    rows, in_table = [], False
    for line in lines:
        if line.startswith("|---"):
            in_table = True
            continue
        if in_table and line.startswith("| "):
            rows.append(_plain(line[2:].split(" | ")[0]))
        elif in_table and not line.strip():
            break
    return rows


def rdl_rules(path: Path | None = None) -> list[str]:
    """A rule per field of every register of the RDL source, and one per field's clamp (an
    array register without its index)."""
    from systemrdl import RDLCompiler

    compiler = RDLCompiler()
    compiler.compile_file(str(path or RDL_SOURCE))
    top = compiler.elaborate().top
    rules = []
    for register in top.registers():
        for field in register.fields():
            name = f"{register.inst_name}.{field.inst_name}"
            rules.append(rdl(name))
            if field.get_property("clamp", default=None):
                rules.append(rdl(name, clamp=True))
    return rules


def headings(path: str) -> list[tuple[int, str]]:
    """(level, text) of every Markdown heading of ``path``, outside code blocks."""
    found, fenced = [], False
    for line in (ROOT / path).read_text().splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (match := re.match(r"(#+) (.*)", line)):
            found.append((len(match.group(1)), match.group(2).strip()))
    return found


def timing_rules() -> list[str]:
    """The sections of docs/top.md that state timing rules: those under "Behaviour", and
    :data:`TIMING_SECTIONS`."""
    rules, inside = [], False
    for level, text in headings(TOP_MD):
        if level == 2:
            inside = text == "Behaviour"
        elif level == 3 and (inside or text in TIMING_SECTIONS):
            rules.append(doc(TOP_MD, text))
    return rules


def families() -> list[type]:
    """The sequence families: the top's and the generator's."""
    from mdfqm_testkit import bbit_stimulus, top_sequences

    return [top_sequences.TopSequence, bbit_stimulus.GeneratorSequence]


def required_rules() -> list[str]:
    """Every rule some sequence must name: the robustness rows, the RDL's fields and clamps,
    the timing sections of docs/top.md."""
    return ([robustness(row) for row in robustness_rows()] + rdl_rules() + timing_rules())


def _matches(rule: str, required: str) -> bool:
    """A sequence's rule names a required one: equal, or for a robustness row the start of
    its first cell."""
    if rule.startswith(f"{ROBUSTNESS}: ") and required.startswith(f"{ROBUSTNESS}: "):
        return _plain(required).startswith(_plain(rule))
    return rule == required


def sequences_for(required: str, named: dict) -> list[type]:
    return sorted({s for rule, seqs in named.items() if _matches(rule, required) for s in seqs},
                  key=lambda s: s.key())


def unmapped() -> list[str]:
    """The required rules no sequence names (and that are not :data:`NOT_STIMULUS`)."""
    named = every_rule(families())
    return [r for r in required_rules()
            if not sequences_for(r, named) and r not in NOT_STIMULUS]


def unknown() -> list[tuple[str, str]]:
    """(sequence, rule) for every rule a sequence names that the documents do not have: a
    robustness row that is no row's start, a field not in the RDL, a heading not in its
    document."""
    required = required_rules()
    found = []
    for rule, sequences in every_rule(families()).items():
        if rule.startswith(f"{ROBUSTNESS}: ") or rule.startswith("rdl: "):
            ok = any(_matches(rule, r) for r in required)
        else:
            path, _, name = rule.partition("#")
            ok = name in {anchor(text) for _, text in headings(path)}
        if not ok:
            found += [(s.key(), rule) for s in sequences]
    return found


# ---------------------------------------------------------------------- coverage of runs
_RECORDED: dict[str, Coverage] = {}


def _file(test: str) -> Path:
    return TRACE_DIR / (re.sub(r"[^\w.\-]+", "_", test) + ".json")


def record(test: str, family: str, coverage: Coverage) -> None:
    """Add a run's coverage to ``test``'s record (``family``: "top" or "generator") and write
    it to ``build/trace``."""
    merged = _RECORDED.setdefault(test, Coverage())
    merged.merge(coverage)
    TRACE_DIR.mkdir(parents=True, exist_ok=True)
    _file(test).write_text(json.dumps({"test": test, "family": family,
                                       "coverage": merged.to_json()}))


def recorded(since: float | None = None, directory: Path | None = None) -> dict:
    """family -> (the tests, their merged coverage), from the records written at or after
    ``since`` (seconds since the epoch)."""
    runs: dict[str, tuple[list, Coverage]] = {}
    for path in sorted((directory or TRACE_DIR).glob("*.json")):
        if since is not None and path.stat().st_mtime < since:
            continue
        data = json.loads(path.read_text())
        tests, coverage = runs.setdefault(data["family"], ([], Coverage()))
        tests.append(data["test"])
        coverage.merge(Coverage.from_json(data["coverage"]))
    return runs


def summary_markdown(since: float | None = None, directory: Path | None = None) -> str:
    """The traceability and coverage summary: per rule of the documents, the sequences that
    check it and, per sequence, its coverpoints' bins hit over their goals in the runs
    recorded (at or after ``since``)."""
    runs = recorded(since, directory)
    named = every_rule(families())
    lines = ["# Traceability: rule -> sequence -> bins hit", "",
             "Generated by `mdfqm_testkit.spec_trace.summary_markdown()` from the runs of this "
             "session: " + ("; ".join(f"{family}: {', '.join(tests)}"
                                     for family, (tests, _) in sorted(runs.items()))
                           or "none recorded") + ".", "",
             "| rule | sequence | bins hit / goals | bins never hit |", "|---|---|---|---|"]

    def cells(sequence: type) -> tuple[str, str]:
        if sequence.family not in runs:
            return "not run", ""
        coverage = runs[sequence.family][1]
        points = [p for p, owner in coverage.owners.items() if owner == sequence.key()]
        if not points:
            return "no coverpoint", ""
        goals = sum(len(coverage.goals[p]) for p in points)
        missing = [f"{p}: {b}" for p in points for b in coverage.open_bins(p)]
        return f"{goals - len(missing)} / {goals}", "; ".join(missing)

    for rule in [*required_rules(), *sorted(set(named) - set(required_rules()))]:
        sequences = sequences_for(rule, named)
        if not sequences:
            reason = NOT_STIMULUS.get(rule, "**no sequence**")
            lines.append(f"| {rule} | {reason} | | |")
        for sequence in sequences:
            hit, missing = cells(sequence)
            lines.append(f"| {rule} | `{sequence.key()}`: {sequence.describe()} | {hit} "
                         f"| {missing} |")
    return "\n".join(lines) + "\n"


def write_summary(since: float | None = None) -> Path | None:
    """Write :func:`summary_markdown` to ``build/traceability.md`` when runs were recorded."""
    if not recorded(since):
        return None
    SUMMARY.parent.mkdir(parents=True, exist_ok=True)
    SUMMARY.write_text(summary_markdown(since))
    return SUMMARY


__all__ = ["NOT_STIMULUS", "Sequence", "rdl_rules", "record", "recorded", "required_rules",
           "robustness_rows", "summary_markdown", "timing_rules", "unknown", "unmapped",
           "write_summary"]
