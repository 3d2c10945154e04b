"""The project's cycle-level bus masters of the drop-in top's two register fronts
(docs/top.md, "Register bus"): one Wishbone-classic master and one AXI4-Lite master, which every
test of the project drives the register file with (tb/test_top.py's bench, the top's vector
stimulus, the pins report).

Both take accesses from a queue, in order, and play them on the bus clock by clock: each clock
:meth:`inputs` gives the bus inputs of the clock and :meth:`observe` takes the front's outputs
of the same clock. An access is an :class:`Access` (a plain ``(address, write, data)`` tuple is
one too). Its ``aim``, if any, holds the access back until the moment it names: the Wishbone
master starts it (``cyc`` and ``stb`` together) only in a clock for which ``aim.now()`` is true
(the request clock is the access, docs/top.md), the AXI4-Lite master raises its AW and W only in
a clock for which ``aim.next()`` is true and keeps ``bready`` high until its response, so that
the write is issued in the next clock. Meanwhile the accesses queued behind it go first (a
firmware waiting for an event still serves the bus). Whether the access met its moment is for
the caller to measure.

How each master meets the rules the fronts must stand (docs/robustness.md, the Wishbone and
AXI4-Lite rows) is its :class:`WishbonePolicy` / :class:`AxiLitePolicy`: ``cyc`` raised before
``stb``, ``cyc`` or ``stb`` alone while idle, random ``sel``; AW and W each after its own delay
(either first, or together), ``bready`` and ``rready`` held low at random, the next write's AW/W
while the last response waits, random ``wstrb`` and ``prot``.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any, NamedTuple

#: (cyc, stb) of an idle Wishbone master clock: neither, ``cyc`` alone (a master holding the
#: bus), ``stb`` alone (a strobe shared with another slave): never both, so never a request
IDLE_WISHBONE = ((0, 0), (0, 0), (1, 0), (0, 1))


class Access(NamedTuple):
    """One register access: word ``address``, ``write`` 1 or 0, the written ``data`` (a
    read's is driven on the bus as it is, and ignored); ``aim`` an object with ``now()`` and
    ``next()`` (see the module docstring) or None; ``tag`` whatever the caller wants back."""

    address: int
    write: int
    data: int
    aim: Any = None
    tag: Any = None


class Done(NamedTuple):
    """An access that completed in this clock and the word a read returned (None: a write)."""

    access: Access
    value: int | None


@dataclass(frozen=True)
class WishbonePolicy:
    """How the Wishbone master paces its accesses: ``leads``, the clocks ``cyc`` is raised
    before ``stb`` (drawn per access); ``gaps``, the idle clocks after an access; ``idle``, the
    (cyc, stb) pairs of idle clocks; ``sel``, the byte lanes (accepted and ignored)."""

    leads: tuple[int, ...] = (0, 0, 0, 1, 2)
    gaps: tuple[int, ...] = (0, 0, 1, 2)
    idle: tuple[tuple[int, int], ...] = IDLE_WISHBONE
    sel: tuple[int, ...] = (0xF, 0xF, 0x1, 0x0)


@dataclass(frozen=True)
class AxiLitePolicy:
    """How the AXI4-Lite master paces its accesses: ``waits``, the clocks before each of AW,
    W, AR is raised (drawn per channel and access: either of AW and W may come first, or both
    together); ``gaps``, the clocks before the next access is started; ``bready`` and
    ``rready``, the chance of taking a response in a clock; ``wstrb`` (ignored by the front);
    ``depth``, accesses of a kind in flight (the next one's address while a response waits)."""

    waits: tuple[int, ...] = (0, 0, 0, 1, 3)
    gaps: tuple[int, ...] = (0, 0, 0, 1, 2)
    bready: float = 0.6
    rready: float = 0.6
    wstrb: tuple[int, ...] = (0xF, 0xF, 0x3, 0x0)
    depth: int = 2


#: queued accesses a master looks at for one that may go (an aimed one waits for its moment)
LOOK = 4


def _access(op) -> Access:
    return op if isinstance(op, Access) else Access(*op)


def _take(ops: deque, due, idle: bool, startable=lambda access: True):
    """The first of the queued ``ops`` (of the first :data:`LOOK`) that may start now: an
    unaimed one once the master's idle gap is over (``idle``), an aimed one when ``due`` (its
    moment does not wait for the gap); an unaimed one that cannot start (``startable``) stops
    the search, so that unaimed accesses keep their order. Removed from ``ops``."""
    for index, op in enumerate(list(ops)[:LOOK]):
        access = _access(op)
        if access.aim is not None and not due(access.aim):
            continue
        if (access.aim is None and not idle) or not startable(access):
            return None
        del ops[index]
        return access
    return None


class WishboneMaster:
    """One access at a time: ``cyc`` raised, ``stb`` with it or ``lead`` clocks later (and, for
    an aimed access, not before its moment), both held until ``ack``; idle clocks between, with
    ``cyc`` or ``stb`` alone at random (never both) and random address, data and ``sel``."""

    def __init__(self, rng, policy: WishbonePolicy | None = None):
        self.rng, self.policy = rng, policy or WishbonePolicy()
        self.current: Access | None = None
        self.gap = self.lead = 0
        #: the accesses that completed in the last observed clock, with their read values
        self.completed: list[Done] = []

    def busy(self) -> bool:
        return self.current is not None

    def inputs(self, ops: deque) -> dict:
        rng, policy = self.rng, self.policy
        if self.current is None and ops:
            self.current = _take(ops, lambda aim: aim.now(), self.gap == 0)
            if self.current is not None:
                self.lead = 0 if self.current.aim is not None else rng.choice(policy.leads)
        op = self.current
        if op is None:
            adr, we, dat = rng.randrange(64), rng.randint(0, 1), rng.getrandbits(32)
            cyc, stb = rng.choice(policy.idle)
        else:
            cyc, stb = 1, int(self.lead == 0)
            self.lead = max(0, self.lead - 1)
            adr, we, dat = op.address, op.write, op.data
        return {"wb_cyc": cyc, "wb_stb": stb, "wb_we": we, "wb_adr": adr, "wb_dat_w": dat,
                "wb_sel": rng.choice(policy.sel)}

    def observe(self, bus: dict, out: dict):
        """The read data of an access that completed this clock (``[value]``, ``[None]`` for
        a write), None when none did; :attr:`completed` names the access."""
        self.completed = []
        if self.current is not None and out["wb_ack"]:
            value = None if self.current.write else out["wb_dat_r"]
            self.completed = [Done(self.current, value)]
            self.current, self.gap = None, self.rng.choice(self.policy.gaps)
            return [value]
        if self.current is None and self.gap:
            self.gap -= 1
        return None

    def issued_write(self) -> Access | None:
        """The write the front issues in this clock, when it issues one."""
        return self.current

    def abort(self) -> None:
        self.current, self.gap = None, 0


class AxiLiteMaster:
    """Accesses started in queue order, a write's AW and W (and a read's AR) raised after their
    own random delays and held, with their payload, until taken; the next write's AW/W (read's
    AR) may start while the previous one waits for its response, so responses meet
    back-pressure with the next access ready; ``bready`` and ``rready`` at random (held high
    while an aimed write is in flight, so that it is issued the clock after its AW and W);
    random payloads on idle channels."""

    def __init__(self, rng, policy: AxiLitePolicy | None = None):
        self.rng, self.policy = rng, policy or AxiLitePolicy()
        self.writes: deque = deque()
        self.reads: deque = deque()
        self.gap = 0
        self.current: dict = {"aw": None, "w": None, "ar": None}
        self.raised: dict = {"aw": 0, "w": 0, "ar": 0}
        self.completed: list[Done] = []

    def busy(self) -> bool:
        return bool(self.writes or self.reads)

    @staticmethod
    def _addressing(ops, channels):
        """The op of ``ops`` still in its address/data phase, if any (the newest)."""
        return ops[-1] if ops and not set(channels) <= ops[-1]["done"] else None

    @staticmethod
    def _raised(op, channel) -> int:
        return int(op is not None and channel not in op["done"] and op["wait"][channel] <= 0)

    def _free(self, access) -> bool:
        """Whether ``access`` can start: its channels free and room in flight; an aimed write
        only with no write in flight (the holding registers and B free, so that it is issued
        the clock after its AW and W)."""
        if access.write and access.aim is not None:
            return not self.writes
        queue, channels = ((self.writes, ("aw", "w")) if access.write
                           else (self.reads, ("ar",)))
        return self._addressing(queue, channels) is None and len(queue) < self.policy.depth

    def inputs(self, ops: deque) -> dict:
        rng, policy = self.rng, self.policy
        while ops:
            access = _take(ops, lambda aim: aim.next(), self.gap == 0, self._free)
            if access is None:
                break
            channels = ("aw", "w") if access.write else ("ar",)
            adr = access.address * 4 + rng.randrange(4)
            waits = {ch: 0 if access.aim is not None else rng.choice(policy.waits)
                     for ch in channels}
            (self.writes if access.write else self.reads).append(
                {"access": access, "adr": adr, "done": set(), "wait": waits})
        w = self._addressing(self.writes, ("aw", "w"))
        r = self._addressing(self.reads, ("ar",))
        self.current = {"aw": w, "w": w, "ar": r}
        self.raised = {ch: self._raised(op, ch) for ch, op in self.current.items()}
        aimed = any(op["access"].aim is not None for op in self.writes)
        return {
            "s_axi_awvalid": self.raised["aw"], "s_axi_wvalid": self.raised["w"],
            "s_axi_arvalid": self.raised["ar"],
            "s_axi_awaddr": w["adr"] if w else rng.randrange(256),
            "s_axi_wdata": w["access"].data if w else rng.getrandbits(32),
            "s_axi_araddr": r["adr"] if r else rng.randrange(256),
            "s_axi_wstrb": rng.choice(policy.wstrb), "s_axi_awprot": rng.randrange(8),
            "s_axi_arprot": rng.randrange(8),
            "s_axi_bready": int(aimed or rng.random() < policy.bready),
            "s_axi_rready": int(rng.random() < policy.rready),
        }

    def observe(self, bus: dict, out: dict):
        """The read data of the access that completed this cycle: ``[value]`` for a read,
        ``[None]`` for a write, None when nothing completed (B and R together: the read's);
        :attr:`completed` names every access that completed (both when B and R did)."""
        for ch, op in self.current.items():
            if op is None or ch in op["done"]:
                continue
            if self.raised[ch] and out[f"s_axi_{ch}ready"]:
                op["done"].add(ch)
            elif not self.raised[ch]:
                op["wait"][ch] -= 1
        done = None
        self.completed = []
        if out["s_axi_bvalid"] and bus["s_axi_bready"]:
            assert self.writes and {"aw", "w"} <= self.writes[0]["done"], "B without a write"
            self.completed.append(Done(self.writes.popleft()["access"], None))
            done = [None]
        if out["s_axi_rvalid"] and bus["s_axi_rready"]:
            assert self.reads and "ar" in self.reads[0]["done"], "R without a read"
            self.completed.append(Done(self.reads.popleft()["access"], out["s_axi_rdata"]))
            done = [out["s_axi_rdata"]]
        if done is not None:
            self.gap = self.rng.choice(self.policy.gaps)
        elif self.gap:
            self.gap -= 1
        return done

    def issued_write(self) -> Access | None:
        """The write the front issues in this clock, when it issues one: the oldest whose AW
        and W were taken and that was not issued yet (the front issues them in order)."""
        for op in self.writes:
            if not op.get("issued"):
                op["issued"] = True
                return op["access"]
        return None

    def abort(self) -> None:
        self.writes.clear()
        self.reads.clear()
        self.gap = 0


#: the master of each front (``MdfqmTop(bus=...)``)
MASTERS = {"wishbone": WishboneMaster, "axi4lite": AxiLiteMaster}
