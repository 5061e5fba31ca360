#include "jointhb/hb/interface_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace jointhb::hb {

namespace {

// "field: rows x cols, expected R x C" or "".
std::string check_size(const char* field, const Eigen::MatrixXd& m, Eigen::Index rows, Eigen::Index cols) {
  if (m.rows() == rows && m.cols() == cols) return {};
  return fmt::format("{}: {} x {}, expected {} x {}", field, m.rows(), m.cols(), rows, cols);
}

std::string check_size(const std::string& field, const Eigen::VectorXd& v, Eigen::Index size) {
  if (v.size() == size) return {};
  return fmt::format("{}: {} entries, expected {}", field, v.size(), size);
}

template <typename Derived>
bool all_finite(const Eigen::DenseBase<Derived>& m) {
  return m.derived().array().isFinite().all();
}

// Symmetric to a relative tolerance of the largest entry (the builder symmetrises exactly).
std::string check_symmetric(const char* field, const Eigen::MatrixXd& m) {
  const double scale = m.size() > 0 ? m.cwiseAbs().maxCoeff() : 0.0;
  const double asymmetry = m.size() > 0 ? (m - m.transpose()).cwiseAbs().maxCoeff() : 0.0;
  if (asymmetry <= 1e-10 * scale) return {};
  return fmt::format("{}: not symmetric (max |R - R^T| = {:.3g}, max |R| = {:.3g})", field, asymmetry, scale);
}

}  // namespace

std::string InterfaceModel::validate() const {
  const Eigen::Index ns = omega2.size(), P = areas.size(), rows = 3 * P;

  // --- modes ---------------------------------------------------------------------------------------
  if (!all_finite(omega2)) return "omega2: not finite";
  if (rigid_modes < 0 || rigid_modes > ns)
    return fmt::format("rigid_modes: {} outside [0, {}] (the number of kept modes)", rigid_modes, ns);
  for (Eigen::Index j = 0; j < ns; ++j) {
    if (omega2[j] < 0.0) return fmt::format("omega2: mode {} has omega^2 = {:.6g} < 0", j, omega2[j]);
    if (j < rigid_modes && omega2[j] != 0.0)
      return fmt::format("omega2: rigid-body mode {} has omega^2 = {:.6g}, expected exactly 0", j, omega2[j]);
  }
  // Ascending, up to the round-off of nearly repeated eigenvalues.
  const double largest = ns > 0 ? omega2.maxCoeff() : 0.0;
  for (Eigen::Index j = 1; j < ns; ++j)
    if (omega2[j] < omega2[j - 1] - 1e-8 * largest)
      return fmt::format("omega2: not ascending (mode {}: {:.9g} after {:.9g})", j, omega2[j], omega2[j - 1]);
  if (!(rayleigh_mass >= 0.0) || !std::isfinite(rayleigh_mass))
    return fmt::format("rayleigh_mass: must be finite and >= 0, got {}", rayleigh_mass);
  if (!(rayleigh_stiffness >= 0.0) || !std::isfinite(rayleigh_stiffness))
    return fmt::format("rayleigh_stiffness: must be finite and >= 0, got {}", rayleigh_stiffness);
  if (!std::isfinite(residual_shift)) return fmt::format("residual_shift: not finite ({})", residual_shift);

  // --- contact points ------------------------------------------------------------------------------
  if (!all_finite(areas)) return "areas: not finite";
  for (Eigen::Index p = 0; p < P; ++p)
    if (!(areas[p] > 0.0)) return fmt::format("areas: point {} has area {:.6g}, must be > 0", p, areas[p]);
  int next = 0;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    const InterfaceGroup& g = groups[k];
    if (g.count < 1) return fmt::format("groups: group {} ('{}') has {} points, must be >= 1", k, g.name, g.count);
    if (g.first != next)
      return fmt::format("groups: group {} ('{}') starts at point {}, expected {} (groups must cover the points in order)",
                         k, g.name, g.first, next);
    next += g.count;
  }
  if (next != P) return fmt::format("groups: cover {} points, the model has {}", next, P);
  if (static_cast<Eigen::Index>(references.size()) != P)
    return fmt::format("references: {} entries, expected {} (one per point)", references.size(), P);
  for (std::size_t p = 0; p < references.size(); ++p)
    if (!all_finite(references[p].gap) || !all_finite(references[p].traction))
      return fmt::format("references: point {} not finite", p);
  if (static_cast<Eigen::Index>(stuck_tangents.size()) != P)
    return fmt::format("stuck_tangents: {} entries, expected {} (one per point)", stuck_tangents.size(), P);
  for (std::size_t p = 0; p < stuck_tangents.size(); ++p)
    if (!all_finite(stuck_tangents[p])) return fmt::format("stuck_tangents: point {} not finite", p);

  // --- modal and residual matrices -----------------------------------------------------------------
  if (std::string e = check_size("gap_shapes", gap_shapes, rows, ns); !e.empty()) return e;
  if (!all_finite(gap_shapes)) return "gap_shapes: not finite";
  if (std::string e = check_size("residual_flexibility", residual_flexibility, rows, rows); !e.empty()) return e;
  if (!all_finite(residual_flexibility)) return "residual_flexibility: not finite";
  if (std::string e = check_symmetric("residual_flexibility", residual_flexibility); !e.empty()) return e;
  if (std::string e = check_size("residual_inertia", residual_inertia, rows, rows); !e.empty()) return e;
  if (!all_finite(residual_inertia)) return "residual_inertia: not finite";
  if (std::string e = check_symmetric("residual_inertia", residual_inertia); !e.empty()) return e;

  // --- load and outputs ----------------------------------------------------------------------------
  if (std::string e = check_size("load_modal", load_modal, ns); !e.empty()) return e;
  if (!all_finite(load_modal)) return "load_modal: not finite";
  if (std::string e = check_size("load_residual0", load_residual0, rows); !e.empty()) return e;
  if (!all_finite(load_residual0)) return "load_residual0: not finite";
  if (std::string e = check_size("load_residual1", load_residual1, rows); !e.empty()) return e;
  if (!all_finite(load_residual1)) return "load_residual1: not finite";
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const InterfaceOutput& o = outputs[k];
    const std::string field = fmt::format("outputs[{}] ('{}')", k, o.name);
    if (std::string e = check_size(field + ".modal", o.modal, ns); !e.empty()) return e;
    if (std::string e = check_size(field + ".residual0", o.residual0, rows); !e.empty()) return e;
    if (std::string e = check_size(field + ".residual1", o.residual1, rows); !e.empty()) return e;
    if (!all_finite(o.modal) || !all_finite(o.residual0) || !all_finite(o.residual1) ||
        !std::isfinite(o.load_residual0) || !std::isfinite(o.load_residual1))
      return field + ": not finite";
  }
  return {};
}

}  // namespace jointhb::hb
