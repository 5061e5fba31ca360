#pragma once
// `jointhb fit CASE.yaml [-o DIR] [-j N] [--resume] [--quiet]`: identifies the parameters named in the
// case's fit section from its measured targets (docs/identification.md, docs/cli.md). Writes
// DIR/fit_history.csv (one flushed row per evaluation), DIR/fit.json, DIR/fit_curves.csv,
// DIR/fit_model_curves.csv and DIR/fit.png (when python3-matplotlib is present). The starts of a
// multi-start search run on -j local worker processes and, under mpirun, on the other ranks (rank 0
// alone writes files); the results do not depend on it.

#include <string>

namespace CLI {
class App;
}

namespace jointhb::study {
class Communicator;
}

namespace jointhb::cli {

class FitCommand {
 public:
  FitCommand(CLI::App& parent, const study::Communicator& communicator);

  [[nodiscard]] bool selected() const;
  /// Runs after parsing; returns the exit code. Throws io::InputError for a bad case file or -o.
  [[nodiscard]] int run() const;

 private:
  CLI::App* app_;
  const study::Communicator& communicator_;
  std::string jobs_;  ///< -j: local worker processes (default 1)
  std::string case_path_;
  std::string output_dir_ = "jointhb-fit";
  bool resume_ = false;
  std::string cache_dir_;  ///< FE cases: the stage cache (default DIR/.cache)
  bool quiet_ = false;
};

}  // namespace jointhb::cli
