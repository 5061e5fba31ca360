// Zero-thickness interface elements, eq. (13)-(24) (interface.hpp,
// docs/zero-thickness-elements.md).
#include "jointhb/fe/interface.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace jointhb::fe {

const char* to_string(InterfaceIntegration integration) {
  return integration == InterfaceIntegration::nodal ? "nodal" : "gauss";
}

const char* to_string(InterfaceMeshes meshes) {
  switch (meshes) {
    case InterfaceMeshes::matching: return "matching";
    case InterfaceMeshes::non_matching: return "non-matching";
    case InterfaceMeshes::automatic: return "automatic";
  }
  return "?";
}

std::string InterfaceOptions::validate() const {
  if (bottom_surface.empty()) return "bottom_surface must name a surface of the mesh";
  if (top_surface.empty()) return "top_surface must name a surface of the mesh";
  if (bottom_surface == top_surface) {
    return fmt::format("bottom_surface and top_surface must differ (both '{}')", bottom_surface);
  }
  if (!(match_tolerance > 0.0 && match_tolerance <= 0.1)) {
    return fmt::format("match_tolerance = {} must lie in (0, 0.1]", match_tolerance);
  }
  return {};
}

namespace {

using Vec3 = Eigen::Vector3d;

// Shape functions of a face in the natural coordinates (ξ, η) of its bottom face, with the corners
// numbered cyclically as face_local_nodes lists them: corner k at (ξ_k, η_k) =
// (-1,-1), (1,-1), (1,1), (-1,1), so that ∂x/∂ξ × ∂x/∂η is the face's outward normal. Quad4: the
// bilinear functions of eq. (14) (the paper numbers the same four functions non-cyclically);
// quad8: the serendipity functions with mid-edge node 4+k between corners k and k+1.
struct ShapeValues {
  std::array<double, 8> h{};
  std::array<double, 8> dxi{};
  std::array<double, 8> deta{};
};

constexpr std::array<double, 8> kXi = {-1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0, -1.0};
constexpr std::array<double, 8> kEta = {-1.0, -1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0};

ShapeValues shape_values(int nodes, double xi, double eta) {
  ShapeValues s;
  if (nodes == 4) {
    for (std::size_t k = 0; k < 4; ++k) {  // eq. (14): h = (1 ± ξ)(1 ± η)/4
      s.h[k] = 0.25 * (1.0 + kXi[k] * xi) * (1.0 + kEta[k] * eta);
      s.dxi[k] = 0.25 * kXi[k] * (1.0 + kEta[k] * eta);
      s.deta[k] = 0.25 * (1.0 + kXi[k] * xi) * kEta[k];
    }
    return s;
  }
  for (std::size_t k = 0; k < 4; ++k) {  // serendipity corners: (1+ξξk)(1+ηηk)(ξξk+ηηk-1)/4
    const double a = 1.0 + kXi[k] * xi;
    const double b = 1.0 + kEta[k] * eta;
    const double c = kXi[k] * xi + kEta[k] * eta - 1.0;
    s.h[k] = 0.25 * a * b * c;
    s.dxi[k] = 0.25 * kXi[k] * b * (c + a);
    s.deta[k] = 0.25 * kEta[k] * a * (c + b);
  }
  for (std::size_t k = 4; k < 8; ++k) {
    if (kXi[k] == 0.0) {  // (1-ξ²)(1+ηηk)/2
      s.h[k] = 0.5 * (1.0 - xi * xi) * (1.0 + kEta[k] * eta);
      s.dxi[k] = -xi * (1.0 + kEta[k] * eta);
      s.deta[k] = 0.5 * (1.0 - xi * xi) * kEta[k];
    } else {  // (1+ξξk)(1-η²)/2
      s.h[k] = 0.5 * (1.0 + kXi[k] * xi) * (1.0 - eta * eta);
      s.dxi[k] = 0.5 * kXi[k] * (1.0 - eta * eta);
      s.deta[k] = -(1.0 + kXi[k] * xi) * eta;
    }
  }
  return s;
}

struct RulePoint {
  double xi, eta, weight;
};

// Nodal: 2-point Lobatto (trapezoid) in each direction, points at the corners, weights 1.
// Gauss: 2×2 (±1/√3, weights 1) for quad4, 3×3 (0, ±√(3/5); 8/9, 5/9) for quad8.
std::vector<RulePoint> integration_rule(InterfaceIntegration integration, int nodes) {
  std::vector<RulePoint> rule;
  if (integration == InterfaceIntegration::nodal) {
    for (std::size_t k = 0; k < 4; ++k) rule.push_back({kXi[k], kEta[k], 1.0});
    return rule;
  }
  if (nodes == 4) {
    const double g = 1.0 / std::sqrt(3.0);
    for (std::size_t k = 0; k < 4; ++k) rule.push_back({g * kXi[k], g * kEta[k], 1.0});
    return rule;
  }
  const double g = std::sqrt(0.6);
  const std::array<double, 3> x = {-g, 0.0, g};
  const std::array<double, 3> w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  for (std::size_t j = 0; j < 3; ++j)
    for (std::size_t i = 0; i < 3; ++i) rule.push_back({x[i], x[j], w[i] * w[j]});
  return rule;
}

// Tangent vectors a1 = ∂x/∂ξ, a2 = ∂x/∂η of the face with nodes `nodes` at (ξ, η).
std::pair<Vec3, Vec3> tangents_at(const Mesh& mesh, const std::vector<int>& nodes,
                                  const ShapeValues& s) {
  Vec3 a1 = Vec3::Zero();
  Vec3 a2 = Vec3::Zero();
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const auto x = mesh.coordinates.col(nodes[k]);
    a1 += s.dxi[k] * x;
    a2 += s.deta[k] * x;
  }
  return {a1, a2};
}

