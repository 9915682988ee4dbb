"""hmfdiff: collisional relaxation of the inhomogeneous HMF model.

Reproduces and extends Benetti & Marcos, Phys. Rev. E 95, 022111 (2017).  The sub-packages
follow the method:

- `meanfield`: equilibrium states, pendulum action-angle variables, Fourier coefficients;
- `kinetic`: dielectric tensor, resonances, Landau / Lenard-Balescu coefficients, closed forms;
- `dynamics`: molecular dynamics, MD(bath) and MD(full), and <dJ^2> measured on the fly;
- `analysis`: diffusion fits, MD against theory, figures;
- `pipeline`: netCDF I/O, dataset layouts, configuration checks, logging.
"""

__version__ = "0.1.0"
