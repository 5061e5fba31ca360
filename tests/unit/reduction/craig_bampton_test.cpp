// Craig–Bampton reduction (reduction/craig_bampton.hpp) on two stacked aluminium blocks joined by
// a zero-thickness interface whose nodes are the boundary. Checked against independent
// computations: the projection Tᵀ K T, Tᵀ M T formed column by column from expand(); the dense
// generalized eigenproblem of the full model; the full static solution.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/reduction/craig_bampton.hpp"
#include "unit/test_constants.hpp"

namespace fe = jointhb::fe;
namespace rd = jointhb::reduction;

namespace {
// (in the anonymous namespace, like the same alias of the other test sources of its unity batch)
using SpMat = Eigen::SparseMatrix<double>;

using test_constants::kTwoPi;

struct Blocks {
  fe::Mesh mesh;
  fe::StructuralMatrices structure;
  fe::Interface interface;
  std::vector<int> boundary;  // the DOFs of every interface node
  SpMat contact;              // stuck contact tangent Gᵀ A C G, C = diag(k_t, k_t, k_n)
};

// Two 20 × 20 × 10 mm blocks, 4 × 4 × 2 elements each, the upper on the lower.
Blocks blocks() {
  Blocks b;
  fe::BoxOptions lower;
  lower.part = "lower";
  lower.size = {0.02, 0.02, 0.01};
  lower.divisions = {4, 4, 2};
  fe::BoxOptions upper = lower;
  upper.part = "upper";
  upper.origin = {0.0, 0.0, 0.01};
  b.mesh = fe::box_mesh(lower);
  fe::append(b.mesh, fe::box_mesh(upper));
  const fe::Material al{"aluminium", 70e9, 0.33, 2700.0};
  b.structure = fe::assemble(b.mesh, {al, al});
  fe::InterfaceOptions io;
  io.bottom_surface = "lower.zmax";
  io.top_surface = "upper.zmin";
  b.interface = fe::build_interface(b.mesh, io);
  std::set<int> nodes;
  for (const auto& e : b.interface.elements) {
    nodes.insert(e.bottom_nodes.begin(), e.bottom_nodes.end());
    nodes.insert(e.top_nodes.begin(), e.top_nodes.end());
  }
  for (int n : nodes)
    for (int d = 0; d < 3; ++d) b.boundary.push_back(3 * n + d);
  // k_n = λ p_N at 10 MPa and λ = 1e6 1/m; k_t = 0.8 k_n.
  const Eigen::Matrix3d C = Eigen::Vector3d(0.8e13, 0.8e13, 1e13).asDiagonal();
  const std::vector<Eigen::Matrix3d> tangents(b.interface.points.size(), C);
  std::vector<Eigen::Triplet<double>> t;
  fe::add_interface_stiffness(b.interface, tangents, t);
  b.contact.resize(b.mesh.num_dofs(), b.mesh.num_dofs());
  b.contact.setFromTriplets(t.begin(), t.end());
  return b;
}

// T = [∂u/∂q_k] column by column through expand().
Eigen::MatrixXd transformation(const rd::CraigBamptonModel& r) {
  const auto n = static_cast<Eigen::Index>(r.boundary.size() + r.interior.size());
  Eigen::MatrixXd T(n, r.size());
  for (int k = 0; k < r.size(); ++k) T.col(k) = r.expand(Eigen::VectorXd::Unit(r.size(), k));
  return T;
}

// The boundary block P K Pᵀ of a full sparse matrix in the model's boundary order, padded to the
// reduced size.
Eigen::MatrixXd on_boundary(const rd::CraigBamptonModel& r, const SpMat& K) {
  const Eigen::MatrixXd dense(K);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(r.size(), r.size());
  for (int a = 0; a < r.num_boundary(); ++a)
    for (int c = 0; c < r.num_boundary(); ++c)
      out(a, c) = dense(r.boundary[static_cast<std::size_t>(a)], r.boundary[static_cast<std::size_t>(c)]);
  return out;
}

Eigen::VectorXd frequencies(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, M);
  Eigen::VectorXd f = solver.eigenvalues();
  for (Eigen::Index k = 0; k < f.size(); ++k) f[k] = std::sqrt(std::max(f[k], 0.0)) / kTwoPi;
  return f;
}

