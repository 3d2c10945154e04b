# amaranth: UnusedElaboratable=no
"""IP-XACT *component* description of the AXI4-Lite drop-in top, for Vivado's IP catalogue and
block designs: the ports, the ``S_AXI`` slave interface (Xilinx ``aximm`` / ``aximm_rtl``,
protocol AXI4LITE), the level-high interrupt, the clock and reset interfaces, the memory map
(from :mod:`mdfqm_spec.regmap`) and the Verilog file set.

    python -m tools.ipxact_component --out build/generated [--phases 3 --width 16]

Writes ``mdfqm_top_axil_n<N>_w<W>.xml`` (IEEE 1685-2009, the ``spirit`` schema Vivado's IP
packager reads and writes as ``component.xml``) beside the Verilog file of the same name. Only
the standard and the Xilinx interface definitions are used; it is checked here by parsing and
against the generated Verilog, not by Vivado.
"""

# (line 1: the top is built only to read its ports, never elaborated here, on purpose)

from __future__ import annotations

import argparse
import xml.etree.ElementTree as ET
from pathlib import Path

from amaranth import Value
from amaranth.lib.wiring import In

from mdfqm_gateware.top import MdfqmTop
from mdfqm_spec.bus import AXI_ADDR_WIDTH
from mdfqm_spec.regmap import REGISTERS

__all__ = ["AXI_LOGICAL", "SPIRIT", "component", "main", "top_ports"]

SPIRIT = "http://www.spiritconsortium.org/XMLSchema/SPIRIT/1685-2009"
VERSION = "0.1.0"
#: AXI4-Lite port suffix -> the logical port of Xilinx's aximm_rtl abstraction
AXI_LOGICAL = {name: name.upper() for name in (
    "awaddr", "awprot", "awvalid", "awready", "wdata", "wstrb", "wvalid", "wready", "bresp",
    "bvalid", "bready", "araddr", "arprot", "arvalid", "arready", "rdata", "rresp", "rvalid",
    "rready")}
_ACCESS = {"RW": "read-write", "R": "read-only", "W": "write-only"}


def _el(parent, tag, text=None, **attrs):
    element = ET.SubElement(parent, f"{{{SPIRIT}}}{tag}",
                            {f"{{{SPIRIT}}}{k}": str(v) for k, v in attrs.items()})
    if text is not None:
        element.text = str(text)
    return element


def top_ports(top: MdfqmTop) -> list[tuple[str, str, int]]:
    """``(name, "in" | "out", width)`` of every port of the top's Verilog module."""
    ports = [("clk", "in", 1), ("rst", "in", 1)]
    for path, member, value in top.signature.flatten(top):
        ports.append(("__".join(map(str, path)), "in" if member.flow == In else "out",
                      len(Value.cast(value))))
    return ports


def _bus_interface(parent, name, bus, abstraction, mode, port_map, parameters=()):
    interface = _el(parent, "busInterface")
    _el(interface, "name", name)
    _el(interface, "busType", vendor="xilinx.com", library=bus[0], name=bus[1], version="1.0")
    _el(interface, "abstractionType", vendor="xilinx.com", library=bus[0], name=abstraction,
        version="1.0")
    mode_element = _el(interface, mode)
    if mode == "slave" and name == "S_AXI":
        _el(mode_element, "memoryMapRef", memoryMapRef="S_AXI")
    maps = _el(interface, "portMaps")
    for logical, physical in port_map:
        entry = _el(maps, "portMap")
        _el(_el(entry, "logicalPort"), "name", logical)
        _el(_el(entry, "physicalPort"), "name", physical)
    if parameters:
        params = _el(interface, "parameters")
        for key, value in parameters:
            param = _el(params, "parameter")
            _el(param, "name", key)
            _el(param, "value", value)


