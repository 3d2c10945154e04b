"""The closed loop: the IP's pins drive the plant, the plant's currents are sampled at the IP's
ADC trigger, the controller runs at each sampling tick and writes the next reference.

Timing (a firmware answering the IP's SAMPLE interrupt): sampling tick ``m`` takes the reference
written during control period ``m - 1``; the first update of period ``m`` samples the currents at
its ADC trigger (``ADC_OFFSET`` clocks after its start), the controller then computes the
reference that tick ``m + 1`` takes: one control period of computation delay. With
``average=True`` the controller uses the mean of the last ``OSR`` per-update samples (one per
update, the last of them the first update of period ``m``) instead of the one sample.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .control import Adc, Encoder, FocController, Tuning
from .modulator import IpModulator, IpSettings
from .motors import Load, Motor
from .plant import DcBus, Plant

__all__ = ["ClosedLoop", "Measurement", "Trace"]


@dataclass(frozen=True)
class Measurement:
    """How the currents are measured: the ADC, and whether the controller averages the
    per-update samples of the last ``OSR`` updates (``average``)."""

    adc: Adc = field(default_factory=Adc)
    average: bool = False


@dataclass
class Trace:
    """What a run records, one row per sampling tick (arrays after :meth:`ClosedLoop.run`)."""

    t: list = field(default_factory=list)          # s, the tick
    w_m: list = field(default_factory=list)        # true mechanical speed (rad/s)
    w_hat: list = field(default_factory=list)      # the controller's estimate
    w_ref: list = field(default_factory=list)
    i_d: list = field(default_factory=list)        # true currents at the tick (A)
    i_q: list = field(default_factory=list)
    i_q_meas: list = field(default_factory=list)   # what the controller used
    i_q_ref: list = field(default_factory=list)
    torque: list = field(default_factory=list)
    u_dc: list = field(default_factory=list)
    codes: list = field(default_factory=list)      # the reference written at each tick
    codes: list = field(default_factory=list)      # the reference written at each tick
    events: int = 0                                 # gate turn-ons (either switch of a leg)
    invalid_samples: int = 0                        # samples with < 2 legs readable
    samples: int = 0
    saturated: int = 0                              # updates whose integrator held
    events_at: list = field(default_factory=list)  # ``events`` at each tick
    # the waveform from ``record_from`` on: at every pin change (and the run's end) the time,
    # the phase currents and the pins from that instant on
    wave_t: list = field(default_factory=list)
    wave_i: list = field(default_factory=list)
    wave_pins: list = field(default_factory=list)

    def arrays(self) -> Trace:
        for name in ("t", "w_m", "w_hat", "w_ref", "i_d", "i_q", "i_q_meas", "i_q_ref",
                     "torque", "u_dc", "events_at", "wave_t", "wave_i"):
            setattr(self, name, np.asarray(getattr(self, name), dtype=float))
        return self


def _turn_ons(old: tuple, new: tuple) -> int:
    up = (new[0] & ~old[0]) & 7
    lo = (new[1] & ~old[1]) & 7
    return bin(up).count("1") + bin(lo).count("1")


class ClosedLoop:
    """A drive: ``motor`` + ``load`` on ``bus``, the IP set up by ``settings``, the controller
    tuned by ``tuning`` (default: :meth:`Tuning.rule` at the sampling rate, ``i_max`` twice the
    rated current), ``measurement`` of the currents, ``encoder``.

    ``edge_source`` (default: :class:`IpModulator` of ``settings``) is anything with
    ``write_reference(codes)``, ``next_update()`` returning an object with ``start``, ``tick``,
    ``adc``, ``edges`` and ``saturated`` (see :class:`mdfqm_drive.modulator.Update`),
    ``f_clk``, ``period``, ``osr`` and ``full_scale()``: the gateware can take its place.
    ``plant_class`` builds the plant (a :class:`Plant` or a subclass).
    """

    def __init__(self, motor: Motor, settings: IpSettings, load: Load | None = None,
                 bus: DcBus | None = None, tuning: Tuning | None = None,
                 measurement: Measurement | None = None, encoder: Encoder | None = None,
                 w_m0: float = 0.0, edge_source=None, plant_class=Plant):
        self.source = edge_source if edge_source is not None else IpModulator(settings)
        src = self.source
        self.plant = plant_class(motor, load, bus, w_m=w_m0)
        self.T_c = src.osr * src.period / src.f_clk
        if tuning is None:
            tuning = Tuning.rule(1 / self.T_c, 2 * motor.i_rated)
        self.tuning = tuning
        self.measurement = measurement if measurement is not None else Measurement()
        self.controller = FocController(motor, self.plant.J, tuning, self.T_c,
                                        src.full_scale(), encoder)
        self.controller.w_hat = w_m0
        self.cycle = 0
        self.pins = (0, 0)
        self.edges = deque()
        self.recent = deque(maxlen=max(src.osr, 1))
        self.trace = Trace()
        self.record_from = math.inf

    def _advance_to(self, cycle: int) -> None:
        plant, f = self.plant, self.source.f_clk
        while self.edges and self.edges[0][0] <= cycle:
            at, up, lo = self.edges.popleft()
            plant.advance((at - self.cycle) / f, *self.pins)
            self.cycle = at
            self.trace.events += _turn_ons(self.pins, (up, lo))
            self.pins = (up, lo)
            if plant.t >= self.record_from:
                self._record()
        plant.advance((cycle - self.cycle) / f, *self.pins)
        self.cycle = cycle

    def _record(self) -> None:
        tr = self.trace
        tr.wave_t.append(self.plant.t)
        tr.wave_i.append(self.plant.phase_currents())
        tr.wave_pins.append(self.pins)

    def run(self, duration: float, w_ref: Callable[[float], float],
            progress: Callable[[float], None] | None = None,
            record_from: float = math.inf) -> Trace:
        """Run for ``duration`` seconds with the speed reference ``w_ref(t)`` (rad/s); record the
        waveform (:class:`Trace`'s ``wave_*``) from ``record_from`` seconds on."""
        self.record_from = record_from
        src, plant, ctrl, tr = self.source, self.plant, self.controller, self.trace
        adc = self.measurement.adc
        end = self.cycle + round(duration * src.f_clk)
        while self.cycle < end:
            upd = src.next_update()
            tr.saturated += bool(upd.saturated)
            self.edges.extend(upd.edges)
            sample = None
            if upd.adc is not None:
                self._advance_to(upd.adc)
                sample = adc.sample(plant.phase_currents(), self.pins[1])
                tr.samples += 1
                tr.invalid_samples += sample is None
                self.recent.append(sample)
            if upd.tick:
                t = plant.t
                if self.measurement.average:
                    valid = [s for s in self.recent if s is not None]
                    i_ab = sum(valid) / len(valid) if valid else None
                else:
                    i_ab = sample
                count = ctrl.encoder.read(plant.theta_m)
                w = w_ref(t)
                codes = ctrl.step(w, count, i_ab, plant.u_dc)
                src.write_reference(codes)
                tr.codes.append(codes)
                tr.t.append(t)
                tr.w_m.append(plant.w_m)
                tr.w_hat.append(ctrl.w_hat)
                tr.w_ref.append(w)
                tr.i_d.append(plant.i_d)
                tr.i_q.append(plant.i_q)
                i_dq = ctrl.i_meas * complex(math.cos(plant.theta), -math.sin(plant.theta))
                tr.i_q_meas.append(i_dq.imag)
                tr.i_q_ref.append(ctrl.i_q_ref)
                tr.torque.append(plant.torque())
                tr.u_dc.append(plant.u_dc)
                tr.events_at.append(tr.events)
                if progress is not None:
                    progress(t)
            self._advance_to(upd.start + src.period)
        if plant.t >= self.record_from:
            self._record()
        return tr
