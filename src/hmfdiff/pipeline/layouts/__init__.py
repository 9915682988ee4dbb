"""Every netCDF dataset the pipeline writes, laid out: named dimensions, and units and a long
name on every variable through one helper (`variable`, re-exported here with the ranges and
units every layout shares, from `variables`).  One module per stage of the physics:

* `equilibrium`: results/equilibrium/, results/orbits/ (mean field; `state_from_dataset`);
* `theory`: results/theory/, results/analytic/ (kinetic theory of the diffusion coefficients);
* `md`: results/md/, results/fits/ (the diffusion measured by MD(bath) and MD(full), fitted);
* `fluctuations`: results/spectrum/, results/scaling/, results/windowed/ (the MD precision
  wing: magnetisation spectra, N D_MD against N, the theory fitted like the MD);
* `relaxation_md`: results/relaxation_md/ (N-body relaxation ensembles);
* `kinetic_relaxation`: results/relaxation/ (relaxation by the Landau or Lenard-Balescu
  equation).

Physics modules return arrays; these modules name them.  They import only the mean-field
physics, and this package imports none of its stage modules, so that a rule whose script
imports one stage's layout does not rerun when another stage's layout or physics changes
(`pipeline.deps`): import the functions from their stage module.
"""

from .variables import (
    ACTION,
    COMPONENT,
    D_UNITS,
    ENERGY_PER_PARTICLE,
    NONNEGATIVE,
    UNIT_INTERVAL,
    flag_word,
    variable,
)

__all__ = [
    "variable",
    "flag_word",
    "NONNEGATIVE",
    "UNIT_INTERVAL",
    "COMPONENT",
    "ENERGY_PER_PARTICLE",
    "D_UNITS",
    "ACTION",
]
