#include "jointhb/preload/preload_solver.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string_view>

#include "../support/contact_tangent.hpp"
#include "../support/stopwatch.hpp"
#include "jointhb/fe/rigid_body_modes.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::preload {

std::string PreloadOptions::validate() const {
  if (load_steps < 1) return fmt::format("load_steps: must be >= 1, got {}", load_steps);
  if (max_iterations < 1) return fmt::format("max_iterations: must be >= 1, got {}", max_iterations);
  if (!(residual_tolerance > 0.0 && residual_tolerance < 1.0))
    return fmt::format("residual_tolerance: must be in (0, 1), got {}", residual_tolerance);
  if (max_line_search < 0) return fmt::format("max_line_search: must be >= 0, got {}", max_line_search);
  if (!(reuse_factor_ratio >= 0.0 && reuse_factor_ratio < 1.0))
    return fmt::format("reuse_factor_ratio: must be in [0, 1), got {}", reuse_factor_ratio);
  if (!(closed_pressure_fraction >= 0.0 && closed_pressure_fraction < 1.0))
    return fmt::format("closed_pressure_fraction: must be in [0, 1), got {}",
                       closed_pressure_fraction);
  return {};
}

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using support::seconds_since;

// Parts joined by interfaces and bolts; every group needs a constraint unless the whole model is
// one free-free group (then the 3-2-1 support holds it).
void check_connectivity_of(const fe::Mesh& mesh, std::span<const ContactInterface> interfaces,
                           std::span<const Bolt> bolts, std::span<const fe::FixedNodes> constraints,
                           std::span<const fe::Tie> ties) {
  const int parts = static_cast<int>(mesh.parts.size());
  std::vector<int> root(static_cast<std::size_t>(parts));
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int p) {
    while (root[static_cast<std::size_t>(p)] != p) p = root[static_cast<std::size_t>(p)];
    return p;
  };
  const auto join = [&](int a, int b) { root[static_cast<std::size_t>(find(a))] = find(b); };
  const auto part_of = [&](const fe::Face& f) {
    return mesh.elements[static_cast<std::size_t>(f.element)].part;
  };
  for (const ContactInterface& ci : interfaces)
    for (const fe::InterfaceElement& e : ci.geometry.elements)
      for (const fe::Face& top : e.top_faces) join(part_of(e.bottom), part_of(top));
  for (const Bolt& b : bolts)
    for (int p : b.parts) join(p, b.parts.front());
  for (const fe::Tie& tie : ties)  // an element joins its two parts when one of its points is tied
    for (const fe::InterfaceElement& e : tie.geometry.elements)
      if (tie.point_area.segment(e.first_point, e.num_points).maxCoeff() > 0.0) join(part_of(e.bottom), part_of(e.top));
  std::vector<bool> constrained(static_cast<std::size_t>(parts), false);
  if (!constraints.empty()) {
    std::vector<bool> fixed_node(static_cast<std::size_t>(mesh.num_nodes()), false);
    for (const fe::FixedNodes& f : constraints)
      for (int n : f.nodes) fixed_node[static_cast<std::size_t>(n)] = true;
    for (const fe::Element& e : mesh.elements)
      for (int n : e.node_span())
        if (fixed_node[static_cast<std::size_t>(n)]) constrained[static_cast<std::size_t>(find(e.part))] = true;
  }
  std::vector<int> groups;
  for (int p = 0; p < parts; ++p)
    if (find(p) == p) groups.push_back(p);
  if (constraints.empty()) {
    if (groups.size() > 1) {
      // Name a part that is not in the group of part 0.
      for (int p = 0; p < parts; ++p)
        if (find(p) != find(0))
          throw std::invalid_argument(fmt::format(
              "part '{}' is neither connected to part '{}' (by an interface, a tie or a bolt) nor "
              "constrained: the model has no constraints and {} separate groups of parts",
              mesh.parts[static_cast<std::size_t>(p)], mesh.parts[0], groups.size()));
    }
    return;
  }
  for (int p = 0; p < parts; ++p)
    if (!constrained[static_cast<std::size_t>(find(p))])
      throw std::invalid_argument(fmt::format(
          "part '{}' is neither constrained nor connected (by an interface, a tie or a bolt) to a "
          "constrained part",
          mesh.parts[static_cast<std::size_t>(p)]));
}

