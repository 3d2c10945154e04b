"""Wishbone classic (B4), as used on chip by the demo: 32-bit data, byte-lane selects, *word*
addresses, no ERR/RTY/stall; a slave answers with ``ack`` (the demo's slaves: one clock after
the request, for one clock). The signature is the drop-in top's
(:class:`mdfqm_gateware.bus.WishboneSignature`), so its register port connects directly.

Master rules: ``cyc`` and ``stb`` rise together and stay high, with ``we``/``adr``/``dat_w``/
``sel`` stable, until the cycle in which ``ack`` is high; they drop in the next cycle.
"""

from amaranth import Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_gateware.bus import WishboneSignature
from mdfqm_spec.validate import validate_positive

__all__ = ["WishboneDecoder", "WishboneSignature"]


class WishboneDecoder(wiring.Component):
    """Route one master to the slave whose address window holds ``adr``.

    A window of ``2**width`` words at ``base`` (a multiple of its size) gets the request with
    the low ``width`` address bits (combinational); ``ack``/``dat_r`` come back from the slave
    whose window held ``adr`` in the clock before (registered), which is the selected slave for
    the demo's slaves: they answer one clock after the request, and a master holds ``adr``
    until ``ack``. So the answer's path starts at registers, not at the master's address. An
    address outside every window is never acknowledged (the bridge times out).

    Ports
    -----
    bus : In(WishboneSignature(addr_width))
        From the master.
    <name> : Out(WishboneSignature(width))
        One per window, to its slave.

    Parameters
    ----------
    addr_width : int in [1, 30]
        Master address width.
    windows : dict of name -> (base, width)
        Word-address windows; names must be identifiers other than ``bus``.
    """

    def __init__(self, addr_width: int, windows: dict):
        validate_positive(addr_width, "addr_width", maximum=30)
        if not isinstance(windows, dict) or not windows:
            raise ValueError(f"windows must be a non-empty dict of name -> (base, width), "
                             f"not {windows!r}")
        spans = []
        for name, window in windows.items():
            if not (isinstance(name, str) and name.isidentifier() and name != "bus"):
                raise ValueError(f"windows: name {name!r} must be an identifier other than 'bus'")
            base, width = window
            validate_positive(width, f"windows[{name!r}] width", maximum=addr_width)
            size = 1 << width
            if (not isinstance(base, int) or base < 0 or base % size
                    or base + size > 1 << addr_width):
                raise ValueError(f"windows[{name!r}] base must be a multiple of {size:#x} inside "
                                 f"the {addr_width}-bit address space, not {base!r}")
            for other, lo, hi in spans:
                if base < hi and lo < base + size:
                    raise ValueError(f"windows[{name!r}] at {base:#06x} ({size} words) overlaps "
                                     f"windows[{other!r}] at {lo:#06x}")
            spans.append((name, base, base + size))
        self.addr_width = addr_width
        self.windows = dict(windows)
        super().__init__({
            "bus": In(WishboneSignature(addr_width)),
            **{name: Out(WishboneSignature(width)) for name, (_, width) in windows.items()},
        })

    def elaborate(self, platform):
        m = Module()
        bus = self.bus
        ack, dat_r = 0, 0
        for name, (base, width) in self.windows.items():
            sub = getattr(self, name)
            hit = bus.adr[width:] == base >> width if width < self.addr_width else 1
            answers = Signal(name=f"{name}_answers")
            m.d.sync += answers.eq(hit)
            m.d.comb += [
                sub.cyc.eq(bus.cyc & hit),
                sub.stb.eq(bus.stb & hit),
                sub.we.eq(bus.we),
                sub.adr.eq(bus.adr[:width]),
                sub.dat_w.eq(bus.dat_w),
                sub.sel.eq(bus.sel),
            ]
            ack = ack | (sub.ack & answers)
            dat_r = dat_r | (sub.dat_r & answers.replicate(32))
        m.d.comb += [bus.ack.eq(ack), bus.dat_r.eq(dat_r)]
        return m
