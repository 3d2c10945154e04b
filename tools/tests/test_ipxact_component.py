"""tools/ipxact_component.py: the component description of the AXI4-Lite top names exactly the
ports of the generated Verilog module, maps every AXI4-Lite signal to one of them, and carries
the register map of mdfqm_spec.regmap."""

import re
import xml.etree.ElementTree as ET

from amaranth.back import verilog

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec.bus import mapped_words
from tools.ipxact_component import AXI_LOGICAL, SPIRIT, component

NS = {"spirit": SPIRIT}


def verilog_ports(phases, width):
    """(name, direction, width) of the module's ports, read from the generated Verilog."""
    text = verilog.convert(MdfqmTop(phases, width, bus="axi4lite"), name="top", emit_src=False)
    body = text[text.index("module top("):text.index("endmodule")]
    ports = set()
    for direction, msb, name in re.findall(r"^\s*(input|output)\s+(?:\[(\d+):0\]\s+)?(\w+);",
                                           body, re.M):
        ports.add((name, direction[:-3] if direction == "output" else "in",
                   int(msb) + 1 if msb else 1))
    return ports


def test_ports_are_the_verilog_modules():
    root = component(3, 16).getroot()
    described = set()
    for port in root.iterfind("spirit:model/spirit:ports/spirit:port", NS):
        wire = port.find("spirit:wire", NS)
        left = wire.find("spirit:vector/spirit:left", NS)
        described.add((port.find("spirit:name", NS).text, wire.find("spirit:direction", NS).text,
                       int(left.text) + 1 if left is not None else 1))
    assert described == verilog_ports(3, 16)


def test_every_axi_signal_is_mapped_to_a_port():
    root = component(3, 16).getroot()
    names = {p.find("spirit:name", NS).text
             for p in root.iterfind("spirit:model/spirit:ports/spirit:port", NS)}
    axi = next(b for b in root.iterfind("spirit:busInterfaces/spirit:busInterface", NS)
               if b.find("spirit:name", NS).text == "S_AXI")
    maps = {m.find("spirit:logicalPort/spirit:name", NS).text:
            m.find("spirit:physicalPort/spirit:name", NS).text
            for m in axi.iterfind("spirit:portMaps/spirit:portMap", NS)}
    assert set(maps) == set(AXI_LOGICAL.values())
    assert set(maps.values()) <= names
    assert axi.find("spirit:slave/spirit:memoryMapRef", NS) is not None


def test_memory_map_is_the_register_map():
    root = component(5, 16).getroot()
    offsets = {int(r.find("spirit:addressOffset", NS).text, 16) // 4
               for r in root.iterfind(".//spirit:addressBlock/spirit:register", NS)}
    assert offsets == set(mapped_words(5))


def test_writes_parseable_xml(tmp_path):
    from tools.ipxact_component import main

    main(["--out", str(tmp_path)])
    tree = ET.parse(tmp_path / "mdfqm_top_axil_n3_w16.xml")
    assert tree.getroot().tag == f"{{{SPIRIT}}}component"
