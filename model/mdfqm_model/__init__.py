"""Golden model of the MDFQM gateware (pure NumPy).

- :mod:`mdfqm_model.contract`: the fixed-point and clock-timing contract (widths, bounds, latency).
- :mod:`mdfqm_model.update`: the per-update algorithm in exact integers (bit-true).
- :mod:`mdfqm_model.clock`: the clock-level model of the core (:class:`CoreModel`).
- :mod:`mdfqm_model.bbit`: the b-bit pulse-width-resolution generator (SVPWM / DPWM / MDFQM).
- :mod:`mdfqm_model.analysis`: switching-count and distortion analysis, the report CLI
  (``python -m mdfqm_model.analysis``); it alone may import matplotlib.
"""

from .contract import ALL_OFF, FEWEST_TRANSITIONS, RULES, ZERO_POLICIES, Contract, loop_latency

__all__ = [
    "ALL_OFF",
    "FEWEST_TRANSITIONS",
    "RULES",
    "ZERO_POLICIES",
    "Contract",
    "loop_latency",
]
