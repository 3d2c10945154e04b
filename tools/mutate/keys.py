"""Mutation keys: a mutation named by the source text of what it mutates, not by its line.

A key is five space-separated fields::

    rtl/mdfqm_gateware/integrator.py@1f0c2a9e integrator $add#0 B[7] const1

1. the source of the cell: ``file@digest``, the digest naming the *source unit* of the line
   Yosys recorded for the cell (:func:`unit_at`); a cell with several sources lists each, joined
   by commas and sorted; a cell Yosys made without a source takes those of what it drives,
   marked ``~``;
2. its hierarchy scope (``top`` for the top level);
3. its type and rank among the cells of that scope and type whose sources are the same units;
4. the port and bit;
5. the mode (``inv``, ``const0``, ``const1``, ``cnot0``/``cnot1`` with the control bit).

A source unit is the smallest piece of Python around the line that stands alone: a simple
statement, the header of a compound one (``with m.If(x):``, not its body), or one element of a
list, tuple, set or dict literal that does not share a line with another element (one entry of
``m.d.sync += [...]``, one port of a signature). Its digest is a hash of its text as
``ast.unparse`` writes it: comments, line breaks and spacing do not count, and edits elsewhere in
the file do not move it. A key whose unit is gone (its text edited) resolves to nothing: the
sample is then drawn again (``python -m tools.mutate.sample``, see :data:`REDRAW`).
"""

from __future__ import annotations

import ast
import hashlib
import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = ["REDRAW", "Key", "StaleKeyError", "Unit", "digest", "locate", "unit_at", "units"]

#: the command that draws the sample again when its keys no longer name the source
REDRAW = "python -m tools.mutate.sample --write"

#: hex digits of a unit's digest (32 bits: no two units of one file share one in practice; a
#: test checks every unit of the gateware)
DIGEST_LENGTH = 8


class StaleKeyError(KeyError):
    """A key that names no cell of the netlist (its source text is gone, or no such cell):
    the message says which and how to draw the sample again."""

    def __str__(self) -> str:           # KeyError's own str() quotes its argument
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True)
class Unit:
    """One source unit of a file: its lines (1-based, inclusive), its text, its digest."""

    first: int
    last: int
    text: str

    @property
    def digest(self) -> str:
        return digest(self.text)


def digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:DIGEST_LENGTH]


_COMPOUND_HEADERS = {
    ast.If: lambda n: f"if {ast.unparse(n.test)}",
    ast.While: lambda n: f"while {ast.unparse(n.test)}",
    ast.For: lambda n: f"for {ast.unparse(n.target)} in {ast.unparse(n.iter)}",
    ast.With: lambda n: "with " + ", ".join(ast.unparse(i) for i in n.items),
    ast.FunctionDef: lambda n: f"def {n.name}({ast.unparse(n.args)})",
    ast.ClassDef: lambda n: f"class {n.name}(" + ", ".join(
        ast.unparse(b) for b in [*n.bases, *n.keywords]) + ")",
    ast.Try: lambda n: "try",
    ast.Match: lambda n: f"match {ast.unparse(n.subject)}",
}


def _elements(node: ast.AST) -> list[tuple[ast.AST, str]]:
    """The elements of a container literal with their text (a dict's key: value pairs)."""
    if isinstance(node, (ast.List, ast.Tuple, ast.Set)):
        return [(e, ast.unparse(e)) for e in node.elts]
    if isinstance(node, ast.Dict):
        return [(v if k is None else _Span(k, v),
                 f"**{ast.unparse(v)}" if k is None else f"{ast.unparse(k)}: {ast.unparse(v)}")
                for k, v in zip(node.keys, node.values, strict=True)]
    return []


class _Span:
    """The lines of a dict entry (its key to its value)."""

    def __init__(self, key: ast.AST, value: ast.AST):
        self.lineno, self.end_lineno = key.lineno, value.end_lineno


def _collect(tree: ast.AST) -> list[Unit]:
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.stmt):
            header = next((f for t, f in _COMPOUND_HEADERS.items() if isinstance(node, t)), None)
            body = getattr(node, "body", None)
            if header is not None and body and isinstance(body, list):
                first = min([node.lineno, *(d.lineno for d in
                                            getattr(node, "decorator_list", ()))])
                out.append(Unit(first, max(node.lineno, body[0].lineno - 1), header(node)))
            elif header is None:
                out.append(Unit(node.lineno, node.end_lineno, ast.unparse(node)))
        elements = _elements(node)
        spans = [(e.lineno, e.end_lineno) for e, _ in elements]
        for i, ((_, text), (a, b)) in enumerate(zip(elements, spans, strict=True)):
            # an element sharing a line with another is not told apart by a line number
            if all(b2 < a or a2 > b for j, (a2, b2) in enumerate(spans) if j != i):
                out.append(Unit(a, b, text))
    return out


