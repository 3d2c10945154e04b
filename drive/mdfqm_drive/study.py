"""Operating points as independent runs, and what a drive engineer measures in each.

:func:`sweep` maps :func:`run_case` over a list of :class:`Case` through any
``concurrent.futures.Executor`` (``executor.map``): a local process pool by default; a cluster's
executor (for example Dask distributed's ``Client.get_executor()``) runs the same code on more
machines. Each case is deterministic (no random input), so where it runs does not change its
numbers.

Metrics (:func:`metrics`), over a steady window after ``settle`` seconds:

- speed MSE by the paper's eq. 12: ``(1/n) sum (w_ref - w_k)^2`` over ``n = 100`` equally spaced
  samples of the true shaft speed, in rpm^2; the speed's peak-to-peak ripple;
- switching events per second: gate turn-ons of either switch of a leg (the IP's EVENTS);
- phase-current THD: the current of phase a between edges (linear between the recorded edges,
  exact to the back-EMF's curvature), resampled every 2 us over whole electrical periods;
  harmonics 2 to 2000 over the fundamental; and the ripple, everything but the fundamental,
  in A rms (meaningful also without load, where THD divides by almost nothing);
- torque ripple: the torque's standard deviation over its mean;
- the sampled i_q's standard deviation (what the current loop sees) and the true i_q's;
- losses of the six switches (:class:`Mosfet`): conduction ``i^2 R_ds(on)`` of the switch that is
  on, diode conduction ``V_f |i|`` while a leg is blanked, switching ``(E_on + E_off)`` per
  turn-on scaled by ``|i| Vdc / (I_ref V_ref)``, reverse recovery ``Q_rr Vdc`` per turn-on that
  takes the current from the opposite diode; and a first-order thermal model to a temperature
  rise after a time.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np

from mdfqm_spec.regmap import DEFAULT_DEAD_MIN

from .control import Adc
from .loop import ClosedLoop, Measurement
from .modulator import IpModulator, IpSettings
from .motors import MOTORS, Load, Motor

__all__ = ["Case", "Mosfet", "metrics", "run_case", "sweep"]

RPM = 2 * math.pi / 60


@dataclass(frozen=True)
class Mosfet:
    """The switch of every position of the inverter, with a first-order thermal path.

    Defaults: a 60 V, 10 mohm-class MOSFET in a DPAK on a board, typical of 24 V motor-control
    boards; every value *assumed* (no datasheet reachable here): ``R_ds_on`` at 100 C (ohm),
    ``V_f`` its body diode (V), ``E_on`` / ``E_off`` (J) at ``V_ref`` (V) and ``I_ref`` (A),
    ``Q_rr`` (C), ``R_th`` junction to ambient (K/W), ``tau_th`` (s).
    """

    name: str = "60 V / 10 mohm-class MOSFET, DPAK (assumed values)"
    R_ds_on: float = 0.015
    V_f: float = 0.8
    E_on: float = 15e-6
    E_off: float = 10e-6
    V_ref: float = 30.0
    I_ref: float = 10.0
    Q_rr: float = 40e-9
    R_th: float = 50.0
    tau_th: float = 120.0

    def temperature_rise(self, power: float, seconds: float) -> float:
        return power * self.R_th * (1 - math.exp(-seconds / self.tau_th))


@dataclass(frozen=True)
class Case:
    """One closed-loop run at a steady operating point (or a speed step, with ``step_to``)."""

    motor: str
    rpm: float
    settings: IpSettings
    load: str = "paper"            # "paper" (a PMSM into 10 ohm), or "const"
    load_fraction: float = 0.0     # of rated torque, with load "const"
    measurement: Measurement = field(default_factory=Measurement)
    settle: float = 0.15
    window: float = 0.25
    step_to: float | None = None   # rpm after ``settle``: a speed step instead of a steady point
    record: bool = True
    dead_min: int = DEFAULT_DEAD_MIN  # the IP's elaboration floor on DEAD (1: nearly none)
    label: str = ""
    w_m0_offset: float = 0.0       # rad/s added to the initial speed: a run's own spread

    def machine(self) -> tuple[Motor, Load]:
        """The motor and its load."""
        motor = MOTORS[self.motor]
        if self.load == "paper":
            return motor, Load.generator(motor, 10.0)
        if self.load == "const":
            return motor, Load(tau_const=self.load_fraction * motor.tau_rated, J=motor.J)
        raise ValueError(f"Case.load must be 'paper' or 'const', not {self.load!r}")

    @property
    def w_m0(self) -> float:
        """The initial speed (rad/s)."""
        return self.rpm * RPM + self.w_m0_offset

    def build(self) -> ClosedLoop:
        """The model path's loop."""
        motor, load = self.machine()
        return ClosedLoop(motor, self.settings, load=load, measurement=self.measurement,
                          w_m0=self.w_m0,
                          edge_source=IpModulator(self.settings, dead_min=self.dead_min))


