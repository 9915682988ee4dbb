"""Is the hot halo's weakly damped mode nonlinear at the paper's N?  Trapping in the mode's field.

The hot halo (beta1 = 40) has a weakly damped eps_cc mode, omega0 - i gamma = 1.586 - 0.0074i
(docs/reference/damped_modes.txt), whose n = 2 resonance 2 Omega(J) = omega0 lies at
J-bar = 0.224, just outside the core.  The Lenard-Balescu dressing treats the noise-driven mode
linearly: its resonant particles respond to it as to a field of coherence time 1/gamma.  That
holds while they cannot complete a bounce in it within that time, omega_b << gamma, with
omega_b the bounce (trapping) frequency of the resonant particles in the mode's own field:
near the resonance, with psi = n w - omega0 t and the mode dM_x = a cos(omega0 t),
H = (1/2) Omega' dJ^2 - a |c_n| cos psi, so omega_b = n sqrt(|Omega'| a |c_n|), Omega' = dOmega/dJ
and a = sqrt(2 <dM_x^2>_mode), <dM_x^2>_mode the linear dressed spectrum's power within
+-10 gamma of omega0.  Since a ~ N^-1/2, omega_b / gamma ~ N^-1/4: the linear (order-1/N)
regime is reached only where omega_b / gamma < 1.

Three steps:

    python studies/mode_trapping.py theory                      # omega_b / gamma against N
    python studies/mode_trapping.py run OUT CASE N FIRST LAST [T_MAX]  # MD(full) realisations
    python studies/mode_trapping.py analyse OUT [CASE ...]      # the mode in the MD
    python studies/mode_trapping.py lineshape OUT [CASE ...]    # shifted or reshaped?
    python studies/mode_trapping.py separatrix OUT [CASE ...]   # resonance inside the layer?
    python studies/mode_trapping.py width OUT [CASE ...]        # weaker source or wider line?

`theory` prints, for the hot halo and the same state with a warmer core (beta1 = 20, 10; the
cases of config/experiments/hothalo_marginal.yaml), the least-damped eps_cc mode, the resonance
and omega_b / gamma at N = 1e3 ... 1e7.  `run` draws MD(full) realisations of CASE at N with the
md_scaling study's hot-halo run settings (t_max 1000, m_every 0.25, max_lag 500), seed s as
that study's seed s; with T_MAX, t_max = T_MAX and max_lag = T_MAX / 2, whose Welch segments
(max_lag long) resolve a mode narrower than 2 pi / 500 (the hot halo's, gamma = 0.0074).
`analyse` compares the MD's Welch N S_x of each (case, N) with the linear
dressed theory smoothed by the same window (jackknife errors over realisations): (i) at the
mode, one resolution width (2 pi / segment) either side of omega0; (ii) the power of the band
omega0 - 0.15 ... omega0 + 0.06, which holds the mode's peak; (iii) the centroid of N S_x over
that band against the theory's, the shift of the peak, in the whole run and in its two halves
(t < t_max / 2 and after: a shift that grows as the core's edge relaxes, ~ (t/N)^1/2, against
one set from the start), and in units of gamma beside omega_b / gamma.  Trapping predicts a
shift that depends on omega_b / gamma alone, whatever the state; an effect of N alone (the
separatrix layer, the order-1/N^2 collision terms) the same shift at the same N.

`lineshape` asks whether the MD's peak is the linear one moved in frequency or the linear one
reshaped, which a centroid over a fixed band cannot tell apart when the mode is broad (beta1 =
10: gamma = 0.076, half the band).  Over the band omega0 -+ max(4 gamma, 0.15) it fits the
mean N S_x by weighted least squares (weights: the standard error over realisations per
frequency) with two models of two parameters each, the window-smoothed linear spectrum
  shift:  A S_lin(omega - delta)
  tilt:   A S_lin(omega) (1 + b (omega - omega0) / gamma)
and prints delta (jackknife error), b, and each model's chi^2 beside that of A S_lin alone
(one parameter).  Adjacent Welch frequencies are correlated by the window, so the chi^2 are
compared between models, not against their degrees of freedom.  For the NARROW_BAND states
(thermal u = 0.2475, 1 % below the critical energy: a mode at omega0 = 0.196 with gamma =
0.0167, whose MD spectrum has a floor below omega ~ 0.13 that the theory lacks; and u = 0.23,
its control) both bands are omega0 -+ 4 gamma.

`separatrix` asks whether the mode's resonance lies inside the separatrix's finite-N motion,
where the resonant orbits change family and neither the linear theory nor the pendulum of
omega_b holds: 1 - kappa_res against rms(|M| - M-bar) / (2 M-bar) (the measure of
studies/separatrix_crossings.py) from the MD's own |M|; the rms of the mode itself (M_parallel
band-passed to omega0 -+ 4 gamma) against the linear one; the excess kurtosis of that
band-passed signal against Gaussian surrogates of the same record (a noise-driven linear mode
is Gaussian; an amplitude-limited one has lighter tails, < 0; a bursting one heavier, > 0);
the floor of N S_x (and of N S of |M|, frame-free) over omega 0.05-0.1; and, for a thermal
state, how much the linear power over the band moves if M0 is the MD's mean |M|.

`width` asks whether a mode that carries less than the linear power is damped more strongly
in the N-body or driven by a weaker source.  Near the mode eps_cc ~ eps'(omega0) (omega -
omega0 + i gamma), so the line is S_bare / |eps'|^2 / ((omega - omega0)^2 + gamma^2) and its
power ~ S_bare / gamma: a deficit by a factor r is either a source r times the linear one at the
linear width (a = r, g = 1) or the linear source with the damping 1/r times the linear one (a =
1, g = 1/r).  It works on the spectrum of |M|, which needs no frame (`_modulus_spectra`: to
first order |M| is M_parallel, but M_parallel is M projected on its direction averaged over a
Welch segment, which at small N lags the direction's wandering and takes power from the mode,
the more so the longer the segment; M_parallel's power over omega0 -+ 4 gamma is printed beside
it).  It fits the mean N S over omega0 - gamma ... omega0 + 4 gamma (WIDTH_FIT: the core and
the upper wing; the lower wing of the u = 0.2475 line meets the MD's floor) with the
window-smoothed
  a S_lin(omega) ((omega - omega0)^2 + gamma^2) / ((omega - omega0)^2 + (g gamma)^2),
the linear spectrum with its pole's width scaled by g and its height by a, and prints a and g
(+- jackknife over realisations), the chi^2 of the two one-parameter hypotheses (g = 1, a
free: weaker source; a = 1, g free: stronger damping) against the two-parameter fit, the
power ratio the fit implies over its band, and MD / linear over the SUB_BANDS (the lower wing,
the core, the upper wing, the far upper wing: a stronger damping lowers the core and leaves
the wings; a weaker source lowers all alike) and over omega0 -+ 4 gamma.  Run it on
realisations run to T_MAX = 2000 (Welch segments of 1000: a resolution of 2 pi / 1000 = 0.38
gamma for u = 0.2475).
"""

