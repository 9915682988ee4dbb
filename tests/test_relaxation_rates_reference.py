"""Guards for hmfdiff.analysis.relaxation_rates: the standard error of a mean over
realisations (ddof 1), the fractions below each edge counting the overflow, and the kinetic
changes since tau = 0 (dM, dC, dS) of synthetic evolutions whose answer is known in closed
form, one of them moving mass beyond the last edge."""

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis.relaxation_rates import (
    cumulative_below_edges,
    kinetic_changes,
    mean_and_error,
)


def kinetic_dataset(nodes, jbar_max, f_of, dM0):
    """A kinetic relaxation file (f, M0, cell_width on tau x J-bar) on `nodes` equal cells of
    [0, jbar_max), f = f_of(J-bar, q) and M0 = 0.7 - dM0 q with q = 1 - e^{-tau} on a tau grid
    of step 0.0025 (linear interpolation of q in tau: error < 1e-6)."""
    jb = (np.arange(nodes) + 0.5) / nodes * jbar_max
    tau_k = np.linspace(0.0, 1.0, 401)
    q_k = 1 - np.exp(-tau_k)
    return xr.Dataset(
        {
            "f": (("tau", "Jbar"), f_of(jb[None, :], q_k[:, None])),
            "M0": (("tau",), 0.7 - dM0 * q_k),
            "cell_width": (("Jbar",), np.full(nodes, jbar_max / nodes)),
        },
        coords={"tau": tau_k, "Jbar": jb},
    )


def test_mean_and_error_is_the_standard_error_with_ddof_1():
    """Guards against sqrt(n) vs sqrt(n - 1) (ddof 0) and std instead of std/sqrt(n): for the
    realisations 1, 2, 3, 6 the mean is 3 and the standard error sqrt(14/3)/2 (sample variance
    (4 + 1 + 0 + 9)/3, by hand); one realisation gives NaN."""
    v = np.array([[1.0, 2.0, 3.0, 6.0], [0.0, 0.0, 0.0, 4.0]])  # (time, realisation)
    m, e = mean_and_error(v)
    np.testing.assert_allclose(m, [3.0, 1.0], rtol=1e-14)
    np.testing.assert_allclose(e, [np.sqrt(14.0 / 3.0) / 2.0, np.sqrt(12.0 / 3.0) / 2.0])
    m1, e1 = mean_and_error(v[:, :1])
    assert np.all(np.isnan(e1)) and np.all(m1 == v[:, 0])


def test_fractions_below_edges_count_the_overflow():
    """Guards against normalising by the binned particles only (particles beyond the last edge
    forgotten): 2 and 3 particles in two bins and 5 beyond them give fractions 0, 0.2, 0.5
    below the three edges."""
    C = cumulative_below_edges(np.array([[2, 3]]), np.array([5]))
    np.testing.assert_allclose(C, [[0.0, 0.2, 0.5]], rtol=1e-14)


def test_kinetic_changes_of_a_known_evolution():
    """Guards against the kinetic dM, dC or dS not being changes since tau = 0 (e.g. M0 itself
    instead of M0(tau) - M0(0)): f uniform on [0, 1/2) moving to [1/2, 1) as q = 1 - e^{-tau}
    (400 nodes, 4 pi f w summing to 1) with M0 = 0.7 - 0.01 q, binned on 8 equal bins:
    dM = -0.01 q, the fraction below J-bar = 1/2 changes by -q, below 1/4 by -q/2, and the
    entropy by the mixing entropy -q ln q - (1 - q) ln(1 - q) (by hand)."""
    ds = kinetic_dataset(
        400, 1.0, lambda jb, q: np.where(jb < 0.5, 1 - q, q) / (4 * np.pi * 0.5), 0.01
    )
    edges = np.linspace(0.0, 1.0, 9)
    tau = np.array([0.0, 0.25, 0.5, 1.0])
    q = 1 - np.exp(-tau)
    ch = kinetic_changes(ds, edges, tau)
    # linear interpolation in tau of a smooth q on a 0.0025 grid: error < 1e-6
    np.testing.assert_allclose(ch["dM"], -0.01 * q, atol=1e-8)
    np.testing.assert_allclose(ch["dC"][:, 4], -q, atol=1e-6)
    np.testing.assert_allclose(ch["dC"][:, 2], -q / 2, atol=1e-6)
    np.testing.assert_allclose(ch["dC"][:, [0, 8]], 0.0, atol=1e-12)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = -np.where(q > 0, q * np.log(q), 0.0) - (1 - q) * np.log(1 - q)
    np.testing.assert_allclose(ch["dS"], h, atol=1e-5)
    assert ch["dS"][0] == pytest.approx(0.0, abs=1e-15)


def test_kinetic_entropy_counts_the_mass_beyond_the_last_edge():
    """Guards against the kinetic dS renormalising the binned fractions to one (the mass beyond
    the last edge ignored).  f is uniform on [0, 1) (8 bins of width 1/8) with a fraction
    q = 1 - e^{-tau} moved uniformly to [1, 3/2), beyond the last edge.  Each bin then holds
    P_b = (1 - q)/8, so (by hand) S = -(1 - q) ln((1 - q)/(4 pi)) and dS = -(1 - q) ln(1 - q)
    - q ln(4 pi); renormalised fractions (1/8 each) would give dS = 0.  dC at the last edge is
    -q."""
    ds = kinetic_dataset(
        600, 1.5, lambda jb, q: np.where(jb < 1.0, 1 - q, q / 0.5) / (4 * np.pi), 0.0
    )
    edges = np.linspace(0.0, 1.0, 9)
    tau = np.array([0.0, 0.2, 0.5, 1.0])
    q = 1 - np.exp(-tau)
    ch = kinetic_changes(ds, edges, tau)
    np.testing.assert_allclose(ch["dC"][:, -1], -q, atol=1e-6)
    with np.errstate(divide="ignore", invalid="ignore"):
        dS = -(1 - q) * np.log(1 - q) - q * np.log(4 * np.pi)
    np.testing.assert_allclose(ch["dS"], dS, atol=1e-5)
    # the effect guarded is large: dS(tau = 1) = -0.97, against 0 when renormalised
    assert ch["dS"][-1] < -0.9
