# ---- figures: everything about them comes from the registry in src ----------------------
import re

from hmfdiff.analysis.figures.registry import FIGURES


def figure_spec(name):
    """The config entry of one figure (which cases it draws)."""
    return config["figures"][name]


def figure_inputs(wildcards):
    """Input files of one figure: a list per kind of input, and the library it draws with."""
    fig = FIGURES[wildcards.name]
    files = {
        kind: [f"{RES}/{path}" for path in paths]
        for kind, paths in fig.input_files(figure_spec(wildcards.name)).items()
    }
    files["lib"] = lib("figure.py")
    return files


def caption_rst(name):
    """The registry's caption of one figure as literal reStructuredText for the report: its
    |eps_cc|, c_n' and * would otherwise be read as substitutions, references and emphasis.
    """
    return re.sub(r"([\\`*_|])", r"\\\1", FIGURES[name].caption)


def figure_names():
    """Figures of the registry that the config asks for, in the registry's order."""
    return [name for name in FIGURES if name in config["figures"]]


def figure_targets():
    return expand(
        f"{RES}/figures/{{name}}.{{ext}}", name=figure_names(), ext=["pdf", "png"]
    )
