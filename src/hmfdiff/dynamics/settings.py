"""The settings of one molecular-dynamics run: the `MDRun` record, its validation and the integer
step counts derived from it.  `hmfdiff.dynamics.runs` builds the records from a config.

Every MD setting is a field of `MDRun`, written once here.  The workflow builds the records
when it is parsed (workflow/rules/md_helpers.smk), hands one to each job as JSON
(`realisation_json` / `from_json`), and `hmfdiff.dynamics.md.run_md` takes it.  Times are in
the HMF unit 1/sqrt(M = 1).  Bad values raise `ConfigError` with one line naming the case, the
field, the value and the allowed range.
"""

from __future__ import annotations

import dataclasses
import json
import math
from numbers import Real

import numpy as np

from ..errors import ConfigError
from ..meanfield import orbits

__all__ = ["DYNAMICS", "MDRun"]

#: MD(bath), eq. hmfmdbath, and MD(full), eq. hmfmdfull
DYNAMICS = ("bath", "full")
TEST_SAMPLINGS = ("uniform", "f")
#: how MD(bath) moves its bath: exact orbits in the static field (`exact_bath`) or integrated
BATHS = ("exact", "integrated")

#: fields that say how the workflow runs and fits the realisations, not what one computes
WORKFLOW_FIELDS = (
    "seeds",
    "threads",
    "job_seconds",
    "fit_window",
    "min_particles",
    "separatrix_band_fit",
)
#: particle-steps per second and thread of a whole realisation (integration, actions and the
#: accumulation of <dJ^2>), a round figure below the MD(full) job measured idle on the 2-core
#: machine (N = 5e5 + 2e4, t = 1000: 1.04e10 in 14.2 s, 7.3e8/s, 2026-11-24): it sizes the blocks
#: of seeds that one job runs (`MDRun.seed_blocks`), so it must not depend on the machine
NOMINAL_PARTICLE_STEPS_PER_S = 5e8
#: an exact-bath particle costs about 1/8 of an integrated one (its orbit's harmonics are summed,
#: not integrated: an MD(bath) realisation of N_b = 5e5 + 2e4 test particles took 3.0 s)
EXACT_BATH_COST = 1 / 8

# (field, smallest value) of the integer fields
_INTEGERS = (
    ("n_particles", 1),
    ("n_test", 0),
    ("n_blocks", 1),
    ("n_bins", 1),
    ("n_store", 0),
    ("seeds", 1),
    ("threads", 1),
    ("min_particles", 0),
)
# (field, lower bound, lower bound included, upper bound) of the real fields; upper open
_REALS = (
    ("dt", 0.0, False, math.inf),
    ("bath_tolerance", 0.0, False, 1e-3),
    ("t_max", 0.0, False, math.inf),
    ("sample_every", 0.0, False, math.inf),
    ("max_lag", 0.0, False, math.inf),
    ("origin_every", 0.0, False, math.inf),
    ("t_equilibrate", 0.0, True, math.inf),
    ("kappa_max", 0.0, False, math.inf),
    ("separatrix_band_fit", 0.0, True, 0.5),
    ("job_seconds", 0.0, False, math.inf),
)
# (field, unit): each field must be a whole multiple of its unit
_MULTIPLES = (
    ("sample_every", "dt"),
    ("max_lag", "sample_every"),
    ("origin_every", "sample_every"),
    ("t_max", "sample_every"),
    ("t_equilibrate", "dt"),
    ("m_every", "dt"),
)


def _whole_multiple(value, unit):
    """round(value / unit) if value is a whole multiple of unit (1e-9 relative), else None."""
    k = int(round(value / unit))
    return k if abs(k * unit - value) <= 1e-9 * max(abs(value), unit) else None


