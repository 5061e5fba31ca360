#include "jointhb/io/discrete_case.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"
#include "continuation_keys.hpp"
#include "fit_keys.hpp"
#include "study_keys.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

int default_time_samples(int harmonics) {
  int samples = 128;
  while (samples < 16 * harmonics) samples *= 2;
  return samples;
}

namespace {

using yaml::child_path;
using yaml::Fields;
using yaml::item_path;

/// The largest harmonic order a case may ask for (keeps a typo from allocating gigabytes).
constexpr long long max_harmonics = 256;
/// Largest periodic-state tolerance (HarmonicBalanceOptions::periodic_tolerance).
constexpr double max_periodic_tolerance = 1e-3;
/// Eigenvalues of K or C below -psd_tolerance · max|λ| make the matrix indefinite (round-off of a
/// singular matrix stays far above it).
constexpr double psd_tolerance = 1e-10;

const std::set<std::string> known_analyses = {"frf", "nonlinear_modes"};

std::string known_analysis_list() { return yaml::Reader::list(known_analyses); }

/// Where a matrix came from, to report problems at its entries.
struct MatrixSource {
  YAML::Node node;
  std::string path;
};

/// One entry of `excitation`, as written.
struct ForceInput {
  std::string path;
  int dof = 0;
  bool harmonic_force = false;
  std::vector<double> amplitudes;  ///< one per level, or one for all
  YAML::Node amplitude_node;
  int harmonic = 1;
  YAML::Node harmonic_node;  ///< null when left at the default
  bool has_static = false;
  double static_force = 0.0;
};

Eigen::VectorXd eigenvalues(const Eigen::MatrixXd& a) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a, Eigen::EigenvaluesOnly).eigenvalues();
}

// Reads the sections in the order their checks need, whatever their order in the file: model
// (sets n), contacts, excitation, analysis, then what the analyses need of the rest.
class DiscreteCaseReader {
 public:
  explicit DiscreteCaseReader(const std::string& file) : reader_(file) {}

  DiscreteCase read(const YAML::Node& root) {
    DiscreteCase c;
    c.source = reader_.file();
    if (root.IsNull()) reader_.fail(root, "model", "required (the file is empty)");
    const Fields top = reader_.fields(root, "", {"model", "contacts", "excitation", "analysis", "fit", "study"});
    const auto* model = top.find("model");
    if (!model) reader_.fail(root, "model", "required");
    read_model(model->value, c);
    if (const auto* contacts = top.find("contacts")) read_contacts(contacts->value, c);
    if (const auto* excitation = top.find("excitation")) read_excitation(excitation->value, c);

    const auto* analysis = top.find("analysis");
    if (!analysis) {
      reader_.fail(root, "analysis", "required; known analyses: " + known_analysis_list());
    }
    const Fields analyses = reader_.fields(analysis->value, "analysis", known_analyses,
                                           &DiscreteCaseReader::unknown_analysis);
    if (analyses.entries().empty()) {
      reader_.fail(analysis->value, "analysis",
                   "must name at least one analysis; known: " + known_analysis_list());
    }
    if (const auto* frf = analyses.find("frf")) {
      c.frf = read_frf(frf->value, analyses.path_of("frf"), c.system.dofs());
      check_frf_excitation(*frf, *c.frf, top, c);
    }
    if (const auto* modes = analyses.find("nonlinear_modes")) {
      c.nonlinear_modes =
          read_nonlinear_modes(modes->value, analyses.path_of("nonlinear_modes"), c.system.dofs());
      c.modes = modes_;
      // EPMC scales the unknowns by the modal amplitude: no static offset is admitted.
      for (const auto& level : c.levels) {
        if (level.has_static_part()) {
          reader_.fail(modes->key, analyses.path_of("nonlinear_modes"),
                       "needs a case without static force (the free vibration about x = 0)");
        }
      }
      for (std::size_t i = 0; i < c.system.contacts.size(); ++i) {
        const auto& k = c.system.contacts[i];
        if (k.has_reference_offset()) {
          reader_.fail(
              modes->key, analyses.path_of("nonlinear_modes"),
              fmt::format("needs contacts without reference state; contacts[{}] has one", i));
        }
      }
    }
    // fit: last, since its parameter names and targets depend on the contacts and analyses.
    if (const auto* section = top.find("fit")) {
      c.fit = read_fit_section(reader_, section->value, "fit", fit_context(c),
                               std::filesystem::path(reader_.file()).parent_path());
    }
    if (const auto* section = top.find("study")) c.study = read_study_section(reader_, section->value, "study", fit_context(c));
    return c;
  }

 private:
  static std::string unknown_analysis(const std::string& key) {
    if (key == "loop_sweep") {
      return "belongs to a case without model (one contact point under a prescribed slip); "
             "analyses of a model: " +
             known_analysis_list();
    }
    return "unknown key; allowed: " + known_analysis_list();
  }

