// Zero-thickness interface elements, eq. (13)-(24) (interface.hpp,
// docs/zero-thickness-elements.md).
#include "jointhb/fe/interface.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include "face_shapes.hpp"
#include "interface_build.hpp"

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

using Vec3 = Eigen::Vector3d;

namespace detail {

long external_node_id(const Mesh& mesh, int node) {
  const auto n = static_cast<std::size_t>(node);
  return n < mesh.node_ids.size() ? mesh.node_ids[n] : static_cast<long>(node) + 1;
}

namespace {
long external_id(const Mesh& mesh, int element) {
  const auto e = static_cast<std::size_t>(element);
  return e < mesh.element_ids.size() ? mesh.element_ids[e] : static_cast<long>(element) + 1;
}
}  // namespace

std::string describe(const Mesh& mesh, const char* side, const Face& face) {
  return fmt::format("{} face of element {} (S{})", side, external_id(mesh, face.element),
                     face.face + 1);
}

PointFrame point_frame(const Mesh& mesh, const std::vector<int>& nodes, const face::Shape& s) {
  Vec3 a1 = Vec3::Zero();
  Vec3 a2 = Vec3::Zero();
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const auto x = mesh.coordinates.col(nodes[k]);
    a1 += s.dxi[k] * x;
    a2 += s.deta[k] * x;
  }
  PointFrame f;
  const Vec3 normal = a1.cross(a2);
  f.det_j = normal.norm();  // dA = |∂x/∂ξ × ∂x/∂η| dξ dη
  if (!(f.det_j > 0.0) || !(a1.norm() > 0.0)) {
    f.det_j = 0.0;
    return f;
  }
  const Vec3 n = normal / f.det_j;
  const Vec3 t1 = a1.normalized();  // ⊥ n since n ∝ a1 × a2
  f.frame.row(0) = t1.transpose();
  f.frame.row(1) = n.cross(t1).transpose();
  f.frame.row(2) = n.transpose();
  return f;
}

Vec3 centre_normal(const Mesh& mesh, const std::vector<int>& nodes) {
  const int n = static_cast<int>(nodes.size());
  const Eigen::Vector2d c = face::centre(n);
  return point_frame(mesh, nodes, face::shape(n, c.x(), c.y())).frame.row(2).transpose();
}

FaceGeometry face_geometry(const Mesh& mesh, const Face& face) {
  FaceGeometry g;
  g.face = face;
  g.nodes = face_nodes(mesh, face);
  for (int n : g.nodes) g.centroid += mesh.coordinates.col(n);
  g.centroid /= static_cast<double>(g.nodes.size());
  for (int n : g.nodes) g.radius = std::max(g.radius, (mesh.coordinates.col(n) - g.centroid).norm());
  const int corners = face::corner_count(static_cast<int>(g.nodes.size()));
  for (int i = 0; i < corners; ++i)
    for (int j = i + 1; j < corners; ++j)
      g.size = std::max(g.size, (mesh.coordinates.col(g.nodes[static_cast<std::size_t>(i)]) -
                                 mesh.coordinates.col(g.nodes[static_cast<std::size_t>(j)]))
                                    .norm());
  return g;
}

}  // namespace detail

