// The decomposed run (paper Sec. III-D/E, IV): slabs of slices along x, one rank per slab range, ghost
// exchange with the two neighbouring ranks, whole cells owned by the rank of their centroid's slice,
// workload-aware initial partition and rebalancing through the shared controllers.
#pragma once
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "controllers/balancer.hpp"
#include "io.hpp"
#include "mpi.hpp"
#include "simulation.hpp"

namespace semlb::engine {

// An error that every rank of a decomposed run throws at the same point with the same message (a verdict
// reached collectively), so that the job can end normally with exit code `code` (1: run-time failure,
// 2: bad input). `failed_step` >= 0 marks a numerical failure at that step: failure.h5 is due. Any other
// exception in a decomposed run is one rank's alone; `semlb sim` then ends the job with MPI_Abort.
struct AgreedError : std::runtime_error {
  AgreedError(const std::string& message, int code, long failed_step = -1)
      : std::runtime_error(message), code(code), failed_step(failed_step) {}
  int code;
  long failed_step;
};

// Runs `local` (which must not call collectives) on every rank, then agrees on the outcome: if it threw
// on any rank, every rank throws AgreedError with the message of the lowest failing rank, prefixed
// "rank R: " unless every rank failed with that same message, and code 2 for an InputError, else 1.
void agree(const Mpi& mpi, const std::function<void()>& local);

struct Decomposition {
  // min_width in slices: on 3 or more ranks at least the ghost region, cutoff + a cell's reach (one cutoff)
  // on either side, so that only neighbouring ranks share elements within the cutoff (docs/engine.md)
  int slices = 0, min_width = 1;
  double x0 = 0, width = 1;       // slice s covers [x0 + s width, x0 + (s+1) width); outside is clamped
  std::string policy = "reactive", initial = "workload";
  // measured: each rank's computation time from its clock; modelled: its share of the workload W_s (work
  // units), so that decisions are the same in every launch (tests, studies that need reproducible decisions)
  std::string timing = "measured";
  long rebalance_every = 100;
  PolicyParams params;

  // InputError names the field: slab widths below the ghost region on >= 3 ranks, more ranks than the
  // slices hold, a policy that needs what the engine cannot observe (e.g. the oracle's true work).
  static Decomposition from_scene(const Scene& scene, int ranks);
  int slice_of(double x) const;
};

// Per-slice workload W_s = sum over cells of n_i * n_N(i) (paper eqs. 2-3): n_N(i) counts the elements in
// the 3x3x3 bins around the cell's centroid, among the cells' own elements and `ghosts` (3 doubles each).
std::vector<double> slice_workload(const State& cells, const std::vector<double>& ghosts, const Decomposition& d,
                                   double cutoff);
int owner_of(int slice, const std::vector<int>& boundaries);

class DistributedSimulation {
 public:
  // Every rank passes the same whole tissue; each keeps the cells of its slab range. `restored` (from a
  // checkpoint) continues its balancer when it was written by as many ranks with the same policy; otherwise
  // the run starts from the initial partition and restarted() says why.
  DistributedSimulation(const Scene& scene, const State& tissue, Mpi& mpi, const std::string& trace_path = "",
                        const std::optional<DecompositionCheckpoint>& restored = std::nullopt);
  void advance(long target);
  State gather();  // rank 0: the whole tissue in cell-id order; other ranks: cells empty
  std::pair<long, long> totals();  // cells and elements over all ranks (on every rank)
  long step() const { return sim_->host_state().step; }
  const std::vector<int>& boundaries() const { return balancer_->boundaries(); }
  long migrated_slices() const { return balancer_->migration(); }
  // The balancer for a checkpoint; complete (with the policy's history) on rank 0, which writes the files.
  DecompositionCheckpoint checkpoint() const;
  // Why a restart did not continue the checkpoint's balancer (empty when it did, or without a checkpoint).
  const std::string& restarted() const { return restarted_; }
  // Per rebalancing interval: the ranks' computation times and the global imbalance (T_max-T_min)/T_mean.
  struct Interval {
    long step;
    std::vector<double> times;            // computation per rank
    std::vector<double> exchange, migrate;  // per rank: ghost exchange; cell migration and rebalancing
    double imbalance;
    long moved;
  };
  const std::vector<Interval>& intervals() const { return intervals_; }
  Simulation& local() { return *sim_; }

 private:
  void exchange_ghosts();
  void migrate_cells();
  // A rebalancing event (LAMMPS-style probe / decide / move): measure() gathers the interval's times and
  // the global W_s on every rank, decide() runs the Balancer (the policy on rank 0, broadcast, every rank's
  // balancer committed to the same boundaries), and migrate_cells() moves the cells.
  Measurement measure();
  void decide(const Measurement& m);
  void write_trace(const TraceEvent& e);
  void collective_check();
  double compute_seconds() const;
  int owner_of_cell(const State& s, long c) const;

  const Scene* scene_;
  Mpi* mpi_;
  Decomposition dec_;
  std::unique_ptr<Balancer> balancer_;
  std::unique_ptr<Simulation> sim_;
  std::vector<double> ghost_positions_;
  std::string trace_path_, trace_kept_, restarted_;  // trace_kept_: the lines before a restart's event
  std::ofstream trace_;
  std::vector<Interval> intervals_;
  double seconds_at_event_ = 0;
  double exchange_s_ = 0, migrate_s_ = 0;  // since the last rebalancing event
  long cells_at_event_ = 0;
  int fault_rank_ = -1;  // SEMLB_FAULT_INJECT=RANK:STEP: throws on that rank alone at that step (tests)
  long fault_step_ = -1;
};

}  // namespace semlb::engine
