"""The mean-field state and its orbits: equilibria (thermal, core-halo) with a self-consistent
M0, pendulum action-angle variables, and the Fourier coefficients c_n, s_n of the potential."""
