"""The Python package jointhb (pybind11 over pipeline/fe_pipeline.hpp), run by ctest (python.pytest).

Checks: the damping curve from Python equals the jointhb program's backbone.csv on the same case
to the last bit; callbacks see every point and can stop a curve; Ctrl-C (KeyboardInterrupt, from
the callback or from SIGINT) ends a curve with its points kept; an exception of the callback
reaches the caller; errors of a case file raise jointhb.InputError carrying file, line and key; a
parameter change recomputes exactly the stages it enters (counted); the GIL is released while a
curve computes; jointhb.fit with a Python objective finds a known least-squares optimum; and the
example scripts under cases/ run.
"""
import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import jointhb

SOURCE = Path(os.environ.get("JOINTHB_SOURCE_DIR", Path(__file__).resolve().parents[2]))
PROGRAM = os.environ.get("JOINTHB_PROGRAM", str(SOURCE / "build" / "jointhb"))


@pytest.fixture(scope="module")
def lap():
    """The built-in default case (the bolted lap of case 08) with its stages computed once."""
    p = jointhb.Pipeline(jointhb.default_case())
    p.interface_model()
    return p


def short(p, **kw):
    """A short damping curve (linear limit into early microslip)."""
    return p.backbone(1, log10_amplitude=(-8.0, -5.5), frequency_drop=0.0, **kw)


def test_the_damping_curve_equals_the_programs_to_the_last_bit(tmp_path):
    out = tmp_path / "cli"
    subprocess.run([PROGRAM, "run", str(SOURCE / "cases/08-lap-damping/case.yaml"), "-o", str(out), "--no-cache"],
                   check=True, capture_output=True)
    rows = list(csv.DictReader(open(out / "backbone.csv")))
    curve = jointhb.Pipeline(jointhb.load_case(str(SOURCE / "cases/08-lap-damping/case.yaml"))).backbone(1)
    assert curve["status"] == "ok" and len(rows) == len(curve["amplitude"]) >= 10
    for column, key in [("amplitude", "amplitude"), ("frequency_hz", "frequency_hz"),
                        ("damping_ratio", "damping_ratio"), ("W_D", "W_D"), ("output_amplitude", "output_amplitude")]:
        cli = np.array([float(r[column]) for r in rows])
        assert np.array_equal(cli, curve[key]), (column, np.max(np.abs(cli - curve[key])))


def test_error_estimates_of_a_fe_curve_on_request(lap):
    """Off by default (NaN columns); error_estimate=True fills them, and the truncation estimate of
    zeta at H = 1 is the change to the curve traced at H = 3 at the same amplitude (T-41b)."""
    plain = short(lap)
    assert np.all(np.isnan(plain["damping_error_truncation"])) and plain["seconds"]["error_estimate"] == 0.0
    b = lap.backbone(1, log10_amplitude=(-5.5, -4.5), frequency_drop=0.0, error_estimate=True)
    assert b["status"] == "ok" and np.all(np.isfinite(b["damping_error_truncation"]))
    assert b["seconds"]["error_estimate"] > 0.0
    # at the samples of the estimate's H + 2 balance: max(N_t, 2(H + 2) + 2) = 32
    h3 = lap.backbone(1, log10_amplitude=(-4.5, -3.5), frequency_drop=0.0, harmonics=3, time_samples=32)
    # the last point of the H = 1 curve and the first of the H = 3 one are both at q = 10^-4.5
    assert abs(b["amplitude"][-1] / h3["amplitude"][0] - 1) < 1e-12
    change = h3["damping_ratio"][0] / b["damping_ratio"][-1] - 1
    assert abs(b["damping_error_truncation"][-1] - change) <= 2e-3 * abs(change) + 1e-8, (
        b["damping_error_truncation"][-1], change)


