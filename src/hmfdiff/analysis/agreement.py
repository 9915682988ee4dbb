"""How well MD agrees with theory, as statistics allow: the summary of results/validation.csv.

Bins used: flag 0 of `fits.VALIDATION_FLAGS`, i.e. at least `md.min_particles` particles in the
bin, |kappa0 - 1| at least `md.separatrix_band_fit`, and a finite MD value, theory and error.
For each case and dynamics, and pooled over all of them:

* the median of |ratio - 1|, beside the median expected if the MD values scatter about the
  theory as their errors say (the median of the mixture over the bins of |t_nu| sigma_i, with
  sigma_i = ND_md_err / theory the bin's relative error: the floor that the realisations'
  statistics set), and the mean ratio with its standard error (spread of the ratios over the
  bins / sqrt(bins));
* the fraction of bins with |z| < 2 and the mean z^2, each beside the value expected if the MD
  values scatter about the theory as their errors say: z = (ND_md - ND_theory) / ND_md_err with
  the error the standard error over n_seeds independent realisations is Student-t distributed
  with nu = n_seeds - 1 degrees of freedom, so P(|z| < 2) = F_nu(2) - F_nu(-2) and
  E[z^2] = nu / (nu - 2) (nu > 2);
* every bin with |z| > 3, by name, and their number against the number Student t expects;
* the same statistics pooled over the bins beside the separatrix band (a usable bin whose
  neighbour in bin order, in its own case and dynamics, is flagged for the separatrix: two per
  line) and over all the others.  Beside the band the particles diffuse, during the fit's lags,
  across structure of the theory's D narrower than that distance, which the asymptotic theory
  does not see and the propagated one does (`analysis.propagated`, docs/validation.md), so these
  bins are counted apart rather than hidden.

The same for the finite-time (windowed) theory, with `ratio_windowed` and `z_windowed`, and for
the propagated theory, with `ratio_propagated` and `z_propagated` (where the table has them).
`python -m hmfdiff.analysis.agreement results/validation.csv` prints the summary; with
`--markdown` the two tables, with `--readme` the block docs/validation.md includes (the tables
and the |z| > 3 bins by name), with `--update PAGE` that block written between the page's
markers (`python -m hmfdiff.analysis.agreement docs/reference/validation.csv --update
docs/validation.md`).  The block comes from the reference copy of a full reproduction's table,
docs/reference/validation.csv; `tests/test_readme_numbers.py` checks the two agree.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np
from scipy import optimize, stats

__all__ = [
    "SELECTION",
    "agreement",
    "summary_text",
    "markdown_table",
    "readme_block",
    "readme_with_block",
    "read_rows",
]

SELECTION = (
    "bins with flag 0: at least md.min_particles particles, |kappa0 - 1| >= "
    "md.separatrix_band_fit, finite MD value, theory and error"
)
#: the two comparisons: (label, ratio column, z column, theory column, theory name per dynamics)
COMPARISONS = {
    "asymptotic": ("ratio", "z", "ND_theory", {"bath": "Landau", "full": "Lenard-Balescu"}),
    "windowed": (
        "ratio_windowed",
        "z_windowed",
        "ND_windowed",
        {"bath": "windowed bare (Landau)", "full": "windowed dressed (Lenard-Balescu)"},
    ),
    "propagated": (
        "ratio_propagated",
        "z_propagated",
        "ND_propagated",
        {"bath": "propagated Landau", "full": "propagated Lenard-Balescu"},
    ),
}
#: the summary's title of each comparison
TITLES = {
    "asymptotic": "MD against the asymptotic theory (ND_theory, bin-averaged):",
    "windowed": "MD against the windowed theory (the finite-time <dJ^2> fitted over the MD's "
    "own lags and window):",
    "propagated": "MD against the propagated theory (the theory's D carried over the MD fit's "
    "lags by its Fokker-Planck equation: the particles' own diffusion across structure in D "
    "during the fit, which matters beside the separatrix):",
}
OUTLIER_Z = 3.0
#: fewer seeds than this in a line's bins: no statistics are printed for it (with n_seeds <= 3
#: Student t has nu <= 2 degrees of freedom and no finite variance: E[z^2] is infinite)
MIN_SEEDS = 4
#: below this N (every MD run of the smoke config) N*D_MD scatters by tens of per cent per bin
#: and the summary prints no statistics at all, only what shows that the pipeline ran
TOY_SIZE = 1e5
#: flag of `fits.VALIDATION_FLAGS` for a bin within the separatrix band
SEPARATRIX_FLAG = 2
#: the pooled groups of `agreement` and how the summary names them
POOLED_LABELS = {
    "all": "all lines",
    "beside separatrix": "beside the separatrix band",
    "elsewhere": "elsewhere",
}


def _expected(dof):
    """P(|t| < 2) and E[t^2] for Student's t with `dof` degrees of freedom (arrays)."""
    dof = np.asarray(dof, dtype=float)
    p2 = stats.t.cdf(2.0, dof) - stats.t.cdf(-2.0, dof)
    with np.errstate(divide="ignore", invalid="ignore"):
        z2 = np.where(dof > 2, dof / (dof - 2.0), np.inf)
    return p2, z2


