"""Shared look of the figures: saving with provenance, panel labels, numbers, axis labels.

Units: the HMF model is written with unit mass and unit coupling (H = sum p^2/2 - (1/2N) sum
cos(theta_i - theta_j)), so time, momentum, action and frequency are pure numbers in
those "HMF units"; axis labels say so for every dimensional quantity, give radians for angles
and no unit for pure numbers (kappa, eps, ratios).
"""

from __future__ import annotations

import json
import math
from string import ascii_lowercase

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402

from ...pipeline.io import atomic_path, provenance  # noqa: E402

__all__ = [
    "plt",
    "save_figure",
    "panel_tag",
    "tag_panels",
    "sci",
    "HMF",
    "state_label",
    "separatrix_line",
    "robust_ylim",
]


class _Pyplot:
    """matplotlib.pyplot, imported when a figure is first drawn: every start of the workflow
    reads the figure registry (which imports the drawing modules), and pyplot alone takes
    ~0.7 s to import, a third of the registry."""

    def __getattr__(self, name):
        import matplotlib.pyplot

        return getattr(matplotlib.pyplot, name)


plt = _Pyplot()

matplotlib.rcParams.update(
    {
        "figure.dpi": 100,
        "savefig.dpi": 150,
        "font.size": 9,
        "axes.grid": False,
        # tick labels beyond [1e-2, 1e3) as a x 10^b in mathtext, like `sci` below
        "axes.formatter.limits": (-2, 3),
        "axes.formatter.use_mathtext": True,
    }
)

HMF = "HMF units"  # unit mass and coupling: see the module docstring


def panel_tag(i):
    """The label of the i-th panel in reading order: (a), (b), ..., (z), (aa), ..."""
    if i < 0:
        raise ValueError(f"panel index {i} < 0")
    letters = ""
    i += 1
    while i:
        i, r = divmod(i - 1, 26)
        letters = ascii_lowercase[r] + letters
    return f"({letters})"


def tag_panels(axes, titles, fontsize=8):
    """Title each panel "(a) title", "(b) title", ... in reading order (rows first).

    `axes` is an array of Axes (any shape, as plt.subplots returns it) and `titles` a sequence
    of the same number of strings, also in reading order."""
    flat = list(np.ravel(axes))
    if len(flat) != len(titles):
        raise ValueError(f"{len(flat)} panels but {len(titles)} titles")
    for i, (ax, title) in enumerate(zip(flat, titles, strict=True)):
        ax.set_title(f"{panel_tag(i)} {title}".rstrip(), fontsize=fontsize)


def sci(x, digits=3):
    """A number for mathtext (without the $ signs): 5000 -> '5\\times10^{3}', 0.728 -> '0.728'.

    Plain decimal notation for 1e-2 <= |x| < 1e3, otherwise mantissa x 10^exponent with
    `digits` significant digits (a mantissa of 1 is left out: 1e6 -> '10^{6}')."""
    x = float(x)
    if not math.isfinite(x):
        return r"\infty" if x > 0 else (r"-\infty" if x < 0 else r"\mathrm{NaN}")
    if x == 0:
        return "0"
    if 1e-2 <= abs(x) < 1e3:
        return f"{x:.{digits}g}"
    mantissa, exponent = f"{x:.{digits - 1}e}".split("e")
    mantissa = mantissa.rstrip("0").rstrip(".")
    exponent = int(exponent)
    if mantissa in ("1", "-1"):
        return f"{mantissa[:-1]}10^{{{exponent}}}"
    return rf"{mantissa}\times10^{{{exponent}}}"


def state_label(ds):
    """'(u, M0) = (..)' for a thermal state, 'case: M0 = ..' otherwise, in mathtext."""
    M0 = float(ds["M0"])
    if "beta" in ds.attrs:
        u = round(0.5 / ds.attrs["beta"] - 0.5 * M0**2, 10) + 0.0  # no -0 or 1e-17
        return rf"$(u, M_0)=({sci(u, 4)}, {sci(M0, 4)})$"
    case = ds.attrs.get("case", "")
    label = rf"$M_0={sci(M0, 4)}$"
    return f"{case}: {label}" if case else label


def separatrix_line(ax, vertical=True, at=1.0):
    """A thin grey line at the separatrix (kappa = 1 unless `at` says otherwise)."""
    (ax.axvline if vertical else ax.axhline)(at, color="0.6", lw=0.8, zorder=0)


def robust_ylim(ax, arrays, pad=0.25):
    """y limits from the 1st-99th percentiles of the finite values (poles would swamp them)."""
    vals = np.concatenate([np.ravel(a)[np.isfinite(np.ravel(a))] for a in arrays])
    if vals.size:
        lo, hi = np.percentile(vals, [1, 99])
        span = max(hi - lo, 1e-12)
        ax.set_ylim(lo - pad * span, hi + pad * span)


def _sources(inputs):
    """Case, git revision and config of every input dataset, by kind, in input order."""
    return {
        kind: [
            {
                "case": ds.attrs.get("case", ""),
                "git_revision": ds.attrs.get("git_revision", ""),
                "config": json.loads(ds.attrs.get("config", "{}")),
            }
            for ds in datasets
        ]
        for kind, datasets in (inputs or {}).items()
    }


def save_figure(fig, pdf, png, inputs=None, title=""):
    """Save a figure as PDF and PNG atomically, with provenance in the metadata.

    A figure that its drawing function gave no super-title gets `title` as one (every figure
    carries its number and subject above its panels), its layout redone to make room."""
    if title and not fig.get_suptitle():
        fig.suptitle(title, fontsize=9)
        fig.tight_layout()
    prov = provenance()
    subject = json.dumps(
        {
            "inputs": _sources(inputs),
            "software_versions": json.loads(prov["software_versions"]),
            "git_revision": prov["git_revision"],
            "history": prov["history"],
        },
        sort_keys=True,
    )
    meta_pdf = {
        "Title": title,
        "Subject": subject,
        "Keywords": f"hmfdiff git {prov['git_revision']}",
        "Creator": "hmfdiff",
    }
    meta_png = {
        "Title": title,
        "Description": subject,
        "Software": f"hmfdiff git {prov['git_revision']}",
    }
    try:
        with atomic_path(pdf) as tmp:
            fig.savefig(tmp, format="pdf", metadata=meta_pdf)
        with atomic_path(png) as tmp:
            fig.savefig(tmp, format="png", metadata=meta_png)
    finally:
        plt.close(fig)
