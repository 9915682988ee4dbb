"""The published equation numbers (hmfdiff.paper_equations) against the paper's LaTeX source,
numbered here as revtex4 with amsmath numbers it, and the attributes that cite them.

The source is shared/paper/benetti_marcos_2017_hmf_diffusion.tex beside the checkout (CI runs
with ../shared); the tests that need it skip, saying so, where it is absent."""

import os
import re
import string
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr
from _smoke import smoke_workdir

from hmfdiff.paper_equations import EQUATIONS, FIGURES, cite, eq
from hmfdiff.pipeline import io, layouts

ROOT = Path(__file__).resolve().parents[1]
TEX = Path(
    os.environ.get(
        "HMFDIFF_PAPER_TEX",
        ROOT.parent / "shared" / "paper" / "benetti_marcos_2017_hmf_diffusion.tex",
    )
)
needs_tex = pytest.mark.skipif(not TEX.is_file(), reason=f"no paper source at {TEX}")

# ---- the numbering, from the source -------------------------------------------------------
#: the source's own \def shorthands for environments
MACROS = {
    "beq": r"\begin{equation}",
    "eeq": r"\end{equation}",
    "bea": r"\begin{eqnarray}",
    "eea": r"\end{eqnarray}",
    "bean": r"\begin{eqnarray*}",
    "eean": r"\end{eqnarray*}",
    "bse": r"\begin{subequations}",
    "ese": r"\end{subequations}",
}
ROWS = {"align", "eqnarray"}  # a number per row (rows split at \\ of the environment itself)
ONE = {"equation"}  # one number
STARRED = {"equation*", "align*", "eqnarray*"}
TOKEN = re.compile(
    r"\\begin\{(?P<begin>[^}]*)\}|\\end\{(?P<end>[^}]*)\}|\\label\{(?P<label>[^}]*)\}"
    r"|(?P<cr>\\\\)|\\(?P<cmd>[A-Za-z]+)"
)


def numbering(text):
    """({label: "(27)"}, [every printed number in order]) of a revtex4 + amsmath document:
    displays numbered in order, \\nonumber rows and starred environments skipped (an equation
    with \\nonumber takes no number: amsmath's \\nonumber gives it back), subequations lettered,
    each appendix counted apart with its letter (revtex4.cls \\appendix); a label takes its row's
    number, or in an unnumbered row the next numbered row's of its display."""
    text = re.sub(r"(?<!\\)%[^\n]*", "", text)
    for name, repl in MACROS.items():
        text = re.sub(rf"\\{name}(?![A-Za-z])", lambda _m, r=repl: r, text)
    text = text[text.index(r"\begin{document}") :]
    counter, prefix, section, appendix = 0, "", 0, False
    labels, printed, stack = {}, [], []
    display, sub = None, None

    def number():
        nonlocal counter
        if sub is not None:
            sub[1] += 1
            return f"({sub[0]}{string.ascii_lowercase[sub[1] - 1]})"
        counter += 1
        return f"({prefix}{counter})"

    for m in TOKEN.finditer(text):
        if m["begin"]:
            env = m["begin"]
            stack.append(env)
            if env == "subequations":
                counter += 1
                sub = [f"{prefix}{counter}", 0]
            elif env in ROWS | ONE | STARRED and display is None:
                display = {"kind": env, "rows": [{"labels": [], "on": env not in STARRED}]}
        elif m["end"]:
            env = m["end"]
            assert stack and stack[-1] == env, (env, stack)
            stack.pop()
            if env == "subequations":
                sub = None
            elif display is not None and env == display["kind"]:
                rows = display["rows"]
                if env in ONE:
                    rows = [
                        {
                            "labels": [lab for r in rows for lab in r["labels"]],
                            "on": all(r["on"] for r in rows),
                        }
                    ]
                nums = [number() if r["on"] else None for r in rows]
                printed += [n for n in nums if n]
                for i, r in enumerate(rows):
                    after = [n for n in nums[i:] if n]
                    for lab in r["labels"]:
                        assert after, f"{lab}: no numbered row at or after its own"
                        labels[lab] = after[0]
                display = None
        elif m["label"] is not None:
            if display is not None:
                display["rows"][-1]["labels"].append(m["label"])
            elif sub is not None:
                labels[m["label"]] = f"({sub[0]})"
        elif m["cr"]:
            if display is not None and display["kind"] in ROWS and stack[-1] == display["kind"]:
                display["rows"].append({"labels": [], "on": True})
        elif m["cmd"] in ("nonumber", "notag") and display is not None:
            display["rows"][-1]["on"] = False
        elif m["cmd"] == "appendix":
            appendix, section = True, 0
        elif m["cmd"] == "section" and appendix and text[m.end() : m.end() + 1] != "*":
            section += 1
            prefix, counter = string.ascii_uppercase[section - 1], 0
    return labels, printed


