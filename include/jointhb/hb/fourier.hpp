#pragma once
// Fourier conventions of jointhb, in one place (docs/theory.md, "Fourier basis").
//
// A T-periodic signal, T = 2π/Ω, is represented by the real coefficients
//   x(t) = x_0 + Σ_{k ∈ orders, k ≥ 1} ( a_k cos kΩt + b_k sin kΩt ),
// stored per signal in the order [x_0, a_k1, b_k1, a_k2, b_k2, ...] over the kept orders
// (x_0 absent when the basis keeps odd harmonics only). It is sampled at t_i = iT/N, i = 0..N-1.
//   synthesis (frequency → time):  x_i = x_0 + Σ a_k cos(2πki/N) + b_k sin(2πki/N)
//   analysis  (time → frequency):  x_0 = (1/N) Σ_i x_i,
//                                  a_k = (2/N) Σ_i x_i cos(2πki/N),  b_k = (2/N) Σ_i x_i
//                                  sin(2πki/N)
// Analysis inverts synthesis exactly when N ≥ 2H + 2 (H: highest order). Parseval:
//   (1/N) Σ_i x_i² = x_0² + ½ Σ_k (a_k² + b_k²).
// Transforms are FFTW real-to-complex / complex-to-real, planned once per batch width and reused;
// several signals (columns) are transformed in one call.

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace jointhb::hb {

class FourierBasis {
 public:
  /// Throws std::invalid_argument unless harmonics ≥ 1, time_samples ≥ 2·harmonics + 2 and the
  /// synthesis matrix (time_samples × size()) has at most 2^26 entries.
  FourierBasis(int harmonics, int time_samples, bool odd_only = false);
  ~FourierBasis();
  FourierBasis(const FourierBasis&);
  FourierBasis& operator=(const FourierBasis&);
  FourierBasis(FourierBasis&&) noexcept;
  FourierBasis& operator=(FourierBasis&&) noexcept;

  [[nodiscard]] int harmonics() const { return harmonics_; }
  [[nodiscard]] int time_samples() const { return time_samples_; }
  [[nodiscard]] bool odd_only() const { return odd_only_; }
  /// Harmonic orders k ≥ 1 kept (1..H, or the odd ones).
  [[nodiscard]] const std::vector<int>& orders() const { return orders_; }
  [[nodiscard]] bool has_mean() const { return !odd_only_; }
  /// Coefficients per signal.
  [[nodiscard]] int size() const { return static_cast<int>(has_mean() + 2 * orders_.size()); }
  /// Position of a_k in a signal's coefficients (b_k follows), -1 when k is not kept.
  [[nodiscard]] int cosine_index(int order) const;

  /// Samples (N × m) of m signals given by their coefficients (size() × m).
  [[nodiscard]] Eigen::MatrixXd to_time(const Eigen::MatrixXd& coefficients) const;
  /// Coefficients (size() × m) of m signals given by their samples (N × m).
  [[nodiscard]] Eigen::MatrixXd to_frequency(const Eigen::MatrixXd& samples) const;

  /// max_t |x(t)| of one signal: located on a fine grid (≥ 8 samples per period of the highest
  /// harmonic) and refined by Newton's method on x'(t) = 0 to round-off.
  [[nodiscard]] double peak_magnitude(const Eigen::VectorXd& coefficients) const;

  /// The synthesis matrix E (N × size()): column j is basis function j at the samples
  /// (computed once at construction).
  [[nodiscard]] const Eigen::MatrixXd& synthesis_matrix() const { return synthesis_; }
  /// The analysis matrix A (size() × N): to_frequency(x) = A x; A E = I.
  [[nodiscard]] Eigen::MatrixXd analysis_matrix() const;

 private:
  struct Plans;
  int harmonics_;
  int time_samples_;
  bool odd_only_;
  std::vector<int> orders_;
  Eigen::MatrixXd synthesis_;
  // FFTW plans, shared by copies. to_time/to_frequency may run on several threads at once: plans
  // are made under a mutex and executed on the caller's arrays (FFTW_UNALIGNED).
  std::shared_ptr<Plans> plans_;
};

/// The coefficients of `x` (DOF-major over basis `from`, `dofs` DOFs) in basis `to`: shared orders
/// copied, the others zero (raising H, or going from odd harmonics to all).
[[nodiscard]] Eigen::VectorXd transfer_coefficients(const FourierBasis& from, const FourierBasis& to,
                                                    const Eigen::VectorXd& x, int dofs);


}  // namespace jointhb::hb
