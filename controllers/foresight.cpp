// Offline perfect-foresight boundaries: a DP over boundary positions with L1 distance transforms in time.
#include "foresight.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "chains.hpp"
#include "common/errors.hpp"
#include "metrics.hpp"
#include "partition.hpp"

namespace semlb {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// I_global of interval t under boundaries b, from prefix sums p (the DP's own cost, used consistently).
double imbalance_of(const std::vector<double>& p, std::span<const int> b) {
  const int S = static_cast<int>(p.size()) - 1, P = static_cast<int>(b.size()) + 1;
  const double mean = p[S] / P;
  if (mean <= 0.0) return 0.0;
  double hi = -kInf, lo = kInf;
  for (int r = 0; r < P; ++r) {
    const double t = p[r + 1 < P ? b[r] : S] - p[r > 0 ? b[r - 1] : 0];
    hi = std::max(hi, t);
    lo = std::min(lo, t);
  }
  return (hi - lo) / mean;
}

double objective(const std::vector<std::vector<double>>& p, const std::vector<std::vector<int>>& path, double lambda) {
  double sum = 0;
  for (size_t t = 0; t < path.size(); ++t) {
    sum += imbalance_of(p[t], path[t]);
    if (t > 0) sum += lambda * static_cast<double>(migration(path[t - 1], path[t]));
  }
  return sum;
}

// Replaces boundary i's trajectory (t >= 1) by the best one with every other boundary as in `path`:
// f_t(x) = c_t(x) + min_y (f_{t-1}(y) + lambda |x - y|), the inner minimum an L1 distance transform (one
// forward and one backward pass, argmin kept for the backtrack). Ties keep the smaller move / position.
void solve_one_boundary(const std::vector<std::vector<double>>& p, std::vector<std::vector<int>>& path, int i,
                        int min_width, double lambda) {
  const int K = static_cast<int>(path.size()), S = static_cast<int>(p[0].size()) - 1;
  const int B = static_cast<int>(path[0].size()), P = B + 1;
  std::vector<double> f(S + 1, kInf), g(S + 1);
  std::vector<int> garg(S + 1);
  std::vector<std::vector<int>> from(K, std::vector<int>(S + 1, -1));
  f[path[0][i]] = 0.0;
  for (int t = 1; t < K; ++t) {
    for (int x = 0; x <= S; ++x) {
      g[x] = f[x];
      garg[x] = x;
    }
    for (int x = 1; x <= S; ++x)
      if (g[x - 1] + lambda < g[x]) {
        g[x] = g[x - 1] + lambda;
        garg[x] = garg[x - 1];
      }
    for (int x = S - 1; x >= 0; --x)
      if (g[x + 1] + lambda < g[x]) {
        g[x] = g[x + 1] + lambda;
        garg[x] = garg[x + 1];
      }
    const auto& b = path[t];
    const auto& pt = p[t];
    const int left = i > 0 ? b[i - 1] : 0, right = i + 1 < B ? b[i + 1] : S;
    double omax = -kInf, omin = kInf;  // the ranks this boundary does not touch
    for (int r = 0; r < P; ++r) {
      if (r == i || r == i + 1) continue;
      const double tr = pt[r + 1 < P ? b[r] : S] - pt[r > 0 ? b[r - 1] : 0];
      omax = std::max(omax, tr);
      omin = std::min(omin, tr);
    }
    const double mean = pt[S] / P;
    std::fill(f.begin(), f.end(), kInf);
    for (int x = left + min_width; x <= right - min_width; ++x) {
      const double tl = pt[x] - pt[left], tr = pt[right] - pt[x];
      const double c = mean <= 0.0 ? 0.0 : (std::max({omax, tl, tr}) - std::min({omin, tl, tr})) / mean;
      f[x] = c + g[x];
      from[t][x] = garg[x];
    }
  }
  int best = -1;
  for (int x = 0; x <= S; ++x)
    if (f[x] < kInf && (best < 0 || f[x] < f[best])) best = x;
  for (int t = K - 1; t >= 1; --t) {
    path[t][i] = best;
    best = from[t][best];
  }
}

void descend(const std::vector<std::vector<double>>& p, std::vector<std::vector<int>>& path, int min_width,
             double lambda) {
  const int B = static_cast<int>(path[0].size());
  double current = objective(p, path, lambda);
  for (int sweep = 0; sweep < 100; ++sweep) {
    for (int i = 0; i < B; ++i) solve_one_boundary(p, path, i, min_width, lambda);
    const double next = objective(p, path, lambda);
    if (B == 1 || !(next < current - 1e-12 * (1.0 + std::fabs(current)))) return;
    current = next;
  }
}

}  // namespace

ForesightPath foresight_path(const std::vector<std::vector<double>>& work, std::span<const int> initial, int min_width,
                             double lambda) {
  if (!std::isfinite(lambda) || lambda < 0.0) throw InputError("foresight: lambda must be finite and >= 0");
  if (work.empty()) throw InputError("foresight: no intervals");
  const int S = static_cast<int>(work[0].size()), P = static_cast<int>(initial.size()) + 1;
  check_partition(initial, S, min_width);
  std::vector<std::vector<double>> p(work.size(), std::vector<double>(S + 1, 0.0));
  for (size_t t = 0; t < work.size(); ++t) {
    if (static_cast<int>(work[t].size()) != S)
      throw InputError("foresight: interval " + std::to_string(t) + " has " + std::to_string(work[t].size()) +
                       " slices, interval 0 has " + std::to_string(S));
    for (int s = 0; s < S; ++s) {
      if (!std::isfinite(work[t][s]) || work[t][s] < 0.0)
        throw InputError("foresight: interval " + std::to_string(t) + ": work[" + std::to_string(s) +
                         "] is not finite and non-negative");
      p[t][s + 1] = p[t][s] + work[t][s];
    }
  }
  const std::vector<int> b0(initial.begin(), initial.end());
  ForesightPath out;
  out.exact = P <= 2;
  if (P == 1) {
    out.boundaries.assign(work.size(), {});
  } else {
    std::vector<std::vector<int>> still(work.size(), b0);
    descend(p, still, min_width, lambda);
    out.boundaries = std::move(still);
    if (P > 2) {  // a second start near balance; the better of the two (ties: the first)
      std::vector<std::vector<int>> balanced(work.size(), b0);
      for (size_t t = 1; t < work.size(); ++t) balanced[t] = optimal_partition(work[t], P, min_width);
      descend(p, balanced, min_width, lambda);
      if (objective(p, balanced, lambda) < objective(p, out.boundaries, lambda)) out.boundaries = std::move(balanced);
    }
  }
  for (size_t t = 0; t < work.size(); ++t) {
    out.imbalance.push_back(global_imbalance(rank_sums(work[t], out.boundaries[t])));
    if (t > 0) out.migration += migration(out.boundaries[t - 1], out.boundaries[t]);
    out.objective += out.imbalance.back();
  }
  out.objective += lambda * static_cast<double>(out.migration);
  return out;
}

std::vector<int> ForesightPolicy::decide(const Observation&) {
  throw InputError(
      "policy 'foresight' is an offline analysis baseline: it needs the true work of the whole run in "
      "advance (run it with `semlb surrogate`, a surrogate manifest or `semlb replay --score`)");
}

namespace {
const Registrar<PolicyInfo> foresight_registrar(
    "foresight", {[](PolicyParams& p) { return std::make_unique<ForesightPolicy>(p.real("lambda", 0.001, 0.0, 1e6)); },
                  PolicyNeeds{.true_work = true}});
}  // namespace

}  // namespace semlb
