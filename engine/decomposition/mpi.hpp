// RAII over MPI (initialised only when the process was started by mpirun) and the few collectives the
// decomposition needs; every return code is checked.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace semlb::engine {

// Non-blocking point-to-point requests (MPI_Isend/MPI_Irecv), owned: wait() completes them; the destructor
// cancels and frees those still active (an exception between the start and the wait), so none leaks and
// nothing waits on a peer that may be gone. The buffers must outlive this object (the caller's members).
class Requests {
 public:
  Requests() = default;
  ~Requests();
  Requests(const Requests&) = delete;
  Requests& operator=(const Requests&) = delete;
  void send(const std::vector<char>& bytes, int to, int tag);  // MPI_PROC_NULL: nothing
  void receive(std::vector<char>& bytes, int from, int tag);   // exactly bytes.size() bytes
  void wait();                                                 // all of them; throws on an MPI error
  // Lets MPI move the pending messages on (MPI_Testall), without waiting: called while the device computes,
  // so that large (rendezvous) messages travel during the local forces rather than in wait().
  void progress();
  bool pending() const { return !requests_.empty(); }

 private:
  std::vector<MPI_Request> requests_;
};

class Mpi {
 public:
  // True when a launcher (mpirun, srun) started this process: then `semlb sim` runs decomposed.
  static bool launched();
  Mpi();   // MPI_Init unless already initialised; errors return instead of aborting
  ~Mpi();  // MPI_Finalize if this object initialised MPI
  Mpi(const Mpi&) = delete;
  Mpi& operator=(const Mpi&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  int local_rank() const;  // rank among the processes of this host (device index)

  // Every rank gives k values; returns them by rank: [v_0[0..k), v_1[0..k), ...].
  std::vector<double> allgather(const std::vector<double>& mine) const;
  void allreduce_sum(std::vector<double>& values) const;
  void allreduce_sum(std::vector<int>& values) const;
  long allreduce_max(long value) const;
  void broadcast(std::vector<int>& values, int root) const;
  void broadcast(std::string& text, int root) const;
  // Sends `send` to `to` and receives from `from` (either may be MPI_PROC_NULL).
  std::vector<char> sendrecv(const std::vector<char>& send, int to, int from) const;
  // sendrecv started, not finished: the sizes are exchanged at once (8 bytes, blocking), then `recv` is sized and
  // the data receive and send are posted on `pending` with tag `tag`; `send` and `recv` stay untouched until
  // pending.wait(). Two exchanges in flight at once need different tags.
  void start_sendrecv(const std::vector<char>& send, int to, int from, std::vector<char>& recv, int tag,
                      Requests& pending) const;
  // Every rank sends parts[r] to rank r; returns what each rank sent here, by source rank.
  std::vector<std::vector<char>> alltoall(const std::vector<std::vector<char>>& parts) const;
  std::vector<std::vector<char>> gather(const std::vector<char>& part, int root) const;
  void barrier() const;
  [[noreturn]] void abort(int code) const;

 private:
  bool owns_ = false;
  int rank_ = 0, size_ = 1;
};

}  // namespace semlb::engine