def test_the_linear_limit_is_the_first_elastic_mode_with_the_cases_damping(lap):
    curve = short(lap)
    f1 = lap.modes()["elastic_frequencies_hz"][0]
    assert abs(curve["frequency_hz"][0] / f1 - 1.0) < 1e-4
    # zeta = b omega / 2 with b = 2 (0.005) / omega_1: 0.5 % up to the condensed model's frequency
    # error (1e-4) and the microslip at the first amplitude (the Gaul-Mayer law has no sharp stick).
    assert abs(curve["damping_ratio"][0] / 0.005 - 1.0) < 1e-3
    assert curve["frequency_hz"][-1] < curve["frequency_hz"][0] and curve["damping_ratio"][-1] > 0.005
    assert curve["termination"] == "reached_end" and curve["ok"]
    assert lap.preload()["termination"] == "converged" and lap.modes()["termination"] == "converged"
    for stage in (lap.preload(), lap.modes()):  # the status convention, as in summary.json
        assert stage["ok"] is True and stage["message"] and "converged" not in stage, stage["message"]


def test_a_callback_sees_every_point_and_can_stop_the_curve(lap):
    seen = []
    curve = short(lap, callback=lambda pt: seen.append(pt["amplitude"]))
    assert seen == list(curve["amplitude"]) and len(seen) >= 3
    stopped = short(lap, callback=lambda pt: len(seen) < 0)  # False at once
    assert stopped["status"] == "stopped" and len(stopped["amplitude"]) == 1
    assert stopped["termination"] == "stopped_by_user" and not stopped["ok"]


def test_keyboard_interrupt_ends_the_curve_with_its_points(lap):
    count = [0]

    def interrupt_at_third(pt):
        count[0] += 1
        if count[0] == 3:
            raise KeyboardInterrupt

    curve = short(lap, callback=interrupt_at_third)
    assert curve["status"] == "interrupted" and len(curve["amplitude"]) == 3
    assert curve["termination"] == "stopped_by_user", curve["termination"]  # Ctrl-C is the user's
    # Ctrl-C while C++ computes (no callback): the signal only sets Python's flag, which the curve
    # checks at its next accepted point. H = 3 makes the curve last well beyond the 0.3 s.
    full = lap.backbone(1, harmonics=3)
    assert full["status"] == "ok" and full["time_samples"] == 64, full["message"]
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        curve = lap.backbone(1, harmonics=3)
    finally:
        timer.join()
    assert curve["status"] == "interrupted", curve["message"]
    assert 1 <= len(curve["amplitude"]) < len(full["amplitude"])
    assert np.array_equal(curve["amplitude"], full["amplitude"][:len(curve["amplitude"])])


def test_an_exception_of_the_callback_reaches_the_caller(lap):
    def broken(pt):
        raise ValueError("from the callback")

    with pytest.raises(ValueError, match="from the callback"):
        short(lap, callback=broken)


def test_a_bad_case_file_raises_input_error_with_file_line_and_key(tmp_path):
    text = (SOURCE / "cases/08-lap-damping/case.yaml").read_text().replace("mu: 0.3", "mu: -0.3")
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    with pytest.raises(jointhb.InputError) as e:
        jointhb.load_case(str(bad))
    line = next(i for i, l in enumerate(text.splitlines(), 1) if "mu: -0.3" in l)
    assert e.value.file.endswith("bad.yaml") and e.value.line == line
    assert e.value.key == "model.interfaces[0].contact.mu" and e.value.constraint
    assert isinstance(e.value, ValueError)
    with pytest.raises(ValueError, match="interfaces.lap.mu"):
        jointhb.Pipeline(jointhb.default_case()).set("interfaces.lap.mu", -1.0)


def test_a_parameter_recomputes_exactly_the_stages_it_enters():
    p = jointhb.Pipeline(jointhb.default_case())
    beta = p.interface_model()["rayleigh_beta"]                 # b = 2 zeta / omega_1, zeta = 0.005
    assert p.counters["condensed"] == 1 and p.counters["preload_solved"] == 1
    p.set("damping.ratio", 0.01)                                # enters no stage
    assert abs(p.interface_model()["rayleigh_beta"] / beta - 2.0) < 1e-12
    p.set("interfaces.lap.mu", 0.2, dynamics_only=True)         # only the condensed model's laws
    p.interface_model()
    assert p.counters["condensed"] == 1 and p.counters["preload_solved"] == 1
    assert p.get("interfaces.lap.mu") == 0.2
    p.set("bolts.bolt-1.preload", 4000.0)                       # preload, modes, condensation
    p.interface_model()
    c = p.counters
    assert (c["preload_solved"], c["modes_solved"], c["condensed"], c["assembled"]) == (2, 2, 2, 1), c
    assert abs(p.preload()["interfaces"][0]["clamping_force"] - 9000.0) < 1e-3
    assert "bolts.bolt-2.preload" in p.parameter_names