struct Evaluation {
  Eigen::VectorXd residual;  // full DOFs
  std::vector<fe::InterfaceContactState> states;
};

Evaluation evaluate(const PreloadModel& model, const Eigen::VectorXd& u, const Eigen::VectorXd& load,
                    double& contact_seconds) {
  Evaluation ev;
  ev.residual = model.structure.stiffness * u - load;
  const auto t0 = std::chrono::steady_clock::now();
  for (const ContactInterface& ci : model.interfaces) {
    // The Newton matrix is built from the tangents (newton_matrix), not from K of the state.
    ev.states.push_back(fe::evaluate_static_contact(ci.geometry, ci.law, u, {}, /*with_stiffness=*/false));
    ev.residual += ev.states.back().force;
  }
  contact_seconds += seconds_since(t0);
  return ev;
}

// The Newton matrix: K_s + Σ_I G_Iᵀ A C̃_I G_I with the symmetric, positive semi-definite part of
// each point's consistent tangent, C̃ = [sym(C_TT)₊ 0; 0 max(C_NN, 0)]: the normal–tangential
// coupling (∂t_T/∂g_N through μ p_N and k_T(p_N)) makes C non-symmetric, and a slipping point's
// tangential tangent can be indefinite, which CHOLMOD's LLᵀ cannot take. The residual stays exact,
// so the fixed point is unchanged; convergence is linear where the coupling matters (small under a
// preload, whose tangential tractions are small), quadratic elsewhere.
SpMat newton_matrix(const PreloadModel& model, const std::vector<fe::InterfaceContactState>& states) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    std::vector<Eigen::Matrix3d> c(states[i].tangent.size(), Eigen::Matrix3d::Zero());
    for (std::size_t p = 0; p < c.size(); ++p) {
      c[p] = support::symmetric_psd_part(states[i].tangent[p]);
      // A closed point without pressure (the linear law at g_N = g_N0, as every point is before
      // the first load step) has no friction capacity and so no tangential tangent: the parts
      // would be free to slide in the Newton matrix. Its stick stiffness k_T stands in there; the
      // residual is exact, so the solution does not change.
      if (!states[i].open[p] && states[i].pressure[static_cast<Eigen::Index>(p)] == 0.0 &&
          c[p].topLeftCorner<2, 2>().isZero(0.0)) {
        const double gap = states[i].gap[3 * static_cast<Eigen::Index>(p) + 2];
        c[p](0, 0) = c[p](1, 1) = model.interfaces[i].law.tangential_state(gap).limits.stiffness;
      }
    }
    fe::add_interface_stiffness(model.interfaces[i].geometry, c, triplets);
  }
  SpMat k(model.structure.stiffness.rows(), model.structure.stiffness.cols());
  k.setFromTriplets(triplets.begin(), triplets.end());
  return model.structure.stiffness + k;
}

InterfaceResult summarise(const ContactInterface& ci, fe::InterfaceContactState state,
                          double closed_fraction) {
  InterfaceResult r;
  r.name = ci.geometry.name;
  const auto& points = ci.geometry.points;
  for (std::size_t p = 0; p < points.size(); ++p) r.clamping_force += points[p].area * state.pressure[static_cast<Eigen::Index>(p)];
  r.mean_pressure = r.clamping_force / ci.geometry.total_area;
  r.max_pressure = state.pressure.size() ? state.pressure.maxCoeff() : 0.0;
  const double closed_level = closed_fraction * r.mean_pressure;
  r.max_gap = -std::numeric_limits<double>::infinity();
  r.min_gap = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < points.size(); ++p) {
    const auto i = static_cast<Eigen::Index>(p);
    if (state.pressure[i] >= closed_level) r.closed_area += points[p].area;
    r.max_gap = std::max(r.max_gap, state.gap[3 * i + 2]);
    r.min_gap = std::min(r.min_gap, state.gap[3 * i + 2]);
  }
  r.closed_area_fraction = r.closed_area / ci.geometry.total_area;
  r.state = std::move(state);
  return r;
}

}  // namespace

void check_connectivity(const fe::Mesh& mesh, std::span<const ContactInterface> interfaces,
                        std::span<const Bolt> bolts, std::span<const fe::FixedNodes> constraints,
                        std::span<const fe::Tie> ties) {
  check_connectivity_of(mesh, interfaces, bolts, constraints, ties);
}


