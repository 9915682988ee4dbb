"""The HTML report embeds every figure of the registry as an image, with its caption, and the
validation table (decoded from the report, not just named in it)."""

import base64
import html
import json
import re

import pytest
import yaml
from _smoke import SMOKE, smoke_workdir, snakemake

from hmfdiff.analysis.figures.registry import FIGURES

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def embedded_results(report_html):
    """{path: entry} of the results that Snakemake (9.x) embeds in a self-contained report:
    a JSON object `var results = {...};` whose entries carry a base64 `data_uri`."""
    m = re.search(
        r'<script id="results">\s*var results = (\{.*?\});?\s*</script>', report_html, re.S
    )
    assert m, "no embedded results in the report"
    return json.loads(m.group(1))


def decode_data_uri(uri):
    header, _, payload = uri.partition(",")
    assert header.startswith("data:") and header.endswith(";base64"), header[:80]
    return header[5:].split(";")[0], base64.b64decode(payload, validate=True)


def plain(html_text):
    """The text of an HTML fragment: tags removed, entities decoded, whitespace collapsed."""
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", html_text)).split())


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    workdir = smoke_workdir(tmp_path_factory)
    out = workdir / "report.html"
    out.unlink(missing_ok=True)
    r = snakemake(["--report", str(out), "--configfile", SMOKE], workdir)
    assert r.returncode == 0, r.stderr[-3000:]
    return workdir, embedded_results(out.read_text())


def test_every_registry_figure_is_embedded_as_an_image_with_its_caption(report):
    workdir, results = report
    wanted = [n for n in FIGURES if n in yaml.safe_load((workdir / SMOKE).read_text())["figures"]]
    assert len(wanted) == len(FIGURES), "the smoke config should draw every figure"
    for name in wanted:
        keys = [k for k in results if k.endswith(f"figures/{name}.png")]
        assert len(keys) == 1, (name, sorted(results))
        entry = results[keys[0]]
        mime, data = decode_data_uri(entry["data_uri"])
        assert mime == "image/png" and data.startswith(PNG_MAGIC), name
        assert data == (workdir / keys[0]).read_bytes(), f"{name}: embedded image differs"
        assert " ".join(FIGURES[name].caption.split()) in plain(entry["caption"]), name
        assert entry["labels"]["figure"] == f"{FIGURES[name].number:02d}"
        # the report's viewer sorts labels with String.localeCompare: a number there raises
        # a TypeError in the browser and no result of the category is shown
        for key, value in entry["labels"].items():
            assert isinstance(value, str), (name, key, value)


def test_validation_table_is_embedded(report):
    workdir, results = report
    keys = [k for k in results if k.endswith("validation.csv")]
    assert len(keys) == 1, sorted(results)
    mime, data = decode_data_uri(results[keys[0]]["data_uri"])
    assert mime == "text/csv"
    assert data == (workdir / keys[0]).read_bytes()
    assert data.startswith(b"case,dynamics,")
