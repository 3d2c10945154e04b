"""Two Wishbone-classic masters on one bus: the UART bridge and the demo's bus sequencer.

Timing: a register ``owner`` (reset: master 0) selects the master whose ``cyc stb we adr dat_w
sel`` the bus takes; the bus side is registered, so the slaves see a master's request one clock
after the master raises it, and the paths into the register decoders behind it start at these
registers. ``cyc``/``stb`` are the owner's of the clock before, dropped in the clock after an
``ack`` (the master drops its own then: no second request reaches a slave). Only the owner sees
``ack``; ``dat_r`` goes to both (both combinational). In a cycle in which the owner's ``cyc``
and the bus's ``cyc`` are low the next owner is chosen: master 1 if its ``cyc`` is high, else
master 0 if its ``cyc`` is high, else unchanged (so an ``ack`` always reaches the master whose
request it answers, even one that gave up waiting for it). A master that is not the owner
waits (``cyc`` high, no ``ack``) until it is.
"""

from amaranth import Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.validate import validate_positive

from .wishbone import WishboneSignature

__all__ = ["WishboneArbiter"]


class WishboneArbiter(wiring.Component):
    """Share one Wishbone-classic bus between two masters, a whole cycle at a time, with the
    request registered (one clock from a master to the slaves).

    Ports
    -----
    m0, m1 : In(WishboneSignature(addr_width))
        The masters; ``m1`` wins when both wait for a free bus.
    bus : Out(WishboneSignature(addr_width))
        To the slaves (or a decoder): ``cyc stb we adr dat_w sel`` registered.
    owner : Out(1)
        The master that owns the bus (registered).

    Parameters
    ----------
    addr_width : int in [1, 30]
    """

    def __init__(self, addr_width: int):
        self.addr_width = validate_positive(addr_width, "addr_width", maximum=30)
        super().__init__({
            "m0": In(WishboneSignature(addr_width)),
            "m1": In(WishboneSignature(addr_width)),
            "bus": Out(WishboneSignature(addr_width)),
            "owner": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        m0, m1, bus, owner = self.m0, self.m1, self.bus, self.owner
        for name in ("we", "adr", "dat_w", "sel"):
            m.d.sync += getattr(bus, name).eq(Mux(owner, getattr(m1, name), getattr(m0, name)))
        for name in ("cyc", "stb"):
            m.d.sync += getattr(bus, name).eq(Mux(owner, getattr(m1, name), getattr(m0, name))
                                              & ~bus.ack)
        m.d.comb += [
            m0.ack.eq(bus.ack & ~owner), m1.ack.eq(bus.ack & owner),
            m0.dat_r.eq(bus.dat_r), m1.dat_r.eq(bus.dat_r),
        ]
        current = Signal()
        m.d.comb += current.eq(Mux(owner, m1.cyc, m0.cyc))
        with m.If(~current & ~bus.cyc):
            with m.If(m1.cyc):
                m.d.sync += owner.eq(1)
            with m.Elif(m0.cyc):
                m.d.sync += owner.eq(0)
        return m
