rule fig01_orbits:
    """Fig. 1: librating, separatrix and rotating orbits in (theta, p)."""
    input:
        orbits=lambda w: f"results/orbits/{figure_case('fig01_orbits')}.nc",
        lib=lib("plotting", "orbits"),
    output:
        pdf="results/figures/fig01_orbits.pdf",
        png="results/figures/fig01_orbits.png",
    log:
        "logs/figures/fig01_orbits.log",
    conda:
        "../envs/hmfdiff.yaml"
    params:
        name="fig01_orbits",
    script:
        "../scripts/figure.py"


rule fig02_action_frequency:
    """Fig. 2: J(kappa); Omega(J) with inset Omega(kappa)."""
    input:
        orbits=lambda w: f"results/orbits/{figure_case('fig02_action_frequency')}.nc",
        lib=lib("plotting", "orbits"),
    output:
        pdf="results/figures/fig02_action_frequency.pdf",
        png="results/figures/fig02_action_frequency.png",
    log:
        "logs/figures/fig02_action_frequency.log",
    conda:
        "../envs/hmfdiff.yaml"
    params:
        name="fig02_action_frequency",
    script:
        "../scripts/figure.py"


rule fig03_poles:
    """Fig. 3: poles omega/l = Omega(kappa) of the dielectric integrand."""
    input:
        orbits=lambda w: f"results/orbits/{figure_case('fig03_poles')}.nc",
        lib=lib("plotting", "orbits"),
    output:
        pdf="results/figures/fig03_poles.pdf",
        png="results/figures/fig03_poles.png",
    log:
        "logs/figures/fig03_poles.log",
    conda:
        "../envs/hmfdiff.yaml"
    params:
        name="fig03_poles",
    script:
        "../scripts/figure.py"


# Short names: `snakemake -j2 fig2`
for _name, _short in FIGURES.items():
    if _name in config["figures"]:

        rule:
            name:
                _short
            input:
                f"results/figures/{_name}.pdf",
                f"results/figures/{_name}.png",
            localrule: True
