// `semlb bench policies|train|engine|cells`: costs printed as tables (a decision, a training step, element
// steps, the host cell stage).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include "common/errors.hpp"

#include "commands.hpp"
#include "controllers/features.hpp"
#include "common/text_io.hpp"
#include "engine/run/bench.hpp"
#include "engine/run/driver.hpp"
#include "surrogate/evaluate.hpp"
#include "controllers/gru.hpp"
#include "surrogate/rollout.hpp"
#ifdef SEMLB_WITH_TORCH
#include "experiments/trainer_module.hpp"
#endif

namespace semlb::cli {
namespace {

int bench_policies(int ranks, int events, int repeats, uint64_t seed, const std::string& weights) {
  const auto scenario = surrogate::make_scenario(seed, ranks);
  std::string gru_file = weights;
  if (gru_file.empty()) {  // no weights given: time an untrained (zero-head) GRU of the shipped shape
    gru_file = (std::filesystem::temp_directory_path() / "semlb_bench_gru.h5").string();
    save_gru_weights(gru_file, GruWeights::random_zero_head(24, kFeatureCount, 1));
  }
  std::printf("# semlb bench policies: P=%d, %d slices, min_width %d, %d events x %d repeats (median)\n", ranks,
              scenario.slices, scenario.min_width, events, repeats);
  std::printf("%-20s %14s %16s\n", "policy", "us/decision", "decisions/s");
  for (const auto& name : policy_names()) {
    PolicyParams params;
    if (name == "gru") params.set("weights", gru_file);
    std::vector<double> us;
    for (int r = 0; r < repeats; ++r) {
      auto policy = make_policy(name, params);
      us.push_back(surrogate::rollout(scenario, *policy, events).us_per_decision);  // foresight: its offline solve
    }
    std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
    const double med = us[us.size() / 2];
    std::printf("%-20s %14.2f %16.0f\n", name.c_str(), med, med > 0 ? 1e6 / med : 0.0);
  }
  if (weights.empty()) std::filesystem::remove(gru_file);
  return 0;
}

// One row's scene: the file with the flags, the backend and the tissue size; every setting checked
// (engine::check_scene: the tissue is built and the device set up when the row runs).
engine::Scene bench_scene(const std::string& scene_file, const std::string& backend, long cells,
                          const SceneFlags& flags) {
  auto scene =
      load_scene(scene_file, flags, {{"backend", backend, "--backends"}, {"cells", std::to_string(cells), "--cells"}});
  engine::check_scene(scene);
  return scene;
}

// --backends: registered names, each once.
std::vector<std::string> bench_backends(const std::string& backends) {
  const auto known = registered("backends");
  std::vector<std::string> out;
  for (const auto& b : split(backends, ',')) {
    if (std::find(known.begin(), known.end(), b) == known.end())
      throw InputError("--backends: '" + b + "' is not a backend (known: " + registered_list("backends") + ")");
    if (std::find(out.begin(), out.end(), b) != out.end()) throw InputError("--backends: '" + b + "' is given twice");
    out.push_back(b);
  }
  return out;
}

// Prints header(), then runs `fn` on the scene with each backend and tissue size, flushing the table after each. Every
// row's scene, backend settings and tissue size are read first, so a bad one prints nothing; --platform and --device
// apply to the rows whose backend reads them (the OpenCL ones) and are refused only when no row's does.
void for_each_scene(const std::string& scene_file, const std::string& backends, const std::string& cells,
                    const SceneFlags& flags, const std::function<void()>& header,
                    const std::function<void(engine::Scene&, const std::string&)>& fn) {
  SceneFlags host = flags;  // without the device selection, for the rows whose backend has none
  host.platform.clear();
  host.device = -1;
  const bool device_flags = host.platform != flags.platform || host.device != flags.device;
  const auto names = bench_backends(backends);
  const auto counts = surrogate::parse_int_list(cells, "--cells");
  std::vector<std::pair<engine::Scene, std::string>> rows;
  bool device_used = false;
  for (const auto& backend : names)
    for (long n : counts) {
      try {
        rows.emplace_back(bench_scene(scene_file, backend, n, flags), backend);
        device_used = true;
      } catch (const InputError&) {  // a backend without a device (or a bad scene: then it fails again here)
        if (!device_flags) throw;
        rows.emplace_back(bench_scene(scene_file, backend, n, host), backend);
      }
    }
  if (device_flags && !device_used)  // no row takes --platform/--device: the first row's error says why
    bench_scene(scene_file, names.front(), counts.front(), flags);
  header();
  for (auto& [scene, backend] : rows) {
    fn(scene, backend);
    std::fflush(stdout);
  }
}

// Element-steps per second and ms per step of a scene per backend and tissue size, with the tissue's
// density and (with SEMLB_OPENCL_PROFILE=1) ms per step of each kernel. `previous`: empty, or one ms-per-step
// figure per printed row (backends x cells, in that order) of an earlier build; each row then prints
// previous / now (> 1: faster now). Throws InputError when the count or a number is wrong.
int bench_engine(const std::string& scene_file, const std::string& backends, const std::string& cells, long steps,
                 long warmup, const std::string& previous, const SceneFlags& flags) {
  for (const auto& s : flags.set)  // the steps timed are --warmup and --steps, not the scene's
    if (s.substr(0, s.find('=')) == "time.steps")
      throw InputError("--set time.steps: bench engine times --steps steps after --warmup; give those instead");
  std::vector<double> before;
  if (!previous.empty()) {
    for (const auto& f : split(previous, ',')) before.push_back(parse_real(f, "--previous: ", 1e-9));
    const size_t rows = bench_backends(backends).size() * surrogate::parse_int_list(cells, "--cells").size();
    if (before.size() != rows)
      throw InputError("--previous: " + std::to_string(before.size()) + " figures for " + std::to_string(rows) +
                       " rows (backends x cells)");
  }
  auto header = [&] {
    std::printf("# semlb bench engine: %s, %ld timed steps after %ld warm-up steps\n", scene_file.c_str(), steps,
                warmup);
    std::printf("%-16s %-9s %9s %10s %10s %14s %10s %6s %9s %8s %9s %9s %9s  %s\n", "backend", "precision", "cells",
                "elements", "seconds", "elem-steps/s", "ms/step", "skin", "builds/st", "ratio", "per_cube", "candid.",
                "neighb.", "device");
  };
  size_t row = 0;
  for_each_scene(scene_file, backends, cells, flags, header, [&](engine::Scene& scene, const std::string& backend) {
    const auto t = engine::time_scene(scene, steps, warmup);
    const auto& stats = t.stats;
    const double ms = 1e3 * t.seconds / static_cast<double>(steps);
    const std::string ratio = before.empty() ? "-" : format_real(std::round(100 * before[row] / ms) / 100);
    ++row;
    std::printf("%-16s %-9s %9ld %10ld %10.4f %14.4g %10.4f %6.2f %9.4f %8s %9.2f %9.1f %9.1f  %s\n", backend.c_str(),
                scene.backend.precision.c_str(), t.cells, t.elements, t.seconds, t.element_steps_per_second(), ms,
                t.list.skin, static_cast<double>(t.list_builds) / static_cast<double>(steps), ratio.c_str(),
                stats.per_cutoff_cube, stats.candidates, stats.neighbours, t.device.c_str());
    if (t.list.skin > 0)
      std::printf("    list: %s, %ld builds in %ld steps, at most %ld partners per element, %ld stored\n",
                  list_settings(t.list).c_str(), t.list_builds, steps, t.list.max_partners, t.list.kmax);
    for (const auto& [kernel, secs] : t.kernel_seconds)  // with SEMLB_OPENCL_PROFILE=1
      std::printf("    kernel %-20s %10.4f ms/step\n", kernel.c_str(), 1e3 * secs / steps);
  });
  return 0;
}

// Milliseconds per cell update of each part of the host cell stage, per backend and tissue size.
int bench_cells(const std::string& scene_file, const std::string& backends, const std::string& cells, long updates,
                const SceneFlags& flags) {
  auto header = [&] {
    std::printf("# semlb bench cells: %s, ms per cell update (mean of %ld, after one untimed)\n", scene_file.c_str(),
                updates);
  };
  for_each_scene(scene_file, backends, cells, flags, header, [&](engine::Scene& scene, const std::string& backend) {
    const auto t = engine::time_cell_stage(scene, updates);
    double total = 0;
    for (const auto& [part, secs] : t.parts) total += secs;
    std::printf("%s %s, %ld cells, %ld elements (%s)\n", backend.c_str(), scene.backend.precision.c_str(), t.cells,
                t.elements, t.device.c_str());
    std::printf("  %-16s %10s %7s\n", "part", "ms/update", "share");
    for (const auto& [part, secs] : t.parts)
      std::printf("  %-16s %10.2f %6.1f%%\n", part.c_str(), 1e3 * secs, 100 * secs / total);
    std::printf("  %-16s %10.2f\n", "total", 1e3 * total);
  });
  return 0;
}

#ifdef SEMLB_WITH_TORCH
int bench_train(long steps, long threads) {
  const auto& trainer = experiments::trainer();
  auto c = trainer.load_train_config(std::string(SEMLB_SOURCE_DIR) + "/surrogate/train/default.yaml",
                                     {"threads=" + std::to_string(threads)});
  trainer.time_training_steps(c, 1);  // warm-up: library start-up and first allocations are not timed
  const auto m = trainer.time_training_steps(c, steps);
  const double total = m.episodes + m.forward + m.backward + m.optimiser;
  std::printf("# semlb bench train: %ld steps of the default recipe (batch %ld x %ld events), %ld episode thread(s)\n",
              steps, c.batch, c.events, threads);
  std::printf("%-22s %12s %8s\n", "phase", "s/step", "share");
  for (const auto& [name, s] : {std::pair{"episode generation", m.episodes},
                                {"forward (soft rollout)", m.forward},
                                {"backward", m.backward},
                                {"clip + Adam", m.optimiser}})
    std::printf("%-22s %12.4f %7.1f%%\n", name, s / steps, 100 * s / total);
  std::printf("%-22s %12.4f\n", "total (sequential)", total / steps);
  std::printf("%-22s %12.4f\n", "with prefetch (est.)", std::max(m.episodes, total - m.episodes) / steps);
  return 0;
}
#endif

}  // namespace

Action add_bench(CLI::App& app) {
  struct Opts {
    std::string what, weights, scene, backends = "cpu-binned", cells = "200", previous;
    long warmup = 2;
    SceneFlags flags;
    int ranks = 16, events = 200, repeats = 5;
    long steps = 10, threads = 1;
    uint64_t seed = 9000;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("bench", "Benchmarks that print a table");
  sub->add_option("what", o->what,
                  "What to benchmark: policies, train (one training step; needs libtorch), engine (element-steps/s), "
                  "cells (the host cell stage, per part)")
      ->required()
      ->check(CLI::IsMember({"policies", "train", "engine", "cells"}));
  sub->add_option("--scene", o->scene,
                  "Scene (default: scenes/mechanics.yaml for bench engine, scenes/epidermis.yaml for bench cells)");
  sub->add_option("--backends", o->backends,
                  "Comma-separated backends (bench engine, cells): " + registered_list("backends"))
      ->capture_default_str();
  sub->add_option("--cells", o->cells, "Cell counts, e.g. 200,2000 (bench engine, cells)")->capture_default_str();
  sub->add_option("--previous", o->previous,
                  "Earlier ms/step, one per row (backends x cells, comma-separated): prints the ratio (bench engine)");
  sub->add_option("--warmup", o->warmup, "Untimed steps first (bench engine)")
      ->capture_default_str()
      ->check(strict_integer(0));
  sub->add_option("--precision", o->flags.precision, "double or float (bench engine, cells; default: the scene's)");
  sub->add_option("--platform", o->flags.platform, "OpenCL platform name substring (bench engine, cells)");
  sub->add_option("--device", o->flags.device, "OpenCL device index (bench engine, cells)")
      ->check(strict_integer(0, 1024));
  sub->add_option("--set", o->flags.set, "Scene override KEY.PATH=VALUE (bench engine, cells; repeatable)");
  sub->add_option("--steps", o->steps, "Steps to time (bench train, engine); cell updates (bench cells)")
      ->capture_default_str()
      ->check(strict_integer(1));
  sub->add_option("--threads", o->threads, "Episode-generation threads (bench train)")
      ->capture_default_str()
      ->check(strict_integer(1));
  sub->add_option("--ranks", o->ranks, "Ranks")->capture_default_str()->check(strict_integer(1, 4096));
  sub->add_option("--events", o->events, "Events per rollout")->capture_default_str()->check(strict_integer(1));
  sub->add_option("--repeats", o->repeats, "Repetitions (the median is printed)")
      ->capture_default_str()
      ->check(strict_integer(1));
  sub->add_option("--seed", o->seed, "Scenario seed")->capture_default_str()->check(strict_integer(0));
  sub->add_option("--weights", o->weights, "GRU weights (default: a random zero-head GRU of the shipped shape)");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    static const std::map<std::string, std::set<std::string>> uses = {
        // the flags each benchmark reads
        {"policies", {"ranks", "events", "repeats", "seed", "weights"}},
        {"train", {"steps", "threads"}},
        {"engine",
         {"scene", "backends", "cells", "previous", "warmup", "precision", "platform", "device", "set", "steps"}},
        {"cells", {"scene", "backends", "cells", "precision", "platform", "device", "set", "steps"}}};
    for (const CLI::Option* opt : sub->get_options())
      for (const auto& name : opt->get_lnames())
        if (opt->count() > 0 && name != "help" && !uses.at(o->what).count(name))
          throw InputError("--" + name + ": bench " + o->what + " does not use it");
    const auto scene = [&](const char* fallback) {
      return o->scene.empty() ? std::string(SEMLB_SOURCE_DIR) + fallback : o->scene;
    };
    if (o->what == "engine")
      return bench_engine(scene("/scenes/mechanics.yaml"), o->backends, o->cells, o->steps, o->warmup, o->previous,
                          o->flags);
    if (o->what == "cells")
      return bench_cells(scene("/scenes/epidermis.yaml"), o->backends, o->cells, o->steps, o->flags);
    if (o->what == "train") {
#ifdef SEMLB_WITH_TORCH
      return bench_train(o->steps, o->threads);
#else
      throw InputError("bench train: this semlb was built without libtorch");
#endif
    }
    return bench_policies(o->ranks, o->events, o->repeats, o->seed, o->weights);
  };
}

}  // namespace semlb::cli