def test_the_gil_is_released_while_a_curve_computes(lap):
    ticks = [0]
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        short(lap)
    finally:
        done.set()
        t.join()
    assert ticks[0] > 20


def test_fit_with_a_python_objective_finds_the_least_squares_optimum():
    # r(a, b) = (a - 2, 3 (b - 0.5), a b - 1): the optimum of S = sum r^2 by hand is not at (2, 0.5);
    # compare with a dense grid's minimum instead of assuming it.
    def residuals(v):
        a, b = v
        return [a - 2.0, 3.0 * (b - 0.5), a * b - 1.0]

    r = jointhb.fit(residuals, [{"name": "a", "lower": 0.0, "upper": 4.0, "start": 1.0},
                                {"name": "b", "lower": 0.0, "upper": 1.0, "start": 0.9}],
                    {"xtol": 1e-9, "ftol_rel": 1e-14, "max_evaluations": 2000})
    a, b = np.meshgrid(np.linspace(1.5, 2.5, 1001), np.linspace(0.3, 0.6, 601))
    s = (a - 2) ** 2 + 9 * (b - 0.5) ** 2 + (a * b - 1) ** 2
    k = np.unravel_index(np.argmin(s), s.shape)
    assert r["ok"] and abs(r["best"]["a"] - a[k]) < 2e-3 and abs(r["best"]["b"] - b[k]) < 1e-3, r["best"]
    assert r["objective"] <= s.min() + 1e-9
    failing = jointhb.fit(lambda v: None, [{"name": "a", "lower": 0.0, "upper": 1.0}], {"max_evaluations": 5})
    assert not failing["ok"]


@pytest.mark.parametrize("script", ["cases/08-lap-damping/damping_curve.py", "cases/12-fit-lap/fit_damping.py"])
def test_the_example_scripts_run(script, tmp_path):
    r = subprocess.run([sys.executable, str(SOURCE / script)], cwd=tmp_path, capture_output=True, text=True,
                       env={**os.environ, "MPLBACKEND": "Agg"})
    assert r.returncode == 0, r.stderr
    assert "ok" in r.stdout.splitlines()[-1], r.stdout


def test_a_discrete_model_from_arrays_meets_the_stuck_closed_form():
    # 1 DOF, Jenkins to ground: below the slip force mu F_N the contact is a spring kt0, so
    # |X| = F / sqrt((k + kt0 - m w^2)^2 + (c w)^2) exactly (harmonic balance of a linear system).
    m, k, c, kt0 = 1.0, 1.0, 0.05, 10.0
    model = jointhb.DiscreteModel([[m]], [[k]], damping=[[c]],
                                  contacts=[{"law": "jenkins", "dofs": [0], "kt0": kt0, "mu": 0.1, "normal_force": 1.0}])
    assert model.dofs == 1
    modes = model.linear_modes()
    assert abs(modes["omega"][0] - np.sqrt((k + kt0) / m)) < 1e-12
    r = model.frf(force=np.array([1e-4]), omega=(0.5, 4.5), harmonics=3)
    assert r["status"] == "ok" and len(r["omega"]) > 10, r["message"]
    assert r["termination"] == "reached_end" and r["ok"]
    w = r["omega"]
    exact = 1e-4 / np.sqrt((k + kt0 - m * w**2) ** 2 + (c * w) ** 2)
    assert np.max(np.abs(r["amplitude_h1"] / exact - 1.0)) < 1e-8
    assert np.all(r["dissipation"] == 0.0)  # stuck: no friction work
    # Stability (monodromy along the orbit): a linear damped system is stable everywhere, its
    # multipliers are exp(-c T / 2) in modulus (|rho| = exp(Re(lambda) T), Re(lambda) = -c/(2m)).
    assert np.all(r["stable"] == 1.0) and all(b == "none" for b in r["bifurcation"])
    expected = np.exp(-c / (2 * m) * 2 * np.pi / w)
    assert np.max(np.abs(r["max_floquet_multiplier"] - expected)) < 1e-4
    peak_w = np.sqrt((k + kt0) / m - c**2 / (2 * m**2))  # the damped peak of the receptance
    assert r["peak"]["refined"] and abs(r["peak"]["omega"] - peak_w) < 1e-6
    b = model.backbone(mode=1, log10_amplitude=(-6.0, -0.5), harmonics=5)
    assert b["status"] == "ok", b["message"]
    assert abs(b["omega"][0] / np.sqrt(k + kt0) - 1.0) < 1e-9
    assert abs(b["damping_ratio"][0] - c / (2.0 * np.sqrt(k + kt0))) < 1e-9
    assert b["omega"][-1] < b["omega"][0] and b["damping_ratio"][-1] > b["damping_ratio"][0]  # slip softens, damps
    assert b["turns"] == []  # the 1-DOF curve rises monotonically in amplitude
    with pytest.raises(ValueError, match="mass"):
        jointhb.DiscreteModel([[1.0, 0.0]], [[1.0]])


