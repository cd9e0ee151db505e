// Subcommands of the semlb binary: each adds itself to the CLI11 app and returns its action.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace semlb::cli {

// Returns the exit code, or -1 when its subcommand was not the one given.
using Action = std::function<int()>;

Action add_surrogate(CLI::App& app);
Action add_replay(CLI::App& app);
Action add_sweep(CLI::App& app);
Action add_bench(CLI::App& app);
Action add_train(CLI::App& app);  // only when built with libtorch (SEMLB_WITH_TORCH)

// The full command line, recorded next to results.
std::string command_line();
void set_command_line(int argc, char** argv);

}  // namespace semlb::cli
