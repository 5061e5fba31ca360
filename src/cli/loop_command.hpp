#pragma once
// `jointhb loop`: one contact point driven through its periodic steady state by a prescribed slip
// (contact::run_loop), with W_D compared against the closed forms. docs/cli.md.

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace jointhb::cli {

class LoopCommand {
 public:
  /// Registers the subcommand and its options on `parent`.
  explicit LoopCommand(CLI::App& parent);

  [[nodiscard]] bool selected() const;
  /// Runs after parsing; returns the exit code. Throws io::InputError / UsageError for bad options.
  [[nodiscard]] int run() const;

 private:
  CLI::App* app_;
  // Numbers are kept as text and converted after parsing (cli_support.hpp explains why).
  std::string law_;
  std::string exponent_;
  std::string friction_coefficient_;
  std::string normal_force_;
  std::string stiffness_;
  std::string amplitude_;
  std::string time_samples_;
  std::vector<std::string> harmonics_;
  std::string normal_amplitude_ = "0";
  std::string normal_phase_deg_ = "0";
  std::string normal_decay_ = "0";
  bool stiffness_follows_normal_ = false;
  bool json_ = false;
  std::string csv_path_;
};

}  // namespace jointhb::cli
