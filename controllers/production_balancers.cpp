// Four production balancers adapted to 1-D slabs: GROMACS DLB, HOOMD-blue LoadBalancer, ALL tensor, LAMMPS shift.
// Each computes real-valued boundaries as its tool does, then apply_targets rounds them and runs the min-width
// sweep. Sources and adaptations: docs/controllers.md "Production balancers".
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "metrics.hpp"
#include "partition.hpp"
#include "policy.hpp"

namespace semlb {
namespace {

double mean_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }

// Edges of the P slabs as reals: 0, b_1, ..., b_{P-1}, slices.
std::vector<double> edges(const Observation& obs) {
  std::vector<double> x{0.0};
  for (int b : obs.boundaries) x.push_back(b);
  x.push_back(obs.slices);
  return x;
}

// Interior boundary i (edge i+1) clamped half-way into each of its two old slabs: [mid(x_i, x_{i+1}),
// mid(x_{i+1}, x_{i+2})] (GROMACS enforce_limits' "halfway" rule, HOOMD's BVLS bounds l, u).
double halfway_clamp(double target, const std::vector<double>& x, size_t i) {
  return std::clamp(target, 0.5 * (x[i] + x[i + 1]), 0.5 * (x[i + 1] + x[i + 2]));
}

// ---------------------------------------------------------------------------------------------------------
// gromacs_dlb: GROMACS dynamic load balancing (src/gromacs/domdec/cellsizes.cpp set_dd_cell_sizes_dlb_root,
// dd_cell_sizes_dlb_root_enforce_limits; partition.cpp DD_PERF_LOSS_DLB_ON; -dlb auto).
struct GromacsParams {
  double relax = 0.5;       // c_relax: under-relaxation of the size change
  double cap = 0.10;        // GMX_DLB_MAX_BOX_SCALING = 10 (%): largest relative size change per event
  double threshold = 0.02;  // DD_PERF_LOSS_DLB_ON: DLB turns on once the imbalance costs this fraction
};

class GromacsDlbPolicy final : public Policy {
 public:
  explicit GromacsDlbPolicy(GromacsParams p) : p_(p) {}

  std::vector<int> decide(const Observation& obs) override {
    const auto& t = obs.times;
    if (t.size() < 2) return obs.boundaries;
    const double tmax = *std::max_element(t.begin(), t.end()), tmean = mean_of(t);
    if (!on_) {  // -dlb auto: off until the measured loss (T_max - T_mean)/T_max reaches the threshold, then on
      const double loss = tmax > 0.0 ? (tmax - tmean) / tmax : 0.0;
      if (loss < p_.threshold) return obs.boundaries;
      on_ = true;
    }
    if (tmean <= 0.0) return obs.boundaries;
    const auto w = widths(obs.boundaries, obs.slices);
    // change_r = -relax (T_r - T_mean)/T_mean; one factor for the whole row so that max |change| <= cap.
    double change_max = 0.0;
    for (double tr : t) change_max = std::max(change_max, p_.relax * std::fabs(tr - tmean) / tmean);
    const double sc = change_max > p_.cap ? p_.relax * p_.cap / change_max : p_.relax;
    std::vector<double> size(t.size());
    for (size_t r = 0; r < t.size(); ++r) size[r] = w[r] * (1.0 - sc * (t[r] - tmean) / tmean);
    const double fac = obs.slices / std::accumulate(size.begin(), size.end(), 0.0);  // sizes sum to the box
    const auto x = edges(obs);
    std::vector<double> targets(obs.boundaries.size());
    double cum = 0.0;
    for (size_t i = 0; i < targets.size(); ++i) {
      cum += size[i] * fac;
      targets[i] = halfway_clamp(cum, x, i);
    }
    return apply_targets(obs.boundaries, targets, obs.slices, obs.min_width);
  }

  PolicyState save_state() const override { return {{"dlb_on", {on_ ? 1.0 : 0.0}}}; }
  void load_state(const PolicyState& s) override {
    if (s.empty()) {
      on_ = false;
      return;
    }
    auto it = s.find("dlb_on");
    if (s.size() != 1 || it == s.end() || it->second.size() != 1 || (it->second[0] != 0.0 && it->second[0] != 1.0))
      throw InputError("gromacs_dlb state: expected dlb_on = [0] or [1]");
    on_ = it->second[0] == 1.0;
  }

