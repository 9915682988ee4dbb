"""The figure registry (inputs per kind, in config order) and the look of every figure: panel
labels (a), (b), ... in reading order, numbers as mathtext powers of ten, labelled axes."""

import re

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
