"""The board demo's gateware: everything between a board's pins and the drop-in top
(``boards/`` holds the thin per-board tops around it).

- :mod:`.uart`: 8N1 UART receiver and transmitter (clocks per bit as a parameter).
- :mod:`.wishbone`: the Wishbone-classic address decoder of the demo's bus.
- :mod:`.bridge`: UART -> Wishbone bridge speaking the frame protocol of :mod:`mdfqm_spec.bridge`.
- :mod:`.arbiter`: two Wishbone masters (the bridge, the bus master) onto one bus.
- :mod:`.bus_master`: writes the top's settings after reset, and what the buttons ask.
- :mod:`.nco`: N-phase sine reference (phase accumulator, quarter/full sine table, amplitude).
- :mod:`.register_bank`: the demo's own registers (NCO, telemetry counters, buttons), built from
  :func:`mdfqm_spec.regmap.demo_window`.
- :mod:`.buttons`: debounced buttons.
- :mod:`.design`: :class:`~.design.DemoDesign`, the whole board-independent demo.
"""

__all__: list[str] = []
