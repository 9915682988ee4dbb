"""N D predicted from MD(full)'s own magnetisation spectrum, against the dressed theory's
(issue 23 part 4).

The kinetic theory's D of an orbit is the spectrum of the fluctuating field at the orbit's
resonant frequencies, N D = sum_n n^2 [c_n^2 N S_x(n Omega) + s_n^2 N S_y(n Omega)]
(`kinetic.spectrum.diffusion_from_spectrum`).  Evaluated with the spectrum MD(full) measures
(Welch, `analysis.md_spectrum`) instead of the dressed theory's (smoothed by the same window),
it says what D the particles should show if they respond to their field as the theory says;
a measured N D below that is not the field's doing.  This prints, for a kappa range, the
average over J-bar (uniform, as the test particles of `studies/test_particles.py`) of both,
and their ratio:

    python studies/spectrum_diffusion.py U KAPPA_LO KAPPA_HI [--fit FIT_FILE] MD_FILES...

U: the thermal state's energy; MD_FILES: MD(full) seed files of that state.  With --fit, a fit
dataset of those realisations (`fits.diffusion_fit`; its `seed` coordinate names them): the
measured N D of its bin nearest the range's middle is divided by the N D from the MD's
spectrum, with a jackknife error that leaves out the same realisation from both (their common
noise, the field of each realisation, cancels).
"""

from __future__ import annotations

import sys

import numpy as np
import xarray as xr

from hmfdiff.analysis.md_spectrum import measured_spectra, smoothed
from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.kinetic.spectrum import SpectrumTable, diffusion_from_spectrum
from hmfdiff.meanfield import equilibrium, orbits

N_MAX = 8


class Tabulated:
    """A spectrum given on a frequency grid, called like `kinetic.spectrum.SpectrumTable`."""

    n_max = N_MAX

    def __init__(self, omega, values):
        self.omega, self.values = omega, values

    def __call__(self, omega, component):
        return np.interp(omega, self.omega, self.values[component])


def seed_of(ds):
    """The realisation's seed, as `fits.diffusion_fit` names it."""
    return int(ds.attrs["seed"])


def main(u, k_lo, k_hi, files, fit_file=None):
    state = equilibrium.ThermalState(M0=equilibrium.thermal_M0_from_energy(float(u)))
    dressed = SpectrumTable(state, n_max=N_MAX, eps=DielectricTensor(state, l_max=6))
    data = [xr.open_dataset(f) for f in files]
    jb = np.linspace(*orbits.rescaled_action(np.array([float(k_lo), float(k_hi)]), state.M0), 201)
    kappa = orbits.kappa_from_rescaled_action(jb, state.M0)

    def nd_md(sets):
        om, meas, n_seg, seg, dt, N = measured_spectra(sets)
        md = Tabulated(om, {"cc": meas["x"][0], "ss": meas["y"][0]})
        return diffusion_from_spectrum(md, kappa, state.M0).mean(), (om, n_seg, seg, dt, N)

    d_md, (om, n_seg, seg, dt, N) = nd_md(data)
    theory = Tabulated(om, {c: smoothed(lambda w, k=c: dressed(w, k), om, seg, dt)
                            for c in ("cc", "ss")})  # fmt: skip
    d_th = diffusion_from_spectrum(theory, kappa, state.M0).mean()
    # jackknife over realisations: the error of d_md
    n = len(data)
    jack = np.array([nd_md(data[:i] + data[i + 1 :])[0] for i in range(n)])
    err = np.sqrt((n - 1) / n * np.sum((jack - jack.mean()) ** 2))
    print(
        f"u = {u}, kappa {k_lo}-{k_hi} ({n} realisations, N = {N:.0e}, {n_seg} Welch "
        f"segments of {seg * dt:g}): N D from MD's spectrum {d_md:.4g} +- {err:.2g}, from the "
        f"dressed theory's {d_th:.4g}, ratio {d_md / d_th:.3f} +- {err / d_th:.3f}"
    )
    if fit_file is None:
        return
    fit = xr.open_dataset(fit_file)
    b = int(np.argmin(np.abs(fit["kappa0"].values - 0.5 * (float(k_lo) + float(k_hi)))))
    per_seed = dict(zip(fit["seed"].values.tolist(), fit["ND_md_seed"].values[:, b], strict=True))
    measured = np.array([per_seed[seed_of(ds)] for ds in data])
    q = measured.mean() / d_md
    qj = np.array([np.delete(measured, i).mean() / jack[i] for i in range(n)])
    q_err = np.sqrt((n - 1) / n * np.sum((qj - qj.mean()) ** 2))
    print(
        f"  measured N D in the bin kappa0 = {float(fit['kappa0'][b]):.3f}: "
        f"{measured.mean():.4g}; measured / from MD's spectrum {q:.3f} +- {q_err:.3f} "
        "(jackknife over realisations, paired)"
    )


if __name__ == "__main__":
    args = sys.argv[4:]
    fit_file = None
    if args[:1] == ["--fit"]:
        fit_file, args = args[1], args[2:]
    if len(sys.argv) < 5 or not args:
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:4], args, fit_file)
