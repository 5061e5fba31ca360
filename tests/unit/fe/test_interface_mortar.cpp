// Zero-thickness interfaces on triangular faces and between non-matching meshes
// (fe/interface.hpp, src/fe/interface_mortar.cpp): areas, frames and rigid-body invariance on
// tri3/tri6 faces; on coincident meshes the mortar construction equals the matching one; the
// patch tests (a uniform traction gives the consistent nodal loads ∫N dA on both sides, a uniform
// or linear top motion gives the exact gap); partial overlap; error messages.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/mesh.hpp"

namespace fe = jointhb::fe;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

// Two unit boxes stacked along z (lower on [0,1]³, upper on [0,1]² × [1,2]) with their own
// divisions and element type; the interface is lower.zmax (bottom) against upper.zmin (top).
fe::Mesh stacked(fe::ElementType lower_type, std::array<int, 3> lower_div, fe::ElementType upper_type,
                 std::array<int, 3> upper_div) {
  fe::BoxOptions lower, upper;
  lower.part = "lower";
  upper.part = "upper";
  lower.type = lower_type;
  upper.type = upper_type;
  lower.divisions = lower_div;
  upper.divisions = upper_div;
  upper.origin.z() = 1.0;
  fe::Mesh mesh = fe::box_mesh(lower);
  fe::append(mesh, fe::box_mesh(upper));
  return mesh;
}

fe::InterfaceOptions joint(fe::InterfaceIntegration integration, fe::InterfaceMeshes meshes) {
  fe::InterfaceOptions o;
  o.name = "joint";
  o.bottom_surface = "lower.zmax";
  o.top_surface = "upper.zmin";
  o.integration = integration;
  o.meshes = meshes;
  return o;
}

// Nodes of the upper box (its elements' nodes).
std::vector<bool> upper_nodes(const fe::Mesh& mesh) {
  std::vector<bool> up(static_cast<std::size_t>(mesh.num_nodes()), false);
  for (const fe::Element& e : mesh.elements)
    if (mesh.parts[static_cast<std::size_t>(e.part)] == "upper")
      for (int n : e.node_span()) up[static_cast<std::size_t>(n)] = true;
  return up;
}

// ∫ N_i dA of every node of a surface, from the surface's faces: the consistent load of a unit
// uniform traction, computed by an independent route (a fine midpoint rule over each face's
// physical area, with the face's shape functions replaced by barycentric interpolation of a
// refined sampling would be circular; instead the closed forms of flat faces with straight edges:
// quad4 A/4 per corner on rectangles, tri3 A/3 per corner, quad8 -A/12 corners and A/3 mid-edge
// nodes on rectangles, tri6 0 corners and A/3 mid-edge nodes).
VectorXd consistent_loads(const fe::Mesh& mesh, const std::string& surface) {
  VectorXd load = VectorXd::Zero(mesh.num_nodes());
  for (const fe::Face& f : mesh.surfaces.at(surface)) {
    const std::vector<int> nodes = fe::face_nodes(mesh, f);
    const auto x = [&](std::size_t k) -> Vector3d { return mesh.coordinates.col(nodes[k]); };
    const bool tri = nodes.size() == 3 || nodes.size() == 6;
    const double area = tri ? 0.5 * (x(1) - x(0)).cross(x(2) - x(0)).norm()
                            : (x(1) - x(0)).cross(x(3) - x(0)).norm();  // rectangles
    const std::size_t corners = tri ? 3 : 4;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      double w = 0.0;
      if (nodes.size() == 3) w = 1.0 / 3.0;
      if (nodes.size() == 4) w = 0.25;
      if (nodes.size() == 6) w = k < corners ? 0.0 : 1.0 / 3.0;
      if (nodes.size() == 8) w = k < corners ? -1.0 / 12.0 : 1.0 / 3.0;
      load(nodes[k]) += w * area;
    }
  }
  return load;
}

constexpr std::array<fe::InterfaceIntegration, 2> kIntegrationRules = {fe::InterfaceIntegration::nodal,
                                                            fe::InterfaceIntegration::gauss};

bool quadratic(fe::ElementType t) {
  return t == fe::ElementType::hex20 || t == fe::ElementType::tet10 || t == fe::ElementType::wedge15;
}

}  // namespace

