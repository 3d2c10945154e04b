"""The plant: a PMSM in rotor coordinates, its shaft and load, a two-level inverter with
freewheeling diodes, and the DC bus. It is advanced from one gate edge to the next
(:meth:`Plant.advance`), so any source of edges can drive it: the golden model through
:mod:`mdfqm_drive.modulator`, or the gate pins of the simulated gateware.

Conventions (those of motulator, the reference this plant is checked against)
------------------------------------------------------------------------------
- Peak-valued space vectors: ``x_ab = 2/3 (x_a + a x_b + a^2 x_c)``, ``a = exp(j 2 pi / 3)``;
  ``x_dq = x_ab exp(-j theta)``, ``theta`` the electrical rotor angle.
- Machine: ``L_d di_d/dt = u_d - R i_d + w L_q i_q``, ``L_q di_q/dt = u_q - R i_q - w L_d i_d -
  w psi_f``; torque ``1.5 n_p (psi_f i_q + (L_d - L_q) i_d i_q)``; ``w = n_p w_m``.
- Shaft: ``(J_motor + J_load) dw_m/dt = tau - B w_m - tau_load(w_m)``.
- Inverter leg ``i``: upper gate on -> pole at Vdc, lower gate on -> pole at 0, both off
  (blanking) -> the diode of the current's direction: pole at 0 if ``i_i > 0``, Vdc if ``i_i < 0``,
  Vdc/2 if zero, the sign taken at the start of the interval (motulator's rule: at the latest
  switching instant). Both gates on is a shoot-through: :class:`ShootThroughError` is raised.

Exactness
---------
Between two edges the pole voltages are constant. With the electrical speed held at its value at
the start of the interval, the current equations are linear with a rotating input, and
:meth:`Plant.advance` solves them in closed form (the 2x2 matrix exponential, no step size).
The currents are solved at the interval's mid-point speed (predicted from the torque at its
start); the speed, the angle and the bus are then advanced with the trapezoidal mean of the
torque and of the DC current over the interval (second order in the interval, which is at most
one update, against a mechanical time constant of tens of milliseconds). The inner loop is pure
Python floats, the fastest for 2x2 algebra.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

from .motors import Load, Motor

__all__ = ["DcBus", "Plant", "ShootThroughError"]

_A = cmath.exp(2j * math.pi / 3)
_A2 = _A * _A


class ShootThroughError(RuntimeError):
    """Both gates of a leg on: the plant refuses (the IP must never do it)."""


@dataclass(frozen=True)
class DcBus:
    """The DC bus: ``C`` (F) behind a source of ``u_source`` (V) with ``r_source`` (ohm).

    ``C = 0`` is a stiff bus at ``u_source``. ``regenerative=False`` is a source that cannot take
    current back (a diode front end): braking energy then charges the capacitor.
    """

    u_source: float
    C: float = 0.0
    r_source: float = 0.05
    regenerative: bool = True

    def __post_init__(self):
        if not self.u_source > 0:
            raise ValueError(f"DcBus.u_source must be > 0, not {self.u_source!r}")
        if self.C < 0 or self.r_source <= 0:
            raise ValueError("DcBus.C must be >= 0 and r_source > 0")


class Plant:
    """PMSM + shaft + load + inverter + DC bus, advanced between gate edges.

    State (read freely): ``i_d``, ``i_q`` (A), ``theta`` (electrical angle, rad, wrapped to
    [-pi, pi)), ``w_m`` (mechanical speed, rad/s), ``theta_m`` (mechanical angle, unwrapped),
    ``u_dc`` (V), ``t`` (s). Accumulated since the start: ``energy_dc`` (J drawn from the bus),
