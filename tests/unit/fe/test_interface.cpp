// Zero-thickness interface (fe/interface.hpp), eq. (13)-(24): pairing of matching surfaces, frames,
// rigid-body invariance, the 12 zero-energy modes of the 8-node element, equal and opposite
// tractions (eq. 20), nodal vs Gauss integration, error messages, and the assembled tangent
// against central differences of the force from the contact laws.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/mesh.hpp"

namespace fe = jointhb::fe;
namespace jc = jointhb::contact;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

// A structured block of hex8 or hex20 elements on [origin, origin + size] (a local helper; the
// official generator lives elsewhere). Surfaces "<name>_bottom" (S1 faces at z = z0) and
// "<name>_top" (S2 faces at z = z1). External ids start at id_base + 1.
fe::Mesh block(const std::string& name, int nx, int ny, int nz, const Vector3d& origin,
               const Vector3d& size, bool quadratic, long id_base) {
  const int s = quadratic ? 2 : 1;  // grid points per element edge
  const int mx = s * nx, my = s * ny, mz = s * nz;
  fe::Mesh m;
  m.coordinates.resize(3, (mx + 1) * (my + 1) * (mz + 1));
  auto idx = [&](int i, int j, int k) { return i + (mx + 1) * (j + (my + 1) * k); };
  for (int k = 0; k <= mz; ++k)
    for (int j = 0; j <= my; ++j)
      for (int i = 0; i <= mx; ++i) {
        m.coordinates.col(idx(i, j, k)) =
            origin + Vector3d(size.x() * i / mx, size.y() * j / my, size.z() * k / mz);
        m.node_ids.push_back(id_base + idx(i, j, k) + 1);
      }
  // Corner offsets in half-element units (0 or 2) and the hex20 edge table of mesh.hpp.
  const int c[8][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0},
                       {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}};
  const auto& edges = fe::hex_edge_corners();
  m.parts.push_back(name);
  for (int ez = 0; ez < nz; ++ez)
    for (int ey = 0; ey < ny; ++ey)
      for (int ex = 0; ex < nx; ++ex) {
        fe::Element e;
        e.type = quadratic ? fe::ElementType::hex20 : fe::ElementType::hex8;
        auto node = [&](int ox, int oy, int oz) {  // offsets in half-element units
          return idx(s * ex + ox * s / 2, s * ey + oy * s / 2, s * ez + oz * s / 2);
        };
        for (int a = 0; a < 8; ++a) e.nodes[a] = node(c[a][0], c[a][1], c[a][2]);
        if (quadratic)
          for (int a = 0; a < 12; ++a) {
            const int* p = c[edges[a][0]];
            const int* q = c[edges[a][1]];
            e.nodes[8 + a] = node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2);
          }
        const int id = m.num_elements();
        m.elements.push_back(e);
        m.element_ids.push_back(id_base + id + 1);
        if (ez == 0) m.surfaces[name + "_bottom"].push_back({id, 0});
        if (ez == nz - 1) m.surfaces[name + "_top"].push_back({id, 1});
      }
  return m;
}

// Two unit-square blocks stacked at z = 1, sharing coordinates but not nodes. Element and node ids
// of the upper block start at 1001.
fe::Mesh stacked(int n_lower, int n_upper, bool quadratic = false) {
  fe::Mesh m =
      block("lower", n_lower, n_lower, 1, Vector3d(0, 0, 0), Vector3d(1, 1, 1), quadratic, 0);
  fe::append(m, block("upper", n_upper, n_upper, 1, Vector3d(0, 0, 1), Vector3d(1, 1, 1), quadratic,
                      1000));
  return m;
}

// Moves the interior in-plane nodes (a smooth map applied to every node keeps the blocks
// coincident and the boundary of the unit square fixed): irregular quadrilaterals.
void distort(fe::Mesh& m) {
  for (int i = 0; i < m.num_nodes(); ++i) {
    auto x = m.coordinates.col(i);
    const double bump = std::sin(std::numbers::pi * x.x()) * std::sin(std::numbers::pi * x.y());
    x.x() += 0.12 * bump;
    x.y() -= 0.07 * bump * x.x();
  }
}

void rotate(fe::Mesh& m, const Matrix3d& r) { m.coordinates = r * m.coordinates; }

