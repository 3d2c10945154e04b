"""The FOC speed drive of the paper's Fig. 1, sampled at the IP's sampling ticks: a speed PI
giving the q-axis current reference (``i_d`` reference 0), dq current PIs, inverse Park, the
reference written to the IP; and the sensors it reads (encoder, phase-current ADC).

Written out rather than taken from motulator's control package on purpose: the firmware of the
firmware-in-the-loop issue implements this same controller in C, so it is kept to the explicit
discrete-time difference equations an MCU runs (each line maps to a line of C), and it reads only
what a firmware can read (ADC codes at the IP's trigger, encoder counts, the bus voltage).

The tuning rule (one for every mode and rate; ``docs/drive.md``)
-----------------------------------------------------------------
- Current loop bandwidth ``alpha_c = 2 pi f_c / 20`` (``f_c`` the sampling rate); per axis,
  internal-model-control gains ``K_p = alpha_c L``, ``K_i = alpha_c R`` (the PI zero cancels the
  winding's pole: first-order response ``alpha_c``), cross-coupling and back-EMF feedforward
  (optional), back-calculation anti-windup, the voltage vector limited to the linear range
  ``u_dc / sqrt(3)`` (the largest circle inside the hexagon; 0.577 in the modulation-index
  units of the reports), the inverse Park angle advanced by ``1.5 w T_c`` (the computation
  delay plus the hold's half period).
- Speed loop bandwidth ``alpha_s = alpha_c / 10``; an I-P controller (proportional on the
  measured speed, integral on the error): ``tau = K_i int(e) - K_p w``, ``K_p = 2 alpha_s J``,
  ``K_i = alpha_s^2 J`` gives a double closed-loop pole at ``-alpha_s`` and no overshoot
  with the inner loop taken as ideal: after a step, ``1 - (1 + alpha_s t) e^(-alpha_s t)`` of
  the step, within 5 % from ``alpha_s t = 4.74``. Torque limit ``k_t i_max``, clamping
  anti-windup.
- Speed from a quadrature encoder (``counts`` per revolution) through a tracking loop
  (``alpha_o = 4 alpha_s``, critically damped), its angle for Park.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from .motors import Motor

__all__ = ["Adc", "Encoder", "FocController", "Tuning"]

_A = cmath.exp(2j * math.pi / 3)
_A2 = _A * _A
_LINEAR = 1 / math.sqrt(3)


@dataclass(frozen=True)
class Tuning:
    """Bandwidths (rad/s) and limits; :meth:`rule` is the project's rule."""

    alpha_c: float
    alpha_s: float
    i_max: float
    decoupling: bool = True
    delay_compensation: bool = True

    @staticmethod
    def rule(f_c: float, i_max: float, decoupling: bool = True) -> Tuning:
        alpha_c = 2 * math.pi * f_c / 20
        return Tuning(alpha_c, alpha_c / 10, i_max, decoupling)

    def settling_time(self, band: float = 0.05) -> float:
        """Seconds from a speed step until the ideal response (inner loop and speed sensing
        ideal) stays within ``band`` of the step: the root of ``(1 + x) e^-x = band``, over
        ``alpha_s``."""
        x = 1.0
        for _ in range(60):  # Newton on f(x) = ln(1 + x) - x - ln(band)
            x -= (math.log1p(x) - x - math.log(band)) / (1 / (1 + x) - 1)
        return x / self.alpha_s

    def step_response(self, J: float, damping: float, T_c: float, t_end: float,
                      dt: float = 1e-5):
        """The linear prediction of a unit speed step from this rule alone: the I-P speed loop,
        the speed tracking loop, the current loop as ``alpha_c / (s + alpha_c)`` behind the
        computation delay and the hold (``1.5 T_c``, a first-order lag), the shaft
        ``J dw/dt = tau - damping w``. Returns ``(t, w)`` (exact discretisation of the linear
        system, step ``dt``)."""
        a_o = 4 * self.alpha_s
        kp, ki = 2 * self.alpha_s * J, self.alpha_s ** 2 * J
        ko_p, ko_i = 2 * a_o, a_o ** 2
        delay = 1.5 * T_c
        # state: w, theta, theta_hat, w_hat, x_i, tau_delayed, tau
        a = np.zeros((7, 7))
        b = np.zeros(7)
        a[0, 0], a[0, 6] = -damping / J, 1 / J
        a[1, 0] = 1
        a[2, 1], a[2, 2], a[2, 3] = ko_p, -ko_p, 1
        a[3, 1], a[3, 2] = ko_i, -ko_i
        a[4, 3], b[4] = -ki, ki
        a[5, 4], a[5, 3], a[5, 5] = 1 / delay, -kp / delay, -1 / delay
        a[6, 5], a[6, 6] = self.alpha_c, -self.alpha_c
        aug = np.zeros((8, 8))
        aug[:7, :7], aug[:7, 7] = a * dt, b * dt
        phi = _expm(aug)
        steps = round(t_end / dt)
        x = np.zeros(7)
        w = np.zeros(steps + 1)
        for k in range(steps):
            x = phi[:7, :7] @ x + phi[:7, 7]
            w[k + 1] = x[0]
        return np.arange(steps + 1) * dt, w

    def band_entry(self, J: float, damping: float, T_c: float, band: float = 0.05) -> float:
        """Seconds after a step from which :meth:`step_response` stays within ``band``."""
        t, w = self.step_response(J, damping, T_c, 20 / self.alpha_s)
        outside = np.nonzero(np.abs(w - 1) > band)[0]
        return float(t[outside[-1] + 1]) if outside.size else 0.0

    def overshoot(self, J: float, damping: float, T_c: float) -> float:
        """The largest excess of :meth:`step_response` over the step (a fraction of it)."""
        _, w = self.step_response(J, damping, T_c, 20 / self.alpha_s)
        return max(float(w.max()) - 1, 0.0)


