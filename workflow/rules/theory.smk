rule theory:
    """Dielectric tensor, Landau and Lenard-Balescu N*D_dif and N*D_pol, resonance contributions."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
    output:
        f"{RES}/theory/{{case}}.nc",
    log:
        f"{LOG}/theory/{{case}}.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=30,
    params:
        library=library("theory.py"),
        grid=lambda w: json.dumps(config["theory"], sort_keys=True),
    script:
        "../scripts/theory.py"
