"""The figure registry (inputs per kind, in config order) and the look of every figure: panel
labels (a), (b), ... in reading order, numbers as mathtext powers of ten, labelled axes."""

import re
import subprocess
import sys

import matplotlib.figure
import numpy as np
import pytest
import yaml
from _smoke import SMOKE, smoke_workdir
from matplotlib import mathtext

from hmfdiff.analysis.figures import style
from hmfdiff.analysis.figures.registry import FIGURES, Inputs
from hmfdiff.pipeline.io import read_dataset


def test_inputs_keep_the_config_order_beyond_nine_cases():
    cases = [f"c{i}" for i in range(12)]
    files = Inputs("theory", "theory/{case}.nc").files("figX", {"cases": cases})
    assert files == [f"theory/c{i}.nc" for i in range(12)]
    fig = FIGURES["fig09_md_thermal"]
    got = fig.input_files({"cases": cases})
    assert got["theory"] == [f"theory/{c}.nc" for c in cases]
    assert got["fit_bath"] == [f"fits/{c}_bath.nc" for c in cases]


def test_inputs_fill_other_fields_from_the_entry_or_the_defaults():
    inputs = Inputs(
        "relaxation", "relaxation/{case}_{equation}.nc", defaults={"equation": ("a", "b")}
    )
    assert inputs.files("f", {"cases": ["x", "y"]}) == [
        "relaxation/x_a.nc",
        "relaxation/x_b.nc",
        "relaxation/y_a.nc",
        "relaxation/y_b.nc",
    ]
    assert inputs.files("f", {"case": "x", "equation": "b"}) == ["relaxation/x_b.nc"]
    with pytest.raises(KeyError, match="figures.f: no case"):
        inputs.files("f", {"equation": "a"})
    with pytest.raises(KeyError, match="'other'"):
        Inputs("k", "{case}_{other}.nc").files("f", {"case": "x"})


def test_fig07_reads_each_role_from_its_key():
    spec = {"core_halo": ["ch1", "ch2"], "two_step": "step", "thermal": "mb"}
    assert FIGURES["fig07_closed_forms"].input_files(spec) == {
        "theory_core_halo": ["theory/ch1.nc", "theory/ch2.nc"],
        "theory_thermal": ["theory/mb.nc"],
        "closed_two_step": ["analytic/step.nc"],
        "closed_thermal": ["analytic/mb.nc"],
    }


@pytest.mark.parametrize(
    "x, text",
    [
        (5000, r"5\times10^{3}"),
        (5e5, r"5\times10^{5}"),
        (1e6, "10^{6}"),
        (1.25e6, r"1.25\times10^{6}"),
        (-2.5e-4, r"-2.5\times10^{-4}"),
        (0.728, "0.728"),
        (0.0632, "0.0632"),
        (-0.1, "-0.1"),
        (0, "0"),
        (999, "999"),
    ],
)
def test_sci_writes_powers_of_ten_in_mathtext(x, text):
    assert style.sci(x) == text
    mathtext.MathTextParser("path").parse(f"${style.sci(x)}$")  # valid mathtext


def test_panel_tags_run_past_z():
    assert [style.panel_tag(i) for i in (0, 1, 25, 26, 27)] == ["(a)", "(b)", "(z)", "(aa)", "(ab)"]


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    """Every registry figure drawn from the smoke run's outputs, the matplotlib Figure kept
    (caught as it is saved, whichever module draws it)."""
    workdir = smoke_workdir(tmp_path_factory)
    specs = yaml.safe_load((workdir / SMOKE).read_text())["figures"]
    results = {p.parent.parent for p in workdir.glob("results/**/figures/fig01_orbits.png")}
    assert len(results) == 1
    results = results.pop()
    out = tmp_path_factory.mktemp("figures")
    saved = []
    savefig = matplotlib.figure.Figure.savefig

    def keep(self, *args, **kwargs):
        if self not in saved:
            saved.append(self)
        return savefig(self, *args, **kwargs)

    figures = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(matplotlib.figure.Figure, "savefig", keep)
        for name, fig in FIGURES.items():
            inputs = {
                kind: [read_dataset(results / p) for p in paths]
                for kind, paths in fig.input_files(specs[name]).items()
            }
            fig.draw(inputs, out / f"{name}.pdf", out / f"{name}.png")
            (figures[name],) = saved
            saved.clear()
    return figures


