"""A conservative discretisation of the Landau and Lenard-Balescu collision operators (eq. hmflb)
on a grid of rescaled actions J-bar.

Continuous form.  In J-bar (J/2 librating, J rotating; phase-space volume 4 pi dJ-bar on both
sides of the separatrix) a librating harmonic n acts as n/2, and d/dJ-bar = Omega-bar d/dh with
Omega-bar = dh/dJ-bar, so on the resonance n Omega = n' Omega' = omega the bracket of eq. hmflb
is k d/dJ-bar - k' d/dJ-bar' = omega (d/dh - d/dh').  For any test function phi(J-bar),

    d/dtau int phi f 4 pi dJ-bar
        = -16 pi^3 sum_{n,n'>0} int int dJ-bar dJ-bar' B_nn' delta(n Omega - n' Omega')
              X[phi] X[ln f] f f',          X[g] = omega (dg/dh - dg/dh'),

with B_nn' = c_n^2 c'_n'^2/|eps_cc(omega)|^2 + sigma_n^2 sigma'_n'^2/|eps_ss(omega)|^2
(eps = 1: Landau), tau = t/N; the factor 16 pi^3 = 4 pi x 2 pi^2 x 2 (the kernel of eq. hmflb in
J-bar) x 1/2 (symmetrisation) x 2 (the mirror terms -n, -n').  phi = 1 (mass) and phi = h
(energy) are conserved, phi = -ln f gives dS/dtau >= 0, and a thermal f = C exp(-beta h) has
X[ln f] = 0.  The current G-bar = G/2 (librating), G (rotating) is continuous at the
separatrix: the current leaving the libration band splits equally into the two directions of
rotation.

Discrete form.  Nodes J-bar_i carry masses m_i = 4 pi w_i f_i (w_i the cell widths); face a is
the dual cell [J-bar_a, J-bar_{a+1}], with the discrete derivative
(d g/dh)_a = (g_{a+1} - g_a)/(h_{a+1} - h_a).  The delta function is integrated over frequency,
int int dJ dJ' delta(n Omega - n' Omega') g = int domega rho_n(omega) rho'_n'(omega) g
(rho: J-bar per unit frequency), with the exact orbital frequency at the ends of sub-cells of
every face (`_subcells`, graded towards the moving separatrix where Omega -> 0
logarithmically) and a uniform density on each; an *event* e is a pair of faces (a, b) (by test
harmonic n) whose sub-cells resonate, with

    W_e = 16 pi^3 sum over resonant sub-cell pairs of B int omega^2 rho rho' domega,
    X_e[g] = (dg/dh)_a - (dg/dh)_b,
    F_e = exp(ln f interpolated where the resonances sit in faces a and b).

Then dm/dtau = -X^T (W F X[ln f]): mass and energy (sum m h at fixed M0) are conserved to
rounding, sum_e W F X[ln f]^2 >= 0 is the entropy production for any W >= 0, and a thermal f
has X[ln f] = 0 exactly.  Every face receives its share of every resonance from both sides,
so the current converges pointwise (to a few per cent at 300 nodes, see the tests).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from ..meanfield import orbits
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag

__all__ = ["Geometry", "Events", "geometry", "resonance_events", "CollisionOperator"]

#: 16 pi^3: 4 pi (phase volume per J-bar) x 4 pi^2 (kernel) x 1/2 (symmetrisation) x 2 (n, n' < 0)
KERNEL = 16.0 * np.pi**3
#: faces closer than this to the separatrix (in kappa) are moved to 1 -+ this
SEPARATRIX_GUARD = 1e-12


@dataclass(frozen=True)
class Geometry:
    """The grid's orbits at one magnetisation M0 (nodes i, faces a between nodes a and a+1)."""

    M0: float
    jbar: np.ndarray  # (N,) node J-bar
    h: np.ndarray  # (N,) node energies
    kappa: np.ndarray  # (N,) node kappa
    xi: np.ndarray  # (N-1,) face J-bar (midpoints)
    dj: np.ndarray  # (N-1,) node spacing J-bar_{a+1} - J-bar_a
    s: np.ndarray  # (N-1,) 2 on librating faces, 1 on rotating faces
    nu: np.ndarray  # (N-1,) discrete physical frequency (h_{a+1} - h_a)/(s_a dj_a)
    kappa_face: np.ndarray  # (N-1,) kappa at the face position

    @property
    def D(self):
        """Face difference operator (N-1, N): (Dg)_a = (g_{a+1} - g_a)/dj_a."""
        n = self.jbar.size
        inv = 1.0 / self.dj
        rows = np.repeat(np.arange(n - 1), 2)
        cols = np.stack([np.arange(n - 1), np.arange(1, n)], axis=1).ravel()
        vals = np.stack([-inv, inv], axis=1).ravel()
        return sparse.csr_matrix((vals, (rows, cols)), shape=(n - 1, n))


