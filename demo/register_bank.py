"""A Wishbone-classic register bank built from a :class:`mdfqm_spec.regmap.Window`.

Timing: a request seen in cycle ``c`` (``cyc & stb & ~ack``) is acknowledged in ``c + 1`` for one
clock; a write updates the register (or pulses the strobe) so that it is visible in ``c + 1``;
a read returns in ``c + 1`` the value of cycle ``c``. Byte selects are ignored (the bridge always
writes whole words). An ``RW`` register listed in ``settable`` can also be loaded by logic
(``<name>_set``/``<name>_value``) in a cycle without a bus write to it; the bus wins.
"""

from amaranth import Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.regmap import Window

from .wishbone import WishboneSignature

__all__ = ["RegisterBank"]


class RegisterBank(wiring.Component):
    """Registers of one address window on a Wishbone-classic slave port.

    Ports
    -----
    bus : In(WishboneSignature(window.addr_width))
        Slave port (one-clock ``ack`` the clock after the request).
    <name> : Out(width) for ``RW``; In(width) for ``R``; Out(1) for ``W`` (a strobe)
        The register value (registered, initial value from ``init``), the value to read, or a
        one-clock pulse the clock after a write.
    <name>_set : In(1), <name>_value : In(width)
        For the ``RW`` registers in ``settable``: load ``<name>_value`` when ``<name>_set`` is
        high and the bus does not write the register in the same clock.

    Parameters
    ----------
    window : Window
    init : dict of name -> int
        Reset values of ``RW`` registers (default 0).
    settable : tuple of names
    """

    def __init__(self, window: Window, init=None, settable=()):
        init = dict(init or {})
        names = {reg.name: reg for reg in window.regs}
        for name in [*init, *settable]:
            if name not in names or names[name].access != "RW":
                raise ValueError(f"{name!r} is not an RW register of the {window.name} window")
        members = {"bus": In(WishboneSignature(window.addr_width))}
        for reg in window.regs:
            if reg.access == "RW":
                value = init.get(reg.name, 0)
                if not 0 <= value < 1 << reg.width:
                    raise ValueError(f"init[{reg.name!r}] must fit in {reg.width} bits, "
                                     f"not {value!r}")
                members[reg.name] = Out(reg.width, init=value)
                if reg.name in settable:
                    members[f"{reg.name}_set"] = In(1)
                    members[f"{reg.name}_value"] = In(reg.width)
            elif reg.access == "R":
                members[reg.name] = In(reg.width)
            else:
                members[reg.name] = Out(1)
        self.window, self.init, self.settable = window, init, tuple(settable)
        super().__init__(members)

    def elaborate(self, platform):
        m = Module()
        bus = self.bus
        request = bus.cyc & bus.stb & ~bus.ack
        m.d.sync += bus.ack.eq(request)
        read = Signal(32)
        for reg in self.window.regs:
            port = getattr(self, reg.name)
            hit = request & (bus.adr == reg.offset)
            if reg.access == "W":
                m.d.sync += port.eq(hit & bus.we)
                continue
            with m.If(bus.adr == reg.offset):
                m.d.comb += read.eq(port)
            if reg.access == "RW":
                with m.If(hit & bus.we):
                    m.d.sync += port.eq(bus.dat_w[:reg.width])
                if reg.name in self.settable:
                    with m.Elif(getattr(self, f"{reg.name}_set")):
                        m.d.sync += port.eq(getattr(self, f"{reg.name}_value"))
        with m.If(request):
            m.d.sync += bus.dat_r.eq(read)
        return m