def main_axes(figure):
    return [ax for ax in figure.axes if ax.get_label() != "<colorbar>"]


def texts(figure):
    out = [figure._suptitle.get_text()] if figure._suptitle else []
    for ax in figure.axes:
        out += [ax.get_title(), ax.get_xlabel(), ax.get_ylabel()]
        if ax.get_legend():
            out += [t.get_text() for t in ax.get_legend().get_texts()]
    return out


@pytest.mark.parametrize("name", list(FIGURES))
def test_panels_are_labelled_in_reading_order(drawn, name):
    axes = main_axes(drawn[name])
    if len(axes) == 1:
        return
    # reading order from the positions on the page: rows top to bottom, then left to right
    boxes = [ax.get_position() for ax in axes]
    rows = np.round([1 - b.y1 for b in boxes], 2)
    order = sorted(range(len(axes)), key=lambda i: (rows[i], boxes[i].x0))
    tags = [re.match(r"\(([a-z]+)\)", axes[i].get_title()) for i in order]
    assert all(tags), [axes[i].get_title() for i in order]
    assert [t.group(1) for t in tags] == list("abcdefghijklmnopqrstuvwxyz"[: len(axes)])


@pytest.mark.parametrize("name", list(FIGURES))
def test_axes_are_labelled_and_numbers_are_not_e_notation(drawn, name):
    figure = drawn[name]
    for ax in main_axes(figure):
        assert ax.get_ylabel(), (name, ax.get_title())
        # an x axis shared by a column of panels is labelled once, under the bottom panel
        shared = ax.get_shared_x_axes().get_siblings(ax)
        assert any(a.get_xlabel() for a in shared), (name, ax.get_title())
    for text in texts(figure):
        assert not re.search(r"\de[+-]\d", text), (name, text)


def test_fig14_theory_is_drawn_over_the_points_in_another_colour(drawn):
    """Issue 22: the theory curves of figure 14 were drawn under the MD points in their colour."""
    from matplotlib.colors import to_rgba

    for ax in main_axes(drawn["fig14_spectrum"]):
        lines = [
            ln for ln in ax.get_lines() if ln.get_linestyle() == "-" and len(ln.get_xdata()) > 50
        ]
        markers = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
        assert lines and markers, ax.get_title()
        for ln in lines:
            for m in markers:
                assert to_rgba(ln.get_color()) != to_rgba(m.get_color()), ax.get_title()
                assert ln.get_zorder() > m.get_zorder(), ax.get_title()
        assert ax.get_legend() is None, "legend on the data"  # one legend, under the panels


# ---- figure 15: N D against N with the bin-averaged theory (issue 21) ---------------------
#: the kinetic equation each dynamics measures, written out here (not read from the library)
OWN = {"bath": "landau", "full": "lenard_balescu"}
OTHER = {"bath": "lenard_balescu", "full": "landau"}


@pytest.fixture(scope="module")
def scaling(tmp_path_factory):
    """{(case, dynamics): (scaling dataset, [fit per N], theory, f)} of figure 15's smoke cases,
    and the smoke results folder."""
    from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset

    workdir = smoke_workdir(tmp_path_factory)
    results = workdir / "results" / "smoke"
    spec = yaml.safe_load((workdir / SMOKE).read_text())["figures"]["fig15_scaling"]
    out = {}
    for case in spec["cases"]:
        theory = read_dataset(results / f"theory/{case}.nc")
        f = state_from_dataset(read_dataset(results / f"equilibrium/{case}.nc")).f
        for dyn in ("bath", "full"):
            ds = read_dataset(results / f"scaling/{case}_{dyn}.nc")
            fits = [
                read_dataset(results / f"scaling/{case}/{dyn}/N{n}/fit.nc") for n in ds["N"].values
            ]
            out[(case, dyn)] = (ds, fits, theory, f)
    return out, results


