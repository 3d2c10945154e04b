"""The drop-in top's bus fronts: Wishbone classic and AXI4-Lite slaves, each turning its bus into
accesses of one register port (:class:`~.bus.RegisterPortSignature`). The access rule they share
is :mod:`mdfqm_spec.bus`'s; the clock-level behaviour of each is in ``docs/top.md``, "Register
bus", and predicted by :mod:`mdfqm_model.top`.

With ``formal=True`` each front carries the handshake rules of its bus as assertions, none of
them assuming anything of the master (so they hold whatever arrives): for Wishbone classic those
of ZipCPU's ``fwbc_slave`` (no ack without a request, one ack per request, the clock after it,
none after reset); for AXI4-Lite those of ``faxil_slave`` (a response held with its payload
until taken, none without a request, exactly one per request, none after reset), with covers.
"""

from amaranth import Const, Module, Mux, ResetSignal, Signal
from amaranth.hdl import Assert, Cover
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.bus import AXI_RESP_OKAY, AXI_RESP_SLVERR
from mdfqm_spec.validate import validate_bool, validate_positive

from .bus import AxiLiteSignature, RegisterPortSignature, WishboneSignature

__all__ = ["AxiLiteFront", "WishboneFront"]


def _after_reset(m):
    """A register that is 1 in every clock whose previous clock was not a reset clock."""
    running = Signal(reset_less=True, name="formal_running")
    m.d.sync += running.eq(~ResetSignal())
    return running


class WishboneFront(wiring.Component):
    """Wishbone classic slave: a request is a clock with ``cyc & stb & ~ack``; its write is
    issued in that clock, ``ack`` is high in the next for one clock, with ``dat_r`` the register
    read in the request clock (0 after a write or with no request). ``sel`` is ignored.

    Ports
    -----
    bus : In(WishboneSignature(addr_width))
    port : Out(RegisterPortSignature(addr_width))

    Parameters
    ----------
    addr_width : int in [1, 30]
    formal : bool
    """

    def __init__(self, addr_width: int, formal: bool = False):
        validate_positive(addr_width, "addr_width", maximum=30)
        self.formal = validate_bool(formal, "formal")
        super().__init__({"bus": In(WishboneSignature(addr_width)),
                          "port": Out(RegisterPortSignature(addr_width))})

    def elaborate(self, platform):
        m = Module()
        bus, port = self.bus, self.port
        request = Signal()
        m.d.comb += [
            request.eq(bus.cyc & bus.stb & ~bus.ack),
            port.w_en.eq(request & bus.we),
            port.w_adr.eq(bus.adr),
            port.w_data.eq(bus.dat_w),
            port.r_adr.eq(bus.adr),
        ]
        m.d.sync += [
            bus.ack.eq(request),
            bus.dat_r.eq(Mux(request & ~bus.we, port.r_data, 0)),
        ]
        if self.formal:
            running = _after_reset(m)
            past_request = Signal(reset_less=True, name="formal_past_request")
            past_ack = Signal(reset_less=True, name="formal_past_ack")
            past_read = Signal(reset_less=True, name="formal_past_read")
            ack_before_last = Signal(reset_less=True, name="formal_ack_before_last")
            m.d.sync += [past_request.eq(request & ~ResetSignal()), past_ack.eq(bus.ack),
                         past_read.eq(request & ~bus.we), ack_before_last.eq(past_ack)]
            m.d.comb += [
                Assert(running | ~bus.ack, "wishbone: ack right after reset"),
                Assert(~running | (bus.ack == past_request),
                       "wishbone: ack is not exactly the clock after a request"),
                Assert(~past_ack | ~bus.ack, "wishbone: two acks for one request"),
                Assert((bus.dat_r == 0) | (bus.ack & past_read),
                       "wishbone: read data outside a read's ack"),
                Cover(bus.ack & past_read & (bus.dat_r != 0)),
                Cover(bus.ack & past_read & ack_before_last),      # an access every other clock
            ]
        return m


