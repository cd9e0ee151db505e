// Runners that launch `mpirun -np RANKS semlb sim` (strong_scaling, load_balance: "mpi_sim", one summary row;
// rank_balance: "mpi_intervals", one row per rebalancing interval and rank; end_to_end: "mpi_end_to_end", the
// paper's load-balance row per launch) and read its outputs; any of them can split a launch into checkpoint/restart
// segments (`segments`).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "common/cleanup.hpp"
#include "common/errors.hpp"
#include "common/process.hpp"
#include "common/text_io.hpp"
#include "engine/decomposition/decomposition.hpp"
#include "engine/effects/effect.hpp"
#include "engine/model/scene.hpp"
#include "engine/run/driver.hpp"
#include "runner.hpp"

namespace semlb::experiments {
namespace {

namespace fs = std::filesystem;

// The scene settings (engine::scene_settings()) these runners take by name.
const std::vector<std::string> kSceneNames = {"cells",   "steps",           "policy", "initial",
                                              "backend", "rebalance_every", "timing"};
// Settings of the launch, not of the scene: the sweep's launch number, how mpirun places the ranks
// (--bind-to, --map-by; "none" leaves Open MPI's default), the GPUs the launch holds (recorded), and the
// checkpoint/restart segments it runs as (launch()).
const std::vector<std::string> kLaunchNames = {"launch", "bind_to", "map_by", "gpus", "segments"};

std::string scene_path(const Job& job, const RunOptions& o) { return o.resolve(job.text("scene", "")); }

// The job's scene (job_scene with kSceneNames).
engine::Scene mpi_scene(const Job& job, const std::string& manifest, const RunOptions& o) {
  return job_scene(job, kSceneNames, manifest, o.base_dir);
}

// The row's policy (its scene.decomposition.policy, else `policy`, else the scene file's, else the engine's
// default) and where an error about it points.
std::pair<std::string, std::string> row_policy(const Job& job, const std::string& manifest, const RunOptions& o) {
  for (const char* k : {"scene.decomposition.policy", "policy"})  // scene.KEY overrides come last, so win
    if (const Setting* s = job.find(k)) return {s->value, where_of(*s, manifest, k)};
  const engine::Scene scene = mpi_scene(job, manifest, o);
  return {scene.decomposition->text("policy", engine::Decomposition{}.policy), scene.decomposition->where("policy")};
}

// The job's `segments`: how many consecutive `semlb sim` invocations one launch is split into, each resuming from
// the previous one's checkpoint (launch()); 1 when absent.
long segments_of(const Job& job, const std::string& manifest) {
  return job.integer("segments", 1, 1, 1L << 20, manifest);
}

// Refuses, before anything runs: an unknown setting, a missing scene or rank count, a value of the wrong type, an
// effect's bad parameter (in the scene or a scene.* setting), `segments` that do not divide the steps, a bad POLICY.KEY
// parameter, and a row whose policy the engine cannot run (PolicyNeeds::true_work).
void check_job(const Job& job, const std::string& manifest, const RunOptions& o) {
  std::vector<std::string> known = {"scene", "ranks"};
  known.insert(known.end(), kSceneNames.begin(), kSceneNames.end());
  known.insert(known.end(), kLaunchNames.begin(), kLaunchNames.end());
  check_settings(
      job, manifest, known, [](const std::string& k) { return k.rfind("scene.", 0) == 0 || is_policy_param(k); },
      "this runner");
  for (const char* k : {"scene", "ranks"})
    if (!job.find(k)) throw InputError(where(manifest, 0, k) + "missing");
  job.integer("ranks", 1, 1, 4096, manifest);
  job.integer("launch", 1, 1, 1000, manifest);
  job.integer("gpus", 0, 0, 4096, manifest);
  for (const char* k : {"bind_to", "map_by"})
    if (const Setting* s = job.find(k);
        s && (s->value.empty() ||
              s->value.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789:-_=") != std::string::npos))
      throw InputError(where_of(*s, manifest, k) +
                       "must be an mpirun placement word (core, numa, socket, ppr:1:numa, none)");
  if (!o.mpi_launcher.empty())
    for (const char* k : {"bind_to", "map_by"})
      if (const Setting* s = job.find(k); s && s->value != "none")
        throw InputError(where_of(*s, manifest, k) + "applies to this machine's mpirun only; the launcher '" +
                         shell_words(o.mpi_launcher) + "' places the ranks");
  scene_overrides(job, kSceneNames, manifest);        // typed values
  engine::make_effects(mpi_scene(job, manifest, o));  // the effects' parameters, now rather than in a launch mid-sweep
  if (const long segments = segments_of(job, manifest); segments > 1)
    if (const long steps = mpi_scene(job, manifest, o).steps; steps % segments != 0)
      throw InputError(where_of(*job.find("segments"), manifest, "segments") + std::to_string(segments) +
                       " segments do not divide the " + std::to_string(steps) +
                       " steps (each segment runs steps / segments)");
  check_policy_params(job, manifest);  // every policy's parameters, also of policies this row does not run
  const auto [policy, at] = row_policy(job, manifest, o);
  try {
    engine::check_engine_policy(policy);
    make_policy(policy, policy_params(job, manifest)[policy]);
  } catch (const InputError& e) {
    throw InputError(at + e.what());
  }
}

// mpirun's placement flags for the job's bind_to / map_by (none when both are absent or "none").
std::vector<std::string> placement(const Job& job) {
  std::vector<std::string> flags;
  for (const auto& [k, flag] : {std::pair{"bind_to", "--bind-to"}, {"map_by", "--map-by"}})
    if (const std::string v = job.text(k, "none"); v != "none") flags.insert(flags.end(), {flag, v});
  return flags;
}

struct Launch {
  std::string dir;     // the run's files
  double seconds = 0;  // the launch's wall seconds, start-up included (every segment's, summed)
  std::string output;  // mpirun's output (the sim's summary line; the last segment's)
};

// Runs the job under mpirun (or o.mpi_launcher) into a fresh directory; returns it and the launch's wall seconds
// (start-up included). The row's policy gets its POLICY.KEY settings as decomposition.params.KEY (other policies' are
// not passed). With `segments` N > 1 the launch is N invocations into the same directory: segment k runs to step
// k x steps/N (time.steps) with a checkpoint at its end (output.checkpoint_every = steps/N, replacing the scene's),
// and segment k > 1 resumes from it (--restart DIR/checkpoint.h5), so the balancer continues across the split and
// run.csv, rank_times.csv and trace.jsonl continue in order (docs/engine.md, "The balancer is part of the
// checkpoint"). Throws with mpirun's output on failure, naming the failed segment; also when a segment's balancer
// started afresh instead of continuing (the sim's "restart:" line).
Launch launch(const Job& job, const RunOptions& o) {
  const std::string scene = scene_path(job, o);
  const fs::path scratch = o.scratch_dir.empty() ? fs::temp_directory_path() : fs::path(o.scratch_dir);
  static std::once_flag swept;  // the folders of sweeps that died by SIGKILL, once per process
  std::call_once(swept, [&] { remove_stale_run_folders(scratch.string(), "semlb_mpi_"); });
  const fs::path dir = scratch / ("semlb_mpi_" + std::to_string(::getpid()) + "_" +
                                  std::to_string(std::hash<std::string>{}(job_key(job))));
  fs::remove_all(dir);
  register_cleanup_path(dir.string());  // removed by a signal's cleanup; finish_run or a failure removes it otherwise
  // An argument vector, started without a shell (common/process.hpp): paths reach `semlb sim` as they are.
  std::vector<std::string> argv = o.mpi_launcher;
  if (argv.empty()) {
    argv = {SEMLB_MPIEXEC, "--oversubscribe"};
    for (const auto& f : placement(job)) argv.push_back(f);
    argv.push_back("-np");
  }
  argv.insert(argv.end(), {job.text("ranks", "1"), fs::read_symlink("/proc/self/exe").string(), "sim", "--quiet",
                           "--scene", scene, "--out", dir.string(), "--set", "backend.cpu-binned.threads=1"});
  auto overrides = scene_overrides(job, kSceneNames, "");
  const std::string policy = row_policy(job, "", o).first;
  for (const auto& [k, s] : job.settings)
    if (is_policy_param(k) && k.rfind(policy + ".", 0) == 0)
      overrides.push_back("decomposition.params." + k.substr(policy.size() + 1) + "=" + s.value);
  for (const auto& o : overrides) argv.insert(argv.end(), {"--set", o});
  const long segments = segments_of(job, "");
  const long length = segments > 1 ? mpi_scene(job, "", o).steps / segments : 0;  // steps per segment
  Launch l{dir.string(), 0.0, ""};
  struct Discard {  // a launch that fails leaves no folder behind
    fs::path dir;
    bool keep = false;
    ~Discard() {
      if (keep) return;
      std::error_code ec;
      fs::remove_all(dir, ec);
      unregister_cleanup_path(dir.string());
    }
  } discard{dir};
  for (long k = 1; k <= segments; ++k) {
    std::vector<std::string> command = argv;
    if (segments > 1) {  // later --set values win (engine::parse_scene applies them in order)
      command.insert(command.end(), {"--set", "time.steps=" + std::to_string(k * length), "--set",
                                     "output.checkpoint_every=" + std::to_string(length)});
      if (k > 1) command.insert(command.end(), {"--restart", (dir / "checkpoint.h5").string()});
    }
    const auto t0 = std::chrono::steady_clock::now();
    const ProcessResult p = run_process(command, {"OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"});
    const std::string& out = p.output;
    const std::string which = segments > 1 ? " in segment " + std::to_string(k) + " of " + std::to_string(segments) +
                                                 " (steps " + std::to_string((k - 1) * length) + "-" +
                                                 std::to_string(k * length) + ")"
                                           : "";
    if (p.status != 0) throw std::runtime_error("MPI launch failed" + which + ": " + shell_words(command) + "\n" + out);
    if (const size_t at = out.find("semlb sim: restart: "); k > 1 && at != std::string::npos)
      throw std::runtime_error("MPI launch" + which + ": the balancer did not continue from the checkpoint (" +
                               out.substr(at, out.find('\n', at) - at) + "): " + shell_words(command));
    l.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    l.output = out;
  }
  discard.keep = true;
  return l;
}

// Removes the run's directory; with --keep-runs its files stay under TRACE_DIR/<its settings, scene left out;
// past 200 characters the first 180 and a hash of all>/
// (scene.yaml, run.csv, rank_times.csv, trace.jsonl, and final.h5 with `final_state`).
void finish_run(const Job& job, const RunOptions& o, const std::string& dir, bool final_state = false) {
  if (!o.trace_dir.empty()) {
    std::string label;
    for (const auto& [k, s] : job.settings)
      if (k != "scene") label += (label.empty() ? "" : "_") + k + "=" + s.value;
    std::replace(label.begin(), label.end(), '/', '-');
    if (label.size() > 200) {  // file names stop at 255 bytes: the start, then a hash of the whole
      char hash[24];
      std::snprintf(hash, sizeof hash, "_%016zx", std::hash<std::string>{}(label));
      label = label.substr(0, 180) + hash;
    }
    const fs::path to = fs::path(o.trace_dir) / label;
    fs::create_directories(to);
    for (const char* f : {"scene.yaml", "run.csv", engine::rank_times::kFile, "trace.jsonl", "final.h5"})
      if (fs::exists(fs::path(dir) / f) && (final_state || std::string(f) != "final.h5"))
        fs::copy_file(fs::path(dir) / f, to / f, fs::copy_options::overwrite_existing);
  }
  fs::remove_all(dir);
  unregister_cleanup_path(dir);
}

// What a finished launch's run.csv and rank_times.csv say: the loop's wall seconds (run.csv's log intervals
// summed), the computation seconds (per rebalancing interval the slowest rank's, summed), the mean I_global over
// the events, the slices moved, the events, and the last logged cells and elements.
struct RunTotals {
  double loop_s = 0, compute_s = 0, mean_imbalance = 0;
  long moved = 0, events = 0;
  std::string cells, elements;
};

RunTotals run_totals(const std::string& dir) {
  namespace rt = engine::rank_times;
  const std::string run_csv = dir + "/run.csv", rank_csv = dir + "/" + rt::kFile;  // written by our sim
  const auto log = csv_rows(run_csv, std::vector<std::string>{"cells", "elements", "wall_s"});
  RunTotals t;
  for (const auto& r : log) t.loop_s += parse_real(r.at("wall_s"), run_csv + ": wall_s: ");
  t.cells = log.back().at("cells");
  t.elements = log.back().at("elements");
  std::map<std::string, double> slowest;  // per interval: the slowest rank's computation time
  double imbalance = 0;
  std::set<std::string> events;
  for (const auto& r : csv_rows(rank_csv, rt::kColumns)) {
    const std::string& step = r.at(rt::kStep);
    slowest[step] = std::max(slowest[step], parse_real(r.at(rt::kComputeS), rank_csv + ": " + rt::kComputeS + ": "));
    if (events.insert(step).second) {
      imbalance += parse_real(r.at(rt::kImbalance), rank_csv + ": " + rt::kImbalance + ": ");
      t.moved += parse_integer(r.at(rt::kMovedSlices), rank_csv + ": " + rt::kMovedSlices + ": ");
    }
  }
  for (const auto& [step, seconds] : slowest) t.compute_s += seconds;
  t.events = static_cast<long>(events.size());
  t.mean_imbalance = events.empty() ? 0.0 : imbalance / static_cast<double>(events.size());
  return t;
}

class MpiSimRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {"elements", "total_s", "wall_s", "compute_s", "mean_imbalance", "migrated_slices", "events"};
  }
  bool measures_time() const override { return true; }
  int mpi_ranks(const Job& job) const override { return static_cast<int>(job.integer("ranks", 1, 1, 4096, "")); }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_job(job, manifest, o);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const Launch l = launch(job, o);
    const RunTotals t = run_totals(l.dir);
    finish_run(job, o, l.dir);
    auto fmt = [&](double v) { return format_real(o.timing ? v : 0.0); };
    return {{t.elements, fmt(l.seconds), fmt(t.loop_s), fmt(t.compute_s), format_real(t.mean_imbalance),
             std::to_string(t.moved), std::to_string(t.events)}};
  }
};

// The machine a launch ran on, without commas (a CSV cell): host, cores, rank 0's device, mpirun's placement.
std::string machine(const Job& job, const Launch& l, const RunOptions& o) {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  std::string device = "unknown device";  // from the sim's summary line "... s on DEVICE; wrote ..."
  const size_t at = l.output.rfind(" s on "), end = l.output.rfind("; wrote ");
  if (at != std::string::npos && end != std::string::npos && end > at) device = l.output.substr(at + 6, end - at - 6);
  std::string m =
      std::string(host) + " " + std::to_string(std::thread::hardware_concurrency()) + " cpus; " + device + "; " +
      (o.mpi_launcher.empty()
           ? "mpirun" + (placement(job).empty() ? std::string(" default placement") : " " + shell_words(placement(job)))
           : shell_words(o.mpi_launcher));
  std::replace(m.begin(), m.end(), ',', ';');
  std::replace(m.begin(), m.end(), '\n', ' ');
  return m;
}

// The paper's end-to-end row (results/end_to_end/load_balance.csv): one launch of one policy and initial
// partition. cells_start is the scene's tissue.cells (the generator makes exactly that many); loop_s the
// time-stepping loop; compute_s the slowest rank's computation per interval, summed; gpus as the manifest
// records it; machine as machine() above. With `segments: N` (launch() above) the row sums the segments (the
// joined run.csv and rank_times.csv). With --keep-runs the launch's final.h5 is kept too.
class MpiEndToEndRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {"policy", "initial", "launch",    "gpus",           "ranks",           "cells_start", "cells_end",
            "steps",  "loop_s",  "compute_s", "mean_imbalance", "migrated_slices", "machine"};
  }
  bool measures_time() const override { return true; }
  int mpi_ranks(const Job& job) const override { return static_cast<int>(job.integer("ranks", 1, 1, 4096, "")); }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_job(job, manifest, o);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const engine::Scene scene = mpi_scene(job, "", o);
    const Launch l = launch(job, o);
    const RunTotals t = run_totals(l.dir);
    finish_run(job, o, l.dir, true);
    auto fmt = [&](double v) { return format_real(o.timing ? v : 0.0); };
    return {{row_policy(job, "", o).first, scene.decomposition->text("initial", engine::Decomposition{}.initial),
             job.text("launch", "1"), job.text("gpus", "0"), job.text("ranks", "1"),
             std::to_string(scene.tissue->integer("cells", 0, 0, 1L << 62)), t.cells, std::to_string(scene.steps),
             fmt(t.loop_s), fmt(t.compute_s), format_real(t.mean_imbalance), std::to_string(t.moved),
             o.timing ? machine(job, l, o) : "-"}};
  }
};

