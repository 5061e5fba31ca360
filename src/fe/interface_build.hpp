#pragma once
// Shared by the matching (interface.cpp) and non-matching (interface_mortar.cpp) construction of
// zero-thickness interfaces.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "face_shapes.hpp"
#include "jointhb/fe/interface.hpp"

namespace jointhb::fe::detail {

/// "bottom face of element 12 (S2)"
[[nodiscard]] std::string describe(const Mesh& mesh, const char* side, const Face& face);

/// External id of node `node` (index + 1 when the mesh has none).
[[nodiscard]] long external_node_id(const Mesh& mesh, int node);

/// The point's frame (rows t1 = ∂x/∂ξ normalised, t2 = n × t1, n = outward normal) and
/// det J = |∂x/∂ξ × ∂x/∂η| of the face with nodes `nodes` at shape values `s`. det_j is 0 for a
/// degenerate face (the frame is then unusable).
struct PointFrame {
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  double det_j = 0.0;
};
[[nodiscard]] PointFrame point_frame(const Mesh& mesh, const std::vector<int>& nodes,
                                     const face::Shape& s);

/// Unit outward normal at the face centre.
[[nodiscard]] Eigen::Vector3d centre_normal(const Mesh& mesh, const std::vector<int>& nodes);

/// Non-matching surfaces: fills result.elements (one per bottom face that any top face overlaps),
/// result.points (with top_shape), total_area and uncovered_area, by segment-to-segment (mortar)
/// integration (interface_mortar.cpp, docs/zero-thickness-elements.md §Non-matching meshes).
void build_mortar(const Mesh& mesh, const std::vector<Face>& bottom_faces,
                  const std::vector<Face>& top_faces, const InterfaceOptions& options,
                  const std::string& who, Interface& result);

}  // namespace jointhb::fe::detail
