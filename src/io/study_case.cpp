// The study of a case file (io/study_case.hpp).
#include "jointhb/io/study_case.hpp"

#include <stdexcept>
#include <variant>

#include "jointhb/io/case_file.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/io/study_outputs.hpp"
#include "jointhb/pipeline/fingerprint.hpp"
#include "jointhb/study/distributed.hpp"
#include "jointhb/study/sample_models.hpp"

namespace jointhb::io {

namespace fs = std::filesystem;

StudyCase read_study_case(const fs::path& file) {
  const CaseFile any = read_case_file(file);
  const auto* c = std::get_if<DiscreteCase>(&any);
  const auto* fe = std::get_if<FeCase>(&any);
  if (!c && !fe)
    throw std::invalid_argument(file.string() +
                                ": a study needs a discrete (model.type discrete) or finite-element (model.type fe) case with a study section");
  const std::optional<study::StudySpec>& section = c ? c->study : fe->study;
  if (!section) throw std::invalid_argument(file.string() + ": the case has no study section (docs/case-files.md, \"study\")");
  StudyCase s;
  s.file = file;
  s.spec = *section;
  pipeline::Fingerprint f;
  f.add("jointhb study case");
  f.add_file(file);
  s.identity = f.hex();
  std::vector<std::string> names;
  for (const auto& p : s.spec.sampling.parameters) names.push_back(p.name);
  if (c) {
    const study::SampleModelFactory factory = study::discrete_sample_models(*c, names, s.spec.outputs);
    s.models = [factory](const fs::path&) { return factory; };
  } else {
    const FeCase model = *fe;
    const study::StudySpec spec = s.spec;
    s.models = [model, spec, names](const fs::path& cache) {
      study::StageStoreFactory store;
      if (!cache.empty()) store = [cache] { return std::make_shared<StageCache>(cache, true); };
      return study::fe_sample_models(model, model, names, spec.outputs, spec.friction_in_dynamics_only, store);
    };
  }
  return s;
}

study::StudyResult run_study_case(const StudyCase& c, const fs::path& dir, study::RunOptions options, const fs::path& cache_dir) {
  const bool root = !options.communicator || options.communicator->rank() == 0;
  options.sample_directory = root ? dir / "samples" : fs::path();
  options.identity = c.identity;
  const study::StudyResult result = study::run_study(c.spec, c.models(cache_dir.empty() ? dir / ".cache" : cache_dir), options);
  if (root) write_study_outputs(dir, c.file.string(), c.spec, result);
  return result;
}

}  // namespace jointhb::io