def geometry(jbar, M0):
    """Orbits of the grid nodes and faces at magnetisation M0."""
    jbar = np.asarray(jbar, dtype=float)
    kappa = orbits.kappa_from_rescaled_action(jbar, M0)
    h = orbits.energy_from_kappa(kappa, M0)
    xi = 0.5 * (jbar[1:] + jbar[:-1])
    dj = np.diff(jbar)
    lib = xi < orbits.jbar_separatrix(M0)
    s = np.where(lib, 2.0, 1.0)
    nu = np.diff(h) / (s * dj)
    kf = orbits.kappa_from_rescaled_action(xi, M0)
    near = np.abs(kf - 1.0) < SEPARATRIX_GUARD
    kf = np.where(near, np.where(lib, 1.0 - SEPARATRIX_GUARD, 1.0 + SEPARATRIX_GUARD), kf)
    if not np.all(nu > 0):
        raise FloatingPointError("the grid's discrete frequencies must be positive")
    return Geometry(float(M0), jbar, h, kappa, xi, dj, s, nu, kf)


@dataclass(frozen=True)
class Events:
    """Resonant pairs of faces (a, b) and, per elementary resonance o (a pair of resonant
    sub-cells over a frequency interval), its event, frequency and bare weights."""

    a: np.ndarray  # (E,) test face
    b: np.ndarray  # (E,) partner face
    C: sparse.csr_matrix  # (E, N-1): X_e = C D
    P: sparse.csr_matrix  # (E, N): ln F_e = P ln f (ln f where the resonances sit in a and b)
    event: np.ndarray  # (O,) event of each elementary resonance
    omega: np.ndarray  # (O,) its frequency n Omega = n' Omega' (interval midpoint)
    bare_cc: np.ndarray  # (O,) 16 pi^3 c_n^2 c'_n'^2 int omega^2 rho rho' domega
    bare_ss: np.ndarray  # (O,) the same with sigma_n^2 sigma'_n'^2

    @property
    def size(self):
        return self.a.size

    def weights(self, eps=None):
        """W_e = sum over the event's resonances of bare_cc/|eps_cc|^2 + bare_ss/|eps_ss|^2;
        eps: None (Landau, eps = 1) or a callable omega -> (eps_cc, eps_ss)."""
        if eps is None:
            w = self.bare_cc + self.bare_ss
        else:
            e_cc, e_ss = eps(self.omega)
            w = self.bare_cc / np.abs(e_cc) ** 2 + self.bare_ss / np.abs(e_ss) ** 2
        return np.bincount(self.event, weights=w, minlength=self.a.size)


