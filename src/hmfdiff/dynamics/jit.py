"""The numba settings of the cached MD kernels: `njit`, numba's with `cache=True` exactly when
`kernel_cache.use_kernel_cache` has pointed this process at a private cache directory.

Its own module, importing no kernel, so that the kernel modules (elementary, integrator,
accumulator, exact_bath) can import it while `kernel_cache` imports the kernels to compile them
(`kernel_cache.warm`): the settings sit below the kernels, the cache warming above them.
"""

from __future__ import annotations

import os

__all__ = ["ENABLE", "njit"]

ENABLE = "HMFDIFF_KERNEL_CACHE"  # set (to the private cache directory) when caching is on


def njit(*args, **kwargs):
    """numba.njit with cache=True when `use_kernel_cache` has run in this process."""
    import numba

    kwargs.setdefault("cache", bool(os.environ.get(ENABLE)))
    return numba.njit(*args, **kwargs)