std::vector<int> statically_determinate_support(const fe::Mesh& mesh) {
  std::vector<bool> used(static_cast<std::size_t>(mesh.num_nodes()), false);
  for (const fe::Element& e : mesh.elements)
    for (int n : e.node_span()) used[static_cast<std::size_t>(n)] = true;
  const Eigen::Matrix3Xd& x = mesh.coordinates;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int count = 0;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (used[static_cast<std::size_t>(n)]) centre += x.col(n), ++count;
  if (count == 0) throw std::invalid_argument("3-2-1 support: the mesh has no elements");
  centre /= count;
  const auto farthest = [&](auto distance) {
    int best = -1;
    double best_d = -1.0;
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (!used[static_cast<std::size_t>(n)]) continue;
      const double d = distance(x.col(n));
      if (d > best_d + 1e-12 * std::abs(best_d)) best_d = d, best = n;
    }
    return best;
  };
  const int a = farthest([&](const auto& p) { return (p - centre).norm(); });
  const int b = farthest([&](const auto& p) { return (p - x.col(a)).norm(); });
  const Eigen::Vector3d e = (x.col(b) - x.col(a)).normalized();
  const int c = farthest([&](const auto& p) {
    const Eigen::Vector3d d = p - x.col(a);
    return (d - d.dot(e) * e).norm();
  });
  Eigen::Index k_ab = 0;
  e.cwiseAbs().maxCoeff(&k_ab);
  const Eigen::Vector3d v = e.cross(x.col(c) - x.col(a));  // motion of C under rotation about AB
  Eigen::Index k_c = 0;
  v.cwiseAbs().maxCoeff(&k_c);
  std::vector<int> dofs = {3 * a, 3 * a + 1, 3 * a + 2};
  for (int d = 0; d < 3; ++d)
    if (d != k_ab) dofs.push_back(3 * b + d);
  dofs.push_back(3 * c + static_cast<int>(k_c));
  // Determinacy: the 6 constrained components of the 6 rigid-body motions must be independent.
  Eigen::Matrix<double, 6, 6> rigid;
  const double scale = (x.col(b) - x.col(a)).norm();
  for (int r = 0; r < 6; ++r) {
    const int node = dofs[static_cast<std::size_t>(r)] / 3, dir = dofs[static_cast<std::size_t>(r)] % 3;
    const Eigen::Vector3d arm = (x.col(node) - centre) / scale;
    for (int m = 0; m < 3; ++m) {
      rigid(r, m) = (dir == m) ? 1.0 : 0.0;
      rigid(r, 3 + m) = Eigen::Vector3d::Unit(m).cross(arm)[dir];
    }
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>> svd(rigid);
  if (!(svd.singularValues()(5) > 1e-6 * svd.singularValues()(0))) {
    throw std::invalid_argument(
        "3-2-1 support: the mesh's nodes are (nearly) collinear; give constraints in the case");
  }
  return dofs;
}

std::vector<Eigen::Matrix3d> stuck_tangents(const ContactInterface& interface,
                                             const Eigen::VectorXd& gaps) {
  std::vector<Eigen::Matrix3d> tangents(interface.geometry.points.size(), Eigen::Matrix3d::Zero());
  for (std::size_t p = 0; p < tangents.size(); ++p) {
    const contact::TangentialState s = interface.law.tangential_state(gaps[3 * static_cast<Eigen::Index>(p) + 2]);
    tangents[p].diagonal() << s.limits.stiffness, s.limits.stiffness, s.normal_stiffness;
  }
  return tangents;
}

Eigen::SparseMatrix<double> dynamic_stiffness(const PreloadModel& model,
                                              const Eigen::VectorXd& displacement) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (const ContactInterface& ci : model.interfaces)
    fe::add_interface_stiffness(ci.geometry, stuck_tangents(ci, fe::gaps(ci.geometry, displacement)), triplets);
  add_bolt_stiffness(model.bolts, triplets);
  SpMat extra(model.structure.stiffness.rows(), model.structure.stiffness.cols());
  extra.setFromTriplets(triplets.begin(), triplets.end());
  return model.structure.stiffness + extra;
}

