// Controller evaluation: one (policy, ranks, seed) job -> one formatted CSV row, optional trace dump.
#include "evaluate.hpp"

#include <cstdio>
#include <filesystem>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "rollout.hpp"
#include "scenario.hpp"

namespace semlb::surrogate {
namespace {

std::string fmt(double v) { return format_real(v); }  // round-trip text (common/text_io.hpp)

void write_trace(const std::string& dir, const EvalJob& job, const RolloutResult& r) {
  std::filesystem::create_directories(dir);
  std::string text;
  for (const auto& e : r.trace) text += to_json(e).dump() + '\n';
  write_file_atomically(
      dir + "/" + job.policy + "_P" + std::to_string(job.ranks) + "_s" + std::to_string(job.seed) + ".jsonl", text);
}

}  // namespace

const std::vector<std::string>& eval_columns() {
  static const std::vector<std::string> c = {"policy",
                                             "ranks",
                                             "seed",
                                             "events",
                                             "slices",
                                             "min_width",
                                             "mean_imbalance",
                                             "migration",
                                             "mean_max_over_mean",
                                             "first_quarter_imbalance",
                                             "last_quarter_imbalance",
                                             "us_per_decision"};
  return c;
}

std::vector<std::string> run_eval_job(const EvalJob& job, const std::map<std::string, PolicyParams>& params,
                                      bool timing, const std::string& trace_dir) {
  const Scenario s = make_scenario(job.seed, job.ranks, job.scenario);
  const auto it = params.find(job.policy);
  auto policy = make_policy(job.policy, it == params.end() ? PolicyParams{} : it->second);
  const RolloutResult r = rollout(s, *policy, job.events, !trace_dir.empty());
  if (!trace_dir.empty() && !r.trace.empty()) write_trace(trace_dir, job, r);  // foresight (offline) writes none
  return {job.policy,
          std::to_string(job.ranks),
          std::to_string(job.seed),
          std::to_string(job.events),
          std::to_string(s.slices),
          std::to_string(s.min_width),
          fmt(r.mean_imbalance),
          std::to_string(r.migration),
          fmt(r.mean_max_over_mean),
          fmt(r.first_quarter_imbalance),
          fmt(r.last_quarter_imbalance),
          timing ? fmt(r.us_per_decision) : "0"};
}

std::vector<long> parse_int_list(const std::string& text, const std::string& flag) {
  std::vector<long> out;
  for (auto tok : split(text, ',')) {
    tok.erase(0, tok.find_first_not_of(' '));  // "2-4, 8": spaces after a comma are list layout
    tok.erase(tok.find_last_not_of(' ') + 1);
    const auto ends = split(tok, '-');  // values are non-negative, so '-' only separates a range
    const std::string at = flag + ": '" + tok + "': ";
    if (ends.size() > 2 || (ends.size() == 2 && (ends[0].empty() || ends[1].empty())))  // "-5", "2-", "1-2-3"
      throw InputError(at + "is not a non-negative integer or an inclusive range A-B with A <= B");
    const long a = parse_integer(ends[0], at, 0), b = ends.size() == 2 ? parse_integer(ends[1], at, 0) : a;
    if (b < a) throw InputError(at + "is not a non-negative integer or an inclusive range A-B with A <= B");
    if (b - a > 1000000) throw InputError(flag + ": range '" + tok + "' is too long");
    for (long v = a; v <= b; ++v) out.push_back(v);
  }
  return out;
}

std::map<std::string, PolicyParams> parse_policy_params(const std::vector<std::string>& options) {
  std::map<std::string, PolicyParams> out;
  for (const auto& o : options) {
    const size_t dot = o.find('.'), eq = o.find('=');
    if (dot == std::string::npos || eq == std::string::npos || dot > eq || dot == 0 || eq == dot + 1)
      throw InputError("--param: '" + o + "' is not POLICY.KEY=VALUE");
    out[o.substr(0, dot)].set(o.substr(dot + 1, eq - dot - 1), o.substr(eq + 1));
  }
  return out;
}

}  // namespace semlb::surrogate
