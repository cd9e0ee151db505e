// The decomposed run (paper Sec. III-D/E, IV): slabs of slices along x, one rank per slab range, ghost
// exchange with the two neighbouring ranks, whole cells owned by the rank of their centroid's slice,
// workload-aware initial partition and rebalancing through the shared controllers (controllers/balancer).
#pragma once
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "collective.hpp"
#include "controllers/balancer.hpp"
#include "controllers/workload.hpp"
#include "decomposition.hpp"
#include "io/io.hpp"
#include "mpi.hpp"
#include "simulation/simulation.hpp"

namespace semlb::engine {

class DistributedSimulation {
 public:
  // Every rank passes the same whole tissue; each keeps the cells of its slab range. `restored` (from a
  // checkpoint) continues its balancer when it was written by as many ranks with the same policy; otherwise
  // the run starts from the initial partition and restarted() says why.
  DistributedSimulation(const Scene& scene, const State& tissue, Mpi& mpi, const std::string& trace_path = "",
                        const std::optional<DecompositionCheckpoint>& restored = std::nullopt);
  // Not copied or moved: the local simulation's hooks refer to this object.
  DistributedSimulation(const DistributedSimulation&) = delete;
  DistributedSimulation& operator=(const DistributedSimulation&) = delete;
  void advance(long target);
  State gather();                  // rank 0: the whole tissue in cell-id order; other ranks: cells empty
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
    std::vector<double> times;              // computation per rank, as the policy saw it (decomposition.timing)
    std::vector<double> exchange, migrate;  // per rank: ghost exchange; cell migration and rebalancing (wall seconds)
    std::vector<double> wall, device;  // per rank: the step phases' wall seconds; device timers' seconds (0 without)
    std::vector<double> exchange_bytes, migrate_bytes;  // per rank: band bytes sent; cell bytes sent to other ranks
    std::vector<double> device_pair, device_list, device_cells;  // per rank: Backend::device_parts of `device`
    double imbalance;
    long moved;
  };
  const std::vector<Interval>& intervals() const { return intervals_; }
  Simulation& local() { return *sim_; }
  // With output.workload: the events recorded so far (rank 0; a restart's earlier events from `path` first), written
  // to `path` atomically (controllers/workload.hpp). `command`, `git_revision`: the run's, kept in the file.
  void write_workload(const std::string& path, const std::string& command, const std::string& git_revision);

 private:
  // This run's points of the local simulation's step (StepHooks): the ghost exchange, the cell migration, the
  // collective failure check, and a recording's W_s before each cell stage.
  class Hooks final : public StepHooks {
   public:
    explicit Hooks(DistributedSimulation& d) : d_(d) {}
    unsigned mask() const override;
    void before_forces() override { d_.start_exchange(); }
    void post_exchange() override { d_.post_exchange(); }
    void before_nonlocal_forces() override { d_.finish_exchange(); }
    void progress() override { d_.pending_.progress(); }
    void before_cells() override { d_.stage_work_before(); }
    void after_cells() override { d_.migrate_cells(); }
    void failure_check() override { d_.collective_check(); }

   private:
    DistributedSimulation& d_;
  };
  Hooks hooks_{*this};
  // The ghost exchange in three parts around the local forces (the before_forces, post_exchange and
  // before_nonlocal_forces hooks; all three in start_exchange without decomposition.overlap).
  void start_exchange();
  void post_exchange();
  void finish_exchange();
  void migrate_cells();
  // A rebalancing event (LAMMPS-style probe / decide / move): measure() gathers the interval's times and
  // the global W_s on every rank, decide() runs the Balancer (the policy on rank 0, broadcast, every rank's
  // balancer committed to the same boundaries), and migrate_cells() moves the cells.
  Measurement measure();
  // W_s of the whole tissue (backends/backend.hpp, slice_workload's rule) on every rank: the grid over every rank's
  // elements, the owned elements' bin counts summed over the ranks, each rank's cells' w_i summed per slice.
  // f() in a turn when this run is one rank (its device work untimed, but another job sharing the device, as the
  // recordings of scripts/gpu/workload_library.sh with JOBS > 1, times its kernels meanwhile: they must not overlap);
  // on P ranks f() holds collectives, which a rank may not wait for inside its turn, and runs as it is (every rank is
  // then between its step's turns, in the same collective).
  template <class F>
  void alone_in_turn(F&& f) {
    if (mpi_->size() == 1)
      sim_->in_turn(f);
    else
      f();
  }
  std::vector<double> global_slice_work();
  std::vector<double> global_slice_work(const Grid& g);
  Grid work_grid_all_ranks();
  void decide(const Measurement& m);
  void write_trace(const TraceEvent& e);
  void collective_check();
  double compute_seconds() const;

  const Scene* scene_;
  Mpi* mpi_;
  Decomposition dec_;
  std::unique_ptr<Balancer> balancer_;
  std::unique_ptr<Simulation> sim_;
  std::string trace_path_, trace_kept_, restarted_;  // trace_kept_: the lines before a restart's event
  std::ofstream trace_;
  std::vector<Interval> intervals_;
  double seconds_at_event_ = 0, device_at_event_ = 0;
  double exchange_s_ = 0, migrate_s_ = 0;           // since the last rebalancing event
  double exchange_bytes_ = 0, migrate_bytes_ = 0;   // since the last rebalancing event
  std::map<std::string, double> kernels_at_event_;  // Backend::step_kernel_seconds at the last event
  std::unique_ptr<DeviceTurns> turns_;              // decomposition.device_sharing: turns
  // With output.workload and device timers: the event's measured seconds per slice (WorkloadEvent::slice_seconds),
  // collective. `work`: the global W_s; `pair_s`, `device_s`: this rank's pair-force and device seconds since the
  // last event (Backend::device_parts).
  std::vector<double> measured_slice_seconds(const WorkloadEvent& e, const std::vector<double>& work, double pair_s,
                                             double device_s);
  // The bands in flight between start_exchange() and finish_exchange(); the buffers are declared first so that
  // they outlive the requests.
  std::vector<char> send_left_, send_right_, from_above_, from_below_;
  Requests pending_;
  long cells_at_event_ = 0;
  std::vector<WorkloadEvent> workload_;  // output.workload: rank 0's record of every event
  // Elements per slice and the edge ghost bands of the whole tissue (collective), into the event `e`.
  void count_elements(WorkloadEvent& e);
  // A recording run with device timers (WorkloadEvent::cell_stage_changes): W_s on one grid before and after each
  // cell stage; the slices whose W_s changed get the stage's bit.
  bool tracks_stages() const;
  void stage_work_before();
  void stage_work_after();
  Grid stage_grid_;
  std::vector<double> stage_work_;      // W_s before the current cell stage
  std::vector<int64_t> stage_changes_;  // per slice, this interval's bits so far
  int stage_ = 0;                       // cell stages in this interval so far
  bool stage_pending_ = false;          // stage_work_before ran, its cell stage's after-count not yet
  int fault_rank_ = -1;                 // SEMLB_FAULT_INJECT=RANK:STEP: throws on that rank alone at that step (tests)
  long fault_step_ = -1;
};

}  // namespace semlb::engine