PreloadResult solve_preload(const PreloadModel& model, const PreloadOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (const std::string msg = options.validate(); !msg.empty())
    throw std::invalid_argument("preload: " + msg);
  if (model.mesh == nullptr) throw std::invalid_argument("preload: the model has no mesh");
  const fe::Mesh& mesh = *model.mesh;
  const int n = mesh.num_dofs();
  if (model.structure.stiffness.rows() != n)
    throw std::invalid_argument("preload: the structural matrices do not match the mesh");
  check_connectivity(*model.mesh, model.interfaces, model.bolts, model.constraints, model.ties);

  PreloadResult result;
  std::vector<fe::FixedNodes> fixed = model.constraints;
  if (fixed.empty()) {
    result.support_dofs = statically_determinate_support(mesh);
    for (int dof : result.support_dofs) {
      fe::FixedNodes f;
      f.nodes = {dof / 3};
      f.directions = {false, false, false};
      f.directions[static_cast<std::size_t>(dof % 3)] = true;
      fixed.push_back(f);
    }
  }
  result.dofs = fe::DofMap::from_fixed_nodes(mesh.num_nodes(), fixed);
  const fe::DofMap& dofs = result.dofs;

  // f_bolt + f_static of eq. (P-1) at s = 1.
  const Eigen::VectorXd static_full = fe::static_load_vector(mesh, model.loads);
  // A free-free model (3-2-1 support) carries only self-equilibrated static loads: the support
  // would otherwise take their resultant.
  if (const std::string problem = fe::equilibrium_problem(mesh, static_full);
      model.constraints.empty() && !problem.empty())
    throw std::invalid_argument("preload: the static loads have " + problem +
                                ", and the model has no constraints (a free-free body carries only "
                                "self-equilibrated loads): add constraints");
  const Eigen::VectorXd bolt_full = bolt_load(model.bolts, n, 1.0) + static_full;
  const double load_norm = dofs.restrict(bolt_full).norm();
  double max_preload = static_full.size() > 0 ? static_full.cwiseAbs().maxCoeff() : 0.0;
  for (const Bolt& b : model.bolts) max_preload = std::max(max_preload, b.preload);
  const double reference = load_norm > 0.0 ? load_norm : 1.0;

  fe::SparseCholesky cholesky(fe::SparseCholesky::Options{
      .backend = options.linear_solver,
      .iterative = fe::with_rigid_body_modes(options.iterative, options.linear_solver, mesh, dofs)});
  Eigen::Index analysed_nonzeros = -1;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  Evaluation last;
  // The factor may serve the next iteration as a chord step (reuse_factor_ratio).
  bool try_chord = false;
  result.termination = Termination::converged;
  for (int k = 1; k <= options.load_steps; ++k) {
    PreloadStep step;
    step.load_factor = static_cast<double>(k) / options.load_steps;
    const Eigen::VectorXd load = step.load_factor * bolt_full;
    Evaluation ev = evaluate(model, u, load, result.contact_seconds);
    double norm = dofs.restrict(ev.residual).norm();
    Eigen::VectorXd u_step = u;
    for (int it = 0;; ++it) {
      step.residual = norm / reference;
      if (!std::isfinite(step.residual)) {
        // A numerical failure of the stage, named as such (issue 20, item 5: p_N0 = 1e300 Pa).
        step.termination = Termination::failed;
        step.message = fmt::format(
            "the residual is not finite at iteration {} (the contact forces or the stiffness "
            "overflow the range of doubles: check the interface pressure p_N0 and decay λ, the "
            "bolt preloads and the materials)", it);
        break;
      }
      if (options.progress) options.progress(k, it, step.residual);
      if (step.residual <= options.residual_tolerance) {
        step.termination = Termination::converged;
        break;
      }
      if (it == options.max_iterations) {
        step.termination = Termination::no_convergence;
        step.message = fmt::format("no convergence in {} iterations (relative residual {:.3e} > {:.1e})",
                                   options.max_iterations, step.residual, options.residual_tolerance);
        break;
      }
      if (try_chord && cholesky.factorized()) {
        // Chord step with the factor of an earlier state: kept if it decreases ‖r‖ (full step,
        // no line search); otherwise refactor at this state below.
        const auto t0 = std::chrono::steady_clock::now();
        const Eigen::VectorXd du = dofs.expand(cholesky.solve(Eigen::VectorXd(-dofs.restrict(ev.residual))));
        result.factor_seconds += seconds_since(t0);
        Evaluation trial = evaluate(model, u_step + du, load, result.contact_seconds);
        const double trial_norm = dofs.restrict(trial.residual).norm();
        if (std::isfinite(trial_norm) && trial_norm < (1.0 - 1e-4) * norm) {
          try_chord = trial_norm <= options.reuse_factor_ratio * norm;
          u_step += du;
          ev = std::move(trial);
          norm = trial_norm;
          ++step.iterations;
          ++step.chord_iterations;
          ++result.total_iterations;
          continue;
        }
      }
      try_chord = false;
      auto t0 = std::chrono::steady_clock::now();
      const SpMat tangent = newton_matrix(model, ev.states);
      const SpMat free = dofs.restrict(tangent);
      result.assembly_seconds += seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      try {
        if (free.nonZeros() != analysed_nonzeros) {
          cholesky.analyze(free);
          analysed_nonzeros = free.nonZeros();
        }
        cholesky.factorize(free);
        ++step.factorizations;
      } catch (const std::exception& error) {
        step.termination = Termination::failed;
        step.message = fmt::format("the tangent stiffness could not be factored ({}); an interface may "
                              "have opened completely or the parts are not held",
                              error.what());
        break;
      }
      const Eigen::VectorXd du = dofs.expand(cholesky.solve(Eigen::VectorXd(-dofs.restrict(ev.residual))));
      result.factor_seconds += seconds_since(t0);
      ++step.iterations;
      ++result.total_iterations;
      // Backtracking line search on ‖r‖ (Armijo-like sufficient decrease).
      double alpha = 1.0;
      bool accepted = false;
      for (int ls = 0; ls <= options.max_line_search; ++ls) {
        Evaluation trial = evaluate(model, u_step + alpha * du, load, result.contact_seconds);
        const double trial_norm = dofs.restrict(trial.residual).norm();
        if (std::isfinite(trial_norm) && trial_norm < (1.0 - 1e-4 * alpha) * norm) {
          try_chord = alpha == 1.0 && trial_norm <= options.reuse_factor_ratio * norm;
          u_step += alpha * du;
          ev = std::move(trial);
          norm = trial_norm;
          accepted = true;
          break;
        }
        alpha *= 0.5;
        ++step.line_search_cuts;
      }
      if (!accepted) {
        step.termination = Termination::failed;
        step.message = fmt::format("the line search found no decrease after {} halvings (relative "
                                   "residual {:.3e})",
                                   options.max_line_search, step.residual);
        break;
      }
    }
    result.steps.push_back(step);
    if (step.termination != Termination::converged) {
      result.termination = step.termination;
      result.message = fmt::format("preload step {}/{} (load factor {:.3g}): {}; the last converged "
                                   "state (load factor {:.3g}) is kept",
                                   k, options.load_steps, step.load_factor, step.message,
                                   result.load_factor);
      break;
    }
    u = u_step;
    last = std::move(ev);
    result.load_factor = step.load_factor;
  }
  if (cholesky.analyzed()) {
    result.factor = cholesky.statistics();
    result.factor_statistics = result.factor.brief();
  }
  result.displacement = u;
  if (last.states.empty()) last = evaluate(model, u, result.load_factor * bolt_full, result.contact_seconds);
  for (std::size_t i = 0; i < model.interfaces.size(); ++i)
    result.interfaces.push_back(summarise(model.interfaces[i], std::move(last.states[i]),
                                          options.closed_pressure_fraction));
  for (const Bolt& b : model.bolts) result.bolt_forces.push_back(result.load_factor * b.preload);
  if (!result.support_dofs.empty()) {
    double reaction = 0.0;
    for (int dof : result.support_dofs) reaction = std::max(reaction, std::abs(last.residual[dof]));
    result.support_reaction = max_preload > 0.0 ? reaction / max_preload : reaction;
  }
  result.dynamic_stiffness = dynamic_stiffness(model, u);
  if (result.termination == Termination::converged) {
    result.message = fmt::format("{} load steps, {} Newton iterations ({} factorisations)",
                                 options.load_steps, result.total_iterations,
                                 result.factor.factorizations);
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace jointhb::preload
