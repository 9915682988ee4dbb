"""The README's and the docs' relative links lead to files that exist, and their #anchors to
headings of those files (GitHub's rule: lower case, punctuation dropped, spaces to hyphens)."""

from __future__ import annotations

import re

import pytest
from _smoke import ROOT

PAGES = sorted(["README.md", *(p.relative_to(ROOT).as_posix() for p in ROOT.glob("docs/*.md"))])
_LINK = re.compile(r"\]\(([^)\s]+)\)")


def anchors(path):
    out = set()
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            title = line.lstrip("#").strip().lower()
            out.add(re.sub(r"[^\w\- ]", "", title).replace(" ", "-"))
    return out


@pytest.mark.parametrize("page", PAGES)
def test_relative_links_resolve(page):
    here = (ROOT / page).parent
    for target in _LINK.findall((ROOT / page).read_text()):
        if re.match(r"[a-z]+:", target):
            continue  # an absolute URL
        path, _, anchor = target.partition("#")
        dest = (here / path).resolve() if path else ROOT / page
        assert dest.exists(), (page, target)
        if anchor:
            assert anchor in anchors(dest), (page, target, sorted(anchors(dest)))


def test_every_docs_page_is_in_the_index():
    index = (ROOT / "docs/index.md").read_text()
    for p in ROOT.glob("docs/*.md"):
        if p.name != "index.md":
            assert f"]({p.name})" in index, p.name
    assert "](docs/index.md)" in (ROOT / "README.md").read_text()


def test_readme_snippet_opens_a_file_of_the_smoke_run(tmp_path_factory, monkeypatch, capsys):
    """The README's 'Opening an intermediate' snippet runs as written after the smoke run, and
    every results/smoke path the README names exists there."""
    from _smoke import smoke_workdir

    smoke = smoke_workdir(tmp_path_factory)
    readme = (ROOT / "README.md").read_text()
    for path in re.findall(r"results/smoke/[\w./-]+\.nc", readme):
        assert (smoke / path).exists(), path
    (snippet,) = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    monkeypatch.chdir(smoke)
    exec(compile(snippet, "README.md", "exec"), {})
    assert "thermal_u-0.1" in capsys.readouterr().out
