"""The timing diagram of ``docs/top.md``, rendered from the top's cycle model.

    .venv/bin/python -m tools.timing_diagram        # print it

A test (``model/tests/test_top_model.py``) checks that the page shows exactly this text.
"""

from __future__ import annotations

from mdfqm_model.top import TopModel
from mdfqm_spec.regmap import ADC_OFFSET, CTRL, CTRL_ENABLE, DEAD, PERIOD

__all__ = ["timing_diagram"]


def timing_diagram(period: int = 16, dead: int = 3, adc_offset: int = 2) -> str:
    """One update of a three-phase top, rendered from :class:`TopModel` (``docs/top.md`` shows
    this text; a test checks it is current). One character per clock: ``‾`` high, ``_`` low;
    ``h`` as a hexadecimal digit. Leg 0 switches from lower to upper in the update shown."""
    m = TopModel(3, 16, dead_min=2)
    f = m.contract.full

    def tick(**kw):
        row = {"up": m.driver.up, "lo": m.driver.lo, "h": m.core.h, "update": m.core.update,
               "ref_valid": kw.get("ref_valid", 0)}
        row.update(m.step(**kw))
        return row

    for address, value in ((PERIOD, period), (DEAD, dead), (ADC_OFFSET, adc_offset),
                           (CTRL, CTRL_ENABLE)):
        bus = {"wb_cyc": 1, "wb_stb": 1, "wb_we": 1, "wb_adr": address, "wb_dat_w": value}
        tick(**bus)
        tick(**bus)
        tick()
    # run to an update start, offer one beat just after it, and follow it to the gates
    while m.core.phase != 0:
        tick()
    tick()
    rows = [tick(), tick(ref_valid=1, ref=[f // 2, -f // 4, -f // 4])]
    while rows[-1]["ref_ready"] == 0:
        rows.append(tick(ref_valid=1, ref=[f // 2, -f // 4, -f // 4]))
    for _ in range(2 * period + 6):
        rows.append(tick())
    starts = [i for i, r in enumerate(rows) if r["sync_out"]]
    s = next(i for i in starts if any(rows[j]["h"] != rows[i]["h"] for j in range(i, len(rows))))
    lo_cycle, hi_cycle = 0, min(len(rows), s + m.latency + dead + 8)
    window = rows[lo_cycle:hi_cycle]

    def wave(values):
        return "".join("‾" if v else "_" for v in values)

    lines = [
        f"PERIOD={period}  DEAD={dead}  ADC_OFFSET={adc_offset}  latency L={m.latency}  "
        f"(s = update start)",
        "cycle            " + "".join(
            "s" if i == s else ("|" if (i - s) % 5 == 0 else " ")
            for i in range(lo_cycle, hi_cycle)),
        "ref__valid       " + wave(r["ref_valid"] for r in window),
        "ref__ready       " + wave(r["ref_ready"] for r in window),
        "sync_out         " + wave(r["sync_out"] for r in window),
        "core.update      " + wave(r["update"] for r in window),
        "core.h           " + "".join(f"{r['h']:x}" for r in window),
        "upper[0]         " + wave(r["up"] & 1 for r in window),
        "lower[0]         " + wave(r["lo"] & 1 for r in window),
        "adc_trigger      " + wave(r["adc_trigger"] for r in window),
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    print(timing_diagram())
