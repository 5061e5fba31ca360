// Global assembly, eq. (1) of assembly.hpp, and the free-DOF map.
//
// The sparsity pattern is built once from the node adjacency (3×3 blocks of nodes sharing an
// element), in compressed column form with sorted rows; element matrices are then added straight
// into the value arrays. Element matrices are computed in parallel in chunks and added serially in
// element order, so the floating-point sums — and the result — do not depend on the thread count.
#include "jointhb/fe/assembly.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <stdexcept>

#include "../support/stopwatch.hpp"
#include "solid_element_kernel.hpp"

namespace jointhb::fe {

std::string AssemblyOptions::validate() const {
  if (threads < 0) return fmt::format("AssemblyOptions::threads = {} must be >= 0", threads);
  return {};
}

namespace {

// Node adjacency (sorted, including the node itself) in CSR form.
struct NodeGraph {
  std::vector<long> offsets;  // neighbours of node i: indices [offsets[i], offsets[i+1])
  std::vector<int> neighbours;
};

NodeGraph node_graph(const Mesh& mesh) {
  const auto n = static_cast<std::size_t>(mesh.num_nodes());
  // Elements of each node (CSR).
  std::vector<long> element_offsets(n + 1, 0);
  for (const Element& element : mesh.elements)
    for (int node : element.node_span()) ++element_offsets[static_cast<std::size_t>(node) + 1];
  for (std::size_t i = 0; i < n; ++i) element_offsets[i + 1] += element_offsets[i];
  std::vector<int> elements_of(static_cast<std::size_t>(element_offsets[n]));
  {
    std::vector<long> fill(element_offsets.begin(), element_offsets.end() - 1);
    for (int e = 0; e < mesh.num_elements(); ++e)
      for (int node : mesh.elements[static_cast<std::size_t>(e)].node_span())
        elements_of[static_cast<std::size_t>(fill[static_cast<std::size_t>(node)]++)] = e;
  }
  NodeGraph g;
  g.offsets.assign(n + 1, 0);
  std::vector<int> scratch;
  for (std::size_t i = 0; i < n; ++i) {
    scratch.clear();
    scratch.push_back(static_cast<int>(i));
    for (long k = element_offsets[i]; k < element_offsets[i + 1]; ++k)
      for (int node :
           mesh.elements[static_cast<std::size_t>(elements_of[static_cast<std::size_t>(k)])]
               .node_span())
        scratch.push_back(node);
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    g.neighbours.insert(g.neighbours.end(), scratch.begin(), scratch.end());
    g.offsets[i + 1] = static_cast<long>(g.neighbours.size());
  }
  return g;
}

void check_mesh(const Mesh& mesh, const std::vector<Material>& materials) {
  if (materials.size() != mesh.parts.size())
    throw std::invalid_argument(
        fmt::format("assemble: {} materials given for {} parts (one material per part is required)",
                    materials.size(), mesh.parts.size()));
  for (std::size_t p = 0; p < materials.size(); ++p)
    if (const std::string message = materials[p].validate(); !message.empty())
      throw std::invalid_argument(fmt::format("assemble: part '{}': {}", mesh.parts[p], message));
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Element& element = mesh.elements[static_cast<std::size_t>(e)];
    if (element.part < 0 || element.part >= static_cast<int>(mesh.parts.size()))
      throw std::invalid_argument(fmt::format("assemble: {} has part index {} (mesh has {} parts)",
                                              element_name(mesh, e), element.part,
                                              mesh.parts.size()));
    for (int node : element.node_span())
      if (node < 0 || node >= mesh.num_nodes())
        throw std::invalid_argument(
            fmt::format("assemble: {} references node index {} (mesh has "
                        "{} nodes)",
                        element_name(mesh, e), node, mesh.num_nodes()));
  }
}

}  // namespace

