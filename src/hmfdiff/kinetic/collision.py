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

Discrete form.  The grid's cells are fixed in eta = kappa - 1 (`grid.ActionGrid`); at
magnetisation M every J-bar scales as sqrt(M), energies h - M as M, frequencies as sqrt(M),
and the Fourier coefficients do not change.  So the geometry and the resonances are computed
once, in reduced units (M = 1), and scaled: the resonance condition n Omega = n' Omega' does
not depend on M.  Nodes i carry masses m_i = 4 pi w_i f_i (w_i the cell widths) and cell-
average energies h_i; face a is the dual cell between nodes a and a+1, with the discrete
derivative (d g/dh)_a = (g_{a+1} - g_a)/(h_{a+1} - h_a) (differences of h - M, formed from
eta without cancellation next to the separatrix).  The delta function is integrated over
frequency, int int dJ dJ' delta(n Omega - n' Omega') g = int domega rho_n(omega)
rho'_n'(omega) g (rho: J-bar per unit frequency), with the exact orbital frequency at the ends
of sub-cells of every face (`_subcells`: geometric in |eta| next to the separatrix, down to
1e-12 of the innermost node's |eta| and then to the separatrix itself, where Omega -> 0
logarithmically) and a uniform density on each; an *event* e is a pair of faces (a, b) (by
test harmonic n) whose sub-cells resonate, with

    W_e = 16 pi^3 sum over resonant sub-cell pairs of B int omega^2 rho rho' domega,
    X_e[g] = (dg/dh)_a - (dg/dh)_b,
    F_e = exp(ln f interpolated where the resonances sit in faces a and b).

Then dm/dtau = -X^T (W F X[ln f]): mass and energy (sum m h at fixed M) are conserved to
rounding, sum_e W F X[ln f]^2 >= 0 is the entropy production for any W >= 0, and a thermal f
has X[ln f] = 0 exactly.  At magnetisation M: W = M^(3/2) W^ (the bare weights), X = X^/M,
the dielectric factor taken at omega = sqrt(M) omega^.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from ..meanfield import separatrix
from ..meanfield.fourier import cos_coefficient_eta, sin_coefficient_imag_eta

__all__ = [
    "Geometry",
    "Events",
    "geometry",
    "resonance_events",
    "jacobian_assembly",
    "CollisionOperator",
]

#: 16 pi^3: 4 pi (phase volume per J-bar) x 4 pi^2 (kernel) x 1/2 (symmetrisation) x 2 (n, n' < 0)
KERNEL = 16.0 * np.pi**3
#: sub-cells of the separatrix face reach down to this fraction of its nodes' |eta|
SEPARATRIX_DEPTH = 1e-12


@dataclass(frozen=True)
class Geometry:
    """The grid's orbits in reduced units (M = 1; nodes i, faces a between nodes a and a+1)."""

    eta: np.ndarray  # (N,) node eta = kappa - 1
    xhat: np.ndarray  # (N,) node offset (J-bar - J-bar_s)/sqrt(M)
    eps: np.ndarray  # (N,) node (cell-average) energy (h - M)/M
    dj: np.ndarray  # (N-1,) node spacing in reduced J-bar
    s: np.ndarray  # (N-1,) 2 on librating faces, 1 on rotating faces
    nu: np.ndarray  # (N-1,) discrete reduced frequency (eps_{a+1} - eps_a)/(s_a dj_a)
    sep_face: int  # the face between the last librating and the first rotating node

    @property
    def D(self):
        """Face difference operator (N-1, N): (Dg)_a = (g_{a+1} - g_a)/dj_a (reduced)."""
        n = self.eta.size
        inv = 1.0 / self.dj
        rows = np.repeat(np.arange(n - 1), 2)
        cols = np.stack([np.arange(n - 1), np.arange(1, n)], axis=1).ravel()
        vals = np.stack([-inv, inv], axis=1).ravel()
        return sparse.csr_matrix((vals, (rows, cols)), shape=(n - 1, n))


def geometry(grid):
    """The reduced geometry of an `ActionGrid`."""
    eta = np.asarray(grid.eta, dtype=float)
    dj = np.diff(grid.xhat)
    lib = eta[1:] < 0.0  # the face lies below its upper node
    s = np.where(lib, 2.0, 1.0)
    nu = np.diff(grid.eps_hat) / (s * dj)
    if not (np.all(dj > 0) and np.all(nu > 0)):
        raise FloatingPointError("the grid's spacings and discrete frequencies must be positive")
    sep_face = int(np.flatnonzero((eta[:-1] < 0.0) & (eta[1:] > 0.0))[0])
    return Geometry(
        eta, np.asarray(grid.xhat, float), np.asarray(grid.eps_hat, float), dj, s, nu, sep_face
    )


