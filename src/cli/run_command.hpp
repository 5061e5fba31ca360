#pragma once
// `jointhb run [CASE.yaml] [-o DIR]`: runs the analysis a case file asks for (so far the W_D
// amplitude sweep of one contact point), or the built-in default case. docs/cli.md.

#include <string>

namespace CLI {
class App;
}

namespace jointhb::cli {

class RunCommand {
 public:
  explicit RunCommand(CLI::App& parent);

  [[nodiscard]] bool selected() const;
  /// Runs after parsing; returns the exit code. Throws io::InputError for a bad case file or -o.
  [[nodiscard]] int run() const;

 private:
  CLI::App* app_;
  std::string case_path_;
  std::string output_dir_ = "jointhb-out";
  bool plot_ = false;
  std::string cache_dir_;  ///< empty: OUTPUT/.cache
  bool no_cache_ = false;
  bool check_only_ = false;  // --check: read and check the case, run nothing
  std::string linear_algebra_ = "serial";  // --linear-algebra serial | petsc | petsc-gamg | petsc-hypre
  double cg_tolerance_ = 1e-10;            // --cg-tolerance (petsc-gamg, petsc-hypre)
  int ranks_ = 1;                          // of the petsc::Session main() made

 public:
  /// --linear-algebra petsc*: main() makes a petsc::Session on every rank before run().
  [[nodiscard]] bool wants_petsc() const { return linear_algebra_.rfind("petsc", 0) == 0; }
  void set_ranks(int ranks) { ranks_ = ranks; }
};

}  // namespace jointhb::cli