def test_the_turns_of_a_damping_curve_are_extrema_of_its_amplitude():
    # The 30-DOF chain of docs/stability.md §7 (10 Jenkins links): at H = 7 its damping curve turns
    # back in amplitude near a 7:1 internal resonance. A located turn is an extremum of log10 q
    # between two consecutive accepted points: beyond both of them (above for a maximum, below for
    # a minimum), which interpolating between them would never give. (Newton's method at fixed
    # log10 q checks the turns themselves in the C++ test NonlinearMode.ChainDampingCurve...)
    n = 30
    k = np.diag([450.0] * (n - 1) + [225.0]) - 225.0 * (np.eye(n, k=1) + np.eye(n, k=-1))
    contacts = [{"law": "jenkins", "dofs": [a, a + 1], "kt0": 225.0, "mu": 0.557, "normal_force": 1.0}
                for a in (0, 3, 6, 9, 12, 16, 19, 22, 25, 28)]
    model = jointhb.DiscreteModel(np.eye(n), k, damping=0.02 * np.eye(n), contacts=contacts)
    b = model.backbone(mode=1, log10_amplitude=(-3.0, 1.0), harmonics=7)
    lam = np.log10(b["amplitude"])
    assert len(b["turns"]) >= 1, b["message"]
    assert abs(b["turns"][0]["log10_amplitude"] + 0.376) < 0.01
    # A turn at a smooth fold is refined to 1e-8 of log10 q or for 40 corrected points, whichever
    # comes first, with an honest bound: nearly all to 1e-7 (since stop 53, whose path through the
    # knot of the internal resonance differs, 262 of 264, the others 1.7e-7 and 0.024); a fold at a
    # kink of the friction laws
    # (docs/continuation.md, "Crossing a corner"), where the curve comes back on another sheet, is
    # not, nor one where the refinement finds a stationary point between the two points' values
    # (several turns between them: docs/stability.md §3); those are reported at the accepted point
    # after them with |delta log10 q| of that step as their bound (up to 0.02 measured).
    refined = [t for t in b["turns"] if t["refined"]]
    assert len(refined) > len(b["turns"]) // 2
    assert sum(t["log10_amplitude_error_bound"] < 1e-7 for t in refined) >= 0.95 * len(refined)
    for t in b["turns"]:
        x, e = t["log10_amplitude"], t["log10_amplitude_error_bound"]
        assert 0.8 < t["omega"] < 0.85
        assert (t["refined"] and 0.0 <= e < 0.05) or (not t["refined"] and 0.0 < e < 0.05), t
        lo, hi = np.minimum(lam[:-1], lam[1:]), np.maximum(lam[:-1], lam[1:])
        near = np.abs(lam[1:] - x) < 0.01
        assert np.any(near & ((x + e >= hi) | (x - e <= lo))), t


