"""The library files a workflow script depends on, read from its imports.

A `script:` rule of Snakemake reruns when its script changes, not when the library it imports
changes; each rule therefore carries a digest of the library files its script imports as a
parameter (`library_digest`), and Snakemake reruns a job whose parameters changed since its
last execution (its default rerun triggers include `params`).  A parameter, not the files as
inputs: the log lists every input of every job, ~25 library files each.  This module derives
the list from the code itself, so it cannot go stale: an `ast` walk over the script and,
transitively,
over every module of the package it reaches (absolute and relative imports, at any depth of
the code, so imports inside functions count too).  The package `__init__.py` files on the way
count as well, since Python runs them on import.  Nothing is imported or executed.
"""

from __future__ import annotations

import ast
import functools
import hashlib
from pathlib import Path

__all__ = ["library_files", "library_digest", "module_imports", "import_graph"]

PACKAGE = "hmfdiff"


def _module_file(src, dotted):
    """The file of module `dotted` under the source root `src`, or None if it is not one."""
    base = Path(src, *dotted.split("."))
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _package_of(src, path):
    """The dotted package that holds the module file `path` (for relative imports)."""
    parts = path.relative_to(src).with_suffix("").parts
    return ".".join(parts[:-1])  # a/b/c.py -> a.b; a/b/__init__.py -> a.b, itself


def _import_nodes(tree, top_level):
    """The import statements of a module: all of them, or (`top_level`) those that run when the
    module is imported (module and class bodies, if/try/with blocks; not function bodies)."""
    if not top_level:
        yield from ast.walk(tree)
        return
    todo = [tree]
    while todo:
        node = todo.pop()
        yield node
        for child in ast.iter_child_nodes(node):
            if not isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
                todo.append(child)


def module_imports(path, src, package=None, top_level=False):
    """Dotted names that the module at `path` imports from the package, as far as the code says.

    `package` is the dotted package holding `path` (None for a script outside `src`, whose
    relative imports, if any, are an error).  `from a.b import c` yields both `a.b` and
    `a.b.c`; the caller keeps those that are modules.  `top_level`: only the imports that run
    when the module is imported (not those inside functions).

    Parsed once per file version (path, size and modification time): a dry run of the workflow
    asks for the same modules once per rule."""
    stat = Path(path).stat()
    return list(_imports(str(path), stat.st_mtime_ns, stat.st_size, package, top_level))


@functools.lru_cache(maxsize=4096)
def _imports(path, mtime_ns, size, package, top_level):
    tree = ast.parse(Path(path).read_text(), filename=path)
    names = []
    for node in _import_nodes(tree, top_level):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                if package is None:
                    raise ValueError(f"{path}: relative import outside the package")
                parts = package.split(".")
                if node.level - 1 > len(parts) - 1:
                    raise ValueError(f"{path}:{node.lineno}: relative import beyond {PACKAGE}")
                base = parts[: len(parts) - (node.level - 1)]
                if node.module:
                    base += node.module.split(".")
                base = ".".join(base)
            else:
                base = node.module
            names.append(base)
            names += [f"{base}.{alias.name}" for alias in node.names if alias.name != "*"]
    return tuple(n for n in names if n == PACKAGE or n.startswith(PACKAGE + "."))


def library_files(script, src):
    """Sorted paths (as given by `src`) of every package file the script at `script` reaches.

    `src` is the source root holding the package folder (src/ of this repository), so the
    paths are src/hmfdiff/... when `src` is relative."""
    src = Path(src)
    if not Path(src, PACKAGE).is_dir():
        raise FileNotFoundError(f"no package {PACKAGE!r} under {src}")
    seen = {}
    todo = [(Path(script), None)]
    while todo:
        path, package = todo.pop()
        for dotted in module_imports(path, src, package):
            parts = dotted.split(".")
            # importing a.b.c runs a/__init__.py and a/b/__init__.py first
            for i in range(1, len(parts) + 1):
                name = ".".join(parts[:i])
                if name in seen:
                    continue
                file = _module_file(src, name)
                if file is None:
                    continue  # an attribute (function, class), not a module
                seen[name] = file
                todo.append((file, _package_of(src, file)))
    return sorted(str(p) for p in seen.values())


def library_digest(script, src):
    """'23 files of hmfdiff, sha256 1f8ec0a99d3e78d4': the number of package files the script
    at `script` reaches (`library_files`) and a digest of their paths under `src` and contents
    (a comment edited counts; the place of the source tree does not)."""
    files = library_files(script, src)
    h = hashlib.sha256()
    for f in files:
        h.update(Path(f).relative_to(src).as_posix().encode() + b"\0")
        h.update(Path(f).read_bytes() + b"\0")
    return f"{len(files)} files of {PACKAGE}, sha256 {h.hexdigest()[:16]}"


def import_graph(src, top_level=False):
    """{module: set of modules it imports} over every module of the package under `src`
    (dotted names; a package is its `__init__`).  Importing a.b.c runs the packages a and a.b
    first, so they count as imported too, except the packages that hold the importer itself
    (already running when it is imported).  `top_level` as in `module_imports`."""
    src = Path(src)
    graph = {}
    for file in sorted(Path(src, PACKAGE).rglob("*.py")):
        parts = file.relative_to(src).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        package = _package_of(src, file)
        own = {".".join(parts[:i]) for i in range(1, len(parts))}
        edges = set()
        for dotted in module_imports(file, src, package, top_level):
            pieces = dotted.split(".")
            for i in range(1, len(pieces) + 1):
                target = ".".join(pieces[:i])
                if target not in own and target != name and _module_file(src, target):
                    edges.add(target)
        graph[name] = edges
    return graph
