// jointhb: harmonic balance for bolted joints with zero-thickness contact elements.
//
// Sample runs:
//   jointhb loop --amplitude 2e-5 --json
//   jointhb run                                  (built-in default case into ./jointhb-out)
//   jointhb run cases/01-contact-loop/case.yaml -o out
//   jointhb fit cases/10-fit-one-dof/case.yaml -o fit-out
//   mpirun -np 2 jointhb study cases/16-study-lap/case.yaml -o study-out
//
// Every error is one line on stderr; exit codes: 0 ok, 1 runtime failure, 2 bad input.

#include <CLI/CLI.hpp>

#include <iostream>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>

#include "cli_support.hpp"
#include "fit_command.hpp"
#include "jointhb/io/input_error.hpp"
#include "loop_command.hpp"
#include "run_support.hpp"
#include "run_command.hpp"
#include "study_command.hpp"
#include "jointhb/fe/petsc_solvers.hpp"
#include "jointhb/study/distributed.hpp"

namespace {

using namespace jointhb::cli;

// Each error is reported as exactly one printable line, prefixed with the command that raised it
// (a message may echo bytes of a binary input file).
void print_error(const std::string& command, const std::string& message) {
  std::cerr << command << ": " << jointhb::io::printable_one_line(message) << '\n';
}

template <class Command>
int run_guarded(const std::string& name, const Command& command) {
  try {
    return command.run();
  } catch (const jointhb::io::InputError& e) {
    // Options have no file position: name the option the way the user typed it.
    if (e.file() == jointhb::io::command_line) {
      print_error(name, "option '" + e.key() + "': " + e.constraint());
    } else {
      print_error(name, e.what());
    }
    return exit_bad_input;
  } catch (const UsageError& e) {
    print_error(name, e.what());
    return exit_bad_input;
  } catch (const std::bad_alloc&) {
    print_error(name, "out of memory: the model needs more memory than this machine has (fewer "
                      "elements, contact points or harmonics need less)");
    return exit_failure;
  } catch (const std::exception& e) {
    print_error(name, e.what());
    return exit_failure;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "jointhb " JOINTHB_VERSION
      ": vibration of bolted joints by harmonic balance with the Gaul-Mayer microslip contact "
      "law.",
      "jointhb"};
  app.set_version_flag("--version", "jointhb " JOINTHB_VERSION);
  app.require_subcommand(0, 1);
  app.footer(
      "Run 'jointhb COMMAND --help' for the options of a command (units, ranges, defaults).\n"
      "Exit codes: 0 ok, 1 runtime failure, 2 bad input (options, case file).");
  LoopCommand loop(app);
  RunCommand run(app);
  // MPI is initialised only when an MPI launcher started the program (study/distributed.hpp). Its
  // threads must not take SIGINT/SIGTERM from the handlers of run, fit and study (run_support.hpp).
  const bool under_mpi = jointhb::study::Communicator::launched_by_mpi();
  if (under_mpi) defer_termination_signals();
  std::optional<jointhb::study::Communicator> communicator;
  try {
    communicator.emplace(&argc, &argv);
  } catch (const std::exception& e) {
    print_error("jointhb", e.what());
    return exit_failure;
  }
  FitCommand fit(app, *communicator);
  StudyCommand study(app, *communicator);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    print_error("jointhb", std::string(e.what()) + " (see 'jointhb --help')");
    return exit_bad_input;
  }

  if (under_mpi && !run.selected() && !study.selected()) allow_termination_signals();  // no handler
  if (loop.selected()) return run_guarded("jointhb loop", loop);
  if (run.selected() && run.wants_petsc()) {
    // Every rank makes the session; rank 0 runs the case, the others serve its linear algebra
    // (fe/petsc_solvers.hpp) until rank 0's session ends.
    std::optional<jointhb::fe::petsc::Session> petsc;
    defer_termination_signals();  // MPI may start its threads here (one process, no launcher)
    try {
      petsc.emplace(&argc, &argv);
    } catch (const std::exception& e) {
      print_error("jointhb run", std::string("option '--linear-algebra': ") + e.what());
      return exit_bad_input;
    }
    if (petsc->rank() > 0) {
      petsc->serve();
      return exit_ok;
    }
    run.set_ranks(petsc->size());
    return run_guarded("jointhb run", run);
  }
  if (run.selected() && communicator->size() > 1) {
    // Without the PETSc path every rank would run the whole case and write the same files.
    if (communicator->rank() == 0)
      print_error("jointhb run", "started on " + std::to_string(communicator->size()) +
                                     " MPI ranks: only --linear-algebra petsc uses several ranks; "
                                     "run it without mpirun");
    return exit_bad_input;
  }
  if (run.selected()) return run_guarded("jointhb run", run);
  if (fit.selected()) return run_guarded("jointhb fit", fit);
  if (study.selected()) return run_guarded("jointhb study", study);
  print_error("jointhb", "a command is required: loop, run, fit or study (see 'jointhb --help')");
  return exit_bad_input;
}
