#pragma once
// Parameter studies (docs/studies.md): many evaluations of one case at the samples of a design
// (study/sampling.hpp), each through the pipeline exactly as an identification evaluates it
// (fit/targets.hpp predictions: damping curves and FRFs of the case, corrected onto the curve at
// the reported abscissae), gathered into one table in sample order, with statistics per output.
//
//   samples ──► [worker threads / MPI ranks take the next sample when free] ──► SampleResult
//          ──► sample files (restart) ──► StudyResult (sample order) ──► statistics
//
// Each sample is evaluated by one worker with one OpenMP thread and deterministic inputs, so its
// result does not depend on which worker or rank computed it, nor on how many there are: the
// table is the same bit for bit for any job or rank count (tests/unit/study, tests/cli).
// A sample that fails (a model the parameters make invalid, a curve that stops short of an
// output, a stage that does not converge) is kept with its status and message and whatever
// values it reached; it never stops the others.

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/contact/termination.hpp"
#include "jointhb/fit/targets.hpp"
#include "jointhb/study/sampling.hpp"

namespace jointhb::study {

/// What each sample reports (docs/studies.md §3).
struct StudyOutputs {
  std::vector<int> modes;              ///< damping curves (EPMC) of these modes
  std::vector<double> amplitudes;      ///< f [Hz] and ζ of each mode at these modal amplitudes q
  std::vector<int> levels;             ///< FRFs at these force levels (0-based)
  std::vector<double> frequencies_hz;  ///< |x̂₁| of each level at these frequencies (may be empty)
};

struct StudySpec {
  Sampling sampling;
  StudyOutputs outputs;
  std::vector<double> quantiles = {0.05, 0.5, 0.95};  ///< in [0, 1], ascending
  /// Finite-element cases: interfaces' mu and n enter the dynamics only (ParameterScope::dynamics,
  /// pipeline/fe_pipeline.hpp): the preloaded state, modes and condensation are shared by all
  /// samples that differ only in them.
  bool friction_in_dynamics_only = false;
  /// Empty when valid, else "FIELD: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// One reported value of a sample: a point of a damping curve or an FRF, or an FRF's peak.
struct OutputKey {
  fit::TargetKind curve = fit::TargetKind::backbone;  ///< backbone or frf
  int index = 0;                   ///< the mode (backbone) or the level (frf)
  std::string quantity;            ///< frequency_hz, damping_ratio, amplitude, peak_amplitude, peak_frequency_hz
  double abscissa = 0.0;           ///< q (backbone), f [Hz] (frf amplitude); 0 for the peaks
  /// "mode 1 damping_ratio at q = 1e-06", "level 0 peak_amplitude".
  [[nodiscard]] std::string label() const;
};

/// The reported values in their order: per mode f then ζ at each amplitude; per level the
/// amplitude at each frequency, then its peak amplitude and peak frequency.
[[nodiscard]] std::vector<OutputKey> output_keys(const StudyOutputs& outputs);
/// The targets whose predictions a sample evaluates (fit/targets.hpp): one backbone target per
/// mode with its f and ζ points, one frf target per level with its amplitude points.
[[nodiscard]] std::vector<fit::Target> study_targets(const StudyOutputs& outputs);

/// The result of one sample.
struct SampleResult {
  std::size_t sample = 0;       ///< 0-based index in the design
  std::vector<double> values;   ///< its parameter values
  Status status;                ///< converged, or failed with the first reason
  double seconds = 0.0;         ///< wall time of its evaluation (0 when read back)
  std::vector<std::optional<double>> outputs;  ///< one per output key; nullopt where not reached
  std::vector<fit::PredictedCurve> curves;     ///< the whole curves, one per study target
  bool reused = false;          ///< read from an earlier run's sample file (not computed)
};

/// A sample's model: its parameter values → the predictions of the study's targets (fit/targets.hpp).
/// May throw (std::invalid_argument for a value the case rejects): the sample fails with the message.
using SampleModel = std::function<fit::ModelPrediction(const std::vector<double>& values)>;
/// Makes one model per worker thread (each owns its pipeline; they may share a disk stage cache).
using SampleModelFactory = std::function<SampleModel()>;

/// Evaluates one sample: the model, then each output read off its predictions — the value corrected
/// onto the curve (PredictedCurve::at_points) or, when the model gave none, interpolated on the curve
/// as the fit's residuals do (log10 q for damping curves; f for FRFs, the largest amplitude where a
/// fold gives several); nullopt outside the curve. Never throws.
[[nodiscard]] SampleResult evaluate_sample(const SampleModel& model, const StudyOutputs& outputs,
                                           std::size_t sample, const std::vector<double>& values);

/// Statistics of one output over the samples that reached it.
struct OutputStatistics {
  OutputKey key;
  std::size_t count = 0;               ///< samples with a value
  double mean = 0.0, std_dev = 0.0;    ///< std_dev with n − 1 (0 for one value)
  double min = 0.0, max = 0.0;
  std::vector<double> quantiles;       ///< at StudySpec::quantiles (type 7 of Hyndman and Fan)
};

/// The p-quantile of `sorted` (ascending, non-empty), linear between order statistics:
/// x_(⌊h⌋) + (h − ⌊h⌋)(x_(⌊h⌋+1) − x_(⌊h⌋)), h = (n − 1) p (0-based), R. J. Hyndman, Y. Fan,
/// "Sample quantiles in statistical packages", Am. Stat. 50 (1996) 361–365, definition 7
/// (numpy's and R's default).
[[nodiscard]] double quantile(const std::vector<double>& sorted, double p);

[[nodiscard]] std::vector<OutputStatistics> output_statistics(const std::vector<OutputKey>& keys,
                                                              const std::vector<SampleResult>& samples,
                                                              const std::vector<double>& quantiles);

/// A sample as one line of JSON (the sample files, and what a rank sends to rank 0): doubles
/// written so that they read back bit-identical, non-finite values as null.
[[nodiscard]] std::string sample_to_json(const SampleResult& sample, const std::string& identity);
/// Reads sample_to_json's text. Throws std::runtime_error when it does not parse. `identity` is
/// set to the identity it was written with.
[[nodiscard]] SampleResult sample_from_json(const std::string& text, std::string& identity);

/// The MPI world a study may run on (study/distributed.hpp makes one); nullptr or a size of 1: this
/// process alone.
class Communicator;

struct RunOptions {
  /// Local workers of rank 0 (≥ 1), each evaluating one sample at a time with one OpenMP thread:
  /// one is a thread, more are child processes (the installed OpenBLAS is not safe for two
  /// threads factorising at once; study/worker_processes.hpp). The other ranks evaluate one sample
  /// at a time each.
  int jobs = 1;
  /// Each finished sample is written there as sample_NNNNNN.json (a file per sample, written to a
  /// temporary name and renamed): what a restart reads. Empty: no files.
  std::filesystem::path sample_directory;
  /// Reuse the sample files found in sample_directory whose identity and values match.
  bool resume = false;
  /// What the sample files must match to be reused: the case and design (e.g. a hash of the case
  /// file's text).
  std::string identity;
  /// Called on the coordinating thread of rank 0 after each sample (computed or reused), in the
  /// order they finish. Returning false stops handing out samples (those running finish).
  std::function<bool(const SampleResult& sample, std::size_t done, std::size_t total)> on_sample;
  const Communicator* communicator = nullptr;
  /// When set (e.g. by a signal handler), no further sample is handed out; running samples finish
  /// and are recorded, the rest stay not run (StudyResult::status() stopped_by_user). Polled every
  /// 100 ms.
  const std::atomic<bool>* interrupt = nullptr;
};

struct StudyResult {
  bool root = true;                    ///< this process holds the results (rank 0)
  std::vector<OutputKey> keys;
  std::vector<SampleResult> samples;   ///< every sample of the design, in order (root only)
  std::vector<bool> done;              ///< per sample: evaluated or reused (false: not run, stopped)
  std::vector<OutputStatistics> statistics;
  std::size_t computed = 0, reused = 0, failed = 0, not_run = 0;
  int ranks = 1, jobs = 1;
  double seconds = 0.0;
  std::vector<std::string> warnings;   ///< e.g. sample files that could not be read or written
  /// converged when every sample converged; no_convergence when some failed but others did not;
  /// failed when none did; stopped_by_user when on_sample stopped it.
  [[nodiscard]] Status status() const;
};

/// Runs the study: evaluates every sample not reused on options.jobs local workers and, with a
/// communicator of size > 1, on every other rank, each taking the next sample when it is free.
/// Throws std::invalid_argument for an invalid spec or options (before any evaluation).
StudyResult run_study(const StudySpec& spec, const SampleModelFactory& factory, const RunOptions& options);

}  // namespace jointhb::study
