rule closed_forms:
    """The paper's closed forms for one case: sech^4 Landau D, two-step and appendix-C eps and D."""
    input:
        equilibrium=f"{RES}/equilibrium/{{case}}.nc",
    output:
        f"{RES}/analytic/{{case}}.nc",
    log:
        f"{LOG}/analytic/{{case}}.log",
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=15,
    params:
        library=library("closed_forms.py"),
        grid=lambda w: json.dumps(config["closed_forms"], sort_keys=True),
    script:
        "../scripts/closed_forms.py"
