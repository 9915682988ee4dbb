# hmfdiff: reproduce Benetti & Marcos, PRE 95, 022111 (2017) from nothing.
#
#   snakemake -j2                                   # every target, paper size
#   snakemake -j2 --configfile config/smoke.yaml    # the same pipeline at toy size
#   snakemake -j2 fig2                              # one figure (fig1 ... fig10)
#
# Every intermediate is a netCDF file under results/; see README.md.

from snakemake.utils import min_version, validate

from hmfdiff.pipeline.config import check_config

min_version("9.0")


report: "workflow/report/workflow.rst"


# The paper's configuration unless another one is given with --configfile (Snakemake would
# otherwise merge the two, and a smoke run would inherit every paper case).
if "cases" not in config:

    configfile: "config/config.yaml"


# Physics-level checks with messages naming case and field, then the JSON schema.
check_config(config)
validate(config, "workflow/schemas/config.schema.yaml")

CASES = list(config["cases"])


wildcard_constraints:
    case="|".join(re.escape(c) for c in CASES),


include: "workflow/rules/common.smk"
include: "workflow/rules/md_helpers.smk"
include: "workflow/rules/figure_helpers.smk"
include: "workflow/rules/equilibrium.smk"
include: "workflow/rules/orbits.smk"
include: "workflow/rules/theory.smk"
include: "workflow/rules/analytic.smk"
include: "workflow/rules/md.smk"
include: "workflow/rules/figures.smk"


rule all:
    default_target: True
    input:
        expand("results/equilibrium/{case}.nc", case=CASES),
        expand("results/orbits/{case}.nc", case=CASES),
        expand("results/theory/{case}.nc", case=theory_cases()),
        expand("results/analytic/{case}.nc", case=CASES),
        "results/validation.csv",
        figure_targets(),
