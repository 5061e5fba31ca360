// The Python extension `jointhb._core` (pybind11): the finite-element pipeline
// (pipeline/fe_pipeline.hpp), case files, and the identification, with results as numpy arrays and
// dicts. The package `jointhb` (src/python/jointhb/__init__.py) re-exports it; docs/python.md is
// the user's page.
//
// Threading: the GIL is released while a stage or a curve computes and taken again for a
// callback. Ctrl-C: Python's SIGINT handler only sets a flag; it is checked at every accepted point
// (PyErr_CheckSignals), and a KeyboardInterrupt there — or raised by the callback — ends the
// curve, which is returned with its accepted points and status "interrupted". The stages before a
// curve (preload, modes, condensation) run to their end.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/fit/fitter.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/io/case_file.hpp"
#include "jointhb/io/discrete_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/io/study_case.hpp"
#include "jointhb/pipeline/fe_fit_model.hpp"
#include "jointhb/pipeline/discrete_pipeline.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

namespace py = pybind11;
using namespace jointhb;

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// ---- conversions -------------------------------------------------------------------------------

template <class T, class F>
py::array_t<double> column(const std::vector<T>& rows, F value) {
  py::array_t<double> a(static_cast<py::ssize_t>(rows.size()));
  auto v = a.mutable_unchecked<1>();
  for (std::size_t i = 0; i < rows.size(); ++i) v(static_cast<py::ssize_t>(i)) = value(rows[i]);
  return a;
}

py::dict timings_dict(const continuation::InterfaceTimings& t) {
  py::dict d;
  d["aft"] = t.aft;
  d["products"] = t.products;
  d["preconditioner_build"] = t.preconditioner;
  d["preconditioner_apply"] = t.preconditioner_apply;
  d["linear_solve"] = t.linear_solve;
  d["error_estimate"] = t.error_estimate;
  d["stability"] = t.stability;
  d["refinement"] = t.refinement;
  d["total"] = t.total;
  d["gmres_iterations"] = t.krylov_iterations;
  d["product_calls"] = t.product_calls;
  d["preconditioner_builds"] = t.factorisations;
  return d;
}

py::dict stage_dict(const pipeline::StageInfo& info) {
  py::dict d;
  d["key"] = info.key;
  d["from_store"] = info.from_store;
  d["location"] = info.location;
  d["store_seconds"] = info.store_seconds;
  d["warning"] = info.warning;
  return d;
}

// The status convention (contact/termination.hpp) in a result's dict, as in summary.json:
// "termination", "ok" and "message", all from the result's status().
void put_status(py::dict& d, const Status& status) {
  d["termination"] = std::string(to_string(status.termination));
  d["ok"] = status.ok();
  d["message"] = status.message;
}

py::dict preload_dict(const preload::PreloadResult& p, const pipeline::StageInfo& info) {
  py::dict d;
  put_status(d, p.status());
  d["load_factor"] = p.load_factor;
  d["newton_iterations"] = p.total_iterations;
  d["displacement"] = p.displacement;
  d["bolt_forces"] = p.bolt_forces;
  py::list interfaces;
  for (const auto& r : p.interfaces) {
    py::dict i;
    i["name"] = r.name;
    i["clamping_force"] = r.clamping_force;
    i["closed_area_fraction"] = r.closed_area_fraction;
    i["mean_pressure"] = r.mean_pressure;
    i["max_pressure"] = r.max_pressure;
    i["pressure"] = r.state.pressure;
    i["gap"] = r.state.gap;
    i["traction"] = r.state.traction;
    interfaces.append(i);
  }
  d["interfaces"] = interfaces;
  d["seconds"] = p.seconds;
  d["stage"] = stage_dict(info);
  return d;
}

py::dict modes_dict(const modal::ModalResult& m, const pipeline::StageInfo& info) {
  py::dict d;
  put_status(d, m.status());
  d["frequencies_hz"] = m.frequencies_hz;
  d["elastic_frequencies_hz"] = pipeline::elastic_frequencies(m);
  d["residuals"] = m.residuals;
  d["shapes"] = m.shapes;
  d["seconds"] = m.seconds;
  d["stage"] = stage_dict(info);
  return d;
}

py::dict interface_dict(const pipeline::InterfaceStage& s) {
  py::dict d;
  const hb::InterfaceModel& im = s.model;
  d["kept_modes"] = im.num_modes();
  d["rigid_modes"] = im.rigid_modes;
  d["contact_points"] = im.num_points();
  d["fine_points"] = s.fine_points;
  Eigen::VectorXd f = im.omega2.cwiseMax(0.0).cwiseSqrt() / kTwoPi;
  d["frequencies_hz"] = f;
  d["cutoff_hz"] = s.settings.options.cutoff_hz;
  d["cutoff_source"] = s.settings.cutoff_source;
  d["rayleigh_alpha"] = im.rayleigh_mass;
  d["rayleigh_beta"] = im.rayleigh_stiffness;
  d["damping_source"] = s.settings.damping_source;
  d["brief"] = s.brief;
  d["seconds"] = s.seconds;
  d["stage"] = stage_dict(s.info);
  return d;
}

// A curve's "status" in the Python package: its termination, with Ctrl-C told apart from a
// callback's stop (both are stopped_by_user): "interrupted" (KeyboardInterrupt), "ok" (ok()),
// "stopped" (stopped_by_user: a callback returned False), else "failed".
std::string curve_status(const Status& status, bool interrupted) {
  if (interrupted) return "interrupted";
  if (status.ok()) return "ok";
  return status.termination == Termination::stopped_by_user ? "stopped" : "failed";
}

// put_status and "status" for a curve; the message says so when Ctrl-C stopped it.
void put_curve_status(py::dict& d, const Status& status, bool interrupted) {
  d["status"] = curve_status(status, interrupted);
  put_status(d, status);
  if (interrupted) d["message"] = "interrupted (KeyboardInterrupt); the accepted points are kept";
}

// An estimate that was not computed (error_estimate off, or failed at the point).
constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();

// Columns "stuck_points" … "gapping_points" (hb/contact_state.hpp), the names of backbone.csv;
// `counts(point)` gives a point's hb::ContactStateCounts.
template <class Point, class Counts>
void put_state_columns(py::dict& d, const std::vector<Point>& points, Counts counts) {
  for (const hb::ContactState s : {hb::ContactState::stuck, hb::ContactState::microslip,
                                   hb::ContactState::gross_slip, hb::ContactState::gapping}) {
    d[py::str(fmt::format("{}_points", hb::contact_state_name(s)))] =
        column(points, [s, counts](const Point& p) { return double(counts(p)[s]); });
  }
}

// The error-estimate columns of a damping curve (docs/theory.md §13), the names of backbone.csv,
// NaN where not computed; `error(point)` gives a point's continuation::BackboneError.
template <class Point, class Error>
void put_backbone_error_columns(py::dict& d, const std::vector<Point>& points, Error error) {
  const auto estimate = [&](const char* name, auto pick) {
    d[name] = column(points, [pick, error](const Point& p) { return error(p).known ? pick(error(p)) : kNotComputed; });
  };
  using E = continuation::BackboneError;
  estimate("omega_error_truncation", [](const E& e) { return e.truncation_known ? e.omega.truncation : kNotComputed; });
  estimate("omega_error_aliasing", [](const E& e) { return e.omega.aliasing; });
  estimate("damping_error_truncation",
           [](const E& e) { return e.truncation_known ? e.damping.truncation : kNotComputed; });
  estimate("damping_error_aliasing", [](const E& e) { return e.damping.aliasing; });
}

