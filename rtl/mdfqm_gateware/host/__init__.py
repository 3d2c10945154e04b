"""Host side of the board demo: the bridge protocol, a client, a simulated device and the CLI
(``python -m mdfqm_gateware.host --help``). Needs pyserial only to talk to real hardware."""
