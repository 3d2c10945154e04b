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


class BridgeModel:
    """:class:`mdfqm_gateware.demo.bridge.UartBridge`:
    ``step(rx_valid, rx_payload, tx_ready, ack, dat_r)``."""

    W, R, E, T = ord("W"), ord("R"), ord("E"), ord("T")

    def __init__(self, addr_width=16, bus_timeout=64, frame_timeout=30_000):
        self.addr_mask = (1 << addr_width) - 1
        self.bus_timeout, self.frame_timeout = bus_timeout, frame_timeout
        self.state = "RECEIVE"
        self.cmd = self.addr = self.data = self.status = 0
        self.count = self.total = self.timer = self.index = 0
        self.cyc = self.we = self.adr = self.dat_w = 0
        self.checksum_error = self.bus_timeout_error = 0

    def reply_byte(self) -> int:
        fields = [self.status, self.addr >> 8, self.addr & 0xFF, *self.data.to_bytes(4, "big"),
                  -self.total & 0xFF]
        return fields[self.index]

    def outputs(self) -> dict:
        replying = self.state == "REPLY"
        return {"rx_ready": int(self.state == "RECEIVE"), "tx_valid": int(replying),
                "tx_payload": self.reply_byte() if replying else 0,
                "cyc": self.cyc, "stb": self.cyc, "we": self.we, "adr": self.adr,
                "dat_w": self.dat_w, "sel": 0b1111, "checksum_error": self.checksum_error,
                "bus_timeout_error": self.bus_timeout_error}

    def step(self, rx_valid=0, rx_payload=0, tx_ready=0, ack=0, dat_r=0) -> dict:
        out = self.outputs()
        self.checksum_error = self.bus_timeout_error = 0
        if self.state == "RECEIVE":
            if rx_valid:
                byte = rx_payload
                self.timer = 0
                last = 7 if self.cmd == self.W else 3
                if self.count == 0:
                    if byte in (self.W, self.R):
                        self.cmd, self.total, self.data, self.count = byte, byte, 0, 1
                elif self.count == last:
                    self.count = 0
                    if (self.total + byte) & 0xFF == 0:
                        self.cyc, self.we = 1, int(self.cmd == self.W)
                        self.adr, self.dat_w = self.addr & self.addr_mask, self.data
                        self.state = "BUS"
                    else:
                        self.status, self.total, self.index = self.E, 0, 0
                        self.checksum_error = 1
                        self.state = "REPLY"
                    return out
                elif self.count < 3:
                    self.total = (self.total + byte) & 0xFF
                    self.addr = ((self.addr << 8) | byte) & 0xFFFF
                    self.count += 1
                else:
                    self.total = (self.total + byte) & 0xFF
                    self.data = ((self.data << 8) | byte) & 0xFFFFFFFF
                    self.count += 1
            elif self.count:
                if self.timer == self.frame_timeout - 1:
                    self.count = self.timer = 0
                else:
                    self.timer += 1
        elif self.state == "BUS":
            if ack or self.timer == self.bus_timeout - 1:
                self.cyc, self.timer, self.total, self.index = 0, 0, 0, 0
                self.state = "REPLY"
                if ack:
                    self.status = self.cmd
                    if self.cmd == self.R:
                        self.data = dat_r
                else:
                    self.status, self.data, self.bus_timeout_error = self.T, 0, 1
            else:
                self.timer += 1
        elif tx_ready:                              # REPLY
            self.total = (self.total + out["tx_payload"]) & 0xFF
            self.index += 1
            if self.index == 8:
                self.index, self.total, self.timer, self.state = 0, 0, 0, "RECEIVE"
        return out