@pytest.fixture(scope="module")
def tex():
    if not TEX.is_file():
        pytest.skip(f"no paper source at {TEX}")
    return TEX.read_text()


@needs_tex
def test_the_table_is_the_source_numbered_as_revtex4_numbers_it(tex):
    labels, printed = numbering(tex)
    assert labels == EQUATIONS  # same labels, same numbers, in the same order
    assert list(labels) == list(EQUATIONS)
    # 76 in the body (four of them lettered groups), then appendices A, B, C
    assert [p for p in printed if p[1].isdigit() and not p[-2].isalpha()][-1] == "(76)"
    assert printed[-20:] == [f"(A{i})" for i in range(1, 14)] + [f"(B{i})" for i in range(1, 6)] + [
        "(C1)",
        "(C2)",
    ]


def test_hand_counted_numbers():
    """Checked by reading the source: the first display; a subequations group and its rows; a
    label on an unnumbered first row of an align (its display's number, 18); the unnumbered
    'J = (1/2pi) oint p dtheta' (an equation with nonumber) before eq. hmfaction, which takes
    no number; the diffusion coefficient: 23 (LBaa) + eq. D, eq. eps, two rows, one equation,
    fp, CEdiff, CEfric1, dfric, D_pol, cond-nocoll, the bare D, hmfhamiltonian,
    hmfparticleenergy, phi, phiphase = 39, then 40-48 and hmfCEdif 49; a label on the first
    row of a subequations group (62a); eqnarray labels in \\nonumber rows (the next numbered
    row: 66, C1); each appendix restarting with its letter."""
    assert EQUATIONS["eq:fdisc"] == "(1)"
    assert EQUATIONS["kinetic-homo"] == "(9)" and EQUATIONS["eq:quasilinhom2"] == "(9b)"
    assert EQUATIONS["eq:LBhom"] == "(18)"
    assert EQUATIONS["eq:phiphase"] == "(39)" and EQUATIONS["eq:hmfaction"] == "(40)"
    assert EQUATIONS["eq:hmfCEdif"] == "(49)" and EQUATIONS["eq:hmfDbare"] == "(52)"
    assert EQUATIONS["coeff-analytic-ncoll"] == "(61)"
    assert EQUATIONS["coeff-analytic-ncoll-exp"] == "(62a)"
    assert EQUATIONS["eq:hmfepscc/ss-ch"] == "(66)" and EQUATIONS["eq:hmfmddif"] == "(76)"
    assert EQUATIONS["eq:hmfaction1"] == "(A3)" and EQUATIONS["eq:w"] == "(A13)"
    assert EQUATIONS["eq:cosellip"] == "(B1)" and EQUATIONS["eps_ss_ap"] == "(C2)"


@needs_tex
def test_figure_numbers_follow_the_captions(tex):
    body = tex[tex.index(r"\begin{document}") :]
    found = re.findall(r"\\begin\{figure\*?\}.*?\\label\{([^}]*)\}", body, re.S)
    assert {lab: str(i) for i, lab in enumerate(found, 1)} == FIGURES


def test_the_table_imports_nothing():
    text = (ROOT / "src/hmfdiff/paper_equations.py").read_text()
    assert not re.findall(r"^(?:from|import) (?!re$|__future__)", text, re.M)


