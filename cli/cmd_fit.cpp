// `semlb fit`: fit learned_repartition's parameters offline (NLopt) on recorded workloads and synthetic scenarios.
#include <cstdio>

#include "commands.hpp"
#include "common/cleanup.hpp"
#include "common/text_io.hpp"
#include "controllers/learned_repartition.hpp"
#include "surrogate/fit/fit.hpp"

namespace semlb::cli {

Action add_fit(CLI::App& app) {
  struct Opts {
    std::string config, out, log;
    std::vector<std::string> sets;
    bool quiet = false;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("fit", "Fit the learned_repartition controller offline (NLopt) and write its weights");
  sub->add_option("--config", o->config,
                  "Fit config (YAML), e.g. surrogate/fit/learned_repartition.yaml (the shipped recipe); its workload "
                  "paths are relative to the working directory")
      ->required();
  sub->add_option("--set", o->sets, "Override KEY=VALUE (repeatable), e.g. --set evaluations=50");
  sub->add_option("--out", o->out, "Weights file to write (HDF5)")->required();
  sub->add_option("--log", o->log, "CSV of every evaluation (default: OUT with .log.csv)");
  sub->add_flag("--quiet", o->quiet, "No progress line");
  return [o, sub] {
    if (!*sub) return -1;         // not the chosen subcommand
    const SignalCleanup cleanup;  // an interrupted fit leaves no temporary file
    const auto config = fit::load_fit_config(o->config, o->sets);
    fit::FitOptions opts;
    opts.out = o->out;
    opts.log = o->log;
    opts.git_revision = SEMLB_GIT_REVISION;
    opts.progress = !o->quiet;
    const auto res = fit::run_fit(config, opts);
    for (size_t i = 0; i < res.candidates.size(); ++i) {  // the search's own and the chosen one (the log has all)
      const auto& c = res.candidates[i];
      if (i < 3 || i == res.chosen)
        std::fprintf(stderr, "fit: %-8s train %.5f validation %.5f%s\n", c.name.c_str(), c.train, c.validation,
                     i == res.chosen ? "  (chosen)" : "");
    }
    const auto& p = res.candidates[res.chosen].params;
    std::string params;
    for (const auto& d : repartition_params()) params += std::string(" ") + d.name + " " + format_real(p.*d.field);
    std::fprintf(stderr, "fit: wrote %s after %ld evaluations in %.1f s:%s\n", o->out.c_str(), res.evaluations,
                 res.seconds, params.c_str());
    return 0;
  };
}

}  // namespace semlb::cli
