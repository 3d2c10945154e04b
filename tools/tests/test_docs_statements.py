"""Sentences of README.md, docs/ and reports/ that state an address, a reset value, a count, a
latency, a module or file, or a measured figure, extracted from the text and checked against
their source: the register map (spec/rdl/mdfqm_top.rdl through mdfqm_spec.regmap), the
contract's formulas, the gateware's source, and the tables `make perf` and `make report` write
(the README's perf table, docs/boards.md's board report). The register table, the port table,
the timing diagram, the word list of the SLVERR responses and the generated report blocks have
tests of their own; the clock-level timing sentences are checked by the model's and the
gateware's tests (docs/robustness.md names them)."""

import importlib
import importlib.util
import inspect
import re
from pathlib import Path

import pytest

from mdfqm_spec import regmap
from mdfqm_spec.contract import MODES, loop_latency, resolution_latency

ROOT = Path(__file__).resolve().parents[2]
TEXTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")),
         *sorted((ROOT / "reports").glob("*.md"))]
REGISTERS = {r.name: r for r in regmap.REGISTERS}
WORDS = {"one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7,
         "eight": 8, "nine": 9, "ten": 10}


def text(name: str) -> str:
    return (ROOT / name).read_text()


def flat(name: str) -> str:
    """The file's text with every run of white space one space (sentences span lines)."""
    return " ".join(text(name).split())


def nearest_register(before: str) -> str | None:
    """The last register name in backticks in ``before``."""
    names = [n for n in re.findall(r"`([A-Z][A-Z0-9_]*)`", before) if n in REGISTERS]
    return names[-1] if names else None


# ---------------------------------------------------------------------------- the register map
def test_register_addresses_in_sentences():
    """`NAME` (word 0xNN, byte 0xMM): the map's word address, and four times it."""
    found = 0
    for path in TEXTS:
        body = " ".join(path.read_text().split())
        for name, word, byte in re.findall(
                r"`([A-Z][A-Z0-9_]*)` \(word (0x[0-9A-Fa-f]+), byte (0x[0-9A-Fa-f]+)\)", body):
            assert REGISTERS[name].offset == int(word, 16), (path.name, name, word)
            assert int(byte, 16) == 4 * int(word, 16), (path.name, name, byte)
            found += 1
    assert found, "no address stated in a sentence: the pattern no longer matches the docs"


def test_reset_values_in_sentences():
    """"holds `NAME = value`" after a reset, "v (the reset value)" of the register named last,
    the modes table's "(reset)" row: the map's reset values."""
    body = flat("docs/top.md")
    held = re.findall(r"after a reset the register file holds `([A-Z_]+) = (\w+)`", body)
    assert held == [("DEAD", "dead_min")]
    assert REGISTERS["DEAD"].reset == "dead_min"
    stated = re.findall(r"((?:(?!\(the reset value\)).){0,200}?)\b(\d+) \(the reset value\)",
                        body)
    assert stated
    for before, value in stated:
        name = nearest_register(before)
        assert name is not None, before
        assert REGISTERS[name].reset == value, (name, value)
    row = re.search(r"\| (\d+) \(reset\) \| MDFQM", body)
    assert row and int(row.group(1)) == 0 and REGISTERS["MODULATION"].reset == "0"


def test_defined_bit_counts():
    """"the N defined bits" of the register named before it: its fields."""
    found = 0
    for path in TEXTS:
        body = " ".join(path.read_text().split())
        for match in re.finditer(r"\bthe (\w+) defined bits\b", body):
            name = nearest_register(body[:match.start()])
            assert name is not None, (path.name, match.group(0))
            fields = len(REGISTERS[name].fields)
            assert WORDS[match.group(1)] == fields, (path.name, name, match.group(0), fields)
            found += 1
    assert found


def irq_fields() -> list[str]:
    return [f.name for f in REGISTERS["IRQ_STATUS"].fields]


