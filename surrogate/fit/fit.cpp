// Offline fit of learned_repartition: episode sets, their objective, NLopt's search and the choice on validation.
#include "fit.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "common/errors.hpp"
#include "common/settings.hpp"
#include "common/text_io.hpp"
#include "common/yaml.hpp"
#include "controllers/policy.hpp"
#include "controllers/workload.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/rollout.hpp"
#include "surrogate/scenario.hpp"
#include "surrogate/workload_replay.hpp"

namespace semlb::fit {
namespace {

// The search box of each parameter (inside its allowed range, repartition_params()): [0, upper].
const std::map<std::string, double> kUpper{{"gain", 1.0},       {"noise_floor", 0.15}, {"trend", 1.0},
                                           {"deadband", 0.005}, {"move_cost", 0.5},    {"fixed_cost", 0.2}};

constexpr size_t kShortlist = 12;  // points of the search besides its best that validation chooses among

// The parameters of `free` from a point of the unit box (in the order of `free`); the others stay 0.
RepartitionParams from_unit(const std::vector<double>& x, const std::vector<std::string>& free) {
  RepartitionParams p;
  for (size_t i = 0; i < free.size(); ++i)
    for (const auto& d : repartition_params())
      if (free[i] == d.name) p.*d.field = std::clamp(x[i], 0.0, 1.0) * kUpper.at(d.name);
  return p;
}

std::vector<std::string> comma_list(const std::string& text) {  // a comma-separated list, empty items left out
  auto v = split(text, ',');
  v.erase(std::remove(v.begin(), v.end(), std::string()), v.end());
  return v;
}

}  // namespace

FitConfig load_fit_config(const std::string& path, const std::vector<std::string>& overrides) {
  const Settings s = load_flat_settings(path, "fit config", overrides);
  FitConfig c;
  for (auto [key, files] : {std::pair{"workloads", &c.workloads}, std::pair{"validation", &c.validation}}) {
    *files = comma_list(s.text(key, ""));
    for (const auto& f : *files) {
      if (!std::filesystem::exists(f)) s.fail(key, "no such workload file '" + f + "'");
      if (!std::filesystem::is_regular_file(f)) s.fail(key, "'" + f + "' is not a file");
    }
  }
  c.ranks = s.text("ranks", c.ranks);
  c.replay_seeds = s.text("replay_seeds", c.replay_seeds);
  c.validation_surrogate_seeds = s.text("validation_surrogate_seeds", c.validation_surrogate_seeds);
  c.surrogate_episodes = s.integer("surrogate_episodes", c.surrogate_episodes, 0, 8000);
  c.surrogate_events = s.integer("surrogate_events", c.surrogate_events, 2, 100000);
  c.surrogate_weight = s.real("surrogate_weight", c.surrogate_weight, 0, 1);
  c.regret_weight = s.real("regret_weight", c.regret_weight, 0, 1000);
  c.evaluations = s.integer("evaluations", c.evaluations, 0, 1000000);
  c.polish = s.integer("polish", c.polish, 0, 1000000);
  c.seed = s.integer("seed", c.seed, 0, std::numeric_limits<long>::max());
  c.threads = s.integer("threads", c.threads, 1, 1024);
  c.grid = s.boolean("grid", c.grid);
  if (s.has("free")) {
    c.free = comma_list(s.text("free", ""));
    if (c.free.empty()) s.fail("free", "must name at least one parameter");
  } else {
    for (const auto& d : repartition_params()) c.free.push_back(d.name);
  }
  for (size_t i = 0; i < c.free.size(); ++i) {
    if (!kUpper.count(c.free[i])) s.fail("free", "'" + c.free[i] + "' is not a learned_repartition parameter");
    if (std::find(c.free.begin(), c.free.begin() + i, c.free[i]) != c.free.begin() + i)
      s.fail("free", "'" + c.free[i] + "' is named twice");
  }
  s.finish("unknown fit setting");
  for (long r : surrogate::parse_int_list(c.ranks, s.where("ranks")))
    if (r < 2 || r > 64) s.fail("ranks", "each must be in [2, 64]");
  for (long seed : surrogate::parse_int_list(c.replay_seeds, s.where("replay_seeds")))
    if (seed < 0) s.fail("replay_seeds", "must be >= 0");
  for (long seed : surrogate::parse_int_list(c.validation_surrogate_seeds, s.where("validation_surrogate_seeds")))
    if (!surrogate::kValidationSeeds.contains(seed))
      s.fail("validation_surrogate_seeds", "must lie in the validation range 8000-8999");
  if (c.workloads.empty() && c.surrogate_episodes == 0)
    s.fail("workloads", "nothing to fit on: no workloads and no surrogate_episodes");
  return c;
}

struct EpisodeSet::WorkloadEpisode {
  std::shared_ptr<const EngineWorkload> workload;
  std::string file;
  surrogate::WorkloadReplay replay;
};
struct EpisodeSet::SurrogateEpisode {
  surrogate::Scenario scenario;
  long events;
};

EpisodeSet::EpisodeSet(const FitConfig& c, bool validation) : c_(c) {
  const auto ranks = surrogate::parse_int_list(c.ranks, "ranks");
  for (const auto& f : validation ? c.validation : c.workloads) {
    auto w = std::make_shared<const EngineWorkload>(read_workload(f));
    for (long p : ranks)
      for (long seed : surrogate::parse_int_list(c.replay_seeds, "replay_seeds")) {
        surrogate::WorkloadReplay r;
        r.ranks = static_cast<int>(p);
        r.seed = static_cast<uint64_t>(seed);
        workload_episodes_.push_back(std::make_shared<const WorkloadEpisode>(WorkloadEpisode{w, f, r}));
      }
  }
  std::vector<long> seeds;
  if (validation)
    seeds = surrogate::parse_int_list(c.validation_surrogate_seeds, "validation_surrogate_seeds");
  else
    for (long i = 0; i < c.surrogate_episodes; ++i) seeds.push_back(i);
  for (size_t i = 0; i < seeds.size(); ++i)
    surrogate_episodes_.push_back(std::make_shared<const SurrogateEpisode>(SurrogateEpisode{
        surrogate::make_scenario(seeds[i], static_cast<int>(ranks[i % ranks.size()])), c.surrogate_events}));
  base_ = losses([] { return make_learned_repartition(RepartitionParams{}); });
  const auto fixed = losses([] { return make_policy("static"); });
  for (size_t i = 0; i < base_.size(); ++i) base_[i] = std::min(base_[i], fixed[i]);
}

std::vector<double> EpisodeSet::losses(const std::function<std::unique_ptr<Policy>()>& make) const {
  const size_t nw = workload_episodes_.size(), n = size();
  std::vector<double> out(n, 0.0);
  std::atomic<size_t> next{0};
  std::vector<std::string> errors(n);
  auto work = [&] {
    for (size_t i; (i = next++) < n;) {
      try {
        auto policy = make();
        if (i < nw) {
          const auto& e = *workload_episodes_[i];
          out[i] = surrogate::replay_workload(*e.workload, e.replay, *policy, "learned_repartition", e.file).loop_s;
        } else {
          const auto& e = *surrogate_episodes_[i - nw];
          const auto r = surrogate::rollout(e.scenario, *policy, static_cast<int>(e.events));
          out[i] = static_cast<double>(r.events) * (1.0 + r.mean_max_over_mean) +
                   static_cast<double>(r.migration) * e.scenario.ranks / e.scenario.slices;
        }
      } catch (const std::exception& err) {
        errors[i] = err.what();
      }
    }
  };
  std::vector<std::thread> pool;
  for (long t = 1; t < c_.threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (const auto& e : errors)
    if (!e.empty()) throw InputError(e);
  return out;
}

double EpisodeSet::objective(const RepartitionParams& p) const {
  const auto l = losses([&p] { return make_learned_repartition(p); });
  const size_t nw = workload_episodes_.size(), ns = surrogate_episodes_.size();
  double w = 0, s = 0;
  auto term = [&](size_t i) {  // the ratio, its excess over the reference counted regret_weight times more
    const double r = l[i] / base_[i];
    return r + c_.regret_weight * std::max(r - 1.0, 0.0);
  };
  for (size_t i = 0; i < nw; ++i) w += term(i);
  for (size_t i = nw; i < nw + ns; ++i) s += term(i);
  if (ns == 0) return w / nw;
  if (nw == 0) return s / ns;
  return (1 - c_.surrogate_weight) * w / nw + c_.surrogate_weight * s / ns;
}

FitResult run_fit(const FitConfig& c, const FitOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::string log_path =
      o.log.empty() ? std::filesystem::path(o.out).replace_extension(".log.csv").string() : o.log;
  for (const auto& [flag, path] :
       {std::pair{"--out", o.out}, std::pair{"--log", log_path}}) {  // before minutes of search
    if (std::filesystem::is_directory(path)) throw InputError(std::string(flag) + ": '" + path + "' is a folder");
    const std::string probe = path + ".tmp";
    if (!std::ofstream(probe)) throw InputError(std::string(flag) + ": cannot write '" + path + "'");
    std::filesystem::remove(probe);
  }
  const EpisodeSet train(c, false);
  const EpisodeSet valid(c, true);
  PendingFile log_file(log_path);  // the weights' own writer does the same for o.out
  std::ofstream log(log_file.tmp());
  if (!log) throw InputError(log_path + ": cannot write the fit log");
  log << "evaluation,phase";
  for (const auto& d : repartition_params()) log << "," << d.name;
  log << ",train_objective\n";
  FitResult res;
  const size_t n = c.free.size();
  std::string phase;
  double best = HUGE_VAL;
  std::vector<double> best_x(n, 0.0);
  std::vector<std::pair<double, RepartitionParams>> evaluated;  // every point, for the validation shortlist
  auto f = [&](const std::vector<double>& x) {
    const auto p = from_unit(x, c.free);
    const double v = train.objective(p);
    evaluated.emplace_back(v, p);
    ++res.evaluations;
    log << res.evaluations << "," << phase;
    for (const auto& d : repartition_params()) log << "," << format_real(p.*d.field);
    log << "," << format_real(v) << "\n";
    if (v < best) best = v, best_x = x;
    if (o.progress && res.evaluations % 10 == 0)
      std::fprintf(stderr, "\rfit: %s, evaluation %ld, best train objective %.5f   ", phase.c_str(), res.evaluations,
                   best);
    return v;
  };
  auto nlopt_f = [](unsigned dims, const double* x, double*, void* data) {
    auto& fn = *static_cast<decltype(f)*>(data);
    return fn(std::vector<double>(x, x + dims));
  };
  phase = "base";
  res.candidates.push_back({"base", RepartitionParams{}, f(std::vector<double>(n, 0.0)), 0});
  nlopt::srand(static_cast<unsigned long>(c.seed));
  if (c.evaluations > 0) {
    phase = "global";
    nlopt::opt g(nlopt::GN_CRS2_LM, static_cast<unsigned>(n));
    g.set_lower_bounds(0.0), g.set_upper_bounds(1.0), g.set_maxeval(static_cast<int>(c.evaluations));
    g.set_min_objective(nlopt_f, &f);
    std::vector<double> x(n, 0.1);
    double v = 0;
    try {
      g.optimize(x, v);
    } catch (const nlopt::roundoff_limited&) {
    }
    res.candidates.push_back({"global", from_unit(best_x, c.free), best, 0});
  }
  if (c.polish > 0) {
    phase = "polish";
    nlopt::opt l(nlopt::LN_SBPLX, static_cast<unsigned>(n));
    l.set_lower_bounds(0.0), l.set_upper_bounds(1.0), l.set_maxeval(static_cast<int>(c.polish));
    l.set_initial_step(0.05);
    l.set_min_objective(nlopt_f, &f);
    std::vector<double> x = best_x;
    double v = 0;
    try {
      l.optimize(x, v);
    } catch (const nlopt::roundoff_limited&) {
    }
    res.candidates.push_back({"polished", from_unit(best_x, c.free), best, 0});
  }
  if (o.progress) std::fprintf(stderr, "\n");
  // The shortlist: the kShortlist best points of the search by training objective (distinct), besides the above.
  std::stable_sort(evaluated.begin(), evaluated.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  auto same = [](const RepartitionParams& a, const RepartitionParams& b) {
    for (const auto& d : repartition_params())
      if (std::fabs(a.*d.field - b.*d.field) > 1e-9 * (1 + std::fabs(b.*d.field))) return false;
    return true;
  };
  for (const auto& [v, p] : evaluated) {
    if (res.candidates.size() >= 3 + kShortlist) break;
    bool known = false;
    for (const auto& cand : res.candidates) known = known || same(cand.params, p);
    if (!known) res.candidates.push_back({"shortlist " + std::to_string(res.candidates.size() - 2), p, v, 0});
  }
  if (c.grid)  // a coarse grid over the correction and the move threshold, for validation to choose among too
    for (double g : {0.05, 0.13, 0.3, 0.5})
      for (double e : {0.0, 0.03, 0.06, 0.1})
        for (double m0 : {0.0, 0.011, 0.03}) {
          RepartitionParams p;
          p.gain = g, p.noise_floor = e, p.fixed_cost = m0;
          res.candidates.push_back(
              {"grid gain " + format_real(g) + " noise_floor " + format_real(e) + " fixed_cost " + format_real(m0), p,
               std::nan(""), 0});
        }
  for (auto& cand : res.candidates) {
    if (std::isnan(cand.train)) cand.train = train.objective(cand.params);  // the grid's; the search's are known
    cand.validation = valid.size() > 0 ? valid.objective(cand.params) : cand.train;
  }
  for (size_t i = 1; i < res.candidates.size(); ++i)
    if (res.candidates[i].validation < res.candidates[res.chosen].validation) res.chosen = i;
  log.close();
  log_file.commit();
  const auto& ch = res.candidates[res.chosen];
  std::ostringstream cands;
  for (const auto& cand : res.candidates)
    cands << cand.name << " train " << format_real(cand.train) << " validation " << format_real(cand.validation)
          << "; ";
  save_repartition_weights(o.out, ch.params,
                           {{"chosen", ch.name},
                            {"candidates", cands.str()},
                            {"git_revision", o.git_revision},
                            {"train_objective", format_real(ch.train)},
                            {"validation_objective", format_real(ch.validation)},
                            {"workloads", join(c.workloads)},
                            {"validation", join(c.validation)},
                            {"evaluations", std::to_string(res.evaluations)},
                            {"free", join(c.free)}});
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace semlb::fit