namespace {

using detail::describe;
using detail::FaceGeometry;
using detail::face_geometry;
using detail::external_node_id;

// The faces of a surface, checked to exist.
void check_faces(const Mesh& mesh, const std::vector<Face>& faces, const char* side,
                 const std::string& name, const std::string& who) {
  for (const Face& f : faces) {
    const ElementType type = mesh.elements.at(static_cast<std::size_t>(f.element)).type;
    if (f.face < 0 || f.face >= face_count(type)) {
      throw std::invalid_argument(fmt::format("{}: surface '{}': {} does not exist ({} has {} faces)",
                                              who, name, describe(mesh, side, f), abaqus_name(type),
                                              face_count(type)));
    }
  }
}

int nodes_of(const Mesh& mesh, const Face& f) {
  return face_node_count(mesh.elements.at(static_cast<std::size_t>(f.element)).type, f.face);
}

// Pairs each bottom face with the top face whose nodes coincide: candidates by centroid, sorted
// along x, then node-by-node within the tolerance (relative to the bottom face's size). Returns
// the message for the first face without a partner ("" when every face has one); errors that no
// other pairing could mend (shared nodes, surfaces not facing each other) throw.
std::string pair_coincident_faces(const Mesh& mesh, const std::vector<Face>& bottom_faces,
                                  const std::vector<Face>& top_faces,
                                  const InterfaceOptions& options, const std::string& who,
                                  std::vector<InterfaceElement>& elements) {
  std::vector<FaceGeometry> top;
  top.reserve(top_faces.size());
  for (const Face& f : top_faces) top.push_back(face_geometry(mesh, f));
  const detail::FacesAlongX along_x(top);

  std::vector<int> used_by(top.size(), -1);  // bottom face index that claimed each top face
  for (std::size_t b = 0; b < bottom_faces.size(); ++b) {
    const FaceGeometry bg = face_geometry(mesh, bottom_faces[b]);
    const double tol = options.match_tolerance * bg.size;
    std::vector<int> matched;
    int match = -1;
    along_x.for_each_in(bg.centroid.x() - tol, bg.centroid.x() + tol, [&](int t) {
      const FaceGeometry& tg = top[static_cast<std::size_t>(t)];
      if (tg.nodes.size() != bg.nodes.size() || (tg.centroid - bg.centroid).norm() > tol) return false;
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
      if (partner.size() != bg.nodes.size()) return false;
      match = t;
      matched = std::move(partner);
      return true;
    });
    if (match < 0) {
      return fmt::format(
          "{}: matching meshes are required: {} (surface '{}') at ({:.6g}, {:.6g}, {:.6g}) has no "
          "coincident face on surface '{}' (set meshes: non-matching for independently meshed "
          "surfaces)",
          who, describe(mesh, "bottom", bg.face), options.bottom_surface, bg.centroid.x(),
          bg.centroid.y(), bg.centroid.z(), options.top_surface);
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
    if (detail::centre_normal(mesh, bg.nodes).dot(detail::centre_normal(mesh, tg.nodes)) >= 0.0) {
      throw std::invalid_argument(fmt::format(
          "{}: surfaces '{}' and '{}' do not face each other: {} and {} coincide but their outward "
          "normals are not opposite",
          who, options.bottom_surface, options.top_surface, describe(mesh, "bottom", bg.face),
          describe(mesh, "top", tg.face)));
    }
    InterfaceElement element;
    element.bottom = bg.face;
    element.top = tg.face;
    element.top_faces = {tg.face};
    element.bottom_nodes = bg.nodes;
    element.top_nodes = std::move(matched);
    elements.push_back(std::move(element));
  }
  for (std::size_t t = 0; t < top.size(); ++t) {
    if (used_by[t] < 0) {
      const Vec3& c = top[t].centroid;
      return fmt::format(
          "{}: matching meshes are required: {} (surface '{}') at ({:.6g}, {:.6g}, {:.6g}) has no "
          "coincident face on surface '{}' (set meshes: non-matching for independently meshed "
          "surfaces)",
          who, describe(mesh, "top", top[t].face), options.top_surface, c.x(), c.y(), c.z(),
          options.bottom_surface);
    }
  }
  return {};
}

// Node pairs of a matching interface: each bottom node has one top partner (and vice versa).
void collect_node_pairs(const Mesh& mesh, const std::string& who, Interface& result) {
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
}

// Integration points of a matching interface: frame and area weight from the bottom face,
// eq. (13)-(14); the top face's weights equal the bottom's (coincident nodes).
void add_matching_points(const Mesh& mesh, InterfaceIntegration integration,
                         const std::string& who, Interface& result) {
  for (std::size_t e = 0; e < result.elements.size(); ++e) {
    InterfaceElement& element = result.elements[e];
    const int nodes = static_cast<int>(element.bottom_nodes.size());
    const std::vector<face::RulePoint> rule = face::rule(integration, nodes);
    element.first_point = result.num_points();
    element.num_points = static_cast<int>(rule.size());
    for (const face::RulePoint& q : rule) {
      const face::Shape s = face::shape(nodes, q.xi, q.eta);
      const detail::PointFrame f = detail::point_frame(mesh, element.bottom_nodes, s);
      if (!(f.det_j > 0.0)) {
        throw std::invalid_argument(
            fmt::format("{}: {} is degenerate (zero area at ξ = {}, η = {})", who,
                        describe(mesh, "bottom", element.bottom), q.xi, q.eta));
      }
      InterfacePoint p;
      p.element = static_cast<int>(e);
      p.natural = {q.xi, q.eta};
      p.shape = s.h;
      p.top_shape.assign(s.h.begin(), s.h.begin() + nodes);
      p.area = q.weight * f.det_j;
      p.frame = f.frame;
      for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k)
        p.position += s.h[k] * mesh.coordinates.col(element.bottom_nodes[k]);
      element.area += p.area;
      result.points.push_back(p);
    }
    result.total_area += element.area;
  }
}

// Nodal integration: the points of one node pair (one per element around it) take the in-plane
// axes of the first of them when their normals agree (a flat neighbourhood). The laws are
// isotropic in the tangent plane, so the response is unchanged, and the points become identical
// — merged exactly into one by the reduction (contact_patches) — also on meshes whose elements
// have different ξ directions (O-grids around holes, free meshes).
void share_node_frames(Interface& result) {
  std::map<int, int> first_at;  // bottom node → its first point
  for (std::size_t p = 0; p < result.points.size(); ++p) {
    InterfacePoint& point = result.points[p];
    const InterfaceElement& element = result.elements[static_cast<std::size_t>(point.element)];
    int node = -1;
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k)
      if (point.shape[k] == 1.0) node = element.bottom_nodes[k];
    if (node < 0) continue;
    const auto [it, inserted] = first_at.emplace(node, static_cast<int>(p));
    if (inserted) continue;
    const Eigen::Matrix3d& reference = result.points[static_cast<std::size_t>(it->second)].frame;
    if ((point.frame.row(2) - reference.row(2)).norm() <= 1e-12) point.frame = reference;
  }
}

