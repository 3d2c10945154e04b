"""tools/gateware_report.py: a short run of three methods, and its argument checks."""

import csv

import pytest

from tools import gateware_report


def test_short_report_agrees_with_the_model(tmp_path):
    code = gateware_report.main(["--out", str(tmp_path), "--seconds", "0.02",
                                 "--methods", "0,2,8"])
    assert code == 0
    text = (tmp_path / "GATEWARE_MODES.md").read_text()
    assert text.count("bit-identical") == 3 and "DIFFERENT" not in text
    with open(tmp_path / "gateware_modes.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["mode"] for r in rows] == ["mdfqm", "svpwm", "svpwm"]
    for r in rows:
        assert r["mismatches"] == "0" and r["identical"] == "True"
        assert float(r["events_gate"]) == float(r["events_model"]) > 0
        assert float(r["thd_i_gate"]) == float(r["thd_i_model"]) > 0
    # SVPWM at b = 8: two transitions per leg per carrier period, 3 kHz, three legs
    assert float(rows[1]["events_gate"]) == pytest.approx(18000, rel=0.01)


@pytest.mark.parametrize("args", [["--seconds", "0.013"], ["--seconds", "0"],
                                  ["--amp", "3"], ["--seconds", "0.0201"]])
def test_rejects_bad_arguments(args, tmp_path):
    with pytest.raises(SystemExit) as info:
        gateware_report.main(["--out", str(tmp_path), *args])
    assert info.value.code == 2