fe::InterfaceOptions options(fe::InterfaceIntegration integration) {
  fe::InterfaceOptions o;
  o.name = "joint";
  o.bottom_surface = "lower_top";
  o.top_surface = "upper_bottom";
  o.integration = integration;
  return o;
}

std::string error_of(const fe::Mesh& m, const fe::InterfaceOptions& o) {
  try {
    (void)fe::build_interface(m, o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

// The nodes of block "upper" are those with external id > 1000.
bool is_upper(const fe::Mesh& m, int node) {
  return m.node_ids[static_cast<std::size_t>(node)] > 1000;
}

std::vector<Matrix3d> constant_tangents(const fe::Interface& itf, const Matrix3d& c) {
  return std::vector<Matrix3d>(static_cast<std::size_t>(itf.num_points()), c);
}

Matrix3d diagonal_law(double k_t, double k_n) { return Vector3d(k_t, k_t, k_n).asDiagonal(); }

constexpr std::array<fe::InterfaceIntegration, 2> kRules = {fe::InterfaceIntegration::nodal,
                                                            fe::InterfaceIntegration::gauss};

}  // namespace

TEST(InterfaceBuild, PairsTheFacesOfStackedBlocks) {
  const fe::Mesh m = stacked(2, 2);
  for (auto rule : kRules) {
    const fe::Interface itf = fe::build_interface(m, options(rule));
    EXPECT_EQ(itf.elements.size(), 4u);
    EXPECT_EQ(itf.num_points(), 16);  // per-element points, also for nodal integration
    EXPECT_EQ(itf.node_pairs.size(), 9u);
    EXPECT_NEAR(itf.total_area, 1.0, 1e-14);
    EXPECT_EQ(itf.gap_operator.rows(), 48);
    EXPECT_EQ(itf.gap_operator.cols(), m.num_dofs());
    for (const fe::NodePair& pair : itf.node_pairs) {
      EXPECT_FALSE(is_upper(m, pair.bottom));
      EXPECT_TRUE(is_upper(m, pair.top));
      EXPECT_EQ((m.coordinates.col(pair.bottom) - m.coordinates.col(pair.top)).norm(), 0.0);
    }
    for (const fe::InterfacePoint& p : itf.points) {
      // S2 of the lower block is (4 5 6 7): ∂x/∂ξ along +x, outward normal +z.
      EXPECT_NEAR((p.frame - Matrix3d::Identity()).norm(), 0.0, 1e-15);
      EXPECT_NEAR(p.position.z(), 1.0, 1e-15);
      EXPECT_NEAR(p.area, 0.25 * 0.25, 1e-15);  // nodal share 1/4 of the element, Gauss w=1
    }
  }
}

TEST(InterfaceBuild, RigidBodyMotionsGiveZeroGapAndForce) {
  fe::Mesh m = stacked(2, 2);
  distort(m);
  const jc::ContactPoint law = [] {
    jc::ContactPointOptions o;
    o.normal = {2.0e6, 2.0e5, 0.0};
    return jc::ContactPoint(o, std::make_shared<jc::GaulMayerLaw>(0.3));
  }();
  for (auto rule : kRules) {
    const fe::Interface itf = fe::build_interface(m, options(rule));
    const auto stiffness =
        fe::assemble_interface_force_and_tangent(itf, VectorXd::Zero(3 * itf.num_points()),
                                                 constant_tangents(itf, diagonal_law(3e9, 5e9)))
            .stiffness;
    const auto reference = fe::evaluate_static_contact(itf, law, VectorXd::Zero(m.num_dofs()));
    std::vector<Matrix3d> motions;  // u = (R - I) x + c
    const Vector3d c(0.3, -0.2, 0.7);
    const Matrix3d finite =
        Eigen::AngleAxisd(0.8, Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
    Matrix3d small;  // linearised rotation θ×
    small << 0, -3e-3, 2e-3, 3e-3, 0, -1e-3, -2e-3, 1e-3, 0;
    for (int k = 0; k < 6; ++k) {
      VectorXd u(m.num_dofs());
      for (int i = 0; i < m.num_nodes(); ++i) {
        const Vector3d x = m.coordinates.col(i);
        Vector3d ui = Vector3d::Zero();
        if (k < 3) ui = Vector3d::Unit(k) * c(k);                  // three translations
        if (k == 3) ui = small * x;                                // small rotation
        if (k == 4) ui = (finite - Matrix3d::Identity()) * x + c;  // finite rotation
        if (k == 5) ui = Eigen::AngleAxisd(1e-4, Vector3d::UnitZ()).toRotationMatrix() * x - x;
        u.segment<3>(3 * i) = ui;
      }
      EXPECT_EQ(fe::gaps(itf, u).norm(), 0.0) << "motion " << k;
      EXPECT_LE((stiffness * u).norm(), 1e-14 * 5e9 * u.norm()) << "motion " << k;
      const auto moved = fe::evaluate_static_contact(itf, law, u);
      EXPECT_EQ((moved.force - reference.force).norm(), 0.0) << "motion " << k;
    }
  }
}

TEST(InterfaceElement, EightNodeElementHasTwelveZeroEnergyModes) {
  // The 24×24 stiffness of eq. (24) with a constant diagonal C: rank 12, 12 zero-energy modes.
  for (bool distorted : {false, true}) {
    fe::Mesh m = stacked(1, 1);
    if (distorted) m.coordinates.col(6) += Vector3d(0.2, 0.1, 0.0);      // lower block's top corner
    if (distorted) m.coordinates.col(8 + 2) += Vector3d(0.2, 0.1, 0.0);  // coincident upper node
    for (auto rule : kRules) {
      const fe::Interface itf = fe::build_interface(m, options(rule));
      const auto k =
          fe::assemble_interface_force_and_tangent(itf, VectorXd::Zero(3 * itf.num_points()),
                                                   constant_tangents(itf, diagonal_law(2e9, 7e9)))
              .stiffness;
      std::vector<int> dofs;
      for (int n : itf.elements[0].bottom_nodes)
        for (int d = 0; d < 3; ++d) dofs.push_back(3 * n + d);
      for (int n : itf.elements[0].top_nodes)
        for (int d = 0; d < 3; ++d) dofs.push_back(3 * n + d);
      ASSERT_EQ(dofs.size(), 24u);
      const Eigen::MatrixXd dense = Eigen::MatrixXd(k);
      Eigen::MatrixXd ke(24, 24);
      for (std::size_t i = 0; i < 24; ++i)
        for (std::size_t j = 0; j < 24; ++j) ke(i, j) = dense(dofs[i], dofs[j]);
      EXPECT_NEAR((dense.norm() - ke.norm()) / ke.norm(), 0.0, 1e-14);  // nothing else
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(ke);
      const double top = eig.eigenvalues().maxCoeff();
      int zero = 0;
      for (double lambda : eig.eigenvalues()) {
        EXPECT_GT(lambda, -1e-12 * top);
        if (lambda < 1e-10 * top) ++zero;
      }
      EXPECT_EQ(zero, 12) << fe::to_string(rule) << (distorted ? " distorted" : "");
    }
  }
}

TEST(InterfaceElement, SixteenNodeElementHasTwentyFourZeroEnergyModes) {
  const fe::Mesh m = stacked(1, 1, true);
  const fe::Interface itf = fe::build_interface(m, options(fe::InterfaceIntegration::gauss));
  ASSERT_EQ(itf.num_points(), 9);
  const Eigen::MatrixXd k =
      Eigen::MatrixXd(fe::assemble_interface_force_and_tangent(
                          itf, VectorXd::Zero(27), constant_tangents(itf, diagonal_law(2e9, 7e9)))
                          .stiffness);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(k);
  const double top = eig.eigenvalues().maxCoeff();
  int nonzero = 0;
  for (double lambda : eig.eigenvalues())
    if (lambda > 1e-10 * top) ++nonzero;
  EXPECT_EQ(nonzero, 24);  // 48 DOFs of the element, rank 24 (3×3 Gauss integrates 8 functions)
}

TEST(InterfaceAssembly, ForceAndStiffnessEqualTheGapOperatorProducts) {
  // f = Gᵀ A t (eq. 22) and K = Gᵀ A C G (eq. 23/24), assembled element-wise, equal the products
  // with the sparse gap operator, for arbitrary (non-symmetric) tangents.
  for (bool quadratic : {false, true}) {
    fe::Mesh m = stacked(2, 2, quadratic);
    distort(m);
    rotate(m, Eigen::AngleAxisd(0.4, Vector3d(1, -1, 2).normalized()).toRotationMatrix());
    for (auto rule : kRules) {
      if (quadratic && rule == fe::InterfaceIntegration::nodal) continue;
      const fe::Interface itf = fe::build_interface(m, options(rule));
      const int np = itf.num_points();
      const VectorXd t = VectorXd::Random(3 * np);
      std::vector<Matrix3d> c(static_cast<std::size_t>(np));
      for (auto& ci : c) ci = Matrix3d::Random();
      const auto a = fe::assemble_interface_force_and_tangent(itf, t, c);
      VectorXd areas(3 * np);
      Eigen::SparseMatrix<double> ac(3 * np, 3 * np);
      std::vector<Eigen::Triplet<double>> trip;
      for (int p = 0; p < np; ++p) {
        areas.segment<3>(3 * p).setConstant(itf.points[static_cast<std::size_t>(p)].area);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            trip.emplace_back(3 * p + i, 3 * p + j,
                              itf.points[static_cast<std::size_t>(p)].area *
                                  c[static_cast<std::size_t>(p)](i, j));
      }
      ac.setFromTriplets(trip.begin(), trip.end());
      const VectorXd f = itf.gap_operator.transpose() * areas.cwiseProduct(t);
      EXPECT_LE((a.force - f).norm(), 1e-13 * f.norm());
      const Eigen::SparseMatrix<double> gt = itf.gap_operator.transpose();
      const Eigen::MatrixXd k = Eigen::MatrixXd(gt * ac * itf.gap_operator);
      EXPECT_LE((Eigen::MatrixXd(a.stiffness) - k).norm(), 1e-13 * k.norm());
    }
  }
}

TEST(InterfaceAssembly, TractionsAreEqualAndOpposite) {
  // eq. (20): the force on each top node is minus the force on its bottom partner.
  fe::Mesh m = stacked(3, 3);
  distort(m);
  for (auto rule : kRules) {
    const fe::Interface itf = fe::build_interface(m, options(rule));
    const VectorXd f = fe::interface_force(itf, VectorXd::Random(3 * itf.num_points()));
    double scale = f.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0);
    for (const fe::NodePair& pair : itf.node_pairs) {
      EXPECT_LE((f.segment<3>(3 * pair.top) + f.segment<3>(3 * pair.bottom)).norm(), 1e-15 * scale);
    }
  }
}

TEST(InterfaceAssembly, UniformOpeningGivesGapDeltaAndForcePressureTimesArea) {
  for (bool quadratic : {false, true}) {
    fe::Mesh m = stacked(3, 3, quadratic);
    distort(m);
    for (auto rule : kRules) {
      if (quadratic && rule == fe::InterfaceIntegration::nodal) continue;
      const fe::Interface itf = fe::build_interface(m, options(rule));
      EXPECT_NEAR(itf.total_area, 1.0, 1e-13);
      const double delta = 3e-6;
      VectorXd u = VectorXd::Zero(m.num_dofs());
      for (int i = 0; i < m.num_nodes(); ++i)
        if (is_upper(m, i)) u(3 * i + 2) = delta;
      const VectorXd g = fe::gaps(itf, u);
      for (int p = 0; p < itf.num_points(); ++p) {
        EXPECT_NEAR(g(3 * p + 2), delta, 1e-15 * delta);
        EXPECT_NEAR(g.segment<2>(3 * p).norm(), 0.0, 1e-14 * delta);  // frame rounding
      }
      // Uniform pressure p: t_N = -p; internal force Σ_top f = -p A n, Σ_bottom f = +p A n.
      const double p = 2.5e6;
      VectorXd t = VectorXd::Zero(3 * itf.num_points());
      for (int q = 0; q < itf.num_points(); ++q) t(3 * q + 2) = -p;
      const VectorXd f = fe::interface_force(itf, t);
      Vector3d top = Vector3d::Zero(), bottom = Vector3d::Zero();
      for (int i = 0; i < m.num_nodes(); ++i)
        (is_upper(m, i) ? top : bottom) += f.segment<3>(3 * i);
      EXPECT_LE((top - Vector3d(0, 0, -p)).norm(), 1e-13 * p);
      EXPECT_LE((bottom - Vector3d(0, 0, p)).norm(), 1e-13 * p);
    }
  }
}

TEST(InterfaceAssembly, GaussAndNodalGiveTheSameTotalsForUniformTraction) {
  fe::Mesh m = stacked(3, 3);
  distort(m);
  const fe::Interface nodal = fe::build_interface(m, options(fe::InterfaceIntegration::nodal));
  const fe::Interface gauss = fe::build_interface(m, options(fe::InterfaceIntegration::gauss));
  // A uniform traction vector (global axes) expressed in each point's frame: on the distorted
  // mesh t1 follows each element's ξ direction.
  const Vector3d traction(1.5e5, -0.8e5, -2.0e6);
  auto total = [&](const fe::Interface& itf) {
    VectorXd t(3 * itf.num_points());
    for (int p = 0; p < itf.num_points(); ++p)
      t.segment<3>(3 * p) = itf.points[static_cast<std::size_t>(p)].frame * traction;
    const VectorXd f = fe::interface_force(itf, t);
    Vector3d sum = Vector3d::Zero();
    for (int i = 0; i < m.num_nodes(); ++i)
      if (is_upper(m, i)) sum += f.segment<3>(3 * i);
    return std::pair{sum, f};
  };
  const auto [sum_nodal, f_nodal] = total(nodal);
  const auto [sum_gauss, f_gauss] = total(gauss);
  EXPECT_LE((sum_nodal - traction).norm(), 1e-13 * traction.norm());
  EXPECT_LE((sum_gauss - traction).norm(), 1e-13 * traction.norm());
  EXPECT_GT((f_nodal - f_gauss).norm(), 1e-3 * f_gauss.norm());  // the distributions differ
}

TEST(InterfaceAssembly, NodalIntegrationDecouplesNodePairs) {
  fe::Mesh m = stacked(3, 3);
  distort(m);
  std::vector<int> pair_of(static_cast<std::size_t>(m.num_nodes()), -1);
  for (auto rule : kRules) {
    const fe::Interface itf = fe::build_interface(m, options(rule));
    for (std::size_t k = 0; k < itf.node_pairs.size(); ++k) {
      pair_of[static_cast<std::size_t>(itf.node_pairs[k].bottom)] = static_cast<int>(k);
      pair_of[static_cast<std::size_t>(itf.node_pairs[k].top)] = static_cast<int>(k);
    }
    const auto k =
        fe::assemble_interface_force_and_tangent(itf, VectorXd::Zero(3 * itf.num_points()),
                                                 constant_tangents(itf, diagonal_law(1e9, 4e9)))
            .stiffness;
    int coupled = 0;
    for (int col = 0; col < k.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
        if (it.value() != 0.0 && pair_of[static_cast<std::size_t>(it.row() / 3)] !=
                                     pair_of[static_cast<std::size_t>(it.col() / 3)])
          ++coupled;
    if (rule == fe::InterfaceIntegration::nodal) {
      EXPECT_EQ(coupled, 0);  // block-diagonal: one 6×6 block per node pair
    } else {
      EXPECT_GT(coupled, 0);  // Gauss couples neighbouring node pairs
    }
  }
}

TEST(InterfaceBuild, TiltedInterfaceHasTheRotatedFrame) {
  const Matrix3d r =
      Eigen::AngleAxisd(1.1, Vector3d(0.3, -1.0, 0.6).normalized()).toRotationMatrix();
  fe::Mesh m = stacked(2, 2);
  rotate(m, r);
  for (auto rule : kRules) {
    const fe::Interface itf = fe::build_interface(m, options(rule));
    EXPECT_NEAR(itf.total_area, 1.0, 1e-13);
    const Vector3d relative(2e-6, -1e-6, 4e-6);  // (g_Tx, g_Ty, g_N) in the rotated frame
    VectorXd u = VectorXd::Zero(m.num_dofs());
    for (int i = 0; i < m.num_nodes(); ++i)
      if (is_upper(m, i)) u.segment<3>(3 * i) = r * relative;
    const VectorXd g = fe::gaps(itf, u);
    for (int p = 0; p < itf.num_points(); ++p) {
      const fe::InterfacePoint& point = itf.points[static_cast<std::size_t>(p)];
      EXPECT_LE((point.frame - r.transpose()).norm(), 1e-14);  // rows R e_x, R e_y, R e_z
      EXPECT_NEAR(point.frame.determinant(), 1.0, 1e-14);
      EXPECT_LE((g.segment<3>(3 * p) - relative).norm(), 1e-14 * relative.norm());
      EXPECT_NEAR((r.transpose() * point.position).z(), 1.0, 1e-14);
    }
  }
}

TEST(InterfaceBuild, ErrorsNameTheSurfaceAndTheElement) {
  {
    fe::InterfaceOptions o = options(fe::InterfaceIntegration::nodal);
    o.top_surface = "nowhere";
    const std::string msg = error_of(stacked(2, 2), o);
    EXPECT_NE(msg.find("unknown surface 'nowhere' (top_surface)"), std::string::npos) << msg;
  }
  {  // non-matching meshes: 2×2 below, 3×3 above
    const std::string msg = error_of(stacked(2, 3), options(fe::InterfaceIntegration::nodal));
    EXPECT_NE(msg.find("interface 'joint': matching meshes are required: bottom face of element "
                       "1 (S2) (surface 'lower_top') at (0.25, 0.25, 1) has no coincident face "
                       "on surface 'upper_bottom'"),
              std::string::npos)
        << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos);
  }
  {  // the top surface larger than the bottom one: an unmatched top face
    fe::Mesh m = stacked(2, 2);
    auto& faces = m.surfaces.at("lower_top");
    faces.erase(faces.begin() + 3);
    const std::string msg = error_of(m, options(fe::InterfaceIntegration::nodal));
    EXPECT_NE(msg.find("top face of element 1004 (S1) (surface 'upper_bottom') at (0.75, 0.75, 1) "
                       "has no coincident face on surface 'lower_top'"),
              std::string::npos)
        << msg;
  }
  {  // a duplicated lower block: coincident faces with the same outward normal
    fe::Mesh m = block("lower", 2, 2, 1, Vector3d(0, 0, 0), Vector3d(1, 1, 1), false, 0);
    fe::append(m, block("copy", 2, 2, 1, Vector3d(0, 0, 0), Vector3d(1, 1, 1), false, 1000));
    fe::InterfaceOptions o = options(fe::InterfaceIntegration::gauss);
    o.top_surface = "copy_top";
    const std::string msg = error_of(m, o);
    EXPECT_NE(msg.find("surfaces 'lower_top' and 'copy_top' do not face each other: bottom face "
                       "of element 1 (S2) and top face of element 1001 (S2)"),
              std::string::npos)
        << msg;
  }
  {  // mixed quad4/quad8
    fe::Mesh m = block("lower", 2, 2, 1, Vector3d(0, 0, 0), Vector3d(1, 1, 1), false, 0);
    fe::append(m, block("upper", 2, 2, 1, Vector3d(0, 0, 1), Vector3d(1, 1, 1), true, 1000));
    const std::string msg = error_of(m, options(fe::InterfaceIntegration::gauss));
    EXPECT_NE(msg.find("mixed face types on a matching interface: top face of element 1001 (S1)"),
              std::string::npos)
        << msg;
  }
  {  // nodal integration of quad8 faces
    const std::string msg = error_of(stacked(2, 2, true), options(fe::InterfaceIntegration::nodal));
    EXPECT_NE(msg.find("integration 'nodal' needs linear faces (tri3, quad4)"), std::string::npos)
        << msg;
  }
  {  // the same faces under two names: no separate nodes
    fe::Mesh m = stacked(2, 2);
    m.surfaces["alias"] = m.surfaces.at("lower_top");
    fe::InterfaceOptions o = options(fe::InterfaceIntegration::nodal);
    o.top_surface = "alias";
    const std::string msg = error_of(m, o);
    EXPECT_NE(msg.find("share node"), std::string::npos) << msg;
  }
  {
    fe::InterfaceOptions o = options(fe::InterfaceIntegration::nodal);
    o.match_tolerance = 0.0;
    EXPECT_NE(error_of(stacked(2, 2), o).find("match_tolerance"), std::string::npos);
  }
}

TEST(InterfaceBuild, ToleranceIsRelativeToTheFaceSize) {
  fe::Mesh m = stacked(2, 2);
  m.coordinates *= 1e-3;  // millimetre-sized blocks
  for (int i = 0; i < m.num_nodes(); ++i)
    if (is_upper(m, i)) m.coordinates(0, i) += 2e-10;  // 4e-7 of the face size (0.7 mm)
  EXPECT_NO_THROW((void)fe::build_interface(m, options(fe::InterfaceIntegration::nodal)));
  for (int i = 0; i < m.num_nodes(); ++i)
    if (is_upper(m, i)) m.coordinates(0, i) += 1e-9;  // 2e-6 of the face size
  EXPECT_NE(error_of(m, options(fe::InterfaceIntegration::nodal)).find("matching meshes"),
            std::string::npos);
}

TEST(InterfaceContact, AssembledTangentMatchesCentralDifferences) {
  jc::ContactPointOptions o;
  o.normal = {2.0e6, 2.0e5, 0.0};  // p_N0 = 2 MPa at g_N = 0, λ = 2e5 1/m
  o.friction_coefficient = 0.4;
  o.stiffness_ratio = 0.8;
  const jc::ContactPoint law(o, std::make_shared<jc::GaulMayerLaw>(0.3));
  fe::Mesh m = stacked(2, 2);
  distort(m);
  rotate(m, Eigen::AngleAxisd(0.5, Vector3d(1, 1, 0).normalized()).toRotationMatrix());
  for (auto rule : kRules) {
    const fe::Interface itf = fe::build_interface(m, options(rule));
    // A closure that varies over the interface, tangential displacements of a few µm, and an
    // initial gap field (one point nearly open).
    VectorXd u = VectorXd::Zero(m.num_dofs());
    for (int i = 0; i < m.num_nodes(); ++i) {
      const Vector3d x = m.coordinates.col(i);
      u.segment<3>(3 * i) = (is_upper(m, i) ? 1.0 : -0.5) *
                            Vector3d(0.3e-6 * (1 + x.x()), -0.2e-6 * x.y(), -1e-6 * (1 + x.z()));
    }
    VectorXd g0 = VectorXd::LinSpaced(itf.num_points(), 0.0, 0.5e-6);
    g0(0) = 60e-6;  // p_N/p_N0 ~ e^-12: closed but tiny pressure
    const auto state = fe::evaluate_static_contact(itf, law, u, g0);
    EXPECT_EQ(state.num_open, 0);
    EXPECT_GT(state.pressure.minCoeff(), 0.0);
    // Microslip is active: tangential tractions, and their coupling to g_N through μ p_N and k_T.
    double coupling = 0.0, friction = 0.0;
    for (int p = 0; p < itf.num_points(); ++p) {
      coupling =
          std::max(coupling, state.tangent[static_cast<std::size_t>(p)].block<2, 1>(0, 2).norm());
      friction = std::max(friction, state.traction.segment<2>(3 * p).norm() / state.pressure(p));
    }
    EXPECT_GT(coupling, 0.0);
    EXPECT_GT(friction, 0.05);
    EXPECT_LT(friction, 0.4);  // below the slip limit μ p_N
    const Eigen::MatrixXd k = Eigen::MatrixXd(state.stiffness);
    const double h = 1e-12;
    double worst = 0.0;
    for (int j = 0; j < m.num_dofs(); ++j) {
      if (k.col(j).norm() == 0.0) continue;
      VectorXd up = u, um = u;
      up(j) += h;
      um(j) -= h;
      const VectorXd fd = (fe::evaluate_static_contact(itf, law, up, g0).force -
                           fe::evaluate_static_contact(itf, law, um, g0).force) /
                          (2 * h);
      worst = std::max(worst, (fd - k.col(j)).norm() / k.col(j).norm());
    }
    EXPECT_LT(worst, 1e-5) << fe::to_string(rule);
    // And the per-point law matches: t_N = -p_N, pressure from eq. (6).
    for (int p = 0; p < itf.num_points(); ++p)
      EXPECT_DOUBLE_EQ(state.pressure(p), o.normal.pressure(state.gap(3 * p + 2)));
    // One law per point gives the same state.
    const std::vector<jc::ContactPoint> laws(static_cast<std::size_t>(itf.num_points()), law);
    const auto same = fe::evaluate_static_contact(itf, laws, u, g0);
    EXPECT_EQ((same.force - state.force).norm(), 0.0);
  }
}
