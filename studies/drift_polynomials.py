"""The float32 polynomials of the MD's drift rotation (`hmfdiff.dynamics.elementary`): the fit
that gives their coefficients, and their errors (issue 39 part 1).

sin d = d + d z S(z) and cos d = 1 + z (-1/2 + z C(z)), z = d^2, on |d| <= DRIFT_MAX (S, C of
degree 2) and on |d| <= DRIFT_SHORT (degree 1).  Least squares at 400 Chebyshev nodes of z in
[0, d_max^2], in 40-digit arithmetic, of the relative error of sin d (weight z) and the absolute
error of cos d (weight z^2); each coefficient is rounded to float32 and the next ones refitted
with it fixed, so that the float32 coefficients, not their unrounded values, are the near-best
fit.  Prints the coefficients, whether they are elementary's, and per band of |d| the largest
error in exact arithmetic and the mean error of the float32 evaluation (the kernel's own,
`elementary.sincos_drift_array`) against the exact values: of sin, of cos and of the norm
sin^2 + cos^2 - 1, beside the same means for sin d and cos d correctly rounded to float32 (what
an unbiased evaluation gives).

    python studies/drift_polynomials.py
"""

from __future__ import annotations

import mpmath as mp
import numpy as np

from hmfdiff.dynamics import elementary


def fit(target, weight, zmax, n_coef):
    """float32 coefficients c_k of sum_k c_k z^k ~ target(z), weighted, at 400 Chebyshev nodes
    of [0, zmax], rounded to float32 one at a time (the rest refitted after each)."""
    nodes = [zmax * (1 + mp.cos(mp.pi * (2 * j + 1) / 800)) / 2 for j in range(400)]
    coef = []
    while len(coef) < n_coef:
        k0 = len(coef)
        A = mp.matrix(len(nodes), n_coef - k0)
        b = mp.matrix(len(nodes), 1)
        for i, z in enumerate(nodes):
            w = weight(z)
            for k in range(n_coef - k0):
                A[i, k] = w * z ** (k0 + k)
            b[i] = w * (target(z) - sum(c * z**k for k, c in enumerate(coef)))
        x, _ = mp.qr_solve(A, b)
        coef.append(mp.mpf(float(np.float32(float(x[0])))))
    return [np.float32(float(c)) for c in coef]


def sin_target(z):
    """(sin d / d - 1) / z."""
    d = mp.sqrt(z)
    return (mp.sin(d) / d - 1) / z


def cos_target(z):
    """((cos d - 1) / z + 1/2) / z."""
    return ((mp.cos(mp.sqrt(z)) - 1) / z + mp.mpf(1) / 2) / z


def main():
    mp.mp.dps = 40
    paths = {
        "long": (elementary.DRIFT_MAX, 3, (elementary._DS1, elementary._DS2, elementary._DS3),
                 (elementary._DC2, elementary._DC3, elementary._DC4)),
        "short": (elementary.DRIFT_SHORT, 2, (elementary._DS1s, elementary._DS2s),
                  (elementary._DC2s, elementary._DC3s)),
    }  # fmt: skip
    rng = np.random.default_rng(0)
    for name, (dmax, n, s_lib, c_lib) in paths.items():
        zmax = mp.mpf(dmax) ** 2
        s_fit = fit(sin_target, lambda z: z, zmax, n)
        c_fit = fit(cos_target, lambda z: z * z, zmax, n)
        same = list(s_fit) == list(s_lib) and list(c_fit) == list(c_lib)
        print(f"{name} path, |d| <= {dmax}: S = {[repr(float(c)) for c in s_fit]}")
        print(f"  C = {[repr(float(c)) for c in c_fit]}  (elementary's: {same})")
        ds = [mp.mpf(x) for x in np.linspace(0, dmax, 2001)]
        es = max(abs(d + d**3 * sum(c * d ** (2 * k) for k, c in enumerate(s_fit)) - mp.sin(d))
                 for d in ds)  # fmt: skip
        ec = max(abs(1 - d**2 / 2 + d**4 * sum(c * d ** (2 * k) for k, c in enumerate(c_fit))
                     - mp.cos(d)) for d in ds)  # fmt: skip
        print(f"  largest error in exact arithmetic: sin {float(es):.2e}, cos {float(ec):.2e}")
        print("  band of |d|      mean error of the float32 evaluation (correctly rounded)")
        edges = [0, 0.03, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5]
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            if hi > dmax + 1e-12:
                break
            d = rng.uniform(lo, hi, 2_000_000).astype(np.float32)
            s, c = (a.astype(np.float64) for a in elementary.sincos_drift_array(d, name == "short"))
            x = d.astype(np.float64)
            sr, cr = (a.astype(np.float32).astype(np.float64) for a in (np.sin(x), np.cos(x)))
            errs = [
                (np.mean(s - np.sin(x)), np.mean(sr - np.sin(x))),
                (np.mean(c - np.cos(x)), np.mean(cr - np.cos(x))),
                (np.mean(s * s + c * c - 1), np.mean(sr * sr + cr * cr - 1)),
            ]
            print(
                f"  [{lo:4.2f}, {hi:4.2f}]"
                + "".join(
                    f"  {name} {m:+.1e} ({m_ref:+.1e})"
                    for name, (m, m_ref) in zip(("sin", "cos", "norm"), errs, strict=True)
                )
            )


if __name__ == "__main__":
    main()
