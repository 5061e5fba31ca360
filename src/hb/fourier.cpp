#include "jointhb/hb/fourier.hpp"

#include <fftw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace jointhb::hb {

// FFTW's planner is not thread-safe; executing a plan on new arrays is (fftw_execute_dft_*).
// Plans are made once per batch width m with FFTW_ESTIMATE | FFTW_UNALIGNED so that any Eigen
// buffer may be passed at execution.
namespace {
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace

struct FourierBasis::Plans {
  struct Pair {
    fftw_plan forward = nullptr;   // r2c: N real samples → N/2+1 complex, m columns
    fftw_plan backward = nullptr;  // c2r
  };
  int n = 0;
  std::mutex mutex;
  std::map<Eigen::Index, Pair> by_width;

  explicit Plans(int samples) : n(samples) {}
  ~Plans() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    for (auto& [m, p] : by_width) {
      fftw_destroy_plan(p.forward);
      fftw_destroy_plan(p.backward);
    }
  }
  Plans(const Plans&) = delete;
  Plans& operator=(const Plans&) = delete;

  Pair get(Eigen::Index m) {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = by_width.find(m); it != by_width.end()) return it->second;
    std::lock_guard<std::mutex> plan_lock(planner_mutex());
    const int half = n / 2 + 1;
    const int width = static_cast<int>(m);
    std::vector<double> real(static_cast<std::size_t>(n) * static_cast<std::size_t>(m));
    std::vector<fftw_complex> cplx(static_cast<std::size_t>(half) * static_cast<std::size_t>(m));
    const unsigned flags = FFTW_ESTIMATE | FFTW_UNALIGNED;
    Pair p;
    p.forward = fftw_plan_many_dft_r2c(1, &n, width, real.data(), nullptr, 1, n, cplx.data(),
                                       nullptr, 1, half, flags);
    p.backward = fftw_plan_many_dft_c2r(1, &n, width, cplx.data(), nullptr, 1, half, real.data(),
                                        nullptr, 1, n, flags);
    if (p.forward == nullptr || p.backward == nullptr) {
      throw std::runtime_error("FourierBasis: FFTW could not plan the transform");
    }
    by_width.emplace(m, p);
    return p;
  }
};

FourierBasis::FourierBasis(int harmonics, int time_samples, bool odd_only)
    : harmonics_(harmonics), time_samples_(time_samples), odd_only_(odd_only) {
  if (harmonics < 1) {
    throw std::invalid_argument(fmt::format("harmonics: must be >= 1, got {}", harmonics));
  }
  if (time_samples < 2 * harmonics + 2) {
    throw std::invalid_argument(fmt::format(
        "time_samples: must be >= 2 harmonics + 2 = {} (no aliasing of the kept harmonics), got {}",
        2 * harmonics + 2, time_samples));
  }
  for (int k = 1; k <= harmonics; ++k) {
    if (!odd_only || k % 2 == 1) orders_.push_back(k);
  }
  if (static_cast<double>(time_samples) * size() > static_cast<double>(1 << 26)) {
    throw std::invalid_argument(fmt::format(
        "time_samples x basis size: {} x {} exceeds 2^26 entries", time_samples, size()));
  }
  synthesis_.resize(time_samples, size());
  for (int i = 0; i < time_samples; ++i) {
    if (has_mean()) synthesis_(i, 0) = 1.0;
    for (int k : orders_) {
      const int c = cosine_index(k);
      // Reduce k·i mod N first: the angle stays in [0, 2π) and exact for every sample.
      const double theta = 2.0 * std::numbers::pi *
                           static_cast<double>((static_cast<long long>(k) * i) % time_samples) /
                           time_samples;
      synthesis_(i, c) = std::cos(theta);
      synthesis_(i, c + 1) = std::sin(theta);
    }
  }
  plans_ = std::make_shared<Plans>(time_samples);
}

FourierBasis::~FourierBasis() = default;
FourierBasis::FourierBasis(const FourierBasis&) = default;
FourierBasis& FourierBasis::operator=(const FourierBasis&) = default;
FourierBasis::FourierBasis(FourierBasis&&) noexcept = default;
FourierBasis& FourierBasis::operator=(FourierBasis&&) noexcept = default;

int FourierBasis::cosine_index(int order) const {
  if (order < 1 || order > harmonics_ || (odd_only_ && order % 2 == 0)) return -1;
  const int position = odd_only_ ? (order - 1) / 2 : order - 1;
  return (has_mean() ? 1 : 0) + 2 * position;
}

Eigen::MatrixXd FourierBasis::to_time(const Eigen::MatrixXd& coefficients) const {
  if (coefficients.rows() != size()) {
    throw std::invalid_argument(fmt::format(
        "FourierBasis::to_time: {} coefficient rows, expected {}", coefficients.rows(), size()));
  }
  const Eigen::Index m = coefficients.cols();
  const int n = time_samples_;
  const int half = n / 2 + 1;
  Eigen::MatrixXd samples(n, m);
  if (m == 0) return samples;
  // Half spectrum Y_k = (a_k − i b_k)/2, Y_0 = x_0: c2r gives x_i = Σ a_k cos + b_k sin.
  std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(half * m));
  for (Eigen::Index j = 0; j < m; ++j) {
    std::complex<double>* y = spectrum.data() + j * half;
    if (has_mean()) y[0] = coefficients(0, j);
    for (int k : orders_) {
      const int c = cosine_index(k);
      y[k] = 0.5 * std::complex<double>(coefficients(c, j), -coefficients(c + 1, j));
    }
  }
  const auto plan = plans_->get(m).backward;
  fftw_execute_dft_c2r(plan, reinterpret_cast<fftw_complex*>(spectrum.data()), samples.data());
  return samples;
}

