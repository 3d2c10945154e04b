"""Firmware in the loop: the C FOC firmware (``sw/foc``) on the C driver, programming the
Verilated drop-in top, closed around the motor model.

:func:`build` compiles the library (``sw/sim/firmware_loop.cpp``): Verilator's model of the
drop-in Verilog that ``make`` writes (``mdfqm_top_n3_w16.v``), the firmware and the driver
against the generated register header, linked into one shared object. :class:`FirmwareLoop`
loads it and runs the drive: the library clocks the top and serves its interrupts with the
firmware; at every ``adc_trigger`` pulse it returns here, the plant is advanced through the
recorded pin changes (the dead time is the pins', nothing is modelled of the driver) to the
trigger's cycle, the currents are converted and the encoder latched, and the conversion goes to
the firmware, which runs its control law on the first conversion of a control period and
writes the next reference through the bus.

The interface is :class:`mdfqm_drive.loop.ClosedLoop`'s where it matters (``run``,
``trace``, ``plant``, ``source``, ``T_c``), so :func:`mdfqm_drive.study.metrics` measures
both paths the same way. The firmware computes in single precision; the model path in double.
"""

from __future__ import annotations

import ctypes
import math
import shutil
import subprocess
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mdfqm_spec.contract import Contract
from mdfqm_spec.regmap import DEFAULT_DEAD_MIN

from .control import Encoder, Tuning
from .loop import ClosedLoop, Measurement, Trace
from .modulator import IpSettings
from .motors import Load, Motor
from .plant import DcBus, Plant

__all__ = ["REACTIONS", "FirmwareLoop", "RtlFaultResult", "RtlSource", "build", "case_loop",
           "default_sw_dir", "firmware_cost", "rtl_fault_case"]

WIDTH = 16
TOP = f"mdfqm_top_n3_w{WIDTH}"
CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-fPIC"]
MODE_CODES = {"mdfqm": 0, "svpwm": 1, "dpwm0": 2, "dpwm1": 3, "dpwm": 4}
_EDGE_ROOM = 4096


def default_sw_dir() -> Path:
    """``sw/`` of the checkout this package is installed from (editable install)."""
    return Path(__file__).resolve().parents[2] / "sw"


def build(out: Path, generated: Path, sw: Path | None = None, jobs: int = 2) -> Path:
    """Compile the firmware-in-the-loop library into ``out`` from the drop-in Verilog and the
    register header in ``generated`` (what ``make generate`` writes); returns its path. Needs
    ``verilator`` and ``gcc``/``g++`` on PATH. The firmware and the driver are compiled as C99
    with every warning an error."""
    sw = default_sw_dir() if sw is None else sw
    verilator, gcc, gxx = (shutil.which(t) for t in ("verilator", "gcc", "g++"))
    if verilator is None or gcc is None or gxx is None:
        raise RuntimeError("firmware in the loop needs verilator, gcc and g++ on PATH")
    out.mkdir(parents=True, exist_ok=True)
    source = generated / f"{TOP}.v"
    if not source.exists() or not (generated / "mdfqm_top_regs.h").exists():
        raise FileNotFoundError(f"{generated} lacks {TOP}.v or mdfqm_top_regs.h: run make generate")
    objs = []
    for c in (sw / "mdfqm_driver.c", sw / "foc" / "mdfqm_foc.c"):
        obj = out / (c.stem + ".o")
        _run([gcc, *CFLAGS, "-I", str(generated), "-I", str(sw), "-I", str(sw / "foc"), "-c",
              str(c), "-o", str(obj)])
        objs.append(str(obj))
    mdir = out / "obj"
    _run([verilator, "--cc", "--build", "-O3", "-j", str(jobs), "--top-module", TOP,
          "-Mdir", str(mdir), "-CFLAGS", "-fPIC -O2", "-Wno-fatal", str(source)])
    root = Path(subprocess.run([verilator, "--getenv", "VERILATOR_ROOT"], check=True,
                               capture_output=True, text=True).stdout.strip())
    lib = out / "libfirmware_loop.so"
    _run([gxx, "-shared", "-fPIC", "-O2", "-std=c++17", "-I", str(mdir),
          "-I", str(root / "include"), "-I", str(root / "include" / "vltstd"),
          "-I", str(generated), "-I", str(sw), "-I", str(sw / "foc"),
          str(sw / "sim" / "firmware_loop.cpp"), *objs, str(mdir / f"V{TOP}__ALL.a"),
          *(str(root / "include" / f) for f in ("verilated.cpp", "verilated_threads.cpp")),
          "-o", str(lib), "-lpthread", "-latomic"])
    return lib


