# ---- molecular dynamics -------------------------------------------------------------
def md_cases():
    """MD cases in a fixed order, so that reordering the config reruns nothing."""
    return sorted(config["md"]["runs"])


def md_setting(case, key):
    """A per-case MD setting, falling back to the md section's default."""
    return config["md"]["runs"][case].get(key, config["md"].get(key))


def md_run(case, dynamics, seed):
    """Everything one MD realisation needs, as plain values (a change reruns the run)."""
    md = config["md"]
    keys = (
        "dt",
        "t_max",
        "t_equilibrate",
        "sample_every",
        "max_lag",
        "origin_every",
        "n_blocks",
    )
    run = {k: md_setting(case, k) for k in keys}
    run.update(
        dynamics=dynamics,
        seed=seed,
        n_particles=md_setting(case, "n_particles"),
        n_test=md_setting(case, f"n_test_{dynamics}"),
        kappa_max=md_setting(case, "kappa_max"),
        n_bins=md_setting(case, "n_bins"),
    )
    return run


def md_files(case, dynamics):
    n = md_setting(case, "seeds")
    return [f"results/md/{case}/{dynamics}/seed{s}.nc" for s in range(n)]


def md_fit_spec(case):
    keys = ("fit_window", "min_particles", "separatrix_band_fit")
    return {k: md_setting(case, k) for k in keys}


def md_mem_mb(case, dynamics):
    """Peak memory: state (~40 B per particle) and the ring buffer of J(t0) of tracked particles."""
    n = md_setting(case, "n_particles") + md_setting(case, f"n_test_{dynamics}")
    n_track = n if dynamics == "full" else md_setting(case, f"n_test_{dynamics}")
    slots = md_setting(case, "max_lag") / md_setting(case, "origin_every") + 1
    return int(1000 + (48 * n + 11 * n_track * slots) / 1e6 * 1.3)


def md_runtime_min(case, dynamics):
    """Wall-time request in minutes, from N, the run length and a conservative 5e7 steps/s."""
    n = md_setting(case, "n_particles") + md_setting(case, f"n_test_{dynamics}")
    t = md_setting(case, "t_max") + md_setting(case, "t_equilibrate")
    steps = n * t / md_setting(case, "dt")
    return int(10 + steps / 5e7 / 60 * 2)


rule md:
    """One MD realisation (seed): MD(bath) or MD(full), with <dJ^2> accumulated on the fly."""
    input:
        equilibrium="results/equilibrium/{case}.nc",
        lib=lib(
            "md",
            "elementary",
            "integrator",
            "accumulator",
            "sampling",
            "orbits",
            "equilibrium",
            "datasets",
            "io",
        ),
    output:
        "results/md/{case}/{dynamics}/seed{seed}.nc",
    log:
        "logs/md/{case}/{dynamics}/seed{seed}.log",
    wildcard_constraints:
        dynamics="bath|full",
        seed=r"\d+",
    conda:
        "../envs/hmfdiff.yaml"
    threads: config["md"]["threads"]
    resources:
        mem_mb=lambda w: md_mem_mb(w.case, w.dynamics),
        runtime=lambda w: md_runtime_min(w.case, w.dynamics),
    params:
        run=lambda w: json.dumps(
            md_run(w.case, w.dynamics, int(w.seed)), sort_keys=True
        ),
    script:
        "../scripts/md.py"


rule fit:
    """N*D_MD per J-bar_0 bin: half the slope of <dJ^2>(dt), pooled over seeds."""
    input:
        seeds=lambda w: md_files(w.case, w.dynamics),
        lib=lib("fits", "orbits", "io"),
    output:
        "results/fits/{case}_{dynamics}.nc",
    log:
        "logs/fits/{case}_{dynamics}.log",
    wildcard_constraints:
        dynamics="bath|full",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        fit=lambda w: json.dumps(md_fit_spec(w.case), sort_keys=True),
    script:
        "../scripts/fit.py"


rule validation:
    """results/validation.csv: MD against theory per case, dynamics and bin, and a summary."""
    input:
        fits=[f"results/fits/{c}_{d}.nc" for c in md_cases() for d in ("bath", "full")],
        theory=[f"results/theory/{c}.nc" for c in md_cases() for d in ("bath", "full")],
        equilibrium=[
            f"results/equilibrium/{c}.nc" for c in md_cases() for d in ("bath", "full")
        ],
        lib=lib("fits", "datasets", "equilibrium", "io"),
    output:
        table=report(
            "results/validation.csv",
            caption="../report/validation.rst",
            category="Validation",
        ),
        summary="results/validation_summary.txt",
    log:
        "logs/validation.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        cases=[c for c in md_cases() for d in ("bath", "full")],
    script:
        "../scripts/validation.py"
