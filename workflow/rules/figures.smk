rule figure:
    """One figure of the paper, drawn from its netCDF inputs (PDF and PNG)."""
    input:
        unpack(figure_inputs),
    output:
        pdf="results/figures/{name}.pdf",
        png="results/figures/{name}.png",
    log:
        "logs/figures/{name}.log",
    wildcard_constraints:
        name="|".join(FIGURES),
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=15,
    params:
        name="{name}",
        cases=lambda w: figure_cases(w.name),
    script:
        "../scripts/figure.py"


# Short names: `snakemake -j2 fig2`
for _name, (_short, _kind) in FIGURES.items():
    if _name in config["figures"]:

        rule:
            name:
                _short
            input:
                f"results/figures/{_name}.pdf",
                f"results/figures/{_name}.png",
            localrule: True
