// Cost of one Newton iteration of harmonic balance, split into AFT, Jacobian assembly and the
// linear solve, against the number of harmonics H.
//
// Description: two models, each at a representative slipping state (HB solved at fixed Ω by a
// damped Newton method; every contact slips during the period):
//   1dof      m = k = 1, one contact to ground k_T0 = 1, μF_N = 1, ζ = 0.02, F = 1, Ω = 1.15
//             (gross slip, amplitude 1.9 g_max for Gaul–Mayer);
//   10dof     chain of 10 unit masses (springs k = 1, x_0 to ground), 5 contacts k_T0 = 2,
//             μF_N = 1: DOF 1, 5, 9 to ground and 3–2, 7–6 between DOFs, modal ζ = 0.02, F = 5
//             on DOF 9, Ω = 1.0 (all five contacts slip, also with the Jenkins law);
// both with the Gaul–Mayer law (n = 1/3) and with the Jenkins law, H = 1…15 with every harmonic
// kept (HarmonicSelection::all: n (2H + 1) unknowns) and N_t = 256; and a sweep of N_t at H = 7.
// At each state, HarmonicBalance::evaluate(X, Ω, jacobian = true) is repeated until 0.2 s have
// passed (0.05 s with --ci; at least 5 calls): HarmonicBalance::timings() gives the AFT (FFTs,
// periodic states, sensitivities) and assembly (S(Ω), S'(Ω), scatter) per call, the wall time of
// the call the rest ("other": allocation, the residual's linear part outside the timers). The
// linear solve is timed here as the continuation does it: Eigen PartialPivLU of the bordered
// (n+1) × (n+1) matrix [∂R/∂X, ∂R/∂Ω; τᵀ] and one solve, repeated likewise. Per iteration:
// total = evaluate + solve. Growth exponents: least-squares slope of log(time) against log(H)
// over H = 3…15.
//
// Bounds (no bound is placed on any time; exit code 1 when one is exceeded): every Newton solve
// converges to ‖R‖_∞ ≤ 1e-10 F; every contact slips at the state that is timed (not stuck, not
// evaluated as a spring); the analytic Jacobian agrees with central differences to 1e-6 of its
// largest entry at H = 3 (the timed Jacobian is the right one); the LU solve's backward error
// ‖J δ − r‖_∞ / (‖J‖_∞ ‖δ‖_∞) ≤ 1e-12; the library's timers are consistent
// (aft + assembly ≤ wall time of the calls, evaluations = calls).
// --ci: H ∈ {1, 3, 7, 15}, N_t ∈ {64, 256, 1024} in the sweep, 0.05 s per measurement.
//
// Sample runs (one thread, as in docs/performance.md):
//   OMP_NUM_THREADS=1 build-val/validation/hb/jointhb_validate_hb_cost validation/hb/results/cost

#include <cstdlib>
#include <random>

#include "study_common.hpp"