  // ---- model -----------------------------------------------------------------------------------

  void read_model(const YAML::Node& node, DiscreteCase& c) {
    const Fields model = reader_.fields(node, "model", {"type", "mass", "stiffness", "damping"});
    const auto* type = model.find("type");
    if (!type) reader_.fail(node, "model.type", "required (discrete)");
    const std::string type_name = reader_.text(type->value, "model.type");
    if (type_name != "discrete") {
      reader_.fail(type->value, "model.type",
                   "must be discrete here (fe: a finite-element case, docs/case-files.md), got '" +
                       type_name + "'");
    }
    if (!model.has("mass")) reader_.fail(node, "model.mass", "required");
    mass_ = {model.find("mass")->value, "model.mass"};
    const Eigen::MatrixXd m = read_matrix(mass_, -1);
    const int n = static_cast<int>(m.rows());
    if (!model.has("stiffness")) reader_.fail(node, "model.stiffness", "required");
    stiffness_ = {model.find("stiffness")->value, "model.stiffness"};
    const Eigen::MatrixXd k = read_matrix(stiffness_, n);

    c.system.mass = m.sparseView();
    c.system.stiffness = k.sparseView();
    check_system(c.system);
    check_semi_definite(k, stiffness_);

    if (const auto* damping = model.find("damping")) read_damping(damping->value, m, k, c);
  }

  /// A square matrix: a list of n rows of n numbers, or a plain number for n = 1. With `n` < 0 it
  /// sets the size (the mass matrix); otherwise it must have n rows.
  // A number of the model or the excitation: finite and of a magnitude doubles can multiply
  // (check_magnitude: 0 or in [1e-100, 1e100]; issue 20, item 3: mass 1e300 gave meaningless
  // amplitudes and stability verdicts).
  double physical_number(const YAML::Node& node, const std::string& path) const {
    const double value = reader_.finite_number(node, path);
    reader_.check(node, path, check_magnitude(value));
    return value;
  }

  Eigen::MatrixXd read_matrix(const MatrixSource& source, int n) const {
    const YAML::Node& node = source.node;
    const std::string& path = source.path;
    if (yaml::Reader::is_plain_scalar(node)) {
      const double value = physical_number(node, path);
      if (n > 1) {
        reader_.fail(node, path,
                     fmt::format("must be a {} x {} matrix like model.mass, got a number", n, n));
      }
      return Eigen::MatrixXd::Constant(1, 1, value);
    }
    if (!node.IsSequence()) {
      reader_.fail(node, path,
                   "must be a square matrix (a list of rows, or a number for one DOF), got " +
                       yaml::Reader::describe(node));
    }
    const auto rows = static_cast<int>(node.size());
    if (rows == 0) reader_.fail(node, path, "must be a non-empty square matrix, got no rows");
    if (n >= 0 && rows != n) {
      reader_.fail(node, path, fmt::format("must have {} rows like model.mass, got {}", n, rows));
    }
    Eigen::MatrixXd a(rows, rows);
    for (int i = 0; i < rows; ++i) {
      const YAML::Node row = node[static_cast<std::size_t>(i)];
      const std::string row_path = item_path(path, static_cast<std::size_t>(i));
      if (!row.IsSequence()) {
        reader_.fail(row, row_path,
                     "must be a row (a list of numbers), got " + yaml::Reader::describe(row));
      }
      const auto columns = static_cast<int>(row.size());
      if (columns != rows) {
        reader_.fail(row, row_path,
                     n >= 0
                         ? fmt::format("must have {} entries like model.mass, got {}", n, columns)
                         : fmt::format("must have {} entries (a square matrix of {} rows), got {}",
                                       rows, rows, columns));
      }
      for (int j = 0; j < rows; ++j) {
        const auto jj = static_cast<std::size_t>(j);
        a(i, j) = physical_number(row[jj], item_path(row_path, jj));
      }
    }
    return a;
  }

