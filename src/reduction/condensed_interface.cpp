#include "jointhb/reduction/condensed_interface.hpp"

#include <fmt/format.h>

#include <set>
#include <stdexcept>

#include "../support/stopwatch.hpp"
#include "jointhb/fe/rigid_body_modes.hpp"

namespace jointhb::reduction {

namespace {

using SpMat = Eigen::SparseMatrix<double>;

// The free DOFs of every node of every zero-thickness element (the Craig–Bampton boundary).
std::vector<int> interface_dofs(const preload::PreloadModel& model, const fe::DofMap& dofs) {
  std::set<int> nodes;
  for (const preload::ContactInterface& ci : model.interfaces)
    for (const fe::InterfaceElement& e : ci.geometry.elements) {
      nodes.insert(e.bottom_nodes.begin(), e.bottom_nodes.end());
      nodes.insert(e.top_nodes.begin(), e.top_nodes.end());
    }
  std::vector<int> boundary;
  for (int n : nodes)
    for (int d = 0; d < 3; ++d)
      if (const int f = dofs.free_of_full[static_cast<std::size_t>(3 * n + d)]; f >= 0) boundary.push_back(f);
  return boundary;
}

// G_r = G P_bᵀ: the gap operator's columns (full mesh DOFs, all on interface nodes) renumbered to
// the reduced boundary coordinates; columns of constrained DOFs drop out (u = 0 there).
SpMat reduced_gap_operator(const SpMat& G, const fe::DofMap& dofs, const CraigBamptonModel& cb) {
  std::vector<int> boundary_position(static_cast<std::size_t>(dofs.num_free()), -1);
  for (int k = 0; k < cb.num_boundary(); ++k) boundary_position[static_cast<std::size_t>(cb.boundary[static_cast<std::size_t>(k)])] = k;
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < G.outerSize(); ++j)
    for (SpMat::InnerIterator it(G, j); it; ++it) {
      const int free = dofs.free_of_full[static_cast<std::size_t>(it.col())];
      if (free < 0) continue;
      const int column = boundary_position[static_cast<std::size_t>(free)];
      if (column < 0) throw std::logic_error("condense: a gap depends on a DOF outside the interface nodes");
      entries.emplace_back(static_cast<int>(it.row()), column, it.value());
    }
  SpMat Gr(G.rows(), cb.size());
  Gr.setFromTriplets(entries.begin(), entries.end());
  return Gr;
}

}  // namespace

CondensedModel condense(const preload::PreloadModel& model, const preload::PreloadResult& preload,
                        const CraigBamptonOptions& options) {
  const auto start = support::Clock::now();
  if (model.mesh == nullptr) throw std::invalid_argument("condense: the model has no mesh");
  if (model.interfaces.empty()) throw std::invalid_argument("condense: the model has no contact interface to condense to");
  if (preload.interfaces.size() != model.interfaces.size())
    throw std::invalid_argument(fmt::format("condense: the preload has {} interfaces, the model {}",
                                            preload.interfaces.size(), model.interfaces.size()));
  CondensedModel r;
  r.dofs = fe::DofMap::from_fixed_nodes(model.mesh->num_nodes(), model.constraints);
  // K_structure + Σ k_b b bᵀ: the linear stiffness the contact laws act beside.
  const SpMat K = r.dofs.restrict(SpMat(model.structure.stiffness +
                                        preload::bolt_stiffness(model.bolts, model.mesh->num_dofs())));
  const SpMat M = r.dofs.restrict(model.structure.mass);
  CraigBamptonOptions cb_options = options;
  cb_options.modal.iterative = fe::with_rigid_body_modes(options.modal.iterative, options.modal.linear_solver,
                                                         *model.mesh, r.dofs);
  r.cb = craig_bampton(K, M, interface_dofs(model, r.dofs), cb_options);

  r.stuck_stiffness = r.cb.stiffness;
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    const preload::ContactInterface& ci = model.interfaces[i];
    const fe::InterfaceContactState& state = preload.interfaces[i].state;
    const auto P = static_cast<Eigen::Index>(ci.geometry.points.size());
    if (state.gap.size() != 3 * P || state.traction.size() != 3 * P)
      throw std::invalid_argument(fmt::format("condense: interface '{}': the preload state has {} gaps for {} points",
                                              ci.geometry.name, state.gap.size() / 3, P));
    CondensedInterface c;
    c.name = ci.geometry.name;
    c.gap_operator = reduced_gap_operator(ci.geometry.gap_operator, r.dofs, r.cb);
    c.areas.resize(P);
    c.reference_gap = state.gap;
    c.reference_traction = state.traction;
    // The stuck tangent of eq. (P-2) at the preloaded gap, weighted by the point areas: A C_pre.
    c.stuck_tangents = preload::stuck_tangents(ci, state.gap);
    std::vector<Eigen::Triplet<double>> weighted;
    for (Eigen::Index p = 0; p < P; ++p) {
      c.areas[p] = ci.geometry.points[static_cast<std::size_t>(p)].area;
      for (int a = 0; a < 3; ++a)
        weighted.emplace_back(static_cast<int>(3 * p + a), static_cast<int>(3 * p + a),
                              c.areas[p] * c.stuck_tangents[static_cast<std::size_t>(p)](a, a));
    }
    SpMat AC(3 * P, 3 * P);
    AC.setFromTriplets(weighted.begin(), weighted.end());
    const SpMat contact = c.gap_operator.transpose() * AC * c.gap_operator;
    r.stuck_stiffness += Eigen::MatrixXd(contact);
    r.interfaces.push_back(std::move(c));
  }
  r.stuck_stiffness = 0.5 * (r.stuck_stiffness + r.stuck_stiffness.transpose()).eval();
  r.seconds = support::seconds_since(start);
  return r;
}

Eigen::VectorXd CondensedModel::expand(const Eigen::Ref<const Eigen::VectorXd>& q) const {
  return dofs.expand(cb.expand(q));
}

}  // namespace jointhb::reduction
