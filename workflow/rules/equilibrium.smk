rule equilibrium:
    """Equilibrium state of one case: beta or self-consistent M0, u, f(kappa), df/dkappa."""
    output:
        f"{RES}/equilibrium/{{case}}.nc",
    log:
        f"{LOG}/equilibrium/{{case}}.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=15,
    params:
        library=library("equilibrium.py"),
        spec=case_spec,
        grid=lambda w: json.dumps(config["grids"]["equilibrium"], sort_keys=True),
    script:
        "../scripts/equilibrium.py"
