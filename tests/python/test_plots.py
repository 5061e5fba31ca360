"""The plot script's reading of summary.json (src/python/jointhb_plot.py): the extrema located
between points are marked for discrete (`curves[]`) and finite-element (`frfs[]`) FRFs alike."""
import json
import os
import subprocess
import sys
from pathlib import Path

SOURCE = Path(os.environ.get("JOINTHB_SOURCE_DIR", Path(__file__).resolve().parents[2]))
PROGRAM = os.environ.get("JOINTHB_PROGRAM", str(SOURCE / "build" / "jointhb"))
sys.path.insert(0, str(SOURCE / "src" / "python"))

import jointhb_plot  # noqa: E402


def test_located_peaks_and_folds_of_a_discrete_run_are_read_for_the_plot(tmp_path):
    """Case 15 (a preloaded normal contact whose FRF folds from 2 N on): every refined peak and fold
    of summary.json, per level, and frf.png drawn."""
    out = tmp_path / "out"
    subprocess.run([PROGRAM, "run", str(SOURCE / "cases/15-normal-contact-fold/case.yaml"), "-o", str(out),
                    "--plot"], check=True, capture_output=True)
    curves = json.load(open(out / "summary.json"))["curves"]
    located = jointhb_plot.located_extrema(str(out))
    assert sorted(located) == sorted(str(c["level"]) for c in curves)
    for c in curves:
        peak, folds = located[str(c["level"])]
        assert peak == ((c["peak"]["frequency_hz"], c["peak"]["amplitude_h1"]) if c["peak"]["refined"] else None)
        assert folds == [(f["frequency_hz"], f["amplitude_h1"]) for f in c["fold_points"] if f["refined"]]
    assert sum(len(f) for _, f in located.values()) >= 2  # the case folds
    assert (out / "frf.png").stat().st_size > 0


def test_a_finite_element_summary_marks_refined_extrema_only(tmp_path):
    summary = {"frfs": [{"level": 0, "peak": {"frequency_hz": 943.0, "amplitude_h1": 2.3e-4, "refined": True},
                         "fold_points": [{"frequency_hz": 944.0, "amplitude_h1": 2.0e-4, "refined": False}]},
                        {"level": 1, "peak": {"frequency_hz": 940.0, "amplitude_h1": 4.0e-4, "refined": False,
                                              "note": "the largest amplitude is at an end of the curve"},
                         "fold_points": []}]}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    assert jointhb_plot.located_extrema(str(tmp_path)) == {"0": ((943.0, 2.3e-4), []), "1": (None, [])}
    assert jointhb_plot.located_extrema(str(tmp_path / "missing")) == {}
