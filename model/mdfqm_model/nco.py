"""Clock-level model of the board demo's N-phase sine reference (:class:`demo.nco.SineNco`).

The phase accumulator, the sine table, the phase offsets and the amplitude scaling are specified
in :mod:`mdfqm_spec.nco`; this module computes the codes from them (vectorised for the analysis)
and models the clock-level timing:

Clock-level timing (:class:`NcoModel`): a cycle with the FSM idle and no beat held *captures*
``base = acc`` (the value visible in that cycle) and the amplitude; each phase then takes
``3 + (sample_width - 1)`` clocks (table address, table data, one clock per magnitude bit of
a serial multiplier, one to apply the sign); ``ref.valid`` rises the clock after the last phase
and holds with its payload until ``ref.ready``; the next capture is the clock after the
transfer. A beat therefore takes ``1 + N (sample_width + 2)`` clocks to compute.
"""

from __future__ import annotations

import numpy as np

from mdfqm_spec.nco import beat_clocks, phase_offsets, sine_table, validate_nco

__all__ = ["NcoModel", "reference_codes"]


def reference_codes(base, amplitude, phases: int, acc_bits: int = 32, table_bits: int = 8,
                    sample_width: int = 16) -> np.ndarray:
    """Codes of every phase for accumulator value(s) ``base``: shape ``base.shape + (N,)``."""
    base = np.asarray(base, dtype=np.int64)
    amplitude = np.asarray(amplitude, dtype=np.int64)
    table = np.asarray(sine_table(table_bits, sample_width), dtype=np.int64)
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
        self.beat_clocks = beat_clocks(phases, sample_width)
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
