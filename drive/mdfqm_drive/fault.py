"""Fault reactions of the inverter, the plant alone (no IP, no controller): the physics a run
through the gateware is to reproduce.

From a running state (the shaft held at a speed by the load, a dyno; the currents ``i_d0``,
``i_q0`` of a steady operating point), every gate goes off for a dead time, then the reaction:

- ``"off"``: every gate stays off. Above the speed at which the line-to-line back-EMF peak
  reaches the bus (:func:`threshold_rpm`), the diodes form an uncontrolled rectifier: current
  flows into the bus (a stiff bus takes it; a capacitor behind a source that cannot take current
  back charges up) and the motor is braked. Below it the currents die out and stay zero.
- ``"asc"``: an active short circuit, the three lower switches on. The currents settle at the
  shorted machine's steady state (``u_d = u_q = 0``), which tends to ``-psi_f / L_d`` on the d
  axis when ``w L`` dominates ``R``.

``python -m mdfqm_drive.fault`` prints the figures docs/drive.md quotes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .motors import MOTORS, Motor
from .plant import DcBus, Plant

__all__ = ["DOC_MOTOR", "DOC_RATIO", "REACTIONS", "FaultResult", "documented_cases",
           "documented_table", "fault_case", "main", "rpm_for_emf_ratio",
           "short_circuit_current", "threshold_rpm"]

#: the gates (upper, lower) each reaction holds
REACTIONS = {"off": (0b000, 0b000), "asc": (0b000, 0b111)}

RPM = 2 * math.pi / 60


def threshold_rpm(motor: Motor, u_dc: float | None = None) -> float:
    """The speed (rpm) at which the line-to-line back-EMF peak ``sqrt(3) n_p psi_f w_m`` equals
    the bus ``u_dc`` (default: the motor's nominal bus)."""
    u_dc = motor.u_dc if u_dc is None else u_dc
    return u_dc / (math.sqrt(3) * motor.n_p * motor.psi_f) / RPM


def rpm_for_emf_ratio(motor: Motor, ratio: float, u_dc: float | None = None) -> float:
    """The speed (rpm) at which the line-to-line back-EMF peak is ``ratio`` times the bus."""
    return ratio * threshold_rpm(motor, u_dc)


@dataclass(frozen=True)
class FaultResult:
    """What :func:`fault_case` measures. Means are over ``window`` (s): the last whole
    electrical periods, at most half the run. Signs: ``i_dc_mean`` is the current out of the
    bus's positive rail (negative: the motor charges the bus), ``torque_mean`` the motor's
    electromagnetic torque (negative: braking at a positive speed)."""

    reaction: str
    rpm: float
    u_dc0: float           # V, the bus at the start
    u_dc_end: float        # V, at the end
    u_dc_max: float        # V, the highest sampled
    i_dc_mean: float       # A, over the window
    torque_mean: float     # Nm, over the window
    i_peak: float          # A, the largest phase current over the run (its start included)
    i_peak_window: float   # A, the largest over the window
    i_d_mean: float        # A, over the window
    i_q_mean: float
    i_d_end: float         # A, at the end
    i_q_end: float
    psi_over_ld: float     # A, psi_f / L_d: the high-speed short-circuit current
    window: float          # s


def fault_case(motor: Motor, speed_rpm: float, u_dc: float | None = None,
               reaction: str = "off", duration: float = 0.1, i_d0: float = 0.0,
               i_q0: float = 0.0, dead_time: float = 2e-6, bus_capacitance: float = 0.0,
               regenerative: bool = False, theta0: float = 0.0,
               sample: float = 1e-5) -> FaultResult:
    """Hold ``motor`` at ``speed_rpm`` with the currents ``(i_d0, i_q0)`` at the electrical
    angle ``theta0``; all gates off for ``dead_time``, then ``reaction`` (a key of
    :data:`REACTIONS`) for the rest of ``duration`` seconds. The bus: ``u_dc`` (default the
    motor's), stiff (``bus_capacitance`` 0) or a capacitor behind a source that can
    (``regenerative``) or cannot take current back. Sampled every ``sample`` seconds."""
    if reaction not in REACTIONS:
        raise ValueError(f"reaction must be one of {sorted(REACTIONS)}, not {reaction!r}")
    u_dc = motor.u_dc if u_dc is None else u_dc
    bus = DcBus(u_dc, C=bus_capacitance, regenerative=regenerative)
    plant = Plant(motor, bus=bus, w_m=speed_rpm * RPM, theta=theta0)
    plant.speed_locked = True
    plant.i_d, plant.i_q = i_d0, i_q0
    period = 2 * math.pi / (motor.n_p * abs(speed_rpm) * RPM) if speed_rpm else duration
    periods = max(1, math.floor(0.5 * duration / period))
    window = min(periods * period, duration)
    upper, lower = REACTIONS[reaction]
    steps = max(2, round(duration / sample))  # a window needs a sample after the first
    dt = duration / steps
    # the window is samples start..steps: whole periods, after the first sample at least
    start = max(1, steps - max(1, round(window / dt)))
    window = (steps - start) * dt
    i_peak = max(abs(c) for c in plant.phase_currents())
    plant.advance(min(dead_time, dt), 0, 0)
    plant.advance(dt - min(dead_time, dt), upper, lower)
    i_peak = max(i_peak, *(abs(c) for c in plant.phase_currents()))
    u_max = plant.u_dc
    torque = u_int = i_d_int = i_q_int = 0.0
    i_peak_window = 0.0
    prev_i = plant.i_d, plant.i_q
    energy0 = plant.energy_dc
    prev_tau, prev_u = plant.torque(), plant.u_dc
    for n in range(1, steps):
        if n == start:
            energy0 = plant.energy_dc
        plant.advance(dt, upper, lower)
        i_peak = max(i_peak, *(abs(c) for c in plant.phase_currents()))
        u_max = max(u_max, plant.u_dc)
        tau, u = plant.torque(), plant.u_dc
        if n >= start:
            torque += 0.5 * (prev_tau + tau) * dt
            u_int += 0.5 * (prev_u + u) * dt
            i_d_int += 0.5 * (prev_i[0] + plant.i_d) * dt
            i_q_int += 0.5 * (prev_i[1] + plant.i_q) * dt
            i_peak_window = max(i_peak_window, *(abs(c) for c in plant.phase_currents()))
        prev_tau, prev_u, prev_i = tau, u, (plant.i_d, plant.i_q)
    return FaultResult(reaction=reaction, rpm=speed_rpm, u_dc0=u_dc, u_dc_end=plant.u_dc,
                       u_dc_max=u_max, i_dc_mean=(plant.energy_dc - energy0) / u_int,
                       torque_mean=torque / window, i_peak=max(i_peak, plant.i_peak),
                       i_peak_window=i_peak_window, i_d_mean=i_d_int / window,
                       i_q_mean=i_q_int / window,
                       i_d_end=plant.i_d, i_q_end=plant.i_q,
                       psi_over_ld=motor.psi_f / motor.L_d, window=window)


def short_circuit_current(motor: Motor, speed_rpm: float) -> complex:
    """The shorted machine's steady state ``i_d + j i_q`` (A) at ``speed_rpm``: from
    ``0 = R i_d - w L_q i_q`` and ``0 = R i_q + w L_d i_d + w psi_f``,
    ``i_d = -w^2 L_q psi_f / D``, ``i_q = -w R psi_f / D``, ``D = R^2 + w^2 L_d L_q``; ``i_d``
    tends to ``-psi_f / L_d`` as ``w`` grows."""
    w = motor.n_p * speed_rpm * RPM
    d = motor.R_s ** 2 + w * w * motor.L_d * motor.L_q
    return complex(-w * w * motor.L_q * motor.psi_f / d, -w * motor.R_s * motor.psi_f / d)


#: the motor and speed docs/drive.md quotes: the 5x-rewound Hurst motor at 1.3x its threshold
#: speed on its 24 V bus, from rated torque (``i_q`` = the rated current)
DOC_MOTOR = "hurst_x5"
DOC_RATIO = 1.3


def documented_cases() -> dict:
    """The runs docs/drive.md quotes, by row label."""
    motor = MOTORS[DOC_MOTOR]
    rpm = rpm_for_emf_ratio(motor, DOC_RATIO)
    i_q0 = motor.i_rated
    return {
        "all gates off, stiff bus": fault_case(motor, rpm, reaction="off", duration=0.1,
                                               i_q0=i_q0),
        "all gates off, 100 uF bus, source not regenerative": fault_case(
            motor, rpm, reaction="off", duration=0.2, i_q0=i_q0, bus_capacitance=100e-6),
        "active short circuit (three lower switches)": fault_case(
            motor, rpm, reaction="asc", duration=0.1, i_q0=i_q0),
    }


def _f(x: float) -> str:
    """Three decimals, without a minus sign on a figure that rounds to zero."""
    text = f"{x:.3f}"
    return text[1:] if text == "-0.000" else text


def documented_table() -> str:
    """The figures docs/drive.md quotes, as the Markdown it quotes them in."""
    motor = MOTORS[DOC_MOTOR]
    rpm = rpm_for_emf_ratio(motor, DOC_RATIO)
    short = short_circuit_current(motor, rpm)
    lines = [
        f"{motor.name}: the line-to-line back-EMF peak reaches the {motor.u_dc:g} V bus at "
        f"{threshold_rpm(motor):.1f} rpm; {DOC_RATIO}x that is {rpm:.1f} rpm (back-EMF peak "
        f"{DOC_RATIO * motor.u_dc:.1f} V). From rated torque (i_q = {motor.i_rated:.3f} A, "
        f"i_d = 0), the shaft held, a 2 us dead time, then:",
        "",
        "| reaction | bus (V): start -> end | mean DC current (A) | mean torque (Nm) "
        "| peak phase current (A): run, window | mean i_d, i_q (A) |",
        "|---|---|---|---|---|---|",
    ]
    cases = documented_cases()
    for name, r in cases.items():
        lines.append(f"| {name} | {r.u_dc0:.2f} -> {r.u_dc_end:.2f} | {_f(r.i_dc_mean)} "
                     f"| {_f(r.torque_mean)} | {_f(r.i_peak)}, {_f(r.i_peak_window)} "
                     f"| {_f(r.i_d_mean)}, {_f(r.i_q_mean)} |")
    off, asc = cases["all gates off, stiff bus"], cases[
        "active short circuit (three lower switches)"]
    w_l = motor.n_p * rpm * RPM * motor.L_d
    lines += [
        "",
        f"Every gate off, stiff bus: {-off.i_dc_mean * off.u_dc0:.1f} W into the bus, a braking "
        f"torque of {-off.torque_mean / motor.tau_rated:.2f}x the rated {motor.tau_rated:g} Nm. "
        f"ASC: {-asc.torque_mean / motor.tau_rated:.2f}x the rated torque. The shorted "
        f"machine's steady state (closed form): i_d = {short.real:.3f} A, i_q = "
        f"{short.imag:.3f} A (amplitude {abs(short):.3f} A); psi_f / L_d = "
        f"{motor.psi_f / motor.L_d:.3f} A; R_s = {motor.R_s:.2f} ohm against w L_d = "
        f"{w_l:.2f} ohm.",
    ]
    return "\n".join(lines)


def main() -> None:
    print(documented_table())


if __name__ == "__main__":
    main()
