"""Why the MD-against-theory bins beside the separatrix band are off (issue 23 part 4).

The full reproduction's validation (docs/reference/validation.csv) has six bins with |z| > 3
where Student t expects 1.35; four of them are the usable bins next to the separatrix band
(`analysis.agreement.beside_separatrix`), worst the thermal u = 0.2475 MD(bath) bin at
kappa0 = 1.039 (N D_MD / N D_Landau = 1.19, z = 8.9).  This study tests the candidate causes
one at a time, each against the bin-averaged theory of the pipeline (`fits.theory_bin_average`
on the MD's own J-bar bins):

    python studies/separatrix_bins.py theory     # seconds: truncation, grid, magnetisation
    python studies/separatrix_bins.py windowed   # seconds: the finite-time theory near kappa = 1
    python studies/separatrix_bins.py md N FIRST LAST [full]   # MD(bath) or MD(full) at
                                                 # u = 0.2475 in fine bins
    python studies/separatrix_bins.py fit        # the fine- and production-bin fits of those
    python studies/separatrix_bins.py propagated # those fine bins against the asymptotic and
                                                 # the propagated theory (`analysis.propagated`)
    python studies/separatrix_bins.py magnetisation  # MD(full): N D per realisation against
                                                 # the realisation's time-averaged |M|
    python studies/separatrix_bins.py blocks     # MD(full): N D per block of origins against
                                                 # |M| over that block's time window
    python studies/separatrix_bins.py spectrum [u=U] [MD_FILES...]  # MD(full)'s
                                                 # magnetisation spectrum against the dressed
                                                 # theory, by band (thermal u, default 0.2475)

`theory`: N D at the outlier bins with n_max = l_max = 6, 8, 10; on 400 and 1600 kappa nodes;
for a thermal state whose M0 is 1.5 % and 3 % off (MD(full)'s <|M|> differs from M0 by up to
2.5 % per realisation at u = 0.2475, N = 1e6).  `windowed`: the asymptotic and the windowed
Landau D (MD's lags 50-200, 4-20) at kappa 0.97-1.05.  `md`: MD(bath) realisations with the
paper's settings for u = 0.2475 (N_b = N, dt = 0.05, lags to 200, the fit window 50-200) but
120 J-bar bins (four per production bin) and the 20 000 test particles uniform in
J-bar in [0.28, 0.50], around the separatrix (J-bar = 0.320), written to
studies/out/sep_N{N}_seed{s}.nc; with `full`, MD(full) (N interacting particles, 1e5 of them
tracked, as the production runs, plus 20 000 test particles uniform in J-bar in [0.20, 0.50]) to
studies/out/sepfull_N{N}_seed{s}.nc.  `fit`: N D per fine bin and per production bin (four
fine bins summed) against the theory (Landau for MD(bath), Lenard-Balescu for MD(full)), for
each dynamics and N found.  `propagated`: the fine bins with kappa 0.95-1.12 (MD(bath)) or
0.88-1.12 (MD(full)) against the bin average of the asymptotic theory and against the theory
propagated over the fit's lags, D from the spectrum (n_max = l_max = 6), interpolated within
|kappa - 1| < 0.001 (and, for comparison, 0.003; and the theory grid on 1600 nodes): per bin,
and the mean z and mean z^2 of each.  `magnetisation`: the correlation over MD(full)'s
realisations between N D in pairs of fine bins and the realisation's time-averaged |M| / M0.
`blocks`: the same within realisations: for each block of origins (10 per realisation), the
half slope of <dJ-bar^2>(lag) over the fit window pooled over the fine bins of a kappa range,
against the mean and the standard deviation of |M| / M0 over the time the block's lags cover.
`spectrum`: the Welch N S_x, N S_y of MD(full)'s magnetisation (`analysis.md_spectrum`, as rule
spectrum; u = 0.2475 is not among figure 14's cases) against the dressed theory smoothed by
the Welch window, summed over frequency bands, for the study's MD(full) runs and any further
md files given (for example the production runs' results/md/thermal_u0.2475/full/*/*.nc).
"""

from __future__ import annotations