// The same for an FRF (continuation::FrfError), the names of frf.csv.
template <class Point, class Error>
void put_frf_error_columns(py::dict& d, const std::vector<Point>& points, Error error) {
  const auto estimate = [&](const char* name, auto pick) {
    d[name] = column(points, [pick, error](const Point& p) { return error(p).known ? pick(error(p)) : kNotComputed; });
  };
  using E = continuation::FrfError;
  estimate("amplitude_error_truncation",
           [](const E& e) { return e.truncation_known ? e.amplitude_h1.truncation : kNotComputed; });
  estimate("amplitude_error_aliasing", [](const E& e) { return e.amplitude_h1.aliasing; });
  estimate("amplitude_max_error_truncation",
           [](const E& e) { return e.truncation_known ? e.amplitude_max.truncation : kNotComputed; });
  estimate("amplitude_max_error_aliasing", [](const E& e) { return e.amplitude_max.aliasing; });
}

// continuation::Accuracy from a dict {'frequency', 'damping', 'min_harmonics', 'max_harmonics',
// 'max_time_samples'}; ValueError for an unknown key or a value out of range (Accuracy::validate),
// or a starting H outside [min_harmonics, max_harmonics].
continuation::Accuracy accuracy_from(const py::object& value, int harmonics, int time_samples, bool frf = false) {
  if (!py::isinstance<py::dict>(value))
    throw py::value_error(frf ? "accuracy: must be a dict, e.g. {'amplitude': 1e-3}"
                              : "accuracy: must be a dict, e.g. {'damping': 1e-2}");
  continuation::Accuracy a;
  const char* outputs = frf ? "amplitude" : "frequency, damping";
  for (const auto& [key, item] : value.cast<py::dict>()) {
    const std::string name = py::str(key);
    if (!frf && name == "frequency") a.frequency = item.cast<double>();
    else if (!frf && name == "damping") a.damping = item.cast<double>();
    else if (frf && name == "amplitude") a.amplitude = item.cast<double>();
    else if (name == "min_harmonics") a.min_harmonics = item.cast<int>();
    else if (name == "max_harmonics") a.max_harmonics = item.cast<int>();
    else if (name == "max_time_samples") a.max_time_samples = item.cast<int>();
    else
      throw py::value_error(fmt::format("accuracy: unknown key '{}' (allowed: {}, min_harmonics, "
                                        "max_harmonics, max_time_samples)", name, outputs));
  }
  if (const std::string e = a.validate(); !e.empty()) throw py::value_error(e);
  if (!a.active()) throw py::value_error(fmt::format("accuracy: give {} > 0 (relative tolerances per point)",
                                                     frf ? "amplitude" : "frequency or damping"));
  if (harmonics < a.min_harmonics || harmonics > a.max_harmonics)
    throw py::value_error(fmt::format("accuracy: the starting harmonics = {} must lie in [{}, {}]", harmonics,
                                      a.min_harmonics, a.max_harmonics));
  if (time_samples > a.max_time_samples)
    throw py::value_error(fmt::format("accuracy: max_time_samples = {} is below the starting time_samples = {}",
                                      a.max_time_samples, time_samples));
  a.min_time_samples = std::min(a.min_time_samples, time_samples);  // as the case-file reader
  return a;
}

// max_output_change of a curve (continuation::Options): in (0, 1], else ValueError.
double output_change_from(double value) {
  if (!(value > 0.0 && value <= 1.0))
    throw py::value_error(std::isfinite(value) ? fmt::format("max_output_change: must be in (0, 1], got {}", value)
                                              : std::string("max_output_change: must be a finite number in (0, 1]"));
  return value;
}

// stability= of an FRF: None (the case's setting), 'auto', True or False; else ValueError.
void stability_from(const py::object& value, continuation::Stability& out) {
  if (value.is_none()) return;
  if (py::isinstance<py::bool_>(value)) {
    out = value.cast<bool>() ? continuation::Stability::always : continuation::Stability::never;
    return;
  }
  if (py::isinstance<py::str>(value) && value.cast<std::string>() == "auto") {
    out = continuation::Stability::automatic;
    return;
  }
  throw py::value_error("stability: must be 'auto', True or False");
}

// stability_method= of an FRF: 'monodromy' or 'hill' (docs/stability.md); else ValueError.
continuation::StabilityMethod stability_method_from(const std::string& value) {
  if (value == "monodromy") return continuation::StabilityMethod::monodromy;
  if (value == "hill") return continuation::StabilityMethod::hill;
  throw py::value_error(fmt::format("stability_method: must be 'monodromy' or 'hill', got '{}'", value));
}

// The located turns of a damping curve in amplitude (BackboneTurn), a dict each.
py::list turns_list(const std::vector<continuation::BackboneTurn>& turns) {
  py::list out;
  for (const auto& t : turns) {
    py::dict turn;
    turn["log10_amplitude"] = t.log10_amplitude;
    turn["omega"] = t.omega;
    turn["damping_ratio"] = t.damping_ratio;
    turn["log10_amplitude_error_bound"] = t.log10_amplitude_bound;
    turn["refined"] = t.refined;
    // between the curve's points after_point − 1 and after_point (None where not known)
    turn["after_point"] = t.after_point >= 0 ? py::object(py::int_(t.after_point)) : py::object(py::none());
    out.append(turn);
  }
  return out;
}

py::dict backbone_dict(const pipeline::BackboneCurve& b, bool interrupted) {
  using P = pipeline::BackbonePoint;
  py::dict d;
  d["mode"] = b.mode;
  d["amplitude"] = column(b.points, [](const P& p) { return p.amplitude; });
  d["output_amplitude"] = column(b.points, [](const P& p) { return p.output_amplitude; });
  d["omega"] = column(b.points, [](const P& p) { return p.omega; });
  d["frequency_hz"] = column(b.points, [](const P& p) { return p.frequency_hz; });
  d["damping_ratio"] = column(b.points, [](const P& p) { return p.damping_ratio; });
  d["W_D"] = column(b.points, [](const P& p) { return p.dissipation; });
  d["damping_ratio_energy"] = column(b.points, [](const P& p) { return p.damping_ratio_energy; });
  d["slipping_points"] = column(b.points, [](const P& p) { return double(p.slipping_points); });
  d["open_points"] = column(b.points, [](const P& p) { return double(p.open_points); });
  put_state_columns(d, b.points, [](const P& p) { return p.states; });
  d["newton_iterations"] = column(b.points, [](const P& p) { return double(p.newton_iterations); });
  put_backbone_error_columns(d, b.points, [](const P& p) -> const continuation::BackboneError& { return p.error; });
  put_curve_status(d, b.status(), interrupted);  // Ctrl-C: stopped_by_user
  d["turns"] = turns_list(b.curve.turns);
  d["energy_gap"] = b.energy_gap;
  d["energy_warning"] = b.energy_warning;
  d["linear_frequency_hz"] = b.curve.linear_omega / kTwoPi;
  d["linear_damping_ratio"] = b.curve.linear_damping_ratio;
  d["harmonics"] = b.harmonics;  // the starting level; per point below (accuracy=...)
  d["time_samples"] = b.time_samples;
  d["harmonics_of_points"] = column(b.points, [](const P& p) { return double(p.harmonics); });
  d["time_samples_of_points"] = column(b.points, [](const P& p) { return double(p.time_samples); });
  d["level_changes"] = b.curve.level_changes;
  d["points_short_of_accuracy"] = b.curve.short_of_accuracy;
  d["unknowns"] = b.curve.unknowns;
  d["newton_iterations_total"] = b.curve.newton_iterations;
  d["seconds"] = timings_dict(b.curve.timings);
  return d;
}

