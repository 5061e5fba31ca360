#pragma once
// Harmonics of one sampled period of a forced steady state, shared by the discrete and the FE
// Newmark drivers (newmark.cpp, fe_newmark.cpp): samples x_j at t_j = t_0 + jT/N, j = 0..N−1,
// phase measured from absolute time (θ_j = Ω t_0 + 2πj/N), direct sums
//   c_0 = (1/N) Σ x_j,   a_k = (2/N) Σ x_j cos kθ_j,   b_k = (2/N) Σ x_j sin kθ_j,
// columns [c_0, a_1, b_1, …, a_H, b_H] (the order of hb/fourier.hpp).

#include <Eigen/Core>
#include <cmath>
#include <numbers>

namespace jointhb::timeint {

inline Eigen::MatrixXd period_harmonics(const Eigen::MatrixXd& samples, double omega, double start_time,
                                        int harmonics) {
  const auto steps = static_cast<int>(samples.cols());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(samples.rows(), 2 * harmonics + 1);
  const double phase0 = std::fmod(omega * start_time, 2.0 * std::numbers::pi);
  for (int j = 0; j < steps; ++j) {
    const double theta = phase0 + 2.0 * std::numbers::pi * j / steps;
    const auto x = samples.col(j);
    c.col(0) += x;
    for (int k = 1; k <= harmonics; ++k) {
      c.col(2 * k - 1) += std::cos(k * theta) * x;
      c.col(2 * k) += std::sin(k * theta) * x;
    }
  }
  c.col(0) /= steps;
  c.rightCols(2 * harmonics) *= 2.0 / steps;
  return c;
}

}  // namespace jointhb::timeint
