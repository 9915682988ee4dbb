"""Equilibrium (Vlasov-stationary) states f(h) of the HMF model and their self-consistency.

f is normalised to one particle: int f(theta, p) dtheta dp = 1.  Every stationary state is a
function of the one-particle energy h = p^2/2 - M0 cos(theta) = M0 (2 kappa^2 - 1), so it is
stored and evaluated as a function of kappa.  Integrals over phase space go through
`PhaseSpaceQuadrature`, which counts the two directions of rotation of every rotating kappa
(the paper's eq. gaussian-def and its integrals count them once; that is an erratum).

States:

* `ThermalState`: f = C exp(-beta h), eq. (hmfeq), with beta from M0 = I1(beta M0)/I0(beta M0)
  (eq. mageq) and energy per particle u = 1/(2 beta) - M0^2/2 (no +1/2 constant in H).
* `CoreHaloState`: the smooth two-Fermi core-halo f_ch* of eq. (hmffch), or the two-step limit
  of eq. (hmffch2) (`shape="step"`), with its M0 solved self-consistently and f normalised.
"""

from __future__ import annotations

import numpy as np
from scipy import special

from . import orbits
from .fourier import cos_coefficient

__all__ = [
    "U_CRITICAL",
    "EquilibriumError",
    "thermal_beta",
    "thermal_energy",
    "thermal_M0_from_energy",
    "PhaseSpaceQuadrature",
    "ThermalState",
    "CoreHaloState",
    "make_state",
]

#: Critical energy of the thermal magnetised branch (beta -> 2, M0 -> 0) without the +1/2 in H.
U_CRITICAL = 0.25
#: Lowest energy per particle (all particles at rest at theta = 0, M0 = 1).
U_MINIMUM = -0.5


class EquilibriumError(ValueError):
    """A parameter of an equilibrium state outside its allowed range, or no solution."""


def _check_M0(M0, name="M0"):
    if not np.isfinite(M0) or not 0.0 < M0 < 1.0:
        raise EquilibriumError(f"{name} = {M0!r} is outside the allowed range 0 < M0 < 1")


def _bessel_ratio(x):
    """I1(x)/I0(x), overflow-free (exponentially scaled Bessel functions)."""
    return special.ive(1, x) / special.ive(0, x)


def thermal_beta(M0):
    """Inverse temperature of the thermal state with magnetisation M0, eq. (mageq).

    Solves M0 = I1(beta M0)/I0(beta M0) for x = beta M0 (I1/I0 increases from 0 to 1), accurate
    to ~1e-14 relative for 1e-3 <= M0 <= 0.999 and beyond.
    """
    _check_M0(M0)
    # bracket: I1/I0(x) ~ 1 - 1/(2x) at large x, so x = 1/(1 - M0) + 2 lies above the root
    hi = 1.0 / (1.0 - M0) + 2.0
    from scipy import optimize  # here: 0.3 s of import that rule orbits never needs

    x = optimize.brentq(lambda x: _bessel_ratio(x) - M0, 1e-300, hi, xtol=1e-300, rtol=1e-15)
    return x / M0


def thermal_energy(M0):
    """Energy per particle u = 1/(2 beta) - M0^2/2 of the thermal state with magnetisation M0."""
    return 0.5 / thermal_beta(M0) - 0.5 * M0**2


def thermal_M0_from_energy(u):
    """Magnetisation of the thermal (magnetised) state with energy per particle u.

    u(M0) decreases monotonically from 1/4 (M0 -> 0) to -1/2 (M0 -> 1); outside that range no
    magnetised thermal state exists.
    """
    if not np.isfinite(u) or not U_MINIMUM < u < U_CRITICAL:
        raise EquilibriumError(
            f"u = {u!r} has no magnetised thermal state: the allowed range is "
            f"{U_MINIMUM} < u < {U_CRITICAL} (u = 1/(2 beta) - M0^2/2)"
        )
    lo, hi = 1e-9, 1.0 - 1e-9
    if thermal_energy(lo) <= u:  # so close to u_c that M0 < 1e-9
        raise EquilibriumError(f"u = {u!r} is too close to u_c = 1/4: M0 would be below 1e-9")
    if thermal_energy(hi) >= u:
        raise EquilibriumError(f"u = {u!r} is too close to -1/2: M0 would exceed 1 - 1e-9")
    from scipy import optimize

    return optimize.brentq(lambda m: thermal_energy(m) - u, lo, hi, xtol=1e-15, rtol=1e-15)


