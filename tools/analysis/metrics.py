"""Distortion measures, exact, of piecewise-constant gate waveforms.

Every waveform here is a :class:`PWave`: breakpoints ``0 = t_0 < t_1 < .. < t_M = T`` and the N
pole states in each segment. ``T`` must hold a whole number of fundamental cycles; the waveform is
treated as periodic with period ``T`` (Fourier series on the window). All measures are computed in
closed form from the segments (no sampling, no truncated sums):

- ``v1``: rms of the fundamental of the line voltage ``v_ab = h_a - h_b`` (Vdc units);
- ``thd_full``: line-voltage THD over the full band, ``sqrt(P - P_dc - V1^2) / V1`` with ``P`` the
  exact mean square;
- ``thd_band``: the same restricted to ``0 < f < f_band`` (every Fourier bin of the window, so it
  includes non-harmonic content: it is THD+N);
- ``thd_harm``: only the harmonics ``n f1`` (n = 2 .. below ``f_band``), THD in the classical sense;
- ``wthd``: weighted THD ``sqrt(sum_{f != 0, f1} (f1 / f)^2 V_f^2) / V1``, computed exactly as
  ``sqrt((2 pi f1)^2 var(psi) - V1^2) / V1`` with ``psi`` the integral of ``v_ab - DC``;
- ``thd_i``: phase-current THD of ``i_a`` through a balanced star R-L load, time constant
  ``tau = L / R``: ``tau di/dt + i = v_a`` (R = 1), ``v_a = h_a - mean(h)``, solved exactly per
  segment in the periodic steady state; ``sqrt(I^2 - I_dc^2 - I1^2) / I1``,
  ``I1 = V1_phase / sqrt(1 + (2 pi f1 tau)^2)``.

DC is excluded from every distortion sum (it is reported separately as ``dc``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PWave", "distortion"]


@dataclass
class PWave:
    """Piecewise-constant N-leg pole-state waveform: ``t`` (M+1,), ``s`` (M, N) in {0, 1}."""

    t: np.ndarray
    s: np.ndarray

    @property
    def period(self) -> float:
        return float(self.t[-1] - self.t[0])

    @classmethod
    def from_samples(cls, h: np.ndarray, rate: float, phases: int) -> PWave:
        """From gate bitmasks held for ``1/rate`` each (runs of equal values merged)."""
        h = np.asarray(h, dtype=np.int64)
        change = np.flatnonzero(np.diff(h)) + 1
        starts = np.concatenate([[0], change])
        t = np.concatenate([starts, [len(h)]]) / rate
        bits = (h[starts, None] >> np.arange(phases)[None, :]) & 1
        return cls(t.astype(float), bits.astype(float))

    @classmethod
    def from_centred_duties(cls, duties: np.ndarray, rate: float) -> PWave:
        """Centred pulses: in carrier period k (length ``1/rate``) leg i is on during
        ``[(1 - a)/2, (1 + a)/2)`` of the period, ``a = duties[k, i]`` in [0, 1]."""
        a = np.clip(np.asarray(duties, dtype=float), 0.0, 1.0)
        k, _n = a.shape
        base = np.arange(k)[:, None]
        on = (base + (1 - a) / 2) / rate
        off = (base + (1 + a) / 2) / rate
        edges = np.concatenate([np.arange(k + 1) / rate, on.ravel(), off.ravel()])
        t = np.unique(edges)
        mid = 0.5 * (t[:-1] + t[1:])
        per = np.minimum(np.floor(mid * rate).astype(np.int64), k - 1)
        frac = mid * rate - per
        s = (np.abs(frac[:, None] - 0.5) < a[per] / 2).astype(float)
        return cls(t, s)

    def switching_events(self, initial: int = 0) -> int:
        """Leg transitions inside the window (starting from the all-``initial`` state)."""
        first = np.abs(self.s[0] - initial).sum()
        return int(first + np.abs(np.diff(self.s, axis=0)).sum())


def _coeff(t: np.ndarray, v: np.ndarray, freqs: np.ndarray) -> np.ndarray:
    """Complex Fourier coefficients ``(1/T) int v e^{-j 2 pi f t}`` at ``freqs`` (> 0)."""
    period = t[-1] - t[0]
    dv = np.diff(np.concatenate([[v[-1]], v]))  # jump at t_s (periodic wrap at t_0)
    keep = dv != 0
    te, de = t[:-1][keep], dv[keep]
    w = 2j * np.pi * np.asarray(freqs, dtype=float)
    out = np.empty(len(w), dtype=complex)
    chunk = max(1, 2_000_000 // max(1, len(te)))
    for i in range(0, len(w), chunk):
        out[i : i + chunk] = np.exp(-np.outer(w[i : i + chunk], te)) @ de
    return out / (w * period)


def _coeff_bins(t: np.ndarray, v: np.ndarray, nbins: int) -> np.ndarray:
    """Coefficients at the window's bins ``l = 1 .. nbins`` (``f = l / T``), by recurrence."""
    period = t[-1] - t[0]
    dv = np.diff(np.concatenate([[v[-1]], v]))
    keep = dv != 0
    te, de = t[:-1][keep], dv[keep]
    z = np.exp(-2j * np.pi * te / period)
    out = np.empty(nbins, dtype=complex)
    cur = z.copy()
    for ell in range(1, nbins + 1):
        if ell % 64 == 0:  # re-anchor against rounding drift
            cur = np.exp(-2j * np.pi * ell * te / period)
        out[ell - 1] = cur @ de
        cur *= z
    ells = np.arange(1, nbins + 1)
    return out / (2j * np.pi * ells)


