// Interface reduction by contact patches (contact_patches.hpp, eq. T-31).
#include "jointhb/reduction/contact_patches.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCore>
#include <chrono>
#include <cmath>
#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace jointhb::reduction {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using SpMat = Eigen::SparseMatrix<double>;

// W R Wᵀ for a dense R (3P × 3P) and a sparse W (3P_c × 3P, a few entries per column): T = R Wᵀ
// column by column as weighted sums of columns of R, then W T column by column — both read R and
// T along their columns (Eigen's dense × sparse products read R by rows; with them the whole merge
// of case 09's 6 400 points took 52 s, with this 33 s, the rest not profiled).
MatrixXd galerkin(const MatrixXd& R, const SpMat& W) {
  const SpMat Wt = W.transpose();
  MatrixXd T = MatrixXd::Zero(R.rows(), Wt.cols());
#pragma omp parallel for schedule(static)
  for (Index c = 0; c < Wt.outerSize(); ++c)
    for (SpMat::InnerIterator it(Wt, c); it; ++it) T.col(c) += it.value() * R.col(it.row());
  MatrixXd out(W.rows(), T.cols());
#pragma omp parallel for schedule(static)
  for (Index c = 0; c < T.cols(); ++c) out.col(c) = W * T.col(c);
  return out;
}

}  // namespace

std::string ContactPatchOptions::validate() const {
  if (!(std::isfinite(size) && size >= 0.0)) return fmt::format("size: must be finite and >= 0 [m], got {}", size);
  return {};
}