  void read_damping(const YAML::Node& node, const Eigen::MatrixXd& m, const Eigen::MatrixXd& k,
                    DiscreteCase& c) {
    const std::string path = "model.damping";
    const Fields damping = reader_.fields(node, path, {"rayleigh", "matrix", "modal"});
    if (damping.entries().empty()) {
      reader_.fail(node, path, "must give one of matrix, modal, rayleigh");
    }
    if (damping.entries().size() > 1) {
      const auto& second = damping.entries()[1];
      reader_.fail(second.key, damping.path_of(second.name),
                   "only one damping model is allowed; '" + damping.entries()[0].name +
                       "' is already given");
    }
    const auto& model = damping.entries().front();
    const std::string model_path = damping.path_of(model.name);
    c.damping_model = model.name;
    const int n = static_cast<int>(m.rows());
    damping_ = {model.value, model_path};
    if (model.name == "rayleigh") {
      const Fields rayleigh = reader_.fields(model.value, model_path, {"alpha", "beta"});
      for (const auto& entry : rayleigh.entries()) {
        const std::string key = rayleigh.path_of(entry.name);
        const double value = reader_.number(entry.value, key);
        reader_.check(entry.value, key, check_non_negative(value));
        (entry.name == "alpha" ? c.rayleigh_alpha : c.rayleigh_beta) = value;
      }
      const Eigen::MatrixXd damping_matrix = c.rayleigh_alpha * m + c.rayleigh_beta * k;
      c.system.damping = damping_matrix.sparseView();
      check_system(c.system);
    } else if (model.name == "matrix") {
      const Eigen::MatrixXd damping_matrix = read_matrix(damping_, n);
      c.system.damping = damping_matrix.sparseView();
      check_system(c.system);
      check_semi_definite(damping_matrix, damping_);
    } else {
      const YAML::Node& ratios = model.value;
      if (!ratios.IsSequence()) {
        reader_.fail(ratios, model_path,
                     "must be a list of damping ratios (one per mode, lowest first), got " +
                         yaml::Reader::describe(ratios));
      }
      if (ratios.size() == 0 || ratios.size() > static_cast<std::size_t>(n)) {
        reader_.fail(ratios, model_path,
                     fmt::format("must have 1 to {} entries (one per mode, lowest first), got {}",
                                 n, ratios.size()));
      }
      for (std::size_t i = 0; i < ratios.size(); ++i) {
        const std::string key = item_path(model_path, i);
        const double zeta = reader_.number(ratios[i], key);
        reader_.check(ratios[i], key, check_non_negative(zeta));
        c.modal_damping_ratios.push_back(zeta);
      }
      try {
        c.system.damping =
            hb::modal_damping_matrix(c.system.mass, c.system.stiffness, c.modal_damping_ratios);
      } catch (const std::invalid_argument& e) {
        reader_.fail(ratios, model_path, e.what());  // not expected: M and the count are checked
      }
      check_system(c.system);
    }
  }

  /// Positive semi-definite up to round-off (K, C).
  void check_semi_definite(const Eigen::MatrixXd& a, const MatrixSource& source) const {
    const Eigen::VectorXd lambda = eigenvalues(a);
    const double smallest = lambda.minCoeff();
    if (smallest < -psd_tolerance * lambda.cwiseAbs().maxCoeff()) {
      reader_.fail(
          source.node, source.path,
          "must be positive semi-definite, got smallest eigenvalue " + format_number(smallest));
    }
  }

  /// Runs DiscreteSystem::validate() and reports its first complaint at the key it concerns.
  void check_system(const hb::DiscreteSystem& system) const {
    const std::string message = system.validate();
    if (message.empty()) return;
    const auto colon = message.find(": ");
    const std::string field = colon == std::string::npos ? "" : message.substr(0, colon);
    const std::string constraint = colon == std::string::npos ? message : message.substr(colon + 2);
    const MatrixSource* matrix = field == "mass"        ? &mass_
                                 : field == "stiffness" ? &stiffness_
                                 : field == "damping"   ? &damping_
                                                        : nullptr;
    if (matrix && matrix->node.IsDefined()) {
      const Eigen::MatrixXd a(field == "mass"        ? system.mass
                              : field == "stiffness" ? system.stiffness
                                                     : system.damping);
      if (constraint.rfind("must be symmetric", 0) == 0) fail_asymmetric(a, *matrix);
      if (constraint.rfind("must be positive definite", 0) == 0) {
        reader_.fail(matrix->node, matrix->path,
                     "must be positive definite, got smallest eigenvalue " +
                         format_number(eigenvalues(a).minCoeff()));
      }
      reader_.fail(matrix->node, matrix->path, constraint);
    }
    // "contacts[i].field": at the field when the entry has it, else at the entry.
    if (field.rfind("contacts[", 0) == 0) {
      const auto close = field.find(']');
      const std::size_t index = std::stoul(field.substr(9, close - 9));
      const std::string name = close + 2 <= field.size() ? field.substr(close + 2) : "";
      if (index < contact_nodes_.size()) {
        const YAML::Node& entry = contact_nodes_[index];
        const YAML::Node value = entry.IsMap() && !name.empty() ? entry[name] : YAML::Node();
        reader_.fail(value.IsDefined() && !value.IsNull() ? value : entry, field, constraint);
      }
    }
    reader_.fail(mass_.node, "model", message);
  }

