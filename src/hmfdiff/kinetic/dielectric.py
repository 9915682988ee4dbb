"""Dielectric tensor of the inhomogeneous HMF model (eqs. hmfepscc, hmfepsss).

In the cos/sin basis the tensor is diagonal:

    eps_cc(omega) = 1 + 2 pi sum_{l != 0} int_0^inf dkappa W(kappa) c_l(kappa)^2 f'(kappa)
                                           / (Omega(kappa) - omega / l)

and the same with sigma_l^2 = |s_l|^2 for eps_ss, where f' = df/dkappa and W = 2 on rotating
orbits counts both directions of rotation (the paper counts them once: erratum).  Time goes as
exp(-i omega t) and the Landau prescription is omega -> omega + i0, so the pole of the l-th term
contributes + i pi sign(l) W c_l^2 f' / |Omega'| (never a literal residue: Omega' < 0 on
librating orbits).

Method.  On each monotonic branch of Omega(kappa) (libration: Omega decreases from
Omega_0 = sqrt(M0) to 0; rotation: Omega increases from 0) the integral is rewritten in the
variable Omega,

    int dkappa g(kappa) / (Omega(kappa) - x0) = int_0^A dOmega G(Omega) / (Omega - x0),
    G = g / |dOmega/dkappa|,

where G is smooth on the closed interval: it vanishes like exp(-pi sqrt(M0)/Omega) at the
separatrix (Omega -> 0) and like (Omega_0 - Omega)^|l| at the bottom of the well.  The principal
value is taken by subtracting the pole,

    PV int_0^A G/(Omega - x0) = int_0^A (G(Omega) - G(x0))/(Omega - x0) + G(x0) log((A - x0)/x0),

with a fixed composite Gauss-Legendre rule in Omega for the smooth remainder, so that the
integral is one matrix product over all frequencies at once.  G(x0) is evaluated exactly at
the pole kappa(x0).
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag

__all__ = ["DielectricTensor", "dielectric_tensor", "pole_density"]

_LIB, _ROT = 0, 1
#: frequencies per block of the quadrature's matrix (`DielectricTensor._branch_term`)
_BLOCK = 128


def _check_state(state):
    if getattr(state, "shape", "fermi") == "step":
        raise NotImplementedError(
            "the two-step core-halo state has df/dkappa made of delta functions: its dielectric "
            "tensor is the closed form of kinetic.analytic (eq. hmfepscc/ss-ch), not this module"
        )


def pole_density(state, kappa, l, component):
    """W(kappa) |coef_l(kappa)|^2 f'(kappa) / |dOmega/dkappa| (the function G of the module doc).

    component is 'cc' or 'ss'.  Points that round onto the separatrix (where G -> 0 faster than
    any power of 1 - kappa) return 0.
    """
    kappa = np.asarray(kappa, dtype=float)
    M0 = state.M0
    if component == "cc":
        coef2 = cos_coefficient(l, kappa) ** 2
    elif component == "ss":
        coef2 = sin_coefficient_imag(l, kappa) ** 2
    else:
        raise ValueError(f"component must be 'cc' or 'ss', got {component!r}")
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        dO = np.abs(orbits.dOmega_dkappa(kappa, M0))
        G = orbits.phase_space_weight(kappa) * coef2 * state.dfdkappa(kappa) / dO
    on_sep = np.abs(kappa - 1.0) < 1e-13
    return np.where(on_sep, 0.0, G)


def _state_breaks_kappa(state):
    """kappa of steep features of f (Fermi edges of a core-halo state), else empty."""
    mus = getattr(state, "mu", None)
    betas = getattr(state, "betas", None)
    if mus is None or betas is None:
        return []
    out = []
    for mu, b in zip(mus, betas, strict=True):
        for d in np.arange(-8, 9) / b:
            h = mu + d
            if h > -state.M0:
                out.append(np.sqrt((h + state.M0) / (2.0 * state.M0)))
    return out


class DielectricTensor:
    """Precomputed quadrature of eps_cc and eps_ss for one equilibrium state.

    Parameters
    ----------
    state : ThermalState or CoreHaloState (shape='fermi')
    l_max : truncation of the sum over l (the paper uses 6)
    n_panels, order : composite Gauss-Legendre rule in Omega on each branch
        (n_panels panels of `order` nodes, plus panel edges at the Fermi edges of a core-halo
        state; doubling it changes eps by < 1e-11 on the paper's states, and eps agrees with an
        independent scipy.quad principal value to < 3e-8, see tests/test_dielectric.py)
    kappa_max : upper end of the rotating branch (default: state.kappa_max, where f ~ 0)
    """

    def __init__(self, state, l_max=6, n_panels=48, order=20, kappa_max=None):
        _check_state(state)
        self.state = state
        self.M0 = M0 = state.M0
        self.l_max = int(l_max)
        self.n_panels = int(n_panels)
        self.order = int(order)
        self.kappa_max = float(state.kappa_max if kappa_max is None else kappa_max)
        Om0 = np.sqrt(M0)
        Omax = float(orbits.frequency(self.kappa_max, M0))
        self.A = (Om0, Omax)
        x, wx = np.polynomial.legendre.leggauss(self.order)
        breaks = _state_breaks_kappa(state)
        self._nodes = []
        for branch, A in ((_LIB, Om0), (_ROT, Omax)):
            edges = list(np.linspace(0.0, A, self.n_panels + 1))
            for kb in breaks:  # steep edges of f, mapped to Omega on this branch
                if (branch == _LIB and 0 < kb < 1) or (branch == _ROT and 1 < kb < self.kappa_max):
                    edges.append(float(orbits.frequency(kb, M0)))
            edges = np.unique(np.asarray(edges))
            a, b = edges[:-1, None], edges[1:, None]
            Om = (0.5 * (b - a) * x + 0.5 * (a + b)).ravel()
            w = (0.5 * (b - a) * wx).ravel()
            kap = self._kappa_of(Om, branch)
            Gcc = np.array([pole_density(state, kap, l, "cc") for l in range(1, self.l_max + 1)])
            Gss = np.array([pole_density(state, kap, l, "ss") for l in range(1, self.l_max + 1)])
            self._nodes.append((Om, w, Gcc, Gss))

    def _kappa_of(self, Om, branch):
        family = "libration" if branch == _LIB else "rotation"
        return orbits.kappa_from_frequency(Om, self.M0, family)

    def __call__(self, omega):
        """(eps_cc, eps_ss) at real frequencies omega (Landau prescription omega + i0)."""
        omega = np.asarray(omega, dtype=float)
        flat = omega.ravel()
        eps_cc = np.ones(flat.shape, dtype=complex)
        eps_ss = np.ones(flat.shape, dtype=complex)
        for branch in (_LIB, _ROT):
            Om, w, Gcc, Gss = self._nodes[branch]
            A = self.A[branch]
            for il, l in enumerate(range(1, self.l_max + 1)):
                for sgn in (1.0, -1.0):
                    x0 = flat / (sgn * l)
                    tcc, tss = self._branch_term(x0, sgn, Om, w, Gcc[il], Gss[il], A, branch, l)
                    eps_cc += 2.0 * np.pi * tcc
                    eps_ss += 2.0 * np.pi * tss
        return eps_cc.reshape(omega.shape), eps_ss.reshape(omega.shape)

    def upper_half_plane(self, z):
        """(eps_cc, eps_ss) at complex frequencies z with Im z > 0, where the integrands have no
        pole and eps is the plain quadrature (its analytic continuation from the real axis);
        accurate while Im z / l_max is well above the spacing of the Omega nodes."""
        z = np.asarray(z, dtype=complex)
        flat = z.ravel()
        eps_cc = np.ones(flat.shape, dtype=complex)
        eps_ss = np.ones(flat.shape, dtype=complex)
        for Om, w, Gcc, Gss in self._nodes:
            for il, l in enumerate(range(1, self.l_max + 1)):
                for sgn in (1.0, -1.0):
                    R = 1.0 / (Om[None, :] - flat[:, None] / (sgn * l))
                    eps_cc += 2.0 * np.pi * (R @ (w * Gcc[il]))
                    eps_ss += 2.0 * np.pi * (R @ (w * Gss[il]))
        return eps_cc.reshape(z.shape), eps_ss.reshape(z.shape)

    def _branch_term(self, x0, sgn, Om, w, Gcc, Gss, A, branch, l):
        """int_0^A G/(Omega - x0 - i0 sgn) dOmega for every x0, both components."""
        pole = (x0 > 0.0) & (x0 < A)
        # a frequency exactly on a node (measure zero) drops that node's term, an error of
        # order w_j G'(x0); the nodes increase, so such hits are found by bisection
        j = np.minimum(np.searchsorted(Om, x0), Om.size - 1)
        hit = Om[j] == x0
        # the three quadratures in one pass over R = 1/(Omega - x0): sum w R, sum w G_cc R,
        # sum w G_ss R, by blocks of frequencies that stay in cache
        V = np.column_stack([w, w * Gcc, w * Gss])
        sums = np.empty((x0.size, 3))
        for a in range(0, x0.size, _BLOCK):
            b = min(a + _BLOCK, x0.size)
            R = np.subtract(Om[None, :], x0[a:b, None])
            with np.errstate(divide="ignore"):
                np.divide(1.0, R, out=R)
            k = np.flatnonzero(hit[a:b])
            R[k, j[a:b][k]] = 0.0
            np.matmul(R, V, out=sums[a:b])
        sumw, tcc, tss = sums.T
        kp = np.full(x0.shape, np.nan)
        if np.any(pole):
            kp[pole] = self._kappa_of(x0[pole], branch)
        with np.errstate(divide="ignore", invalid="ignore"):
            logt = np.where(pole, np.log(np.abs(A - x0) / np.abs(x0)), 0.0)
        out = []
        for comp, t in (("cc", tcc), ("ss", tss)):
            t = t.astype(complex)
            if np.any(pole):
                G0 = np.zeros(x0.shape)
                G0[pole] = pole_density(self.state, kp[pole], l, comp)
                t = t - G0 * sumw + G0 * logt + 1j * np.pi * sgn * G0
            out.append(t)
        return out[0], out[1]


def dielectric_tensor(state, omega, l_max=6, **accuracy):
    """eps_cc(omega), eps_ss(omega) (eqs. hmfepscc, hmfepsss), complex arrays shaped like omega.

    omega is real; the Landau prescription omega -> omega + i0 is applied, so
    eps(-omega) = conj(eps(omega)).  accuracy: n_panels, order, kappa_max of `DielectricTensor`.
    """
    return DielectricTensor(state, l_max=l_max, **accuracy)(omega)
