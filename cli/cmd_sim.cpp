// `semlb sim`: run a scene (snapshots, checkpoints, run.csv) on one backend.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "common/cleanup.hpp"
#include "common/errors.hpp"
#include "common/process.hpp"
#include "common/text_io.hpp"
#include "engine/decomposition/distributed.hpp"
#include "engine/run/driver.hpp"
#include "engine/decomposition/mpi.hpp"
#include "engine/backends/opencl.hpp"
#include "engine/simulation/simulation.hpp"

namespace semlb::cli {

// --backend/--precision/--platform/--device/--steps/--seed and `more` (e.g. bench's --cells) after the --set ones
// (commands.hpp); each flag is named after its scene setting (engine::scene_settings()).
SceneOverrides scene_overrides(const SceneFlags& f, const std::vector<std::array<std::string, 3>>& more) {
  SceneOverrides o{f.set, std::vector<std::string>(f.set.size())};
  auto number = [](long v) { return v >= 0 ? std::to_string(v) : std::string(); };  // -1: not given
  std::vector<std::array<std::string, 3>> flags = {
      {"backend", f.backend, "--backend"},    {"precision", f.precision, "--precision"},
      {"platform", f.platform, "--platform"}, {"device", number(f.device), "--device"},
      {"steps", number(f.steps), "--steps"},  {"seed", number(f.seed), "--seed"}};
  flags.insert(flags.end(), more.begin(), more.end());
  for (const auto& [name, value, flag] : flags)
    if (!value.empty()) {
      // after the --sets: load_scene refuses a flag whose setting a --set gives too
      o.assignments.push_back(engine::scene_override(name, value, flag + ": "));
      o.flags.push_back(flag);
    }
  return o;
}

std::string list_settings(const engine::ListStats& list) {
  char skin[32];
  std::snprintf(skin, sizeof skin, "%g", list.skin);
  return "skin " + std::string(skin) + " um" + (list.newton ? " (half: newton)" : "") +
         (list.bin_divisions > 1 ? ", bins of (cutoff + skin) / " + std::to_string(list.bin_divisions) : "");
}

engine::Scene load_scene(const std::string& file, const SceneFlags& flags,
                         const std::vector<std::array<std::string, 3>>& more) {
  const auto o = scene_overrides(flags, more);
  return engine::load_scene(file, o.assignments, o.flags);
}

void add_scene_flags(CLI::App* sub, SceneFlags& f) {
  sub->add_option("--backend", f.backend, "Backend: " + registered_list("backends") + " (default: the scene's)");
  sub->add_option("--precision", f.precision, "double or float (default: the scene's)");
  sub->add_option("--platform", f.platform, "OpenCL platform name substring, e.g. NVIDIA or Portable");
  sub->add_option("--device", f.device, "OpenCL device index within the platform")->check(strict_integer(0, 1024));
  sub->add_option("--set", f.set,
                  "Scene override KEY.PATH=VALUE, e.g. tissue.cells=2000 (repeatable); effects: " +
                      registered_list("effects") + "; cell types: " + registered_list("cell-types"));
}

namespace {
// The loop's part of the breakdown: loop time, rates and the phase table (LAMMPS's end of run), through `line`.
template <class Line>
void loop_table(const engine::RunSummary& sum, Line& line, std::string& text) {
  line("Loop time of %.4g s on %d rank%s for %ld steps with %ld elements at the end\n", sum.loop_seconds, sum.ranks,
       sum.ranks == 1 ? "" : "s", sum.steps, sum.elements);
  line("Performance: %.4g element-steps/s, %.4g ms/step\n", sum.element_steps / sum.loop_seconds,
       1000.0 * sum.loop_seconds / static_cast<double>(sum.steps));
  line("%-10s | %10s | %10s | %10s | %6s | %11s\n", "phase", "min (s)", "avg (s)", "max (s)", "%loop", "imbalance %");
  double accounted = sum.output_seconds;
  for (const auto& p : sum.phases) {
    line("%-10s | %10.4g | %10.4g | %10.4g | %6.1f | %11.1f\n", p.name.c_str(), p.min, p.avg, p.max,
         100.0 * p.avg / sum.loop_seconds, p.avg > 0 ? 100.0 * (p.max - p.min) / p.avg : 0.0);
    accounted += p.avg;
  }
  line("%-10s | %10s | %10.4g | %10s | %6.1f | %11s\n", "output", "", sum.output_seconds, "",
       100.0 * sum.output_seconds / sum.loop_seconds, "(rank 0)");
  line("%-10s | %10s | %10.4g | %10s | %6.1f | %11s\n", "other", "", std::max(0.0, sum.loop_seconds - accounted), "",
       100.0 * std::max(0.0, sum.loop_seconds - accounted) / sum.loop_seconds, "");
  if (!sum.phases_note.empty()) text += "(" + sum.phases_note + ")\n";
}

// The seconds from the loop's end to `process` (the process's seconds so far): 0 rather than the few ms below it that
// the start's clock-tick resolution (/proc, 10 ms) can give.
double end_seconds(const engine::RunSummary& sum, double process) {
  return std::max(0.0, process - sum.start_seconds - sum.loop_seconds);
}

// The end-of-run breakdown, as LAMMPS ends a run: the loop time, element-steps per second, and per phase its seconds
// (min / avg / max over the ranks), its share of the loop (of the average) and its imbalance (max - min) / avg; then
// what the user waited for outside the loop: the start (process start to the first step) and the end, of `process`
// seconds in all.
std::string breakdown(const engine::RunSummary& sum, double process) {
  std::string text;
  auto line = [&](const char* fmt, auto... a) {
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, a...);
    text += buf;
  };
  if (sum.steps > 0 && sum.loop_seconds > 0) loop_table(sum, line, text);
  line("Start %.3g s", sum.start_seconds);
  for (size_t k = 0; k < sum.start_parts.size(); ++k)
    line("%s%s %.3g s", k == 0 ? " (" : ", ", sum.start_parts[k].first.c_str(), sum.start_parts[k].second);
  line("%s; end %.3g s (%s the closing files %.3g s); process %.4g s\n", sum.start_parts.empty() ? "" : ")",
       end_seconds(sum, process), sum.wrote_final ? "final.h5 and" : "no final.h5:", sum.closing_seconds, process);
  if (sum.list.skin > 0)
    line("Neighbour list: %s, %ld builds over the ranks (in the force phases)\n", list_settings(sum.list).c_str(),
         sum.list.builds);
  return text;
}

// OUT/log.txt: the command line and TEXT, after the log already there when APPEND (a run continued by --restart into
// its own folder, as run.csv continues). A log that cannot be written is a warning: the run's results are in place.
void write_log(const std::string& out, bool append, const std::string& text) {
  try {
    const std::string path = out + "/log.txt";
    const std::string before = append && std::filesystem::exists(path) ? read_file(path) : "";
    write_file_atomically(path, before + "# " + command_line() + "\n" + text);
  } catch (const std::exception& e) {
    std::cerr << "semlb sim: warning: no log.txt: " << e.what() << "\n";
  }
}

// The breakdown (not with --quiet) and the last line, the process's seconds so far and its start, loop and end, on
// stderr; both in OUT/log.txt (write_log), also with --quiet (as LAMMPS's log.lammps ends a run).
void report(const engine::RunSummary& sum, const std::string& out, bool quiet, bool restarted) {
  const double process = process_seconds();
  const std::string text = breakdown(sum, process);
  char times[160];
  std::snprintf(times, sizeof times, "%.4g s (start %.3g s, loop %.4g s, end %.3g s)", process, sum.start_seconds,
                sum.loop_seconds, end_seconds(sum, process));
  const std::string last = "semlb sim: " + std::to_string(sum.steps) + " steps, " + std::to_string(sum.cells) +
                           " cells, " + std::to_string(sum.elements) + " elements in " + times + " on " + sum.device +
                           (sum.wrote_final ? "; wrote " + out + "/final.h5" : "; output.final: false") + "\n";
  std::cerr << (quiet ? "" : text) << last;
  write_log(out, restarted, text + last);
}
}  // namespace