from __future__ import annotations

import dataclasses
import functools
import re
import sys
from pathlib import Path

import numpy as np
import yaml

CONFIG = "config/config.yaml"
MARGINAL = "config/experiments/hothalo_marginal.yaml"
CASES = ("corehalo_hothalo", "corehalo_hothalo_b20", "corehalo_hothalo_b10")
SIZES = (1e3, 4e3, 1.6e4, 6.4e4, 2.56e5, 5e5, 1e6, 4e6, 1e7)
HARMONIC = 2  # the mode is even (eps_cc): the librating orbits' lowest even harmonic
#: states whose bands are omega0 -+ 4 gamma only: below omega ~ 0.13 the MD(full) spectrum of
#: thermal u = 0.2475 (1 % below the critical energy) carries a floor N S_x ~ 0.1-0.4 that
#: the linear theory lacks (1e-5 ... 1e-2 there; `separatrix` below), which a wider band would
#: count as the mode's power; thermal u = 0.23, its control (further from the critical energy),
#: alike, so that the two compare over the same bands
NARROW_BAND = ("thermal_u0.2475", "thermal_u0.23")
#: the band below the u = 0.2475 mode where its MD spectrum has that floor (`separatrix`)
FLOOR = (0.05, 0.1)
#: `width`: the fit's band, (omega - omega0) / gamma: the core and the upper wing; below
#: omega0 - gamma the u = 0.2475 line's lower wing meets the floor (at N = 250000 it doubles
#: the MD's N S_x at omega0 - 4 gamma)
WIDTH_FIT = (-1.0, 4.0)
#: `width`: the sub-bands, (omega - omega0) / gamma, over which MD / linear is printed
SUB_BANDS = ((-4.0, -1.0), (-1.0, 1.0), (1.0, 4.0), (4.0, 12.0))
#: `width`: bins of (1 - kappa_res) / (the separatrix's slow motion) over which MD / linear is
#: printed: does the line fall short where its resonant orbits lie within that motion?
REACH_BINS = (0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, np.inf)


def band_offsets(case, gamma, kind):
    """(below, above) omega0 of the band of `analyse` (kind 'power': omega0 - 0.15 ...
    omega0 + 0.06, which holds the hot halo's peak) or of `lineshape` ('fit': -+ max(4 gamma,
    0.15)); -+ 4 gamma for the NARROW_BAND states."""
    if case in NARROW_BAND:
        return 4.0 * gamma, 4.0 * gamma
    if kind == "power":
        return 0.15, 0.06
    half = max(4.0 * gamma, 0.15)
    return half, half


def case_spec(case):
    """The case's state spec, from config.yaml or the hothalo_marginal experiment; a name
    thermal_u<U> in neither is the thermal state of energy U."""
    for path in (CONFIG, MARGINAL):
        with open(path) as f:
            cases = yaml.safe_load(f).get("cases") or {}
        if case in cases:
            return cases[case]
    if m := re.fullmatch(r"thermal_u(-?\d+(?:\.\d+)?)", case):
        return {"kind": "thermal", "u": float(m[1])}
    sys.exit(f"error: case {case!r} in neither {CONFIG} nor {MARGINAL}, nor thermal_u<U>")


def mode_parameters(case):
    """(state, omega0, gamma, N <dM_x^2>_mode, resonance dict) of the case's least-damped
    eps_cc mode."""
    from hmfdiff.kinetic.dielectric import DielectricTensor
    from hmfdiff.kinetic.modes import least_damped_modes
    from hmfdiff.kinetic.spectrum import dressed_spectrum
    from hmfdiff.meanfield import orbits
    from hmfdiff.meanfield.equilibrium import make_state
    from hmfdiff.meanfield.fourier import cos_coefficient

    state = make_state(case_spec(case))
    M0 = float(state.M0)
    tensor = DielectricTensor(state)
    rep = least_damped_modes(state, "cc", tensor=tensor)
    z = rep.zeros[rep.stable_mask][0]
    omega0, gamma = float(z.real), float(-z.imag)
    w = np.linspace(omega0 - 10 * gamma, omega0 + 10 * gamma, 4001)
    dressed = dressed_spectrum(state, w, tensor)
    power = 2.0 * np.trapezoid(dressed, w) / (2.0 * np.pi)  # both signs of omega
    kappa = float(orbits.kappa_from_frequency(omega0 / HARMONIC, M0, "libration"))
    res = {
        "kappa": kappa,
        "jbar": float(orbits.rescaled_action(kappa, M0)),
        "c_n": float(cos_coefficient(HARMONIC, kappa)),
        "dOmega_dJ": float(orbits.dOmega_dkappa(kappa, M0) / orbits.dJ_dkappa(kappa, M0)),
        "peak": float(np.max(1.0 / np.abs(tensor(w)[0]) ** 2)),
    }
    return state, omega0, gamma, power, res


