"""How much the linear dressed spectrum of a thermal state moves with its magnetisation: can a
misplaced or fluctuating M0 make the MD's field look weaker than the theory's?

    python studies/dressing_sensitivity.py [U] [OUT]

At u = 0.2475 (1 % below the critical energy) MD(full)'s N S_x over omega = 0.1-0.4, where the
dressing multiplies the bare spectrum by about 15, is about 0.89 of the linear dressed theory
at N = 1e6 and 4e6 (docs/findings.md).  MD(full)'s <|M|> differs from M0 by up to 2.5 % per
realisation at N = 1e6 (studies/separatrix_bins.py).  This prints, for thermal states whose
M0 is that of U times 0.970 ... 1.030 (beta from the Bessel self-consistency at each M0), the
dressed N S_x = S_bare / |eps_cc|^2 (`kinetic.spectrum.dressed_spectrum`) integrated over the
bands 0.1-0.2, 0.2-0.4, 0.1-0.4 and 0.4-0.8, relative to the state's own, and the mean of the
+-offsets (what a symmetric scatter of M0 over realisations gives to second order).
"""

from __future__ import annotations

import sys

import numpy as np
from _realisations import emit

from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.kinetic.spectrum import dressed_spectrum
from hmfdiff.meanfield import equilibrium

BANDS = ((0.1, 0.2), (0.2, 0.4), (0.1, 0.4), (0.4, 0.8))
SCALES = (0.97, 0.985, 1.0, 1.015, 1.03)


def band_powers(M0, omega):
    """The dressed N S_x of the thermal state of magnetisation M0, integrated over each band."""
    state = equilibrium.ThermalState(M0=M0)
    dressed = dressed_spectrum(state, omega, DielectricTensor(state))
    out = []
    for lo, hi in BANDS:
        inside = (omega >= lo) & (omega <= hi)
        out.append(float(np.trapezoid(dressed[inside], omega[inside])))
    return np.array(out)


def main(u=0.2475, out=None):
    u = float(u)
    M0 = equilibrium.thermal_M0_from_energy(u)
    omega = np.linspace(0.05, 0.85, 1601)
    power = {s: band_powers(s * M0, omega) for s in SCALES}
    names = "  ".join(f"{lo}-{hi}" for lo, hi in BANDS)
    lines = [
        "# Dressed N S_x band powers against M0 (studies/dressing_sensitivity.py), relative to",
        f"# the state's own: thermal u = {u}, M0 = {M0:.6f}; bands (omega): {names}",
    ]
    for s in SCALES:
        cells = "  ".join(
            f"{lo}-{hi}: {v:.3f}" for (lo, hi), v in zip(BANDS, power[s] / power[1.0], strict=True)
        )
        lines.append(f"M0 x {s:.3f}: {cells}")
    for d in (0.015, 0.03):
        mean = 0.5 * (power[1.0 - d] + power[1.0 + d]) / power[1.0]
        cells = "  ".join(f"{lo}-{hi}: {v:.3f}" for (lo, hi), v in zip(BANDS, mean, strict=True))
        lines.append(f"mean of M0 x (1 -+ {d}): {cells}")
    emit(lines, out)


if __name__ == "__main__":
    if len(sys.argv) > 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