def test_fig15_theory_is_the_bin_average_of_each_dynamics_at_each_N(scaling):
    """ND_theory of the scaling file is the theory of its dynamics (Landau for MD(bath),
    Lenard-Balescu for MD(full)), ND_theory_other the other one, each averaged over the bin
    with the tracked density of that N's runs: recomputed from the fit of each N, and for
    MD(bath) (uniform test particles at every N) equal to validation.csv's ND_theory of the
    same case and bins.  A bin-centre value or the wrong equation fails it."""
    import csv

    from hmfdiff.analysis.fits import theory_at_bins, theory_bin_average

    sets, results = scaling
    with open(results / "validation.csv") as fh:
        rows = list(csv.DictReader(fh))
    differs_from_centre, cross_checked = [], []
    for (case, dyn), (ds, fits, theory, f) in sets.items():
        assert ds["ND_theory"].attrs["equation"] == OWN[dyn]
        assert ds["ND_theory_other"].attrs["equation"] == OTHER[dyn]
        assert [int(x.attrs["N"]) for x in fits] == ds["N"].values.tolist()
        for i, fit in enumerate(fits):
            for var, eq in (("ND_theory", OWN[dyn]), ("ND_theory_other", OTHER[dyn])):
                expected = theory_bin_average(theory, fit, f, equation=eq)
                np.testing.assert_allclose(ds[var].values[i], expected, rtol=1e-12, err_msg=var)
            centre = theory_at_bins(theory, ds["kappa0"].values, dyn, OWN[dyn])
            ok = np.isfinite(centre) & np.isfinite(ds["ND_theory"].values[i])
            differs_from_centre.append(
                np.max(np.abs(ds["ND_theory"].values[i][ok] / centre[ok] - 1)) > 1e-3
            )
        val = [r for r in rows if r["case"] == case and r["dynamics"] == "bath"]
        if dyn == "bath" and len(val) == ds.sizes["bin"]:  # an MD case with the same bins
            got = np.array([float(r["ND_theory"]) for r in val])
            for i in range(ds.sizes["N"]):
                np.testing.assert_allclose(ds["ND_theory"].values[i], got, rtol=1e-5)
            cross_checked.append(case)
    assert any(differs_from_centre), "the theory is not averaged over the bins"
    assert cross_checked, "no study to compare with validation.csv"


def test_fig15_draws_both_theories_in_every_drawn_bin_and_its_legend_off_the_data(drawn, scaling):
    """Each panel (rows: studies; columns: MD(bath), MD(full)) has, per drawn bin, the MD
    points, a solid line through ND_theory (the theory of the panel's dynamics) and a dashed
    one through ND_theory_other, both over N; the bins named by kappa0 are those drawn; axes
    carry units; the legends lie outside every panel."""
    figure = drawn["fig15_scaling"]
    sets, results = scaling
    spec = yaml.safe_load((results.parents[1] / SMOKE).read_text())
    axes = main_axes(figure)
    keys = [(case, dyn) for case in spec["figures"]["fig15_scaling"]["cases"] for dyn in OWN]
    assert len(axes) == len(keys)
    for ax, key in zip(axes, keys, strict=True):
        ds = sets[key][0]
        bins = np.flatnonzero(ds["drawn"].values)
        assert bins.size >= 1, key
        kappa0 = spec["md_scaling"]["studies"][key[0]].get("kappa0")
        if kappa0:
            k = ds["kappa0"].values
            assert sorted(bins) == sorted({int(np.argmin(np.abs(k - t))) for t in kappa0})
        assert len(ax.containers) == bins.size, key  # one errorbar (MD points) per bin
        N = ds["N"].values
        for ls, var in (("-", "ND_theory"), ("--", "ND_theory_other")):
            lines = [
                ln for ln in ax.get_lines() if ln.get_linestyle() == ls and len(ln.get_xdata())
            ]
            for b in bins:
                y = ds[var].values[:, b]
                assert any(
                    np.array_equal(ln.get_xdata(), N)
                    and np.allclose(ln.get_ydata(), y, rtol=1e-12, equal_nan=True)
                    for ln in lines
                ), (key, var, float(ds["kappa0"][b]))
        assert "HMF units" in ax.get_ylabel() and "$N$" in ax.get_xlabel()
        assert ax.get_xscale() == ax.get_yscale() == "log"
    figure.canvas.draw()
    boxes = [ax.get_window_extent() for ax in axes]
    legends = [ax.get_legend() for ax in axes if ax.get_legend()] + list(figure.legends)
    assert legends
    for leg in legends:
        assert not any(leg.get_window_extent().overlaps(b) for b in boxes), "legend on the data"
    caption = FIGURES["fig15_scaling"].caption
    for word in ("Landau", "Lenard-Balescu", "bin", "dashed", "solid"):
        assert word in caption, word