def test_interrupt_sources_are_the_irq_status_fields():
    """docs/top.md's "Interrupt" list and the README's list of what drives `irq` name every
    IRQ_STATUS field, and nothing else."""
    section = text("docs/top.md").split("### Interrupt", 1)[1].split("###", 1)[0]
    assert re.findall(r"^- `([A-Z_]+)`:", section, re.M) == irq_fields()
    listed = re.search(r"\(`irq`: ([^)]*)\)", flat("README.md"))
    assert listed, "the README no longer lists the interrupt sources"
    items = [item.strip().replace(" ", "_").upper() for item in listed.group(1).split(",")]
    # "sampling tick" is SAMPLE: the first five letters name each field
    assert sorted(item[:5] for item in items) == sorted(f[:5] for f in irq_fields())


# ---------------------------------------------------------------------------- the contract
def test_latencies_and_sizes_of_the_drop_in_top():
    body = flat("docs/top.md")
    head = re.search(r"`max_bits` = (\d+) \(up to (\d+) slots per update\), loop latency "
                     r"L = (\d+) clocks \(L_b = (\d+) for a slot-mode update\), dead-time floor "
                     r"`dead_min` = (\d+) clocks", body)
    assert head, "the drop-in file's description no longer matches"
    max_bits, slots, latency, long_latency, dead_min = map(int, head.groups())
    assert max_bits == regmap.default_max_bits(16) and slots == 2 ** max_bits
    assert latency == loop_latency(3, "largest_duty")
    assert long_latency == resolution_latency(3, max_bits)
    assert dead_min == regmap.DEFAULT_DEAD_MIN
    examples = re.search(r"\(`resolution_latency`; ([^)]*)\)", body)
    assert examples
    checked = 0
    for part in examples.group(1).split(";"):
        phases, rest = re.fullmatch(r"\s*N = (\d+): (.*)", part).groups()
        for value, bits in re.findall(r"(\d+) at (?:`max_bits` = )?(\d+)", rest):
            assert int(value) == resolution_latency(int(phases), int(bits)), part
            checked += 1
    assert checked >= 3
    modes = re.search(r"`INFO.MODES` \(the codes `0 \.\. MODES - 1` are built in: (\d+), or "
                      r"(\d+) for the MDFQM-only top\)", body)
    assert modes and (int(modes.group(1)), int(modes.group(2))) == (len(MODES), 1)


def test_invariant_counts_are_the_sources():
    """"the `Assert`s named `invariant: ...`: six in a leg's logic, three in the top's"."""
    from mdfqm_gateware.driver import LegDriver
    from mdfqm_gateware.top import MdfqmTop

    stated = re.search(r"named `invariant: \.\.\.`: (\w+) in a leg's logic, (\w+) in the top's",
                       flat("docs/top.md"))
    assert stated
    leg = inspect.getsource(LegDriver).count('"invariant:')
    top = inspect.getsource(MdfqmTop).count('"invariant:')
    assert (WORDS[stated.group(1)], WORDS[stated.group(2)]) == (leg, top)


