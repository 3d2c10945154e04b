"""The analysis: exact metrics against hand-derived and brute-force values, and the CLI."""

import io

import numpy as np
import pytest

from mdfqm_spec.contract import Contract
from tools.analysis.metrics import PWave, distortion
from tools.analysis.progress import Progress
from tools.analysis.signals import (
    bbit_method,
    ideal,
    ideal_duties,
    mdfqm,
    reference_codes,
    run_method,
)


def six_step(f1, steps_per_cycle=6, cycles=3):
    """Six-step (square-wave) operation: leg i on for half a cycle, shifted by 120 degrees."""
    n = steps_per_cycle * cycles
    k = np.arange(n) % 6
    legs = [((k - 2 * i) % 6 < 3).astype(int) for i in range(3)]
    h = legs[0] | (legs[1] << 1) | (legs[2] << 2)
    return PWave.from_samples(h, f1 * steps_per_cycle, 3)


def test_six_step_hand_values():
    f1, tau = 50.0, 2e-3
    d = distortion(six_step(f1), f1, 2000.0, tau)
    # line voltage: 120-degree quasi-square wave, harmonics 6k +- 1 with V_n = V_1 / n
    assert d["thd_full"] == pytest.approx(np.sqrt(np.pi**2 / 9 - 1), rel=1e-9)  # 31.08 %
    n = np.array([m for m in range(2, 200001) if m % 6 in (1, 5)], dtype=float)
    assert d["wthd"] == pytest.approx(np.sqrt((1 / n**4).sum()), rel=1e-6)
    inband = n[n * f1 < 2000.0]
    assert d["thd_band"] == pytest.approx(np.sqrt((1 / inband**2).sum()), rel=1e-9)
    assert d["thd_harm"] == pytest.approx(d["thd_band"], rel=1e-12)
    # phase current: V_n = V_1 / n too, I_n = V_n / |1 + j n w tau|
    w = 2 * np.pi * f1 * tau
    i_n2 = (1 / n**2) / (1 + (n * w) ** 2)
    assert d["thd_i"] == pytest.approx(np.sqrt(i_n2.sum() * (1 + w**2)), rel=1e-6)
    # fundamental of the line voltage: peak 2 sqrt(3) / pi Vdc
    assert d["v1"] == pytest.approx(2 * np.sqrt(3) / np.pi / np.sqrt(2), rel=1e-9)


def brute_force(w: PWave, rate, f1, f_band, tau, fine=64):
    """Sample on a grid ``fine`` times finer than the waveform's own (``rate``): the in-band
    THD by FFT with the zero-order-hold sinc correction, the current by exact exponential steps
    per fine sample and its sampled mean square."""
    t = w.t
    dt = 1.0 / (rate * fine)
    k = round(w.period / dt)
    assert k <= 1 << 16
    idx = np.minimum(np.searchsorted(t, (np.arange(k) + 0.5) * dt) - 1, len(w.s) - 1)
    s = w.s[idx]
    vab = s[:, 0] - s[:, 1]
    va = s[:, 0] - s.mean(axis=1)
    c = np.fft.fft(vab) / k
    ell = np.fft.fftfreq(k, 1 / k).round().astype(int)
    c = c * np.sinc(ell / k)
    l1 = round(f1 * w.period)
    f = np.abs(ell) / w.period
    p1 = 2 * abs(c[ell == l1][0]) ** 2
    band = (f > 0) & (f < f_band) & (np.abs(ell) != l1)
    thd_band = np.sqrt((np.abs(c[band]) ** 2).sum() / p1)
    # current: exact discretisation of tau di/dt + i = v at the fine step, two periods
    a = np.exp(-dt / tau)
    i, cur = 0.0, np.empty(k)
    for _ in range(2):
        for n in range(k):
            i = a * i + (1 - a) * va[n]
            cur[n] = i
    ca = np.fft.fft(va) / k * np.sinc(ell / k)
    i1 = 2 * abs(ca[ell == l1][0]) ** 2 / (1 + (2 * np.pi * f1 * tau) ** 2)
    ms = np.mean(cur**2) - np.mean(cur) ** 2
    return thd_band, np.sqrt((ms - i1) / i1)


def test_metrics_against_brute_force(rng):
    c = Contract(3, 16)
    refs = reference_codes(c, 1200.0, 50.0, 0.3, 0.04)
    run = run_method(c, mdfqm(2, 0), 1200.0, 50.0, 0.3, 0.04)
    f_band, tau = 900.0, float(rng.uniform(0.5e-3, 3e-3))
    d = distortion(run.wave, 50.0, f_band, tau)
    thd_band, thd_i = brute_force(run.wave, 2400.0, 50.0, f_band, tau)
    assert d["thd_band"] == pytest.approx(thd_band, rel=1e-6)
    assert d["thd_i"] == pytest.approx(thd_i, rel=2e-3)  # fine-grid sampling of the ripple
    assert refs.shape == (48, 3)