# ---- figure 16: the N-body relaxation rate against N (issue 21) -----------------------------
def test_fig16_draws_the_file_values_and_both_equations(drawn, tmp_path_factory):
    """Panels (b)-(d) of figure 16 draw, at each N, the N-body value of the files (state and
    thermal control) and each kinetic equation's value as a horizontal line: the window rates
    of results/relaxation_rates/{case}.nc and 1/tau_R^coarse of relaxation_comparison."""
    workdir = smoke_workdir(tmp_path_factory)
    spec = yaml.safe_load((workdir / SMOKE).read_text())["figures"]["fig16_relaxation_rates"]
    results = workdir / "results" / "smoke"
    rates = read_dataset(results / f"relaxation_rates/{spec['case']}.nc")
    comparison = read_dataset(results / f"relaxation_comparison/{spec['case']}.nc")
    axes = main_axes(drawn["fig16_relaxation_rates"])
    assert len(axes) == 4

    def horizontal(ax):
        return sorted(
            float(ln.get_ydata()[0])
            for ln in ax.get_lines()
            if ln.get_marker() in ("None", "", None)
            and len(set(np.ravel(ln.get_ydata()))) == 1
            and float(ln.get_ydata()[0]) != 0.0
        )

    def points(ax):
        return sorted(
            float(y)
            for ln in ax.get_lines()
            if ln.get_marker() in ("o", "s")
            for y in ln.get_ydata()
            if np.isfinite(y)
        )

    def finite(values):
        return sorted(float(v) for v in np.ravel(values) if np.isfinite(v))

    for ax, key in ((axes[1], "entropy_rate"), (axes[2], "current")):
        expect = finite([float(rates[f"{key}_{eq}"]) for eq in ("landau", "lenard_balescu")])
        np.testing.assert_allclose(horizontal(ax), expect, rtol=1e-12)
        np.testing.assert_allclose(points(ax), finite(rates[f"{key}_md"].values), rtol=1e-12)
    expect = finite(
        [1.0 / float(comparison[f"tau_relax_coarse_{eq}"]) for eq in ("landau", "lenard_balescu")]
    )
    np.testing.assert_allclose(horizontal(axes[3]), expect, rtol=1e-12)
    n = comparison["N"].values
    np.testing.assert_allclose(
        points(axes[3]), finite(n / comparison["t_relax_md"].values), rtol=1e-12
    )