import glob
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from hmfdiff.analysis.fits import diffusion_fit, kappa_of_jbar, theory_at_bins, theory_bin_average
from hmfdiff.kinetic.spectrum import SpectrumTable, diffusion_from_spectrum, windowed_diffusion
from hmfdiff.kinetic.theory import theory_grid
from hmfdiff.meanfield import equilibrium, orbits
from hmfdiff.pipeline.layouts.theory import theory_dataset

OUT = Path(__file__).resolve().parent / "out"
U = 0.2475
FIT_WINDOW = (50.0, 200.0)
PRODUCTION_BINS = 30  # md.n_bins over [0, J-bar(kappa_max = 2)]
FINE = 4  # fine bins per production bin


def thermal(u=U, scale=1.0):
    return equilibrium.ThermalState(M0=scale * equilibrium.thermal_M0_from_energy(u))


def theory(state, **grid):
    return theory_dataset(theory_grid(state, **grid))


def fit_like(edges, M0, dynamics, jbar_range):
    """The attributes of a fit that `theory_bin_average` reads (uniform test particles)."""
    return xr.Dataset(
        {"jbar_edges": ("edge", edges), "M0": M0},
        attrs=dict(
            dynamics=dynamics,
            N=1_000_000,
            n_test=20_000,
            n_tracked_from_f=100_000,
            test_sampling="uniform",
            jbar_range=np.asarray(jbar_range, dtype=float),
        ),
    )


def study_theory():
    outliers = {-0.2: [1.164, 1.413], 0.0: [1.039], U: [0.942, 1.039]}
    print("N D at the outlier bins' centres with n_max = l_max = 6, 8, 10, over n_max = 6")
    for u, k in outliers.items():
        st, k = thermal(u), np.array(k)
        base = None
        for n in (6, 8, 10):
            ds = theory(st, n_max=n, l_max=n)
            d = np.array([theory_at_bins(ds, k, dyn) for dyn in ("bath", "full")])
            base = d if base is None else base
            r = np.round(d / base, 4)
            print(f"  u = {u:+}: n_max {n:2d}, kappa {k}: Landau {r[0]}, Lenard-Balescu {r[1]}")
    st = thermal()
    edges = np.linspace(0.0, orbits.rescaled_action(2.0, st.M0), PRODUCTION_BINS + 1)
    k0 = kappa_of_jbar(0.5 * (edges[1:] + edges[:-1]), st.M0)
    sel = (k0 > 0.9) & (k0 < 1.1)
    print(f"u = {U}: bin averages on the production bins kappa0 = {np.round(k0[sel], 3)}")
    cases = [("400 nodes", 1.0, {}), ("1600 nodes", 1.0, {"n_kappa": 1600})]
    cases += [(f"M0 x {s}", s, {}) for s in (0.97, 0.985, 1.015, 1.03)]
    ref = {}
    for label, scale, grid in cases:
        st = thermal(scale=scale)
        ds = theory(st, **grid)
        for dyn in ("bath", "full"):
            fit = fit_like(edges, st.M0, dyn, (0.0, edges[-1]))
            v = theory_bin_average(ds, fit, st.f)[sel]
            ref.setdefault(dyn, v)
            print(f"  {label:11s} {dyn}: {np.round(v, 4)}  ratio {np.round(v / ref[dyn], 3)}")


def study_windowed():
    st = thermal()
    table = SpectrumTable(st, n_max=6)
    k = np.array([0.97, 0.99, 1.005, 1.01, 1.014, 1.018, 1.022, 1.026, 1.03, 1.04, 1.05])
    print("kappa        ", k)
    print("Omega        ", np.round(orbits.frequency(k, st.M0), 4), f"(sqrt M0 = {st.M0**0.5:.4f})")
    print("asymptotic   ", np.round(diffusion_from_spectrum(table, k, st.M0), 3))
    for lags in (np.arange(50.0, 201.0, 2.0), np.arange(4.0, 21.0, 2.0)):
        w = windowed_diffusion(table, k, st.M0, lags)
        print(f"lags {lags[0]:.0f}-{lags[-1]:.0f}  ", np.round(w, 3))


#: the file-name prefix of each dynamics' realisations in OUT
PREFIX = {"bath": "sep", "full": "sepfull"}


