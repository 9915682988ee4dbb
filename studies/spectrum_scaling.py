"""Field or response: the hot halo's core-edge N D excess against N (issue 38 part 3).

In MD(full) of the hot halo (`corehalo_hothalo`), N D in the bin at the core's edge (kappa0 =
0.43 of the md_scaling study) falls with N towards the dressed (Lenard-Balescu) theory.  The
kinetic theory's D of an orbit is the field's spectrum at its resonances,
N D = sum_n n^2 [c_n^2 N S_x(n Omega) + sigma_n^2 N S_y(n Omega)]
(`kinetic.spectrum.diffusion_from_spectrum`), so the excess is either in the FIELD (the
measured N S_x, N S_y at n Omega exceed the dressed theory's) or in the RESPONSE (the field is
the theory's, but the particles' N D exceeds what that field gives them).  Per N this reports,
for the bin, with jackknife errors over realisations (paired: one realisation left out of
every quantity at once):

  (a) the measured N D (`fits.diffusion_fit` with the md_scaling fit settings and bins);
  Welch route (as studies/spectrum_diffusion.py): (b) N D from the MD's measured spectrum
      (Welch, `analysis.md_spectrum`), (c) from the dressed theory's spectrum smoothed by the
      same window, both averaged over the bin with the density of its tracked particles
      (`fits.tracked_density`); field (b)/(c), response (a)/(b);
  time domain: (bw) the quasi-linear <dJ^2>(lag) of the bin's orbits in each realisation's
      measured field (`fluctuations.quasilinear_dj2`; the field high-passed at OMEGA_MIN),
      fitted over the MD's window, and (cw) the dressed theory fitted over the same lags
      (`spectrum.windowed_diffusion`): the same finite-time kernel as (a) on both sides, which
      matters where the spectrum has structure narrower than the Welch resolution (here the
      weakly damped eps_cc mode at omega = 1.585, just below 2 Omega of the bin's upper edge);
      field (bw)/(cw), response (a)/(bw);
  (d) N S_x, N S_y averaged over the bands n Omega(kappa) swept by the bin (widened by the
      Welch resolution 4 pi / segment) and over four sub-bands of each, MD against dressed,
      and each harmonic's share of (c) and (b);
  excursions: (am) walkers that start in the bin and diffuse with the quasi-linear N D(kappa)
      of the MD's own field (`excursion_nd`), fitted like the MD: the part of (a)/(bw) that
      is the particles' wandering over a steep D(kappa) during the fit window, with no
      dynamics beyond local quasi-linear diffusion; and the rms kappa excursion of the bin's
      particles against the e-folding length of the dressed D(kappa) across the bin;
and power-law fits against N (`separatrix_crossings.scaling_exponent`).  Control: the deep
core (--kappa0 0.25), where MD(full) follows the dressed theory.

Two steps (one core each; `run` skips seed files already written):

    python studies/spectrum_scaling.py run OUT_DIR N FIRST_SEED LAST_SEED
    python studies/spectrum_scaling.py analyse OUT_DIR [--kappa0 0.43]

`run` draws the realisations of the md_scaling study of config/config.yaml
(`dynamics.runs.md_scaling_runs`: corehalo_hothalo, MD(full), the same settings at any N;
seed s is the md_scaling study's seed s) into OUT_DIR/N{N}/seed{s}.nc; `analyse` reads every
OUT_DIR/N*/ (seeds 0 ... R-1) and prints the table (docs/reference/spectrum_scaling_hothalo.txt).
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import yaml

CASE = "corehalo_hothalo"
CONFIG = "config/config.yaml"


def scaling_run(n, config=CONFIG):
    """The md_scaling study's MD(full) record of the case at size n (its own n when listed;
    otherwise the record of the smallest listed size with n_particles = n)."""
    from hmfdiff.dynamics.runs import md_scaling_runs

    with open(config) as f:
        cfg = yaml.safe_load(f)
    runs = {k[2]: r for k, r in md_scaling_runs(cfg).items() if k[:2] == (CASE, "full")}
    if n in runs:
        return cfg, runs[n]
    return cfg, dataclasses.replace(runs[min(runs)], n_particles=int(n))


def run(out, n, first, last):
    from _realisations import draw_realisations

    from hmfdiff.meanfield.equilibrium import make_state

    cfg, rec = scaling_run(int(n))
    state = make_state(cfg["cases"][CASE])
    draw_realisations(Path(out) / f"N{int(n)}", state, rec, first, last, CASE, f"N = {n} ")


N_MAX = 8
#: a harmonic's band is listed where it carries at least this share of the bin's N D from the
#: dressed spectrum or from the MD's
SHARE_MIN = 0.02


class Tabulated:
    """A spectrum on a frequency grid, called like `kinetic.spectrum.SpectrumTable`."""

    n_max = N_MAX

    def __init__(self, omega, values):
        self.omega, self.values = omega, values

    def __call__(self, omega, component):
        return np.interp(np.abs(omega), self.omega, self.values[component], right=0.0)


#: the time-domain route drops the field below this frequency (FFT of the whole series): the
#: MD(full) magnetisation drifts (relaxation of |M|, the neutral rotation of its direction),
#: and on unperturbed orbits a drifting field gives a bounded but growing J offset that a fit
#: over lags reads as diffusion; the resonances of the bin lie at n Omega >= 0.79
OMEGA_MIN = 0.3


def highpass(x, dt, omega_min=OMEGA_MIN):
    """x with its Fourier components at |omega| < omega_min removed (mean included)."""
    X = np.fft.rfft(x)
    X[2.0 * np.pi * np.fft.rfftfreq(x.size, d=dt) < omega_min] = 0.0
    return np.fft.irfft(X, n=x.size)


def _fmt(x, e):
    return f"{x:.4g} +- {e:.2g}"


def excursion_nd(
    kappa, nd, N, M0, jbar_lo, jbar_hi, density, lags, window, *, walkers=20000, dt=0.5, seed=0
):
    """N D that a fit of <dJ^2>(lag) over `window` reads for walkers that start in the bin
    [jbar_lo, jbar_hi] (drawn with `density` of J-bar) and diffuse with the local
    D(J) = nd(kappa(J)) / N (Ito, drift dD/dJ: the Fokker-Planck form d_t f = d_J (D d_J f) of a
    Hamiltonian random forcing), nd tabulated at `kappa` on one orbit family: the bin's N D
    without any dynamics beyond local quasi-linear diffusion, but with the particles' wandering
    over a steep D(kappa) during the window.  Monte Carlo (seeded)."""
    from hmfdiff.analysis.fits import fit_slope
    from hmfdiff.meanfield import orbits

    rng = np.random.default_rng(seed)
    J_grid = orbits.action(kappa, M0)
    D_grid = np.asarray(nd, dtype=float) / N
    dD = np.gradient(D_grid, J_grid)
    jb = np.linspace(jbar_lo, jbar_hi, 401)
    cdf = np.cumsum(density(jb))
    jb0 = np.interp(rng.uniform(0.0, cdf[-1], walkers), cdf, jb)
    J = orbits.action(orbits.kappa_from_rescaled_action(jb0, M0), M0)
    J0 = J.copy()
    steps = np.rint(np.asarray(lags, dtype=float) / dt).astype(int)
    out = np.zeros(steps.size)
    lo, hi = J_grid[0], J_grid[-1]
    for s in range(1, steps.max() + 1):
        D = np.interp(J, J_grid, D_grid)
        J = J + np.interp(J, J_grid, dD) * dt + np.sqrt(2.0 * D * dt) * rng.normal(size=J.size)
        J = np.clip(J, lo, hi)
        hit = steps == s
        if hit.any():
            out[hit] = np.mean((J - J0) ** 2)
    return 0.5 * N * fit_slope(np.asarray(lags, dtype=float), out, window)[0]


class Context:
    """What every size shares: the state, the fit settings, the bare and dressed tables, and
    their Welch-smoothed versions (one segment length for all sizes)."""

    def __init__(self, target):
        from hmfdiff.kinetic.dielectric import DielectricTensor
        from hmfdiff.kinetic.spectrum import SpectrumTable
        from hmfdiff.meanfield.equilibrium import make_state

        cfg, self.rec = scaling_run(1000)
        self.spec = self.rec.fit_settings()
        self.state = make_state(cfg["cases"][CASE])
        self.M0 = float(self.state.M0)
        self.target = target
        self.bare = SpectrumTable(self.state, n_max=N_MAX)
        self.dressed = SpectrumTable(
            self.state, n_max=N_MAX, eps=DielectricTensor(self.state, l_max=6)
        )
        self._smoothed = {}
        self.profile_printed = False

    def smoothed_tables(self, om, seg, dt):
        """(dressed, bare) smoothed by the Welch window, as `Tabulated` on om."""
        from hmfdiff.analysis.md_spectrum import smoothed

        key = (seg, dt, om.size)
        if key not in self._smoothed:
            out = []
            for table in (self.dressed, self.bare):
                vals = {
                    c: smoothed(lambda w, c=c, t=table: t(w, c), om, seg, dt) for c in ("cc", "ss")
                }
                out.append(Tabulated(om, vals))
            self._smoothed[key] = tuple(out)
        return self._smoothed[key]


def size_result(folder, ctx):
    """The split at one N (a folder of seed files): prints it, returns (N, seeds, est, err)."""
    from hmfdiff.analysis.fits import diffusion_fit, fit_slope, tracked_density
    from hmfdiff.analysis.fluctuations import quasilinear_dj2
    from hmfdiff.analysis.md_spectrum import _slow_frame, resonance_bands, seed_spectra
    from hmfdiff.analysis.relaxation_md import jackknife
    from hmfdiff.kinetic.spectrum import bin_diffusion_from_spectrum
    from hmfdiff.meanfield import orbits
    from hmfdiff.pipeline.io import read_dataset
    from hmfdiff.pipeline.layouts.md import seed_files

    M0, spec, rec = ctx.M0, ctx.spec, ctx.rec
    window = spec["fit_window"]
    n_seeds = len(list(Path(folder).glob("seed*.nc")))
    data = [read_dataset(p) for p in seed_files(folder, n_seeds)]
    fit = diffusion_fit(
        data,
        window=window,
        min_particles=spec["min_particles"],
        separatrix_band=spec["separatrix_band_fit"],
    )
    b = int(np.argmin(np.abs(fit["kappa0"].values - ctx.target)))
    lo, hi = fit["jbar_edges"].values[b : b + 2]
    k_lo, k_hi = orbits.kappa_from_rescaled_action(np.array([lo, hi]), M0)
    N = float(fit.attrs["N"])
    lag = fit["lag"].values
    jac = 4.0 if hi <= orbits.jbar_separatrix(M0) else 1.0
    sums = np.array([ds["sum_dJbar2"].values[b] for ds in data])
    counts = np.array([ds["count"].values[b] for ds in data])
    om, S, seg, dt, _ = seed_spectra(data)
    theory, bare_s = ctx.smoothed_tables(om, seg, dt)

    def density(jb):
        return tracked_density(jb, fit, ctx.state.f)

    def nd_of(table):
        return bin_diffusion_from_spectrum(table, lo, hi, M0, density, per_harmonic=True)

    c_terms = nd_of(theory)
    c = float(c_terms.sum())
    c0 = bin_diffusion_from_spectrum(ctx.dressed, lo, hi, M0, density)
    win = lag[(lag >= window[0]) & (lag <= window[1])]
    cw = bin_diffusion_from_spectrum(ctx.dressed, lo, hi, M0, density, lags=win)
    share_c = c_terms.sum(axis=1) / c
    pad = 4.0 * np.pi / (seg * dt)
    bands = resonance_bands(k_lo, k_hi, M0, N_MAX, pad=pad)
    # the component that carries each harmonic's resonance (on librating orbits S_y, sigma_n,
    # for odd n and S_x, c_n, for even n)
    comp = {
        n: ("x", "cc") if c_terms[n - 1, 0] >= c_terms[n - 1, 1] else ("y", "ss") for n in bands
    }
    # each band, and the band in four: the padding below, the lower and upper halves of
    # n Omega over the bin, the padding above (for n = 2 the weakly damped eps_cc mode at
    # omega = 1.585 lies in the padding below)
    sub_edges = {n: [a, a + pad, 0.5 * (a + z), z - pad, z] for n, (a, z) in bands.items()}
    selections = {
        n: [(om >= e[0]) & (om <= e[4])] + [(om >= e[q]) & (om < e[q + 1]) for q in range(4)]
        for n, e in sub_edges.items()
    }
    nb = 5 * len(bands)

    # (bw): the quasi-linear <dJ^2>(lag) of the bin's orbits in each realisation's measured
    # field (slow frame, as the Welch spectra; high-passed at OMEGA_MIN), at the origins and
    # lags of the MD's accumulator, fitted over the same window; bin-averaged with the tracked
    # density
    jb = np.linspace(lo, hi, 43)[1:-1]
    kq = orbits.kappa_from_rescaled_action(jb, M0)
    wq = density(jb)
    wq = wq / wq.sum()
    lag_fine = np.rint(lag / rec.m_every).astype(int)
    n_t = min(ds.sizes["time_fine"] for ds in data)
    origins = np.arange(0, n_t - lag_fine.max(), int(round(rec.origin_every / rec.m_every)))
    qdj2 = []
    for ds in data:
        px, py = _slow_frame(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t], seg)
        hx, hy = highpass(px, rec.m_every), highpass(py, rec.m_every)
        dj2 = quasilinear_dj2(hx, hy, rec.m_every, kq, M0, lag_fine, origins, n_max=N_MAX)
        qdj2.append(wq @ dj2)
    qdj2 = np.array(qdj2)  # (R, lag)
    # the quasi-linear N D(kappa) in the MD's field (all realisations) on either side of the bin,
    # for the walkers of `excursion_nd`
    kp = np.linspace(max(k_lo - 0.15, 0.02), min(k_hi + 0.15, 0.97), 49)
    prof = np.zeros((kp.size, lag.size))
    for ds in data:
        px, py = _slow_frame(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t], seg)
        hx, hy = highpass(px, rec.m_every), highpass(py, rec.m_every)
        prof += quasilinear_dj2(hx, hy, rec.m_every, kp, M0, lag_fine, origins, n_max=N_MAX)
    nd_prof = 0.5 * N * fit_slope(lag, prof / n_seeds, window)[0]
    nd_prof = np.maximum(nd_prof, 0.0)
    a_model = excursion_nd(kp, nd_prof, N, M0, lo, hi, density, lag[lag <= window[1]], window)

    def estimator(idx):
        idx = np.asarray(idx, dtype=int)
        msd = jac * sums[idx].sum(0) / counts[idx].sum(0)
        a = 0.5 * N * fit_slope(lag, msd, window)[0]
        md = Tabulated(om, {"cc": S["x"][idx].mean(0), "ss": S["y"][idx].mean(0)})
        bt = nd_of(md)
        bb = float(bt.sum())
        band = [
            md.values[comp[n][1]][sel].mean() / theory.values[comp[n][1]][sel].mean()
            for n in bands
            for sel in selections[n]
        ]
        bw = 0.5 * N * fit_slope(lag, qdj2[idx].mean(0), window)[0]
        shares = bt.sum(axis=1) / bb
        return np.array([a, bb, a / bb, bb / c, a / c, *band, *shares, bw, bw / cw, a / bw])

    est, err = jackknife(np.arange(n_seeds), estimator)
    n_seg = (data[0].sizes["time_fine"] - seg) // (seg // 2) + 1
    print(
        f"\nN = {N:.0f}: {n_seeds} realisations (seeds 0-{n_seeds - 1}), {n_seeds} x {n_seg} "
        f"Welch segments of {seg * dt:g} (resolution 4 pi / segment = {pad:.4f})\n"
        f"  bin {b}: kappa0 = {float(fit['kappa0'][b]):.4f}, J-bar {lo:.5f}-{hi:.5f}, kappa "
        f"{k_lo:.4f}-{k_hi:.4f}, Omega {orbits.frequency(k_hi, M0):.4f}-"
        f"{orbits.frequency(k_lo, M0):.4f}; flag {int(fit['flag'][b])}, n_particles_in_bin "
        f"{int(fit['n_particles_in_bin'][b])} (all realisations)\n"
        f"  (a) measured N D {_fmt(est[0], err[0])} (the fit's pooled ND_md "
        f"{float(fit['ND_md'].values[b]):.4g} +- {float(fit['ND_md_err'][b]):.2g}, seed spread)\n"
        f"  Welch route:  (b) N D from the MD's spectrum {_fmt(est[1], err[1])}; (c) from the "
        f"dressed spectrum smoothed by the same window {c:.4g}\n"
        f"                field (b)/(c) {_fmt(est[3], err[3])}; response (a)/(b) "
        f"{_fmt(est[2], err[2])}; (a)/(c) {_fmt(est[4], err[4])}\n"
        f"  time domain:  (bw) quasi-linear N D in the MD's field, fitted like the MD "
        f"{_fmt(est[-3], err[-3])}; (cw) the dressed theory fitted over the same lags {cw:.4g} "
        f"(asymptotic, unsmoothed: c0 = {c0:.4g})\n"
        f"                field (bw)/(cw) {_fmt(est[-2], err[-2])}; response (a)/(bw) "
        f"{_fmt(est[-1], err[-1])}; (a)/(cw) {_fmt(est[0] / cw, err[0] / cw)}"
    )
    print(
        f"  excursions: (am) N D of walkers diffusing from the bin with the quasi-linear D(kappa) "
        f"of the MD's field (kappa {kp[0]:.3f}-{kp[-1]:.3f}), fitted like the MD: {a_model:.4g}; "
        f"(am)/(bw) {a_model / est[-3]:.3f}; (a)/(am) {est[0] / a_model:.3f} +- "
        f"{err[0] / a_model:.2g}"
    )
    if not ctx.profile_printed:
        ctx.profile_printed = True
        from hmfdiff.kinetic.spectrum import diffusion_from_spectrum

        kk = np.linspace(k_lo, k_hi, 8)
        dk = diffusion_from_spectrum(ctx.dressed, kk, M0)
        prof = ", ".join(f"{x:.3f}: {d:.3g}" for x, d in zip(kk, dk, strict=True))
        fold = (kk[-1] - kk[4]) / np.log(dk[-1] / dk[4])
        print(
            f"  dressed N D (asymptotic) across the bin, kappa: N D = {prof}; e-folding length "
            f"in kappa over the upper half {fold:.4f}"
        )
    # how far the bin's particles wander over the fit window: rms dJ of the pooled <dJ^2>,
    # as a kappa with dJ/dkappa at the bin's centre
    jk = float(orbits.dJ_dkappa(float(fit["kappa0"][b]), M0))
    rms = [np.sqrt(np.interp(t, lag, fit["msd"].values[b])) / jk for t in window]
    print(
        f"  rms kappa excursion of the bin's particles at lag {window[0]:g}: {rms[0]:.4f}, "
        f"at {window[1]:g}: {rms[1]:.4f}"
    )
    for i, n in enumerate(bands):
        sm = est[5 + nb + i]
        if max(share_c[n - 1], sm) < SHARE_MIN:
            continue
        x, cc = comp[n]
        sel = selections[n][0]
        amp = theory.values[cc][sel].mean() / bare_s.values[cc][sel].mean()
        j = 5 + 5 * i
        e = sub_edges[n]
        subs = "; ".join(
            f"{e[q]:.3f}-{e[q + 1]:.3f} {_fmt(est[j + 1 + q], err[j + 1 + q])} (dressed "
            f"{theory.values[cc][selections[n][q + 1]].mean():.3g})"
            for q in range(4)
        )
        print(
            f"  n = {n}: N S_{x} over omega {bands[n][0]:.3f}-{bands[n][1]:.3f}: MD / dressed "
            f"{_fmt(est[j], err[j])} (dressed / bare {amp:.3g}); share of N D: dressed "
            f"{share_c[n - 1]:.3f}, MD's spectrum {sm:.3f} +- {err[5 + nb + i]:.2g}\n"
            f"      sub-bands, MD / dressed: {subs}"
        )
    return N, n_seeds, est, err


def analyse(out, *opts):
    from hmfdiff.analysis.separatrix_crossings import scaling_exponent

    target = float(opts[1]) if opts[:1] == ("--kappa0",) else 0.43
    ctx = Context(target)
    rec, spec = ctx.rec, ctx.spec
    print(
        f"case {CASE}, MD(full), the md_scaling run settings of {CONFIG} (t_max {rec.t_max:g}, "
        f"dt {rec.dt:g}, n_track {rec.n_track}, n_test {rec.n_test} uniform in J-bar, fit "
        f"window {spec['fit_window']}, m_every {rec.m_every}); M0 = {ctx.M0:.6f}; harmonics "
        f"n <= {N_MAX}, dielectric l_max 6; bin nearest kappa0 = {target}; errors: jackknife "
        "over realisations"
    )
    folders = sorted(Path(out).glob("N*"), key=lambda p: int(p.name[1:]))
    rows = [size_result(f, ctx) for f in folders if len(list(f.glob("seed*.nc"))) >= 2]
    if len(rows) < 3:
        return
    Ns = np.array([r[0] for r in rows])
    est = np.array([r[2] for r in rows])
    err = np.array([r[3] for r in rows])
    print(
        "\nPower laws y = A N^b over N = "
        + ", ".join(f"{n:.0f}" for n in Ns)
        + " (weighted least squares in log-log, jackknife errors; b error not rescaled):"
    )
    m = est.shape[1]
    names = {
        0: "(a) measured N D",
        1: "(b) N D from MD spectrum",
        m - 3: "(bw) quasi-linear, MD field",
        3: "field (b)/(c)",
        m - 2: "field (bw)/(cw)",
        2: "response (a)/(b)",
        m - 1: "response (a)/(bw)",
        4: "(a)/(c)",
    }
    for j, name in names.items():
        ok = np.isfinite(est[:, j]) & (est[:, j] > 0) & (err[:, j] > 0)
        if ok.sum() >= 3:
            bexp, berr, _, chi2 = scaling_exponent(Ns[ok], est[ok, j], err[ok, j])
            print(f"  {name:28s} b = {bexp:+.3f} +- {berr:.3f}, chi2/dof {chi2:.2f}")
    for j, name in ((4, "(a)/(c) - 1"), (m - 2, "(bw)/(cw) - 1"), (m - 1, "(a)/(bw) - 1")):
        x = est[:, j] - 1.0
        ok = x > 2.0 * err[:, j]
        if ok.sum() >= 3:
            bexp, berr, _, chi2 = scaling_exponent(Ns[ok], x[ok], err[ok, j])
            print(
                f"  {name:28s} b = {bexp:+.3f} +- {berr:.3f}, chi2/dof {chi2:.2f} (the N where "
                f"it exceeds 2 sigma: {', '.join(f'{n:.0f}' for n in Ns[ok])})"
            )


if __name__ == "__main__":
    cmd, args = (sys.argv[1], sys.argv[2:]) if len(sys.argv) > 1 else (None, [])
    if cmd == "run" and len(args) == 4:
        run(*args)
    elif cmd == "analyse" and args:
        analyse(args[0], *args[1:])
    else:
        sys.exit(__doc__.split("\n\n")[3])
