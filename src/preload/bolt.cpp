#include "jointhb/preload/bolt.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace jointhb::preload {

std::string BoltOptions::validate() const {
  auto bad = [](const char* field, const char* constraint, double value) {
    return fmt::format("{}: {}, got {}", field, constraint, value);
  };
  if (!axis_point.allFinite()) return "axis_point: must be finite";
  if (!axis_direction.allFinite() || !(axis_direction.norm() > 0.0))
    return "axis_direction: must be a finite, non-zero vector";
  if (head_surface.empty()) return "head_surface: must name a surface";
  if (nut_surface.empty()) return "nut_surface: must name a surface";
  if (!(head_radius > 0.0) || !std::isfinite(head_radius)) return bad("head_radius", "must be > 0", head_radius);
  if (!(nut_radius > 0.0) || !std::isfinite(nut_radius)) return bad("nut_radius", "must be > 0", nut_radius);
  // An annulus r_i ≤ r ≤ r_o (eq. B-4) needs 0 ≤ r_i < r_o.
  const auto annulus = [](const char* field, const char* outer, double inner, double radius) -> std::string {
    if (inner >= 0.0 && inner < radius) return {};
    return fmt::format("{}: must be >= 0 and < {} = {}, got {}", field, outer, radius, inner);
  };
  if (auto msg = annulus("head_inner_radius", "head_radius", head_inner_radius, head_radius); !msg.empty()) return msg;
  if (auto msg = annulus("nut_inner_radius", "nut_radius", nut_inner_radius, nut_radius); !msg.empty()) return msg;
  if (!(axial_stiffness > 0.0) || !std::isfinite(axial_stiffness))
    return bad("axial_stiffness", "must be > 0", axial_stiffness);
  if (!(preload >= 0.0) || !std::isfinite(preload)) return bad("preload", "must be >= 0", preload);
  return {};
}

namespace {

struct Footprint {
  std::map<int, double> weights;  // node → ∫ N_i dA (consistent load of a unit pressure)
  double area = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<int> parts;
};

// Faces of `surface` whose centroid lies at a distance in [inner_radius, radius] from the axis
// (eq. B-4): a disc, or a washer's annulus around a hole. Nodal weights are the
// consistent loads of a unit pressure on a parallelogram: A/4 per corner (quad4), −A/12 per
// corner and A/3 per mid-edge node (quad8; Zienkiewicz & Taylor, The FEM vol. 1, §8.6); on a
// flat triangle (tetrahedron and wedge faces): A/3 per corner (tri3), 0 per corner and A/3 per
// mid-edge node (tri6; ∫ L_a (2L_a − 1) dA = 0, ∫ 4 L_a L_b dA = A/3).
Footprint select_footprint(const fe::Mesh& mesh, const std::string& bolt, const char* role,
                           const std::string& surface, const Eigen::Vector3d& point,
                           const Eigen::Vector3d& axis, double inner_radius, double radius) {
  const auto it = mesh.surfaces.find(surface);
  if (it == mesh.surfaces.end()) {
    throw std::invalid_argument(
        fmt::format("bolt '{}': {}_surface: unknown surface '{}'", bolt, role, surface));
  }
  Footprint fp;
  for (const fe::Face& face : it->second) {
    const std::vector<int> nodes = fe::face_nodes(mesh, face);
    const Eigen::Vector3d c = fe::face_centre(mesh, face);
    const Eigen::Vector3d off = c - point;
    const double distance = (off - off.dot(axis) * axis).norm();
    if (distance > radius || distance < inner_radius) continue;
    const bool triangle =
        fe::face_corner_count(mesh.elements[static_cast<std::size_t>(face.element)].type,
                              face.face) == 3;
    const Eigen::Vector3d d1 = mesh.coordinates.col(nodes[triangle ? 1 : 2]) -
                               mesh.coordinates.col(nodes[0]);
    const Eigen::Vector3d d2 = mesh.coordinates.col(nodes[triangle ? 2 : 3]) -
                               mesh.coordinates.col(nodes[triangle ? 0 : 1]);
    const Eigen::Vector3d normal2 = d1.cross(d2);  // 2 A n for a planar quad or a triangle
    const double area = 0.5 * normal2.norm();
    if (std::abs(normal2.normalized().dot(axis)) < 0.9) {
      throw std::invalid_argument(fmt::format(
          "bolt '{}': {}_surface '{}': face S{} of element {} is not perpendicular to the bolt "
          "axis (|n·a| = {:.3f} < 0.9)",
          bolt, role, surface, face.face + 1, mesh.element_ids[static_cast<std::size_t>(face.element)],
          std::abs(normal2.normalized().dot(axis))));
    }
    if (triangle) {
      for (std::size_t k = 0; k < nodes.size(); ++k)
        fp.weights[nodes[k]] += (nodes.size() == 3 || k >= 3 ? 1.0 / 3.0 : 0.0) * area;
    } else if (nodes.size() == 4) {
      for (int n : nodes) fp.weights[n] += 0.25 * area;
    } else {
      for (std::size_t k = 0; k < 8; ++k) fp.weights[nodes[k]] += (k < 4 ? -1.0 / 12.0 : 1.0 / 3.0) * area;
    }
    fp.area += area;
    fp.centroid += area * c;
    fp.parts.push_back(mesh.elements[static_cast<std::size_t>(face.element)].part);
  }
  if (fp.weights.empty()) {
    if (inner_radius > 0.0) {
      throw std::invalid_argument(fmt::format(
          "bolt '{}': {}_surface '{}': no face has its centre between {}_inner_radius = {} m and "
          "{}_radius = {} m of the axis",
          bolt, role, surface, role, inner_radius, role, radius));
    }
    throw std::invalid_argument(fmt::format(
        "bolt '{}': {}_surface '{}': no face has its centre within {}_radius = {} m of the axis",
        bolt, role, surface, role, radius));
  }
  fp.centroid /= fp.area;
  std::sort(fp.parts.begin(), fp.parts.end());
  fp.parts.erase(std::unique(fp.parts.begin(), fp.parts.end()), fp.parts.end());
  return fp;
}

}  // namespace

