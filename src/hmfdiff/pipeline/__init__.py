"""Pipeline plumbing, free of physics: netCDF I/O with provenance, dataset layouts, the
configuration checks, logging and threads."""
