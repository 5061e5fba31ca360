// Non-matching interfaces: segment-to-segment (mortar) integration of the gap
// (interface_build.hpp, docs/zero-thickness-elements.md §Non-matching meshes).
//
// For each bottom face b, every top face m over it is projected onto b's plane and clipped against
// b (Sutherland–Hodgman); the overlap polygon — a "segment" — is split into triangles from its
// centre and integrated by a collapsed Gauss rule, each quadrature point x carrying b's shape
// functions N_i^b at its natural coordinates on b and m's N_j^m at those on m (eq. M-1):
//   gauss:  every quadrature point is an interface point, g = R (Σ_j N_j^m u_j − Σ_i N_i^b u_i),
//           area w_q — uniform pressure gives exactly the consistent nodal forces ∫N dA on both
//           sides (the patch test) when the rule integrates N_i^b N_j^m exactly;
//   nodal:  (linear bottom faces) dual mortar (Wohlmuth 2000): with b's dual functions
//           ψ_i = Σ_k A_ik N_k^b, A = D M⁻¹, M_ik = ∫_b N_i N_k dA, D = diag ∫_b N_i dA (eq. M-2),
//           the point at bottom node i has area D̃_i = ∫_overlap ψ_i dA (eq. M-3) and top weights
//           M̃_ij / D̃_i with M̃_ij = ∫_overlap ψ_i N_j^m dA (eq. M-4):
//             g_i = R_i (Σ_j (M̃_ij / D̃_i) u_j^top − u_i^bottom).
//           On coincident meshes M̃ = D̃ = D and this is exactly the nodal (Lobatto) element.
// The frame of a point is the bottom face's, as for matching meshes. Faces are taken flat within
// each bottom face's plane (the projected area is corrected by 1/|n·n_b| for warped faces).

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include "interface_build.hpp"

namespace jointhb::fe::detail {

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Polygon = std::vector<Vec2>;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double signed_area(const Polygon& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) a += cross2(p[i], p[(i + 1) % p.size()]);
  return 0.5 * a;
}

// Sutherland–Hodgman: the part of `subject` inside the convex counter-clockwise polygon `clip`.
Polygon clip_polygon(Polygon subject, const Polygon& clip) {
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const Vec2 a = clip[e];
    const Vec2 edge = clip[(e + 1) % clip.size()] - a;
    const auto side = [&](const Vec2& p) { return cross2(edge, p - a); };
    Polygon out;
    for (std::size_t i = 0; i < subject.size(); ++i) {
      const Vec2& p = subject[i];
      const Vec2& q = subject[(i + 1) % subject.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0.0) out.push_back(p);
      if ((sp >= 0.0) != (sq >= 0.0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    subject = std::move(out);
  }
  return subject;
}

struct Plane {
  Vec3 origin, e1, e2, n;
  [[nodiscard]] Vec2 project(const Vec3& x) const { return {e1.dot(x - origin), e2.dot(x - origin)}; }
};

// A face with its outward normal at the centre.
struct FaceData : FaceGeometry {
  Vec3 normal = Vec3::Zero();
};

FaceData face_data(const Mesh& mesh, const Face& f) {
  FaceData d{face_geometry(mesh, f)};
  d.normal = centre_normal(mesh, d.nodes);
  return d;
}

Eigen::Matrix2Xd nodes_in_plane(const Mesh& mesh, const std::vector<int>& nodes, const Plane& plane) {
  Eigen::Matrix2Xd x(2, static_cast<Eigen::Index>(nodes.size()));
  for (std::size_t k = 0; k < nodes.size(); ++k)
    x.col(static_cast<Eigen::Index>(k)) = plane.project(mesh.coordinates.col(nodes[k]));
  return x;
}

Polygon corners_of(const Eigen::Matrix2Xd& nodes2d, bool reverse) {
  Polygon p;
  const int corners = face::corner_count(static_cast<int>(nodes2d.cols()));
  for (int k = 0; k < corners; ++k) p.push_back(nodes2d.col(k));
  if (reverse) std::reverse(p.begin(), p.end());
  return p;
}

bool convex_ccw(const Polygon& p) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % p.size()];
    const Vec2& c = p[(i + 2) % p.size()];
    if (!(cross2(b - a, c - b) > 0.0)) return false;
  }
  return true;
}

// One quadrature point of a segment: natural coordinates on both faces and the area weight.
struct SegmentPoint {
  Vec2 bottom, top;
  double weight = 0.0;
};

struct Segment {
  int top = 0;  // index into the top FaceData list
  double area = 0.0;
  std::vector<SegmentPoint> points;
};

