"""A simulated demo device behind a serial-like interface, for the CLI without hardware
(``--port sim://``) and for the host's tests.

Bytes follow the bridge's rules (:mod:`demo.bridge`): a frame starts only with
``'W'``/``'R'``, a partial frame is dropped after ``frame_timeout`` seconds of silence, a bad
checksum is answered ``'E'``, an address outside the windows ``'T'``. Registers follow the
register maps (the drop-in top's and the demo's); the counters advance
with the (simulated) time at a plausible rate while enabled: they are *not* a model of MDFQM.
Faults can be injected on the line (``inject``).
"""

from __future__ import annotations

import time
from collections import deque

from mdfqm_spec import bridge as proto
from mdfqm_spec import regmap as top
from mdfqm_spec.contract import latch_mode, loop_latency
from mdfqm_spec.regmap import ID_VALUE, INFO_TOP, TOP_BASE, demo_window, info_word

from .device import TOP_MAP

__all__ = ["INJECTIONS", "SimulatedDevice"]

#: what :meth:`SimulatedDevice.inject` can do to the next reply or request
INJECTIONS = ("drop_reply", "corrupt_reply", "truncate_reply", "corrupt_request")


class SimulatedDevice:
    """Serial-port stand-in: ``write``, ``read``, ``reset_input_buffer``, ``in_waiting``.

    Parameters
    ----------
    clk_hz, phases, width, acc_bits : the device's configuration (INFO, CLK_HZ)
    max_bits : the top's (its INFO; 0 the MDFQM-only top). MODULATION reads back the clamped
        request at once (the gateware takes it at the next update start).
    clock : callable
        Seconds, monotonic (a fake clock in tests).
    frame_timeout : float
        Silence in seconds after which a partial request is dropped.
    """

    def __init__(self, clk_hz=18_000_000, phases=3, width=16, acc_bits=32,
                 clock=time.monotonic, frame_timeout=0.003, max_bits=8, watchdog=True):
        self.clk_hz, self.phases, self.width, self.acc_bits = clk_hz, phases, width, acc_bits
        self.clock, self.frame_timeout = clock, frame_timeout
        self.map = TOP_MAP
        self.demo = demo_window(phases, width, acc_bits)
        self.out = bytearray()
        self.partial = bytearray()
        self.last_byte = None
        self.injected = deque()
        self.log = []                         # (cmd, addr, data, status) of executed requests
        m = self.map
        latency = loop_latency(phases, "largest_duty")
        self.max_bits, self.watchdog = max_bits, watchdog
        self.regs = {m.ctrl: 0, m.period: latency, m.osr: 1, m.dead: 64, m.min_pulse: 0,
                     m.dead_min: 64, TOP_BASE + top.ID: top.ID_VALUE, m.modulation: 0,
                     m.watchdog: 0, m.watchdog_trips: 0,
                     m.info: info_word(phases, width, "largest_duty", False, False, latency,
                                       max_bits, asc=True, watchdog=watchdog)}
        self.fault = False
        self.demo_regs = {"NCO_FREQ": round(50 * (1 << acc_bits) / clk_hz),
                          "NCO_AMP": 1 << (width - 3)}
        self.start = clock()
        self.live = [0.0] * phases            # switching events, advanced with the time
        self.snapshot = 0                      # the clock count at the last SNAPSHOT
        self.last_advance = self.start

    # ------------------------------------------------------------------ serial interface
    def write(self, data: bytes) -> int:
        for byte in bytes(data):
            self._byte(byte)
        return len(data)

    def read(self, size: int = 1) -> bytes:
        chunk, self.out = bytes(self.out[:size]), self.out[size:]
        return chunk

    @property
    def in_waiting(self) -> int:
        return len(self.out)

    def reset_input_buffer(self) -> None:
        self.out.clear()

    def close(self) -> None:
        pass

    def inject(self, what: str) -> None:
        """Damage the next request or reply: one of :data:`INJECTIONS`."""
        if what not in INJECTIONS:
            raise ValueError(f"inject: {what!r} is not one of {INJECTIONS}")
        self.injected.append(what)

    # ------------------------------------------------------------------ the bridge
    def _byte(self, byte: int) -> None:
        now = self.clock()
        if self.partial and self.last_byte is not None and \
                now - self.last_byte >= self.frame_timeout:
            self.partial.clear()
        self.last_byte = now
        if not self.partial and byte not in (proto.CMD_WRITE, proto.CMD_READ):
            return
        self.partial.append(byte)
        if len(self.partial) < proto.request_length(self.partial[0]):
            return
        frame, self.partial = bytes(self.partial), bytearray()
        if self.injected and self.injected[0] == "corrupt_request":
            self.injected.popleft()
            frame = frame[:-1] + bytes([frame[-1] ^ 0x01])
        cmd, addr = frame[0], int.from_bytes(frame[1:3], "big")
        data = int.from_bytes(frame[3:7], "big") if cmd == proto.CMD_WRITE else 0
        if sum(frame) & 0xFF:
            status = proto.STATUS_BAD_CHECKSUM
        else:
            result = self._access(cmd, addr, data)
            status, data = (proto.STATUS_BUS_TIMEOUT, 0) if result is None else (cmd, result)
        self.log.append((cmd, addr, data, status))
        reply = proto.encode_reply(status, addr, data)
        what = self.injected.popleft() if self.injected else None
        if what == "drop_reply":
            return
        if what == "corrupt_reply":
            reply = reply[:3] + bytes([reply[3] ^ 0x10]) + reply[4:]
        if what == "truncate_reply":
            reply = reply[:5]
        self.out += reply

    # ------------------------------------------------------------------ registers
    def _advance(self) -> int:
        """Advance the counters to now; returns the clock count."""
        now = self.clock()
        m = self.map
        if self.regs[m.ctrl] & m.ctrl_enable and not self.fault:
            update_hz = self.clk_hz / max(self.regs[m.period], 8)
            rate = 2 * 0.3 * update_hz                       # turn-ons per second, plausible
            self.live = [e + rate * (now - self.last_advance) for e in self.live]
        self.last_advance = now
        return round((now - self.start) * self.clk_hz) & 0xFFFFFFFF

    def _access(self, cmd: int, addr: int, data: int):
        """The data of a read / the echo of a write, or None when no register answers."""
        write = cmd == proto.CMD_WRITE
        if self.demo.base <= addr < self.demo.base + (1 << self.demo.addr_width):
            return self._demo(addr - self.demo.base, write, data)
        if TOP_BASE <= addr < TOP_BASE + (1 << top.ADDR_WIDTH):
            return self._modulator(addr, write, data)
        return None

    def _demo(self, offset: int, write: bool, data: int) -> int:
        reg = next((r for r in self.demo.regs if r.offset == offset), None)
        if reg is None:
            return data if write else 0
        if write:
            if reg.access == "RW":
                self.demo_regs[reg.name] = data & ((1 << reg.width) - 1)
            elif reg.name == "SNAPSHOT":
                self.snapshot = self._advance()
            return data
        if reg.access == "RW":
            return self.demo_regs[reg.name]
        values = {"ID": ID_VALUE, "CLK_HZ": self.clk_hz, "CYCLES": self.snapshot,
                  "INFO": self.phases | self.width << 8 | self.acc_bits << 16
                  | INFO_TOP,
                  "NCO_PHASE": (self._advance() * self.demo_regs["NCO_FREQ"])
                  & ((1 << self.acc_bits) - 1),
                  "BUTTONS": 0}
        return values.get(reg.name, 0)

    def _modulator(self, addr: int, write: bool, data: int) -> int:
        m = self.map
        self._advance()
        if write:
            if addr == m.fault_clear[0] and data & m.fault_clear[1]:
                self.fault = False
            elif addr == m.modulation:
                mode, bits, _ = latch_mode(
                    (data & top.MODULATION_MODE) >> top.MODULATION_MODE_SHIFT,
                    (data & top.MODULATION_BITS) >> top.MODULATION_BITS_SHIFT, self.max_bits)
                self.regs[addr] = (mode << top.MODULATION_MODE_SHIFT
                                   | bits << top.MODULATION_BITS_SHIFT)
            elif addr == m.watchdog:
                self.regs[addr] = min(data, 0xFFFF) * self.watchdog
            elif addr in (m.ctrl, m.period, m.osr, m.dead, m.min_pulse):
                limit = {m.ctrl: 3, m.period: 0xFFFF, m.osr: 0xFF}.get(addr, m.time_max)
                value = min(data, limit) if addr != m.ctrl else data & 3
                if addr == m.dead:
                    value = max(value, self.regs[m.dead_min])
                self.regs[addr] = value
            return data
        if m.events <= addr < m.events + self.phases:
            return round(self.live[addr - m.events]) & 0xFFFFFFFF
        if addr == m.status:
            bits = m.status_bits
            active = self.regs[m.ctrl] & m.ctrl_enable and not self.fault
            return (bits["active"] if active else 0) | (bits["fault"] if self.fault else 0)
        return self.regs.get(addr, 0)
