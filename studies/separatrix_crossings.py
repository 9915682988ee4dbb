"""How wide is the separatrix at finite N?  Separatrix crossings in the self-consistent N-body.

    python studies/separatrix_crossings.py all          # the table of the docs (hot + thermal)
    python studies/separatrix_crossings.py CASE [N:R ...] [--dt DT] [--every DELTA] [--t T]
                                           [--classical]

CASE: hot (the hot-halo core-halo state of figures 11-13, `studies/separatrix_layer.CASES`) or
thermal (the Maxwell-Boltzmann state u = 0); N:R runs R realisations of N particles (default
1000:16 2000:12 4000:8 8000:6 16000:4).  Each realisation: N particles drawn from the state
(`sampling.sample_state`, angles rotated so that M lies on x, mean momentum removed), integrated
by the project's leapfrog in their own field (`integrator.leapfrog`, Field.SELF: MD(full)) at
dt = 0.1 for t_eq = 100 (the fluctuations build up), then for T = 2000 with (theta, p) of the
tracked particles sampled every Delta = 0.5 and |M|(t) kept at every step.  Tracked: the
particles with |kappa - 1| < 0.2 at the start of the measurement (kappa in the field of that
moment), at most 2000 drawn at random; rates are scaled to the whole system by N_window / n_track.
T is far below the relaxation time (~ 40 N or more).  One core.

What is measured (`hmfdiff.analysis.separatrix_crossings`; M-bar = the time mean of |M|):
crossings of the instantaneous separatrix (kappa_inst = 1, |M|(t) and phi(t)), of the fixed one
(amplitude M-bar, phase phi(t)), and family changes (libration <-> rotation, read off the bottom
passages: the definition that needs no field amplitude); the change of J-bar (frozen-field
action with |M|(t)) over the half-orbit of each family change, and for comparison over
consecutive half-orbits of particles near the separatrix that do not change family; the kappa
spread within one period; the separatrix's own motion rms(dM)/(2 M-bar).  The layer's width
delta(N) is estimated four ways (see the column list printed with the table).  Errors: bootstrap
over realisations (400 resamples); exponents: weighted least squares of ln y on ln N.
Output of `all`: docs/reference/separatrix_crossings.txt.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from hmfdiff.analysis import separatrix_crossings as sc  # noqa: E402
from hmfdiff.dynamics import sampling  # noqa: E402
from hmfdiff.dynamics.integrator import Field, Particles, advance_in_field, leapfrog  # noqa: E402
from hmfdiff.meanfield import orbits  # noqa: E402
from hmfdiff.meanfield.equilibrium import make_state  # noqa: E402

CASES = {
    "hot": dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0),
    "thermal": dict(kind="thermal", u=0.0),
}
DEFAULT_SIZES = {
    "hot": [(1000, 24), (2000, 16), (4000, 12), (8000, 8), (16000, 6), (32000, 4)],
    "thermal": [(1000, 12), (2000, 8), (4000, 6), (8000, 6), (16000, 4), (32000, 4)],
}
SEED = {"hot": 3801, "thermal": 3802}
T_EQ = 100.0
WINDOW = 0.4  # tracked: |kappa - 1| < WINDOW at the start
N_TRACK_MAX = 2000
NEAR = 0.05  # "near the separatrix": |kappa - 1| < NEAR
BAND = 0.01  # the fixed hysteresis band of the third crossing count
N_BOOT = 400


def realisation(state, N, seed, member, *, dt, every, T):
    """One MD(full) realisation: the sums each table column needs."""
    rng = sampling.make_rng(seed, member)
    theta, p = sampling.sample_state(state, N, rng)
    theta, _ = sampling.rotate_to_x_axis(theta)
    P = Particles(theta, p - p.mean())
    n_eq = int(round(T_EQ / dt))
    leapfrog(P, n_eq, dt, Field.SELF)
    # tracked particles: near the separatrix of the field of this moment
    Mx, My = P.moments()[:2]
    k0 = sc.instantaneous_kappa(P.theta.astype(float), P.p.astype(float), Mx, My)
    window = np.flatnonzero(np.abs(k0 - 1.0) < WINDOW)
    idx = np.sort(rng.choice(window, size=min(window.size, N_TRACK_MAX), replace=False))
    g = np.count_nonzero(np.abs(k0 - 1.0) < 0.02) / (0.04 * N)  # fraction per unit kappa
    k_start = k0[idx]
    n_per = int(round(every / dt))
    if n_per < 1 or abs(n_per * dt - every) > 1e-9 * every:
        raise ValueError(f"the sampling interval {every} must be a multiple of dt = {dt}")
    n_s = int(round(T / every)) + 1
    th_s = np.empty((n_s, idx.size), np.float32)
    p_s = np.empty((n_s, idx.size), np.float32)
    m_s = np.empty((n_s, 2))
    m_all = np.empty(((n_s - 1) * n_per, 2))
    th_s[0] = np.arctan2(P.S[idx], P.C[idx])
    p_s[0] = P.p[idx]
    m_s[0] = Mx, My
    t0 = time.perf_counter()
    for s in range(1, n_s):
        m = leapfrog(P, n_per, dt, Field.SELF)
        m_all[(s - 1) * n_per : s * n_per] = m
        th_s[s] = np.arctan2(P.S[idx], P.C[idx])
        p_s[s] = P.p[idx]
        m_s[s] = m[-1]
    wall_md = time.perf_counter() - t0
    t = every * np.arange(n_s)
    return analyse(t, th_s, p_s, m_s, m_all, N, dt, g, window.size, k_start) | {"wall": wall_md}


def analyse(t, th_s, p_s, m_s, m_all, N, dt, g, n_window, k_start):
    theta = th_s.astype(float)
    p = p_s.astype(float)
    n_tr = theta.shape[1]
    T = t[-1] - t[0]
    mod_all = np.hypot(m_all[:, 0], m_all[:, 1])
    Mbar = float(mod_all.mean())
    mod, phase = sc.field_polar(m_s[:, 0], m_s[:, 1])
    k_inst = sc.instantaneous_kappa(theta, p, m_s[:, 0], m_s[:, 1])
    k_fix = sc.kappa_in_field(theta, p, Mbar, phase)
    out = {"n_track": n_tr, "exposure": T * n_tr * N / n_window, "g": g}
    # crossings of kappa = 1, three ways
    for name, kap, band in (("inst", k_inst, 0.0), ("fix", k_fix, 0.0), ("band", k_inst, BAND)):
        part, _, _ = sc.crossing_times(t, kap, band=band)
        out["c_" + name] = part.size
    passages = sc.bottom_passages(t, theta, phase)
    changes = sc.family_changes(*passages)
    out["c_topo"] = changes[0].size
    # completeness of the window: family changes of particles that started at |k - 1| > 0.2
    out["c_topo_outer"] = int(np.count_nonzero(np.abs(k_start[changes[0]] - 1.0) > 0.2))
    # half-orbits: segment means of kappa (fixed amplitude) and of J-bar (frozen field)
    pp, pt, pdir = passages
    jbar = sc.rescaled_action_in_field(k_inst, mod)
    same = pp[1:] == pp[:-1]
    seg = np.flatnonzero(same)  # half-orbit from passage seg to seg + 1
    seg_k = sc.segment_means(t, k_fix, pp[seg], pt[seg], pt[seg + 1])
    seg_j = sc.segment_means(t, jbar, pp[seg], pt[seg], pt[seg + 1])
    seg_T = pt[seg + 1] - pt[seg]
    seg_r = pdir[seg] * pdir[seg + 1]
    # consecutive half-orbits of one particle: seg[i] + 1 == seg[i + 1]
    pair = np.flatnonzero(seg[1:] == seg[:-1] + 1)
    a, b = pair, pair + 1
    near = (np.abs(seg_k[a] - 1.0) < NEAR) & (np.abs(seg_k[b] - 1.0) < NEAR)
    change = seg_r[a] != seg_r[b]
    dk = (seg_k[b] - seg_k[a])[near]
    dj_cross = (seg_j[b] - seg_j[a])[change]
    dj_ctrl = (seg_j[b] - seg_j[a])[near & ~change]
    jump, _, _ = sc.action_jumps(t, jbar, passages, changes)
    assert np.allclose(np.sort(jump), np.sort(dj_cross), equal_nan=True)
    out |= {
        "dk_ss": float(np.sum(dk * dk)),
        "dk_n": dk.size,
        "T_seg_sum": float(np.sum(seg_T[np.abs(seg_k - 1.0) < NEAR])),
        "T_seg_n": int(np.count_nonzero(np.abs(seg_k - 1.0) < NEAR)),
        "dj": dj_cross[np.isfinite(dj_cross)],
        "dj_ctrl": dj_ctrl[np.isfinite(dj_ctrl)],
    }
    # kappa spread within a period (the librating period at kappa = 0.95)
    W = float(orbits.period(0.95, Mbar))
    for name, kap in (("inst", k_inst), ("fix", k_fix)):
        s, n = sc.kappa_spread_over_period(t, kap, W, near=NEAR, reference=k_fix)
        out[f"spread_{name}_ss"] = s * s * n
        out[f"spread_{name}_n"] = n
    motion = sc.separatrix_motion(mod_all, N)
    eps = np.gradient(mod_all, dt) / Mbar**1.5  # slow parameter: d|M|/dt / (|M| sqrt|M|)
    out |= {
        "Mbar": Mbar,
        "dM_ss": motion["rms_dM"] ** 2,
        "eps_ss": float(np.mean(eps * eps)),
    }
    return out


def classical_jumps(M0, eps, n=2000, dt=0.02, every=0.25, seed=3803):
    """The classical separatrix-crossing jump measured with the same estimator: n test particles
    in |M|(t) = M0 (1 - s t) (slow parameter eps = s / sqrt(M0) = |d|M|/dt| / M0^1.5 at t = 0),
    started on librating orbits at uniform angle with J-bar = J-bar_s(M0 (1 - x)),
    x = s (30 + u / sqrt(M0)), u uniform in [0, 40] (so each escapes into rotation once, at
    t = x / s in [30, 30 + 40 / sqrt(M0)], after several half-orbits, at a random phase),
    integrated by the project's leapfrog in that prescribed field (`advance_in_field`).
    Returns (mean, rms, number) of Delta J-bar over the half-orbits around each particle's
    first family change (lib -> rot)."""
    rng = np.random.default_rng(seed)
    s = eps * np.sqrt(M0)
    x = s * (30.0 + rng.uniform(0.0, 40.0, n) / np.sqrt(M0))
    k = orbits.kappa_from_rescaled_action(orbits.jbar_separatrix(M0 * (1.0 - x)), M0)
    th, p = orbits.phase_point(rng.uniform(0, 2 * np.pi, n), k, M0, 1.0)
    P = Particles(th, p)
    T = 30.0 + 40.0 / np.sqrt(M0) + 40.0
    n_per = int(round(every / dt))
    n_s = int(round(T / every)) + 1
    t = every * np.arange(n_s)
    th_s = np.empty((n_s, n))
    p_s = np.empty((n_s, n))
    th_s[0], p_s[0] = P.theta, P.p
    steps = np.arange(n_per + 1) * dt
    for i in range(1, n_s):
        m = M0 * (1.0 - s * (t[i - 1] + steps))
        advance_in_field(P, np.stack([m, np.zeros_like(m)], 1), dt=dt)
        th_s[i], p_s[i] = P.theta, P.p
    mod = M0 * (1.0 - s * t)
    kap = sc.instantaneous_kappa(th_s, p_s, mod, np.zeros_like(mod))
    passages = sc.bottom_passages(t, th_s)
    changes = sc.family_changes(*passages)
    first = np.unique(changes[0], return_index=True)[1]
    first = first[changes[2][first] == 1]
    ch = tuple(c[first] for c in changes)
    jump, _, _ = sc.action_jumps(t, sc.rescaled_action_in_field(kap, mod), passages, ch)
    jump = jump[np.isfinite(jump)]
    return float(np.mean(jump)), float(np.sqrt(np.mean(jump * jump))), jump.size


def classical_table(M0, eps_values=(1e-3, 3e-3, 1e-2)):
    print(
        f"# classical jump (slow linear ramp of |M|, M0 = {M0:.5f}; "
        "the same half-orbit estimator):",
        flush=True,
    )
    rms = []
    for eps in eps_values:
        m, r, n = classical_jumps(M0, eps)
        rms.append(r)
        print(
            f"#   eps = {eps:.0e}: dJ_mean = {m:+.3e}  dJ_rms = {r:.3e}  ({n} escapes)", flush=True
        )
    b, db, a, _ = sc.scaling_exponent(np.array(eps_values), np.array(rms))
    print(f"#   dJ_rms = {a:.3e} eps^({b:.3f} +- {db:.3f})", flush=True)


def pooled(reals, idx):
    """Every table quantity from the realisations `idx` (for the bootstrap)."""
    r = [reals[i] for i in idx]

    def tot(key):
        return sum(x[key] for x in r)

    ex = tot("exposure")
    dM = np.sqrt(np.mean([x["dM_ss"] for x in r]))
    Mbar = np.mean([x["Mbar"] for x in r])
    dj = np.concatenate([x["dj"] for x in r])
    djc = np.concatenate([x["dj_ctrl"] for x in r])
    T_seg = tot("T_seg_sum") / tot("T_seg_n")
    g = np.mean([x["g"] for x in r])
    q = {
        "nu_topo": tot("c_topo") / ex,
        "nu_inst": tot("c_inst") / ex,
        "nu_fix": tot("c_fix") / ex,
        "nu_band": tot("c_band") / ex,
        "dj_mean": float(np.mean(dj)) if dj.size else np.nan,
        "dj_rms": float(np.sqrt(np.mean(dj * dj))) if dj.size else np.nan,
        "djc_rms": float(np.sqrt(np.mean(djc * djc))) if djc.size else np.nan,
        "spread_inst": np.sqrt(tot("spread_inst_ss") / tot("spread_inst_n")),
        "spread_fix": np.sqrt(tot("spread_fix_ss") / tot("spread_fix_n")),
        "dk_rms": np.sqrt(tot("dk_ss") / tot("dk_n")),
        "width_M": dM / (2.0 * Mbar),
        "rms_dM": dM,
        "eps_rms": np.sqrt(np.mean([x["eps_ss"] for x in r])),
        "T_seg": T_seg,
        "g": g,
    }
    q["delta_rate"] = q["nu_topo"] * T_seg / (g * np.sqrt(2.0 / np.pi))
    return q


def summarise(reals, rng):
    n = len(reals)
    best = pooled(reals, range(n))
    boot = [pooled(reals, rng.integers(0, n, n)) for _ in range(N_BOOT)]
    err = {k: float(np.nanstd([b[k] for b in boot])) for k in best}
    return best, err


COLUMNS = [
    ("nu_topo", "nu_fam", "{:.3e}"),
    ("nu_inst", "nu_inst", "{:.3e}"),
    ("nu_band", "nu_inst.01", "{:.3e}"),
    ("nu_fix", "nu_fixed", "{:.3e}"),
    ("dj_mean", "dJ_mean", "{:+.2e}"),
    ("dj_rms", "dJ_rms", "{:.3e}"),
    ("djc_rms", "dJ_ctrl", "{:.3e}"),
    ("spread_inst", "spr_inst", "{:.3e}"),
    ("spread_fix", "spr_fixed", "{:.3e}"),
    ("dk_rms", "dk_half", "{:.3e}"),
    ("width_M", "dM/2M", "{:.3e}"),
    ("rms_dM", "rms_dM", "{:.3e}"),
    ("delta_rate", "delta_rate", "{:.3e}"),
    ("eps_rms", "eps_rms", "{:.3e}"),
]
EXPONENTS = [
    "nu_topo",
    "nu_inst",
    "nu_fix",
    "dj_rms",
    "djc_rms",
    "spread_inst",
    "spread_fix",
    "dk_rms",
    "width_M",
    "delta_rate",
]


def run_case(case, sizes, *, dt, every, T, classical=False):
    state = make_state(CASES[case])
    rng = np.random.default_rng(SEED[case] + 7)
    if classical:
        classical_table(state.M0)
    rows = []
    print(
        f"# case {case}: M0 (theory) = {state.M0:.6f}; dt = {dt}, Delta = {every}, T = {T}, "
        f"t_eq = {T_EQ}, tracked |kappa - 1| < {WINDOW} (at most {N_TRACK_MAX})",
        flush=True,
    )
    for N, R in sizes:
        reals = []
        t0 = time.perf_counter()
        for r in range(R):
            reals.append(realisation(state, N, SEED[case], 1000 * N + r, dt=dt, every=every, T=T))
        best, err = summarise(reals, rng)
        wall = time.perf_counter() - t0
        n_tr = int(np.mean([x["n_track"] for x in reals]))
        n_changes = sum(x["c_topo"] for x in reals)
        outer = sum(x["c_topo_outer"] for x in reals)
        sqrtN = np.sqrt(N) * best["rms_dM"]
        rows.append((N, best, err))
        cells = " ".join(
            f"{fmt.format(best[k])}({fmt.format(err[k]).lstrip('+')})" for k, _, fmt in COLUMNS
        )
        print(
            f"{case:7s} {N:6d} {R:3d} {n_tr:5d} {T:6.0f} {n_changes:6d} {outer:4d} "
            f"{np.mean([x['Mbar'] for x in reals]):.5f} "
            f"{sqrtN:.4f}({np.sqrt(N) * err['rms_dM']:.4f}) "
            f"{best['T_seg']:.2f} {best['g']:.3f} {cells}  [{wall:.0f} s]",
            flush=True,
        )
    Ns = np.array([r[0] for r in rows], float)
    print(f"# exponents, {case}: y = a N^b, weighted least squares (bootstrap errors)")
    for k in EXPONENTS:
        y = np.array([r[1][k] for r in rows])
        e = np.array([r[2][k] for r in rows])
        if np.all(np.isfinite(y)) and np.all(y > 0) and np.all(e > 0):
            b, db, a, chi2 = sc.scaling_exponent(Ns, y, e)
            print(
                f"#   {case:7s} {k:12s} b = {b:+.3f} +- {db:.3f}   a = {a:.3e}   "
                f"chi2/dof = {chi2:.2f}"
            )
    return rows


HEADER = (
    "case        N   R track      T fam_ch  out  M-bar     sqrtN_rmsdM   T_half  g     "
    + " ".join(f"{lab}(err)" for _, lab, _ in COLUMNS)
)


def parse_sizes(args):
    return [tuple(int(float(x)) for x in a.split(":")) for a in args]


def main(argv):
    if not argv:
        print(__doc__)
        return 2
    opts = {"--dt": 0.1, "--every": 0.5, "--t": 2000.0}
    classical = "--classical" in argv
    argv = [a for a in argv if a != "--classical"]
    rest = []
    it = iter(argv)
    for a in it:
        if a in opts:
            opts[a] = float(next(it))
        else:
            rest.append(a)
    kw = dict(dt=opts["--dt"], every=opts["--every"], T=opts["--t"])
    print(HEADER, flush=True)
    if rest[0] == "all":
        for case in ("hot", "thermal"):
            run_case(case, DEFAULT_SIZES[case], classical=True, **kw)
        return 0
    case = rest[0]
    if case not in CASES:
        print(__doc__)
        return 2
    sizes = parse_sizes(rest[1:]) if rest[1:] else DEFAULT_SIZES[case]
    run_case(case, sizes, classical=classical, **kw)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
