#pragma once
// One contact point of a zero-thickness interface: the exponential normal law (eq. 6) and a
// tangential law (eq. 10 or Jenkins) whose slip limit and stiffness follow the normal pressure:
//   slip limit      L   = μ p_N
//   stiffness       k_T = χ λ p_N   (proportional: Mindlin's k_T/k_N = χ, 2(1-ν)/(2-ν) for equal
//                                   materials)   or   k_T = k_T0 (constant)
// Input: the relative displacement g = (g_Tx, g_Ty, g_N) (g_N: gap, opening positive).
// Output: the traction t = (t_Tx, t_Ty, t_N) conjugate to g (t_N = -p_N) and its consistent
// tangent. Below the gapping floor p_N < ε_gap p_N0 (p_N = 0 for the linear law) the point is
// open: t_T = 0 and its tangents vanish, so no quantity divides by p_N. With μ = 0 (frictionless)
// t_T = 0 and k_T = 0 everywhere. All quantities are per unit area; with p_N0 a force (N)
// they are forces.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "jointhb/contact/normal_law.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "jointhb/contact/tangential_law.hpp"

namespace jointhb::contact {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

enum class TangentialStiffnessModel {
  proportional,  ///< k_T = χ λ p_N (follows the normal stiffness)
  constant,      ///< k_T = k_T0
};

struct ContactPointOptions {
  NormalLaw normal;                   ///< eq. (6), or (N-1), (N-2) of normal_law.hpp
  double friction_coefficient = 0.3;  ///< μ [-], ≥ 0 (0: frictionless, no tangential stiffness)
  TangentialStiffnessModel stiffness_model = TangentialStiffnessModel::proportional;
  double stiffness_ratio = 2.0 * (1.0 - 0.33) / (2.0 - 0.33);  ///< χ [-], > 0 (proportional)
  double tangential_stiffness = 0.0;    ///< k_T0 [Pa/m], > 0 (constant model)
  double gap_pressure_ratio = 1.0e-12;  ///< ε_gap ∈ [0, 1): p_N/p_N0 below which the point is open

  [[nodiscard]] std::string validate() const;
  /// χ k ε_gap with k = λ p_N0 (exponential laws) or k_N (linear): the proportional stiffness at
  /// the gapping floor, a positive lower bound where a frozen k_T must stay valid (T-30).
  [[nodiscard]] double tangential_stiffness_floor() const;
};

/// Slip limit and stiffness at a gap, with their derivatives with respect to the gap.
struct TangentialState {
  TangentialLimits limits;
  double d_limit = 0.0;           ///< dL/dg_N
  double d_stiffness = 0.0;       ///< dk_T/dg_N
  double pressure = 0.0;          ///< p_N
  double normal_stiffness = 0.0;  ///< λ p_N
  bool open = false;              ///< p_N below the gapping floor
};

/// One increment of a contact point.
struct ContactStep {
  Vec3 traction = Vec3::Zero();    ///< t_1 = (t_Tx, t_Ty, t_N)
  Mat3 tangent = Mat3::Zero();     ///< consistent tangent ∂t_1/∂g_1 (t_0 and g_0 held)
  Mat3 d_previous = Mat3::Zero();  ///< ∂t_1/∂t_T0 in the first two columns (third zero)
  double dissipation = 0.0;
  bool open = false;
};

/// Periodic steady state of a contact point on a sampled path.
struct PeriodicContactResult {
  PeriodicStateResult tangential;        ///< the tangential periodic state (with step derivatives)
  std::vector<Vec3> traction;            ///< t(t_i)
  std::vector<double> d_limit;           ///< dL_i/dg_N,i
  std::vector<double> d_stiffness;       ///< dk_i/dg_N,i
  std::vector<double> normal_stiffness;  ///< λ p_N,i = dt_N/dg_N
  double open_fraction = 0.0;            ///< share of samples below the gapping floor
};

class ContactPoint {
 public:
  /// Throws std::invalid_argument naming the field when options are invalid or law is null.
  ContactPoint(ContactPointOptions options, std::shared_ptr<const TangentialLaw> law);

  [[nodiscard]] const ContactPointOptions& options() const { return options_; }
  [[nodiscard]] const TangentialLaw& law() const { return *law_; }

  /// The same point with the constant stiffness model k_T = `stiffness` (> 0; same law, normal
  /// law, μ and gapping floor): the frozen-stiffness point of hb/interface_balance.hpp (T-30).
  [[nodiscard]] ContactPoint with_constant_stiffness(double stiffness) const;

  [[nodiscard]] TangentialState tangential_state(double gap) const;

  /// Increment from (t_T0, g_0) to g_1.
  [[nodiscard]] ContactStep step(const Vec2& tangential_traction, const Vec3& g0,
                                 const Vec3& g1) const;

  /// Periodic steady state on the path g(t_i), i = 0..N-1; the reference state (preload) fixes
  /// the traction when the periodicity condition does not.
  [[nodiscard]] PeriodicContactResult periodic(const std::vector<Vec3>& path,
                                               const PeriodicStateOptions& options = {}) const;

  /// δt_i (3N × m) of the periodic state for m path perturbations δg_i (3N × m, rows 3i..3i+2).
  [[nodiscard]] static Eigen::MatrixXd periodic_sensitivity(const PeriodicContactResult& state,
                                                            const Eigen::MatrixXd& path);

 private:
  ContactPointOptions options_;
  std::shared_ptr<const TangentialLaw> law_;
};

}  // namespace jointhb::contact
