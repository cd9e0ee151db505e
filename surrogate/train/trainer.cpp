// Training loop.
#include "trainer.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <numbers>
#include <sstream>

#include "common/errors.hpp"
#include "controllers/features.hpp"
#include "controllers/gru.hpp"
#include "common/h5.hpp"
#include "controllers/reactive.hpp"
#include "common/progress_line.hpp"
#include "common/text_io.hpp"
#include "episodes.hpp"
#include "model.hpp"
#include "soft_rollout.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/rollout.hpp"

namespace semlb::train {
namespace fs = std::filesystem;
namespace {

struct Validation {
  double imbalance = 0, migration = 0;
};

// Mean over the validation (seed, ranks) grid of hard rollouts; `weights` null = the reactive rule.
Validation validate(const TrainConfig& c, const GruWeights* weights) {
  Validation v;
  long n = 0;
  for (long seed : surrogate::parse_int_list(c.validation_seeds, "validation_seeds"))
    for (long ranks : surrogate::parse_int_list(c.validation_ranks, "validation_ranks")) {
      const auto s = surrogate::make_scenario(static_cast<uint64_t>(seed), static_cast<int>(ranks));
      auto policy = weights ? make_gru_policy(*weights, ReactiveParams{}) : make_policy("reactive");
      const auto r = surrogate::rollout(s, *policy, static_cast<int>(c.validation_events));
      v.imbalance += r.mean_imbalance;
      v.migration += r.migration;
      ++n;
    }
  v.imbalance /= n;
  v.migration /= n;
  return v;
}

double learning_rate(const TrainConfig& c, long step) {
  const double progress = c.steps > 0 ? static_cast<double>(step) / c.steps : 1.0;
  const double floor = c.lr * c.lr_final_frac;
  return floor + (c.lr - floor) * 0.5 * (1.0 + std::cos(std::numbers::pi * progress));
}

double temperature(const TrainConfig& c, long step) {
  const double progress = c.steps > 1 ? static_cast<double>(step) / (c.steps - 1) : 1.0;
  return c.temp_start + (c.temp_end - c.temp_start) * progress;
}

void save_checkpoint(const std::string& path, Controller& model, torch::optim::Adam& opt, long step,
                     const std::string& config) {
  torch::serialize::OutputArchive root, m, o;
  model->save(m);
  opt.save(o);
  root.write("model", m);
  root.write("optimizer", o);
  root.write("step", torch::tensor(static_cast<int64_t>(step)));
  root.write("config", torch::tensor(static_cast<int64_t>(std::hash<std::string>{}(config))));
  PendingFile pending(path);  // a failed or interrupted save leaves the last checkpoint as it was
  root.save_to(pending.tmp());
  pending.commit();
}

long load_checkpoint(const std::string& path, Controller& model, torch::optim::Adam& opt, const std::string& config) {
  torch::serialize::InputArchive root, m, o;
  try {
    root.load_from(path);
  } catch (const std::exception&) {
    throw InputError(path + ": not a readable training checkpoint (remove it to start afresh)");
  }
  torch::Tensor step, hash;
  root.read("step", step);
  root.read("config", hash);
  if (hash.item<int64_t>() != static_cast<int64_t>(std::hash<std::string>{}(config)))
    throw InputError(path + ": checkpoint was written with a different training config (remove it to start afresh)");
  root.read("model", m);
  root.read("optimizer", o);
  model->load(m);
  opt.load(o);
  return step.item<int64_t>();
}

// Validation log: rows with step <= `keep_through` survive a resume, so no row is duplicated.
void start_log(const std::string& path, long keep_through) {
  std::string kept =
      "step,wall_seconds,loss,lr,temperature,val_imbalance,val_migration,reactive_imbalance,reactive_migration\n";
  if (keep_through >= 0 && fs::exists(path)) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line))
      if (std::atol(line.c_str()) <= keep_through) kept += line + "\n";
  }
  write_file_atomically(path, kept);
}