// Dual-mortar coefficients A = D M⁻¹ of a linear bottom face (eq. M-2), and D.
struct DualBasis {
  Eigen::MatrixXd a;
  Eigen::VectorXd d;
};

DualBasis dual_basis(const Mesh& mesh, const std::vector<int>& nodes) {
  const int n = static_cast<int>(nodes.size());
  std::vector<face::RulePoint> rule;
  if (face::is_triangle(n)) {
    rule = face::triangle_rule(3);
  } else {
    for (const auto& [y, wy] : face::gauss_legendre(3))
      for (const auto& [x, wx] : face::gauss_legendre(3)) rule.push_back({x, y, wx * wy});
  }
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  for (const face::RulePoint& q : rule) {
    const face::Shape s = face::shape(n, q.xi, q.eta);
    const double w = q.weight * point_frame(mesh, nodes, s).det_j;
    const Eigen::Map<const Eigen::VectorXd> h(s.h.data(), n);
    m += w * h * h.transpose();
    d += w * h;
  }
  return {d.asDiagonal() * m.inverse(), d};
}

// The dual-mortar share of one bottom node, summed over the bottom faces around it.
struct NodeShare {
  double d = 0.0;        // D_i = Σ_e D̃_e,i: the node's contact area (eq. M-3)
  double full = 0.0;     // Σ_e ∫_e N_i dA: its area if every face around it were covered
  std::map<int, double> m;  // top node j → M_ij = Σ_e M̃_e,ij (eq. M-4)
  Vec3 normal = Vec3::Zero();  // Σ_e D̃_e,i n_e(node): the averaged normal (exact on flat faces)
  Vec3 t1 = Vec3::Zero();      // the owner face's t1 at the node
  int owner = -1, corner = -1;  // the first element with the node, and the node's corner in it
};

// One point per bottom node with D_i > D_full,i / 4 (a node on the rim of a partial overlap
// carries none: its weights M_ij / D_i would be ill-conditioned; its share counts as uncovered),
// grouped under the node's first element: g_i = R_i (Σ_j (M_ij / D_i) u_j^top − u_i^bottom).
void add_node_points(const Mesh& mesh, const std::map<int, NodeShare>& shares, Interface& result) {
  std::vector<std::vector<int>> owned(result.elements.size());
  for (const auto& [node, share] : shares)
    if (share.owner >= 0) owned[static_cast<std::size_t>(share.owner)].push_back(node);
  for (std::size_t e = 0; e < result.elements.size(); ++e) {
    InterfaceElement& element = result.elements[e];
    element.first_point = result.num_points();
    element.top_nodes.clear();
    std::map<int, int> local;
    for (int node : owned[e])
      for (const auto& [j, mij] : shares.at(node).m)
        if (local.emplace(j, 0).second) element.top_nodes.push_back(j);
    std::sort(element.top_nodes.begin(), element.top_nodes.end());
    for (std::size_t k = 0; k < element.top_nodes.size(); ++k) local[element.top_nodes[k]] = static_cast<int>(k);
    const int nb = static_cast<int>(element.bottom_nodes.size());
    for (int node : owned[e]) {
      const NodeShare& share = shares.at(node);
      if (!(share.d > 0.25 * share.full)) {
        result.uncovered_area += std::max(0.0, share.d);
        continue;
      }
      const Vec2 xi = face::corner(nb, share.corner);
      InterfacePoint p;
      p.element = static_cast<int>(e);
      p.natural = xi;
      p.shape = face::shape(nb, xi.x(), xi.y()).h;
      p.top_shape.assign(element.top_nodes.size(), 0.0);
      for (const auto& [j, mij] : share.m) p.top_shape[static_cast<std::size_t>(local.at(j))] = mij / share.d;
      const Vec3 n = share.normal.normalized();
      const Vec3 t1 = (share.t1 - share.t1.dot(n) * n).normalized();
      p.frame.row(0) = t1.transpose();
      p.frame.row(1) = n.cross(t1).transpose();
      p.frame.row(2) = n.transpose();
      p.area = share.d;
      p.position = mesh.coordinates.col(node);
      result.total_area += p.area;
      result.points.push_back(std::move(p));
    }
    element.num_points = result.num_points() - element.first_point;
  }
}

}  // namespace

