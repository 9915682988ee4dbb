"""Every netCDF dataset the pipeline writes, laid out in one place: named dimensions, and units
and a long name on every variable through one helper (`variable`).

* equilibrium and orbits: mean-field functions tabulated on `orbits.kappa_grid`
  (results/equilibrium/, results/orbits/); `state_from_dataset` rebuilds the state of a file;
* theory, closed forms, md, fit: the results of `kinetic.theory.theory_grid`,
  `kinetic.closed_forms.closed_forms`, `dynamics.md.run_md` and `analysis.fits` laid out
  (results/theory/, results/analytic/, results/md/, results/fits/).

Physics modules return arrays; this module names them.  It imports only the mean-field physics,
so that a rule whose script imports it does not rerun when another stage's physics changes.
"""

from __future__ import annotations

import json
import re

import numpy as np
import xarray as xr

from ..meanfield import orbits
from ..meanfield.equilibrium import CoreHaloState, ThermalState, make_state
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag
from .io import cf_units

__all__ = [
    "variable",
    "equilibrium_dataset",
    "state_from_dataset",
    "orbits_dataset",
    "theory_dataset",
    "closed_forms_dataset",
    "md_dataset",
    "fit_dataset",
]

D_UNITS = "action^2 / time (N * D, the 1/N factored out)"
ACTION = "action (dimensionless HMF units)"


#: physical ranges of the values (`variable`'s keyword `valid`): only true bounds, which no
#: legitimate result can cross
NONNEGATIVE = (0, None)  # counts, sums of squares, densities f, D_dif, errors, actions, ...
UNIT_INTERVAL = (0, 1)  # M0, |M|, probabilities, flags 0/1
COMPONENT = (-1, 1)  # Mx, My, Fourier coefficients of cos and sin theta
#: energy per particle of the interacting system: H/N = <p^2>/2 - M^2/2 >= -1/2
ENERGY_PER_PARTICLE = (-0.5, None)


def variable(dims, data, units, long_name, valid=None, **attrs):
    """A netCDF variable with named dimensions, units and long_name (and any other attributes).

    valid: (lo, hi), the physical range of the values (None for an open side), stored as the
    CF attributes valid_min / valid_max in the variable's type; `io.read_dataset` refuses a
    file holding a value outside it (NaN, a masked value, is not outside).

    units: CF units ("1", "rad") or an HMF quantity of `io.HMF_UNITS` (stored as "1" with the
    quantity in `comment`); any other string is refused (ValueError, `io.cf_units`)."""
    attrs = cf_units(units, attrs)
    if valid is not None:
        kind = np.asarray(data).dtype.type
        for key, bound in zip(("valid_min", "valid_max"), valid, strict=True):
            if bound is not None:
                attrs[key] = kind(bound)
    return xr.Variable(dims, data, {"long_name": long_name, **attrs})


def _flag_word(meaning):
    """A flag meaning as one CF word (CF 3.5: letters, digits and _ - . + @; blanks separate)."""
    return re.sub(r"[^A-Za-z0-9_.+@-]+", "_", meaning).strip("_")


# ------------------------------------------------------------------------------ mean field
def equilibrium_dataset(state, n_kappa, kappa_max):
    """results/equilibrium/{case}.nc: scalars M0, u (beta), f and df/dkappa on a kappa grid."""
    kappa = orbits.kappa_grid(n_kappa, kappa_max)
    f = state.f(kappa)
    dos = 2.0 * np.pi * orbits.phase_space_weight(kappa) * orbits.dJ_dkappa(kappa, state.M0)
    k = ("kappa",)
    data = {
        "f": variable(
            k,
            f,
            "1",
            "phase-space density f(kappa), normalised to int f dtheta dp = 1",
            valid=NONNEGATIVE,
        ),
        "dfdkappa": variable(
            k, state.dfdkappa(kappa), "1", "df/dkappa (smooth part; steps in attribute 'steps')"
        ),
        "density_of_states": variable(
            k,
            dos,
            "1",
            "phase-space area per unit kappa, "
            "2 pi dJ/dkappa times 2 on rotating orbits (both directions)",
            valid=NONNEGATIVE,
        ),
        "kappa_distribution": variable(
            k,
            f * dos,
            "1",
            "probability density of kappa, f * density_of_states",
            valid=NONNEGATIVE,
        ),
        "M0": variable(
            (), float(state.M0), "1", "magnetisation M0 (self-consistent)", valid=UNIT_INTERVAL
        ),
        "u": variable(
            (),
            float(state.u),
            "1",
            "energy per particle u = <p^2>/2 - M0^2/2",
            valid=ENERGY_PER_PARTICLE,
        ),
    }
    if isinstance(state, ThermalState):
        data["beta"] = variable(
            (),
            float(state.beta),
            "1",
            "inverse temperature beta, M0 = I1(beta M0)/I0(beta M0)",
            valid=NONNEGATIVE,
        )
    if isinstance(state, CoreHaloState):
        data["mass"] = variable(
            (),
            float(state.mass),
            "1",
            "int f_raw dtheta dp before normalisation",
            valid=NONNEGATIVE,
        )
    kc = variable(
        k,
        kappa,
        "1",
        "orbit label kappa = sqrt((h + M0)/(2 M0)); < 1 librating",
        valid=NONNEGATIVE,
    )
    ds = xr.Dataset(data, coords={"kappa": kc})
    ds.attrs["kind"] = state.kind if not getattr(state, "shape", "") == "step" else "two_step"
    ds.attrs["state_params"] = json.dumps(state.params, sort_keys=True)
    if isinstance(state, CoreHaloState) and state.shape == "step":
        ds.attrs["steps"] = json.dumps(
            {
                "kappa": list(map(float, state.step_kappas)),
                "weight": list(map(float, state.step_weights)),
                "meaning": "df/dkappa = -sum_i weight_i delta(kappa - kappa_i)",
            }
        )
    return ds