long external_id(const Mesh& mesh, int element) {
  const auto e = static_cast<std::size_t>(element);
  return e < mesh.element_ids.size() ? mesh.element_ids[e] : static_cast<long>(element) + 1;
}

long external_node_id(const Mesh& mesh, int node) {
  const auto n = static_cast<std::size_t>(node);
  return n < mesh.node_ids.size() ? mesh.node_ids[n] : static_cast<long>(node) + 1;
}

// "bottom face of element 12 (S2)"
std::string describe(const Mesh& mesh, const char* side, const Face& face) {
  return fmt::format("{} face of element {} (S{})", side, external_id(mesh, face.element),
                     face.face + 1);
}

struct FaceGeometry {
  Face face;
  std::vector<int> nodes;
  Vec3 centroid = Vec3::Zero();
  double size = 0.0;  // longest distance between two corners
};

FaceGeometry face_geometry(const Mesh& mesh, const Face& face) {
  FaceGeometry g;
  g.face = face;
  g.nodes = face_nodes(mesh, face);
  for (int n : g.nodes) g.centroid += mesh.coordinates.col(n);
  g.centroid /= static_cast<double>(g.nodes.size());
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i + 1; j < 4; ++j)
      g.size = std::max(
          g.size, (mesh.coordinates.col(g.nodes[i]) - mesh.coordinates.col(g.nodes[j])).norm());
  return g;
}

// Unit outward normal at the face centre.
Vec3 centre_normal(const Mesh& mesh, const std::vector<int>& nodes) {
  const auto [a1, a2] =
      tangents_at(mesh, nodes, shape_values(static_cast<int>(nodes.size()), 0, 0));
  return a1.cross(a2).normalized();
}

}  // namespace