// Gap operator G, eq. (19): rows 3p+r = frame row r · (Σ_k top_shape_k u_top_k − Σ_i h_i u_i).
void build_gap_operator(const Mesh& mesh, Interface& result) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(result.points.size() * 8 * 18);
  for (int p = 0; p < result.num_points(); ++p) {
    const InterfacePoint& point = result.points[static_cast<std::size_t>(p)];
    const InterfaceElement& element = result.elements[static_cast<std::size_t>(point.element)];
    const auto add = [&](int node, double h) {
      if (h == 0.0) return;  // nodal integration: only the point's own nodes
      for (int r = 0; r < 3; ++r)
        for (int d = 0; d < 3; ++d)
          if (const double v = h * point.frame(r, d); v != 0.0)
            triplets.emplace_back(3 * p + r, 3 * node + d, v);
    };
    for (std::size_t k = 0; k < element.top_nodes.size(); ++k)
      add(element.top_nodes[k], point.top_shape[k]);
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k)
      add(element.bottom_nodes[k], -point.shape[k]);
  }
  result.gap_operator.resize(3 * result.num_points(), mesh.num_dofs());
  result.gap_operator.setFromTriplets(triplets.begin(), triplets.end());
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
  check_faces(mesh, bottom_faces, "bottom", options.bottom_surface, who);
  check_faces(mesh, top_faces, "top", options.top_surface, who);
  if (options.integration == InterfaceIntegration::nodal) {
    for (const Face& f : bottom_faces) {
      if (const int n = nodes_of(mesh, f); n == 6 || n == 8) {
        throw std::invalid_argument(fmt::format(
            "{}: integration 'nodal' needs linear faces (tri3, quad4), surface '{}' has {} faces "
            "({}): use 'gauss'",
            who, options.bottom_surface, n == 8 ? "quad8" : "tri6",
            describe(mesh, "bottom", f)));
      }
    }
  }

  Interface result;
  result.name = options.name;
  result.integration = options.integration;
  result.num_mesh_nodes = mesh.num_nodes();
  bool matching = options.meshes != InterfaceMeshes::non_matching;
  if (matching) {
    // One face type on both surfaces of a matching interface.
    const int per_face = nodes_of(mesh, bottom_faces.front());
    auto check_type = [&](const std::vector<Face>& faces, const char* side, const std::string& name) {
      for (const Face& f : faces) {
        if (const int n = nodes_of(mesh, f); n != per_face) {
          throw std::invalid_argument(fmt::format(
              "{}: mixed face types on a matching interface: {} (surface '{}') has {} nodes, the "
              "first bottom face (surface '{}') has {}",
              who, describe(mesh, side, f), name, n, options.bottom_surface, per_face));
        }
      }
    };
    if (options.meshes == InterfaceMeshes::matching) {
      check_type(bottom_faces, "bottom", options.bottom_surface);
      check_type(top_faces, "top", options.top_surface);
    }
    const std::string unmatched =
        pair_coincident_faces(mesh, bottom_faces, top_faces, options, who, result.elements);
    if (!unmatched.empty() && options.meshes == InterfaceMeshes::matching) {
      throw std::invalid_argument(unmatched);
    }
    matching = unmatched.empty();
    if (matching) {
      check_type(bottom_faces, "bottom", options.bottom_surface);
      check_type(top_faces, "top", options.top_surface);
    } else {
      result.elements.clear();
    }
  }
  if (matching) {
    result.meshes = InterfaceMeshes::matching;
    collect_node_pairs(mesh, who, result);
    add_matching_points(mesh, options.integration, who, result);
    if (options.integration == InterfaceIntegration::nodal) share_node_frames(result);
  } else {
    result.meshes = InterfaceMeshes::non_matching;
    detail::build_mortar(mesh, bottom_faces, top_faces, options, who, result);
  }
  build_gap_operator(mesh, result);
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
    if (interface.meshes == InterfaceMeshes::matching) {
      for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k) {
        const double h = point.shape[k];
        if (h == 0.0) continue;
        relative += h * (u.segment<3>(3 * element.top_nodes[k]) -
                         u.segment<3>(3 * element.bottom_nodes[k]));
      }
    } else {
      // Non-matching: both sides' weights sum to 1 (partition of unity), so the displacement of
      // one bottom node is subtracted from every term first (same cancellation-free property
      // for a common translation).
      const Vec3 reference = u.segment<3>(3 * element.bottom_nodes.front());
      for (std::size_t k = 0; k < element.top_nodes.size(); ++k)
        if (const double w = point.top_shape[k]; w != 0.0)
          relative += w * (u.segment<3>(3 * element.top_nodes[k]) - reference);
      for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k)
        if (const double h = point.shape[k]; h != 0.0)
          relative -= h * (u.segment<3>(3 * element.bottom_nodes[k]) - reference);
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
    for (std::size_t k = 0; k < element.top_nodes.size(); ++k)
      if (const double w = point.top_shape[k]; w != 0.0) f.segment<3>(3 * element.top_nodes[k]) += w * tau;
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k)
      if (const double h = point.shape[k]; h != 0.0) f.segment<3>(3 * element.bottom_nodes[k]) -= h * tau;
  }
  return f;
}