def _stats(t, v):
    dt = np.diff(t)
    period = t[-1] - t[0]
    dc = float(v @ dt / period)
    power = float((v * v) @ dt / period)
    return dt, period, dc, power


def _integral_var(t, v, dc):
    """Variance of ``psi(t) = int_0^t (v - dc)`` over the window (piecewise linear, exact)."""
    dt = np.diff(t)
    period = t[-1] - t[0]
    psi = np.concatenate([[0.0], np.cumsum((v - dc) * dt)])
    a, b = psi[:-1], psi[1:]
    mean = float(((a + b) / 2) @ dt / period)
    msq = float(((a * a + a * b + b * b) / 3) @ dt / period)
    return msq - mean * mean


def _rl_current_power(t, v, tau):
    """Mean square of the periodic steady-state ``i``: ``tau di/dt + i = v``, exact per segment."""
    dt = np.diff(t)
    period = t[-1] - t[0]
    e = np.exp(-dt / tau)
    # i_{s+1} = e_s i_s + (1 - e_s) v_s from i_0 = 0, in closed form per block of <= 40 tau:
    # i_k = exp(-(t_k - t0)/tau) [i_b0 + sum_{s<k} (1 - e_s) v_s exp((t_{s+1} - t0)/tau)]
    i0 = np.empty(len(v) + 1)
    i0[0] = 0.0
    start = 0
    n = len(v)
    while start < n:
        t0 = t[start]
        stop = int(np.searchsorted(t, t0 + 40 * tau, side="right")) - 1
        stop = min(max(stop, start + 1), n)
        rel = (t[start + 1 : stop + 1] - t0) / tau
        terms = (1.0 - e[start:stop]) * v[start:stop] * np.exp(rel)
        i0[start + 1 : stop + 1] = np.exp(-rel) * (i0[start] + np.cumsum(terms))
        start = stop
    decay = np.exp(-(t - t[0]) / tau)  # response to i(0) = 1
    i_start = i0[-1] / (1.0 - np.exp(-period / tau))
    i = i0 + i_start * decay
    a = i[:-1] - v
    e2 = e * e
    integral = v * v * dt + 2 * v * a * tau * (1 - e) + a * a * tau / 2 * (1 - e2)
    return float(integral.sum() / period)


def distortion(w: PWave, f1: float, f_band: float, tau: float) -> dict:
    """All measures of one waveform at fundamental ``f1`` (see the module docstring)."""
    t = w.t - w.t[0]
    period = w.period
    cycles = f1 * period
    if abs(cycles - round(cycles)) > 1e-6 or round(cycles) < 1:
        raise ValueError(f"the window ({period} s) must hold whole cycles of {f1} Hz")
    s = w.s
    vab = s[:, 0] - s[:, 1]
    _, _, dc, power = _stats(t, vab)
    c1 = _coeff(t, vab, np.array([f1]))[0]
    p1 = 2 * abs(c1) ** 2
    df = 1.0 / period
    nb = int(np.ceil(f_band / df - 1e-9))  # bins l = 1 .. nb - 1 lie below f_band
    l1 = round(cycles)
    cb = _coeff_bins(t, vab, max(nb - 1, 0))
    bins = np.arange(1, len(cb) + 1)
    cb, bins = cb[bins != l1], bins[bins != l1]
    p_band = float(2 * (np.abs(cb) ** 2).sum())
    p_harm = float(2 * (np.abs(cb[bins % l1 == 0]) ** 2).sum())
    var_psi = _integral_var(t, vab, dc)
    wthd2 = ((2 * np.pi * f1) ** 2 * var_psi - p1) / p1
    va = s[:, 0] - s.mean(axis=1)
    _, _, dca, _ = _stats(t, va)
    ca1 = _coeff(t, va, np.array([f1]))[0]
    i1 = 2 * abs(ca1) ** 2 / (1 + (2 * np.pi * f1 * tau) ** 2)
    pi_ = _rl_current_power(t, va, tau)
    return {
        "v1": float(np.sqrt(p1)),
        "dc": dc,
        "thd_full": float(np.sqrt(max(power - dc * dc - p1, 0.0) / p1)),
        "thd_band": float(np.sqrt(p_band / p1)),
        "thd_harm": float(np.sqrt(p_harm / p1)),
        "wthd": float(np.sqrt(max(wthd2, 0.0))),
        "thd_i": float(np.sqrt(max(pi_ - dca * dca - i1, 0.0) / i1)),
    }
