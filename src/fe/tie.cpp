// Bonded surfaces (fe/tie.hpp, docs/ties.md): the interface gap operator with a bilateral linear
// penalty, K_tie = k Gᵀ A G (TIE-1), k = α E_max / h (TIE-2).
#include "jointhb/fe/tie.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace jointhb::fe {

std::string TieOptions::validate() const {
  if (slave_surface.empty()) return "slave_surface must name a surface of the mesh";
  if (master_surface.empty()) return "master_surface must name a surface of the mesh";
  if (slave_surface == master_surface)
    return fmt::format("slave_surface and master_surface must differ (both '{}')", slave_surface);
  if (!(penalty_factor >= 1.0 && penalty_factor <= 1e6))
    return fmt::format("penalty_factor = {} must lie in [1, 1e6]", penalty_factor);
  if (!(match_tolerance > 0.0 && match_tolerance <= 0.1))
    return fmt::format("match_tolerance = {} must lie in (0, 0.1]", match_tolerance);
  return {};
}

int Tie::num_tied_points() const {
  return static_cast<int>((point_area.array() > 0.0).count());
}

namespace {

// Nodal integration where it is defined (linear faces: decoupled node pairs, docs/zero-thickness-elements.md §4),
// Gauss for quadratic faces (interface.hpp refuses nodal integration of quad8 faces).
InterfaceIntegration integration_for(const Mesh& mesh, const std::string& surface) {
  const auto it = mesh.surfaces.find(surface);
  if (it == mesh.surfaces.end() || it->second.empty()) return InterfaceIntegration::nodal;
  const Face& face = it->second.front();
  if (face.element < 0 || face.element >= mesh.num_elements()) return InterfaceIntegration::nodal;
  return is_quadratic(mesh.elements[static_cast<std::size_t>(face.element)].type) ? InterfaceIntegration::gauss
                                                                                  : InterfaceIntegration::nodal;
}

// E_max and h of eq. (TIE-2): the largest Young's modulus and the smallest edge of the elements
// owning the tie's faces on either side.
void set_penalty(const Mesh& mesh, const std::vector<Material>& material_per_part, Tie& tie) {
  std::set<int> owners;
  for (const InterfaceElement& e : tie.geometry.elements) owners.insert({e.bottom.element, e.top.element});
  double youngs = 0.0, edge = std::numeric_limits<double>::infinity();
  for (int index : owners) {
    const Element& element = mesh.elements[static_cast<std::size_t>(index)];
    youngs = std::max(youngs, material_per_part[static_cast<std::size_t>(element.part)].youngs_modulus);
    for (const auto& [a, b] : edge_corners(element.type))
      edge = std::min(edge, (mesh.coordinates.col(element.nodes[static_cast<std::size_t>(a)]) -
                             mesh.coordinates.col(element.nodes[static_cast<std::size_t>(b)]))
                                .norm());
  }
  tie.youngs_modulus = youngs;
  tie.element_size = edge;
  tie.penalty = tie.penalty_factor * youngs / edge;
}

// Zeroes the area of every point whose slave node is not in `tied_nodes` (sorted). Needs points
// at the slave nodes (h_i(ξ_p) = δ_ik for one corner k), which nodal integration gives.
void restrict_to_nodes(const std::string& who, const std::vector<int>& tied_nodes, Tie& tie) {
  const Interface& g = tie.geometry;
  for (int p = 0; p < g.num_points(); ++p) {
    const InterfacePoint& point = g.points[static_cast<std::size_t>(p)];
    const InterfaceElement& element = g.elements[static_cast<std::size_t>(point.element)];
    int node = -1;
    bool at_node = true;
    for (std::size_t k = 0; k < element.bottom_nodes.size(); ++k) {
      if (std::abs(point.shape[k] - 1.0) <= 1e-12) node = element.bottom_nodes[k];
      else if (std::abs(point.shape[k]) > 1e-12) at_node = false;
    }
    if (!at_node || node < 0)
      throw std::invalid_argument(fmt::format(
          "{}: a tied node set needs the tie's points at the slave nodes (nodal integration of "
          "linear quadrilateral faces); point {} is not at a node",
          who, p));
    if (!std::binary_search(tied_nodes.begin(), tied_nodes.end(), node)) tie.point_area[p] = 0.0;
  }
  if (!(tie.point_area.array() > 0.0).any())
    throw std::invalid_argument(fmt::format(
        "{}: no node of the tied node set lies on the slave surface '{}'", who, tie.slave_surface));
}

}  // namespace

