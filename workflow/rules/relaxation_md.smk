rule relaxation_md:
    """An ensemble of N-body relaxations (full dynamics) of one case at one N."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
        kernels=KERNELS,
    output:
        f"{RES}/relaxation_md/{{case}}/N{{n}}.nc",
    log:
        f"{LOG}/relaxation_md/{{case}}/N{{n}}.log",
    wildcard_constraints:
        n=r"\d+",
    priority: 2
    conda:
        "../envs/hmfdiff.yaml"
    threads: lambda w: config["relaxation_md"]["threads"]
    resources:
        mem_mb=2000,
        runtime=lambda w: relaxation_md_runtime_min(w.case, w.n),
    params:
        library=library("relaxation_md.py"),
        run=lambda w: relaxation_md_run(w.case),
        initial="state",
    script:
        "../scripts/relaxation_md.py"


rule relaxation_md_control:
    """The thermal control of an ensemble: the thermal state of the case's energy, with the same
    N, realisations, bins, time step and schedule (the measurement floor)."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
        kernels=KERNELS,
    output:
        f"{RES}/relaxation_md/{{case}}/thermal/N{{n}}.nc",
    log:
        f"{LOG}/relaxation_md/{{case}}/thermal/N{{n}}.log",
    wildcard_constraints:
        n=r"\d+",
    priority: 2
    conda:
        "../envs/hmfdiff.yaml"
    threads: lambda w: config["relaxation_md"]["threads"]
    resources:
        mem_mb=2000,
        runtime=lambda w: relaxation_md_runtime_min(w.case, w.n),
    params:
        library=library("relaxation_md.py"),
        run=lambda w: relaxation_md_run(w.case),
        initial="thermal",
    script:
        "../scripts/relaxation_md.py"


rule relaxation_comparison:
    """N-body relaxation against the kinetic evolutions at matched t/N; relaxation time vs N."""
    input:
        unpack(relaxation_comparison_inputs),
    output:
        table=f"{RES}/relaxation_comparison.csv",
        summary=f"{RES}/relaxation_comparison_summary.txt",
        datasets=[f"{RES}/relaxation_comparison/{c}.nc" for c in relaxation_md_cases()],
    log:
        f"{LOG}/relaxation_comparison.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("relaxation_comparison.py"),
        cases=relaxation_md_cases(),
    script:
        "../scripts/relaxation_comparison.py"


rule relaxation_rates_md:
    """An ensemble over the early window, drawn from the case's state or from the thermal state
    of its energy (the control), at one N."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
        kernels=KERNELS,
    output:
        f"{RES}/relaxation_rates/{{case}}/{{initial}}/N{{n}}.nc",
    log:
        f"{LOG}/relaxation_rates/{{case}}/{{initial}}/N{{n}}.log",
    wildcard_constraints:
        n=r"\d+",
        initial="|".join(INITIALS),
    priority: 2
    conda:
        "../envs/hmfdiff.yaml"
    threads: lambda w: config["relaxation_md"]["threads"]
    resources:
        mem_mb=2000,
        runtime=lambda w: relaxation_rates_runtime_min(w.n),
    params:
        library=library("relaxation_md.py"),
        run=lambda w: relaxation_rates_run(),
        initial=lambda w: w.initial,
    script:
        "../scripts/relaxation_md.py"


rule relaxation_rates:
    """Early N-body relaxation across N against the kinetic equations and the thermal control."""
    input:
        unpack(relaxation_rates_inputs),
    output:
        dataset=f"{RES}/relaxation_rates/{{case}}.nc",
        summary=f"{RES}/relaxation_rates/{{case}}_summary.txt",
    log:
        f"{LOG}/relaxation_rates/{{case}}.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=15,
    params:
        library=library("relaxation_rates.py"),
    script:
        "../scripts/relaxation_rates.py"