# ---------------------------------------------------------------------------- modules and files
def resolves(dotted: str) -> bool:
    """A module, or an attribute of one."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            if importlib.util.find_spec(".".join(parts[:k])) is None:
                continue
        except ModuleNotFoundError:
            continue
        if k == len(parts):
            return True
        obj = importlib.import_module(".".join(parts[:k]))
        for attribute in parts[k:]:
            if not hasattr(obj, attribute):
                return False
            obj = getattr(obj, attribute)
        return True
    return False


PACKAGES = ("mdfqm_model", "mdfqm_spec", "mdfqm_gateware", "mdfqm_host", "tools", "boards")


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: p.name)
def test_named_modules_and_files_exist(path):
    """Every `python -m module`, every dotted name of the project's packages in backticks and
    every repository path in backticks names something that exists (a report generated by a
    module that was since moved says so here)."""
    body = path.read_text()
    names = set(re.findall(r"python -m ([\w.]+)", body)) - {"pytest"}
    names |= {n for n in re.findall(r"`([\w.]+)`", body)
              if n.split(".")[0] in PACKAGES and "." in n}
    missing = sorted(n for n in names if not resolves(n))
    assert not missing, f"{path.name} names modules that do not exist: {missing}"
    files = {f for f in re.findall(r"`([\w./-]+/[\w.-]+\.(?:py|md|rdl|c|h|core|toml|lock))`",
                                   body) if not f.startswith("build/")}
    absent = sorted(f for f in files if not (ROOT / f).exists())
    assert not absent, f"{path.name} names files that do not exist: {absent}"


# ---------------------------------------------------------------------------- measured figures
def perf_rows() -> list[dict[str, str]]:
    """The README's perf table, a dict per row keyed by its header's cells."""
    block = text("README.md").split("<!-- perf:begin -->", 1)[1].split("<!-- perf:end -->")[0]
    lines = [[c.strip() for c in line.strip().strip("|").split("|")]
             for line in block.splitlines() if line.startswith("| ") and "---" not in line]
    header = lines[0]
    return [dict(zip(header, cells, strict=True)) for cells in lines[1:]]


def perf_row(design: str, device: str, phases: int = 3) -> dict[str, str]:
    rows = [r for r in perf_rows()
            if r["design"] == design and r["N / width"] == f"{phases} / 16"
            and r["device"].startswith(device)]
    assert len(rows) == 1, (design, device)
    return rows[0]


def board_rows() -> list[list[str]]:
    block = text("docs/boards.md").split("<!-- boards-report:begin -->", 1)[1]
    block = block.split("<!-- boards-report:end -->")[0]
    return [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in block.splitlines() if line.startswith("| ") and "---" not in line][1:]


def test_docs_state_no_area_figure_of_their_own():
    """docs/top.md and docs/boards.md state no LUT4 or logic-cell figure outside the tables the
    scripts write (they point to the README's area table, which `make perf` writes, and to the
    board table, which `make report` writes), so no figure there can go stale."""
    for name in ("docs/top.md", "docs/boards.md"):
        prose = re.sub(r"<!-- boards-report:begin -->.*?<!-- boards-report:end -->", "",
                       flat(name), flags=re.S)
        assert not re.search(r"[\d,]+ (LUT4|logic cells)", prose), name


def test_board_figures_quoted_from_make_report():
    """docs/boards.md's margins, from its own board-report table (which `make report`
    writes)."""
    body = flat("docs/boards.md")
    margins = [int(m) for row in board_rows() for m in re.findall(r"\+(\d+) %", row[8])]
    assert len(margins) == len(board_rows())
    stated = re.search(r"leave (\d+)-(\d+) % of margin", body)
    assert stated and (int(stated.group(1)), int(stated.group(2))) == (min(margins),
                                                                         max(margins))


#: a status line of `make perf` on a row with a target
STATUS_LINE = re.compile(r"^  - (.+?), N = (\d+), (.+?): ([\d.]+) MHz \(min ([\d.]+)\) against "
                         r"([\d.]+): (met|MISSED)", re.M)


def test_fmax_figures_quoted_from_make_perf():
    """The README's "Status and known limits" quotes make perf's Fmax (median and minimum over
    the seeds) of every row with a target, against that target, met or missed as the table
    says: the table's figures."""
    status = text("README.md").split("<!-- perf-status:begin -->", 1)[1]
    status = status.split("<!-- perf-status:end -->")[0]
    quoted = STATUS_LINE.findall(status)
    assert quoted
    for design, phases, device, fmax, fmax_min, target, verdict in quoted:
        row = perf_row(design, device, int(phases))
        assert float(row["Fmax median (MHz)"]) == float(fmax), (design, device)
        assert float(row["Fmax min (MHz)"]) == float(fmax_min), (design, device)
        cell = row["target (MHz)"]
        assert float(cell.split()[0]) == pytest.approx(float(target), abs=0.05), (design, cell)
        assert cell.endswith(f"({verdict})"), cell
    measured = {(r["design"], r["N / width"].split(" /")[0], r["device"].split(" (")[0])
                for r in perf_rows()
                if r["target (MHz)"] != "-" and re.fullmatch(r"[\d.]+", r["Fmax median (MHz)"])}
    assert measured == {(design, phases, device) for design, phases, device, *_ in quoted}