class AxiLiteFront(wiring.Component):
    """AXI4-Lite slave with one access in flight per direction.

    AW and W are taken independently (``awready = ~aw_full``, ``wready = ~w_full``): each is
    held in a register from the clock after its handshake. The write is issued in the first
    clock in which both are held and the B channel is free (``~bvalid | bready``); ``bvalid``
    rises in the next clock and both holding registers empty. A read is issued in the clock
    after the AR handshake when the R channel is free (``~rvalid | rready``), ``rvalid`` and
    ``rdata`` (the register in the clock of the issue) in the next. ``bresp``/``rresp`` are
    OKAY, or SLVERR for a word that holds no register (see :mod:`mdfqm_spec.bus`). ``wstrb``,
    ``awprot``, ``arprot`` and the address's low two bits are ignored.

    Ports
    -----
    bus : In(AxiLiteSignature(addr_width + 2))
    port : Out(RegisterPortSignature(addr_width))

    Parameters
    ----------
    addr_width : int in [1, 30]
        Word-address bits of the register port.
    mapped : iterable of int
        The word addresses that hold a register.
    formal : bool
    """

    def __init__(self, addr_width: int, mapped, formal: bool = False):
        validate_positive(addr_width, "addr_width", maximum=30)
        self.mapped = frozenset(mapped)
        if not all(isinstance(a, int) and 0 <= a < (1 << addr_width) for a in self.mapped):
            raise ValueError(f"mapped must hold word addresses in [0, {(1 << addr_width) - 1}]")
        self.formal = validate_bool(formal, "formal")
        self.addr_width = addr_width
        super().__init__({"bus": In(AxiLiteSignature(addr_width + 2)),
                          "port": Out(RegisterPortSignature(addr_width))})

    def elaborate(self, platform):
        m = Module()
        bus, port, aw = self.bus, self.port, self.addr_width
        mask = Const(sum(1 << a for a in self.mapped), 1 << aw)

        def response(address):
            return Mux(mask.bit_select(address, 1), AXI_RESP_OKAY, AXI_RESP_SLVERR)

        aw_full, w_full, ar_full = Signal(), Signal(), Signal()
        # The holding registers are read only while their full flag is set. While it is clear
        # they follow their channel, so the handshake that sets it leaves the request in them
        # and the clock that ends the access keeps it (no state of theirs goes unread), and a
        # reset has no value to give them.
        aw_adr = Signal(aw, reset_less=True)
        ar_adr = Signal(aw, reset_less=True)
        w_data = Signal(32, reset_less=True)
        do_write, do_read = Signal(), Signal()
        m.d.comb += [
            bus.awready.eq(~aw_full),
            bus.wready.eq(~w_full),
            bus.arready.eq(~ar_full),
            do_write.eq(aw_full & w_full & (~bus.bvalid | bus.bready)),
            do_read.eq(ar_full & (~bus.rvalid | bus.rready)),
            port.w_en.eq(do_write),
            port.w_adr.eq(aw_adr),
            port.w_data.eq(w_data),
            port.r_adr.eq(ar_adr),
        ]
        with m.If(do_write):
            m.d.sync += [aw_full.eq(0), w_full.eq(0), bus.bvalid.eq(1),
                         bus.bresp.eq(response(aw_adr))]
        with m.Else():
            with m.If(bus.awvalid & ~aw_full):
                m.d.sync += aw_full.eq(1)
            with m.If(bus.wvalid & ~w_full):
                m.d.sync += w_full.eq(1)
            with m.If(bus.bready):
                m.d.sync += bus.bvalid.eq(0)
        with m.If(do_read):
            m.d.sync += [ar_full.eq(0), bus.rvalid.eq(1), bus.rdata.eq(port.r_data),
                         bus.rresp.eq(response(ar_adr))]
        with m.Else():
            with m.If(bus.arvalid & ~ar_full):
                m.d.sync += ar_full.eq(1)
            with m.If(bus.rready):
                m.d.sync += bus.rvalid.eq(0)
        with m.If(~aw_full):
            m.d.sync += aw_adr.eq(bus.awaddr[2:])
        with m.If(~w_full):
            m.d.sync += w_data.eq(bus.wdata)
        with m.If(~ar_full):
            m.d.sync += ar_adr.eq(bus.araddr[2:])
        if self.formal:
            self._properties(m, aw_full, w_full, ar_full, do_write)
        return m

    def _properties(self, m, aw_full, w_full, ar_full, do_write):
        bus = self.bus
        running = _after_reset(m)
        # accesses in flight, counted from the handshakes alone (faxil_slave's counters)
        writes_aw, writes_w, reads = (Signal(2, name=f"formal_{n}") for n in ("aw", "w", "ar"))
        b_done = bus.bvalid & bus.bready
        m.d.sync += [
            writes_aw.eq(writes_aw + (bus.awvalid & bus.awready) - b_done),
            writes_w.eq(writes_w + (bus.wvalid & bus.wready) - b_done),
            reads.eq(reads + (bus.arvalid & bus.arready) - (bus.rvalid & bus.rready)),
        ]
        held = Signal(reset_less=True, name="formal_b_held")
        held_r = Signal(reset_less=True, name="formal_r_held")
        past_b = Signal(2, reset_less=True, name="formal_past_bresp")
        past_r = Signal(34, reset_less=True, name="formal_past_r")
        past_write = Signal(reset_less=True, name="formal_past_write")
        m.d.sync += [
            held.eq(bus.bvalid & ~bus.bready & ~ResetSignal()),
            held_r.eq(bus.rvalid & ~bus.rready & ~ResetSignal()),
            past_b.eq(bus.bresp),
            past_r.eq(bus.rdata | (bus.rresp << 32)),
            past_write.eq(do_write & ~ResetSignal()),
        ]
        legal = (AXI_RESP_OKAY, AXI_RESP_SLVERR)
        m.d.comb += [
            Assert(running | ~(bus.bvalid | bus.rvalid), "axi4lite: a response right after reset"),
            Assert(~held | (bus.bvalid & (bus.bresp == past_b)),
                   "axi4lite: B dropped or changed before bready"),
            Assert(~held_r | (bus.rvalid & ((bus.rdata | (bus.rresp << 32)) == past_r)),
                   "axi4lite: R dropped or changed before rready"),
            Assert(writes_aw == aw_full + bus.bvalid,
                   "axi4lite: write responses do not match the AW requests one for one"),
            Assert(writes_w == w_full + bus.bvalid,
                   "axi4lite: write responses do not match the W beats one for one"),
            Assert(reads == ar_full + bus.rvalid,
                   "axi4lite: read responses do not match the AR requests one for one"),
            Assert(~bus.bvalid | (bus.bresp == legal[0]) | (bus.bresp == legal[1]),
                   "axi4lite: bresp neither OKAY nor SLVERR"),
            Assert(~bus.rvalid | (bus.rresp == legal[0]) | (bus.rresp == legal[1]),
                   "axi4lite: rresp neither OKAY nor SLVERR"),
            Assert(~past_write | bus.bvalid, "axi4lite: a write issued without its response"),
            Cover(bus.bvalid & bus.bready & (bus.bresp == AXI_RESP_OKAY)),
            Cover(bus.rvalid & bus.rready & (bus.rresp == AXI_RESP_SLVERR)),
            Cover(bus.rvalid & (bus.rdata != 0)),
            Cover(held & bus.bvalid & (writes_aw == 2)),
            Cover(aw_full & ~w_full & bus.bvalid),
        ]