Action add_sim(CLI::App& app) {
  struct Opts {
    std::string scene, out, restart;
    SceneFlags flags;
    bool quiet = false, list = false, wait = false;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("sim", "Run a scene: DIR/final.h5, snapshots + XDMF, run.csv, checkpoint.h5");
  sub->add_option("--scene", o->scene, "Scene file (YAML), e.g. scenes/epidermis.yaml");
  sub->add_option("--out", o->out, "Output directory");
  sub->add_option("--steps", o->flags.steps, "Final step number (default: the scene's time.steps)")
      ->check(strict_integer(0, 1L << 40));
  sub->add_option("--seed", o->flags.seed, "Random seed (default: the scene's)")->check(strict_integer(0, 1L << 53));
  sub->add_option("--restart", o->restart, "Continue from a checkpoint (DIR/checkpoint.h5): bit-for-bit");
  add_scene_flags(sub, o->flags);
  sub->add_flag("--quiet", o->quiet, "No status line and no end-of-run breakdown (the last line stays)");
  sub->add_flag("--wait", o->wait, "When another run is writing --out, wait for it (default: exit 2 naming it)");
  sub->add_flag("--list-devices", o->list, "List OpenCL platforms and devices and exit");
  return [o, sub] {
    if (!*sub) return -1;
    if (o->list) {
      for (const auto& d : engine::cl::list_devices())
        std::cout << d.platform_name << ": " << d.device_name << (d.gpu ? " (GPU)" : "") << "\n";
      return 0;
    }
    if (o->scene.empty() || o->out.empty()) throw InputError("sim: --scene and --out are required");
    std::unique_ptr<engine::Mpi> mpi;  // under mpirun: decomposed across the ranks
    if (engine::Mpi::launched()) mpi = std::make_unique<engine::Mpi>();
    // output.workload records rebalancing events: one device then runs as a decomposition of one rank
    if (!mpi && load_scene(o->scene, o->flags).record_workload) mpi = std::make_unique<engine::Mpi>();
    if (!mpi) {
      // On one device a SIGINT, SIGTERM or SIGHUP removes the --out folder's lock on the way out (common/cleanup.hpp),
      // before the backend starts its threads (they inherit the blocked signals).
      const SignalCleanup cleanup;
      auto scene = load_scene(o->scene, o->flags);
      engine::RunConfig rc{o->out, o->restart, o->quiet, SEMLB_GIT_REVISION, command_line()};
      rc.wait = o->wait;
      try {
        const auto sum = engine::run_scene(scene, rc);
        report(sum, o->out, o->quiet, !o->restart.empty());
      } catch (const engine::SimulationError& e) {
        const std::string line =
            "semlb sim: " + o->scene + ": " + e.what() + " (state written to " + o->out + "/failure.h5)\n";
        std::cerr << line;
        write_log(o->out, !o->restart.empty(), line);
        return 1;
      }
      return 0;
    }
    // Decomposed: every error reaches every rank (docs/engine.md "Failures"). Errors all ranks agreed on end
    // the job normally, reported once by rank 0; any other is this rank's alone: name it, abort the job.
    try {
      engine::Scene scene;
      engine::agree(*mpi, [&] { scene = load_scene(o->scene, o->flags); });
      engine::RunConfig rc{o->out, o->restart, o->quiet, SEMLB_GIT_REVISION, command_line()};
      rc.wait = o->wait;
      const auto sum = engine::run_scene_decomposed(scene, rc, *mpi);
      if (mpi->rank() == 0) report(sum, o->out, o->quiet, !o->restart.empty());
    } catch (const engine::AgreedError& e) {
      if (mpi->rank() == 0) {
        const std::string line = "semlb sim: " + (e.code == 2 ? "" : o->scene + ": ") + e.what() +
                                 (e.failed_step >= 0 ? " (state written to " + o->out + "/failure.h5)" : "") + "\n";
        std::cerr << line << std::flush;
        if (e.failed_step >= 0) write_log(o->out, !o->restart.empty(), line);  // bad input writes nothing
      }
      return e.code;
    } catch (const std::exception& e) {
      // One write(2) for the whole line: unbuffered stderr would send it in pieces, and mpirun's abort notice
      // could land between them.
      const std::string line = "semlb sim: rank " + std::to_string(mpi->rank()) + ": " + e.what() + "\n";
      std::fwrite(line.data(), 1, line.size(), stderr);
      std::fflush(stderr);
      if (mpi->size() == 1) return dynamic_cast<const InputError*>(&e) ? 2 : 1;
      mpi->abort(dynamic_cast<const InputError*>(&e) ? 2 : 1);
    }
    return 0;
  };
}

}  // namespace semlb::cli