Interface build_interface(const Mesh& mesh, const InterfaceOptions& options) {
  const std::string who = fmt::format("interface '{}'", options.name);
  if (std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument(who + ": " + msg);
  }
  auto surface = [&](const std::string& name, const char* field) -> const std::vector<Face>& {
    const auto it = mesh.surfaces.find(name);
    if (it == mesh.surfaces.end()) {
      throw std::invalid_argument(fmt::format("{}: unknown surface '{}' ({})", who, name, field));
    }
    if (it->second.empty()) {
      throw std::invalid_argument(fmt::format("{}: surface '{}' ({}) is empty", who, name, field));
    }
    return it->second;
  };
  const std::vector<Face>& bottom_faces = surface(options.bottom_surface, "bottom_surface");
  const std::vector<Face>& top_faces = surface(options.top_surface, "top_surface");

  // Quadrilateral faces only (zero-thickness elements on triangles are not implemented), and one
  // face type (quad4 or quad8) on both surfaces.
  auto nodes_of = [&](const Face& f) {
    return face_node_count(mesh.elements.at(static_cast<std::size_t>(f.element)).type, f.face);
  };
  auto check_quadrilateral = [&](const std::vector<Face>& faces, const char* side,
                                 const std::string& name) {
    for (const Face& f : faces) {
      const ElementType type = mesh.elements.at(static_cast<std::size_t>(f.element)).type;
      if (f.face < 0 || f.face >= face_count(type)) {
        throw std::invalid_argument(fmt::format("{}: surface '{}': {} does not exist ({} has {} "
                                                "faces)",
                                                who, name, describe(mesh, side, f),
                                                abaqus_name(type), face_count(type)));
      }
      if (face_corner_count(type, f.face) != 4) {
        throw std::invalid_argument(fmt::format(
            "{}: surface '{}' has a triangular face ({}, tri{} of a {}): interface elements "
            "need quadrilateral faces (hexahedra, or the side faces S3..S5 of wedges)",
            who, name, describe(mesh, side, f), face_node_count(type, f.face), abaqus_name(type)));
      }
    }
  };
  check_quadrilateral(bottom_faces, "bottom", options.bottom_surface);
  check_quadrilateral(top_faces, "top", options.top_surface);
  const int face_nodes_per_face = nodes_of(bottom_faces.front());
  auto check_type = [&](const std::vector<Face>& faces, const char* side, const std::string& name) {
    for (const Face& f : faces) {
      const int n = nodes_of(f);
      if (n != face_nodes_per_face) {
        throw std::invalid_argument(fmt::format(
            "{}: mixed quad4/quad8 faces: {} (surface '{}') has {} nodes, the first bottom face "
            "(surface '{}') has {}",
            who, describe(mesh, side, f), name, n, options.bottom_surface, face_nodes_per_face));
      }
    }
  };
  check_type(bottom_faces, "bottom", options.bottom_surface);
  check_type(top_faces, "top", options.top_surface);
  if (face_nodes_per_face == 8 && options.integration == InterfaceIntegration::nodal) {
    throw std::invalid_argument(fmt::format(
        "{}: integration 'nodal' needs quad4 faces, surface '{}' has quad8 faces (hex20): use "
        "'gauss' (3×3)",
        who, options.bottom_surface));
  }

  // Pair each bottom face with the top face whose nodes coincide: candidates by centroid, sorted
  // along x, then node-by-node within the tolerance (relative to the bottom face's size).
  std::vector<FaceGeometry> top;
  top.reserve(top_faces.size());
  for (const Face& f : top_faces) top.push_back(face_geometry(mesh, f));
  std::vector<int> order(top.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return top[static_cast<std::size_t>(a)].centroid.x() <
           top[static_cast<std::size_t>(b)].centroid.x();
  });
  std::vector<double> sorted_x(order.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    sorted_x[i] = top[static_cast<std::size_t>(order[i])].centroid.x();

  Interface result;
  result.name = options.name;
  result.integration = options.integration;
  result.num_mesh_nodes = mesh.num_nodes();
  std::vector<int> used_by(top.size(), -1);  // bottom face index that claimed each top face

  for (std::size_t b = 0; b < bottom_faces.size(); ++b) {
    const FaceGeometry bg = face_geometry(mesh, bottom_faces[b]);
    const double tol = options.match_tolerance * bg.size;
    std::vector<int> matched;
    int match = -1;
    auto first = std::lower_bound(sorted_x.begin(), sorted_x.end(), bg.centroid.x() - tol);
    for (auto it = first; it != sorted_x.end() && *it <= bg.centroid.x() + tol; ++it) {
      const int t = order[static_cast<std::size_t>(it - sorted_x.begin())];
      const FaceGeometry& tg = top[static_cast<std::size_t>(t)];
      if ((tg.centroid - bg.centroid).norm() > tol) continue;
      std::vector<int> partner;
      std::vector<bool> taken(tg.nodes.size(), false);
      for (int bn : bg.nodes) {
        for (std::size_t j = 0; j < tg.nodes.size(); ++j) {
          if (!taken[j] &&
              (mesh.coordinates.col(tg.nodes[j]) - mesh.coordinates.col(bn)).norm() <= tol) {
            taken[j] = true;
            partner.push_back(tg.nodes[j]);
            break;
          }
        }
      }
      if (partner.size() == bg.nodes.size()) {
        match = t;
        matched = std::move(partner);
        break;
      }
    }
    if (match < 0) {
      throw std::invalid_argument(fmt::format(
          "{}: matching meshes are required: {} (surface '{}') at ({:.6g}, {:.6g}, {:.6g}) has no "
          "coincident face on surface '{}'",
          who, describe(mesh, "bottom", bg.face), options.bottom_surface, bg.centroid.x(),
          bg.centroid.y(), bg.centroid.z(), options.top_surface));
    }
    const FaceGeometry& tg = top[static_cast<std::size_t>(match)];
    if (used_by[static_cast<std::size_t>(match)] >= 0) {
      throw std::invalid_argument(fmt::format(
          "{}: {} (surface '{}') coincides with two bottom faces: {} and {}", who,
          describe(mesh, "top", tg.face), options.top_surface,
          describe(
              mesh, "bottom",
              bottom_faces[static_cast<std::size_t>(used_by[static_cast<std::size_t>(match)])]),
          describe(mesh, "bottom", bg.face)));
    }
    used_by[static_cast<std::size_t>(match)] = static_cast<int>(b);
    for (std::size_t k = 0; k < matched.size(); ++k) {
      if (matched[k] == bg.nodes[k]) {
        throw std::invalid_argument(fmt::format(
            "{}: {} and {} share node {}: an interface needs separate nodes on each side", who,
            describe(mesh, "bottom", bg.face), describe(mesh, "top", tg.face),
            external_node_id(mesh, matched[k])));
      }
    }
    if (centre_normal(mesh, bg.nodes).dot(centre_normal(mesh, tg.nodes)) >= 0.0) {
      throw std::invalid_argument(fmt::format(
          "{}: surfaces '{}' and '{}' do not face each other: {} and {} coincide but their outward "
          "normals are not opposite",
          who, options.bottom_surface, options.top_surface, describe(mesh, "bottom", bg.face),
          describe(mesh, "top", tg.face)));
    }
    InterfaceElement element;
    element.bottom = bg.face;
    element.top = tg.face;
    element.bottom_nodes = bg.nodes;
    element.top_nodes = std::move(matched);
    result.elements.push_back(std::move(element));
  }
  for (std::size_t t = 0; t < top.size(); ++t) {
    if (used_by[t] < 0) {
      const Vec3& c = top[t].centroid;
      throw std::invalid_argument(fmt::format(
          "{}: matching meshes are required: {} (surface '{}') at ({:.6g}, {:.6g}, {:.6g}) has no "
          "coincident face on surface '{}'",
          who, describe(mesh, "top", top[t].face), options.top_surface, c.x(), c.y(), c.z(),
          options.bottom_surface));
    }
  }

  // Node pairs: each bottom node has one top partner (and vice versa).
  std::vector<int> top_of(static_cast<std::size_t>(mesh.num_nodes()), -1);
  std::vector<int> bottom_of(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (const InterfaceElement& e : result.elements) {
    for (std::size_t k = 0; k < e.bottom_nodes.size(); ++k) {
      const auto bn = static_cast<std::size_t>(e.bottom_nodes[k]);
      const auto tn = static_cast<std::size_t>(e.top_nodes[k]);
      if ((top_of[bn] >= 0 && top_of[bn] != e.top_nodes[k]) ||
          (bottom_of[tn] >= 0 && bottom_of[tn] != e.bottom_nodes[k])) {
        throw std::invalid_argument(fmt::format(
            "{}: node {} of {} is coincident with more than one node across the interface "
            "(duplicate nodes?)",
            who, external_node_id(mesh, e.bottom_nodes[k]), describe(mesh, "bottom", e.bottom)));
      }
      top_of[bn] = e.top_nodes[k];
      bottom_of[tn] = e.bottom_nodes[k];
    }
  }
  for (std::size_t n = 0; n < top_of.size(); ++n)
    if (top_of[n] >= 0) result.node_pairs.push_back({static_cast<int>(n), top_of[n]});

  // Integration points: frame and area weight from the bottom face, eq. (13)-(14).
  const std::vector<RulePoint> rule = integration_rule(options.integration, face_nodes_per_face);
  for (std::size_t e = 0; e < result.elements.size(); ++e) {
    InterfaceElement& element = result.elements[e];
    element.first_point = result.num_points();
    element.num_points = static_cast<int>(rule.size());
    for (const RulePoint& q : rule) {
      const ShapeValues s = shape_values(face_nodes_per_face, q.xi, q.eta);
      const auto [a1, a2] = tangents_at(mesh, element.bottom_nodes, s);
      const Vec3 normal = a1.cross(a2);
      const double det_j = normal.norm();  // dA = |∂x/∂ξ × ∂x/∂η| dξ dη
      if (!(det_j > 0.0) || !(a1.norm() > 0.0)) {
        throw std::invalid_argument(
            fmt::format("{}: {} is degenerate (zero area at ξ = {}, η = {})", who,
                        describe(mesh, "bottom", element.bottom), q.xi, q.eta));
      }
      InterfacePoint p;
      p.element = static_cast<int>(e);
      p.natural = {q.xi, q.eta};
      p.shape = s.h;
      p.area = q.weight * det_j;
      const Vec3 n = normal / det_j;
      const Vec3 t1 = a1.normalized();  // ⊥ n since n ∝ a1 × a2
      p.frame.row(0) = t1.transpose();
      p.frame.row(1) = n.cross(t1).transpose();
      p.frame.row(2) = n.transpose();
      for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k)
        p.position += s.h[k] * mesh.coordinates.col(element.bottom_nodes[k]);
      element.area += p.area;
      result.points.push_back(p);
    }
    result.total_area += element.area;
  }

  // Gap operator G, eq. (19): rows 3p+r = frame row r · Σ_i h_i (u_i^top - u_i^bottom).
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(result.points.size() * static_cast<std::size_t>(face_nodes_per_face) * 18);
  for (int p = 0; p < result.num_points(); ++p) {
    const InterfacePoint& point = result.points[static_cast<std::size_t>(p)];
    const InterfaceElement& element = result.elements[static_cast<std::size_t>(point.element)];
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k) {
      const double h = point.shape[k];
      if (h == 0.0) continue;  // nodal integration: only the point's own node pair
      for (int r = 0; r < 3; ++r) {
        for (int d = 0; d < 3; ++d) {
          const double v = h * point.frame(r, d);
          if (v == 0.0) continue;
          triplets.emplace_back(3 * p + r, 3 * element.top_nodes[k] + d, v);
          triplets.emplace_back(3 * p + r, 3 * element.bottom_nodes[k] + d, -v);
        }
      }
    }
  }
  result.gap_operator.resize(3 * result.num_points(), mesh.num_dofs());
  result.gap_operator.setFromTriplets(triplets.begin(), triplets.end());
  return result;
}

