"""The import structure of the package: no module of hmfdiff takes part in an import cycle.

The graph is read from the code (`hmfdiff.pipeline.deps.import_graph`, an `ast` walk; nothing
imported).  Two graphs: the imports that run when a module is imported (a cycle there can fail
on import, depending on which module is imported first), and every import at any depth, those
inside functions too (a cycle there is a circle in the design, such as the kernel cache that
imported the MD driver whose kernels imported the cache's `njit`)."""

import graphlib
from pathlib import Path

import pytest

from hmfdiff.pipeline.deps import import_graph

SRC = Path(__file__).resolve().parents[1] / "src"


def cycle(graph):
    """One cycle of the graph as a list of modules, each importing the next (first == last), or
    None."""
    try:
        tuple(graphlib.TopologicalSorter(graph).static_order())
    except graphlib.CycleError as e:
        return e.args[1][::-1]  # graphlib lists each module before the one importing it
    return None


def write(root, rel, text=""):
    path = Path(root, rel)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def test_the_graph_sees_cycles_at_module_level_and_inside_functions(tmp_path):
    """The check itself: a cycle through module-level imports, one closed by an import inside a
    function (only in the full graph), and a package's own parents, which are not cycles."""
    write(tmp_path, "hmfdiff/__init__.py", "from .a import one\n")  # a package importing its own
    write(tmp_path, "hmfdiff/a/__init__.py")
    write(tmp_path, "hmfdiff/a/one.py", "from .. import a\nfrom . import two\n")
    write(tmp_path, "hmfdiff/a/two.py", "import numpy\n\ndef f():\n    from .three import x\n")
    write(tmp_path, "hmfdiff/a/three.py", "from hmfdiff.a.one import y\nx = 1\n")
    top, full = import_graph(tmp_path, top_level=True), import_graph(tmp_path)
    assert top["hmfdiff.a.one"] == {"hmfdiff.a.two"} and top["hmfdiff.a.two"] == set()
    assert full["hmfdiff.a.two"] == {"hmfdiff.a.three"}
    assert cycle(top) is None
    assert set(cycle(full)) == {"hmfdiff.a.one", "hmfdiff.a.two", "hmfdiff.a.three"}
    write(tmp_path, "hmfdiff/a/two.py", "from .three import x\n")
    assert set(cycle(import_graph(tmp_path, top_level=True))) == {
        "hmfdiff.a.one",
        "hmfdiff.a.two",
        "hmfdiff.a.three",
    }


@pytest.mark.parametrize("top_level", [True, False], ids=["module_level", "any_depth"])
def test_no_module_of_hmfdiff_takes_part_in_an_import_cycle(top_level):
    graph = import_graph(SRC, top_level=top_level)
    assert len(graph) > 50 and "hmfdiff.dynamics.md" in graph
    assert cycle(graph) is None, " imports ".join(cycle(graph))


def test_the_jit_settings_import_no_kernel():
    """The kernels import `dynamics.jit`; the kernel cache imports the kernels (to warm them)."""
    graph = import_graph(SRC)
    assert graph["hmfdiff.dynamics.jit"] == set()
    for kernel in ("elementary", "integrator", "accumulator", "exact_bath"):
        imports = graph[f"hmfdiff.dynamics.{kernel}"]
        assert "hmfdiff.dynamics.jit" in imports and "hmfdiff.dynamics.kernel_cache" not in imports
    assert "hmfdiff.dynamics.md" in graph["hmfdiff.dynamics.kernel_cache"]
    top = import_graph(SRC, top_level=True)["hmfdiff.dynamics.kernel_cache"]
    assert top == {"hmfdiff.dynamics.jit"}  # importing it must not import a kernel


#: imports of analysis/ inside functions of pipeline/, with the reason
PIPELINE_READS_ANALYSIS = {
    # the config check validates the config's figures against the figure registry: it serves
    # the Snakefile, above every floor, and imports the registry (and through it the drawing
    # modules) only when it checks figures, so that importing pipeline loads no analysis
    "hmfdiff.pipeline.config": {"hmfdiff.analysis.figures.registry"},
}


def test_pipeline_does_not_import_analysis():
    """pipeline/ (I/O, layouts, config) is a floor below analysis/, which imports it: no module
    of pipeline imports analysis at module level, and inside functions only the exceptions
    above."""
    top, full = import_graph(SRC, top_level=True), import_graph(SRC)
    pipeline = [m for m in full if m.split(".")[:2] == ["hmfdiff", "pipeline"]]
    assert "hmfdiff.pipeline.io" in pipeline
    for module in pipeline:
        upward = {m for m in top[module] if m.startswith("hmfdiff.analysis")}
        assert not upward, (module, upward)
        upward = {m for m in full[module] if m.startswith("hmfdiff.analysis")}
        allowed = {  # an allowed module and the packages that hold it (run on its import)
            ".".join(m.split(".")[:i])
            for m in PIPELINE_READS_ANALYSIS.get(module, ())
            for i in range(2, m.count(".") + 2)
        }
        assert upward <= allowed, (module, upward - allowed)


def test_each_layout_imports_only_its_helpers_and_the_mean_field():
    """pipeline/layouts/: the package imports only the shared helpers (a script importing one
    stage's layout does not watch the others, `pipeline.deps`), and no layout imports the
    physics of a stage (kinetic, dynamics, analysis): only the mean field, pipeline's own and
    the paper's equation numbers (a table, importing nothing)."""
    full = import_graph(SRC)
    package = "hmfdiff.pipeline.layouts"
    assert full[package] == {f"{package}.variables"}
    stages = [m for m in full if m.startswith(package + ".")]
    assert len(stages) >= 7, stages
    for module in stages:
        outside = {
            m
            for m in full[module]
            if not m.startswith(("hmfdiff.meanfield", "hmfdiff.pipeline"))
            and m != "hmfdiff.paper_equations"
        }
        assert not outside, (module, outside)