namespace {

// K = Gᵀ A C G element by element for any top weights: the element's nodes are its bottom nodes
// (weights -h_i) followed by its top nodes (weights +top_shape_k), and
// K(a, b) = Σ_p w_a w_b a_p R_pᵀ C_p R_p, eq. (23)/(24).
void add_general_interface_stiffness(const Interface& interface,
                                     std::span<const Eigen::Matrix3d> tangents,
                                     std::vector<Eigen::Triplet<double>>& triplets, int dof_offset) {
  std::vector<int> nodes;
  std::vector<double> w;
  std::vector<Eigen::Matrix3d> block;
  for (const InterfaceElement& element : interface.elements) {
    nodes = element.bottom_nodes;
    nodes.insert(nodes.end(), element.top_nodes.begin(), element.top_nodes.end());
    const std::size_t n = nodes.size();
    const std::size_t nb = element.bottom_nodes.size();
    block.assign(n * n, Eigen::Matrix3d::Zero());
    for (int p = element.first_point; p < element.first_point + element.num_points; ++p) {
      const InterfacePoint& point = interface.points[static_cast<std::size_t>(p)];
      w.assign(n, 0.0);
      for (std::size_t i = 0; i < nb; ++i) w[i] = -point.shape[i];
      for (std::size_t k = 0; k < element.top_nodes.size(); ++k) w[nb + k] = point.top_shape[k];
      const Eigen::Matrix3d d = point.area * (point.frame.transpose() *
                                              tangents[static_cast<std::size_t>(p)] * point.frame);
      for (std::size_t i = 0; i < n; ++i) {
        if (w[i] == 0.0) continue;
        for (std::size_t j = 0; j < n; ++j)
          if (w[j] != 0.0) block[i * n + j] += (w[i] * w[j]) * d;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) {
        const Eigen::Matrix3d& k = block[i * n + j];
        if (k.isZero(0.0)) continue;
        const int r0 = dof_offset + 3 * nodes[i];
        const int c0 = dof_offset + 3 * nodes[j];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) triplets.emplace_back(r0 + a, c0 + b, k(a, b));
      }
    }
  }
}

}  // namespace

void add_interface_stiffness(const Interface& interface, std::span<const Eigen::Matrix3d> tangents,
                             std::vector<Eigen::Triplet<double>>& triplets, int dof_offset) {
  if (static_cast<int>(tangents.size()) != interface.num_points()) {
    throw std::invalid_argument(fmt::format("add_interface_stiffness: {} tangents for {} points",
                                            tangents.size(), interface.num_points()));
  }
  if (interface.meshes != InterfaceMeshes::matching) {
    add_general_interface_stiffness(interface, tangents, triplets, dof_offset);
    return;
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
