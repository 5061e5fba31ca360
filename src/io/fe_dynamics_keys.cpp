// The dynamic analyses of a finite-element case (fe_dynamics_keys.hpp, docs/case-files.md).
#include "fe_dynamics_keys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "continuation_keys.hpp"
#include "jointhb/io/value_checks.hpp"

#include "../support/numeric_constants.hpp"

namespace jointhb::io {
namespace {

using yaml::Fields;
using yaml::item_path;

using support::kTwoPi;

// A point inside or on the model lies within about half an element diagonal of a node; farther
// than this many largest element edges it is off the model (a typo, mm for m), and the "nearest
// node" would silently be some corner far away.
constexpr double kMaxPointDistanceInEdges = 2.0;

// The mesh's characteristic element size for the point check: its longest element edge [m].
double longest_edge(const fe::Mesh& mesh) {
  double longest = 0.0;
  for (const fe::Element& e : mesh.elements)
    for (const auto& [a, b] : fe::edge_corners(e.type))
      longest = std::max(longest, (mesh.coordinates.col(e.nodes[static_cast<std::size_t>(a)]) -
                                   mesh.coordinates.col(e.nodes[static_cast<std::size_t>(b)]))
                                      .norm());
  return longest;
}

class DynamicsReader {
 public:
  DynamicsReader(const yaml::Reader& reader, const fe::Mesh& mesh) : r_(reader), mesh_(mesh) {}

  FeDynamicsSpec read(const Fields& analysis) {
    FeDynamicsSpec d;
    const bool nm = analysis.has("nonlinear_modes"), frf = analysis.has("frf");
    if (!nm && !frf) {
      for (const char* key : {"damping", "reduction", "excitation", "outputs"})
        if (const auto* e = analysis.find(key))
          r_.fail(e->key, analysis.path_of(key), "is a setting of analysis.nonlinear_modes or analysis.frf; neither is given");
    }
    if (const auto* e = analysis.find("damping")) read_damping(e->value, analysis.path_of("damping"), d);
    if (const auto* e = analysis.find("reduction")) read_reduction(e->value, analysis.path_of("reduction"), d);
    if (const auto* e = analysis.find("excitation")) {
      d.excitation = node_direction(e->value, analysis.path_of("excitation"), false);
      d.excitation.name = "excitation";
    }
    if (const auto* e = analysis.find("outputs")) {
      const std::string path = analysis.path_of("outputs");
      if (!e->value.IsSequence() || e->value.size() == 0)
        r_.fail(e->value, path, "must be a non-empty list of {name, point, direction}");
      for (std::size_t i = 0; i < e->value.size(); ++i) {
        FeNodeDirection o = node_direction(e->value[i], item_path(path, i), true);
        for (const FeNodeDirection& other : d.outputs)
          if (other.name == o.name) r_.fail(e->value[i], item_path(path, i), fmt::format("output name '{}' is used twice", o.name));
        d.outputs.push_back(o);
      }
    } else if (analysis.has("excitation")) {
      FeNodeDirection o = d.excitation;
      o.name = "drive";
      d.outputs.push_back(o);
    }
    if (frf && !analysis.has("excitation"))
      r_.fail(analysis.find("frf")->key, analysis.path_of("excitation"), "required by analysis.frf (the point and direction of the force)");
    if (nm) d.nonlinear_modes = read_nonlinear_modes(analysis.find("nonlinear_modes")->value, analysis.path_of("nonlinear_modes"));
    if (frf) d.frf = read_frf(analysis.find("frf")->value, analysis.path_of("frf"), d);
    return d;
  }

 private:
  const yaml::Reader& r_;
  const fe::Mesh& mesh_;

  double number_in(const Fields& f, const char* name, double lo, double hi, bool lo_open, bool hi_open) const {
    const auto* e = f.find(name);
    const double v = r_.number(e->value, f.path_of(name));
    const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    if (!ok)
      r_.fail(e->value, f.path_of(name), fmt::format("must be in {}{}, {}{}, got {}", lo_open ? "(" : "[", lo,
                                                      hi == std::numeric_limits<double>::infinity() ? "inf" : fmt::format("{}", hi),
                                                      hi_open ? ")" : "]", v));
    return v;
  }

  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& path) const {
    if (!node.IsSequence() || node.size() != 3)
      r_.fail(node, path, "must be a list of 3 numbers, got " + yaml::Reader::describe(node));
    Eigen::Vector3d v;
    for (std::size_t k = 0; k < 3; ++k) v[static_cast<Eigen::Index>(k)] = r_.finite_number(node[k], item_path(path, k));
    return v;
  }

