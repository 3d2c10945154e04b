"""The demo's own bus master: writes the drop-in top's demo settings after reset, then does
what the enable and fault-clear buttons ask (the top's registers are reachable only by bus).

Timing: every access raises ``cyc``/``stb`` (registered) and holds them until the clock with
``ack``; they drop in the next clock. From the idle state, in priority order: the next write
of ``init`` (in order, once after reset), an enable toggle (read ``ctrl``, one idle clock,
write it back with ``enable_mask`` flipped), a fault clear (write ``clear_value`` to
``clear_addr``). A button pulse is remembered until its access starts.
"""

from amaranth import Array, Const, Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.validate import validate_positive

from .wishbone import WishboneSignature

__all__ = ["BusSequencer"]


class BusSequencer(wiring.Component):
    """A small Wishbone master: initial writes, then read-modify-write and write on request.

    Ports
    -----
    bus : Out(WishboneSignature(addr_width))
        Master port (``sel`` always ``0b1111``).
    enable_toggle : In(1)
        Pulse: flip ``enable_mask`` in the register at ``ctrl_addr``.
    fault_clear : In(1)
        Pulse: write ``clear_value`` to ``clear_addr``.
    busy : Out(1)
        Initial writes not finished, or an access in progress.

    Parameters
    ----------
    addr_width : int
    init : sequence of (addr, data)
        Writes made once after reset.
    ctrl_addr, enable_mask, clear_addr, clear_value : int
    ctrl_width : int in [1, 32]
        Bits of the register at ``ctrl_addr`` that an enable toggle reads and writes back (it
        writes the bits above as 0: they must read 0), so that no flop holds a bit that is
        always 0. ``enable_mask`` must fit in them.
    """

    def __init__(self, addr_width: int, init, ctrl_addr: int, enable_mask: int,
                 clear_addr: int, clear_value: int, ctrl_width: int = 32):
        self.addr_width = validate_positive(addr_width, "addr_width", maximum=30)
        top = (1 << addr_width) - 1
        for name, value in (("ctrl_addr", ctrl_addr), ("clear_addr", clear_addr)):
            validate_positive(value, name, minimum=0, maximum=top)
        for name, value in (("enable_mask", enable_mask), ("clear_value", clear_value)):
            validate_positive(value, name, minimum=0, maximum=0xFFFF_FFFF)
        self.ctrl_width = validate_positive(ctrl_width, "ctrl_width", maximum=32)
        if enable_mask >> ctrl_width:
            raise ValueError(f"enable_mask {enable_mask:#x} must fit in ctrl_width = "
                             f"{ctrl_width} bits")
        for i, entry in enumerate(init):
            if not (isinstance(entry, tuple) and len(entry) == 2):
                raise ValueError(f"init[{i}] must be an (addr, data) tuple, not {entry!r}")
            validate_positive(entry[0], f"init[{i}] addr", minimum=0, maximum=top)
            validate_positive(entry[1], f"init[{i}] data", minimum=0, maximum=0xFFFF_FFFF)
        self.init = tuple(init)
        self.ctrl_addr, self.enable_mask = ctrl_addr, enable_mask
        self.clear_addr, self.clear_value = clear_addr, clear_value
        super().__init__({
            "bus": Out(WishboneSignature(addr_width)),
            "enable_toggle": In(1),
            "fault_clear": In(1),
            "busy": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        bus = self.bus
        count = len(self.init)
        index = Signal(range(count + 1))
        toggle, clear = Signal(), Signal()
        ctrl = Signal(self.ctrl_width)
        init_adr = Array(Const(a, self.addr_width) for a, _ in self.init) if count else None
        init_dat = Array(Const(d, 32) for _, d in self.init) if count else None
        taken_toggle, taken_clear = Signal(), Signal()
        m.d.comb += bus.sel.eq(0b1111)
        m.d.sync += [toggle.eq((toggle & ~taken_toggle) | self.enable_toggle),
                     clear.eq((clear & ~taken_clear) | self.fault_clear)]

        def access(we, adr, dat=0):
            m.d.sync += [bus.cyc.eq(1), bus.stb.eq(1), bus.we.eq(we), bus.adr.eq(adr),
                         bus.dat_w.eq(dat)]

        with m.FSM():
            with m.State("IDLE"):
                m.d.comb += self.busy.eq(index != count)
                if count:
                    with m.If(index != count):
                        access(1, init_adr[index], init_dat[index])
                        m.d.sync += index.eq(index + 1)
                        m.next = "WRITE"
                with m.If(index == count):
                    with m.If(toggle):
                        m.d.comb += taken_toggle.eq(1)
                        access(0, self.ctrl_addr)
                        m.next = "READ_CTRL"
                    with m.Elif(clear):
                        m.d.comb += taken_clear.eq(1)
                        access(1, self.clear_addr, self.clear_value)
                        m.next = "WRITE"
            with m.State("READ_CTRL"):
                m.d.comb += self.busy.eq(1)
                with m.If(bus.ack):
                    m.d.sync += [bus.cyc.eq(0), bus.stb.eq(0),
                                 ctrl.eq(bus.dat_r[:self.ctrl_width] ^ self.enable_mask)]
                    m.next = "WRITE_CTRL"
            with m.State("WRITE_CTRL"):
                m.d.comb += self.busy.eq(1)
                access(1, self.ctrl_addr, ctrl)
                m.next = "WRITE"
            with m.State("WRITE"):
                m.d.comb += self.busy.eq(1)
                with m.If(bus.ack):
                    m.d.sync += [bus.cyc.eq(0), bus.stb.eq(0)]
                    m.next = "IDLE"
        return m
