"""Why the evolution with the grid's innermost node at |kappa - 1| = 1e-64 does not advance:
the backward-Euler steps' Newton iterations, logged.

    python studies/newton_deep_layer.py SECONDS ETA_MIN

Evolves ch2* by the Landau equation (studies/separatrix_layer.py's settings, layer_eta_min =
ETA_MIN) for SECONDS of wall time, wrapping `kinetic.relaxation._backward_euler_offsets`, and
prints the number of Newton solves, how many failed to converge, the mean time per solve and the
step sizes dt (and whether each converged) of the last twelve solves.  One core.
"""

from __future__ import annotations

import signal
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import separatrix_layer as sl  # noqa: E402

import hmfdiff.kinetic.relaxation as R  # noqa: E402
from hmfdiff.kinetic.relaxation import RelaxationSettings  # noqa: E402

LOG = []
_solve = R._backward_euler_offsets


def _logged(op, vol, level0, d0, dt, gauge, scales, tol=1e-13, max_iter=50, **kw):
    t = time.perf_counter()
    out = _solve(op, vol, level0, d0, dt, gauge, scales, tol, max_iter, **kw)
    LOG.append((dt, out[2], time.perf_counter() - t))
    return out


def report(*_):
    a = np.array(LOG)
    print(
        f"Newton solves {len(a)}, not converged {int((a[:, 1] == 0).sum())}, "
        f"mean {a[:, 2].mean():.3f} s each"
    )
    print("last dt:", " ".join(f"{x:.3e}" for x in a[-12:, 0]))
    print("converged:", " ".join(str(int(x)) for x in a[-12:, 1]))
    sys.exit(0)


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    seconds, eta = int(argv[0]), float(argv[1])
    R._backward_euler_offsets = _logged
    signal.signal(signal.SIGALRM, report)
    signal.alarm(seconds)
    spec, kappa_max = sl.CASES["ch2"]
    settings = RelaxationSettings(
        equation="landau", kappa_max=kappa_max, **{**sl.BASE, "layer_eta_min": eta}
    )
    print(f"ch2 landau layer_eta_min = {eta:g}, {seconds} s of wall time")
    R.evolve(sl.make_state(spec), settings)
    report()


if __name__ == "__main__":
    main(sys.argv[1:])
