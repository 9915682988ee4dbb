"""Layouts of the MD precision wing (issue 15): results/spectrum/{case}.nc (the magnetisation's
fluctuation spectrum, measured and theory), results/scaling/{case}_{dynamics}.nc (N*D_MD against
N) and results/windowed/{case}_{dynamics}.nc (the theory fitted like the MD)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .variables import D_UNITS, NONNEGATIVE, UNIT_INTERVAL
from .variables import variable as _var

__all__ = ["spectrum_dataset", "scaling_dataset", "windowed_dataset"]

_S_UNITS = "time (N S(omega): two-sided, int S domega/2pi = variance)"
_WHAT = {
    "bath": ("MD(bath)", "bare bath (no collective effects)"),
    "full": ("MD(full)", "dressed by the dielectric tensor (|eps|^-2)"),
}


def spectrum_dataset(comp):
    """results/spectrum/{case}.nc from `analysis.md_spectrum.spectrum_comparison`."""
    data = {}
    coords = {"omega_theory": _var(("omega_theory",), comp["omega_theory"], "1/time", "frequency")}
    for dyn, (md, th) in _WHAT.items():
        om = f"omega_{dyn}"
        coords[om] = _var((om,), comp[om], "1/time", f"Welch frequencies of {md}")
        for c, e in (("x", "cc"), ("y", "ss")):
            k = f"NS{c}_{dyn}"
            data[k] = _var(
                (om,),
                comp[k],
                _S_UNITS,
                f"N S_{c}: measured spectrum of dM_{c} in {md} "
                "(Welch, mean over segments and seeds)",
                valid=NONNEGATIVE,  # a mean of squared moduli
            )
            data[f"{k}_err"] = _var(
                (om,),
                comp[f"{k}_err"],
                _S_UNITS,
                f"standard error of {k} (spread of the per-seed means / sqrt(seeds))",
                valid=NONNEGATIVE,
            )
            data[f"{k}_theory"] = _var(
                (om,),
                comp[f"{k}_theory"],
                _S_UNITS,
                f"N S_{c} of the theory, {th} (eps_{e})",
                valid=NONNEGATIVE,
            )
            data[f"{k}_smoothed"] = _var(
                (om,),
                comp[f"{k}_smoothed"],
                _S_UNITS,
                f"N S_{c} of the theory, {th}, convolved with the Welch window (the "
                "expectation of the measured estimate)",
                valid=NONNEGATIVE,  # the window's kernel K = |sum w e^(i nu t)|^2 >= 0
            )
            data[f"{k}_theory_fine"] = _var(
                ("omega_theory",),
                comp[f"{k}_theory_fine"],
                _S_UNITS,
                f"N S_{c}, {th}",
                valid=NONNEGATIVE,
            )
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(comp["attrs"])
    return ds


_EQUATION = {
    "landau": "Landau (bare, no collective effects)",
    "lenard_balescu": "Lenard-Balescu (dressed by the dielectric tensor)",
}


def scaling_dataset(fits, sizes, *, dynamics, theory, other, equations, drawn):
    """results/scaling/{case}_{dynamics}.nc: N*D_MD per bin at each N, from the fit datasets
    (`analysis.fits.diffusion_fit`) of the sizes, in the order of `sizes`; beside it the
    kinetic theory (N, bin) of this dynamics and the other one, bin-averaged like
    validation.csv's ND_theory (`analysis.scaling.scaling_theory`); `equations` names them
    (e.g. ('landau', 'lenard_balescu') for MD(bath)); `drawn`, the bins figure 15 draws."""
    ref = fits[0]
    b, nb = ("bin",), ("N", "bin")
    own_eq, other_eq = equations
    averaged = (
        "averaged over the bin with the density of the tracked particles of the runs at this N "
        "(as ND_theory of validation.csv)"
    )
    drawn_flag = np.zeros(ref.sizes["bin"], dtype=np.int8)
    drawn_flag[list(drawn)] = 1
    data = {
        "ND_md": _var(nb, np.stack([f["ND_md"].values for f in fits]), D_UNITS, "N D_MD"),
        "ND_md_err": _var(
            nb,
            np.stack([f["ND_md_err"].values for f in fits]),
            D_UNITS,
            "standard error",
            valid=NONNEGATIVE,
        ),
        "ND_theory": _var(
            nb,
            np.asarray(theory, dtype=float),
            D_UNITS,
            f"N D of the kinetic theory of {_WHAT[dynamics][0]}: {_EQUATION[own_eq]}, {averaged}",
            valid=NONNEGATIVE,
            equation=own_eq,
        ),
        "ND_theory_other": _var(
            nb,
            np.asarray(other, dtype=float),
            D_UNITS,
            f"N D of the other kinetic theory, {_EQUATION[other_eq]}, {averaged}",
            valid=NONNEGATIVE,
            equation=other_eq,
        ),
        "flag": _var(
            nb,
            np.stack([f["flag"].values for f in fits]),
            "1",
            "bin quality (fits)",
            valid=(ref["flag"].attrs.get("valid_min"), ref["flag"].attrs.get("valid_max")),
        ),
        "drawn": _var(
            b, drawn_flag, "1", "1 for the bins drawn in figure 15, else 0", valid=UNIT_INTERVAL
        ),
        "n_seeds": _var(
            ("N",),
            np.asarray([int(f.attrs["n_seeds"]) for f in fits], dtype=np.int64),
            "1",
            "realisations (seeds) at this N",
            valid=(1, None),
        ),
        "n_particles_in_bin": _var(
            nb,
            np.stack([f["n_particles_in_bin"].values for f in fits]),
            "1",
            "tracked particles per bin, all seeds",
            valid=NONNEGATIVE,
        ),
        "kappa0": _var(b, ref["kappa0"].values, "1", "kappa at the bin centre", valid=NONNEGATIVE),
        "M0": _var(
            (), float(ref["M0"]), "1", "magnetisation used for the actions", valid=UNIT_INTERVAL
        ),
    }
    coords = {
        "N": _var(
            ("N",), np.asarray(sizes, dtype=np.int64), "1", "number of particles N", valid=(1, None)
        ),
        "jbar0": _var(b, ref["jbar0"].values, "action", "bin centre, J-bar_0", valid=NONNEGATIVE),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(
        dynamics=dynamics,
        fit_window=list(ref.attrs["fit_window"]),
        n_seeds=int(min(int(f.attrs["n_seeds"]) for f in fits)),
        D_convention="<dJ^2> = 2 D dt; N*D stored",
    )
    return ds


def windowed_dataset(nd_windowed, nd_spectrum, fit, *, n_max, l_max, nd_propagated=None):
    """results/windowed/{case}_{dynamics}.nc from `analysis.windowed.windowed_at_bins` (and
    `analysis.propagated.propagated_at_bins`, when given)."""
    b = ("bin",)
    th = "bare (Landau)" if fit.attrs["dynamics"] == "bath" else "dressed (Lenard-Balescu)"
    data = {
        "ND_windowed": _var(
            b,
            nd_windowed,
            D_UNITS,
            f"N D of the theory, {th}: half the slope of the finite-time <dJ^2>(t) fitted over "
            "the MD fit's lags and window, averaged over the bin like ND_md",
        ),
        "ND_spectrum": _var(
            b,
            nd_spectrum,
            D_UNITS,
            f"asymptotic N D of the theory, {th}, through the tabulated spectrum, bin average",
            valid=NONNEGATIVE,  # a sum over resonances of spectra >= 0
        ),
    }
    if nd_propagated is not None:
        data["ND_propagated"] = _var(
            b,
            nd_propagated,
            D_UNITS,
            f"N D of the theory, {th}, propagated over the MD fit's lags: half the slope over "
            "the fit window of the <dJ^2>(t) of the bin's particles diffusing by the theory's "
            "D(J) (analysis.propagated), the like-for-like prediction where D varies on the "
            "scale the particles cover (beside the separatrix)",
            valid=NONNEGATIVE,
        )
    coords = {
        "jbar0": _var(b, fit["jbar0"].values, "action", "bin centre, J-bar_0", valid=NONNEGATIVE),
        "kappa0": _var(b, fit["kappa0"].values, "1", "kappa at the bin centre", valid=NONNEGATIVE),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(
        dynamics=fit.attrs["dynamics"],
        fit_window=list(fit.attrs["fit_window"]),
        n_max=int(n_max),
        l_max=int(l_max),
    )
    return ds