  /// Reports the entry below the diagonal that differs most from its mirror.
  [[noreturn]] void fail_asymmetric(const Eigen::MatrixXd& a, const MatrixSource& source) const {
    if (!source.node.IsSequence()) {
      reader_.fail(source.node, source.path, "must be symmetric");  // computed (rayleigh, modal)
    }
    Eigen::Index row = 1;
    Eigen::Index column = 0;
    double worst = -1.0;
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      for (Eigen::Index j = 0; j < i; ++j) {
        const double difference = std::abs(a(i, j) - a(j, i));
        if (difference > worst) {
          worst = difference;
          row = i;
          column = j;
        }
      }
    }
    const auto i = static_cast<std::size_t>(row);
    const auto j = static_cast<std::size_t>(column);
    reader_.fail(source.node[i][j], item_path(item_path(source.path, i), j),
                 fmt::format("must equal {}[{}][{}] = {} (the matrix must be symmetric), got {}",
                             source.path, j, i, a(column, row), a(row, column)));
  }

  // ---- contacts --------------------------------------------------------------------------------

  void read_contacts(const YAML::Node& node, DiscreteCase& c) {
    if (!node.IsSequence()) {
      reader_.fail(node, "contacts",
                   "must be a list of contact elements, got " + yaml::Reader::describe(node));
    }
    const int n = c.system.dofs();
    for (std::size_t i = 0; i < node.size(); ++i) {
      contact_nodes_.push_back(node[i]);
      c.system.contacts.push_back(read_contact(node[i], item_path("contacts", i), n));
    }
    check_system(c.system);
  }

  hb::ContactElement read_contact(const YAML::Node& node, const std::string& path, int n) const {
    const Fields f = reader_.fields(
        node, path,
        {"law", "dofs", "kt0", "kn", "mu", "normal_force", "n", "reference_force", "reference_slip"});
    if (!f.has("law")) reader_.fail(node, f.path_of("law"), "required");
    hb::ContactElement e;
    const YAML::Node law = f.find("law")->value;
    e.law = reader_.text(law, f.path_of("law"));
    reader_.check(law, f.path_of("law"),
                  check_one_of(e.law, {"gaul-mayer", "jenkins", "normal-exponential"}));
    // The normal law (N-3) has its own keys: the preload and the normal stiffness k_N.
    const std::vector<const char*> keys =
        e.normal() ? std::vector<const char*>{"law", "dofs", "kn", "normal_force"}
                   : std::vector<const char*>{"law", "dofs", "kt0", "mu", "normal_force"};
    for (const char* name : {"kt0", "kn", "mu", "n", "reference_force", "reference_slip"}) {
      const auto* entry = f.find(name);
      if (entry == nullptr) continue;
      if (e.normal() && std::string_view(name) != "kn") {
        reader_.fail(entry->key, f.path_of(name),
                     "not a parameter of law normal-exponential (its keys: law, dofs, kn, normal_force)");
      }
      if (!e.normal() && std::string_view(name) == "kn") {
        reader_.fail(entry->key, f.path_of(name),
                     "a parameter of law normal-exponential only (friction laws take kt0)");
      }
    }
    for (const char* name : keys) {
      if (!f.has(name)) reader_.fail(node, f.path_of(name), "required for law " + e.law);
    }
    if (const auto* exponent = f.find("n")) {
      if (e.law == "jenkins") {
        reader_.fail(exponent->key, f.path_of("n"),
                     "not a parameter of the jenkins law (only gaul-mayer has an exponent)");
      }
      e.exponent = reader_.number(exponent->value, f.path_of("n"));
      reader_.check(exponent->value, f.path_of("n"), check_open_unit(e.exponent));
    } else if (e.law == "gaul-mayer") {
      reader_.fail(node, f.path_of("n"), "required for law gaul-mayer (in (0, 1))");
    }

    const YAML::Node dofs = f.find("dofs")->value;
    const std::string dofs_path = f.path_of("dofs");
    if (!dofs.IsSequence() || dofs.size() < 1 || dofs.size() > 2) {
      reader_.fail(dofs, dofs_path,
                   "must be [a] (to ground) or [a, b] (between two DOFs), got " +
                       (dofs.IsSequence() ? fmt::format("{} entries", dofs.size())
                                          : yaml::Reader::describe(dofs)));
    }
    int indices[2] = {0, -1};
    for (std::size_t k = 0; k < dofs.size(); ++k) {
      const std::string key = item_path(dofs_path, k);
      const long long dof = reader_.integer(dofs[k], key);
      reader_.check(dofs[k], key, check_in_range(dof, 0, n - 1));
      indices[k] = static_cast<int>(dof);
    }
    if (indices[1] == indices[0]) {
      reader_.fail(dofs[1], item_path(dofs_path, 1),
                   fmt::format("must differ from {}[0] = {} (a contact joins two different DOFs)",
                               dofs_path, indices[0]));
    }
    e.dof_a = indices[0];
    e.dof_b = indices[1];

    const auto positive = [&](const char* name) {
      const YAML::Node value = f.find(name)->value;
      const double x = reader_.number(value, f.path_of(name));
      reader_.check(value, f.path_of(name), check_positive(x));
      reader_.check(value, f.path_of(name), check_magnitude(x));
      return x;
    };
    e.normal_force = positive("normal_force");
    if (e.normal()) {
      e.stiffness = positive("kn");
      return e;
    }
    e.stiffness = positive("kt0");
    e.friction_coefficient = positive("mu");
    if (const auto* force = f.find("reference_force")) {
      const std::string key = f.path_of("reference_force");
      e.reference_force = reader_.finite_number(force->value, key);
      if (std::abs(e.reference_force) > e.slip_limit()) {
        reader_.fail(
            force->value, key,
            fmt::format("must be in [-mu normal_force, mu normal_force] = [{}, {}], got {}",
                        -e.slip_limit(), e.slip_limit(), e.reference_force));
      }
    }
    if (const auto* slip = f.find("reference_slip")) {
      e.reference_slip = reader_.finite_number(slip->value, f.path_of("reference_slip"));
    }
    return e;
  }

  // ---- excitation ------------------------------------------------------------------------------

  void read_excitation(const YAML::Node& node, DiscreteCase& c) {
    if (!node.IsSequence() || node.size() == 0) {
      reader_.fail(
          node, "excitation",
          "must be a non-empty list of forces, got " +
              (node.IsSequence() ? std::string("an empty list") : yaml::Reader::describe(node)));
    }
    const int n = c.system.dofs();
    for (std::size_t i = 0; i < node.size(); ++i) {
      forces_.push_back(read_force(node[i], item_path("excitation", i), n));
    }

    // Levels: the longest amplitude list; shorter lists must have one entry (used at every level).
    std::size_t levels = 1;
    const ForceInput* longest = nullptr;
    for (const auto& force : forces_) {
      if (force.amplitudes.size() > levels) {
        levels = force.amplitudes.size();
        longest = &force;
      }
    }
    for (const auto& force : forces_) {
      const std::size_t count = force.amplitudes.size();
      if (force.harmonic_force && count != 1 && count != levels) {
        reader_.fail(force.amplitude_node, child_path(force.path, "amplitude"),
                     fmt::format("must have {} entries (one per level, like {}.amplitude) or 1, "
                                 "got {}",
                                 levels, longest->path, count));
      }
    }

    Eigen::VectorXd static_force;
    for (const auto& force : forces_) {
      if (!force.has_static) continue;
      if (static_force.size() == 0) static_force = Eigen::VectorXd::Zero(n);
      static_force[force.dof] += force.static_force;
    }
    for (std::size_t level = 0; level < levels; ++level) {
      hb::Excitation excitation;
      excitation.static_force = static_force;
      double label = 0.0;
      for (const auto& force : forces_) {
        if (!force.harmonic_force) continue;
        const double amplitude = force.amplitudes[force.amplitudes.size() == 1 ? 0 : level];
        excitation.forces.push_back({force.dof, amplitude, force.harmonic});
        label = std::max(label, std::abs(amplitude));
      }
      c.levels.push_back(std::move(excitation));
      c.level_amplitudes.push_back(label);
    }
  }

  ForceInput read_force(const YAML::Node& node, const std::string& path, int n) const {
    const Fields f = reader_.fields(node, path, {"dof", "amplitude", "harmonic", "static"});
    ForceInput force;
    force.path = path;
    const auto* dof = f.find("dof");
    if (!dof) reader_.fail(node, f.path_of("dof"), "required");
    const long long index = reader_.integer(dof->value, f.path_of("dof"));
    reader_.check(dof->value, f.path_of("dof"), check_in_range(index, 0, n - 1));
    force.dof = static_cast<int>(index);

    const auto* amplitude = f.find("amplitude");
    const auto* stat = f.find("static");
    if (!amplitude && !stat) {
      reader_.fail(node, path,
                   "must give amplitude (a harmonic force) or static (a constant force)");
    }
    if (amplitude) {
      force.harmonic_force = true;
      force.amplitude_node = amplitude->value;
      const std::string key = f.path_of("amplitude");
      if (amplitude->value.IsSequence()) {
        if (amplitude->value.size() == 0) {
          reader_.fail(amplitude->value, key, "must be a number or a non-empty list of numbers");
        }
        for (std::size_t i = 0; i < amplitude->value.size(); ++i) {
          force.amplitudes.push_back(physical_number(amplitude->value[i], item_path(key, i)));
        }
      } else {
        force.amplitudes.push_back(physical_number(amplitude->value, key));
      }
    }
    if (const auto* harmonic = f.find("harmonic")) {
      const std::string key = f.path_of("harmonic");
      if (!amplitude) reader_.fail(harmonic->key, key, "only with amplitude (a harmonic force)");
      const long long order = reader_.integer(harmonic->value, key);
      reader_.check(harmonic->value, key, check_in_range(order, 1, max_harmonics));
      force.harmonic = static_cast<int>(order);
      force.harmonic_node = harmonic->value;
    }
    if (stat) {
      force.has_static = true;
      force.static_force = physical_number(stat->value, f.path_of("static"));
    }
    return force;
  }

  // ---- analysis.frf ----------------------------------------------------------------------------

  /// A range [start, end] of two distinct positive numbers.
  std::pair<double, double> read_range(const YAML::Node& node, const std::string& path) const {
    if (!node.IsSequence() || node.size() != 2) {
      reader_.fail(node, path, "must be a range [start, end] of two numbers");
    }
    const double start = reader_.number(node[0], item_path(path, 0));
    reader_.check(node[0], item_path(path, 0), check_positive(start));
    reader_.check(node[0], item_path(path, 0), check_magnitude(start));
    const double end = reader_.number(node[1], item_path(path, 1));
    reader_.check(node[1], item_path(path, 1), check_positive(end));
    reader_.check(node[1], item_path(path, 1), check_magnitude(end));
    if (end == start) {
      reader_.fail(node[1], item_path(path, 1),
                   fmt::format("must differ from start {}, got {}", start, end));
    }
    return {start, end};
  }

  // `harmonics` and `time_samples` (default: default_time_samples(H)), shared by the analyses.
  void read_harmonics(const Fields& f, int& harmonics, int& time_samples) const {
    if (const auto* entry = f.find("harmonics")) {
      const long long h = reader_.integer(entry->value, f.path_of("harmonics"));
      reader_.check(entry->value, f.path_of("harmonics"), check_in_range(h, 1, max_harmonics));
      harmonics = static_cast<int>(h);
    }
    time_samples = default_time_samples(harmonics);
    if (const auto* samples = f.find("time_samples")) {
      const std::string key = f.path_of("time_samples");
      const long long count = reader_.integer(samples->value, key);
      const long long min = 2LL * harmonics + 2;
      if (count < min || count > max_time_samples) {
        reader_.fail(samples->value, key,
                     fmt::format("must be in [2 harmonics + 2 = {}, {}], got {}", min,
                                 max_time_samples, count));
      }
      time_samples = static_cast<int>(count);
    }
  }

  // `harmonic_selection` and `periodic_tolerance`; returns the selection's node when given.
  const YAML::Node* read_selection(const Fields& f, hb::HarmonicSelection& selection,
                                   double& periodic_tolerance) const {
    const YAML::Node* given = nullptr;
    if (const auto* entry = f.find("harmonic_selection")) {
      const std::string key = f.path_of("harmonic_selection");
      given = &entry->value;
      const std::string name = reader_.text(entry->value, key);
      reader_.check(entry->value, key, check_one_of(name, {"auto", "all", "odd"}));
      selection = name == "all"   ? hb::HarmonicSelection::all
                  : name == "odd" ? hb::HarmonicSelection::odd
                                  : hb::HarmonicSelection::automatic;
    }
    if (const auto* tolerance = f.find("periodic_tolerance")) {
      const std::string key = f.path_of("periodic_tolerance");
      periodic_tolerance = reader_.number(tolerance->value, key);
      reader_.check(tolerance->value, key, check_positive(periodic_tolerance));
      if (periodic_tolerance > max_periodic_tolerance) {
        reader_.fail(
            tolerance->value, key,
            fmt::format("must be in (0, {}], got {}", max_periodic_tolerance, periodic_tolerance));
      }
    }
    return given;
  }

  continuation::FrfOptions read_frf(const YAML::Node& node, const std::string& path, int n) {
    const Fields f = reader_.fields(
        node, path,
        {"omega", "frequency_hz", "harmonics", "time_samples", "output_dof", "harmonic_selection",
         "periodic_tolerance", "check_jacobian", "stability", "stability_method",
         "error_estimate", "continuation", "max_output_change", "accuracy"});
    continuation::FrfOptions o;

    const auto* omega = f.find("omega");
    const auto* hz = f.find("frequency_hz");
    if (omega && hz) {
      const auto& later = f.entries()[std::max(index_of(f, "omega"), index_of(f, "frequency_hz"))];
      reader_.fail(later.key, f.path_of(later.name),
                   "give either omega [rad/s] or frequency_hz [Hz], not both");
    }
    if (!omega && !hz) {
      reader_.fail(node, f.path_of("omega"),
                   "required: the range [start, end] in rad/s (or frequency_hz in Hz)");
    }
    if (omega) {
      std::tie(o.omega_start, o.omega_end) = read_range(omega->value, f.path_of("omega"));
    } else {
      const auto [f0, f1] = read_range(hz->value, f.path_of("frequency_hz"));
      o.omega_start = 2.0 * std::numbers::pi * f0;
      o.omega_end = 2.0 * std::numbers::pi * f1;
    }

    read_harmonics(f, o.harmonics, o.time_samples);
    if (const auto* output = f.find("output_dof")) {
      const long long dof = reader_.integer(output->value, f.path_of("output_dof"));
      reader_.check(output->value, f.path_of("output_dof"), check_in_range(dof, 0, n - 1));
      o.output_dof = static_cast<int>(dof);
    }
    if (const auto* selection = read_selection(f, o.selection, o.periodic_tolerance)) {
      selection_node_ = *selection;
    }
    reader_.flag(f, "check_jacobian", o.check_jacobian);
    reader_.flag(f, "error_estimate", o.error_estimate);  // continuation/error_estimate.hpp
    // H and N_t per point from the estimates of the amplitudes (continuation/accuracy.hpp).
    if (const auto* e = f.find("accuracy"))
      read_accuracy_keys(reader_, e->value, f.path_of("accuracy"), o.harmonics, o.time_samples, true, o.accuracy);
    if (const auto* stability = f.find("stability"))  // Floquet multipliers at every point
      o.stability = read_stability_key(reader_, stability->value, f.path_of("stability"));
    if (const auto* method = f.find("stability_method"))
      o.stability_method = read_stability_method_key(reader_, method->value, f.path_of("stability_method"));
    if (const auto* steps = f.find("continuation")) {
      read_continuation(steps->value, f.path_of("continuation"), o.continuation);
    }
    read_output_change(f, o.continuation);
    return o;
  }

  continuation::BackboneOptions read_nonlinear_modes(const YAML::Node& node,
                                                     const std::string& path, int n) {
    const Fields f = reader_.fields(node, path,
                                    {"mode", "log10_amplitude", "harmonics", "time_samples", "output_dof",
                                     "harmonic_selection", "periodic_tolerance", "error_estimate",
                                     "continuation", "points_per_decade", "max_output_change", "accuracy",
                                     "max_damping_ratio"});
    continuation::BackboneOptions o;
    modes_.clear();
    if (const auto* mode = f.find("mode")) {
      // One mode number, or a list of them (one damping curve each).
      const std::string key = f.path_of("mode");
      const auto read_one = [&](const YAML::Node& value, const std::string& where) {
        const long long k = reader_.integer(value, where);
        reader_.check(value, where, check_in_range(k, 1, n));
        for (int seen : modes_) {
          if (seen == k) reader_.fail(value, where, fmt::format("mode {} is listed twice", k));
        }
        modes_.push_back(static_cast<int>(k));
      };
      if (mode->value.IsSequence()) {
        if (mode->value.size() == 0) reader_.fail(mode->value, key, "must list at least one mode");
        for (std::size_t i = 0; i < mode->value.size(); ++i) {
          read_one(mode->value[i], item_path(key, i));
        }
      } else {
        read_one(mode->value, key);
      }
      o.mode.mode = modes_.front();
    } else {
      modes_.push_back(1);
    }
    const auto* range = f.find("log10_amplitude");
    if (!range) {
      reader_.fail(node, f.path_of("log10_amplitude"),
                   "required: [start, end] of log10 of the modal amplitude");
    }
    {
      const std::string key = f.path_of("log10_amplitude");
      if (!range->value.IsSequence() || range->value.size() != 2) {
        reader_.fail(range->value, key, "must be a list [start, end]");
      }
      o.log10_amplitude_start = reader_.number(range->value[0], item_path(key, 0));
      reader_.check(range->value[0], item_path(key, 0), check_finite(o.log10_amplitude_start));
      o.log10_amplitude_end = reader_.number(range->value[1], item_path(key, 1));
      reader_.check(range->value[1], item_path(key, 1), check_finite(o.log10_amplitude_end));
      if (o.log10_amplitude_end == o.log10_amplitude_start) {
        reader_.fail(range->value[1], item_path(key, 1), "must differ from start");
      }
    }
    if (const auto* output = f.find("output_dof")) {
      const long long dof = reader_.integer(output->value, f.path_of("output_dof"));
      reader_.check(output->value, f.path_of("output_dof"), check_in_range(dof, 0, n - 1));
      o.output_dof = static_cast<int>(dof);
    }
    read_harmonics(f, o.mode.harmonics, o.mode.time_samples);
    read_selection(f, o.mode.selection, o.mode.periodic_tolerance);
    reader_.flag(f, "error_estimate", o.error_estimate);  // continuation/error_estimate.hpp
    // H and N_t per point from the estimates, starting from harmonics/time_samples (continuation/accuracy.hpp).
    if (const auto* e = f.find("accuracy"))
      read_accuracy_keys(reader_, e->value, f.path_of("accuracy"), o.mode.harmonics, o.mode.time_samples, false, o.accuracy);
    if (const auto* steps = f.find("continuation")) {
      read_continuation(steps->value, f.path_of("continuation"), o.continuation);
    }
    // At least this many points per decade of q: λ = log10 q advances by at most 1/points_per_decade.
    if (const auto* e = f.find("points_per_decade")) {
      const std::string key = f.path_of("points_per_decade");
      const double v = reader_.number(e->value, key);
      if (!(std::isfinite(v) && v > 0.0 && v <= 1000.0)) reader_.fail(e->value, key, fmt::format("must be in (0, 1000], got {}", v));
      o.continuation.max_parameter_step = 1.0 / v;
    }
    read_output_change(f, o.continuation);  // of f and ζ
    // The curve ends at the first point with ζ ≥ this (1: where the mode becomes overdamped); 0, the default: never.
    if (const auto* e = f.find("max_damping_ratio")) {
      const std::string key = f.path_of("max_damping_ratio");
      const double v = reader_.number(e->value, key);
      if (!(std::isfinite(v) && v >= 0.0)) reader_.fail(e->value, key, fmt::format("must be finite and >= 0 (0: none), got {}", v));
      o.max_damping_ratio = v;
    }
    return o;
  }

  // max_output_change: at most this relative change of the outputs between two points
  // (continuation::Options: f and ζ of a damping curve, amplitude_h1 of an FRF).
  void read_output_change(const Fields& f, continuation::Options& c) {
    const auto* e = f.find("max_output_change");
    if (!e) return;
    const std::string key = f.path_of("max_output_change");
    const double v = reader_.number(e->value, key);
    if (!(std::isfinite(v) && v > 0.0 && v <= 1.0)) reader_.fail(e->value, key, fmt::format("must be in (0, 1], got {}", v));
    c.max_output_change = v;
  }

  std::vector<int> modes_;  // analysis.nonlinear_modes.mode, as listed

  static std::size_t index_of(const Fields& f, const std::string& name) {
    for (std::size_t i = 0; i < f.entries().size(); ++i) {
      if (f.entries()[i].name == name) return i;
    }
    return 0;
  }

  void read_continuation(const YAML::Node& node, const std::string& path,
                         continuation::Options& o) const {
    read_continuation_keys(reader_, node, path, o);
  }

  /// What an FRF needs of the excitation: a harmonic force at every level, harmonics within H,
  /// and a symmetric case for harmonic_selection odd.
  void check_frf_excitation(const Fields::Entry& frf, const continuation::FrfOptions& options,
                            const Fields& top, const DiscreteCase& c) const {
    const auto* excitation = top.find("excitation");
    if (!excitation) {
      reader_.fail(frf.key, "excitation", "required by analysis.frf (a list of forces)");
    }
    const bool any_harmonic = std::any_of(forces_.begin(), forces_.end(),
                                          [](const ForceInput& f) { return f.harmonic_force; });
    if (!any_harmonic) {
      reader_.fail(excitation->value, "excitation",
                   "analysis.frf needs a harmonic force (an entry with amplitude)");
    }
    for (std::size_t level = 0; level < c.level_amplitudes.size(); ++level) {
      if (c.level_amplitudes[level] == 0.0) {
        reader_.fail(excitation->value, "excitation",
                     fmt::format("level {} has only zero amplitudes (analysis.frf needs a force "
                                 "at every level)",
                                 level));
      }
    }
    for (const auto& force : forces_) {
      if (force.harmonic > options.harmonics) {
        reader_.fail(force.harmonic_node, child_path(force.path, "harmonic"),
                     fmt::format("must be <= analysis.frf.harmonics = {}, got {}",
                                 options.harmonics, force.harmonic));
      }
    }
    if (options.selection != hb::HarmonicSelection::odd) return;
    // The conditions of hb::is_symmetric, each reported with the entry that breaks it.
    std::string reason;
    for (const auto& force : forces_) {
      if (!reason.empty()) break;
      if (force.has_static && force.static_force != 0.0) {
        reason = force.path + " is a static force";
      } else if (force.harmonic_force && force.harmonic % 2 == 0) {
        reason = fmt::format("{} forces the even harmonic {}", force.path, force.harmonic);
      }
    }
    for (std::size_t i = 0; i < c.system.contacts.size() && reason.empty(); ++i) {
      const auto& contact = c.system.contacts[i];
      if (contact.has_reference_offset()) {
        reason = fmt::format("contacts[{}] has a reference force or slip", i);
      } else if (contact.normal()) {
        reason = fmt::format("contacts[{}] is a normal element (its law is not odd: a static offset develops)", i);
      }
    }
    if (!reason.empty()) {
      reader_.fail(selection_node_, "analysis.frf.harmonic_selection",
                   "odd needs a symmetric case, but " + reason + " (use auto or all)");
    }
  }

  yaml::Reader reader_;
  MatrixSource mass_;
  MatrixSource stiffness_;
  MatrixSource damping_;
  std::vector<YAML::Node> contact_nodes_;
  std::vector<ForceInput> forces_;
  YAML::Node selection_node_;  ///< analysis.frf.harmonic_selection, when given
};

}  // namespace

DiscreteCase parse_discrete_case(const std::string& text, const std::string& file_name) {
  return DiscreteCaseReader(file_name).read(yaml::load(text, file_name));
}

DiscreteCase read_discrete_case(const std::filesystem::path& file) {
  return parse_discrete_case(yaml::read_text_file(file), file.string());
}

}  // namespace jointhb::io
