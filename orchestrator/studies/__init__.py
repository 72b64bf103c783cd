"""Stage 8, the studies: many cases at once (sweeps on local or Dask executors) and what is
learnt across them (speed against error, stability, the synthetic-record study)."""