void build_mortar(const Mesh& mesh, const std::vector<Face>& bottom_faces,
                  const std::vector<Face>& top_faces, const InterfaceOptions& options,
                  const std::string& who, Interface& result) {
  std::vector<FaceData> top;
  top.reserve(top_faces.size());
  double top_radius = 0.0;
  for (const Face& f : top_faces) {
    top.push_back(face_data(mesh, f));
    top_radius = std::max(top_radius, top.back().radius);
  }
  const FacesAlongX along_x(top);

  const bool nodal = options.integration == InterfaceIntegration::nodal;
  std::map<int, NodeShare> shares;  // dual mortar: bottom node → its summed share
  for (const Face& bf : bottom_faces) {
    const FaceData b = face_data(mesh, bf);
    const int nb = static_cast<int>(b.nodes.size());
    Plane plane;
    plane.origin = b.centroid;
    plane.n = b.normal;
    const Vec3 edge = mesh.coordinates.col(b.nodes[1]) - mesh.coordinates.col(b.nodes[0]);
    plane.e1 = (edge - edge.dot(plane.n) * plane.n).normalized();
    plane.e2 = plane.n.cross(plane.e1);
    const Eigen::Matrix2Xd b2d = nodes_in_plane(mesh, b.nodes, plane);
    const Polygon b_poly = corners_of(b2d, false);
    if (!convex_ccw(b_poly)) {
      throw std::invalid_argument(fmt::format("{}: {} is not a convex face (non-matching interfaces "
                                              "need convex faces)",
                                              who, describe(mesh, "bottom", bf)));
    }
    const double b_area = signed_area(b_poly);

    // Segments with every top face that overlaps b in b's plane.
    std::vector<Segment> segments;
    const double reach = b.radius + top_radius;
    along_x.for_each_in(b.centroid.x() - reach, b.centroid.x() + reach, [&](int t) {
      const FaceData& m = top[static_cast<std::size_t>(t)];
      if ((m.centroid - b.centroid).norm() > b.radius + m.radius) return false;
      if (!(m.normal.dot(b.normal) < -0.5)) return false;  // not facing b (within 60°)
      if (std::abs(b.normal.dot(m.centroid - b.centroid)) > b.radius) return false;  // far off the plane
      const Eigen::Matrix2Xd m2d = nodes_in_plane(mesh, m.nodes, plane);
      const Polygon overlap = clip_polygon(corners_of(m2d, true), b_poly);
      if (overlap.size() < 3) return false;
      const double area = signed_area(overlap);
      if (!(area > 1e-10 * b_area)) return false;
      Segment seg;
      seg.top = t;
      seg.area = area;
      const int nm = static_cast<int>(m.nodes.size());
      const bool quadratic = nb == 6 || nb == 8 || nm == 6 || nm == 8;
      const std::vector<face::RulePoint> rule = face::triangle_rule(quadratic ? 5 : 3);
      Vec2 c = Vec2::Zero();
      for (const Vec2& v : overlap) c += v;
      c /= static_cast<double>(overlap.size());
      for (std::size_t k = 0; k < overlap.size(); ++k) {
        const Vec2 p1 = overlap[k] - c, p2 = overlap[(k + 1) % overlap.size()] - c;
        const double tri_area = 0.5 * cross2(p1, p2);
        if (!(tri_area > 0.0)) continue;
        for (const face::RulePoint& q : rule) {
          const Vec2 x = c + q.xi * p1 + q.eta * p2;
          SegmentPoint sp;
          if (!face::inverse_map(b2d, x, sp.bottom) || !face::inverse_map(m2d, x, sp.top)) {
            throw std::invalid_argument(fmt::format(
                "{}: cannot locate a point of the overlap of {} and {} on both faces (degenerate "
                "face?)",
                who, describe(mesh, "bottom", bf), describe(mesh, "top", m.face)));
          }
          const face::Shape s = face::shape(nb, sp.bottom.x(), sp.bottom.y());
          const double cosine = std::abs(point_frame(mesh, b.nodes, s).frame.row(2).dot(plane.n));
          sp.weight = 2.0 * tri_area * q.weight / std::max(cosine, 1e-3);
          seg.points.push_back(sp);
        }
      }
      segments.push_back(std::move(seg));
      return false;
    });
    double covered = 0.0;
    for (const Segment& s : segments) covered += s.area;
    result.uncovered_area += std::max(0.0, b_area - covered);
    if (nodal) {  // every bottom face's ∫N_i dA, covered or not: the nodes' full shares
      const DualBasis full = dual_basis(mesh, b.nodes);
      for (int i = 0; i < nb; ++i) shares[b.nodes[static_cast<std::size_t>(i)]].full += full.d(i);
    }
    if (segments.empty()) continue;

    // The element: b with the union of the overlapping top faces' nodes.
    InterfaceElement element;
    element.bottom = bf;
    element.bottom_nodes = b.nodes;
    std::map<int, int> local;  // top node → index in element.top_nodes
    double largest = 0.0;
    for (const Segment& s : segments) {
      const FaceData& m = top[static_cast<std::size_t>(s.top)];
      element.top_faces.push_back(m.face);
      if (s.area > largest) largest = s.area, element.top = m.face;
      for (int n : m.nodes)
        if (local.emplace(n, static_cast<int>(element.top_nodes.size())).second) element.top_nodes.push_back(n);
    }
    const int element_index = static_cast<int>(result.elements.size());
    element.first_point = result.num_points();
    const std::size_t nt = element.top_nodes.size();
    const auto top_weights = [&](const Segment& s, const SegmentPoint& sp) {
      const FaceData& m = top[static_cast<std::size_t>(s.top)];
      const face::Shape sm = face::shape(static_cast<int>(m.nodes.size()), sp.top.x(), sp.top.y());
      std::vector<double> w(nt, 0.0);
      for (std::size_t k = 0; k < m.nodes.size(); ++k) w[static_cast<std::size_t>(local.at(m.nodes[k]))] = sm.h[k];
      return w;
    };

    if (!nodal) {
      for (const Segment& s : segments) {
        for (const SegmentPoint& sp : s.points) {
          const face::Shape sb = face::shape(nb, sp.bottom.x(), sp.bottom.y());
          InterfacePoint p;
          p.element = element_index;
          p.natural = sp.bottom;
          p.shape = sb.h;
          p.top_shape = top_weights(s, sp);
          p.frame = point_frame(mesh, b.nodes, sb).frame;
          p.area = sp.weight;
          for (std::size_t k = 0; k < b.nodes.size(); ++k) p.position += sb.h[k] * mesh.coordinates.col(b.nodes[k]);
          element.area += p.area;
          result.points.push_back(std::move(p));
        }
      }
    } else {
      // Dual mortar, eq. (M-2)-(M-4): the element's shares of its corners' D̃_i and M̃_ij, summed
      // per bottom node below (one point per node: one constraint per node, as Lagrange
      // multipliers on the bottom nodes would impose — per-element points would over-constrain
      // a stiff non-matching interface).
      const DualBasis dual = dual_basis(mesh, b.nodes);
      Eigen::VectorXd d_tilde = Eigen::VectorXd::Zero(nb);
      Eigen::MatrixXd m_tilde = Eigen::MatrixXd::Zero(nb, static_cast<Eigen::Index>(nt));
      for (const Segment& s : segments) {
        for (const SegmentPoint& sp : s.points) {
          const face::Shape sb = face::shape(nb, sp.bottom.x(), sp.bottom.y());
          const Eigen::VectorXd psi = dual.a * Eigen::Map<const Eigen::VectorXd>(sb.h.data(), nb);
          const std::vector<double> w = top_weights(s, sp);
          d_tilde += sp.weight * psi;
          m_tilde += sp.weight * psi * Eigen::Map<const Eigen::RowVectorXd>(w.data(), static_cast<Eigen::Index>(nt));
        }
      }
      for (int i = 0; i < nb; ++i) {
        NodeShare& share = shares[b.nodes[static_cast<std::size_t>(i)]];
        share.d += d_tilde(i);
        for (std::size_t k = 0; k < nt; ++k) share.m[element.top_nodes[k]] += m_tilde(i, static_cast<Eigen::Index>(k));
        const Vec2 xi = face::corner(nb, i);
        const PointFrame f = point_frame(mesh, b.nodes, face::shape(nb, xi.x(), xi.y()));
        share.normal += std::max(0.0, d_tilde(i)) * f.frame.row(2).transpose();
        if (share.owner < 0) share.owner = element_index, share.corner = i, share.t1 = f.frame.row(0).transpose();
        element.area += d_tilde(i);
      }
    }
    element.num_points = result.num_points() - element.first_point;
    if (!nodal && element.num_points == 0) continue;
    result.total_area += nodal ? 0.0 : element.area;
    result.elements.push_back(std::move(element));
  }
  if (nodal) add_node_points(mesh, shares, result);
  if (result.elements.empty()) {
    throw std::invalid_argument(fmt::format(
        "{}: surfaces '{}' and '{}' do not overlap: no top face lies over a bottom face (facing "
        "it, within a face size of its plane)",
        who, options.bottom_surface, options.top_surface));
  }
}

}  // namespace jointhb::fe::detail
