"""N-phase sine reference of the board demo: phase accumulator, sine table, amplitude.

Specification (bit-true; the gateware is :class:`demo.nco.SineNco`, the clock-level model
:class:`mdfqm_model.nco.NcoModel`):

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

The clock-level timing (a beat every ``1 + N (sample_width + 1)`` clocks) is
:class:`mdfqm_model.nco.NcoModel`'s.
"""

from __future__ import annotations

import math

from .validate import validate_int

__all__ = ["beat_clocks", "phase_offsets", "sine_quarter", "sine_table", "validate_nco"]


def validate_nco(acc_bits: int, table_bits: int, sample_width: int) -> None:
    """``ValueError`` naming the first bad parameter."""
    validate_int(table_bits, "table_bits", 2, 12)
    validate_int(sample_width, "sample_width", 4, 24)
    validate_int(acc_bits, "acc_bits", table_bits + 2, 32)


def beat_clocks(phases: int, sample_width: int) -> int:
    """Clocks the NCO takes to compute a beat: the capture, then per phase the table address,
    the table data, one clock per magnitude bit (``sample_width - 1``) and one for the sign."""
    return 1 + phases * (sample_width + 2)


def sine_quarter(table_bits: int, sample_width: int) -> list[int]:
    """``m(j)``, the quarter wave (``2**table_bits`` entries, all > 0)."""
    q = 1 << table_bits
    amp = (1 << (sample_width - 1)) - 1
    return [round(amp * math.sin(math.pi / 2 * (j + 0.5) / q)) for j in range(q)]


def sine_table(table_bits: int, sample_width: int) -> list[int]:
    """``s(k)``, the full wave built from the quarter by symmetry (``4 Q`` entries)."""
    m = sine_quarter(table_bits, sample_width)
    return m + m[::-1] + [-v for v in m] + [-v for v in m[::-1]]


def phase_offsets(phases: int, acc_bits: int) -> list[int]:
    """Accumulator offsets of the phases: ``-floor(i 2**acc_bits / N) mod 2**acc_bits``."""
    return [(-(i * (1 << acc_bits) // phases)) % (1 << acc_bits) for i in range(phases)]