rd::CraigBamptonOptions cutoff(double hz) {
  rd::CraigBamptonOptions o;
  o.cutoff_hz = hz;
  o.initial_count = 8;
  o.modal.shift = -1.0;
  return o;
}

}  // namespace

TEST(CraigBampton, ReducedMatricesAreTheProjectionThroughExpand) {
  const Blocks b = blocks();
  const rd::CraigBamptonModel r = rd::craig_bampton(b.structure.stiffness, b.structure.mass, b.boundary, cutoff(300e3));
  ASSERT_GT(r.num_modes(), 4);
  EXPECT_EQ(r.num_boundary(), 150);  // 2 × 25 interface nodes × 3
  const Eigen::MatrixXd T = transformation(r);
  const Eigen::MatrixXd K(b.structure.stiffness), M(b.structure.mass);
  const Eigen::MatrixXd Kr = T.transpose() * K * T, Mr = T.transpose() * M * T;
  EXPECT_LT((Kr - r.stiffness).norm(), 1e-10 * Kr.norm());
  EXPECT_LT((Mr - r.mass).norm(), 1e-10 * Mr.norm());
  // Tᵀ f through project() is the same product.
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(K.rows(), -1.0, 2.0);
  EXPECT_LT((r.project(f) - T.transpose() * f).norm(), 1e-12 * (T.transpose() * f).norm());
  // The fixed-interface modes are M_ii-normalised: the modal block of M_r is the identity and
  // that of K_r is Λ, all below the cutoff.
  EXPECT_LT((r.mass.bottomRightCorner(r.num_modes(), r.num_modes()) -
             Eigen::MatrixXd::Identity(r.num_modes(), r.num_modes())).norm(), 1e-12);
  EXPECT_LE(r.normal_frequencies_hz.maxCoeff(), 300e3);
  EXPECT_FALSE(r.truncated_by_max_modes);
}

// The contact tangent acts on boundary DOFs only, so reducing K + K_c equals reducing K and adding
// K_c to the boundary block: the structure is reduced once, whatever the contact state.
TEST(CraigBampton, BoundaryStiffnessAddsExactlyAfterReduction) {
  const Blocks b = blocks();
  const SpMat K = b.structure.stiffness, Kc = b.structure.stiffness + b.contact;
  const rd::CraigBamptonModel without = rd::craig_bampton(K, b.structure.mass, b.boundary, cutoff(300e3));
  const rd::CraigBamptonModel with = rd::craig_bampton(Kc, b.structure.mass, b.boundary, cutoff(300e3));
  ASSERT_EQ(with.size(), without.size());
  const Eigen::MatrixXd added = without.stiffness + on_boundary(without, b.contact);
  EXPECT_LT((with.stiffness - added).norm(), 1e-11 * added.norm());
  EXPECT_LT((with.mass - without.mass).norm(), 1e-12 * with.mass.norm());
}

