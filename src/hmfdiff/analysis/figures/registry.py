"""The figure registry: the one list of figures that the workflow rules and the report read.

Contract (how to add a figure, e.g. figure 11):

1. Write the drawing function `fig11_relaxation(inputs, pdf, png)` in the module of its group
   (a new module for a new group).  `inputs` maps each input *kind* to a list of xarray
   datasets in the order the figure's config entry names them, e.g.
   `{"relaxation": [ds0, ds1, ...]}` (never keys sorted as strings).  It takes nothing else:
   every number it needs is in its datasets.  It draws with `style.plt`, titles panels with
   `style.tag_panels` ((a), (b), ... in reading order), writes numbers with `style.sci`
   (5\\times10^{3}, never 5e+03), gives every axis its unit (`style.HMF` for dimensional
   quantities) and saves with `style.save_figure(fig, pdf, png, inputs, title)` (atomic
   writes, provenance in the metadata).
2. Add one `Figure(...)` to `_FIGURE_LIST` below, for example::

       Figure(
           "fig11_relaxation",                 # file stem, config key, results/figures/{name}.*
           "fig11",                            # short target: snakemake -j2 fig11
           fig11_relaxation,
           (Inputs("relaxation", "relaxation/{case}_{equation}.nc",
                   defaults={"equation": ("landau", "lenard_balescu")}),),
           "Fig. 11: ... (eq. hmflb, ...).",   # caption shown in the report (labels of the
                                               # paper's source become its numbers: cite)
           "4. Relaxation (figures 11-13)",    # report section; the number orders the menu
       )

3. Give it an entry under `figures:` in the config (and the schema) naming its cases, e.g.
   `fig11_relaxation: {cases: [corehalo_ch2]}`.

`Inputs(kind, pattern, keys=("case", "cases"), defaults={})`: `pattern` is a path under the
results directory with a `{case}` field, filled with every case that the figure's config
entry names under `keys` (each a string or a list, concatenated in the order of `keys`).  Any
other field, such as `{equation}` above, is filled from the config entry's key of the same
name (a string or a list) or else from `defaults`; files are listed case by case, the other
fields varying fastest.  Kinds that go together (theory and fits of the same cases) list the
same keys, so their lists run in parallel.

Nothing else ties a figure to the workflow: the generic rule `figure` (workflow/rules/
figures.smk) builds its inputs from `Figure.input_files`, the short target from `target`,
the report entry from `caption` and `category`; the library files that rerun it come from the
imports of workflow/scripts/figure.py, which imports this module (hmfdiff.pipeline.deps).
"""

from __future__ import annotations

import itertools
import re
import string
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from ...paper_equations import cite
from .fluctuation_figures import fig14_spectrum, fig15_scaling
from .md_figures import fig08_dj2, fig09_md_thermal, fig10_md_corehalo
from .orbit_figures import fig01_orbits, fig02_action_frequency, fig03_poles
from .relaxation_figures import fig11_relaxation
from .relaxation_md_figures import (
    fig12_relaxation_md,
    fig13_relaxation_time,
    fig16_relaxation_rates,
)
from .theory_figures import (
    fig04_contributions,
    fig05_dielectric,
    fig06_landau_lenard_balescu,
    fig07_closed_forms,
)

__all__ = ["Figure", "Inputs", "FIGURES"]

CASES = ("case", "cases")  # the config keys that name the cases of most figures


def _as_list(value):
    return [value] if isinstance(value, str | int | float) else list(value)