TEST(InterfaceFaces, TriangularFacesGiveTheAreaFrameAndRigidInvariance) {
  for (fe::ElementType type : {fe::ElementType::tet4, fe::ElementType::tet10, fe::ElementType::wedge6,
                               fe::ElementType::wedge15}) {
    const fe::Mesh mesh = stacked(type, {2, 3, 1}, type, {2, 3, 1});
    for (fe::InterfaceIntegration rule : kIntegrationRules) {
      if (quadratic(type) && rule == fe::InterfaceIntegration::nodal) continue;
      const fe::Interface itf = fe::build_interface(mesh, joint(rule, fe::InterfaceMeshes::matching));
      SCOPED_TRACE(std::string(fe::abaqus_name(type)) + " " + fe::to_string(rule));
      EXPECT_EQ(itf.meshes, fe::InterfaceMeshes::matching);
      EXPECT_EQ(itf.elements.size(), mesh.surfaces.at("lower.zmax").size());
      EXPECT_NEAR(itf.total_area, 1.0, 1e-13);
      for (const fe::InterfacePoint& p : itf.points) {
        EXPECT_NEAR(p.frame(2, 2), 1.0, 1e-14);  // n = +z: outward from the lower box
        EXPECT_NEAR((p.frame * p.frame.transpose() - Matrix3d::Identity()).norm(), 0.0, 1e-14);
      }
      // A rigid rotation + translation of the whole assembly opens no gap.
      const Matrix3d w = (Matrix3d() << 0, -0.3, 0.2, 0.3, 0, -0.1, -0.2, 0.1, 0).finished() * 1e-3;
      VectorXd u(mesh.num_dofs());
      for (int i = 0; i < mesh.num_nodes(); ++i)
        u.segment<3>(3 * i) = Vector3d(1e-3, -2e-3, 5e-4) + w * mesh.coordinates.col(i);
      EXPECT_LE(fe::gaps(itf, u).cwiseAbs().maxCoeff(), 1e-18);
      // A unit normal traction gives the consistent loads, -∫N dA below and +∫N dA above.
      VectorXd t = VectorXd::Zero(3 * itf.num_points());
      for (int p = 0; p < itf.num_points(); ++p) t(3 * p + 2) = 1.0;
      const VectorXd f = fe::interface_force(itf, t);
      const VectorXd below = consistent_loads(mesh, "lower.zmax");
      const VectorXd above = consistent_loads(mesh, "upper.zmin");
      if (rule == fe::InterfaceIntegration::gauss) {
        for (int i = 0; i < mesh.num_nodes(); ++i)
          EXPECT_NEAR(f(3 * i + 2), above(i) - below(i), 1e-14) << "node " << i;
      }
      EXPECT_NEAR(f.sum(), 0.0, 1e-14);
    }
  }
}

TEST(InterfaceFaces, NodalIntegrationOfQuadraticFacesIsRefused) {
  const fe::Mesh mesh = stacked(fe::ElementType::tet10, {2, 2, 1}, fe::ElementType::tet10, {2, 2, 1});
  try {
    (void)fe::build_interface(mesh, joint(fe::InterfaceIntegration::nodal, fe::InterfaceMeshes::matching));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("integration 'nodal' needs linear faces (tri3, quad4), surface "
                                         "'lower.zmax' has tri6 faces"),
              std::string::npos)
        << e.what();
  }
}

TEST(InterfaceMortar, CoincidentMeshesGiveTheMatchingInterface) {
  for (fe::ElementType type : {fe::ElementType::hex8, fe::ElementType::tet4, fe::ElementType::hex20}) {
    const fe::Mesh mesh = stacked(type, {3, 2, 1}, type, {3, 2, 1});
    for (fe::InterfaceIntegration rule : kIntegrationRules) {
      if (quadratic(type) && rule == fe::InterfaceIntegration::nodal) continue;
      SCOPED_TRACE(std::string(fe::abaqus_name(type)) + " " + fe::to_string(rule));
      const fe::Interface m = fe::build_interface(mesh, joint(rule, fe::InterfaceMeshes::matching));
      const fe::Interface n = fe::build_interface(mesh, joint(rule, fe::InterfaceMeshes::non_matching));
      EXPECT_EQ(n.meshes, fe::InterfaceMeshes::non_matching);
      EXPECT_NEAR(n.total_area, 1.0, 1e-13);
      EXPECT_NEAR(n.uncovered_area, 0.0, 1e-13);
      // The stiffness Gᵀ A C G of a constant law (isotropic in the tangent plane, as every law:
      // the merged dual-mortar point may turn its t1 about n).
      const Matrix3d c = Vector3d(2.0, 2.0, 7.0).asDiagonal();
      const auto stiffness = [&](const fe::Interface& itf) {
        const std::vector<Matrix3d> cs(static_cast<std::size_t>(itf.num_points()), c);
        return Eigen::MatrixXd(fe::assemble_interface_force_and_tangent(
                                   itf, VectorXd::Zero(3 * itf.num_points()), cs)
                                   .stiffness);
      };
      const Eigen::MatrixXd km = stiffness(m), kn = stiffness(n);
      EXPECT_LE((km - kn).cwiseAbs().maxCoeff(), 1e-12 * km.cwiseAbs().maxCoeff());
      if (rule == fe::InterfaceIntegration::nodal) {
        // The dual mortar is the nodal element with its per-element points merged per node: one
        // point per bottom node, the coincident top node's weight 1 and every other weight 0.
        EXPECT_EQ(static_cast<std::size_t>(n.num_points()), m.node_pairs.size());
        for (const fe::InterfacePoint& p : n.points) {
          const fe::InterfaceElement& e = n.elements[static_cast<std::size_t>(p.element)];
          for (std::size_t k = 0; k < e.top_nodes.size(); ++k) {
            const bool coincident = (mesh.coordinates.col(e.top_nodes[k]) - p.position).norm() < 1e-12;
            EXPECT_NEAR(p.top_shape[k], coincident ? 1.0 : 0.0, 1e-12);
          }
        }
      }
    }
  }
}