def test_reading_the_registry_leaves_pyplot_unimported():
    """Every start of the workflow (each dry run, each Slurm job) reads the figure registry;
    pyplot is imported only when a figure is drawn (`style.plt`), which then works as pyplot."""
    code = (
        "import sys\n"
        "from hmfdiff.analysis.figures.registry import FIGURES\n"
        "assert FIGURES and 'matplotlib.pyplot' not in sys.modules, 'pyplot imported'\n"
        "from hmfdiff.analysis.figures.style import plt\n"
        "fig, ax = plt.subplots()\n"
        "assert 'matplotlib.pyplot' in sys.modules and plt.get_backend().lower() == 'agg'\n"
        "assert plt.rcParams['savefig.dpi'] == 150\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]


# ---- what a first look at the smoke figures met (issue 36) ----------------------------------
def _agg_renderer(figure):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return canvas.get_renderer()


@pytest.mark.parametrize("name", list(FIGURES))
def test_every_figure_has_a_super_title_and_no_colliding_tick_labels_or_nan(drawn, name):
    """Every figure carries a super-title (7, 11, 12, 16 had none); no two tick labels of an
    axis, major or minor, overlap (figure 16 (b, c): the log axis autoscaled to 400-432 around
    the smoke config's one size and wrote 4.05, 4.1, ... x 10^2 into each other); no text says
    NaN (figure 11's legend read 'tau_R^fine = NaN' where no relaxation time was reached)."""
    figure = drawn[name]
    assert figure.get_suptitle(), name
    renderer = _agg_renderer(figure)
    for ax in figure.axes:
        for which in "xy":
            labels = [
                t
                for minor in (False, True)
                for t in getattr(ax, f"get_{which}ticklabels")(minor=minor)
                if t.get_visible() and t.get_text()
            ]
            boxes = [t.get_window_extent(renderer) for t in labels]
            for i in range(len(boxes)):
                for j in range(i + 1, len(boxes)):
                    assert not boxes[i].overlaps(boxes[j]), (
                        name,
                        ax.get_title(),
                        labels[i].get_text(),
                        labels[j].get_text(),
                    )
    for text in texts(figure) + [t.get_text() for ax in figure.axes for t in ax.texts]:
        assert "NaN" not in text, (name, text)


def test_fig11_shows_tau_0_and_says_when_tau_R_was_not_reached(drawn, tmp_path_factory):
    """Panels (c, d) of figure 11 (M0 and S against tau) include the initial state, tau = 0,
    which a log axis hid; where the run ended before the entropy deficit fell by e, the legend
    says that tau_R^fine was not reached by the run's last tau (the smoke run's case)."""
    workdir = smoke_workdir(tmp_path_factory)
    spec = yaml.safe_load((workdir / SMOKE).read_text())["figures"]["fig11_relaxation"]
    results = workdir / "results" / "smoke"
    axes = main_axes(drawn["fig11_relaxation"])
    for row, case in enumerate(spec["cases"]):
        runs = [
            read_dataset(results / f"relaxation/{case}_{eq}.nc")
            for eq in ("landau", "lenard_balescu")
        ]
        for ax in axes[4 * row + 2 : 4 * row + 4]:
            assert ax.get_xlim()[0] <= 0.0, ax.get_title()
            assert any(0.0 in ln.get_xdata() for ln in ax.get_lines()), ax.get_title()
        legend = " ".join(t.get_text() for t in axes[4 * row + 2].get_legend().get_texts())
        for ds in runs:
            if not np.isfinite(float(ds["tau_relax_fine"])):
                assert f"not reached by $\\tau={style.sci(float(ds['tau'][-1]), 3)}$" in legend
    assert any(
        not np.isfinite(float(read_dataset(p)["tau_relax_fine"]))
        for p in results.glob("relaxation/*.nc")
    ), "the smoke run reaches tau_R: the 'not reached' branch is not exercised"


def test_fig16_d_says_when_it_has_no_data(drawn, tmp_path_factory):
    """Panel (d) of figure 16 (N / t_R of the full relaxation) says that it has no data where no
    ensemble relaxed within its run (the smoke config), instead of an empty frame."""
    workdir = smoke_workdir(tmp_path_factory)
    spec = yaml.safe_load((workdir / SMOKE).read_text())["figures"]["fig16_relaxation_rates"]
    cmp_ = read_dataset(workdir / f"results/smoke/relaxation_comparison/{spec['case']}.nc")
    ax = main_axes(drawn["fig16_relaxation_rates"])[3]
    said = any("no data at this size" in t.get_text() for t in ax.texts)
    assert said == (not np.isfinite(cmp_["t_relax_md"].values).any())
    assert said, "the smoke run relaxes: the empty-panel branch is not exercised"