def bounce_over_gamma(N, gamma, power, res):
    """omega_b / gamma at N (module docstring)."""
    a = np.sqrt(2.0 * power / N)
    return HARMONIC * np.sqrt(abs(res["dOmega_dJ"]) * a * abs(res["c_n"])) / gamma


def theory():
    print("# The least-damped eps_cc mode and the bounce frequency of its n = 2 resonant orbits")
    print("# (studies/mode_trapping.py theory); N <dM_x^2>_mode: linear dressed power within")
    print("# +-10 gamma of omega0 (both signs of omega)")
    for case in CASES:
        state, omega0, gamma, power, res = mode_parameters(case)
        print(
            f"{case}: M0 = {state.M0:.5f}, omega0 = {omega0:.5f}, gamma = {gamma:.5f}, "
            f"peak |1/eps_cc|^2 = {res['peak']:.4g}, N <dM_x^2>_mode = {power:.4g}; resonance "
            f"kappa = {res['kappa']:.4f} (J-bar {res['jbar']:.4f}), c_2 = {res['c_n']:.4f}, "
            f"dOmega/dJ = {res['dOmega_dJ']:.4f}"
        )
        cells = ", ".join(f"{N:.3g}: {bounce_over_gamma(N, gamma, power, res):.3g}" for N in SIZES)
        print(f"  omega_b / gamma at N = {cells}")
        cross = (2.0 * power) * (
            HARMONIC**2 * abs(res["dOmega_dJ"]) * abs(res["c_n"]) / gamma**2
        ) ** 2
        print(f"  omega_b = gamma at N = {cross:.3g}")


def md_run(case, n, t_max=None):
    """The md_scaling study's hot-halo MD(full) record at size n, for `case` (run to t_max
    with lags to t_max / 2 if given)."""
    from hmfdiff.dynamics.runs import md_scaling_runs

    with open(CONFIG) as f:
        cfg = yaml.safe_load(f)
    runs = {
        k[2]: r for k, r in md_scaling_runs(cfg).items() if k[:2] == ("corehalo_hothalo", "full")
    }
    rec = runs[int(n)] if int(n) in runs else runs[min(runs)]
    rec = dataclasses.replace(rec, n_particles=int(n), case=case)
    if t_max is not None:
        rec = dataclasses.replace(rec, t_max=float(t_max), max_lag=0.5 * float(t_max))
    return rec


def run(out, case, n, first, last, t_max=None):
    from _realisations import draw_realisations

    from hmfdiff.meanfield.equilibrium import make_state

    folder = Path(out) / case / f"N{int(n)}"
    state = make_state(case_spec(case))
    rec = md_run(case, n, t_max)
    draw_realisations(folder, state, rec, first, last, case, f"{case} N = {n} ")


def _spectra(data, N, part, seg):
    """Welch N S_x (realisations, frequencies) of the samples `part` of each realisation."""
    from hmfdiff.analysis.fluctuations import welch_spectrum
    from hmfdiff.analysis.md_spectrum import _slow_frame

    dt = float(data[0].attrs["m_every"])
    rows = []
    for ds in data:
        px, _ = _slow_frame(ds["Mx_fine"].values[part], ds["My_fine"].values[part], seg)
        om, S, _, _ = welch_spectrum(px[None, :], dt, seg)
        rows.append(N * S)
    return om, np.array(rows), dt


def _dressed_spectrum(state):
    """The linear dressed N S_x of `state` as a callable of omega."""
    from hmfdiff.kinetic.dielectric import DielectricTensor
    from hmfdiff.kinetic.spectrum import dressed_spectrum

    return functools.partial(dressed_spectrum, state, eps=DielectricTensor(state))


def _ensembles(out, case):
    """(files, datasets, N, samples, Welch segment) of each N{N} folder of OUT/CASE with at
    least four realisations, in increasing N."""
    from hmfdiff.pipeline.io import read_dataset

    for folder in sorted((Path(out) / case).glob("N*"), key=lambda p: int(p.name[1:])):
        files = sorted(folder.glob("seed*.nc"))
        if len(files) < 4:
            continue
        data = [read_dataset(p) for p in files]
        n_t = min(ds.sizes["time_fine"] for ds in data)
        seg = int(round(float(data[0].attrs["max_lag"]) / float(data[0].attrs["m_every"])))
        yield files, data, float(data[0].attrs["N"]), n_t, seg