// Stability columns of an FRF (docs/stability.md): "stable" and "max_floquet_multiplier" (−1
// where not computed) and "bifurcation" (list of str), from points with stability_known, stable,
// max_multiplier and bifurcation (discrete or finite-element).
template <class P>
void put_stability_columns(py::dict& d, const std::vector<P>& points) {
  d["stable"] = column(points, [](const P& p) { return p.stability_known ? (p.stable ? 1.0 : 0.0) : -1.0; });
  d["max_floquet_multiplier"] = column(points, [](const P& p) { return p.stability_known ? p.max_multiplier : -1.0; });
  py::list bifurcation;
  for (const auto& p : points) bifurcation.append(hb::to_string(p.bifurcation));
  d["bifurcation"] = bifurcation;
}

py::dict frf_dict(const pipeline::FrfCurve& r, bool interrupted) {
  using P = pipeline::FrfPoint;
  py::dict d;
  d["level"] = r.level;
  d["force"] = r.force;
  d["output"] = r.output;
  d["omega"] = column(r.points, [](const P& p) { return p.omega; });
  d["frequency_hz"] = column(r.points, [](const P& p) { return p.frequency_hz; });
  d["amplitude_h1"] = column(r.points, [](const P& p) { return p.amplitude_h1; });
  d["amplitude_max"] = column(r.points, [](const P& p) { return p.amplitude_max; });
  d["dissipation"] = column(r.points, [](const P& p) { return p.dissipation; });
  d["slipping_points"] = column(r.points, [](const P& p) { return double(p.slipping_points); });
  put_state_columns(d, r.points, [](const P& p) { return p.states; });
  d["newton_iterations"] = column(r.points, [](const P& p) { return double(p.newton_iterations); });
  put_frf_error_columns(d, r.points, [](const P& p) -> const continuation::FrfError& { return p.error; });
  d["harmonics_of_points"] = column(r.points, [](const P& p) { return double(p.harmonics); });
  d["time_samples_of_points"] = column(r.points, [](const P& p) { return double(p.time_samples); });
  put_stability_columns(d, r.points);
  d["level_changes"] = r.curve.level_changes;
  d["points_short_of_accuracy"] = r.curve.short_of_accuracy;
  put_curve_status(d, r.status(), interrupted);
  d["peak_amplitude"] = r.peak_amplitude;
  d["peak_frequency_hz"] = r.peak_frequency_hz;
  d["peak_refined"] = r.peak_refined;
  d["peak_amplitude_bound"] = r.peak_refined ? r.curve.peak->value_bound : 0.0;
  py::list folds;
  for (const continuation::FrfExtremum& f : r.curve.folds)
    folds.append(py::dict(py::arg("frequency_hz") = f.omega / (2.0 * std::numbers::pi),
                          py::arg("amplitude_h1") = f.amplitude_h1,
                          py::arg("frequency_bound_hz") = f.value_bound / (2.0 * std::numbers::pi),
                          py::arg("refined") = f.refined));
  d["folds"] = folds;
  d["unknowns"] = r.curve.unknowns;
  d["seconds"] = timings_dict(r.curve.timings);
  return d;
}

// ---- callbacks from the computing thread ------------------------------------------------------

/// Turns a Python callable (or None) into a point callback: takes the GIL, calls it with the
/// point as a dict, stops the curve when it returns False, when it raises KeyboardInterrupt or
/// when Ctrl-C was pressed. Any other exception of the callback is kept and re-raised once the
/// curve has returned.
class PointCallback {
 public:
  explicit PointCallback(py::object callback) : callback_(std::move(callback)) {}

  template <class Point>
  bool operator()(const Point& point, py::dict (*to_dict)(const Point&)) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) return interrupt();
    if (callback_.is_none()) return true;
    try {
      const py::object r = callback_(to_dict(point));
      return r.is_none() || r.cast<bool>();
    } catch (py::error_already_set& e) {
      if (e.matches(PyExc_KeyboardInterrupt)) return interrupt();
      error_ = std::make_unique<py::error_already_set>(std::move(e));
      return false;
    }
  }

  [[nodiscard]] bool interrupted() const { return interrupted_; }
  /// Re-raises the callback's own exception (with the GIL held).
  void rethrow() {
    if (error_) {
      std::unique_ptr<py::error_already_set> e = std::move(error_);
      throw *e;
    }
  }

 private:
  bool interrupt() {
    PyErr_Clear();
    interrupted_ = true;
    return false;
  }
  py::object callback_;
  bool interrupted_ = false;
  std::unique_ptr<py::error_already_set> error_;
};

py::dict backbone_point(const pipeline::BackbonePoint& p) {
  py::dict d;
  d["mode"] = p.mode;
  d["amplitude"] = p.amplitude;
  d["output_amplitude"] = p.output_amplitude;
  d["frequency_hz"] = p.frequency_hz;
  d["damping_ratio"] = p.damping_ratio;
  d["W_D"] = p.dissipation;
  d["slipping_points"] = p.slipping_points;
  d["newton_iterations"] = p.newton_iterations;
  return d;
}

py::dict frf_point(const pipeline::FrfPoint& p) {
  py::dict d;
  d["level"] = p.level;
  d["force"] = p.force;
  d["frequency_hz"] = p.frequency_hz;
  d["amplitude_h1"] = p.amplitude_h1;
  d["amplitude_max"] = p.amplitude_max;
  d["dissipation"] = p.dissipation;
  d["slipping_points"] = p.slipping_points;
  d["newton_iterations"] = p.newton_iterations;
  return d;
}

// ---- the objects -------------------------------------------------------------------------------

/// A finite-element case as read from a file (the model and the analyses it asks for).
struct Case {
  std::shared_ptr<const io::FeCase> c;
};

/// A case from text (YAML, or JSON, which YAML reads): `file_name` names it in errors and its
/// directory is where mesh files are looked up.
Case parse_case(const std::string& text, const std::string& file_name) {
  io::CaseFile f = io::parse_case_file(text, file_name);
  if (auto* fe = std::get_if<io::FeCase>(&f)) return Case{std::make_shared<io::FeCase>(std::move(*fe))};
  throw py::value_error(file_name + ": the Python package runs finite-element cases (model.type fe); use "
                                    "jointhb.DiscreteModel for lumped models");
}

Case default_case() {
  io::CaseFile f = io::parse_case_file(io::default_case_text(), "built-in default case");
  return Case{std::make_shared<io::FeCase>(std::get<io::FeCase>(std::move(f)))};
}

class Pipeline {
 public:
  Pipeline(const Case& c, const std::optional<std::string>& cache_dir, bool keep_in_memory) : case_(c.c) {
    std::shared_ptr<pipeline::StageStore> store;
    if (cache_dir)
      store = std::make_shared<io::StageCache>(*cache_dir, true);
    else if (keep_in_memory)
      store = std::make_shared<pipeline::MemoryStageStore>();
    pipe_ = std::make_unique<pipeline::FePipeline>(*case_, *case_, std::move(store));
  }

  py::dict preload() {
    const preload::PreloadResult* p = nullptr;
    {
      py::gil_scoped_release free;
      p = &pipe_->preload();
    }
    return preload_dict(*p, pipe_->preload_info());
  }

  py::dict modes() {
    const modal::ModalResult* m = nullptr;
    {
      py::gil_scoped_release free;
      m = &pipe_->modes();
    }
    return modes_dict(*m, pipe_->modes_info());
  }

  py::dict interface_model() {
    const pipeline::InterfaceStage* s = nullptr;
    {
      py::gil_scoped_release free;
      s = &pipe_->interface_stage();
    }
    return interface_dict(*s);
  }

