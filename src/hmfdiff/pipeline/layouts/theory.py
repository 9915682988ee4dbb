"""Layouts of the kinetic theory of the diffusion: results/theory/{case}.nc
(`kinetic.theory.theory_grid`: Landau and Lenard-Balescu N D_dif, N D_pol, their resonances,
eps(omega)) and results/analytic/{case}.nc (`kinetic.closed_forms.closed_forms`)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ...paper_equations import FIGURES, eq
from .variables import D_UNITS, NONNEGATIVE, UNIT_INTERVAL, variable

__all__ = ["theory_dataset", "closed_forms_dataset"]


def theory_dataset(grid):
    """results/theory/{case}.nc from `kinetic.theory.theory_grid`: Landau and Lenard-Balescu
    N D_dif, N D_pol and their resonance contributions on kappa, eps(omega) as real and
    imaginary parts; kappa-dependent variables NaN in the separatrix band."""
    note = grid["attrs"]["separatrix_band_note"]
    k, kr = ("kappa",), ("kappa", "resonance")

    def kv(vals, units, long_name, valid=NONNEGATIVE):
        return variable(k, vals, units, long_name, valid=valid, masked=note)

    res = grid["resonances"]
    data = {
        "J": kv(grid["J"], "action", f"action J(kappa) ({eq('hmfaction')})"),
        "Jbar": kv(
            grid["Jbar"], "action", "rescaled action J-bar (J/2 for kappa < 1, J for kappa > 1)"
        ),
        # not "Omega": CF names may not differ by case only, and the frequency coordinate of
        # eps is "omega" (the orbits file, which has no omega, keeps the name Omega)
        "Omega_orbit": kv(
            grid["Omega"], "1/time", f"orbital frequency Omega(kappa) ({eq('hmfomega')})"
        ),
        "resonance_n": variable(
            ("resonance",),
            res["n"].astype(np.int32),
            "1",
            "harmonic n of the test orbit (n > 0; the mirror resonance (-n, -n') is included "
            "in gamma)",
            valid=(1, None),
        ),
        "resonance_nprime": variable(
            ("resonance",),
            res["nprime"].astype(np.int32),
            "1",
            "harmonic n' of the bath orbit",
            valid=(1, None),
        ),
        "resonance_branch": variable(
            ("resonance",),
            res["branch"].astype(np.int32),
            "1",
            "orbit family of kappa*",
            valid=UNIT_INTERVAL,
            flag_values=np.array([0, 1], dtype=np.int32),  # CF 3.5: the variable's own type
            flag_meanings="libration rotation",
        ),
        "resonance_kappa_star": variable(
            kr,
            res["kappa_star"],
            "1",
            "resonant kappa*: n Omega(kappa) = n' Omega(kappa*)",
            valid=NONNEGATIVE,
            missing="NaN where the resonance has no root or kappa is in the separatrix band",
        ),
        "M0": variable((), float(grid["M0"]), "1", "magnetisation M0", valid=UNIT_INTERVAL),
        "separatrix_mask": variable(
            k,
            grid["masked"].astype(np.int8),
            "1",
            "1 where |kappa - 1| < separatrix_band",
            valid=UNIT_INTERVAL,
        ),
    }
    for name, word, theory, d_eq in (
        ("landau", "without", "Landau", "hmfDbare"),
        ("lenard_balescu", "with", "Lenard-Balescu", "hmfD"),
    ):
        eqs = f"{theory}, {eq('hmfCEdif', d_eq)}"
        coef = grid[name]
        data[f"D_{name}"] = kv(coef["D"], D_UNITS, f"N D_dif {word} collective effects ({eqs})")
        data[f"Dpol_{name}"] = kv(
            coef["Dpol"],
            D_UNITS,
            f"N D_pol {word} collective effects ({eq('hmfCEpol')}); flux = D_dif df/dJ - D_pol f",
            valid=None,  # friction: no sign of its own
        )
        data[f"gamma_{name}"] = variable(
            kr,
            coef["gamma"],
            D_UNITS,
            f"contribution gamma(kappa, kappa*) of each resonance to N D_dif ({theory}, "
            f"{eq('hmfCEdif')}; fig. {FIGURES['fig:hmfcontribs']}); sums to D_{name}",
            valid=NONNEGATIVE,
            missing="NaN where the resonance has no root",
        )
    for comp in ("cc", "ss"):
        e = grid[f"eps_{comp}"]
        data[f"eps_{comp}_real"] = variable(("omega",), e.real, "1", f"Re eps_{comp}(omega)")
        data[f"eps_{comp}_imag"] = variable(("omega",), e.imag, "1", f"Im eps_{comp}(omega)")
    coords = {
        "kappa": variable(
            k,
            grid["kappa"],
            "1",
            f"orbit label kappa ({eq('hmfkappa')}); < 1 librating, > 1 rotating",
            valid=NONNEGATIVE,
        ),
        "omega": variable(
            ("omega",), grid["omega"], "1/time", "real frequency (Landau prescription omega + i0)"
        ),
        "resonance": variable(
            ("resonance",),
            np.arange(res["n"].size, dtype=np.int32),
            "1",
            "resonance index, ordered (n, n', branch)",
            valid=NONNEGATIVE,
        ),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(grid["attrs"])
    return ds


def closed_forms_dataset(forms):
    """results/analytic/{case}.nc from `kinetic.closed_forms.closed_forms`: the paper's closed
    forms on librating orbits, and the closed-form dielectric tensor where there is one."""
    n_max, method = forms["n_max"], forms["dielectric_method"]
    long_names = {
        "D_landau_sech4": f"N D_dif, Landau, sech^4 closed form ({eq('coeff-analytic-ncoll')}; the "
        "n = n' = +-1 term)",
        "D_landau_small_kappa": f"N D_dif ~ 32 pi^2 kappa^4 f ({eq('coeff-analytic-ncoll-exp')})",
        "D_landau_librating_sum": f"N D_dif, Landau, librating resonances |n|,|n'| <= {n_max}",
        "Dpol_landau_sech4": "N D_pol, Landau, sech^4 closed form, sign corrected",
        "D_lenard_balescu_closed": f"N D_dif with collective effects, {method}, "
        f"|n|, |n'| <= {n_max}",
    }
    data = {
        name: variable(
            ("kappa",),
            np.asarray(vals, dtype=float),
            D_UNITS,
            long_names[name],
            valid=NONNEGATIVE if name.startswith("D_") else None,  # N D_dif >= 0; D_pol: friction
        )
        for name, vals in forms["D"].items()
    }
    for comp, e in forms["eps"].items():
        for part, vals, word in (("real", e.real, "Re"), ("imag", e.imag, "Im")):
            data[f"eps_{comp}_{part}"] = variable(
                ("omega",), vals, "1", f"{word} eps_{comp}(omega), closed form", method=method
            )
    data["M0"] = variable((), float(forms["M0"]), "1", "magnetisation M0", valid=UNIT_INTERVAL)
    coords = {
        "kappa": variable(
            ("kappa",), forms["kappa"], "1", "orbit label kappa (< 1)", valid=NONNEGATIVE
        ),
        "omega": variable(("omega",), forms["omega"], "1/time", "real frequency"),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(
        n_max=int(n_max),
        l_max=int(forms["l_max"]),
        separatrix_band=float(forms["separatrix_band"]),
        dielectric_method=method or "none",
        D_convention="<dJ^2> = 2 D dt; N*D stored",
    )
    if np.isfinite(forms.get("expansion_parameter", np.nan)):
        ds.attrs.update(
            dielectric_expansion_parameter=float(forms["expansion_parameter"]),
            dielectric_applies=int(forms["applies"]),
            dielectric_validity=(
                "expansion in 1/(beta M0), applicable up to "
                f"{forms['applies_up_to']:g}: "
                + (
                    "applies here"
                    if forms["applies"]
                    else "does NOT apply here (stored for "
                    "comparison only; eps_* and D_lenard_balescu_closed are not this state's)"
                )
            ),
        )
    return ds