# ---- citing ---------------------------------------------------------------------------------
def test_eq_and_cite():
    assert eq("hmfCEdif") == eq("eq:hmfCEdif") == "eq. (49)"
    assert eq("hmfCEdif", "hmfDbare") == "eqs. (49), (52)"
    with pytest.raises(KeyError, match="hmfCEdiff"):
        eq("hmfCEdiff")
    assert cite("N D_dif (Landau, eqs. hmfCEdif, hmfDbare)") == "N D_dif (Landau, eqs. (49), (52))"
    assert cite("eqs. hmfCEdif + hmfD and hmfepsss") == "eqs. (49) + (51) and (54)"
    # the longest label first: hmfepscc/ss-ch is not hmfepscc followed by /ss-ch
    assert cite("two-step, eq. hmfepscc/ss-ch (corrected)") == "two-step, eq. (66) (corrected)"
    assert cite("(eq. coeff-analytic-ncoll-exp)") == "(eq. (62a))"
    # labels that can only be labels are cited wherever they stand
    assert cite("appendix C (eps_cc_ap, eps_ss_ap)") == "appendix C (eq. (C1), eq. (C2))"
    assert cite("see eq:hmflb") == "see eq. (47)"
    assert cite("fig. hmfcontribs; Fig. fig:eps") == "fig. 4; Fig. 5"
    # not labels: left alone
    for text in ("hmfdiff 0.1.0", "eq. hmfCEdifx", "eps_cc and t, w, D", "thermal_u-0.1", 3):
        assert cite(text) == text


def test_written_attributes_cite_numbers(tmp_path):
    """io.write_dataset stores every text attribute, a variable's or the file's, whichever
    module wrote it, with the published numbers."""
    ds = xr.Dataset(
        {
            "D": layouts.variable(
                ("k",), np.ones(2), "1", "N D (eq. hmfCEdif)", method="appendix C (eps_cc_ap)"
            )
        },
        attrs={"dynamics": "full N-body HMF (eq. hmfmdfull)"},
    )
    io.write_dataset(ds, tmp_path / "x.nc", title="test of fig. hmfcontribs")
    with netCDF4.Dataset(tmp_path / "x.nc") as nc:
        assert nc["D"].long_name == "N D (eq. (49))"
        assert nc["D"].method == "appendix C (eq. (C1))"
        assert nc.dynamics == "full N-body HMF (eq. (74))"
        assert nc.title == "test of fig. 4"


def _label_citations(text, names):
    """Citations of the paper by a LaTeX label in `text`: 'eq. L', 'eqs. L', 'fig. L' or a label
    with eq:/fig: written out."""
    alt = "|".join(map(re.escape, sorted(names, key=len, reverse=True)))
    return re.findall(rf"(?:\b[EeFf](?:qs?|ig)\.? |\b(?:eq|fig):)(?:{alt})(?![\w/-])", text)


@needs_tex
def test_no_smoke_output_cites_a_label(tex, tmp_path_factory):
    """No attribute of any netCDF file of the smoke run cites an equation or figure by its
    LaTeX label (long_names said 'eq. hmfCEdif'; analytic files 'eq. hmfepscc/ss-ch')."""
    labels = set(re.findall(r"\\label\{([^}]*)\}", tex))
    names = labels | {lab.split(":", 1)[1] for lab in labels if ":" in lab}
    found = []
    for path in sorted(smoke_workdir(tmp_path_factory).glob("results/**/*.nc")):
        with netCDF4.Dataset(path) as nc:
            objects = [("", nc)] + list(nc.variables.items())
            for name, obj in objects:
                for key in obj.ncattrs():
                    value = obj.getncattr(key)
                    if isinstance(value, str) and _label_citations(value, names):
                        found.append(f"{path.name} {name}.{key}: {value[:120]}")
    assert not found, "\n".join(found[:20])
    assert _label_citations("N D_dif (eqs. hmfCEdif, hmfD)", names)  # the check sees them