def test_a_preloaded_normal_contact_softens_and_folds_the_frf():
    # Case 15's block (bolt 2e8 N/m, rough contact F_N0 = 2 kN, k_N = 1e9 N/m, zeta = 0.1 %) built
    # from numpy arrays: the backbone's curvature at small amplitude is the Lindstedt-Poincare
    # kappa = (1.5 r - 2.5 r^2) lam^2 / 24 (docs/case-files.md, N-3), and the 8 N FRF folds twice with
    # unstable points only between its folds.
    kb, kn, fn = 2.0e8, 1.0e9, 2000.0
    w0 = np.sqrt(kb + kn)
    contact = {"law": "normal-exponential", "dofs": [0], "kn": kn, "normal_force": fn}
    model = jointhb.DiscreteModel(np.eye(1), [[kb]], damping=[[2e-3 * w0]], contacts=[contact])
    lam, r = kn / fn, kn / (kb + kn)
    kappa = (1.5 * r - 2.5 * r * r) * lam ** 2 / 24.0
    b = model.backbone(mode=1, log10_amplitude=(-8.0, -7.0), harmonics=6)
    assert b["ok"], b["message"]
    q, w = b["amplitude"], 2 * np.pi * b["frequency_hz"]
    small = q < 6e-8  # lam q < 0.03: the O(a^4) remainder below 0.1 % of kappa
    assert np.any(small)
    assert np.allclose((w[small] / w0 - 1.0) / q[small] ** 2, kappa, rtol=5e-3)
    f = model.frf(force=np.array([8.0]), omega=(31000.0, 36000.0), output_dof=0, harmonics=8)
    assert f["ok"] and len(f["folds"]) == 2, f["message"]
    lo, hi = sorted(x["omega"] for x in f["folds"])
    unstable = f["omega"][f["stable"] == 0]
    assert len(unstable) > 3 and np.all((unstable >= lo - 1e-3) & (unstable <= hi + 1e-3))


def lap_dict(mu=0.3):
    """Case 08 written as Python values (the same numbers as cases/08-lap-damping/case.yaml)."""
    plate = lambda name, x0, z0: {"name": name, "material": "aluminium", "element": "C3D8I",
                                  "box": {"origin": [x0, 0.0, z0], "size": [0.100, 0.030, 0.004],
                                          "divisions": [20, 6, 1]}}
    bolt = lambda name, x: {"name": name, "point": [x, 0.015, 0.0], "direction": [0.0, 0.0, 1.0],
                            "head": {"surface": "upper.zmax", "radius": 0.0045},
                            "nut": {"surface": "lower.zmin", "radius": 0.0045}, "stiffness": 5.0e8, "preload": 5000.0}
    return {"model": {"type": "fe",
                      "materials": {"aluminium": {"youngs_modulus": 70.0e9, "poissons_ratio": 0.33, "density": 2700.0}},
                      "parts": [plate("lower", 0.0, 0.0), plate("upper", 0.060, 0.004)],
                      "interfaces": [{"name": "lap", "bottom": "lower.zmax", "top": "upper.zmin",
                                      "region": {"min": [0.060, 0.0, 0.0039], "max": [0.100, 0.030, 0.0041]},
                                      "integration": "nodal",
                                      "contact": {"pressure": 1.0e6, "decay": 1.0e6, "mu": mu, "law": "gaul-mayer",
                                                  "n": 0.3333333333333333, "stiffness_ratio": 0.8}}],
                      "bolts": [bolt("bolt-1", 0.070), bolt("bolt-2", 0.090)]},
            "analysis": {"preload": {"load_steps": 4, "tolerance": 1.0e-9},
                         "modes": {"count": 12, "shift_hz": -10.0},
                         "damping": {"ratio": 0.005}, "reduction": {"cutoff_factor": 20},
                         "excitation": {"point": [0.160, 0.015, 0.008], "direction": [0, 0, 1]},
                         "nonlinear_modes": {"mode": 1, "log10_amplitude": [-8, -4], "frequency_drop": 0.03,
                                             "harmonics": 1}}}


def test_a_case_from_python_values_is_the_case_file():
    # The stage keys hash the typed model and settings: equal keys = the same computation.
    from_dict = jointhb.Pipeline(jointhb.case_from_dict(lap_dict()))
    from_file = jointhb.Pipeline(jointhb.load_case(str(SOURCE / "cases/08-lap-damping/case.yaml")))
    assert from_dict.keys == from_file.keys
    assert jointhb.Pipeline(jointhb.case_from_dict(lap_dict(mu=0.31))).keys["model"] != from_file.keys["model"]
    with pytest.raises(jointhb.InputError) as e:
        jointhb.case_from_dict(lap_dict(mu="much"))
    assert e.value.key == "model.interfaces[0].contact.mu" and e.value.line > 0