@dataclass(frozen=True)
class Inputs:
    """The input files of one kind of a figure (see the module docstring)."""

    kind: str
    pattern: str
    keys: Sequence[str] = CASES
    defaults: Mapping[str, Sequence[str]] = field(default_factory=dict)

    def fields(self):
        """The fields of `pattern` other than `case`, in the order they appear."""
        names = [f for _, f, _, _ in string.Formatter().parse(self.pattern) if f]
        return [f for f in dict.fromkeys(names) if f != "case"]

    def cases(self, figure, spec):
        """The cases of this kind named by the figure's config entry `spec`, in order."""
        cases = [c for k in self.keys if k in spec for c in _as_list(spec[k])]
        if not cases:
            raise KeyError(
                f"figures.{figure}: no case for its {self.kind!r} inputs; give "
                + " or ".join(repr(k) for k in self.keys)
            )
        return cases

    def files(self, figure, spec):
        """Paths under the results directory, case by case, other fields fastest."""
        values = []
        for name in self.fields():
            if name in spec:
                values.append(_as_list(spec[name]))
            elif name in self.defaults:
                values.append(list(self.defaults[name]))
            else:
                raise KeyError(f"figures.{figure}: {self.kind!r} inputs need the key {name!r}")
        names = self.fields()
        return [
            self.pattern.format(case=case, **dict(zip(names, combo, strict=True)))
            for case in self.cases(figure, spec)
            for combo in itertools.product(*values)
        ]


@dataclass(frozen=True)
class Figure:
    """One figure: its file stem, short target, drawing function, inputs, caption, category."""

    name: str
    target: str
    draw: Callable[..., None]
    inputs: tuple[Inputs, ...]
    caption: str
    category: str

    def __post_init__(self):
        # the caption as the report shows it: the paper's equations by their published numbers
        object.__setattr__(self, "caption", cite(self.caption))
        kinds = [i.kind for i in self.inputs]
        if len(set(kinds)) != len(kinds) or "lib" in kinds:
            raise ValueError(f"{self.name}: input kinds {kinds} must be distinct and not 'lib'")
        if not re.fullmatch(r"fig[1-9]\d*", self.target):
            raise ValueError(f"{self.name}: target {self.target!r} is not figN")

    @property
    def number(self):
        """The figure's number, from its target: 'fig4' -> 4."""
        return int(self.target.removeprefix("fig"))

    @property
    def kinds(self):
        return [i.kind for i in self.inputs]

    def input_files(self, spec):
        """{kind: [path under the results directory, ...]} for the config entry `spec`."""
        return {i.kind: i.files(self.name, spec) for i in self.inputs}


def _theory(keys=CASES):
    return Inputs("theory", "theory/{case}.nc", keys)


_ORBITS = (Inputs("orbits", "orbits/{case}.nc"),)
_FIT_BATH = Inputs("fit_bath", "fits/{case}_bath.nc")
_FIT_FULL = Inputs("fit_full", "fits/{case}_full.nc")
_WINDOWED_BATH = Inputs("windowed_bath", "windowed/{case}_bath.nc")
_WINDOWED_FULL = Inputs("windowed_full", "windowed/{case}_full.nc")
_ORBIT_CAT = "1. Mean-field orbits (figures 1-3)"
_THEORY_CAT = "2. Kinetic theory (figures 4-7)"
_MD_CAT = "3. Molecular dynamics against theory (figures 8-10)"
_PRECISION_CAT = "5. MD precision: fluctuation spectrum and 1/N scaling (figures 14-15)"
_RELAX_CAT = "4. Relaxation (figures 11-13)"