def firmware_cost(out: Path, generated: Path, sw: Path | None = None,
                  periods: int = 1000) -> dict:
    """The firmware's cost per control period (OSR 4: one SAMPLE interrupt, four conversions):
    x86-64 instructions executed in its two entry points (``gcc -O2``, valgrind's callgrind,
    glibc's sinf/cosf) and bus accesses, from ``sw/sim/firmware_cost.c``. Needs gcc and
    valgrind."""
    sw = default_sw_dir() if sw is None else sw
    gcc, valgrind = shutil.which("gcc"), shutil.which("valgrind")
    if gcc is None or valgrind is None:
        raise RuntimeError("the firmware's cost is measured with gcc and valgrind")
    out.mkdir(parents=True, exist_ok=True)
    bench = out / "firmware_cost"
    _run([gcc, *CFLAGS, "-I", str(generated), "-I", str(sw), "-I", str(sw / "foc"),
          str(sw / "sim" / "firmware_cost.c"), str(sw / "foc" / "mdfqm_foc.c"),
          str(sw / "mdfqm_driver.c"), "-lm", "-o", str(bench)])
    trace = out / "callgrind.out"
    done = subprocess.run([valgrind, "--tool=callgrind", f"--callgrind-out-file={trace}",
                           "--toggle-collect=mdfqm_foc_irq", "--toggle-collect=mdfqm_foc_adc",
                           str(bench), str(periods)], check=True, capture_output=True, text=True)
    words = done.stdout.split()
    counts = {words[k]: int(words[k + 1]) for k in range(0, len(words) - 1, 2)}
    total = next(int(line.split()[1]) for line in trace.read_text().splitlines()
                 if line.startswith("totals:"))
    version = subprocess.run([valgrind, "--version"], capture_output=True, text=True).stdout
    return {"instructions": total / periods, "reads": counts["reads"] / periods,
            "writes": counts["writes"] / periods, "steps": counts["steps"],
            "periods": periods, "valgrind": version.strip()}


def _run(cmd: list[str]) -> None:
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[:3])} ... failed:\n{done.stdout[-3000:]}"
                           f"{done.stderr[-3000:]}")


class _Config(ctypes.Structure):
    """``mdfqm_foc_config_t`` (sw/foc/mdfqm_foc.h), field for field."""

    _fields_ = [(n, ctypes.c_float) for n in ("R_s", "L_d", "L_q", "psi_f", "J")] + [
        ("n_p", ctypes.c_uint32)] + [
        (n, ctypes.c_float) for n in ("alpha_c", "alpha_s", "i_max")] + [
        (n, ctypes.c_uint32) for n in ("decoupling", "delay_compensation", "encoder_counts")] + [
        ("adc_lsb", ctypes.c_float), ("average", ctypes.c_uint32), ("f_clk", ctypes.c_float)] + [
        (n, ctypes.c_uint32) for n in ("period", "osr", "dead", "min_pulse", "adc_offset",
                                       "mode", "bits", "fewest_transitions",
                                       "fault_reaction")] + [
        ("asc_exit_speed", ctypes.c_float)]


_LIBS: dict[str, ctypes.CDLL] = {}


def _load(path: Path) -> ctypes.CDLL:
    key = str(Path(path).resolve())
    if key not in _LIBS:
        lib = ctypes.CDLL(key)
        vp, u64, pu64 = ctypes.c_void_p, ctypes.c_uint64, ctypes.POINTER(ctypes.c_uint64)
        pi32, pu32 = ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_uint32)
        for name, res, args in (
                ("fil_new", vp, [ctypes.c_char_p, u64]),
                ("fil_free", None, [vp]),
                ("fil_init", ctypes.c_int, [vp, ctypes.POINTER(_Config), ctypes.c_float]),
                ("fil_run", ctypes.c_int, [vp, u64, pu64]),
                ("fil_edges", ctypes.c_size_t, [vp, pu64, pu32, pu32, ctypes.c_size_t]),
                ("fil_adc", ctypes.c_int, [vp, pi32, ctypes.c_int32, ctypes.c_float,
                                           ctypes.c_float]),
                ("fil_outputs", None, [vp, ctypes.POINTER(ctypes.c_float), pi32]),
                ("fil_set_fault", None, [vp, ctypes.c_int]),
                ("fil_counters", None, [vp, pu64])):
            fn = getattr(lib, name)
            fn.restype, fn.argtypes = res, args
        _LIBS[key] = lib
    return _LIBS[key]


