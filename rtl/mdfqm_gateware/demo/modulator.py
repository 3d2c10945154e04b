"""The fallback modulator of the demo: MdfqmCore + GateDriver behind a thin register block
(:func:`~.regmap.modulator_window`), used while the drop-in top is not in the tree."""

from amaranth import Cat, Module, Mux, signed
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out, connect

from ..core import MdfqmCore
from ..driver import GateDriver
from .registers import RegisterBank
from .regmap import CTRL_ENABLE, modulator_window
from .wishbone import WishboneSignature

__all__ = ["CoreModulator"]


class CoreModulator(wiring.Component):
    """MDFQM core, dead-time gate driver and their registers.

    ``CTRL.ENABLE`` is cleared while the fault latch is set, so gates resume after a fault
    only when the fault is cleared *and* the modulator is enabled again.

    Ports
    -----
    bus : In(WishboneSignature(4))
        The modulator window (:func:`~.regmap.modulator_window`).
    ref : In(stream.Signature(ArrayLayout(signed(width), phases)))
        Phase references (the core's ``ref``).
    fault_in : In(1)
        Asynchronous active-high fault (synchronised in the driver).
    enable_toggle : In(1)
        Toggle ``CTRL.ENABLE`` (a button); a bus write in the same clock wins.
    fault_clear : In(1)
        Clear the fault latch (a button), like a write to ``FAULT_CLEAR``.
    upper, lower : Out(phases)
        Gates, active high, registered.
    event : Out(phases)
        One-clock strobe per leg: a switch of that leg turned on.
    active, fault, fault_input : Out(1)
        The driver's taken enable, fault latch and synchronised fault input.

    Parameters
    ----------
    phases, width : int
        As :class:`~mdfqm_gateware.core.MdfqmCore`.
    dead_min : int
        Dead-time floor in clocks (:class:`~mdfqm_gateware.driver.GateDriver`).
    time_width : int
        Width of the dead-time and minimum-pulse counters (the driver's; 10 bits keep its
        comparisons short enough for 24 MHz on an iCE40UP5K).
    init : dict
        Reset values of the ``rw`` registers.
    """

    def __init__(self, phases: int, width: int, dead_min: int, time_width: int = 10,
                 init=None):
        self.core = MdfqmCore(phases, width)
        self.driver = GateDriver(phases, dead_min, time_width)
        self.regs = RegisterBank(modulator_window(time_width), init=init, settable=("CTRL",))
        self.phases, self.width, self.dead_min = phases, width, dead_min
        super().__init__({
            "bus": In(WishboneSignature(4)),
            "ref": In(stream.Signature(data.ArrayLayout(signed(width), phases))),
            "fault_in": In(1),
            "enable_toggle": In(1),
            "fault_clear": In(1),
            "upper": Out(phases),
            "lower": Out(phases),
            "event": Out(phases),
            "active": Out(1),
            "fault": Out(1),
            "fault_input": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        core, driver, regs = self.core, self.driver, self.regs
        m.submodules.core, m.submodules.driver, m.submodules.regs = core, driver, regs
        connect(m, wiring.flipped(self.bus), regs.bus)
        connect(m, wiring.flipped(self.ref), core.ref)
        m.d.comb += [
            core.period.eq(regs.PERIOD),
            core.osr.eq(regs.OSR),
            core.zero_policy.eq(regs.CTRL[1]),
            core.sync_in.eq(0),
            driver.h.eq(core.h),
            driver.update.eq(core.update),
            driver.enable.eq(regs.CTRL[0]),
            driver.dead.eq(regs.DEAD),
            driver.min_pulse.eq(regs.MIN_PULSE),
            driver.fault_in.eq(self.fault_in),
            driver.fault_clear.eq(regs.FAULT_CLEAR | self.fault_clear),
            regs.CTRL_set.eq(driver.fault | self.enable_toggle),
            regs.CTRL_value.eq(Mux(driver.fault, regs.CTRL & ~CTRL_ENABLE,
                                   regs.CTRL ^ CTRL_ENABLE)),
            regs.STATUS.eq(Cat(driver.active, driver.fault, driver.fault_input, core.saturated,
                               core.period_clamped)),
            regs.DEAD_MIN.eq(self.dead_min),
            self.upper.eq(driver.upper),
            self.lower.eq(driver.lower),
            self.event.eq(driver.event),
            self.active.eq(driver.active),
            self.fault.eq(driver.fault),
            self.fault_input.eq(driver.fault_input),
        ]
        return m

