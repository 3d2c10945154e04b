"""The seeds' comparisons as sweeps of independent jobs (run in parallel by :func:`run_jobs`).

Sweeps (defaults of :class:`Config`; every choice is stated in the report):

- ``freq``: reference frequency 20-100 Hz at amplitude ``amp_freq``, sampled at ``fc`` = 3 kHz,
  MDFQM at OSR 4 and OSR 2 with both zero policies; SVPWM and DPWM at ``fsw = fc``
  (patent Figs. 12-13).
- ``amp``: amplitude ratio Vd/Vdc (phase peak / Vdc) at ``f0_amp`` = 50 Hz, same methods
  (patent Figs. 14-15).
- ``paper``: switching reduction vs amplitude for ``fc`` = 3, 4, 5 kHz at OSR 4 (paper Table 3).
- ``equal``: SVPWM and DPWM with the carrier swept, against MDFQM at ``fc``, for distortion at
  equal switching count.
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field

import numpy as np

from mdfqm_spec.contract import ALL_OFF, FEWEST_TRANSITIONS, Contract

from .metrics import distortion
from .signals import Method, ideal, mdfqm, run_mdfqm_batch, run_method

__all__ = ["Config", "Job", "make_jobs", "run_job", "run_jobs"]


@dataclass
class Config:
    """Every parameter of the default report (``quick`` shrinks the sweeps)."""

    phases: int = 3
    width: int = 16
    fc: float = 3000.0
    seconds: float = 1.0
    tau: float = 1e-3
    f_band: float = 1500.0
    amp_freq: float = 0.5
    f0_amp: float = 50.0
    f0_paper: float = 25.0
    freqs: list = field(default_factory=lambda: [20, 30, 40, 50, 60, 70, 80, 90, 100])
    amps: list = field(
        default_factory=lambda: [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.575]
    )
    paper_fcs: list = field(default_factory=lambda: [3000.0, 4000.0, 5000.0])
    paper_amps: list = field(
        default_factory=lambda: list(np.round(np.arange(0.02, 0.5761, 0.02), 3))
    )
    equal_amps: list = field(default_factory=lambda: [0.25, 0.5])
    equal_fsw: list = field(
        default_factory=lambda: [500, 750, 1000, 1250, 1500, 2000, 2500, 3000, 4000]
    )
    osrs: list = field(default_factory=lambda: [4, 2])

    @classmethod
    def quick(cls) -> Config:
        return cls(
            seconds=0.5,
            freqs=[20, 60, 100],
            amps=[0.1, 0.2, 0.3, 0.4, 0.5],
            paper_fcs=[3000.0],
            paper_amps=[0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5],
            equal_amps=[0.5],
            equal_fsw=[1000, 2000, 3000],
        )

    def contract(self) -> Contract:
        return Contract(self.phases, self.width)


@dataclass
class Job:
    """One method over a list of ``(f0, amp)`` points at one sampling / carrier frequency."""

    sweep: str
    method: Method
    fc: float
    points: list
    fsw: float | None = None
    metrics: bool = True

    @property
    def size(self) -> int:
        return len(self.points)


def _carrier_methods() -> list[Method]:
    return [ideal("svpwm"), ideal("dpwm")]


def _mdfqm_methods(osrs) -> list[Method]:
    return [mdfqm(o, p) for o in osrs for p in (ALL_OFF, FEWEST_TRANSITIONS)]


def make_jobs(cfg: Config) -> list[Job]:
    jobs: list[Job] = []
    freq_pts = [(float(f), cfg.amp_freq) for f in cfg.freqs]
    amp_pts = [(cfg.f0_amp, float(a)) for a in cfg.amps]
    for sweep, pts in (("freq", freq_pts), ("amp", amp_pts)):
        for m in _mdfqm_methods(cfg.osrs):
            jobs.append(Job(sweep, m, cfg.fc, pts))
        for m in _carrier_methods():
            jobs.append(Job(sweep, m, cfg.fc, pts))
    paper_pts = [(cfg.f0_paper, float(a)) for a in cfg.paper_amps]
    for fc in cfg.paper_fcs:
        for m in _mdfqm_methods([4]):
            jobs.append(Job("paper", m, fc, paper_pts, metrics=False))
        jobs.append(Job("paper", ideal("svpwm"), fc, paper_pts, metrics=False))
    eq_pts = [(cfg.f0_amp, float(a)) for a in cfg.equal_amps]
    for m in _mdfqm_methods(cfg.osrs):
        jobs.append(Job("equal", m, cfg.fc, eq_pts))
    for fsw in cfg.equal_fsw:
        for m in _carrier_methods():
            jobs.append(Job("equal", m, cfg.fc, eq_pts, fsw=float(fsw)))
    return jobs


def run_job(cfg: Config, job: Job) -> list[dict]:
    """Run one job; one record (a flat dict) per point."""
    c = cfg.contract()
    m = job.method
    if m.kind == "mdfqm":
        runs = run_mdfqm_batch(c, m.osr, m.zero_policy, job.fc, job.points, cfg.seconds, m.rule)
    else:
        runs = [run_method(c, m, job.fc, f0, a, cfg.seconds, job.fsw) for f0, a in job.points]
    out = []
    for (f0, a), run in zip(job.points, runs, strict=True):
        rec = {
            "sweep": job.sweep,
            "method": m.label,
            "kind": m.kind,
            "mode": m.mode,
            "osr": m.osr,
            "zero_policy": m.zero_policy,
            "fc": job.fc,
            "fsw": job.fsw if job.fsw is not None else (job.fc if m.kind != "mdfqm" else None),
            "f0": f0,
            "amp": a,
            "events_per_s": run.events_per_second(),
            "saturated": run.saturated,
        }
        if job.metrics:
            rec.update(distortion(run.wave, f0, cfg.f_band, cfg.tau))
        out.append(rec)
    return out


def _worker(args):
    cfg_dict, job = args
    return run_job(Config(**cfg_dict), job)


def run_jobs(cfg: Config, jobs: list[Job], workers: int = 2, progress=None) -> list[dict]:
    """Run every job (``workers`` processes; 1 = in this process), reporting to ``progress``."""
    records: list[dict] = []
    total = sum(j.size for j in jobs)
    if progress is not None:
        progress.start(total)
    # biggest first for a better schedule
    order = sorted(
        jobs, key=lambda j: -(j.size * (j.method.osr if j.method.kind == "mdfqm" else 1))
    )
    if workers <= 1:
        for job in order:
            records.extend(run_job(cfg, job))
            if progress is not None:
                progress.advance(job.size, f"{job.sweep}: {job.method.label}")
    else:
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futs = {pool.submit(_worker, (asdict(cfg), job)): job for job in order}
            for fut in as_completed(futs):
                job = futs[fut]
                records.extend(fut.result())
                if progress is not None:
                    progress.advance(job.size, f"{job.sweep}: {job.method.label}")
    if progress is not None:
        progress.finish()
    return records