@dataclass(frozen=True)
class RtlSource:
    """What the measurements need of the pins' source: the clock, PERIOD, OSR and FULL."""

    f_clk: float
    period: int
    osr: int
    full: int

    def full_scale(self) -> int:
        return self.full


def case_loop(case, library: Path) -> FirmwareLoop:
    """The loop of a :class:`mdfqm_drive.study.Case` through the firmware and the RTL (for
    ``study.run_case(case, functools.partial(case_loop, library=...))``)."""
    if case.dead_min != DEFAULT_DEAD_MIN:
        raise ValueError(f"the drop-in top is built with dead_min {DEFAULT_DEAD_MIN}, "
                         f"not the case's {case.dead_min}")
    motor, load = case.machine()
    return FirmwareLoop(library, motor, case.settings, load=load,
                        measurement=case.measurement, w_m0=case.w_m0)


COUNTERS = ("cycle", "first_update", "bus_reads", "bus_writes", "bus_clocks", "irqs",
            "periods", "steps", "missed", "faults", "watchdogs", "all_off_sent")
#: FAULT_REACTION's codes (docs/top.md, "Fault reaction")
REACTIONS = {"off": 0, "asc_low": 1, "asc_high": 2}


class FirmwareLoop:
    """The drive of :class:`mdfqm_drive.loop.ClosedLoop` with the firmware and the RTL in place
    of the controller and the modulator model: ``library`` from :func:`build`, the rest as
    ``ClosedLoop``'s (the IP's registers from ``settings``; ``width`` 16, three phases: the
    ``mdfqm_top_n3_w16`` drop-in). Currents are measured in-line (the firmware's one topology).
    ``log`` / ``log_clocks``: write the first clocks' pins and bus for a clock-by-clock check.
    ``fault_reaction`` (a key of :data:`REACTIONS`) the firmware sets for the fault pin;
    ``asc_exit_rpm``: the speed below which the firmware ends an active short circuit (0:
    never).
    """

    def __init__(self, library: Path, motor: Motor, settings: IpSettings,
                 load: Load | None = None, bus: DcBus | None = None,
                 tuning: Tuning | None = None, measurement: Measurement | None = None,
                 encoder: Encoder | None = None, w_m0: float = 0.0,
                 log: Path | None = None, log_clocks: int = 0, plant_class=Plant,
                 fault_reaction: str = "off", asc_exit_rpm: float = 0.0):
        if fault_reaction not in REACTIONS:
            raise ValueError(f"fault_reaction must be one of {sorted(REACTIONS)}, "
                             f"not {fault_reaction!r}")
        self.measurement = measurement if measurement is not None else Measurement()
        if self.measurement.adc.topology != "inline":
            raise ValueError("FirmwareLoop measures in-line currents only (the firmware's "
                             f"topology), not {self.measurement.adc.topology!r}")
        self.settings = settings
        self.source = RtlSource(settings.f_clk, settings.period, max(settings.osr, 1),
                                 Contract(3, WIDTH).full)
        self.plant = plant_class(motor, load, bus, w_m=w_m0)
        self.T_c = self.source.osr * settings.period / settings.f_clk
        self.tuning = tuning if tuning is not None else Tuning.rule(1 / self.T_c,
                                                                    2 * motor.i_rated)
        self.encoder = encoder if encoder is not None else Encoder()
        self.lib = _load(library)
        self.handle = self.lib.fil_new(str(log).encode() if log else None, log_clocks)
        cfg = _Config(
            R_s=motor.R_s, L_d=motor.L_d, L_q=motor.L_q, psi_f=motor.psi_f, J=self.plant.J,
            n_p=motor.n_p, alpha_c=self.tuning.alpha_c, alpha_s=self.tuning.alpha_s,
            i_max=self.tuning.i_max, decoupling=int(self.tuning.decoupling),
            delay_compensation=int(self.tuning.delay_compensation),
            encoder_counts=self.encoder.counts, adc_lsb=self.measurement.adc.lsb,
            average=int(self.measurement.average), f_clk=settings.f_clk,
            period=settings.period, osr=settings.osr, dead=settings.dead,
            min_pulse=settings.min_pulse, adc_offset=settings.adc_offset,
            mode=MODE_CODES[settings.mode], bits=settings.bits,
            fewest_transitions=int(settings.zero_policy),
            fault_reaction=REACTIONS[fault_reaction],
            asc_exit_speed=asc_exit_rpm * 2 * math.pi / 60)
        if self.lib.fil_init(self.handle, ctypes.byref(cfg), w_m0) != 0:
            raise RuntimeError("the firmware's initialisation failed (not a 3-phase mdfqm IP?)")
        self.cycle = 0
        self.pins = (0, 0)
        self.edges = deque()
        self.trace = Trace()
        self.record_from = math.inf
        self._buf = ((ctypes.c_uint64 * _EDGE_ROOM)(), (ctypes.c_uint32 * _EDGE_ROOM)(),
                     (ctypes.c_uint32 * _EDGE_ROOM)())
        # what the firmware was given and computed, step by step (a check of the C port)
        self.firmware_inputs: list = []
        self.firmware_outputs: list = []

    def close(self) -> None:
        if self.handle:
            self.lib.fil_free(self.handle)
            self.handle = None

    def __del__(self):
        self.close()

    def counters(self) -> dict:
        out = (ctypes.c_uint64 * len(COUNTERS))()
        self.lib.fil_counters(self.handle, out)
        return dict(zip(COUNTERS, out, strict=True))

    def set_fault(self, level: bool) -> None:
        """The top's ``fault_in`` from the library's next clock on."""
        self.lib.fil_set_fault(self.handle, int(level))

    def _drain(self) -> None:
        cyc, up, lo = self._buf
        while True:
            n = self.lib.fil_edges(self.handle, cyc, up, lo, _EDGE_ROOM)
            self.edges.extend(zip(cyc[:n], up[:n], lo[:n], strict=True))
            if n < _EDGE_ROOM:
                return

    # the plant follows the recorded pin changes exactly as the model path's loop does
    _advance_to = ClosedLoop._advance_to
    _record = ClosedLoop._record

    def run(self, duration: float, w_ref: Callable[[float], float],
            progress: Callable[[float], None] | None = None,
            record_from: float = math.inf,
            on_sample: Callable[[Plant], None] | None = None) -> Trace:
        """As :meth:`ClosedLoop.run`: ``duration`` seconds, speed reference ``w_ref(t)``;
        ``on_sample(plant)`` at every ADC trigger (the plant advanced to it)."""
        self.record_from = record_from
        lib, handle, plant, tr = self.lib, self.handle, self.plant, self.trace
        adc = self.measurement.adc
        end = self.cycle + round(duration * self.source.f_clk)
        trigger = ctypes.c_uint64()
        codes_in = (ctypes.c_int32 * 3)()
        values = (ctypes.c_float * 4)()
        codes_out = (ctypes.c_int32 * 3)()
        while True:
            got = lib.fil_run(handle, end, ctypes.byref(trigger))
            self._drain()
            if not got:
                self._advance_to(end)
                break
            self._advance_to(trigger.value)
            if on_sample is not None:
                on_sample(plant)
            codes_in[:] = [adc.code(i) for i in plant.phase_currents()]
            count = self.encoder.read(plant.theta_m)
            t = plant.t
            w = w_ref(t)
            tr.samples += 1
            inputs = (tuple(codes_in), count, plant.u_dc, w)
            if not lib.fil_adc(handle, codes_in, count, plant.u_dc, w):
                continue
            lib.fil_outputs(handle, values, codes_out)
            w_hat, i_q_ref, _, i_q_meas = values
            codes = tuple(codes_out)
            self.firmware_inputs.append(inputs)
            self.firmware_outputs.append((w_hat, i_q_ref, codes))
            tr.codes.append(codes)
            tr.t.append(t)
            tr.w_m.append(plant.w_m)
            tr.w_hat.append(w_hat)
            tr.w_ref.append(w)
            tr.i_d.append(plant.i_d)
            tr.i_q.append(plant.i_q)
            tr.i_q_meas.append(i_q_meas)
            tr.i_q_ref.append(i_q_ref)
            tr.torque.append(plant.torque())
            tr.u_dc.append(plant.u_dc)
            tr.events_at.append(tr.events)
            if progress is not None:
                progress(t)
        if plant.t >= self.record_from:
            self._record()
        return tr


