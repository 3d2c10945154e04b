"""Cycle models of the board-demo blocks, written from the timing stated in their docstrings.

Every model has ``outputs()`` (what is visible during the current cycle, a function of its
registers) and ``step(**inputs)`` (returns ``outputs()`` of this cycle, then advances one clock),
like :class:`mdfqm_model.clock.CoreModel`. Pure Python: the cocotb tests generate their stimulus
with the model in the loop, then compare the RTL with it on every clock (harness.check_cycles).
"""

from __future__ import annotations

__all__ = ["UartRxModel", "UartTxModel", "line_bits"]


def line_bits(byte: int, divider: int, stop: int = 1) -> list[int]:
    """Line levels of one 8N1 frame, ``divider`` clocks per bit (start, data LSB first, stop)."""
    bits = [0] + [(byte >> i) & 1 for i in range(8)] + [stop]
    return [b for b in bits for _ in range(divider)]


class UartTxModel:
    """:class:`mdfqm_gateware.demo.uart.UartTx`: ``step(valid, payload)``."""

    def __init__(self, divider: int):
        self.divider = divider
        self.tx, self.count, self.left, self.shreg = 1, 0, 0, 0

    def outputs(self) -> dict:
        ready = int(self.left == 0 or (self.left == 1 and self.count == 0))
        return {"ready": ready, "tx": self.tx, "busy": int(self.left != 0)}

    def step(self, valid: int = 0, payload: int = 0) -> dict:
        out = self.outputs()
        if valid and out["ready"]:
            self.tx, self.shreg, self.left, self.count = 0, payload | 0x100, 10, self.divider - 1
        elif self.left:
            if self.count == 0:
                self.tx = 1 if self.left == 1 else self.shreg & 1
                self.shreg >>= 1
                self.left -= 1
                self.count = self.divider - 1
            else:
                self.count -= 1
        return out


class UartRxModel:
    """:class:`mdfqm_gateware.demo.uart.UartRx`: ``step(rx, ready)``."""

    def __init__(self, divider: int):
        self.divider = divider
        self.sync = [1, 1]             # sync1, rx_s
        self.state, self.count, self.bit, self.shreg = "IDLE", 0, 0, 0
        self.valid, self.payload, self.overrun, self.frame_error = 0, 0, 0, 0

    def outputs(self) -> dict:
        return {"valid": self.valid, "payload": self.payload, "overrun": self.overrun,
                "frame_error": self.frame_error}

    def step(self, rx: int = 1, ready: int = 0) -> dict:
        out = self.outputs()
        d, rx_s = self.divider, self.sync[1]
        self.sync = [rx, self.sync[0]]
        self.overrun = self.frame_error = 0
        new_byte = False
        state = self.state
        if state == "IDLE":
            if not rx_s:
                self.count, self.state = d // 2 - 1, "START"
        elif state == "WAIT_HIGH":
            if rx_s:
                self.state = "IDLE"
        elif self.count:
            self.count -= 1
        elif state == "START":
            self.count, self.bit = d - 1, 0
            self.state = "IDLE" if rx_s else "DATA"
        elif state == "DATA":
            self.count = d - 1
            self.shreg = (self.shreg >> 1) | (rx_s << 7)
            self.bit = (self.bit + 1) % 8
            if self.bit == 0:
                self.state = "STOP"
        elif rx_s:                                   # STOP, sampled high
            new_byte, self.state = True, "IDLE"
        else:                                        # STOP, sampled low
            self.frame_error, self.state = 1, "WAIT_HIGH"
        if new_byte and out["valid"] and not ready:
            self.overrun = 1
        elif new_byte:
            self.valid, self.payload = 1, self.shreg
        elif ready:
            self.valid = 0
        return out
