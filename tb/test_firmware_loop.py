"""Firmware in the loop: the C FOC firmware (sw/foc) on the C driver programs the Verilated
drop-in top, whose pins drive the motor model (drive/mdfqm_drive/firmware_loop.py).

One short speed step of the paper's drive at a 32 MHz clock (docs/drive.md, "Firmware in the
loop"), checked three ways:
- every clock of the run: the top's outputs equal the golden model's stepped through the same
  inputs (the bus cycles the firmware made, the fault input);
- every control step: the firmware's single-precision arithmetic gives the codes the Python
  controller (the model path's, in double precision) computes from the same inputs;
- the drive: the speed follows the step as the model path's does, and the firmware's bus
  traffic per control period is what docs/drive.md states.
"""

import math

import numpy as np
import pytest

from mdfqm_drive.control import Encoder, FocController, Tuning
from mdfqm_drive.fault import fault_case, rpm_for_emf_ratio, short_circuit_current
from mdfqm_drive.firmware_loop import FirmwareLoop, build, rtl_fault_case
from mdfqm_drive.loop import ClosedLoop
from mdfqm_drive.modulator import IpModulator, IpSettings
from mdfqm_drive.motors import MOTORS, Load
from mdfqm_gateware.dropin import default_configs, dropin_verilog
from mdfqm_spec.contract import loop_latency
from mdfqm_testkit.clock_log import NAME, replay_clock_log, top_params
from mdfqm_testkit.harness import ROOT, verilator_build_env

RPM = 2 * math.pi / 60
F_CLK = 32e6
F_C = 20e3                      # sampling (control) rate
OSR = 4
PERIOD = round(F_CLK / (F_C * OSR))
DEAD = 64                       # 2 us at 32 MHz, the paper's dead time
STEP_AT, DURATION = 0.002, 0.014
RPM_FROM, RPM_TO = 150.0, 300.0


