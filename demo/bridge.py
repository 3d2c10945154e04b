"""UART -> Wishbone bridge: the binary request/reply protocol of
:mod:`mdfqm_spec.bridge` on a byte stream, as a Wishbone-classic master.

Timing, clock by clock (predicted by ``tb/mdfqm_testkit/demo_models.py: BridgeModel``):

- Receiving (``rx.ready`` high): a byte accepted where a frame starts is kept only if it is
  ``'W'`` or ``'R'``. The other bytes of the frame follow; a frame with bytes missing is dropped
  when no byte has been accepted for ``frame_timeout`` clocks. The clock after the checksum byte
  is accepted, either the bus cycle starts (``cyc = stb = 1``, registered) or, for a wrong
  checksum, the ``'E'`` reply starts.
- Bus cycle: ``cyc``/``stb`` stay high until the first clock with ``ack`` (``dat_r`` is taken
  then) or until they have been high for ``bus_timeout`` clocks without one; they drop in the
  next clock, in which the reply starts.
- Reply: ``tx.valid`` is high for the eight reply bytes (payload combinational from registers);
  the clock after the last one is accepted, the bridge receives again. Bytes arriving while the
  bridge executes or replies are not read (the UART receiver holds one and drops the rest).
"""

from amaranth import Array, Cat, Const, Module, Mux, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.bridge import CMD_READ, CMD_WRITE, STATUS_BAD_CHECKSUM, STATUS_BUS_TIMEOUT
from mdfqm_spec.validate import validate_positive

from .wishbone import WishboneSignature

__all__ = ["UartBridge"]


class UartBridge(wiring.Component):
    """Execute ``'W'``/``'R'`` requests from a byte stream as Wishbone-classic cycles.

    Ports
    -----
    rx : In(stream.Signature(8))
        Request bytes (from :class:`~.uart.UartRx`); ``rx.ready`` is combinational from
        registers only.
    tx : Out(stream.Signature(8))
        Reply bytes (to :class:`~.uart.UartTx`); valid and payload combinational from registers.
    bus : Out(WishboneSignature(addr_width))
        Wishbone-classic master; ``adr`` (the low ``addr_width`` bits of the request's 16-bit
        address) and ``dat_w`` are the request's registers: they change while a request is
        received and hold still from its checksum byte to the end of its cycle. ``sel`` is
        always ``0b1111``.
    checksum_error : Out(1)
        One-clock pulse (registered) when a request with a wrong checksum is answered ``'E'``.
    bus_timeout_error : Out(1)
        One-clock pulse (registered) when a bus cycle ends without ``ack`` (reply ``'T'``).

    Parameters
    ----------
    addr_width : int in [1, 16]
    bus_timeout : int in [1, 65536]
        Clocks a bus cycle may last without ``ack``.
    frame_timeout : int in [2, 2**24]
        Clocks of silence after which an incomplete request is dropped.
    """

    def __init__(self, addr_width: int = 16, bus_timeout: int = 64,
                 frame_timeout: int = 30_000):
        self.addr_width = validate_positive(addr_width, "addr_width", maximum=16)
        self.bus_timeout = validate_positive(bus_timeout, "bus_timeout", maximum=1 << 16)
        self.frame_timeout = validate_positive(frame_timeout, "frame_timeout", minimum=2,
                                               maximum=1 << 24)
        super().__init__({
            "rx": In(stream.Signature(8)),
            "tx": Out(stream.Signature(8)),
            "bus": Out(WishboneSignature(addr_width)),
            "checksum_error": Out(1),
            "bus_timeout_error": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        bus = self.bus
        cmd = Signal(8)
        addr = Signal(16)
        data = Signal(32)
        status = Signal(8)
        count = Signal(range(8))          # bytes of the current request received
        total = Signal(8)                 # running sum of the request / reply bytes
        timer = Signal(range(max(self.frame_timeout, self.bus_timeout)))
        index = Signal(range(8))          # reply byte being sent

        m.d.sync += [self.checksum_error.eq(0), self.bus_timeout_error.eq(0)]
        # the request's own registers drive the bus: they hold still from the checksum byte
        # until the cycle ends (a read's data is taken in its ack clock)
        m.d.comb += [bus.sel.eq(0b1111), bus.adr.eq(addr), bus.dat_w.eq(data)]
        byte = self.rx.payload
        last = Mux(cmd == CMD_WRITE, 7, 3)

        with m.FSM():
            with m.State("RECEIVE"):
                m.d.comb += self.rx.ready.eq(1)
                with m.If(self.rx.valid):
                    m.d.sync += timer.eq(0)
                    with m.If(count != 0):
                        m.d.sync += total.eq(total + byte)
                    with m.If(count == 0):
                        with m.If((byte == CMD_WRITE) | (byte == CMD_READ)):
                            m.d.sync += [cmd.eq(byte), total.eq(byte), data.eq(0),
                                         count.eq(1)]
                    with m.Elif(count == last):
                        m.d.sync += count.eq(0)
                        with m.If((total + byte)[:8] == 0):
                            m.d.sync += [bus.cyc.eq(1), bus.stb.eq(1),
                                         bus.we.eq(cmd == CMD_WRITE)]
                            m.next = "BUS"
                        with m.Else():
                            m.d.sync += [status.eq(STATUS_BAD_CHECKSUM), total.eq(0),
                                         index.eq(0), self.checksum_error.eq(1)]
                            m.next = "REPLY"
                    with m.Elif(count < 3):
                        m.d.sync += [addr.eq(Cat(byte, addr[:8])), count.eq(count + 1)]
                    with m.Else():
                        m.d.sync += [data.eq(Cat(byte, data[:24])), count.eq(count + 1)]
                with m.Elif(count != 0):
                    with m.If(timer == self.frame_timeout - 1):
                        m.d.sync += [count.eq(0), timer.eq(0)]
                    with m.Else():
                        m.d.sync += timer.eq(timer + 1)
            with m.State("BUS"):
                with m.If(bus.ack | (timer == self.bus_timeout - 1)):
                    m.d.sync += [bus.cyc.eq(0), bus.stb.eq(0), timer.eq(0), total.eq(0),
                                 index.eq(0)]
                    m.next = "REPLY"
                    with m.If(bus.ack):
                        m.d.sync += status.eq(cmd)
                        with m.If(cmd == CMD_READ):
                            m.d.sync += data.eq(bus.dat_r)
                    with m.Else():
                        m.d.sync += [status.eq(STATUS_BUS_TIMEOUT), data.eq(0),
                                     self.bus_timeout_error.eq(1)]
                with m.Else():
                    m.d.sync += timer.eq(timer + 1)
            with m.State("REPLY"):
                fields = Array([status, addr[8:], addr[:8], data[24:], data[16:24], data[8:16],
                                data[:8], (Const(0, 8) - total)[:8]])
                m.d.comb += [self.tx.valid.eq(1), self.tx.payload.eq(fields[index])]
                with m.If(self.tx.ready):
                    m.d.sync += [total.eq(total + self.tx.payload), index.eq(index + 1)]
                    with m.If(index == 7):
                        m.d.sync += [total.eq(0), timer.eq(0)]
                        m.next = "RECEIVE"
        return m