def test_centred_duties_equal_samples():
    # duties on a grid of 8 slots: both constructors give the same waveform and measures
    ang = 2 * np.pi * np.arange(40) / 20  # 2 cycles of 50 Hz at 1 kHz
    v = 0.4 * np.cos(ang[:, None] - 2 * np.pi * np.arange(3)[None, :] / 3)
    duties = np.round(ideal_duties(v, "svpwm") * 4) / 4  # even slot counts: exactly centred
    w1 = PWave.from_centred_duties(duties, 1000.0)
    slots = np.zeros((len(duties), 8), dtype=np.int64)
    on = np.round(duties * 8).astype(int)
    for i in range(3):
        start = (8 - on[:, i : i + 1]) // 2
        pos = np.arange(8)[None, :]
        slots |= ((pos >= start) & (pos < start + on[:, i : i + 1])).astype(np.int64) << i
    w2 = PWave.from_samples(slots.ravel(), 8000.0, 3)
    d1 = distortion(w1, 50.0, 1000.0, 1e-3)
    d2 = distortion(w2, 50.0, 1000.0, 1e-3)
    for key in d1:
        assert d1[key] == pytest.approx(d2[key], rel=1e-9, abs=1e-12)
    assert w1.switching_events() == w2.switching_events()


def test_svpwm_counts_and_bbit_agrees_with_ideal():
    c = Contract(3, 16)
    r_ideal = run_method(c, ideal("svpwm"), 3000.0, 50.0, 0.4, 0.2)
    r_b8 = run_method(c, bbit_method("svpwm", 8), 3000.0, 50.0, 0.4, 0.2)
    assert r_ideal.events_per_second() == pytest.approx(18000.0)
    assert r_b8.events_per_second() == pytest.approx(18000.0)
    di = distortion(r_ideal.wave, 50.0, 1500.0, 1e-3)
    db = distortion(r_b8.wave, 50.0, 1500.0, 1e-3)
    for key in ("v1", "thd_full", "wthd", "thd_i"):
        assert db[key] == pytest.approx(di[key], rel=0.01), key


def test_ideal_duties_modes():
    v = np.array([[0.3, -0.1, -0.2], [-0.25, 0.05, 0.2]])
    sv = ideal_duties(v, "svpwm")
    assert np.allclose(sv - sv.mean(axis=1, keepdims=True), v - v.mean(axis=1, keepdims=True))
    assert np.allclose(sv.max(axis=1) + sv.min(axis=1), 1.0)  # centred zero split
    d = ideal_duties(v, "dpwm")
    assert np.allclose(d[0].max(), 1.0) and np.allclose(d[1].min(), 0.0)
    with pytest.raises(ValueError, match="no ideal form"):
        ideal_duties(v, "mdfqm")


def test_window_must_hold_whole_cycles():
    with pytest.raises(ValueError, match="whole cycles"):
        distortion(six_step(50.0, cycles=3), 40.0, 1000.0, 1e-3)


def test_progress_bar_text():
    buf = io.StringIO()
    p = Progress(stream=buf, use_tqdm=False)
    p.start(10)
    p.advance(4, "freq: SVPWM")
    p.advance(6, "amp")
    p.finish()
    lines = buf.getvalue().splitlines()
    assert "40.0% 4/10 points" in lines[1] and "freq: SVPWM" in lines[1]
    assert "100.0% 10/10" in lines[-1]


def test_cli_quick(tmp_path):
    pytest.importorskip("matplotlib")
    from tools.analysis.__main__ import main

    assert main(["--out", str(tmp_path), "--quick", "--jobs", "1", "--no-progress"]) == 0
    text = (tmp_path / "REPORT.md").read_text()
    assert "The seeds' claims next to the model" in text
    assert "Paper Table 3" in text and "Equal switching count" in text
    assert (tmp_path / "results.csv").exists()
    assert len(list(tmp_path.glob("*.png"))) == 6


def test_cli_rejects_bad_arguments(tmp_path, capsys):
    from tools.analysis.__main__ import main

    with pytest.raises(SystemExit):
        main(["--out", str(tmp_path), "--tau", "-1"])
    assert "--tau must be > 0" in capsys.readouterr().err
