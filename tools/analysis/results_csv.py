"""``results.csv``: every record of the sweep, one row a point, in a stable order."""

from __future__ import annotations

import csv
from pathlib import Path

__all__ = ["write_csv"]


def write_csv(records, path: Path) -> None:
    """Write ``records`` to ``path``: the union of their fields as columns (first-seen order),
    rows sorted by sweep, method, fc, f0, amp and carrier frequency."""
    keys = []
    for r in records:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in sorted(
            records,
            key=lambda r: (r["sweep"], r["method"], r["fc"], r["f0"], r["amp"], r["fsw"] or 0),
        ):
            w.writerow(r)
