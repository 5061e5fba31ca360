// FRF peaks against the damping curve (issue 4 §4: "the peaks of FRFs at several force levels
// must lie on the backbone; report the distance").
//
// Description: for the systems of cases/03 (1 DOF, Gaul–Mayer joint to ground) and cases/04 (two
// masses, two Gaul–Mayer joints, mode 1), the EPMC damping curve (H = 7) and FRFs at six force
// levels from microslip to gross slip (H = 7, continuation::trace_frf) are computed. Each FRF peak
// (the accepted point of largest |fundamental|, refined by a parabola through its neighbours in
// Ω) is placed on the backbone by its modal amplitude q = |Φᵀ M X₁| (the fundamental projected on
// the stuck mode, mass-normalised) and the backbone frequency at that q (interpolated in log q) is
// compared with the peak frequency.
//
// Expected: a forced peak of a lightly damped mode lies on the backbone up to O(ζ²) (the
// damped resonance lies below the undamped one by ~ζ² ω) plus the resolution of the FRF's
// continuation steps and the projection error of a multi-DOF shape. Bounds: |Ω_peak − Ω_bb|/Ω_bb
// ≤ 2 ζ² + 2e-3 at every level, with ζ the backbone's damping ratio at that amplitude.
//
// Sample runs:
//   build/validation/hb/jointhb_validate_hb_frf_peaks_on_backbone validation/hb/results/frf_peaks
// --ci: three force levels per system.