def test_the_cases_fit_section_runs_on_the_pipeline(tmp_path):
    # Case 12's fit reduced further than tests/cli/fit_fe_case.sh (which checks the estimate against
    # the truth): the damping ratio alone from 4 microslip points and 6 evaluations. The damping
    # enters no stage, so preload, modes and condensation are computed once for every curve.
    case_dir = SOURCE / "cases/12-fit-lap"
    measured = (case_dir / "measured_backbone.csv").read_text().splitlines()[:6]  # comment, header, 4 rows
    (tmp_path / "measured_backbone.csv").write_text("\n".join(measured) + "\n")
    text = "\n".join(l for l in (case_dir / "case.yaml").read_text().splitlines() if "interfaces.lap.mu" not in l)
    text = text.replace("max_evaluations: 80", "max_evaluations: 6")
    p = jointhb.Pipeline(jointhb.parse_case(text, str(tmp_path / "case.yaml")))
    r = p.fit()
    assert r["ok"] and set(r["best"]) == {"damping.ratio"}, r
    zeta = r["best"]["damping.ratio"]
    assert abs(zeta - 0.005) < abs(0.015 - 0.005) / 2, zeta  # from the start 0.015 towards the truth
    c = p.counters
    assert c["preload_solved"] == 1 and c["condensed"] == 1 and c["curves"] >= 3, c
    # The Jacobian's two points on two child processes: the same result bit for bit.
    r2 = p.fit(jobs=2)
    assert r2["values"] == r["values"] and r2["objective"] == r["objective"], (r, r2)
    assert r2["standard_errors"] == r["standard_errors"] and r2["evaluations"] == r["evaluations"]
    with pytest.raises(ValueError, match="jobs"):
        p.fit(jobs=0)


def test_contact_fields_along_the_curve_add_up_to_the_dissipation(lap):
    c = short(lap, contact_fields=True)
    f = c["contact"]
    n, points = len(c["amplitude"]), len(f["area"])
    assert points == 192 and f["W_D"].shape == (n, points) and f["position"].shape == (points, 3)
    # sum_p A_p W_D,p over the contact points is the curve's W_D [J] (coincident points share the
    # node pair's value, and their areas add up to the pair's)
    total = f["W_D"] @ f["area"]
    assert np.allclose(total, c["W_D"], rtol=1e-9, atol=0.0), (total, c["W_D"])
    assert set(np.unique(f["state"])) <= {0.0, 1.0, 2.0}
    assert np.all(f["pressure_max"] >= f["pressure_min"])


def test_a_discrete_case_file_gives_the_programs_frf(tmp_path):
    case = SOURCE / "cases/02-two-dof-frf/case.yaml"
    subprocess.run([PROGRAM, "run", str(case), "-o", str(tmp_path / "cli")], check=True, capture_output=True)
    rows = [r for r in csv.DictReader(open(tmp_path / "cli" / "frf.csv")) if r["level"] == "0"]
    model = jointhb.load_case(str(case))
    assert isinstance(model, jointhb.DiscreteModel) and model.source.endswith("case.yaml")
    r = model.frf(level=0)
    assert r["status"] == "ok" and len(rows) == len(r["omega"])
    for column in ("omega", "amplitude_h1", "dissipation", "amplitude_error_truncation", "amplitude_error_aliasing"):
        assert np.array_equal(np.array([float(x[column]) for x in rows]), r[column]), column
    # a parameter: the stuck mode follows kt0 of the first contact
    names = model.parameter_names
    assert "contacts[0].kt0" in names
    before = model.linear_modes()["omega"][0]
    model.set("contacts[0].kt0", 2.0 * model_param(case, "kt0"))
    assert model.linear_modes()["omega"][0] > before
    with pytest.raises(ValueError, match="contacts"):
        model.set("contacts[0].kt0", -1.0)


def model_param(case, key):
    """The first value of `key` in the case file's contacts (a flow-style map)."""
    import re
    return float(re.search(rf"{key}:\s*([-+0-9.eE]+)", case.read_text()).group(1))


