"""Host side of the board demos: a client of the bridge protocol (:mod:`mdfqm_spec.bridge`), the
demo device in physical units, a simulated device and the CLI (``mdfqm-host --help``, or
``python -m mdfqm_host``). Needs pyserial only to talk to real hardware."""

__all__: list[str] = []
