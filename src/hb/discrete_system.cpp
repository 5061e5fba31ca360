#include "jointhb/hb/discrete_system.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/contact/preloaded_normal_law.hpp"

namespace jointhb::hb {
namespace {

std::string check_square(const SparseMatrix& a, int n, const char* name, bool may_be_empty) {
  if (may_be_empty && a.rows() == 0 && a.cols() == 0) return {};
  if (a.rows() != n || a.cols() != n) {
    return fmt::format("{}: must be {} x {} like the mass matrix, got {} x {}", name, n, n,
                       a.rows(), a.cols());
  }
  const Eigen::MatrixXd d(a);
  if (!d.allFinite()) return fmt::format("{}: must be finite", name);
  const double scale = d.cwiseAbs().maxCoeff();
  if ((d - d.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    return fmt::format("{}: must be symmetric", name);
  }
  return {};
}

}  // namespace

Eigen::VectorXd Excitation::at(double omega, double time, int dofs) const {
  Eigen::VectorXd f = static_force.size() == dofs ? static_force : Eigen::VectorXd::Zero(dofs);
  for (const auto& h : forces) f[h.dof] += h.amplitude * std::cos(h.harmonic * omega * time);
  return f;
}

bool Excitation::has_static_part() const {
  return static_force.size() > 0 && static_force.cwiseAbs().maxCoeff() > 0.0;
}

std::string DiscreteSystem::validate() const {
  const int n = dofs();
  if (n <= 0 || mass.cols() != n) return "mass: must be a non-empty square matrix";
  if (auto m = check_square(mass, n, "mass", false); !m.empty()) return m;
  if (auto m = check_square(damping, n, "damping", true); !m.empty()) return m;
  if (auto m = check_square(stiffness, n, "stiffness", false); !m.empty()) return m;
  Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(mass)};
  if (llt.info() != Eigen::Success) return "mass: must be positive definite";
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const auto& c = contacts[i];
    const std::string where = fmt::format("contacts[{}]", i);
    if (c.dof_a < 0 || c.dof_a >= n || c.dof_b >= n || c.dof_b == c.dof_a || c.dof_b < -1) {
      return fmt::format("{}.dofs: must be one DOF or two different DOFs in [0, {}], got [{}, {}]",
                         where, n - 1, c.dof_a, c.dof_b);
    }
    if (c.law != "jenkins" && c.law != "gaul-mayer" && !c.normal()) {
      return fmt::format("{}.law: must be one of jenkins, gaul-mayer, normal-exponential, got '{}'",
                         where, c.law);
    }
    if (c.law == "gaul-mayer" && !(c.exponent > 0.0 && c.exponent < 1.0)) {
      return fmt::format("{}.n: must be in (0, 1), got {}", where, c.exponent);
    }
    if (!c.normal() && (!(c.friction_coefficient > 0.0) || !std::isfinite(c.friction_coefficient))) {
      return fmt::format("{}.mu: must be finite and > 0, got {}", where, c.friction_coefficient);
    }
    if (!(c.normal_force > 0.0) || !std::isfinite(c.normal_force)) {
      return fmt::format("{}.normal_force: must be finite and > 0, got {}", where, c.normal_force);
    }
    if (!(c.stiffness > 0.0) || !std::isfinite(c.stiffness)) {
      return fmt::format("{}.{}: must be finite and > 0, got {}", where, c.normal() ? "kn" : "kt0",
                         c.stiffness);
    }
    if (c.normal() && c.has_reference_offset()) {
      return where + ".reference_force: a normal element is about its preloaded state (must be 0)";
    }
    if (!std::isfinite(c.reference_force) || std::abs(c.reference_force) > c.slip_limit()) {
      return fmt::format("{}.reference_force: must satisfy |F_ref| <= mu F_N, got {}", where,
                         c.reference_force);
    }
    if (!std::isfinite(c.reference_slip)) return where + ".reference_slip: must be finite";
  }
  return {};
}

std::shared_ptr<const contact::TangentialLaw> DiscreteSystem::make_law(
    const ContactElement& element) {
  if (element.normal()) return std::make_shared<contact::PreloadedNormalLaw>();
  return contact::make_tangential_law(element.law, element.exponent);
}

SparseMatrix stuck_stiffness(const DiscreteSystem& system) {
  Eigen::MatrixXd k(system.stiffness);
  for (const auto& c : system.contacts) {
    k(c.dof_a, c.dof_a) += c.stiffness;
    if (c.dof_b >= 0) {
      k(c.dof_b, c.dof_b) += c.stiffness;
      k(c.dof_a, c.dof_b) -= c.stiffness;
      k(c.dof_b, c.dof_a) -= c.stiffness;
    }
  }
  return k.sparseView();
}

namespace {

LinearModes dense_modes(const SparseMatrix& mass, const SparseMatrix& stiffness) {
  const Eigen::MatrixXd m(mass);
  const Eigen::MatrixXd k(stiffness);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m);
  if (eig.info() != Eigen::Success) {
    throw std::invalid_argument("linear modes: the mass matrix must be positive definite");
  }
  LinearModes modes;
  modes.omega = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  modes.shapes = eig.eigenvectors();  // mass-normalised: Φᵀ M Φ = I
  return modes;
}

}  // namespace

LinearModes linear_modes(const DiscreteSystem& system, bool with_stuck_contacts) {
  return dense_modes(system.mass, with_stuck_contacts ? stuck_stiffness(system) : system.stiffness);
}

SparseMatrix modal_damping_matrix(const SparseMatrix& mass, const SparseMatrix& stiffness,
                                  const std::vector<double>& damping_ratios) {
  const LinearModes modes = dense_modes(mass, stiffness);
  if (static_cast<Eigen::Index>(damping_ratios.size()) > modes.omega.size()) {
    throw std::invalid_argument(fmt::format("modal damping: {} ratios given for {} modes",
                                            damping_ratios.size(), modes.omega.size()));
  }
  Eigen::VectorXd d = Eigen::VectorXd::Zero(modes.omega.size());
  for (std::size_t i = 0; i < damping_ratios.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    d[k] = 2.0 * damping_ratios[i] * modes.omega[k];
  }
  const Eigen::MatrixXd m(mass);
  const Eigen::MatrixXd mphi = m * modes.shapes;
  const Eigen::MatrixXd c = mphi * d.asDiagonal() * mphi.transpose();
  return c.sparseView();
}

}  // namespace jointhb::hb
