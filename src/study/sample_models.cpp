// The models a study evaluates (study/sample_models.hpp).
#include "jointhb/study/sample_models.hpp"

#include "jointhb/pipeline/discrete_fit_model.hpp"
#include "jointhb/pipeline/fe_fit_model.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

namespace jointhb::study {

SampleModelFactory discrete_sample_models(const pipeline::DiscreteProblem& problem, std::vector<std::string> names,
                                          const StudyOutputs& outputs) {
  auto base = std::make_shared<const pipeline::DiscreteProblem>(problem);
  auto targets = std::make_shared<const std::vector<fit::Target>>(study_targets(outputs));
  return [base, names = std::move(names), targets]() -> SampleModel {
    return [base, names, targets](const std::vector<double>& values) {
      pipeline::DiscreteProblem c = *base;
      pipeline::set_model_parameters(c, names, values);  // throws for a value the model rejects
      return pipeline::predict(c, *targets);
    };
  };
}

SampleModelFactory fe_sample_models(const pipeline::FeModel& model, const pipeline::FeAnalysis& analysis,
                                    std::vector<std::string> names, const StudyOutputs& outputs,
                                    bool friction_in_dynamics_only, StageStoreFactory store) {
  auto m = std::make_shared<const pipeline::FeModel>(model);
  auto a = std::make_shared<const pipeline::FeAnalysis>(analysis);
  auto targets = study_targets(outputs);
  return [m, a, names = std::move(names), targets = std::move(targets), friction_in_dynamics_only, store]() -> SampleModel {
    // One pipeline per worker; FeFitModel refers to it, so both live in one shared object.
    struct Worker {
      pipeline::FePipeline pipeline;
      pipeline::FeFitModel fit_model;
      Worker(const pipeline::FeModel& model, const pipeline::FeAnalysis& analysis, std::shared_ptr<pipeline::StageStore> s,
             const std::vector<std::string>& names, const std::vector<fit::Target>& targets, bool dynamics_only)
          : pipeline(model, analysis, std::move(s)), fit_model(pipeline, names, targets, dynamics_only) {}
    };
    auto worker = std::make_shared<Worker>(*m, *a, store ? store() : nullptr, names, targets, friction_in_dynamics_only);
    return [worker](const std::vector<double>& values) { return worker->fit_model.predict(values); };
  };
}

}  // namespace jointhb::study