 private:
  GromacsParams p_;
  bool on_ = false;
};

// ---------------------------------------------------------------------------------------------------------
// hoomd_balance: HOOMD-blue LoadBalancer (hoomd/LoadBalancer.cc adjust(); hoomd/tune/balance.py defaults).
struct HoomdParams {
  double tolerance = 1.02;  // balance only while max/mean load exceeds this
  long max_iterations = 1;  // balancing passes per event
  double max_scale = 0.05;  // m_max_scale: at most 5% rescaling of a slab per pass
};

// Bounded least squares of HOOMD's adjust() in one dimension: boundaries x_1..x_{P-1} minimising
// sum_r (x_r - x_{r-1} - target_r)^2 with lo_j <= x_j <= hi_j (x_0 = 0, x_P = length fixed). The problem is
// strictly convex with a tridiagonal Hessian; projected Gauss-Seidel converges to its unique minimiser.
std::vector<double> bounded_widths_fit(const std::vector<double>& target, const std::vector<double>& lo,
                                       const std::vector<double>& hi, double length) {
  const size_t n = lo.size();
  std::vector<double> x(n + 2, 0.0);
  x[n + 1] = length;
  // Start from the unconstrained optimum (every width off by the same amount), clamped.
  const double excess = (std::accumulate(target.begin(), target.end(), 0.0) - length) / target.size();
  double cum = 0.0;
  for (size_t j = 1; j <= n; ++j) {
    cum += target[j - 1] - excess;
    x[j] = std::clamp(cum, lo[j - 1], hi[j - 1]);
  }
  for (int sweep = 0; sweep < 100000; ++sweep) {
    double change = 0.0;
    for (size_t j = 1; j <= n; ++j) {
      const double best = 0.5 * ((x[j - 1] + target[j - 1]) + (x[j + 1] - target[j]));
      const double v = std::clamp(best, lo[j - 1], hi[j - 1]);
      change = std::max(change, std::fabs(v - x[j]));
      x[j] = v;
    }
    if (change <= 1e-12 * length) break;
  }
  return {x.begin() + 1, x.end() - 1};
}

class HoomdBalancePolicy final : public Policy {
 public:
  explicit HoomdBalancePolicy(HoomdParams p) : p_(p) {}

  std::vector<int> decide(const Observation& obs) override {
    const size_t ranks = obs.times.size();
    if (ranks < 2) return obs.boundaries;
    const auto x0 = edges(obs);
    // Later passes re-count the load of moved slabs with the work density of the measured interval taken
    // uniform inside each old slab (HOOMD re-counts its particles): cumulative load F is piecewise linear.
    std::vector<double> f0{0.0};
    for (double tr : obs.times) f0.push_back(f0.back() + tr);
    auto cumulative = [&](double pos) {
      const size_t r = std::min<size_t>(std::upper_bound(x0.begin(), x0.end(), pos) - x0.begin() - 1, ranks - 1);
      return f0[r] + obs.times[r] * (pos - x0[r]) / (x0[r + 1] - x0[r]);
    };
    std::vector<double> x = x0, load = obs.times;
    bool moved = false;
    for (long pass = 0; pass < p_.max_iterations; ++pass) {
      const double m = mean_of(load);
      if (m <= 0.0 || *std::max_element(load.begin(), load.end()) / m <= p_.tolerance) break;
      std::vector<double> target(ranks), lo(ranks - 1), hi(ranks - 1);
      for (size_t r = 0; r < ranks; ++r) {
        // scale by the inverse of the imbalance factor N_r / <N>; an empty slab grows by the largest step
        double scale = load[r] > 0.0 ? m / load[r] : 1.0 + p_.max_scale;
        scale = std::clamp(scale, 1.0 - p_.max_scale, 1.0 + p_.max_scale);
        target[r] = scale * (x[r + 1] - x[r]);
      }
      for (size_t j = 0; j + 1 < ranks; ++j) {
        lo[j] = 0.5 * (x[j] + x[j + 1]);
        hi[j] = 0.5 * (x[j + 1] + x[j + 2]);
      }
      const auto inner = bounded_widths_fit(target, lo, hi, obs.slices);
      std::copy(inner.begin(), inner.end(), x.begin() + 1);
      for (size_t r = 0; r < ranks; ++r) load[r] = cumulative(x[r + 1]) - cumulative(x[r]);
      moved = true;
    }
    if (!moved) return obs.boundaries;
    return apply_targets(obs.boundaries, std::vector<double>(x.begin() + 1, x.end() - 1), obs.slices, obs.min_width);
  }

