# hmfdiff: reproduce Benetti & Marcos, PRE 95, 022111 (2017) from nothing.
#
#   snakemake -j2                                   # every target, paper size
#   snakemake -j2 --configfile config/smoke.yaml    # the same pipeline at toy size
#   snakemake -j2 fig2                              # one figure (fig1 ... fig16)
#
# Every intermediate is a netCDF file under results/; see README.md.

import sys

from snakemake.utils import min_version

from hmfdiff.pipeline.config import ConfigError, check_config_files, prepare_config

min_version("9.0")


report: "workflow/report/workflow.rst"


# The configuration, checked once before any job; a bad one stops here with one line naming
# the case or section, the field, the value and what is allowed, and nothing is written.
# The paper's configuration is read unless --configfile is given (Snakemake would otherwise
# merge the two, and a smoke run would inherit every paper case).  --config overrides are
# applied on top of the file, whichever top-level key they name (nested keys merge; numbers as
# strings are read):
#   snakemake --config md='{dt: 0.05}' 'cases={thermal_u-0.1: {u: -0.12}}'
CONFIG_FILES = [str(f) for f in workflow.overwrite_configfiles]
DEFAULT_CONFIG = not CONFIG_FILES
if DEFAULT_CONFIG:
    CONFIG_FILES.insert(0, "config/config.yaml")
try:
    check_config_files(CONFIG_FILES)  # malformed YAML, a key given twice: named by file
except ConfigError as e:
    sys.exit(f"Config error: {e}")

if DEFAULT_CONFIG:

    configfile: "config/config.yaml"


try:
    prepare_config(config, f"{workflow.basedir}/workflow/schemas/config.schema.yaml")
except ConfigError as e:
    sys.exit(f"Config error: {e}")

CASES = list(config["cases"])
RES = config["results_dir"]  # every output (results/smoke for config/smoke.yaml)
LOG = config["log_dir"]  # every job's log


wildcard_constraints:
    case="|".join(re.escape(c) for c in CASES),


include: "workflow/rules/common.smk"
include: "workflow/rules/md_helpers.smk"
include: "workflow/rules/figure_helpers.smk"
include: "workflow/rules/relaxation_helpers.smk"
include: "workflow/rules/relaxation_md_helpers.smk"
include: "workflow/rules/equilibrium.smk"
include: "workflow/rules/orbits.smk"
include: "workflow/rules/theory.smk"
include: "workflow/rules/analytic.smk"
include: "workflow/rules/md.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/relaxation.smk"
include: "workflow/rules/relaxation_md.smk"


# A run that starts holds the directory lock: job scripts still in .snakemake/scripts were left
# by killed jobs (restart after a kill: snakemake --unlock, then the same command with
# --rerun-incomplete).
onstart:
    from hmfdiff.pipeline.runtime import (
        drop_local_job_rate_limiter,
        remove_stale_job_scripts,
    )

    remove_stale_job_scripts()
    drop_local_job_rate_limiter(workflow)


rule all:
    default_target: True
    input:
        expand(f"{RES}/equilibrium/{{case}}.nc", case=CASES),
        expand(f"{RES}/orbits/{{case}}.nc", case=CASES),
        expand(f"{RES}/theory/{{case}}.nc", case=theory_cases()),
        expand(f"{RES}/analytic/{{case}}.nc", case=CASES),
        f"{RES}/validation.csv",
        relaxation_files(),
        relaxation_md_files(),
        relaxation_comparison_outputs(),
        relaxation_rates_outputs(),
        figure_targets(),
