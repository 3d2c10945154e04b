"""Functional coverage of the generated stimulus: named bins, grouped in coverpoints, each
coverpoint owned by the stimulus sequence that aims at it (mdfqm_testkit.sequences), the bins
hit by what the golden model shows while the stimulus is generated, never by what a sequence
meant to do.

Why not cocotb-coverage: the long runs generate their stimulus in plain Python, outside any
simulator, before the vector file is written (tb/mdfqm_testkit/vectors.py), and the
per-clock cocotb tests replay the same generated stimulus; so the bins are sampled in the
generator, where cocotb-coverage's decorators and its process-wide coverage database would add a
dependency and global state shared by every test of a pytest session (and by the xdist
workers) for what is a dictionary of counters. :class:`Coverage` is that dictionary: goals
declared per run, hits counted, the bins missing at the end of a run listed (the tests assert
there are none), and a JSON form, so that a session merges its workers' runs into one
traceability summary (mdfqm_testkit.spec_trace).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable


class Coverage:
    """Coverpoints (name -> the bins a run must hit) and the hits counted per bin.

    ``want(point, bins)`` declares goals; ``hit(point, bin)`` counts one; a hit of an
    undeclared bin is counted too (a goal of another configuration, or a bin beyond the goals,
    shown in the summary), and :meth:`missing` lists the goals never hit."""

    def __init__(self) -> None:
        self.goals: dict[str, set[str]] = {}
        self.hits: Counter = Counter()
        #: coverpoint -> the name of the sequence that aims at it
        self.owners: dict[str, str] = {}
        self._open: dict[str, set[str]] = {}      # the goals not hit yet, per coverpoint

    def want(self, point: str, bins: Iterable, owner: str = "") -> None:
        bins = {str(b) for b in bins}
        self.goals.setdefault(point, set()).update(bins)
        if owner:
            self.owners[point] = owner
        self._open.setdefault(point, set()).update(b for b in bins if not self.hits[point, b])

    def hit(self, point: str, bin_, count: int = 1) -> None:
        bin_ = str(bin_)
        self.hits[point, bin_] += count
        if point in self._open:
            self._open[point].discard(bin_)

    def is_open(self, point: str) -> bool:
        """Whether ``point`` has a goal not hit yet."""
        return bool(self._open.get(point))

    def count(self, point: str, bin_) -> int:
        return self.hits[point, str(bin_)]

    def covered(self, point: str, bin_) -> bool:
        return self.hits[point, str(bin_)] > 0

    def open_bins(self, point: str) -> list[str]:
        """The goals of ``point`` not hit yet."""
        return sorted(self._open.get(point, ()))

    def missing(self) -> list[tuple[str, str]]:
        """Every (coverpoint, bin) declared and never hit."""
        return [(point, b) for point in sorted(self.goals) for b in self.open_bins(point)]

    def merge(self, other: Coverage) -> None:
        for (point, b), n in other.hits.items():
            self.hit(point, b, n)
        for point, bins in other.goals.items():
            self.want(point, bins, other.owners.get(point, ""))

    def to_json(self) -> dict:
        return {"goals": {p: sorted(b) for p, b in sorted(self.goals.items())},
                "owners": dict(sorted(self.owners.items())),
                "hits": [[p, b, n] for (p, b), n in sorted(self.hits.items())]}

    @classmethod
    def from_json(cls, data: dict) -> Coverage:
        coverage = cls()
        for point, b, n in data["hits"]:
            coverage.hit(point, b, n)
        for point, bins in data["goals"].items():
            coverage.want(point, bins, data.get("owners", {}).get(point, ""))
        return coverage

    def report(self, points: Iterable[str] | None = None) -> str:
        """One line per coverpoint: its bins hit of its goals, and the missing ones."""
        lines = []
        for point in sorted(points if points is not None else self.goals):
            goals = self.goals.get(point, set())
            hit = [b for b in goals if self.hits[point, b]]
            line = f"{point}: {len(hit)}/{len(goals)}"
            if len(hit) < len(goals):
                line += " missing " + ", ".join(self.open_bins(point))
            lines.append(line)
        return "\n".join(lines)


def band(value: int, edges: Iterable[int]) -> str:
    """The band of ``value`` between consecutive ``edges`` (ascending, the first the lowest
    value of the first band), named ``"lo..hi"`` (``"lo"`` for a band of one value, ``"lo.."``
    for the last, open one)."""
    edges = list(edges)
    for lo, hi in zip(edges, [*edges[1:], None], strict=True):
        if hi is None or value < hi:
            if value < lo:
                break
            return f"{lo}.." if hi is None else (f"{lo}" if hi == lo + 1 else f"{lo}..{hi - 1}")
    raise ValueError(f"{value} below the first band ({edges[0]})")


def band_low(name: str) -> int:
    """The lowest value of the band :func:`band` named ``name``."""
    return int(name.split("..")[0])


def bands(edges: Iterable[int]) -> list[str]:
    """The names :func:`band` gives to the bands between ``edges``."""
    edges = list(edges)
    return [band(lo, edges) for lo in edges]
