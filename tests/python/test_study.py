"""jointhb.run_study (docs/studies.md §6): the same files as `jointhb study`, bit for bit, for any
number of worker processes forked from the Python interpreter; study.json returned as a dict; a
resumed study reuses the records; bad input raises."""
import math
import os
import subprocess
from pathlib import Path

import pytest

import jointhb

SOURCE = Path(os.environ.get("JOINTHB_SOURCE_DIR", Path(__file__).resolve().parents[2]))
PROGRAM = os.environ.get("JOINTHB_PROGRAM", str(SOURCE / "build" / "jointhb"))

CASE = """
model: {type: discrete, mass: 1.0, stiffness: 1.0e4, damping: {modal: [0.002]}}
contacts:
  - {law: jenkins, dofs: [0], kt0: 1.0e4, mu: 0.2, normal_force: 20.0}
analysis:
  nonlinear_modes: {mode: 1, log10_amplitude: [-5, -2], harmonics: 3}
study:
  sampling: sobol
  samples: 8
  parameters:
    - {name: "contacts[0].kt0", lower: 3.0e3, upper: 3.0e4, log_scale: true}
    - {name: "contacts[0].normal_force", lower: 5, upper: 50}
  amplitudes: [1.0e-5, 1.0e-3]
"""


@pytest.fixture()
def case_file(tmp_path):
    path = tmp_path / "study.yaml"
    path.write_text(CASE)
    return path


def test_run_study_equals_the_program_for_any_job_count(case_file, tmp_path):
    one = jointhb.run_study(case_file, tmp_path / "one", jobs=1)
    two = jointhb.run_study(case_file, tmp_path / "two", jobs=2)
    assert one["status"] == "converged" and one["counts"]["computed"] == 8, one["counts"]
    assert two["jobs"] == 2
    subprocess.run([PROGRAM, "study", str(case_file), "-o", str(tmp_path / "cli"), "-j", "1", "--quiet"], check=True)
    for name in ("study.csv", "study_statistics.csv", "study_curves.csv"):
        a = (tmp_path / "one" / name).read_bytes()
        assert a == (tmp_path / "two" / name).read_bytes(), name
        assert a == (tmp_path / "cli" / name).read_bytes(), name
    # The stuck limit of each sample: f = sqrt(k + kt0) / 2 pi at q = 1e-5 (below every slip amplitude here).
    rows = [line.split(",") for line in (tmp_path / "one" / "study.csv").read_text().splitlines()]
    header, rows = rows[0], rows[1:]
    kt, f = header.index("contacts[0].kt0"), header.index("mode1_frequency_hz_q1e-05")
    for r in rows:
        assert abs(float(r[f]) / (math.sqrt(1e4 + float(r[kt])) / (2 * math.pi)) - 1) < 1e-6, r


def test_resume_reuses_the_records(case_file, tmp_path):
    jointhb.run_study(case_file, tmp_path / "out", jobs=2)
    again = jointhb.run_study(case_file, tmp_path / "out", jobs=2, resume=True)
    assert again["counts"] == {"computed": 0, "reused": 8, "failed": 0, "not_run": 0}, again["counts"]


def test_bad_input_raises(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(CASE.replace('"contacts[0].kt0"', '"contacts[0].k"'))
    with pytest.raises(jointhb.InputError, match="unknown parameter"):
        jointhb.run_study(bad, tmp_path / "bad")
    plain = tmp_path / "plain.yaml"
    plain.write_text(CASE.split("study:")[0])
    with pytest.raises(ValueError, match="no study section"):
        jointhb.run_study(plain, tmp_path / "plain")
    with pytest.raises(ValueError, match="jobs"):
        jointhb.run_study(bad, tmp_path / "bad", jobs=0)


def test_workers_forked_after_a_computation_in_the_interpreter_finish(tmp_path):
    # A preload in the interpreter (CHOLMOD's OpenMP regions) and then run_study(jobs=2): the
    # workers' own factorisations once waited forever in libgomp (src/study/worker_processes.cpp).
    # In a subprocess, so that a regression fails on the timeout instead of hanging the suite.
    text = (SOURCE / "cases" / "16-study-lap" / "case.yaml").read_text()
    text = text[: text.index("study:")] + (
        "study:\n  sampling: list\n  parameters:\n"
        "    - {name: interfaces.lap.mu, values: [0.2, 0.3]}\n  amplitudes: [1.0e-7, 1.0e-6]\n")
    case = tmp_path / "small.yaml"
    case.write_text(text)
    script = (
        "import jointhb, sys\n"
        f"p = jointhb.Pipeline(jointhb.load_case({str(case)!r}))\n"
        "assert p.preload()['ok']\n"
        f"s = jointhb.run_study({str(case)!r}, {str(tmp_path / 'out')!r}, jobs=2)\n"
        "print(s['counts'])\n")
    try:
        done = subprocess.run(["/usr/bin/python3", "-c", script], capture_output=True, text=True,
                              timeout=180, env=dict(os.environ))
    except subprocess.TimeoutExpired:
        pytest.fail("run_study(jobs=2) after a preload in the interpreter did not finish in 180 s")
    assert done.returncode == 0, done.stderr
    assert "'computed': 2" in done.stdout, done.stdout
