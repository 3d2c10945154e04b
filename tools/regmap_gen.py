"""The drop-in top's register map, from its one source ``spec/rdl/mdfqm_top.rdl`` (SystemRDL 2.0).

    python -m tools.regmap_gen --out build/generated [--check]

Compiles the RDL with systemrdl-compiler and writes

- ``spec/mdfqm_spec/regmap_top.py``: the map as plain Python data (committed; what
  :mod:`mdfqm_spec.regmap`, and through it the gateware, the model and the host, use);
- the register table of ``docs/top.md``, between ``<!-- regmap:begin -->`` and
  ``<!-- regmap:end -->``, and its list of the words that hold no register (the AXI4-Lite
  ``SLVERR`` words), between ``<!-- regmap-unmapped:begin -->`` and
  ``<!-- regmap-unmapped:end -->`` (committed);
- into ``--out``: ``mdfqm_top_regs.h`` (PeakRDL-cheader, plus the registers' byte offsets),
  ``mdfqm_top_regs.md`` (PeakRDL-markdown: every register and field) and ``mdfqm_top_regs.xml``
  (PeakRDL-ipxact, IEEE 1685-2014), all for the drop-in configuration (the RDL parameters'
  defaults).

With ``--check`` the committed files are not written: it exits 1, naming them, when they differ
from what the RDL gives. Only this tool imports systemrdl-compiler and PeakRDL (``pip install
-e .[dev]``); the hardware packages read the generated Python file.

Conventions the RDL follows (``spec/rdl/README.md``): 32-bit registers at byte addresses = 4 x
the bus's word address; ``sw`` gives a register's access (``R`` every field ``sw = r``, ``W``
every field ``sw = w``, else ``RW``); the user-defined property ``clamp`` is the value a write
stores, an expression (Python syntax) of ``v`` (the written word, unsigned), ``s`` (the word as
signed 32-bit; both shifted down to the field's lsb), the addrmap's parameters, ``min``, ``max``
and integer arithmetic; a reset that depends on the configuration is the addrmap parameter it
equals.
"""

from __future__ import annotations

import argparse
import ast
import json
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

from peakrdl_cheader.c_standards import CStandard
from peakrdl_cheader.exporter import CHeaderExporter
from peakrdl_ipxact import IPXACTExporter
from peakrdl_markdown import MarkdownExporter
from systemrdl import RDLCompileError, RDLCompiler
from systemrdl import warnings as rdl_warnings
from systemrdl.node import AddrmapNode, FieldNode, RegNode

__all__ = [
    "BEGIN",
    "DOCS",
    "END",
    "PYTHON_MAP",
    "RDL",
    "UNMAPPED_BEGIN",
    "UNMAPPED_END",
    "Compiled",
    "check_clamp",
    "clamp_value",
    "compile_rdl",
    "describe",
    "generate",
    "main",
    "render_python",
    "render_table",
    "render_unmapped",
    "splice",
    "splice_docs",
    "table_of",
    "unmapped",
]

ROOT = Path(__file__).resolve().parents[1]
RDL = ROOT / "spec" / "rdl" / "mdfqm_top.rdl"
PYTHON_MAP = ROOT / "spec" / "mdfqm_spec" / "regmap_top.py"
DOCS = ROOT / "docs" / "top.md"
BEGIN, END = "<!-- regmap:begin -->", "<!-- regmap:end -->"
UNMAPPED_BEGIN, UNMAPPED_END = "<!-- regmap-unmapped:begin -->", "<!-- regmap-unmapped:end -->"
HEADER_NAME, MARKDOWN_NAME, IPXACT_NAME = (f"mdfqm_top_regs.{ext}" for ext in ("h", "md", "xml"))
TOP_NAME = "mdfqm_top"
GENERATED = "generated from spec/rdl/mdfqm_top.rdl by tools/regmap_gen.py; do not edit"
_WORD_BYTES = 4


# ---------------------------------------------------------------------------- compiling
class Compiled:
    """The RDL compiled once; :meth:`elaborate` gives its top addrmap for any parameters."""

    def __init__(self, path: Path | None = None):
        self.path = Path(path or RDL)
        # every optional check on, each an error: explicit addresses and bit positions, a reset
        # for every stored field, tightly packed arrays
        self.compiler = RDLCompiler(warning_flags=rdl_warnings.ALL, error_flags=rdl_warnings.ALL)
        self.compiler.compile_file(str(self.path))
        self.top = self.elaborate()
        self.parameters = {p.name: p.get_value() for p in self.top.inst.parameters}

    def elaborate(self, **parameters) -> AddrmapNode:
        """The top addrmap with ``parameters`` overriding the defaults (elaboration only)."""
        return self.compiler.elaborate(TOP_NAME, TOP_NAME, parameters=parameters).top