Bolt build_bolt(const fe::Mesh& mesh, const BoltOptions& options) {
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument(fmt::format("bolt '{}': {}", options.name, msg));
  }
  Bolt bolt;
  bolt.name = options.name;
  bolt.axis = options.axis_direction.normalized();
  bolt.axial_stiffness = options.axial_stiffness;
  bolt.preload = options.preload;
  const Footprint head = select_footprint(mesh, options.name, "head", options.head_surface, options.axis_point,
                                          bolt.axis, options.head_inner_radius, options.head_radius);
  const Footprint nut = select_footprint(mesh, options.name, "nut", options.nut_surface, options.axis_point,
                                         bolt.axis, options.nut_inner_radius, options.nut_radius);
  // The head must lie on the +a side of the nut: the preload then compresses the clamped parts.
  if (!((head.centroid - nut.centroid).dot(bolt.axis) > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "bolt '{}': the head footprint (centre {:.4g}, {:.4g}, {:.4g}) is not on the "
        "axis_direction side of the nut footprint (centre {:.4g}, {:.4g}, {:.4g})",
        options.name, head.centroid.x(), head.centroid.y(), head.centroid.z(), nut.centroid.x(),
        nut.centroid.y(), nut.centroid.z()));
  }
  bolt.head_area = head.area;
  bolt.nut_area = nut.area;
  bolt.head_inner_radius = options.head_inner_radius;
  bolt.nut_inner_radius = options.nut_inner_radius;
  bolt.coupling.resize(mesh.num_dofs());
  std::map<int, double> entries;  // sorted DOF → value (a node may be in both footprints)
  for (const auto& [node, w] : head.weights) {
    bolt.head_nodes.push_back(node);
    for (int d = 0; d < 3; ++d) entries[3 * node + d] += w / head.area * bolt.axis[d];
  }
  for (const auto& [node, w] : nut.weights) {
    bolt.nut_nodes.push_back(node);
    for (int d = 0; d < 3; ++d) entries[3 * node + d] -= w / nut.area * bolt.axis[d];
  }
  for (const auto& [dof, value] : entries)
    if (value != 0.0) bolt.coupling.insert(dof) = value;
  std::set_union(head.parts.begin(), head.parts.end(), nut.parts.begin(), nut.parts.end(),
                 std::back_inserter(bolt.parts));
  return bolt;
}

void add_bolt_stiffness(const std::vector<Bolt>& bolts,
                        std::vector<Eigen::Triplet<double>>& triplets) {
  for (const Bolt& bolt : bolts) {
    for (Eigen::SparseVector<double>::InnerIterator i(bolt.coupling); i; ++i)
      for (Eigen::SparseVector<double>::InnerIterator j(bolt.coupling); j; ++j)
        triplets.emplace_back(static_cast<int>(i.index()), static_cast<int>(j.index()),
                              bolt.axial_stiffness * i.value() * j.value());
  }
}

Eigen::SparseMatrix<double> bolt_stiffness(const std::vector<Bolt>& bolts, int num_dofs) {
  std::vector<Eigen::Triplet<double>> triplets;
  add_bolt_stiffness(bolts, triplets);
  Eigen::SparseMatrix<double> k(num_dofs, num_dofs);
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

Eigen::VectorXd bolt_load(const std::vector<Bolt>& bolts, int num_dofs, double load_factor) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(num_dofs);
  for (const Bolt& bolt : bolts)
    for (Eigen::SparseVector<double>::InnerIterator i(bolt.coupling); i; ++i)
      f[i.index()] -= load_factor * bolt.preload * i.value();
  return f;
}

}  // namespace jointhb::preload