class PhaseSpaceQuadrature:
    """Nodes and weights for int dtheta dp g(h(theta, p)) as a sum over kappa.

    int dtheta dp g = 2 pi int_0^1 g dJ/dkappa dkappa + 2 * 2 pi int_1^kmax g dJ/dkappa dkappa,
    the factor 2 counting both directions of rotation.  Composite Gauss-Legendre on panels that
    are graded geometrically towards the separatrix (where dJ/dkappa diverges logarithmically)
    and that break at `breaks` (steps or steep edges of f).
    """

    def __init__(self, M0, kappa_max, breaks=(), order=24, grading=12):
        _check_M0(M0)
        edges = [0.0, 1.0, kappa_max]
        edges += [1.0 - 10.0 ** (-j) for j in range(1, grading)]
        edges += [1.0 + 10.0 ** (-j) for j in range(1, grading) if 1.0 + 10.0 ** (-j) < kappa_max]
        edges += [b for b in breaks if 0.0 < b < kappa_max]
        edges += list(np.linspace(0.0, kappa_max, 64))
        edges = np.unique(np.asarray(edges, dtype=float))
        # no panel may be so thin (or so close to kappa = 1) that a node rounds onto kappa = 1
        edges = edges[(np.abs(edges - 1.0) > 10.0 ** (-grading)) | (edges == 1.0)]
        edges = edges[np.concatenate(([True], np.diff(edges) > 1e-12))]
        x, wx = np.polynomial.legendre.leggauss(order)
        a, b = edges[:-1, None], edges[1:, None]
        nodes = (0.5 * (b - a) * x + 0.5 * (a + b)).ravel()
        wts = (0.5 * (b - a) * wx).ravel()
        self.M0 = M0
        self.kappa = nodes
        self.weights = (
            wts * 2.0 * np.pi * orbits.phase_space_weight(nodes) * orbits.dJ_dkappa(nodes, M0)
        )

    def integrate(self, values):
        """Sum of values(kappa_k) * weight_k along the last axis."""
        return np.sum(np.asarray(values) * self.weights, axis=-1)


class ThermalState:
    """Maxwell-Boltzmann state f = C exp(-beta h) with magnetisation M0 (eqs. hmfeq, mageq)."""

    kind = "thermal"

    def __init__(self, M0=None, u=None):
        if (M0 is None) == (u is None):
            raise EquilibriumError("a thermal state takes exactly one of M0 or u")
        if M0 is None:
            M0 = thermal_M0_from_energy(u)
        _check_M0(M0)
        self.M0 = float(M0)
        self.beta = thermal_beta(self.M0)
        self.u = 0.5 / self.beta - 0.5 * self.M0**2
        x = self.beta * self.M0
        # log C = log sqrt(beta/(2 pi)^3) - log I0(x); I0 = ive(0, x) e^x
        self._logC = 0.5 * np.log(self.beta / (2.0 * np.pi) ** 3) - np.log(special.ive(0, x)) - x

    @property
    def params(self):
        return {"M0": self.M0}

    @property
    def kappa_max(self):
        """kappa beyond which f < 1e-20 f(0)."""
        return float(np.sqrt((46.0 + 2 * self.beta * self.M0) / (2.0 * self.beta * self.M0)))

    def f_energy(self, h):
        return np.exp(self._logC - self.beta * np.asarray(h, dtype=float))

    def f(self, kappa):
        """f(kappa) = C exp(-beta M0 (2 kappa^2 - 1)), eq. (gaussian-def)."""
        k = np.asarray(kappa, dtype=float)
        return np.exp(self._logC + self.beta * self.M0 * (1.0 - 2.0 * k**2))

    def dfdkappa(self, kappa):
        k = np.asarray(kappa, dtype=float)
        return -4.0 * self.beta * self.M0 * k * self.f(k)

    def quadrature(self, order=24):
        return PhaseSpaceQuadrature(self.M0, self.kappa_max, order=order)


