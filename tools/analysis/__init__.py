"""Analysis of the golden model: switching counts and distortion, SVPWM against MDFQM.

Run ``python -m tools.analysis --out reports/`` (``--quick`` for a smaller sweep).

- :mod:`.signals`: references as codes, running each method, switching counts.
- :mod:`.metrics`: line-voltage THD (full band and below a stated frequency), weighted THD and
  phase-current THD through a balanced R-L load, all from the exact Fourier coefficients of the
  piecewise-constant gate waveforms.
- :mod:`.sweeps`: the seeds' comparisons (patent Figs. 12-15, paper Table 3, equal switching).
- :mod:`.progress`: the progress bar of a sweep run (tqdm if installed, else its own).
- :mod:`.records`: reading the records: selecting points, methods in display order, series.
- :mod:`.comparisons`: the numbers compared: reductions and distortion ratios against SVPWM,
  the paper's Table 3 fit, the equal-switching-count interpolation.
- :mod:`.plots`: the PNG figures (matplotlib, imported lazily).
- :mod:`.results_csv`: ``results.csv``, every record as one row.
- :mod:`.tables`: the markdown tables of the sweeps and comparisons.
- :mod:`.claims`: the seeds' claims next to the model, with verdicts and notes.
- :mod:`.document`: the text of ``REPORT.md``, assembling the sections.

Only the plots import matplotlib; the model itself imports NumPy only.
"""

__all__: list[str] = []
