"""Molecular dynamics of the HMF model: the settings of a run (settings), sampling of initial
conditions, elementary kernels, the velocity-Verlet integrator, the <dJ^2> accumulator and the
MD(bath) / MD(full) driver (md).
"""

import os

# The kernels synchronise all threads at every time step.  With OpenMP's default active
# waiting, a thread that loses its core to another process stalls the others, which then spin:
# on this 2-core machine with a competing process, 2 threads fell from 1.6e8 to 7e7
# particle-steps/s.  Passive waiting (set only if the user has not chosen) avoids the collapse;
# it must be set before the OpenMP runtime starts, i.e. before the first parallel kernel runs.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
