"""tools/regmap_gen.py: the top's register map has one source, spec/rdl/mdfqm_top.rdl. Every
derived file is what the RDL gives (the committed regmap_top.py and docs/top.md's table byte for
byte); the compiled RDL agrees with mdfqm_spec.regmap field by field and with the golden model
(reset values, write clamps) in two configurations; the C header compiles and its offsets are the
Python addresses; the IP-XACT file lists every register; a scratch RDL that disagrees fails."""

import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from mdfqm_model.top import TopModel
from mdfqm_spec import regmap
from mdfqm_spec.bus import mapped_words
from mdfqm_spec.contract import (
    BITS_WIDTH,
    MODE_WIDTH,
    MODES,
    RULES,
    TIME_WIDTH,
    loop_latency,
    modes_built_in,
)
from tools import regmap_gen
from tools.regmap_gen import clamp_value, compile_rdl, describe, generate, table_of

IPXACT = "{http://www.accellera.org/XMLSchema/IPXACT/1685-2014}"
#: write data that crosses every clamp's bounds (and dead_min = 7 / 64 of the configurations)
WORDS = (0, 1, 2, 6, 7, 8, 63, 64, 65, 127, 128, 255, 256, 0x7FFF, 0x8000, 0xFFFF, 0x10000,
         0x1FFFF, 0x1234567, 0x7FFFFFFF, 0x80000000, 0xFFFF8000, 0xFFFFFFFE, 0xFFFFFFFF)


@pytest.fixture(scope="module")
def compiled():
    return compile_rdl()


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """Every derived file regenerated from the RDL into a temporary directory (a copy of
    docs/top.md gets the table)."""
    tmp = tmp_path_factory.mktemp("regmap")
    docs = tmp / "top.md"
    shutil.copy(regmap_gen.DOCS, docs)
    written = generate(tmp / "out", python_path=tmp / "regmap_top.py", docs=docs)
    return tmp, written


# ---------------------------------------------------------------------------- derived files
def test_committed_python_map_is_what_the_rdl_gives(generated):
    tmp, _ = generated
    assert (tmp / "regmap_top.py").read_text() == regmap_gen.PYTHON_MAP.read_text(), \
        "spec/mdfqm_spec/regmap_top.py is stale: run python -m tools.regmap_gen"


def test_docs_table_is_what_the_rdl_gives(generated):
    tmp, _ = generated
    assert table_of((tmp / "top.md").read_text()) == table_of(regmap_gen.DOCS.read_text()), \
        "docs/top.md's register table is stale: run python -m tools.regmap_gen"


def test_docs_slverr_words_are_what_the_rdl_gives(generated):
    tmp, _ = generated
    region = (regmap_gen.UNMAPPED_BEGIN, regmap_gen.UNMAPPED_END)
    assert table_of((tmp / "top.md").read_text(), *region) == \
        table_of(regmap_gen.DOCS.read_text(), *region), \
        "docs/top.md's list of the words that hold no register is stale: run " \
        "python -m tools.regmap_gen"


@pytest.mark.parametrize("phases", range(3, 17))
def test_slverr_words_are_the_words_the_fronts_answer_slverr(compiled, phases):
    """The words docs/top.md lists as holding no register (arrays from element N on, the
    ranges) are exactly those the AXI4-Lite front and its model answer SLVERR for
    (mdfqm_spec.bus.mapped_words, whose responses tb/test_top.py checks), at every N."""
    data = describe(compiled)
    arrays, ranges = regmap_gen.unmapped(data)
    by_name = {reg.name: reg for reg in data.registers}
    listed = {w for a, b in ranges for w in range(a, b + 1)}
    listed |= {by_name[name].offset + i for name in arrays
               for i in range(phases, by_name[name].count)}
    assert listed == set(range(1 << regmap.ADDR_WIDTH)) - mapped_words(phases)


