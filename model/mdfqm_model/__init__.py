"""Golden model of the mdfqm gateware (NumPy only): predicts every output bit on every clock.

- :mod:`mdfqm_model.update`: the per-update MDFQM algorithm in exact integers (bit-true).
- :mod:`mdfqm_model.bbit`: the b-bit pulse-width-resolution generator (SVPWM / DPWM / MDFQM).
- :mod:`mdfqm_model.clock`: the clock-level models of the core and of the generator.
- :mod:`mdfqm_model.driver`: the gate driver; :mod:`mdfqm_model.top`: the drop-in top.
- :mod:`mdfqm_model.clarke`, :mod:`mdfqm_model.nco`: the alpha-beta front, the demo's sine.

The contract these models implement is :mod:`mdfqm_spec.contract` (prose: ``docs/contract.md``);
the analysis and reports that use them are in ``tools/``.
"""

from .clock import CoreModel, GeneratorModel
from .driver import GateDriverModel
from .top import TopModel
from .update import mdfqm_update

__all__ = ["CoreModel", "GateDriverModel", "GeneratorModel", "TopModel", "mdfqm_update"]