ContactPatchResult merge_contact_patches(const hb::InterfaceModel& model, const preload::PreloadModel& fe,
                                         const ContactPatchOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (const std::string msg = options.validate(); !msg.empty()) throw std::invalid_argument("contact patches: " + msg);
  if (const std::string msg = model.validate(); !msg.empty()) throw std::invalid_argument("contact patches: model: " + msg);
  if (model.groups.size() != fe.interfaces.size())
    throw std::invalid_argument(fmt::format("contact patches: the model has {} interfaces, the FE model {}",
                                            model.groups.size(), fe.interfaces.size()));
  const int P = model.num_points();
  ContactPatchResult r;
  r.fine_points = P;
  r.patch_of_point.assign(static_cast<std::size_t>(P), -1);

  // ---- patches: square cells in each interface's (t1, t2) coordinates ------------------------
  std::vector<std::vector<int>> members;  // patch → fine points
  std::vector<int> patch_group;           // patch → group
  for (std::size_t gi = 0; gi < model.groups.size(); ++gi) {
    const hb::InterfaceGroup& g = model.groups[gi];
    const fe::Interface& geometry = fe.interfaces[gi].geometry;
    if (geometry.num_points() != g.count)
      throw std::invalid_argument(fmt::format("contact patches: interface '{}' has {} points in the model, {} in the FE model",
                                              g.name, g.count, geometry.num_points()));
    double s_min[2] = {INFINITY, INFINITY}, s_max[2] = {-INFINITY, -INFINITY};
    for (const fe::InterfacePoint& pt : geometry.points)
      for (int d = 0; d < 2; ++d) {
        s_min[d] = std::min(s_min[d], pt.frame.row(d).dot(pt.position));
        s_max[d] = std::max(s_max[d], pt.frame.row(d).dot(pt.position));
      }
    // Cells [s_min + k h, s_min + (k+1) h); the far edge s_max belongs to the last cell, so a
    // 40 mm side in 10 mm patches has 4 cells, not 5. Size 0: coincident points only (cells of
    // 1e-9 of the interface's extent).
    const bool coincident = options.size == 0.0;
    const double h = coincident ? 1e-9 * std::max({s_max[0] - s_min[0], s_max[1] - s_min[1], 1e-300}) : options.size;
    long last[2];
    for (int d = 0; d < 2; ++d)
      last[d] = std::max(0L, static_cast<long>(std::ceil((s_max[d] - s_min[d]) / h - 1e-9)) - 1);
    std::map<std::pair<long, long>, std::vector<int>> cell_patches;
    for (int q = 0; q < g.count; ++q) {
      const fe::InterfacePoint& pt = geometry.points[static_cast<std::size_t>(q)];
      const auto cell = [&](int d) {
        const double x = (pt.frame.row(d).dot(pt.position) - s_min[d]) / h;
        return std::min(last[d], static_cast<long>(std::floor(x + 1e-9)));
      };
      std::vector<int>& candidates = cell_patches[std::make_pair(cell(0), cell(1))];
      int patch = -1;
      for (int c : candidates) {
        const int first = members[static_cast<std::size_t>(c)].front() - g.first;
        if ((pt.frame - geometry.points[static_cast<std::size_t>(first)].frame).cwiseAbs().maxCoeff() <= 1e-9) {
          patch = c;
          break;
        }
        if (!coincident)  // coincident points with different frames stay apart (their gaps differ)
          throw std::invalid_argument(fmt::format(
              "contact patches: interface '{}': points {} and {} of one patch have different local frames (a curved "
              "interface): use a smaller size", g.name, first, q));
      }
      if (patch < 0) {
        patch = static_cast<int>(members.size());
        candidates.push_back(patch);
        members.emplace_back();
        patch_group.push_back(static_cast<int>(gi));
      }
      members[static_cast<std::size_t>(patch)].push_back(g.first + q);
      r.patch_of_point[static_cast<std::size_t>(g.first + q)] = patch;
    }
  }
  const int Pc = static_cast<int>(members.size());
  r.patches = Pc;

  // ---- W and the reduced model ----------------------------------------------------------------
  hb::InterfaceModel& m = r.model;
  m.omega2 = model.omega2;
  m.rigid_modes = model.rigid_modes;
  m.rayleigh_mass = model.rayleigh_mass;
  m.rayleigh_stiffness = model.rayleigh_stiffness;
  m.residual_shift = model.residual_shift;
  m.load_name = model.load_name;
  m.load_modal = model.load_modal;
  m.areas.resize(Pc);
  // Load weights ω_p = A_p p_p (area weights where a whole patch carries no pressure).
  std::vector<Eigen::Triplet<double>> w;
  std::vector<double> weight(static_cast<std::size_t>(P));
  for (int c = 0; c < Pc; ++c) {
    double area = 0.0, load = 0.0;
    for (int p : members[static_cast<std::size_t>(c)]) {
      area += model.areas[p];
      load += model.areas[p] * std::max(-model.references[static_cast<std::size_t>(p)].traction.z(), 0.0);
    }
    m.areas[c] = area;
    for (int p : members[static_cast<std::size_t>(c)]) {
      const double pressure = std::max(-model.references[static_cast<std::size_t>(p)].traction.z(), 0.0);
      weight[static_cast<std::size_t>(p)] = load > 0.0 ? model.areas[p] * pressure / load : model.areas[p] / area;
      for (int d = 0; d < 3; ++d) w.emplace_back(3 * c + d, 3 * p + d, weight[static_cast<std::size_t>(p)]);
    }
  }
  r.point_weights = weight;
  SpMat W(3 * Pc, 3 * P);
  W.setFromTriplets(w.begin(), w.end());
  m.gap_shapes = W * model.gap_shapes;
  m.residual_flexibility = galerkin(model.residual_flexibility, W);
  m.residual_inertia = galerkin(model.residual_inertia, W);
  m.residual_flexibility = 0.5 * (m.residual_flexibility + m.residual_flexibility.transpose()).eval();
  m.residual_inertia = 0.5 * (m.residual_inertia + m.residual_inertia.transpose()).eval();
  m.load_residual0 = W * model.load_residual0;
  m.load_residual1 = W * model.load_residual1;
  for (const hb::InterfaceOutput& o : model.outputs) {
    hb::InterfaceOutput oc = o;
    oc.residual0 = W * o.residual0;
    oc.residual1 = W * o.residual1;
    m.outputs.push_back(oc);
  }
  // Groups: patches are numbered interface by interface, so each group's patches are contiguous.
  int first = 0;
  for (std::size_t gi = 0; gi < model.groups.size(); ++gi) {
    int count = 0;
    for (int c = 0; c < Pc; ++c) count += patch_group[static_cast<std::size_t>(c)] == static_cast<int>(gi) ? 1 : 0;
    m.groups.push_back({model.groups[gi].name, model.groups[gi].law, first, count});
    first += count;
  }
  // Reference states and stuck tangents: mean traction, the gap of the mean pressure.
  m.references.resize(static_cast<std::size_t>(Pc));
  m.stuck_tangents.resize(static_cast<std::size_t>(Pc));
  for (int c = 0; c < Pc; ++c) {
    const contact::ContactPoint& law = model.groups[static_cast<std::size_t>(patch_group[static_cast<std::size_t>(c)])].law;
    hb::ContactPointReference ref;
    for (int p : members[static_cast<std::size_t>(c)]) {
      ref.traction += model.areas[p] / m.areas[c] * model.references[static_cast<std::size_t>(p)].traction;
      ref.gap += weight[static_cast<std::size_t>(p)] * model.references[static_cast<std::size_t>(p)].gap;
    }
    const double pressure = -ref.traction.z();
    if (pressure > 0.0) ref.gap.z() = law.options().normal.gap_at_pressure(pressure);
    const contact::TangentialState s = law.tangential_state(ref.gap.z());
    ref.traction.z() = -s.pressure;  // the law's own value at that gap (round-off of the inverse)
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    C.diagonal() << s.limits.stiffness, s.limits.stiffness, s.normal_stiffness;
    m.references[static_cast<std::size_t>(c)] = ref;
    m.stuck_tangents[static_cast<std::size_t>(c)] = C;
  }
  if (const std::string msg = m.validate(); !msg.empty())
    throw std::logic_error("contact patches: the reduced model is inconsistent: " + msg);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace jointhb::reduction
