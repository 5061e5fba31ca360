#pragma once
// The TRUE errors of a damping-curve or FRF point at (H, N_t), against which the estimates of
// continuation/error_estimate.hpp are measured (error_estimate_test.cpp and
// validation/hb/error_estimate.cpp): the same point solved by Newton at the same λ (or Ω)
//   at (H, N_ref):      the aliasing part,  true_aliasing = out(H, N_ref) − out(H, N_t)
//   at (H_ref, N_ref):  the total,          true_total    = out(H_ref, N_ref) − out(H, N_t)
//   the truncation part true_truncation = out(H_ref, N_ref) − out(H, N_ref),
// each relative to |out(H, N_t)|. The reference is reached on a ladder H → 15 → 31 → H_ref
// (each level from the previous one's transferred coefficients).

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/continuation/frf.hpp"

namespace jointhb::error_reference {

struct TrueError {
  double truncation = 0.0;
  double aliasing = 0.0;
  double total = 0.0;
};

struct ModeTruth {
  bool ok = false;
  TrueError omega, damping;
};

struct FrfTruth {
  bool ok = false;
  TrueError amplitude_h1, amplitude_max;
};

/// m = 1, k = 1e4, one contact (`law`: "jenkins" or "gaul-mayer", n = 1/3) to ground with
/// k_T0 = 3e4, μF_N = 1, ζ = 0.2 % of the stuck system (validation/hb/epmc_convergence.cpp):
/// Jenkins slips at |x| = 3.33e-5, Gaul–Mayer reaches gross slip at g_max = 5e-5.
inline hb::DiscreteSystem one_dof_system(const std::string& law) {
  hb::DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.stiffness = Eigen::MatrixXd::Constant(1, 1, 1e4).sparseView();
  s.damping = Eigen::MatrixXd::Constant(1, 1, 2.0 * 0.002 * std::sqrt(4e4)).sparseView();
  hb::ContactElement c;
  c.law = law;
  c.exponent = 1.0 / 3.0;
  c.dof_a = 0;
  c.stiffness = 3e4;
  c.friction_coefficient = 1.0;
  c.normal_force = 1.0;
  s.contacts.push_back(c);
  return s;
}

/// Options of a damping curve that stops at its first point, exactly at amplitude q (Newton from
/// the linear mode at fixed λ = log10 q): the point whose estimate is compared with the truth.
inline continuation::BackboneOptions single_point_options(double q, int h, int samples) {
  continuation::BackboneOptions o;
  o.mode.harmonics = h;
  o.mode.time_samples = samples;
  o.log10_amplitude_start = std::log10(q);
  o.log10_amplitude_end = o.log10_amplitude_start + 1.0;
  o.continuation.max_points = 1;
  o.continuation.max_start_iterations = 100;
  o.continuation.residual_tolerance = 1e-13;
  return o;
}

inline double relative_to(double value, double base) {
  return base != 0.0 ? (value - base) / std::abs(base) : value - base;
}

inline TrueError true_error(double point, double fine_sampled, double reference) {
  return {relative_to(reference, point) - relative_to(fine_sampled, point),
          relative_to(fine_sampled, point), relative_to(reference, point)};
}

inline std::vector<int> ladder(int h, int h_ref) {
  std::vector<int> levels;
  for (const int level : {15, 31, h_ref})
    if (level > h && level <= h_ref) levels.push_back(level);
  return levels;
}

/// The true errors of damping-curve point y at λ, computed with options `o` (H, N_t).
inline ModeTruth mode_truth(const hb::DiscreteSystem& system, const hb::NonlinearModeOptions& o,
                            const Eigen::VectorXd& y, double lambda, int h_ref = 63,
                            int n_ref = 2048, double tolerance = 1e-13) {
  ModeTruth t;
  hb::NonlinearModeOptions fine = o;
  fine.time_samples = n_ref;
  const hb::NonlinearModeResidual sampled(system, fine);
  const std::optional<Eigen::VectorXd> ys =
      continuation::solve_mode_at(sampled, y, lambda, tolerance);
  if (!ys) return t;
  Eigen::VectorXd yr = *ys;
  hb::FourierBasis from = sampled.balance().basis();
  for (const int h : ladder(o.harmonics, h_ref)) {
    hb::NonlinearModeOptions lo = fine;
    lo.harmonics = h;
    const hb::NonlinearModeResidual level(system, lo);
    Eigen::VectorXd start(level.unknowns());
    start.head(level.balance().unknowns()) = hb::transfer_coefficients(
        from, level.balance().basis(), yr.head(yr.size() - 2), system.dofs());
    start.tail(2) = yr.tail(2);
    const std::optional<Eigen::VectorXd> next =
        continuation::solve_mode_at(level, start, lambda, tolerance);
    if (!next) return t;
    yr = *next;
    from = level.balance().basis();
  }
  const auto outputs = [](const Eigen::VectorXd& v) {
    const double omega = v[v.size() - 2];
    return std::pair<double, double>{omega, v[v.size() - 1] / (2.0 * omega)};
  };
  const auto [w, z] = outputs(y);
  const auto [ws, zs] = outputs(*ys);
  const auto [wr, zr] = outputs(yr);
  t.omega = true_error(w, ws, wr);
  t.damping = true_error(z, zs, zr);
  t.ok = true;
  return t;
}

/// The true errors of FRF point x at Ω, computed with options `o` (H, N_t); `scale` of the
/// residual (the force amplitude).
inline FrfTruth frf_truth(const hb::DiscreteSystem& system, const hb::Excitation& excitation,
                          const hb::HarmonicBalanceOptions& o, const Eigen::VectorXd& x,
                          double omega, int dof, double scale, int h_ref = 63, int n_ref = 2048,
                          double tolerance = 1e-13) {
  FrfTruth t;
  hb::HarmonicBalanceOptions fine = o;
  fine.time_samples = n_ref;
  const hb::HarmonicBalance base(system, excitation, o);
  const hb::HarmonicBalance sampled(system, excitation, fine);
  const std::optional<Eigen::VectorXd> xs =
      continuation::solve_balance_at(sampled, x, omega, tolerance, scale);
  if (!xs) return t;
  Eigen::VectorXd xr = *xs;
  hb::FourierBasis from = sampled.basis();
  std::optional<hb::HarmonicBalance> last;
  for (const int h : ladder(o.harmonics, h_ref)) {
    hb::HarmonicBalanceOptions lo = fine;
    lo.harmonics = h;
    last.emplace(system, excitation, lo);
    const std::optional<Eigen::VectorXd> next = continuation::solve_balance_at(
        *last, hb::transfer_coefficients(from, last->basis(), xr, system.dofs()), omega, tolerance,
        scale);
    if (!next) return t;
    xr = *next;
    from = last->basis();
  }
  const auto outputs = [dof](const hb::HarmonicBalance& b, const Eigen::VectorXd& v) {
    return std::pair<double, double>{
        b.fundamental_amplitude(v, dof),
        b.basis().peak_magnitude(v.segment(b.index(dof, 0), b.basis().size()))};
  };
  const auto [a, p] = outputs(base, x);
  const auto [as, ps] = outputs(sampled, *xs);
  const auto [ar, pr] = last ? outputs(*last, xr) : outputs(sampled, xr);
  t.amplitude_h1 = true_error(a, as, ar);
  t.amplitude_max = true_error(p, ps, pr);
  t.ok = true;
  return t;
}

}  // namespace jointhb::error_reference