TEST(InterfaceMortar, PatchTestUniformTractionGivesConsistentLoadsOnBothMeshes) {
  struct Pair {
    fe::ElementType lower, upper;
    std::array<int, 3> lower_div, upper_div;
  };
  const std::vector<Pair> pairs = {
      {fe::ElementType::hex8, fe::ElementType::hex8, {2, 2, 1}, {3, 3, 1}},
      {fe::ElementType::hex8, fe::ElementType::hex8, {5, 3, 1}, {2, 7, 1}},
      {fe::ElementType::hex8, fe::ElementType::tet4, {4, 3, 1}, {3, 5, 1}},
      {fe::ElementType::tet4, fe::ElementType::hex20, {3, 2, 1}, {2, 3, 1}},
      {fe::ElementType::hex20, fe::ElementType::tet10, {2, 3, 1}, {3, 2, 1}},
  };
  for (const Pair& pr : pairs) {
    const fe::Mesh mesh = stacked(pr.lower, pr.lower_div, pr.upper, pr.upper_div);
    const VectorXd below = consistent_loads(mesh, "lower.zmax");
    const VectorXd above = consistent_loads(mesh, "upper.zmin");
    for (fe::InterfaceIntegration rule : kIntegrationRules) {
      if (quadratic(pr.lower) && rule == fe::InterfaceIntegration::nodal) continue;
      SCOPED_TRACE(std::string(fe::abaqus_name(pr.lower)) + "/" + fe::abaqus_name(pr.upper) + " " +
                   fe::to_string(rule));
      const fe::Interface itf = fe::build_interface(mesh, joint(rule, fe::InterfaceMeshes::non_matching));
      EXPECT_NEAR(itf.total_area, 1.0, 1e-12);
      // A uniform traction (tangential and normal) is transmitted exactly: the consistent loads.
      const Vector3d traction(0.3, -0.2, -1.0);  // global axes
      VectorXd t(3 * itf.num_points());
      for (int p = 0; p < itf.num_points(); ++p)
        t.segment<3>(3 * p) = itf.points[static_cast<std::size_t>(p)].frame * traction;
      const VectorXd f = fe::interface_force(itf, t);
      for (int i = 0; i < mesh.num_nodes(); ++i)
        for (int d = 0; d < 3; ++d)
          EXPECT_NEAR(f(3 * i + d), traction(d) * (above(i) - below(i)), 1e-13) << "node " << i << " dof " << d;
      // A uniform top motion relative to the bottom gives exactly that gap at every point.
      const std::vector<bool> up = upper_nodes(mesh);
      VectorXd u = VectorXd::Zero(mesh.num_dofs());
      const Vector3d d(1e-3, -4e-4, 2e-4);
      for (int i = 0; i < mesh.num_nodes(); ++i)
        if (up[static_cast<std::size_t>(i)]) u.segment<3>(3 * i) = d;
      const VectorXd g = fe::gaps(itf, u);
      for (int p = 0; p < itf.num_points(); ++p)
        EXPECT_NEAR((g.segment<3>(3 * p) - itf.points[static_cast<std::size_t>(p)].frame * d).norm(), 0.0, 1e-17);
    }
  }
}

