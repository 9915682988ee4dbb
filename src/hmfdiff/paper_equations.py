"""The published equation and figure numbers of Benetti & Marcos, PRE 95, 022111 (2017), by the
LaTeX labels of its source, so that what a user reads (netCDF attributes, figure captions)
cites "eq. (49)", which a reader of the paper can find, not "eq. hmfCEdif".

The numbers are those the paper's class gives (revtex4 with amsmath, the source
paper/benetti_marcos_2017_hmf_diffusion.tex; `tests/test_paper_equations.py` derives them from
it again and compares):

- every `equation`, and every row of an `align` or `eqnarray`, is numbered (1), (2), ... unless
  starred or marked `\\nonumber` (an `equation` with `\\nonumber` takes no number: amsmath
  gives its number back); rows of inner environments (`cases`, `aligned`) are not rows;
- `subequations` take one number and letter their rows: (9a), (9b);
- `\\appendix` restarts the count in each appendix, prefixed by its letter (revtex4.cls:
  `\\@addtoreset{equation}{section}`, `\\theequation@prefix{\\thesection}`): (A1) ... (A13),
  (B1) ... (B5), (C1), (C2);
- a label in an unnumbered row of a multi-row display is the display's number, that of its
  next numbered row (where LaTeX's `\\ref` puts it too, in `align` and in `eqnarray`).

Figures are numbered 1-10 in the order of their captions.
"""

from __future__ import annotations

import re

__all__ = ["EQUATIONS", "FIGURES", "eq", "cite"]

#: label in the source -> published number, in the order of the source
EQUATIONS = {
    "eq:fdisc": "(1)",
    "eq:klim": "(2)",
    "eq:phid": "(3)",
    "eq:fsmooth": "(4)",
    "eq:quasilin1": "(5)",
    "eq:phismooth": "(6)",
    "eq:delphi": "(7)",
    "eq:quasilin2": "(8)",
    "kinetic-homo": "(9)",
    "eq:quasilinhom1": "(9a)",
    "eq:quasilinhom2": "(9b)",
    "eq:ftransform": "(10)",
    "eq:phitransform": "(11)",
    "coll-ini": "(14)",
    "fluctuat": "(15)",
    "epsilon-definition": "(16)",
    "fluctu-phi": "(17)",
    "eq:LBhom": "(18)",
    "eq:aaevolve": "(19)",
    "eq:aaevolve1": "(19a)",
    "eq:aaevolve2": "(19b)",
    "kinetic-aa": "(22)",
    "kinetic-aa1": "(22a)",
    "kinetic-aa2": "(22b)",
    "eq:LBaa": "(23)",
    "eq:D": "(24)",
    "eq:eps": "(25)",
    "eq:fp": "(29)",
    "eq:CEdiff": "(30)",
    "eq:CEfric1": "(31)",
    "eq:dfric": "(32)",
    "cond-nocoll": "(34)",
    "eq:hmfhamiltonian": "(36)",
    "eq:hmfparticleenergy": "(37)",
    "eq:phiphase": "(39)",
    "eq:hmfaction": "(40)",
    "eq:hmfkappa": "(41)",
    "eq:hmfjacob": "(42)",
    "eq:hmfomega": "(43)",
    "eq:hmfft1": "(44)",
    "eq:hmfcm": "(45)",
    "eq:hmfsm": "(46)",
    "eq:hmflb": "(47)",
    "eq:domdk": "(48)",
    "eq:hmfCEdif": "(49)",
    "eq:hmfCEpol": "(50)",
    "eq:hmfD": "(51)",
    "eq:hmfDbare": "(52)",
    "eq:hmfepscc": "(53)",
    "eq:hmfepsss": "(54)",
    "gaussian-def": "(59)",
    "coeff-analytic-ncoll": "(61)",
    "coeff-analytic-ncoll-exp": "(62a)",
    "eq:hmffch2": "(63)",
    "eq:hmffch2k": "(64)",
    "partial-ch": "(65)",
    "eq:hmfepscc/ss-ch": "(66)",
    "eq:hmffch": "(67)",
    "eps_cc_ap_def": "(69a)",
    "eps_ss_ap_def": "(69b)",
    "eq:hmfmdbath": "(71)",
    "eq:hmfeq": "(72)",
    "eq:mageq": "(73)",
    "eq:hmfmdfull": "(74)",
    "eq:dj2": "(75)",
    "eq:hmfmddif": "(76)",
    "eq:hmfaction1": "(A3)",
    "eq:hmfaction2": "(A4)",
    "eq:hmfkappaapend": "(A5)",
    "eq:clei2": "(A6)",
    "eq:t": "(A12)",
    "eq:w": "(A13)",
    "eq:cosellip": "(B1)",
    "eq:sinellip": "(B2)",
    "eq:milnsn2": "(B3)",
    "eq:milnsndn": "(B4)",
    "eq:milnsncn": "(B5)",
    "eps_cc_ap": "(C1)",
    "eps_ss_ap": "(C2)",
}

