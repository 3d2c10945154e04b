"""Reading the sweep's records (one dict per point, from :func:`.sweeps.run_jobs`): selecting
points, the methods of a sweep in display order, x-y series, and the names of the distortion
fields."""

from __future__ import annotations

import numpy as np

__all__ = ["METRICS", "method_labels", "select", "series"]


METRICS = [
    ("thd_full", "line THD, full band"),
    ("thd_band", "line THD below f_band"),
    ("wthd", "line WTHD"),
    ("thd_i", "phase-current THD (R-L)"),
]


def select(records, **kw):
    """The records whose fields equal every keyword given, in their order."""
    out = []
    for r in records:
        if all(r.get(k) == v for k, v in kw.items()):
            out.append(r)
    return out


def method_labels(records, sweep):
    """The methods of ``sweep``: carrier methods in order of appearance, then MDFQM variants."""
    seen = []
    for r in records:
        if r["sweep"] == sweep and r["method"] not in seen:
            seen.append(r["method"])
    carriers = [m for m in seen if not m.startswith("MDFQM")]
    return carriers + sorted(m for m in seen if m.startswith("MDFQM"))[::-1]


def series(records, sweep, method, xkey, ykey, **kw):
    """``(x, y)`` arrays of one method in one sweep, sorted by ``xkey`` (NaN where ``ykey`` is
    missing)."""
    rs = sorted(select(records, sweep=sweep, method=method, **kw), key=lambda r: r[xkey])
    return np.array([r[xkey] for r in rs], float), np.array([r.get(ykey, np.nan) for r in rs])
