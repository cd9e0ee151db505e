// `semlb sim`: a scene run with snapshots, checkpoints, run.csv, status line and failure handling.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "device/backend.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

class Mpi;

struct RunConfig {
  std::string out_dir;
  std::string restart;  // a checkpoint (or any state file) to continue from; its step is kept
  bool quiet = false;
  std::string git_revision = "unknown", command_line;
  bool wait = false;  // out_dir in use by another run (common/dir_lock.hpp): wait for it instead of InputError
};

// One phase's seconds over the run: the least, mean and largest over the ranks (one device: all three the same).
struct PhaseSpread {
  std::string name;
  double min = 0, avg = 0, max = 0;
};

struct RunSummary {
  long steps = 0, cells = 0, elements = 0;
  std::string device;
  // The end-of-run breakdown `semlb sim` prints: the time-stepping loop's wall seconds (final.h5 not included), the
  // element-steps it made (elements after each stretch between stops x its steps), rank 0's seconds writing files
  // in it (run.csv rows, snapshots, checkpoints), the phase timers of run.csv per rank (decomposed: also the ghost
  // exchange and migration of the rebalancing intervals), and the neighbour list's builds summed over the ranks.
  int ranks = 1;
  double loop_seconds = 0, element_steps = 0, output_seconds = 0;
  std::vector<PhaseSpread> phases;
  std::string phases_note;  // what the phases leave out, printed under them (empty: nothing)
  ListStats list;           // the neighbour list's: its builds summed over the ranks
  // What the user waits for outside the loop: seconds from the process's start to the loop's (common/process.hpp),
  // its known parts ("load", the process up to main: dynamic libraries and static setup; "tissue", making or reading
  // the initial state; "device", the backend's setup with its program build and upload; rank 0's when decomposed),
  // and the seconds after the loop that wrote final.h5 and the closing files.
  double start_seconds = 0, closing_seconds = 0;
  std::vector<std::pair<std::string, double>> start_parts;
  bool wrote_final = true;  // final.h5 written (output.final)
};

// DIR/rank_times.csv of a decomposed run: one row per rebalancing interval and rank. Columns, written and read
// by these names in kColumns' order: the interval's last step, the rank, its computation, ghost-exchange and
// migration seconds (computation in work units under decomposition.timing: modelled), the interval's
// I_global and the slices moved at its end; then the step phases' wall seconds, the device timers' seconds (0
// without them; decomposition.timing: device), the bytes the rank sent in ghost bands and in migrating cells, and
// the device seconds' parts (Backend::device_parts): local pair forces, neighbour-list builds, cell stage.
namespace rank_times {
inline constexpr const char* kFile = "rank_times.csv";
inline constexpr const char *kStep = "step", *kRank = "rank", *kComputeS = "compute_s", *kExchangeS = "exchange_s",
                            *kMigrateS = "migrate_s", *kImbalance = "imbalance", *kMovedSlices = "moved_slices",
                            *kWallS = "wall_s", *kDeviceS = "device_s", *kExchangeBytes = "exchange_bytes",
                            *kMigrateBytes = "migrate_bytes", *kDevicePairS = "device_pair_s",
                            *kDeviceListS = "device_list_s", *kDeviceCellsS = "device_cells_s";
inline constexpr std::array<const char*, 14> kColumns = {
    kStep,  kRank,    kComputeS,      kExchangeS,    kMigrateS,    kImbalance,   kMovedSlices,
    kWallS, kDeviceS, kExchangeBytes, kMigrateBytes, kDevicePairS, kDeviceListS, kDeviceCellsS};
}  // namespace rank_times

// Output: DIR/final.h5, DIR/snapshots/step_NNNNNNNNN.h5 (the first step's included) + DIR/snapshots.xmf,
// DIR/run.csv, DIR/scene.yaml, DIR/checkpoint.h5; on a numerical failure DIR/failure.h5 (the state frozen since
// the failing step, labelled with it) and a SimulationError. Each of final, checkpoint and failure.h5 has an
// XDMF index beside it (NAME.xmf). Bad input throws
// InputError before anything is written, also a restart (or tissue.file) state at or past time.steps, which would
// run nothing. DIR is locked (DIR/.semlb.lock) while the run writes it: a second run into DIR is an InputError
// naming the first (or waits, with config.wait). A write error (a full disk) throws std::runtime_error naming the
// file; no temporary file is left and earlier files (the last checkpoint) stay whole.
// Every setting a run of SCENE reads, read and checked without building the tissue or touching a device: the tissue
// section (check_tissue), the backend's (backend_settings), the effects' (make_effects) and the decomposition's
// (Decomposition::from_scene at one rank). InputError naming the file and line, or the flag. `semlb bench` and the
// sweeps' engine runners check every row with it before the first one runs.
void check_scene(const Scene& scene);
RunSummary run_scene(Scene& scene, const RunConfig& config);
// The same across the ranks of `mpi` (docs/engine.md "Decomposition"): rank 0 writes final.h5, run.csv,
// checkpoints and snapshots (gathered, cells in id order), trace.jsonl (one line per rebalancing event, in
// `semlb replay`'s format) and rank_times.csv (rank_times::kColumns). Errors that
// all ranks agree on (bad input, a numerical failure: then failure.h5, rank 0's files) throw AgreedError on
// every rank; any other exception is this rank's alone (the caller aborts the job).
RunSummary run_scene_decomposed(Scene& scene, const RunConfig& config, Mpi& mpi);

}  // namespace semlb::engine
