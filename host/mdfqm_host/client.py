"""A client of the bridge protocol over any serial-like port (pyserial's ``Serial``, or
:class:`~.simdevice.SimulatedDevice`): ``write(bytes)``, ``read(n)`` returning at most ``n``
bytes within the port's timeout, ``reset_input_buffer()``."""

from __future__ import annotations

import time
from collections.abc import Callable

from mdfqm_spec import bridge as proto

__all__ = ["BusError", "Client", "NoReplyError"]

#: silence that makes the device drop a partial frame: 30 byte times at 115200 baud are 2.6 ms
RESYNC_SECONDS = 0.02


class NoReplyError(IOError):
    """No (complete, valid) reply after every retry."""


class BusError(IOError):
    """The device answered ``'T'``: nothing on the chip acknowledged the address."""


class Client:
    """Read and write device registers, retrying on lost or corrupted frames.

    A request is sent, then exactly one 8-byte reply is read. A short, corrupt or mismatched
    reply (wrong status or address echo) counts as a failure: the client waits
    ``RESYNC_SECONDS`` (the device drops any partial frame), flushes its input and sends the
    request again, up to ``retries`` times. A reply ``'E'`` (the device saw a bad checksum) is
    retried the same way; ``'T'`` raises :class:`BusError` at once (it is not a line error).
    """

    def __init__(self, port, retries: int = 3, sleep: Callable[[float], None] = time.sleep):
        self.port, self.retries, self.sleep = port, retries, sleep
        self.stats = {"requests": 0, "retries": 0}

    def _transact(self, frame: bytes, cmd: int, addr: int) -> proto.Reply:
        self.stats["requests"] += 1
        problem = ""
        for attempt in range(self.retries + 1):
            if attempt:
                self.stats["retries"] += 1
                self.sleep(RESYNC_SECONDS)
                self.port.reset_input_buffer()
            self.port.write(frame)
            raw = self.port.read(proto.REPLY_LENGTH)
            try:
                reply = proto.decode_reply(raw)
            except proto.ProtocolError as error:
                problem = str(error)
                continue
            if reply.status == proto.STATUS_BUS_TIMEOUT and reply.addr == addr:
                raise BusError(f"no register at address {addr:#06x}")
            if reply.status != cmd or reply.addr != addr or (
                    cmd == proto.CMD_WRITE and reply.data != int.from_bytes(frame[3:7], "big")):
                problem = f"reply {reply} does not answer {frame.hex(' ')}"
                continue
            return reply
        raise NoReplyError(f"no valid reply after {self.retries + 1} attempts: {problem}")

    def read(self, addr: int) -> int:
        """The 32-bit word at word address ``addr``."""
        return self._transact(proto.encode_read(addr), proto.CMD_READ, addr).data

    def write(self, addr: int, value: int) -> None:
        """Write the 32-bit word ``value`` at word address ``addr``."""
        self._transact(proto.encode_write(addr, value), proto.CMD_WRITE, addr)
