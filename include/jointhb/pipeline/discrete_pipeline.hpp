#pragma once
// The pipeline of a lumped model (docs/pipeline.md): the discrete counterpart of FePipeline, with
// no preload and no reduction. It holds the typed problem (pipeline/discrete_problem.hpp), keeps
// the linear modes while the model is unchanged, traces FRFs and damping curves with the same
// drivers as a discrete case file (continuation/frf.hpp, backbone.hpp), and sets the
// identification's parameters (pipeline/discrete_fit_model.hpp names) on the model.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/pipeline/discrete_problem.hpp"

namespace jointhb::pipeline {

class DiscretePipeline {
 public:
  /// Throws std::invalid_argument when the system is invalid (DiscreteSystem::validate).
  explicit DiscretePipeline(DiscreteProblem problem);

  [[nodiscard]] const DiscreteProblem& problem() const { return problem_; }

  /// Linear modes with the contacts stuck (their k_T0 in K) or removed; kept until a parameter
  /// changes.
  const hb::LinearModes& linear_modes(bool stuck = true);

  /// The FRF under `excitation` with `options`, or at level `level` of the problem's frf settings.
  continuation::FrfCurve frf(const hb::Excitation& excitation, const continuation::FrfOptions& options,
                             const std::function<bool(const continuation::FrfPoint&)>& on_point = {});
  continuation::FrfCurve frf(std::size_t level, const std::function<bool(const continuation::FrfPoint&)>& on_point = {});

  /// The damping curve (EPMC) with `options`, or of `mode` with the problem's nonlinear_modes settings.
  continuation::BackboneCurve backbone(const continuation::BackboneOptions& options,
                                       const std::function<bool(const continuation::BackbonePoint&)>& on_point = {});
  continuation::BackboneCurve backbone(int mode,
                                       const std::function<bool(const continuation::BackbonePoint&)>& on_point = {});

  /// contacts[i].kt0 | mu | normal_force | n, damping.rayleigh.alpha | beta, damping.modal[k].
  [[nodiscard]] std::vector<std::string> parameter_names() const;
  /// Sets one value and rebuilds what depends on it (C for a damping parameter). Throws
  /// std::invalid_argument naming the parameter and the violated constraint (nothing changes then).
  void set_parameter(const std::string& name, double value);

  /// Curves traced so far.
  [[nodiscard]] int curves() const { return curves_; }

 private:
  DiscreteProblem problem_;
  std::optional<hb::LinearModes> stuck_modes_, free_modes_;
  int curves_ = 0;
};

}  // namespace jointhb::pipeline