def run_case(case: Case, build: Callable | None = None) -> dict:
    """Run ``case`` on the loop ``build(case)`` returns (default :meth:`Case.build`, the model
    path); return its metrics (plain floats and lists: picklable, JSON-able)."""
    loop = case.build() if build is None else build(case)
    w0, w1 = case.rpm * RPM, (case.step_to if case.step_to is not None else case.rpm) * RPM

    def w_ref(t):
        return w0 if t < case.settle else w1

    start = time.process_time()
    duration = case.settle + case.window
    tr = loop.run(duration, w_ref, record_from=case.settle if case.record else math.inf)
    cpu = time.process_time() - start
    tr.arrays()
    out = {"case": case, "cpu_s": cpu, "sim_s": duration, "T_c": loop.T_c,
           "update_rate": loop.source.f_clk / loop.source.period}
    out.update(metrics(loop, case))
    return out


def _resampled(t, y, t0, t1, step):
    grid = np.arange(t0, t1, step)
    return grid, np.interp(grid, t, y)


def metrics(loop: ClosedLoop, case: Case, mosfet: Mosfet | None = None) -> dict:
    """The metrics of a finished run (see the module docstring)."""
    tr = loop.trace
    mosfet = mosfet if mosfet is not None else Mosfet()
    motor = loop.plant.motor
    steady = tr.t >= case.settle
    t = tr.t[steady]
    out = {}
    rpm_err = (tr.w_ref[steady] - tr.w_m[steady]) / RPM
    idx = np.linspace(0, len(t) - 1, 100).round().astype(int)
    out["speed_mse"] = float(np.mean(rpm_err[idx] ** 2))
    out["speed_rms"] = float(np.sqrt(np.mean(rpm_err ** 2)))
    out["speed_pp"] = float(np.ptp(tr.w_m[steady]) / RPM)
    ev = tr.events_at[steady]
    out["events_per_s"] = float((ev[-1] - ev[0]) / (t[-1] - t[0]))
    out["iq_std"] = float(np.std(tr.i_q[steady]))
    out["iq_meas_std"] = float(np.std(tr.i_q_meas[steady]))
    out["iq_mean"] = float(np.mean(tr.i_q[steady]))
    tq = tr.torque[steady]
    out["torque_ripple"] = float(np.std(tq) / max(abs(np.mean(tq)), 1e-9))
    out["invalid_fraction"] = tr.invalid_samples / max(tr.samples, 1)
    codes = np.asarray(tr.codes, dtype=float)[steady]
    u_ab = (2 / 3) * (codes[:, 0] + np.exp(2j * np.pi / 3) * codes[:, 1]
                      + np.exp(-2j * np.pi / 3) * codes[:, 2])
    out["modulation"] = float(np.mean(np.abs(u_ab)) / loop.source.full_scale())
    out["saturated"] = tr.saturated
    if len(tr.wave_t) > 2:
        out.update(_waveform_metrics(tr, motor, case, loop.plant.u_dc, mosfet))
    # series for the plots
    out["series"] = {"t": tr.t.tolist(), "rpm": (tr.w_m / RPM).tolist(),
                     "rpm_ref": (tr.w_ref / RPM).tolist(), "i_q": tr.i_q.tolist(),
                     "i_q_meas": tr.i_q_meas.tolist()}
    return out