void write_weights(const std::string& out, Controller& model, const TrainConfig& c, long steps,
                   const std::string& git_revision) {
  const auto w = export_weights(model, c.ds_max_frac, parse_feature_set(c.features, ""));
  const Parity p = record_parity(model, 16, 3, static_cast<uint64_t>(c.seed));
  save_gru_weights(out, w, [&](h5::File& f) {
    f.write_attr("trainer", std::string("semlb train (libtorch " TORCH_VERSION ")"));
    f.write_attr("git_revision", git_revision);
    f.write_attr("steps", steps);
    f.write_attr("training_seeds", std::string("0-7999"));
    f.write_attr("validation_seeds", c.validation_seeds);
    f.write_attr("config", to_yaml(c));
    f.write("/parity/inputs",
            {static_cast<hsize_t>(p.shape[0]), static_cast<hsize_t>(p.shape[1]), static_cast<hsize_t>(p.shape[2])},
            p.inputs);
    f.write("/parity/residuals", {static_cast<hsize_t>(p.shape[0]), static_cast<hsize_t>(p.shape[1])}, p.residuals);
  });
}

long kill_after_step() {  // test hook: SEMLB_TRAIN_KILL_AFTER=N sends SIGKILL after checkpointing step N
  const char* v = std::getenv("SEMLB_TRAIN_KILL_AFTER");
  return v ? std::atol(v) : -1;
}

}  // namespace

StepTiming time_training_steps(const TrainConfig& c, long steps) {
  torch::manual_seed(static_cast<uint64_t>(c.seed));
  torch::set_num_threads(1);
  Controller model(kFeatureCount, c.hidden);
  torch::optim::Adam opt(model->parameters(), torch::optim::AdamOptions(c.lr));
  StepTiming t;
  const auto workloads = load_training_workloads(c);
  auto clock = [] { return std::chrono::steady_clock::now(); };
  auto since = [](auto a) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count(); };
  for (long step = 0; step < steps; ++step) {
    auto a = clock();
    const auto batch = make_batch(c, step, workloads);
    t.episodes += since(a);
    a = clock();
    auto loss = soft_rollout_loss(model, batch, c, temperature(c, step));
    t.forward += since(a);
    a = clock();
    opt.zero_grad();
    loss.backward();
    t.backward += since(a);
    a = clock();
    torch::nn::utils::clip_grad_norm_(model->parameters(), c.clip);
    opt.step();
    t.optimiser += since(a);
  }
  return t;
}

