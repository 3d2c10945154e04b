"""Analysis of the golden model: switching counts and distortion, SVPWM against MDFQM.

Run ``python -m tools.analysis --out reports/`` (``--quick`` for a smaller sweep).

- :mod:`.signals`: references as codes, running each method, switching counts.
- :mod:`.metrics`: line-voltage THD (full band and below a stated frequency), weighted THD and
  phase-current THD through a balanced R-L load, all from the exact Fourier coefficients of the
  piecewise-constant gate waveforms.
- :mod:`.sweeps`: the seeds' comparisons (patent Figs. 12-15, paper Table 3, equal switching).
- :mod:`.report`: PNG plots (matplotlib, imported lazily) and the markdown table.

Only the plots import matplotlib; the model itself imports NumPy only.
"""

__all__: list[str] = []