def _expm(m):
    """Matrix exponential by scaling and squaring with a Taylor series (small, well-scaled
    matrices: the step is far below every time constant)."""
    norm = float(np.abs(m).sum(axis=1).max())
    k = max(0, math.ceil(math.log2(norm)) + 1) if norm > 0.5 else 0
    a = m / (1 << k)
    out = np.eye(len(m))
    term = np.eye(len(m))
    for n in range(1, 20):
        term = term @ a / n
        out = out + term
    for _ in range(k):
        out = out @ out
    return out


@dataclass(frozen=True)
class Adc:
    """Phase-current measurement: ``bits`` resolution over ``[-i_range, i_range)`` A;
    ``topology`` ``"inline"`` (a sensor in each phase, always valid) or ``"shunt"`` (a shunt under
    each leg: a leg's current is readable only while its lower switch is on)."""

    bits: int = 12
    i_range: float = 8.0
    topology: str = "inline"

    def __post_init__(self):
        if self.topology not in ("inline", "shunt"):
            raise ValueError(f"Adc.topology must be 'inline' or 'shunt', not {self.topology!r}")

    @property
    def lsb(self) -> float:
        """Amps per code."""
        return 2 * self.i_range / (1 << self.bits)

    def code(self, i: float) -> int:
        """The signed code of the current ``i`` (rounded, saturated)."""
        return min(max(round(i / self.lsb), -(1 << (self.bits - 1))), (1 << (self.bits - 1)) - 1)

    def convert(self, i: float) -> float:
        return self.code(i) * self.lsb

    def sample(self, currents, lower: int):
        """The measured ``i_ab``, or None when fewer than two legs are readable."""
        m = [self.convert(i) for i in currents]
        if self.topology == "inline":
            valid = (0, 1, 2)
        else:
            valid = tuple(i for i in range(3) if (lower >> i) & 1)
        if len(valid) < 2:
            return None
        if len(valid) == 2:
            missing = ({0, 1, 2} - set(valid)).pop()
            m[missing] = -(m[valid[0]] + m[valid[1]])
        return (2.0 / 3.0) * (m[0] + _A * m[1] + _A2 * m[2])