def analyse(out, cases):
    from hmfdiff.analysis.md_spectrum import smoothed
    from hmfdiff.analysis.relaxation_md import jackknife

    print("# The mode in MD(full) against the linear dressed theory (studies/mode_trapping.py")
    print("# analyse; +- jackknife over realisations).  at mode: N S_x within one resolution")
    print(
        "# width of omega0, MD / linear; band: N S_x summed over omega0 - 0.15 ... omega0 + 0.06,"
    )
    print("# MD / linear (omega0 -+ 4 gamma for NARROW_BAND states); shift: centroid of N S_x over")
    print("# the band, MD - linear (whole run; first and second half of the run, segments of half")
    print("# the length)")
    for case in cases:
        state, omega0, gamma, power, res = mode_parameters(case)
        dressed = _dressed_spectrum(state)
        print(f"{case}: omega0 = {omega0:.5f}, gamma = {gamma:.5f}")
        for files, data, N, n_t, seg in _ensembles(out, case):
            cells = []
            for part, length in (
                (slice(0, n_t), seg),
                (slice(0, n_t // 2), seg // 2),
                (slice(n_t // 2, n_t), seg // 2),
            ):
                om, S, dt = _spectra(data, N, part, length)
                below, above = band_offsets(case, gamma, "power")
                band = (om > omega0 - below) & (om < omega0 + above)
                th = smoothed(dressed, om[band], length, dt)

                def centroid(v, om=om[band]):
                    return float((v * om).sum() / v.sum())

                shift, shift_err = jackknife(S[:, band], lambda v, c=centroid: c(v.mean(0)))
                cells.append((shift - centroid(th), shift_err))
                if length == seg:
                    near = np.abs(om - omega0) <= 2.0 * np.pi / (seg * dt) * (1 + 1e-9)
                    th_near = smoothed(dressed, om[near], seg, dt).mean()
                    at, at_err = jackknife(
                        S[:, near].mean(axis=1), lambda v, t=th_near: v.mean() / t
                    )
                    total = float(th.sum())
                    pw, pw_err = jackknife(S[:, band], lambda v, t=total: v.mean(0).sum() / t)
            x = bounce_over_gamma(N, gamma, power, res)
            (sh, she), (s1, s1e), (s2, s2e) = cells
            print(
                f"  N = {N:.0f} ({len(files)} realisations): at mode {at:.3f} +- {at_err:.3f}; "
                f"band {pw:.3f} +- {pw_err:.3f}; shift {sh:+.4f} +- {she:.4f} (halves "
                f"{s1:+.4f} +- {s1e:.4f}, {s2:+.4f} +- {s2e:.4f}); omega_b = "
                f"{x * gamma:.4f}, omega_b / gamma = {x:.3g}, shift / gamma = {sh / gamma:+.3g}",
                flush=True,
            )


def _fit_shift(mean, err, th_at, om, grid):
    """(chi^2, A, delta) of A S_lin(omega - delta) by a scan of delta over `grid` (A linear)."""
    w = 1.0 / err**2
    best = (np.inf, np.nan, np.nan)
    for d in grid:
        t = th_at(om - d)
        a = float((w * mean * t).sum() / (w * t * t).sum())
        chi2 = float((w * (mean - a * t) ** 2).sum())
        if chi2 < best[0]:
            best = (chi2, a, float(d))
    return best


def _fit_tilt(mean, err, th, x):
    """(chi^2, A, b) of A S_lin(omega) (1 + b x), linear least squares."""
    w = 1.0 / err
    design = np.stack([th * w, th * x * w], axis=1)
    coef, *_ = np.linalg.lstsq(design, mean * w, rcond=None)
    chi2 = float(((design @ coef - mean * w) ** 2).sum())
    return chi2, float(coef[0]), float(coef[1] / coef[0])


def lineshape(out, cases):
    from hmfdiff.analysis.md_spectrum import smoothed
    from hmfdiff.analysis.relaxation_md import jackknife

    print("# The mode's line shape in MD(full) (studies/mode_trapping.py lineshape): over")
    print(
        "# omega0 -+ max(4 gamma, 0.15) (-+ 4 gamma for NARROW_BAND states), the mean N S_x fitted"
    )
    print("# by A S_lin(omega - delta) (shift)")
    print("# and by A S_lin(omega) (1 + b (omega - omega0)/gamma) (tilt); chi^2 of each and of")
    print("# A S_lin alone (amplitude); delta +- jackknife over realisations")
    for case in cases:
        state, omega0, gamma, _, _ = mode_parameters(case)
        dressed = _dressed_spectrum(state)
        half = band_offsets(case, gamma, "fit")[0]
        print(f"{case}: omega0 = {omega0:.5f}, gamma = {gamma:.5f}, band +-{half:.3f}")
        for files, data, N, n_t, seg in _ensembles(out, case):
            om, S, dt = _spectra(data, N, slice(0, n_t), seg)
            band = np.abs(om - omega0) < half
            o = om[band]
            fine = np.linspace(o[0] - 0.06, o[-1] + 0.06, 4 * o.size + 97)
            th_fine = smoothed(dressed, fine, seg, dt)

            def th_at(w, fine=fine, th_fine=th_fine):
                return np.interp(w, fine, th_fine)

            grid = np.arange(-0.05, 0.05 + 1e-12, 2.5e-4)
            x = (o - omega0) / gamma

            def fits(v, o=o, x=x, th_at=th_at, grid=grid):
                mean = v.mean(0)
                err = v.std(0, ddof=1) / np.sqrt(v.shape[0])
                sh = _fit_shift(mean, err, th_at, o, grid)
                ti = _fit_tilt(mean, err, th_at(o), x)
                w = 1.0 / err**2
                t = th_at(o)
                a = float((w * mean * t).sum() / (w * t * t).sum())
                amp = float((w * (mean - a * t) ** 2).sum())
                return sh, ti, amp

            sh, ti, amp = fits(S[:, band])
            delta, delta_err = jackknife(S[:, band], lambda v, f=fits: f(v)[0][2])
            print(
                f"  N = {N:.0f} ({len(files)} realisations, {o.size} frequencies): shift delta = "
                f"{delta:+.4f} +- {delta_err:.4f} (A {sh[1]:.3f}), chi^2 {sh[0]:.1f}; tilt b = "
                f"{ti[2]:+.3f} (A {ti[1]:.3f}), chi^2 {ti[0]:.1f}; amplitude alone chi^2 {amp:.1f}",
                flush=True,
            )


def excess_kurtosis(x):
    """<x^4> / <x^2>^2 - 3 of x about its mean (0 for a Gaussian; -1.5 for a sinusoid)."""
    x = np.asarray(x, dtype=float) - np.mean(x)
    return float(np.mean(x**4) / np.mean(x**2) ** 2 - 3.0)


def band_passed(x, dt, lo, hi):
    """x with its Fourier components outside lo <= omega <= hi (and its mean) removed."""
    X = np.fft.rfft(np.asarray(x, dtype=float) - np.mean(x))
    omega = 2.0 * np.pi * np.fft.rfftfreq(len(x), dt)
    X[(omega < lo) | (omega > hi)] = 0.0
    return np.fft.irfft(X, len(x))


def phase_randomised(x, rng):
    """A Gaussian surrogate of x: its Fourier amplitudes with random phases (the same
    periodogram), mean removed."""
    X = np.fft.rfft(np.asarray(x, dtype=float) - np.mean(x))
    phase = np.exp(2j * np.pi * rng.random(X.size))
    phase[0] = 1.0
    if len(x) % 2 == 0:
        phase[-1] = 1.0
    return np.fft.irfft(X * phase, len(x))


def band_kurtosis_excess(x, dt, lo, hi, rng, surrogates=20):
    """(excess kurtosis of x band-passed to lo-hi, the mean of the same over `surrogates`
    Gaussian surrogates of x): a record of finite length holds few independent samples of a
    narrow band, so a Gaussian's sample kurtosis is biased below 0 (about -6 / samples); the
    surrogates measure that bias, and the difference is the departure from Gaussian."""
    data = excess_kurtosis(band_passed(x, dt, lo, hi))
    null = [
        excess_kurtosis(band_passed(phase_randomised(x, rng), dt, lo, hi))
        for _ in range(surrogates)
    ]
    return data, float(np.mean(null))


def separatrix(out, cases):
    """Where the mode's resonance lies against the separatrix's finite-N motion."""
    from hmfdiff.analysis.md_spectrum import _slow_frame, smoothed
    from hmfdiff.analysis.relaxation_md import jackknife
    from hmfdiff.meanfield import orbits

    print("# The mode's n = 2 resonance against the separatrix's motion in MD(full) (studies/")
    print("# mode_trapping.py separatrix).  1 - kappa_res: the resonance's distance from the")
    print("# separatrix; dkappa_gamma = gamma / (2 |dOmega/dkappa|): the resonant orbits' spread")
    print("# in kappa over the mode's width; M-bar: time mean of |M| per realisation; the")
    print(
        "# separatrix moves in kappa by rms(|M| - M-bar) / (2 M-bar) (as in separatrix_crossings);"
    )
    print(
        f"# floor: mean N S_x over omega {FLOOR[0]}-{FLOOR[1]}, MD and linear dressed "
        "(+- jackknife), and the MD's"
    )
    print("# mean N S of |M| there (the same in any frame)")
    print("# mode rms: sqrt(N) rms of M_parallel band-passed to omega0 -+ 4 gamma, MD and linear;")
    print("# kurtosis: excess kurtosis of that band-passed M_parallel minus that of 20 Gaussian")
    print(
        "# (phase-randomised) surrogates of each realisation, mean over realisations +- its error"
    )
    for case in cases:
        state, omega0, gamma, _, res = mode_parameters(case)
        M0 = float(state.M0)
        spread = gamma / (HARMONIC * abs(float(orbits.dOmega_dkappa(res["kappa"], M0))))
        dressed = _dressed_spectrum(state)
        print(
            f"{case}: M0 = {M0:.5f}, omega0 = {omega0:.5f}, gamma = {gamma:.5f}, peak "
            f"|1/eps_cc|^2 = {res['peak']:.4g}; 1 - kappa_res = {1.0 - res['kappa']:.3e}, "
            f"dkappa_gamma = {spread:.3e}"
        )
        for files, data, N, n_t, seg in _ensembles(out, case):
            mods = [np.hypot(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t]) for ds in data]
            mbar = np.array([m.mean() for m in mods])
            rms = np.sqrt(np.mean([np.mean((m - m.mean()) ** 2) for m in mods]))
            motion = rms / (2.0 * mbar.mean())
            om, S, dt = _spectra(data, N, slice(0, n_t), seg)
            sel = (om >= FLOOR[0]) & (om <= FLOOR[1])
            floor, floor_err = jackknife(S[:, sel].mean(axis=1), lambda v: v.mean())
            th = float(smoothed(dressed, om[sel], seg, dt).mean())
            s_mod = _modulus_spectra(data, N, n_t, seg)[1][:, sel]
            floor_mod, floor_mod_err = jackknife(s_mod.mean(axis=1), lambda v: v.mean())
            lo, hi = omega0 - 4.0 * gamma, omega0 + 4.0 * gamma
            rng = np.random.default_rng(5)
            mode_rms, kurt = [], []
            for ds in data:
                par, _ = _slow_frame(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t], seg)
                mode_rms.append(np.mean(band_passed(par, dt, lo, hi) ** 2))
                k, k0 = band_kurtosis_excess(par, dt, lo, hi, rng)
                kurt.append(k - k0)
            kurt = np.array(kurt)
            w = np.linspace(lo, hi, 2001)
            lin_rms = np.sqrt(2.0 * np.trapezoid(dressed(w), w) / (2.0 * np.pi))
            print(
                f"  N = {N:.0f} ({len(files)} realisations): M-bar / M0 = {mbar.mean() / M0:.4f} "
                f"+- {mbar.std(ddof=1) / np.sqrt(mbar.size) / M0:.4f}; sqrt(N) rms(|M| - M-bar) = "
                f"{np.sqrt(N) * rms:.4f}; separatrix motion in kappa {motion:.3e} = "
                f"{motion / (1.0 - res['kappa']):.3g} (1 - kappa_res) = {motion / spread:.3g} "
                f"dkappa_gamma; floor MD {floor:.4f} +- {floor_err:.4f}, linear {th:.3g}, |M| "
                f"{floor_mod:.4f} +- {floor_mod_err:.4f}; mode rms "
                f"MD {np.sqrt(N * np.mean(mode_rms)):.4f}, linear {lin_rms:.4f}; kurtosis "
                f"{kurt.mean():+.4f} +- {kurt.std(ddof=1) / np.sqrt(kurt.size):.4f}"
                + _offset_power(state, omega0, gamma, mbar.mean() / M0),
                flush=True,
            )


def _offset_power(state, omega0, gamma, scale):
    """For a thermal state: the linear dressed power over omega0 -+ 4 gamma of the thermal state
    of magnetisation scale M0, over the state's own (can the MD's mean |M| explain a power
    deficit?); '' otherwise."""
    if getattr(state, "kind", "") != "thermal":
        return ""
    from hmfdiff.kinetic.dielectric import DielectricTensor
    from hmfdiff.kinetic.spectrum import dressed_spectrum
    from hmfdiff.meanfield.equilibrium import ThermalState

    w = np.linspace(omega0 - 4.0 * gamma, omega0 + 4.0 * gamma, 600)
    power = []
    for m in (state.M0, scale * state.M0):
        st = ThermalState(M0=float(m))
        power.append(np.trapezoid(dressed_spectrum(st, w, DielectricTensor(st)), w))
    return f"; linear power over omega0 -+ 4 gamma at M0 x M-bar / M0: {power[1] / power[0]:.4f}"


def pole_rewidth_factor(omega, omega0, gamma, g):
    """((omega - omega0)^2 + gamma^2) / ((omega - omega0)^2 + (g gamma)^2): the linear line's
    Lorentzian of half-width gamma turned into one of half-width g gamma, at equal source."""
    d2 = (np.asarray(omega, dtype=float) - omega0) ** 2
    return (d2 + gamma**2) / (d2 + (g * gamma) ** 2)


def fit_source_and_width(mean, err, model, grid):
    """Weighted least squares of mean (err) by a model(g) over g in `grid`, a linear:
    {'free': (chi2, a, g), 'source': (chi2, a, 1), 'damping': (chi2, 1, g)}.  model(g) is the
    window-smoothed model spectrum at the fitted frequencies for amplitude 1."""
    w = 1.0 / np.asarray(err, dtype=float) ** 2
    mean = np.asarray(mean, dtype=float)
    T = np.array([model(g) for g in grid])  # (g, frequency)
    a = (T * w * mean).sum(axis=1) / (T * T * w).sum(axis=1)
    chi2 = ((mean - a[:, None] * T) ** 2 * w).sum(axis=1)
    chi2_1 = ((mean - T) ** 2 * w).sum(axis=1)
    k, k1 = int(np.argmin(chi2)), int(np.argmin(chi2_1))
    free, damping = (
        (float(chi2[k]), float(a[k]), float(grid[k])),
        (float(chi2_1[k1]), 1.0, float(grid[k1])),
    )
    t = model(1.0)
    a1 = float((w * mean * t).sum() / (w * t * t).sum())
    source = (float((w * (mean - a1 * t) ** 2).sum()), a1, 1.0)
    return {"free": free, "source": source, "damping": damping}


def width(out, cases):
    """Weaker source or stronger damping: the mode's height and width in MD(full)."""
    lo, hi = (f"{v:+g}" for v in WIDTH_FIT)
    print("# The mode's source and damping in MD(full) (studies/mode_trapping.py width), from the")
    print("# MD's N S of |M| (no frame; `_modulus_spectra`): the mean N S over (omega - omega0) /")
    print(f"# gamma = {lo} ... {hi} fitted by the window-smoothed linear N S_x, a S_lin(omega)")
    print("# ((omega - omega0)^2 + gamma^2) / ((omega - omega0)^2 + (g gamma)^2); a: the source")
    print("# over the linear one, g: the damping over the linear gamma (+- jackknife over")
    print("# realisations); chi^2 of the fit with a and g free, with g = 1 (weaker source) and")
    print("# with a = 1 (stronger damping); power: the fitted model's power over the fit band /")
    print("# the linear; then MD / linear summed over sub-bands of (omega - omega0) / gamma (+-")
    print("# jackknife), and the same over -4..+4 for M_parallel in the slow frame of `analyse`")
    print("# (which at small N loses power to the frame's lag); slow separatrix motion: rms of")
    print("# |M| below omega0 - 4 gamma (Hann-tapered periodogram) over 2 M-bar, in kappa, and")
    print("# where in the line the n = 2 resonance lies that far inside the separatrix; then MD /")
    print("# linear over omega0 -+ 6 gamma where the linear N S_x exceeds 10 times the MD's")
    print("# floor, grouped by (1 - kappa_res) / slow motion (number of frequencies)")
    for case in cases:
        state, omega0, gamma, _, _ = mode_parameters(case)
        dressed = _dressed_spectrum(state)
        print(f"{case}: M0 = {state.M0:.5f}, omega0 = {omega0:.5f}, gamma = {gamma:.5f}")
        for files, data, N, n_t, seg in _ensembles(out, case):
            om, S, dt = _modulus_spectra(data, N, n_t, seg)
            r = source_and_width(om, S, dt, seg, dressed, omega0, gamma)
            slow, edge = _slow_separatrix_motion(data, n_t, dt, state, omega0, gamma)
            bands = _band_ratios(om, S, seg, dt, dressed, omega0, gamma, (*SUB_BANDS, (-4, 4)))
            om_p, S_p, _ = _spectra(data, N, slice(0, n_t), seg)
            ((*_, par, par_err),) = _band_ratios(
                om_p, S_p, seg, dt, dressed, omega0, gamma, ((-4, 4),)
            )
            print(
                f"  N = {N:.0f} ({len(files)} realisations, {r['n_freq']} frequencies, resolution "
                f"{2 * np.pi / (seg * dt) / gamma:.2f} gamma): a = {r['a']:.3f} +- "
                f"{r['a_err']:.3f}, g = {r['g']:.3f} +- {r['g_err']:.3f}, power {r['power']:.3f}"
                f" +- {r['power_err']:.3f}; chi^2 free {r['chi2_free']:.1f}, g = 1 "
                f"{r['chi2_source']:.1f} (a {r['a_source']:.3f}), a = 1 {r['chi2_damping']:.1f} "
                f"(g {r['g_damping']:.3f}); MD / linear over (omega - omega0) / gamma in "
                + ", ".join(f"{lo:+g}..{hi:+g}: {v:.3f} +- {e:.3f}" for lo, hi, v, e in bands)
                + f"; M_parallel over -4..+4: {par:.3f} +- {par_err:.3f}; slow separatrix motion "
                f"{slow:.3e} = 1 - kappa_res at (omega - omega0) / gamma = {edge:+.2f}",
                flush=True,
            )
            cells = _ratio_by_reach(om, S, dt, seg, dressed, state, omega0, gamma, slow)
            print("    MD / linear by (1 - kappa_res) / slow motion: " + ", ".join(cells))


def _modulus_spectra(data, N, n_t, seg):
    """(omega, N S of |M| per realisation, dt): the even mode's spectrum without a frame.  To
    first order in the fluctuation |M| is M_parallel, but `_spectra` projects M on its direction
    averaged over a Welch segment (`_slow_frame`), which at small N lags the direction's
    wandering and takes power from the mode; |M| needs no frame."""
    from hmfdiff.analysis.fluctuations import welch_spectrum

    dt = float(data[0].attrs["m_every"])
    rows = []
    for ds in data:
        mod = np.hypot(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t])
        om, S, _, _ = welch_spectrum(mod[None, :], dt, seg)
        rows.append(N * S)
    return om, np.array(rows), dt


def _band_ratios(om, S, seg, dt, linear, omega0, gamma, bands):
    """(lo, hi, MD / linear, its jackknife error) of the Welch spectra S (realisations,
    frequencies) summed over each band (lo, hi) of (omega - omega0) / gamma, against the
    window-smoothed `linear`."""
    from hmfdiff.analysis.md_spectrum import smoothed
    from hmfdiff.analysis.relaxation_md import jackknife

    x = (om - omega0) / gamma
    cells = []
    for lo, hi in bands:
        sel = (x > lo) & (x < hi)
        th = float(smoothed(linear, om[sel], seg, dt).sum())
        v, e = jackknife(S[:, sel], lambda s, t=th: s.mean(0).sum() / t)
        cells.append((float(lo), float(hi), float(v), float(e)))
    return cells


def low_frequency_variance(x, dt, cutoff):
    """The variance of x (about its mean) at omega below `cutoff`, from its Hann-tapered
    periodogram: a sharp cut of the plain Fourier transform lets a strong line above the cutoff
    leak into it through the record's ends (side lobes ~ 1/omega), the taper's fall as
    omega^-3."""
    x = np.asarray(x, dtype=float) - np.mean(x)
    win = np.hanning(x.size + 2)[1:-1]
    X = np.fft.rfft(win * x)
    omega = 2.0 * np.pi * np.fft.rfftfreq(x.size, dt)
    weight = np.where(omega == 0.0, 1.0, 2.0)  # the one-sided transform counts omega > 0 twice
    return float((weight * np.abs(X) ** 2)[omega < cutoff].sum() / (x.size * np.sum(win**2)))


def _slow_separatrix_motion(data, n_t, dt, state, omega0, gamma):
    """(dkappa_slow, x): the separatrix's slow motion in kappa, rms of |M| below omega0 - 4
    gamma (where the linear spectrum is ~ 0; `low_frequency_variance`) over 2 M-bar, averaged
    over the realisations in quadrature; and the (omega - omega0) / gamma whose n = 2 librating
    resonance lies that far inside the separatrix (1 - kappa_res = dkappa_slow)."""
    from scipy.optimize import brentq

    from hmfdiff.meanfield import orbits

    var = []
    for ds in data:
        m = np.hypot(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t])
        var.append(low_frequency_variance(m, dt, omega0 - 4.0 * gamma) / (2 * m.mean()) ** 2)
    slow = float(np.sqrt(np.mean(var)))
    M0 = float(state.M0)

    def distance(x):
        w = (omega0 + x * gamma) / HARMONIC
        return np.log(1.0 - float(orbits.kappa_from_frequency(w, M0, "libration"))) - np.log(slow)

    top = (HARMONIC * np.sqrt(M0) * (1.0 - 1e-9) - omega0) / gamma  # the librating band's edge
    try:
        edge = brentq(distance, -4.0, min(12.0, top), xtol=1e-3)
    except ValueError:
        edge = np.nan
    return slow, float(edge)


