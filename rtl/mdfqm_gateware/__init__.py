"""mdfqm gateware: Amaranth 0.5 components of the MDFQM / SVPWM gating-signal generator.

The fixed-point and timing contract every block follows is :mod:`mdfqm_model.contract`.
"""