def compile_rdl(path: Path | None = None) -> Compiled:
    """``path`` (default: :data:`RDL`) compiled."""
    return Compiled(path)


# ---------------------------------------------------------------------------- clamps
_CLAMP_OPS = (ast.Add, ast.Sub, ast.Mult, ast.FloorDiv, ast.Mod, ast.Pow, ast.USub)


def check_clamp(expr: str, parameters) -> ast.Expression:
    """Parse a ``clamp`` and check it uses only ``v``, ``s``, the parameters, ``min``, ``max``,
    integer literals and ``+ - * // % **``; raises ValueError otherwise."""
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as error:
        raise ValueError(f"clamp {expr!r}: {error.msg}") from None
    names = {"v", "s", *parameters}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            if not (isinstance(node.func, ast.Name) and node.func.id in ("min", "max")
                    and len(node.args) >= 2 and not node.keywords):
                raise ValueError(f"clamp {expr!r}: only min(a, b, ...) and max(a, b, ...)")
        elif isinstance(node, ast.Name):
            if node.id not in names | {"min", "max"}:
                raise ValueError(f"clamp {expr!r}: unknown name {node.id!r}")
        elif isinstance(node, ast.Constant):
            if type(node.value) is not int:
                raise ValueError(f"clamp {expr!r}: only integer literals")
        elif not isinstance(node, (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Load,
                                   *_CLAMP_OPS)):
            raise ValueError(f"clamp {expr!r}: {type(node).__name__} is not allowed")
    return tree


def clamp_value(expr: str, word: int, parameters: dict, lsb: int = 0) -> int:
    """The value a write of the 32-bit ``word`` gives a field at ``lsb`` under ``clamp``
    ``expr`` (before the field keeps its low ``width`` bits)."""
    tree = check_clamp(expr, parameters)
    signed = word - (1 << 32) if word >> 31 else word
    env = {**{k: int(v) for k, v in parameters.items()}, "v": word >> lsb, "s": signed >> lsb}
    ops = {ast.Add: int.__add__, ast.Sub: int.__sub__, ast.Mult: int.__mul__,
           ast.FloorDiv: int.__floordiv__, ast.Mod: int.__mod__, ast.Pow: int.__pow__}

    def value(node):
        if isinstance(node, ast.Constant):
            return node.value
        if isinstance(node, ast.Name):
            return env[node.id]
        if isinstance(node, ast.UnaryOp):
            return -value(node.operand)
        if isinstance(node, ast.BinOp):
            return ops[type(node.op)](value(node.left), value(node.right))
        return (min if node.func.id == "min" else max)(*map(value, node.args))

    return value(tree.body)


# ---------------------------------------------------------------------------- the map as data
@dataclass
class FieldData:
    name: str
    lsb: int
    width: int
    access: str             # sw: "r", "rw", "w"
    reset: int | str        # an int, or the name of the parameter it equals
    clamp: str = ""
    doc: str = ""
    onwrite: str = ""       # e.g. "woclr"
    singlepulse: bool = False
    intr: bool = False
    in_force: bool = False  # sw = rw, hw = w: a read returns the hardware's value, not the write

    @property
    def mask(self) -> int:
        return ((1 << self.width) - 1) << self.lsb


@dataclass
class RegisterData:
    name: str
    offset: int             # word address
    access: str             # "R", "RW", "W"
    width: int              # bits up to the highest field's
    reset: str              # as documented: a number, a parameter's name or "config"
    clamp: str
    doc: str
    count: int
    title: str = ""         # the RDL `name`: a few words
    notes: str = ""         # the RDL `desc`
    fields: list = field(default_factory=list)

    def named_fields(self) -> list:
        """Fields that get constants of their own (not the one field named as the register)."""
        return [f for f in self.fields if not (len(self.fields) == 1 and f.name == self.name)]


