"""Register maps of the board demo (pure data: shared by the gateware, the host CLI and the
tests; no Amaranth import).

All addresses are Wishbone *word* addresses as sent in the bridge protocol
(:mod:`mdfqm_gateware.host.protocol`). Access: ``rw`` read/write, ``ro`` read-only, ``strobe``
write-only (any write pulses the function; reads return 0). Writes keep the low ``width`` bits.
Reading an unused offset inside a window returns 0; an address outside every window is not
acknowledged (reply ``'T'``). The drop-in top's own registers are at ``TOP_BASE`` (its map is
:mod:`mdfqm_model.top`, documented in ``docs/top.md``); the demo's block is :func:`demo_window`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["DEMO", "DEMO_ID", "TOP_BASE", "Reg", "Window", "demo_window"]

#: value of the demo's ID register: "MDFQ"
DEMO_ID = 0x4D444651
#: INFO[24]: the window at TOP_BASE holds the drop-in top (always 1 in this version)
INFO_TOP = 1 << 24


@dataclass(frozen=True)
class Reg:
    name: str
    offset: int
    width: int
    access: str          # "rw" | "ro" | "strobe"
    doc: str


@dataclass(frozen=True)
class Window:
    name: str
    base: int
    addr_width: int      # the window holds 2**addr_width words
    regs: tuple

    def __post_init__(self):
        seen = set()
        for reg in self.regs:
            if reg.access not in ("rw", "ro", "strobe"):
                raise ValueError(f"{self.name}.{reg.name}: access {reg.access!r}")
            if not 0 <= reg.offset < 1 << self.addr_width or reg.offset in seen:
                raise ValueError(f"{self.name}.{reg.name}: offset {reg.offset:#x}")
            if not 1 <= reg.width <= 32:
                raise ValueError(f"{self.name}.{reg.name}: width {reg.width}")
            seen.add(reg.offset)

    def __getitem__(self, name: str) -> Reg:
        for reg in self.regs:
            if reg.name == name:
                return reg
        raise KeyError(f"no register {name!r} in the {self.name} window")

    def addr(self, name: str) -> int:
        """Bus word address of register ``name``."""
        return self.base + self[name].offset


#: the drop-in top's window (``docs/top.md``; addresses from :mod:`mdfqm_model.top`)
TOP_BASE = 0x000


def demo_window(phases: int, width: int, acc_bits: int) -> Window:
    """The demo's own block: identification, the NCO, telemetry counters, buttons."""
    if not 1 <= phases <= 8:
        raise ValueError(f"phases must be an integer in [1, 8] for the demo, not {phases!r}")
    return Window("demo", 0x100, 5, (
        Reg("ID", 0x00, 32, "ro", f"{DEMO_ID:#010x} ('MDFQ')"),
        Reg("INFO", 0x01, 32, "ro", "[7:0] phases, [15:8] reference width, [23:16] NCO "
                                    "accumulator bits, [24] modulator is the drop-in top"),
        Reg("CLK_HZ", 0x02, 32, "ro", "system clock in Hz"),
        Reg("NCO_FREQ", 0x03, acc_bits, "rw", "phase increment per clock: "
                                              "f = NCO_FREQ * CLK_HZ / 2**acc_bits"),
        Reg("NCO_AMP", 0x04, width - 1, "rw", "peak reference code, 2**(width-2) codes per "
                                              "Vdc"),
        Reg("NCO_PHASE", 0x05, acc_bits, "ro", "phase accumulator"),
        Reg("SNAPSHOT", 0x06, 1, "strobe", "copy CYCLES and SWITCHES_i, all in one clock"),
        Reg("CYCLES", 0x07, 32, "ro", "clock counter at the last SNAPSHOT"),
        *(Reg(f"SWITCHES_{i}", 0x08 + i, 32, "ro",
              f"turn-ons of either switch of leg {i} at the last SNAPSHOT") for i in range(phases)),
        Reg("BUTTONS", 0x10, 8, "ro", "debounced buttons, bit i = button i pressed"),
    ))


#: the default configuration's demo window (three phases, 16-bit references, 32-bit NCO)
DEMO = demo_window(3, 16, 32)
