rule orbits:
    """Action-angle variables J, Omega, derivatives and Fourier coefficients c_n, s_n on a kappa grid."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
    output:
        f"{RES}/orbits/{{case}}.nc",
    log:
        f"{LOG}/orbits/{{case}}.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=15,
    params:
        library=library("orbits.py"),
        grid=lambda w: json.dumps(config["grids"]["orbits"], sort_keys=True),
    script:
        "../scripts/orbits.py"