Eigen::VectorXd gaps(const Interface& interface, const Eigen::VectorXd& u) {
  if (u.size() != interface.num_mesh_dofs()) {
    throw std::invalid_argument(fmt::format("gaps: u has {} entries, the mesh has {} DOFs",
                                            u.size(), interface.num_mesh_dofs()));
  }
  // Equal to G u, but each node pair's difference u^top - u^bottom is formed first (eq. 19): no
  // cancellation of large common motions (a free-free structure's rigid-body drift), and a
  // rigid-body motion of both bodies gives exactly g = 0.
  Eigen::VectorXd g(3 * interface.num_points());
  for (int p = 0; p < interface.num_points(); ++p) {
    const InterfacePoint& point = interface.points[static_cast<std::size_t>(p)];
    const InterfaceElement& element = interface.elements[static_cast<std::size_t>(point.element)];
    Vec3 relative = Vec3::Zero();
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k) {
      const double h = point.shape[k];
      if (h == 0.0) continue;
      relative +=
          h * (u.segment<3>(3 * element.top_nodes[k]) - u.segment<3>(3 * element.bottom_nodes[k]));
    }
    g.segment<3>(3 * p) = point.frame * relative;
  }
  return g;
}

Eigen::VectorXd interface_force(const Interface& interface, const Eigen::VectorXd& tractions) {
  if (tractions.size() != 3 * interface.num_points()) {
    throw std::invalid_argument(fmt::format("interface_force: {} tractions, need 3 per point = {}",
                                            tractions.size(), 3 * interface.num_points()));
  }
  // f = Gᵀ A t, eq. (22): the point's traction a_p R_pᵀ t_p (global axes) goes with +h_i to the
  // top node and -h_i to the bottom node (equal and opposite, eq. 20).
  Eigen::VectorXd f = Eigen::VectorXd::Zero(interface.num_mesh_dofs());
  for (int p = 0; p < interface.num_points(); ++p) {
    const InterfacePoint& point = interface.points[static_cast<std::size_t>(p)];
    const InterfaceElement& element = interface.elements[static_cast<std::size_t>(point.element)];
    const Vec3 tau = point.area * (point.frame.transpose() * tractions.segment<3>(3 * p));
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k) {
      const double h = point.shape[k];
      if (h == 0.0) continue;
      f.segment<3>(3 * element.top_nodes[k]) += h * tau;
      f.segment<3>(3 * element.bottom_nodes[k]) -= h * tau;
    }
  }
  return f;
}

