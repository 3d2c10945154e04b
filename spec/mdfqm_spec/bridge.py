"""The UART <-> Wishbone bridge protocol (pure Python: used by the host CLI, its simulated
device and the tests; the gateware takes its byte values from here).

Frames (all multi-byte fields big-endian; ``C`` makes the bytes of a frame sum to 0 mod 256)::

    host -> device   write   'W'  A1 A0  D3 D2 D1 D0  C        8 bytes
                     read    'R'  A1 A0  C                     4 bytes
    device -> host   reply   S    A1 A0  D3 D2 D1 D0  C        8 bytes, one per request

``A`` is a Wishbone *word* address (16 bits), ``D`` a 32-bit word. Reply status ``S``:

- ``'W'``: the write completed (``D`` echoes the data written);
- ``'R'``: the read completed (``D`` is the data read);
- ``'E'``: the request's checksum was wrong; no bus cycle ran (``A``/``D`` echo what arrived);
- ``'T'``: no slave acknowledged within the bridge's bus timeout (unmapped address); ``D = 0``.

The device ignores bytes other than ``'W'``/``'R'`` where a frame would start, and drops an
incomplete frame after a silence of ``frame_timeout`` clocks (about 30 byte times on the
boards), so a host recovers from any error by waiting that long and sending the request again.
Only one request is in flight: the device does not read the line while it executes and replies.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "CMD_READ",
    "CMD_WRITE",
    "REPLY_LENGTH",
    "STATUS_BAD_CHECKSUM",
    "STATUS_BUS_TIMEOUT",
    "ProtocolError",
    "Reply",
    "checksum",
    "decode_reply",
    "encode_read",
    "encode_reply",
    "encode_write",
    "request_length",
]

CMD_WRITE = ord("W")
CMD_READ = ord("R")
STATUS_BAD_CHECKSUM = ord("E")
STATUS_BUS_TIMEOUT = ord("T")
STATUSES = (CMD_WRITE, CMD_READ, STATUS_BAD_CHECKSUM, STATUS_BUS_TIMEOUT)
REPLY_LENGTH = 8
ADDR_BITS = 16


class ProtocolError(Exception):
    """A reply that does not follow the protocol (length, checksum, status or echo)."""


def checksum(frame: bytes) -> int:
    """The byte that makes ``frame + checksum`` sum to 0 mod 256."""
    return -sum(frame) & 0xFF


def _check_addr(addr) -> int:
    if isinstance(addr, bool) or not isinstance(addr, int) or not 0 <= addr < 1 << ADDR_BITS:
        raise ValueError(f"addr must be an integer in [0, 0xffff], not {addr!r}")
    return addr


def _check_data(data) -> int:
    if isinstance(data, bool) or not isinstance(data, int) or not 0 <= data < 1 << 32:
        raise ValueError(f"data must be an integer in [0, 0xffffffff], not {data!r}")
    return data


def request_length(cmd: int) -> int:
    """Bytes of a request starting with ``cmd``, the checksum included."""
    return {CMD_WRITE: 8, CMD_READ: 4}[cmd]


def encode_write(addr: int, data: int) -> bytes:
    body = bytes([CMD_WRITE]) + _check_addr(addr).to_bytes(2, "big") + \
        _check_data(data).to_bytes(4, "big")
    return body + bytes([checksum(body)])


def encode_read(addr: int) -> bytes:
    body = bytes([CMD_READ]) + _check_addr(addr).to_bytes(2, "big")
    return body + bytes([checksum(body)])


def encode_reply(status: int, addr: int, data: int) -> bytes:
    body = bytes([status]) + _check_addr(addr).to_bytes(2, "big") + \
        _check_data(data).to_bytes(4, "big")
    return body + bytes([checksum(body)])


@dataclass(frozen=True)
class Reply:
    status: int
    addr: int
    data: int

    @property
    def ok(self) -> bool:
        return self.status in (CMD_WRITE, CMD_READ)


def decode_reply(frame: bytes) -> Reply:
    """Parse one reply; ``ProtocolError`` on a wrong length, checksum or status byte."""
    if len(frame) != REPLY_LENGTH:
        raise ProtocolError(f"reply of {len(frame)} bytes, expected {REPLY_LENGTH}: "
                            f"{bytes(frame).hex(' ')}")
    if sum(frame) & 0xFF:
        raise ProtocolError(f"reply checksum wrong: {bytes(frame).hex(' ')}")
    if frame[0] not in STATUSES:
        raise ProtocolError(f"reply status {frame[0]:#04x} unknown: {bytes(frame).hex(' ')}")
    return Reply(frame[0], int.from_bytes(frame[1:3], "big"), int.from_bytes(frame[3:7], "big"))