@cache
def _units_of(path: str, stamp: tuple[int, int]) -> tuple[Unit, ...]:
    text = Path(path).read_text()
    try:
        tree = ast.parse(text)
    except SyntaxError:
        tree = None
    found = _collect(tree) if tree is not None else []
    # the smallest unit first; of two with the same lines, the outer one (found first by
    # ast.walk, which goes breadth first): a statement on one line is itself, whole
    order = {id(u): i for i, u in enumerate(found)}
    return tuple(sorted(found, key=lambda u: (u.last - u.first, order[id(u)])))


def units(path: Path | str) -> tuple[Unit, ...]:
    """Every source unit of a Python file, smallest first (cached while the file is
    unchanged)."""
    stat = Path(path).stat()
    return _units_of(str(path), (stat.st_mtime_ns, stat.st_size))


def unit_at(path: Path | str, line: int) -> Unit:
    """The source unit of ``line`` of ``path`` (the smallest that holds it); a line outside
    every unit (a comment, a file that is not Python) is a unit of its own stripped text."""
    for unit in units(path):
        if unit.first <= line <= unit.last:
            return unit
    lines = Path(path).read_text().splitlines()
    text = lines[line - 1].strip() if 0 < line <= len(lines) else ""
    return Unit(line, line, text)


def locate(path: Path | str, wanted: str) -> list[Unit]:
    """The units of ``path`` whose digest is ``wanted`` (first line first; empty when the
    text is gone)."""
    if not Path(path).exists():
        return []
    found = [u for u in units(path) if u.digest == wanted]
    if not found:          # a line outside every unit (:func:`unit_at`)
        lines = Path(path).read_text().splitlines()
        found = [Unit(i, i, t.strip()) for i, t in enumerate(lines, 1)
                 if digest(t.strip()) == wanted]
    return sorted(found, key=lambda u: u.first)


_KEY = re.compile(r"(?P<src>\S+) (?P<scope>\S+) (?P<type>\S+)#(?P<rank>\d+) "
                  r"(?P<port>\w+)\[(?P<bit>\d+)\] (?P<mode>[a-z]+\d?)(?:/(?P<ctrl>\d+))?")


@dataclass(frozen=True)
class Key:
    """A parsed mutation key (see the module docstring)."""

    sources: tuple[str, ...]       # file@digest, ``~`` at the end when taken from what it drives
    scope: str                     # "" for the top level
    type: str
    rank: int
    port: str
    bit: int
    mode: str
    ctrlbit: int | None

    @classmethod
    def parse(cls, text: str) -> Key:
        match = _KEY.fullmatch(text)
        sources = () if match is None or match["src"] == "nosrc" else tuple(
            sorted(match["src"].split(",")))
        if match is None or any("@" not in s for s in sources):
            raise StaleKeyError(f"not a mutation key: {text!r} (file@digest scope type#rank "
                           f"port[bit] mode, tools/mutate/keys.py); draw the sample again with "
                           f"`{REDRAW}`")
        return cls(sources,
                   "" if match["scope"] == "top" else match["scope"], match["type"],
                   int(match["rank"]), match["port"], int(match["bit"]), match["mode"],
                   None if match["ctrl"] is None else int(match["ctrl"]))

    def __str__(self) -> str:
        kind = self.mode if self.ctrlbit is None else f"{self.mode}/{self.ctrlbit}"
        source = ",".join(self.sources) or "nosrc"
        return (f"{source} {self.scope or 'top'} {self.type}#{self.rank} {self.port}[{self.bit}] "
                f"{kind}")

    @property
    def files(self) -> tuple[str, ...]:
        return tuple(s.rstrip("~").split("@")[0] for s in self.sources)

    def where(self, root: Path) -> list[tuple[str, Unit | None]]:
        """Each source as ``(file, its unit now)``; None when the text is gone."""
        out = []
        for source in self.sources:
            file, _, wanted = source.rstrip("~").partition("@")
            path = _file(root, file)
            found = locate(path, wanted) if path is not None else []
            out.append((file, found[0] if found else None))
        return out


def _file(root: Path, file: str) -> Path | None:
    """A key's file: in the repository, or (a library's) on the import path."""
    if (root / file).exists():
        return root / file
    import importlib.util

    top = file.split("/")[0]
    spec = importlib.util.find_spec(top) if re.fullmatch(r"\w+", top) else None
    if spec is not None and spec.submodule_search_locations:
        path = Path(next(iter(spec.submodule_search_locations))).parent / file
        if path.exists():
            return path
    return None
