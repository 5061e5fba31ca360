#pragma once
// `jointhb study CASE.yaml [-o DIR] [-j N] [--resume] [--cache-dir DIR] [--quiet]`, also
// under `mpirun -np N`: the parameter study of the case's study section (docs/studies.md,
// docs/cli.md). Writes DIR/study.csv, study_statistics.csv, study_curves.csv, study.json,
// DIR/samples/ (one file per finished sample: what --resume reads) and DIR/study.png.
#include <string>

namespace CLI {
class App;
}
namespace jointhb::study {
class Communicator;
}

namespace jointhb::cli {

class StudyCommand {
 public:
  StudyCommand(CLI::App& parent, const study::Communicator& communicator);
  [[nodiscard]] bool selected() const;
  /// Runs after parsing; returns the exit code. Throws io::InputError for a bad case file.
  [[nodiscard]] int run() const;

 private:
  CLI::App* app_;
  const study::Communicator& communicator_;
  std::string case_path_;
  std::string output_dir_ = "jointhb-study";
  std::string jobs_;        ///< local workers (default: the cores; 1 under MPI)
  bool resume_ = false;
  std::string cache_dir_;   ///< FE cases: the stage cache (default DIR/.cache)
  bool quiet_ = false;
};

}  // namespace jointhb::cli
