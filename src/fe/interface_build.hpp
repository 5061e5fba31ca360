#pragma once
// Shared by the matching (interface.cpp) and non-matching (interface_mortar.cpp) construction of
// zero-thickness interfaces.

#include <Eigen/Core>
#include <algorithm>
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

/// A face with the geometry both constructions search by.
struct FaceGeometry {
  Face face;
  std::vector<int> nodes;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< mean of the nodes
  double size = 0.0;    ///< longest distance between two corners
  double radius = 0.0;  ///< largest centroid-node distance
};
[[nodiscard]] FaceGeometry face_geometry(const Mesh& mesh, const Face& face);

/// Faces ordered by centroid x, for the candidates near a point: for_each_in(lo, hi, f) calls
/// f(index into the list given) for every face whose centroid x lies in [lo, hi]; f returns true
/// to stop.
class FacesAlongX {
 public:
  template <class FaceList>  // a vector of FaceGeometry or of types derived from it
  explicit FacesAlongX(const FaceList& faces) : order_(faces.size()), x_(faces.size()) {
    for (std::size_t i = 0; i < faces.size(); ++i) order_[i] = static_cast<int>(i);
    std::sort(order_.begin(), order_.end(), [&](int a, int b) {
      return faces[static_cast<std::size_t>(a)].centroid.x() < faces[static_cast<std::size_t>(b)].centroid.x();
    });
    for (std::size_t i = 0; i < order_.size(); ++i) x_[i] = faces[static_cast<std::size_t>(order_[i])].centroid.x();
  }
  template <class F>
  void for_each_in(double lo, double hi, F&& f) const {
    for (auto it = std::lower_bound(x_.begin(), x_.end(), lo); it != x_.end() && *it <= hi; ++it)
      if (f(order_[static_cast<std::size_t>(it - x_.begin())])) return;
  }

 private:
  std::vector<int> order_;
  std::vector<double> x_;
};

/// Unit outward normal at the face centre.
[[nodiscard]] Eigen::Vector3d centre_normal(const Mesh& mesh, const std::vector<int>& nodes);

/// Non-matching surfaces: fills result.elements (one per bottom face that any top face overlaps),
/// result.points (with top_shape), total_area and uncovered_area, by segment-to-segment (mortar)
/// integration (interface_mortar.cpp, docs/zero-thickness-elements.md §Non-matching meshes).
void build_mortar(const Mesh& mesh, const std::vector<Face>& bottom_faces,
                  const std::vector<Face>& top_faces, const InterfaceOptions& options,
                  const std::string& who, Interface& result);

}  // namespace jointhb::fe::detail
