"""Campaigns: many scans (or kilometres of profile) through ``analyse`` on a Dask cluster.

- :mod:`.inputs`   INPUTS (files, globs, manifest CSV) -> one job per input, in input order;
- :mod:`.folder`   atomic per-scan output folders and the resume sidecar;
- :mod:`.worker`   what a Dask worker runs for one input (reads, analyses, writes, returns a
  small record; big arrays never leave the worker);
- :mod:`.sections` long line profiles cut into sections along chainage, read in chunks;
- :mod:`.runner`   the Dask client side: local cluster or ``--scheduler``, progress, Ctrl-C;
- :mod:`.table`    ``campaign.csv``, its anisotropy sectors in ``campaign_anisotropy.csv`` (and
  ``campaign.parquet`` when pyarrow is installed);
- :mod:`.report`   ``report.html`` of the campaign.
"""
