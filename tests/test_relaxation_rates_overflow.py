"""Guard for hmfdiff.analysis.relaxation_rates.kinetic_changes: the coarse-grained kinetic
entropy counts the mass that has left the binned range (beyond the last edge) in the
normalisation of its bin fractions, as the MD side does with its overflow."""

import numpy as np
import xarray as xr

from hmfdiff.analysis.relaxation_rates import kinetic_changes


def test_kinetic_entropy_counts_the_mass_beyond_the_last_edge():
    """Guards against the kinetic dS renormalising the binned fractions to one (mass beyond
    the last edge ignored, mutation RR06 of the first sweep).  f is uniform on [0, 1) (the 8
    bins of width 1/8) with a fraction q = 1 - e^{-tau} moved uniformly to [1, 3/2), beyond
    the last edge.  Each bin then holds P_b = (1 - q)/8 of the particles, so (by hand)
    S = -(1 - q) ln((1 - q)/(4 pi)) and dS = -(1 - q) ln(1 - q) - q ln(4 pi); renormalised
    fractions (1/8 each) would give dS = 0.  dC at the last edge is -q.  Linear interpolation
    of q on the 0.0025 tau grid: error < 1e-6."""
    nodes = 600
    jb = (np.arange(nodes) + 0.5) / nodes * 1.5  # cells of width 1/400 on [0, 3/2)
    tau_k = np.linspace(0.0, 1.0, 401)
    q_k = 1 - np.exp(-tau_k)
    inside = jb[None, :] < 1.0
    f = np.where(inside, (1 - q_k[:, None]) / 1.0, q_k[:, None] / 0.5) / (4 * np.pi)
    ds = xr.Dataset(
        {
            "f": (("tau", "Jbar"), f),
            "M0": (("tau",), np.full(tau_k.size, 0.6)),
            "cell_width": (("Jbar",), np.full(nodes, 1.5 / nodes)),
        },
        coords={"tau": tau_k, "Jbar": jb},
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