def state_from_dataset(ds):
    """Rebuild the equilibrium state stored in an equilibrium dataset (checks M0 agrees)."""
    spec = {"kind": ds.attrs["kind"], **json.loads(ds.attrs["state_params"])}
    state = make_state(spec)
    stored = float(ds["M0"])
    if not np.isclose(state.M0, stored, rtol=1e-10, atol=0):
        raise ValueError(
            f"equilibrium file gives M0 = {stored!r} but its parameters give {state.M0!r}: "
            "the file is stale; rerun the equilibrium rule"
        )
    return state


def orbits_dataset(M0, n_kappa, kappa_max, n_max):
    """results/orbits/{case}.nc: J, J-bar, Omega, dJ/dkappa, dOmega/dkappa, c_n, sigma_n for
    harmonics 0 ... n_max."""
    kappa = orbits.kappa_grid(n_kappa, kappa_max)
    n = np.arange(0, n_max + 1)
    k, nk = ("kappa",), ("n", "kappa")
    data = {
        "J": variable(k, orbits.action(kappa, M0), "1", "action J", valid=NONNEGATIVE),
        "Jbar": variable(
            k,
            orbits.rescaled_action(kappa, M0),
            "1",
            "rescaled action J-bar (J/2 for kappa < 1)",
            valid=NONNEGATIVE,
        ),
        "Omega": variable(
            k,
            orbits.frequency(kappa, M0),
            "1",
            "orbital frequency Omega = dh/dJ",
            valid=NONNEGATIVE,
        ),
        "dJ_dkappa": variable(k, orbits.dJ_dkappa(kappa, M0), "1", "dJ/dkappa", valid=NONNEGATIVE),
        "dOmega_dkappa": variable(k, orbits.dOmega_dkappa(kappa, M0), "1", "dOmega/dkappa"),
        "c": variable(
            nk,
            cos_coefficient(n[:, None], kappa[None, :]),
            "1",
            "c_n = (1/2pi) int cos(theta(w)) exp(-inw) dw (real; c_-n = c_n)",
            valid=COMPONENT,
        ),
        "sigma": variable(
            nk,
            sin_coefficient_imag(n[:, None], kappa[None, :], 1.0),
            "1",
            "s_n = -i sigma_n for p > 0 (sigma flips sign for p < 0; s_-n = -s_n)",
            valid=COMPONENT,
        ),
        "M0": variable((), float(M0), "1", "magnetisation M0", valid=UNIT_INTERVAL),
    }
    for name, var in data.items():
        if not np.all(np.isfinite(var.values)):
            raise FloatingPointError(f"orbits dataset: non-finite values in {name}")
    coords = {
        "kappa": variable(k, kappa, "1", "orbit label kappa", valid=NONNEGATIVE),
        "n": variable(("n",), n, "1", "Fourier harmonic n", valid=NONNEGATIVE),
    }
    return xr.Dataset(data, coords=coords)