_FIGURE_LIST = (
    Figure(
        "fig01_orbits",
        "fig1",
        fig01_orbits,
        _ORBITS,
        "Fig. 1: a librating orbit (kappa < 1), the separatrix (kappa = 1) and "
        "a rotating orbit (kappa > 1, both directions) of h = p^2/2 - M0 cos(theta), from the "
        "inverse angle-action map (appendix A).",
        _ORBIT_CAT,
    ),
    Figure(
        "fig02_action_frequency",
        "fig2",
        fig02_action_frequency,
        _ORBITS,
        "Fig. 2: (a) the action J(kappa) (eq. hmfaction), discontinuous at the "
        "separatrix; (b) the frequency Omega(J) (eq. hmfomega), inset Omega(kappa).",
        _ORBIT_CAT,
    ),
    Figure(
        "fig03_poles",
        "fig3",
        fig03_poles,
        _ORBITS,
        "Fig. 3: poles of the dielectric integrand, Omega(kappa) = omega/l: two "
        "poles kappa_1 < 1 < kappa_2 for 0 < omega/l < Omega_0, one above Omega_0.",
        _ORBIT_CAT,
    ),
    Figure(
        "fig04_contributions",
        "fig4",
        fig04_contributions,
        (_theory(),),
        "Fig. 4: normalised contribution gamma(kappa, kappa*)/D_dif(kappa) "
        "of each resonant orbit kappa* to the Lenard-Balescu diffusion coefficient "
        "(eq. hmfCEdif), one panel per thermal state (paper: M0 = 0.05 and 0.9).",
        _THEORY_CAT,
    ),
    Figure(
        "fig05_dielectric",
        "fig5",
        fig05_dielectric,
        (_theory(),),
        "Fig. 5: (a) cosine and (b) sine components of the dielectric tensor "
        "(eqs. hmfepscc, hmfepsss; Landau prescription), paper: thermal (u, M0) = "
        "(-0.1, 0.728); vertical lines at Omega_0 and 2 Omega_0.",
        _THEORY_CAT,
    ),
    Figure(
        "fig06_landau_lenard_balescu",
        "fig6",
        fig06_landau_lenard_balescu,
        (_theory(),),
        "Fig. 6: N D_dif(kappa) with (Lenard-Balescu, eqs. hmfCEdif + "
        "hmfD) and without (Landau, eq. hmfDbare) collective effects, paper: thermal (u, M0) = "
        "(-0.1, 0.7285) and (0.2475, 0.0632); cut near the separatrix.",
        _THEORY_CAT,
    ),
    Figure(
        "fig07_closed_forms",
        "fig7",
        fig07_closed_forms,
        (
            Inputs("theory_core_halo", "theory/{case}.nc", ("core_halo",)),
            Inputs("theory_thermal", "theory/{case}.nc", ("thermal",)),
            Inputs("closed_two_step", "analytic/{case}.nc", ("two_step",)),
            Inputs("closed_thermal", "analytic/{case}.nc", ("thermal",)),
        ),
        "Fig. 7: (a-c) eps_cc, eps_ss and N D_dif of the smooth core-halo states "
        "(paper: ch1*, ch2*) against the two-step closed form (eqs. hmfepscc/ss-ch, "
        "corrected); (d-f) the same for the thermal state M0 = 0.95 against appendix C "
        "(eqs. eps_cc_ap, eps_ss_ap, corrected).",
        _THEORY_CAT,
    ),
    Figure(
        "fig08_dj2",
        "fig8",
        fig08_dj2,
        (_FIT_FULL,),
        "Fig. 8: <dJ^2>(dt) from MD(full) for several J0, with the linear fits "
        "(eq. hmfmddif) over the shaded window; one panel per case.",
        _MD_CAT,
    ),
    Figure(
        "fig09_md_thermal",
        "fig9",
        fig09_md_thermal,
        (_theory(), _FIT_BATH, _FIT_FULL, _WINDOWED_BATH, _WINDOWED_FULL),
        "Fig. 9: N D from MD against theory for thermal states (paper: (u, M0) = "
        "(-0.2, 0.816), (0.0, 0.622), (0.2475, 0.063)): MD(bath) vs Landau (top row), "
        "MD(full) vs Lenard-Balescu (bottom row); errors from the spread between seeds; grey "
        "line: separatrix; black crosses: the theory propagated over the fit's lags (what the "
        "fit measures at this N; beside the separatrix the particles diffuse across the "
        "theory's structure during the fit).",
        _MD_CAT,
    ),
    Figure(
        "fig10_md_corehalo",
        "fig10",
        fig10_md_corehalo,
        (_theory(), _FIT_BATH, _FIT_FULL, _WINDOWED_BATH, _WINDOWED_FULL),
        "Fig. 10: the same for the core-halo state ch2* (beta1 = 30, beta2 = 10, "
        "eta1 = 0.298, eta2 = 0.051, mu1 = -0.517, mu2 = 0.19, M0 = 0.8).",
        _MD_CAT,
    ),
    Figure(
        "fig11_relaxation",
        "fig11",
        fig11_relaxation,
        (
            Inputs(
                "relaxation",
                "relaxation/{case}_{equation}.nc",
                defaults={"equation": ("landau", "lenard_balescu")},
            ),
        ),
        "Fig. 11: collisional relaxation by the kinetic equations at order 1/N (eq. hmflb in "
        "conservation form, the paper's Conclusions), with M0 solved self-consistently at every "
        "step: per case, f(J-bar) at several rescaled times tau = t/N under the Landau (bare) "
        "and Lenard-Balescu (dressed) equations against the thermal state of the same energy "
        "(dotted), and M0(tau) and the fine-grained entropy S(tau) = -int f ln f for both "
        "equations; the legend's tau_R^fine is the e-folding time of the fine-grained entropy "
        "deficit S_eq - S on the kinetic grid (figure 13's tau_R^coarse is that of the "
        "histogram entropy on the MD's J-bar bins, a different number).",
        _RELAX_CAT,
    ),
    Figure(
        "fig12_relaxation_md",
        "fig12",
        fig12_relaxation_md,
        (Inputs("relaxation_comparison", "relaxation_comparison/{case}.nc"),),
        "Fig. 12: collisional relaxation in N-body (full dynamics, eq. hmfmdfull; ensembles of "
        "independent realisations at several N) against the Lenard-Balescu and Landau "
        "evolutions (eq. hmflb) at matched rescaled time t/N: (a) mean |M| with its standard "
        "error, (b) coarse-grained entropy of the J-bar histogram (dotted: the thermal state of "
        "the same energy; dashed: the N-body ensemble of that thermal state at the same N, "
        "realisations, bins and times, where run: the measurement's floor), (c) L1 distance "
        "sum_b |P_b(MD) - P_b(LB)| between the binned f with "
        "its jackknife error and the distance expected from sampling noise alone (dotted), (d) "
        "f(J-bar) snapshots of the largest N at three times (markers; empty bins not drawn, "
        "J-bar range of the occupied bins) and Lenard-Balescu (lines).",
        _RELAX_CAT,
    ),
    Figure(
        "fig13_relaxation_time",
        "fig13",
        fig13_relaxation_time,
        (Inputs("relaxation_comparison", "relaxation_comparison/{case}.nc"),),
        "Fig. 13: relaxation time per particle t_R/N of the N-body ensembles (t_R in HMF time: "
        "the time at which the coarse-grained entropy deficit S_eq - S of the J-bar histogram "
        "has fallen by e), with its jackknife error over groups of realisations, against N "
        "(open squares, where a thermal control was run: the deficit measured against the "
        "control's entropy instead of the theory's S_eq), with the fitted power law t_R = A "
        "N^alpha and its exponent, and the kinetic predictions tau_R^coarse of the "
        "Lenard-Balescu and Landau equations, independent of N at their order 1/N (same "
        "definition on the same bins, on the grid with the layer next to the separatrix "
        "resolved; not the fine-grained tau_R^fine of figure 11).",
        _RELAX_CAT,
    ),
    Figure(
        "fig16_relaxation_rates",
        "fig16",
        fig16_relaxation_rates,
        (
            Inputs("relaxation_rates", "relaxation_rates/{case}.nc"),
            Inputs("relaxation_comparison", "relaxation_comparison/{case}.nc"),
        ),
        "Fig. 16: the N-body relaxation rate against N (config relaxation_rates): (a) change "
        "of the coarse-grained J-bar entropy over the early window t/N <= tau_* at each N "
        "(points, band: standard error over realisations; dotted: ensembles of the thermal "
        "state of the same energy, the measurement's floor) with the Landau and Lenard-Balescu "
        "evolutions binned the same way; (b) that change over tau_* against N; (c) the "
        "particles carried out through the core edge (the J-bar edge the Landau evolution "
        "drains most) per unit t/N over the window; (d) the rate N/t_R of the full relaxation "
        "(figure 13) with 1/tau_R^coarse of both equations.  Lines: kinetic predictions; grey "
        "squares: the thermal control.",
        _RELAX_CAT,
    ),
    Figure(
        "fig14_spectrum",
        "fig14",
        fig14_spectrum,
        (Inputs("spectrum", "spectrum/{case}.nc"),),
        "Fig. 14: power spectrum of the magnetisation fluctuations, N S_x (along M) and N S_y "
        "(across M), measured in MD(bath) and MD(full) (Welch estimate over segments of one "
        "fit window, averaged over seeds; points with standard errors), one panel per "
        "component and dynamics, against the kinetic theory (black lines): the bare bath "
        "spectrum (a sum over orbits of c_n'^2, sigma_n'^2 times f and the density of states "
        "at omega = n' Omega) for MD(bath) and the dressed one (divided by |eps_cc|^2, "
        "|eps_ss|^2) for MD(full); open diamonds: the theory convolved with the Welch window "
        "(the expectation of the estimate, at the Welch frequencies).  The screening of the "
        "libration band and the dielectric tensor's modes show up as dips and peaks of the "
        "MD(full) spectrum.  As omega -> 0 both theories vanish (exponentially: the orbits "
        "with Omega -> 0 lie at the separatrix); in MD(full) S_y the lowest Welch frequencies "
        "(shaded, omega < 2 x 2 pi / segment) lie above the theory: the direction of M wanders "
        "without restoring force (eps_ss(0) = 0, the free rotation of the magnetisation, with "
        "the total momentum held at zero), a motion the linear bath spectrum does not contain "
        "and which the frame of the segment-averaged direction removes only below the "
        "resolution; the agreement statistics leave these frequencies out.",
        _PRECISION_CAT,
    ),
    Figure(
        "fig15_scaling",
        "fig15",
        fig15_scaling,
        (
            Inputs("scaling_bath", "scaling/{case}_bath.nc"),
            Inputs("scaling_full", "scaling/{case}_full.nc"),
        ),
        "Fig. 15: N D_MD against the number of particles N (config md_scaling), one row per "
        "study, MD(bath) left and MD(full) right, in a few J-bar_0 bins (points; errors: "
        "standard error from the spread between the seeds at each N, 8 or more in the paper "
        "config; points of neighbouring bins set slightly apart in N).  Lines, in each bin's "
        "colour: the kinetic theory averaged over the bin with the density of the tracked "
        "particles, as ND_theory of validation.csv; solid the theory of the panel's dynamics "
        "(Landau, bare, for MD(bath); Lenard-Balescu, dressed, for MD(full)), dashed the other "
        "one.  N D is independent of N, on the solid line, where the kinetic theory's 1/N "
        "ordering holds.  Paper config: a thermal state (u = 0: flat from N = 1e3 on the theory "
        "of each dynamics) and the hot halo, whose deep core (kappa0 = 0.25) follows the "
        "dressed theory at every N while at the core's edge (kappa0 = 0.43, the edge at J-bar "
        "= 0.136) MD(full) lies 2-3 times above it up to N = 6.4e4, the finite-N effect, and "
        "MD(bath) below the bare theory where the rms excursion of J over the fit window is "
        "comparable to the core's size (N <= 1.6e4).",
        _PRECISION_CAT,
    ),
)

FIGURES: dict[str, Figure] = {f.name: f for f in _FIGURE_LIST}
if len(FIGURES) != len(_FIGURE_LIST) or len({f.target for f in _FIGURE_LIST}) != len(FIGURES):
    raise ValueError("figure names and targets must be unique")