@dataclass
class MapData:
    parameters: dict
    addr_width: int
    registers: list

    def constants(self) -> dict:
        """Name -> value of every generated constant; raises ValueError when two names clash
        (say a register ``IRQ`` with a field ``STATUS`` and a register ``IRQ_STATUS``)."""
        pairs = [("ADDR_WIDTH", self.addr_width), ("PARAMETERS", None)]
        for reg in self.registers:
            pairs.append((f"{reg.name}_BASE" if reg.count > 1 else reg.name, reg.offset))
        for reg in self.registers:
            named = reg.named_fields()
            for f in named:
                pairs += [(f"{reg.name}_{f.name}", f.mask), (f"{reg.name}_{f.name}_SHIFT", f.lsb)]
            if named:
                pairs.append((f"{reg.name}_MASK", sum(f.mask for f in reg.fields)))
        out = dict(pairs)
        if len(out) != len(pairs):
            clashes = sorted({name for name, _ in pairs if [n for n, _ in pairs].count(name) > 1})
            raise ValueError(f"generated names clash: {clashes}")
        del out["PARAMETERS"]
        return out


def _text(node, prop: str) -> str:
    text = node.get_property(prop, default=None) or ""
    return " ".join(text.split())


def _access(fields: list) -> str:
    kinds = {f.access for f in fields}
    return "R" if kinds == {"r"} else "W" if kinds == {"w"} else "RW"


def _probe(value):
    """Another value of a parameter, to find what depends on it."""
    if isinstance(value, bool):
        return not value
    if isinstance(value, int):
        return value - 1 if value > 0 else 1
    raise ValueError(f"parameter value {value!r}: only integer and boolean parameters")


def _resets(top: AddrmapNode) -> dict:
    return {f.get_path(): f.get_property("reset", default=0) or 0
            for reg in top.registers() for f in reg.fields()}