def _subcells(geom, m, m_sep):
    """Split every face's dual cell [J-bar_a, J-bar_{a+1}] into sub-cells on which the orbital
    frequency is monotone and nearly linear: m equal parts, or, for the face that contains the
    separatrix, m_sep parts on each side graded geometrically towards J-bar_s (where
    Omega -> 0 logarithmically).  Returns a dict of sub-cell arrays: face, branch (0 librating,
    1 rotating), frequency at both ends, length in J-bar, kappa at the midpoint."""
    js = orbits.jbar_separatrix(geom.M0)
    lo_j, hi_j = geom.jbar[:-1], geom.jbar[1:]
    sep = np.flatnonzero((lo_j <= js) & (js <= hi_j))
    edges, face = [], []
    t = np.linspace(0.0, 1.0, m + 1)
    for a in range(lo_j.size):
        if a in sep:
            below = js - np.geomspace(max(js - lo_j[a], 1e-300), 1e-12 * js, m_sep)
            above = js + np.geomspace(1e-12 * js, max(hi_j[a] - js, 1e-300), m_sep)
            pts = np.unique(np.concatenate(([lo_j[a]], below, [js], above, [hi_j[a]])))
        else:
            pts = lo_j[a] + t * geom.dj[a]
        edges.append(np.stack([pts[:-1], pts[1:]], axis=1))
        face.append(np.full(pts.size - 1, a))
    edges = np.concatenate(edges)
    face = np.concatenate(face)
    jb = np.unique(edges.ravel())
    with np.errstate(all="ignore"):
        kb = orbits.kappa_from_rescaled_action(jb, geom.M0)
        om = np.where(jb == js, 0.0, orbits.frequency(kb, geom.M0))
    i0 = np.searchsorted(jb, edges[:, 0])
    i1 = np.searchsorted(jb, edges[:, 1])
    mid = 0.5 * (edges[:, 0] + edges[:, 1])
    with np.errstate(all="ignore"):
        kappa_mid = orbits.kappa_from_rescaled_action(mid, geom.M0)
    theta = (mid - geom.jbar[face]) / geom.dj[face]
    return {
        "face": face,
        "theta": theta,
        "branch": (mid > js).astype(int),
        "om0": om[i0],
        "om1": om[i1],
        "length": edges[:, 1] - edges[:, 0],
        "kappa": kappa_mid,
    }


def _branch_partition(sub, branch):
    """Sub-cells of one branch sorted by frequency: (indices, boundaries (P+1,))."""
    idx = np.flatnonzero(sub["branch"] == branch)
    lo = np.minimum(sub["om0"][idx], sub["om1"][idx])
    hi = np.maximum(sub["om0"][idx], sub["om1"][idx])
    order = np.argsort(lo)
    idx, lo, hi = idx[order], lo[order], hi[order]
    return idx, np.concatenate((lo, hi[-1:]))


def _overlaps(part_t, part_p, n, npr):
    """Elementary intervals of the common refinement of n x (test partition) and n' x (partner
    partition): (test sub-cell, partner sub-cell, overlap's lower and upper omega)."""
    (it, bt), (ip, bp) = part_t, part_p
    st, sp = n * bt, npr * bp
    lo, hi = max(st[0], sp[0]), min(st[-1], sp[-1])
    if hi <= lo:
        return np.zeros(0, int), np.zeros(0, int), np.zeros(0), np.zeros(0)
    pts = np.unique(np.concatenate((st, sp)))
    pts = pts[(pts >= lo) & (pts <= hi)]
    mid = 0.5 * (pts[1:] + pts[:-1])
    kt = np.clip(np.searchsorted(st, mid) - 1, 0, it.size - 1)
    kp = np.clip(np.searchsorted(sp, mid) - 1, 0, ip.size - 1)
    return it[kt], ip[kp], pts[:-1], pts[1:]


