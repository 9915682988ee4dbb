rule figure:
    """One figure of the paper, drawn from its netCDF inputs (PDF and PNG)."""
    input:
        unpack(figure_inputs),
    output:
        pdf=f"{RES}/figures/{{name}}.pdf",
        png=report(
            f"{RES}/figures/{{name}}.png",
            caption="../report/figure.rst",
            category=lambda w: FIGURES[w.name].category,
            labels=lambda w: {
                "figure": f"{FIGURES[w.name].number:02d}",
                "file": f"{w.name}.png",
            },
        ),
    log:
        f"{LOG}/figures/{{name}}.log",
    wildcard_constraints:
        name="|".join(FIGURES),
    conda:
        "../envs/hmfdiff.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=15,
    params:
        library=library("figure.py"),
        spec=lambda w: json.dumps(figure_spec(w.name), sort_keys=True),
        # the registry's caption as it reads (the report's template escapes it for RST)
        caption=lambda w: FIGURES[w.name].caption,
    script:
        "../scripts/figure.py"


# Short names: `snakemake -j2 fig2`
for _name in figure_names():

    rule:
        name:
            FIGURES[_name].target
        input:
            f"{RES}/figures/{_name}.pdf",
            f"{RES}/figures/{_name}.png",
        localrule: True
