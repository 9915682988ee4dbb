"""Layouts of the diffusion measured by MD: results/md/{case}/{dynamics}/seeds{first}-{last}/
seed{seed}.nc (`dynamics.md.run_md`: sums of <dJ^2> per bin and lag; one folder per MD job, a
block of seeds) and results/fits/{case}_{dynamics}.nc (`analysis.fits.diffusion_fit`: N D_MD
per bin)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from ...paper_equations import eq
from .variables import ACTION, COMPONENT, NONNEGATIVE, UNIT_INTERVAL, flag_word, variable

__all__ = ["md_dataset", "fit_dataset", "seed_files"]

SEED_FILE = re.compile(r"seed(\d+)\.nc")


def seed_files(inputs, n_seeds):
    """The seed files of one run, in the order of the seed: `inputs` are seed{s}.nc files or
    folders of them (one per MD job).  Together they must hold exactly seeds 0 ... n_seeds - 1,
    once each (RuntimeError naming what is missing or repeated otherwise)."""
    inputs = [inputs] if isinstance(inputs, str | Path) else list(inputs)
    found = {}
    for p in map(Path, inputs):
        files = sorted(p.glob("seed*.nc")) if p.is_dir() else [p]
        for f in files:
            m = SEED_FILE.fullmatch(f.name)
            if not m:
                raise RuntimeError(f"{f}: not a seed file (seed<s>.nc)")
            s = int(m.group(1))
            if s in found:
                raise RuntimeError(f"seed {s} twice: {found[s]} and {f}")
            found[s] = f
    missing = sorted(set(range(n_seeds)) - set(found))
    extra = sorted(set(found) - set(range(n_seeds)))
    if missing or extra:
        raise RuntimeError(
            f"{', '.join(map(str, inputs))}: seeds {missing} missing, {extra} unexpected "
            f"(expected seeds 0 ... {n_seeds - 1})"
        )
    return [str(found[s]) for s in range(n_seeds)]


def md_dataset(result):
    """results/md/{case}/{dynamics}/seeds{first}-{last}/seed{seed}.nc from `dynamics.md.run_md`:
    sums per (bin, lag) and per (bin, lag, block) over (origin, particle) pairs, eq. (75)
    (<dJ^2> = sum_dJ2 / count; use ds["count"]: ds.count is a method); Mx, My, energy,
    momentum; a few stored tracks."""
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
        "ND_md": variable(
            b, fit["ND_md"], nd, f"N D_MD = N slope/2 of <dJ^2>(dt) ({eq('hmfmddif')})"
        ),
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
            flag_meanings=" ".join(map(flag_word, flags.values())),
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