  FeNodeDirection node_direction(const YAML::Node& node, const std::string& path, bool named) const {
    const Fields f = r_.fields(node, path, named ? std::set<std::string>{"name", "point", "direction"}
                                                 : std::set<std::string>{"point", "direction"});
    FeNodeDirection o;
    if (named) {
      if (!f.has("name")) r_.fail(node, f.path_of("name"), "required");
      o.name = r_.text(f.find("name")->value, f.path_of("name"));
      if (o.name.empty()) r_.fail(f.find("name")->value, f.path_of("name"), "must not be empty");
    }
    if (!f.has("point")) r_.fail(node, f.path_of("point"), "required: [x, y, z] in m (the nearest node is used)");
    o.point = vector3(f.find("point")->value, f.path_of("point"));
    if (const auto* e = f.find("direction")) {
      o.direction = vector3(e->value, f.path_of("direction"));
      if (!(o.direction.norm() > 0.0)) r_.fail(e->value, f.path_of("direction"), "must not be zero");
      o.direction.normalize();
    }
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < mesh_.num_nodes(); ++i) {
      const double dist = (mesh_.coordinates.col(i) - o.point).norm();
      if (dist < best) best = dist, o.node = i;
    }
    o.distance = best;
    check_on_model(f.find("point")->value, f.path_of("point"), o);
    return o;
  }

  void check_on_model(const YAML::Node& node, const std::string& path, const FeNodeDirection& o) const {
    if (mesh_.elements.empty()) return;
    const double h = longest_edge(mesh_);
    if (o.distance <= kMaxPointDistanceInEdges * h) return;
    const Eigen::Vector3d x = mesh_.coordinates.col(o.node);
    r_.fail(node, path,
            fmt::format("must lie on the model (within {} x its longest element edge = {:.4g} m of a node), but "
                        "lies {:.4g} m from the nearest node, {} at [{:.6g}, {:.6g}, {:.6g}] (coordinates are in m)",
                        kMaxPointDistanceInEdges, kMaxPointDistanceInEdges * h, o.distance,
                        mesh_.node_ids.empty() ? static_cast<long>(o.node + 1)
                                               : mesh_.node_ids[static_cast<std::size_t>(o.node)],
                        x.x(), x.y(), x.z()));
  }

  void read_damping(const YAML::Node& node, const std::string& path, FeDynamicsSpec& d) const {
    const Fields f = r_.fields(node, path, {"ratio", "frequency_hz", "rayleigh"});
    if (f.has("rayleigh") && (f.has("ratio") || f.has("frequency_hz")))
      r_.fail(f.find("rayleigh")->key, f.path_of("rayleigh"), "give either rayleigh {alpha, beta} or ratio (with frequency_hz), not both");
    if (const auto* e = f.find("rayleigh")) {
      const Fields rf = r_.fields(e->value, f.path_of("rayleigh"), {"alpha", "beta"});
      if (rf.has("alpha")) d.rayleigh_mass = number_in(rf, "alpha", 0.0, std::numeric_limits<double>::infinity(), false, true);
      if (rf.has("beta")) d.rayleigh_stiffness = number_in(rf, "beta", 0.0, std::numeric_limits<double>::infinity(), false, true);
      return;
    }
    if (!f.has("ratio")) r_.fail(node, f.path_of("ratio"), "required (or rayleigh: {alpha, beta})");
    d.damping_ratio = number_in(f, "ratio", 0.0, 1.0, true, true);
    if (f.has("frequency_hz")) d.damping_frequency_hz = number_in(f, "frequency_hz", 0.0, std::numeric_limits<double>::infinity(), true, true);
  }

  void read_reduction(const YAML::Node& node, const std::string& path, FeDynamicsSpec& d) const {
    const Fields f = r_.fields(node, path, {"cutoff_hz", "cutoff_factor", "contact_patch"});
    if (f.has("contact_patch"))
      d.contact_patch = number_in(f, "contact_patch", 0.0, std::numeric_limits<double>::infinity(), false, true);
    if (f.has("cutoff_hz") && f.has("cutoff_factor"))
      r_.fail(f.find("cutoff_factor")->key, f.path_of("cutoff_factor"), "give either cutoff_hz or cutoff_factor, not both");
    if (f.has("cutoff_hz")) d.cutoff_hz = number_in(f, "cutoff_hz", 0.0, std::numeric_limits<double>::infinity(), true, true);
    if (f.has("cutoff_factor")) d.cutoff_factor = number_in(f, "cutoff_factor", 1.0, 1000.0, true, false);
  }