def test_generated_python_map_is_ruff_clean_and_marked(generated):
    tmp, _ = generated
    text = (tmp / "regmap_top.py").read_text()
    assert text.startswith(f"# {regmap_gen.GENERATED}\n")
    ruff = Path(sys.executable).with_name("ruff")
    if not ruff.exists():
        pytest.skip("ruff is not installed beside this Python")
    done = subprocess.run([str(ruff), "check", "--config", str(regmap_gen.ROOT / "pyproject.toml"),
                           str(tmp / "regmap_top.py")], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


# ---------------------------------------------------------------------------- RDL vs the map
def mismatches(compiled) -> list[str]:
    """Every difference between the compiled RDL and :mod:`mdfqm_spec.regmap`."""
    top, params = compiled.top, compiled.parameters
    bad = []
    if params != regmap.PARAMETERS:
        bad.append(f"parameters {params} != {regmap.PARAMETERS}")
    rdl_regs = list(top.registers())
    if [r.inst_name for r in rdl_regs] != [r.name for r in regmap.REGISTERS]:
        bad.append("register names or order differ")
    for node in rdl_regs:
        try:
            reg = regmap.TOP[node.inst_name]
        except KeyError:
            continue
        count = node.array_dimensions[0] if node.is_array else 1
        fields = sorted(node.fields(), key=lambda f: f.lsb)
        kinds = {f.get_property("sw").name for f in fields}
        access = "R" if kinds == {"r"} else "W" if kinds == {"w"} else "RW"
        address = regmap.REF_BASE if reg.name == "REF" else \
            regmap.EVENTS_BASE if reg.name == "EVENTS" else getattr(regmap, reg.name)
        facts = {"offset": (node.raw_address_offset, reg.offset * 4),
                 "address constant": (node.raw_address_offset, address * 4),
                 "count": (count, reg.count), "access": (access, reg.access),
                 "width": (max(f.msb for f in fields) + 1, reg.width),
                 "fields": ([f.inst_name for f in fields], [f.name for f in reg.fields])}
        for key, (want, have) in facts.items():
            if want != have:
                bad.append(f"{reg.name} {key}: RDL {want}, map {have}")
        for node_f, f in zip(fields, reg.fields, strict=False):   # names compared above
            reset = node_f.get_property("reset", default=0) or 0
            mapped = params[f.reset] if isinstance(f.reset, str) else f.reset
            facts = {"lsb": (node_f.lsb, f.lsb), "width": (node_f.width, f.width),
                     "sw": (node_f.get_property("sw").name, f.access),
                     "reset": (int(reset), int(mapped)),
                     "clamp": (node_f.get_property("clamp", default=None) or "", f.clamp),
                     "singlepulse": (node_f.get_property("singlepulse"), f.singlepulse)}
            for key, (want, have) in facts.items():
                if want != have:
                    bad.append(f"{reg.name}.{f.name} {key}: RDL {want}, map {have}")
            if len(reg.fields) > 1 or f.name != reg.name:
                mask = getattr(regmap, f"{reg.name}_{f.name}", None)
                if mask != ((1 << node_f.width) - 1) << node_f.lsb:
                    bad.append(f"{reg.name}_{f.name}: {mask}")
    return bad


def test_rdl_matches_the_python_map_field_by_field(compiled):
    assert mismatches(compiled) == []


def test_every_generated_constant_reaches_mdfqm_spec_regmap():
    """regmap re-exports each constant of regmap_top unchanged (none shadowed by a hand-written
    name), and keeps the names the gateware, the model and the host import."""
    from mdfqm_spec import regmap_top

    for name in regmap_top.__all__:
        assert getattr(regmap, name) is getattr(regmap_top, name), name
    for name in ("ID", "INFO", "DEAD_MIN", "CTRL", "CMD", "STATUS", "PERIOD", "OSR", "DEAD",
                 "MIN_PULSE", "ADC_OFFSET", "EVENTS_TOTAL", "GATES", "IRQ_ENABLE", "IRQ_STATUS",
                 "REF_BASE", "EVENTS_BASE", "CTRL_ENABLE", "CTRL_ZERO_POLICY", "CTRL_MASK",
                 "CMD_REF_COMMIT", "CMD_FAULT_CLEAR", "CMD_COUNT_CLEAR", "STATUS_FAULT",
                 "STATUS_FAULT_INPUT", "STATUS_ACTIVE", "STATUS_REF_PENDING", "STATUS_SATURATED",
                 "STATUS_PERIOD_CLAMPED", "ADDR_WIDTH", "TOP", "REGISTERS", "ID_VALUE"):
        assert hasattr(regmap, name), name


def test_the_map_keeps_the_contract():
    """Facts the gateware relies on, stated independently of the RDL."""
    assert int.from_bytes(b"MDFQ", "big") == regmap.ID_VALUE
    assert regmap.ADDR_WIDTH == 6 and regmap.MAX_PHASES == 16
    assert regmap.TOP["EVENTS"].count == regmap.MAX_PHASES
    for name in ("DEAD_MIN", "DEAD", "MIN_PULSE"):
        assert regmap.TOP[name].width == TIME_WIDTH
    for name in ("EVENTS_TOTAL", "EVENTS"):
        assert regmap.TOP[name].width == regmap.COUNTER_WIDTH == 32
    assert regmap.DEFAULT_DEAD_MIN == 64
    assert regmap.PARAMETERS["latency"] == loop_latency(regmap.PARAMETERS["phases"],
                                                        RULES[regmap.PARAMETERS["rule"]])
    enable, status = regmap.TOP["IRQ_ENABLE"], regmap.TOP["IRQ_STATUS"]
    assert [(f.name, f.lsb) for f in enable.fields] == [(f.name, f.lsb) for f in status.fields]
    assert all(f.intr and f.onwrite == "woclr" for f in status.fields)
    assert (regmap.IRQ_FAULT, regmap.IRQ_COUNTER_WRAP, regmap.IRQ_SAMPLE, regmap.IRQ_SHORT_EDGE,
            regmap.IRQ_WATCHDOG, regmap.IRQ_MASK) == (1, 2, 4, 8, 16, 31)
    # the watchdog's timeout and trip count are 16-bit (the gateware's counters)
    assert regmap.WATCHDOG_TIMEOUT == regmap.WATCHDOG_TRIPS_TRIPS == 0xFFFF
    assert regmap.PARAMETERS["modes"] == modes_built_in(regmap.PARAMETERS["max_bits"]) == \
        len(MODES)
    assert regmap.MODULATION_MODE == (1 << MODE_WIDTH) - 1
    assert regmap.MODULATION_BITS >> regmap.MODULATION_BITS_SHIFT == (1 << BITS_WIDTH) - 1
    assert all(f.singlepulse and f.access == "w" for f in regmap.TOP["CMD"].fields)


def test_intr_fields_name_their_enable(compiled):
    for field in compiled.top.get_child_by_name("IRQ_STATUS").fields():
        enable = field.get_property("enable")
        assert enable.get_path() == f"mdfqm_top.IRQ_ENABLE.{field.inst_name}"


# ---------------------------------------------------------------------------- RDL vs the model
CONFIGS = [
    {},
    {"phases": 5, "width": 18, "rule": "exact_nearest", "dead_min": 7, "upper_active_low": True,
     "lower_active_low": False, "counter_width": 16},
    {"max_bits": 0, "asc": False, "watchdog": False},
]


def _rdl_parameters(config: dict) -> dict:
    params = dict(regmap.PARAMETERS)
    params.update({k: v for k, v in config.items() if k != "rule"})
    rule = config.get("rule", RULES[params["rule"]])
    params["rule"] = RULES.index(rule)
    params["latency"] = loop_latency(params["phases"], rule)
    params["modes"] = modes_built_in(params["max_bits"])
    return params


def _access(model, address, we, value=0):
    """One Wishbone-classic access; returns ``dat_r`` (issued in the first clock)."""
    bus = {"wb_cyc": 1, "wb_stb": 1, "wb_we": we, "wb_adr": address, "wb_dat_w": value}
    model.step(**bus)
    out = model.step(**bus)
    model.step()
    return out["wb_dat_r"]


def _addresses(reg, phases):
    return [reg.offset + i for i in ((0, phases - 1) if reg.count > 1 else (0,))]


@pytest.mark.parametrize("config", CONFIGS, ids=["dropin", "n5_w18", "mdfqm_only"])
def test_rdl_resets_are_the_models(compiled, config):
    """Each register read first thing after reset equals the RDL's reset for that
    configuration's parameters."""
    params = _rdl_parameters(config)
    top = compiled.elaborate(**params)
    for node in top.registers():
        reg = regmap.TOP[node.inst_name]
        want = sum((f.get_property("reset", default=0) or 0) << f.lsb for f in node.fields())
        for address in _addresses(reg, params["phases"]):
            assert _access(TopModel(**config), address, 0) == want, (reg.name, address)


@pytest.mark.parametrize("config", CONFIGS, ids=["dropin", "n5_w18", "mdfqm_only"])
def test_rdl_clamps_are_the_models(compiled, config):
    """A write of each word to each stored read/write register of the RDL reads back what its
    fields' clamps give (the written bits where a field has none)."""
    params = _rdl_parameters(config)
    checked = set()
    for node in compiled.elaborate(**params).registers():
        fields = list(node.fields())
        if {f.get_property("sw").name for f in fields} != {"rw"} or \
                any(f.get_property("onwrite") or f.get_property("intr") for f in fields):
            continue
        if {f.get_property("hw").name for f in fields} == {"w"}:
            continue        # reads the value in force (MODULATION): test_modulation_reads_...
        for address in _addresses(regmap.TOP[node.inst_name], params["phases"]):
            model = TopModel(**config)
            for word in WORDS:
                want = 0
                for f in fields:
                    clamp = f.get_property("clamp", default=None)
                    value = clamp_value(clamp, word, params, f.lsb) if clamp else word >> f.lsb
                    want |= (value & ((1 << f.width) - 1)) << f.lsb
                _access(model, address, 1, word)
                assert _access(model, address, 0) == want, (node.inst_name, hex(word))
        checked.add(node.inst_name)
    assert {"CTRL", "PERIOD", "OSR", "DEAD", "MIN_PULSE", "ADC_OFFSET", "IRQ_ENABLE",
            "REF", "FAULT_REACTION"} <= checked


def test_clamps_are_checked_expressions():
    params = regmap.PARAMETERS
    assert clamp_value("min(max(v, dead_min), 65535)", 3, params) == 64
    assert clamp_value("min(max(s, -2**(width - 1)), 2**(width - 1) - 1)", 0xFFFFFFFF,
                       params) == -1
    assert clamp_value("min(v, 3)", 0b11100, params, lsb=2) == 3
    for bad in ("min(v, 65535", "open('x')", "v.bit_length()", "min(v, x)", "v if s else 0",
                "min(v, 1.5)", "min(v)"):
        with pytest.raises(ValueError, match="clamp"):
            clamp_value(bad, 0, params)


# ---------------------------------------------------------------------------- C header, IP-XACT
def test_c_header_compiles_and_its_offsets_are_the_python_addresses(generated, tmp_path):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("no gcc")
    _, written = generated
    header = next(p for p in written if p.name == regmap_gen.HEADER_NAME)
    text = header.read_text()
    macros = dict(re.findall(r"^#define (MDFQM_TOP__\w+?)(?:\(i\))? (.+)$", text, re.M))
    checks = []
    for reg in regmap.REGISTERS:
        byte = reg.offset * 4
        if reg.count > 1:
            assert macros[f"MDFQM_TOP__{reg.name}_OFFSET"] == f"(0x{byte:02x}u + 0x4u * (i))"
            assert macros[f"MDFQM_TOP__{reg.name}_COUNT"] == f"{reg.count}u"
            checks += [f"MDFQM_TOP__{reg.name}_OFFSET(1) == {byte + 4}",
                       f"offsetof(mdfqm_top_t, {reg.name}[1]) == {byte + 4}",
                       f"MDFQM_TOP__{reg.name}_COUNT == {reg.count}"]
        else:
            assert int(macros[f"MDFQM_TOP__{reg.name}_OFFSET"].rstrip("u"), 16) == byte
            checks += [f"MDFQM_TOP__{reg.name}_OFFSET == {byte}",
                       f"offsetof(mdfqm_top_t, {reg.name}) == {byte}"]
        prefix = f"MDFQM_TOP__{reg.name}{'X' if reg.count > 1 else ''}"   # PeakRDL: REFX
        for f in reg.fields:
            assert int(macros[f"{prefix}__{f.name}_bm"], 16) == f.mask
            checks += [f"{prefix}__{f.name}_bm == {f.mask}u", f"{prefix}__{f.name}_bp == {f.lsb}"]

    def compiles(conditions):
        source = tmp_path / "check.c"
        source.write_text(
            f'#include <stddef.h>\n#include "{header}"\n' + "".join(
                f"typedef char check_{k}[({c}) ? 1 : -1];\n" for k, c in enumerate(conditions)))
        return subprocess.run([gcc, "-Wall", "-Werror", "-std=c99", "-fsyntax-only",
                               str(source)], capture_output=True, text=True)

    done = compiles(checks)
    assert done.returncode == 0, done.stderr
    wrong = compiles([f"MDFQM_TOP__CTRL_OFFSET == {regmap.CTRL * 4 + 4}"])
    assert wrong.returncode != 0           # the check itself can fail


def test_ipxact_lists_every_register(generated):
    _, written = generated
    path = next(p for p in written if p.name == regmap_gen.IPXACT_NAME)
    root = ET.parse(path).getroot()
    block = root.find(f"{IPXACT}memoryMaps/{IPXACT}memoryMap/{IPXACT}addressBlock")
    found = {}
    for register in block.iterfind(f"{IPXACT}register"):
        dim = register.find(f"{IPXACT}dim")
        fields = [(f.findtext(f"{IPXACT}name"), int(f.findtext(f"{IPXACT}bitOffset")),
                   int(f.findtext(f"{IPXACT}bitWidth")))
                  for f in register.iterfind(f"{IPXACT}field")]
        found[register.findtext(f"{IPXACT}name")] = (
            int(register.findtext(f"{IPXACT}addressOffset").removeprefix("'h"), 16),
            int(dim.text) if dim is not None else 1, fields)
    assert found == {reg.name: (reg.offset * 4, reg.count,
                                [(f.name, f.lsb, f.width) for f in reg.fields])
                     for reg in regmap.REGISTERS}


def test_markdown_reference_covers_every_register(generated):
    _, written = generated
    text = next(p for p in written if p.name == regmap_gen.MARKDOWN_NAME).read_text()
    for reg in regmap.REGISTERS:
        assert text.count(f"### {reg.name} register") == reg.count, reg.name


# ---------------------------------------------------------------------------- disagreement fails
def test_an_rdl_that_disagrees_with_the_committed_map_fails(tmp_path):
    """A scratch copy of the RDL with OSR's clamp and CTRL's address changed: the generator's
    check names both committed files, the field-by-field comparison names both registers."""
    text = regmap_gen.RDL.read_text()
    edits = {'clamp = "min(v, 255)"': 'clamp = "min(v, 127)"', "} CTRL @ 0x0C;": "} CTRL @ 0xE0;"}
    for old, new in edits.items():
        assert text.count(old) == 1
        text = text.replace(old, new)
    scratch = tmp_path / "mdfqm_top.rdl"
    scratch.write_text(text)
    stale = generate(tmp_path / "out", rdl=scratch, check=True)
    assert sorted(stale) == sorted([regmap_gen.PYTHON_MAP, regmap_gen.DOCS])
    assert regmap_gen.main(["--out", str(tmp_path / "out"), "--rdl", str(scratch),
                            "--check"]) == 1
    bad = mismatches(compile_rdl(scratch))
    assert any(m.startswith("OSR.OSR clamp") for m in bad), bad
    assert any(m.startswith("CTRL offset") for m in bad), bad


def test_the_generator_rejects_a_bad_clamp_and_a_derived_reset(tmp_path):
    text = regmap_gen.RDL.read_text()
    scratch = tmp_path / "bad.rdl"
    scratch.write_text(text.replace('clamp = "min(v, 255)"', 'clamp = "min(v, osr_max)"'))
    with pytest.raises(ValueError, match=r"OSR.*unknown name 'osr_max'"):
        describe(compile_rdl(scratch))
    scratch.write_text(text.replace("DEAD[15:0] = dead_min;", "DEAD[15:0] = dead_min + 1;"))
    with pytest.raises(ValueError, match=r"DEAD.*must be equal to it"):
        describe(compile_rdl(scratch))


def test_committed_files_pass_the_check_mode(tmp_path):
    assert generate(tmp_path / "out", check=True) == []


# ---------------------------------------------------------------------------- the hardware path
def test_hardware_and_model_packages_load_no_rdl_compiler():
    code = ("import sys, mdfqm_gateware, mdfqm_spec.regmap, mdfqm_model\n"
            "from mdfqm_gateware import MdfqmTop\n"
            "MdfqmTop()\n"
            "bad = sorted(m for m in sys.modules\n"
            "             if m.split('.')[0] in ('systemrdl', 'antlr4', 'tools')\n"
            "             or m.startswith('peakrdl'))\n"
            "print(bad)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=regmap_gen.ROOT)
    assert out.stdout.strip() == "[]", out.stdout
