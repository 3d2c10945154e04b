"""tools/timing_diagram.py: the diagram in docs/top.md is the one the top's model renders, and it
shows the documented latency, dead time and ADC offset."""

from pathlib import Path

from tools.timing_diagram import timing_diagram

DOCS = Path(__file__).resolve().parents[2] / "docs" / "top.md"


def test_docs_timing_diagram_is_current():
    assert timing_diagram() in DOCS.read_text()


def test_timing_diagram_shows_dead_time_and_adc_offset():
    lines = {line[:17].strip(): line[17:] for line in timing_diagram().splitlines()[1:]}
    s = lines["cycle"].index("s")
    assert lines["sync_out"][s] == "‾"
    assert lines["core.update"][s + 8] == "‾"
    lower_off = lines["lower[0]"].index("_", s)
    upper_on = lines["upper[0]"].index("‾", s)
    assert (lower_off, upper_on) == (s + 9, s + 12)          # L + 1, L + 1 + DEAD
    assert lines["adc_trigger"][s + 3] == "‾"                # s + 1 + ADC_OFFSET
