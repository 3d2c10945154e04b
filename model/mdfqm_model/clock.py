"""Clock-level models of the MDFQM core (:class:`CoreModel`) and of the gating-signal generator
(:class:`GeneratorModel`): they predict every output of the gateware on every clock.

A plain per-cycle state machine implementing the section "Clock-level timing of the core" of
:mod:`mdfqm_spec.contract`; the arithmetic of each update is *not* duplicated here, it is
:func:`mdfqm_model.update.mdfqm_update` called at the commit point.

Registers (all reset synchronously to zero)
-------------------------------------------
- ``phase``: update sequencer; a cycle with ``phase == 0`` is an *update start*. At a start the
  runtime inputs are latched: ``P = max(period, L)``, ``period_clamped <= (period < L)``
  (a register, visible from the next cycle), ``osr = max(osr, 1)``, ``zero_policy``.
  Next ``phase`` = 0 if ``phase + 1 >= P`` else ``phase + 1``, with ``P`` the value latched at the
  start of the current update (in the start cycle itself: the value being latched). The output
  ``elapsed`` is ``phase``: the clocks since the update start.
- ``sync_in`` (instances sharing update boundaries): high in a cycle whose ``phase + 1 >= L``
  (the update in flight has committed by the next cycle) makes the next cycle an update start;
  earlier in an update it is ignored, so it can never cut an update short. ``start`` (output) is
  high in every update start cycle: wire one instance's ``start`` to the others' ``sync_in``; a
  follower out of step restarts one clock after the leader's start, one already in step (same
  period, common reset) stays in the same clock, since sync_in is ignored at its own start.
- ``sub``: update counter of the sampling switch; a start with ``sub == 0`` is a *sampling tick*
  (output ``sample`` = 1 in that cycle). At every start ``sub <= 0 if sub + 1 >= osr else sub + 1``,
  ``osr`` being the value latched at that start (this cycle's input, clamped to >= 1).
- Reference stage: ``ready = not (busy or full)`` (combinational from the registers). A beat
  accepted in cycle ``a`` (``ref_valid and ready and not rst``) keeps ``busy`` set from ``a+1``
  for ``2N`` cycles (``busy`` counts them down), then sets ``full`` with ``pending = R`` (common
  mode removed) in ``a + K``, ``K = contract.reference_latency(N) = 2N + 1``. In a cycle with
  ``full`` whose next cycle is a sampling tick, ``pending`` becomes ``held`` and ``full``
  clears (both visible in the tick's cycle, which ``fresh_reference`` marks). Every update
  uses ``held`` (zero-order hold; 0 after reset).
- An update starting in cycle ``s`` takes ``X`` and ``R`` of cycle ``s``; its ``h``, integrator
  ``X``, ``saturated`` flag and the one-cycle ``update`` strobe are visible in cycle ``s + L``
  (``L = contract.loop_latency(N, rule)`` by default). ``P >= L`` guarantees at most one update in
  flight, so the ``h_prev`` used by the zero policy (the ``h`` register at the commit) is the
  previously output state.

``step`` returns the outputs visible *during* the cycle (a function of the registers only), then
advances the registers with that cycle's inputs. ``rst`` is synchronous: the outputs of the rst
cycle come from the current state and the next state is the reset state (an in-flight update is
discarded, no beat is accepted).

Input ranges: ``ref`` entries are ``width``-bit two's complement codes, ``period`` unsigned 16-bit,
``osr`` unsigned 8-bit, ``zero_policy`` 0/1, ``rst``/``ref_valid`` 0/1; anything else raises
``ValueError``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mdfqm_spec.contract import (
    BITS_WIDTH,
    MODE_WIDTH,
    MODES,
    OSR_WIDTH,
    PERIOD_WIDTH,
    Contract,
    latch_mode,
    loop_latency,
    min_period,
    reference_latency,
    resolution_latency,
    validate_max_bits,
    validate_rule,
    validate_zero_policy,
)

from .bbit import bbit_update
from .inputs import check_bit, check_uint, stimulus_columns
from .update import mdfqm_update, remove_common_mode

__all__ = ["GENERATOR_OUTPUTS", "OSR_MAX", "OUTPUTS", "PERIOD_MAX", "CoreModel", "GeneratorModel"]

#: names of the per-cycle outputs, in the order of :meth:`CoreModel.step`'s dict
OUTPUTS = ("ref_ready", "start", "sample", "h", "update", "saturated", "period_clamped",
           "elapsed")
#: the generator's outputs: the core's, ``mode_clamped`` and the mode and b in force
GENERATOR_OUTPUTS = (*OUTPUTS, "mode_clamped", "mode_in_force", "bits_in_force")
#: the runtime inputs every model takes (the generator adds ``mode`` and ``bits``)
INPUTS = ("rst", "ref_valid", "ref", "period", "osr", "zero_policy", "sync_in")
#: largest value of the unsigned 16-bit ``period`` input
PERIOD_MAX = (1 << PERIOD_WIDTH) - 1
#: largest value of the unsigned 8-bit ``osr`` input
OSR_MAX = (1 << OSR_WIDTH) - 1




class CoreModel:
    """Cycle-accurate model of the core (reference stage, sequencer, sampling switch, MDFQM loop).

    ``phases`` N >= 3, ``width`` W (``FULL = 2**(W-2)``), ``rule`` one of ``contract.RULES``,
    ``latency`` the loop latency L in clocks (default ``contract.loop_latency(phases, rule)``).
    """

    OUTPUTS = OUTPUTS
    INPUTS = INPUTS

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty", latency=None):
        self.contract = Contract(phases, width)
        self.rule = validate_rule(rule)
        if latency is None:
            latency = loop_latency(phases, rule)
        if isinstance(latency, bool) or not isinstance(latency, (int, np.integer)) or latency < 1:
            raise ValueError(f"latency must be an integer >= 1, not {latency!r}")
        self.latency = int(latency)
        self.phases = phases
        self.reset()

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """Put every register in its reset state (all zero)."""
        n = self.phases
        self.phase = 0
        self.p_lat = 0
        self.period_clamped = 0
        self.sub = 0
        self.osr_lat = 0
        self.policy_lat = 0
        self.busy = 0
        self.beat: tuple[int, ...] = (0,) * n
        self.full = 0
        # the update starting in this cycle (a sampling tick) uses a beat handed over in the
        # cycle before: a new sample
        self.fresh_reference = 0
        self.pending: tuple[int, ...] = (0,) * n
        self.held: tuple[int, ...] = (0,) * n
        self.x: tuple[int, ...] = (0,) * n
        self.h = 0
        self.saturated = 0
        self.update = 0
        # the update in flight: [cycles until commit, X, R, zero_policy] or None
        self.inflight = None
        self.cycle = 0

    @property
    def ref_ready(self) -> int:
        return int(not (self.busy or self.full))

    def outputs(self) -> dict:
        """The outputs visible in the current cycle (a function of the registers only)."""
        return {
            "ref_ready": self.ref_ready,
            "start": int(self.phase == 0),
            "sample": int(self.phase == 0 and self.sub == 0),
            "h": self.h,
            "update": self.update,
            "saturated": self.saturated,
            "period_clamped": self.period_clamped,
            "elapsed": self.phase,
        }

    def _check_ref(self, ref: Sequence[int]) -> tuple[int, ...]:
        c = self.contract
        vals = tuple(ref)
        if len(vals) != self.phases:
            raise ValueError(f"ref must have {self.phases} entries, got {len(vals)}")
        out = []
        for v in vals:
            if (
                isinstance(v, (bool, np.bool_))
                or not isinstance(v, (int, np.integer))
                or not c.code_min <= v <= c.code_max
            ):
                raise ValueError(
                    f"ref entries must be {c.width}-bit codes in [{c.code_min}, {c.code_max}], "
                    f"not {v!r}"
                )
            out.append(int(v))
        return tuple(out)

    # ------------------------------------------------------------------ one clock
    def step(
        self,
        rst=0,
        ref_valid=0,
        ref=None,
        period=None,
        osr=1,
        zero_policy=0,
        sync_in=0,
        **extra,
    ) -> dict:
        """Outputs visible during this cycle, then advance to the next cycle.

        ``ref`` defaults to all-zero codes; ``period=None`` means ``L`` (the minimum legal period).
        ``extra``: the inputs a subclass adds (none for the core).
        """
        extra = self._check_extra(extra)
        rst = check_bit(rst, "rst")
        ref_valid = check_bit(ref_valid, "ref_valid")
        ref = (0,) * self.phases if ref is None else self._check_ref(ref)
        period = self.latency if period is None else check_uint(period, 16, "period")
        osr = check_uint(osr, 8, "osr")
        if isinstance(zero_policy, np.integer):
            zero_policy = int(zero_policy)
        zero_policy = validate_zero_policy(zero_policy)
        sync_in = check_bit(sync_in, "sync_in")
        out = self.outputs()
        self.cycle += 1
        if rst:
            cycle = self.cycle
            self.reset()
            self.cycle = cycle
            return out

        # ---- reference stage (next-state values)
        accept = ref_valid and self.ref_ready
        start = self.phase == 0
        r_for_update = self.held
        n_full, n_pending = self.full, self.pending
        if self.busy == 1:
            n_full, n_pending = 1, tuple(remove_common_mode(self.beat, self.phases))
        n_busy = reference_latency(self.phases) - 1 if accept else max(self.busy - 1, 0)
        n_beat = ref if accept else self.beat

        # ---- sequencer and sampling switch
        if start:
            p, clamped, latency, token = self._latch(period, extra)
            self.p_lat = p
            self.period_clamped = int(clamped)
            self.osr_lat = max(osr, 1)
            self.policy_lat = zero_policy
            self.sub = 0 if self.sub + 1 >= self.osr_lat else self.sub + 1
            self.phase = 0 if p <= 1 else 1  # sync_in cannot restart here: 1 < L
            if self.inflight is not None:  # impossible while P >= the update's latency
                raise AssertionError("update started while another is in flight")
            self.inflight = [latency, self.x, r_for_update, zero_policy, token]
        else:
            restart = sync_in and self.phase + 1 >= self._restart_latency()
            self.phase = 0 if restart or self.phase + 1 >= self.p_lat else self.phase + 1

        # the hand-over, in the cycle before a sampling tick (phase and sub are the next cycle's)
        self.fresh_reference = int(bool(self.full and self.phase == 0 and self.sub == 0))
        if self.fresh_reference:
            n_full, self.held = 0, self.pending
        self.busy, self.beat = n_busy, n_beat
        self.full, self.pending = n_full, n_pending

        # ---- the output between presentations (slot layouts), then the loop: commit the update
        # in flight when its result becomes visible
        self._advance_output()
        self.update = 0
        if self.inflight is not None:
            self.inflight[0] -= 1
            if self.inflight[0] == 0:
                _, x, r, policy, token = self.inflight
                self._commit(x, r, policy, token)
                self.update = 1
                self.inflight = None
        return out

    # ------------------------------------------------------------------ hooks (the core's)
    def _check_extra(self, extra: dict) -> dict:
        if extra:
            raise TypeError(f"{type(self).__name__}.step() got unexpected inputs {sorted(extra)}")
        return extra

    def _latch(self, period: int, extra: dict):
        """At an update start: ``(P, period_clamped, latency of this update, token)``."""
        return max(period, self.latency), period < self.latency, self.latency, None

    def _restart_latency(self) -> int:
        """``sync_in`` restarts once ``phase + 1 >=`` this (the update in flight committed)."""
        return self.latency

    def _advance_output(self) -> None:
        """Per-cycle change of the output between presentations (none for the core)."""

    def _commit(self, x, r, policy, token) -> None:
        res = mdfqm_update(x, r, self.h, self.contract, self.rule, policy)
        self.h = res.h
        self.x = res.x_next
        self.saturated = int(res.saturated)

    # ------------------------------------------------------------------ many clocks
    def simulate(self, stim: dict, trace_state: bool = False) -> dict:
        """Run ``C`` cycles from the current state.

        ``stim`` maps input names (``rst``, ``ref_valid``, ``ref`` (C x N), ``period``, ``osr``,
        ``zero_policy``) to arrays of length ``C`` or scalars (held for all cycles); a missing
        input takes :meth:`step`'s default. ``C`` is the length of the array inputs, or
        ``stim["cycles"]`` when all inputs are scalars. Returns the outputs as int64 arrays of
        length ``C``; with ``trace_state`` also ``x`` (C x N, the integrator visible in each cycle)
        and ``phase``, ``sub``, ``full``.
        """
        cols, c = stimulus_columns(stim, self.INPUTS, {"ref": self.phases})
        out = {k: np.zeros(c, dtype=np.int64) for k in self.OUTPUTS}
        if trace_state:
            out["x"] = np.zeros((c, self.phases), dtype=np.int64)
            for k in ("phase", "sub", "full"):
                out[k] = np.zeros(c, dtype=np.int64)
        for i in range(c):
            kw = {}
            for name, (kind, v) in cols.items():
                kw[name] = v[i] if kind == "array" else v
            if trace_state:
                out["x"][i] = self.x
                out["phase"][i] = self.phase
                out["sub"][i] = self.sub
                out["full"][i] = self.full
            o = self.step(**kw)
            for k in self.OUTPUTS:
                out[k][i] = o[k]
        return out


class GeneratorModel(CoreModel):
    """Cycle-accurate model of the gating-signal generator (RTL ``GatingSignalGenerator``).

    The core's model plus the section "b-bit pulse-width resolution: the gating-signal generator"
    of :mod:`mdfqm_spec.contract`: runtime ``mode`` and ``bits`` latched at each update start
    (:func:`mdfqm_spec.contract.latch_mode`), short / long updates, the mode-dependent minimum
    period and sync threshold, slot layouts presented ``L_b`` after their start. The arithmetic
    of each update is :func:`mdfqm_model.bbit.bbit_update` (which is
    :func:`mdfqm_model.update.mdfqm_update` for mdfqm), called at the commit point; its
    ``slots`` are the layout.

    ``max_bits`` B in ``[1, min(12, width - 2)]``; ``long_latency`` defaults to
    ``contract.resolution_latency(phases, max_bits)``. Extra inputs of :meth:`step`: ``mode``
    (3-bit code, default 0 = mdfqm) and ``bits`` (4-bit, default 0); extra outputs
    ``mode_clamped``, ``mode_in_force`` and ``bits_in_force`` (the mode and b latched at the last
    update start, after the clamp; 0 and 0 after reset).
    """

    OUTPUTS = GENERATOR_OUTPUTS
    INPUTS = (*INPUTS, "mode", "bits")

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty",
                 max_bits: int = 8, latency=None, long_latency=None):
        Contract(phases, width)
        self.max_bits = validate_max_bits(max_bits, width)
        if long_latency is None:
            long_latency = resolution_latency(phases, max_bits)
        if (isinstance(long_latency, bool) or not isinstance(long_latency, (int, np.integer))
                or long_latency < 2):
            raise ValueError(f"long_latency must be an integer >= 2, not {long_latency!r}")
        self.long_latency = int(long_latency)
        super().__init__(phases, width, rule, latency)

    def reset(self) -> None:
        super().reset()
        self.mode_lat = 0
        self.bits_lat = 0
        self.long_lat = 0
        self.prev_bbit = 0
        self.mode_clamped = 0
        self.h_last = 0
        self.slots: tuple[int, ...] = (0,)
        self.slot_len = 1
        self.slot_idx = 0
        self.slot_pos = 0

    def outputs(self) -> dict:
        out = super().outputs()
        out["mode_clamped"] = self.mode_clamped
        out["mode_in_force"] = self.mode_lat
        out["bits_in_force"] = self.bits_lat
        return out

    def _check_extra(self, extra: dict) -> dict:
        unknown = set(extra) - {"mode", "bits"}
        if unknown:
            raise TypeError(f"GeneratorModel.step() got unexpected inputs {sorted(unknown)}")
        mode = check_uint(extra.get("mode", 0), MODE_WIDTH, "mode")
        bits = check_uint(extra.get("bits", 0), BITS_WIDTH, "bits")
        return {"mode": mode, "bits": bits}

    def _latch(self, period: int, extra: dict):
        mode, b, clamped_mode = latch_mode(extra["mode"], extra["bits"], self.max_bits)
        long = bool(mode != 0 or self.prev_bbit)
        p_min = min_period(long, b, self.latency, self.long_latency)
        self.mode_lat, self.bits_lat, self.long_lat = mode, b, int(long)
        self.prev_bbit = int(mode != 0)
        self.mode_clamped = int(clamped_mode)
        p = max(period, p_min)
        latency = self.long_latency if long else self.latency
        return p, period < p_min, latency, (mode, b, p)

    def _restart_latency(self) -> int:
        return self.long_latency if self.long_lat else self.latency

    def _advance_output(self) -> None:
        if self.slot_idx + 1 < len(self.slots):
            if self.slot_pos + 1 >= self.slot_len:
                self.slot_idx += 1
                self.slot_pos = 0
                self.h = self.slots[self.slot_idx]
            else:
                self.slot_pos += 1

    def _commit(self, x, r, policy, token) -> None:
        mode, b, p = token
        res = bbit_update(x, r, self.contract, MODES[mode], b, self.h_last, self.rule, policy)
        self.x = res.x_next
        self.saturated = int(res.saturated)
        self.slots = res.slots
        self.slot_len = p >> b
        self.slot_idx = 0
        self.slot_pos = 0
        self.h = res.slots[0]
        self.h_last = res.slots[-1]