def test_a_discrete_damping_curve_carries_the_programs_estimates_and_contact_states(tmp_path):
    case = SOURCE / "cases/03-one-dof-gaul-mayer/case.yaml"
    subprocess.run([PROGRAM, "run", str(case), "-o", str(tmp_path / "cli")], check=True, capture_output=True)
    rows = list(csv.DictReader(open(tmp_path / "cli" / "backbone.csv")))
    b = jointhb.load_case(str(case)).backbone(1)
    assert b["status"] == "ok" and len(rows) == len(b["amplitude"])
    for column in ("damping_ratio", "omega_error_truncation", "omega_error_aliasing", "damping_error_truncation",
                   "damping_error_aliasing", "slipping_points", "stuck_points", "microslip_points",
                   "gross_slip_points", "gapping_points"):
        assert np.array_equal(np.array([float(x[column]) for x in rows]), b[column]), column
    # one contact: in exactly one state per point, stuck first and at its limit last (docs/theory.md §14)
    states = b["stuck_points"] + b["microslip_points"] + b["gross_slip_points"]
    assert np.all(states == 1) and b["stuck_points"][0] == 1 and b["gross_slip_points"][-1] == 1


def test_accuracy_chooses_the_harmonics_per_point_as_the_program_does(tmp_path, lap):
    """accuracy={...} traces case 03 with H and N_t per point (docs/theory.md §13, T-44): the same
    points and levels as the program's backbone.csv with the same request; every kept point's estimates
    meet the request; a bad request is a ValueError naming the key, on discrete and FE models."""
    source = (SOURCE / "cases/03-one-dof-gaul-mayer/case.yaml").read_text()
    request = "accuracy: {damping: 1.0e-3, max_harmonics: 9}"
    text = source.replace("    log10_amplitude: [-8, -3.5]", "    log10_amplitude: [-8, -3.5]\n    " + request, 1)
    text = text.replace("    harmonics: 7\n    time_samples: 128\n  frf:", "    harmonics: 1\n    time_samples: 32\n  frf:", 1)
    assert request in text and "harmonics: 1\n" in text
    case = tmp_path / "case.yaml"
    case.write_text(text)
    subprocess.run([PROGRAM, "run", str(case), "-o", str(tmp_path / "cli")], check=True, capture_output=True)
    rows = list(csv.DictReader(open(tmp_path / "cli" / "backbone.csv")))
    model = jointhb.load_case(str(SOURCE / "cases/03-one-dof-gaul-mayer/case.yaml"))
    b = model.backbone(1, harmonics=1, time_samples=32, accuracy={"damping": 1e-3, "max_harmonics": 9})
    assert b["status"] == "ok" and len(rows) == len(b["amplitude"])
    for column in ("amplitude", "damping_ratio", "harmonics", "time_samples"):
        mine = b[{"harmonics": "harmonics_of_points", "time_samples": "time_samples_of_points"}.get(column, column)]
        assert np.array_equal(np.array([float(x[column]) for x in rows]), mine), column
    assert b["harmonics_of_points"][0] == 1 and b["harmonics_of_points"].max() >= 3 and b["level_changes"] > 0
    kept_within = (np.abs(b["damping_error_truncation"]) <= 1e-3) & (10 * np.abs(b["damping_error_aliasing"]) <= 1e-3)
    at_limit = (b["harmonics_of_points"] == 9) | (b["time_samples_of_points"] == 2048)
    assert np.all(kept_within | at_limit) and b["points_short_of_accuracy"] == np.sum(~kept_within)
    for bad, key in (({"damping": 2.0}, "accuracy.damping"), ({"dampin": 1e-3}, "unknown key 'dampin'"),
                     ({"frequency": 0.0}, "frequency or damping > 0")):
        with pytest.raises(ValueError, match=key):
            model.backbone(1, harmonics=1, time_samples=32, accuracy=bad)
    with pytest.raises(ValueError, match="starting harmonics = 9"):
        lap.backbone(1, harmonics=9, accuracy={"damping": 1e-2, "max_harmonics": 7})


def lap_case_with_frf(tmp_path, frf):
    """Case 12's truth (the bolted lap) with `analysis.frf: {frf}` added, written to
    tmp_path/case.yaml: (its path, its text)."""
    truth = (SOURCE / "cases/12-fit-lap/truth.yaml").read_text()
    entry = "  frf: {" + frf + "}\n  nonlinear_modes:"
    text = truth.replace("  nonlinear_modes:", entry, 1)
    assert entry in text
    case = tmp_path / "case.yaml"
    case.write_text(text)
    return case, text


