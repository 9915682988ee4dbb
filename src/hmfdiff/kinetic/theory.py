"""Kinetic-theory grids of one equilibrium state as an xarray.Dataset (figs. 4, 5, 6, 9, 10).

`theory_dataset` evaluates, on a kappa grid on both sides of the separatrix, the Landau and
Lenard-Balescu diffusion (N D_dif) and polarisation (N D_pol) coefficients in the action J,
the resonance contributions gamma(kappa, kappa*) of fig. hmfcontribs, and the dielectric tensor
on an omega grid (real and imaginary parts: netCDF has no complex type).
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ..meanfield import orbits
from .dielectric import DielectricTensor
from .diffusion import _coefficients_from_table, resonance_table

__all__ = ["theory_dataset", "default_omega"]

_D_UNITS = "action^2 / time (N * D, the 1/N factored out)"


def default_omega(M0, n=401):
    """omega grid of fig. eps: 0 to 4 Omega_0 (Omega_0 = sqrt(M0))."""
    return np.linspace(0.0, 4.0 * np.sqrt(M0), n)


def theory_dataset(
    state,
    *,
    n_kappa=400,
    kappa_min=0.01,
    kappa_max=3.0,
    separatrix_band=0.01,
    n_max=6,
    l_max=6,
    omega=None,
    n_panels=48,
    order=20,
):
    """Landau and Lenard-Balescu N D_dif, N D_pol and eps(omega) of `state` (ThermalState or
    CoreHaloState with shape='fermi').

    kappa = linspace(kappa_min, kappa_max, n_kappa); points with |kappa - 1| < separatrix_band are
    kept on the grid but every kappa-dependent variable is NaN there (Omega -> 0 and the
    perturbative theory fails at the separatrix; the paper cuts its curves there too).  omega
    defaults to `default_omega(M0)`.  n_panels, order: quadrature of the dielectric integrals.
    """
    if getattr(state, "shape", "fermi") == "step":
        raise NotImplementedError(
            "the two-step core-halo state (shape='step') has delta-function df/dkappa: its "
            "dielectric tensor and diffusion coefficients are the closed forms of kinetic.analytic"
        )
    M0 = state.M0
    kappa = np.linspace(kappa_min, kappa_max, int(n_kappa))
    masked = np.abs(kappa - 1.0) < separatrix_band
    kv = kappa[~masked]
    omega = default_omega(M0) if omega is None else np.asarray(omega, dtype=float)

    eps = DielectricTensor(state, l_max=l_max, n_panels=n_panels, order=order)
    table = resonance_table(state, kv, n_max)
    lan = _coefficients_from_table(state, kv, table, n_max, l_max, False, None, {})
    lb = _coefficients_from_table(state, kv, table, n_max, l_max, True, eps, {})
    eps_cc, eps_ss = eps(omega)

    R = table["n"].size

    def full(vals, fill=np.nan):
        vals = np.asarray(vals)
        out = np.full((kappa.size,) + vals.shape[1:], fill, dtype=vals.dtype)
        out[~masked] = vals
        return out

    J = full(orbits.action(kv, M0))
    Jbar = full(orbits.rescaled_action(kv, M0))
    Om = full(orbits.frequency(kv, M0))
    for name, arr in (("landau", lan), ("lenard_balescu", lb)):
        for key in ("D", "Dpol"):
            if not np.all(np.isfinite(arr[key])):
                raise FloatingPointError(f"non-finite {key} ({name}) outside the separatrix band")
    if not (np.all(np.isfinite(eps_cc)) and np.all(np.isfinite(eps_ss))):
        raise FloatingPointError("non-finite dielectric tensor on the omega grid")

    band_note = (
        f"NaN for |kappa - 1| < separatrix_band = {separatrix_band}: Omega -> 0 and the "
        "action-angle perturbation theory fails at the separatrix (the paper cuts its curves there)"
    )

    def kvar(vals, units, long_name, extra=None):
        attrs = {"units": units, "long_name": long_name, "masked": band_note}
        attrs.update(extra or {})
        return ("kappa", vals, attrs)

    data = {
        "J": kvar(J, "action", "action J(kappa) (eq. hmfaction)"),
        "Jbar": kvar(Jbar, "action", "rescaled action J-bar (J/2 for kappa < 1, J for kappa > 1)"),
        "Omega": kvar(Om, "1/time", "orbital frequency Omega(kappa) (eq. hmfomega)"),
        "D_landau": kvar(
            full(lan["D"]),
            _D_UNITS,
            "N D_dif without collective effects (Landau, eqs. hmfCEdif, hmfDbare)",
        ),
        "D_lenard_balescu": kvar(
            full(lb["D"]),
            _D_UNITS,
            "N D_dif with collective effects (Lenard-Balescu, eqs. hmfCEdif, hmfD)",
        ),
        "Dpol_landau": kvar(
            full(lan["Dpol"]),
            _D_UNITS,
            "N D_pol without collective effects (eq. hmfCEpol); flux = D_dif df/dJ - D_pol f",
        ),
        "Dpol_lenard_balescu": kvar(
            full(lb["Dpol"]),
            _D_UNITS,
            "N D_pol with collective effects (eq. hmfCEpol); flux = D_dif df/dJ - D_pol f",
        ),
        "eps_cc_real": ("omega", eps_cc.real, {"units": "1", "long_name": "Re eps_cc(omega)"}),
        "eps_cc_imag": ("omega", eps_cc.imag, {"units": "1", "long_name": "Im eps_cc(omega)"}),
        "eps_ss_real": ("omega", eps_ss.real, {"units": "1", "long_name": "Re eps_ss(omega)"}),
        "eps_ss_imag": ("omega", eps_ss.imag, {"units": "1", "long_name": "Im eps_ss(omega)"}),
        "resonance_n": (
            "resonance",
            table["n"].astype(np.int32),
            {
                "units": "1",
                "long_name": "harmonic n of the test orbit (n > 0; the "
                "mirror resonance (-n, -n') is included in gamma)",
            },
        ),
        "resonance_nprime": (
            "resonance",
            table["nprime"].astype(np.int32),
            {"units": "1", "long_name": "harmonic n' of the bath orbit"},
        ),
        "resonance_branch": (
            "resonance",
            table["branch"].astype(np.int32),
            {
                "units": "1",
                "long_name": "orbit family of kappa*",
                "flag_values": "0 1",
                "flag_meanings": "libration rotation",
            },
        ),
        "resonance_kappa_star": (
            ("kappa", "resonance"),
            full(table["kappa_star"]),
            {
                "units": "1",
                "long_name": "resonant kappa*: n Omega(kappa) = n' Omega(kappa*)",
                "missing": "NaN where the resonance has no root or kappa is in the separatrix band",
            },
        ),
        "gamma_landau": (
            ("kappa", "resonance"),
            full(lan["gamma"]),
            {
                "units": _D_UNITS,
                "long_name": "contribution gamma(kappa, kappa*) of "
                "each resonance to N D_dif (Landau); sums to D_landau",
                "missing": "NaN where the resonance has no root",
            },
        ),
        "gamma_lenard_balescu": (
            ("kappa", "resonance"),
            full(lb["gamma"]),
            {
                "units": _D_UNITS,
                "long_name": "contribution gamma(kappa, "
                "kappa*) of each resonance to N D_dif (Lenard-Balescu; fig. "
                "hmfcontribs); sums to D_lenard_balescu",
                "missing": "NaN where the resonance has no root",
            },
        ),
        "M0": ((), M0, {"units": "1", "long_name": "magnetisation M0"}),
        "separatrix_mask": (
            "kappa",
            masked.astype(np.int8),
            {"units": "1", "long_name": "1 where |kappa - 1| < separatrix_band"},
        ),
    }
    ds = xr.Dataset(
        data,
        coords={
            "kappa": (
                "kappa",
                kappa,
                {
                    "units": "1",
                    "long_name": "orbit label kappa (eq. hmfkappa); < 1 librating, > 1 rotating",
                },
            ),
            "omega": (
                "omega",
                omega,
                {"units": "1/time", "long_name": "real frequency (Landau prescription omega + i0)"},
            ),
            "resonance": (
                "resonance",
                np.arange(R, dtype=np.int32),
                {"long_name": "resonance index, ordered (n, n', branch)"},
            ),
        },
    )
    ds.attrs.update(
        n_max=int(n_max),
        l_max=int(l_max),
        separatrix_band=float(separatrix_band),
        separatrix_band_note=band_note,
        eps_quadrature=f"Gauss-Legendre in Omega per branch: n_panels={n_panels}, order={order}; "
        "principal values by pole subtraction (hmfdiff.kinetic.dielectric)",
        eps_kappa_max=float(eps.kappa_max),
        D_convention="<dJ^2> = 2 D dt; N*D stored; rotating orbits counted for both directions",
        time_dependence="exp(-i omega t)",
    )
    ds.attrs["Omega0"] = float(np.sqrt(M0))
    ds.attrs["state_kind"] = str(getattr(state, "kind", type(state).__name__))
    ds.attrs["state_params"] = json.dumps(getattr(state, "params", {}))
    if getattr(state, "beta", None) is not None:
        ds.attrs["beta"] = float(state.beta)
    return ds
