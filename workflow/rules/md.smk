rule kernels:
    """Compile the MD kernels once into a shared numba cache (one per kernel version), which
    every MD job copies before it starts: no job compiles, and no two write one cache.
    """
    input:
        lib=lib("kernels.py"),
    output:
        directory(KERNELS),
    log:
        "logs/kernels.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1500,
        runtime=15,
    script:
        "../scripts/kernels.py"


rule md:
    """One MD realisation (seed): MD(bath) or MD(full), with <dJ^2> accumulated on the fly."""
    input:
        equilibrium="results/equilibrium/{case}.nc",
        kernels=KERNELS,
        lib=lib("md.py"),
    output:
        "results/md/{case}/{dynamics}/seed{seed}.nc",
    log:
        "logs/md/{case}/{dynamics}/seed{seed}.log",
    wildcard_constraints:
        dynamics="bath|full",
        seed=r"\d+",
    conda:
        "../envs/hmfdiff.yaml"
    threads: lambda w: md_run(w.case, w.dynamics).threads
    resources:
        mem_mb=lambda w: md_mem_mb(w.case, w.dynamics),
        runtime=lambda w: md_runtime_min(w.case, w.dynamics),
    params:
        run=lambda w: md_run(w.case, w.dynamics).realisation_json(),
    script:
        "../scripts/md.py"


rule fit:
    """N*D_MD per J-bar_0 bin: half the slope of <dJ^2>(dt), pooled over seeds."""
    input:
        seeds=lambda w: md_files(w.case, w.dynamics),
        lib=lib("fit.py"),
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
        lib=lib("validation.py"),
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
