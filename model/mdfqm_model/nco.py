"""N-phase sine reference of the board demo: phase accumulator, sine table, amplitude.

Specification (bit-true; the gateware is :class:`mdfqm_gateware.demo.nco.SineNco`):

- Phase accumulator of ``acc_bits`` bits: ``acc <- (acc + freq) mod 2**acc_bits`` every clock,
  so the output frequency is ``freq * f_clk / 2**acc_bits``.
- Sine table of ``4 Q`` entries, ``Q = 2**table_bits`` per quarter wave, sampled half a step off
  the axes so that the quarter-wave symmetry is exact:
  ``m(j) = round(A sin(pi/2 (j + 1/2) / Q))`` for ``j < Q``, ``A = 2**(sample_width-1) - 1``,
  and ``s(k) = m(j)``, ``m(Q-1-j)``, ``-m(j)``, ``-m(Q-1-j)`` in quadrants 0..3 of
  ``k = q Q + j``. A quarter table stores ``m``, a full table stores ``s``; both give ``s``.
- Phase ``i`` of ``N`` lags by ``i/N`` turn: its table index is the top ``table_bits + 2``
  bits of ``(base - floor(i 2**acc_bits / N)) mod 2**acc_bits``.
- Code (``FULL = 2**(width-2)`` codes per Vdc, as the core's reference):
  ``c_i = sign(s) floor(amplitude |s| / 2**(sample_width-1))``, truncated toward zero so that
  the wave is symmetric; ``amplitude`` is an unsigned ``width - 1``-bit number of codes, so
  ``|c_i| < 2**(width-1)`` always fits.

Clock-level timing (:class:`NcoModel`): a cycle with the FSM idle and no beat held *captures*
``base = acc`` (the value visible in that cycle) and the amplitude; each phase then takes
``2 + (sample_width - 1)`` clocks (table address, table data, one clock per magnitude bit of
a serial multiplier); ``ref.valid`` rises the clock after the last phase and holds with its
payload until ``ref.ready``; the next capture is the clock after the transfer. A beat therefore
takes ``1 + N (sample_width + 1)`` clocks to compute.
"""

from __future__ import annotations

import numpy as np

__all__ = ["NcoModel", "phase_offsets", "reference_codes", "sine_quarter", "sine_table",
           "validate_nco"]


def _int_in(value, name, lo, hi):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or \
            not lo <= value <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], not {value!r}")
    return int(value)


def validate_nco(acc_bits: int, table_bits: int, sample_width: int) -> None:
    """``ValueError`` naming the first bad parameter."""
    _int_in(table_bits, "table_bits", 2, 12)
    _int_in(sample_width, "sample_width", 4, 24)
    _int_in(acc_bits, "acc_bits", table_bits + 2, 32)


def sine_quarter(table_bits: int, sample_width: int) -> np.ndarray:
    """``m(j)``, the quarter wave (int64, ``2**table_bits`` entries, all > 0)."""
    q = 1 << table_bits
    amp = (1 << (sample_width - 1)) - 1
    return np.rint(amp * np.sin(np.pi / 2 * (np.arange(q) + 0.5) / q)).astype(np.int64)


def sine_table(table_bits: int, sample_width: int) -> np.ndarray:
    """``s(k)``, the full wave built from the quarter by symmetry (int64, ``4 Q`` entries)."""
    m = sine_quarter(table_bits, sample_width)
    return np.concatenate([m, m[::-1], -m, -m[::-1]])


def phase_offsets(phases: int, acc_bits: int) -> list[int]:
    """Accumulator offsets of the phases: ``-floor(i 2**acc_bits / N) mod 2**acc_bits``."""
    return [(-(i * (1 << acc_bits) // phases)) % (1 << acc_bits) for i in range(phases)]


def reference_codes(base, amplitude, phases: int, acc_bits: int = 32, table_bits: int = 8,
                    sample_width: int = 16) -> np.ndarray:
    """Codes of every phase for accumulator value(s) ``base``: shape ``base.shape + (N,)``."""
    base = np.asarray(base, dtype=np.int64)
    amplitude = np.asarray(amplitude, dtype=np.int64)
    table = sine_table(table_bits, sample_width)
    mask = (1 << acc_bits) - 1
    shift = acc_bits - table_bits - 2
    out = []
    for offset in phase_offsets(phases, acc_bits):
        s = table[((base + offset) & mask) >> shift]
        mag = (amplitude * np.abs(s)) >> (sample_width - 1)
        out.append(np.where(s < 0, -mag, mag))
    return np.stack(out, axis=-1)


class NcoModel:
    """Clock-level model: ``step(freq, amplitude, ready)`` returns the outputs visible in this
    cycle (``valid``, ``payload`` (tuple of N codes), ``phase``), then advances one clock."""

    def __init__(self, phases: int = 3, width: int = 16, acc_bits: int = 32,
                 table_bits: int = 8, sample_width: int = 16):
        validate_nco(acc_bits, table_bits, sample_width)
        self.phases, self.width = phases, width
        self.acc_bits, self.table_bits, self.sample_width = acc_bits, table_bits, sample_width
        self.beat_clocks = 1 + phases * (sample_width + 1)
        self.acc = 0
        self.valid = 0
        self.payload = (0,) * phases
        self.busy = 0          # clocks left of the computation in progress (0: idle)
        self.result = None

    def outputs(self) -> dict:
        return {"valid": self.valid, "payload": self.payload, "phase": self.acc}

    def step(self, freq: int = 0, amplitude: int = 0, ready: int = 0) -> dict:
        out = self.outputs()
        if self.busy:
            self.busy -= 1
            if self.busy == 0:
                self.valid, self.payload = 1, self.result
        elif not self.valid:
            codes = reference_codes(self.acc, amplitude & ((1 << (self.width - 1)) - 1),
                                    self.phases, self.acc_bits, self.table_bits,
                                    self.sample_width)
            self.result = tuple(int(c) for c in codes)
            self.busy = self.beat_clocks - 1
        elif ready:
            self.valid = 0
        self.acc = (self.acc + freq) % (1 << self.acc_bits)
        return out