Eigen::MatrixXd FourierBasis::to_frequency(const Eigen::MatrixXd& samples) const {
  if (samples.rows() != time_samples_) {
    throw std::invalid_argument(fmt::format(
        "FourierBasis::to_frequency: {} sample rows, expected {}", samples.rows(), time_samples_));
  }
  const Eigen::Index m = samples.cols();
  const int n = time_samples_;
  const int half = n / 2 + 1;
  Eigen::MatrixXd coefficients(size(), m);
  if (m == 0) return coefficients;
  std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(half * m));
  const auto plan = plans_->get(m).forward;
  // An out-of-place r2c plan preserves its input (FFTW_PRESERVE_INPUT is the default for every
  // transform but c2r), so the samples are passed as they are, without a copy; only the C API's
  // signature needs the const_cast.
  fftw_execute_dft_r2c(plan, const_cast<double*>(samples.data()),
                       reinterpret_cast<fftw_complex*>(spectrum.data()));
  // X_k = Σ x_i e^{−2πiki/N}: a_k = (2/N) Re X_k, b_k = −(2/N) Im X_k, x_0 = X_0/N.
  const double scale = 2.0 / n;
  for (Eigen::Index j = 0; j < m; ++j) {
    const std::complex<double>* x = spectrum.data() + j * half;
    if (has_mean()) coefficients(0, j) = x[0].real() / n;
    for (int k : orders_) {
      const int c = cosine_index(k);
      coefficients(c, j) = scale * x[k].real();
      coefficients(c + 1, j) = -scale * x[k].imag();
    }
  }
  return coefficients;
}

double FourierBasis::peak_magnitude(const Eigen::VectorXd& c) const {
  if (c.size() != size()) {
    throw std::invalid_argument(fmt::format(
        "FourierBasis::peak_magnitude: {} coefficients, expected {}", c.size(), size()));
  }
  // x^(d)(θ) for d = 0, 1, 2 at phase θ = Ωt.
  const auto derivative = [&](double theta, int d) {
    double v = d == 0 && has_mean() ? c[0] : 0.0;
    for (int k : orders_) {
      const int a = cosine_index(k);
      const double ck = std::cos(k * theta), sk = std::sin(k * theta);
      const double kd = std::pow(static_cast<double>(k), d);
      if (d == 0) v += c[a] * ck + c[a + 1] * sk;
      if (d == 1) v += kd * (-c[a] * sk + c[a + 1] * ck);
      if (d == 2) v -= kd * (c[a] * ck + c[a + 1] * sk);
    }
    return v;
  };
  const int grid = std::max(time_samples_, 8 * harmonics_);
  const double h = 2.0 * std::numbers::pi / grid;
  double best = 0.0;
  double best_theta = 0.0;
  for (int i = 0; i < grid; ++i) {
    const double v = std::abs(derivative(i * h, 0));
    if (v > best) {
      best = v;
      best_theta = i * h;
    }
  }
  // Newton on x'(θ) = 0 within one grid cell of the best sample; keep the best value seen.
  double theta = best_theta;
  for (int it = 0; it < 30; ++it) {
    const double d2 = derivative(theta, 2);
    if (d2 == 0.0) break;
    const double next = theta - derivative(theta, 1) / d2;
    if (!(std::abs(next - best_theta) <= h)) break;
    const double v = std::abs(derivative(next, 0));
    if (v >= best) best = v;
    if (std::abs(next - theta) <= 1e-15 * (1.0 + std::abs(theta))) break;
    theta = next;
  }
  return best;
}

Eigen::MatrixXd FourierBasis::analysis_matrix() const {
  Eigen::MatrixXd a = synthesis_matrix().transpose();
  const double scale = 2.0 / time_samples_;
  a *= scale;
  if (has_mean()) a.row(0) *= 0.5;
  return a;
}

// The coefficients of `x` (DOF-major over basis `from`) in basis `to`: shared orders copied,
// the others zero.
Eigen::VectorXd transfer_coefficients(const FourierBasis& from, const FourierBasis& to,
                                      const Eigen::VectorXd& x, int dofs) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dofs) * to.size());
  for (int i = 0; i < dofs; ++i) {
    const Eigen::Index fi = static_cast<Eigen::Index>(i) * from.size();
    const Eigen::Index ti = static_cast<Eigen::Index>(i) * to.size();
    if (from.has_mean() && to.has_mean()) y[ti] = x[fi];
    for (int k : from.orders()) {
      const int b = to.cosine_index(k);
      if (b < 0) continue;
      const int a = from.cosine_index(k);
      y[ti + b] = x[fi + a];
      y[ti + b + 1] = x[fi + a + 1];
    }
  }
  return y;
}


}  // namespace jointhb::hb