def _expected_median(rel_err, dof):
    """The median m of |ratio - 1| over bins i whose ratio - 1 = sigma_i t_i, t_i Student t
    with dof_i degrees of freedom: the root of mean_i P(|t_i| < m / sigma_i) = 1/2 (the median
    of the mixture, which the sample median of many bins approaches)."""
    sig = np.asarray(rel_err, dtype=float)
    dof = np.asarray(dof, dtype=float)

    def below(m):
        return float(np.mean(2.0 * stats.t.cdf(m / sig, dof) - 1.0)) - 0.5

    # at hi every P(|t_i| < hi / sigma_i) >= P(|t_1| < 10) = 0.94 > 1/2: the root is below
    hi = 10.0 * float(np.max(sig))
    return float(optimize.brentq(below, 0.0, hi, xtol=1e-12))


def _p_outlier(dof):
    """P(|t| > OUTLIER_Z) for Student's t with `dof` degrees of freedom (arrays)."""
    return 2.0 * stats.t.sf(OUTLIER_Z, np.asarray(dof, dtype=float))


def beside_separatrix(rows):
    """Flags, one per row: the row is a bin beside the separatrix band, i.e. its neighbour in
    row order (rows are in bin order within each case and dynamics, as `fits.validation_rows`
    writes them) belongs to the same case and dynamics and carries the separatrix flag."""
    out = []
    for i, r in enumerate(rows):
        line = (r["case"], r["dynamics"])
        near = [
            rows[j]
            for j in (i - 1, i + 1)
            if 0 <= j < len(rows) and (rows[j]["case"], rows[j]["dynamics"]) == line
        ]
        out.append(any(int(n["flag"]) == SEPARATRIX_FLAG for n in near))
    return out


def _usable(rows, ratio, z):
    return [
        r
        for r in rows
        if int(r["flag"]) == 0
        and np.isfinite(r.get(ratio, np.nan))
        and np.isfinite(r.get(z, np.nan))
    ]


