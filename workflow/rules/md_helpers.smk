# ---- molecular dynamics -------------------------------------------------------------
def md_cases():
    """MD cases in a fixed order, so that reordering the config reruns nothing."""
    return sorted(config["md"]["runs"])


def md_setting(case, key):
    """A per-case MD setting, falling back to the md section's default."""
    return config["md"]["runs"][case].get(key, config["md"].get(key))


def md_run(case, dynamics, seed):
    """Everything one MD realisation needs, as plain values (a change reruns the run)."""
    md = config["md"]
    keys = (
        "dt",
        "t_max",
        "t_equilibrate",
        "sample_every",
        "max_lag",
        "origin_every",
        "n_blocks",
    )
    run = {k: md_setting(case, k) for k in keys}
    run.update(
        dynamics=dynamics,
        seed=seed,
        n_particles=md_setting(case, "n_particles"),
        n_test=md_setting(case, f"n_test_{dynamics}"),
        kappa_max=md_setting(case, "kappa_max"),
        n_bins=md_setting(case, "n_bins"),
    )
    return run


def md_files(case, dynamics):
    n = md_setting(case, "seeds")
    return [f"results/md/{case}/{dynamics}/seed{s}.nc" for s in range(n)]


def md_fit_spec(case):
    keys = ("fit_window", "min_particles", "separatrix_band_fit")
    return {k: md_setting(case, k) for k in keys}


def md_mem_mb(case, dynamics):
    """Peak memory: state (~40 B per particle) and the ring buffer of J(t0) of tracked particles."""
    n = md_setting(case, "n_particles") + md_setting(case, f"n_test_{dynamics}")
    n_track = n if dynamics == "full" else md_setting(case, f"n_test_{dynamics}")
    slots = md_setting(case, "max_lag") / md_setting(case, "origin_every") + 1
    return int(1000 + (48 * n + 11 * n_track * slots) / 1e6 * 1.3)


def md_runtime_min(case, dynamics):
    """Wall-time request in minutes, from N, the run length and a conservative 5e7 steps/s."""
    n = md_setting(case, "n_particles") + md_setting(case, f"n_test_{dynamics}")
    t = md_setting(case, "t_max") + md_setting(case, "t_equilibrate")
    steps = n * t / md_setting(case, "dt")
    return int(10 + steps / 5e7 / 60 * 2)