#: figure label -> published number
FIGURES = {
    "fig:hmforbits": "1",
    "fig:hmfactom": "2",
    "fig:hmfpoles": "3",
    "fig:hmfcontribs": "4",
    "fig:eps": "5",
    "fig:hmfCENCEcompare": "6",
    "M0.8": "7",
    "fig:dj2t": "8",
    "fig:hmfdiff": "9",
    "fig:hmfch": "10",
}


def _key(label, table, prefix):
    """The key of `table` for `label`, given with or without its `prefix` ("eq:", "fig:")."""
    for key in (label, prefix + label):
        if key in table:
            return key
    raise KeyError(f"{label!r} is not a label of the paper ({prefix}...)")


def eq(*labels):
    """'eq. (49)' for eq("hmfCEdif"), 'eqs. (49), (52)' for several labels ("eq:" optional);
    KeyError for a label the paper does not have."""
    nums = [EQUATIONS[_key(lab, EQUATIONS, "eq:")] for lab in labels]
    return ("eq. " if len(nums) == 1 else "eqs. ") + ", ".join(nums)


def _short(key):
    return key.split(":", 1)[1] if ":" in key else key


#: the equation labels as code writes them (with and without "eq:"), longest first so that
#: hmfepscc/ss-ch is read before hmfepscc and coeff-analytic-ncoll-exp before ...-ncoll
_EQ_NAMES = sorted({n for k in EQUATIONS for n in (k, _short(k))}, key=len, reverse=True)
_EQ_ALT = "|".join(map(re.escape, _EQ_NAMES))
_END = r"(?![\w:/-])"  # a label ends where no label character follows
#: 'eq. L', 'eqs. L1, L2 + L3 and L4' (also without the dot); the separators are kept
_ONE = rf"(?:{_EQ_ALT}){_END}"
_CITED = re.compile(rf"\b(?P<word>[Ee]qs?\.?) (?P<list>{_ONE}(?:(?:, | \+ | and ){_ONE})*)")
#: a label standing alone that nothing else could be: one with "eq:" written out, or with one
#: of - _ / in it (eps_cc_ap, coeff-analytic-ncoll, gaussian-def)
_BARE_NAMES = sorted(
    (n for n in _EQ_NAMES if n.startswith("eq:") or re.search(r"[-_/]", n)), key=len, reverse=True
)
_BARE = re.compile(rf"(?<![\w:/-])(?:{'|'.join(map(re.escape, _BARE_NAMES))}){_END}")
_FIG_NAMES = sorted({n for k in FIGURES for n in (k, _short(k))}, key=len, reverse=True)
_FIG = re.compile(
    rf"\b(?P<word>[Ff]ig\.?) (?P<label>{'|'.join(map(re.escape, _FIG_NAMES))}){_END}"
    rf"|(?<![\w:/-])(?P<bare>fig:(?:{'|'.join(map(re.escape, map(_short, FIGURES)))})){_END}"
)


def _number(name):
    return EQUATIONS[_key(name, EQUATIONS, "eq:")]


def cite(text):
    """`text` with the paper's LaTeX labels replaced by published numbers: 'eq. hmfCEdif' ->
    'eq. (49)', 'eqs. hmfCEdif, hmfD' -> 'eqs. (49), (51)', 'fig. hmfcontribs' -> 'fig. 4',
    and a label that can only be one (eq:..., or one with - _ / in it: 'eps_cc_ap') -> 'eq.
    (C1)'.  Text citing no label is returned unchanged."""
    if not isinstance(text, str):
        return text

    def listed(m):
        items = re.split(r"(, | \+ | and )", m["list"])
        return m["word"] + " " + "".join(x if i % 2 else _number(x) for i, x in enumerate(items))

    text = _CITED.sub(listed, text)
    text = _BARE.sub(lambda m: "eq. " + _number(m.group(0)), text)

    def figure(m):
        if m["bare"]:
            return "fig. " + FIGURES[m["bare"]]
        return m["word"] + " " + FIGURES[_key(m["label"], FIGURES, "fig:")]

    return _FIG.sub(figure, text)