def settings() -> IpSettings:
    mid_update = (loop_latency(3) + (PERIOD + DEAD) // 2) % PERIOD
    return IpSettings(period=PERIOD, osr=OSR, dead=DEAD, mode="mdfqm", adc_offset=mid_update,
                      f_clk=F_CLK)


def w_ref(t):
    return (RPM_FROM if t < STEP_AT else RPM_TO) * RPM


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    pytest.importorskip("mdfqm_drive")
    from tools import regmap_gen

    work = tmp_path_factory.mktemp("firmware_loop")
    compiled = regmap_gen.compile_rdl()
    regmap_gen.write_peakrdl(compiled, regmap_gen.describe(compiled), work)
    (work / f"{NAME}.v").write_text(dropin_verilog(dict(default_configs(3, 16))[NAME](), NAME))
    verilator_build_env()
    return build(work / "lib", work)


@pytest.fixture(scope="module")
def runs(library, tmp_path_factory):
    motor = MOTORS["hurst_x5"]
    load = Load.generator(motor, 10.0)
    log = tmp_path_factory.mktemp("firmware_loop_log") / "clocks.log"
    clocks = round(DURATION * F_CLK) + 10
    rtl = FirmwareLoop(library, motor, settings(), load=load, w_m0=RPM_FROM * RPM, log=log,
                       log_clocks=clocks)
    rtl.run(DURATION, w_ref)
    counters = rtl.counters()
    rtl.close()       # flushes the log
    model = ClosedLoop(motor, settings(), load=load, w_m0=RPM_FROM * RPM,
                       edge_source=IpModulator(settings()))
    model.run(DURATION, w_ref)
    return rtl, model, counters, log


def test_every_clock_of_the_run_equals_the_golden_model(runs):
    _, _, counters, log = runs
    _, p = top_params()
    with log.open() as lines:
        model, checked = replay_clock_log(lines, p)
    assert checked == counters["cycle"] >= DURATION * F_CLK
    # the registers hold what the firmware was asked to set
    assert (model.period, model.osr, model.dead, model.adc_offset) == \
        (PERIOD, OSR, DEAD, settings().adc_offset)


def test_the_firmware_computes_what_the_model_controller_computes(runs):
    """The same inputs through the model path's controller (double precision): the codes agree
    to a few counts of the 16384 per Vdc (float rounding), the speed estimate to 1e-4."""
    rtl, _, _, _ = runs
    motor = rtl.plant.motor
    tuning = Tuning.rule(1 / rtl.T_c, 2 * motor.i_rated)
    ctrl = FocController(motor, rtl.plant.J, tuning, rtl.T_c, rtl.source.full_scale(),
                         Encoder())
    ctrl.w_hat = RPM_FROM * RPM
    adc = rtl.measurement.adc
    a = complex(-0.5, math.sqrt(3) / 2)
    worst = 0
    for (adc_codes, count, u_dc, w), (w_hat, _, codes) in zip(
            rtl.firmware_inputs, rtl.firmware_outputs, strict=True):
        m = [c * adc.lsb for c in adc_codes]
        i_ab = (2 / 3) * (m[0] + a * m[1] + a.conjugate() * m[2])
        want = ctrl.step(w, count, i_ab, u_dc)
        worst = max(worst, *(abs(x - y) for x, y in zip(codes, want, strict=True)))
        assert w_hat == pytest.approx(ctrl.w_hat, rel=1e-4, abs=1e-3)
    assert len(rtl.firmware_outputs) >= DURATION * F_C - 2
    assert worst <= 4, f"codes differ by up to {worst} counts"


def test_the_speed_step_through_the_rtl_follows_the_model_path(runs):
    rtl, model, counters, _ = runs
    a, b = rtl.trace.arrays(), model.trace.arrays()
    assert counters["missed"] == 0 and counters["steps"] == len(a.t)
    n = min(len(a.t), len(b.t))
    assert np.max(np.abs(a.t[:n] - b.t[:n])) < 1 / F_CLK * 100   # the same sampling instants
    # the paths start equal and part by float rounding, amplified through the ADC's
    # quantisation into different switching (docs/drive.md): a few rpm in the step's transient
    gap = np.abs(a.w_m[:n] - b.w_m[:n]) / RPM
    step = RPM_TO - RPM_FROM
    assert gap[:10].max() < 0.002 * step, "the paths differ from the first control periods"
    assert gap.max() < 0.05 * step and np.sqrt(np.mean(gap ** 2)) < 0.02 * step, \
        f"the two paths' speeds differ by up to {gap.max():.2f} rpm"
    # the step is taken: at the end within 5 % of it, as the model path
    assert abs(a.w_m[-1] / RPM - RPM_TO) < 0.05 * (RPM_TO - RPM_FROM)
    # switching: the same count of gate turn-ons within 2 %
    assert abs(a.events - b.events) <= 0.02 * b.events


def test_bus_traffic_per_control_period(runs):
    """docs/drive.md: per control period the firmware reads IRQ_STATUS once and writes it once
    (the acknowledge), writes REF[0..2] and CMD.REF_COMMIT; its initialisation reads ID, INFO,
    DEAD_MIN, CTRL twice and FAULT_REACTION, and writes ten registers."""
    _, _, counters, _ = runs
    periods = counters["periods"]
    init_reads = counters["bus_reads"] - periods
    init_writes = counters["bus_writes"] - 5 * periods
    assert periods == counters["irqs"] and periods >= DURATION * F_C - 2
    assert (init_reads, init_writes) == (6, 10)


def test_the_docs_example_runs(library, monkeypatch):
    """docs/drive.md's example, as written, with the library this module built."""
    from mdfqm_drive import firmware_loop

    text = (ROOT / "docs" / "drive.md").read_text()
    example = text.split("## Firmware in the loop", 1)[1].split("```python", 1)[1]
    example = example.split("```", 1)[0]
    monkeypatch.setattr(firmware_loop, "build", lambda *args, **kw: library)
    scope = {}
    exec(compile(example, "docs/drive.md", "exec"), scope)
    drive, trace = scope["drive"], scope["trace"]
    counters = drive.counters()
    assert counters["missed"] == 0 and counters["steps"] == len(trace.t) >= 240
    assert trace.w_m[-1] > trace.w_m[0]      # the step is being taken


@pytest.mark.parametrize("reaction", ["off", "asc_low", "asc_high"])
def test_the_fault_reaction_reaches_the_motor(library, reaction):
    """docs/top.md's fault reaction, set by the firmware, seen by the motor: held by a dyno at
    1.3x the speed where its line-to-line back-EMF peak reaches the bus, the fault pin raised
    after 5 ms. Every gate off: the diodes feed the bus and brake, as the plant alone does from
    the same speed (docs/drive.md, "Fault reaction: the plant"); an active short circuit: no
    bus current, the shorted machine's steady currents, the peak below psi_f / L_d."""
    motor = MOTORS["hurst_x5"]
    rpm = rpm_for_emf_ratio(motor, 1.3)
    got = rtl_fault_case(library, motor, settings(), rpm, reaction, before=0.005, after=0.03)
    assert got.asc_exit is None and got.rpm_end == pytest.approx(rpm)
    if reaction == "off":
        alone = fault_case(motor, rpm, reaction="off", duration=0.1)
        assert got.i_dc_mean < 0 and got.torque_mean < 0
        assert got.i_dc_mean == pytest.approx(alone.i_dc_mean, rel=0.03)
        assert got.torque_mean == pytest.approx(alone.torque_mean, rel=0.03)
    else:
        steady = short_circuit_current(motor, rpm)
        assert got.i_dc_mean == 0.0
        assert got.i_d_mean == pytest.approx(steady.real, rel=0.02)
        assert got.i_q_mean == pytest.approx(steady.imag, rel=0.02)
        assert got.i_peak < motor.psi_f / motor.L_d