  // harmonics, time_samples, periodic_tolerance, tangential_stiffness.
  void read_balance(const Fields& f, hb::InterfaceBalanceOptions& b) const {
    if (const auto* e = f.find("harmonics")) {
      const long long h = r_.integer(e->value, f.path_of("harmonics"));
      r_.check(e->value, f.path_of("harmonics"), check_in_range(h, 1, 64));
      b.harmonics = static_cast<int>(h);
    }
    b.time_samples = pipeline::default_time_samples(b.harmonics);
    if (const auto* e = f.find("time_samples")) {
      const long long n = r_.integer(e->value, f.path_of("time_samples"));
      r_.check(e->value, f.path_of("time_samples"), check_in_range(n, 2 * b.harmonics + 2, 65536));
      b.time_samples = static_cast<int>(n);
    }
    if (f.has("periodic_tolerance")) b.periodic_tolerance = number_in(f, "periodic_tolerance", 0.0, 1e-3, true, false);
    if (const auto* e = f.find("tangential_stiffness")) {
      const std::string v = r_.text(e->value, f.path_of("tangential_stiffness"));
      r_.check(e->value, f.path_of("tangential_stiffness"), check_one_of(v, {"preloaded", "instantaneous"}));
      b.preloaded_tangential_stiffness = v == "preloaded";
    }
  }

  FeNonlinearModesSpec read_nonlinear_modes(const YAML::Node& node, const std::string& path) const {
    const Fields f = r_.fields(node, path, {"mode", "log10_amplitude", "frequency_drop", "harmonics", "time_samples",
                                            "periodic_tolerance", "tangential_stiffness", "continuation",
                                            "points_per_decade", "max_output_change", "fields", "volume_fields",
                                            "error_estimate", "accuracy"});
    FeNonlinearModesSpec o;
    o.balance.harmonics = 1;
    if (const auto* e = f.find("mode")) {
      const std::string key = f.path_of("mode");
      o.modes.clear();
      const auto add = [&](const YAML::Node& v, const std::string& where) {
        const long long k = r_.integer(v, where);
        r_.check(v, where, check_in_range(k, 1, 100));
        if (std::find(o.modes.begin(), o.modes.end(), static_cast<int>(k)) != o.modes.end())
          r_.fail(v, where, fmt::format("mode {} is listed twice", k));
        o.modes.push_back(static_cast<int>(k));
      };
      if (e->value.IsSequence()) {
        if (e->value.size() == 0) r_.fail(e->value, key, "must list at least one mode");
        for (std::size_t i = 0; i < e->value.size(); ++i) add(e->value[i], item_path(key, i));
      } else {
        add(e->value, key);
      }
    }
    if (const auto* e = f.find("log10_amplitude")) {
      const std::string key = f.path_of("log10_amplitude");
      if (!e->value.IsSequence() || e->value.size() != 2) r_.fail(e->value, key, "must be a list [start, end]");
      o.log10_amplitude_start = r_.finite_number(e->value[0], item_path(key, 0));
      o.log10_amplitude_end = r_.finite_number(e->value[1], item_path(key, 1));
      if (o.log10_amplitude_start == o.log10_amplitude_end) r_.fail(e->value[1], item_path(key, 1), "must differ from start");
    }
    if (f.has("frequency_drop")) o.frequency_drop = number_in(f, "frequency_drop", 0.0, 0.9, false, false);
    if (const auto* e = f.find("fields")) {
      const long long k = r_.integer(e->value, f.path_of("fields"));
      r_.check(e->value, f.path_of("fields"), check_in_range(k, 0, 1000));
      o.fields = static_cast<int>(k);
    }
    r_.flag(f, "volume_fields", o.volume_fields);
    r_.flag(f, "error_estimate", o.error_estimate);  // continuation/interface_error_estimate.hpp
    read_balance(f, o.balance);
    // H and N_t per point from the estimates, starting from harmonics/time_samples (continuation/accuracy.hpp).
    if (const auto* e = f.find("accuracy"))
      read_accuracy_keys(r_, e->value, f.path_of("accuracy"), o.balance.harmonics, o.balance.time_samples, false, o.accuracy);
    if (const auto* e = f.find("continuation")) read_continuation_keys(r_, e->value, f.path_of("continuation"), o.continuation);
    // At least this many points per decade of q: λ = log10 q advances by at most 1/points_per_decade.
    if (f.has("points_per_decade"))
      o.continuation.max_parameter_step = 1.0 / number_in(f, "points_per_decade", 0.0, 1000.0, true, false);
    // At most this relative change of f or ζ between two points (continuation::Options).
    if (f.has("max_output_change"))
      o.continuation.max_output_change = number_in(f, "max_output_change", 0.0, 1.0, true, false);
    return o;
  }

