rule kernels:
    """Compile the MD kernels once into a shared numba cache (one per kernel version), which
    every MD job copies before it starts: no job compiles, and no two write one cache.
    """
    output:
        directory(KERNELS),
    log:
        f"{LOG}/kernels.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1500,
        runtime=15,
    params:
        library=library("kernels.py"),
    script:
        "../scripts/kernels.py"


# priorities: the long jobs (MD blocks, relaxations) start first, so that the short ones (fits,
# figures) fill both cores at the end instead of one MD block running alone
rule md:
    """A block of MD realisations (seeds {first} ... {last}) of MD(bath) or MD(full), with
    <dJ^2> accumulated on the fly: one seed{s}.nc per seed in the block's folder.
    """
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
        kernels=KERNELS,
    output:
        directory(f"{RES}/md/{{case}}/{{dynamics}}/seeds{{first}}-{{last}}"),
    log:
        f"{LOG}/md/{{case}}/{{dynamics}}/seeds{{first}}-{{last}}.log",
    wildcard_constraints:
        dynamics="bath|full",
        first=r"\d+",
        last=r"\d+",
    priority: 3
    conda:
        "../envs/hmfdiff.yaml"
    threads: lambda w: md_run(w.case, w.dynamics).threads
    resources:
        mem_mb=lambda w: md_mem_mb(w.case, w.dynamics),
        runtime=lambda w: md_runtime_min(w.case, w.dynamics, w.first, w.last),
    params:
        library=library("md.py"),
        run=lambda w: md_run(w.case, w.dynamics).realisation_json(),
        seeds=lambda w: md_block(w.case, w.dynamics, w.first, w.last),
    script:
        "../scripts/md.py"


rule fit:
    """N*D_MD per J-bar_0 bin: half the slope of <dJ^2>(dt), pooled over seeds."""
    input:
        seeds=lambda w: md_folders(w.case, w.dynamics),
    output:
        f"{RES}/fits/{{case}}_{{dynamics}}.nc",
    log:
        f"{LOG}/fits/{{case}}_{{dynamics}}.log",
    wildcard_constraints:
        dynamics="bath|full",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("fit.py"),
        fit=lambda w: json.dumps(md_fit_spec(w.case), sort_keys=True),
        n_seeds=lambda w: md_run(w.case, w.dynamics).seeds,
    script:
        "../scripts/fit.py"


rule windowed:
    """The theory's finite-time <dJ^2> fitted over the MD fit's own lags and window, bare for
    MD(bath), dressed for MD(full), averaged over each bin like ND_md."""
    input:
        fit=f"{RES}/fits/{{case}}_{{dynamics}}.nc",
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
    output:
        f"{RES}/windowed/{{case}}_{{dynamics}}.nc",
    log:
        f"{LOG}/windowed/{{case}}_{{dynamics}}.log",
    wildcard_constraints:
        dynamics="bath|full",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("windowed.py"),
        n_max=config["theory"]["n_max"],
        l_max=config["theory"]["l_max"],
        separatrix_band=config["theory"]["separatrix_band"],
    script:
        "../scripts/windowed.py"


rule validation:
    """results/validation.csv: MD against theory per case, dynamics and bin, and a summary."""
    input:
        fits=[f"{RES}/fits/{c}_{d}.nc" for c in md_cases() for d in ("bath", "full")],
        theory=[f"{RES}/theory/{c}.nc" for c in md_cases() for d in ("bath", "full")],
        equilibrium=[
            f"{RES}/equilibrium/{c}.nc" for c in md_cases() for d in ("bath", "full")
        ],
        windowed=[
            f"{RES}/windowed/{c}_{d}.nc" for c in md_cases() for d in ("bath", "full")
        ],
    output:
        table=report(
            f"{RES}/validation.csv",
            caption="../report/validation.rst",
            category="Validation",
        ),
        summary=f"{RES}/validation_summary.txt",
    log:
        f"{LOG}/validation.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("validation.py"),
        cases=[c for c in md_cases() for d in ("bath", "full")],
        sizes={c: MD_RUNS[(c, "full")].n_particles for c in md_cases()},
    script:
        "../scripts/validation.py"


