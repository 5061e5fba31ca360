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


def run_study(case_file, output, jobs=1, resume=False, cache_dir=None):
    """The parameter study of a case file's study section (docs/studies.md): every sample through
    the pipeline on `jobs` worker processes, the files of `jointhb study` written into `output`
    (study.csv, study_statistics.csv, study_curves.csv, study.json, samples/; no plot), and
    study.json returned as a dict. `resume=True` reuses the sample records found in output/samples.
    Raises jointhb.InputError for a bad case file, ValueError for a case without a study section."""
    import json
    import os

    from . import _core

    if int(jobs) < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    _core._run_study(os.fspath(case_file), os.fspath(output), int(jobs), bool(resume),
                     os.fspath(cache_dir) if cache_dir else "")
    with open(os.path.join(os.fspath(output), "study.json")) as f:
        return json.load(f)


def case_from_dict(case, directory="."):
    """A finite-element case from Python values: the same keys as a case file (docs/case-files.md),
    e.g. {"model": {"type": "fe", "materials": {...}, "parts": [...], "interfaces": [...],
    "bolts": [...]}, "analysis": {...}}. Mesh files are looked up in `directory`. Errors raise
    jointhb.InputError naming the key path (and a line of the dict written one key per line)."""
    import json
    import os

    text = json.dumps(case, indent=1, allow_nan=False)
    return parse_case(text, os.path.join(str(directory), "<python dict>"))

__all__ = ["Case", "DiscreteModel", "InputError", "Pipeline", "StageError", "case_from_dict", "default_case", "fit", "run_study",
           "load_case", "parse_case"]
