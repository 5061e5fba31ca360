#pragma once
// The models a study evaluates (study/study.hpp): a case's pipeline with the sample's parameter
// values set, predicting the study's targets exactly as an identification predicts its own
// (pipeline/discrete_fit_model.hpp, pipeline/fe_fit_model.hpp): the same parameter names, the same
// curves, the same correction onto the curve at the reported abscissae.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "jointhb/pipeline/discrete_problem.hpp"
#include "jointhb/pipeline/fe_analysis.hpp"
#include "jointhb/pipeline/fe_model.hpp"
#include "jointhb/pipeline/stage_store.hpp"
#include "jointhb/study/study.hpp"

namespace jointhb::study {

/// A lumped model: each sample sets `names` on a copy of `problem` (pipeline::set_model_parameters)
/// and predicts the targets of `outputs` (pipeline::predict).
[[nodiscard]] SampleModelFactory discrete_sample_models(const pipeline::DiscreteProblem& problem,
                                                        std::vector<std::string> names, const StudyOutputs& outputs);

/// Where a worker's finite-element pipeline keeps its stages (e.g. one disk cache shared by all
/// workers, so that samples with the same stage inputs share a preload); nullptr: in the pipeline only.
using StageStoreFactory = std::function<std::shared_ptr<pipeline::StageStore>()>;

/// A finite-element model: each worker owns one FePipeline (its kept stages carry over between its
/// samples whose stage keys agree), sets `names` on it per sample (the interfaces' mu and n in the
/// dynamics only with friction_in_dynamics_only) and predicts with pipeline::FeFitModel.
[[nodiscard]] SampleModelFactory fe_sample_models(const pipeline::FeModel& model, const pipeline::FeAnalysis& analysis,
                                                  std::vector<std::string> names, const StudyOutputs& outputs,
                                                  bool friction_in_dynamics_only, StageStoreFactory store = {});

}  // namespace jointhb::study
