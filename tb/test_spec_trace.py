"""Every rule of the specification has stimulus: each row of docs/robustness.md, each field and
each clamp of spec/rdl/mdfqm_top.rdl and each timing section of docs/top.md is named by a
sequence of the top's or the generator's stimulus (tb/mdfqm_testkit/top_sequences.py,
tb/mdfqm_testkit/bbit_stimulus.py), or listed with the reason no stimulus can check it; and every
rule a sequence names exists in the documents. Pure Python, no simulation: the rules are read
from the documents themselves, so a new row, field or section without a sequence fails here."""

import json

import pytest

from mdfqm_testkit import spec_trace
from mdfqm_testkit.coverage import Coverage, band, bands
from mdfqm_testkit.sequences import anchor, rdl, robustness


def test_every_rule_of_the_documents_has_a_sequence():
    missing = spec_trace.unmapped()
    assert not missing, "rules no sequence names:\n" + "\n".join(missing)


def test_every_rule_a_sequence_names_is_in_the_documents():
    stale = spec_trace.unknown()
    assert not stale, "rules the documents do not have:\n" + "\n".join(
        f"{name}: {rule}" for name, rule in stale)


def test_the_rules_are_read_from_the_documents():
    """The readers find what the documents hold (a reader that found nothing would let every
    mapping pass): the table's rows, every register field, the clamps, the timing sections."""
    rows = spec_trace.robustness_rows()
    assert len(rows) >= 25 and rows[0].startswith("reference beyond the linear range")
    assert rows[-1].startswith("illegal elaboration parameters")
    rules = spec_trace.rdl_rules()
    assert rdl("PERIOD.PERIOD") in rules and rdl("PERIOD.PERIOD", clamp=True) in rules
    assert rdl("REF.REF", clamp=True) in rules and rdl("CMD.ALL_OFF") in rules
    assert rdl("CTRL.ENABLE", clamp=True) not in rules          # no clamp: stored as written
    timing = spec_trace.timing_rules()
    assert "docs/top.md#reference-watchdog" in timing
    assert "docs/top.md#update-timing-and-the-adc-trigger" in timing


@pytest.mark.parametrize("rule", [robustness("a row no document has"),
                                  rdl("PERIOD.NOT_A_FIELD"), "docs/top.md#no-such-section"])
def test_a_rule_outside_the_documents_is_found(rule):
    """A sequence naming a rule the documents lack is reported (so the check can fail)."""
    from mdfqm_testkit.top_sequences import TopSequence

    class Stray(TopSequence):
        rules = (rule,)

    try:
        assert ("top: Stray", rule) in spec_trace.unknown()
    finally:
        TopSequence.registry.remove(Stray)


def test_a_row_without_a_sequence_is_found(monkeypatch):
    """A robustness row no sequence names is reported (so the check can fail)."""
    rows = spec_trace.robustness_rows()
    monkeypatch.setattr(spec_trace, "robustness_rows", lambda: [*rows, "a new bad input"])
    assert robustness("a new bad input") in spec_trace.unmapped()


def test_anchors_as_github_makes_them():
    assert anchor("Reference input: which wins") == "reference-input-which-wins"
    assert anchor("Gate driver (per leg)") == "gate-driver-per-leg"
    assert anchor("Every clamp, in one place") == "every-clamp-in-one-place"


def test_the_summary_names_each_rule_its_sequences_and_bins(tmp_path):
    """build/traceability.md's text: a line per rule and sequence with the bins hit over the
    goals, and the bins never hit, from the runs recorded."""
    coverage = Coverage()
    coverage.want("sync pulse", ("ignored: update in flight", "starts the next update"),
                  "top: SyncPulses")
    coverage.hit("sync pulse", "starts the next update")
    (tmp_path / "run.json").write_text(
        json.dumps({"test": "t", "family": "top", "coverage": coverage.to_json()}))
    text = spec_trace.summary_markdown(directory=tmp_path)
    line = next(line for line in text.splitlines()
                if line.startswith("| docs/robustness.md: sync_in at any time")
                and "`top: SyncPulses`" in line)
    assert "| 1 / 2 | sync pulse: ignored: update in flight |" in line
    assert "not run" in next(line for line in text.splitlines()
                             if "`generator: HeldMode`" in line)


def test_coverage_counts_goals_hits_and_what_is_missing():
    coverage = Coverage()
    coverage.want("point", ("a", "b", 3), "top: Owner")
    coverage.hit("point", "a")
    coverage.hit("point", 3)
    coverage.hit("elsewhere", "x")           # a hit beyond the goals is kept, not a goal
    assert coverage.missing() == [("point", "b")]
    assert coverage.is_open("point") and not coverage.is_open("elsewhere")
    other = Coverage.from_json(json.loads(json.dumps(coverage.to_json())))
    assert other.missing() == [("point", "b")] and other.owners == {"point": "top: Owner"}
    other.hit("point", "b")
    coverage.merge(other)
    assert coverage.missing() == [] and coverage.count("point", "a") == 2


def test_bands_name_the_ranges_between_edges():
    assert bands((0, 1, 256, 4096)) == ["0", "1..255", "256..4095", "4096.."]
    assert [band(v, (0, 1, 256, 4096)) for v in (0, 1, 255, 256, 65535)] == [
        "0", "1..255", "1..255", "256..4095", "4096.."]
    with pytest.raises(ValueError):
        band(3, (8, 16))
