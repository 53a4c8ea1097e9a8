"""Parameter sweeps and uncertainty: the ``[sweep]`` table of a case, run on Dask.

``spec`` (the table and its distributions), ``paths`` (dotted input paths), ``sampling``
(Latin hypercube / Sobol designs), ``store`` (one folder per sample, keyed by its parameters),
``cluster`` (the Dask client), ``statistics`` (summaries and SALib indices), ``plotting``,
``report`` and ``run`` (the driver called by the case runner). See ``docs/sweeps.md``.
"""