def resonance_events(geom, n_max, m=4, m_sep=24):
    """Every pair of faces in resonance n Omega = n' Omega' (1 <= n, n' <= n_max) (`Events`).

    The measure int int dJ-bar dJ-bar' delta(n Omega - n' Omega') and the Fourier coefficients
    are integrated over sub-cells (`_subcells`) with a uniform J-bar density per unit frequency
    on each; the dielectric factor is applied per elementary resonance (`Events.weights`).
    """
    sub = _subcells(geom, m, m_sep)
    width = np.abs(sub["om1"] - sub["om0"])
    if not np.all(width > 0):
        raise FloatingPointError("a sub-cell of the grid has an empty frequency range")
    ns = np.arange(1, n_max + 1)
    c2 = cos_coefficient(ns[:, None], sub["kappa"][None, :]) ** 2  # (n_max, n_sub)
    s2 = sin_coefficient_imag(ns[:, None], sub["kappa"][None, :]) ** 2
    parts = [_branch_partition(sub, b) for b in (0, 1)]
    nf = geom.nu.size
    keys, vcc, vss, tha, thb, oms = [], [], [], [], [], []
    for n in range(1, n_max + 1):
        for npr in range(1, n_max + 1):
            for bt in (0, 1):
                for bp in (0, 1):
                    if n == npr and bt == bp:
                        continue  # only the trivial J' = J resonance
                    t, p, lo, hi = _overlaps(parts[bt], parts[bp], n, npr)
                    ft, fp = sub["face"][t], sub["face"][p]
                    keep = ft != fp
                    t, p, lo, hi, ft, fp = t[keep], p[keep], lo[keep], hi[keep], ft[keep], fp[keep]
                    dens = sub["length"][t] * sub["length"][p] / (n * width[t] * npr * width[p])
                    # int omega^2 domega over the overlap (X = omega (d ln f/dh - d ln f'/dh))
                    meas = dens * (hi**3 - lo**3) / 3.0
                    keys.append(ft * nf + fp)
                    oms.append(0.5 * (lo + hi))
                    vcc.append(meas * c2[n - 1, t] * c2[npr - 1, p])
                    vss.append(meas * s2[n - 1, t] * s2[npr - 1, p])
                    tha.append(sub["theta"][t])
                    thb.append(sub["theta"][p])
    keys = np.concatenate(keys)
    uk, inv = np.unique(keys, return_inverse=True)
    vcc, vss = np.concatenate(vcc), np.concatenate(vss)
    # where in each face the resonances sit on average (f is sampled there)
    wt = vcc + vss
    wsum = np.bincount(inv, weights=wt)
    wsum = np.where(wsum > 0, wsum, 1.0)
    theta_a = np.bincount(inv, weights=wt * np.concatenate(tha)) / wsum
    theta_b = np.bincount(inv, weights=wt * np.concatenate(thb)) / wsum
    a, b = np.divmod(uk, nf)
    dh = geom.s * geom.nu * geom.dj  # h_{a+1} - h_a
    E = a.size
    rows = np.repeat(np.arange(E), 2)
    cols = np.stack([a, b], axis=1).ravel()
    cvals = np.stack([geom.dj[a] / dh[a], -geom.dj[b] / dh[b]], axis=1).ravel()
    C = sparse.csr_matrix((cvals, (rows, cols)), shape=(E, nf))
    r4 = np.repeat(np.arange(E), 4)
    c4 = np.stack([a, a + 1, b, b + 1], axis=1).ravel()
    p4 = np.stack([1.0 - theta_a, theta_a, 1.0 - theta_b, theta_b], axis=1).ravel()
    P = sparse.csr_matrix((p4, (r4, c4)), shape=(E, nf + 1))
    if not (np.all(np.isfinite(vcc)) and np.all(np.isfinite(vss))):
        raise FloatingPointError("non-finite resonance weight on the grid")
    return Events(a, b, C, P, inv, np.concatenate(oms), KERNEL * vcc, KERNEL * vss)


class CollisionOperator:
    """dm/dtau = -X^T (W F X[ln f]) for one geometry, resonance set and dielectric factor.

    eps : None (Landau) or a callable omega -> (eps_cc, eps_ss) (Lenard-Balescu), evaluated at
    the frequency of every elementary resonance.
    """

    def __init__(self, geom, events, eps=None):
        self.geom = geom
        self.events = events
        ev = events
        self.W = ev.weights(eps)
        self.D = geom.D
        self.X = (ev.C @ self.D).tocsr()  # (E, N)
        self.P = ev.P
        self.XT = self.X.T.tocsr()

    def _parts(self, y):
        F = np.exp(self.P @ y)
        Xy = self.X @ y
        return F, Xy

    def rate(self, y):
        """dm/dtau at ln f = y (mass per node per unit tau)."""
        F, Xy = self._parts(y)
        return -(self.XT @ (self.W * F * Xy))

    def jacobian(self, y):
        """d(rate)/dy as a sparse (N, N) matrix."""
        F, Xy = self._parts(y)
        WF = self.W * F
        J = self.XT @ sparse.diags(WF) @ self.X + self.XT @ sparse.diags(WF * Xy) @ self.P
        return -J

    def face_flux(self, y):
        """Number flux 4 pi G-bar through each face a (towards larger J-bar)."""
        F, Xy = self._parts(y)
        q = self.events.C.T @ (self.W * F * Xy)
        return -q / self.geom.dj

    def entropy_production(self, y):
        """dS/dtau = sum_e W F X[ln f]^2 >= 0."""
        F, Xy = self._parts(y)
        return float(np.sum(self.W * F * Xy**2))