@dataclass(frozen=True)
class Events:
    """Resonant pairs of faces (a, b) and, per elementary resonance o (a pair of resonant
    sub-cells over a frequency interval), its event, frequency and bare weights, in reduced
    units (M = 1)."""

    a: np.ndarray  # (E,) test face
    b: np.ndarray  # (E,) partner face
    C: sparse.csr_matrix  # (E, N-1): X_e = C D (reduced)
    P: sparse.csr_matrix  # (E, N): ln F_e = P ln f (ln f where the resonances sit in a and b)
    event: np.ndarray  # (O,) event of each elementary resonance
    omega: np.ndarray  # (O,) its reduced frequency n Omega = n' Omega' (interval midpoint)
    bare_cc: np.ndarray  # (O,) 16 pi^3 c_n^2 c'_n'^2 int omega^2 rho rho' domega (reduced)
    bare_ss: np.ndarray  # (O,) the same with sigma_n^2 sigma'_n'^2
    #: (E, N-1): which faces carry each event's current (None: C itself); 'mixed' reads
    #: d ln f/dh at the resonance (C, second order) and hands the current to the face the
    #: resonance lies in (A, the face's own quotient's row)
    A: sparse.csr_matrix | None = None

    @property
    def size(self):
        return self.a.size

    def weights(self, M, eps=None):
        """W_e at magnetisation M: M^(3/2) times the sum over the event's resonances of
        bare_cc/|eps_cc|^2 + bare_ss/|eps_ss|^2; eps: None (Landau, eps = 1) or a callable
        omega -> (eps_cc, eps_ss), evaluated at omega = sqrt(M) omega^."""
        if eps is None:
            w = self.bare_cc + self.bare_ss
        else:
            e_cc, e_ss = eps(np.sqrt(M) * self.omega)
            w = self.bare_cc / np.abs(e_cc) ** 2 + self.bare_ss / np.abs(e_ss) ** 2
        return M**1.5 * np.bincount(self.event, weights=w, minlength=self.a.size)


def _face_points(geom, m, m_sep):
    """Sub-cell edges (eta) of every face: m parts uniform in eta far from the separatrix and
    geometric in |eta| within grid.LOG_CELL of it; the separatrix face, m_sep parts on each
    side geometric from its nodes' |eta| down to SEPARATRIX_DEPTH of them, then to eta = 0."""
    from .grid import LOG_CELL

    lo, hi = geom.eta[:-1], geom.eta[1:]
    t = np.linspace(0.0, 1.0, m + 1)
    pts, face = [], []
    for a in range(lo.size):
        if a == geom.sep_face:
            below = -np.geomspace(-lo[a], -lo[a] * SEPARATRIX_DEPTH, m_sep)
            above = np.geomspace(hi[a] * SEPARATRIX_DEPTH, hi[a], m_sep)
            p = np.concatenate((below, [0.0], above))
        elif max(abs(lo[a]), abs(hi[a])) <= LOG_CELL:
            p = np.sign(lo[a]) * np.exp(np.log(abs(lo[a])) + t * np.log(hi[a] / lo[a]))
            p[0], p[-1] = lo[a], hi[a]
        else:
            p = lo[a] + t * (hi[a] - lo[a])
        pts.append(p)
        face.append(np.full(p.size - 1, a))
    return pts, np.concatenate(face)


