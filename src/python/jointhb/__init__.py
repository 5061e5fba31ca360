"""jointhb: vibration of bolted, built-up structures by harmonic balance.

The finite-element pipeline of a case file -- preload, modes, the model condensed to the contact
interface, damping curves (EPMC) and nonlinear FRFs -- as a Python object. Every stage is
computed when first needed and kept while its inputs do not change; ``Pipeline.set`` changes a
parameter and with it exactly the stages that depend on it. Units are SI throughout.

    import jointhb
    p = jointhb.Pipeline(jointhb.load_case("cases/08-lap-damping/case.yaml"))
    curve = p.backbone(mode=1)                  # numpy arrays
    print(curve["frequency_hz"], curve["damping_ratio"])

See docs/python.md.
"""

from ._core import (  # noqa: F401  (the package's interface)
    Case,
    DiscreteModel,
    InputError,
    Pipeline,
    StageError,
    default_case,
    fit,
    load_case,
    parse_case,
)


def case_from_dict(case, directory="."):
    """A finite-element case from Python values: the same keys as a case file (docs/case-files.md),
    e.g. {"model": {"type": "fe", "materials": {...}, "parts": [...], "interfaces": [...],
    "bolts": [...]}, "analysis": {...}}. Mesh files are looked up in `directory`. Errors raise
    jointhb.InputError naming the key path (and a line of the dict written one key per line)."""
    import json
    import os

    text = json.dumps(case, indent=1, allow_nan=False)
    return parse_case(text, os.path.join(str(directory), "<python dict>"))

__all__ = ["Case", "DiscreteModel", "InputError", "Pipeline", "StageError", "case_from_dict", "default_case", "fit",
           "load_case", "parse_case"]