  py::dict backbone(int mode, const py::object& callback, const std::optional<std::pair<double, double>>& log10_amplitude,
                    const std::optional<double>& frequency_drop, const std::optional<int>& harmonics,
                    const std::optional<int>& time_samples, bool contact_fields,
                    const std::optional<bool>& error_estimate, const py::object& accuracy,
                    const std::optional<double>& max_output_change) {
    if (!case_->dynamics || !case_->dynamics->nonlinear_modes)
      throw py::value_error(case_->source + ": the case has no analysis.nonlinear_modes (give it one in the case file)");
    pipeline::FeNonlinearModesSpec nm = *case_->dynamics->nonlinear_modes;
    if (log10_amplitude) nm.log10_amplitude_start = log10_amplitude->first, nm.log10_amplitude_end = log10_amplitude->second;
    if (frequency_drop) nm.frequency_drop = *frequency_drop;
    if (harmonics) nm.balance.harmonics = *harmonics, nm.balance.time_samples = pipeline::default_time_samples(*harmonics);
    if (time_samples) nm.balance.time_samples = *time_samples;
    if (error_estimate) nm.error_estimate = *error_estimate;
    // A fixed level requested here replaces the case's accuracy (whose range it could miss).
    if (harmonics || time_samples) nm.accuracy = continuation::Accuracy{};
    if (!accuracy.is_none()) nm.accuracy = accuracy_from(accuracy, nm.balance.harmonics, nm.balance.time_samples);
    if (max_output_change) nm.continuation.max_output_change = output_change_from(*max_output_change);
    if (const std::string e = nm.balance.validate(); !e.empty()) throw py::value_error("backbone: " + e);
    PointCallback on_point(callback);
    pipeline::BackboneCurve b;
    {
      py::gil_scoped_release free;
      b = pipe_->backbone(mode, nm, [&](const pipeline::BackbonePoint& p) { return on_point(p, &backbone_point); });
    }
    on_point.rethrow();
    py::dict d = backbone_dict(b, on_point.interrupted());
    if (contact_fields) d["contact"] = contact_fields_of(b, nm.balance);
    return d;
  }

  /// What every contact point of the model (before the merge of coincident points) does over the
  /// period at each accepted point of `b` (hb::InterfacePointSummary): arrays points × curve points.
  py::dict contact_fields_of(const pipeline::BackboneCurve& b, const hb::InterfaceBalanceOptions& balance_options) {
    const pipeline::InterfaceStage& st = pipe_->interface_stage();
    const preload::PreloadModel& fe = pipe_->structure();
    const auto fine = static_cast<Eigen::Index>(st.patch_of_point.size());
    const auto n = static_cast<Eigen::Index>(b.curve.points.size());
    Eigen::MatrixXd position(fine, 3);
    Eigen::VectorXd area(fine);
    Eigen::MatrixXd wd(n, fine), tangential(n, fine), normal(n, fine), pmin(n, fine), pmax(n, fine), state(n, fine),
        ratio(n, fine);
    std::vector<std::string> interface_of;
    {
      py::gil_scoped_release free;
      Eigen::Index k = 0;
      for (const auto& ci : fe.interfaces)
        for (const fe::InterfacePoint& pt : ci.geometry.points) {
          position.row(k) = pt.position.transpose();
          area[k] = pt.area;
          ++k;
          interface_of.push_back(ci.geometry.name);
        }
      std::optional<hb::InterfaceBalance> balance;  // at the level of the point (accuracy: per point)
      for (Eigen::Index i = 0; i < n; ++i) {
        const auto& p = b.curve.points[static_cast<std::size_t>(i)];
        if (!balance || balance->options().harmonics != p.harmonics || balance->options().time_samples != p.time_samples) {
          hb::InterfaceBalanceOptions bo = balance_options;
          bo.harmonics = p.harmonics;
          bo.time_samples = p.time_samples;
          balance.emplace(st.model, bo);
        }
        const Eigen::Index U = balance->unknowns();
        const std::vector<hb::InterfacePointSummary> s = balance->point_summaries(p.state.amplitude * p.unknowns.head(U));
        for (Eigen::Index q = 0; q < fine; ++q) {
          const hb::InterfacePointSummary& v = s[static_cast<std::size_t>(st.patch_of_point[static_cast<std::size_t>(q)])];
          wd(i, q) = v.dissipation;
          tangential(i, q) = v.tangential_motion;
          normal(i, q) = v.normal_motion;
          pmin(i, q) = v.pressure_min;
          pmax(i, q) = v.pressure_max;
          state(i, q) = static_cast<double>(v.state);
          ratio(i, q) = v.limit_ratio;
        }
      }
    }
    py::dict d;
    d["position"] = position;
    d["area"] = area;
    d["interface"] = interface_of;
    d["W_D"] = wd;
    d["tangential_motion"] = tangential;
    d["normal_motion"] = normal;
    d["pressure_min"] = pmin;
    d["pressure_max"] = pmax;
    d["limit_ratio"] = ratio;
    d["state"] = state;
    return d;
  }

  py::dict frf(std::size_t level, const py::object& callback, const std::optional<std::pair<double, double>>& frequency_hz,
               const std::optional<double>& force, const std::optional<int>& harmonics,
               const std::optional<bool>& error_estimate, const py::object& accuracy,
               const std::optional<double>& max_output_change, const py::object& stability,
               const std::optional<std::string>& stability_method) {
    if (!case_->dynamics || !case_->dynamics->frf)
      throw py::value_error(case_->source + ": the case has no analysis.frf (give it one in the case file)");
    pipeline::FeFrfSpec fs = *case_->dynamics->frf;
    if (frequency_hz) fs.omega_start = kTwoPi * frequency_hz->first,
                      fs.omega_end = kTwoPi * frequency_hz->second;
    if (force) fs.forces = {*force}, level = 0;
    if (harmonics) fs.balance.harmonics = *harmonics, fs.balance.time_samples = pipeline::default_time_samples(*harmonics);
    if (error_estimate) fs.error_estimate = *error_estimate;
    if (harmonics) fs.accuracy = continuation::Accuracy{};  // a fixed level, as for backbone()
    if (!accuracy.is_none())
      fs.accuracy = accuracy_from(accuracy, fs.balance.harmonics, fs.balance.time_samples, true);
    if (max_output_change) fs.continuation.max_output_change = output_change_from(*max_output_change);
    stability_from(stability, fs.stability);
    if (stability_method) fs.stability_method = stability_method_from(*stability_method);
    if (const std::string e = fs.balance.validate(); !e.empty()) throw py::value_error("frf: " + e);
    PointCallback on_point(callback);
    pipeline::FrfCurve r;
    {
      py::gil_scoped_release free;
      r = pipe_->frf(level, fs, [&](const pipeline::FrfPoint& p) { return on_point(p, &frf_point); });
    }
    on_point.rethrow();
    return frf_dict(r, on_point.interrupted());
  }

  void set(const std::string& name, double value, bool dynamics_only) {
    pipe_->set_parameter(name, value,
                         dynamics_only ? pipeline::ParameterScope::dynamics : pipeline::ParameterScope::everywhere);
  }

  py::dict counters() const {
    const pipeline::StageCounters& k = pipe_->counters();
    py::dict d;
    d["assembled"] = k.assembled;
    d["preload_solved"] = k.preload_solved;
    d["preload_read"] = k.preload_read;
    d["preload_reused"] = k.preload_reused;
    d["modes_solved"] = k.modes_solved;
    d["modes_read"] = k.modes_read;
    d["modes_reused"] = k.modes_reused;
    d["condensed"] = k.condensed;
    d["condensation_read"] = k.condensation_read;
    d["condensation_reused"] = k.condensation_reused;
    d["curves"] = k.curves;
    return d;
  }

