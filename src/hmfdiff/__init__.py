"""hmfdiff: diffusion coefficients of the inhomogeneous HMF model.

Reproduces Benetti & Marcos, Phys. Rev. E 95, 022111 (2017): action-angle variables of the
pendulum (`orbits`), Fourier coefficients of the HMF potential (`fourier`), equilibrium states
(`equilibrium`), and the kinetic theory and molecular dynamics built on them.
"""

__version__ = "0.1.0"
