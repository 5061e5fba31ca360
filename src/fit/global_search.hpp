#pragma once
// The global phase of a fit's `direct` and `mlsl` searches (private to src/fit; fit/fitter.hpp),
// written so that its candidates are evaluated in batches: every point of a batch is known before
// any of it is evaluated, so the batch can be spread over worker processes and MPI ranks, and the
// search's path depends only on the objective values — the same result on any number of workers
// (docs/identification.md §2, "global searches"). NLopt's DIRECT-L and MLSL call the objective one
// point after another; these are the same methods with the batch structure made explicit.
//
// DIRECT-L (D. R. Jones, C. D. Perttunen, B. E. Stuckman, J. Optim. Theory Appl. 79 (1993)
// 157–181: DIRECT; J. M. Gablonsky, C. T. Kelley, J. Global Optim. 21 (2001) 27–37: the locally
// biased form). The unit box is divided into hyperrectangles, each sampled at its centre c, with
// side 3^(−l_i) in coordinate i. A rectangle's size is half its longest side, d = 3^(−min l)/2
// (the L∞ measure of DIRECT-L). An iteration selects the potentially optimal rectangles: those
// (d_j, f_j) on the lower-right convex hull of the points (d, f) that satisfy, with the slope K_j
// to the next hull point,
//     f_j − K_j d_j ≤ f_min − ε |f_min|,   ε = 0 (NLopt's DIRECT-L)    (Jones et al. 1993, Def. 4.1)
// — one rectangle per size (the one with the least f, DIRECT-L). Every selected rectangle is
// sampled at c ± δ e_i, δ = 3^(−min l − 1), along all its longest sides i (the batch), then
// trisected along those sides in the order of w_i = min(f(c + δe_i), f(c − δe_i)), so that the
// best values land in the largest new rectangles (Jones et al. 1993, §4.2).
//
// MLSL (A. H. G. Rinnooy Kan, G. T. Timmer, Math. Program. 39 (1987) 57–78, multi-level single
// linkage; with low-discrepancy points, S. Kucherenko, Y. Sytsko, Comput. Optim. Appl. 30 (2005)
// 297–318). Iteration k adds N points of a Sobol sequence (shifted by a seeded random vector,
// modulo 1; the batch) to the sample; of all kN sample points, a local search starts from each x
// that has not started one, has no sample point of lower S within the critical distance
//     r_k = π^(−1/2) (Γ(1 + n/2) σ ln(kN) / (kN))^(1/n),   σ = 4        (Rinnooy Kan & Timmer, §3)
// and no local minimum found so far of lower S within r_k — at most `max_local` a level, those of
// least S. The iteration's local searches are independent of one another: they run as one batch.

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace jointhb::fit::detail {

/// S at each point (unit box) of a batch, in order.
using BatchObjective =
    std::function<std::vector<double>(const std::vector<std::vector<double>>& points)>;

/// What one local search found.
struct LocalMinimum {
  std::vector<double> u;  ///< the best point (unit box)
  double objective = std::numeric_limits<double>::infinity();  ///< its S (∞: nothing succeeded)
  int evaluations = 0;
};
/// Local searches from each of `starts` (unit box), each with at most `max_evaluations`: one
/// result per start, in order.
using LocalSearches = std::function<std::vector<LocalMinimum>(
    const std::vector<std::vector<double>>& starts, int max_evaluations)>;

struct GlobalOutcome {
  std::vector<double> best;  ///< the point of least S (the first one found, on ties)
  double objective = std::numeric_limits<double>::infinity();
  int evaluations = 0;  ///< of the objective (MLSL: the samples and the local searches)
  int batches = 0;
  int largest_batch = 0;
  int local_searches = 0;     ///< MLSL
  std::string stop_reason;    ///< MAXEVAL_REACHED or XTOL_REACHED (NLopt's names)
};

/// DIRECT-L over the unit box of `dimensions`: iterations while their batch fits in
/// `max_evaluations` and some selected rectangle's new side is ≥ `xtol`.
[[nodiscard]] GlobalOutcome direct_l(int dimensions, const BatchObjective& objective,
                                     int max_evaluations, double xtol);

struct MlslOptions {
  int max_evaluations = 400;  ///< samples and local searches together
  int population = 0;         ///< N, points per iteration; 0: max(8, 4 · dimensions)
  int max_local = 4;          ///< local searches per iteration at most
  double sigma = 4.0;         ///< σ of the critical distance
  unsigned seed = 1;          ///< the random shift of the Sobol points
};

/// MLSL over the unit box of `dimensions` (see above). Each iteration's local searches share
/// what is left of the budget after its sample, equally.
[[nodiscard]] GlobalOutcome mlsl(int dimensions, const BatchObjective& objective,
                                 const LocalSearches& local, const MlslOptions& options);

}  // namespace jointhb::fit::detail
