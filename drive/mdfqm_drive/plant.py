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
- Inverter leg ``i``: upper gate on -> pole at Vdc, lower gate on -> pole at 0. Both off (a
  blanked leg): its diodes decide. The upper diode conducts a current into the leg (``i_i < 0``,
  pole at Vdc), the lower one a current out of it (``i_i > 0``, pole at 0); with neither
  forward-biased the leg carries no current and its pole floats with the motor's terminal.
  Both gates on is a shoot-through: :class:`ShootThroughError` is raised.

Exactness
---------
Between two edges the driven pole voltages are constant. With the electrical speed held at its
value at the start of the interval, the current equations are linear with a rotating input, and
:meth:`Plant.advance` solves them in closed form (the 2x2 matrix exponential, no step size).
The currents are solved at the interval's mid-point speed (predicted from the torque at its
start); the speed, the angle and the bus are then advanced with the trapezoidal mean of the
torque and of the DC current over the interval (second order in the interval, which is at most
one update, against a mechanical time constant of tens of milliseconds). The inner loop is pure
Python floats, the fastest for 2x2 algebra.

Diodes
------
The fast path: every leg driven, or each blanked leg's current of one sign at both ends of an
interval no longer than a sub-step (a dead time with current flowing): the closed form above with
the blanked poles at the rails of their currents' signs. Otherwise the interval is cut into
sub-steps (at most 1/400 of an electrical period and 25 us; with a capacitor bus also short
enough for the bus to move by 0.2 % at most) and at every sub-step the conduction state is found
(each blanked leg with no current: blocked, or starting through the diode whose voltage turns
forward; the consistent choice, as an ideal diode's complementarity asks). Within a sub-step:

- no leg blocked: the closed form;
- one leg blocked: the other two carry one current and its negative (the star point floats); a
  scalar equation along that direction, one Runge-Kutta (RK4) step (the blocked pole is whatever
  keeps its current at zero: this also covers a salient rotor, whose inductance along that
  direction turns with the rotor);
- two or three blocked: no current.

An event ends a sub-step early: a diode's current reaching zero, or a blocked leg's pole leaving
the rails (its diode turning forward); the instant is found on the same sub-step solution (regula
falsi, to 1e-12 s or to just past the event: a current 1e-9 of Vdc/R_s beyond zero, a pole 1e-9
of Vdc beyond its rail), then the conduction state is found again.
"""

from __future__ import annotations

import cmath
import itertools
import math
from dataclasses import dataclass

from .motors import Load, Motor

__all__ = ["DcBus", "Plant", "ShootThroughError"]

_A = cmath.exp(2j * math.pi / 3)
_A2 = _A * _A
_PHASE = (1.0 + 0j, _A, _A2)          # phase k's axis, a^k
_PHASE_CONJ = (1.0 + 0j, _A2, _A)     # its conjugate: phase k's current is Re(i_ab a^-k)
_ANGLE = (0.0, 2 * math.pi / 3, 4 * math.pi / 3)
_SIN_120 = math.sin(2 * math.pi / 3)

_STEP_MAX = 25e-6          # s, the longest sub-step while a diode conducts or blocks
_STEPS_PER_PERIOD = 400    # sub-steps per electrical period at least
_BUS_STEP = 2e-3           # a capacitor bus moves by at most this fraction in a sub-step
_T_EVENT = 1e-12           # s, the root finder's resolution of a conduction event
_EVENT_PAST = 1e-9         # how far past its threshold an event may be found (relative)
_V_TOL = 1e-9              # of Vdc: a blocked pole this far beyond its rail is still blocked
_I_TOL = 1e-9              # of Vdc / R_s: a current this small is no current


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
    ``i_peak`` (A, the largest phase current at an edge or at the end of a diode sub-step; the
    current's extremes are there, up to the back-EMF's curvature within an interval).
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
        self.i_peak = 0.0  # the largest phase current at an edge (or a diode sub-step's end)
        self.speed_locked = False  # True: the shaft is held at w_m (a locked rotor or a dyno)
        self._i_eps = _I_TOL * motor.u_dc / motor.R_s

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
        (bit ``i`` = leg ``i``), a blanked leg at the rail its current's diode connects (Vdc/2
        with no current: its pole floats, and :meth:`advance` finds which diode, if any, turns
        on)."""
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
        p = self.pole_voltages(upper, lower)
        blanked = ~(upper | lower) & 7
        currents = _phases(self.i_d, self.i_q, self.theta)
        if not blanked:
            self._advance_poles(dt, p, currents)
            return
        if blanked == 7 and self.i_d == 0.0 and self.i_q == 0.0 and self._stays_blocked(dt):
            state = (0.0, 0.0, self.theta, self.theta_m, self.w_m, self.u_dc)
            self._commit(self._trial_open(state, dt), dt)
            return
        if dt <= self._step_max():
            # a dead time with current flowing: the diodes of the currents' signs, checked at
            # the end of the interval (a sub-step is too short for a current to cross zero and
            # come back)
            keep = self._freewheeling(blanked, currents)
            if keep:
                failed = self._advance_poles(dt, p, currents, keep)
                if failed is None:
                    return
                # a current reached zero: the events start from this attempt
                self._advance_events(dt, upper, lower, failed)
                return
        self._advance_events(dt, upper, lower)

    def _step_max(self) -> float:
        """The longest sub-step: 1/400 of an electrical period, 25 us at most."""
        w_e = abs(self.motor.n_p * self.w_m)
        if w_e * _STEP_MAX * _STEPS_PER_PERIOD > 2 * math.pi:
            return 2 * math.pi / (w_e * _STEPS_PER_PERIOD)
        return _STEP_MAX

    def _freewheeling(self, blanked: int, currents) -> list | None:
        """``[(leg, sign)]`` of the blanked legs, each with a current clearly of one sign; None
        if a blanked leg carries (next to) no current."""
        keep = []
        for k in range(3):
            if (blanked >> k) & 1:
                c = currents[k]
                if c > self._i_eps:
                    keep.append((k, 1))
                elif c < -self._i_eps:
                    keep.append((k, -1))
                else:
                    return None
        return keep

    def _advance_poles(self, dt: float, p: tuple[float, float, float], currents,
                       keep=()) -> tuple | None:
        """Advance with the pole voltages ``p`` held from the phase currents ``currents``; with
        ``keep`` (``[(leg, sign)]``), only if each of those legs' currents still has that sign
        at the end. Returns None if it advanced; else, unchanged, the trial (see
        :meth:`_trial`) of the whole interval."""
        m = self.motor
        u_ab = (2.0 / 3.0) * (p[0] + _A * p[1] + _A2 * p[2])
        i_d0, i_q0, th0 = self.i_d, self.i_q, self.theta
        w_m0 = self.w_m
        # the currents are solved at the interval's mid-point speed (predicted from the torque
        # at its start), the speed then advanced with the interval's trapezoidal torque
        w_mid = w_m0
        if not self.speed_locked:
            w_mid += 0.5 * dt * self._accel(self.torque(i_d0, i_q0), w_m0)
        w = m.n_p * w_mid
        i_d1, i_q1 = _currents_after(dt, i_d0, i_q0, u_ab, th0, w, m)
        # advance the angle with the speed of the interval the currents were solved for
        th1 = th0 + w * dt
        end = _phases(i_d1, i_q1, th1)
        for k, sign in keep:
            if sign * end[k] <= self._i_eps:
                state = (i_d0, i_q0, th0, self.theta_m, w_m0, self.u_dc)
                p_dot_i = 0.5 * (p[0] * (currents[0] + end[0]) + p[1] * (currents[1] + end[1])
                                 + p[2] * (currents[2] + end[2]))
                return self._finish(state, dt, i_d1, i_q1, w_mid, self.torque(i_d0, i_q0),
                                    p_dot_i)
        self.i_d, self.i_q = i_d1, i_q1
        tau = 0.5 * (self.torque(i_d0, i_q0) + self.torque())
        self.theta = (th1 + math.pi) % (2 * math.pi) - math.pi
        self.theta_m += w_mid * dt
        if not self.speed_locked:
            self.w_m = w_m0 + dt * self._accel(tau, w_mid)
        i_a0, i_b0, i_c0 = currents
        i_a1, i_b1, i_c1 = end
        self.i_peak = max(self.i_peak, abs(i_a1), abs(i_b1), abs(i_c1))
        i_dc = 0.5 * (p[0] * (i_a0 + i_a1) + p[1] * (i_b0 + i_b1) + p[2] * (i_c0 + i_c1))
        i_dc /= self.u_dc if self.u_dc > 0 else 1.0
        self.energy_dc += i_dc * self.u_dc * dt
        self._advance_bus(dt, i_dc)
        self.t += dt
        return None

    def _accel(self, tau: float, w_m: float) -> float:
        return (tau - self.motor.B * w_m - self.load.torque(w_m)) / self.J

    def _advance_bus(self, dt: float, i_dc: float) -> None:
        self.u_dc = self._bus_after(self.u_dc, dt, i_dc)

    def _bus_after(self, u_dc: float, dt: float, i_dc: float) -> float:
        bus = self.bus
        if bus.C == 0:
            return u_dc
        # the source through r_source, exact for a constant load current over the interval
        tau = bus.r_source * bus.C
        target = bus.u_source - bus.r_source * i_dc
        u1 = target + (u_dc - target) * math.exp(-dt / tau)
        if not bus.regenerative and u1 > bus.u_source:
            # the source blocks: the capacitor alone takes the inverter's current
            u1 = max(u_dc, bus.u_source) - i_dc * dt / bus.C
            u1 = max(u1, min(target, bus.u_source))
        return u1

    # ---------------------------------------------------------------------------------------
    # diode conduction: sub-steps between conduction events
    # ---------------------------------------------------------------------------------------
    #
    # A conduction state is ``modes``: per leg 1 (pole at Vdc: upper switch or diode), 0 (pole
    # at 0) or None (blocked: no current, the pole floats); and ``diodes``: {leg: sign} for the
    # legs conducting through a diode, whose current must keep that sign (+1 lower, -1 upper).
    # A state tuple is ``(i_d, i_q, theta, theta_m, w_m, u_dc)``; a trial appends the energy
    # drawn from the bus.

    def _advance_events(self, dt: float, upper: int, lower: int, first=None) -> None:
        """Advance through the conduction events; ``first``: the trial of the whole interval
        in the conduction state of the currents' signs, if already solved."""
        remaining = dt
        stalls = 0
        while remaining > 0:
            modes, diodes = self._conduction(upper, lower)
            h = min(remaining, self._substep(modes, remaining))
            state = (self.i_d, self.i_q, self.theta, self.theta_m, self.w_m, self.u_dc)
            reuse = first is not None and h == dt
            trial = first if reuse else self._trial(state, modes, h)
            first = None
            late = self._event_value(trial, modes, diodes)
            if late > 0:
                h, trial = self._find_event(state, modes, diodes, h, trial, late)
                # a state that events at once again and again would never end: refuse
                stalls = stalls + 1 if h <= 4 * _T_EVENT else 0
                if stalls > 50:
                    raise RuntimeError(f"diode conduction does not advance at t = {self.t} s")
            self._commit(trial, h)
            remaining = remaining - h if h < remaining else 0.0
            self._stop_reversed(modes, diodes)

    def _substep(self, modes, remaining: float) -> float:
        if modes.count(None) == 3 and self._stays_blocked(remaining):
            return remaining
        h = self._step_max()
        i = abs(complex(self.i_d, self.i_q))
        if self.bus.C > 0 and i > 0:
            # the bus held over a sub-step: let it move by 0.2 % at most
            h = min(h, _BUS_STEP * self.bus.C * self.u_dc / i)
        return h

    def _stays_blocked(self, dt: float) -> bool:
        """Every leg blocked: whether the line-to-line back-EMF peak stays below the bus for
        ``dt`` (then nothing conducts)."""
        m = self.motor
        w_end = self.w_m if self.speed_locked else self.w_m + dt * self._accel(0.0, self.w_m)
        e_ll = math.sqrt(3) * m.n_p * abs(m.psi_f) * max(abs(self.w_m), abs(w_end))
        u_min = min(self.u_dc, self.bus.u_source) if self.bus.C > 0 else self.u_dc
        return e_ll < u_min * (1 - 1e-6)

    def _conduction(self, upper: int, lower: int):
        """The consistent conduction state now: driven legs, blanked legs by their currents'
        signs, and for each blanked leg without current the choice (blocked, or starting through
        one of its diodes) that an ideal diode allows: a blocked pole within the rails, a
        starting current growing in its diode's direction. Fewest starting legs first."""
        currents = _phases(self.i_d, self.i_q, self.theta)
        eps = self._i_eps
        modes = [None, None, None]
        diodes = {}
        zero = []
        for k in range(3):
            bit = 1 << k
            if upper & bit:
                modes[k] = 1
            elif lower & bit:
                modes[k] = 0
            elif currents[k] > eps:
                modes[k], diodes[k] = 0, 1
            elif currents[k] < -eps:
                modes[k], diodes[k] = 1, -1
            else:
                zero.append(k)
        if not zero:
            return modes, diodes
        if sum(abs(c) <= 2 * eps for c in currents) >= 2:
            # two legs without current: by Kirchhoff none has any
            self.i_d = self.i_q = 0.0
            blanked = [k for k in range(3) if not (upper | lower) & (1 << k)]
            zero = blanked
            for k in blanked:
                modes[k] = None
                diodes.pop(k, None)
        else:
            self._zero_leg(zero[0])
        best = None
        for combo in _CHOICES[len(zero)]:
            cand = list(modes)
            cand_diodes = dict(diodes)
            started = {}
            for k, mode in zip(zero, combo, strict=True):
                cand[k] = mode
                if mode is not None:
                    started[k] = cand_diodes[k] = 1 if mode == 0 else -1
            bad = self._inconsistency(cand, started)
            if bad <= 0:
                return cand, cand_diodes
            if best is None or bad < best[0]:
                best = (bad, cand, cand_diodes)
        return best[1], best[2]

    def _inconsistency(self, modes, started) -> float:
        """<= 0 if ``modes`` is a consistent conduction state now (every blocked pole within
        the rails, every starting current growing in its diode's direction); else how far off
        (relative: volts over Vdc, A/s over Vdc/L)."""
        state = (self.i_d, self.i_q, self.theta, self.theta_m, self.w_m, self.u_dc)
        margin, rates = self._blocked_margin(state, modes)
        bad = margin / self.u_dc - _V_TOL
        if started:
            if rates is None:
                return max(bad, 1.0)  # a lone diode cannot start a current
            scale = self.u_dc / min(self.motor.L_d, self.motor.L_q)
            for k, sign in started.items():
                growth = sign * rates[k] / scale
                bad = max(bad, -growth if growth > 0 else _V_TOL - growth)
        return bad

    def _blocked_margin(self, state, modes):
        """How far (V) the most forward-biased blocked leg's pole lies beyond its rail (-inf if
        none is blocked), and the phase currents' rates of change (A/s) if current can flow
        (two or three legs clamped), else None."""
        i_d, i_q, theta, _, w_m, u_dc = state
        m = self.motor
        w = m.n_p * w_m
        clamped = [k for k in range(3) if modes[k] is not None]
        p = [u_dc if mode == 1 else 0.0 for mode in modes]
        if len(clamped) == 3:
            u = (2.0 / 3.0) * (p[0] + _A * p[1] + _A2 * p[2]) * cmath.exp(-1j * theta)
            did = (u.real - m.R_s * i_d + w * m.L_q * i_q) / m.L_d
            diq = (u.imag - m.R_s * i_q - w * m.L_d * i_d - w * m.psi_f) / m.L_q
            d_ab = (complex(did, diq) + 1j * w * complex(i_d, i_q)) * cmath.exp(1j * theta)
            return -math.inf, tuple((d_ab * _PHASE_CONJ[k]).real for k in range(3))
        if len(clamped) == 2:
            k = modes.index(None)
            x = (complex(i_d, i_q) * _axis(theta, k).conjugate()).imag
            x_rate, p_k = self._pair_rates(x, theta, w, k, _known_voltage(p, k))
            rates = tuple(0.0 if j == k else -x_rate * math.sin(_ANGLE[k] - _ANGLE[j])
                          for j in range(3))
            return max(p_k - u_dc, -p_k), rates
        # no current: a blocked terminal sits at the star point plus its back-EMF
        emf = [-w * m.psi_f * math.sin(theta - _ANGLE[k]) for k in range(3)]
        if clamped:
            c = clamped[0]
            star = p[c] - emf[c]
            return max(max(star + emf[k] - u_dc, -star - emf[k])
                       for k in range(3) if k != c), None
        return max(emf) - min(emf) - u_dc, None

    def _pair_rates(self, x, theta, w, k, u_known):
        """Leg ``k`` blocked, the other two carrying ``i_ab = j a^k x``, the other two poles'
        voltage ``u_known`` (:func:`_known_voltage`): ``(dx/dt, pole k)``.

        In rotor coordinates the current lies along ``j n``, ``n = e^(-j (theta - 2 pi k / 3))``
        (phase k's axis), which turns at ``-w``; the blocked pole enters the voltage as
        ``(2/3) p_k n``, and is whatever keeps the current on that line:
        ``Re(di/dt conj(n)) = x w``; then ``dx/dt = Im(di/dt conj(n))``."""
        m = self.motor
        rotor = cmath.exp(-1j * theta)
        n = rotor * _PHASE[k]
        u0 = u_known * rotor
        i = 1j * n * x
        f0 = complex((u0.real - m.R_s * i.real + w * m.L_q * i.imag) / m.L_d,
                     (u0.imag - m.R_s * i.imag - w * m.L_d * i.real - w * m.psi_f) / m.L_q)
        f1 = (2.0 / 3.0) * complex(n.real / m.L_d, n.imag / m.L_q)
        nc = n.conjugate()
        p_k = (x * w - (f0 * nc).real) / (f1 * nc).real
        return ((f0 + p_k * f1) * nc).imag, p_k

    def _trial(self, state, modes, t):
        """The state after ``t`` in conduction state ``modes`` (nothing is changed)."""
        clamped = 3 - modes.count(None)
        if clamped == 3:
            return self._trial_clamped(state, modes, t)
        if clamped == 2:
            return self._trial_pair(state, modes, t)
        return self._trial_open(state, t)

    def _mid_speed(self, w_m0, tau0, t):
        if self.speed_locked:
            return w_m0
        return w_m0 + 0.5 * t * self._accel(tau0, w_m0)

    def _finish(self, state, t, i_d1, i_q1, w_mid, tau0, p_dot_i):
        """The trial's end: angle, speed (trapezoidal torque), bus (trapezoidal DC current)."""
        _, _, th0, thm0, w_m0, u0 = state
        tau = 0.5 * (tau0 + self.torque(i_d1, i_q1))
        w_m1 = w_m0 if self.speed_locked else w_m0 + t * self._accel(tau, w_mid)
        theta = (th0 + self.motor.n_p * w_mid * t + math.pi) % (2 * math.pi) - math.pi
        i_dc = p_dot_i / u0
        return (i_d1, i_q1, theta, thm0 + w_mid * t, w_m1, self._bus_after(u0, t, i_dc),
                i_dc * u0 * t)

    def _trial_clamped(self, state, modes, t):
        i_d0, i_q0, th0, _, w_m0, u0 = state
        p = [u0 if mode == 1 else 0.0 for mode in modes]
        u_ab = (2.0 / 3.0) * (p[0] + _A * p[1] + _A2 * p[2])
        tau0 = self.torque(i_d0, i_q0)
        w_mid = self._mid_speed(w_m0, tau0, t)
        w = self.motor.n_p * w_mid
        i_d1, i_q1 = _currents_after(t, i_d0, i_q0, u_ab, th0, w, self.motor)
        c0 = _phases(i_d0, i_q0, th0)
        c1 = _phases(i_d1, i_q1, th0 + w * t)
        p_dot_i = 0.5 * (p[0] * (c0[0] + c1[0]) + p[1] * (c0[1] + c1[1]) + p[2] * (c0[2] + c1[2]))
        return self._finish(state, t, i_d1, i_q1, w_mid, tau0, p_dot_i)

    def _trial_pair(self, state, modes, t):
        i_d0, i_q0, th0, _, w_m0, u0 = state
        k = modes.index(None)
        p = [u0 if mode == 1 else 0.0 for mode in modes]
        u_known = _known_voltage(p, k)
        tau0 = self.torque(i_d0, i_q0)
        w_mid = self._mid_speed(w_m0, tau0, t)
        w = self.motor.n_p * w_mid
        x0 = (complex(i_d0, i_q0) * _axis(th0, k).conjugate()).imag

        def rate(tt, x):
            return self._pair_rates(x, th0 + w * tt, w, k, u_known)[0]

        k1 = rate(0.0, x0)
        k2 = rate(0.5 * t, x0 + 0.5 * t * k1)
        k3 = rate(0.5 * t, x0 + 0.5 * t * k2)
        k4 = rate(t, x0 + t * k3)
        x1 = x0 + t * (k1 + 2 * k2 + 2 * k3 + k4) / 6
        i1 = 1j * _axis(th0 + w * t, k) * x1
        # leg j of the two carries -x sin(phi_k - phi_j): sin(-2 pi / 3) for the next leg
        # after k, sin(2 pi / 3) for the one before
        p_dot_i = 0.5 * (x0 + x1) * _SIN_120 * (p[(k + 1) % 3] - p[(k + 2) % 3])
        return self._finish(state, t, i1.real, i1.imag, w_mid, tau0, p_dot_i)

    def _trial_open(self, state, t):
        _, _, th0, thm0, w_m0, u0 = state
        w_m1 = w_m0 if self.speed_locked else w_m0 + t * self._accel(0.0, w_m0)
        theta = (th0 + self.motor.n_p * w_m0 * t + math.pi) % (2 * math.pi) - math.pi
        return (0.0, 0.0, theta, thm0 + w_m0 * t, w_m1, self._bus_after(u0, t, 0.0), 0.0)

    def _event_value(self, trial, modes, diodes) -> float:
        """> 0 if, at ``trial``'s end, a diode's current has reversed or a blocked pole lies
        beyond a rail: the largest such excess (relative: over Vdc / R_s, over Vdc)."""
        value = -math.inf
        if diodes:
            currents = _phases(trial[0], trial[1], trial[2])
            scale = self._i_eps / _I_TOL
            for k, sign in diodes.items():
                value = max(value, -sign * currents[k] / scale - _I_TOL)
        if None in modes:
            margin, _ = self._blocked_margin(trial[:6], modes)
            value = max(value, margin / trial[5] - 2 * _V_TOL)
        return value

    def _find_event(self, state, modes, diodes, h, trial, late):
        """The first instant in ``(0, h]`` at which :meth:`_event_value` turns positive, and the
        trial there: regula falsi with the Illinois modification (a bracket ``[early, late]``;
        superlinear on these smooth functions), ending just past the event."""
        start = (*state, 0.0)
        lo, f_lo = 0.0, min(self._event_value(start, modes, diodes), 0.0)
        hi, f_hi = h, late
        side = 0
        for _ in range(100):
            if hi - lo <= _T_EVENT or late <= _EVENT_PAST:
                break
            t = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
            if not lo < t < hi:
                t = 0.5 * (lo + hi)
            at = self._trial(state, modes, t)
            value = self._event_value(at, modes, diodes)
            if value > 0:
                hi, f_hi, trial, late = t, value, at, value
                if side == 1:
                    f_lo *= 0.5
                side = 1
            else:
                lo, f_lo = t, value
                if side == -1:
                    f_hi *= 0.5
                side = -1
        return hi, trial

    def _commit(self, trial, t):
        self.i_d, self.i_q, self.theta, self.theta_m, self.w_m, self.u_dc, energy = trial
        self.energy_dc += energy
        self.t += t
        self.i_peak = max(self.i_peak, *(abs(c) for c in self.phase_currents()))

    def _stop_reversed(self, modes, diodes):
        """A diode whose current reached zero blocks: its leg's current is set to zero (all
        currents, if another leg is blocked or more than one diode stopped)."""
        currents = _phases(self.i_d, self.i_q, self.theta)
        stopped = [k for k, sign in diodes.items() if sign * currents[k] < -self._i_eps]
        if not stopped:
            return
        if len(stopped) > 1 or None in modes:
            self.i_d = self.i_q = 0.0
        else:
            self._zero_leg(stopped[0])

    def _zero_leg(self, k):
        """Remove leg ``k``'s current (the space vector's component along its axis)."""
        z = complex(self.i_d, self.i_q) * cmath.exp(1j * self.theta)
        z -= (z * _PHASE_CONJ[k]).real * _PHASE[k]
        z *= cmath.exp(-1j * self.theta)
        self.i_d, self.i_q = z.real, z.imag


#: the choices for 1, 2, 3 blanked legs without current, fewest starting legs first
_CHOICES = {n: sorted(itertools.product((None, 0, 1), repeat=n),
                      key=lambda combo: sum(mode is not None for mode in combo))
            for n in (1, 2, 3)}


def _phases(i_d, i_q, theta):
    z = complex(i_d, i_q) * cmath.exp(1j * theta)
    return z.real, (z * _A2).real, (z * _A).real


def _known_voltage(p, k):
    """The stationary voltage vector of the poles other than ``k``: ``(2/3) sum p_j a^j``."""
    return (2.0 / 3.0) * (p[(k + 1) % 3] * _PHASE[(k + 1) % 3]
                          + p[(k + 2) % 3] * _PHASE[(k + 2) % 3])


def _axis(theta, k):
    """Phase ``k``'s axis in rotor coordinates."""
    return cmath.exp(-1j * (theta - _ANGLE[k]))


def _currents_after(dt, i_d, i_q, u_ab, theta, w, m: Motor):
    """``(i_d, i_q)`` after ``dt`` with the stationary voltage ``u_ab`` held and the electrical
    speed ``w`` constant: ``x(t) = E x0 + Re[(A + jw)^-1 (E - e^{-jwt}) c] + A^-1 (E - I) g``,
    ``E = e^{At}``, ``c = (U/L_d, -jU/L_q)``, ``U = u_ab e^{-j theta}``, ``g = (0, -w psi/L_q)``.

    With ``L_d = L_q = L`` (a surface motor) the system is one complex equation,
    ``L di/dt = U e^{-jwt} - (R + jwL) i - jw psi``, whose solution is
    ``i = e^{-(R/L + jw) t} (i_0 - i_c - U/R) + i_c + (U/R) e^{-jwt}``, ``i_c = -jw psi /
    (R + jwL)``: the same numbers (to 1e-13) at 2.5x the speed."""
    R, Ld, Lq, psi = m.R_s, m.L_d, m.L_q, m.psi_f
    if Ld == Lq:
        i_c = -1j * w * psi / complex(R, w * Ld)
        u = u_ab * cmath.exp(-1j * theta) / R
        z = (cmath.exp(complex(-R / Ld, -w) * dt) * (complex(i_d, i_q) - i_c - u) + i_c
             + u * cmath.exp(-1j * w * dt))
        return z.real, z.imag
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