  FeFrfSpec read_frf(const YAML::Node& node, const std::string& path, const FeDynamicsSpec& d) const {
    const Fields f = r_.fields(node, path, {"frequency_hz", "omega", "force", "output", "harmonics", "time_samples",
                                            "periodic_tolerance", "tangential_stiffness", "continuation", "error_estimate",
                                            "accuracy", "max_output_change", "stability", "stability_method"});
    FeFrfSpec o;
    o.balance.harmonics = 1;
    const auto* hz = f.find("frequency_hz");
    const auto* omega = f.find("omega");
    if (hz && omega) r_.fail(omega->key, f.path_of("omega"), "give either omega [rad/s] or frequency_hz [Hz], not both");
    if (!hz && !omega) r_.fail(node, f.path_of("frequency_hz"), "required: the range [start, end] in Hz (or omega in rad/s)");
    {
      const auto* e = hz ? hz : omega;
      const std::string key = f.path_of(hz ? "frequency_hz" : "omega");
      if (!e->value.IsSequence() || e->value.size() != 2) r_.fail(e->value, key, "must be a list [start, end]");
      double v[2];
      for (std::size_t k = 0; k < 2; ++k) {
        v[k] = r_.number(e->value[k], item_path(key, k));
        r_.check(e->value[k], item_path(key, k), check_positive(v[k]));
      }
      if (v[0] == v[1]) r_.fail(e->value[1], item_path(key, 1), "must differ from start");
      const double scale = hz ? kTwoPi : 1.0;
      o.omega_start = scale * v[0];
      o.omega_end = scale * v[1];
    }
    if (!f.has("force")) r_.fail(node, f.path_of("force"), "required: the force amplitude F [N] (or a list, one curve each)");
    {
      const auto* e = f.find("force");
      const std::string key = f.path_of("force");
      const auto add = [&](const YAML::Node& v, const std::string& where) {
        const double x = r_.number(v, where);
        r_.check(v, where, check_positive(x));
        o.forces.push_back(x);
      };
      if (e->value.IsSequence()) {
        if (e->value.size() == 0) r_.fail(e->value, key, "must list at least one force");
        for (std::size_t i = 0; i < e->value.size(); ++i) add(e->value[i], item_path(key, i));
      } else {
        add(e->value, key);
      }
    }
    if (const auto* e = f.find("output")) {
      const std::string name = r_.text(e->value, f.path_of("output"));
      const auto it = std::find_if(d.outputs.begin(), d.outputs.end(), [&](const FeNodeDirection& x) { return x.name == name; });
      if (it == d.outputs.end()) {
        std::string known;
        for (const auto& x : d.outputs) known += (known.empty() ? "" : ", ") + x.name;
        r_.fail(e->value, f.path_of("output"), fmt::format("unknown output '{}'; analysis.outputs has: {}", name, known));
      }
      o.output = static_cast<int>(it - d.outputs.begin());
    }
    r_.flag(f, "error_estimate", o.error_estimate);  // continuation/interface_error_estimate.hpp
    if (const auto* e = f.find("stability"))  // hb/interface_orbit_monodromy.hpp at every point
      o.stability = read_stability_key(r_, e->value, f.path_of("stability"));
    if (const auto* e = f.find("stability_method"))  // or hb/interface_hill_stability.hpp
      o.stability_method = read_stability_method_key(r_, e->value, f.path_of("stability_method"));
    read_balance(f, o.balance);
    // H and N_t per point from the estimates of the amplitudes (continuation/accuracy.hpp).
    if (const auto* e = f.find("accuracy"))
      read_accuracy_keys(r_, e->value, f.path_of("accuracy"), o.balance.harmonics, o.balance.time_samples, true, o.accuracy);
    if (const auto* e = f.find("continuation")) read_continuation_keys(r_, e->value, f.path_of("continuation"), o.continuation);
    // At most this relative change of amplitude_h1 between two points (continuation::Options).
    if (f.has("max_output_change"))
      o.continuation.max_output_change = number_in(f, "max_output_change", 0.0, 1.0, true, false);
    return o;
  }
};

}  // namespace

FeDynamicsSpec read_fe_dynamics(const yaml::Reader& reader, const yaml::Fields& analysis, const fe::Mesh& mesh) {
  return DynamicsReader(reader, mesh).read(analysis);
}

}  // namespace jointhb::io