void add_interface_stiffness(const Interface& interface, std::span<const Eigen::Matrix3d> tangents,
                             std::vector<Eigen::Triplet<double>>& triplets, int dof_offset) {
  if (static_cast<int>(tangents.size()) != interface.num_points()) {
    throw std::invalid_argument(fmt::format("add_interface_stiffness: {} tangents for {} points",
                                            tangents.size(), interface.num_points()));
  }
  // Per element, eq. (23): K_T(i,j) = Σ_p h_i h_j a_p R_pᵀ C_p R_p (3×3 blocks in global axes),
  // then eq. (24): +K_T on the bottom-bottom and top-top blocks, -K_T on the mixed ones.
  std::vector<Eigen::Matrix3d> block;
  std::vector<char> used;
  for (const InterfaceElement& element : interface.elements) {
    const std::size_t n = element.bottom_nodes.size();
    block.assign(n * n, Eigen::Matrix3d::Zero());
    used.assign(n * n, 0);
    for (int p = element.first_point; p < element.first_point + element.num_points; ++p) {
      const InterfacePoint& point = interface.points[static_cast<std::size_t>(p)];
      const Eigen::Matrix3d d = point.area * (point.frame.transpose() *
                                              tangents[static_cast<std::size_t>(p)] * point.frame);
      for (std::size_t i = 0; i < n; ++i) {
        if (point.shape[i] == 0.0) continue;
        for (std::size_t j = 0; j < n; ++j) {
          if (point.shape[j] == 0.0) continue;
          block[i * n + j] += (point.shape[i] * point.shape[j]) * d;
          used[i * n + j] = 1;
        }
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) {
        if (!used[i * n + j]) continue;
        const Eigen::Matrix3d& k = block[i * n + j];
        const std::array<int, 2> row_nodes = {element.bottom_nodes[i], element.top_nodes[i]};
        const std::array<int, 2> col_nodes = {element.bottom_nodes[j], element.top_nodes[j]};
        for (std::size_t si = 0; si < 2; ++si) {
          for (std::size_t sj = 0; sj < 2; ++sj) {
            const double sign = si == sj ? 1.0 : -1.0;
            const int r0 = dof_offset + 3 * row_nodes[si];
            const int c0 = dof_offset + 3 * col_nodes[sj];
            for (int a = 0; a < 3; ++a)
              for (int b = 0; b < 3; ++b) triplets.emplace_back(r0 + a, c0 + b, sign * k(a, b));
          }
        }
      }
    }
  }
}

