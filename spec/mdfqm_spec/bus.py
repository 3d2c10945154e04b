"""The register buses of the drop-in top: which fronts exist, and the facts both the gateware and
the model need about them (``docs/top.md``, "Register bus").

Both fronts drive one register file through the same access rule: a *write* is taken by the
register file :data:`WRITE_LATENCY` clocks after the clock in which the front issues it, and
takes effect at the end of that clock (visible in the next one); a *read* returns the registers
as they are in the clock in which the front issues it. The Wishbone-classic front
issues an access in every request clock (``cyc & stb & ~ack``); the AXI4-Lite front issues a
write in the clock after it holds both the address (AW) and the data (W) and the write response
channel is free, and a read in the clock after it holds the address (AR) and the read data
channel is free.
"""

from __future__ import annotations

from .regmap import ADDR_WIDTH, REGISTERS

__all__ = [
    "AXI_ADDR_WIDTH",
    "AXI_RESP_OKAY",
    "AXI_RESP_SLVERR",
    "BUSES",
    "WRITE_LATENCY",
    "mapped_words",
    "validate_bus",
]

#: the fronts of :class:`mdfqm_gateware.top.MdfqmTop` (its ``bus`` parameter)
BUSES = ("wishbone", "axi4lite")
#: clocks from a write's issue by the front to the clock in which the register file takes it
#: (the issued write is registered first: the bus inputs' paths end there, not in the register
#: decode and the gate driver behind it)
WRITE_LATENCY = 1
#: AXI4-Lite addresses are byte addresses: the word address shifted left by 2
AXI_ADDR_WIDTH = ADDR_WIDTH + 2
#: AXI4-Lite responses: OKAY for every mapped word (also a write to a read-only one, ignored),
#: SLVERR for a word that holds no register (reads return 0, writes are ignored)
AXI_RESP_OKAY = 0b00
AXI_RESP_SLVERR = 0b10


def validate_bus(bus) -> str:
    if bus not in BUSES:
        raise ValueError(f"bus must be one of {BUSES}, not {bus!r}")
    return bus


def mapped_words(phases: int) -> frozenset:
    """Word addresses that hold a register of a top with ``phases`` legs (the per-leg arrays
    hold ``phases`` of their ``count`` words)."""
    words = set()
    for reg in REGISTERS:
        words.update(range(reg.offset, reg.offset + (phases if reg.count > 1 else 1)))
    return frozenset(words)