@dataclass(frozen=True)
class Encoder:
    """A quadrature encoder of ``counts`` per mechanical revolution (4x the lines), aligned to the
    rotor's electrical angle 0."""

    counts: int = 4096

    def read(self, theta_m: float) -> int:
        return math.floor(theta_m / (2 * math.pi) * self.counts)


class FocController:
    """One call per sampling tick: measurements in, the voltage reference (codes) out."""

    def __init__(self, motor: Motor, J: float, tuning: Tuning, T_c: float, full: int,
                 encoder: Encoder | None = None):
        self.motor, self.J, self.tuning, self.T_c, self.full = motor, J, tuning, T_c, full
        self.encoder = encoder if encoder is not None else Encoder()
        self.kp_d = tuning.alpha_c * motor.L_d
        self.kp_q = tuning.alpha_c * motor.L_q
        self.ki = tuning.alpha_c * motor.R_s
        self.ks_p = 2 * tuning.alpha_s * J
        self.ks_i = tuning.alpha_s ** 2 * J
        self.tau_max = motor.k_t * tuning.i_max
        alpha_o = 4 * tuning.alpha_s
        self.ko_p, self.ko_i = 2 * alpha_o, alpha_o ** 2
        self.reset()

    def reset(self) -> None:
        self.int_d = self.int_q = 0.0
        self.int_s = 0.0
        self.theta_hat = None  # the tracking loop's mechanical angle (unwrapped)
        self.w_hat = 0.0
        self.i_q_ref = 0.0
        self.i_meas = 0j

    def speed_estimate(self, count: int) -> tuple[float, float]:
        """Advance the tracking loop with an encoder count; ``(w_m estimate, mechanical angle of
        the count)``."""
        theta = 2 * math.pi * count / self.encoder.counts
        if self.theta_hat is None:
            self.theta_hat = theta
        err = theta - self.theta_hat
        self.theta_hat += self.T_c * (self.w_hat + self.ko_p * err)
        self.w_hat += self.T_c * self.ko_i * err
        return self.w_hat, theta

    def step(self, w_ref: float, count: int, i_ab: complex | None, u_dc: float):
        """``w_ref`` (rad/s), the encoder ``count``, the measured ``i_ab`` (None: no valid sample,
        the last one is reused), the measured bus voltage. Returns the three reference codes
        (FULL per ``u_dc``), which the IP takes at the next sampling tick."""
        m, tn = self.motor, self.tuning
        w_m, theta_m = self.speed_estimate(count)
        w_e = m.n_p * w_m
        theta_e = m.n_p * theta_m
        # speed I-P with clamping anti-windup
        tau_free = self.int_s + self.ks_i * self.T_c * (w_ref - w_m) - self.ks_p * w_m
        tau = min(max(tau_free, -self.tau_max), self.tau_max)
        if tau == tau_free:
            self.int_s += self.ks_i * self.T_c * (w_ref - w_m)
        self.i_q_ref = tau / m.k_t
        # dq currents
        if i_ab is not None:
            self.i_meas = i_ab
        i_dq = self.i_meas * cmath.exp(-1j * theta_e)
        e_d, e_q = -i_dq.real, self.i_q_ref - i_dq.imag
        u_d = self.kp_d * e_d + self.int_d
        u_q = self.kp_q * e_q + self.int_q
        if tn.decoupling:
            u_d -= w_e * m.L_q * i_dq.imag
            u_q += w_e * (m.L_d * i_dq.real + m.psi_f)
        u_free = complex(u_d, u_q)
        u_max = _LINEAR * u_dc
        u = u_free if abs(u_free) <= u_max else u_free * (u_max / abs(u_free))
        # back-calculation: integrate the error the limited voltage realises
        self.int_d += self.ki * self.T_c * (e_d + (u.real - u_free.real) / self.kp_d)
        self.int_q += self.ki * self.T_c * (e_q + (u.imag - u_free.imag) / self.kp_q)
        advance = 1.5 * w_e * self.T_c if tn.delay_compensation else 0.0
        u_ab = u * cmath.exp(1j * (theta_e + advance))
        scale = self.full / u_dc
        return tuple(round(scale * (u_ab * rot).real) for rot in (1, _A2, _A))
