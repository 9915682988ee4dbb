"""What every layout shares: the `variable` helper (named dimensions, units and a long name on
every variable, its physical range as CF valid_min / valid_max), the ranges, the units of N*D and
of the actions, and CF flag words."""

from __future__ import annotations

import re

import numpy as np
import xarray as xr

from ..io import cf_units

__all__ = [
    "variable",
    "flag_word",
    "NONNEGATIVE",
    "UNIT_INTERVAL",
    "COMPONENT",
    "ENERGY_PER_PARTICLE",
    "D_UNITS",
    "ACTION",
]

D_UNITS = "action^2 / time (N * D, the 1/N factored out)"
ACTION = "action (dimensionless HMF units)"


#: physical ranges of the values (`variable`'s keyword `valid`): only true bounds, which no
#: legitimate result can cross
NONNEGATIVE = (0, None)  # counts, sums of squares, densities f, D_dif, errors, actions, ...
UNIT_INTERVAL = (0, 1)  # M0, |M|, probabilities, flags 0/1
COMPONENT = (-1, 1)  # Mx, My, Fourier coefficients of cos and sin theta
#: energy per particle of the interacting system: H/N = <p^2>/2 - M^2/2 >= -1/2
ENERGY_PER_PARTICLE = (-0.5, None)


def variable(dims, data, units, long_name, valid=None, **attrs):
    """A netCDF variable with named dimensions, units and long_name (and any other attributes).

    valid: (lo, hi), the physical range of the values (None for an open side), stored as the
    CF attributes valid_min / valid_max in the variable's type; `io.read_dataset` refuses a
    file holding a value outside it (NaN, a masked value, is not outside).

    units: CF units ("1", "rad") or an HMF quantity of `io.HMF_UNITS` (stored as "1" with the
    quantity in `comment`); any other string is refused (ValueError, `io.cf_units`)."""
    attrs = cf_units(units, attrs)
    if valid is not None:
        kind = np.asarray(data).dtype.type
        for key, bound in zip(("valid_min", "valid_max"), valid, strict=True):
            if bound is not None:
                attrs[key] = kind(bound)
    return xr.Variable(dims, data, {"long_name": long_name, **attrs})


def flag_word(meaning):
    """A flag meaning as one CF word (CF 3.5: letters, digits and _ - . + @; blanks separate)."""
    return re.sub(r"[^A-Za-z0-9_.+@-]+", "_", meaning).strip("_")
