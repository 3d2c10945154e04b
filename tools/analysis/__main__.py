"""CLI: ``python -m tools.analysis [--out reports/] [--quick] [--jobs 2]``."""

from __future__ import annotations

import os

__all__ = []


# single-threaded BLAS: the sweeps run in parallel processes instead (and a loaded machine
# makes multi-threaded BLAS on small vectors thrash)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402


def main(argv=None) -> int:
    from .document import markdown
    from .plots import make_plots
    from .progress import Progress
    from .results_csv import write_csv
    from .sweeps import Config, make_jobs, run_jobs

    p = argparse.ArgumentParser(
        prog="python -m tools.analysis",
        description="Reproduce the seeds' switching-count and distortion comparisons "
        "(SVPWM vs MDFQM) with the golden model; writes PNG plots, REPORT.md and results.csv.",
    )
    p.add_argument("--out", default="reports", help="output directory (default: reports)")
    p.add_argument("--quick", action="store_true", help="a smaller sweep (seconds, for CI)")
    p.add_argument("--jobs", type=int, default=2, help="worker processes (default: 2)")
    p.add_argument("--tau", type=float, default=None, help="R-L load time constant in s (1e-3)")
    p.add_argument("--band", type=float, default=None, help="in-band THD limit in Hz (1500)")
    p.add_argument("--amp", type=float, default=None, help="amplitude of the frequency sweep")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    a = p.parse_args(argv)
    if a.jobs < 1:
        p.error("--jobs must be >= 1")
    cfg = Config.quick() if a.quick else Config()
    if a.tau is not None:
        if a.tau <= 0:
            p.error("--tau must be > 0")
        cfg.tau = a.tau
    if a.band is not None:
        if a.band <= 0:
            p.error("--band must be > 0")
        cfg.f_band = a.band
    if a.amp is not None:
        if not 0 < a.amp < 1:
            p.error("--amp must be in (0, 1)")
        cfg.amp_freq = a.amp
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    records = run_jobs(cfg, make_jobs(cfg), a.jobs, Progress(enabled=not a.no_progress))
    files = [] if a.no_plots else make_plots(records, cfg, out)
    write_csv(records, out / "results.csv")
    text = markdown(records, cfg, files, time.monotonic() - t0)
    (out / "REPORT.md").write_text(text)
    print(
        f"wrote {out / 'REPORT.md'}, results.csv and {len(files)} plots "
        f"in {time.monotonic() - t0:.1f} s",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
