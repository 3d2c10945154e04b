"""tools/pins_report.py: the dead-time transform and the diode rule on cases derived by hand
from the driver's documented contract (docs/top.md, "Gate driver"), the continuous-time
transform of part (b) against the golden model's driver on clock-aligned edges, the
equal-switching search, and a --quick run through the RTL that must agree with the model."""

import csv
import math

import numpy as np
import pytest

from mdfqm_spec.contract import Contract
from tools import pins_report
from tools.analysis.metrics import PWave
from tools.analysis.signals import bbit_method, run_method
from tools.pins_report import (
    DEAD_CLOCKS,
    DEAD_SECONDS,
    F_CLK,
    FC,
    OFF,
    GateWave,
    dead_time_gates,
    driver_gates,
    equalise,
    pole_voltage,
)


def one_leg(times, states):
    return PWave(np.asarray(times, float), np.asarray(states)[:, None])


def gates(w: GateWave):
    return w.t.tolist(), w.g.tolist()


# ------------------------------------------------------------------ the dead-time transform
# docs/top.md: at a command edge both switches turn off; the commanded switch turns on once both
# have been off for dt; an upper pulse of w clocks (lower on before and after) is on for w - dt
# when w > dt, and swallowed when w <= dt (the lower switch comes back after the dead time).


def test_pulse_longer_than_the_dead_time_loses_dt():
    w = dead_time_gates(one_leg([0, 10, 30, 50], [0, 1, 0]), 4.0)
    # lower to 10, blank 10..14, upper 14..30 (20 - 4 = 16), blank 30..34, lower again
    assert gates(w) == ([0, 10, 14, 30, 34, 50], [[0], [OFF], [1], [OFF], [0]])


@pytest.mark.parametrize("width", [3, 4])
def test_pulse_within_the_dead_time_is_swallowed(width):
    w = dead_time_gates(one_leg([0, 10, 10 + width, 50], [0, 1, 0]), 4.0)
    assert gates(w) == ([0, 10, 14, 50], [[0], [OFF], [0]])


def test_the_switch_commanded_when_the_dead_time_ends_turns_on():
    # lower -> upper at 10, back at 11, upper again at 12: at 14 the command is upper
    w = dead_time_gates(one_leg([0, 10, 11, 12, 50], [0, 1, 0, 1]), 4.0)
    assert gates(w) == ([0, 10, 14, 50], [[0], [OFF], [1]])


def test_no_dead_time_is_the_command():
    w = dead_time_gates(one_leg([0, 10, 30, 50], [0, 1, 0]), 0.0)
    assert gates(w) == ([0, 10, 30, 50], [[0], [1], [0]])


def test_periodic_wrap():
    # period 10, upper commanded on [8, 12) (across the wrap): 4 clocks, swallowed by dt = 4
    cmd = one_leg([0, 2, 8, 10], [1, 0, 1])
    assert gates(dead_time_gates(cmd, 4.0, periodic=True)) == (
        [0, 2, 8, 10], [[OFF], [0], [OFF]])
    # dt = 1: blank 8..9, upper 9..12 (across the wrap), blank 2..3, lower 3..8
    assert gates(dead_time_gates(cmd, 1.0, periodic=True)) == (
        [0, 2, 3, 8, 9, 10], [[1], [OFF], [0], [OFF], [1]])


def test_legs_are_independent():
    cmd = PWave(np.array([0.0, 10, 20, 40]), np.array([[0, 1], [1, 1], [1, 0]]))
    assert gates(dead_time_gates(cmd, 3.0)) == (
        [0, 10, 13, 20, 23, 40], [[0, 1], [OFF, 1], [1, 1], [1, OFF], [1, 0]])


def test_pins_round_trip_and_shoot_through():
    w = GateWave.from_pins([0, 1, 1, 0, 0], [1, 0, 0, 0, 1], 1)
    assert gates(w) == ([0, 1, 3, 4, 5], [[0], [1], [OFF], [0]])
    up, lo = w.per_clock(5)
    assert up.tolist() == [0, 1, 1, 0, 0] and lo.tolist() == [1, 0, 0, 0, 1]
    with pytest.raises(ValueError, match="both switches"):
        GateWave.from_pins([1], [1], 1)


