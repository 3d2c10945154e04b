"""Measurement and report scripts: Fmax/area (`perf`), the golden model's analysis (`analysis`),
the gateware mode table (`gateware_report`), the board table (`board_report`) and the top's
timing diagram (`timing_diagram`). Run from the repository root (`make perf`, `make report`)."""

__all__: list[str] = []