// The study is one function of the multi-call program jointhb_validate_hb (CMakeLists.txt).
namespace jointhb_study_hb_cost {

namespace {

using namespace validation_study;

struct Model {
  std::string name;
  std::string law;
  hb::DiscreteSystem system;
  hb::Excitation excitation;
  double omega = 0.0;
};

ContactSpec contact(const std::string& law, double stiffness) {
  ContactSpec c;
  c.law = law;
  c.exponent = 1.0 / 3.0;
  c.stiffness = stiffness;
  c.slip_limit = 1.0;
  return c;
}

std::vector<Model> models() {
  std::vector<Model> list;
  for (const std::string law : {"gaul-mayer", "jenkins"}) {
    Model one;
    one.name = "1dof";
    one.law = law;
    one.system = oscillator(contact(law, 1.0), 0.02);
    one.excitation = cosine_force(0, 1.0);
    one.omega = 1.15;
    list.push_back(std::move(one));
    Model ten;
    ten.name = "10dof";
    ten.law = law;
    ten.system =
        chain(10, 1.0, contact(law, 2.0), {{1, -1}, {3, 2}, {5, -1}, {7, 6}, {9, -1}}, 0.02);
    ten.excitation = cosine_force(9, 5.0);
    ten.omega = 1.0;
    list.push_back(std::move(ten));
  }
  return list;
}

struct Measurement {
  std::string model, law;
  int harmonics = 0, samples = 0;
  Index unknowns = 0;
  double aft = 0.0, assembly = 0.0, other = 0.0, solve = 0.0;  // seconds per iteration
  int calls = 0, solves = 0;
  double residual = 0.0;
  bool slipping = true;
  double backward_error = 0.0;
  [[nodiscard]] double total() const { return aft + assembly + other + solve; }
};

hb::HarmonicBalanceOptions balance_options(int h, int n) {
  hb::HarmonicBalanceOptions o;
  o.harmonics = h;
  o.time_samples = n;
  o.selection = hb::HarmonicSelection::all;
  return o;
}

// Largest |analytic − central difference| / max |analytic| of ∂R/∂X at x.
double jacobian_error(const hb::HarmonicBalance& balance, const VectorXd& x, double omega) {
  hb::HarmonicBalanceEvaluation ev, plus, minus;
  balance.evaluate(x, omega, true, ev);
  const double h = 1e-7 * x.lpNorm<Eigen::Infinity>();
  double error = 0.0;
  for (Index j = 0; j < x.size(); ++j) {
    VectorXd xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    balance.evaluate(xp, omega, false, plus);
    balance.evaluate(xm, omega, false, minus);
    const VectorXd fd = (plus.residual - minus.residual) / (2.0 * h);
    error = std::max(error, (fd - ev.d_coefficients.col(j)).lpNorm<Eigen::Infinity>());
  }
  return error / ev.d_coefficients.cwiseAbs().maxCoeff();
}

Measurement measure(const Model& m, int h, int n, const VectorXd* guess,
                    const hb::HarmonicBalance* guess_balance, double budget, VectorXd& solution,
                    Scorecard& score) {
  hb::HarmonicBalance balance(m.system, m.excitation, balance_options(h, n));
  Measurement r;
  r.model = m.name;
  r.law = m.law;
  r.harmonics = h;
  r.samples = n;
  r.unknowns = balance.unknowns();
  const VectorXd x0 =
      guess ? pad(*guess_balance, *guess, balance) : balance.stuck_solution(m.omega);
  NewtonOptions no;
  no.residual_tolerance = 1e-12;
  const NewtonResult nr = solve_at_omega(balance, x0, m.omega, no);
  r.residual = nr.residual;
  solution = nr.x;
  const std::string where = fmt::format("{} {} H = {} N_t = {}", m.name, m.law, h, n);
  score.check(nr.converged && nr.residual <= 1e-10,
              fmt::format("{}: Newton {} (residual {:.2e}) {}", where,
                          nr.converged ? "converged" : "failed", nr.residual, nr.message));
  for (const auto& c : nr.evaluation.contacts) r.slipping = r.slipping && !c.stuck && !c.skipped;
  score.check(r.slipping, fmt::format("{}: a contact sticks at the timed state", where));

  // Evaluations.
  hb::HarmonicBalanceEvaluation ev;
  balance.evaluate(nr.x, m.omega, true, ev);  // warm-up (allocations, FFTW buffers)
  balance.reset_timings();
  const auto start = Clock::now();
  double wall = 0.0;
  while (r.calls < 5 || wall < budget) {
    balance.evaluate(nr.x, m.omega, true, ev);
    ++r.calls;
    wall = seconds_since(start);
  }
  const hb::HarmonicBalanceTimings t = balance.timings();
  score.check(t.evaluations == r.calls && t.jacobians == r.calls && t.aft + t.assembly <= wall,
              fmt::format("{}: timers inconsistent (evaluations {}, jacobians {}, calls {}, aft + "
                          "assembly {:.3e} s, wall {:.3e} s)",
                          where, t.evaluations, t.jacobians, r.calls, t.aft + t.assembly, wall));
  r.aft = t.aft / r.calls;
  r.assembly = t.assembly / r.calls;
  r.other = std::max(0.0, wall / r.calls - r.aft - r.assembly);

  // Bordered LU as in the continuation's corrector.
  const Index size = balance.unknowns();
  MatrixXd bordered(size + 1, size + 1);
  bordered.topLeftCorner(size, size) = ev.d_coefficients;
  bordered.topRightCorner(size, 1) = ev.d_omega;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (Index j = 0; j <= size; ++j) bordered(size, j) = uniform(random);
  VectorXd rhs(size + 1);
  rhs.head(size) = -ev.residual - ev.d_coefficients.col(0);  // any non-trivial right-hand side
  rhs[size] = 1.0;
  VectorXd delta;
  const auto solve_start = Clock::now();
  double solve_wall = 0.0;
  while (r.solves < 5 || solve_wall < budget) {
    const Eigen::PartialPivLU<MatrixXd> lu(bordered);
    delta = lu.solve(rhs);
    ++r.solves;
    solve_wall = seconds_since(solve_start);
  }
  r.solve = solve_wall / r.solves;
  r.backward_error =
      (bordered * delta - rhs).lpNorm<Eigen::Infinity>() /
      (bordered.cwiseAbs().rowwise().sum().maxCoeff() * delta.lpNorm<Eigen::Infinity>());
  score.check(r.backward_error <= 1e-12,
              fmt::format("{}: LU backward error {:.2e}", where, r.backward_error));
  if (h == 3 && n == 256) {
    const double e = jacobian_error(balance, nr.x, m.omega);
    score.check(e <= 1e-6, fmt::format("{}: Jacobian differs from central differences by {:.2e} "
                                       "of its largest entry",
                                       where, e));
  }
  return r;
}

}  // namespace

int run(int argc, char** argv) {
  const Arguments args = parse_arguments(argc, argv);
  if (!args.ok) return 2;
  Scorecard score;
  const auto start = Clock::now();
  const double budget = args.ci ? 0.05 : 0.2;
  std::vector<int> hs;
  if (args.ci) {
    hs = {1, 3, 7, 15};
  } else {
    for (int h = 1; h <= 15; ++h) hs.push_back(h);
  }
  const std::vector<int> ns = args.ci ? std::vector<int>{64, 256, 1024}
                                      : std::vector<int>{64, 128, 256, 512, 1024, 2048, 4096};
  const char* threads = std::getenv("OMP_NUM_THREADS");

  const std::vector<std::string> columns = {"model",
                                            "law",
                                            "H",
                                            "N_t",
                                            "unknowns",
                                            "aft_s",
                                            "assembly_s",
                                            "other_s",
                                            "solve_s",
                                            "total_s",
                                            "evaluate_calls",
                                            "solves",
                                            "residual",
                                            "lu_backward_error"};
  Csv table_h(args.prefix + "_harmonics.csv", columns);
  Csv table_n(args.prefix + "_samples.csv", columns);
  const auto write = [](Csv& t, const Measurement& r) {
    t.row({r.model, r.law, fmt::format("{}", r.harmonics), fmt::format("{}", r.samples),
           fmt::format("{}", r.unknowns), csv_number(r.aft), csv_number(r.assembly),
           csv_number(r.other), csv_number(r.solve), csv_number(r.total()),
           fmt::format("{}", r.calls), fmt::format("{}", r.solves), csv_number(r.residual),
           csv_number(r.backward_error)});
  };

  std::vector<Measurement> by_h, by_n;
  for (const Model& m : models()) {
    VectorXd previous;
    std::unique_ptr<hb::HarmonicBalance> previous_balance;
    for (const int h : hs) {
      VectorXd solution;
      const Measurement r = measure(m, h, 256, previous_balance ? &previous : nullptr,
                                    previous_balance.get(), budget, solution, score);
      write(table_h, r);
      by_h.push_back(r);
      previous = solution;
      previous_balance =
          std::make_unique<hb::HarmonicBalance>(m.system, m.excitation, balance_options(h, 256));
    }
    for (const int n : ns) {
      VectorXd solution;
      const Measurement r = measure(m, 7, n, nullptr, nullptr, budget, solution, score);
      write(table_n, r);
      by_n.push_back(r);
    }
  }

  // ---- summary ----
  fmt::print(
      "Cost per Newton iteration of HB{} (OMP_NUM_THREADS = {}), N_t = 256, all harmonics "
      "kept; times in microseconds per iteration\n",
      args.ci ? " (--ci)" : "", threads ? threads : "unset");
  for (const std::string law : {"gaul-mayer", "jenkins"}) {
    for (const std::string model : {"1dof", "10dof"}) {
      fmt::print("\n{} {}:\n  {:>3} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10}\n", model, law, "H",
                 "unknowns", "AFT", "assembly", "other", "solve", "total");
      std::vector<double> x, aft, assembly, solve, total;
      for (const auto& r : by_h) {
        if (r.model != model || r.law != law) continue;
        fmt::print("  {:>3} {:>8} {:>10.2f} {:>10.2f} {:>10.2f} {:>10.2f} {:>10.2f}\n", r.harmonics,
                   r.unknowns, 1e6 * r.aft, 1e6 * r.assembly, 1e6 * r.other, 1e6 * r.solve,
                   1e6 * r.total());
        if (r.harmonics < 3) continue;
        x.push_back(r.harmonics);
        aft.push_back(r.aft);
        assembly.push_back(r.assembly);
        solve.push_back(r.solve);
        total.push_back(r.total());
      }
      fmt::print(
          "  growth exponent in H (H = 3..{}): AFT {:.2f}, assembly {:.2f}, solve {:.2f}, "
          "total {:.2f}\n",
          hs.back(), loglog_slope(x, aft), loglog_slope(x, assembly), loglog_slope(x, solve),
          loglog_slope(x, total));
      std::vector<double> nn, aft_n;
      for (const auto& r : by_n) {
        if (r.model != model || r.law != law) continue;
        nn.push_back(r.samples);
        aft_n.push_back(r.aft);
      }
      fmt::print("  AFT at H = 7 vs N_t = {}..{}: growth exponent {:.2f}; ", ns.front(), ns.back(),
                 loglog_slope(nn, aft_n));
      for (const auto& r : by_n) {
        if (r.model == model && r.law == law) fmt::print(" {}:{:.1f}", r.samples, 1e6 * r.aft);
      }
      fmt::print(" us\n");
    }
  }
  fmt::print("\ntables: {}_{{harmonics,samples}}.csv; run time {:.1f} s\n", args.prefix,
             seconds_since(start));
  return score.finish();
}

}  // namespace jointhb_study_hb_cost