# ------------------------------------------------------------------------------ kinetic theory
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
        "J": kv(grid["J"], "action", "action J(kappa) (eq. hmfaction)"),
        "Jbar": kv(
            grid["Jbar"], "action", "rescaled action J-bar (J/2 for kappa < 1, J for kappa > 1)"
        ),
        "Omega": kv(grid["Omega"], "1/time", "orbital frequency Omega(kappa) (eq. hmfomega)"),
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
    for name, word, eqs in (
        ("landau", "without", "Landau, eqs. hmfCEdif, hmfDbare"),
        ("lenard_balescu", "with", "Lenard-Balescu, eqs. hmfCEdif, hmfD"),
    ):
        coef = grid[name]
        data[f"D_{name}"] = kv(coef["D"], D_UNITS, f"N D_dif {word} collective effects ({eqs})")
        data[f"Dpol_{name}"] = kv(
            coef["Dpol"],
            D_UNITS,
            f"N D_pol {word} collective effects (eq. hmfCEpol); flux = D_dif df/dJ - D_pol f",
            valid=None,  # friction: no sign of its own
        )
        data[f"gamma_{name}"] = variable(
            kr,
            coef["gamma"],
            D_UNITS,
            f"contribution gamma(kappa, kappa*) of each resonance to N D_dif ({eqs.split(',')[0]};"
            f" fig. hmfcontribs); sums to D_{name}",
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
            "orbit label kappa (eq. hmfkappa); < 1 librating, > 1 rotating",
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
        "D_landau_sech4": "N D_dif, Landau, sech^4 closed form (eq. coeff-analytic-ncoll; the "
        "n = n' = +-1 term)",
        "D_landau_small_kappa": "N D_dif ~ 32 pi^2 kappa^4 f (eq. coeff-analytic-ncoll-exp)",
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


# ------------------------------------------------------------------------------ MD and fits
def md_dataset(result):
    """results/md/{case}/{dynamics}/seed{seed}.nc from `dynamics.md.run_md`: sums per (bin, lag)
    and per (bin, lag, block) over (origin, particle) pairs, eq. dj2 (<dJ^2> = sum_dJ2 / count;
    use ds["count"]: ds.count is a method); Mx, My, energy, momentum; a few stored tracks."""
    run, a, edges, series = result.run, result.sums, result.jbar_edges, result.series
    bl, bll, t, tt = ("bin", "lag"), ("bin", "lag", "block"), ("t",), ("t", "tracer")
    data = {}

    def sums(name, i, units, long_name, dtype=float, valid=NONNEGATIVE):  # per (bin, lag), block
        vals = a[i].astype(dtype)
        data[name] = variable(bl, vals.sum(-1), units, long_name, valid=valid)
        data[f"{name}_block"] = variable(
            bll, vals, units, f"{name} restricted to a block of origins", valid=valid
        )

    pairs = "sum over origins and particles of"
    sums("sum_dJ2", 0, f"{ACTION}^2", f"{pairs} (J(t0+lag) - J(t0))^2")
    sums("sum_dJbar2", 1, f"{ACTION}^2", f"{pairs} (Jbar(t0+lag) - Jbar(t0))^2")
    sums("sum_dJ", 2, ACTION, f"{pairs} J(t0+lag) - J(t0)", valid=None)
    sums("count", 3, "1", "number of (origin, particle) pairs in the sums", np.int64)
    who = "the bath / interacting particles"
    data.update(
        n_particles_in_bin=variable(
            ("bin",),
            result.n_particles_in_bin,
            "1",
            "number of distinct particles in the bin at any origin",
            valid=NONNEGATIVE,
        ),
        n_origins_in_block=variable(
            ("block",),
            result.n_origins_in_block,
            "1",
            "number of time origins in the block",
            valid=NONNEGATIVE,
        ),
        Mx=variable(t, series["Mx"], "1", f"magnetisation x component of {who}", valid=COMPONENT),
        My=variable(t, series["My"], "1", f"magnetisation y component of {who}", valid=COMPONENT),
        energy=variable(
            t,
            series["energy"],
            "energy per particle",
            result.attrs["energy_definition"],
            valid=(-1.0, None),  # H/N >= -1/2 (full); p^2/2 - M0 cos theta >= -M0 >= -1 (bath)
        ),
        momentum=variable(
            t,
            series["momentum"],
            "momentum per particle",
            f"total momentum per particle sum p_i / N of {who}",
        ),
        Mx_fine=variable(
            ("time_fine",),
            result.m_fine[:, 0],
            "1",
            f"magnetisation x component of {who}, every m_every (for its spectrum)",
            valid=COMPONENT,
        ),
        My_fine=variable(
            ("time_fine",),
            result.m_fine[:, 1],
            "1",
            f"magnetisation y component of {who}, every m_every (for its spectrum)",
            valid=COMPONENT,
        ),
        sample_theta=variable(
            tt, result.sample_theta, "rad", "angle of sample tracked particles in the action frame"
        ),
        sample_p=variable(tt, result.sample_p, "1", "momentum of sample tracked particles"),
        sample_J=variable(
            tt, result.sample_J, ACTION, "action J of sample tracked particles", valid=NONNEGATIVE
        ),
    )
    coords = {
        "jbar_edges": variable(
            ("edge",),
            edges,
            ACTION,
            "edges of the bins of initial rescaled action",
            valid=NONNEGATIVE,
        ),
        "jbar0": variable(
            ("bin",),
            0.5 * (edges[1:] + edges[:-1]),
            ACTION,
            "bin centre of the initial rescaled action Jbar(t0)",
            valid=NONNEGATIVE,
        ),
        "lag": variable(
            ("lag",),
            np.arange(run.lag_samples + 1) * run.sample_every,
            "time (1/sqrt(M=1) units)",
            "time lag Delta t",
            valid=NONNEGATIVE,
        ),
        "t": variable(
            t,
            np.arange(result.sample_theta.shape[0]) * run.sample_every,
            "time",
            "time since the start of production",
            valid=NONNEGATIVE,
        ),
        "time_fine": variable(
            ("time_fine",),
            np.arange(result.m_fine.shape[0]) * run.m_every,
            "time",
            "time since the start of production (magnetisation every m_every)",
            valid=NONNEGATIVE,
        ),
        "block": variable(
            ("block",),
            np.arange(run.n_blocks),
            "1",
            "block of consecutive time origins",
            valid=NONNEGATIVE,
        ),
        "tracer": variable(
            ("tracer",),
            result.tracer,
            "1",
            "index of the stored tracked particle",
            valid=NONNEGATIVE,
        ),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(result.attrs)
    return ds


def fit_dataset(fit):
    """results/fits/{case}_{dynamics}.nc from `analysis.fits.diffusion_fit`: N*D_MD per J-bar_0
    bin with its standard error and flag, the per-seed values and the pooled <dJ^2>(lag)."""
    b, nd, flags = ("bin",), "action^2/time", fit["flags"]
    data = {
        "ND_md": variable(b, fit["ND_md"], nd, "N D_MD = N slope/2 of <dJ^2>(dt) (eq. hmfmddif)"),
        "ND_md_err": variable(
            b,
            fit["ND_md_err"],
            nd,
            "standard error of ND_md",
            valid=NONNEGATIVE,
            method=fit["attrs"]["error_method"],
        ),
        "ND_md_seed": variable(("seed", "bin"), fit["ND_md_seed"], nd, "N D_MD of each seed"),
        "intercept": variable(b, fit["intercept"], "action^2", "intercept of the linear fit"),
        "msd": variable(
            ("bin", "lag"),
            fit["msd"],
            "action^2",
            "<dJ^2>(dt) pooled over seeds, J units (4 <dJbar^2> below the separatrix)",
            valid=NONNEGATIVE,
        ),
        "n_particles_in_bin": variable(
            b,
            fit["n_particles_in_bin"],
            "1",
            "tracked particles per bin, all seeds",
            valid=NONNEGATIVE,
        ),
        "kappa0": variable(b, fit["kappa0"], "1", "kappa at the bin centre", valid=NONNEGATIVE),
        "J0": variable(b, fit["J0"], "action", "action J at the bin centre", valid=NONNEGATIVE),
        "flag": variable(
            b,
            fit["flag"],
            "1",
            "bin quality",
            valid=(min(flags), max(flags)),
            flag_values=np.array(list(flags), dtype=np.asarray(fit["flag"]).dtype),
            flag_meanings=" ".join(map(_flag_word, flags.values())),
            comment="; ".join(f"{k}: {v}" for k, v in flags.items()),
        ),
        "M0": variable(
            (), float(fit["M0"]), "1", "magnetisation used for the actions", valid=UNIT_INTERVAL
        ),
    }
    coords = {
        "jbar0": variable(b, fit["jbar0"], "action", "bin centre, J-bar_0", valid=NONNEGATIVE),
        "jbar_edges": variable(
            ("edge",), fit["jbar_edges"], "action", "edges of the J-bar_0 bins", valid=NONNEGATIVE
        ),
        "lag": variable(("lag",), fit["lag"], "time", "time lag dt", valid=NONNEGATIVE),
        "seed": variable(("seed",), fit["seed"], "1", "MD seed (realisation)", valid=NONNEGATIVE),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(fit["attrs"])
    return ds