  py::dict fit_case(int jobs) {
    if (!case_->fit) throw py::value_error(case_->source + ": the case has no fit section");
    const io::FitSection& s = *case_->fit;
    std::vector<std::string> names;
    for (const auto& p : s.parameters) names.push_back(p.name);
    pipeline::FeFitModel model(*pipe_, names, s.targets, s.friction_in_dynamics_only);
    fit::FitResult r;
    {
      py::gil_scoped_release free;
      // The starts on `jobs` child processes, which run C++ only (never Python).
      fit::ParallelOptions parallel;
      parallel.jobs = jobs;
      r = fit::fit(model.model(), s.parameters, s.options, {}, {}, parallel);
    }
    py::dict d = fit_result_dict(r, names);
    d["values_put_on_the_curve"] = model.corrected();
    return d;
  }

  static py::dict fit_result_dict(const fit::FitResult& r, const std::vector<std::string>& names) {
    py::dict d;
    d["ok"] = r.ok;
    py::dict best;
    for (std::size_t i = 0; i < names.size() && i < r.best.size(); ++i) best[py::str(names[i])] = r.best[i];
    d["best"] = best;
    d["values"] = r.best;
    d["objective"] = r.objective;
    d["residuals"] = r.residuals;
    d["evaluations"] = r.evaluations;
    d["failed_evaluations"] = r.failed_evaluations;
    d["stop_reason"] = r.stop_reason;
    d["has_jacobian"] = r.has_jacobian;
    d["standard_errors"] = r.has_jacobian ? py::cast(r.standard_errors) : py::none();
    d["warnings"] = r.warnings;
    d["seconds"] = r.seconds;
    return d;
  }

  pipeline::FePipeline& pipe() { return *pipe_; }

 private:
  std::shared_ptr<const io::FeCase> case_;
  std::unique_ptr<pipeline::FePipeline> pipe_;
};

// ---- discrete models from numpy arrays -------------------------------------------------------

hb::SparseMatrix sparse_of(const Eigen::MatrixXd& a, const char* name, Eigen::Index n) {
  if (a.rows() != n || a.cols() != n)
    throw py::value_error(std::string(name) + ": must be " + std::to_string(n) + " x " + std::to_string(n) + ", got " +
                          std::to_string(a.rows()) + " x " + std::to_string(a.cols()));
  if (!a.allFinite()) throw py::value_error(std::string(name) + ": must be finite");
  return a.sparseView();
}

template <class T>
T item(const py::dict& d, const char* key, T fallback) {
  return d.contains(key) ? d[key].cast<T>() : fallback;
}

