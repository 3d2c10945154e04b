"""The markdown tables of ``REPORT.md``: switching events and distortion along the frequency and
amplitude sweeps, the paper's Table 3 reductions and the equal-switching comparison, with the
cell formatting they share."""

from __future__ import annotations

import numpy as np

from .comparisons import equal_rows, pct
from .records import METRICS, method_labels, select
from .sweeps import Config

__all__ = [
    "distortion_tables",
    "equal_switching_table",
    "events_table",
    "fmt",
    "md_table",
    "paper_table",
]


def fmt(v, digits=4):
    """``v`` to ``digits`` significant digits; ``-`` for None or a non-finite float."""
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "-"
    return f"{v:.{digits}g}"


def md_table(header, rows):
    """A markdown table (no trailing newline)."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def _svpwm_events(records, sweep, xkey):
    """SVPWM's events per second at each point of ``sweep``, keyed by ``xkey``."""
    return {r[xkey]: r["events_per_s"] for r in select(records, sweep=sweep, method="SVPWM")}


def events_table(records, sweep: str, xkey: str, xhead: str) -> list[str]:
    """Events per second of every method along ``sweep`` (x = ``xkey``, column ``xhead``), with
    the change against SVPWM in %."""
    sv = _svpwm_events(records, sweep, xkey)
    ms = method_labels(records, sweep)
    rows = []
    for x in sorted(sv):
        row = [f"{x:g}"]
        for m in ms:
            r = select(records, sweep=sweep, method=m, **{xkey: x})[0]
            cell = f"{r['events_per_s']:.0f}"
            if m != "SVPWM":
                cell += f" ({-pct(r['events_per_s'], sv[x]):+.0f} %)"
            row.append(cell)
        rows.append(row)
    return [md_table([xhead, *[f"{m} /s" for m in ms]], rows), ""]


def distortion_tables(records, sweep: str, xkey: str, xhead: str) -> list[str]:
    """One table a distortion metric (every method along ``sweep``), each under its name."""
    xs = sorted(_svpwm_events(records, sweep, xkey))
    ms = method_labels(records, sweep)
    out = []
    for key, name in METRICS:
        rows = []
        for x in xs:
            rows.append(
                [f"{x:g}"]
                + [fmt(select(records, sweep=sweep, method=m, **{xkey: x})[0][key]) for m in ms]
            )
        out += [f"**{name}**", "", md_table([xhead, *ms], rows), ""]
    return out


def paper_table(records, cfg: Config) -> list[str]:
    """% fewer events than SVPWM against amplitude, per carrier frequency and MDFQM variant."""
    ms = [m for m in method_labels(records, "paper") if m.startswith("MDFQM")]
    header = ["amp"] + [f"{m.split()[-1]}, fc {fc / 1e3:g} kHz" for fc in cfg.paper_fcs for m in ms]
    rows = []
    for amp in cfg.paper_amps:
        row = [f"{amp:g}"]
        for fc in cfg.paper_fcs:
            sv = select(records, sweep="paper", method="SVPWM", fc=fc, amp=amp)[0]
            for m in ms:
                r = select(records, sweep="paper", method=m, fc=fc, amp=amp)[0]
                row.append(f"{pct(r['events_per_s'], sv['events_per_s']):.0f}")
        rows.append(row)
    return [md_table(header, rows), ""]


def equal_switching_table(records, cfg: Config) -> list[str]:
    """Each MDFQM point against SVPWM / DPWM at the same switching count (:func:`equal_rows`):
    the equalising carrier and, per metric, MDFQM / carrier method."""
    rows = []
    for r in equal_rows(records, cfg):
        row = [
            f"{r['amp']:g}",
            r["method"],
            f"{r['events']:.0f}",
            r["carrier"],
            f"{r['fsw_equal']:.0f}" + ("" if r["in_range"] else " (extrapolated)"),
        ]
        for key, _ in METRICS:
            mv, cv = r[key]
            row.append(f"{fmt(mv, 3)} / {fmt(cv, 3)} = x{mv / cv:.2f}")
        rows.append(row)
    return [
        md_table(["amp", "MDFQM", "events /s", "vs", "fsw (Hz)", *[n for _, n in METRICS]], rows),
        "",
    ]
