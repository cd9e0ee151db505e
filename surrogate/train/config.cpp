// Trainer configuration: one visitor lists every field once, with its range, for reading and for printing.
#include "config.hpp"

#include <yaml-cpp/yaml.h>

#include <limits>
#include <sstream>
#include <type_traits>

#include "common/errors.hpp"
#include "common/settings.hpp"
#include "common/text_io.hpp"
#include "common/yaml.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/scenario.hpp"
#include "controllers/features.hpp"

namespace semlb::train {
namespace {

constexpr long kLong = std::numeric_limits<long>::max();
constexpr double kReal = std::numeric_limits<double>::max();

// The allowed values of a real field: [min, max], an end open when min_open / max_open.
struct Range {
  double min = -kReal, max = kReal;
  bool min_open = false, max_open = false;
};
constexpr Range kAnyReal{}, kPositive{0, kReal, true}, kFraction{0, 1};

// Every field once, with its allowed values (for reading) or without (for printing); checks that involve
// two fields are in check().
template <class C, class F>
void visit(C& c, F&& f) {
  f("steps", c.steps, 0, kLong), f("batch", c.batch, 1, kLong), f("events", c.events, 1, kLong);
  f("bptt", c.bptt, 0, kLong), f("lr", c.lr, kPositive), f("lr_final_frac", c.lr_final_frac, Range{0, 1, true});
  f("clip", c.clip, kAnyReal), f("temp_start", c.temp_start, kPositive), f("temp_end", c.temp_end, kPositive);
  f("spread_weight", c.spread_weight, kAnyReal), f("migration_penalty", c.migration_penalty, kAnyReal);
  f("difficulty_floor", c.difficulty_floor, kAnyReal), f("hidden", c.hidden, 1, 1024);
  f("ds_max_frac", c.ds_max_frac, Range{0, 1, true}), f("ranks_min", c.ranks_min, 2, 64),
      f("ranks_max", c.ranks_max, 2, 64);
  f("seed", c.seed, std::numeric_limits<long>::min(), kLong), f("threads", c.threads, 1, kLong);
  f("validate_every", c.validate_every, std::numeric_limits<long>::min(), kLong);
  f("validation_seeds", c.validation_seeds), f("validation_ranks", c.validation_ranks);
  f("validation_events", c.validation_events, 1, kLong), f("checkpoint_every", c.checkpoint_every, 1, kLong);
  f("imbalance_norm", c.imbalance_norm), f("migration_norm", c.migration_norm), f("features", c.features);
  f("workloads", c.workloads), f("trace_fraction", c.trace_fraction, kFraction);
  f("front_fraction", c.front_fraction, kFraction), f("trace_coarsen_max", c.trace_coarsen_max, 1, kLong);
  f("trace_jitter_max", c.trace_jitter_max, Range{0.005, 0.3});
}

struct Read {  // reads each field from the settings, in its range; an unset field keeps its default
  const Settings& s;
  void operator()(const char* key, long& v, long min, long max) const { v = s.integer(key, v, min, max); }
  void operator()(const char* key, double& v, Range r) const {
    v = s.real(key, v, r.min, r.max, r.min_open, r.max_open);
  }
  void operator()(const char* key, std::string& v) const { v = s.text(key, v); }
};

// The checks that involve two fields, or a field's words; errors name the field's line or flag.
void check(const TrainConfig& c, const Settings& s) {
  if (c.ranks_max < c.ranks_min) s.fail("ranks_max", "must be >= ranks_min (" + std::to_string(c.ranks_min) + ")");
  if (c.imbalance_norm != "reactive" && c.imbalance_norm != "fixed")
    s.fail("imbalance_norm", "must be reactive or fixed");
  if (c.migration_norm != "slices" && c.migration_norm != "reactive")
    s.fail("migration_norm", "must be slices or reactive");
  for (long seed : surrogate::parse_int_list(c.validation_seeds, "validation_seeds"))
    if (!surrogate::kValidationSeeds.contains(seed))
      s.fail("validation_seeds", "must lie in the validation range 8000-8999");
  for (long r : surrogate::parse_int_list(c.validation_ranks, "validation_ranks"))
    if (r < 2 || r > 64) s.fail("validation_ranks", "each must be in [2, 64] (the training rank range's limits)");
  parse_feature_set(c.features, s.where("features"));
  if (c.trace_fraction != 0 && c.workloads.empty())
    s.fail("trace_fraction", "needs workloads (comma-separated workload files)");
}

}  // namespace

TrainConfig load_train_config(const std::string& path, const std::vector<std::string>& overrides) {
  const Settings s = load_flat_settings(path, "training config", overrides);
  TrainConfig c;
  visit(c, Read{s});
  s.finish("unknown training setting");
  check(c, s);
  return c;
}

std::string to_yaml(const TrainConfig& c) {
  std::ostringstream out;
  visit(c, [&](const char* name, const auto& field, auto&&...) {
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double>)
      out << name << ": " << format_real(field) << "\n";
    else
      out << name << ": " << field << "\n";
  });
  return out.str();
}

}  // namespace semlb::train
