"""The specification of mdfqm, as pure Python (no NumPy, no Amaranth): what the gateware builds and
the golden model predicts.

- :mod:`mdfqm_spec.contract`: the fixed-point and timing contract (widths, bounds, latencies, the
  sorting network, the runtime clamps) and its parameter validators; in prose:
  ``docs/contract.md``.
- :mod:`mdfqm_spec.regmap`: the register maps of the drop-in top and of the board demo.
- :mod:`mdfqm_spec.bridge`: the board demo's UART-to-Wishbone frame protocol.
- :mod:`mdfqm_spec.nco`: the board demo's sine reference (tables, phase offsets).
- :mod:`mdfqm_spec.validate`: generic parameter validators.
"""

from .contract import Contract, loop_latency, resolution_latency

__all__ = ["Contract", "loop_latency", "resolution_latency"]
