"""The bin average of the theory's windowed and spectral predictions (hmfdiff.analysis.windowed):
each J-bar_0 bin is the mean over its tracked particles, i.e. the integral of D weighted by the
density of tracked particles over the bin, divided by the bin's number of particles."""

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis.fits import kappa_of_jbar
from hmfdiff.analysis.windowed import windowed_at_bins
from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.kinetic.spectrum import SpectrumTable, diffusion_from_spectrum
from hmfdiff.meanfield.equilibrium import ThermalState


def test_bin_average_is_the_density_weighted_integral_over_the_bin():
    """MD(full) of a thermal state (tracked density 4 pi N f, which falls 70-fold across the
    first bin) in two wide bins of librating orbits: ND_spectrum per bin against the same D
    (`diffusion_from_spectrum`, dressed) integrated by 40-point Gauss-Legendre with the
    Maxwell-Boltzmann weight f(kappa(J-bar)) written here.  Guards against the unweighted mean
    over the sub-points (measured +47 % in the first bin) and against sub-points at the left
    ends of their cells instead of the centres (-18 %).  Measured: 5.0e-3 and 3.4e-3 with the
    default 7 sub-points (the midpoint rule's error on a weight that varies 70-fold)."""
    state = ThermalState(M0=0.72846)
    M0 = state.M0
    edges = np.array([0.1, 0.5, 0.9])
    lag = np.arange(0.0, 101.0, 5.0)
    fit = xr.Dataset({"M0": ((), M0)}, coords={"lag": ("lag", lag), "jbar_edges": ("edge", edges)})
    fit.attrs.update(dynamics="full", fit_window=[20.0, 100.0], N=1000.0, n_test=0)
    _, nd_s = windowed_at_bins(fit, state, n_max=3, l_max=3)

    table = SpectrumTable(state, n_max=3, eps=DielectricTensor(state, l_max=3))
    x, w = np.polynomial.legendre.leggauss(40)
    beta = state.beta
    for b in range(edges.size - 1):
        lo, hi = edges[b], edges[b + 1]
        jb = 0.5 * (hi - lo) * x + 0.5 * (hi + lo)
        k = kappa_of_jbar(jb, M0)
        weight = w * np.exp(-beta * M0 * (2.0 * k**2 - 1.0))  # f(kappa) up to its constant
        ref = np.sum(weight * diffusion_from_spectrum(table, k, M0)) / np.sum(weight)
        assert nd_s[b] == pytest.approx(ref, rel=1.5e-2), (b, nd_s[b], ref)