/// M ẍ + C ẋ + K x + f_nl(x) = f(t) with friction contacts (hb/discrete_system.hpp): the discrete
/// pipeline (pipeline/discrete_pipeline.hpp), built from arrays or read from a discrete case file.
class DiscreteModel {
 public:
  DiscreteModel(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness, const std::optional<Eigen::MatrixXd>& damping,
                const std::vector<py::dict>& contacts) {
    pipeline::DiscreteProblem problem;
    hb::DiscreteSystem& system = problem.system;
    const Eigen::Index n = mass.rows();
    system.mass = sparse_of(mass, "mass", n);
    system.stiffness = sparse_of(stiffness, "stiffness", n);
    if (damping) {
      system.damping = sparse_of(*damping, "damping", n);
      problem.damping_model = "matrix";
    }
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      const py::dict& c = contacts[i];
      hb::ContactElement e;
      e.law = item<std::string>(c, "law", "jenkins");
      const std::vector<int> dofs = item<std::vector<int>>(c, "dofs", {0});
      if (dofs.empty() || dofs.size() > 2)
        throw py::value_error("contacts[" + std::to_string(i) + "].dofs: one DOF (to ground) or two");
      e.dof_a = dofs[0];
      e.dof_b = dofs.size() == 2 ? dofs[1] : -1;
      e.stiffness = item<double>(c, e.law == "normal-exponential" ? "kn" : "kt0", e.stiffness);
      e.friction_coefficient = item<double>(c, "mu", e.friction_coefficient);
      e.normal_force = item<double>(c, "normal_force", e.normal_force);
      e.exponent = item<double>(c, "n", e.exponent);
      system.contacts.push_back(e);
    }
    if (const std::string e = system.validate(); !e.empty()) throw py::value_error("DiscreteModel: " + e);
    pipe_ = std::make_unique<pipeline::DiscretePipeline>(std::move(problem));
  }
  explicit DiscreteModel(pipeline::DiscreteProblem problem, std::string source)
      : pipe_(std::make_unique<pipeline::DiscretePipeline>(std::move(problem))), source_(std::move(source)) {}

  [[nodiscard]] int dofs() const { return pipe_->problem().system.dofs(); }
  [[nodiscard]] const std::string& source() const { return source_; }
  pipeline::DiscretePipeline& pipe() { return *pipe_; }

  py::dict linear_modes(bool stuck) {
    const hb::LinearModes& m = pipe_->linear_modes(stuck);
    py::dict d;
    d["omega"] = m.omega;
    d["frequency_hz"] = Eigen::VectorXd(m.omega / kTwoPi);
    d["shapes"] = m.shapes;
    return d;
  }

  /// Without `force`: the case's excitation level `level` and analysis.frf settings, each
  /// overridden by the keywords given.
  py::dict frf(const std::optional<Eigen::VectorXd>& force, const std::optional<std::pair<double, double>>& omega,
               std::optional<int> output_dof, std::optional<int> harmonics, std::optional<int> time_samples,
               std::size_t level, const py::object& callback, const py::object& accuracy,
               const std::optional<double>& max_output_change, const py::object& stability,
               const std::optional<std::string>& stability_method) {
    const pipeline::DiscreteProblem& pr = pipe_->problem();
    continuation::FrfOptions o = pr.frf.value_or(continuation::FrfOptions{});
    hb::Excitation x;
    if (force) {
      if (force->size() != dofs()) throw py::value_error("frf: force must have one amplitude per DOF");
      for (Eigen::Index i = 0; i < force->size(); ++i)
        if ((*force)[i] != 0.0) x.forces.push_back({static_cast<int>(i), (*force)[i], 1});
    } else {
      if (pr.levels.empty()) throw py::value_error("frf: give force (the model has no excitation levels)");
      if (level >= pr.levels.size()) throw py::value_error("frf: level beyond the case's excitation levels");
      x = pr.levels[level];
    }
    if (!pr.frf && !omega) throw py::value_error("frf: give omega = (start, end) [rad/s]");
    if (omega) o.omega_start = omega->first, o.omega_end = omega->second;
    if (output_dof) o.output_dof = *output_dof;
    if (harmonics) o.harmonics = *harmonics, o.time_samples = io::default_time_samples(*harmonics);
    if (time_samples) o.time_samples = *time_samples;
    if (harmonics || time_samples) o.accuracy = continuation::Accuracy{};  // a fixed level, as for backbone()
    if (!accuracy.is_none()) o.accuracy = accuracy_from(accuracy, o.harmonics, o.time_samples, true);
    if (max_output_change) o.continuation.max_output_change = output_change_from(*max_output_change);
    stability_from(stability, o.stability);
    if (stability_method) o.stability_method = stability_method_from(*stability_method);
    if (const std::string e = o.validate(dofs()); !e.empty()) throw py::value_error("frf: " + e);
    PointCallback on_point(callback);
    continuation::FrfCurve r;
    {
      py::gil_scoped_release free;
      r = pipe_->frf(x, o, [&](const continuation::FrfPoint& p) { return on_point(p, &point); });
    }
    on_point.rethrow();
    using P = continuation::FrfPoint;
    py::dict d;
    d["omega"] = column(r.points, [](const P& p) { return p.omega; });
    d["frequency_hz"] = column(r.points, [](const P& p) { return p.omega / kTwoPi; });
    d["amplitude_h1"] = column(r.points, [](const P& p) { return p.amplitude_h1; });
    d["amplitude_max"] = column(r.points, [](const P& p) { return p.amplitude_max; });
    d["dissipation"] = column(r.points, [](const P& p) { return p.dissipation; });
    put_stability_columns(d, r.points);
    const auto extremum = [](const continuation::FrfExtremum& e) {
      py::dict out;
      out["omega"] = e.omega;
      out["amplitude_h1"] = e.amplitude_h1;
      out["error_bound"] = e.value_bound;
      out["refined"] = e.refined;
      return out;
    };
    put_frf_error_columns(d, r.points, [](const P& p) -> const continuation::FrfError& { return p.error; });
    d["harmonics_of_points"] = column(r.points, [](const P& p) { return double(p.harmonics); });
    d["time_samples_of_points"] = column(r.points, [](const P& p) { return double(p.time_samples); });
    d["level_changes"] = r.level_changes;
    d["points_short_of_accuracy"] = r.short_of_accuracy;
    if (r.peak) d["peak"] = extremum(*r.peak);
    py::list folds;
    for (const auto& f : r.folds) folds.append(extremum(f));
    d["folds"] = folds;
    put_curve_status(d, r.status(), on_point.interrupted());
    d["harmonics"] = r.kept_harmonics;
    d["seconds"] = r.timings.total;
    return d;
  }

  /// Without keywords: the case's analysis.nonlinear_modes settings (or the defaults).
  py::dict backbone(int mode, const std::optional<std::pair<double, double>>& log10_amplitude,
                    std::optional<int> harmonics, std::optional<int> time_samples, const py::object& callback,
                    const py::object& accuracy, const std::optional<double>& max_output_change,
                    const std::optional<double>& max_damping_ratio) {
    continuation::BackboneOptions o = pipe_->problem().nonlinear_modes.value_or(continuation::BackboneOptions{});
    if (max_damping_ratio) o.max_damping_ratio = *max_damping_ratio;
    o.mode.mode = mode;
    if (harmonics) o.mode.harmonics = *harmonics, o.mode.time_samples = io::default_time_samples(*harmonics);
    if (time_samples) o.mode.time_samples = *time_samples;
    // A fixed level requested here replaces the case's accuracy (whose range it could miss).
    if (harmonics || time_samples) o.accuracy = continuation::Accuracy{};
    if (!accuracy.is_none()) o.accuracy = accuracy_from(accuracy, o.mode.harmonics, o.mode.time_samples);
    if (max_output_change) o.continuation.max_output_change = output_change_from(*max_output_change);
    if (log10_amplitude) o.log10_amplitude_start = log10_amplitude->first, o.log10_amplitude_end = log10_amplitude->second;
    if (const std::string e = o.validate(dofs()); !e.empty()) throw py::value_error("backbone: " + e);
    PointCallback on_point(callback);
    continuation::BackboneCurve b;
    {
      py::gil_scoped_release free;
      b = pipe_->backbone(o, [&](const continuation::BackbonePoint& p) { return on_point(p, &point); });
    }
    on_point.rethrow();
    using P = continuation::BackbonePoint;
    py::dict d;
    d["amplitude"] = column(b.points, [](const P& p) { return p.state.amplitude; });
    d["omega"] = column(b.points, [](const P& p) { return p.state.omega; });
    d["frequency_hz"] = column(b.points, [](const P& p) { return p.state.omega / kTwoPi; });
    d["damping_ratio"] = column(b.points, [](const P& p) { return p.state.damping_ratio; });
    d["W_D"] = column(b.points, [](const P& p) { return p.state.dissipation; });
    d["damping_ratio_energy"] = column(b.points, [](const P& p) { return p.state.damping_ratio_energy; });
    d["slipping_points"] = column(b.points, [](const P& p) { return double(p.state.slipping_points); });
    put_state_columns(d, b.points, [](const P& p) { return p.state.states; });  // gapping_points 0, as in backbone.csv
    put_backbone_error_columns(d, b.points, [](const P& p) -> const continuation::BackboneError& { return p.error; });
    d["harmonics_of_points"] = column(b.points, [](const P& p) { return double(p.harmonics); });
    d["time_samples_of_points"] = column(b.points, [](const P& p) { return double(p.time_samples); });
    d["level_changes"] = b.level_changes;
    d["points_short_of_accuracy"] = b.short_of_accuracy;
    d["turns"] = turns_list(b.turns);
    put_curve_status(d, b.status(), on_point.interrupted());
    d["linear_omega"] = b.linear_omega;
    d["linear_damping_ratio"] = b.linear_damping_ratio;
    d["seconds"] = b.seconds;
    return d;
  }

 private:
  static py::dict point(const continuation::FrfPoint& p) {
    py::dict d;
    d["omega"] = p.omega;
    d["amplitude_h1"] = p.amplitude_h1;
    d["dissipation"] = p.dissipation;
    return d;
  }
  static py::dict point(const continuation::BackbonePoint& p) {
    py::dict d;
    d["amplitude"] = p.state.amplitude;
    d["omega"] = p.state.omega;
    d["damping_ratio"] = p.state.damping_ratio;
    d["W_D"] = p.state.dissipation;
    return d;
  }

  std::unique_ptr<pipeline::DiscretePipeline> pipe_;
  std::string source_;
};

/// A case file of either kind: a Case (finite elements) or a DiscreteModel.
py::object load_any_case(const std::string& path) {
  io::CaseFile f = io::read_case_file(path);
  if (auto* fe = std::get_if<io::FeCase>(&f)) return py::cast(Case{std::make_shared<io::FeCase>(std::move(*fe))});
  if (auto* d = std::get_if<io::DiscreteCase>(&f)) {
    const std::string source = d->source;
    return py::cast(DiscreteModel(static_cast<pipeline::DiscreteProblem&&>(std::move(*d)), source));
  }
  throw py::value_error(path + ": a loop-sweep case (no model); run it with `jointhb run`");
}

