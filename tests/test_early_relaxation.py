"""The early-window analysis of N-body ensembles (analysis.relaxation_rates) on synthetic
ensembles of known answer, made here with numpy, not by the code under test.

Model: every particle starts uniform in J-bar over [0, 1/2) and jumps once, by +1/2, at an
exponential time of rate lam.  By tau a fraction q = 1 - exp(-lam tau) has jumped, so the
fraction below J-bar = 1/2 has changed by -q, and the coarse-grained entropy on bins of equal
width (four below 1/2, four above) by H(q) = -q ln q - (1 - q) ln(1 - q).  Each realisation's
values scatter about these; the standard errors must describe that scatter.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis.relaxation_rates import compare_rates, ensemble_changes
from hmfdiff.pipeline.layouts.relaxation_md import relaxation_md_dataset

EDGES = np.linspace(0.0, 1.0, 9)
TAU = np.array([0.0, 0.05, 0.1, 0.2, 0.4])


def _entropy_change(q):
    q = np.asarray(q, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = -np.where(q > 0, q * np.log(q), 0.0) - np.where(q < 1, (1 - q) * np.log(1 - q), 0.0)
    return h


def _synthetic(rng, n, r, lam, M0=0.7, m_offset=0.0, m_noise=0.01):
    """hist (T, R, B), overflow (T, R), M_abs (T, R) of the jump model; lam = 0: a stationary
    control, uniform over [0, 1) and measured with a jitter of 0.02 (periodic) at every time."""
    j0 = rng.uniform(0.0, 0.5 if lam > 0 else 1.0, size=(r, n))
    t_jump = rng.exponential(1.0 / lam, size=(r, n)) if lam > 0 else np.full((r, n), np.inf)
    hist = np.empty((TAU.size, r, EDGES.size - 1), dtype=np.int64)
    for k, tau in enumerate(TAU):
        j = j0 + 0.5 * (t_jump < tau)
        if lam == 0 and k > 0:
            j = np.mod(j + 0.02 * rng.standard_normal(j.shape), 1.0)
        for i in range(r):
            hist[k, i] = np.histogram(j[i], EDGES)[0]
    overflow = np.zeros((TAU.size, r), dtype=np.int64)
    M = M0 + m_offset + m_noise * rng.standard_normal((TAU.size, r))
    return hist, overflow, M


def test_changes_follow_the_jump_model_within_their_errors():
    """Over 150 synthetic ensembles, (estimate - truth) / error is a unit normal for the current
    through J-bar = 1/2, the entropy change and the <|M|> offset: a wrong standard error (the
    spread instead of the error of the mean, a missing sqrt) or a biased change fails."""
    rng = np.random.default_rng(20261125)
    lam, n, r = 0.9, 4000, 12
    q = 1 - np.exp(-lam * TAU[-1])
    z = {"dC": [], "dS": [], "M": []}
    for _ in range(150):
        hist, over, M = _synthetic(rng, n, r, lam, m_offset=0.003)
        ch = ensemble_changes(hist, over, M, EDGES, 0.7)
        (dc, dc_e), (ds, ds_e) = ch["dC"], ch["dS"]
        z["dC"].append((dc[-1, 4] - (-q)) / dc_e[-1, 4])
        z["dS"].append((ds[-1] - _entropy_change(q)) / ds_e[-1])
        z["M"].append((ch["M_offset"][0] - 0.003) / ch["M_offset"][1])
    for key, v in z.items():
        v = np.asarray(v)
        # Student t with 11 degrees of freedom: std 1.10; 150 draws: mean within +-0.3
        assert abs(v.mean()) < 0.3, (key, v.mean())
        assert 0.85 < v.std() < 1.4, (key, v.std())


def test_changes_at_every_time_and_edge():
    """The mean changes follow the model at every time (not only the last) and the edges away
    from the jump see none of it; tau = 0 is zero by construction."""
    rng = np.random.default_rng(7)
    lam = 2.0
    hist, over, M = _synthetic(rng, 20000, 8, lam)
    ch = ensemble_changes(hist, over, M, EDGES, 0.7)
    q = 1 - np.exp(-lam * TAU)
    dc, dc_e = ch["dC"]
    assert np.all(dc[0] == 0) and np.all(dc_e[0] == 0)
    np.testing.assert_allclose(dc[:, 4], -q, atol=4 * dc_e[:, 4].max() + 1e-12)
    # below 1/2 the fraction under edge e (e = 1, 2, 3) loses q e/4; above, gains nothing more
    for e in (2, 6):
        expect = -q * (e / 4 if e <= 4 else (8 - e) / 4)
        np.testing.assert_allclose(dc[:, e], expect, atol=4 * dc_e[:, e].max() + 1e-12)
    ds, ds_e = ch["dS"]
    np.testing.assert_allclose(ds, _entropy_change(q), atol=4 * ds_e.max() + 2e-4)


def _md_dataset(hist, over, M, n, initial, M0):
    out = {
        "time": TAU * n,
        "M_abs": M,
        "M_phase": np.zeros_like(M),
        "energy": np.zeros_like(M),
        "momentum": np.zeros_like(M),
        "M0_actions": M.mean(axis=1),
        "hist": hist,
        "overflow": over,
        "wall_time_s": 0.0,
    }

    class _State:
        pass

    st = _State()
    st.M0 = M0
    run = {"dt": 0.1, "tau_max": float(TAU[-1]), "seed": 0}
    ds = relaxation_md_dataset(out, EDGES, case="synthetic", state=st, n_particles=n, run=run)
    ds.attrs["initial"] = initial
    return ds


def _kinetic(lam, equation):
    """A kinetic evolution of the jump model: f on 400 uniform nodes of [0, 1], the mass below
    1/2 moved above it at the model's rate; Sdot at tau = 0 from dH/dq dq/dtau (infinite)."""
    nodes = 400
    w = np.full(nodes, 1.0 / nodes)
    jb = (np.arange(nodes) + 0.5) / nodes
    tau = np.linspace(0.0, 0.5, 201)
    q = 1 - np.exp(-lam * tau)
    f = np.where(jb[None, :] < 0.5, 1 - q[:, None], q[:, None]) / (4 * np.pi * 0.5)
    return xr.Dataset(
        {
            "f": (("tau", "Jbar"), f),
            "M0": (("tau",), 0.7 - 0.01 * q),
            "cell_width": (("Jbar",), w),
            "Sdot": (("tau_flux",), [np.inf]),
        },
        coords={"tau": tau, "Jbar": jb},
        attrs={"equation": equation},
    )