// Rayleigh–Ritz: the reduced frequencies bound the full ones from above, and the error below the
// cutoff falls as the cutoff rises (more fixed-interface modes kept).
TEST(CraigBampton, FrequenciesConvergeFromAboveWithTheCutoff) {
  const Blocks b = blocks();
  const SpMat K = b.structure.stiffness + b.contact;
  const Eigen::VectorXd full = frequencies(Eigen::MatrixXd(K), Eigen::MatrixXd(b.structure.mass));
  double previous = 1.0;
  // Elastic modes from 66 kHz; the fixed-interface modes start at 70 kHz. Score the band below
  // 100 kHz (7 modes) with cutoffs of 1.5, 3 and 6 times its top.
  for (double hz : {150e3, 300e3, 600e3}) {
    const rd::CraigBamptonModel r = rd::craig_bampton(K, b.structure.mass, b.boundary, cutoff(hz));
    const Eigen::VectorXd reduced = frequencies(r.stiffness, r.mass);
    double worst = 0.0;
    for (Eigen::Index k = 6; k < reduced.size() && full[k] < 100e3; ++k) {  // skip 6 rigid modes
      EXPECT_GE(reduced[k], full[k] * (1.0 - 1e-9)) << "mode " << k << " cutoff " << hz;
      worst = std::max(worst, reduced[k] / full[k] - 1.0);
    }
    // measured: 150 kHz 15 modes 7.5e-2; 300 kHz 72 modes 1.1e-3; 600 kHz 230 modes 6.3e-5
    std::printf("cutoff %.0f kHz: %d fixed-interface modes, worst relative error %.3g\n", hz / 1e3,
                r.num_modes(), worst);
    EXPECT_LT(worst, previous) << "cutoff " << hz;
    previous = worst;
  }
  EXPECT_LT(previous, 1e-4);
  // Rigid-body motion is represented exactly (the constraint modes contain it).
  const rd::CraigBamptonModel r = rd::craig_bampton(K, b.structure.mass, b.boundary, cutoff(150e3));
  EXPECT_LT(frequencies(r.stiffness, r.mass)[5], 1e-3 * full[6]);
}

// Loads on the boundary only: the constraint modes make the static response exact (Guyan).
TEST(CraigBampton, StaticResponseToBoundaryLoadsIsExact) {
  const Blocks b = blocks();
  const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(b.mesh.num_nodes(), {{b.mesh.node_sets.at("lower.zmin")}});
  const SpMat K = dofs.restrict(SpMat(b.structure.stiffness + b.contact));
  const SpMat M = dofs.restrict(b.structure.mass);
  std::vector<int> boundary;
  for (int d : b.boundary) boundary.push_back(dofs.free_of_full[static_cast<std::size_t>(d)]);
  const rd::CraigBamptonModel r = rd::craig_bampton(K, M, boundary, cutoff(60e3));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(K.rows());
  for (std::size_t k = 0; k < boundary.size(); ++k) f[boundary[k]] = std::sin(1.0 + static_cast<double>(k));
  const Eigen::VectorXd u = Eigen::MatrixXd(K).ldlt().solve(f);
  const Eigen::VectorXd q = r.stiffness.ldlt().solve(r.project(f));
  EXPECT_LT((r.expand(q) - u).norm(), 1e-9 * u.norm());
  EXPECT_LT(q.tail(r.num_modes()).norm(), 1e-9 * q.head(r.num_boundary()).norm());
}

TEST(CraigBampton, BadInputIsNamed) {
  const Blocks b = blocks();
  const SpMat& K = b.structure.stiffness;
  const SpMat& M = b.structure.mass;
  EXPECT_THROW((void)rd::craig_bampton(K, M, b.boundary, cutoff(0.0)), std::invalid_argument);
  std::vector<int> twice = b.boundary;
  twice.push_back(b.boundary.front());
  EXPECT_THROW((void)rd::craig_bampton(K, M, twice, cutoff(1e5)), std::invalid_argument);
  EXPECT_THROW((void)rd::craig_bampton(K, M, {-1}, cutoff(1e5)), std::invalid_argument);
  // The boundary on the lower block only: the upper block floats, K_ii is singular.
  std::vector<int> lower_only;
  for (int n : b.mesh.node_sets.at("lower.zmax"))
    for (int d = 0; d < 3; ++d) lower_only.push_back(3 * n + d);
  try {
    (void)rd::craig_bampton(K, M, lower_only, cutoff(1e5));
    FAIL() << "expected a singular interior";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
  }
}
