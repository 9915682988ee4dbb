rule relaxation:
    """Collisional relaxation f(J-bar, tau) of one case by the Landau or Lenard-Balescu equation."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
    output:
        f"{RES}/relaxation/{{case}}_{{equation}}.nc",
    log:
        f"{LOG}/relaxation/{{case}}_{{equation}}.log",
    wildcard_constraints:
        equation="landau|lenard_balescu",
    priority: 2
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=60,
    params:
        library=library("relaxation.py"),
        run=lambda w: relaxation_run(w.case),
    script:
        "../scripts/relaxation.py"