TEST(InterfaceMortar, DualMortarReproducesALinearTopFieldAtTheBottomNodes) {
  const fe::Mesh mesh = stacked(fe::ElementType::hex8, {4, 3, 1}, fe::ElementType::hex8, {3, 5, 1});
  const fe::Interface itf =
      fe::build_interface(mesh, joint(fe::InterfaceIntegration::nodal, fe::InterfaceMeshes::non_matching));
  const std::vector<bool> up = upper_nodes(mesh);
  const Matrix3d b = (Matrix3d() << 1, 2, 0, -1, 3, 0, 0.5, -2, 0).finished() * 1e-3;
  VectorXd u = VectorXd::Zero(mesh.num_dofs());
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (up[static_cast<std::size_t>(i)]) u.segment<3>(3 * i) = b * mesh.coordinates.col(i);
  const VectorXd g = fe::gaps(itf, u);
  for (int p = 0; p < itf.num_points(); ++p) {
    const fe::InterfacePoint& pt = itf.points[static_cast<std::size_t>(p)];
    EXPECT_NEAR((g.segment<3>(3 * p) - pt.frame * (b * pt.position)).norm(), 0.0, 1e-17) << p;
  }
}

TEST(InterfaceMortar, PartialOverlapReportsTheUncoveredArea) {
  // The upper box shifted by 0.25 in x: a quarter of the bottom surface has nothing over it.
  fe::BoxOptions lower, upper;
  lower.part = "lower";
  upper.part = "upper";
  lower.divisions = {4, 2, 1};
  upper.divisions = {3, 3, 1};
  upper.origin = Vector3d(0.25, 0.0, 1.0);
  fe::Mesh mesh = fe::box_mesh(lower);
  fe::append(mesh, fe::box_mesh(upper));
  const fe::Interface g =
      fe::build_interface(mesh, joint(fe::InterfaceIntegration::gauss, fe::InterfaceMeshes::non_matching));
  EXPECT_NEAR(g.total_area, 0.75, 1e-12);
  EXPECT_NEAR(g.uncovered_area, 0.25, 1e-12);
  const fe::Interface n =
      fe::build_interface(mesh, joint(fe::InterfaceIntegration::nodal, fe::InterfaceMeshes::non_matching));
  // Dual mortar: the nodes at x = 0 carry no point and the column at x = 0.25 the covered half.
  EXPECT_NEAR(n.total_area + n.uncovered_area, 1.0, 1e-12);
  EXPECT_GT(n.total_area, 0.7);
}

TEST(InterfaceMortar, AutomaticChoosesMatchingWhenTheNodesCoincide) {
  const fe::Mesh same = stacked(fe::ElementType::hex8, {2, 2, 1}, fe::ElementType::hex8, {2, 2, 1});
  const fe::Mesh other = stacked(fe::ElementType::hex8, {2, 2, 1}, fe::ElementType::hex8, {3, 2, 1});
  const auto o = joint(fe::InterfaceIntegration::nodal, fe::InterfaceMeshes::automatic);
  EXPECT_EQ(fe::build_interface(same, o).meshes, fe::InterfaceMeshes::matching);
  EXPECT_EQ(fe::build_interface(other, o).meshes, fe::InterfaceMeshes::non_matching);
}

TEST(InterfaceMortar, DisjointSurfacesAreAnError) {
  fe::BoxOptions lower, upper;
  lower.part = "lower";
  upper.part = "upper";
  upper.origin = Vector3d(3.0, 0.0, 1.0);
  fe::Mesh mesh = fe::box_mesh(lower);
  fe::append(mesh, fe::box_mesh(upper));
  try {
    (void)fe::build_interface(mesh, joint(fe::InterfaceIntegration::gauss, fe::InterfaceMeshes::non_matching));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("interface 'joint': surfaces 'lower.zmax' and 'upper.zmin' do not "
                                         "overlap"),
              std::string::npos)
        << e.what();
  }
}

TEST(InterfaceFaces, NodalPointsOfOneNodePairShareTheirFrameOnAFlatInterface) {
  // Tetrahedra: the faces around a node have different ξ directions (t1); the points of one node
  // pair get the first one's, so they are identical (one contact point after merging).
  const fe::Mesh mesh = stacked(fe::ElementType::tet4, {3, 2, 1}, fe::ElementType::tet4, {3, 2, 1});
  const fe::Interface itf =
      fe::build_interface(mesh, joint(fe::InterfaceIntegration::nodal, fe::InterfaceMeshes::matching));
  std::map<std::pair<double, double>, Matrix3d> frame_at;
  std::set<std::pair<double, double>> t1_directions;
  for (const fe::InterfacePoint& p : itf.points) {
    const auto key = std::make_pair(p.position.x(), p.position.y());
    const auto [it, inserted] = frame_at.emplace(key, p.frame);
    if (!inserted) {
      EXPECT_EQ((it->second - p.frame).norm(), 0.0) << "point at " << key.first << ", " << key.second;
    }
    t1_directions.insert({std::round(p.frame(0, 0) * 1e6), std::round(p.frame(0, 1) * 1e6)});
  }
  EXPECT_EQ(frame_at.size(), itf.node_pairs.size());
  EXPECT_GT(t1_directions.size(), 1u);  // the elements' own t1 do differ from node to node
}