def test_the_fe_frf_peak_is_located_between_its_points_as_the_program_does(tmp_path):
    """Case 12's lap with an FRF at 2 N across its first resonance (H = 3, matrix-free): the peak is
    located between the accepted points (docs/stability.md §3, finite-element FRFs) with a bound far
    below its distance to the highest point, as the program's summary.json reports it."""
    case, _ = lap_case_with_frf(tmp_path, "frequency_hz: [941, 949], force: [2.0], harmonics: 3")
    r = jointhb.Pipeline(jointhb.load_case(str(case))).frf()
    assert r["status"] == "ok" and r["peak_refined"] and r["folds"] == []
    highest = int(np.argmax(r["amplitude_h1"]))
    assert 0 < highest < len(r["amplitude_h1"]) - 1
    lo, hi = r["frequency_hz"][highest - 1], r["frequency_hz"][highest + 1]
    assert lo < r["peak_frequency_hz"] < hi
    gain = r["peak_amplitude"] - r["amplitude_h1"][highest]  # measured 1.0e-8 m (4.5e-5 relative)
    assert gain > 0.0 and r["peak_amplitude_bound"] < 1e-3 * gain
    subprocess.run([PROGRAM, "run", str(case), "-o", str(tmp_path / "cli")], check=True, capture_output=True,
                   cwd=SOURCE / "cases/12-fit-lap")
    peak = json.load(open(tmp_path / "cli" / "summary.json"))["frfs"][0]["peak"]
    assert peak["refined"] and peak["frequency_hz"] == r["peak_frequency_hz"]
    assert peak["amplitude_h1"] == r["peak_amplitude"] and peak["amplitude_h1_error_bound"] == r["peak_amplitude_bound"]


def test_hills_method_on_an_fe_frf_has_the_stuck_joints_multipliers_at_small_force(tmp_path):
    """Case 12's lap, FRF at 1 mN across its first resonance (H = 1) with stability by Hill's method
    (stability=True, stability_method='hill': docs/stability.md §7, T-36a): at so small a force the
    joint is stuck (the Gaul–Mayer points' tangent is C_pre), so the largest multiplier is the least
    damped elastic mode's e^{-c_1 T / 2}, c_j = alpha + beta omega_j^2 (closed form; the rigid-body
    modes' trivial multipliers are left out). The program reports the method in summary.json."""
    case, text = lap_case_with_frf(tmp_path, "frequency_hz: [955, 965], force: [0.001], harmonics: 1")
    pipe = jointhb.Pipeline(jointhb.load_case(str(case)))
    im = pipe.interface_model()
    omega = 2 * np.pi * np.asarray(im["frequencies_hz"])[im["rigid_modes"]:]
    c = im["rayleigh_alpha"] + im["rayleigh_beta"] * omega ** 2
    r = pipe.frf(stability=True, stability_method="hill")
    assert r["status"] == "ok" and len(r["omega"]) > 5
    assert np.all(r["stable"] == 1)
    period = 2 * np.pi / np.asarray(r["omega"])
    expected = np.exp(-0.5 * np.min(c) * period)
    assert np.max(np.abs(r["max_floquet_multiplier"] - expected)) < 1e-6, (r["max_floquet_multiplier"], expected)
    # The case's stability (auto) with Hill's method: 63 merged points at H = 1, 3P(2H+1) = 567 <= 2100
    auto = pipe.frf(stability_method="hill")
    assert np.all(auto["stable"] == 1) and np.allclose(auto["max_floquet_multiplier"], r["max_floquet_multiplier"])
    with pytest.raises(ValueError, match="stability_method"):
        pipe.frf(stability=True, stability_method="shooting")
    with pytest.raises(ValueError, match="stability"):
        pipe.frf(stability="sometimes")
    cli = text.replace("harmonics: 1}", "harmonics: 1, stability: true, stability_method: hill}", 1)
    (tmp_path / "cli.yaml").write_text(cli)
    subprocess.run([PROGRAM, "run", str(tmp_path / "cli.yaml"), "-o", str(tmp_path / "out")], check=True,
                   capture_output=True, cwd=SOURCE / "cases/12-fit-lap")
    st = json.load(open(tmp_path / "out" / "summary.json"))["frfs"][0]["stability"]
    assert st["method"] == "hill" and st["computed"] and st["points_known"] == len(r["omega"]), st
