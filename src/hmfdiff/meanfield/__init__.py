"""The mean-field state and its orbits: equilibria (thermal, core-halo) with a self-consistent
M0, pendulum action-angle variables, the Fourier coefficients c_n, s_n of the potential, and
J-bar histograms read as f and its entropy (histograms)."""