def _ratio_by_reach(om, S, dt, seg, dressed, state, omega0, gamma, slow):
    """MD / linear summed over the Welch frequencies within omega0 -+ 6 gamma grouped by how far
    their n = 2 librating resonance lies inside the separatrix, in units of its slow motion, y =
    (1 - kappa_res) / dkappa_slow (REACH_BINS), at the frequencies where the smoothed linear N S_x
    is at least 10 times the MD's floor (mean N S_x over FLOOR): one cell per bin, 'lo-hi: ratio
    +- jackknife (frequencies)'."""
    from hmfdiff.analysis.md_spectrum import smoothed
    from hmfdiff.analysis.relaxation_md import jackknife
    from hmfdiff.meanfield import orbits

    floor = S[:, (om >= FLOOR[0]) & (om <= FLOOR[1])].mean()
    near = np.abs(om - omega0) < 6.0 * gamma
    th = np.zeros(om.size)
    th[near] = smoothed(dressed, om[near], seg, dt)
    kappa = orbits.kappa_from_frequency(om / HARMONIC, float(state.M0), "libration")
    y = np.where(np.isfinite(kappa), (1.0 - kappa) / slow, np.inf)
    use = near & (th > 10.0 * floor)
    cells = []
    for lo, hi in zip(REACH_BINS[:-1], REACH_BINS[1:], strict=True):
        sel = use & (y >= lo) & (y < hi)
        if not sel.any():
            continue
        t = float(th[sel].sum())
        v, e = jackknife(S[:, sel], lambda s, t=t: s.mean(0).sum() / t)
        cells.append(f"{lo:g}-{hi:g}: {v:.3f} +- {e:.3f} ({sel.sum()})")
    return cells


