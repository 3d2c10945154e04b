"""The numbers the report compares, derived from the records: reductions in switching events
against SVPWM, distortion ratios, the fit of the paper's Table 3 and the equal-switching-count
interpolation."""

from __future__ import annotations

import numpy as np

from .records import METRICS, method_labels, select, series
from .sweeps import Config

__all__ = [
    "PAPER_CLAIMS",
    "equal_rows",
    "loglog_interp",
    "paper_fit",
    "pct",
    "ratios",
    "reductions",
]


PAPER_CLAIMS = [(400, 10.0), (200, 30.0), (150, 50.0), (100, 65.0)]  # rpm, % fewer events


def pct(a, b):
    """Percent fewer events of a than b."""
    return 100.0 * (1.0 - a / b)


def loglog_interp(x, xs, ys):
    """Interpolate ``ys(xs)`` at ``x`` linearly in log-log (xs increasing)."""
    order = np.argsort(xs)
    return float(np.exp(np.interp(np.log(x), np.log(xs[order]), np.log(ys[order]))))


def reductions(records, sweep, method, key="f0"):
    """``(x, % fewer events than SVPWM, events per second)`` of ``method`` along ``key``."""
    sv = {
        (r["f0"], r["amp"]): r["events_per_s"] for r in select(records, sweep=sweep, method="SVPWM")
    }
    rs = sorted(select(records, sweep=sweep, method=method), key=lambda r: r[key])
    return [
        (r[key], pct(r["events_per_s"], sv[(r["f0"], r["amp"])]), r["events_per_s"]) for r in rs
    ]


def ratios(records, sweep, method, metric):
    """``metric`` of ``method`` over SVPWM's at the same point, for every point of ``sweep``."""
    sv = {(r["f0"], r["amp"]): r[metric] for r in select(records, sweep=sweep, method="SVPWM")}
    return [
        r[metric] / sv[(r["f0"], r["amp"])] for r in select(records, sweep=sweep, method=method)
    ]


def paper_fit(records, cfg: Config, fc: float, method: str):
    """Best scale ``a`` (amplitude at 100 rpm, amplitude proportional to speed) for Table 3."""
    amps, ev = series(records, "paper", method, "amp", "events_per_s", fc=fc)
    _, sv = series(records, "paper", "SVPWM", "amp", "events_per_s", fc=fc)
    red = pct(ev, sv)
    speeds = np.array([s for s, _ in PAPER_CLAIMS], float)
    claims = np.array([c for _, c in PAPER_CLAIMS])
    grid = np.linspace(amps.min() * 400 / 100 / 4, amps.max() / 4, 400)
    cost = [np.sum((np.interp(a * speeds / 100, amps, red) - claims) ** 2) for a in grid]
    a = float(grid[int(np.argmin(cost))])
    model = np.interp(a * speeds / 100, amps, red)
    return a, model, amps, red


def equal_rows(records, cfg: Config):
    """Each MDFQM point of the ``equal`` sweep against SVPWM and DPWM interpolated (log-log) to
    its switching count: ``{amp, method, carrier, events, fsw_equal, in_range}`` and, per
    metric, ``(MDFQM value, carrier-method value)``."""
    rows = []
    for amp in cfg.equal_amps:
        for carrier in ("SVPWM", "DPWM"):
            xs, _ = series(records, "equal", carrier, "events_per_s", "events_per_s", amp=amp)
            for m in [m for m in method_labels(records, "equal") if m.startswith("MDFQM")]:
                r = select(records, sweep="equal", method=m, amp=amp)[0]
                ev = r["events_per_s"]
                row = {"amp": amp, "method": m, "carrier": carrier, "events": ev}
                row["fsw_equal"] = ev / (6 if carrier == "SVPWM" else 4)
                row["in_range"] = bool(xs.min() <= ev <= xs.max())
                for key, _ in METRICS:
                    x, y = series(records, "equal", carrier, "events_per_s", key, amp=amp)
                    row[key] = (r[key], loglog_interp(ev, x, y))
                rows.append(row)
    return rows