def _subcells(geom, m, m_sep):
    """Split every face's dual cell [node a, node a+1] into sub-cells on which the orbital
    frequency is monotone and nearly linear (`_face_points`).  Returns a dict of sub-cell
    arrays (reduced units): face, position theta in the face, branch (0 librating, 1
    rotating), frequency at both ends, J-bar length, eta at the middle."""
    pts, face = _face_points(geom, m, m_sep)
    e0 = np.concatenate([p[:-1] for p in pts])
    e1 = np.concatenate([p[1:] for p in pts])
    ends = np.unique(np.concatenate((e0, e1)))
    nz = ends != 0.0
    om = np.zeros(ends.size)
    om[nz] = separatrix.frequency(ends[nz], 1.0)
    x = np.zeros(ends.size)
    x[nz] = separatrix.jbar_offset(ends[nz], 1.0)
    i0, i1 = np.searchsorted(ends, e0), np.searchsorted(ends, e1)
    # the middle: geometric in |eta| on log sub-cells (and half the outer end on the one that
    # ends on the separatrix), arithmetic on linear ones
    logcell = (np.sign(e0) == np.sign(e1)) & (e0 != 0.0) & (e1 != 0.0)
    with np.errstate(invalid="ignore"):
        geo = np.sign(e0 + e1) * np.sqrt(np.abs(e0 * e1))
    mid = np.where(logcell & (np.abs(e1 - e0) > 0.1 * np.abs(e0 + e1)), geo, 0.5 * (e0 + e1))
    xmid = separatrix.jbar_offset(mid, 1.0)
    theta = (xmid - geom.xhat[face]) / geom.dj[face]
    return {
        "face": face,
        "theta": theta,
        "branch": (mid > 0.0).astype(int),
        "om0": om[i0],
        "om1": om[i1],
        "length": x[i1] - x[i0],
        "eta": mid,
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


def _derivative_at(geom, face, theta, derivative):
    """(E, N-1) rows giving d g/dh at the resonances' positions theta (0: node a, 1: node a+1)
    in the faces, from the face differences (D g)_a: 'face' takes the face's own difference
    quotient (first order in the face width); 'interpolated' interpolates the difference
    quotients of the face and its neighbour on the resonance's side linearly in J-bar between
    the faces' centres (second order).  Either way a row sums the quotients with weights
    adding to one, so that X[h] = 0 and X[1] = 0 exactly."""
    nf = geom.nu.size
    de = geom.s * geom.nu * geom.dj  # eps_{a+1} - eps_a
    q = geom.dj / de  # (d g/dh)_a = q_a (D g)_a
    E = face.size
    if derivative == "face":
        return sparse.csr_matrix((q[face], (np.arange(E), face)), shape=(E, nf))
    if derivative != "interpolated":
        raise ValueError(f"derivative = {derivative!r}: 'face' or 'interpolated'")
    x = geom.xhat
    centre = 0.5 * (x[1:] + x[:-1])
    pos = x[face] + theta * geom.dj[face]
    other = np.where(pos < centre[face], face - 1, face + 1)
    ok = (other >= 0) & (other < nf)
    other = np.clip(other, 0, nf - 1)
    with np.errstate(invalid="ignore", divide="ignore"):  # no neighbour at the grid's ends
        w = np.where(ok, np.abs(pos - centre[face]) / np.abs(centre[other] - centre[face]), 0.0)
    w = np.clip(w, 0.0, 1.0)
    rows = np.concatenate((np.arange(E), np.arange(E)))
    cols = np.concatenate((face, other))
    vals = np.concatenate(((1.0 - w) * q[face], w * q[other]))
    return sparse.csr_matrix((vals, (rows, cols)), shape=(E, nf))


def resonance_events(geom, n_max, m=4, m_sep=24, derivative="face"):
    """Every pair of faces in resonance n Omega = n' Omega' (1 <= n, n' <= n_max) (`Events`),
    in reduced units.

    The measure int int dJ-bar dJ-bar' delta(n Omega - n' Omega') and the Fourier coefficients
    are integrated over sub-cells (`_subcells`) with a uniform J-bar density per unit frequency
    on each; the dielectric factor is applied per elementary resonance (`Events.weights`).
    """
    sub = _subcells(geom, m, m_sep)
    width = np.abs(sub["om1"] - sub["om0"])
    if not np.all(width > 0):
        raise FloatingPointError("a sub-cell of the grid has an empty frequency range")
    ns = np.arange(1, n_max + 1)
    c2 = cos_coefficient_eta(ns[:, None], sub["eta"][None, :]) ** 2  # (n_max, n_sub)
    s2 = sin_coefficient_imag_eta(ns[:, None], sub["eta"][None, :]) ** 2
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
                    # int omega^2 domega over the overlap (X = omega (d ln f/dh - d ln f'/dh'))
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
    E = a.size
    read = "interpolated" if derivative == "mixed" else derivative
    C = _derivative_at(geom, a, theta_a, read) - _derivative_at(geom, b, theta_b, read)
    A = None
    if derivative == "mixed":
        A = _derivative_at(geom, a, theta_a, "face") - _derivative_at(geom, b, theta_b, "face")
    r4 = np.repeat(np.arange(E), 4)
    c4 = np.stack([a, a + 1, b, b + 1], axis=1).ravel()
    p4 = np.stack([1.0 - theta_a, theta_a, 1.0 - theta_b, theta_b], axis=1).ravel()
    P = sparse.csr_matrix((p4, (r4, c4)), shape=(E, nf + 1))
    if not (np.all(np.isfinite(vcc)) and np.all(np.isfinite(vss))):
        raise FloatingPointError("non-finite resonance weight on the grid")
    return Events(a, b, C, P, inv, np.concatenate(oms), KERNEL * vcc, KERNEL * vss, A)


def jacobian_assembly(Xhat, P, Ahat=None):
    """Sparse maps from per-event weights to the entries of the dense Jacobian: with v, u per
    event, (X^T diag(v) X)_ij = (A1 v)_{jN+i} and (X^T diag(u) P)_ij = (A2 u)_{jN+i}, A1 and A2
    (N*N, E) holding the outer products of each event's few nonzeros; so that a Newton matrix
    costs two sparse matrix-vector products, its columns contiguous (LAPACK's order).  Computed
    once per grid (reduced X^)."""
    n = Xhat.shape[1]
    Xc = (Xhat if Ahat is None else Ahat).tocoo()  # the left factor: A^ where it differs
    maps = []
    for right in (Xhat.tocsr(), P.tocsr()):
        start, idx, dat = right.indptr, right.indices, right.data
        counts = start[Xc.row + 1] - start[Xc.row]
        rep = np.repeat(np.arange(Xc.nnz), counts)
        offs = np.arange(rep.size) - np.repeat(np.cumsum(counts) - counts, counts)
        k = start[Xc.row[rep]] + offs
        rows = idx[k] * n + Xc.col[rep]
        vals = Xc.data[rep] * dat[k]
        maps.append(sparse.csr_matrix((vals, (rows, Xc.row[rep])), shape=(n * n, Xhat.shape[0])))
    return tuple(maps)


class CollisionOperator:
    """dm/dtau = -X^T (W F X[ln f]) at magnetisation M for one geometry, resonance set and
    dielectric factor (m the node masses at M).

    eps : None (Landau) or a callable omega -> (eps_cc, eps_ss) (Lenard-Balescu), evaluated at
    the frequency of every elementary resonance.
    """

    def __init__(self, geom, events, M, eps=None, assembly=None):
        self.geom = geom
        self.events = events
        self.M = float(M)
        self.W = events.weights(self.M, eps)
        self.Xhat = (events.C @ geom.D).tocsr()  # (E, N), reduced units
        self.X = (self.Xhat / self.M).tocsr()  # X = X^/M
        self.P = events.P
        # the current's attribution to faces: X itself, or A (events.A) where it differs
        self.Ahat = None if events.A is None else (events.A @ geom.D).tocsr()
        self.XT = (self.X if self.Ahat is None else self.Ahat / self.M).T.tocsr()
        self.dj = np.sqrt(self.M) * geom.dj  # face spacings in J-bar
        self.assembly = assembly

    def _parts(self, y, level=0.0):
        # ln F_e = ln f on the test side + ln f on the partner side: P's rows sum to 2
        F = np.exp(2.0 * level + self.P @ y)
        Xy = self.X @ y
        return F, Xy

    def rate(self, y, level=0.0):
        """dm/dtau at ln f = level + y (mass per node per unit tau).  X annihilates constants,
        so that y may be ln f's offsets from a level, which keep their digits where ln f
        differs between neighbouring cells below its own rounding (next to the separatrix)."""
        F, Xy = self._parts(y, level)
        return -(self.XT @ (self.W * F * Xy))

    def jacobian_dense(self, y, level=0.0):
        """d(rate)/dy as a dense (N, N) array in Fortran order, from `jacobian_assembly`
        (J = -(X^T diag(W F) X + X^T diag(W F X y) P) with X = X^/M)."""
        if self.assembly is None:
            self.assembly = jacobian_assembly(self.Xhat, self.P, self.Ahat)
        F, Xy = self._parts(y, level)
        WF = self.W * F
        n = self.X.shape[1]
        J = self.assembly[0] @ (WF / self.M**2) + self.assembly[1] @ (WF * Xy / self.M)
        return -J.reshape(n, n).T

    def jacobian(self, y, level=0.0):
        """d(rate)/dy as a sparse (N, N) matrix."""
        F, Xy = self._parts(y, level)
        WF = self.W * F
        J = self.XT @ sparse.diags(WF) @ self.X + self.XT @ sparse.diags(WF * Xy) @ self.P
        return -J

    def face_flux(self, y, level=0.0):
        """Number flux 4 pi G-bar through each face a (towards larger J-bar)."""
        F, Xy = self._parts(y, level)
        # C at M is C^/sqrt(M) (dj/dh: sqrt(M) dj^ / (M deps^)), and dj = sqrt(M) dj^
        attribution = self.events.C if self.events.A is None else self.events.A
        q = (attribution.T @ (self.W * F * Xy)) / np.sqrt(self.M)
        return -q / self.dj

    def entropy_production(self, y, level=0.0):
        """dS/dtau = sum_e W F X[ln f] A[ln f] (= sum_e W F X[ln f]^2 >= 0 where A is X)."""
        F, Xy = self._parts(y, level)
        Ay = Xy if self.Ahat is None else (self.Ahat @ y) / self.M
        return float(np.sum(self.W * F * Xy * Ay))