/// fit::fit with a Python objective: values (numpy array) → residuals (sequence of floats), or
/// None / an exception for a failed evaluation.
py::dict fit_objective(const py::function& objective, const std::vector<py::dict>& parameters, const py::dict& options) {
  std::vector<fit::FitParameter> ps;
  std::vector<std::string> names;
  for (const py::dict& p : parameters) {
    fit::FitParameter f;
    f.name = p["name"].cast<std::string>();
    f.lower = p["lower"].cast<double>();
    f.upper = p["upper"].cast<double>();
    f.start = p.contains("start") ? p["start"].cast<double>() : 0.5 * (f.lower + f.upper);
    f.log_scale = p.contains("log_scale") && p["log_scale"].cast<bool>();
    if (const std::string e = f.validate(); !e.empty()) throw py::value_error("fit parameter " + e);
    ps.push_back(f);
    names.push_back(f.name);
  }
  fit::FitOptions o;
  for (const auto& [key, value] : options) {
    const std::string k = key.cast<std::string>();
    if (k == "algorithm") o.algorithm = value.cast<std::string>();
    else if (k == "local_algorithm") o.local_algorithm = value.cast<std::string>();
    else if (k == "xtol") o.xtol = value.cast<double>();
    else if (k == "ftol_rel") o.ftol_rel = value.cast<double>();
    else if (k == "max_evaluations") o.max_evaluations = value.cast<int>();
    else if (k == "starts") o.starts = value.cast<int>();
    else if (k == "seed") o.seed = value.cast<unsigned>();
    else throw py::value_error("fit: unknown option '" + k + "'");
  }
  if (const std::string e = o.validate(); !e.empty()) throw py::value_error("fit options: " + e);
  bool interrupted = false;
  const fit::Model model = [&](const std::vector<double>& values) {
    fit::Evaluation e;
    if (interrupted) return fit::Evaluation{false, "interrupted", {}};
    try {
      const py::object r = objective(py::cast(values));
      if (r.is_none()) return fit::Evaluation{false, "the objective returned None", {}};
      e.residuals = r.cast<std::vector<double>>();
    } catch (py::error_already_set& err) {
      if (err.matches(PyExc_KeyboardInterrupt)) interrupted = true;
      e.ok = false;
      e.message = err.what();
    }
    return e;
  };
  const fit::FitResult r = fit::fit(model, ps, o);  // the objective runs Python: the GIL stays held
  py::dict d = Pipeline::fit_result_dict(r, names);
  d["interrupted"] = interrupted;
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "jointhb: vibration of bolted joints by harmonic balance (the finite-element pipeline)";
  static py::exception<io::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<pipeline::StageError> stage_error(m, "StageError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const io::InputError& e) {
      // The exception carries the position: file, line, column, key and the violated constraint.
      py::object exc = py::handle(input_error.ptr())(e.what());
      exc.attr("file") = e.file();
      exc.attr("line") = e.line();
      exc.attr("column") = e.column();
      exc.attr("key") = e.key();
      exc.attr("constraint") = e.constraint();
      PyErr_SetObject(input_error.ptr(), exc.ptr());
    } catch (const pipeline::StageError& e) {
      stage_error(e.what());
    }
  });

  py::class_<Case>(m, "Case", "A finite-element case as read from a case file (model and analyses).")
      .def_property_readonly("source", [](const Case& c) { return c.c->source; }, "the case file")
      .def_property_readonly("dofs", [](const Case& c) { return c.c->mesh.num_dofs(); }, "DOFs of the mesh")
      .def_property_readonly("nodes", [](const Case& c) { return c.c->mesh.num_nodes(); })
      .def_property_readonly("interfaces",
                             [](const Case& c) {
                               std::vector<std::string> n;
                               for (const auto& i : c.c->interfaces) n.push_back(i.geometry.name);
                               return n;
                             })
      .def_property_readonly("bolts",
                             [](const Case& c) {
                               std::vector<std::string> n;
                               for (const auto& b : c.c->bolts) n.push_back(b.name);
                               return n;
                             })
      .def_property_readonly("has_fit", [](const Case& c) { return c.c->fit.has_value(); })
      .def_property_readonly("coordinates", [](const Case& c) { return Eigen::MatrixXd(c.c->mesh.coordinates); },
                             "node coordinates [m], 3 x nodes")
      .def("__repr__", [](const Case& c) {
        return "<jointhb.Case " + c.c->source + ": " + std::to_string(c.c->mesh.num_dofs()) + " DOFs>";
      });

  m.def("load_case", &load_any_case, py::arg("path"),
        "Reads a case file (YAML, docs/case-files.md): a finite-element case gives a Case (for Pipeline), a "
        "discrete one a DiscreteModel. Raises jointhb.InputError with file, line, column, key and constraint "
        "for any problem of the file.");
  m.def("parse_case", &parse_case, py::arg("text"), py::arg("file_name"),
        "A finite-element case from YAML or JSON text; file_name names it in errors, its directory is where "
        "mesh files are found.");
  m.def("default_case", &default_case, "The built-in default case: the bolted lap of case 08.");

  py::class_<Pipeline>(m, "Pipeline",
                       "The pipeline of a finite-element case: preload -> modes -> condensed interface model -> "
                       "damping curves and FRFs. Each stage is computed when first needed and kept while its "
                       "inputs are unchanged; set() changes a parameter and so exactly the stages it enters.")
      .def(py::init<const Case&, const std::optional<std::string>&, bool>(), py::arg("case"),
           py::arg("cache_dir") = py::none(), py::arg("keep_in_memory") = false,
           "cache_dir: keep stages on disk there (shared with `jointhb run --cache-dir`); keep_in_memory: keep "
           "every stage computed in memory, so that returning to earlier parameters reads it.")
      .def("preload", &Pipeline::preload,
           "The preloaded static state: converged, message, displacement [m] (3 per node), bolt_forces [N], "
           "per interface the pressure [Pa], gap [m] and traction [Pa] per contact point.")
      .def("modes", &Pipeline::modes,
           "The modes of K_t about the preloaded state: frequencies_hz, elastic_frequencies_hz, shapes (free DOFs).")
      .def("interface_model", &Pipeline::interface_model,
           "The condensed interface model: kept and rigid modes, contact points, cutoff, Rayleigh damping.")
      .def("backbone", &Pipeline::backbone, py::arg("mode") = 1, py::arg("callback") = py::none(), py::kw_only(),
           py::arg("log10_amplitude") = py::none(), py::arg("frequency_drop") = py::none(),
           py::arg("harmonics") = py::none(), py::arg("time_samples") = py::none(), py::arg("contact_fields") = false,
           py::arg("error_estimate") = py::none(), py::arg("accuracy") = py::none(),
           py::arg("max_output_change") = py::none(),
           "The damping curve (EPMC) of elastic mode `mode`: numpy arrays amplitude (q [m sqrt(kg)]), "
           "frequency_hz, damping_ratio, W_D [J], output_amplitude [m], ...; status, message, seconds. "
           "callback(point: dict) is called at every accepted point; returning False stops the curve. "
           "Ctrl-C ends the curve with its accepted points (status 'interrupted'). Keywords override the "
           "case's analysis.nonlinear_modes. contact_fields=True adds 'contact': per contact point its "
           "position [m], area [m^2], interface, and per curve point x contact point W_D [J/m^2 per cycle], "
           "tangential and normal motion [m], pressure min/max [Pa], limit_ratio (max |t_T|/(mu p_N)), state "
           "(0 stuck, 1 microslip, 2 gross slip, 3 gapping, 4 open). error_estimate=True adds the estimated "
           "relative errors omega_error_truncation, omega_error_aliasing, damping_error_truncation, "
           "damping_error_aliasing (NaN where not computed; docs/theory.md section 13). "
           "accuracy={'frequency': 1e-4, 'damping': 1e-2} (also 'min_harmonics', 'max_harmonics', "
           "'max_time_samples') chooses H and N_t per point from those estimates, starting from `harmonics`; "
           "harmonics_of_points and time_samples_of_points give each point's level. max_output_change=0.05 "
           "limits the relative change of f and zeta between two points (docs/continuation.md, step rule 7).")
      .def("frf", &Pipeline::frf, py::arg("level") = 0, py::arg("callback") = py::none(), py::kw_only(),
           py::arg("frequency_hz") = py::none(), py::arg("force") = py::none(), py::arg("harmonics") = py::none(),
           py::arg("error_estimate") = py::none(), py::arg("accuracy") = py::none(),
           py::arg("max_output_change") = py::none(), py::arg("stability") = py::none(),
           py::arg("stability_method") = py::none(),
           "The nonlinear FRF at force level `level` of analysis.frf (or at `force` [N]): numpy arrays "
           "frequency_hz, amplitude_h1 [m], amplitude_max [m], dissipation [J]; peak, status, message. "
           "error_estimate=True adds amplitude_error_truncation, amplitude_error_aliasing, "
           "amplitude_max_error_truncation, amplitude_max_error_aliasing (NaN where not computed). "
           "accuracy={'amplitude': 1e-3} (also min_harmonics, max_harmonics, max_time_samples) chooses H "
           "and N_t per point; harmonics_of_points and time_samples_of_points give each point's level. "
           "max_output_change=0.05 limits the relative change of amplitude_h1 between two points. "
           "stable, max_floquet_multiplier (-1 where not computed: analysis.frf.stability, automatic up to "
           "10 contact points, 3P(2H+1) <= 2100 for Hill's method; stability=True/False/'auto' overrides it) and bifurcation (list of str) give "
           "each point's stability; stability_method='monodromy' (default) or 'hill' (Hill's method, exact "
           "at folds, docs/stability.md).")
      .def_property_readonly("parameter_names", [](const Pipeline& p) { return const_cast<Pipeline&>(p).pipe().parameter_names(); },
                             "interfaces.<name>.pressure|decay|cutoff_gap|normal_stiffness|mu|n|stiffness_ratio|kt, bolts.<name>.preload, damping.*")
      .def("get", [](Pipeline& p, const std::string& name) { return p.pipe().parameter(name); }, py::arg("name"))
      .def("set", &Pipeline::set, py::arg("name"), py::arg("value"), py::arg("dynamics_only") = false,
           "Sets a parameter; the stages it enters are recomputed when next needed. dynamics_only (mu, n): "
           "only in the condensed model's contact laws.")
      .def_property_readonly("counters", &Pipeline::counters,
                             "how often each stage was solved, read from the store, or reused")
      .def_property_readonly("keys",
                             [](Pipeline& p) {
                               const pipeline::FeStageKeys k = p.pipe().keys();
                               return py::dict(py::arg("model") = k.model, py::arg("preload") = k.preload,
                                               py::arg("modes") = k.modes);
                             })
      .def("fit", &Pipeline::fit_case, py::arg("jobs") = 1,
           "Runs the case's fit section (parameters, measured targets, options) on this pipeline. jobs > 1: "
           "the starts of a multi-start search, then the Jacobian's points, on that many child processes "
           "(the result is the same bit for bit).");

  py::class_<DiscreteModel>(m, "DiscreteModel",
                            "A lumped model M x'' + C x' + K x + f_nl(x) = f(t) with friction contacts (SI units).")
      .def(py::init<const Eigen::MatrixXd&, const Eigen::MatrixXd&, const std::optional<Eigen::MatrixXd>&,
                    const std::vector<py::dict>&>(),
           py::arg("mass"), py::arg("stiffness"), py::arg("damping") = py::none(), py::arg("contacts") = std::vector<py::dict>{},
           "mass, stiffness, damping: n x n arrays [kg, N/m, N s/m]; contacts: dicts {law: 'jenkins' | 'gaul-mayer', "
           "dofs: [a] (to ground) or [a, b], kt0 [N/m], mu, normal_force [N], n (gaul-mayer)}, or {law: "
           "normal-exponential, dofs, kn [N/m], normal_force [N] (the preload)}. ValueError names "
           "the violated constraint.")
      .def_property_readonly("dofs", &DiscreteModel::dofs)
      .def_property_readonly("source", &DiscreteModel::source, "the case file it was read from ('' when built)")
      .def("linear_modes", &DiscreteModel::linear_modes, py::arg("stuck") = true,
           "Linear modes with the contacts stuck (stiffness kt0) or removed: omega [rad/s], frequency_hz, shapes.")
      .def("frf", &DiscreteModel::frf, py::arg("force") = py::none(), py::arg("omega") = py::none(),
           py::arg("output_dof") = py::none(), py::arg("harmonics") = py::none(), py::arg("time_samples") = py::none(),
           py::arg("level") = 0, py::arg("callback") = py::none(), py::arg("accuracy") = py::none(),
           py::arg("max_output_change") = py::none(), py::arg("stability") = py::none(),
           py::arg("stability_method") = py::none(),
           "Nonlinear FRF under f(t) = force cos(Omega t) (force: amplitude per DOF [N]) over omega = (start, end) "
           "[rad/s]; without force, the case's excitation level `level` and analysis.frf settings. Numpy arrays "
           "omega, frequency_hz, amplitude_h1, amplitude_max [m], dissipation [J], stable (1/0, -1: not "
           "computed), max_floquet_multiplier, bifurcation (list of str); peak and folds (dicts: omega, "
           "amplitude_h1, error_bound, refined); status, message. accuracy={'amplitude': 1e-3} chooses H and "
           "N_t per point (harmonics_of_points, time_samples_of_points); max_output_change limits the relative "
           "change of amplitude_h1 between two points. stability=True/False/'auto' and stability_method="
           "'monodromy'|'hill' override analysis.frf's (docs/stability.md).")
      .def("backbone", &DiscreteModel::backbone, py::arg("mode") = 1, py::arg("log10_amplitude") = py::none(),
           py::arg("harmonics") = py::none(), py::arg("time_samples") = py::none(), py::arg("callback") = py::none(),
           py::arg("accuracy") = py::none(), py::arg("max_output_change") = py::none(),
           py::arg("max_damping_ratio") = py::none(),
           "Damping curve (EPMC) of linear mode `mode` over log10 of the modal amplitude (the case's "
           "analysis.nonlinear_modes settings or the defaults): numpy arrays amplitude, omega, frequency_hz, "
           "damping_ratio, W_D, the error estimates, harmonics_of_points, time_samples_of_points; status, "
           "message. accuracy={'damping': 1e-3, ...} chooses H and N_t per point (as Pipeline.backbone); "
           "harmonics or time_samples given here trace at that fixed level; max_output_change as "
           "Pipeline.backbone; max_damping_ratio (default 0: none; 1: where the mode becomes overdamped) "
           "ends the curve at its first point with zeta >= it.")
      .def_property_readonly("parameter_names", [](DiscreteModel& d) { return d.pipe().parameter_names(); },
                             "contacts[i].kt0|kn|mu|normal_force|n, damping.rayleigh.alpha|beta, damping.modal[k]")
      .def("set", [](DiscreteModel& d, const std::string& name, double value) { d.pipe().set_parameter(name, value); },
           py::arg("name"), py::arg("value"), "Sets a parameter (C is rebuilt for a damping parameter).");

  m.def("fit", &fit_objective, py::arg("objective"), py::arg("parameters"), py::arg("options") = py::dict(),
        "Least squares with NLopt: objective(values: list) -> residuals (or None when it fails); parameters: "
        "list of dicts {name, lower, upper, start, log_scale}; options: algorithm, xtol, ftol_rel, "
        "max_evaluations, starts, seed. Returns best values, objective, standard errors.");

  m.def(
      "_run_study",
      [](const std::string& case_file, const std::string& output, int jobs, bool resume, const std::string& cache_dir) {
        const jointhb::io::StudyCase c = jointhb::io::read_study_case(case_file);
        jointhb::study::RunOptions options;
        options.jobs = jobs;
        options.resume = resume;
        std::filesystem::create_directories(output);
        const py::gil_scoped_release release;  // the workers run C++ only (child processes never enter Python)
        const jointhb::study::StudyResult r = jointhb::io::run_study_case(c, output, options, cache_dir);
        return std::string(jointhb::to_string(r.status().termination));
      },
      py::arg("case_file"), py::arg("output"), py::arg("jobs"), py::arg("resume"), py::arg("cache_dir"),
      "The study of a case file into OUTPUT (docs/studies.md); jointhb.run_study wraps it.");
}
