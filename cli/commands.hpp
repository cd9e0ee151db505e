// Subcommands of the semlb binary: each adds itself to the CLI11 app and returns its action.
#pragma once
#include <CLI/CLI.hpp>

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace semlb::engine {
struct Scene;
struct ListStats;
}  // namespace semlb::engine

namespace semlb::cli {

// Returns the exit code, or -1 when its subcommand was not the one given.
using Action = std::function<int()>;

Action add_surrogate(CLI::App& app);
Action add_replay(CLI::App& app);
Action add_sweep(CLI::App& app);
Action add_bench(CLI::App& app);
Action add_train(CLI::App& app);
Action add_fit(CLI::App& app);
Action add_sim(CLI::App& app);
Action add_list(CLI::App& app);

// The names a registry holds (any kind of the catalogue common/registry.hpp listed_kinds, e.g. policies, backends,
// pair-terms, or "kinds" for the kinds themselves), as `semlb list WHAT` prints them, and as "a, b, c" for --help
// texts; std::logic_error for another WHAT.
std::vector<std::string> registered(const std::string& what);
std::string registered_list(const std::string& what);

// Flags shared by the subcommands that run scenes (sim, bench engine); -1/empty = the scene's value.
struct SceneFlags {
  std::string backend, precision, platform;
  int device = -1;
  long steps = -1, seed = -1;
  std::vector<std::string> set;
};
void add_scene_flags(CLI::App* sub, SceneFlags& flags);
// Scene overrides (engine::load_scene's KEY=VALUE and the flag each came from, "" for a --set).
struct SceneOverrides {
  std::vector<std::string> assignments, flags;
};
// The --set ones, then the flags', with `more` ({setting of engine::scene_settings, value or "" when not given, the
// flag's name}); engine::load_scene refuses a flag whose setting a --set gives too.
SceneOverrides scene_overrides(const SceneFlags& flags, const std::vector<std::array<std::string, 3>>& more = {});
// "skin 0.5 um (half: newton), bins of (cutoff + skin) / 2": the neighbour list's settings, as sim and bench print
// them.
std::string list_settings(const engine::ListStats& list);
// FILE loaded with scene_overrides(flags, more): engine::load_scene, its errors naming the flag or --set at fault.
engine::Scene load_scene(const std::string& file, const SceneFlags& flags,
                         const std::vector<std::array<std::string, 3>>& more = {});

// CLI11 check for an integer option: the whole argument is an integer in [min, max], read by the one strict
// parser (common/text_io.hpp: no hex, no '+', no trailing text); the message names the value and the range.
CLI::Validator strict_integer(long min, long max = std::numeric_limits<long>::max());

// The full command line, recorded next to results.
std::string command_line();
void set_command_line(int argc, char** argv);

}  // namespace semlb::cli