rule spectrum:
    """N S_x, N S_y of the magnetisation measured in MD(bath) and MD(full) (Welch, all seeds)
    against the bare and dressed bath spectra; harmonics n' <= max(8, theory n_max): fewer
    leave out the slow orbits' high harmonics that fill the low frequencies."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
        bath=lambda w: md_folders(w.case, "bath"),
        full=lambda w: md_folders(w.case, "full"),
    output:
        f"{RES}/spectrum/{{case}}.nc",
    log:
        f"{LOG}/spectrum/{{case}}.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("spectrum.py"),
        n_max=max(8, config["theory"]["n_max"]),
        l_max=config["theory"]["l_max"],
        seeds_bath=lambda w: md_run(w.case, "bath").seeds,
        seeds_full=lambda w: md_run(w.case, "full").seeds,
    script:
        "../scripts/spectrum.py"


rule md_scaling:
    """Every MD realisation of one size N = {n} of the 1/N study of {case} (config md_scaling),
    seed after seed in one job: at small N a realisation takes less than starting a job.
    """
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
        kernels=KERNELS,
    output:
        directory(f"{RES}/scaling/{{case}}/{{dynamics}}/N{{n}}/seeds"),
    log:
        f"{LOG}/scaling/{{case}}/{{dynamics}}/N{{n}}/md.log",
    wildcard_constraints:
        dynamics="bath|full",
        n=r"\d+",
    priority: 1
    conda:
        "../envs/hmfdiff.yaml"
    threads: lambda w: scaling_run(w.case, w.dynamics, w.n).threads
    resources:
        mem_mb=lambda w: scaling_run(w.case, w.dynamics, w.n).memory_mb(),
        runtime=lambda w: scaling_run(w.case, w.dynamics, w.n).runtime_min(
            scaling_run(w.case, w.dynamics, w.n).seeds
        ),
    params:
        library=library("md.py"),
        run=lambda w: scaling_run(w.case, w.dynamics, w.n).realisation_json(),
        seeds=lambda w: [0, scaling_run(w.case, w.dynamics, w.n).seeds - 1],
    script:
        "../scripts/md.py"


rule fit_scaling:
    """N*D_MD per bin at one N of the 1/N study, pooled over its seeds."""
    input:
        seeds=f"{RES}/scaling/{{case}}/{{dynamics}}/N{{n}}/seeds",
    output:
        f"{RES}/scaling/{{case}}/{{dynamics}}/N{{n}}/fit.nc",
    log:
        f"{LOG}/scaling/{{case}}/{{dynamics}}/N{{n}}/fit.log",
    wildcard_constraints:
        dynamics="bath|full",
        n=r"\d+",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("fit.py"),
        fit=lambda w: json.dumps(
            scaling_run(w.case, w.dynamics, w.n).fit_settings(), sort_keys=True
        ),
        n_seeds=lambda w: scaling_run(w.case, w.dynamics, w.n).seeds,
    script:
        "../scripts/fit.py"


rule scaling:
    """results/scaling/{case}_{dynamics}.nc: N*D_MD per bin against N (figure 15), beside the
    theory of the dynamics and the other one, bin-averaged like validation.csv's ND_theory.
    """
    input:
        fits=lambda w: [
            f"{RES}/scaling/{w.case}/{w.dynamics}/N{n}/fit.nc"
            for n in scaling_sizes(w.case)
        ],
        theory=f"{RES}/theory/{{case}}.nc",
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
    output:
        f"{RES}/scaling/{{case}}_{{dynamics}}.nc",
    log:
        f"{LOG}/scaling/{{case}}_{{dynamics}}.log",
    wildcard_constraints:
        dynamics="bath|full",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        library=library("scaling.py"),
        sizes=lambda w: scaling_sizes(w.case),
        kappa0=lambda w: SCALING_KAPPA0[w.case],
    script:
        "../scripts/scaling.py"