def _waveform_metrics(tr, motor, case, u_dc, mosfet: Mosfet) -> dict:
    t = tr.wave_t
    i = tr.wave_i
    pins = tr.wave_pins
    out = {}
    f_e = motor.n_p * (case.step_to or case.rpm) / 60
    periods = math.floor((t[-1] - t[0]) * f_e)
    if periods >= 1 and case.step_to is None:
        step = 2e-6
        t1 = t[0] + periods / f_e
        _, ia = _resampled(t, i[:, 0], t[0], t1, step)
        coeffs = np.fft.rfft(ia) / len(ia)
        spectrum = np.abs(coeffs)
        fund = spectrum[periods]
        harm = spectrum[2 * periods:2000 * periods + 1:periods]
        out["thd"] = float(np.sqrt(np.sum(harm ** 2)) / fund) if fund > 0 else math.nan
        out["i_peak_fund"] = float(2 * fund)
        # everything but the fundamental and the mean: the ripple, in A rms
        rest = coeffs.copy()
        rest[0] = rest[periods] = 0
        out["i_ripple_rms"] = float(np.sqrt(2 * np.sum(np.abs(rest[1:]) ** 2)))
    # losses, per interval between recorded edges (pins constant, currents linear)
    dt = np.diff(t)
    i_mid = 0.5 * (i[1:] + i[:-1])
    up = np.array([p[0] for p in pins[:-1]])
    lo = np.array([p[1] for p in pins[:-1]])
    cond = 0.0
    diode = 0.0
    for leg in range(3):
        on = (((up >> leg) & 1) | ((lo >> leg) & 1)).astype(bool)
        i2 = (i[1:, leg] ** 2 + i[1:, leg] * i[:-1, leg] + i[:-1, leg] ** 2) / 3
        cond += float(np.sum(i2[on] * dt[on])) * mosfet.R_ds_on
        diode += float(np.sum(np.abs(i_mid[~on, leg]) * dt[~on])) * mosfet.V_f
    switching = 0.0
    recovery = 0.0
    for k in range(1, len(pins)):
        (u0, l0), (u1, l1) = pins[k - 1], pins[k]
        for leg in range(3):
            bit = 1 << leg
            turned_on = (u1 & bit and not u0 & bit) or (l1 & bit and not l0 & bit)
            if not turned_on:
                continue
            cur = abs(i[k, leg])
            switching += (mosfet.E_on + mosfet.E_off) * cur * u_dc / (mosfet.I_ref
                                                                      * mosfet.V_ref)
            # hard: the upper switch takes a current that flowed in through the upper diode's
            # opposite, i.e. out of the leg (i > 0) through the lower diode, and vice versa
            hard = (u1 & bit and i[k, leg] > 0) or (l1 & bit and i[k, leg] < 0)
            if hard:
                recovery += mosfet.Q_rr * u_dc
    span = t[-1] - t[0]
    out["loss_conduction"] = float(cond / span)
    out["loss_diode"] = float(diode / span)
    out["loss_switching"] = float(switching / span)
    out["loss_recovery"] = float(recovery / span)
    total = float((cond + diode + switching + recovery) / span)
    out["loss_total"] = total
    out["temp_rise_15min"] = mosfet.temperature_rise(total / 6, 15 * 60)
    if case.record and span > 0:
        keep = t <= t[0] + min(span, 0.1)
        out["wave"] = {"t": t[keep].tolist(), "i": i[keep].tolist(),
                       "v_ab": [((p[0] & 1) - ((p[0] >> 1) & 1)) * u_dc
                                if ((p[0] | p[1]) & 3) == 3 else math.nan
                                for p, k in zip(pins, keep, strict=True) if k]}
    return out


def sweep(cases, executor: Executor | None = None, progress=None, runner=run_case) -> list[dict]:
    """Run every case through ``executor.map(runner, cases)`` (default: a process pool over all
    cores, :func:`run_case`); ``progress(done, total)`` after each. Results in the order of
    ``cases``."""
    cases = list(cases)
    own = executor is None
    if own:
        executor = ProcessPoolExecutor(max_workers=os.cpu_count() or 1)
    try:
        results = []
        for n, res in enumerate(executor.map(runner, cases), 1):
            results.append(res)
            if progress is not None:
                progress(n, len(cases))
        return results
    finally:
        if own:
            executor.shutdown()


def with_settings(case: Case, **changes) -> Case:
    """``case`` with some of its IP settings changed."""
    return replace(case, settings=replace(case.settings, **changes))


def shunt(average: bool = False) -> Measurement:
    return Measurement(Adc(topology="shunt"), average)
