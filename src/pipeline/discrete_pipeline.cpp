// The pipeline of a lumped model (pipeline/discrete_pipeline.hpp).
#include "jointhb/pipeline/discrete_pipeline.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "jointhb/pipeline/discrete_fit_model.hpp"

namespace jointhb::pipeline {

DiscretePipeline::DiscretePipeline(DiscreteProblem problem) : problem_(std::move(problem)) {
  if (const std::string e = problem_.system.validate(); !e.empty()) throw std::invalid_argument(e);
}

const hb::LinearModes& DiscretePipeline::linear_modes(bool stuck) {
  std::optional<hb::LinearModes>& m = stuck ? stuck_modes_ : free_modes_;
  if (!m) m = hb::linear_modes(problem_.system, stuck);
  return *m;
}

continuation::FrfCurve DiscretePipeline::frf(const hb::Excitation& excitation, const continuation::FrfOptions& options,
                                             const std::function<bool(const continuation::FrfPoint&)>& on_point) {
  ++curves_;
  return continuation::trace_frf(problem_.system, excitation, options, on_point);
}

continuation::FrfCurve DiscretePipeline::frf(std::size_t level,
                                             const std::function<bool(const continuation::FrfPoint&)>& on_point) {
  if (!problem_.frf) throw std::invalid_argument("the problem has no frf settings");
  if (level >= problem_.levels.size())
    throw std::invalid_argument(fmt::format("frf level {}: the problem has {} excitation levels", level,
                                            problem_.levels.size()));
  return frf(problem_.levels[level], *problem_.frf, on_point);
}

continuation::BackboneCurve DiscretePipeline::backbone(const continuation::BackboneOptions& options,
                                                       const std::function<bool(const continuation::BackbonePoint&)>& on_point) {
  ++curves_;
  return continuation::trace_backbone(problem_.system, options, on_point);
}

continuation::BackboneCurve DiscretePipeline::backbone(int mode,
                                                       const std::function<bool(const continuation::BackbonePoint&)>& on_point) {
  if (!problem_.nonlinear_modes) throw std::invalid_argument("the problem has no nonlinear_modes settings");
  continuation::BackboneOptions o = *problem_.nonlinear_modes;
  o.mode.mode = mode;
  return backbone(o, on_point);
}

std::vector<std::string> DiscretePipeline::parameter_names() const { return discrete_parameter_names(problem_); }

void DiscretePipeline::set_parameter(const std::string& name, double value) {
  DiscreteProblem changed = problem_;  // set_model_parameters checks the whole system: apply on a copy
  set_model_parameters(changed, {name}, {value});
  problem_ = std::move(changed);
  stuck_modes_.reset();
  free_modes_.reset();
}

}  // namespace jointhb::pipeline