@dataclasses.dataclass(frozen=True, kw_only=True)
class MDRun:
    """Every setting of one MD run (all realisations of one case and dynamics).

    What is simulated: `dynamics` 'bath' (N_b = n_particles bath particles in the static field
    M0, n_test >= 1 test particles driven by their magnetisation) or 'full' (n_particles
    interacting particles, plus n_test test particles); test particles are drawn uniformly in
    J-bar over `jbar_range` (default [0, J-bar(kappa_max)]) or from f (`test_sampling` 'f');
    for 'full' with `zero_momentum`, the mean momentum of the N particles is removed.
    Integration and measurement: time step `dt`; `t_equilibrate` without measurement, then
    `t_max` of production sampled every `sample_every`; origins every `origin_every`, lags up to
    `max_lag`, origins split into `n_blocks` blocks; `n_bins` bins of the initial J-bar uniform
    over [0, J-bar(kappa_max)]; `n_store` tracked particles stored for illustration; the
    magnetisation (Mx, My) stored every `m_every` (default: every sample) for its spectrum.
    MD(bath): `bath` 'exact' synthesises the bath's magnetisation from its exact orbits
    (`exact_bath`, harmonics per particle chosen so that the truncation error of each
    particle's cos theta, sin theta is below `bath_tolerance`), 'integrated' integrates the
    N_b bath particles.  MD(full): `n_track` of the N particles, drawn at random, have their
    actions measured (None: all N); they are statistically equivalent, and the noise of <dJ^2>
    comes from the field, not from the number of tracked particles.
    Workflow (`WORKFLOW_FIELDS`, no effect on one realisation's numbers): `seeds`
    realisations, run in blocks of about `job_seconds` of work per job (`seed_blocks`),
    `threads` per job, and the fit of <dJ^2> over `fit_window` = (t_min, t_max)
    in bins with at least `min_particles`, flagging bins within `separatrix_band_fit` of
    kappa = 1.  `case` names the run in messages.
    """

    case: str = ""
    dynamics: str
    n_particles: int
    n_test: int
    dt: float
    t_max: float
    sample_every: float
    max_lag: float
    origin_every: float
    t_equilibrate: float = 0.0
    n_blocks: int = 10
    kappa_max: float = 2.0
    n_bins: int = 30
    test_sampling: str = "uniform"
    jbar_range: tuple[float, float] | None = None
    zero_momentum: bool = True
    n_store: int = 16
    m_every: float | None = None
    bath: str = "exact"
    bath_tolerance: float = 1e-9
    n_track: int | None = None
    seeds: int = 1
    threads: int = 1
    job_seconds: float = 60.0
    fit_window: tuple[float, float] | None = None
    min_particles: int = 0
    separatrix_band_fit: float = 0.0

    # ---------------------------------------------------------------- validation
    def _fail(self, message):
        where = f"md run '{self.case}'" if self.case else "md run"
        raise ConfigError(f"{where}: {message}")

    def _set(self, name, value):
        object.__setattr__(self, name, value)

    def _real(self, name, value, lo, lo_closed, hi):
        ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(value)
        if not ok:
            self._fail(f"field '{name}' = {value!r} must be a finite number")
        if value < lo or (value == lo and not lo_closed) or value >= hi:
            lb = "[" if lo_closed else "("
            self._fail(f"field '{name}' = {value!r} is outside the allowed range {lb}{lo}, {hi})")
        return float(value)

    def __post_init__(self):
        if self.dynamics not in DYNAMICS:
            self._fail(f"field 'dynamics' = {self.dynamics!r} must be 'bath' or 'full'")
        lowest = dict(_INTEGERS, n_test=1 if self.dynamics == "bath" else 0)
        for name, lo in lowest.items():
            v = getattr(self, name)
            ok = isinstance(v, Real) and not isinstance(v, bool) and float(v).is_integer()
            if not (ok and v >= lo):
                what = (
                    f"'{name}' (config key 'n_test_{self.dynamics}')"
                    if name == "n_test"
                    else f"'{name}'"
                )
                self._fail(f"field {what} = {v!r} must be an integer >= {lo}")
            self._set(name, int(v))
        for name, lo, lo_closed, hi in _REALS:
            self._set(name, self._real(name, getattr(self, name), lo, lo_closed, hi))
        if self.n_track is not None:
            v = self.n_track
            ok = isinstance(v, Real) and not isinstance(v, bool) and float(v).is_integer()
            if not (ok and 1 <= v <= self.n_particles):
                self._fail(
                    f"field 'n_track' = {v!r} must be null (all) or an integer in "
                    f"[1, n_particles = {self.n_particles}]"
                )
            self._set("n_track", int(v))
        if self.m_every is None:
            self._set("m_every", self.sample_every)
        self._set("m_every", self._real("m_every", self.m_every, 0.0, False, math.inf))
        if self.bath not in BATHS:
            self._fail(f"field 'bath' = {self.bath!r} must be 'exact' or 'integrated'")
        if self.max_lag > self.t_max:
            self._fail(
                f"field 'max_lag' = {self.max_lag} exceeds t_max = {self.t_max}: allowed "
                f"(0, t_max = {self.t_max}] (every lag lies within the run)"
            )
        for name, unit in _MULTIPLES:
            v, u = getattr(self, name), getattr(self, unit)
            if v > 0 and _whole_multiple(v, u) in (None, 0):
                self._fail(f"field '{name}' = {v} must be a whole multiple of {unit} = {u}")
        if self.fit_window is not None:
            self._set("fit_window", self._window())
        if not self.n_blocks <= self.n_origins:
            self._fail(
                f"field 'n_blocks' = {self.n_blocks} must be an integer in "
                f"[1, number of origins = {self.n_origins}]"
            )
        if self.test_sampling not in TEST_SAMPLINGS:
            self._fail(f"field 'test_sampling' = {self.test_sampling!r} must be 'uniform' or 'f'")
        if self.jbar_range is not None:
            r = self.jbar_range
            ok = isinstance(r, list | tuple) and len(r) == 2
            ok = ok and all(isinstance(x, Real) and math.isfinite(x) for x in r)
            if not (ok and 0 <= r[0] < r[1]):
                self._fail(
                    f"field 'jbar_range' = {r!r} must be (Jbar_min, Jbar_max) with "
                    "0 <= Jbar_min < Jbar_max"
                )
            self._set("jbar_range", (float(r[0]), float(r[1])))
        if not isinstance(self.zero_momentum, bool):
            self._fail(f"field 'zero_momentum' = {self.zero_momentum!r} must be true or false")

    def _window(self):
        w = self.fit_window
        if not isinstance(w, list | tuple) or len(w) != 2:
            self._fail(f"field 'fit_window' = {w!r} must be [t_min, t_max]")
        t0 = self._real("fit_window[0]", w[0], 0.0, True, math.inf)
        t1 = self._real("fit_window[1]", w[1], -math.inf, True, math.inf)
        if not t0 < t1 <= self.max_lag:
            self._fail(
                f"field 'fit_window' = {list(w)} must satisfy 0 <= t_min < t_max <= "
                f"max_lag = {self.max_lag} (the fit needs measured lags; the run is "
                f"t_max = {self.t_max} long)"
            )
        return (t0, t1)

    # ---------------------------------------------------------------- derived counts
    @property
    def steps_per_sample(self):
        """Time steps between two samples: sample_every / dt."""
        return _whole_multiple(self.sample_every, self.dt)

    @property
    def equilibration_steps(self):
        """Time steps before production: t_equilibrate / dt."""
        return 0 if self.t_equilibrate == 0 else _whole_multiple(self.t_equilibrate, self.dt)

    @property
    def n_samples(self):
        """Sampling intervals of production, t_max / sample_every (n_samples + 1 samples)."""
        return _whole_multiple(self.t_max, self.sample_every)

    @property
    def lag_samples(self):
        """Longest lag in samples: max_lag / sample_every."""
        return _whole_multiple(self.max_lag, self.sample_every)

    @property
    def origin_samples(self):
        """Samples between two time origins: origin_every / sample_every."""
        return _whole_multiple(self.origin_every, self.sample_every)

    @property
    def n_origins(self):
        """Time origins whose whole lag window fits in the run."""
        return (self.n_samples - self.lag_samples) // self.origin_samples + 1

    @property
    def n_steps(self):
        """Time steps of the whole run, equilibration included."""
        return self.equilibration_steps + self.n_samples * self.steps_per_sample

    @property
    def m_steps(self):
        """Time steps between two stored values of the magnetisation: m_every / dt."""
        return _whole_multiple(self.m_every, self.dt)

    @property
    def n_m_samples(self):
        """Stored magnetisation values over production: t_max // m_every + 1."""
        return self.n_samples * self.steps_per_sample // self.m_steps + 1

    @property
    def n_tracked_from_f(self):
        """Tracked particles drawn from f: for 'full' n_track (all N by default), else 0."""
        if self.dynamics != "full":
            return 0
        return self.n_particles if self.n_track is None else self.n_track

    @property
    def n_tracked(self):
        """Particles whose actions are measured: the test particles, and for 'full' the n_track
        tracked particles of the N (all N by default)."""
        return self.n_test + self.n_tracked_from_f

    @property
    def exact_bath(self):
        """True when MD(bath) synthesises its bath from exact orbits."""
        return self.dynamics == "bath" and self.bath == "exact"

    # ---------------------------------------------------------------- state-dependent values
    def jbar_max(self, M0):
        """J-bar(kappa_max): the upper edge of the bins (and default test-particle range)."""
        return float(orbits.rescaled_action(self.kappa_max, M0))

    def jbar_edges(self, M0):
        """Edges of the n_bins uniform bins of the initial J-bar over [0, J-bar(kappa_max)]."""
        return np.linspace(0.0, self.jbar_max(M0), self.n_bins + 1)

    def test_jbar_range(self, M0):
        """(Jbar_min, Jbar_max) of the uniform test particles: jbar_range or [0, J-bar_max]."""
        return self.jbar_range if self.jbar_range is not None else (0.0, self.jbar_max(M0))

    # ---------------------------------------------------------------- estimates for schedulers
    def memory_mb(self):
        """Peak memory of one job: state (~48 B per particle) and the ring buffer of J(t0)
        (~11 B per tracked particle and slot), with 30 % margin and 1 GB of interpreter."""
        n = self.n_particles + self.n_test
        slots = self.max_lag / self.origin_every + 1
        return int(1000 + (48 * n + 11 * self.n_tracked * slots) / 1e6 * 1.3)

    def particle_steps(self):
        """Particle-steps of one realisation (an exact-bath particle counts `EXACT_BATH_COST`)."""
        n_bath = self.n_particles * EXACT_BATH_COST if self.exact_bath else self.n_particles
        return (n_bath + self.n_test) * (self.t_max + self.t_equilibrate) / self.dt

    def runtime_min(self, seeds=1):
        """Wall-time request of one job of `seeds` realisations in minutes, at a conservative
        5e7 particle-steps/s."""
        return int(10 + seeds * self.particle_steps() / 5e7 / 60 * 2)

    def seeds_per_job(self):
        """Realisations per MD job: as many as fit in `job_seconds` of one thread's work at the
        nominal speed (`NOMINAL_PARTICLE_STEPS_PER_S`), at least one.  It depends on what one
        realisation computes and on `job_seconds` only, not on `seeds`, `threads` or the
        machine, so that the blocks (the MD jobs' outputs) stay put; changing `job_seconds`
        regroups the seeds and so reruns the MD."""
        per_seed = self.particle_steps() / NOMINAL_PARTICLE_STEPS_PER_S
        return max(1, int(self.job_seconds // per_seed))

    def seed_blocks(self):
        """[(first, last)] (inclusive) of the blocks of seeds, one per MD job: aligned at
        multiples of `seeds_per_job`, the last one cut at `seeds`.  Raising `seeds` keeps every
        full block and adds new ones; only a partial last block is run again."""
        b = self.seeds_per_job()
        return [(s, min(s + b, self.seeds) - 1) for s in range(0, self.seeds, b)]

    # ---------------------------------------------------------------- serialisation
    def to_dict(self, *, realisation_only=False):
        d = dataclasses.asdict(self)
        for k, v in d.items():
            d[k] = list(v) if isinstance(v, tuple) else v
        if realisation_only:
            d = {k: v for k, v in d.items() if k not in WORKFLOW_FIELDS}
        return d

    def to_json(self):
        """Every field as JSON (`from_json` gives the record back)."""
        return json.dumps(self.to_dict(), sort_keys=True)

    def realisation_json(self):
        """The fields that change the numbers of a realisation, as JSON: the md rule's params,
        so that changing the fit, the number of seeds or the threads reruns no simulation.
        `from_json` reads it back with the workflow fields at their defaults."""
        return json.dumps(self.to_dict(realisation_only=True), sort_keys=True)

    @classmethod
    def from_json(cls, text):
        return cls(**json.loads(text))

    def fit_settings(self):
        """What the fit of <dJ^2> needs: fit_window, min_particles, separatrix_band_fit."""
        d = self.to_dict()
        return {k: d[k] for k in ("fit_window", "min_particles", "separatrix_band_fit")}

    def attrs(self, M0):
        """netCDF attributes of a run's output (the test-particle range resolved with M0)."""
        jr = "none" if self.n_test == 0 else np.asarray(self.test_jbar_range(M0), dtype=float)
        return {
            "dynamics": self.dynamics,
            "N": self.n_particles,
            "n_test": self.n_test,
            "n_tracked": self.n_tracked,
            "n_tracked_from_f": self.n_tracked_from_f,
            "bath": self.bath if self.dynamics == "bath" else "none",
            "bath_tolerance": self.bath_tolerance if self.exact_bath else "none",
            "m_every": self.m_every,
            "test_sampling": self.test_sampling if self.n_test else "none",
            "jbar_range": jr if self.test_sampling == "uniform" else "none",
            "dt": self.dt,
            "t_max": self.t_max,
            "t_equilibrate": self.t_equilibrate,
            "sample_every": self.sample_every,
            "origin_every": self.origin_every,
            "max_lag": self.max_lag,
            "n_origins": self.n_origins,
            "n_blocks": self.n_blocks,
            "kappa_max": self.kappa_max,
            "n_bins": self.n_bins,
            "zero_momentum": int(self.zero_momentum and self.dynamics == "full"),
        }

    @classmethod
    def defaults(cls):
        """{field: default} of the fields that have one (for the schema's documentation)."""
        return {
            f.name: f.default
            for f in dataclasses.fields(cls)
            if f.default is not dataclasses.MISSING
        }