def study_md(n, first, last, dynamics="bath"):
    from hmfdiff.dynamics.md import run_md
    from hmfdiff.dynamics.settings import MDRun
    from hmfdiff.pipeline.layouts.md import md_dataset

    OUT.mkdir(exist_ok=True)
    run = MDRun(
        case=f"u{U}-separatrix",
        dynamics=dynamics,
        n_particles=n,
        n_track=100_000 if dynamics == "full" else None,
        n_test=20_000,
        dt=0.05,
        t_max=600.0,
        sample_every=2.0,
        max_lag=200.0,
        origin_every=10.0,
        n_bins=FINE * PRODUCTION_BINS,
        # MD(full)'s outlier bin below the band (kappa0 = 0.942) lies at J-bar 0.256-0.276
        jbar_range=(0.28, 0.50) if dynamics == "bath" else (0.20, 0.50),
        m_every=2.0,
        n_store=0,
    )
    for seed in range(first, last + 1):
        t = time.perf_counter()
        md_dataset(run_md(thermal(), run, seed, 1, progress=lambda m: None)).to_netcdf(
            OUT / f"{PREFIX[dynamics]}_N{n}_seed{seed}.nc"
        )
        print(f"{dynamics}, N = {n}, seed {seed}: {time.perf_counter() - t:.1f} s", flush=True)


def coarsen(ds, factor):
    """The MD dataset with `factor` consecutive J-bar bins summed into one."""
    sums = {k: v.coarsen(bin=factor).sum() for k, v in ds.data_vars.items() if "bin" in v.dims}
    edges = ds["jbar_edges"].values[::factor]
    out = xr.Dataset(sums, coords={"lag": ds["lag"], "jbar_edges": ("edge", edges)})
    out.attrs = dict(ds.attrs, n_bins=out.sizes["bin"])
    out["jbar0"] = ("bin", 0.5 * (edges[1:] + edges[:-1]))
    return out


def study_fit():
    st = thermal()
    ds_th = theory(st, n_kappa=1600, separatrix_band=0.003)
    for dynamics, prefix in PREFIX.items():
        found = glob.glob(str(OUT / f"{prefix}_N*"))
        for n in sorted({int(Path(f).name.split("_")[1][1:]) for f in found}):
            fit_size(st, ds_th, dynamics, prefix, n)


def fit_size(st, ds_th, dynamics, prefix, n):
    """The fits of one dynamics and N, fine and production bins, against the theory."""
    theory_name = {"bath": "Landau", "full": "Lenard-Balescu"}[dynamics]
    files = sorted(glob.glob(str(OUT / f"{prefix}_N{n}_seed*.nc")))
    data = [xr.open_dataset(f) for f in files]
    for factor, what in ((1, "fine bins"), (FINE, "production bins")):
        fit = diffusion_fit([coarsen(d, factor) for d in data], FIT_WINDOW, 200, 0.0)
        th = theory_bin_average(ds_th, fit, st.f)
        e, nd, err = fit["jbar_edges"].values, fit["ND_md"].values, fit["ND_md_err"].values
        print(f"MD({dynamics}) N = {n:.0e}, {len(files)} seeds, {what}, fit window {FIT_WINDOW}:")
        for i in np.flatnonzero(fit["n_particles_in_bin"].values >= 200):
            lo, hi = kappa_of_jbar(e[i : i + 2], st.M0)
            if 0.9 < lo < 1.1:
                print(
                    f"  kappa {lo:.3f}-{hi:.3f}: MD {nd[i]:.3f} +- {err[i]:.3f}, "
                    f"{theory_name} {th[i]:.3f}, ratio {nd[i] / th[i]:.3f}, "
                    f"z {(nd[i] - th[i]) / err[i]:+.1f}"
                )


