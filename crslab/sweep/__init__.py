"""``crslab sweep``: run one lab over many variations of the arm and its setup, and tabulate how
it fares (status and metrics per sample).

- :mod:`crslab.sweep.variations`: what may vary (``--vary NAME=LO:HI``) and how each name maps
  onto a run (the plant, the resting pose, faults, the lab's watched variables);
- :mod:`crslab.sweep.sampling`: seeded Latin hypercube or Sobol samples, or a full grid;
- :mod:`crslab.sweep.sample_job`: one sample's run, as a self-contained job for an executor;
- :mod:`crslab.sweep.run_metrics`: the metrics computed from a run's signals;
- :mod:`crslab.sweep.table`: the table (CSV or Parquet), its summary and its plot.
"""