 private:
  HoomdParams p_;
};

// ---------------------------------------------------------------------------------------------------------
// all_tensor: ALL's tensor method (include/ALL_Tensor.hpp balance(); include/ALL_Functions.hpp borderShift1d).
class AllTensorPolicy final : public Policy {
 public:
  explicit AllTensorPolicy(std::optional<double> gamma) : gamma_(gamma) {}

  std::vector<int> decide(const Observation& obs) override {
    const auto w = widths(obs.boundaries, obs.slices);
    std::vector<double> targets(obs.boundaries.size());
    for (size_t i = 0; i < targets.size(); ++i) {
      const double work_l = obs.times[i], work_r = obs.times[i + 1];
      const double d_l = w[i], d_r = w[i + 1];
      double shift = 0.0;
      if (work_l + work_r > 0.0) {
        // gamma = max(4.1, 2 (1 + d_max/d_min)) of the two slabs at this boundary, unless given
        const double gamma = gamma_ ? *gamma_ : std::max(4.1, 2.0 * (1.0 + std::max(d_l, d_r) / std::min(d_l, d_r)));
        shift = 0.5 / gamma * (work_r - work_l) / (work_r + work_l) * (d_l + d_r);
        // at most 0.49 of what the shrinking slab has above the minimum width (borders never cross)
        const double maxmove = 0.49 * ((shift > 0.0 ? d_r : d_l) - obs.min_width);
        shift = std::clamp(shift, -maxmove, maxmove);
      }
      targets[i] = obs.boundaries[i] + shift;
    }
    return apply_targets(obs.boundaries, targets, obs.slices, obs.min_width);
  }

 private:
  std::optional<double> gamma_;
};

// ---------------------------------------------------------------------------------------------------------
// lammps_shift: LAMMPS fix balance ... shift x Niter stopthresh (src/balance.cpp shift(), adjust();
// src/fix_balance.cpp; doc/src/balance.rst "shift" style).
struct LammpsParams {
  double threshold = 1.05;   // thresh: rebalance when max/mean slab work exceeds it
  long niter = 10;           // Niter: bisection iterations
  double stopthresh = 1.05;  // stop once every cut's cumulative work is within stopthresh - 1 of its target
  bool weight_time = false;  // weight time 1.0: rescale each slab's slice work so that it sums to its time
};

class LammpsShiftPolicy final : public Policy {
 public:
  explicit LammpsShiftPolicy(LammpsParams p) : p_(p) {}

