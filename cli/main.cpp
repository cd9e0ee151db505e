// semlb: one binary, CLI11 subcommands. Exit codes: 0 ok, 1 runtime failure, 2 bad input.
#include <climits>
#include <iostream>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "commands.hpp"
#include "common/errors.hpp"
#include "common/process.hpp"
#include "common/text_io.hpp"
#include "common/version.hpp"

namespace semlb::cli {
namespace {
std::string g_command_line;
}
std::string command_line() { return g_command_line; }

CLI::Validator strict_integer(long min, long max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        try {
          parse_integer(text, "", min, max);
          return "";
        } catch (const InputError& e) {
          return e.what();
        }
      },
      "INT", "strict_integer");
}
void set_command_line(int argc, char** argv) {  // quoted for /bin/sh where a word needs it: provenance a shell reruns
  g_command_line = semlb::shell_words(std::vector<std::string>(argv, argv + argc));
}

// The cell stage frees and allocates arrays of 1e7 elements (positions, keys, staging) at every cell
// update. Served from the heap instead of fresh mmap()s, they skip ~1e5 page faults each time: the cell
// stage at 6.6e6 elements went from 788 to 330-345 ms (semlb bench cells, PoCL). Freed memory stays mapped.
void keep_large_allocations_on_the_heap() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}
}  // namespace semlb::cli

int main(int argc, char** argv) {
  semlb::mark_main_started();
  using namespace semlb::cli;
  keep_large_allocations_on_the_heap();
  set_command_line(argc, argv);
  CLI::App app{"semlb: multi-GPU subcellular-element simulation with learned load balancing"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "semlb " + semlb::version_string(),
                       "Print the version and git revision, then exit");
  std::vector<Action> actions = {add_surrogate(app), add_replay(app), add_sweep(app),
                                 add_bench(app),     add_sim(app),    add_list(app)};
#ifdef SEMLB_WITH_TORCH
  actions.push_back(add_train(app));
#endif
#ifdef SEMLB_WITH_FIT
  actions.push_back(add_fit(app));
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string known;
    bool is_known = false;
    for (const auto* s : app.get_subcommands([](CLI::App*) { return true; })) {
      known += (known.empty() ? "" : ", ") + s->get_name();
      is_known = is_known || (argc > 1 && s->get_name() == argv[1]);
    }
    if (argc > 1 && argv[1][0] != '-' && !is_known)
      std::cerr << "semlb: unknown subcommand '" << argv[1] << "' (known: " << known << ")\n";
    else
      std::cerr << "semlb: " << e.what() << " (see semlb --help)\n";
    return 2;
  }
  try {
    for (const auto& action : actions)
      if (const int rc = action(); rc >= 0) return rc;
  } catch (const semlb::InputError& e) {
    std::cerr << "semlb: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "semlb: error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