class CoreHaloState:
    """Core-halo state: two Fermi functions of h (eq. hmffch) or two steps (eq. hmffch2).

    f_raw(h) = eta1 / (1 + exp(beta1 (h - mu1))) + eta2 / (1 + exp(beta2 (h - mu2)))
    (or eta1 Theta(mu1 - h) + eta2 Theta(mu2 - h) for shape="step").  M0 is the non-zero root of
    M0 = int cos(theta) f_raw / int f_raw (h depends on M0), f = f_raw / mass is normalised and
    `mass` = int f_raw dtheta dp is kept, since the paper's parameters need not give mass 1.

    For the two-step shape, the paper writes kappa_i = sqrt(mu_i/M0 + 1); with
    h = M0 (2 kappa^2 - 1) the step sits at kappa_i = sqrt((mu_i/M0 + 1)/2): eq. hmffch2k is
    right, the kappa_i below it lacks the factor 1/2.
    """

    kind = "core_halo"

    def __init__(self, eta1, eta2, mu1, mu2, beta1=None, beta2=None, shape="fermi", M0_guess=None):
        if shape not in ("fermi", "step"):
            raise EquilibriumError(f"shape = {shape!r}: must be 'fermi' or 'step'")
        self.shape = shape
        for name, val in (("eta1", eta1), ("eta2", eta2)):
            if not np.isfinite(val) or val < 0:
                raise EquilibriumError(f"{name} = {val!r} must be >= 0")
        if eta1 + eta2 <= 0:
            raise EquilibriumError("eta1 + eta2 must be > 0 (the state would be empty)")
        for name, val in (("mu1", mu1), ("mu2", mu2)):
            if not np.isfinite(val) or not -1.0 < val:
                raise EquilibriumError(f"{name} = {val!r} must be > -1 (h >= -M0 > -1)")
        if shape == "fermi":
            for name, val in (("beta1", beta1), ("beta2", beta2)):
                if val is None or not np.isfinite(val) or val <= 0:
                    raise EquilibriumError(f"{name} = {val!r} must be > 0 (inverse temperature)")
        self.eta = (float(eta1), float(eta2))
        self.mu = (float(mu1), float(mu2))
        self.betas = (float(beta1), float(beta2)) if shape == "fermi" else (np.inf, np.inf)
        self.M0 = self._solve_M0(M0_guess)
        self.mass = self._raw_integral(self.M0, lambda q: 1.0)
        if not self.mass > 0:
            raise EquilibriumError("the core-halo state has zero mass")
        mean_h = self._raw_integral(self.M0, self._h_of_kappa) / self.mass
        self.u = mean_h + 0.5 * self.M0**2  # u = <p^2>/2 - M0^2/2 = <h> + M0^2/2

    @property
    def params(self):
        d = {"eta1": self.eta[0], "eta2": self.eta[1], "mu1": self.mu[0], "mu2": self.mu[1]}
        if self.shape == "fermi":
            d.update(beta1=self.betas[0], beta2=self.betas[1])
        return d

    # f as a function of the energy ---------------------------------------------------------
    def _f_raw_energy(self, h):
        h = np.asarray(h, dtype=float)
        out = np.zeros_like(h)
        for eta, mu, b in zip(self.eta, self.mu, self.betas, strict=True):
            if self.shape == "step":
                out = out + eta * (h < mu)
            else:
                out = out + eta * special.expit(-b * (h - mu))
        return out

    def _df_raw_dh(self, h):
        h = np.asarray(h, dtype=float)
        out = np.zeros_like(h)
        if self.shape == "step":
            return out  # delta functions: see step_kappas / step_weights
        for eta, mu, b in zip(self.eta, self.mu, self.betas, strict=True):
            s = special.expit(-b * (h - mu))
            out = out - eta * b * s * (1.0 - s)
        return out

    def _h_max(self):
        return max(
            mu + (40.0 / b if np.isfinite(b) else 0.0)
            for mu, b in zip(self.mu, self.betas, strict=True)
        )

    def _kappa_max(self, M0):
        return float(np.sqrt(max(self._h_max() + M0, 0.0) / (2.0 * M0)) * 1.05 + 0.5)

    def _breaks(self, M0):
        br = []
        for mu, b in zip(self.mu, self.betas, strict=True):
            for d in [0.0] if not np.isfinite(b) else np.arange(-12, 13) * 1.0 / b:
                hh = mu + d
                if hh > -M0:
                    br.append(np.sqrt((hh + M0) / (2.0 * M0)))
        return br

    def _h_of_kappa(self, q):
        return orbits.energy_from_kappa(q.kappa, q.M0)

    def _raw_integral(self, M0, g):
        q = PhaseSpaceQuadrature(M0, self._kappa_max(M0), breaks=self._breaks(M0))
        return q.integrate(self._f_raw_energy(orbits.energy_from_kappa(q.kappa, M0)) * g(q))

    def _magnetisation_map(self, M0):
        """int cos(theta) f_raw / int f_raw with the potential of magnetisation M0."""
        num = self._raw_integral(M0, lambda q: cos_coefficient(0, q.kappa))
        den = self._raw_integral(M0, lambda q: 1.0)
        return num / den

    def _solve_M0(self, guess):
        from scipy import optimize

        g = lambda M: self._magnetisation_map(M) - M  # noqa: E731
        grid = np.linspace(0.01, 0.99, 50)
        vals = np.array([g(M) for M in grid])
        roots = []
        for i in np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:])):
            roots.append(optimize.brentq(g, grid[i], grid[i + 1], xtol=1e-14, rtol=1e-15))
        if not roots:
            raise EquilibriumError(
                f"no magnetised self-consistent solution M0 in (0.01, 0.99) for core-halo "
                f"parameters eta={self.eta}, mu={self.mu}, beta={self.betas}"
            )
        if guess is not None:
            return min(roots, key=lambda r: abs(r - guess))
        return max(roots)

    # f as a function of kappa (normalised) -----------------------------------------------
    def f(self, kappa):
        h = orbits.energy_from_kappa(kappa, self.M0)
        return self._f_raw_energy(h) / self.mass

    def f_energy(self, h):
        return self._f_raw_energy(h) / self.mass

    def dfdkappa(self, kappa):
        """df/dkappa = 4 M0 kappa df/dh (zero between the steps for the two-step shape)."""
        kappa = np.asarray(kappa, dtype=float)
        h = orbits.energy_from_kappa(kappa, self.M0)
        return 4.0 * self.M0 * kappa * self._df_raw_dh(h) / self.mass

    @property
    def step_kappas(self):
        """kappa_i = sqrt((mu_i/M0 + 1)/2) of the steps (two-step shape), eq. (hmffch2k)."""
        return np.sqrt((np.asarray(self.mu) / self.M0 + 1.0) / 2.0)

    @property
    def step_weights(self):
        """Weights w_i = eta_i / mass of df/dkappa = -sum_i w_i delta(kappa - kappa_i) (two steps).

        Eq. partial-ch, with delta[M0(kappa_i^2 - kappa^2)] = delta(kappa - kappa_i)/(2 M0 kappa_i).
        """
        return np.asarray(self.eta) / self.mass

    @property
    def kappa_max(self):
        return self._kappa_max(self.M0)

    def quadrature(self, order=24):
        return PhaseSpaceQuadrature(
            self.M0, self.kappa_max, breaks=self._breaks(self.M0), order=order
        )


def make_state(spec):
    """Build a state from a config case: {'kind': 'thermal', 'M0' or 'u'} or
    {'kind': 'core_halo', eta1, eta2, mu1, mu2, beta1, beta2} or
    {'kind': 'two_step', eta1, eta2, mu1, mu2}."""
    kind = spec.get("kind")
    if kind == "thermal":
        return ThermalState(M0=spec.get("M0"), u=spec.get("u"))
    if kind == "core_halo":
        return CoreHaloState(
            spec["eta1"],
            spec["eta2"],
            spec["mu1"],
            spec["mu2"],
            spec["beta1"],
            spec["beta2"],
            shape="fermi",
            M0_guess=spec.get("M0_guess"),
        )
    if kind == "two_step":
        return CoreHaloState(
            spec["eta1"],
            spec["eta2"],
            spec["mu1"],
            spec["mu2"],
            shape="step",
            M0_guess=spec.get("M0_guess"),
        )
    raise EquilibriumError(f"kind = {kind!r}: must be 'thermal', 'core_halo' or 'two_step'")