def study_propagated():
    from hmfdiff.analysis.propagated import nd_from_theory, propagated_at_bins
    from hmfdiff.kinetic.dielectric import DielectricTensor

    st = thermal()
    ds_th = theory(st, n_kappa=1600, separatrix_band=0.003)
    for dynamics, prefix in PREFIX.items():
        eps = DielectricTensor(st, l_max=6) if dynamics == "full" else None
        table = SpectrumTable(st, n_max=6, eps=eps)

        def spectrum(k, t=table):
            return diffusion_from_spectrum(t, k, st.M0)

        variants = {
            "gap 0.001": dict(nd_of_kappa=spectrum, gap=0.001),
            "gap 0.003": dict(nd_of_kappa=spectrum, gap=0.003),
            "grid 1600": dict(nd_of_kappa=nd_from_theory(ds_th, dynamics), gap=0.003),
        }
        lo = 0.95 if dynamics == "bath" else 0.88
        for n in sizes(prefix):
            files = sorted(glob.glob(str(OUT / f"{prefix}_N{n}_seed*.nc")))
            fit = diffusion_fit([xr.open_dataset(f) for f in files], FIT_WINDOW, 200, 0.0)
            th = theory_bin_average(ds_th, fit, st.f)
            prop = {k: propagated_at_bins(fit, f_of_kappa=st.f, **v) for k, v in variants.items()}
            nd, err = fit["ND_md"].values, fit["ND_md_err"].values
            kc = kappa_of_jbar(fit["jbar0"].values, st.M0)
            sel = (fit["n_particles_in_bin"].values >= 200) & (kc > lo) & (kc < 1.12)
            sel &= np.isfinite(th) & np.all([np.isfinite(v) for v in prop.values()], axis=0)
            print(f"MD({dynamics}) N = {n:.0e}, {len(files)} seeds, {sel.sum()} fine bins:")
            print(
                "  kappa          MD              asymptotic  propagated (" + ", ".join(prop) + ")"
            )
            e = fit["jbar_edges"].values
            for i in np.flatnonzero(sel):
                a, b = kappa_of_jbar(e[i : i + 2], st.M0)
                p = "  ".join(f"{v[i]:7.3f}" for v in prop.values())
                print(f"  {a:.3f}-{b:.3f}  {nd[i]:7.3f} +- {err[i]:.3f}  {th[i]:7.3f}   {p}")
            for name, v in {"asymptotic": th, **prop}.items():
                z = ((nd - v) / err)[sel]
                print(f"  {name:10s}: mean z {z.mean():+.2f}, mean z^2 {np.mean(z**2):.2f}")


def sizes(prefix):
    found = glob.glob(str(OUT / f"{prefix}_N*"))
    return sorted({int(Path(f).name.split("_")[1][1:]) for f in found})


def study_magnetisation():
    st = thermal()
    for n in sizes(PREFIX["full"]):
        files = sorted(glob.glob(str(OUT / f"{PREFIX['full']}_N{n}_seed*.nc")))
        data = [xr.open_dataset(f) for f in files]
        m = np.array([np.mean(np.hypot(d["Mx_fine"], d["My_fine"])) for d in data]) / st.M0
        fit = diffusion_fit([coarsen(d, 2) for d in data], FIT_WINDOW, 200, 0.0)
        print(
            f"MD(full) N = {n:.0e}: <|M|>/M0 over {len(files)} realisations {m.mean():.4f} "
            f"(spread {m.std(ddof=1):.4f})"
        )
        e, per = fit["jbar_edges"].values, fit["ND_md_seed"].values
        for i in range(per.shape[1]):
            a, b = kappa_of_jbar(e[i : i + 2], st.M0)
            y = per[:, i]
            if 0.93 < a < 1.08 and np.all(np.isfinite(y)):
                r = np.corrcoef(m, y)[0, 1]
                print(
                    f"  kappa {a:.3f}-{b:.3f}: N D {y.mean():7.3f}, correlation with <|M|> {r:+.2f}"
                )


