"""The mdfqm IP in a simulated FOC speed drive of a PMSM (``docs/drive.md``).

- :mod:`mdfqm_drive.motors`: the motors and loads; :mod:`mdfqm_drive.plant`: PMSM, shaft,
  inverter with freewheeling diodes, DC bus, advanced from gate edge to gate edge;
- :mod:`mdfqm_drive.modulator`: the drop-in top's pins and ADC trigger from the golden model;
- :mod:`mdfqm_drive.control`: the FOC controller, its tuning rule, the sensors;
- :mod:`mdfqm_drive.loop`: the closed loop; :mod:`mdfqm_drive.study`: operating points as
  independent runs through any ``concurrent.futures`` executor, and their metrics.

It imports :mod:`mdfqm_model` and :mod:`mdfqm_spec`; they never import it.
"""

__all__ = []