@dataclass(frozen=True)
class RtlFaultResult:
    """What :func:`rtl_fault_case` measures after the fault (signs as
    :class:`mdfqm_drive.fault.FaultResult`'s: ``i_dc_mean`` out of the bus, negative when the
    motor charges it; ``torque_mean`` negative when it brakes). Means over whole periods of the
    six-pulse ripple within the last half of the run after the fault; ``asc_exit`` the seconds
    from the fault to the firmware's end of the active short circuit (None: it did not end),
    ``rpm_at_exit`` the true speed then."""

    reaction: str
    rpm: float
    u_dc0: float
    u_dc_end: float
    u_dc_max: float
    i_dc_mean: float
    torque_mean: float
    i_peak: float
    i_d_mean: float
    i_q_mean: float
    rpm_end: float
    asc_exit: float | None
    rpm_at_exit: float | None
    psi_over_ld: float


def rtl_fault_case(library: Path, motor: Motor, settings: IpSettings, speed_rpm: float,
                   reaction: str, held: bool = True, bus: DcBus | None = None,
                   before: float = 0.02, after: float = 0.1, asc_exit_rpm: float = 0.0,
                   load: Load | None = None) -> RtlFaultResult:
    """The drive through the firmware and the RTL at ``speed_rpm``, imposed by a dyno (the
    controller asked for that speed), for ``before`` seconds; then the fault pin goes active
    and stays so for ``after`` seconds, the IP's ``reaction`` (:data:`REACTIONS`) set by the
    firmware. ``held``: the dyno keeps the speed after the fault (else the shaft is free, its
    inertia the motor's and ``load``'s); ``asc_exit_rpm``: the firmware ends an active short
    circuit below that speed."""
    w = speed_rpm * 2 * math.pi / 60
    loop = FirmwareLoop(library, motor, settings, load=load, bus=bus, w_m0=w,
                        fault_reaction=reaction, asc_exit_rpm=asc_exit_rpm)
    try:
        loop.plant.speed_locked = True
        loop.run(before, lambda t: w)
        loop.set_fault(True)
        loop.plant.speed_locked = held
        t_fault, u_dc0 = loop.plant.t, loop.plant.u_dc
        rows = []
        shorted = [False, None, None]

        def sample(plant):
            if loop.pins in ((0, 7), (7, 0)):     # every lower, or every upper, switch on
                shorted[0] = True
            elif shorted[0] and shorted[1] is None:
                shorted[1], shorted[2] = plant.t - t_fault, plant.w_m * 60 / (2 * math.pi)
            rows.append((plant.t, plant.u_dc, plant.torque(), plant.i_d, plant.i_q,
                         max(abs(i) for i in plant.phase_currents()), plant.energy_dc,
                         plant.w_m))

        loop.plant.i_peak = 0.0
        loop.run(after, lambda t: w, on_sample=sample)
        data = np.array(rows)
        # whole periods of the six-pulse ripple (the diode bridge's) in the last half
        ripple = 1 / (3 * motor.n_p * abs(w) / math.pi) if w else after
        span = max(math.floor(0.5 * after / ripple), 1) * ripple
        window = data[data[:, 0] >= data[-1, 0] - min(span, 0.5 * after)]
        t = window[:, 0]
        u_int = np.trapezoid(window[:, 1], t)
        return RtlFaultResult(
            reaction=reaction, rpm=speed_rpm, u_dc0=u_dc0, u_dc_end=loop.plant.u_dc,
            u_dc_max=float(data[:, 1].max()),
            i_dc_mean=float((window[-1, 6] - window[0, 6]) / u_int),
            torque_mean=float(np.trapezoid(window[:, 2], t) / (t[-1] - t[0])),
            i_peak=float(max(data[:, 5].max(), loop.plant.i_peak)),
            i_d_mean=float(np.mean(window[:, 3])), i_q_mean=float(np.mean(window[:, 4])),
            rpm_end=loop.plant.w_m * 60 / (2 * math.pi), asc_exit=shorted[1],
            rpm_at_exit=shorted[2], psi_over_ld=motor.psi_f / motor.L_d)
    finally:
        loop.close()