@pytest.mark.parametrize("lam_md", [0.6, 2.4])
def test_compare_rates_places_the_ensembles_between_the_equations(lam_md):
    """Ensembles that follow the 'landau' rate (lam = 0.6) or the 'lenard_balescu' rate (2.4)
    are found on that equation's value within their errors, off the other one, with the thermal
    control (no jumps) at zero; the core edge is the edge of the jump."""
    rng = np.random.default_rng(int(lam_md * 10))
    md = []
    for n in (2000, 8000):
        r = 64000 // n
        md.append(_md_dataset(*_synthetic(rng, n, r, lam_md), n, "state", 0.7))
        md.append(_md_dataset(*_synthetic(rng, n, r, 0.0, M0=0.68), n, "thermal", 0.68))
    kin = {"landau": _kinetic(0.6, "landau"), "lenard_balescu": _kinetic(2.4, "lenard_balescu")}
    ds, lines = compare_rates(md, kin)
    assert ds.attrs["core_edge"] == 4 and ds.attrs["core_edge_jbar"] == 0.5
    q_end = 1 - np.exp(-np.array([0.6, 2.4]) * TAU[-1])
    np.testing.assert_allclose(
        [float(ds.current_landau), float(ds.current_lenard_balescu)], q_end / TAU[-1], rtol=2e-3
    )
    np.testing.assert_allclose(
        [float(ds.entropy_rate_landau), float(ds.entropy_rate_lenard_balescu)],
        _entropy_change(q_end) / TAU[-1],
        rtol=2e-3,
    )
    follows = "landau" if lam_md == 0.6 else "lenard_balescu"
    other = "lenard_balescu" if follows == "landau" else "landau"
    st, th = ds.sel(initial="state"), ds.sel(initial="thermal")
    for key in ("current", "entropy_rate"):
        z = (st[f"{key}_md"] - float(ds[f"{key}_{follows}"])) / st[f"{key}_md_err"]
        assert np.all(np.abs(z) < 4), (key, z.values)
        z_other = (st[f"{key}_md"] - float(ds[f"{key}_{other}"])) / st[f"{key}_md_err"]
        assert np.all(np.abs(z_other) > 10), (key, z_other.values)
        assert np.all(np.abs(th[f"{key}_md"] / th[f"{key}_md_err"]) < 4), key
    # <|M|> offsets: both ensembles drawn at their own M0 with no offset
    assert np.all(np.abs(ds.M_offset_md / ds.M_offset_md_err) < 4)
    assert list(ds.n_realisations.values) == [32, 8]
    assert any("N = 8000 (R = 8)" in line for line in lines)


def test_compare_rates_needs_both_initials_at_every_size():
    rng = np.random.default_rng(3)
    md = [_md_dataset(*_synthetic(rng, 500, 4, 1.0), 500, "state", 0.7)]
    with pytest.raises(ValueError, match="missing"):
        compare_rates(md, {"landau": _kinetic(1.0, "landau")})
