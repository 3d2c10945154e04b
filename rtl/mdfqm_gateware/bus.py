"""The buses of the drop-in top: Wishbone classic (word addresses), AXI4-Lite (byte addresses),
and the register port between either front and the register file (:mod:`.fronts`).

The Wishbone member names and shapes match the demo's bus (cyc stb we adr dat_w sel out, dat_r
ack in, from the master's view), so a master connects with ``wiring.connect``.
"""

from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.validate import validate_positive

__all__ = ["AxiLiteSignature", "RegisterPortSignature", "WishboneSignature"]


class _AddressedSignature(wiring.Signature):
    """A signature fixed by its address width: equal, hashed and shown by it."""

    addr_width: int

    def __eq__(self, other):
        return type(other) is type(self) and self.addr_width == other.addr_width

    def __hash__(self):
        return hash((type(self), self.addr_width))

    def __repr__(self):
        return f"{type(self).__name__}({self.addr_width})"


class WishboneSignature(_AddressedSignature):
    """Wishbone classic, master's view; a slave takes ``In(WishboneSignature(addr_width))``.

    Members
    -------
    cyc, stb, we : Out(1)
    adr : Out(addr_width)
        Word address.
    dat_w : Out(32)
    sel : Out(4)
        Byte lanes; the top accepts and ignores it (every write is a whole word).
    dat_r : In(32)
        Valid in the ``ack`` cycle.
    ack : In(1)
        One clock, the cycle after the request (registered).

    Parameters
    ----------
    addr_width : int in [1, 30]
    """

    def __init__(self, addr_width: int):
        self.addr_width = validate_positive(addr_width, "addr_width", maximum=30)
        super().__init__({
            "cyc": Out(1),
            "stb": Out(1),
            "we": Out(1),
            "adr": Out(addr_width),
            "dat_w": Out(32),
            "sel": Out(4),
            "dat_r": In(32),
            "ack": In(1),
        })


class AxiLiteSignature(_AddressedSignature):
    """AXI4-Lite, 32-bit data, master's view; a slave takes ``In(AxiLiteSignature(addr_width))``.

    Members
    -------
    awaddr, araddr : Out(addr_width)
        Byte addresses (the low two bits select a byte lane and are ignored by the top).
    awprot, arprot : Out(3)
        Accepted and ignored.
    awvalid, wvalid, arvalid, bready, rready : Out(1)
    awready, wready, arready, bvalid, rvalid : In(1)
    wdata : Out(32)
    wstrb : Out(4)
        Byte strobes; the top accepts and ignores them (every write is a whole word).
    bresp, rresp : In(2)
        ``0b00`` OKAY or ``0b10`` SLVERR (:mod:`mdfqm_spec.bus`).
    rdata : In(32)

    Parameters
    ----------
    addr_width : int in [3, 32]
    """

    def __init__(self, addr_width: int):
        self.addr_width = validate_positive(addr_width, "addr_width", minimum=3, maximum=32)
        super().__init__({
            "awaddr": Out(addr_width), "awprot": Out(3), "awvalid": Out(1), "awready": In(1),
            "wdata": Out(32), "wstrb": Out(4), "wvalid": Out(1), "wready": In(1),
            "bresp": In(2), "bvalid": In(1), "bready": Out(1),
            "araddr": Out(addr_width), "arprot": Out(3), "arvalid": Out(1), "arready": In(1),
            "rdata": In(32), "rresp": In(2), "rvalid": In(1), "rready": Out(1),
        })


class RegisterPortSignature(_AddressedSignature):
    """The register file's port, seen from a bus front (``Out`` for the front).

    Members
    -------
    w_en : Out(1)
        Write ``w_data`` to word ``w_adr`` at the end of this clock (visible in the next).
    w_adr, r_adr : Out(addr_width)
        Word addresses.
    w_data : Out(32)
    r_data : In(32)
        The register at ``r_adr`` in this clock (combinational; 0 where no register is).

    Parameters
    ----------
    addr_width : int in [1, 30]
    """

    def __init__(self, addr_width: int):
        self.addr_width = validate_positive(addr_width, "addr_width", maximum=30)
        super().__init__({
            "w_en": Out(1), "w_adr": Out(addr_width), "w_data": Out(32),
            "r_adr": Out(addr_width), "r_data": In(32),
        })
