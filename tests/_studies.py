"""Loading a script of studies/ as a module in a test (studies/ is not a package; its scripts
import their shared helpers from studies/ itself)."""

import importlib.util
import sys
from pathlib import Path

STUDIES = Path(__file__).resolve().parents[1] / "studies"


def load_study(name):
    """studies/{name}.py as a module."""
    if str(STUDIES) not in sys.path:
        sys.path.append(str(STUDIES))
    spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