def agreement(rows, comparison="asymptotic"):
    """Statistics per (case, dynamics) and pooled ('all', 'all'), as a list of dicts with keys
    case, dynamics, theory, bins, median_dev, median_dev_expected, mean_ratio, mean_ratio_err,
    frac_z2, frac_z2_expected, mean_z2, mean_z2_expected, outliers (list of rows with |z| > 3),
    outliers_expected (their number under Student t) and seeds (the fewest and the most
    n_seeds of its bins); then, pooled, the bins beside the
    separatrix band ('beside separatrix', `beside_separatrix`) and all others ('elsewhere')."""
    ratio, z, theory_col, theory = COMPARISONS[comparison]
    keys = list(dict.fromkeys((r["case"], r["dynamics"]) for r in rows))
    groups = [(c, d, [r for r in rows if (r["case"], r["dynamics"]) == (c, d)]) for c, d in keys]
    groups.append(("all", "all", list(rows)))
    beside = beside_separatrix(rows)
    groups.append(("beside separatrix", "all", [r for r, b in zip(rows, beside, strict=True) if b]))
    groups.append(("elsewhere", "all", [r for r, b in zip(rows, beside, strict=True) if not b]))
    out = []
    for case, dyn, sel in groups:
        sel = _usable(sel, ratio, z)
        entry = {"case": case, "dynamics": dyn, "theory": theory.get(dyn, "theory"), "bins": 0}
        out.append(entry)
        if not sel:
            continue
        q = np.array([r[ratio] for r in sel], dtype=float)
        zs = np.array([r[z] for r in sel], dtype=float)
        dof = [max(int(r.get("n_seeds", 2)) - 1, 1) for r in sel]
        p2, z2 = _expected(dof)
        rel_err = [abs(r["ND_md_err"] / r[theory_col]) for r in sel]
        entry.update(
            bins=len(sel),
            median_dev=float(np.median(np.abs(q - 1.0))),
            median_dev_expected=_expected_median(rel_err, dof),
            mean_ratio=float(np.mean(q)),
            mean_ratio_err=float(np.std(q, ddof=1) / np.sqrt(q.size)) if q.size > 1 else np.nan,
            frac_z2=float(np.mean(np.abs(zs) < 2.0)),
            frac_z2_expected=float(np.mean(p2)),
            mean_z2=float(np.mean(zs**2)),
            mean_z2_expected=float(np.mean(z2)),
            outliers=[r for r in sel if abs(r[z]) > OUTLIER_Z],
            outliers_expected=float(np.sum(_p_outlier(dof))),
            seeds=(min(dof) + 1, max(dof) + 1),
        )
    return out


def _outlier_name(r, ratio, z):
    return (
        f"{r['case']} {r['dynamics']} kappa0 = {float(r['kappa0']):.3f} "
        f"(ratio {float(r[ratio]):.3f}, z = {float(r[z]):+.1f})"
    )


def _selection_values(rows):
    """The selection's values where the rows carry them (rows from the fits, not from CSV)."""
    vals = {(r["min_particles"], r["separatrix_band"]) for r in rows if "min_particles" in r}
    if not vals:
        return ""
    said = "; ".join(f"min_particles = {m}, separatrix_band_fit = {b:g}" for m, b in sorted(vals))
    return f" (here {said})"


def _toy_header(sizes):
    """The first line of a toy-size summary: which runs are below TOY_SIZE, and that the
    summary holds no statistics ('' if none is)."""
    toy = {c: n for c, n in (sizes or {}).items() if n < TOY_SIZE}
    if not toy:
        return ""
    said = ", ".join(f"{c} N = {n}" for c, n in sorted(toy.items()))
    return (
        f"TOY SIZE, NO STATISTICS ({said}: below N = {TOY_SIZE:.0e}, where N*D_MD scatters by "
        "tens of per cent per bin): the numbers below show that the pipeline ran end to end "
        "and validate nothing about the theory; the paper-size comparison is `snakemake -j2` "
        "with config/config.yaml."
    )


def _seeds_said(e):
    lo, hi = e["seeds"]
    return f"{lo} seeds" if lo == hi else f"{lo}-{hi} seeds"