def describe(compiled: Compiled) -> MapData:
    """The compiled map as :class:`MapData`; raises ValueError for what breaks the conventions
    (registers not 32-bit, unaligned, clashing names, bad clamps, resets that depend on a
    parameter without being equal to it)."""
    top, params = compiled.top, compiled.parameters
    base = _resets(top)
    depends: dict = {}
    for name, value in params.items():
        probe = _probe(value)
        for path, reset in _resets(compiled.elaborate(**{name: probe})).items():
            if reset != base[path]:
                if base[path] != int(value) or reset != int(probe):
                    raise ValueError(f"{path}: a reset that depends on parameter {name!r} must "
                                     f"be equal to it")
                depends.setdefault(path, []).append(name)
    registers, words = [], 0
    for reg in top.registers():
        registers.append(_register(reg, params, depends))
        words = max(words, (reg.raw_address_offset + reg.total_size) // _WORD_BYTES)
    return MapData(dict(params), max(words - 1, 1).bit_length(), registers)


def _register(reg: RegNode, params: dict, depends: dict) -> RegisterData:
    path = reg.get_path(empty_array_suffix="")
    if reg.get_property("regwidth") != 32 or reg.raw_address_offset % _WORD_BYTES:
        raise ValueError(f"{path}: registers are 32 bits wide at word-aligned addresses")
    count = 1
    if reg.is_array:
        if len(reg.array_dimensions) != 1 or reg.array_stride != _WORD_BYTES:
            raise ValueError(f"{path}: arrays are one-dimensional, one register per word")
        count = reg.array_dimensions[0]
    fields = [_field(f, params, depends) for f in reg.fields()]
    fields.sort(key=lambda f: f.lsb)
    named = {f.name for f in fields if isinstance(f.reset, str)}
    if not named:
        value = sum(f.reset << f.lsb for f in fields)
        reset = str(value) if value < 10 else f"0x{value:08X}"
    elif len(fields) == 1:
        reset = fields[0].reset
    else:
        reset = "config"
    clamps = [f for f in fields if f.clamp]
    clamp = (clamps[0].clamp if len(fields) == 1 and clamps else
             "; ".join(f"{f.name}: {f.clamp}" for f in clamps))
    title, notes = _text(reg, "name"), _text(reg, "desc")
    if title == reg.inst_name:      # the RDL default `name` is the instance name
        title = ""
    return RegisterData(
        name=reg.inst_name, offset=reg.raw_address_offset // _WORD_BYTES, access=_access(fields),
        width=max(f.lsb + f.width for f in fields), reset=reset, clamp=clamp,
        doc=". ".join(t for t in (title, notes) if t), count=count, title=title, notes=notes,
        fields=fields)


def _field(node: FieldNode, params: dict, depends: dict) -> FieldData:
    path = node.get_path(empty_array_suffix="")
    on = depends.get(node.get_path(), [])
    if len(on) > 1:
        raise ValueError(f"{path}: reset depends on {on}, not one parameter")
    clamp = node.get_property("clamp", default=None) or ""
    if clamp:
        try:
            check_clamp(clamp, params)
        except ValueError as error:
            raise ValueError(f"{path}: {error}") from None
    onwrite = node.get_property("onwrite")
    doc = _text(node, "desc") or (_text(node, "name") if node.get_property("name") !=
                                   node.inst_name else "")
    return FieldData(
        name=node.inst_name, lsb=node.lsb, width=node.width, access=node.get_property("sw").name,
        reset=on[0] if on else int(node.get_property("reset", default=0) or 0), clamp=clamp,
        doc=doc, onwrite=onwrite.name if onwrite else "",
        singlepulse=bool(node.get_property("singlepulse")), intr=bool(node.get_property("intr")),
        in_force=(node.get_property("sw").name == "rw" and node.get_property("hw").name == "w"
                  and not node.get_property("intr")))


# ---------------------------------------------------------------------------- the Python file
def _str(text: str, indent: int, used: int, room: int = 100) -> list[str]:
    """``text`` as a Python string literal starting ``used`` columns in, split into implicitly
    joined lines (indented by ``indent``) when it does not fit."""
    literal = json.dumps(text, ensure_ascii=False)
    if used + len(literal) + 1 <= room:
        return [literal]
    pad = " " * indent
    lines, line = [], ""
    for word in re.split(r"(?<= )", text):
        if line and indent + 4 + len(json.dumps(line + word, ensure_ascii=False)) > room:
            lines.append(line)
            line = ""
        line += word
    lines.append(line)
    return ["(", *(f"{pad}    {json.dumps(chunk, ensure_ascii=False)}" for chunk in lines),
            f"{pad})"]


def _value(key: str, value, indent: int = 0, used: int = 0) -> list[str]:
    if isinstance(value, str):
        return _str(value, indent, used)
    if isinstance(value, bool):
        return [str(value)]
    if isinstance(value, int):
        hexadecimal = key == "offset" or (key == "reset" and value > 9)
        return [f"0x{value:02X}" if hexadecimal else str(value)]
    raise TypeError(value)


def _record(record: dict, indent: int) -> list[str]:
    pad = " " * indent
    if "fields" not in record:         # a field: its items packed into as few lines as fit
        items = [f'"{k}": {_value(k, v)[0]}' for k, v in record.items()]
        lines, line = [], f"{pad}{{{items[0]}"
        for item in items[1:]:
            if len(line) + len(item) + 4 <= 100:
                line += f", {item}"
            else:
                lines.append(line + ",")
                line = f"{pad} {item}"
        lines.append(line + "},")
        if all(len(x) <= 100 for x in lines):
            return lines
    lines = [f"{pad}{{"]
    for key, value in record.items():
        if key == "fields":
            lines.append(f'{pad}    "fields": (')
            for item in value:
                lines.extend(_record(item, indent + 8))
            lines.append(f"{pad}    ),")
            continue
        prefix = f'{pad}    "{key}": '
        first, *rest = _value(key, value, indent + 4, len(prefix))
        lines.append(prefix + first)
        lines.extend(rest)
        lines[-1] += ","
    lines.append(f"{pad}}},")
    return lines


#: the keys of a field record written only when they differ from these defaults
FIELD_DEFAULTS = {"clamp": "", "doc": "", "onwrite": "", "singlepulse": False, "intr": False,
                  "in_force": False}


def render_python(data: MapData) -> str:
    """The text of ``spec/mdfqm_spec/regmap_top.py``."""
    constants = data.constants()
    out = [
        f"# {GENERATED}",
        '"""The drop-in top\'s register map as plain data, compiled from its SystemRDL source:',
        ":mod:`mdfqm_spec.regmap` builds its records and constants from this module.",
        "",
        "Addresses are 32-bit-word addresses (the RDL's byte addresses / 4). Constants: the word",
        "address of each register (``<NAME>_BASE`` the first of an array); for each field that is",
        "not its register's only namesake, its mask ``<REG>_<FIELD>`` and position",
        "``<REG>_<FIELD>_SHIFT``, and ``<REG>_MASK`` the bits the register defines. A reset is an",
        "int, or the name of the configuration parameter it equals (``PARAMETERS``: the RDL",
        "addrmap's parameters and their drop-in defaults); a register's ``reset`` is as documented",
        '(``"config"``: several parameters). ``clamp``: the value a write stores, an expression of',
        "``v`` (the written word), ``s`` (the word as signed 32-bit) and the parameters.",
        '"""',
        "",
        "# the constants (mdfqm_spec.regmap imports them all); the records are REGISTERS",
        "__all__ = [",
        *(f'    "{name}",' for name in sorted([*constants, "PARAMETERS"])),
        "]",
        "",
        "#: the RDL addrmap's parameters and their defaults (the drop-in configuration)",
        "PARAMETERS = {",
        *(f'    "{k}": {_value(k, v)[0]},' for k, v in data.parameters.items()),
        "}",
        "#: word-address bits of the bus: the fewest that hold every register",
        f"ADDR_WIDTH = {data.addr_width}",
        "",
        "# word addresses",
    ]
    for reg in data.registers:
        out.append(f"{reg.name}_BASE = 0x{reg.offset:02X}" if reg.count > 1 else
                   f"{reg.name} = 0x{reg.offset:02X}")
    for reg in data.registers:
        named = reg.named_fields()
        if not named:
            continue
        out += ["", f"# {reg.name} fields"]
        for f in named:
            out.append(f"{reg.name}_{f.name} = 0x{f.mask:08X}")
            out.append(f"{reg.name}_{f.name}_SHIFT = {f.lsb}")
        out.append(f"{reg.name}_MASK = 0x{sum(f.mask for f in reg.fields):08X}")
    out += ["", "#: every register, in address order", "REGISTERS = ("]
    for reg in data.registers:
        record = {k: getattr(reg, k) for k in ("name", "offset", "access", "width", "reset",
                                                "clamp", "doc", "count")}
        record["fields"] = [
            {k: getattr(f, k) for k in ("name", "lsb", "width", "access", "reset", *FIELD_DEFAULTS)
             if FIELD_DEFAULTS.get(k) != getattr(f, k)}
            for f in reg.fields]
        out.extend(_record(record, 4))
    out.append(")")
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------------------- the docs table
def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _bits(f: FieldData) -> str:
    return f"[{f.lsb}]" if f.width == 1 else f"[{f.lsb + f.width - 1}:{f.lsb}]"


def render_table(data: MapData) -> str:
    """The register table of ``docs/top.md`` (between the markers)."""
    rows = [
        f"<!-- {GENERATED} -->",
        "| addr | name | access | reset | clamp (stored value) | fields / notes |",
        "|---|---|---|---|---|---|",
    ]
    for reg in data.registers:
        addr = f"0x{reg.offset:02X}" + ("+i" if reg.count > 1 else "")
        name = f"{reg.name}[i]" if reg.count > 1 else reg.name
        named = reg.named_fields()
        fields = ", ".join(f"{_bits(f)} {f.name}" + (f" ({f.doc})" if f.doc else "")
                           for f in named)
        notes = ": ".join(t for t in (reg.title, fields) if t)
        if reg.notes:
            notes = f"{notes}. {reg.notes}" if notes else reg.notes
        clamp = f"`{reg.clamp}`" if reg.clamp else ""
        rows.append(f"| {addr} | `{name}` | {reg.access} | `{reg.reset}` | {_cell(clamp)} | "
                    f"{_cell(notes)} |")
    return "\n".join(rows) + "\n"


def unmapped(data: MapData) -> tuple[list[str], list[tuple[int, int]]]:
    """The words of the bus that hold no register: the arrays (one element per leg: those
    from ``phases`` on hold none) and the ranges ``(first, last)`` no register holds at all."""
    arrays = [reg.name for reg in data.registers if reg.count > 1]
    held = {w for reg in data.registers for w in range(reg.offset, reg.offset + reg.count)}
    ranges: list[tuple[int, int]] = []
    for word in sorted(set(range(1 << data.addr_width)) - held):
        if ranges and ranges[-1][1] == word - 1:
            ranges[-1] = (ranges[-1][0], word)
        else:
            ranges.append((word, word))
    return arrays, ranges


def render_unmapped(data: MapData) -> str:
    """The list of the words that hold no register, for a sentence of ``docs/top.md``."""
    arrays, ranges = unmapped(data)
    parts = ["/".join(f"`{name}[i]`" for name in arrays) + " with `i >= N`"] if arrays else []
    parts += [f"`0x{a:02X}`" if a == b else f"`0x{a:02X}`-`0x{b:02X}`" for a, b in ranges]
    return ", ".join(parts)


def splice(text: str, table: str, begin: str = BEGIN, end: str = END,
           inline: bool = False) -> str:
    """``text`` with what lies between the markers replaced by ``table`` (``inline``: inside
    a sentence, no line break after the first marker)."""
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        raise ValueError(f"expected one {begin} ... {end} region")
    head, rest = text.split(begin)
    _, tail = rest.split(end)
    return f"{head}{begin}{'' if inline else chr(10)}{table}{end}{tail}"


def table_of(text: str, begin: str = BEGIN, end: str = END) -> str:
    """The region between the markers (what :func:`render_table` wrote there)."""
    splice(text, "", begin, end)        # checks the markers
    return text.split(begin)[1].split(end)[0].removeprefix("\n")


def splice_docs(text: str, data: MapData) -> str:
    """``docs/top.md``'s text with both generated regions rewritten."""
    text = splice(text, render_table(data))
    return splice(text, render_unmapped(data), UNMAPPED_BEGIN, UNMAPPED_END, inline=True)


# ---------------------------------------------------------------------------- PeakRDL outputs
def _offsets(data: MapData) -> str:
    prefix = TOP_NAME.upper()
    lines = [
        "",
        "// Byte offsets of the registers in the bus window (4 x the word address; the same as",
        f"// offsetof({TOP_NAME}_t, NAME)), added by tools/regmap_gen.py. The _reset values above",
        "// are those of the drop-in configuration: INFO, DEAD_MIN, DEAD and PERIOD depend on the",
        "// instance's parameters (read INFO and DEAD_MIN).",
    ]
    for reg in data.registers:
        byte = reg.offset * _WORD_BYTES
        if reg.count > 1:
            lines.append(f"#define {prefix}__{reg.name}_OFFSET(i) (0x{byte:02x}u + 0x4u * (i))")
            lines.append(f"#define {prefix}__{reg.name}_COUNT {reg.count}u")
        else:
            lines.append(f"#define {prefix}__{reg.name}_OFFSET 0x{byte:02x}u")
    return "\n".join(lines) + "\n"


def write_peakrdl(compiled: Compiled, data: MapData, out: Path) -> list[Path]:
    """The C header, the markdown reference and the IP-XACT file, into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    top = compiled.top
    header, markdown, ipxact = out / HEADER_NAME, out / MARKDOWN_NAME, out / IPXACT_NAME
    CHeaderExporter().export(top, str(header), std=CStandard.gnu99, reuse_typedefs=False)
    text = header.read_text()
    footer = text.rindex("\n#ifdef __cplusplus\n}")
    header.write_text(text[:footer] + _offsets(data) + text[footer:])
    MarkdownExporter().export(top, str(markdown), input_files=[_relative(compiled.path)])
    IPXACTExporter(vendor="mdfqm", library="mdfqm", version="0.1.0").export(
        top, str(ipxact), component_name="mdfqm_top_regs")
    return [header, markdown, ipxact]


def _relative(path: Path) -> str:
    path = Path(path).resolve()
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else path.name


# ---------------------------------------------------------------------------- entry points
def generate(out: Path, rdl: Path | None = None, python_path: Path | None = None,
             docs: Path | None = None, check: bool = False) -> list[Path]:
    """Write every derived file (defaults: :data:`RDL`, :data:`PYTHON_MAP`, :data:`DOCS`); with
    ``check`` write only ``out`` and return the committed files that differ from what the RDL
    gives (else the files written)."""
    python_path, docs = Path(python_path or PYTHON_MAP), Path(docs or DOCS)
    compiled = compile_rdl(rdl)
    data = describe(compiled)
    written = write_peakrdl(compiled, data, Path(out))
    python_text = render_python(data)
    docs_text = splice_docs(docs.read_text(), data)
    stale = []
    for path, text in ((python_path, python_text), (docs, docs_text)):
        if path.exists() and path.read_text() == text:
            continue
        if check:
            stale.append(path)
        else:
            path.write_text(text)
            written.append(path)
    return stale if check else written


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("build/generated"))
    parser.add_argument("--rdl", type=Path, default=None, help=f"default: {_relative(RDL)}")
    parser.add_argument("--check", action="store_true",
                        help="write only --out; exit 1 if a committed file is out of date")
    args = parser.parse_args(argv)
    try:
        paths = generate(args.out, args.rdl, check=args.check)
    except RDLCompileError:         # systemrdl-compiler has printed where and why
        return 1
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    if args.check:
        for path in paths:
            print(f"{_relative(path)} is out of date: run python -m tools.regmap_gen",
                  file=sys.stderr)
        return 1 if paths else 0
    for path in paths:
        print(f"wrote {_relative(path)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