``i_peak`` (A, the largest phase current at an edge; the current's extremes are at edges, up
to the back-EMF's curvature within an interval).
    """

    def __init__(self, motor: Motor, load: Load | None = None, bus: DcBus | None = None,
                 w_m: float = 0.0, theta: float = 0.0):
        self.motor = motor
        self.load = load if load is not None else Load()
        self.bus = bus if bus is not None else DcBus(motor.u_dc)
        self.J = motor.J + self.load.J
        self.i_d = 0.0
        self.i_q = 0.0
        self.theta = theta
        self.theta_m = theta / motor.n_p
        self.w_m = float(w_m)
        self.u_dc = self.bus.u_source
        self.t = 0.0
        self.energy_dc = 0.0
        self.i_peak = 0.0  # the largest phase-current magnitude |i_ab| at an edge so far
        self.speed_locked = False  # True: the shaft is held at w_m (a locked rotor or a dyno)

    # ---------------------------------------------------------------------------------------
    # what a sensor sees
    # ---------------------------------------------------------------------------------------

    def i_ab(self) -> complex:
        return complex(self.i_d, self.i_q) * cmath.exp(1j * self.theta)

    def phase_currents(self) -> tuple[float, float, float]:
        """``(i_a, i_b, i_c)`` (A), out of the inverter into the motor."""
        z = self.i_ab()
        return z.real, (z * _A2).real, (z * _A).real

    def torque(self, i_d: float | None = None, i_q: float | None = None) -> float:
        m = self.motor
        i_d = self.i_d if i_d is None else i_d
        i_q = self.i_q if i_q is None else i_q
        return 1.5 * m.n_p * (m.psi_f * i_q + (m.L_d - m.L_q) * i_d * i_q)

    def pole_voltages(self, upper: int, lower: int) -> tuple[float, float, float]:
        """Pole voltages (V, against the negative rail) for gate masks ``upper`` / ``lower``
        (bit ``i`` = leg ``i``), with the blanked legs resolved by the current's sign."""
        if upper & lower & 7:
            raise ShootThroughError(
                f"both gates on in legs {upper & lower:03b} at t = {self.t:.9f} s")
        currents = self.phase_currents()
        out = []
        for i in range(3):
            if (upper >> i) & 1:
                out.append(self.u_dc)
            elif (lower >> i) & 1:
                out.append(0.0)
            else:
                c = currents[i]
                out.append(self.u_dc if c < 0 else 0.0 if c > 0 else 0.5 * self.u_dc)
        return out[0], out[1], out[2]

    # ---------------------------------------------------------------------------------------
    # advancing
    # ---------------------------------------------------------------------------------------

    def advance(self, dt: float, upper: int, lower: int) -> None:
        """Hold the gates ``upper`` / ``lower`` (3-bit masks) for ``dt`` seconds."""
        if dt < 0:
            raise ValueError(f"dt must be >= 0, not {dt!r}")
        if dt == 0:
            return
        if not (upper | lower) & 7 and self.i_d == 0.0 and self.i_q == 0.0:
            self._advance_floating(dt)
            return
        p = self.pole_voltages(upper, lower)
        self._advance_poles(dt, p)

    def _advance_floating(self, dt: float) -> None:
        """Every gate off and no current: the terminals float and the currents stay zero as long
        as the line-to-line back-EMF peak stays below the bus (the diodes stay blocked)."""
        m = self.motor
        e_ll = math.sqrt(3) * m.psi_f * m.n_p * abs(self.w_m)
        if e_ll >= self.u_dc:
            raise NotImplementedError(
                f"gates off at {self.w_m * 30 / math.pi:.0f} rpm: the line-to-line back-EMF peak "
                f"({e_ll:.1f} V) exceeds the bus ({self.u_dc:.1f} V) and the diode bridge "
                "conducts; the plant does not model diode-bridge conduction from rest")
        w_m0 = self.w_m
        self.theta = (self.theta + m.n_p * w_m0 * dt + math.pi) % (2 * math.pi) - math.pi
        self.theta_m += w_m0 * dt
        if not self.speed_locked:
            self.w_m = w_m0 + dt * self._accel(0.0, w_m0)
        self._advance_bus(dt, 0.0)
        self.t += dt

    def _advance_poles(self, dt: float, p: tuple[float, float, float]) -> None:
        m = self.motor
        u_ab = (2.0 / 3.0) * (p[0] + _A * p[1] + _A2 * p[2])
        i_a0, i_b0, i_c0 = self.phase_currents()
        i_d0, i_q0, th0 = self.i_d, self.i_q, self.theta
        w_m0 = self.w_m
        # the currents are solved at the interval's mid-point speed (predicted from the torque
        # at its start), the speed then advanced with the interval's trapezoidal torque
        w_mid = w_m0
        if not self.speed_locked:
            w_mid += 0.5 * dt * self._accel(self.torque(i_d0, i_q0), w_m0)
        w = m.n_p * w_mid
        self.i_d, self.i_q = _currents_after(dt, i_d0, i_q0, u_ab, th0, w, m)
        tau = 0.5 * (self.torque(i_d0, i_q0) + self.torque())
        # advance the angle with the speed of the interval the currents were solved for
        self.theta = (th0 + w * dt + math.pi) % (2 * math.pi) - math.pi
        self.theta_m += w_mid * dt
        if not self.speed_locked:
            self.w_m = w_m0 + dt * self._accel(tau, w_mid)
        i_a1, i_b1, i_c1 = self.phase_currents()
        self.i_peak = max(self.i_peak, abs(i_a1), abs(i_b1), abs(i_c1))
        i_dc = 0.5 * (p[0] * (i_a0 + i_a1) + p[1] * (i_b0 + i_b1) + p[2] * (i_c0 + i_c1))
        i_dc /= self.u_dc if self.u_dc > 0 else 1.0
        self.energy_dc += i_dc * self.u_dc * dt
        self._advance_bus(dt, i_dc)
        self.t += dt

    def _accel(self, tau: float, w_m: float) -> float:
        return (tau - self.motor.B * w_m - self.load.torque(w_m)) / self.J

    def _advance_bus(self, dt: float, i_dc: float) -> None:
        bus = self.bus
        if bus.C == 0:
            return
        # the source through r_source, exact for a constant load current over the interval
        tau = bus.r_source * bus.C
        target = bus.u_source - bus.r_source * i_dc
        u1 = target + (self.u_dc - target) * math.exp(-dt / tau)
        if not bus.regenerative and u1 > bus.u_source:
            # the source blocks: the capacitor alone takes the inverter's current
            u1 = max(self.u_dc, bus.u_source) - i_dc * dt / bus.C
            u1 = max(u1, min(target, bus.u_source))
        self.u_dc = u1


def _currents_after(dt, i_d, i_q, u_ab, theta, w, m: Motor):
    """``(i_d, i_q)`` after ``dt`` with the stationary voltage ``u_ab`` held and the electrical
    speed ``w`` constant: ``x(t) = E x0 + Re[(A + jw)^-1 (E - e^{-jwt}) c] + A^-1 (E - I) g``,
    ``E = e^{At}``, ``c = (U/L_d, -jU/L_q)``, ``U = u_ab e^{-j theta}``, ``g = (0, -w psi/L_q)``."""
    R, Ld, Lq, psi = m.R_s, m.L_d, m.L_q, m.psi_f
    a, b, c, d = -R / Ld, w * Lq / Ld, -w * Ld / Lq, -R / Lq
    mu = 0.5 * (a + d)
    h = 0.5 * (a - d)
    s = cmath.sqrt(h * h + b * c)
    em = math.exp(mu * dt)
    st = s * dt
    if abs(st) < 1e-9:
        ch, sh = 1.0, dt
    else:
        ch, sh = cmath.cosh(st), cmath.sinh(st) / s
    e11 = em * (ch + sh * h)
    e22 = em * (ch - sh * h)
    e12 = em * sh * b
    e21 = em * sh * c
    # rotating input
    U = u_ab * cmath.exp(-1j * theta)
    c1, c2 = U / Ld, -1j * U / Lq
    rot = cmath.exp(-1j * w * dt)
    y1 = e11 * c1 + e12 * c2 - rot * c1
    y2 = e21 * c1 + e22 * c2 - rot * c2
    m11, m12, m21, m22 = a + 1j * w, b, c, d + 1j * w
    det_m = m11 * m22 - m12 * m21
    p1 = (m22 * y1 - m12 * y2) / det_m
    p2 = (-m21 * y1 + m11 * y2) / det_m
    # constant back-EMF input (q axis only)
    g2 = -w * psi / Lq
    f1 = e12 * g2
    f2 = (e22 - 1) * g2
    det_a = a * d - b * c
    q1 = (d * f1 - b * f2) / det_a
    q2 = (-c * f1 + a * f2) / det_a
    i_d1 = e11 * i_d + e12 * i_q + p1 + q1
    i_q1 = e21 * i_d + e22 * i_q + p2 + q2
    return i_d1.real, i_q1.real
