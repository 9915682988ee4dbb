# ---- figures: everything about them comes from the registry in src ----------------------
from hmfdiff.analysis.figures.registry import FIGURES


def figure_spec(name):
    """The config entry of one figure (which cases it draws)."""
    return config["figures"][name]


def figure_inputs(wildcards):
    """Input files of one figure: a list per kind of input."""
    fig = FIGURES[wildcards.name]
    return {
        kind: [f"{RES}/{path}" for path in paths]
        for kind, paths in fig.input_files(figure_spec(wildcards.name)).items()
    }


def figure_names():
    """Figures of the registry that the config asks for, in the registry's order."""
    return [name for name in FIGURES if name in config["figures"]]


def figure_targets():
    return expand(
        f"{RES}/figures/{{name}}.{{ext}}", name=figure_names(), ext=["pdf", "png"]
    )
