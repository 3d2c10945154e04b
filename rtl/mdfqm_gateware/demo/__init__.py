"""The shared board demo: everything between a board's pins and the MDFQM drop-in top.

- :mod:`.uart`: 8N1 UART receiver and transmitter (clocks per bit as a parameter).
- :mod:`.wishbone`: the Wishbone-classic signature used on chip, and an address decoder.
- :mod:`.bridge`: UART -> Wishbone bridge speaking the binary protocol of
  :mod:`mdfqm_gateware.host.protocol`.
- :mod:`.nco`: N-phase sine reference (phase accumulator, quarter/full sine table, amplitude).
- :mod:`.registers`: the demo register block (NCO, telemetry counters, status).
- :mod:`.buttons`: debounced buttons mapped to register actions.
- :mod:`.design`: :class:`~.design.DemoDesign`, the whole board-independent demo.

This package's ``__init__`` imports nothing, so the host CLI can use the protocol constants
without Amaranth.
"""