def _summary_line(label, e, toy):
    """One line of the summary: the statistics with their expectations, or, at toy size or
    with fewer than MIN_SEEDS seeds, what was run and that there are no statistics."""
    if not e["bins"]:
        return f"{label}: no usable bins"
    if toy:
        return (
            f"{label}: {e['bins']} bins, {_seeds_said(e)}, median |ratio - 1| "
            f"{e['median_dev']:.3f}; no statistics at toy size"
        )
    if e["seeds"][0] < MIN_SEEDS:
        return (
            f"{label}: {e['bins']} bins, {_seeds_said(e)}: no statistics (below {MIN_SEEDS} "
            "seeds Student t's expected z^2 is infinite)"
        )
    return (
        f"{label}: {e['bins']}  {e['median_dev']:.3f} ({e['median_dev_expected']:.3f})  "
        f"{e['mean_ratio']:.3f} +- {e['mean_ratio_err']:.3f}  "
        f"{e['frac_z2']:.2f} ({e['frac_z2_expected']:.2f})  "
        f"{e['mean_z2']:.2f} ({e['mean_z2_expected']:.2f})"
    )


def summary_text(rows, sizes=None):
    """The text of results/validation_summary.txt (asymptotic and windowed blocks).

    `sizes`: {case: N of its MD runs}, where known (the workflow's rule passes them; a
    validation.csv does not hold them).  Where some N is below TOY_SIZE the summary says in
    its first line that it holds no statistics, and gives per line only the bins, the seeds
    and the median |ratio - 1|; elsewhere a line whose bins have fewer than MIN_SEEDS seeds
    says the same instead of numbers."""
    header = _toy_header(sizes)
    toy = bool(header)
    lines = [header] if toy else []
    lines.append(f"Bins used: {SELECTION}{_selection_values(rows)}.")
    if not toy:
        lines.append(
            "Expected values: Student t with n_seeds - 1 degrees of freedom (the MD error is "
            "the standard error over independent realisations)."
        )
    for comparison, (ratio, z, _, _) in _present(rows):
        lines.append("")
        lines.append(TITLES[comparison])
        if not toy:
            lines.append(
                "case dynamics vs theory: bins  median|ratio-1| (expected)  mean ratio  "
                "fraction|z|<2 (expected)  mean z^2 (expected)"
            )
        stats_ = agreement(rows, comparison)
        for e in stats_:
            label = (
                f"pooled, {POOLED_LABELS[e['case']]}"
                if _pooled(e)
                else f"{e['case']} {e['dynamics']} vs {e['theory']}"
            )
            lines.append(_summary_line(label, e, toy))
        if not toy:
            lines += _outlier_lines(stats_, ratio, z, indent="  ")
    return "\n".join(lines)


def _present(rows):
    """The comparisons whose ratio column holds a number in some row (older tables lack the
    later columns, or hold them empty once read back through a newer header)."""
    return [
        (c, v)
        for c, v in COMPARISONS.items()
        if c == "asymptotic" or any(np.isfinite(float(r.get(v[0], np.nan))) for r in rows)
    ]


def _pooled(entry):
    return entry["dynamics"] == "all"


def _outlier_lines(stats_, ratio, z, indent):
    """The bins with |z| > OUTLIER_Z by name (those beside the separatrix band marked), and
    their count against Student t's expectation, pooled, beside the band and elsewhere."""
    pooled = {e["case"]: e for e in stats_ if _pooled(e)}
    beside = {id(r) for r in pooled["beside separatrix"].get("outliers", [])}
    outliers = [r for e in stats_ if not _pooled(e) and e["bins"] for r in e["outliers"]]
    if not outliers:
        return [f"No bin with |z| > {OUTLIER_Z:g}."]
    counts = "; ".join(
        f"{POOLED_LABELS[k]} {len(pooled[k].get('outliers', []))} "
        f"({pooled[k].get('outliers_expected', 0.0):.2f})"
        for k in POOLED_LABELS
    )
    out = [f"Bins with |z| > {OUTLIER_Z:g}, observed (expected under Student t): {counts}:"]
    for r in outliers:
        mark = " [beside the separatrix band]" if id(r) in beside else ""
        out.append(indent + _outlier_name(r, ratio, z) + mark)
    return out


