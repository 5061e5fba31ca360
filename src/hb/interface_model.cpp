// Consistency checks of hb::InterfaceModel (interface_model.hpp).
#include "jointhb/hb/interface_model.hpp"

#include <fmt/format.h>

#include <cmath>

namespace jointhb::hb {

std::string InterfaceModel::validate() const {
  const int ns = num_modes(), P = num_points();
  if (P == 0) return "areas: no contact point";
  if (ns == 0) return "omega2: no kept mode";
  if (gap_shapes.rows() != 3 * P || gap_shapes.cols() != ns)
    return fmt::format("gap_shapes: must be {} × {}, got {} × {}", 3 * P, ns, gap_shapes.rows(), gap_shapes.cols());
  for (const auto* r : {&residual_flexibility, &residual_inertia})
    if (r->rows() != 3 * P || r->cols() != 3 * P)
      return fmt::format("{}: must be {} × {}", r == &residual_flexibility ? "residual_flexibility" : "residual_inertia", 3 * P, 3 * P);
  if (rigid_modes < 0 || rigid_modes > ns) return fmt::format("rigid_modes: must be in [0, {}], got {}", ns, rigid_modes);
  for (int j = 0; j < ns; ++j) {
    if (!(omega2[j] >= 0.0) || !std::isfinite(omega2[j])) return fmt::format("omega2[{}]: must be finite and ≥ 0, got {}", j, omega2[j]);
    if (j < rigid_modes && omega2[j] != 0.0) return fmt::format("omega2[{}]: a rigid-body mode must be exactly 0", j);
  }
  if (!(rayleigh_mass >= 0.0) || !(rayleigh_stiffness >= 0.0)) return "rayleigh: a and b must be ≥ 0";
  if (static_cast<int>(references.size()) != P || static_cast<int>(stuck_tangents.size()) != P)
    return fmt::format("references/stuck_tangents: must have {} entries", P);
  int next = 0;
  for (const InterfaceGroup& g : groups) {
    if (g.first != next || g.count <= 0) return fmt::format("groups: '{}' must start at point {} and be non-empty", g.name, next);
    next += g.count;
  }
  if (next != P) return fmt::format("groups: cover {} of {} points", next, P);
  for (int p = 0; p < P; ++p)
    if (!(areas[p] > 0.0) || !std::isfinite(areas[p])) return fmt::format("areas[{}]: must be finite and > 0, got {}", p, areas[p]);
  if (load_modal.size() != ns || load_residual0.size() != 3 * P || load_residual1.size() != 3 * P)
    return "load: load_modal must have n_s entries, load_residual0/1 3P";
  for (const InterfaceOutput& o : outputs)
    if (o.modal.size() != ns || o.residual0.size() != 3 * P || o.residual1.size() != 3 * P)
      return fmt::format("outputs: '{}' has inconsistent sizes", o.name);
  if (!gap_shapes.allFinite() || !residual_flexibility.allFinite() || !residual_inertia.allFinite())
    return "gap_shapes/residual matrices: must be finite";
  return {};
}

}  // namespace jointhb::hb