# ------------------------------------------------------------------ against the golden model
# Part (b) keeps dead_time_gates in continuous time; on clock-aligned edges it must give the
# gates GateDriverModel gives (driver_gates), one clock later.


def model_gates(h: np.ndarray, dead: int, periodic: bool) -> tuple[np.ndarray, np.ndarray]:
    """GateDriverModel's gates for the per-clock command ``h``, clock ``c`` of ``h`` at index
    ``c`` (the driver's clock of delay taken out): with ``periodic`` the last of three repeats
    of ``h``, else after the first command held (``dead + 2`` clocks: the legs on to it, as
    dead_time_gates assumes before the waveform)."""
    n = len(h)
    if periodic:
        up, lo = driver_gates(np.tile(h, 3), dead)
        return up[2 * n:], lo[2 * n:]
    lead = dead + 2
    up, lo = driver_gates(np.concatenate([np.full(lead, h[0]), h]), dead)
    return up[lead:], lo[lead:]


def transform_gates(h: np.ndarray, dead: int, periodic: bool,
                    rate: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """dead_time_gates of the per-clock command ``h`` with clocks of ``1/rate`` (in seconds
    at the report's clock, rounding in every edge), per clock."""
    w = dead_time_gates(PWave.from_samples(h, rate, 3), dead / rate, periodic=periodic)
    turns = w.t * rate
    assert np.allclose(turns, np.round(turns), atol=1e-6, rtol=0)
    return GateWave(np.round(turns), w.g).per_clock(len(h))


@pytest.mark.parametrize("rate", [1.0, F_CLK])
@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("dead", [1, 2, 3, 7, 20])
def test_transform_is_the_model_driver_on_clock_edges(dead, periodic, rate):
    # random commands, runs of 1 to 3 dead times (pulses swallowed, a pulse of exactly the
    # dead time, reverting and re-reverting within a dead time, long ones), three legs
    # independent; in clocks and in seconds
    rng = np.random.default_rng(31 + dead)
    runs = rng.integers(1, 3 * dead + 2, 400)
    h = np.repeat(rng.integers(0, 8, len(runs)), runs)
    up, lo = model_gates(h, dead, periodic)
    want_up, want_lo = transform_gates(h, dead, periodic, rate)
    assert (up == want_up).all() and (lo == want_lo).all()
    assert ((up | lo) != 7).any()                    # blanking intervals were compared


@pytest.mark.parametrize(("mode", "bits"), [("svpwm", 8), ("svpwm", 4), ("dpwm", 8)])
def test_sweep_waveform_is_the_model_driver_on_clock_edges(mode, bits):
    # part (b)'s path (run_method in seconds, the periodic transform with the report's dead
    # time) at the carrier of part (a), where every slot edge is a clock edge (13 clocks per
    # b = 8 slot, shorter than the 20-clock dead time: swallowed pulses)
    samples = 6
    wave = run_method(Contract(3, 16), bbit_method(mode, bits), FC, 50.0, 0.5, samples / FC,
                      fsw=FC).wave
    clocks = round(samples * F_CLK / FC)
    edges = wave.t * F_CLK
    assert np.allclose(edges, np.round(edges), atol=1e-6, rtol=0)
    h = np.repeat((wave.s.astype(np.int64) << np.arange(3)).sum(axis=1),
                  np.diff(np.round(edges).astype(np.int64)))
    assert len(h) == clocks
    gates = dead_time_gates(wave, DEAD_SECONDS, periodic=True)
    turns = gates.t * F_CLK
    assert np.allclose(turns, np.round(turns), atol=1e-6, rtol=0)
    want_up, want_lo = GateWave(np.round(turns), gates.g).per_clock(clocks)
    up, lo = model_gates(h, DEAD_CLOCKS, periodic=True)
    assert (up == want_up).all() and (lo == want_lo).all()


# ------------------------------------------------------------------ the diode rule


def test_blanking_follows_the_current_sign():
    # leg a upper, b and c lower: v = h - mean(h) = (2/3, -1/3, -1/3), so in steady state
    # i_a = 2/3 > 0 (its blanking sits at the lower rail) and i_b = -1/3 < 0 (the upper rail)
    t = np.array([0, 5e-3, 5.002e-3, 12e-3, 12.002e-3, 20e-3])
    g = np.array([[1, 0, 0], [OFF, 0, 0], [1, 0, 0], [1, OFF, 0], [1, 0, 0]])
    pole, stats = pole_voltage(GateWave(t, g), 1e-3)
    assert pole.s.tolist() == [[1, 0, 0], [0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 0, 0]]
    assert stats == {"blank": 2, "blank_cross": 0}


@pytest.mark.parametrize(("others", "mean"), [(0, 0.5 - 0.02), (1, 0.5 + 0.02)])
def test_volt_second_error_of_one_dead_time_per_period(others, mean):
    # leg a: 50 % square wave, period 100 us, dt 2 us; legs b, c held at `others`. Mean of v_a
    # is 1/3 (others 0: i_a > 0, ripple << 1/3) or -1/3 (others 1: i_a < 0); with i_a > 0 each
    # rising edge reaches the pole dt late and each falling edge on time, so the pole's mean is
    # 0.5 - dt/P; with i_a < 0 the falling edges are late: 0.5 + dt/P
    period, periods = 100e-6, 200
    t = np.arange(2 * periods + 1) * period / 2
    s = np.zeros((2 * periods, 3), dtype=int)
    s[0::2, 0] = 1
    s[:, 1:] = others
    pole, stats = pole_voltage(dead_time_gates(PWave(t, s), 2e-6, periodic=True), 1e-3)
    assert np.diff(pole.t) @ pole.s[:, 0] / pole.period == pytest.approx(mean, abs=1e-12)
    assert stats == {"blank": 2 * periods, "blank_cross": 0}


# ------------------------------------------------------------------ the equal-switching search


def test_equalise_power_law():
    # events 100 m, THD 1/m = 100 / events: a straight line in log-log, so the interpolation
    # at 1234 events/s is exact: THD 100 / 1234, m 12.34, between m = 12 and 13
    r = equalise(lambda m: (100.0 * m, 1.0 / m), 1234.0, 5)
    assert (r["m_lo"], r["m_hi"]) == (12, 13)
    assert r["thd"] == pytest.approx(100 / 1234, rel=1e-12)
    assert r["m"] == pytest.approx(12.34, rel=1e-12)


def test_equalise_non_monotone_events():
    events = {57: 5700.0, 58: 6100.0, 59: 6050.0, 60: 6000.0}
    r = equalise(lambda m: (events[m], 1.0 / m), 5980.0, 60)
    # down from 60 through 59 and 58 (still above) to 57 (below); nothing untried between
    assert (r["m_lo"], r["m_hi"], r["evals"]) == (57, 60, 4)
    assert 1 / 60 <= r["thd"] <= 1 / 57


def test_equalise_out_of_reach():
    r = equalise(lambda m: (min(100.0 * m, 500.0), 1.0 / m), 1000.0, 2, m_max=50)
    assert math.isnan(r["thd"]) and math.isnan(r["m"])


# ------------------------------------------------------------------ the quick run


def test_quick_run_agrees_with_the_model(tmp_path):
    code = pins_report.main(["--quick", "--out", str(tmp_path), "--jobs", "2",
                             "--no-progress"])
    assert code == 0
    text = (tmp_path / "PINS_MODES.md").read_text()
    assert "every RTL point equals the model" in text and "DIFFERENT" not in text
    for name in ("pins_modes.png", "pins_sweep_thd.png", "which_mode_where.png"):
        assert (tmp_path / name).stat().st_size > 0
    with open(tmp_path / "pins_modes.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6 and {int(r["dead_clocks"]) for r in rows} == {1, 20}
    for r in rows:
        assert r["mismatches"] == "0" and r["ok"] == "True" and r["pins_identical"] == "True"
        for key in ("events", "turn_ons", "thd_i", "v1"):
            assert float(r[f"rtl_{key}"]) == pytest.approx(float(r[f"model_{key}"]), rel=1e-9)
        assert float(r["rtl_events"]) > 0 and float(r["rtl_thd_i"]) > 0
    with open(tmp_path / "pins_sweep.csv") as f:
        sweep = list(csv.DictReader(f))
    assert len(sweep) == 5 * 3 * 2 * 2        # modes x amplitudes x dead times x budgets
    assert all(not math.isnan(float(r["thd_i"])) for r in sweep)
