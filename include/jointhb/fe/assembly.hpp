#pragma once
// Assembly of the global stiffness and consistent mass of a Mesh, and the map between the full
// DOF vector (DOF 3i + d = node i, axis d) and the free DOFs left by fixed (Dirichlet) nodes.
//
//   K = Σ_e L_eᵀ K_e L_e,   M = Σ_e L_eᵀ M_e L_e                                   (1)
// with K_e, M_e of solid_element.hpp and L_e the gather of element e's DOFs.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <string>
#include <vector>

#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

struct AssemblyOptions {
  /// OpenMP threads computing element matrices; 0 = the OpenMP default. The result is bit-identical
  /// for every thread count (elements are computed in parallel, summed serially in element order).
  int threads = 0;

  /// Empty when valid, else a message naming the field.
  [[nodiscard]] std::string validate() const;
};

struct StructuralMatrices {
  /// Full symmetric matrices (both triangles stored), num_dofs × num_dofs, compressed, with the
  /// nodal 3×3 block pattern of the mesh (explicit zeros possible inside blocks).
  Eigen::SparseMatrix<double> stiffness;  ///< [N/m]
  Eigen::SparseMatrix<double> mass;       ///< [kg]
  double total_mass = 0.0;                ///< Σ_e ρ_e V_e [kg]
  double total_volume = 0.0;              ///< Σ_e V_e [m³]
  double seconds = 0.0;                   ///< wall time of assemble()
};

/// Eq. (1). `material_per_part[p]` is the material of Mesh::parts[p]. Throws std::invalid_argument
/// when the counts differ, a material or the options are invalid, an element references a
/// non-existent node or part, or an element has det J ≤ 0 (the message gives its external id).
[[nodiscard]] StructuralMatrices assemble(const Mesh& mesh,
                                          const std::vector<Material>& material_per_part,
                                          const AssemblyOptions& options = {});

/// Nodes whose selected directions are fixed (u_d = 0).
struct FixedNodes {
  std::vector<int> nodes;  ///< node indices (e.g. a Mesh::node_sets entry)
  std::array<bool, 3> directions{true, true, true};  ///< fixed x, y, z
};

/// The free DOFs of a mesh with some DOFs fixed; free DOFs keep their relative order.
struct DofMap {
  std::vector<int> free_of_full;  ///< full DOF → free index, −1 if fixed
  std::vector<int> full_of_free;  ///< free index → full DOF

  /// Throws std::invalid_argument for a node index outside [0, num_nodes).
  [[nodiscard]] static DofMap from_fixed_nodes(int num_nodes, const std::vector<FixedNodes>& fixed);

  [[nodiscard]] int num_full() const { return static_cast<int>(free_of_full.size()); }
  [[nodiscard]] int num_free() const { return static_cast<int>(full_of_free.size()); }

  /// The full vector with zeros at the fixed DOFs.
  [[nodiscard]] Eigen::VectorXd expand(const Eigen::VectorXd& free) const;
  /// The free entries of a full vector.
  [[nodiscard]] Eigen::VectorXd restrict(const Eigen::VectorXd& full) const;
  /// The free–free block of a full matrix (compressed, same storage order).
  [[nodiscard]] Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& full) const;
};

}  // namespace jointhb::fe
