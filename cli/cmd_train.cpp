// `semlb train`: train the GRU controller in the differentiable surrogate and export HDF5 weights.
#include <cstdio>

#include "commands.hpp"
#include "experiments/trainer_module.hpp"

namespace semlb::cli {

Action add_train(CLI::App& app) {
  struct Opts {
    std::string config, out, checkpoint, log;
    std::vector<std::string> sets;
    long steps = -1;
    bool quiet = false;
  };
  auto o = std::make_shared<Opts>();
  auto* sub =
      app.add_subcommand("train", "Train the GRU controller (libtorch, CPU); resumes from OUT.ckpt after a kill");
  sub->add_option("--config", o->config,
                  "Training config (YAML); default: surrogate/train/default.yaml (the v1 recipe)");
  sub->add_option("--set", o->sets, "Override KEY=VALUE (repeatable), e.g. --set batch=16");
  sub->add_option("--steps", o->steps, "Optimisation steps (0 exports the untrained, zero-head model)")
      ->check(strict_integer(0));
  sub->add_option("--out", o->out, "Weights file to write (HDF5)")->required();
  sub->add_option("--checkpoint", o->checkpoint, "Checkpoint file (default: OUT.ckpt)");
  sub->add_option("--log", o->log, "Validation log CSV (default: OUT with .log.csv)");
  sub->add_flag("--quiet", o->quiet, "No progress line");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    auto sets = o->sets;
    if (o->steps >= 0) sets.push_back("steps=" + std::to_string(o->steps));
    const auto& trainer = experiments::trainer();
    const auto config = trainer.load_train_config(o->config, sets);
    train::TrainOptions opts;
    opts.out = o->out;
    opts.checkpoint = o->checkpoint;
    opts.log = o->log;
    opts.git_revision = SEMLB_GIT_REVISION;
    opts.progress = !o->quiet;
    const auto sum = trainer.run_training(config, opts);
    std::fprintf(stderr,
                 "train: wrote %s after %ld steps in %.1f s; validation imbalance %.3f%% (reactive %.3f%%), "
                 "migration %.1f (reactive %.1f); parity error %.2e\n",
                 o->out.c_str(), sum.steps, sum.seconds, 100 * sum.val_imbalance, 100 * sum.reactive_imbalance,
                 sum.val_migration, sum.reactive_migration, sum.parity_error);
    return 0;
  };
}

}  // namespace semlb::cli