def study_blocks():
    for n in sizes(PREFIX["full"]):
        files = sorted(glob.glob(str(OUT / f"{PREFIX['full']}_N{n}_seed*.nc")))
        print(f"MD(full) N = {n:.0e}, {len(files)} realisations x 10 blocks of origins:")
        for k_lo, k_hi in ((0.91, 0.99), (1.01, 1.10), (0.91, 1.10), (0.5, 0.8), (1.3, 1.8)):
            rows = []
            for f in files:
                d = xr.open_dataset(f)
                M0 = float(d.attrs["M0_actions"])
                e = d["jbar_edges"].values
                kc = kappa_of_jbar(0.5 * (e[1:] + e[:-1]), M0)
                sel = (kc > k_lo) & (kc < k_hi)
                lag = d["lag"].values
                w = (lag >= FIT_WINDOW[0]) & (lag <= FIT_WINDOW[1])
                msd = d["sum_dJbar2_block"].values[sel][:, w].sum(0) / d["count_block"].values[sel][
                    :, w
                ].sum(0)  # (lag, block)
                nd = 0.5 * n * np.polyfit(lag[w], msd, 1)[0]
                m = np.hypot(d["Mx_fine"].values, d["My_fine"].values) / M0
                tf = d["time_fine"].values
                per = d["n_origins_in_block"].values
                first = np.r_[0, np.cumsum(per)[:-1]]
                for b in range(per.size):
                    t0 = d.attrs["origin_every"] * first[b]
                    t1 = d.attrs["origin_every"] * (first[b] + per[b] - 1) + FIT_WINDOW[1]
                    mb = m[(tf >= t0) & (tf <= t1)]
                    rows.append((nd[b], mb.mean(), mb.std()))
            r = np.array(rows)
            print(
                f"  kappa {k_lo}-{k_hi}: N D(J-bar) {r[:, 0].mean():.3f} (blocks' sd "
                f"{r[:, 0].std():.3f}); correlation with the block's <|M|>/M0 "
                f"{np.corrcoef(r[:, 0], r[:, 1])[0, 1]:+.2f} (its sd {r[:, 1].std():.3f}), "
                f"with its sd of |M|/M0 {np.corrcoef(r[:, 0], r[:, 2])[0, 1]:+.2f}"
            )


def study_spectrum(extra):
    """`extra`: md files, optionally after u=U (another thermal state; then only those files)."""
    from hmfdiff.analysis.md_spectrum import measured_spectra, smoothed
    from hmfdiff.kinetic.dielectric import DielectricTensor

    u = U
    if extra and extra[0].startswith("u="):
        u, extra = float(extra[0][2:]), extra[1:]
    st = thermal(u)
    print(f"thermal state u = {u}, M0 = {st.M0:.6f}")
    dressed = SpectrumTable(st, n_max=8, eps=DielectricTensor(st, l_max=6))
    bare = SpectrumTable(st, n_max=8)
    sets = {}
    if u == U:
        sets = {
            f"study N = {n:.0e}": sorted(glob.glob(str(OUT / f"{PREFIX['full']}_N{n}_seed*.nc")))
            for n in sizes(PREFIX["full"])
        }
    if extra:
        sets["files given"] = sorted(extra)
    bands = ((0.03, 0.1), (0.1, 0.2), (0.2, 0.4), (0.1, 0.4), (0.4, 0.8), (0.8, 1.05),
             (0.8, 1.5), (1.5, 3.0))  # fmt: skip
    for name, files in sets.items():
        om, meas, n_seg, seg, dt, N = measured_spectra([xr.open_dataset(f) for f in files])
        print(
            f"{name}: {len(files)} realisations, N = {N:.0e}, {n_seg} Welch segments "
            f"of {seg * dt:g}"
        )
        for c, comp in (("x", "cc"), ("y", "ss")):
            th = smoothed(lambda w, k=comp: dressed(w, k), om, seg, dt)
            thb = smoothed(lambda w, k=comp: bare(w, k), om, seg, dt)
            S, E = meas[c]
            for lo, hi in bands:
                m = (om >= lo) & (om < hi)
                r, e = S[m].sum() / th[m].sum(), np.sqrt(np.sum(E[m] ** 2)) / th[m].sum()
                print(
                    f"  N S_{c}, omega {lo}-{hi}: MD / dressed {r:8.3f} +- {e:.3f}  "
                    f"(dressed / bare {th[m].sum() / thb[m].sum():.2f})"
                )


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else ""
    if what == "theory":
        study_theory()
    elif what == "windowed":
        study_windowed()
    elif what == "md" and len(sys.argv) in (5, 6) and sys.argv[5:] in ([], ["full"]):
        dyn = sys.argv[5] if len(sys.argv) == 6 else "bath"
        study_md(int(float(sys.argv[2])), int(sys.argv[3]), int(sys.argv[4]), dyn)
    elif what == "fit":
        study_fit()
    elif what == "propagated":
        study_propagated()
    elif what == "magnetisation":
        study_magnetisation()
    elif what == "blocks":
        study_blocks()
    elif what == "spectrum":
        study_spectrum(sys.argv[2:])
    else:
        sys.exit(__doc__.split("\n\n")[1])