TrainSummary run_training(const TrainConfig& c, const TrainOptions& o) {
  if (o.out.empty()) throw InputError("--out: a weights file is required");
  const std::string ckpt = o.checkpoint.empty() ? o.out + ".ckpt" : o.checkpoint;
  const std::string log = o.log.empty() ? fs::path(o.out).replace_extension(".log.csv").string() : o.log;
  const std::string config = to_yaml(c);
  torch::manual_seed(static_cast<uint64_t>(c.seed));
  torch::set_num_threads(1);  // tiny tensors: threading costs more than it gains; the other cores make episodes
  Controller model(kFeatureCount, c.hidden);
  torch::optim::Adam opt(model->parameters(), torch::optim::AdamOptions(c.lr));
  const auto workloads = load_training_workloads(c);  // read once, shared by every batch
  long step = 0;
  ProgressLine progress(o.progress);
  if (fs::exists(ckpt)) {
    step = load_checkpoint(ckpt, model, opt, config);
    progress.note(format_text("train: resuming from %s at step %ld", ckpt.c_str(), step));
  }
  start_log(log, fs::exists(ckpt) ? step : -1);
  const Validation reactive = validate(c, nullptr);
  const long kill_after = kill_after_step();
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const long first = step;
  double last_loss = NAN;

  auto log_validation = [&](long at) {
    const GruWeights current = export_weights(model, c.ds_max_frac, parse_feature_set(c.features, ""));
    const Validation v = validate(c, &current);
    const long trained = std::max(0L, at - 1);  // the log names the last step's learning rate and temperature
    std::ofstream(log, std::ios::app) << at << "," << format_real(seconds()) << "," << format_real(last_loss) << ","
                                      << format_real(learning_rate(c, trained)) << ","
                                      << format_real(temperature(c, trained)) << "," << format_real(v.imbalance) << ","
                                      << format_real(v.migration) << "," << format_real(reactive.imbalance) << ","
                                      << format_real(reactive.migration) << "\n";
    progress.note(
        format_text("train: step %ld validation: imbalance %.3f%% (reactive %.3f%%), migration %.1f (reactive %.1f)",
                    at, 100 * v.imbalance, 100 * reactive.imbalance, v.migration, reactive.migration));
    return v;
  };

  // The next batch is generated while this one trains (episodes depend only on (seed, step, index)).
  auto prefetch = [&](long s) {
    return std::async(std::launch::async, [&c, &workloads, s] { return make_batch(c, s, workloads); });
  };
  auto next_batch = prefetch(step);
  for (; step < c.steps; ++step) {
    for (auto& group : opt.param_groups())
      static_cast<torch::optim::AdamOptions&>(group.options()).lr(learning_rate(c, step));
    const std::vector<Episode> batch = next_batch.get();
    if (step + 1 < c.steps) next_batch = prefetch(step + 1);
    SoftStats stats;
    auto loss = soft_rollout_loss(model, batch, c, temperature(c, step), &stats);
    last_loss = loss.item<double>();
    if (!std::isfinite(last_loss))
      throw std::runtime_error("train: step " + std::to_string(step) + ": loss is not finite (soft imbalance " +
                               std::to_string(stats.imbalance) + ")");
    opt.zero_grad();
    loss.backward();
    torch::nn::utils::clip_grad_norm_(model->parameters(), c.clip);
    opt.step();
    const long done = step + 1;
    if (progress.on() && (done % 10 == 0 || done == c.steps)) {
      const double s = seconds(),
                   eta = eta_seconds(s, static_cast<double>(done - first), static_cast<double>(c.steps - done));
      progress.show(format_text(
          "train: step %ld/%ld  loss %.4f  soft imbalance %.2f%%  migration %.1f  lr %.2e  T %.2f  %.0f s  ETA %.0f s",
          done, c.steps, last_loss, 100 * stats.imbalance, stats.migration, learning_rate(c, step),
          temperature(c, step), s, eta));
    }
    if (c.validate_every > 0 && done % c.validate_every == 0 && done < c.steps) log_validation(done);
    if (done % c.checkpoint_every == 0 && done < c.steps) {
      save_checkpoint(ckpt, model, opt, done, config);
      if (kill_after >= 0 && done >= kill_after) std::raise(SIGKILL);
    }
  }
  const Validation final = log_validation(c.steps);
  write_weights(o.out, model, c, c.steps, o.git_revision);
  TrainSummary sum;
  sum.parity_error = gru_parity_error(o.out);
  if (!(sum.parity_error < 1e-5)) {
    fs::remove(o.out);
    throw std::runtime_error("train: exported weights fail parity (max error " + std::to_string(sum.parity_error) +
                             ")");
  }
  fs::remove(ckpt);
  sum.steps = c.steps;
  sum.seconds = seconds();
  sum.val_imbalance = final.imbalance;
  sum.val_migration = final.migration;
  sum.reactive_imbalance = reactive.imbalance;
  sum.reactive_migration = reactive.migration;
  return sum;
}

}  // namespace semlb::train

extern "C" const semlb::train::Entry* semlb_train_entry() {
  static const semlb::train::Entry entry{&semlb::train::load_train_config, &semlb::train::to_yaml,
                                         &semlb::train::run_training, &semlb::train::time_training_steps};
  return &entry;
}
