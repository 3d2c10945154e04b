"""The Wishbone classic bus of the drop-in top (slave side): 32-bit data, word addresses.

Member names and shapes match the demo's ``WishboneSignature`` (cyc stb we adr dat_w sel out,
dat_r ack in, from the master's view), so a master connects with ``wiring.connect``.
"""

from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.validate import validate_positive

__all__ = ["WishboneSignature"]


class WishboneSignature(wiring.Signature):
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

    def __eq__(self, other):
        return (isinstance(other, WishboneSignature) and self.addr_width == other.addr_width)

    def __hash__(self):
        return hash((type(self), self.addr_width))

    def __repr__(self):
        return f"WishboneSignature({self.addr_width})"
