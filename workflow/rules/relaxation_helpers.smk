# Helpers of the kinetic relaxation rule (relaxation.smk).


def relaxation_cases():
    """Cases evolved by the kinetic equations; each must be a smooth state under `cases`."""
    runs = config.get("relaxation", {}).get("runs", {})
    for name in runs:
        kind = config["cases"].get(name, {}).get("kind")
        if kind is None:
            sys.exit(
                f"Config error: relaxation.runs.{name}: no case of that name under `cases` "
                f"(cases: {', '.join(config['cases'])})"
            )
        if kind == "two_step":
            sys.exit(
                f"Config error: relaxation.runs.{name}: kind two_step has delta-function "
                "df/dkappa; evolve a smooth state (thermal or core_halo)"
            )
    return sorted(runs)


def relaxation_files():
    equations = config.get("relaxation", {}).get("equations", [])
    return [
        f"{RES}/relaxation/{c}_{e}.nc" for c in relaxation_cases() for e in equations
    ]


def relaxation_run(case):
    """The settings of one case's evolution (defaults merged with its own), as JSON."""
    rel = config["relaxation"]
    run = {k: v for k, v in rel.items() if k not in ("runs", "equations")}
    run.update(rel["runs"][case] or {})
    return json.dumps(run, sort_keys=True)