StructuralMatrices assemble(const Mesh& mesh, const std::vector<Material>& material_per_part,
                            const AssemblyOptions& options) {
  const auto start = support::Clock::now();
  if (const std::string message = options.validate(); !message.empty())
    throw std::invalid_argument(message);
  check_mesh(mesh, material_per_part);

  std::vector<detail::IsotropicConstants> constants;
  for (const Material& m : material_per_part)
    constants.push_back({m.lame_lambda(), m.shear_modulus(), m.density});

  // Compressed-column pattern: column 3b + d holds, for each neighbour a of node b (sorted), the
  // rows 3a, 3a + 1, 3a + 2; so entry (3a + i, 3b + d) sits at outer[3b + d] + 3 k + i, with k the
  // position of a among b's neighbours.
  const NodeGraph graph = node_graph(mesh);
  const int num_dofs = mesh.num_dofs();
  std::vector<int> outer(static_cast<std::size_t>(num_dofs) + 1, 0);
  for (int b = 0; b < mesh.num_nodes(); ++b) {
    const auto degree = static_cast<int>(graph.offsets[static_cast<std::size_t>(b) + 1] -
                                         graph.offsets[static_cast<std::size_t>(b)]);
    for (int d = 0; d < 3; ++d)
      outer[static_cast<std::size_t>(3 * b + d + 1)] =
          outer[static_cast<std::size_t>(3 * b + d)] + 3 * degree;
  }
  const auto nnz = static_cast<std::size_t>(outer.back());
  std::vector<int> inner(nnz);
  for (int b = 0; b < mesh.num_nodes(); ++b)
    for (int d = 0; d < 3; ++d) {
      auto position = static_cast<std::size_t>(outer[static_cast<std::size_t>(3 * b + d)]);
      for (long k = graph.offsets[static_cast<std::size_t>(b)];
           k < graph.offsets[static_cast<std::size_t>(b) + 1]; ++k)
        for (int i = 0; i < 3; ++i)
          inner[position++] = 3 * graph.neighbours[static_cast<std::size_t>(k)] + i;
    }
  std::vector<double> k_values(nnz, 0.0), m_values(nnz, 0.0);

  // Element matrices in parallel, chunk by chunk (bounded memory), then the serial scatter.
  constexpr int kChunk = 2048;
  constexpr int kMaxSize = 60 * 60;
  std::vector<double> k_buffer(static_cast<std::size_t>(kChunk) * kMaxSize);
  std::vector<double> m_buffer(static_cast<std::size_t>(kChunk) * kMaxSize);
  std::vector<double> volumes(kChunk);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  StructuralMatrices result;
  for (int first = 0; first < mesh.num_elements(); first += kChunk) {
    const int count = std::min(kChunk, mesh.num_elements() - first);
#pragma omp parallel for num_threads(threads) schedule(dynamic, 64)
    for (int i = 0; i < count; ++i) {
      const Element& element = mesh.elements[static_cast<std::size_t>(first + i)];
      const int n = node_count(element.type);
      double x[3 * 20];
      for (int a = 0; a < n; ++a)
        for (int d = 0; d < 3; ++d)
          x[3 * a + d] = mesh.coordinates(d, element.nodes[static_cast<std::size_t>(a)]);
      const auto offset = static_cast<std::size_t>(i) * kMaxSize;
      volumes[static_cast<std::size_t>(i)] =
          detail::element_kernel(element.type, x, constants[static_cast<std::size_t>(element.part)],
                                 k_buffer.data() + offset, m_buffer.data() + offset);
    }
    for (int i = 0; i < count; ++i) {
      const int e = first + i;
      const Element& element = mesh.elements[static_cast<std::size_t>(e)];
      const double volume = volumes[static_cast<std::size_t>(i)];
      if (!(volume > 0.0))
        throw std::invalid_argument(fmt::format(
            "assemble: {} ({}): det J <= 0 at an integration point or the centre (inverted or "
            "degenerate element)",
            element_name(mesh, e), abaqus_name(element.type)));
      result.total_volume += volume;
      result.total_mass += constants[static_cast<std::size_t>(element.part)].density * volume;
      const int n = node_count(element.type);
      const int size = 3 * n;
      const double* ke = k_buffer.data() + static_cast<std::size_t>(i) * kMaxSize;
      const double* me = m_buffer.data() + static_cast<std::size_t>(i) * kMaxSize;
      for (int b = 0; b < n; ++b) {
        const int node_b = element.nodes[static_cast<std::size_t>(b)];
        const int* begin =
            graph.neighbours.data() + graph.offsets[static_cast<std::size_t>(node_b)];
        const int* end =
            graph.neighbours.data() + graph.offsets[static_cast<std::size_t>(node_b) + 1];
        for (int a = 0; a < n; ++a) {
          const int node_a = element.nodes[static_cast<std::size_t>(a)];
          const auto k = static_cast<int>(std::lower_bound(begin, end, node_a) - begin);
          for (int d = 0; d < 3; ++d) {
            const auto base =
                static_cast<std::size_t>(outer[static_cast<std::size_t>(3 * node_b + d)] + 3 * k);
            const auto column =
                static_cast<std::size_t>(3 * b + d) * static_cast<std::size_t>(size);
            for (int r = 0; r < 3; ++r) {
              k_values[base + static_cast<std::size_t>(r)] +=
                  ke[column + static_cast<std::size_t>(3 * a + r)];
              m_values[base + static_cast<std::size_t>(r)] +=
                  me[column + static_cast<std::size_t>(3 * a + r)];
            }
          }
        }
      }
    }
  }

  const auto nnz_index = static_cast<Eigen::Index>(nnz);
  result.stiffness = Eigen::Map<const Eigen::SparseMatrix<double>>(
      num_dofs, num_dofs, nnz_index, outer.data(), inner.data(), k_values.data());
  result.mass = Eigen::Map<const Eigen::SparseMatrix<double>>(
      num_dofs, num_dofs, nnz_index, outer.data(), inner.data(), m_values.data());
  result.seconds = support::seconds_since(start);
  return result;
}