InterfaceAssembly assemble_interface_force_and_tangent(const Interface& interface,
                                                       const Eigen::VectorXd& tractions,
                                                       std::span<const Eigen::Matrix3d> tangents) {
  InterfaceAssembly a;
  a.force = interface_force(interface, tractions);
  std::vector<Eigen::Triplet<double>> triplets;
  const std::size_t per_element =
      interface.elements.empty() ? 0 : interface.elements.front().bottom_nodes.size();
  const std::size_t blocks = interface.integration == InterfaceIntegration::nodal
                                 ? per_element
                                 : per_element * per_element;
  triplets.reserve(interface.elements.size() * blocks * 36);
  add_interface_stiffness(interface, tangents, triplets);
  a.stiffness.resize(interface.num_mesh_dofs(), interface.num_mesh_dofs());
  a.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  return a;
}

namespace {

template <class LawOf>
InterfaceContactState evaluate_static(const Interface& interface, const LawOf& law_of,
                                      const Eigen::VectorXd& u, bool with_stiffness,
                                      const Eigen::VectorXd& initial_normal_gap) {
  const int np = interface.num_points();
  if (initial_normal_gap.size() != 0 && initial_normal_gap.size() != np) {
    throw std::invalid_argument(fmt::format(
        "evaluate_static_contact: initial_normal_gap has {} entries, need 0 or one per point ({})",
        initial_normal_gap.size(), np));
  }
  InterfaceContactState s;
  s.gap = gaps(interface, u);
  if (initial_normal_gap.size() != 0)
    for (int p = 0; p < np; ++p) s.gap(3 * p + 2) += initial_normal_gap(p);
  s.traction.resize(3 * np);
  s.pressure.resize(np);
  s.tangent.resize(static_cast<std::size_t>(np));
  s.open.assign(static_cast<std::size_t>(np), false);
  for (int p = 0; p < np; ++p) {
    // Preload convention: from the stress-free state (t_T0 = 0, g_0 = 0) straight to g_1.
    const contact::ContactStep step =
        law_of(p).step(contact::Vec2::Zero(), contact::Vec3::Zero(), s.gap.segment<3>(3 * p));
    s.traction.segment<3>(3 * p) = step.traction;
    s.pressure(p) = -step.traction.z();
    s.tangent[static_cast<std::size_t>(p)] = step.tangent;
    s.open[static_cast<std::size_t>(p)] = step.open;
    s.num_open += step.open ? 1 : 0;
  }
  if (!with_stiffness) {
    s.force = interface_force(interface, s.traction);
    return s;
  }
  InterfaceAssembly a = assemble_interface_force_and_tangent(interface, s.traction, s.tangent);
  s.force = std::move(a.force);
  s.stiffness = std::move(a.stiffness);
  return s;
}

}  // namespace

InterfaceContactState evaluate_static_contact(const Interface& interface,
                                              const contact::ContactPoint& law,
                                              const Eigen::VectorXd& u,
                                              const Eigen::VectorXd& initial_normal_gap,
                                              bool with_stiffness) {
  return evaluate_static(
      interface, [&](int) -> const contact::ContactPoint& { return law; }, u, with_stiffness,
      initial_normal_gap);
}

InterfaceContactState evaluate_static_contact(const Interface& interface,
                                              std::span<const contact::ContactPoint> laws,
                                              const Eigen::VectorXd& u,
                                              const Eigen::VectorXd& initial_normal_gap,
                                              bool with_stiffness) {
  if (static_cast<int>(laws.size()) != interface.num_points()) {
    throw std::invalid_argument(
        fmt::format("evaluate_static_contact: {} laws for {} points (need one per point)",
                    laws.size(), interface.num_points()));
  }
  return evaluate_static(
      interface,
      [&](int p) -> const contact::ContactPoint& { return laws[static_cast<std::size_t>(p)]; }, u,
      with_stiffness, initial_normal_gap);
}

}  // namespace jointhb::fe