def markdown_table(rows, comparison="asymptotic"):
    """The page's table: one line per case and dynamics, then the pooled line."""
    head = (
        "| case | dynamics | bins | median \\|ratio - 1\\| (expected) | mean ratio | "
        "\\|z\\| < 2 (expected) | mean z^2 (expected) |\n|---|---|---|---|---|---|---|"
    )
    body = []
    for e in agreement(rows, comparison):
        if not e["bins"]:
            continue
        case, dyn = (
            (f"*{POOLED_LABELS[e['case']]}*", "all")
            if _pooled(e)
            else (
                e["case"],
                e["dynamics"],
            )
        )
        body.append(
            f"| {case} | {dyn} | {e['bins']} | {100 * e['median_dev']:.1f} % "
            f"({100 * e['median_dev_expected']:.1f} %) | "
            f"{e['mean_ratio']:.3f} +- {e['mean_ratio_err']:.3f} | "
            f"{100 * e['frac_z2']:.0f} % ({100 * e['frac_z2_expected']:.0f} %) | "
            f"{e['mean_z2']:.2f} ({e['mean_z2_expected']:.2f}) |"
        )
    return "\n".join([head, *body])


def readme_block(rows):
    """The page's block: per comparison its table and its bins with |z| > 3 by name."""
    out = []
    what_of = {"windowed": "windowed (finite-time)", "propagated": "propagated (finite-N)"}
    for comparison, (ratio, z, _, _) in _present(rows):
        what = what_of.get(comparison, comparison)
        out += [f"MD against the {what} theory:", "", markdown_table(rows, comparison), ""]
        head, *bad = _outlier_lines(agreement(rows, comparison), ratio, z, indent="- ")
        out += [head, "", *bad] if bad else [head]
        out.append("")
    return "\n".join(out).rstrip() + "\n"


#: the lines around the block in docs/validation.md (the names keep their first page's)
README_MARKERS = ("<!-- agreement:start -->", "<!-- agreement:end -->")


def readme_with_block(text, block):
    """`text` (a page: docs/validation.md) with what lies between `README_MARKERS` replaced by
    `block`.
    ValueError unless each marker occurs exactly once, start before end."""
    start, end = README_MARKERS
    if text.count(start) != 1 or text.count(end) != 1 or text.index(start) > text.index(end):
        raise ValueError(f"page: needs one {start} line before one {end} line")
    head, rest = text.split(start)
    _, tail = rest.split(end)
    return f"{head}{start}\n{block}{end}{tail}"


def read_rows(path):
    """The rows of a validation.csv, numbers as floats, flag and n_seeds as integers."""
    rows = []
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            row = {}
            for k, v in r.items():
                if k in ("case", "dynamics"):
                    row[k] = v
                elif k in ("flag", "n_particles_in_bin", "n_seeds"):
                    row[k] = int(float(v))
                else:
                    row[k] = float(v) if v not in ("", None) else np.nan
            rows.append(row)
    return rows


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    markdown = "--markdown" in argv
    update = None
    if "--update" in argv:
        i = argv.index("--update")
        if i + 1 >= len(argv):
            sys.exit("agreement: --update needs the page's path (docs/validation.md)")
        update = argv.pop(i + 1)
        argv.pop(i)
    paths = [a for a in argv if not a.startswith("--")]
    if len(paths) != 1:
        sys.exit(
            "usage: python -m hmfdiff.analysis.agreement VALIDATION_CSV "
            "[--markdown | --readme | --update docs/validation.md]"
        )
    rows = read_rows(paths[0])
    if update is not None:
        readme = Path(update)
        try:
            new = readme_with_block(readme.read_text(), readme_block(rows))
        except (OSError, ValueError) as err:
            sys.exit(f"agreement: {err}")
        readme.write_text(new)
        print(f"agreement: {readme}: block between the markers rewritten from {paths[0]}")
    elif "--readme" in argv:
        print(readme_block(rows), end="")
    elif markdown:
        print("MD against the asymptotic theory:\n")
        print(markdown_table(rows, "asymptotic"))
        print("\nMD against the windowed theory:\n")
        print(markdown_table(rows, "windowed"))
    else:
        print(summary_text(rows))


if __name__ == "__main__":
    main()
