#include "jointhb/fe/mesh_checks.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "jointhb/fe/hexahedron.hpp"
#include "jointhb/fe/simplex_elements.hpp"

namespace jointhb::fe {

std::string MeshCheckOptions::validate() const {
  if (!(min_jacobian_ratio > 0.0 && min_jacobian_ratio < 1.0)) {
    return fmt::format("min_jacobian_ratio: must lie in (0, 1), got {}", min_jacobian_ratio);
  }
  return {};
}

namespace {

// J = ∂x/∂ξ = Σ_a x_a (∂N_a/∂ξ)ᵀ of element `element` at the reference point xi.
Eigen::Matrix3d jacobian(const Mesh& mesh, int element, const Eigen::Vector3d& xi) {
  const Element& e = mesh.elements[static_cast<std::size_t>(element)];
  const Eigen::Matrix3Xd dn = shape_derivatives(e.type, xi);
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  for (int a = 0; a < node_count(e.type); ++a)
    j += mesh.coordinates.col(e.nodes[static_cast<std::size_t>(a)]) * dn.col(a).transpose();
  return j;
}

// The points where det J is sampled (mesh_checks.hpp).
std::vector<Eigen::Vector3d> sample_points(ElementType type) {
  std::vector<Eigen::Vector3d> points;
  if (family(type) != ElementFamily::hexahedron) {
    // Linear tetrahedra and wedges: the corners and the centre; quadratic ones: the points of
    // the mass rule (as the 3×3×3 rule for hex20).
    if (!is_quadratic(type)) {
      for (int a = 0; a < node_count(type); ++a)
        points.push_back(simplex_node_natural_coordinates(type, a));
      points.push_back(centre_natural_coordinates(type));
    } else {
      for (const GaussPoint& g : integration_rule(type, true)) points.push_back(g.xi);
    }
    return points;
  }
  if (node_count(type) == 8) {
    for (int a = 0; a < 8; ++a) points.push_back(hex_node_natural_coordinates(a));
    points.emplace_back(0.0, 0.0, 0.0);
  } else {
    for (const GaussPoint& g : hex_gauss_rule(3)) points.push_back(g.xi);
  }
  return points;
}

// The longest of the element's corner-to-corner edges (12, 6 or 9).
double longest_edge(const Mesh& mesh, const Element& element) {
  double longest = 0.0;
  for (const auto& [a, b] : edge_corners(element.type)) {
    longest = std::max(longest, (mesh.coordinates.col(element.nodes[static_cast<std::size_t>(a)]) -
                                 mesh.coordinates.col(element.nodes[static_cast<std::size_t>(b)]))
                                    .norm());
  }
  return longest;
}

struct DetRange {
  double min = 0.0;
  double max = 0.0;
};

DetRange det_range(const Mesh& mesh, int element) {
  DetRange range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Eigen::Vector3d& xi :
       sample_points(mesh.elements[static_cast<std::size_t>(element)].type)) {
    const double det = jacobian(mesh, element, xi).determinant();
    range.min = std::min(range.min, det);
    range.max = std::max(range.max, det);
  }
  return range;
}

std::string node_name(const Mesh& mesh, int n) {
  const auto i = static_cast<std::size_t>(n);
  return n >= 0 && i < mesh.node_ids.size() ? fmt::format("node {}", mesh.node_ids[i])
                                            : fmt::format("node index {}", n);
}

void check_sets(const Mesh& mesh, std::vector<MeshProblem>& problems) {
  const auto bad = [&](std::string message) {
    problems.push_back({MeshProblem::Kind::bad_set, -1, std::move(message)});
  };
  for (const auto& [name, nodes] : mesh.node_sets) {
    for (int n : nodes) {
      if (n < 0 || n >= mesh.num_nodes()) {
        bad(fmt::format("node set '{}': node index {} outside [0, {})", name, n, mesh.num_nodes()));
        break;
      }
    }
  }
  for (const auto& [name, elements] : mesh.element_sets) {
    for (int e : elements) {
      if (e < 0 || e >= mesh.num_elements()) {
        bad(fmt::format("element set '{}': element index {} outside [0, {})", name, e,
                        mesh.num_elements()));
        break;
      }
    }
  }
  for (const auto& [name, faces] : mesh.surfaces) {
    for (const Face& f : faces) {
      if (f.element < 0 || f.element >= mesh.num_elements() || f.face < 0 ||
          f.face >= face_count(mesh.elements[static_cast<std::size_t>(f.element)].type)) {
        bad(fmt::format("surface '{}': face (element index {}, face {}) does not exist", name,
                        f.element, f.face));
        break;
      }
    }
  }
}

}  // namespace

double jacobian_ratio(const Mesh& mesh, int element) {
  const DetRange range = det_range(mesh, element);
  const double scale = std::max(std::abs(range.min), std::abs(range.max));
  return scale > 0.0 ? range.min / scale : 0.0;
}