  std::vector<int> decide(const Observation& obs) override {
    std::vector<double> cost = require_field(obs.slice_work, obs, "lammps_shift", "slice_work");
    const int np = obs.ranks();
    if (np < 2) return obs.boundaries;
    if (p_.weight_time) {  // ImbalanceTime: per-particle weight x (rank time / rank weight); empty slabs spread it
      const auto sums = rank_sums(cost, obs.boundaries);
      const auto x = edges(obs);
      for (int r = 0; r < np; ++r)
        for (int s = static_cast<int>(x[r]); s < static_cast<int>(x[r + 1]); ++s)
          cost[s] = sums[r] > 0.0 ? cost[s] * obs.times[r] / sums[r] : obs.times[r] / (x[r + 1] - x[r]);
    }
    std::vector<double> prefix{0.0};
    for (double c : cost) prefix.push_back(prefix.back() + c);
    const double total = prefix.back();
    if (total <= 0.0) return obs.boundaries;
    const auto load = rank_sums(cost, obs.boundaries);
    if (*std::max_element(load.begin(), load.end()) / (total / np) <= p_.threshold) return obs.boundaries;

    // Cumulative work below a real cut position, work spread uniformly inside each slice.
    auto cumulative = [&](double pos) {
      const int s = std::min(static_cast<int>(pos), obs.slices - 1);
      return prefix[s] + (pos - s) * cost[s];
    };
    std::vector<double> split = edges(obs), sum(np + 1), target(np + 1);
    for (int i = 0; i <= np; ++i) {
      sum[i] = cumulative(split[i]);
      target[i] = total / np * i;
    }
    sum[np] = target[np] = total;
    // lo[i] / hi[i]: closest current cut at or below / above cut i whose sum brackets target[i]
    std::vector<double> lo(np + 1), hi(np + 1), losum(np + 1), hisum(np + 1);
    lo[0] = hi[0] = 0.0;
    lo[np] = hi[np] = obs.slices;
    losum[0] = hisum[0] = 0.0;
    losum[np] = hisum[np] = total;
    for (int i = 1; i < np; ++i) {
      for (int j = i; j >= 0; --j)
        if (sum[j] <= target[i]) {
          lo[i] = split[j];
          losum[i] = sum[j];
          break;
        }
      for (int j = i; j <= np; ++j)
        if (sum[j] >= target[i]) {
          hi[i] = split[j];
          hisum[i] = sum[j];
          break;
        }
    }
    const double delta = p_.stopthresh - 1.0;
    for (long m = 0; m < p_.niter; ++m) {
      // tighten the brackets with the current sums, keep them monotone, bisect every unmet cut
      for (int i = 1; i < np; ++i) {
        if (sum[i] <= target[i]) lo[i] = split[i], losum[i] = sum[i];
        if (sum[i] >= target[i]) hi[i] = split[i], hisum[i] = sum[i];
      }
      for (int i = 1; i < np; ++i)
        if (lo[i] < lo[i - 1]) lo[i] = lo[i - 1], losum[i] = losum[i - 1];
      for (int i = np - 1; i > 0; --i)
        if (hi[i] > hi[i + 1]) hi[i] = hi[i + 1], hisum[i] = hisum[i + 1];
      bool change = false;
      for (int i = 1; i < np; ++i)
        if (sum[i] != target[i]) {
          change = true;
          split[i] = 0.5 * (lo[i] + hi[i]);
        }
      for (int i = 1; i < np; ++i) sum[i] = cumulative(split[i]);
      if (!change) break;
      bool done = true;
      for (int i = 1; i < np; ++i)
        if (std::fabs(sum[i] - target[i]) / target[i] > delta) done = false;
      if (done) break;
    }
    return apply_targets(obs.boundaries, std::vector<double>(split.begin() + 1, split.end() - 1), obs.slices,
                         obs.min_width);
  }

 private:
  LammpsParams p_;
};

// Parameter ranges (docs/controllers.md "Input rules: parameter ranges"): none lets a policy move work toward
// the slower rank, and none overshoots balance by more than it started from.
const Registrar<PolicyInfo> gromacs_registrar("gromacs_dlb", {[](PolicyParams& params) {
                                                GromacsParams p;
                                                p.relax = params.real("relax", p.relax, 0.0, 2.0, true, true);
                                                p.cap = params.real("cap", p.cap, 0.0, 1.0, true, true);
                                                p.threshold = params.real("threshold", p.threshold, 0.0, 1.0);
                                                return std::make_unique<GromacsDlbPolicy>(p);
                                              }});

const Registrar<PolicyInfo> hoomd_registrar("hoomd_balance", {[](PolicyParams& params) {
                                              HoomdParams p;
                                              p.tolerance = params.real("tolerance", p.tolerance, 0.0, kMaxThreshold);
                                              p.max_iterations =
                                                  params.integer("max_iterations", p.max_iterations, 1, 100);
                                              p.max_scale = params.real("max_scale", p.max_scale, 0.0, 1.0, true, true);
                                              return std::make_unique<HoomdBalancePolicy>(p);
                                            }});

const Registrar<PolicyInfo> all_tensor_registrar("all_tensor", {[](PolicyParams& params) {
                                                   std::optional<double> gamma;
                                                   if (params.has("gamma")) gamma = params.real("gamma", 0.0, 1.0, 1e6);
                                                   return std::make_unique<AllTensorPolicy>(gamma);
                                                 }});

const Registrar<PolicyInfo> lammps_registrar(
    "lammps_shift", {[](PolicyParams& params) {
                       LammpsParams p;
                       p.threshold = params.real("threshold", p.threshold, 0.0, kMaxThreshold);
                       p.niter = params.integer("niter", p.niter, 1, 1000);
                       p.stopthresh = params.real("stopthresh", p.stopthresh, 1.0, kMaxThreshold);
                       const std::string weight = params.text("weight", "none");
                       if (weight != "none" && weight != "time")
                         throw InputError("policy parameter 'weight': '" + weight + "' is not one of none, time");
                       p.weight_time = weight == "time";
                       return std::make_unique<LammpsShiftPolicy>(p);
                     },
                     PolicyNeeds{.slice_work = true}});

}  // namespace
}  // namespace semlb
