"""The PNG figures of the report (matplotlib, imported only when plotting): switching events
and distortion against frequency and amplitude (patent Figs. 12-15), the reduction against the
paper's Table 3, and distortion at equal switching count."""

from __future__ import annotations

from pathlib import Path

from .comparisons import PAPER_CLAIMS, paper_fit, pct
from .records import METRICS, method_labels, series
from .sweeps import Config

__all__ = ["make_plots", "save_figure"]


def save_figure(fig, path: Path) -> None:
    """Lay ``fig`` out, write it to ``path`` at the reports' 72 dpi and close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=72)
    plt.close(fig)


def make_plots(records, cfg: Config, out: Path) -> list[str]:
    """Write the PNG figures into ``out``; return their file names in order."""
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []

    def style(m):
        if m == "SVPWM":
            return {"color": "k", "marker": "s"}
        if m == "DPWM":
            return {"color": "0.5", "marker": "D"}
        color = "tab:blue" if "OSR4" in m else "tab:orange"
        ls = "-" if "all-off" in m else "--"
        return {"color": color, "linestyle": ls, "marker": "o" if "all-off" in m else "^"}

    def save(fig, name):
        save_figure(fig, out / name)
        files.append(name)

    for sweep, xkey, xlabel, fig_sw, fig_d, title in (
        (
            "freq",
            "f0",
            "reference frequency (Hz)",
            "fig12_switching_vs_frequency.png",
            "fig13_distortion_vs_frequency.png",
            f"amplitude {cfg.amp_freq} Vdc, fc = {cfg.fc / 1e3:g} kHz",
        ),
        (
            "amp",
            "amp",
            "amplitude ratio Vd/Vdc (phase peak)",
            "fig14_switching_vs_amplitude.png",
            "fig15_distortion_vs_amplitude.png",
            f"f0 = {cfg.f0_amp:g} Hz, fc = {cfg.fc / 1e3:g} kHz",
        ),
    ):
        fig, ax = plt.subplots(figsize=(7, 4.2))
        for m in method_labels(records, sweep):
            x, y = series(records, sweep, m, xkey, "events_per_s")
            ax.plot(x, y, label=m, **style(m))
        ax.set_xlabel(xlabel)
        ax.set_ylabel("switching events / s (leg transitions)")
        ax.set_title("Switching events, " + title)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        save(fig, fig_sw)
        fig, axs = plt.subplots(2, 2, figsize=(9, 6.5))
        for axx, (key, name) in zip(axs.ravel(), METRICS, strict=True):
            for m in method_labels(records, sweep):
                x, y = series(records, sweep, m, xkey, key)
                axx.plot(x, y, label=m, **style(m))
            axx.set_yscale("log")
            axx.set_title(
                name + (f" ({cfg.f_band / 1e3:g} kHz)" if key == "thd_band" else ""), fontsize=9
            )
            axx.set_xlabel(xlabel, fontsize=8)
            axx.grid(alpha=0.3, which="both")
        axs[0, 0].legend(fontsize=6)
        fig.suptitle("Distortion, " + title + f", load tau = {cfg.tau * 1e3:g} ms", fontsize=10)
        save(fig, fig_d)

    fig, ax = plt.subplots(figsize=(7, 4.2))
    colors = ["tab:blue", "tab:green", "tab:red", "tab:purple"]
    for fc, col in zip(cfg.paper_fcs, colors, strict=False):
        for m in [m for m in method_labels(records, "paper") if m.startswith("MDFQM")]:
            amps, ev = series(records, "paper", m, "amp", "events_per_s", fc=fc)
            _, sv = series(records, "paper", "SVPWM", "amp", "events_per_s", fc=fc)
            ax.plot(
                amps,
                pct(ev, sv),
                color=col,
                linestyle="-" if "all-off" in m else "--",
                label=f"fc {fc / 1e3:g} kHz, {m.split()[-1]}",
            )
    a, model, _, _ = paper_fit(records, cfg, cfg.paper_fcs[0], "MDFQM OSR4 all-off")
    for (speed, claim), _mv in zip(PAPER_CLAIMS, model, strict=True):
        ax.plot(a * speed / 100, claim, "k*", markersize=10)
        ax.annotate(
            f"{speed} rpm",
            (a * speed / 100, claim),
            fontsize=7,
            xytext=(4, 4),
            textcoords="offset points",
        )
    ax.set_xlabel("amplitude ratio Vd/Vdc (phase peak)")
    ax.set_ylabel("% fewer switching events than SVPWM")
    ax.set_title(
        f"Paper Table 3: MDFQM OSR 4 vs SVPWM (stars: claims at amp = {a:.3f} x rpm/100)",
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save(fig, "table3_reduction_vs_amplitude.png")

    fig, axs = plt.subplots(
        len(cfg.equal_amps), 2, figsize=(9, 3.6 * len(cfg.equal_amps)), squeeze=False
    )
    for row, amp in enumerate(cfg.equal_amps):
        for col, key in enumerate(("thd_i", "wthd")):
            axx = axs[row, col]
            for m in method_labels(records, "equal"):
                x, y = series(records, "equal", m, "events_per_s", key, amp=amp)
                st = style(m)
                if m.startswith("MDFQM"):
                    axx.plot(
                        x,
                        y,
                        linestyle="none",
                        markersize=9,
                        label=m,
                        **{k: v for k, v in st.items() if k != "linestyle"},
                    )
                else:
                    axx.plot(x, y, label=m + " (carrier swept)", **st)
            axx.set_xscale("log")
            axx.set_yscale("log")
            axx.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            axx.set_xlabel("switching events / s", fontsize=8)
            axx.set_title(f"{dict(METRICS)[key]}, amplitude {amp}", fontsize=9)
            axx.grid(alpha=0.3, which="both")
        axs[row, 0].legend(fontsize=6)
    fig.suptitle("Distortion against switching count (equal-switching comparison)", fontsize=10)
    save(fig, "equal_switching.png")
    return files
