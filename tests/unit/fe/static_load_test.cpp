// Consistent nodal forces of surface pressures (fe/static_load.hpp) against closed forms: the
// classical nodal shares of a uniform load on flat faces, and the resultant of a pressure on a
// curved face against the boundary integral ∫ n dA = ½ ∮ x × dx (Stokes), computed independently.
#include "jointhb/fe/static_load.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "jointhb/fe/box_mesh.hpp"

namespace jointhb::fe {
namespace {

// A flat face in the plane z = 0, counter-clockwise seen from +z (outward normal +z).
Eigen::Matrix3Xd flat_face(int nodes) {
  Eigen::Matrix3Xd x(3, nodes);
  if (nodes == 4 || nodes == 8) {
    x.leftCols(4) << 0, 2, 2, 0, 0, 0, 3, 3, 0, 0, 0, 0;  // 2 × 3 rectangle
  } else {
    x.leftCols(3) << 0, 4, 0, 0, 0, 3, 0, 0, 0;  // right triangle, legs 4 and 3
  }
  const int corners = nodes == 4 || nodes == 8 ? 4 : 3;
  if (nodes == 6 || nodes == 8)
    for (int k = 0; k < corners; ++k) x.col(corners + k) = 0.5 * (x.col(k) + x.col((k + 1) % corners));
  return x;
}

TEST(StaticLoad, FlatFacesGetTheClassicalNodalShares) {
  const double p = 1.5e5;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  {  // quad4: pA/4 per node, A = 6
    const Eigen::Matrix3Xd f = face_pressure_forces(flat_face(4), p);
    for (int a = 0; a < 4; ++a) EXPECT_LT((f.col(a) + p * 6.0 / 4.0 * n).norm(), 1e-9 * p);
  }
  {  // quad8: corners +pA/12 (a pull), mid-edge nodes −pA/3
    const Eigen::Matrix3Xd f = face_pressure_forces(flat_face(8), p);
    for (int a = 0; a < 4; ++a) EXPECT_LT((f.col(a) - p * 6.0 / 12.0 * n).norm(), 1e-9 * p);
    for (int a = 4; a < 8; ++a) EXPECT_LT((f.col(a) + p * 6.0 / 3.0 * n).norm(), 1e-9 * p);
  }
  {  // tri3: pA/3 per node, A = 6
    const Eigen::Matrix3Xd f = face_pressure_forces(flat_face(3), p);
    for (int a = 0; a < 3; ++a) EXPECT_LT((f.col(a) + p * 6.0 / 3.0 * n).norm(), 1e-9 * p);
  }
  {  // tri6: nothing at the corners, pA/3 at the mid-edge nodes
    const Eigen::Matrix3Xd f = face_pressure_forces(flat_face(6), p);
    for (int a = 0; a < 3; ++a) EXPECT_LT(f.col(a).norm(), 1e-9 * p);
    for (int a = 3; a < 6; ++a) EXPECT_LT((f.col(a) + p * 6.0 / 3.0 * n).norm(), 1e-9 * p);
  }
  EXPECT_THROW((void)face_pressure_forces(Eigen::Matrix3Xd::Zero(3, 5), p), std::invalid_argument);
}

// ½ ∮ x × dx along the boundary of a quad8 face (its four parabolic edges through the corner and
// mid-edge nodes), by 5-point Gauss on each edge: the vector area ∫ n dA of any surface it bounds.
Eigen::Vector3d vector_area_by_boundary(const Eigen::Matrix3Xd& x) {
  const double g[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
  Eigen::Vector3d area = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d a = x.col(k), b = x.col((k + 1) % 4), m = x.col(4 + k);
    for (int q = 0; q < 5; ++q) {  // x(s) = a s(s−1)/2 + m (1 − s²) + b s(s+1)/2, s ∈ [−1, 1]
      const double s = g[q];
      const Eigen::Vector3d xs = a * s * (s - 1) / 2 + m * (1 - s * s) + b * s * (s + 1) / 2;
      const Eigen::Vector3d dxs = a * (s - 0.5) - 2.0 * m * s + b * (s + 0.5);
      area += 0.5 * w[q] * xs.cross(dxs);
    }
  }
  return area;
}

TEST(StaticLoad, PressureOnACurvedFaceHasTheResultantOfItsVectorArea) {
  // A quad8 patch of a cylinder of radius 0.3 about the y axis, twisted at one corner.
  Eigen::Matrix3Xd x(3, 8);
  const auto on_cylinder = [](double angle, double y) {
    return Eigen::Vector3d(0.3 * std::sin(angle), y, 0.3 * std::cos(angle));
  };
  x.col(0) = on_cylinder(-0.4, 0.0);
  x.col(1) = on_cylinder(0.4, 0.0);
  x.col(2) = on_cylinder(0.45, 0.5) + Eigen::Vector3d(0.0, 0.05, 0.0);
  x.col(3) = on_cylinder(-0.4, 0.5);
  x.col(4) = on_cylinder(0.0, 0.0);
  x.col(5) = on_cylinder(0.42, 0.26);
  x.col(6) = on_cylinder(0.0, 0.52);
  x.col(7) = on_cylinder(-0.4, 0.25);
  const double p = 2.0e6;
  const Eigen::Vector3d resultant = face_pressure_forces(x, p).rowwise().sum();
  const Eigen::Vector3d expected = -p * vector_area_by_boundary(x);
  EXPECT_LT((resultant - expected).norm(), 1e-12 * expected.norm()) << resultant.transpose() << " vs " << expected.transpose();
  EXPECT_GT(expected.norm(), 0.1 * p);
}

TEST(StaticLoad, LoadVectorOfABoxSumsToThePressureTimesTheAreaAndClosesOnAllSides) {
  // Quadrilateral faces (hexahedra, wedges' sides), triangles (tetrahedra, wedges' ends), both
  // orders.
  for (ElementType type : {ElementType::hex8, ElementType::hex20, ElementType::tet4, ElementType::tet10,
                           ElementType::wedge6, ElementType::wedge15}) {
    BoxOptions o;
    o.size = {0.2, 0.1, 0.05};
    o.divisions = {4, 3, 2};
    o.type = type;
    const Mesh mesh = box_mesh(o);
    StaticLoads top;
    top.pressures.push_back({"top", mesh.surfaces.at("box.zmax"), 1e5});
    const LoadResultant r = load_resultant(mesh, static_load_vector(mesh, top));
    EXPECT_LT((r.force - Eigen::Vector3d(0.0, 0.0, -1e5 * 0.02)).norm(), 1e-9 * 1e5 * 0.02) << abaqus_name(type);
    // The centre of pressure is the face's centre (0.1, 0.05, 0.05): M = x_c × F.
    EXPECT_LT((r.moment - Eigen::Vector3d(0.1, 0.05, 0.05).cross(r.force)).norm(), 1e-9 * 1e5 * 0.02 * 0.2);

    StaticLoads all;
    for (const char* side : {"box.xmin", "box.xmax", "box.ymin", "box.ymax", "box.zmin", "box.zmax"})
      all.pressures.push_back({side, mesh.surfaces.at(side), 3e5});
    all.forces.push_back({"pair", {0, 1}, Eigen::Vector3d(0.0, 5.0, 0.0)});
    all.forces.push_back({"pair", {0, 1}, Eigen::Vector3d(0.0, -5.0, 0.0)});
    const LoadResultant closed = load_resultant(mesh, static_load_vector(mesh, all));
    EXPECT_LT(closed.force.norm(), 1e-9 * 3e5 * 0.2);
    EXPECT_LT(closed.moment.norm(), 1e-9 * 3e5 * 0.2 * 0.2);
  }
}

TEST(StaticLoad, BadLoadsAreNamed) {
  BoxOptions o;
  const Mesh mesh = box_mesh(o);
  StaticLoads loads;
  loads.forces.push_back({"model.loads[1]", {99}, Eigen::Vector3d::UnitX()});
  try {
    (void)static_load_vector(mesh, loads);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("model.loads[1]: node index 99"), std::string::npos) << e.what();
  }
  loads.forces[0] = {"model.loads[0]", {0}, Eigen::Vector3d(NAN, 0.0, 0.0)};
  EXPECT_THROW((void)static_load_vector(mesh, loads), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::fe