DofMap DofMap::from_fixed_nodes(int num_nodes, const std::vector<FixedNodes>& fixed) {
  if (num_nodes < 0) throw std::invalid_argument("DofMap: num_nodes must be >= 0");
  std::vector<char> is_fixed(static_cast<std::size_t>(3 * num_nodes), 0);
  for (std::size_t s = 0; s < fixed.size(); ++s)
    for (int node : fixed[s].nodes) {
      if (node < 0 || node >= num_nodes)
        throw std::invalid_argument(
            fmt::format("DofMap: fixed node set {} contains node index {} (mesh has {} nodes)", s,
                        node, num_nodes));
      for (int d = 0; d < 3; ++d)
        if (fixed[s].directions[static_cast<std::size_t>(d)])
          is_fixed[static_cast<std::size_t>(3 * node + d)] = 1;
    }
  DofMap map;
  map.free_of_full.assign(is_fixed.size(), -1);
  for (std::size_t i = 0; i < is_fixed.size(); ++i)
    if (!is_fixed[i]) {
      map.free_of_full[i] = static_cast<int>(map.full_of_free.size());
      map.full_of_free.push_back(static_cast<int>(i));
    }
  return map;
}

Eigen::VectorXd DofMap::expand(const Eigen::VectorXd& free) const {
  if (free.size() != num_free())
    throw std::invalid_argument(
        fmt::format("DofMap::expand: vector of size {}, must be {}", free.size(), num_free()));
  Eigen::VectorXd full = Eigen::VectorXd::Zero(num_full());
  for (int i = 0; i < num_free(); ++i) full(full_of_free[static_cast<std::size_t>(i)]) = free(i);
  return full;
}

Eigen::VectorXd DofMap::restrict(const Eigen::VectorXd& full) const {
  if (full.size() != num_full())
    throw std::invalid_argument(
        fmt::format("DofMap::restrict: vector of size {}, must be {}", full.size(), num_full()));
  Eigen::VectorXd free(num_free());
  for (int i = 0; i < num_free(); ++i) free(i) = full(full_of_free[static_cast<std::size_t>(i)]);
  return free;
}

Eigen::SparseMatrix<double> DofMap::restrict(const Eigen::SparseMatrix<double>& full) const {
  if (full.rows() != num_full() || full.cols() != num_full())
    throw std::invalid_argument(fmt::format("DofMap::restrict: matrix {}×{}, must be {}×{}",
                                            full.rows(), full.cols(), num_full(), num_full()));
  // The free numbering is monotone in the full one, so each kept column keeps its sorted rows.
  Eigen::SparseMatrix<double> free(num_free(), num_free());
  free.reserve(full.nonZeros());
  for (int j = 0; j < num_free(); ++j) {
    free.startVec(j);
    for (Eigen::SparseMatrix<double>::InnerIterator it(full,
                                                       full_of_free[static_cast<std::size_t>(j)]);
         it; ++it) {
      const int i = free_of_full[static_cast<std::size_t>(it.index())];
      if (i >= 0) free.insertBack(i, j) = it.value();
    }
  }
  free.finalize();
  return free;
}

}  // namespace jointhb::fe