Tie build_tie(const Mesh& mesh, const std::vector<Material>& material_per_part, const TieOptions& options) {
  const std::string who = fmt::format("tie '{}'", options.name);
  if (const std::string problem = options.validate(); !problem.empty())
    throw std::invalid_argument(who + ": " + problem);
  if (material_per_part.size() != mesh.parts.size())
    throw std::invalid_argument(fmt::format("{}: {} materials for {} parts", who, material_per_part.size(),
                                            mesh.parts.size()));
  Tie tie;
  tie.name = options.name;
  tie.slave_surface = options.slave_surface;
  tie.master_surface = options.master_surface;
  tie.penalty_factor = options.penalty_factor;

  InterfaceOptions io;
  io.name = options.name;
  io.bottom_surface = options.slave_surface;
  io.top_surface = options.master_surface;
  io.integration = integration_for(mesh, options.slave_surface);
  io.match_tolerance = options.match_tolerance;
  io.meshes = InterfaceMeshes::automatic;
  try {
    tie.geometry = build_interface(mesh, io);
  } catch (const std::invalid_argument& error) {
    // The interface's message names its bottom and top: say which is which.
    std::string message = error.what();
    const std::string prefix = fmt::format("interface '{}': ", options.name);
    if (message.starts_with(prefix)) message.erase(0, prefix.size());
    throw std::invalid_argument(fmt::format("{} (slave = bottom, master = top): {}", who, message));
  }

  const Interface& g = tie.geometry;
  tie.point_area.resize(g.num_points());
  for (int p = 0; p < g.num_points(); ++p) tie.point_area[p] = g.points[static_cast<std::size_t>(p)].area;
  if (!options.tied_nodes.empty()) {
    std::vector<int> nodes = options.tied_nodes;
    std::sort(nodes.begin(), nodes.end());
    restrict_to_nodes(who, nodes, tie);
  }
  tie.area = tie.point_area.sum();
  set_penalty(mesh, material_per_part, tie);
  return tie;
}

// K_tie = k Gᵀ A G, eq. (TIE-1), from the rows of G alone (whatever built them: coincident node
// pairs or mortar segments), one dense block per run of points of one interface element, made
// exactly symmetric.
void add_tie_stiffness(const Tie& tie, std::vector<Eigen::Triplet<double>>& triplets) {
  const Interface& g = tie.geometry;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = g.gap_operator;
  const int points = g.num_points();
  std::vector<int> columns;
  for (int first = 0; first < points;) {
    int last = first + 1;
    while (last < points && g.points[static_cast<std::size_t>(last)].element == g.points[static_cast<std::size_t>(first)].element) ++last;
    columns.clear();
    for (int r = 3 * first; r < 3 * last; ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows, r); it; ++it)
        columns.push_back(static_cast<int>(it.col()));
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const auto n = static_cast<Eigen::Index>(columns.size());
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(3 * (last - first), n);
    Eigen::VectorXd weight(3 * (last - first));
    for (int r = 3 * first; r < 3 * last; ++r) {
      weight[r - 3 * first] = tie.penalty * tie.point_area[r / 3];
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows, r); it; ++it) {
        const auto c = std::lower_bound(columns.begin(), columns.end(), static_cast<int>(it.col())) - columns.begin();
        block(r - 3 * first, c) = it.value();
      }
    }
    if ((weight.array() > 0.0).any()) {
      Eigen::MatrixXd k = block.transpose() * weight.asDiagonal() * block;
      k = 0.5 * (k + k.transpose()).eval();
      for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i)
          if (k(i, j) != 0.0) triplets.emplace_back(columns[static_cast<std::size_t>(i)], columns[static_cast<std::size_t>(j)], k(i, j));
    }
    first = last;
  }
}

Eigen::SparseMatrix<double> tie_stiffness(std::span<const Tie> ties, int num_dofs) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (const Tie& tie : ties) add_tie_stiffness(tie, triplets);
  Eigen::SparseMatrix<double> k(num_dofs, num_dofs);
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

}  // namespace jointhb::fe
