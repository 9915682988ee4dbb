"""Kinetic theory at order 1/N: the dielectric tensor, resonances, Landau and Lenard-Balescu
diffusion and polarisation coefficients, and the paper's closed forms."""