#include <fmt/format.h>
#include <fmt/os.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_hb (CMakeLists.txt).
namespace jointhb_study_hb_frf_peaks_on_backbone {

namespace {

using namespace jointhb;

struct Case {
  std::string name;
  hb::DiscreteSystem system;
  int force_dof = 0;
  double omega_min = 0.0, omega_max = 0.0;
  std::vector<double> forces;
};

hb::ContactElement gaul_mayer(int a, int b, double kt0, double limit) {
  hb::ContactElement c;
  c.law = "gaul-mayer";
  c.exponent = 1.0 / 3.0;
  c.dof_a = a;
  c.dof_b = b;
  c.stiffness = kt0;
  c.friction_coefficient = 1.0;
  c.normal_force = limit;
  return c;
}

Case one_dof() {
  Case c;
  c.name = "case03";
  c.system.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  c.system.stiffness = Eigen::MatrixXd::Constant(1, 1, 1.0e4).sparseView();
  c.system.damping = hb::modal_damping_matrix(c.system.mass, c.system.stiffness, {0.002});
  c.system.contacts = {gaul_mayer(0, -1, 3.0e4, 1.0)};
  c.omega_min = 90.0;
  c.omega_max = 220.0;
  c.forces = {0.005, 0.02, 0.05, 0.1, 0.2, 0.4};
  return c;
}

Case two_dof() {
  Case c;
  c.name = "case04";
  Eigen::MatrixXd k(2, 2);
  k << 3.0e4, -1.0e4, -1.0e4, 1.0e4;
  c.system.mass = Eigen::MatrixXd::Identity(2, 2).sparseView();
  c.system.stiffness = k.sparseView();
  c.system.damping = hb::modal_damping_matrix(c.system.mass, c.system.stiffness, {0.002, 0.002});
  c.system.contacts = {gaul_mayer(0, -1, 2.0e4, 2.0), gaul_mayer(0, 1, 1.0e4, 0.5)};
  c.force_dof = 1;
  c.omega_min = 60.0;
  c.omega_max = 160.0;
  c.forces = {0.002, 0.01, 0.03, 0.06, 0.1, 0.2};
  return c;
}

double interpolate_log(const std::vector<double>& q, const std::vector<double>& v, double x) {
  if (x <= q.front()) return v.front();
  if (x >= q.back()) return v.back();
  const auto it = std::upper_bound(q.begin(), q.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - q.begin()) - 1;
  const double t = (std::log(x) - std::log(q[i])) / (std::log(q[i + 1]) - std::log(q[i]));
  return v[i] + t * (v[i + 1] - v[i]);
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  const bool ci = args.ci;
  const std::string& prefix = args.prefix;
  auto out = fmt::output_file(prefix + "_table.csv");
  out.print("case,force,q_peak,omega_peak,omega_backbone,zeta_backbone,rel_distance,bound\n");
  int failures = 0;
  double worst = 0.0;
  for (Case c : {one_dof(), two_dof()}) {
    if (ci) c.forces = {c.forces[0], c.forces[2], c.forces[4]};
    continuation::BackboneOptions bo;
    bo.mode.harmonics = 7;
    bo.mode.time_samples = 128;
    bo.log10_amplitude_start = -8.0;
    bo.log10_amplitude_end = -2.5;
    const continuation::BackboneCurve bb = continuation::trace_backbone(c.system, bo);
    if (!bb.completed()) {
      std::printf("FAIL %s: backbone: %s\n", c.name.c_str(), bb.message.c_str());
      ++failures;
      continue;
    }
    std::vector<double> q, om, zeta;
    for (const auto& p : bb.points) {
      q.push_back(p.state.amplitude);
      om.push_back(p.state.omega);
      zeta.push_back(p.state.damping_ratio);
    }
    const hb::LinearModes modes = hb::linear_modes(c.system, true);
    Eigen::VectorXd phi = modes.shapes.col(0);
    const Eigen::VectorXd m_phi = c.system.mass * phi;
    for (double force : c.forces) {
      hb::Excitation e;
      e.forces.push_back({c.force_dof, force, 1});
      continuation::FrfOptions fo;
      fo.omega_start = c.omega_min;
      fo.omega_end = c.omega_max;
      fo.harmonics = 7;
      fo.time_samples = 128;
      fo.output_dof = c.force_dof;
      fo.continuation.max_step = 0.02;  // resolve the peak
      // The peaks are compared, not the points' stability or error estimates (studies of their
      // own: stability_shooting, error_estimate), which took 95 % of this study's time.
      fo.stability = continuation::Stability::never;
      fo.error_estimate = false;
      const continuation::FrfCurve curve = continuation::trace_frf(c.system, e, fo);
      if (!curve.completed()) {
        std::printf("FAIL %s F = %g: FRF: %s\n", c.name.c_str(), force, curve.message.c_str());
        ++failures;
        continue;
      }
      const hb::HarmonicBalance balance(c.system, e,
                                        {7, 128, hb::HarmonicSelection::automatic, 1e-14, true});
      const int a1 = balance.basis().cosine_index(1);
      // Modal amplitude of the fundamental along the stuck mode: |φᵀ M (a₁ − i b₁)|.
      const auto modal = [&](const Eigen::VectorXd& x) {
        double re = 0.0, im = 0.0;
        for (int i = 0; i < c.system.dofs(); ++i) {
          re += m_phi[i] * x[balance.index(i, a1)];
          im += m_phi[i] * x[balance.index(i, a1 + 1)];
        }
        return std::hypot(re, im);
      };
      std::size_t k = 0;
      for (std::size_t i = 0; i < curve.points.size(); ++i) {
        if (modal(curve.points[i].coefficients) > modal(curve.points[k].coefficients)) k = i;
      }
      double omega_peak = curve.points[k].omega;
      double q_peak = modal(curve.points[k].coefficients);
      if (k > 0 && k + 1 < curve.points.size()) {
        // Parabola through the three points around the maximum, in (Ω, q).
        const double x0 = curve.points[k - 1].omega, x1 = omega_peak,
                     x2 = curve.points[k + 1].omega;
        const double y0 = modal(curve.points[k - 1].coefficients), y1 = q_peak,
                     y2 = modal(curve.points[k + 1].coefficients);
        const double d = (x0 - x1) * (x0 - x2) * (x1 - x2);
        const double A = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
        const double B = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
        if (A < 0.0) {
          const double xv = -B / (2.0 * A);
          if (xv > x0 && xv < x2) {
            omega_peak = xv;
            q_peak = y1 + A * (xv - x1) * (xv - x1) + (B + 2.0 * A * x1) * (xv - x1);
          }
        }
      }
      const double omega_bb = interpolate_log(q, om, q_peak);
      const double zeta_bb = interpolate_log(q, zeta, q_peak);
      const double distance = (omega_peak - omega_bb) / omega_bb;
      const double bound = 2.0 * zeta_bb * zeta_bb + 2e-3;
      out.print("{},{},{},{},{},{},{:.3e},{:.3e}\n", c.name, force, q_peak, omega_peak, omega_bb,
                zeta_bb, distance, bound);
      worst = std::max(worst, std::abs(distance));
      if (!(std::abs(distance) <= bound)) {
        std::printf("FAIL %s F = %g: peak at %.5f rad/s, backbone %.5f (%.2e > %.2e)\n",
                    c.name.c_str(), force, omega_peak, omega_bb, distance, bound);
        ++failures;
      }
    }
  }
  std::printf(
      "frf_peaks_on_backbone: FRF peaks of cases 03 and 04 vs their EPMC damping curves: largest "
      "relative distance %.2e; %d failures\n",
      worst, failures);
  return failures == 0 ? 0 : 1;
}

}  // namespace jointhb_study_hb_frf_peaks_on_backbone
