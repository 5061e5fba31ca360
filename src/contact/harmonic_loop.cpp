// One contact point driven through its periodic steady state (harmonic_loop.hpp).
#include "jointhb/contact/harmonic_loop.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"

namespace jointhb::contact {
namespace {

bool finite_positive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

std::string LoopOptions::validate() const {
  if (law != "gaul-mayer" && law != "jenkins") {
    return "law: must be 'gaul-mayer' or 'jenkins', got '" + law + "'";
  }
  if (law == "gaul-mayer" && !(exponent > 0.0 && exponent < 1.0)) {
    return "n: must lie in (0, 1), got " + std::to_string(exponent);
  }
  if (!finite_positive(friction_coefficient)) return "mu: must be > 0 and finite";
  if (!finite_positive(normal_force)) return "normal_force: must be > 0 and finite";
  if (!finite_positive(stiffness)) return "kt0: must be > 0 and finite";
  if (!(std::isfinite(amplitude) && amplitude >= 0.0)) {
    return "amplitude: must be >= 0 and finite";
  }
  for (const auto& h : harmonics) {
    if (h.order < 1) return "harmonic order: must be >= 1";
    if (!std::isfinite(h.amplitude) || !std::isfinite(h.phase)) {
      return "harmonic amplitude and phase: must be finite";
    }
  }
  if (!std::isfinite(normal_amplitude) || !std::isfinite(normal_phase)) {
    return "normal_amplitude and normal_phase: must be finite";
  }
  if (!(std::isfinite(normal_decay) && normal_decay >= 0.0)) {
    return "lambda: must be >= 0 and finite";
  }
  if (normal_amplitude != 0.0 && normal_decay <= 0.0) {
    return "lambda: must be > 0 when the normal amplitude is not zero";
  }
  if (!finite_positive(friction_coefficient * normal_force)) {
    return "mu * normal_force: the slip limit must be finite";
  }
  // The loop is computed in SI doubles: powers of the slip over the stick range g_s = μF_N/k_T0
  // (up to the third in W_D) must stay representable. Outside [1e-100, 1e100] they do not (W_D
  // came out 0 at a/g_s = 3e-119 and 3e154), so such loops are refused, not answered wrongly.
  double slip = std::abs(amplitude);
  for (const auto& h : harmonics) slip += std::abs(h.amplitude);
  const double ratio = slip * stiffness / (friction_coefficient * normal_force);
  if (slip > 0.0 && !(ratio >= kMinSlipRatio && ratio <= kMaxSlipRatio)) {
    return fmt::format(
        "amplitude: the slip over the stick range, (a + Σ|a_k|) k_T0/(μ F_N) = {:.3g}, must lie in "
        "[{:g}, {:g}]: outside, the loop's energies over- or underflow doubles (rescale the units)",
        ratio, kMinSlipRatio, kMaxSlipRatio);
  }
  if (time_samples < 4) return "time_samples: must be >= 4";
  for (const auto& h : harmonics) {
    if (2 * h.order >= time_samples) {
      return "harmonic order: must be < time_samples/2 (it would alias onto a lower harmonic)";
    }
  }
  return {};
}

std::shared_ptr<const TangentialLaw> make_tangential_law(const std::string& name, double exponent) {
  if (name == "gaul-mayer") return std::make_shared<GaulMayerLaw>(exponent);
  if (name == "jenkins") return std::make_shared<JenkinsLaw>();
  throw std::invalid_argument("unknown tangential law '" + name + "' (known: gaul-mayer, jenkins)");
}

LoopResult run_loop(const LoopOptions& o) {
  if (const std::string msg = o.validate(); !msg.empty()) throw std::invalid_argument(msg);
  const auto law = make_tangential_law(o.law, o.exponent);
  const int n = o.time_samples;
  LoopResult r;
  PeriodicPath path;
  path.slip.resize(static_cast<std::size_t>(n));
  path.limits.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double theta = 2.0 * std::numbers::pi * i / n;
    double g = o.amplitude * std::cos(theta);
    for (const auto& h : o.harmonics) g += h.amplitude * std::cos(h.order * theta + h.phase);
    const double gn = o.normal_amplitude * std::cos(theta + o.normal_phase);
    const double fn = o.normal_force * std::exp(-o.normal_decay * gn);  // eq. (6), force form
    const auto k = static_cast<std::size_t>(i);
    path.slip[k] = Vec2(g, 0.0);
    path.limits[k].slip_limit = o.friction_coefficient * fn;
    path.limits[k].stiffness =
        o.stiffness_follows_normal ? o.stiffness * fn / o.normal_force : o.stiffness;
    r.phase.push_back(theta);
    r.slip.push_back(g);
    r.normal_force.push_back(fn);
  }
  PeriodicStateOptions options;
  options.keep_step_derivatives = false;
  const auto start = std::chrono::steady_clock::now();
  r.state = solve_periodic_state(*law, path, options);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  for (const auto& t : r.state.traction) {
    r.force.push_back(t.x());
    r.force_amplitude = std::max(r.force_amplitude, std::abs(t.x()));
  }
  r.dissipation = r.state.dissipation;
  r.loading_span = 0.5 * r.state.loading_slip;  // two loading branches per period
  const closed_form::MicroslipParameters p{o.exponent, o.friction_coefficient * o.normal_force,
                                           o.stiffness};
  r.full_slip_span =
      o.law == "gaul-mayer" ? closed_form::full_slip_span(p) : p.slip_limit / p.stiffness;
  r.formulas_apply = o.law == "gaul-mayer" && o.harmonics.empty() && o.normal_amplitude == 0.0;
  if (r.formulas_apply) {
    r.dissipation_paper = closed_form::dissipation_paper(r.loading_span, p);
    r.dissipation_paper_amplitude_reading = closed_form::dissipation_paper(o.amplitude, p);
    r.dissipation_general = closed_form::dissipation_general(r.loading_span, p);
  }
  if (o.law == "jenkins" && o.harmonics.empty() && o.normal_amplitude == 0.0) {
    r.dissipation_jenkins =
        closed_form::dissipation_jenkins(o.amplitude, p.slip_limit, p.stiffness);
  }
  return r;
}

}  // namespace jointhb::contact