def source_and_width(om, S, dt, seg, linear, omega0, gamma, fit_band=WIDTH_FIT, grid=None):
    """The fit of `width` on Welch spectra S (realisations, frequencies) at om (segments of seg
    samples dt apart) against the linear spectrum `linear` (a callable of omega) with its mode
    omega0 - i gamma, over omega0 + fit_band gamma: a dict of a, g, the power ratio over the
    fit band (each with its jackknife error), the number of frequencies fitted and the chi^2
    (and best parameter) of each hypothesis."""
    from hmfdiff.analysis.md_spectrum import smoothed
    from hmfdiff.analysis.relaxation_md import jackknife

    x = (om - omega0) / gamma
    band = (x > fit_band[0]) & (x < fit_band[1])
    o = om[band]
    reach = 13 * 2.0 * np.pi / (seg * dt)  # the window's kernel: +-12 resolution widths
    fine = np.linspace(o[0] - reach, o[-1] + reach, 6001)
    lin_fine = linear(fine)

    @functools.cache
    def model(g):
        def spectrum(w):
            return np.interp(w, fine, lin_fine) * pole_rewidth_factor(w, omega0, gamma, g)

        return smoothed(spectrum, o, seg, dt)

    if grid is None:
        grid = np.round(np.arange(0.5, 2.0 + 1e-9, 0.005), 6)
    lin_power = float(model(1.0).sum())

    def fits(v):
        # weights from the linear line's shape, not from each frequency's own scatter (which
        # weighs the frequencies that fluctuated low more, and broadens the fitted line): the
        # Welch estimates' relative error is about the same at every frequency
        rel = np.median(v.std(0, ddof=1) / np.abs(v.mean(0)))
        return fit_source_and_width(v.mean(0), rel * model(1.0) / np.sqrt(v.shape[0]), model, grid)

    def estimates(v):
        _, a, g = fits(v)["free"]
        return np.array([a, g, a * float(model(g).sum()) / lin_power])

    best = fits(S[:, band])
    (a, g, pw), (a_err, g_err, pw_err) = jackknife(S[:, band], estimates)
    return {
        "a": a, "a_err": a_err, "g": g, "g_err": g_err, "power": pw, "power_err": pw_err,
        "n_freq": int(o.size), "chi2_free": best["free"][0], "chi2_source": best["source"][0],
        "a_source": best["source"][1], "chi2_damping": best["damping"][0],
        "g_damping": best["damping"][2],
    }  # fmt: skip


def main(argv):
    commands = ("theory", "run", "analyse", "lineshape", "separatrix", "width")
    if not argv or argv[0] not in commands:
        sys.exit(__doc__)
    if argv[0] == "theory":
        theory()
    elif argv[0] == "run":
        if len(argv) not in (6, 7):
            sys.exit("usage: mode_trapping.py run OUT CASE N FIRST LAST [T_MAX]")
        run(argv[1], argv[2], float(argv[3]), argv[4], argv[5], *map(float, argv[6:]))
    elif argv[0] == "analyse":
        analyse(argv[1], argv[2:] or CASES)
    elif argv[0] == "lineshape":
        lineshape(argv[1], argv[2:] or CASES)
    elif argv[0] == "width":
        width(argv[1], argv[2:] or CASES)
    else:
        separatrix(argv[1], argv[2:] or CASES)


if __name__ == "__main__":
    main(sys.argv[1:])