double element_volume(const Mesh& mesh, int element) {
  double volume = 0.0;
  const ElementType type = mesh.elements.at(static_cast<std::size_t>(element)).type;
  for (const GaussPoint& g : family(type) == ElementFamily::hexahedron ? hex_gauss_rule(3)
                                                                        : integration_rule(type, true))
    volume += g.weight * jacobian(mesh, element, g.xi).determinant();
  return volume;
}

std::vector<MeshProblem> check_mesh(const Mesh& mesh, const MeshCheckOptions& options) {
  if (const std::string message = options.validate(); !message.empty()) {
    throw std::invalid_argument("check_mesh: " + message);
  }
  std::vector<MeshProblem> problems;
  if (mesh.node_ids.size() != static_cast<std::size_t>(mesh.num_nodes()) ||
      mesh.element_ids.size() != mesh.elements.size()) {
    problems.push_back({MeshProblem::Kind::inconsistent_sizes, -1,
                        fmt::format("{} node ids for {} nodes, {} element ids for {} elements",
                                    mesh.node_ids.size(), mesh.num_nodes(), mesh.element_ids.size(),
                                    mesh.elements.size())});
  }
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Element& element = mesh.elements[static_cast<std::size_t>(e)];
    if (element.part < 0 || element.part >= static_cast<int>(mesh.parts.size())) {
      problems.push_back({MeshProblem::Kind::bad_part, e,
                          fmt::format("{}: part index {} outside [0, {})", element_name(mesh, e),
                                      element.part, mesh.parts.size())});
    }
    bool nodes_ok = true;
    const auto nodes = element.node_span();
    for (std::size_t a = 0; a < nodes.size(); ++a) {
      if (nodes[a] < 0 || nodes[a] >= mesh.num_nodes()) {
        problems.push_back({MeshProblem::Kind::node_out_of_range, e,
                            fmt::format("{}: local node {} has index {} outside [0, {})",
                                        element_name(mesh, e), a + 1, nodes[a], mesh.num_nodes())});
        nodes_ok = false;
        continue;
      }
      for (std::size_t b = 0; b < a; ++b) {
        if (nodes[b] == nodes[a]) {
          problems.push_back(
              {MeshProblem::Kind::repeated_node, e,
               fmt::format("{}: {} appears twice (local nodes {} and {})", element_name(mesh, e),
                           node_name(mesh, nodes[a]), b + 1, a + 1)});
          nodes_ok = false;
        }
      }
    }
    if (!nodes_ok) continue;  // the shape checks need distinct nodes in range

    const DetRange range = det_range(mesh, e);
    const double edge = longest_edge(mesh, element);
    const double scale = std::max(std::abs(range.min), std::abs(range.max));
    const double ratio = scale > 0.0 ? range.min / scale : 0.0;
    if (ratio < -options.min_jacobian_ratio) {
      problems.push_back(
          {MeshProblem::Kind::inverted_element, e,
           fmt::format("{} ({}): inverted, min det J = {:.3g} (min/max det J ratio {:.3g}); check "
                       "the node order",
                       element_name(mesh, e), abaqus_name(element.type), range.min, ratio)});
    } else if (ratio < options.min_jacobian_ratio ||
               range.max < options.min_jacobian_ratio * std::pow(edge / 2.0, 3)) {
      problems.push_back(
          {MeshProblem::Kind::degenerate_element, e,
           fmt::format("{} ({}): degenerate, min/max det J ratio {:.3g}, max det J {:.3g} for a "
                       "longest edge of {:.3g} m",
                       element_name(mesh, e), abaqus_name(element.type), ratio, range.max, edge)});
    }
  }
  check_sets(mesh, problems);
  return problems;
}

std::vector<std::vector<int>> connected_components(const Mesh& mesh) {
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int n : mesh.elements[static_cast<std::size_t>(e)].node_span()) {
      if (n < 0 || n >= mesh.num_nodes()) {
        throw std::invalid_argument(
            fmt::format("connected_components: {} has node index {} "
                        "outside [0, {}) (run check_mesh first)",
                        element_name(mesh, e), n, mesh.num_nodes()));
      }
    }
  }
  // Union–find over nodes; an element joins all its nodes.
  std::vector<int> parent(static_cast<std::size_t>(mesh.num_nodes()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int n) {
    while (parent[static_cast<std::size_t>(n)] != n) {
      auto& p = parent[static_cast<std::size_t>(n)];
      p = parent[static_cast<std::size_t>(p)];  // path halving
      n = p;
    }
    return n;
  };
  for (const Element& element : mesh.elements) {
    const auto nodes = element.node_span();
    for (std::size_t a = 1; a < nodes.size(); ++a) {
      const int ra = find(nodes[0]);
      const int rb = find(nodes[a]);
      if (ra != rb) parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    }
  }
  std::vector<std::vector<int>> components;
  std::vector<int> component_of_root(parent.size(), -1);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const int root = find(mesh.elements[static_cast<std::size_t>(e)].nodes[0]);
    int& c = component_of_root[static_cast<std::size_t>(root)];
    if (c < 0) {
      c = static_cast<int>(components.size());
      components.emplace_back();
    }
    components[static_cast<std::size_t>(c)].push_back(e);
  }
  return components;
}

}  // namespace jointhb::fe
