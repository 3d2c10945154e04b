# amaranth: UnusedElaboratable=no
"""docs/core.md, the map of the core: every stage row names a file and a class that exist, and its
clocks are the components' own latencies, adding up to the loop latency of the contract."""

# (line 1: components built only to read their latency are never elaborated, on purpose)

import importlib
import re
from pathlib import Path

import pytest

from mdfqm_gateware.selector import ArgMax, Candidates, StateDecoder, candidate_width
from mdfqm_gateware.sort import SortNetwork
from mdfqm_spec.contract import Contract, argmax_stages, loop_latency, sorting_network

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "core.md"


def map_rows() -> list[list[str]]:
    text = DOC.read_text()
    block = text[text.index("<!-- core-map:begin -->"):text.index("<!-- core-map:end -->")]
    rows = [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in block.splitlines() if line.startswith("| ")]
    return rows[1:]


def block_latencies(phases: int, width: int = 16) -> dict:
    c = Contract(phases, width)
    return {
        "sort1": SortNetwork(phases, c.t_width).latency,
        "candidates": Candidates(phases, width).latency,
        "sort2": ArgMax(phases, candidate_width(phases, width)).latency,
        "decoder": StateDecoder(phases).latency,
    }


def test_every_row_names_a_real_file_and_class():
    rows = map_rows()
    assert len(rows) == 8
    for stage, file, cls, *_ in rows:
        path = ROOT / file.strip("`")
        assert path.is_file(), stage
        module = importlib.import_module(
            ".".join(path.relative_to(ROOT / "rtl").with_suffix("").parts))
        assert hasattr(module, cls.strip("`")), (stage, cls)


def test_clocks_for_three_phases_are_the_components_and_sum_to_the_latency():
    rows = {row[0]: int(row[3]) for row in map_rows()}
    for stage, clocks in block_latencies(3).items():
        assert rows[stage] == clocks, stage
    assert sum(rows.values()) == loop_latency(3) == 8


@pytest.mark.parametrize("phases", [3, 4, 5, 8, 9, 12])
def test_any_n_column_is_the_components(phases):
    formula = {row[0]: row[4] for row in map_rows()}
    values = {"depth(sort1)": len(sorting_network(phases)),
              "argmax_stages(N)": argmax_stages(phases)}
    clocks = {stage: int(values.get(text, text)) for stage, text in formula.items()}
    for stage, latency in block_latencies(phases).items():
        assert clocks[stage] == latency, stage
    assert sum(clocks.values()) == loop_latency(phases)


def test_prose_timeline_matches():
    text = DOC.read_text()
    assert re.search(r"visible in `s \+ 8`", text)