class MpiIntervalsRunner final : public Runner {
 public:
  // rank_times.csv's columns of the same names (engine::rank_times), less the exchange and migration times.
  std::vector<std::string> columns() const override {
    namespace rt = engine::rank_times;
    return {rt::kStep, rt::kRank, rt::kComputeS, rt::kImbalance, rt::kMovedSlices};
  }
  bool measures_time() const override { return true; }
  int mpi_ranks(const Job& job) const override { return static_cast<int>(job.integer("ranks", 1, 1, 4096, "")); }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_job(job, manifest, o);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    namespace rt = engine::rank_times;
    const std::string dir = launch(job, o).dir;
    std::vector<std::vector<std::string>> rows;
    for (const auto& r : csv_rows(dir + "/" + rt::kFile, rt::kColumns)) {
      std::vector<std::string> row;
      for (const auto& c : columns()) row.push_back(c == rt::kComputeS && !o.timing ? "0" : r.at(c));
      rows.push_back(std::move(row));
    }
    finish_run(job, o, dir);
    return rows;
  }
};

const Registrar<RunnerInfo> sim("mpi_sim", {[] { return std::make_unique<MpiSimRunner>(); }});
const Registrar<RunnerInfo> intervals("mpi_intervals", {[] { return std::make_unique<MpiIntervalsRunner>(); }});
const Registrar<RunnerInfo> end_to_end("mpi_end_to_end", {[] { return std::make_unique<MpiEndToEndRunner>(); }});

}  // namespace
}  // namespace semlb::experiments
