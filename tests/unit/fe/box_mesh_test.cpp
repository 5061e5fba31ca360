#include "jointhb/fe/box_mesh.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <tuple>

#include "jointhb/fe/mesh_checks.hpp"

namespace jointhb::fe {
namespace {

BoxOptions sample_box(ElementType type) {
  BoxOptions options;
  options.part = "plate";
  options.origin = Eigen::Vector3d(-1.0, 0.5, 2.0);
  options.size = Eigen::Vector3d(0.3, 0.02, 0.05);
  options.divisions = {3, 2, 4};
  options.type = type;
  return options;
}

// Outward unit normal of a face from its corners: (x2 - x0) × (x3 - x1), normalised.
Eigen::Vector3d face_normal(const Mesh& mesh, const Face& face) {
  const std::vector<int> n = face_nodes(mesh, face);
  const Eigen::Vector3d d1 = mesh.coordinates.col(n[2]) - mesh.coordinates.col(n[0]);
  const Eigen::Vector3d d2 = mesh.coordinates.col(n[3]) - mesh.coordinates.col(n[1]);
  return d1.cross(d2).normalized();
}

TEST(BoxMesh, Hex8CountsIdsAndParts) {
  const Mesh mesh = box_mesh(sample_box(ElementType::hex8));
  EXPECT_EQ(mesh.num_nodes(), 4 * 3 * 5);
  EXPECT_EQ(mesh.num_elements(), 3 * 2 * 4);
  ASSERT_EQ(mesh.parts, std::vector<std::string>{"plate"});
  EXPECT_EQ(mesh.node_ids.front(), 1);
  EXPECT_EQ(mesh.node_ids.back(), mesh.num_nodes());
  EXPECT_EQ(mesh.element_ids.back(), mesh.num_elements());
  EXPECT_EQ(mesh.element_sets.at("plate").size(), 24u);
  for (const Element& e : mesh.elements) {
    EXPECT_EQ(e.type, ElementType::hex8);
    EXPECT_EQ(e.part, 0);
  }
  EXPECT_TRUE(check_mesh(mesh).empty());
}

TEST(BoxMesh, Hex20HasOneNodePerCornerAndEdge) {
  const Mesh mesh = box_mesh(sample_box(ElementType::hex20_reduced));
  const int nx = 3, ny = 2, nz = 4;
  const int corners = (nx + 1) * (ny + 1) * (nz + 1);
  const int edges = nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz;
  EXPECT_EQ(mesh.num_nodes(), corners + edges);
  EXPECT_EQ(mesh.num_elements(), nx * ny * nz);

  // No two nodes at the same place, and every node used.
  std::set<std::tuple<double, double, double>> places;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    places.emplace(mesh.coordinates(0, n), mesh.coordinates(1, n), mesh.coordinates(2, n));
  }
  EXPECT_EQ(static_cast<int>(places.size()), mesh.num_nodes());
  std::set<int> used;
  for (const Element& e : mesh.elements) used.insert(e.node_span().begin(), e.node_span().end());
  EXPECT_EQ(static_cast<int>(used.size()), mesh.num_nodes());
  EXPECT_TRUE(check_mesh(mesh).empty());
}

TEST(BoxMesh, Hex20MidEdgeNodesAreAtEdgeMidpoints) {
  // Abaqus mid-edge node k lies between corners kEdges[k - 8] (mesh.hpp).
  const auto& edges = hex_edge_corners();
  const Mesh mesh = box_mesh(sample_box(ElementType::hex20));
  for (const Element& e : mesh.elements) {
    for (std::size_t k = 0; k < 12; ++k) {
      const Eigen::Vector3d mid = mesh.coordinates.col(e.nodes[8 + k]);
      const Eigen::Vector3d a =
          mesh.coordinates.col(e.nodes[static_cast<std::size_t>(edges[k][0])]);
      const Eigen::Vector3d b =
          mesh.coordinates.col(e.nodes[static_cast<std::size_t>(edges[k][1])]);
      EXPECT_LT((mid - 0.5 * (a + b)).norm(), 1e-15) << "mid-edge node " << 8 + k;
    }
  }
}

TEST(BoxMesh, ElementVolumesSumToTheBoxVolume) {
  for (ElementType type : {ElementType::hex8_incompatible, ElementType::hex20}) {
    const BoxOptions options = sample_box(type);
    const Mesh mesh = box_mesh(options);
    double volume = 0.0;
    for (int e = 0; e < mesh.num_elements(); ++e) volume += element_volume(mesh, e);
    EXPECT_NEAR(volume, options.size.prod(), 1e-15) << abaqus_name(type);
  }
}

TEST(BoxMesh, SidesAreSurfacesWithOutwardNormalsAndNodeSets) {
  for (ElementType type : {ElementType::hex8, ElementType::hex20}) {
    const BoxOptions options = sample_box(type);
    const Mesh mesh = box_mesh(options);
    const std::array<const char*, 6> names = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
    for (std::size_t s = 0; s < 6; ++s) {
      const std::string name = "plate." + std::string(names[s]);
      const auto axis = static_cast<Eigen::Index>(s / 2);
      const double sign = s % 2 == 0 ? -1.0 : 1.0;
      const double plane = options.origin[axis] + (sign > 0 ? options.size[axis] : 0.0);
      ASSERT_TRUE(mesh.surfaces.count(name)) << name;
      ASSERT_TRUE(mesh.node_sets.count(name)) << name;
      const auto& faces = mesh.surfaces.at(name);
      int expected_faces = 1;
      for (std::size_t d = 0; d < 3; ++d)
        if (static_cast<Eigen::Index>(d) != axis) expected_faces *= options.divisions[d];
      EXPECT_EQ(static_cast<int>(faces.size()), expected_faces) << name;

      const auto& nodes = mesh.node_sets.at(name);
      std::set<int> on_side;
      for (int n = 0; n < mesh.num_nodes(); ++n)
        if (std::abs(mesh.coordinates(axis, n) - plane) < 1e-12) on_side.insert(n);
      EXPECT_EQ(std::set<int>(nodes.begin(), nodes.end()), on_side) << name;

      for (const Face& face : faces) {
        const Eigen::Vector3d normal = face_normal(mesh, face);
        EXPECT_NEAR(normal[axis], sign, 1e-12) << name << " element " << face.element;
        for (int n : face_nodes(mesh, face)) EXPECT_TRUE(on_side.count(n)) << name;
      }
    }
  }
}

TEST(BoxMesh, InvalidOptionsNameTheField) {
  const auto message = [](const BoxOptions& options) {
    try {
      (void)box_mesh(options);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  BoxOptions options;
  options.size.y() = -1.0;
  EXPECT_NE(message(options).find("size.y"), std::string::npos) << message(options);
  options = {};
  options.divisions[2] = 0;
  EXPECT_NE(message(options).find("divisions.z"), std::string::npos) << message(options);
  options = {};
  options.origin.x() = std::nan("");
  EXPECT_NE(message(options).find("origin.x"), std::string::npos) << message(options);
  options = {};
  options.part.clear();
  EXPECT_NE(message(options).find("part"), std::string::npos) << message(options);
}

TEST(BoxMesh, AppendedBoxesStaySeparate) {
  BoxOptions lower;
  lower.part = "lower";
  lower.divisions = {2, 1, 1};
  BoxOptions upper = lower;
  upper.part = "upper";
  upper.origin.z() = 1.0;  // touching lower's top side: coincident nodes, not merged
  Mesh mesh = box_mesh(lower);
  append(mesh, box_mesh(upper));
  EXPECT_EQ(mesh.num_nodes(), 2 * 12);
  const auto components = connected_components(mesh);
  ASSERT_EQ(components.size(), 2u);
  EXPECT_EQ(components[0], (std::vector<int>{0, 1}));
  EXPECT_EQ(components[1], (std::vector<int>{2, 3}));
  EXPECT_TRUE(mesh.surfaces.count("upper.zmin"));
}

}  // namespace
}  // namespace jointhb::fe
