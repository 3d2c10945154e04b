"""mdfqm gateware: Amaranth 0.5 components of the MDFQM / SVPWM gating-signal generator.

The drop-in components, for a user's own Amaranth design::

    from mdfqm_gateware import MdfqmTop
    top = MdfqmTop(phases=3, width=16)          # core + gate driver + Wishbone registers

- :class:`MdfqmCore`: the MDFQM loop alone (reference stream in, gate state out).
- :class:`GatingSignalGenerator`: the core plus SVPWM / DPWM / b-bit resolutions at run time.
- :class:`GateDriver`: dead time, minimum pulse, fault latch and polarity for N legs.
- :class:`MdfqmTop`: the drop-in IP (core, driver, counters, ADC trigger, register file).
- :class:`InverseClarke`: an alpha-beta front for the three-phase core's reference stream.

How the blocks fit together: ``docs/core.md``. The fixed-point and timing contract every block
follows is ``docs/contract.md`` (its numbers: :mod:`mdfqm_spec.contract`). Verilog of the
drop-in configurations: ``mdfqm-dropin --out DIR`` (:mod:`mdfqm_gateware.dropin`). This package
imports Amaranth and :mod:`mdfqm_spec` only (no NumPy).
"""

from .clarke import InverseClarke
from .core import MdfqmCore
from .driver import GateDriver, LegDriver
from .generator import GatingSignalGenerator
from .top import MdfqmTop

__all__ = [
    "GateDriver",
    "GatingSignalGenerator",
    "InverseClarke",
    "LegDriver",
    "MdfqmCore",
    "MdfqmTop",
]
