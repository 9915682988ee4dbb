"""What the studies that draw their own MD realisations share: one seed file per realisation,
skipped when already written (a study can be stopped and resumed), and a report printed or
written to a file."""

from __future__ import annotations

import sys
import time
from pathlib import Path


def draw_realisations(folder, state, rec, first, last, case, label=""):
    """Seeds first ... last of the MD record `rec` of `state` into folder/seed{s}.nc (one
    thread each; a seed file already there is kept)."""
    from hmfdiff.dynamics.md import run_md
    from hmfdiff.pipeline.io import write_dataset
    from hmfdiff.pipeline.layouts.md import md_dataset

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for seed in range(int(first), int(last) + 1):
        path = folder / f"seed{seed}.nc"
        if path.exists():
            continue
        t0 = time.perf_counter()
        ds = md_dataset(run_md(state, rec, seed, 1, progress=None))
        prov = {"md": rec.to_dict(realisation_only=True), "seed": seed, "M0": state.M0}
        write_dataset(ds, path, prov, case=case)
        print(f"{label}seed {seed}: {time.perf_counter() - t0:.1f} s", flush=True)


def emit(lines, out=None):
    """Print the report's lines, and write them to `out` when given."""
    text = "\n".join(lines) + "\n"
    if out:
        Path(out).write_text(text)
    sys.stdout.write(text)
