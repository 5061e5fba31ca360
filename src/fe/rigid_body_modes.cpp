// Rigid-body modes of a solid mesh (fe/rigid_body_modes.hpp).
#include "jointhb/fe/rigid_body_modes.hpp"

namespace jointhb::fe {

Eigen::MatrixXd rigid_body_modes(const Mesh& mesh) {
  const int nodes = mesh.num_nodes();
  Eigen::MatrixXd modes = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(nodes), 6);
  if (nodes == 0) return modes;
  const Eigen::Vector3d centroid = mesh.coordinates.rowwise().mean();
  const double size = (mesh.coordinates.colwise() - centroid).cwiseAbs().maxCoeff();
  const double scale = size > 0.0 ? 1.0 / size : 1.0;
  for (int i = 0; i < nodes; ++i) {
    const Eigen::Vector3d x = scale * (mesh.coordinates.col(i) - centroid);
    const Eigen::Index row = 3 * static_cast<Eigen::Index>(i);
    for (int d = 0; d < 3; ++d) modes(row + d, d) = 1.0;
    for (int a = 0; a < 3; ++a) modes.block<3, 1>(row, 3 + a) = Eigen::Vector3d::Unit(a).cross(x);  // e_a × x
  }
  return modes;
}

Eigen::MatrixXd rigid_body_modes(const Mesh& mesh, const DofMap& dofs) {
  const Eigen::MatrixXd full = rigid_body_modes(mesh);
  Eigen::MatrixXd free(dofs.num_free(), full.cols());
  for (Eigen::Index j = 0; j < full.cols(); ++j) free.col(j) = dofs.restrict(Eigen::VectorXd(full.col(j)));
  return free;
}

IterativeSettings with_rigid_body_modes(IterativeSettings settings, LinearSolver backend,
                                        const Mesh& mesh, const DofMap& dofs) {
  if (backend == LinearSolver::cg && settings.near_null_space.size() == 0)
    settings.near_null_space = rigid_body_modes(mesh, dofs);
  return settings;
}

}  // namespace jointhb::fe