def component(phases: int = 3, width: int = 16) -> ET.ElementTree:
    """The component description of ``MdfqmTop(phases, width, bus="axi4lite")``."""
    top = MdfqmTop(phases, width, bus="axi4lite")
    name = f"mdfqm_top_axil_n{phases}_w{width}"
    ET.register_namespace("spirit", SPIRIT)
    root = ET.Element(f"{{{SPIRIT}}}component")
    for tag, text in (("vendor", "mdfqm"), ("library", "mdfqm"), ("name", name),
                      ("version", VERSION)):
        _el(root, tag, text)
    interfaces = _el(root, "busInterfaces")
    _bus_interface(interfaces, "S_AXI", ("interface", "aximm"), "aximm_rtl", "slave",
                   [(logical, f"s_axi__{suffix}") for suffix, logical in AXI_LOGICAL.items()],
                   [("PROTOCOL", "AXI4LITE"), ("DATA_WIDTH", 32),
                    ("ADDR_WIDTH", AXI_ADDR_WIDTH)])
    _bus_interface(interfaces, "RST", ("signal", "reset"), "reset_rtl", "slave",
                   [("RST", "rst")], [("POLARITY", "ACTIVE_HIGH")])
    _bus_interface(interfaces, "IRQ", ("signal", "interrupt"), "interrupt_rtl", "master",
                   [("INTERRUPT", "irq")], [("SENSITIVITY", "LEVEL_HIGH")])
    _bus_interface(interfaces, "CLK", ("signal", "clock"), "clock_rtl", "slave",
                   [("CLK", "clk")], [("ASSOCIATED_BUSIF", "S_AXI"), ("ASSOCIATED_RESET", "rst")])

    memory_map = _el(_el(root, "memoryMaps"), "memoryMap")
    _el(memory_map, "name", "S_AXI")
    block = _el(memory_map, "addressBlock")
    _el(block, "name", "registers")
    _el(block, "baseAddress", "0x0")
    _el(block, "range", 1 << AXI_ADDR_WIDTH)
    _el(block, "width", 32)
    _el(block, "usage", "register")
    for reg in REGISTERS:
        for index in range(min(reg.count, phases) if reg.count > 1 else 1):
            register = _el(block, "register")
            _el(register, "name", f"{reg.name}_{index}" if reg.count > 1 else reg.name)
            if reg.doc:
                _el(register, "description", reg.doc)
            _el(register, "addressOffset", hex((reg.offset + index) * 4))
            _el(register, "size", 32)
            _el(register, "access", _ACCESS[reg.access])

    model = _el(root, "model")
    view = _el(_el(model, "views"), "view")
    _el(view, "name", "xilinx_anylanguagesynthesis")
    _el(view, "envIdentifier", ":vivado.xilinx.com:synthesis")
    _el(view, "language", "Verilog")
    _el(view, "modelName", name)
    _el(_el(view, "fileSetRef"), "localName", "verilog_sources")
    ports = _el(model, "ports")
    for port_name, direction, bits in top_ports(top):
        port = _el(ports, "port")
        _el(port, "name", port_name)
        wire = _el(port, "wire")
        _el(wire, "direction", direction)
        if bits > 1:
            vector = _el(wire, "vector")
            _el(vector, "left", bits - 1)
            _el(vector, "right", 0)
    file_set = _el(_el(root, "fileSets"), "fileSet")
    _el(file_set, "name", "verilog_sources")
    file = _el(file_set, "file")
    _el(file, "name", f"{name}.v")
    _el(file, "fileType", "verilogSource")
    ET.indent(root)
    return ET.ElementTree(root)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("build/generated"))
    parser.add_argument("--phases", type=int, default=3)
    parser.add_argument("--width", type=int, default=16)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / f"mdfqm_top_axil_n{args.phases}_w{args.width}.xml"
    component(args.phases, args.width).write(path, xml_declaration=True, encoding="UTF-8")
    print(f"wrote {path}: IP-XACT (1685-2009) component of the AXI4-Lite top")


if __name__ == "__main__":
    main()
