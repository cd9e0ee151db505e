// Trainer configuration: one visitor lists every field once, for parsing and for printing.
#include "config.hpp"

#include <yaml-cpp/yaml.h>

#include <type_traits>
#include <sstream>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "common/yaml.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/scenario.hpp"
#include "controllers/features.hpp"

namespace semlb::train {
namespace {

template <class C, class F>
void visit(C& c, F&& f) {
  f("steps", c.steps), f("batch", c.batch), f("events", c.events), f("bptt", c.bptt), f("lr", c.lr), f("lr_final_frac", c.lr_final_frac);
  f("clip", c.clip), f("temp_start", c.temp_start), f("temp_end", c.temp_end), f("spread_weight", c.spread_weight);
  f("migration_penalty", c.migration_penalty), f("difficulty_floor", c.difficulty_floor), f("hidden", c.hidden);
  f("ds_max_frac", c.ds_max_frac), f("ranks_min", c.ranks_min), f("ranks_max", c.ranks_max), f("seed", c.seed);
  f("threads", c.threads), f("validate_every", c.validate_every), f("validation_seeds", c.validation_seeds);
  f("validation_ranks", c.validation_ranks), f("validation_events", c.validation_events);
  f("checkpoint_every", c.checkpoint_every), f("imbalance_norm", c.imbalance_norm), f("migration_norm", c.migration_norm);
  f("features", c.features), f("workloads", c.workloads), f("trace_fraction", c.trace_fraction);
  f("front_fraction", c.front_fraction), f("trace_coarsen_max", c.trace_coarsen_max);
  f("trace_jitter_max", c.trace_jitter_max);
}

void parse(const std::string& text, long& out, const std::string& at) { out = parse_integer(text, at); }
void parse(const std::string& text, double& out, const std::string& at) { out = parse_real(text, at); }
void parse(const std::string& text, std::string& out, const std::string&) { out = text; }

void set(TrainConfig& c, const std::string& key, const std::string& value, const std::string& file, long line) {
  bool found = false;
  visit(c, [&](const char* name, auto& field) {
    if (key != name) return;
    found = true;
    parse(value, field, file == "--set" ? "--set " + key + ": " : where(file, line, key));
  });
  if (!found) throw InputError(where(file, line, key) + "unknown training setting");
}

void check(const TrainConfig& c) {
  auto need = [](bool ok, const char* field, const char* what) {
    if (!ok) throw InputError(std::string("training setting '") + field + "': " + what);
  };
  need(c.steps >= 0, "steps", "must be >= 0");
  need(c.batch >= 1, "batch", "must be >= 1");
  need(c.events >= 1, "events", "must be >= 1");
  need(c.bptt >= 0, "bptt", "must be >= 0");
  need(c.lr > 0 && c.lr_final_frac > 0 && c.lr_final_frac <= 1, "lr", "need lr > 0 and 0 < lr_final_frac <= 1");
  need(c.temp_start > 0 && c.temp_end > 0, "temp_start", "temperatures must be > 0");
  need(c.hidden >= 1 && c.hidden <= 1024, "hidden", "must be in [1, 1024]");
  need(c.ds_max_frac > 0 && c.ds_max_frac <= 1, "ds_max_frac", "must be in (0, 1]");
  need(c.ranks_min >= 2 && c.ranks_max >= c.ranks_min && c.ranks_max <= 64, "ranks_min", "need 2 <= ranks_min <= ranks_max <= 64");
  need(c.threads >= 1, "threads", "must be >= 1");
  need(c.checkpoint_every >= 1, "checkpoint_every", "must be >= 1");
  need(c.imbalance_norm == "reactive" || c.imbalance_norm == "fixed", "imbalance_norm", "must be reactive or fixed");
  need(c.migration_norm == "slices" || c.migration_norm == "reactive", "migration_norm", "must be slices or reactive");
  for (long s : surrogate::parse_int_list(c.validation_seeds, "validation_seeds"))
    need(surrogate::kValidationSeeds.contains(s), "validation_seeds", "must lie in the validation range 8000-8999");
  for (long r : surrogate::parse_int_list(c.validation_ranks, "validation_ranks"))
    need(r >= 2 && r <= 64, "validation_ranks", "each must be in [2, 64] (the training rank range's limits)");
  need(c.validation_events >= 1, "validation_events", "must be >= 1");
  parse_feature_set(c.features, "training setting 'features': ");
  need(c.trace_fraction >= 0 && c.trace_fraction <= 1, "trace_fraction", "must be in [0, 1]");
  need(c.front_fraction >= 0 && c.front_fraction <= 1, "front_fraction", "must be in [0, 1]");
  need(c.trace_coarsen_max >= 1, "trace_coarsen_max", "must be >= 1");
  need(c.trace_jitter_max >= 0.005 && c.trace_jitter_max <= 0.3, "trace_jitter_max", "must be in [0.005, 0.3]");
  need(c.trace_fraction == 0 || !c.workloads.empty(), "trace_fraction", "needs workloads (comma-separated workload files)");
}

}  // namespace

TrainConfig load_train_config(const std::string& path, const std::vector<std::string>& overrides) {
  TrainConfig c;
  if (!path.empty()) {
    const YAML::Node root = load_yaml_file(path, "training config");
    if (root && !root.IsNull()) {
      if (!root.IsMap()) throw InputError(path + ": a training config must be a YAML mapping");
      for (const auto& kv : root) {
        if (!kv.second.IsScalar()) throw InputError(where(path, kv.second.Mark().line + 1, kv.first.Scalar()) + "must be a single value");
        set(c, kv.first.Scalar(), kv.second.Scalar(), path, kv.first.Mark().line + 1);
      }
    }
  }
  for (const auto& o : overrides) {
    const size_t eq = o.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set: '" + o + "' is not KEY=VALUE");
    set(c, o.substr(0, eq), o.substr(eq + 1), "--set", 0);
  }
  check(c);
  return c;
}

std::string to_yaml(const TrainConfig& c) {
  std::ostringstream out;
  visit(c, [&](const char* name, const auto& field) {
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double>) out << name << ": " << format_real(field) << "\n";
    else out << name << ": " << field << "\n";
  });
  return out.str();
}

}  // namespace semlb::train
